"""Running the trade study: one recording run per configuration (:func:`record`, errors against the reference,
:func:`errors`) and the cost measured side by side with the bare model (:func:`run_scenario`, :func:`run_study`).
The package docstring, :mod:`mjrft.tools.tradeoff`, describes the measurements."""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field, replace
from typing import Callable

import mujoco
import numpy as np

from mjrft.coupler import GranularTerrain
from mjrft.errors import NonFiniteError, TerrainStabilityWarning, unknown
from mjrft.media import generic, get_medium
from mjrft.settings import DEFAULTS, custom_entries

from .scenarios import (INERTIAL_VARIANTS, LAW_VARIANTS, REFERENCE_LAW, SCENARIOS, Config, Scenario, default_grid,
                        get_scenario, reference_config)

SAMPLE_DT = 0.002  # s; errors are computed on samples at these instants (a multiple of every timestep)
QUICK_DURATION = 0.5  # --quick runs every scenario for this fraction of its duration
MIN_TIMED = 2.0  # s of wall time with terrain after which the timing repeats stop early
MIN_SAMPLE = 0.1  # s; one timing sample repeats a short rollout back to back until it lasts this long


@dataclass
class Trace:
    """Samples every SAMPLE_DT: time, net granular force (n, 3), tracked position (n, 3), sinkage (n,)."""

    time: np.ndarray
    force: np.ndarray
    position: np.ndarray
    sinkage: np.ndarray


@dataclass
class Row:
    """One line of the result table."""

    scenario: str
    config: Config
    resolution: float  # m
    elements: int
    cost_ratio: float = math.nan
    peak_force: float = math.nan  # N, max |F|
    rms_force: float = math.nan  # N, sqrt(mean |F|^2)
    final_position: tuple = (math.nan, math.nan, math.nan)
    sinkage: float = math.nan  # m
    err_peak: float = math.nan  # relative
    err_rms: float = math.nan  # relative
    err_position: float = math.nan  # m
    err_sinkage: float = math.nan  # m
    warnings: int = 0
    status: str = "ok"
    trace: Trace | None = field(default=None, repr=False)
    #: reference row only: errors between the two finest resolutions at the default timestep (see run_scenario)
    convergence: dict | None = None


def law_and_medium(variant: str, medium):
    """The coupler's (law, medium) for a study law variant on a scenario's medium."""
    if variant not in LAW_VARIANTS:
        raise unknown("law variant", variant, LAW_VARIANTS)
    med = get_medium(medium)
    if variant == "rft_generic":  # the generic profile of the same grains (their size and density kept)
        med = replace(generic.scaled(med.zeta, name=f"generic*zeta({med.name})"), grain_diameter=med.grain_diameter,
                      grain_density=med.grain_density, volume_fraction=med.volume_fraction)
    return LAW_VARIANTS[variant], med


def _model_for(scenario: Scenario, timestep: float) -> mujoco.MjModel:
    model = scenario.build()
    model.opt.timestep = timestep
    return model


def make_terrain(scenario: Scenario, model: mujoco.MjModel, config: Config) -> GranularTerrain:
    law, medium = law_and_medium(config.law, custom_entries(model).get("medium", DEFAULTS["medium"]))
    if config.law == "hybrid" and scenario.hybrid_extra is not None:
        medium = medium.with_extra(**scenario.hybrid_extra())
    return GranularTerrain(model, medium, law, resolution_scale=config.resolution_scale,
                           inertial=INERTIAL_VARIANTS.get(config.law))


def _simulate(model, data, terrain, control, duration, frame_skip, sample_every=0, on_sample=None):
    """Run ``duration`` s: ``control()`` every ``frame_skip`` steps, ``on_sample()`` every ``sample_every``."""
    nsteps = int(round(duration / model.opt.timestep))
    piece = math.gcd(frame_skip, sample_every) if sample_every else frame_skip
    done = 0
    while done < nsteps:
        if done % frame_skip == 0:
            control()
        n = min(piece, nsteps - done)
        if terrain is None:
            mujoco.mj_step(model, data, n)
        else:
            terrain.step(data, n)
        done += n
        if sample_every and done % sample_every == 0:
            on_sample()


def _fresh(model, data, terrain, scenario):
    mujoco.mj_resetData(model, data)
    if terrain is not None:
        terrain.reset()
    mujoco.mj_forward(model, data)
    return scenario.controller(model, data)


def record(scenario: Scenario, model, data, terrain, config: Config) -> Trace:
    """The untimed recording run of one configuration."""
    control = _fresh(model, data, terrain, scenario)
    sample_every = int(round(SAMPLE_DT / model.opt.timestep))
    if abs(sample_every * model.opt.timestep - SAMPLE_DT) > 1e-12:
        raise ValueError(f"timestep {model.opt.timestep!r} s does not divide the sample interval {SAMPLE_DT} s")
    bodies = np.array([model.body(b).id for b in scenario.measure_bodies])
    track = model.body(scenario.track_body).id if scenario.track_body else None
    ts, fs, ps, ss = [], [], [], []

    def on_sample():
        ts.append(data.time)
        fs.append(terrain.wrench[bodies, :3].sum(axis=0))
        ps.append(data.xpos[track].copy() if track is not None else np.full(3, np.nan))
        ss.append(terrain.sinkage()[bodies].max())

    _simulate(model, data, terrain, control, scenario.duration, config.frame_skip, sample_every, on_sample)
    return Trace(np.array(ts), np.array(fs), np.array(ps), np.array(ss))


def _timed(scenario, model, data, terrain, frame_skip, min_sample: float = 0.0) -> float:
    """Wall time of one rollout: the mean over back-to-back rollouts lasting at least ``min_sample`` s
    (so that a rollout of a tiny model is not timed alone; set-up between rollouts is not timed)."""
    total, k = 0.0, 0
    while True:
        control = _fresh(model, data, terrain, scenario)
        t0 = time.perf_counter()
        _simulate(model, data, terrain, control, scenario.duration, frame_skip)
        total += time.perf_counter() - t0
        k += 1
        if total >= min_sample:
            return total / k


def _cost_ratio(scenario, bare_model, bare_data, model, data, terrain, frame_skip, repeats) -> float:
    """Median over interleaved samples (bare, terrain, bare, terrain, ..., bare) of each terrain sample's
    time over the mean of the two bare samples around it; stops early once MIN_TIMED s with terrain."""
    bare = [_timed(scenario, bare_model, bare_data, None, 10, MIN_SAMPLE)]
    ratios, spent = [], 0.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TerrainStabilityWarning)
        for _ in range(repeats):
            t = _timed(scenario, model, data, terrain, frame_skip, MIN_SAMPLE)
            bare.append(_timed(scenario, bare_model, bare_data, None, 10, MIN_SAMPLE))
            ratios.append(t / (0.5 * (bare[-2] + bare[-1])))
            spent += t
            if spent > MIN_TIMED:
                break
    return float(np.median(ratios))


def errors(trace: Trace, ref: Trace, kinematic: bool) -> dict:
    """Peak / RMS force errors (relative), final position and sinkage errors (m) of ``trace`` against ``ref``."""
    if trace.time.shape != ref.time.shape or not np.allclose(trace.time, ref.time, atol=1e-9):
        raise ValueError("traces are sampled at different instants")
    peak, peak_ref = np.linalg.norm(trace.force, axis=1).max(), np.linalg.norm(ref.force, axis=1).max()
    rms_ref = math.sqrt(np.mean(np.sum(ref.force ** 2, axis=1)))
    out = {
        "err_peak": abs(peak - peak_ref) / peak_ref if peak_ref > 0 else math.nan,
        "err_rms": math.sqrt(np.mean(np.sum((trace.force - ref.force) ** 2, axis=1))) / rms_ref if rms_ref > 0
        else math.nan,
        "err_position": math.nan,
        "err_sinkage": math.nan,
    }
    if not kinematic:
        out["err_position"] = float(np.linalg.norm(trace.position[-1] - ref.position[-1]))
        out["err_sinkage"] = abs(_late_mean(trace.sinkage) - _late_mean(ref.sinkage))
    return out


def _late_mean(x: np.ndarray) -> float:
    return float(np.mean(x[len(x) * 3 // 4:]))


def run_scenario(scenario: Scenario, configs: list[Config], *, repeats: int = 3, progress=print) -> list[Row]:
    """Run every configuration of one scenario; errors against the scenario's reference configuration.

    The reference is the configuration labelled ``"reference"`` (added when missing).
    """
    repeats = max(1, int(repeats))
    configs = list(configs)
    if not any(c.factor == "reference" for c in configs):
        configs.append(reference_config(scenario))
    # the bare model: default timestep and frame skip, no terrain
    bare_model = (scenario.build_bare or scenario.build)()
    bare_model.opt.timestep = 0.001
    bare_data = mujoco.MjData(bare_model)
    _timed(scenario, bare_model, bare_data, None, 10)  # warm caches
    rows = []
    for cfg in configs:
        model = _model_for(scenario, cfg.timestep)
        data = mujoco.MjData(model)
        terrain = make_terrain(scenario, model, cfg)
        row = Row(scenario.name, cfg, terrain.resolution, terrain.n_elements)
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", TerrainStabilityWarning)
                _fresh(model, data, terrain, scenario)
                terrain.step(data, 5)  # compile / load the kernel outside the timing
                row.trace = record(scenario, model, data, terrain, cfg)
            row.warnings = sum(issubclass(w.category, TerrainStabilityWarning) for w in caught)
            row.cost_ratio = _cost_ratio(scenario, bare_model, bare_data, model, data, terrain, cfg.frame_skip,
                                         repeats)
        except NonFiniteError as exc:
            row.status = f"failed: {exc}"
        tr = row.trace
        if tr is not None and row.status == "ok":
            row.peak_force = float(np.linalg.norm(tr.force, axis=1).max())
            row.rms_force = float(math.sqrt(np.mean(np.sum(tr.force ** 2, axis=1))))
            row.final_position = tuple(float(v) for v in tr.position[-1])
            row.sinkage = _late_mean(tr.sinkage) if not scenario.kinematic else math.nan
        rows.append(row)
        if progress:
            progress(f"  {scenario.name:9s} {cfg.label:22s} {row.elements:6d} el  cost {row.cost_ratio:6.2f}x  {row.status}")
    ref = next(r for r in rows if r.config.factor == "reference")
    if ref.status != "ok":
        raise RuntimeError(f"the reference configuration of scenario {scenario.name!r} failed: {ref.status}")
    for r in rows:
        if r.status == "ok":
            for k, v in errors(r.trace, ref.trace, scenario.kinematic).items():
                setattr(r, k, v)
    # is the reference converged in resolution? errors of the second-finest against the finest resolution
    # at the default timestep: a reference cannot be trusted to better than this
    ladder = sorted((r for r in rows if r.status == "ok" and r.config.factor in ("default", "resolution")
                     and r.config.law == REFERENCE_LAW and r.config.timestep == 0.001 and r.config.frame_skip == 10),
                    key=lambda r: r.config.resolution_scale)
    if len(ladder) >= 2:
        ref.convergence = {"finer": ladder[0].config.label, "coarser": ladder[1].config.label,
                           **errors(ladder[1].trace, ladder[0].trace, scenario.kinematic)}
    return rows


def run_study(scenarios=None, *, quick: bool = False, repeats: int = 3, progress=print,
              grid: Callable[[Scenario], list[Config]] | None = None) -> list[Row]:
    """Run the study on ``scenarios`` (names or :class:`Scenario` objects; default all) and return the rows.

    ``grid(scenario)`` replaces :func:`default_grid` (e.g. a hand-picked list of :class:`Config`).
    """
    items = list(SCENARIOS) if scenarios is None else list(scenarios)
    chosen = [n if isinstance(n, Scenario) else get_scenario(n) for n in items]
    if quick:  # half the simulated time as well (the humanoid then shifts its weight but keeps both feet down)
        chosen = [replace(sc, duration=QUICK_DURATION * sc.duration) for sc in chosen]
    rows = []
    for sc in chosen:
        configs = grid(sc) if grid is not None else default_grid(sc, quick)
        if progress:
            progress(f"{sc.name}: {sc.description} ({len(configs)} configurations)")
        rows += run_scenario(sc, configs, repeats=1 if quick else repeats, progress=progress)
    return rows

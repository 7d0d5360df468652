"""The speed/accuracy trade study (``mjrft bench``): element resolution, force law, timestep, frame skip.

For four standard scenarios the study runs a grid of configurations, each one side by side with the
bare MuJoCo model, and reports the cost per simulated second relative to the bare model and the
error against a converged reference::

    mjrft bench --quick --out bench_out            # small grid, half the simulated time, about a minute
    mjrft bench --scenarios hexapod,plate          # the full grid of two scenarios
    python benchmarks/trade_study.py               # full study -> benchmarks/results/

Outputs (in ``--out``): ``trade_study.md`` (Markdown table), ``trade_study.csv`` (one row per
scenario and configuration) and ``trade_study.png`` (Pareto plot: cost ratio against force error).

Scenarios (:data:`SCENARIOS`)
-----------------------------
``hexapod``   RHex-class hexapod (:func:`mjrft.models.hexapod_model`, C-legs, poppy_cp), open-loop
              alternating tripod at 2 Hz (hip position targets advancing at 4 pi rad/s, tripod B half
              a turn ahead, as ``benchmarks/bench_step.py``), 2 s. Granular bodies: torso + six legs.
``humanoid``  HUBO-class humanoid standing on its right foot, 2.5 s: a posture controller leans both
              legs (hip roll = -ankle roll, a parallelogram) to bring the centre of mass over the right
              sole (PD on the centre of mass, 0-1 s), then folds the left leg up (hip pitch -0.6, knee
              1.2, ankle pitch -0.6 rad, 1.2-1.8 s); the right ankle pitch holds the centre of mass over
              the sole fore-aft. The feet are Li/HUBO's widest boards, 30.4 cm wide (reference section 6):
              on the default 15.2 cm feet one-foot stance on poppy seeds topples in every configuration
              (the plastic rolling resistance of a plate, about ``alpha_z L w^3 / 12`` = 31 N m/rad, is
              far below the body's toppling stiffness ``m g h`` = 330 N m/rad; it grows as ``w^3``).
``plate``     Li 2013's plate (3.81 x 2.54 x 0.64 cm, :func:`mjrft.models.rigs.plate_rig_xml`) at attack
              angle beta = 30 deg, driven at 4 cm/s along intrusion angle gamma = 60 deg from 1 cm above
              the surface to 5.6 cm centre depth, 2 s.
``hexapod_small`` The DynaRoACH-sized hexapod (:func:`mjrft.models.hexapod_model` ``variant="small"``, 25 g,
              C-legs of 1 cm radius) on 3 mm glass (``glass3_cp``, the DynaRoACH paper's medium) with its
              scene's dry inertial regime on (:mod:`mjrft.laws.inertial`), open-loop alternating tripod at
              10 Hz (the paper's fluid-like running range), 1 s. Granular bodies: torso + six legs.
``cleg``      Li 2013's leg-rotation rig (:func:`mjrft.models.rigs.leg_rig_xml`, C-leg: one closed mesh, a
              semicircle of 7.62 cm chord, 2.54 cm wide, 0.64 cm thick, axle 2 cm above the surface) turning at
              pi/2 rad/s from leg angle -pi/2 to +pi/2, 2 s (Li's 0.2 rad/s would take 16 s; the dry
              laws are rate-independent, so only the wet law notices the speed).

The rigs are kinematic: their joints get an armature of 1e6 (kg or kg m^2), so the granular forces
cannot change their motion, and ``qpos``/``qvel`` are re-prescribed every control period.

Configurations (:func:`default_grid`)
-------------------------------------
One factor at a time around the scenario's default (the model's own resolution, ``rft`` with the
medium's own Li fit, 1 ms x 10 steps per control period):

* resolution: 4, 2, 1, 1/2 and 1/4 x the model's resolution (hexapod 5 mm, humanoid 2 cm); the rigs
  (5 mm) stop at 1/2, where they have converged (1/2 and 1/4 differed by < 0.05 % in a trial run);
* law: ``depth_only``; ``rft_generic`` (Li RFT with the generic profile scaled to the medium's zeta,
  i.e. Li's scaling routine instead of a measured fit); ``rft`` (the medium's own fit); ``rft3d``;
  ``wet`` (SGRFT speed factor on the medium's own fit; on the rigs: the plate's 40 mm/s lies inside
  its 10-50 mm/s calibration, the C-leg's elements move up to 12 cm/s, where the factor is held at its
  50 mm/s value) and ``hybrid`` (curved-leg model, with the leg's width and maximum depth as
  :mod:`mjrft.tools.rigs` gives them; C-leg rig only); ``rft_inertial`` (the medium's own fit plus the dry
  inertial regime, :mod:`mjrft.laws.inertial`; RHex-class hexapod: its legs pass poppy seeds' critical
  speed sqrt(2 g d) = 11.7 cm/s) and ``rft_quasistatic`` (the small hexapod's scene with the regime
  off). Rows of ``wet``, ``hybrid``, ``rft_inertial`` and ``rft_quasistatic`` measure a different
  physics, not a discretisation error;
* timestep: 2, 1, 0.5 ms at a fixed control period of 10 ms (frame skip 5, 10, 20);
* frame skip at 1 ms: 1, 5, 10, 20 (the control period changes with it);
* the presets of :mod:`mjrft.tools.presets` (``fast``, ``accurate``; ``default`` is the default row).

Reference (error zero by definition): the scenario's finest resolution (robots 1/4 x, rigs 1/2 x) with
the smallest timestep (0.5 ms x 20) and the medium's own Li fit.

Measurements
------------
* cost: wall time of one rollout with terrain over wall time of the same rollout of the bare model,
  i.e. cost per simulated second relative to plain MuJoCo. The bare model of a robot is its
  rigid-ground twin (``sand=False``: MuJoCo contacts instead of grains) running the same controller;
  that of a rig is the rig without terrain (a few microseconds per step, so a rig's ratio is
  essentially the terrain's own cost in units of a trivial MuJoCo step). Bare runs use the models'
  default 1 ms x 10. The terrain and bare rollouts alternate (bare, terrain, bare, ..., terrain, bare;
  up to ``repeats`` terrain samples, fewer once 2 s with terrain have been timed; a rollout shorter
  than 0.1 s is repeated back to back within its sample); each terrain sample is divided by the mean of
  the two bare samples around it and the median of these ratios is reported, so a noisy, shared machine
  affects both sides alike. Compilation and model set-up are outside the timing.
* errors, from a separate (untimed) recording run sampled every 2 ms of simulated time (the same
  instants in every configuration; stepping in pieces does not change the physics):

  - peak force: ``| max_t |F| - max_t |F_ref| | / max_t |F_ref|``, F the net granular force on the
    scenario's bodies (robot: all granular bodies; rig: the plate or leg);
  - RMS force: ``sqrt(mean_t |F - F_ref|^2) / sqrt(mean_t |F_ref|^2)``;
  - final position: distance (mm) between the final positions of the torso / pelvis (robots only;
    a rig's motion is prescribed);
  - sinkage: difference (mm) of the mean, over the last quarter of the run, of the deepest element
    depth of the granular bodies (robots only).

A configuration whose run raises :class:`~mjrft.errors.NonFiniteError` is reported as ``failed``;
stability warnings (:class:`~mjrft.errors.TerrainStabilityWarning`) are counted in ``warnings``.
"""

from __future__ import annotations

import csv
import math
import os
import time
import warnings
from dataclasses import dataclass, field, replace
from typing import Callable

import mujoco
import numpy as np

from mjrft.coupler import DEFAULTS, GranularTerrain, _custom
from mjrft.errors import NonFiniteError, TerrainStabilityWarning, check_positive, unknown
from mjrft.media import generic, get_medium

from .outputs import output_dir

SAMPLE_DT = 0.002  # s; errors are computed on samples at these instants (a multiple of every timestep)
CONTROL_PERIOD = 0.01  # s; the default control period (1 ms x 10)
RESOLUTION_SCALES = (4.0, 2.0, 1.0, 0.5, 0.25)
RIG_RESOLUTION_SCALES = (4.0, 2.0, 1.0, 0.5)  # the rigs converge by 1/2 (x0.5 and x0.25 differ by < 0.05 %)
TIMESTEPS = (0.002, 0.001, 0.0005)
FRAME_SKIPS = (1, 5, 10, 20)
DRY_LAWS = ("depth_only", "rft_generic", "rft", "rft3d")
#: law variants of the study -> law name in the coupler (``rft_generic`` also swaps the medium, see law_and_medium)
LAW_VARIANTS = {
    "depth_only": "depth_only",
    "rft_generic": "rft",
    "rft": "rft",
    "rft3d": "rft3d",
    "wet": "wet",
    "hybrid": "hybrid",
    "rft_inertial": "rft",  # with the dry inertial regime on
    "rft_quasistatic": "rft",  # with the dry inertial regime off (a scene that turns it on)
}
#: the inertial regime each variant forces on (True) or off (False); others follow the scene's mjrft:inertial
INERTIAL_VARIANTS = {"rft_inertial": True, "rft_quasistatic": False}
#: variants that model a different physics; their errors are model differences, not accuracy
MODEL_DIFFERENCE_LAWS = ("wet", "hybrid", "rft_inertial", "rft_quasistatic")
REFERENCE_LAW = "rft"
QUICK_DURATION = 0.5  # --quick runs every scenario for this fraction of its duration
MIN_TIMED = 2.0  # s of wall time with terrain after which the timing repeats stop early
MIN_SAMPLE = 0.1  # s; one timing sample repeats a short rollout back to back until it lasts this long


# ---------------------------------------------------------------------------------------------------
# configurations and scenarios
# ---------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Config:
    """One point of the grid. ``resolution_scale`` multiplies the model's own resolution (its ``<custom>``)."""

    label: str
    factor: str  # "default", "resolution", "law", "timestep", "frame_skip", "reference", "preset"
    resolution_scale: float = 1.0
    law: str = REFERENCE_LAW
    timestep: float = 0.001
    frame_skip: int = 10

    def key(self) -> tuple:
        return (round(self.resolution_scale, 9), self.law, round(self.timestep, 12), self.frame_skip)


@dataclass
class Scenario:
    """A standard scenario: a model builder, a controller factory and what to measure."""

    name: str
    description: str
    duration: float  # s of simulated time
    build: Callable[[], mujoco.MjModel]  # the model with terrain settings in <custom>, default timestep
    controller: Callable[[mujoco.MjModel, mujoco.MjData], Callable[[], None]]  # called every control period
    measure_bodies: tuple[str, ...]  # bodies whose granular force is measured
    track_body: str | None  # body whose final position is compared (None: kinematic rig)
    laws: tuple[str, ...] = DRY_LAWS
    kinematic: bool = False
    build_bare: Callable[[], mujoco.MjModel] | None = None  # plain-MuJoCo twin (None: ``build`` without terrain)
    resolution_scales: tuple[float, ...] = RESOLUTION_SCALES  # coarse to fine; the finest is the reference's
    hybrid_extra: Callable[[], dict] | None = None  # medium constants the hybrid law needs (leg width, depth)
    presets: bool = True  # takes part in choosing the presets (recommend_presets)


def _rigs():
    from mjrft.models import rigs  # the rig builders (imported lazily: mjrft.models imports nothing heavy)

    return rigs


# --- hexapod --------------------------------------------------------------------------------------
def _hexapod_model(sand: bool = True) -> mujoco.MjModel:
    """The hexapod held in the sagittal plane (``planar=True``, as in Li 2013's robot simulation). Choice: the
    free body's heading is set by its start transient and nothing restores it (:mod:`mjrft.envs.hexapod`), so
    a free walk's errors would measure how far two nearly equal runs turn apart, not the numerics."""
    from mjrft.models import hexapod_model

    return hexapod_model(sand=sand, planar=True)


def _hexapod_controller(model, data, freq: float = 2.0):
    """Open-loop alternating tripod at ``freq`` Hz: every hip target advances at 2 pi freq rad/s, tripod B + pi."""
    tripod_a = {"leg_lf", "leg_rm", "leg_lr"}
    offset = np.array([
        0.0 if mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, model.jnt_bodyid[model.actuator_trnid[i, 0]])
        in tripod_a else math.pi for i in range(model.nu)])
    omega = 2 * math.pi * freq

    def control():
        data.ctrl[:] = omega * data.time + offset

    return control


# --- the small (DynaRoACH-sized) hexapod -----------------------------------------------------------
SMALL_MEDIUM = "glass3_cp"  # the DynaRoACH paper's 3 mm glass
SMALL_FREQ = 10.0  # Hz, above the paper's ~6 Hz walk-to-run transition


def _small_hexapod_model(sand: bool = True) -> mujoco.MjModel:
    from mjrft.models import hexapod_model

    return hexapod_model(variant="small", sand=sand, medium=SMALL_MEDIUM)


def _small_hexapod_controller(model, data):
    return _hexapod_controller(model, data, SMALL_FREQ)


# --- humanoid on one foot -------------------------------------------------------------------------
BOARD_WIDTH = 0.304  # m, the widest board of the HUBO experiments (reference section 6)


def _humanoid_model(sand: bool = True) -> mujoco.MjModel:
    from mjrft.models import humanoid_model

    return humanoid_model(foot_width=BOARD_WIDTH, sand=sand)


def _smooth(x: float) -> float:
    x = min(1.0, max(0.0, x))
    return 0.5 - 0.5 * math.cos(math.pi * x)


def _humanoid_controller(model, data):
    """Stand on the right foot: lean over the right sole (PD on the centre of mass), fold the left leg up.

    Both legs lean as a parallelogram (hip roll = theta, ankle roll = -theta, torso upright) with
    ``theta = 0.15 s + 3 (y_com - y_d) + 0.5 vy_com`` rad (``s`` a 1 s cosine ramp, ``y_d = s y_sole``);
    the right ankle pitch (and the opposite hip pitch) hold the centre of mass over the sole
    fore-aft with the same gains; from 1.2 s to 1.8 s the left leg folds (hip pitch -0.6, knee 1.2,
    ankle pitch -0.6 rad), lifting its foot ~10 cm.
    """
    act = {mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_ACTUATOR, i): i for i in range(model.nu)}
    pelvis = model.body("pelvis").id
    sole = model.site("right_sole").id
    kp, kd = 3.0, 0.5
    i_roll = [(act[f"{s}_hip_roll"], act[f"{s}_ankle_roll"]) for s in ("left", "right")]
    i_lhp, i_lkn, i_lap = act["left_hip_pitch"], act["left_knee"], act["left_ankle_pitch"]
    i_rhp, i_rap = act["right_hip_pitch"], act["right_ankle_pitch"]

    def control():
        mujoco.mj_subtreeVel(model, data)
        t = data.time
        com, vel, foot = data.subtree_com[pelvis], data.subtree_linvel[pelvis], data.site_xpos[sole]
        s = _smooth(t / 1.0)
        theta = 0.15 * s + kp * (com[1] - s * foot[1]) + kd * vel[1]
        for hip, ankle in i_roll:
            data.ctrl[hip] = theta
            data.ctrl[ankle] = -theta
        lift = _smooth((t - 1.2) / 0.6)
        data.ctrl[i_lhp] = -0.6 * lift
        data.ctrl[i_lkn] = 1.2 * lift
        data.ctrl[i_lap] = -0.6 * lift
        lean = -kp * (com[0] - foot[0]) - kd * vel[0]  # shank pitch: positive leans forward
        data.ctrl[i_rap] = -lean
        data.ctrl[i_rhp] = lean

    return control


# --- kinematic rigs -------------------------------------------------------------------------------
RIG_ARMATURE = 1e6
PLATE_BETA = math.radians(30.0)
PLATE_GAMMA = math.radians(60.0)
PLATE_SPEED = 0.04  # m/s along gamma
PLATE_START = 0.01  # m, plate_z at t = 0 (centre 1 cm + half a thickness above the surface)
LEG_OMEGA = math.pi / 2  # rad/s
LEG_START = -math.pi / 2  # rad, leg angle at t = 0


def _heavy(xml: str) -> mujoco.MjModel:
    """Compile ``xml`` with every joint's armature set to RIG_ARMATURE (set in the spec: MuJoCo bakes the
    armature into the compiled model, a later ``model.dof_armature`` edit does not reach the mass matrix)."""
    spec = mujoco.MjSpec.from_string(xml)
    for joint in spec.joints:
        joint.armature = RIG_ARMATURE
    return spec.compile()


def _plate_model() -> mujoco.MjModel:
    return _heavy(_rigs().plate_rig_xml())


def _plate_controller(model, data):
    """Prescribe the plate's path: beta fixed, velocity PLATE_SPEED along gamma (down and forward)."""
    vx, vz = PLATE_SPEED * math.cos(PLATE_GAMMA), -PLATE_SPEED * math.sin(PLATE_GAMMA)

    def control():
        t = data.time
        data.qpos[:3] = (vx * t, PLATE_START + vz * t, PLATE_BETA)
        data.qvel[:3] = (vx, vz, 0.0)

    control()
    return control


def _leg_model() -> mujoco.MjModel:
    return _heavy(_rigs().leg_rig_xml("c"))


def _leg_hybrid_extra() -> dict:
    """The hybrid law's leg width and maximum penetration depth of the C-leg over the sweep (as
    ``mjrft.tools.rigs``)."""
    rigs = _rigs()
    geo = rigs.leg_geometry("c")
    v = np.asarray(geo["vertices"], float)
    theta = LEG_START + LEG_OMEGA * np.linspace(0.0, 2.0, 2001)
    z = rigs.default_axle_height("c") - np.outer(np.sin(theta), v[:, 0]) + np.outer(np.cos(theta), v[:, 2])
    return {"hybrid_width": geo["width"], "hybrid_max_depth": float(max(0.0, -z.min()))}


def _leg_controller(model, data):
    """Prescribe the leg angle: LEG_START + LEG_OMEGA t."""

    def control():
        data.qpos[0] = LEG_START + LEG_OMEGA * data.time
        data.qvel[0] = LEG_OMEGA

    control()
    return control


SCENARIOS: dict[str, Scenario] = {
    s.name: s for s in (
        Scenario("cleg", "rotating C-leg rig (Li 2013), pi/2 rad/s from -90 to +90 deg", 2.0,
                 _leg_model, _leg_controller, ("leg",), None, DRY_LAWS + ("wet", "hybrid"), kinematic=True,
                 resolution_scales=RIG_RESOLUTION_SCALES, hybrid_extra=_leg_hybrid_extra),
        Scenario("plate", "plate intrusion (Li 2013 plate), beta 30 deg, gamma 60 deg, 4 cm/s", 2.0,
                 _plate_model, _plate_controller, ("plate",), None, DRY_LAWS + ("wet",), kinematic=True,
                 resolution_scales=RIG_RESOLUTION_SCALES),
        Scenario("hexapod", "RHex-class hexapod (sagittal plane), open-loop tripod at 2 Hz", 2.0,
                 _hexapod_model, _hexapod_controller,
                 ("torso", "leg_lf", "leg_lm", "leg_lr", "leg_rf", "leg_rm", "leg_rr"), "torso",
                 DRY_LAWS + ("rft_inertial",), build_bare=lambda: _hexapod_model(sand=False)),
        Scenario("hexapod_small", "DynaRoACH-sized hexapod on 3 mm glass, inertial regime on, tripod at 10 Hz", 1.0,
                 _small_hexapod_model, _small_hexapod_controller,
                 ("torso", "leg_lf", "leg_lm", "leg_lr", "leg_rf", "leg_rm", "leg_rr"), "torso",
                 DRY_LAWS + ("rft_quasistatic",), build_bare=lambda: _small_hexapod_model(sand=False),
                 presets=False),
        Scenario("humanoid", "HUBO-class humanoid standing on its right foot (30.4 cm boards)", 2.5,
                 _humanoid_model, _humanoid_controller, ("left_foot", "right_foot"), "pelvis",
                 build_bare=lambda: _humanoid_model(sand=False)),
    )
}


def get_scenario(name: str) -> Scenario:
    if name in SCENARIOS:
        return SCENARIOS[name]
    raise unknown("scenario", name, SCENARIOS)


def reference_config(scenario: Scenario | None = None, scale: float | None = None) -> Config:
    """Finest resolution, smallest timestep, the medium's own Li fit, the default control period."""
    dt = min(TIMESTEPS)
    if scale is None:
        scale = min(scenario.resolution_scales if scenario is not None else RESOLUTION_SCALES)
    return Config("reference", "reference", scale, REFERENCE_LAW, dt, int(round(CONTROL_PERIOD / dt)))


def _preset_configs() -> list[Config]:
    from .presets import PRESETS

    out = []
    for name, p in PRESETS.items():
        if name == "default":
            continue
        out.append(Config(f"preset {name}", "preset", p["resolution_scale"], p["law"], p["timestep"],
                          p["frame_skip"]))
    return out


def default_grid(scenario: Scenario, quick: bool = False) -> list[Config]:
    """The configurations of ``scenario`` (see the module docstring); ``quick``: a small grid."""
    base = Config("default", "default")
    if quick:
        return [base, Config("resolution x4", "resolution", 4.0), Config("law depth_only", "law", law="depth_only"),
                Config("dt 2 ms x 5", "timestep", timestep=0.002, frame_skip=5), reference_config(scale=0.5)]
    configs = [base]
    for s in scenario.resolution_scales:
        configs.append(Config(f"resolution x{s:g}", "resolution", s))
    for law in scenario.laws:
        configs.append(Config(f"law {law}", "law", law=law))
    for dt in TIMESTEPS:
        fs = int(round(CONTROL_PERIOD / dt))
        configs.append(Config(f"dt {dt * 1e3:g} ms x {fs}", "timestep", timestep=dt, frame_skip=fs))
    for fs in FRAME_SKIPS:
        configs.append(Config(f"frame skip {fs}", "frame_skip", frame_skip=fs))
    configs.append(reference_config(scenario))
    configs += _preset_configs()
    return dedupe(configs)


def dedupe(configs: list[Config]) -> list[Config]:
    """Drop configurations identical to an earlier one; the first keeps its place, a preset's name is
    added to its label (``"resolution x4 = preset fast"``)."""
    out: dict = {}
    for c in configs:
        k = c.key()
        if k not in out:
            out[k] = c
        elif c.factor == "preset":
            out[k] = replace(out[k], label=f"{out[k].label} = {c.label}")
    return list(out.values())


# ---------------------------------------------------------------------------------------------------
# running
# ---------------------------------------------------------------------------------------------------
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
    law, medium = law_and_medium(config.law, _custom(model).get("medium", DEFAULTS["medium"]))
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


# ---------------------------------------------------------------------------------------------------
# outputs
# ---------------------------------------------------------------------------------------------------
CSV_FIELDS = ("scenario", "config", "factor", "law", "resolution_scale", "resolution_mm", "elements", "timestep_ms",
              "frame_skip", "cost_ratio", "err_peak_force", "err_rms_force", "err_final_position_mm",
              "err_sinkage_mm", "peak_force_N", "rms_force_N", "final_x_m", "final_y_m", "final_z_m",
              "sinkage_mm", "stability_warnings", "status")


def _num(v, fmt="{:.6g}"):
    return "" if v is None or (isinstance(v, float) and not math.isfinite(v)) else fmt.format(v)


def write_csv(rows: list[Row], path) -> str:
    """One line per scenario and configuration; empty cells where a value does not apply."""
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(CSV_FIELDS)
        for r in rows:
            c = r.config
            w.writerow([r.scenario, c.label, c.factor, c.law, _num(c.resolution_scale), _num(r.resolution * 1e3),
                        r.elements, _num(c.timestep * 1e3), c.frame_skip, _num(r.cost_ratio), _num(r.err_peak),
                        _num(r.err_rms), _num(r.err_position * 1e3), _num(r.err_sinkage * 1e3), _num(r.peak_force),
                        _num(r.rms_force), *(_num(v) for v in r.final_position), _num(r.sinkage * 1e3), r.warnings,
                        r.status])
        fh.flush()
    return str(path)


def _pct(v):
    return "–" if not math.isfinite(v) else f"{100 * v:.2f} %"


def _mm(v):
    return "–" if not math.isfinite(v) else f"{1e3 * v:.2f}"


def markdown_table(rows: list[Row]) -> str:
    """The result table, one section per scenario."""
    out = []
    for name in dict.fromkeys(r.scenario for r in rows):
        sc = SCENARIOS.get(name)
        out.append(f"#### {name}: {sc.description if sc else ''}\n")
        out.append("| configuration | law | resolution | elements | dt x skip | cost (x bare) | peak F err | "
                   "RMS F err | final pos err (mm) | sinkage err (mm) | notes |")
        out.append("|---|---|---|---:|---|---:|---:|---:|---:|---:|---|")
        for r in (r for r in rows if r.scenario == name):
            c = r.config
            notes = []
            if r.status != "ok":
                notes.append("failed (non-finite)")
            if r.warnings:
                notes.append(f"{r.warnings} stability warning(s)")
            if c.law in MODEL_DIFFERENCE_LAWS:
                notes.append("other physics: error = model difference")
            if abs(c.timestep * c.frame_skip - CONTROL_PERIOD) > 1e-12 and not (sc and sc.kinematic):
                notes.append(f"control period {c.timestep * c.frame_skip * 1e3:g} ms: error includes the "
                             "different control signal")
            cost = "–" if not math.isfinite(r.cost_ratio) else f"{r.cost_ratio:.2f}"
            out.append(f"| {c.label} | {c.law} | {r.resolution * 1e3:g} mm | {r.elements} | "
                       f"{c.timestep * 1e3:g} ms x {c.frame_skip} | {cost} | {_pct(r.err_peak)} | {_pct(r.err_rms)} | "
                       f"{_mm(r.err_position)} | {_mm(r.err_sinkage)} | {'; '.join(notes)} |")
        conv = next((r.convergence for r in rows if r.scenario == name and r.config.factor == "reference"
                     and r.convergence), None)
        if conv:
            out.append(f"\nResolution convergence at 1 ms, {conv['coarser']} against {conv['finer']}: peak F "
                       f"{_pct(conv['err_peak'])}, RMS F {_pct(conv['err_rms'])}, final position "
                       f"{_mm(conv['err_position'])} mm, sinkage {_mm(conv['err_sinkage'])} mm (the reference is "
                       "no more certain than this).")
        out.append("")
    return "\n".join(out)


#: preset criteria: worst case over the scenarios of the study (see :func:`recommend_presets`)
FAST_MAX_RMS, FAST_MAX_PEAK = 0.20, 0.10
ACCURATE_MAX_RMS, ACCURATE_MAX_PEAK, ACCURATE_MAX_POSITION = 0.01, 0.01, 0.001
ACCURATE_GAIN = 4.0  # the accurate preset's force errors are at most 1/4 of the default configuration's


def recommend_presets(rows: list[Row]) -> dict:
    """Pick the "fast" and "accurate" configurations from a study's rows.

    Candidates: configurations with the ``rft`` law (the medium's own fit) and the default 10 ms control
    period that ran in every scenario of ``rows`` without failure and with no more stability warnings
    than the scenario's default configuration (a preset must not be less stable than the default).
    Cost is the geometric mean of the cost ratios over the scenarios; errors are the worst case.

    * fast: the cheapest candidate with RMS force error <= 20 % and peak force error <= 10 %;
    * accurate: the cheapest candidate that is not the reference of every scenario, with RMS and peak
      force errors <= 1 % and at most 1/4 of the default configuration's (a clear gain over the default,
      not only a threshold the default may already meet) and final position error <= 1 mm, in every
      scenario whose reference is converged:
      a scenario whose two finest resolutions (at 1 ms) already differ by more than these limits
      (``Row.convergence`` of its reference row) can not tell such errors apart and is left out of
      this criterion (its name is listed under ``"unconverged"``).

    Scenarios registered with ``presets=False`` are reported but take no part: the small hexapod at 10 Hz,
    whose 1 ms default is already 22 % (RMS force) from its 0.5 ms reference, says that fast gaits need a
    finer timestep, which its own env can set, not what the other robots' presets should be.

    Returns ``{name: {"config": Config, "cost": geometric-mean ratio, "err_rms": worst, "err_peak": worst,
    "err_position": worst (m, nan without robots)}}`` (a name is missing when no candidate qualifies).
    """
    rows = [r for r in rows if r.scenario not in SCENARIOS or SCENARIOS[r.scenario].presets]
    scenarios = list(dict.fromkeys(r.scenario for r in rows))
    unconverged = []
    for r in rows:
        conv = r.convergence
        if r.config.factor == "reference" and conv is not None and (
                conv["err_rms"] > ACCURATE_MAX_RMS or conv["err_peak"] > ACCURATE_MAX_PEAK
                or conv["err_position"] > ACCURATE_MAX_POSITION):
            unconverged.append(r.scenario)
    allowed = {sc: 0 for sc in scenarios}
    for r in rows:
        if r.config.factor == "default":
            allowed[r.scenario] = r.warnings
    by_key: dict = {}
    for r in rows:
        by_key.setdefault(r.config.key(), []).append(r)
    cands = []
    for key, rs in by_key.items():
        c = rs[0].config
        if (c.law != REFERENCE_LAW or abs(c.timestep * c.frame_skip - CONTROL_PERIOD) > 1e-12
                or len({r.scenario for r in rs}) != len(scenarios)
                or any(r.status != "ok" or r.warnings > allowed[r.scenario] or not math.isfinite(r.cost_ratio)
                       for r in rs)):
            continue
        conv = [r for r in rs if r.scenario not in unconverged]

        def worst(rs_, attr):
            vals = [getattr(r, attr) for r in rs_ if math.isfinite(getattr(r, attr))]
            return max(vals) if vals else math.nan

        cands.append({"config": c, "cost": float(np.exp(np.mean(np.log([r.cost_ratio for r in rs])))),
                      "err_rms": worst(rs, "err_rms"), "err_peak": worst(rs, "err_peak"),
                      "err_position": worst(rs, "err_position"),
                      "conv": {k: worst(conv, k) for k in ("err_rms", "err_peak", "err_position")},
                      "reference": all(r.config.factor == "reference" for r in rs)})
    cands.sort(key=lambda d: d["cost"])
    defaults = [r for r in rows if r.config.factor == "default" and r.scenario not in unconverged]
    gain = {k: max((getattr(r, k) for r in defaults), default=math.inf) / ACCURATE_GAIN
            for k in ("err_rms", "err_peak")}
    out = {}
    for d in cands:
        public = {k: v for k, v in d.items() if k not in ("conv", "reference")}
        if "fast" not in out and d["err_rms"] <= FAST_MAX_RMS and d["err_peak"] <= FAST_MAX_PEAK:
            out["fast"] = public
        e = d["conv"]
        if ("accurate" not in out and not d["reference"] and e["err_rms"] <= min(ACCURATE_MAX_RMS, gain["err_rms"])
                and e["err_peak"] <= min(ACCURATE_MAX_PEAK, gain["err_peak"])
                and not e["err_position"] > ACCURATE_MAX_POSITION):
            out["accurate"] = public
    out["unconverged"] = unconverged
    return out


def recommendation_text(rows: list[Row]) -> str:
    rec = recommend_presets(rows)
    left_out = [s for s in dict.fromkeys(r.scenario for r in rows) if s in SCENARIOS and not SCENARIOS[s].presets]
    note = f", {', '.join(left_out)} reported but not used" if left_out else ""
    lines = [f"#### Preset choice (worst case over the scenarios above{note}, cost = geometric mean)\n",
             "| preset | criterion | chosen configuration | resolution x | dt x skip | cost (x bare) | worst RMS F err | "
             "worst peak F err | worst final pos err (mm) |", "|---|---|---|---:|---|---:|---:|---:|---:|"]
    crit = {"fast": f"RMS F <= {FAST_MAX_RMS:.0%}, peak F <= {FAST_MAX_PEAK:.0%}",
            "accurate": f"RMS and peak F <= {ACCURATE_MAX_RMS:.0%} and <= 1/{ACCURATE_GAIN:g} of the default's, "
                        f"position <= {ACCURATE_MAX_POSITION * 1e3:g} mm"}
    if rec["unconverged"]:
        crit["accurate"] += f" (not judged on {', '.join(rec['unconverged'])}: reference not converged)"
    for name in ("fast", "accurate"):
        d = rec.get(name)
        if d is None:
            lines.append(f"| {name} | {crit[name]} | none qualifies | | | | | | |")
            continue
        c = d["config"]
        lines.append(f"| {name} | {crit[name]} | {c.label} | {c.resolution_scale:g} | {c.timestep * 1e3:g} ms x "
                     f"{c.frame_skip} | {d['cost']:.2f} | {_pct(d['err_rms'])} | {_pct(d['err_peak'])} | "
                     f"{_mm(d['err_position'])} |")
    return "\n".join(lines) + "\n"


def write_markdown(rows: list[Row], path, title: str = "Speed/accuracy trade study") -> str:
    text = (f"# {title}\n\nCost: wall time per simulated second relative to the bare MuJoCo model (robots: the "
            "rigid-ground twin with the same controller; rigs: the rig without terrain; 1 ms x 10), measured "
            "interleaved in one run. Errors against the reference (finest resolution, 0.5 ms, the medium's own Li "
            "fit): peak and RMS of the net granular force (relative), final position and late-run sinkage (robots "
            "only). See `mjrft.tools.tradeoff`.\n\n" + markdown_table(rows) + "\n" + recommendation_text(rows))
    with open(path, "w") as fh:
        fh.write(text)
        fh.flush()
    return str(path)


def pareto_front(points: list[tuple[float, float]]) -> list[int]:
    """Indices of the points not dominated in (cost, error), both smaller-is-better, sorted by cost."""
    idx = [i for i, (c, e) in enumerate(points) if math.isfinite(c) and math.isfinite(e)]
    idx.sort(key=lambda i: (points[i][0], points[i][1]))
    front, best = [], math.inf
    for i in idx:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


FACTOR_STYLE = {"default": ("k", "o"), "resolution": ("tab:blue", "o"), "law": ("tab:orange", "s"),
                "timestep": ("tab:green", "^"), "frame_skip": ("tab:purple", "v"), "reference": ("tab:red", "*"),
                "preset": ("tab:brown", "D")}
ERROR_FLOOR = 1e-4  # plotted in place of a zero error (the reference) on the log axis


def plot_pareto(rows: list[Row], path) -> str:
    """Cost ratio (x, log) against RMS force error (y, log), one panel per scenario, Pareto front drawn."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.ticker import FuncFormatter, NullFormatter

    names = list(dict.fromkeys(r.scenario for r in rows))
    ncol = 2 if len(names) > 1 else 1
    nrow = math.ceil(len(names) / ncol)
    fig = Figure(figsize=(6.0 * ncol, 4.6 * nrow), constrained_layout=True)
    FigureCanvasAgg(fig)
    for k, name in enumerate(names):
        ax = fig.add_subplot(nrow, ncol, k + 1)
        rs = [r for r in rows if r.scenario == name and r.status == "ok" and math.isfinite(r.cost_ratio)]
        pts = [(r.cost_ratio, max(r.err_rms, ERROR_FLOOR)) for r in rs]
        for factor, (color, marker) in FACTOR_STYLE.items():
            sel = [i for i, r in enumerate(rs) if r.config.factor == factor]
            if sel:
                ax.scatter([pts[i][0] for i in sel], [100 * pts[i][1] for i in sel], c=color, marker=marker,
                           s=60 if factor in ("reference", "preset") else 36, label=factor, zorder=3)
        for i, r in enumerate(rs):
            ax.annotate(r.config.label.replace("resolution ", "res ").replace("law ", ""), (pts[i][0], 100 * pts[i][1]),
                        fontsize=6.5, xytext=(3, 3), textcoords="offset points")
        dry = [i for i, r in enumerate(rs) if r.config.law not in MODEL_DIFFERENCE_LAWS]
        front = [dry[j] for j in pareto_front([pts[i] for i in dry])]
        ax.plot([pts[i][0] for i in front], [100 * pts[i][1] for i in front], "-", color="0.5", lw=1, zorder=2,
                label="Pareto front")
        ax.set_xscale("log")
        ax.set_yscale("log")
        for axis in (ax.xaxis, ax.yaxis):
            axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
            axis.set_minor_formatter(NullFormatter())
        ax.set_xlabel("cost per simulated second (x bare MuJoCo)")
        ax.set_ylabel("RMS force error (%)")
        ax.set_title(f"{name}", fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="best")
    fig.suptitle(f"mjrft speed/accuracy trade (reference plotted at {100 * ERROR_FLOOR:g} %)", fontsize=11)
    fig.savefig(path, dpi=120)
    return str(path)


def write_outputs(rows: list[Row], out_dir, stem: str = "trade_study") -> dict:
    """Write the Markdown table, CSV and Pareto PNG into ``out_dir``; returns their paths."""
    os.makedirs(out_dir, exist_ok=True)
    return {
        "markdown": write_markdown(rows, os.path.join(out_dir, f"{stem}.md")),
        "csv": write_csv(rows, os.path.join(out_dir, f"{stem}.csv")),
        "png": plot_pareto(rows, os.path.join(out_dir, f"{stem}.png")),
    }


# ---------------------------------------------------------------------------------------------------
# command line: mjrft bench
# ---------------------------------------------------------------------------------------------------
def parse_scenarios(text) -> list[str]:
    """``"hexapod,plate"`` (or a list) -> validated scenario names; ``"all"`` -> every scenario."""
    if text is None:
        return list(SCENARIOS)
    items = text if isinstance(text, (list, tuple)) else [text]
    names = [n.strip() for item in items for n in str(item).split(",") if n.strip()]
    if not names:
        raise ValueError(f"no scenario given; valid choices: {', '.join(sorted(SCENARIOS))} (or 'all')")
    if names == ["all"]:
        return list(SCENARIOS)
    for n in names:
        get_scenario(n)
    return list(dict.fromkeys(names))


def add_arguments(parser) -> None:
    parser.add_argument("--scenarios", default="all",
                        help=f"comma-separated scenarios: {', '.join(SCENARIOS)} (default: all)")
    parser.add_argument("--quick", action="store_true",
                        help="small grid (default, 4x coarser, depth_only, 2 ms, a 1/2-resolution reference), half "
                             "the simulated time, 1 timing repeat: about a minute")
    parser.add_argument("--repeats", type=int, default=3, help="timing repeats per configuration (default 3)")
    parser.add_argument("--out", default="bench_results", help="output folder (default ./bench_results)")


def main(args) -> int:
    names = parse_scenarios(args.scenarios)
    repeats = int(check_positive("repeats", args.repeats))
    output_dir(args.out)
    t0 = time.perf_counter()
    rows = run_study(names, quick=args.quick, repeats=repeats)
    paths = write_outputs(rows, args.out)
    print()
    print(markdown_table(rows))
    print(recommendation_text(rows))
    print(f"study took {time.perf_counter() - t0:.0f} s; wrote {paths['markdown']}, {paths['csv']}, {paths['png']}")
    return 0


__all__ = ["Config", "Row", "SCENARIOS", "Scenario", "Trace", "default_grid", "errors", "law_and_medium",
           "markdown_table", "pareto_front", "plot_pareto", "reference_config", "run_scenario", "run_study",
           "write_csv", "write_markdown", "write_outputs"]

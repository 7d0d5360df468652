"""Tests of the speed/accuracy trade study (mjrft.tools.tradeoff), `mjrft bench` and the presets
(mjrft.tools.presets)."""

from __future__ import annotations

import csv
import math
from dataclasses import replace

import mujoco
import numpy as np
import pytest

from mjrft.tools import cli, presets
from mjrft.tools import tradeoff as T
from mjrft.tools.tradeoff import measure
from mjrft.media import MEDIA, generic
from mjrft.settings import element_size_scale, resolve_settings

C = T.Config
# a tiny grid: the model's resolution, 4x and 2x coarser, and a reference at half the resolution and 0.5 ms
TINY = [C("default", "default"), C("resolution x4", "resolution", 4.0), C("resolution x2", "resolution", 2.0),
        T.reference_config(scale=0.5)]
PLATE = replace(T.SCENARIOS["plate"], duration=0.4)  # the plate is in the grains from t = 0.03 s


@pytest.fixture(scope="module")
def plate_rows():
    return T.run_study([PLATE], grid=lambda sc: TINY, repeats=1, progress=None)


def _row(rows, label):
    return next(r for r in rows if r.config.label == label)


def test_reference_has_zero_error(plate_rows):
    ref = _row(plate_rows, "reference")
    assert ref.status == "ok" and ref.config.factor == "reference"
    assert ref.err_peak == 0.0 and ref.err_rms == 0.0
    assert ref.elements > _row(plate_rows, "default").elements
    assert ref.peak_force > 1.0  # the plate is 1.5 cm deep at the end: about 1.6 N
    # convergence of the reference: the two finest resolutions at 1 ms (default against x2 here)
    conv = ref.convergence
    assert conv["finer"] == "default" and conv["coarser"] == "resolution x2"
    assert conv["err_rms"] == pytest.approx(T.errors(_row(plate_rows, "resolution x2").trace,
                                                     _row(plate_rows, "default").trace, True)["err_rms"])


def test_errors_grow_as_resolution_coarsens(plate_rows):
    err = [_row(plate_rows, lab).err_rms for lab in ("reference", "default", "resolution x2", "resolution x4")]
    assert all(math.isfinite(e) for e in err)
    assert err[0] < err[1] < err[2] < err[3], err
    assert err[1] < 0.03  # the default resolution is within 3 % of the reference on this short intrusion
    elements = [_row(plate_rows, lab).elements for lab in ("resolution x4", "resolution x2", "default")]
    assert elements == sorted(elements) and elements[0] < elements[-1]
    # a kinematic rig has no position or sinkage error to report
    assert all(math.isnan(r.err_position) and math.isnan(r.err_sinkage) for r in plate_rows)


def test_costs_are_measured(plate_rows):
    for r in plate_rows:
        assert math.isfinite(r.cost_ratio) and r.cost_ratio > 0
    # Wall-clock ratios between configurations are not compared here: on a noisy 2-core CI machine the
    # reference (4x the elements, 2x the steps) has measured cheaper than the default. What is
    # deterministic is the work each configuration asks for.
    ref, default = _row(plate_rows, "reference"), _row(plate_rows, "default")
    assert ref.elements > 2 * default.elements
    assert ref.config.timestep < default.config.timestep


def test_outputs_written(plate_rows, tmp_path):
    paths = T.write_outputs(plate_rows, tmp_path / "out")
    md = open(paths["markdown"]).read()
    assert "#### plate" in md and "| configuration |" in md and "reference" in md
    assert "Resolution convergence at 1 ms, resolution x2 against default" in md
    for r in plate_rows:
        assert f"| {r.config.label} |" in md
    with open(paths["csv"], newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == len(plate_rows) and tuple(rows[0]) == T.CSV_FIELDS
    ref = next(r for r in rows if r["factor"] == "reference")
    assert float(ref["err_rms_force"]) == 0.0 and ref["err_final_position_mm"] == ""
    assert float(next(r for r in rows if r["config"] == "resolution x4")["err_rms_force"]) > 0
    with open(paths["png"], "rb") as fh:
        assert fh.read(8) == b"\x89PNG\r\n\x1a\n"


def test_robot_scenario_reports_position_and_sinkage():
    hexapod = replace(T.SCENARIOS["hexapod"], duration=0.3)
    rows = T.run_study([hexapod], grid=lambda sc: [C("resolution x4", "resolution", 4.0),
                                                   T.reference_config(scale=1.0)], repeats=1, progress=None)
    coarse, ref = rows
    assert ref.err_position == 0.0 and ref.err_sinkage == 0.0
    assert 0 < coarse.err_position < 0.02 and 0 <= coarse.err_sinkage < 0.005
    assert coarse.sinkage > 0 and np.all(np.isfinite(coarse.final_position))
    assert math.isfinite(coarse.cost_ratio) and coarse.cost_ratio > 0  # against the rigid-ground twin


def test_humanoid_stands_on_one_foot():
    """The humanoid scenario's posture controller: weight on the right board, left foot out of the grains."""
    sc = T.SCENARIOS["humanoid"]
    cfg = C("resolution x4", "resolution", 4.0)
    model = measure._model_for(sc, cfg.timestep)
    data = mujoco.MjData(model)
    terrain = T.make_terrain(sc, model, cfg)
    trace = T.record(sc, model, data, terrain, cfg)
    assert trace.time[-1] == pytest.approx(sc.duration)
    left, right = model.body("left_foot").id, model.body("right_foot").id
    weight = model.body_subtreemass[0] * 9.81
    assert terrain.wrench[right, 2] == pytest.approx(weight, rel=0.1)
    assert abs(terrain.wrench[left, 2]) < 0.02 * weight and terrain.sinkage()[left] == 0.0
    pelvis = model.body("pelvis").id
    assert data.xpos[pelvis, 2] > 0.7 and np.arccos(data.xmat[pelvis, 8]) < 0.15


def test_default_grid():
    for name, sc in T.SCENARIOS.items():
        grid = T.default_grid(sc)
        labels = [c.label for c in grid]
        assert len({c.key() for c in grid}) == len(grid)
        assert sum(c.factor == "reference" for c in grid) == 1
        ref = next(c for c in grid if c.factor == "reference")
        assert ref.law == "rft" and ref.timestep == min(T.TIMESTEPS)
        assert ref.resolution_scale == min(sc.resolution_scales)
        for law in ("depth_only", "rft_generic", "rft3d"):
            assert f"law {law}" in labels
        assert ("law wet" in labels) == (name in ("plate", "cleg"))
        assert ("law hybrid" in labels) == (name == "cleg")
        assert any("preset fast" in lab for lab in labels) and any("preset accurate" in lab for lab in labels)
    quick = T.default_grid(T.SCENARIOS["hexapod"], quick=True)
    assert len(quick) == 5 and quick[-1].factor == "reference"


def test_law_variants():
    law, med = T.law_and_medium("rft_generic", "poppy_cp")
    assert law == "rft" and med.zeta == MEDIA["poppy_cp"].zeta
    np.testing.assert_allclose(med.coeffs, np.array(generic.coeffs) * MEDIA["poppy_cp"].zeta / generic.zeta)
    assert T.law_and_medium("rft", "poppy_cp") == ("rft", MEDIA["poppy_cp"])
    with pytest.raises(ValueError, match="valid choices: .*rft_generic"):
        T.law_and_medium("magic", "poppy_cp")


def test_pareto_front():
    pts = [(1.0, 0.5), (2.0, 0.1), (3.0, 0.2), (1.5, 0.6), (4.0, 0.0), (math.nan, 0.0)]
    assert T.pareto_front(pts) == [0, 1, 4]


def _synthetic(scenario, label, scale, dt, fs, cost, rms, peak=0.0, pos=0.0, warnings=0, factor="resolution"):
    r = T.Row(scenario, C(label, factor, scale, "rft", dt, fs), 0.005 * scale, 100)
    r.cost_ratio, r.err_rms, r.err_peak, r.err_position, r.warnings = cost, rms, peak, pos, warnings
    return r


def test_recommend_presets():
    rows = []
    for sc in ("a", "b"):
        rows += [_synthetic(sc, "x4", 4, 1e-3, 10, 1.5, 0.15, 0.05, 0.01),
                 _synthetic(sc, "x8", 8, 1e-3, 10, 1.2, 0.40, 0.20, 0.03),  # too inaccurate for fast
                 _synthetic(sc, "dt2", 1, 2e-3, 5, 1.0, 0.05, 0.01, 0.001, warnings=2),  # warns: excluded
                 _synthetic(sc, "x1", 1, 1e-3, 10, 3.0, 0.05, 0.001, 0.005),
                 _synthetic(sc, "acc", 0.5, 5e-4, 20, 14.0, 0.004, 0.001, 0.0004),
                 _synthetic(sc, "ref", 0.25, 5e-4, 20, 60.0, 0.0, 0.0, 0.0, factor="reference")]
    rec = T.recommend_presets(rows)
    assert rec["fast"]["config"].label == "x4" and rec["fast"]["cost"] == pytest.approx(1.5)
    assert rec["accurate"]["config"].label == "acc" and rec["accurate"]["err_rms"] == pytest.approx(0.004)
    assert "fast" in T.recommendation_text(rows) and "acc" in T.recommendation_text(rows)
    # as many warnings as the scenario's default configuration is allowed, more is not
    rows += [_synthetic(sc, "default", 1, 1e-3, 10, 3.0, 0.05, 0.001, 0.005, warnings=2, factor="default")
             for sc in ("a", "b")]
    rows = [r for r in rows if r.config.label != "x1"]
    assert T.recommend_presets(rows)["fast"]["config"].label == "dt2"
    next(r for r in rows if r.config.label == "dt2" and r.scenario == "a").warnings = 3  # more than the default
    assert T.recommend_presets(rows)["fast"]["config"].label == "x4"
    assert T.recommend_presets(rows)["unconverged"] == []


def test_recommend_skips_unconverged_scenarios_for_accurate():
    rows = []
    for sc, acc_rms in (("a", 0.004), ("b", 0.08)):  # "b" misses 1 % because its reference is unconverged
        rows += [_synthetic(sc, "acc", 0.5, 5e-4, 20, 14.0, acc_rms), _synthetic(sc, "x1", 1, 1e-3, 10, 3.0, 0.1),
                 _synthetic(sc, "ref", 0.25, 5e-4, 20, 60.0, 0.0, factor="reference")]
    assert "accurate" not in T.recommend_presets(rows)
    rows[-1].convergence = {"err_rms": 0.05, "err_peak": 0.01, "err_position": 0.002}  # "b": finest two differ
    rec = T.recommend_presets(rows)
    assert rec["unconverged"] == ["b"] and rec["accurate"]["config"].label == "acc"
    assert rec["accurate"]["err_rms"] == pytest.approx(0.08)  # the worst case still reports every scenario
    assert "not judged on b" in T.recommendation_text(rows)
    # accurate must also cut the default configuration's force errors four-fold
    rows += [_synthetic(sc, "default", 1, 1e-3, 10, 3.0, 0.008, 0.004, 0.0002, factor="default") for sc in "ab"]
    assert "accurate" not in T.recommend_presets(rows)  # "acc" has 0.4 % RMS on "a": more than 0.8 % / 4
    rows[0].err_rms = 0.001
    assert T.recommend_presets(rows)["accurate"]["config"].label == "acc"
    # one configuration may qualify for both presets
    rows = [_synthetic(sc, "acc", 0.5, 5e-4, 20, 1.0, 0.001) for sc in "ab"]
    rec = T.recommend_presets(rows)
    assert rec["fast"]["config"].label == rec["accurate"]["config"].label == "acc"


def test_parse_scenarios():
    assert T.parse_scenarios("all") == list(T.SCENARIOS)
    assert T.parse_scenarios("hexapod, plate,hexapod") == ["hexapod", "plate"]
    with pytest.raises(ValueError, match="nope.*valid choices: cleg, hexapod, hexapod_small, humanoid, plate"):
        T.parse_scenarios("hexapod,nope")


def test_cli_bad_input(capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main(["bench", "--scenarios", "sandcastle"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "sandcastle" in err and "valid choices" in err
    with pytest.raises(SystemExit) as exc:
        cli.main(["bench", "--repeats", "0"])
    assert exc.value.code == 2 and "repeats" in capsys.readouterr().err


def test_cli_writes_outputs(monkeypatch, tmp_path, capsys):
    monkeypatch.setitem(T.SCENARIOS, "plate", replace(PLATE, duration=0.2))
    monkeypatch.setattr(measure, "default_grid", lambda sc, quick=False: [TINY[1], TINY[3]])  # run_study's grid
    out = tmp_path / "bench"
    assert cli.main(["bench", "--scenarios", "plate", "--quick", "--out", str(out)]) == 0
    for name in ("trade_study.md", "trade_study.csv", "trade_study.png"):
        assert (out / name).stat().st_size > 0
    assert "Preset choice" in capsys.readouterr().out


# ------------------------------------------------------------------------------------------ presets
def test_get_preset_and_resolve():
    assert set(presets.PRESETS) == {"fast", "default", "accurate"}
    for p in presets.PRESETS.values():  # every preset keeps the 10 ms control period
        assert p["timestep"] * p["frame_skip"] == pytest.approx(0.01)
    fast = presets.get_preset("fast")
    fast["law"] = "changed"
    assert presets.PRESETS["fast"]["law"] == "rft"  # a copy
    with pytest.raises(ValueError, match="unknown preset 'turbo'; valid choices: accurate, default, fast"):
        presets.get_preset("turbo")
    got = presets.resolve("accurate", law="depth_only", frame_skip=4)
    assert got == presets.EnvSettings(medium=None, law="depth_only", resolution=None, resolution_scale=0.5,
                                      timestep=0.0005, frame_skip=4)
    assert presets.resolve(None) == presets.EnvSettings(medium=None, law=None, resolution=None, resolution_scale=1.0,
                                                        timestep=None, frame_skip=presets.FRAME_SKIP)
    assert presets.resolve("fast", resolution=0.01).resolution_scale == 1.0
    # a robot's own step per preset replaces the preset's generic one; an explicit argument still wins
    steps = {"accurate": (0.00025, 40), "fast": (None, 10)}
    got = presets.resolve("accurate", preset_steps=steps)
    assert (got.timestep, got.frame_skip, got.resolution_scale) == (0.00025, 40, 0.5)
    assert presets.resolve("fast", preset_steps=steps).timestep is None  # the model's own
    assert presets.resolve("default", preset_steps=steps).timestep == 0.001  # no own step: the generic one
    assert presets.resolve("accurate", timestep=0.001, preset_steps=steps).timestep == 0.001
    # a robot's own step only when neither preset, timestep nor frame_skip is given (then each is checked)
    own = (0.0005, 20)
    assert (presets.resolve(None, own_step=own).timestep, presets.resolve(None, own_step=own).frame_skip) == own
    for kw, step in (({"preset": "fast"}, (0.001, 10)), ({"timestep": 0.002}, (0.002, presets.FRAME_SKIP)),
                     ({"frame_skip": 5}, (None, 5))):
        got = presets.resolve(kw.pop("preset", None), own_step=own, **kw)
        assert (got.timestep, got.frame_skip) == step
    with pytest.raises(ValueError, match="frame_skip must be an integer >= 1"):
        presets.resolve(None, own_step=(0.0005, 0))
    assert presets.resolve(None, medium="poppy_lp").medium is MEDIA["poppy_lp"]  # looked up once, here
    for bad, match in (({"medium": "mud"}, "unknown medium 'mud'; valid choices: "),
                       ({"law": "fluid"}, "unknown law 'fluid'; valid choices: "),
                       ({"resolution": -1.0}, "resolution must be finite and > 0"),
                       ({"timestep": 0.0}, "timestep must be finite and > 0"),
                       ({"frame_skip": 2.5}, "frame_skip must be an integer >= 1")):
        with pytest.raises(ValueError, match=match):
            presets.resolve("fast", **bad)


@pytest.fixture
def gymnasium():
    gym = pytest.importorskip("gymnasium")
    pytest.importorskip("imageio")  # gymnasium.envs.mujoco needs it
    import mjrft.envs  # noqa: F401  (registers the ids)

    return gym


def test_one_rule_scales_the_element_size_only_when_no_resolution_is_given():
    """The preset's scale and the terrain's resolution_scale follow mjrft.settings.element_size_scale."""
    assert element_size_scale(None, 4.0) == 4.0 and element_size_scale(0.01, 4.0) == 1.0
    with pytest.raises(ValueError, match="resolution_scale must be finite and > 0"):
        element_size_scale(None, 0.0)
    for name, p in presets.PRESETS.items():
        assert presets.resolve(name).resolution_scale == element_size_scale(None, p["resolution_scale"])
        assert presets.resolve(name, resolution=0.01).resolution_scale == element_size_scale(0.01, p["resolution_scale"])


def test_env_presets(gymnasium):
    """An env's presets take its robot's own steps (fast, default: the own step; accurate: the measured one)."""
    env = gymnasium.make("mjrft/HexapodSand-v0", preset="fast", max_episode_steps=5)
    u = env.unwrapped
    assert u.terrain.resolution == 4 * resolve_settings(u.model).resolution == pytest.approx(0.02)
    assert (u.model.opt.timestep, u.frame_skip) == (0.0005, 20) and u.dt == pytest.approx(0.01)
    env.reset(seed=0)
    obs, reward, *_ = env.step(np.zeros(6, np.float32))
    assert np.all(np.isfinite(obs)) and np.isfinite(reward)
    env.close()
    u = gymnasium.make("mjrft/HexapodSand-v0", preset="accurate").unwrapped
    assert (u.model.opt.timestep, u.frame_skip) == (0.00025, 40) and u.metadata["render_fps"] == 100
    assert u.terrain.resolution == pytest.approx(0.0025) and u.terrain.law == "rft"
    # "default" is the env without a preset
    plain, default = (gymnasium.make("mjrft/BipedSand-v0", **kw).unwrapped for kw in ({}, {"preset": "default"}))
    assert (default.model.opt.timestep, default.frame_skip, default.terrain.implicit, default.terrain.resolution) == (
        plain.model.opt.timestep, plain.frame_skip, plain.terrain.implicit, plain.terrain.resolution)
    u = gymnasium.make("mjrft/HumanoidSand-v0", preset="accurate").unwrapped
    assert (u.model.opt.timestep, u.frame_skip) == (0.001, 10) and u.terrain.resolution == pytest.approx(0.01)
    assert gymnasium.make("mjrft/HexapodRigid-v0", preset="accurate").unwrapped.model.opt.timestep == 0.0001
    # explicit keyword arguments win over the robot's preset step
    u = gymnasium.make("mjrft/HexapodSand-v0", preset="accurate", timestep=0.0005, frame_skip=20).unwrapped
    assert (u.model.opt.timestep, u.frame_skip) == (0.0005, 20)


def test_env_explicit_kwargs_override_preset(gymnasium):
    env = gymnasium.make("mjrft/HexapodSand-v0", preset="accurate", law="depth_only", resolution=0.01,
                         timestep=0.001, frame_skip=5, max_episode_steps=5)
    u = env.unwrapped
    assert u.terrain.law == "depth_only" and u.terrain.resolution == 0.01
    assert u.model.opt.timestep == 0.001 and u.frame_skip == 5
    env.close()
    # no preset: the model's own resolution and the sand hexapod's own step (mjrft.envs.hexapod.SAND_TIMESTEP)
    from mjrft.envs.hexapod import SAND_FRAME_SKIP, SAND_TIMESTEP

    u = gymnasium.make("mjrft/HexapodSand-v0", max_episode_steps=5).unwrapped
    assert u.terrain.resolution == 0.005 and u.model.opt.timestep == SAND_TIMESTEP == 0.0005
    assert u.frame_skip == SAND_FRAME_SKIP == 20


def test_env_unknown_preset_lists_valid_names(gymnasium):
    with pytest.raises(ValueError, match="unknown preset 'turbo'; valid choices: accurate, default, fast"):
        gymnasium.make("mjrft/HexapodSand-v0", preset="turbo")
    with pytest.raises(ValueError, match="timestep"):
        gymnasium.make("mjrft/BipedSand-v0", timestep=-0.001)


def test_scenarios_registered_without_presets_do_not_choose_them():
    assert not T.SCENARIOS["hexapod_small"].presets and T.SCENARIOS["hexapod"].presets
    rows = [_synthetic(sc, "x4", 4, 1e-3, 10, 1.5, rms) for sc, rms in (("a", 0.15), ("hexapod_small", 0.5))]
    assert T.recommend_presets(rows)["fast"]["config"].label == "x4"  # the small hexapod's 50 % is not counted
    assert "hexapod_small reported but not used" in T.recommendation_text(rows)


def test_the_biped_fast_preset_halves_its_step_where_its_coarse_feet_chatter(gymnasium):
    """benchmarks/env_presets.py: the fast preset's 4x coarser feet chatter under the 30 deg rect gait at the biped's
    own 2 ms implicit step; its fast step (1 ms) does not (no preset warns more than the default)."""
    import warnings

    from mjrft import TerrainStabilityWarning
    from mjrft.train.evaluate import evaluate

    def warned(**kw):
        with warnings.catch_warnings(record=True) as rec:
            warnings.simplefilter("always", TerrainStabilityWarning)
            evaluate("rect:angle=30", "mjrft/BipedSand-v0", episodes=1, seed=0,
                     env_kwargs=dict(pitch_free=False, preset="fast", episode_seconds=4.0, **kw))
        return sum(issubclass(w.category, TerrainStabilityWarning) for w in rec)

    assert gymnasium.make("mjrft/BipedSand-v0", preset="fast").unwrapped.model.opt.timestep == 0.001
    assert warned() == 0
    assert warned(timestep=0.002, frame_skip=5) > 0  # control: the own step

"""A robot from MuJoCo Menagerie on sand: the Unitree Go2 (its MJX variant, vendored with its collision geometry
under models/third_party/unitree_go2/) standing on its position servos and trotting, on the CPU path
(``GranularTerrain(model, "poppy_cp", floor="auto")`` at the model's own 2 ms step) and in MJX
(``mjrft.mjx.Sand``, float32)."""

from __future__ import annotations

import os
import warnings

import mujoco
import numpy as np
import pytest

import mjrft
import mjrft.models
from mjrft.errors import TerrainStabilityWarning, ValidityRangeWarning

GO2_DIR = os.path.join(os.path.dirname(mjrft.models.__file__), "third_party", "unitree_go2")
GO2 = os.path.join(GO2_DIR, "scene_mjx.xml")
MASS = 15.206408  # kg: the sum of the upstream model's <inertial> masses
FEET = ("FL", "FR", "RL", "RR")  # the foot spheres, on the bodies <leg>_calf
REST = 0.2  # s: the window at the end of the standing run over which the load is averaged


def go2(sand: bool = True, implicit: bool = True):
    """(model, data at the "home" keyframe, its servo targets in ctrl, the terrain or None)."""
    m = mujoco.MjModel.from_xml_path(GO2)
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key("home").id)
    terrain = mjrft.GranularTerrain(m, "poppy_cp", floor="auto", implicit=implicit) if sand else None
    return m, d, terrain


def weight(m) -> float:
    return float(m.body_subtreemass[0]) * -float(m.opt.gravity[2])


def stand(m, d, terrain, seconds: float = 1.5) -> np.ndarray:
    """Step ``seconds`` holding the home pose; the net vertical granular force over the weight at every step."""
    load = np.empty(int(round(seconds / m.opt.timestep)))
    for i in range(len(load)):
        terrain.step(d)
        load[i] = terrain.wrench[:, 2].sum() / weight(m)
    return load


def trot_ctrl(m, t: float, stride: float, lift: float = 0.8, freq: float = 1.5) -> np.ndarray:
    """Servo targets of a trot around the home pose: the diagonal pairs FL+RR and FR+RL in antiphase; each leg's
    thigh swings ``stride`` rad either side of home (a larger thigh angle puts the foot further back: a positive
    stride pushes the body forward in stance), its knee flexes by up to ``lift`` rad in the swing half."""
    phase = 2 * np.pi * freq * t + np.array([0.0, np.pi, np.pi, 0.0])  # actuators FL, FR, RL, RR
    ctrl = m.key("home").ctrl.reshape(4, 3).copy()
    ctrl[:, 1] += stride * np.cos(phase)
    ctrl[:, 2] -= lift * np.maximum(np.sin(phase), 0.0)
    return ctrl.ravel()


# ----------------------------------------------------------------- the vendored model


def test_vendored_go2_keeps_the_collision_geometry_and_inertials():
    m = mujoco.MjModel.from_xml_path(GO2)
    assert os.path.isfile(os.path.join(GO2_DIR, "LICENSE")) and os.path.isfile(os.path.join(GO2_DIR, "README.md"))
    assert m.nmesh == 0 and m.opt.timestep == 0.002 and m.opt.integrator == mujoco.mjtIntegrator.mjINT_EULER
    assert m.nu == 12 and m.nkey == 1 and m.key("home").qpos[2] == pytest.approx(0.27)
    floor = m.geom("floor").id
    assert m.geom_type[floor] == mujoco.mjtGeom.mjGEOM_PLANE
    robot = [g for g in range(m.ngeom) if g != floor]
    assert len(robot) == 23 and all(m.geom_type[g] == mujoco.mjtGeom.mjGEOM_SPHERE for g in robot)
    assert all(m.geom_contype[g] and m.geom_conaffinity[g] for g in robot)  # every geom left collides
    assert float(m.body_subtreemass[0]) == pytest.approx(MASS, rel=1e-12)
    assert m.geom_size[m.geom("FL").id, 0] == pytest.approx(0.0175)


# ----------------------------------------------------------------- CPU path


def test_go2_stands_on_sand_and_carries_its_weight():
    m, d, terrain = go2()
    assert terrain.floor == m.geom("floor").id and terrain.surface == 0.0
    assert (m.geom_contype[terrain.floor], m.geom_conaffinity[terrain.floor]) == (0, 0)
    with warnings.catch_warnings():
        warnings.simplefilter("error", TerrainStabilityWarning)  # the implicit step is stable at 2 ms
        warnings.simplefilter("ignore", ValidityRangeWarning)  # the feet go deeper than Li 2013's plates did
        load = stand(m, d, terrain)
    rest = load[-int(round(REST / m.opt.timestep)):]
    assert abs(rest.mean() - 1.0) < 0.02  # measured 1.00002
    assert np.abs(rest - 1.0).max() < 1e-3  # every step of the last 0.2 s (measured 3.3e-4)
    assert load.max() < 3.0  # the landing from the home pose (measured 2.26)
    assert np.all(np.isfinite(d.qpos)) and np.abs(d.qvel).max() < 0.01 and d.ncon == 0
    # the legs carry it, the feet deep in the loose grains, the trunk above them
    calves = [m.body(f"{f}_calf").id for f in FEET]
    assert terrain.wrench[calves, 2].sum() / weight(m) > 0.97  # measured 0.991
    sink = terrain.sinkage()
    assert np.all((0.10 < sink[calves]) & (sink[calves] < 0.20))  # measured 146-154 mm
    assert sink[m.body("base").id] < 0.02 and 0.07 < d.qpos[2] < 0.14  # measured 6 mm; 0.104 m
    assert abs(d.qpos[3]) > 0.999  # upright


def test_go2_without_the_granular_force_falls_through_the_surface():
    """Control: the floor's contacts are gone, so nothing but the grains holds the robot up."""
    m, d, terrain = go2()
    mujoco.mj_step(m, d, int(round(1.5 / m.opt.timestep)))
    assert d.qpos[2] < -5.0 and d.ncon == 0  # free fall (measured -10.8 m)


def test_go2_stands_on_its_rigid_floor():
    """Control: on the unchanged scene the servos hold the home pose on MuJoCo's floor, the sinkage above is the
    sand's."""
    m, d, _ = go2(sand=False)
    mujoco.mj_step(m, d, int(round(1.5 / m.opt.timestep)))
    assert d.ncon >= 4 and 0.22 < d.qpos[2] < 0.29 and np.abs(d.qvel).max() < 0.05  # measured 0.248 m


def test_go2_explicit_step_at_2ms_is_past_its_limit():
    """Control for the per-step bound: the explicit granular step at the model's 2 ms is beyond the feet's
    stability limit (about 1.4 ms); the terrain says so and the load oscillates from step to step."""
    m, d, terrain = go2(implicit=False)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        load = stand(m, d, terrain)
    assert any(issubclass(w.category, TerrainStabilityWarning) and "calf" in str(w.message) for w in caught)
    rest = load[-int(round(REST / m.opt.timestep)):]
    assert np.ptp(rest) > 0.2  # measured 0.63 to 1.37 times the weight


@pytest.mark.parametrize("stride, sign", [(0.3, 1.0), (-0.3, -1.0)], ids=["forward", "reversed"])
def test_go2_trots_on_sand(stride, sign):
    m, d, terrain = go2()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ValidityRangeWarning)
        terrain.step(d, int(round(0.5 / m.opt.timestep)))  # settle first
        start, t0, load = d.qpos[:3].copy(), d.time, []
        for _ in range(int(round(2.5 / m.opt.timestep))):
            d.ctrl[:] = trot_ctrl(m, d.time - t0, stride)
            terrain.step(d)  # raises NonFiniteError on a non-finite state or force
            load.append(terrain.wrench[:, 2].sum() / weight(m))
            assert 0.04 < d.qpos[2] < 0.2 and d.qpos[3] > 0.97, d.time  # neither buried nor tipped over
    moved = d.qpos[:3] - start
    assert sign * moved[0] > 0.15  # measured +0.33 m forward, -0.24 m reversed in 2.5 s
    assert abs(moved[1]) < 0.5 * abs(moved[0])
    assert abs(np.mean(load) - 1.0) < 0.02  # the grains carry it throughout the gait (vertical momentum balance; measured 0.999, 0.998)


# ----------------------------------------------------------------- MJX


@pytest.mark.slow
def test_go2_stands_on_sand_in_mjx():
    """The same robot in MJX (float32) holding its home pose with the explicit granular step: the model's 2 ms is
    past the explicit limit there as on the CPU (the load oscillates by +-37 %), so the model runs at 0.5 ms
    (``model.opt.timestep`` set before ``put_model``), a third of the limit. At 2 ms the implicit step holds it
    (tests/mjrft/mjx/test_mjx_implicit.py)."""
    pytest.importorskip("jax", reason="mjrft.mjx needs the optional extra mjrft[mjx] (JAX)")
    pytest.importorskip("mujoco.mjx", reason="mjrft.mjx needs mujoco-mjx (mjrft[mjx])")
    import jax.numpy as jnp

    import mjrft.mjx as rmjx

    m = mujoco.MjModel.from_xml_path(GO2)
    m.opt.timestep = 0.0005
    sand = rmjx.Sand(m, "poppy_cp", floor="auto")
    assert (m.geom_contype[m.geom("floor").id], m.geom_conaffinity[m.geom("floor").id]) == (0, 0)
    from mjrft.mjx.compare import stand as mjx_stand

    home = m.key("home")
    d, state, load = mjx_stand(sand, m, home.qpos, home.ctrl, 1.5)
    assert d.qpos.dtype == jnp.float32
    sand.check(state)  # NonFiniteError if any state or force went non-finite
    rest = load[-int(round(REST / m.opt.timestep)):]
    assert abs(rest.mean() - 1.0) < 0.02  # measured 1.000005
    assert np.abs(rest - 1.0).max() < 1e-3 and abs(rmjx.resting_load(sand, state) - 1.0) < 1e-3  # measured 1.2e-5
    # the CPU path at the model's 2 ms with the implicit step rests at the same height
    mc, dc, terrain = go2()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ValidityRangeWarning)
        stand(mc, dc, terrain)
    assert abs(float(d.qpos[2]) - dc.qpos[2]) < 1e-3  # measured 0.104 m both, 0.14 mm apart
    calves = [m.body(f"{f}_calf").id for f in FEET]
    np.testing.assert_allclose(np.asarray(state.sinkage)[calves], terrain.sinkage()[calves], atol=1e-3)
    # control: the same compiled step with the grains' stresses scaled by 1e-6 (a per-world medium,
    # state.params) lets it fall through the surface: nothing else holds it
    soft = sand.init(params=sand.params_of("poppy_cp", stress_scale=1e-6))
    d, state, _ = mjx_stand(sand, m, home.qpos, home.ctrl, 1.5, state=soft)
    assert float(d.qpos[2]) < -5.0  # free fall

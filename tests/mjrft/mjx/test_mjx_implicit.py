"""The implicit granular step in MJX (``mjrft.mjx.Sand(..., implicit=True)``, ``Sand.step``): the applied wrench equals
the CPU terrain's implicit step on recorded walking states (float64), a G that is zeroed gives the explicit wrench
and is rejected by that comparison, its pieces (the 6x6 of the spring moments, the CoM jacobians, the smooth
acceleration with the applied wrench) equal MuJoCo's, non-finite results are reported and not applied, and the
Go2 rests at its own 2 ms step where the explicit step oscillates."""

from __future__ import annotations

import copy
import os
import types
import warnings

import mujoco
import numpy as np
import pytest

jax = pytest.importorskip("jax", reason="mjrft.mjx needs the optional extra mjrft[mjx] (JAX)")
pytest.importorskip("mujoco.mjx", reason="mjrft.mjx needs mujoco-mjx (mjrft[mjx])")

import jax.numpy as jnp  # noqa: E402
from mujoco import mjx  # noqa: E402

import mjrft  # noqa: E402
import mjrft.models  # noqa: E402
import mjrft.mjx as rmjx  # noqa: E402
from mjrft import stability  # noqa: E402
from mjrft.errors import NonFiniteError  # noqa: E402
from mjrft.mjx.compare import replay_steps, stand  # noqa: E402
from mjrft.mjx.terrain import k6  # noqa: E402

HEXAPOD = mjrft.models.model_path("hexapod")
GO2 = os.path.join(os.path.dirname(mjrft.models.__file__), "third_party", "unitree_go2", "scene_mjx.xml")
MODES = {"memory": {}, "viscous": {"yield_displacement": 0.0, "v_eps": 0.1}}  # viscous: a wide ramp, for dampers below it
TOL = 1e-9  # float64: largest |MJX - CPU| over the largest |CPU| of the applied wrench


def tripod_ctrl(t: float) -> np.ndarray:
    """Hip servo targets of the hexapod's 2 Hz alternating tripod."""
    return 2 * np.pi * 2 * t + np.array([0.0, np.pi, 0.0, np.pi, 0.0, np.pi])


def replay_walk(kw: dict, every: int = 50, count: int = 12):
    """Walk the hexapod on the CPU path with the implicit step (``terrain.step(data, 1)``); every ``every`` steps take
    the MjData before the step and the memory, and replay that one step on a second implicit terrain and on an
    explicit one bound to copies of it. Returns (model, the implicit replay terrain, [(data before, memory,
    implicit wrench, explicit wrench, qvel after the implicit step)])."""
    model = mujoco.MjModel.from_xml_path(HEXAPOD)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        out = replay_steps(model, kw, every * count, every, ctrl=tripod_ctrl)
        implicit = mjrft.GranularTerrain(model, implicit=True, **kw)
    return model, implicit, out


def _zero_springs(sand: rmjx.Sand) -> rmjx.Sand:
    """``sand`` with every element's T k replaced by 0 (G = 0: the implicit system becomes the identity)."""
    sand._spring_tk = lambda f_yield, ml, vel, dt, u: jnp.zeros(f_yield.shape[:-1], f_yield.dtype)
    return sand


def relative(a, b) -> float:
    return float(np.abs(np.asarray(a) - b).max() / np.abs(b).max())


# ----------------------------------------------------------------- pieces (fast)


def test_implicit_terrain_is_accepted():
    model = mujoco.MjModel.from_xml_path(HEXAPOD)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        terrain = mjrft.GranularTerrain(model, implicit=True)
    sand = rmjx.Sand.from_terrain(terrain)
    assert sand.implicit and not rmjx.Sand(model).implicit
    assert rmjx.Sand(model, implicit=True).implicit
    np.testing.assert_array_equal(sand.imp_rows, np.unique(terrain.elem_body))
    # another MJX implementation is refused by name for the implicit step (it needs MJX's mass-matrix factor)
    fake = types.SimpleNamespace(impl="warp", opt=types.SimpleNamespace(timestep=1e-3))
    with pytest.raises(NotImplementedError, match="JAX implementation only"):
        sand.step(fake, None, sand.init())


def test_k6_equals_the_kernels():
    rng = np.random.default_rng(3)
    moments = rng.normal(size=(4, 10))
    expected = np.zeros((4, 6, 6))
    for i in range(4):
        stability.add_k6(expected[i], moments[i], 1.0)
    with jax.enable_x64(True):
        got = np.asarray(k6(jnp.asarray(moments)))
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-15)
    # control: the moments read in another order (xy and xz swapped) give another matrix
    swapped = moments[:, [0, 1, 2, 3, 4, 6, 5, 7, 8, 9]]
    with jax.enable_x64(True):
        assert np.abs(np.asarray(k6(jnp.asarray(swapped))) - expected).max() > 0.1


def test_com_jacobians_equal_mujocos():
    model, _, states = replay_walk({}, every=300, count=1)
    data = copy.copy(states[0][0])
    mujoco.mj_forward(model, data)
    sand = rmjx.Sand(model)
    with jax.enable_x64(True):
        got = np.asarray(sand.com_jacobians(mjx.put_data(model, data)))
    expected, at_origin = (np.zeros((6 * sand.imp_rows.size, model.nv)) for _ in range(2))
    for i, b in enumerate(sand.imp_rows):
        mujoco.mj_jacBodyCom(model, data, expected[6 * i:6 * i + 3], expected[6 * i + 3:6 * i + 6], int(b))
        mujoco.mj_jacBody(model, data, at_origin[6 * i:6 * i + 3], at_origin[6 * i + 3:6 * i + 6], int(b))
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-14)
    # control: the jacobian at the body's frame origin (not its CoM) is told apart
    assert np.abs(got - at_origin).max() > 1e-3


@pytest.fixture(scope="module")
def corrected():
    """(model, implicit terrain, data before the step, memory) of the replayed walking state (memory mode) whose
    implicit wrench differs most from the explicit one."""
    model, terrain, states = replay_walk(MODES["memory"])
    before, u = max(states, key=lambda s: relative(s[3], s[2]) if np.abs(s[2]).max() > 0 else 0.0)[:2]
    return model, terrain, before, u


# ----------------------------------------------------------------- against the CPU implicit step (float64)


@pytest.fixture(scope="module", params=list(MODES))
def replayed(request):
    return request.param, *replay_walk(MODES[request.param])


@pytest.mark.slow
def test_applied_wrench_equals_the_cpu_implicit_step(replayed):
    """One MJX step from each recorded state with the recorded memory applies the CPU implicit step's wrench
    (measured: 2.5e-15 of the largest value, memory mode; the states after the step agree to 2e-15 in qvel); in the
    memory mode a Sand whose G is zeroed applies the explicit wrench instead, which the same comparison rejects,
    with the same memory."""
    mode, model, terrain, states = replayed
    with jax.enable_x64(True):
        mx = mjx.put_model(model)
        sand = rmjx.Sand.from_terrain(terrain)
        step = jax.jit(sand.step)
        zero = jax.jit(_zero_springs(rmjx.Sand.from_terrain(terrain)).step) if mode == "memory" else None
        corrected = 0
        for before, u, f_implicit, f_explicit, qvel in states:
            d, state = step(mx, mjx.put_data(model, before), sand.init()._replace(u=jnp.asarray(u)))
            assert int(state.bad_body) == -1
            assert relative(state.wrench, f_implicit) <= TOL
            assert relative(d.qvel, qvel) <= TOL
            np.testing.assert_array_equal(np.asarray(d.xfrc_applied), before.xfrc_applied)  # the caller's kept
            if relative(f_explicit, f_implicit) > 1e-3:
                corrected += 1
                if zero is not None:
                    # control: G = 0 gives the explicit wrench (F' = F), rejected by the comparison above
                    dz, sz = zero(mx, mjx.put_data(model, before), sand.init()._replace(u=jnp.asarray(u)))
                    assert relative(sz.wrench, f_explicit) <= TOL
                    assert relative(sz.wrench, f_implicit) > 1e3 * TOL
                    np.testing.assert_array_equal(np.asarray(sz.u), np.asarray(state.u))  # the explicit memory
        assert corrected >= 3, f"only {corrected} of {len(states)} states have an implicit correction"  # measured 5-6


@pytest.mark.slow
def test_smooth_acceleration_includes_the_applied_wrench(corrected):
    """The implicit step adds the applied wrench to qfrc_smooth / qacc_smooth as J^T F' and M^-1 J^T F': equal to
    what MJX's fwd_acceleration computes from xfrc_applied (control: they differ from the values without it)."""
    model, terrain, before, u = corrected
    with jax.enable_x64(True):
        mx = mjx.put_model(model)
        sand = rmjx.Sand.from_terrain(terrain)

        @jax.jit
        def stages(d, state):
            d = mjx.fwd_velocity(mx, mjx.fwd_position(mx, d))
            smooth = mjx.fwd_acceleration(mx, mjx.fwd_actuation(mx, d))
            d, state = sand._implicit_stage(mx, d, state, mx.opt.timestep)
            return smooth, d, mjx.fwd_acceleration(mx, d), state

        smooth, d, full, state = stages(mjx.put_data(model, before), sand.init()._replace(u=jnp.asarray(u)))
    assert float(np.abs(np.asarray(state.wrench)).max()) > 0.02  # N: measured 0.065
    for name in ("qfrc_smooth", "qacc_smooth"):
        got, expected = np.asarray(getattr(d, name)), np.asarray(getattr(full, name))
        assert relative(got, expected) < 1e-12, name
        assert relative(np.asarray(getattr(smooth, name)), expected) > 1e-3, name  # control


@pytest.mark.slow
def test_nonfinite_is_reported_not_applied(corrected):
    """A non-finite state (NaN hip velocity) or a non-finite implicit wrench (NaN spring moments) gives no granular
    wrench, keeps the memory and records the body."""
    model, terrain, before, u = corrected
    hip = int(model.jnt_dofadr[model.joint("hip_lf").id])
    sand = rmjx.Sand.from_terrain(terrain)
    mx = sand.put_model()
    step = jax.jit(sand.step)
    d0 = mjx.put_data(model, before)
    s0 = sand.init()._replace(u=jnp.asarray(u, d0.qpos.dtype))
    d, state = step(mx, d0.replace(qvel=d0.qvel.at[hip].set(jnp.nan)), s0)
    assert int(state.bad_body) == model.body("leg_lf").id and not np.any(np.asarray(state.wrench))
    assert np.all(np.isfinite(np.asarray(d.xfrc_applied)))
    np.testing.assert_array_equal(np.asarray(state.u), np.asarray(s0.u))
    with pytest.raises(NonFiniteError, match="leg_lf"):
        sand.check(state)
    nan = rmjx.Sand.from_terrain(terrain)
    nan._spring_tk = lambda f_yield, ml, vel, dt, u: jnp.full(f_yield.shape[:-1], jnp.nan, f_yield.dtype)
    d, state = jax.jit(nan.step)(mx, d0, s0)
    assert int(state.bad_body) in set(sand.imp_rows.tolist()) and not np.any(np.asarray(state.wrench))
    assert np.all(np.isfinite(np.asarray(d.qvel)))  # nothing non-finite reached the dynamics
    d, state = step(mx, d0, s0)  # control: the same state steps normally
    assert int(state.bad_body) == -1 and np.abs(np.asarray(state.wrench)).max() > 0.02


# ----------------------------------------------------------------- the Go2 at its own 2 ms (float32)


@pytest.mark.slow
def test_go2_rests_at_its_own_timestep():
    """MuJoCo Menagerie's Go2 holding its home pose for 1.5 s at the model's 2 ms, float32: with the implicit step
    every step's net vertical granular force over the last 0.2 s is within 2 % of the weight (measured within
    5e-5) and the trunk rests at the CPU implicit step's height; the explicit step (control) swings between about
    0.63 and 1.37 times the weight from step to step. The guards say so: the explicit step fires the springs'
    limit and chatter on the calves (sand.check warns, as the CPU terrain does), and the feet go deeper than the
    law's calibrated 9.5 cm; the implicit step fires no stability guard."""
    results = {}
    for implicit in (True, False):
        m = mujoco.MjModel.from_xml_path(GO2)
        sand = rmjx.Sand(m, "poppy_cp", floor="auto", implicit=implicit)
        home = m.key("home")
        d, state, load = stand(sand, m, home.qpos, home.ctrl, 1.5)
        assert d.qpos.dtype == jnp.float32 and m.opt.timestep == 0.002
        flags = sand.flags(state)
        if implicit:
            assert not (flags["springs"] or flags["depth_stiffness"] or flags["chatter"]), state.guard_count
        else:
            assert flags["springs"] and flags["chatter"] and flags["depth_range"], state.guard_count
            with pytest.warns(mjrft.TerrainStabilityWarning, match=r"body '\w\w_calf' chatters"):
                sand.check(state)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", mjrft.ValidityRangeWarning)
            sand.check(state)
        results[implicit] = load[-int(round(0.2 / m.opt.timestep)):], float(d.qpos[2])
    rest, height = results[True]
    assert np.abs(rest - 1.0).max() < 0.02
    swing, _ = results[False]
    assert swing.max() > 1.25 and swing.min() < 0.75  # measured 1.373, 0.628
    # the CPU path's implicit step at 2 ms rests at the same height
    m = mujoco.MjModel.from_xml_path(GO2)
    data = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, data, m.key("home").id)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        terrain = mjrft.GranularTerrain(m, "poppy_cp", floor="auto", implicit=True)
        terrain.step(data, int(round(1.5 / m.opt.timestep)))
    assert abs(height - data.qpos[2]) < 1e-3  # measured 103.86 mm (MJX) and 103.9 mm (CPU)

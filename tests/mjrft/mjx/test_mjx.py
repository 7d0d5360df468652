"""mjrft.mjx on CPU JAX: the JAX wrench equals the numba kernel's, a resting robot carries its weight, batched worlds
equal single ones, non-finite states are reported (the general pass's scenes: tests/mjrft/mjx/test_mjx_scenes.py)."""

from __future__ import annotations

import numpy as np
import pytest

jax = pytest.importorskip("jax", reason="mjrft.mjx needs the optional extra mjrft[mjx] (JAX)")
pytest.importorskip("mujoco.mjx", reason="mjrft.mjx needs mujoco-mjx (mjrft[mjx])")

import jax.numpy as jnp  # noqa: E402
import mujoco  # noqa: E402
from mujoco import mjx  # noqa: E402

import mjrft  # noqa: E402
import mjrft.mjx as rmjx  # noqa: E402
from mjrft.errors import NonFiniteError  # noqa: E402
from mjrft.mjx.compare import record_states, wrench_errors  # noqa: E402

pytestmark = pytest.mark.slow  # every test compiles MJX programs (5-60 s each on 2 cores)

LAWS = ("rft", "rft3d", "depth_only")
HEXAPOD = mjrft.models.model_path("hexapod")


def tripod_ctrl(t: float) -> np.ndarray:
    """Hip servo targets of a 2 Hz alternating tripod (tripod A = lf, rm, lr; B half a turn behind)."""
    return 2 * np.pi * 2 * t + np.array([0.0, np.pi, 0.0, np.pi, 0.0, np.pi])


def record_walk(law: str, every: int = 40, count: int = 5, **kw):
    """Walk the hexapod on the CPU path and record a state every ``every`` steps (mjrft.mjx.compare)."""
    model = mujoco.MjModel.from_xml_path(HEXAPOD)
    with _quiet():
        terrain = mjrft.GranularTerrain(model, law=law, **kw)
        states = record_states(model, terrain, every * count, every, ctrl=tripod_ctrl)
    return model, terrain, states


class _quiet:
    def __enter__(self):
        import warnings

        self._w = warnings.catch_warnings()
        self._w.__enter__()
        warnings.simplefilter("ignore")

    def __exit__(self, *exc):
        self._w.__exit__(*exc)


@pytest.fixture(scope="module", params=LAWS)
def walk(request):
    return request.param, *record_walk(request.param)


def relative_error(a, b) -> float:
    return float(np.abs(np.asarray(a) - b).max() / np.abs(b).max())


@pytest.mark.parametrize("x64, tol", [(True, 1e-9), (False, 1e-4)], ids=["float64", "float32"])
def test_wrench_equals_numba_kernel_on_walking_states(walk, x64, tol):
    law, model, terrain, states = walk
    sand = rmjx.Sand.from_terrain(terrain)
    assert any(np.abs(w[:, 2]).max() > 0.05 for _, _, w, _ in states)  # the legs really push on the sand
    ew, eu = wrench_errors(sand, model, states, x64)
    assert ew <= tol and eu <= tol, law
    with jax.enable_x64(x64):
        s = states[-1]
        d = mjx.put_data(model, s.data)
        w, new = jax.jit(sand.wrench)(d, sand.init()._replace(u=jnp.asarray(s.u_before, d.xpos.dtype)),
                                      model.opt.timestep)
        assert w.dtype == (jnp.float64 if x64 else jnp.float32) and int(new.bad_body) == -1


def test_wrong_physics_is_rejected_by_the_comparison(walk):
    """Control: the comparison of the test above fails for a JAX terrain with another law or the memory off."""
    law, model, terrain, states = walk
    other = rmjx.Sand.from_terrain(terrain)
    other._stress = rmjx.LAWS["depth_only" if law != "depth_only" else "rft"]
    data, u0, w_ref, _ = states[-1]
    with jax.enable_x64(True):
        d = mjx.put_data(model, data)
        w, _ = jax.jit(other.wrench)(d, other.init()._replace(u=jnp.asarray(u0)), model.opt.timestep)
        assert relative_error(w, w_ref) > 1e-2
        fresh = rmjx.Sand.from_terrain(terrain)
        w, _ = jax.jit(fresh.wrench)(d, fresh.init(), model.opt.timestep)  # memory forgotten
        assert relative_error(w, w_ref) > 1e-3


@pytest.fixture(scope="module")
def hexapod():
    model = mujoco.MjModel.from_xml_path(HEXAPOD)
    sand = rmjx.Sand(model)
    mx = sand.put_model()

    def run(d, state, n):
        def body(carry, _):
            d, s = carry
            return sand.step(mx, d, s), None

        return jax.lax.scan(body, (d, state), None, length=n)[0]

    return model, sand, mx, jax.jit(run, static_argnums=2)


def test_resting_robot_carries_its_weight(hexapod):
    model, sand, mx, run = hexapod
    d, state = run(mjx.make_data(mx), sand.init(), 600)
    assert abs(rmjx.resting_load(sand, state) - 1.0) < 0.005
    assert int(state.bad_body) == -1
    assert 0.002 < float(np.max(state.sinkage)) < 0.03  # the legs rest in the sand, not on it
    weight = float(model.body_subtreemass[0]) * 9.81
    # control: without the granular wrench the robot falls through the surface (nothing else holds it)
    free = jax.jit(lambda d: jax.lax.fori_loop(0, 600, lambda _, d: mjx.step(mx, d), d))(mjx.make_data(mx))
    assert float(free.qpos[2]) < float(d.qpos[2]) - 0.05 and weight > 0


@pytest.mark.parametrize("x64, steps, tol", [(True, 50, 1e-12), (False, 5, 1e-6)], ids=["float64", "float32"])
def test_batched_worlds_equal_single_ones(x64, steps, tol):
    """vmap over worlds changes nothing but the batching: in float64 the worlds equal single runs through the legs'
    impact on the sand; in float32 too over the first steps (after that, float32 rounding that differs between
    the batched and the single program grows through the impact, as in any stiff contact)."""
    with jax.enable_x64(x64):
        model = mujoco.MjModel.from_xml_path(HEXAPOD)
        sand = rmjx.Sand(model)
        mx = sand.put_model()
        run = jax.jit(lambda d, s: jax.lax.scan(lambda c, _: (sand.step(mx, *c), None), (d, s), None,
                                                length=steps)[0])
        qpos = np.tile(model.qpos0, (3, 1))
        qpos[:, 0] += [0.0, 0.01, -0.02]
        qpos[:, 2] += [0.0, -0.003, 0.002]
        d0 = mjx.make_data(mx)
        batch = jax.vmap(lambda q: d0.replace(qpos=q))(jnp.asarray(qpos))
        states = jax.vmap(lambda _: sand.init())(jnp.arange(3))
        db, sb = jax.jit(jax.vmap(run))(batch, states)
        assert float(np.abs(np.asarray(sb.wrench)).max()) > 0.01  # the legs are in the sand
        for k in range(3):
            d1, s1 = run(d0.replace(qpos=jnp.asarray(qpos[k])), sand.init())
            np.testing.assert_allclose(np.asarray(sb.wrench[k]), np.asarray(s1.wrench), rtol=0, atol=tol)
            np.testing.assert_allclose(np.asarray(db.qpos[k]), np.asarray(d1.qpos), rtol=0, atol=tol)


def test_nonfinite_state_is_reported_not_applied(hexapod):
    model, sand, mx, run = hexapod
    d = mjx.make_data(mx)
    hip = int(model.jnt_dofadr[model.joint("hip_lf").id])
    d = d.replace(qvel=d.qvel.at[hip].set(jnp.nan))
    d = jax.jit(mjx.forward)(mx, d)  # (op by op, unjitted, it takes minutes)
    w, state = jax.jit(sand.wrench)(d, sand.init(), 1e-3)
    assert np.all(np.isfinite(np.asarray(w))) and not np.any(np.asarray(w))
    assert int(state.bad_body) == model.body("leg_lf").id
    with pytest.raises(NonFiniteError, match="leg_lf"):
        sand.check(state)
    sand.check(sand.init())  # a finite state passes
    stepped, stepped_state = jax.jit(sand.step)(mx, d, sand.init())
    assert np.all(np.isfinite(np.asarray(stepped.xfrc_applied)))
    assert int(stepped_state.bad_body) != -1


def test_cull_matches_full_evaluation_and_flags_overflow(walk):
    law, model, terrain, states = walk
    full = rmjx.Sand.from_terrain(terrain)
    data, u0, _, _ = states[-1]
    with jax.enable_x64(True):
        d = mjx.put_data(model, data)
        w_full, s_full = full.wrench(d, full.init()._replace(u=jnp.asarray(u0)), 1e-3)
        n_buried = int(np.sum(np.asarray(s_full.u).any(axis=1)))
        culled = rmjx.Sand.from_terrain(terrain, cull=max(n_buried + 50, 1))
        w_cull, s_cull = culled.wrench(d, culled.init()._replace(u=jnp.asarray(u0)), 1e-3)
        np.testing.assert_allclose(np.asarray(w_cull), np.asarray(w_full), rtol=1e-12, atol=1e-15)
        small = rmjx.Sand.from_terrain(terrain, cull=1)
        w_small, s_small = small.wrench(d, small.init()._replace(u=jnp.asarray(u0)), 1e-3)
        assert int(s_small.bad_body) == -2 and not np.any(np.asarray(w_small))
        with pytest.raises(NonFiniteError, match="cull"):
            small.check(s_small)


def test_bad_cull_is_refused():
    model = mujoco.MjModel.from_xml_path(HEXAPOD)
    for bad in (0, -3, 2.5, True, 10**9):
        with pytest.raises(ValueError, match="cull must be"):
            rmjx.Sand(model, cull=bad)


def test_per_world_medium_and_surface_equal_the_cpu_terrain_changed_in_place():
    """state.params / state.surface of a world (Sand.params_of, as the MJX env's terrain_randomization draws them)
    give the wrench of the CPU terrain after set_medium(medium, stress_scale) and set_surface(height)."""
    model, terrain, states = record_walk("rft", count=2)
    sand = rmjx.Sand.from_terrain(terrain)
    data, u0, w_own, _ = states[-1]
    terrain.set_medium("poppy_lp", stress_scale=1.2)
    terrain.set_surface(0.003)
    terrain.bind(data)  # binding to another MjData forgets the memory: bind first, then restore it
    terrain.terrain_state.u[:] = u0
    w_ref = terrain.compute(data).copy()
    assert relative_error(w_own, w_ref) > 0.05  # the change matters
    with jax.enable_x64(True):
        d = mjx.put_data(model, data)
        state = sand.init(params=sand.params_of("poppy_lp", stress_scale=1.2), surface=0.003)
        w, _ = jax.jit(sand.wrench)(d, state._replace(u=jnp.asarray(u0)), model.opt.timestep)
    assert relative_error(w, w_ref) <= 1e-9


SERVO = """<mujoco><option timestep="0.0005" integrator="{integrator}"/>
<worldbody><body><joint name="j" type="hinge" axis="0 1 0" armature="1e-5" damping="1e-4"/>
<geom type="capsule" fromto="0 0 0 0.05 0 0" size="0.005" mass="0.01"/></body></worldbody>
<actuator><position joint="j" kp="2" kv="0.02" forcerange="-0.3 0.3"/></actuator></mujoco>"""


@pytest.mark.parametrize("integrator", ["implicitfast", "Euler"])
@pytest.mark.parametrize("target", [0.05, 0.16, -0.3], ids=["free", "clamped", "clamped-negative"])
def test_step_integrates_clamped_servos_as_mujoco(integrator, target):
    """A hip-like servo (kp 2, kv 0.02, force clamped at 0.3 N m, 1e-5 kg m^2 of armature) stepped 200 times by
    mjrft.mjx.step equals mujoco.mj_step in float64. Control: MJX's own step keeps the clamped servo's kv in the
    implicitfast derivative (MuJoCo leaves it out) and ends far from MuJoCo whenever the force clamps."""
    model = mujoco.MjModel.from_xml_string(SERVO.format(integrator=integrator))
    with jax.enable_x64(True):
        mx = mjx.put_model(model)
        ours, theirs = jax.jit(rmjx.step), jax.jit(mjx.step)
        d = mujoco.MjData(model)
        d.ctrl[0] = target
        a = b = mjx.put_data(model, d)
        gap_ours = gap_theirs = 0.0
        for _ in range(200):
            mujoco.mj_step(model, d)
            a, b = ours(mx, a), theirs(mx, b)
            gap_ours = max(gap_ours, abs(float(a.qvel[0]) - d.qvel[0]))
            gap_theirs = max(gap_theirs, abs(float(b.qvel[0]) - d.qvel[0]))
    assert gap_ours < 1e-12
    clamps = target != 0.05
    if integrator == "implicitfast" and clamps:
        assert gap_theirs > 1e-2
    else:
        assert gap_theirs < 1e-12

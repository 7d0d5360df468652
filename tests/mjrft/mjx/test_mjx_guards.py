"""The JAX path's guards (mjrft.mjx.guards, Sand.step/check/flags/auto_step): the stability limits equal the CPU
terrain's on recorded walking states, chatter is tracked as the CPU tracks it, gymnasium's Ant at a 10 ms Euler step
is flagged where it used to be thrown up silently (and a stable step stays silent), the automatic sub-steps keep an
unstable timestep silent, a model put on the device before the terrain is refused, and accelerometers on sand equal
the CPU path's. (The Go2 at its own 2 ms with the explicit step: tests/mjrft/mjx/test_mjx_implicit.py.)"""

from __future__ import annotations

import copy
import os
import warnings

import mujoco
import numpy as np
import pytest

jax = pytest.importorskip("jax", reason="mjrft.mjx needs the optional extra mjrft[mjx] (JAX)")
pytest.importorskip("mujoco.mjx", reason="mjrft.mjx needs mujoco-mjx (mjrft[mjx])")

import jax.numpy as jnp  # noqa: E402
from mujoco import mjx  # noqa: E402

import mjrft  # noqa: E402
import mjrft.mjx as rmjx  # noqa: E402
from mjrft import stability  # noqa: E402
from mjrft.errors import TerrainStabilityWarning, ValidityRangeWarning  # noqa: E402
from mjrft.mjx import guards  # noqa: E402
from mjrft.mjx.compare import record_states  # noqa: E402

HEXAPOD = mjrft.models.model_path("hexapod")
OFFSETS = np.array([0.0, np.pi, 0.0, np.pi, 0.0, np.pi])


def tripod_ctrl(t: float) -> np.ndarray:
    return 2 * np.pi * 2 * t + OFFSETS


def hexapod_model() -> mujoco.MjModel:
    model = mujoco.MjModel.from_xml_path(HEXAPOD)
    bottom = model.geom("bed_bottom").id  # as the MJX env: the bed's rigid bottom without contacts
    model.geom_contype[bottom] = model.geom_conaffinity[bottom] = 0
    return model


# ----------------------------------------------------------------- the pieces, against the CPU's


def test_largest_rate_equals_the_cpus():
    """The squarings' largest eigenvalue of W6 K6 equals mjrft.stability.largest_rate (Cholesky and Jacobi) within
    its bound 1 / (e 2^12) on random mobilities and moments, also for a hinged (singular) W6 and two equal
    eigenvalues; control: two squarings are rejected."""
    rng = np.random.default_rng(7)
    cases = []
    for i in range(40):
        a = rng.normal(size=(6, 6)) * (10.0 ** rng.uniform(-1, 2, size=6))
        w = a @ a.T
        if i % 4 == 1:  # a hinge: mobility of rank 2
            b = rng.normal(size=(6, 2))
            w = b @ b.T
        r = rng.normal(size=(rng.integers(1, 30), 3)) * 0.05
        k = rng.uniform(0, 1e4, size=r.shape[0])
        mono = np.asarray(guards.monomials(jnp.asarray(r)))
        moments = (k[:, None] * mono).sum(axis=0)
        cases.append((w, moments))
    cases.append((np.eye(6), np.array([1.0, 0, 0, 0, 0, 0, 0, 0, 0, 0])))  # three equal translational modes
    w6 = np.stack([c[0] for c in cases])
    mom = np.stack([c[1] for c in cases])
    with jax.enable_x64(True):
        got = np.asarray(jax.jit(lambda w, m: guards.largest_rate(w, guards.k6(m)))(w6, mom))
        jac = np.zeros((6, 6))
    expected = []
    for w, m in cases:  # largest_rate takes J and (M^-1 J^T)^T with W6 = J minv_jac^T: J = I, minv_jac = W6
        np.copyto(jac, np.eye(6))
        expected.append(stability.largest_rate(jac, w.copy(), m))
    expected = np.array(expected)
    rel = np.abs(got - expected) / expected
    assert rel.max() < 1.0 / (np.e * 2 ** guards.SQUARINGS) + 1e-9
    old = guards.SQUARINGS
    try:
        guards.SQUARINGS = 2
        with jax.enable_x64(True):
            coarse = np.asarray(jax.jit(lambda w, m: guards.largest_rate(w, guards.k6(m)))(w6, mom))
    finally:
        guards.SQUARINGS = old
    assert (np.abs(coarse - expected) / expected).max() > 1e-2


def test_limits_and_growth_equal_the_cpus():
    """The limits (float32 and float64) and the growth factor (float64: its threshold 1 is not read from it in
    float32) equal mjrft.stability's; the growth exceeds 1 exactly beyond the limit."""
    lam = np.array([0.0, 1.0, 3e3, 4e5, 2e7])
    for delta, tau in ((1e-3, 2e-3), (0.0, 0.0)):
        K, c = guards.spring(jnp.asarray(lam, jnp.float32), delta, tau)
        want = [stability.max_stable_dt(*stability.spring(x, 0.0, delta, tau), 1.0) for x in lam]
        np.testing.assert_allclose(np.asarray(guards.max_stable_dt(K, c)), want, rtol=1e-6)
    for delta, tau in ((1e-3, 2e-3), (0.0, 0.0)):
        with jax.enable_x64(True):
            K, c = guards.spring(jnp.asarray(lam), delta, tau)
            got = np.asarray(guards.max_stable_dt(K, c))
            growth = {dt: np.asarray(guards.step_growth(K, c, dt)) for dt in (1e-4, 1e-3, 1e-2)}
        want = [stability.max_stable_dt(*stability.spring(x, 0.0, delta, tau), 1.0) for x in lam]
        np.testing.assert_allclose(got, want, rtol=1e-12)
        for dt, g in growth.items():
            np.testing.assert_allclose(g, [stability.step_growth(*stability.spring(x, 0.0, delta, tau), 1.0, dt)
                                           for x in lam], rtol=1e-12)
            live = lam > 0
            assert np.array_equal((g > 1.0 + 1e-9)[live], (dt > got * (1 + 1e-9))[live])
    np.testing.assert_allclose(np.asarray(guards.depth_stable_dt(jnp.asarray(lam))),
                               [stability.depth_stable_dt(x) for x in lam], rtol=1e-6)


def test_chatter_is_tracked_as_on_the_cpu():
    """track_chatter of every body at once equals mjrft.stability.track_chatter step by step on a force that
    alternates by 20 % (it fires on step CHATTER_STEPS), and stays silent (control) on one that alternates by 2 %
    and on one that only grows."""
    steps = guards.CHATTER_STEPS + 10
    t = np.arange(steps)
    forces = np.zeros((steps, 4, 3))
    forces[:, 1, 2] = 10.0 * (1 + 0.2 * (-1.0) ** t)   # chatters
    forces[:, 2, 2] = 10.0 * (1 + 0.02 * (-1.0) ** t)  # changes by 4 %: below CHATTER_AMPLITUDE
    forces[:, 3, 2] = 10.0 * (1 + 0.2 * t)             # grows, never reverses
    cpu = np.zeros((4, stability.TRACK_SLOTS, 10))
    rec = jnp.zeros((4, guards.CHATTER_SLOTS))
    track = jax.jit(guards.track_chatter)
    with jax.enable_x64(True):
        for k in range(steps):
            wrench = np.zeros((4, 6))
            wrench[:, :3] = forces[k]
            stability.track_chatter(wrench, np.arange(4), cpu)
            rec = track(rec, jnp.asarray(forces[k]))
            np.testing.assert_allclose(np.asarray(rec)[:, :7], cpu[:, stability.CHATTER_SLOT, :7], rtol=1e-12)
    run = np.asarray(rec)[:, 6]
    assert run[1] >= guards.CHATTER_STEPS and run[2] == 0 and run[3] == 0


def test_sub_step_rule_is_the_wrappers():
    from mjrft.envs import wrapper

    assert (guards.SAFETY, guards.SPRING_STEP, guards.MAX_SUBSTEPS) == (wrapper.SAFETY, wrapper.SPRING_STEP,
                                                                         wrapper.MAX_SUBSTEPS)
    for springs, static, depth, implicit in ((2e-3, 1e-2, 5e-2, False), (np.inf, 4e-3, np.inf, False),
                                             (1e-3, 1e-2, 5e-2, True), (np.inf, np.inf, np.inf, False)):
        k = int(guards.substeps_for(jnp.array([springs, depth]), static, 0.01, implicit, 2e-3, 64))
        limit = min(springs, static)
        if implicit:
            rate = wrapper.spring_rate(limit, 2e-3)
            dt_s = min(wrapper.SPRING_STEP / rate if rate > 0 else np.inf, wrapper.SAFETY * depth)
        else:
            dt_s = wrapper.SAFETY * min(limit, depth)
        want = 1 if not np.isfinite(dt_s) else int(min(64, max(1, np.ceil(0.01 / dt_s - 1e-9))))
        assert k == want


# ----------------------------------------------------------------- the hexapod: limits against the CPU, silence


@pytest.fixture(scope="module")
def hexapod():
    model = hexapod_model()
    sand = rmjx.Sand(model)
    mx = sand.put_model()
    return model, sand, mx, jax.jit(sand.step)


@pytest.mark.slow
def test_stable_timesteps_equal_the_cpu_terrains(hexapod):
    """The last step's smallest stable timesteps (state.stable_dt: springs, depth stiffness) equal the CPU terrain's
    min_stable_timesteps on the same states (recorded walking the tripod; float32 against float64); control: the
    CPU's limit of the same springs without their lever arms is rejected."""
    model, sand, mx, step = hexapod
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        terrain = mjrft.GranularTerrain(model)
        states = record_states(model, terrain, 240, 60, ctrl=tripod_ctrl)
    checked = 0
    for s in states:
        data = copy.copy(s.data)
        cpu = mjrft.GranularTerrain(model)
        cpu.bind(data)
        cpu.terrain_state.u[:] = s.u_before
        cpu.compute(data)
        springs, depth = cpu.min_stable_timesteps(data)
        _, state = step(mx, mjx.put_data(model, s.data), sand.init()._replace(u=jnp.asarray(s.u_before, jnp.float32)))
        got = np.asarray(state.stable_dt)
        if not np.isfinite(springs):
            continue
        checked += 1
        np.testing.assert_allclose(got, [springs, depth], rtol=2e-3)
        # control: the CPU's limit of springs acting at the centre of mass (their lever arms dropped) is rejected
        st = cpu.terrain_state
        wrong = np.full(model.nbody, np.inf)
        no_arms = st.stiff.copy()
        no_arms[:, 1:] = 0.0
        cpu._stability.limits_into(data, wrong, cpu.terrain_model, st, no_arms, vertical=False)
        assert abs(wrong.min() - got[0]) / got[0] > 0.05
    assert checked >= 3


@pytest.mark.slow
def test_stable_tripod_stays_silent_and_a_coarse_step_is_flagged(hexapod):
    """The hexapod walking the tripod at its own 1 ms (the CPU terrain is silent there, docs/numerics.md) fires no
    guard and check() warns nothing; control: the same model at 8 ms fires the springs' guard and check() warns
    naming the body and time."""
    model, sand, mx, step = hexapod

    def walk(m, steps):
        d, state = mjx.make_data(m), sand.init()
        for _ in range(steps):
            d, state = step(m, d.replace(ctrl=jnp.asarray(tripod_ctrl(float(d.time)), jnp.float32)), state)
        return d, state

    _, state = walk(mx, 200)
    assert not any(bool(v) for v in sand.flags(state).values()), np.asarray(state.guard_count)
    assert np.isfinite(np.asarray(state.stable_dt)).all()  # the legs are in the sand, the limits evaluated
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sand.check(state)
    coarse = mx.replace(opt=mx.opt.replace(timestep=jnp.asarray(0.008, jnp.float32)))
    _, bad = walk(coarse, 40)
    assert bool(sand.flags(bad)["springs"])
    with pytest.warns(TerrainStabilityWarning, match=r"stability limit of the granular stiffness on body '\w+' "
                                                     r"from t = "):
        sand.check(bad)
    sand.check(bad)  # once per guard and body: no second warning (pytest's filter would fail on an unexpected one)


# ----------------------------------------------------------------- gymnasium's Ant at a 10 ms Euler step


@pytest.mark.slow
def test_ant_at_a_10_ms_euler_step_is_flagged_not_silent():
    """gymnasium's Ant dropped on sand at a 10 ms Euler step (the CPU terrain warns that it exceeds the springs'
    limit, 3.8 ms) fires the springs' and the depth stiffness's guards on landing in both worlds of a batch, and
    check() warns naming the world, body and time; control: the same program at 2 ms stays silent in stability."""
    import gymnasium

    path = os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets", "ant.xml")
    model = mujoco.MjModel.from_xml_path(path)
    model.opt.integrator = mujoco.mjtIntegrator.mjINT_EULER
    sand = rmjx.Sand(model, floor="auto")
    mx = sand.put_model()
    run = jax.jit(jax.vmap(lambda m, n, d, s: jax.lax.fori_loop(0, n, lambda _, c: sand.step(m, *c), (d, s)),
                           in_axes=(None, None, 0, 0)))
    worlds = 2
    d0 = jax.vmap(lambda z: mjx.make_data(mx).replace(qpos=mjx.make_data(mx).qpos.at[2].add(z)))(
        jnp.array([-0.15, -0.13]))  # dropped from 0.6 m and 0.62 m: on the sand within 0.1 s
    s0 = jax.vmap(lambda _: sand.init())(jnp.arange(worlds))
    _, state = run(mx, 20, d0, s0)
    flags = sand.flags(state)
    assert flags["springs"].tolist() == [True, True] and flags["depth_stiffness"].any()
    assert not flags["nonfinite"].any()
    with pytest.warns(TerrainStabilityWarning, match=r"body '#\d+' from t = 0\.\d+ s in world 0 \(2 of 2 worlds\)"):
        sand.check(state)
    fine = mx.replace(opt=mx.opt.replace(timestep=jnp.asarray(0.002, jnp.float32)))
    _, calm = run(fine, 120, d0, s0)
    calm_flags = sand.flags(calm)
    assert not (calm_flags["springs"].any() or calm_flags["depth_stiffness"].any() or calm_flags["chatter"].any())
    assert calm_flags["speed_range"].all()  # both landed (at 2 m/s, beyond Li's 1 m/s) while the guards watched


@pytest.mark.slow
def test_auto_step_sub_steps_an_unstable_timestep(hexapod):
    """auto_step at 8 ms (where the plain step fires the springs' guard, the test above) splits every step into
    sub-steps below half the limits and fires no stability guard; state.substeps holds how many."""
    model, sand, mx, _ = hexapod
    coarse = mx.replace(opt=mx.opt.replace(timestep=jnp.asarray(0.008, jnp.float32)))
    auto = jax.jit(lambda m, d, s: sand.auto_step(m, d, s))
    d, state = mjx.make_data(coarse), sand.init()
    used = []
    for _ in range(40):
        d, state = auto(coarse, d.replace(ctrl=jnp.asarray(tripod_ctrl(float(d.time)), jnp.float32)), state)
        used.append(int(state.substeps))
    flags = sand.flags(state)
    assert not (flags["springs"] or flags["depth_stiffness"] or flags["chatter"]), np.asarray(state.guard_count)
    assert min(used) >= 2 and abs(float(d.time) - 40 * 0.008) < 1e-4
    limit = min(float(state.stable_dt[0]), sand.static_limit(), float(state.stable_dt[1]))
    assert 0.008 / int(state.substeps) <= guards.SAFETY * limit * (1 + 1e-5) or int(state.substeps) == 64


# ----------------------------------------------------------------- the order of put_model, accelerometers


BOX = """
<mujoco>
  <option timestep="0.001" integrator="implicitfast"/>
  <worldbody>
    <geom name="floor" type="plane" size="1 1 0.1"/>
    <body name="box" pos="0 0 0.021">
      <freejoint/>
      <geom type="box" size="0.03 0.03 0.02" mass="0.2"/>
      <site name="imu" pos="0.01 0 0.01"/>
    </body>
  </worldbody>
  <sensor>
    <accelerometer site="imu"/>
    <touch site="imu"/>
  </sensor>
</mujoco>
"""


def test_a_model_put_on_the_device_first_is_refused():
    """An MJX model put before the terrain removed the floor's contacts (the robot would stand on the rigid plane
    with no granular load) is refused when the step is traced, naming the floor and the order; control: the model
    put after the terrain (sand.put_model()) traces."""
    model = mujoco.MjModel.from_xml_string(BOX)
    early = mjx.put_model(model)  # the floor still collides
    sand = rmjx.Sand(model, floor="auto", resolution=0.01)
    with pytest.raises(ValueError, match=r"floor geom 'floor' \(contype 1, conaffinity 1\).*put on the device "
                                         r"\(mjx.put_model\) before mjrft.mjx.Sand was built"):
        jax.eval_shape(sand.step, early, mjx.make_data(early), sand.init())
    late = sand.put_model()
    jax.eval_shape(sand.step, late, mjx.make_data(late), sand.init())


def test_accelerometer_on_sand_equals_the_cpu_path():
    """A box settling into the sand with an accelerometer (and a touch sensor, which has no contacts to read): after
    60 steps MJX's sensordata equals the CPU path's (float64), although the model has no constraint rows; control:
    the reading differs from that of the box falling freely (0), so a sensor left unupdated is rejected."""
    model = mujoco.MjModel.from_xml_string(BOX)
    cpu_model = mujoco.MjModel.from_xml_string(BOX)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ValidityRangeWarning)
        terrain = mjrft.GranularTerrain(cpu_model, floor="auto", resolution=0.01)
        sand = rmjx.Sand(model, floor="auto", resolution=0.01)
    data = mujoco.MjData(cpu_model)
    terrain.step(data, 60)
    with jax.enable_x64(True):
        mx = sand.put_model()
        assert mjx.make_data(mx)._impl.efc_J.size == 0  # no constraint rows: MJX's own forward skips sensor_acc
        d, _ = jax.jit(lambda d, s: jax.lax.fori_loop(0, 60, lambda _, c: sand.step(mx, *c), (d, s)))(
            mjx.make_data(mx), sand.init())
        got = np.asarray(d.sensordata)
    np.testing.assert_allclose(got, data.sensordata, rtol=1e-9, atol=1e-9)
    assert np.linalg.norm(data.sensordata[:3]) > 1.0 and got[3] == 0.0

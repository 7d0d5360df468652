"""The ground memory in MJX (mjrft.mjx.ground): on the hexapod's recorded CPU walks with ``ground_memory=True`` the
JAX terrain, stepped through the same states under ``jit`` and ``vmap`` over two worlds with different histories,
gives the numba kernel's wrench at every step and its ground cells (footprints, ridges, packing, the relaxation's
lists) at the end, float64 to rounding and float32 within 1e-4; the grains' solid volume is conserved; the same
comparison rejects the terrain without the memory and a ground with a doubled footprint; the readers equal the CPU
terrain's; a terrain without the memory traces no ground at all; the MJX env's auto-reset restores the prepared
bed. On the kernel's general pass (a height field of two strips of media, each with its own packing rows, one under
water, with the inertial regime) a foot dragged level through the grains, lifted and pressed in again on its own
track gives the numba kernel's wrench at every step and its cells at the end under ``vmap`` over two worlds, and the
same comparison rejects the forces of the terrain without the memory and of the memory without its packing rows.
With the hybrid law in one of the strips the same foot meets its own wake: the JAX terrain gives the kernel's wrench
at every step and its cells and wake at the end, and the kernel with its wake emptied gives other forces."""

from __future__ import annotations

import copy
import dataclasses
import warnings

import numpy as np
import pytest

jax = pytest.importorskip("jax", reason="mjrft.mjx needs the optional extra mjrft[mjx] (JAX)")
pytest.importorskip("mujoco.mjx", reason="mjrft.mjx needs mujoco-mjx (mjrft[mjx])")

import jax.numpy as jnp  # noqa: E402
import mujoco  # noqa: E402
from mujoco import mjx  # noqa: E402

import mjrft  # noqa: E402
import mjrft.mjx as rmjx  # noqa: E402
from mjrft.ground import C_COL, C_H, C_MARK, C_PEND, C_PHI, C_STAMP, C_SUB, ground_volumes  # noqa: E402
from mjrft.ground import WAKE_SLABS, GroundOptions  # noqa: E402
from mjrft.models import hexapod_model  # noqa: E402
from mjrft.mjx.ground import Ground  # noqa: E402
from mjrft.regions import Region  # noqa: E402

pytestmark = pytest.mark.slow  # every test compiles MJX programs (10-40 s each on 2 cores)

STEPS = 160  # 40 updates of the ground (every 4 ms at the hexapod's 1 ms step)
GAITS = (2.0, 3.0)  # the two worlds' tripod frequencies (Hz): different footprints, ridges and avalanches
FIELDS = (C_PHI, C_H, C_PEND, C_SUB, C_COL)


def walk(freq: float, memory: bool = True):
    """The hexapod's tripod at ``freq`` on the CPU path: its terrain, the MjData after each ``mj_step1`` and the
    wrench the kernel applied."""
    m = hexapod_model()
    d = mujoco.MjData(m)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t = mjrft.GranularTerrain(m, ground_memory=memory)
    datas, wrenches = [], []
    for _ in range(STEPS):
        d.ctrl[:] = 2 * np.pi * freq * d.time + np.arange(m.nu) % 2 * np.pi
        mujoco.mj_step1(m, d)
        t.compute(d)
        datas.append(copy.copy(d))
        wrenches.append(t.wrench.copy())
        saved = d.xfrc_applied.copy()
        d.xfrc_applied[:] += t.wrench
        mujoco.mj_step2(m, d)
        d.xfrc_applied[:] = saved
    return m, t, datas, np.array(wrenches)


KINEMATICS = ("xpos", "xmat", "xipos", "geom_xpos", "geom_xmat", "cvel", "subtree_com")  # what the wrench reads


def recorded(m, datas):
    """The recorded states as one mjx.Data with a leading axis over the steps (the first state on the device, the
    kinematics the wrench reads and the time of every step)."""
    first = mjx.put_data(m, datas[0])
    steps = jax.tree_util.tree_map(lambda a: jnp.broadcast_to(a, (len(datas),) + a.shape), first)
    fields = {k: jnp.asarray(np.stack([getattr(d, k) for d in datas]).reshape((len(datas),) + getattr(first, k).shape),
                             getattr(first, k).dtype) for k in KINEMATICS}
    return steps.replace(time=jnp.asarray([d.time for d in datas], first.time.dtype), **fields)


def replay(sand, m, runs, x64: bool, batched: bool = True):
    """``sand.wrench`` through each run's recorded states from a fresh state (one jitted ``lax.scan`` per world,
    ``vmap`` over the worlds): (the final states, the wrenches (worlds, steps, nbody, 6)) as numpy."""
    with jax.enable_x64(x64):
        stacks = [recorded(m, r[2]) for r in runs]

        def world(datas):
            def body(s, d):
                w, s = sand.wrench(d, s, m.opt.timestep)
                return s, w

            return jax.lax.scan(body, sand.init(), datas)

        if batched:
            state, w = jax.jit(jax.vmap(world))(jax.tree_util.tree_map(lambda *a: jnp.stack(a), *stacks))
        else:
            state, w = jax.jit(world)(stacks[0])
            state, w = jax.tree_util.tree_map(lambda a: a[None], (state, w))
        return jax.tree_util.tree_map(np.asarray, state), np.asarray(w)


def relative(a, ref):
    return float(np.abs(a - ref).max() / np.abs(ref).max())


def cell_errors(cells, ref) -> float:
    """The largest difference of the cells' fields, each over its largest CPU value, and of the clocks' fields."""
    err = max(relative(cells[..., f], ref[..., f]) for f in FIELDS)
    exact = max(float(np.abs(cells[..., f] - ref[..., f]).max()) for f in (C_STAMP, C_MARK))
    return err + exact


@pytest.fixture(scope="module")
def runs():
    return [walk(f) for f in GAITS]


@pytest.fixture(scope="module")
def replayed(runs):
    sand = rmjx.Sand.from_terrain(runs[0][1], guards=False)
    return sand, replay(sand, runs[0][0], runs, x64=True)


def test_the_ground_and_the_wrench_equal_the_kernels_under_vmap(runs, replayed):
    sand, (state, w) = replayed
    cpu = [r[1].terrain_state for r in runs]
    for k, (m, t, _, wrench) in enumerate(runs):
        assert cpu[k].g_clock[1] > 10 and cpu[k].g_height.min() < -3e-3  # footprints, and relaxation sweeps ran
        assert relative(w[k], wrench) <= 1e-9, k
        assert cell_errors(state.ground.cells[k], cpu[k].g_cells) <= 1e-9, k
        assert np.array_equal(state.ground.clock[k], cpu[k].g_clock)
        assert np.array_equal(state.ground.count[k], cpu[k].g_count)
    # the two worlds kept their own histories
    assert np.abs(cpu[0].g_height - cpu[1].g_height).max() > 1e-3
    # the readers equal the CPU terrain's
    x, y = np.meshgrid(np.linspace(-0.4, 0.5, 37), np.linspace(-0.3, 0.3, 25))
    with jax.enable_x64(True):
        for k, (_, t, _, _) in enumerate(runs):
            one = jax.tree_util.tree_map(lambda a: jnp.asarray(a[k]), state)
            assert np.abs(np.asarray(sand.ground_height(one, x, y)) - t.ground_height(x, y)).max() <= 1e-12
            assert np.abs(np.asarray(sand.ground_packing(one, x, y)) - t.ground_packing(x, y)).max() <= 1e-12


def test_the_grains_are_conserved(runs, replayed):
    """The grains' solid volume is conserved to rounding while the bulk volume changed with the packing; control: the
    same check rejects the ground with one ridge's grains removed. A reset restores the prepared bed."""
    sand, (state, _) = replayed
    with jax.enable_x64(True):
        solid0 = float(sand.ground.volumes(sand.ground.init())[0])
        for k, (_, t, _, _) in enumerate(runs):
            g = jax.tree_util.tree_map(lambda a: jnp.asarray(a[k]), state.ground)
            solid, bulk = (float(v) for v in sand.ground.volumes(g))
            assert abs(solid - solid0) <= 1e-12 * solid0, k
            assert abs(bulk) > 1e-7  # m^3: the sheared and loaded grains changed their volume
            assert (solid, bulk) == pytest.approx(ground_volumes(t.terrain_model.ground, t.terrain_state), rel=1e-12)
            ridge = np.unravel_index(np.argmax(state.ground.cells[k][..., C_H]), state.ground.cells[k].shape[:2])
            lost = g._replace(cells=g.cells.at[ridge + (C_H,)].set(0.0))
            assert abs(float(sand.ground.volumes(lost)[0]) - solid0) > 1e-7 * solid0
            # Sand.reset restores the prepared bed
            fresh = rmjx.Sand.reset(jax.tree_util.tree_map(lambda a: jnp.asarray(a[k]), state)).ground
            assert all(np.array_equal(a, b) for a, b in zip(fresh, sand.init().ground))


def test_float32_follows_and_the_wrong_physics_is_rejected(runs, replayed):
    m, t, _, wrench = runs[0]
    ref = t.terrain_state.g_cells
    state, w = replay(rmjx.Sand.from_terrain(t, guards=False), m, runs[:1], x64=False, batched=False)
    assert relative(w[0], wrench) <= 1e-4
    assert max(relative(state.ground.cells[0][..., f], ref[..., f]) for f in (C_PHI, C_H, C_PEND)) <= 1e-4
    # control: the terrain without the ground memory
    no_memory = rmjx.Sand.from_terrain(mjrft.GranularTerrain(m), guards=False)
    assert relative(replay(no_memory, m, runs[:1], x64=True, batched=False)[1][0], wrench) > 1e-2

    class Doubled(Ground):  # control: every footprint displaces twice its bodies' volume
        def update(self, g, pos, vel, nrm, depth, u, area, dt, ok):
            return super().update(g, pos, vel, nrm, depth, u, 2.0 * area, dt, ok)

    doubled = rmjx.Sand.from_terrain(t, guards=False)
    doubled.ground = Doubled(t.terrain_model)
    state, w = replay(doubled, m, runs[:1], x64=True, batched=False)
    assert relative(state.ground.cells[0][..., C_H], ref[..., C_H]) > 0.1
    assert relative(w[0], wrench) > 1e-3


def test_a_terrain_without_the_memory_traces_no_ground():
    """On the direct pass and on the general pass (the inertial regime)."""
    m = hexapod_model()
    d = mjx.make_data(mjx.put_model(m))
    for kw in ({}, {"inertial": True}):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            plain = rmjx.Sand(hexapod_model(), guards=False, **kw)
            ground = rmjx.Sand(hexapod_model(), guards=False, ground_memory=True, **kw)
        assert plain.ground is None and plain.init().ground is None and plain.general == bool(kw)
        assert not ground.ground.wake and ground.init().ground.wake is None  # no hybrid law: no wake traced
        text = str(jax.make_jaxpr(plain.wrench)(d, plain.init(), 0.001))
        assert "while" not in text and "scatter" not in text
        assert "while" in str(jax.make_jaxpr(ground.wrench)(d, ground.init(), 0.001))  # control: the memory's loops


def test_the_mjx_env_resets_the_ground_with_the_episode():
    """The MJX hexapod with ``terrain.ground_memory``: an auto-reset (the first state's data with the ended episode's
    sand) starts on the prepared bed, its first step's ground the first episode's bit for bit; control: the same
    step with the time nudged off 0 keeps the ended episode's footprints. The hybrid law's env with the memory keeps
    its wake (empty at the start)."""
    import mjrft.mjx.envs as envs

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        env = envs.load("HexapodSand", config_overrides={"terrain.ground_memory": True})
    assert env.sand.ground is not None and env.gym_kwargs["ground_memory"] is True
    reset, step = jax.jit(env.reset), jax.jit(env.step)
    first = reset(jax.random.PRNGKey(5))
    action = jnp.full(6, 2 / 3)
    s1 = step(first, action)
    s2 = step(step(s1, action), action)
    cells = s2.info["sand"].ground.cells
    assert float(jnp.min(cells[..., C_H])) < -2e-4 and int(s2.info["sand"].ground.clock[0]) > 0
    restarted = s2.replace(data=first.data, obs=first.obs)
    s3 = step(restarted, action)
    np.testing.assert_array_equal(np.asarray(s3.info["sand"].ground.cells), np.asarray(s1.info["sand"].ground.cells))
    kept = step(restarted.replace(data=first.data.replace(time=jnp.float32(1e-7))), action)
    assert float(jnp.abs(kept.info["sand"].ground.cells - s1.info["sand"].ground.cells).max()) > 1e-4
    # the hybrid law, a law of the general pass, keeps the wake of its undisturbed-grain rule in the memory
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        hybrid = envs.load("HexapodSand", config_overrides={"terrain.ground_memory": True, "terrain.law": "hybrid"})
    wake = hybrid.sand.init().ground.wake
    assert hybrid.sand.ground.wake and wake.shape[-1] == WAKE_SLABS and bool(jnp.all(jnp.isinf(wake)))


# ------------------------------------------------------------------------------------------------
# the general pass: regions with their own packing rows, water, a height field, the inertial regime
# ------------------------------------------------------------------------------------------------
RIG = """<mujoco><option timestep="0.005"/><asset><hfield name="hf" nrow="3" ncol="4" size="0.3 0.2 0.003 0.1"
elevation="0.8 0.9 1.0 0.0  0.4 0.5 0.6 0.7  0 0.1 0.2 0.3"/></asset><worldbody>
<geom name="ground" type="hfield" hfield="hf" euler="0 0 0.4" contype="0" conaffinity="0"/>
<body name="foot"><joint name="x" type="slide" axis="1 0 0"/><joint name="z" type="slide" axis="0 0 1"/>
<geom type="box" size="0.0185 0.0135 0.005" mass="0.1"/></body></worldbody></mujoco>"""
# a scene of the general pass with every part the ground memory meets there (one compiled program): a tilted height
# field of poppy seeds (x < 0, the kernel's batched dry strip) beside loose 0.3 mm glass under 1 cm of water, each
# with its own closely minus loosely packed row, with the inertial regime
SCENE = {"medium": "poppy_cp", "law": "rft", "surface": "ground", "inertial": True, "transition": 0.02,
         "regions": [Region(0.0, "glass03_lp", "rft", water_depth=0.01)]}
# the foot's centre (x, height above the undisturbed surface), m: above fresh grains in the water (within reach of the
# water only: culled at the sand, it would miss the water's drag), on into the dry strip,
# pressed in, dragged level across the strips' edge, lifted into the water, moved back over its ridges, pressed in on
# its own track and dragged level (a footprint that neither deepens nor fills: the bodies' volume in a cell equals
# what it has taken to rounding, which mjrft.ground.DEEPEN_TOL keeps from deciding the kernel's and JAX's branches)
PATH = ((0.04, 0.011), (-0.045, 0.01), (-0.045, -0.006), (0.05, -0.006), (0.05, 0.009), (-0.03, 0.006),
        (-0.03, -0.008), (0.02, -0.008))
SPEED = 0.2  # m/s; at the rig's 5 ms step a sample every 1 mm, an update of the ground at every step


def rig(memory=True, **changes):
    """(model, terrain) of a box foot on slide joints in x and z over :data:`SCENE` (with ``changes``) with a ground
    memory on a small grid of 6 mm cells (the foot's 5 mm elements fall on no cell edge)."""
    m = mujoco.MjModel.from_xml_string(RIG)
    options = GroundOptions(cell=0.006, extent=(-0.1, 0.1, -0.05, 0.05), period=0.002) if memory else False
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return m, mjrft.GranularTerrain(m, resolution=0.005, ground_memory=options, **{**SCENE, **changes})


def drag(m, t, shift=0.0):
    """The foot moved kinematically along :data:`PATH` (shifted by ``shift`` in x) on terrain ``t``: (model,
    terrain, the MjData of each step, the wrench of each step), as :func:`walk`."""
    step = SPEED * m.opt.timestep
    pts = [np.array(PATH[0])]
    for a, b in zip(PATH[:-1], PATH[1:]):
        a, b = np.array(a), np.array(b)
        n = int(np.ceil(np.linalg.norm(b - a) / step))
        pts += [a + (b - a) * (k + 1) / n for k in range(n)]
    d = mujoco.MjData(m)
    datas, wrenches = [], []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a kinematic rig: the stability checks do not apply
        for k, (x, z) in enumerate(pts):
            v = pts[min(k + 1, len(pts) - 1)] - pts[max(k - 1, 0)]
            d.qpos[:] = (x + shift, z + float(t.surface_height(x + shift, 0.0)))
            d.qvel[:] = v / np.linalg.norm(v) * SPEED
            mujoco.mj_fwdPosition(m, d)
            mujoco.mj_fwdVelocity(m, d)
            d.time += m.opt.timestep
            wrenches.append(t.compute(d).copy())
            datas.append(copy.copy(d))
    return m, t, datas, np.array(wrenches)


def test_the_general_pass_reads_and_updates_the_ground_as_the_kernel():
    """Two worlds under ``vmap``, the second's track 13 mm further along x (so it crosses the strips' edge
    elsewhere)."""
    runs = [drag(*rig(), shift) for shift in (0.0, 0.013)]
    m, t = runs[0][0], runs[0][1]
    sand = rmjx.Sand.from_terrain(t, guards=False)
    assert sand.general and sand.hfield and sand.features.water and sand.features.inertia
    state, w = replay(sand, m, runs, x64=True)
    for k, (_, tk, _, wrench) in enumerate(runs):
        cpu = tk.terrain_state
        assert cpu.g_clock[1] > 10 and cpu.g_height.min() < -3e-3 and cpu.g_height.max() > 3e-3  # prints, ridges
        assert np.ptp(cpu.g_phi) > 5e-3  # the packing changed (and the elements read it: the control below)
        assert relative(w[k], wrench) <= 1e-9, (k, relative(w[k], wrench))
        assert cell_errors(state.ground.cells[k], cpu.g_cells) <= 1e-9, k
        assert np.array_equal(state.ground.clock[k], cpu.g_clock) and np.array_equal(state.ground.count[k], cpu.g_count)
    assert np.abs(runs[0][1].terrain_state.g_height - runs[1][1].terrain_state.g_height).max() > 1e-3
    # the readers equal the CPU terrain's on the height field
    x, y = np.meshgrid(np.linspace(-0.12, 0.12, 25), np.linspace(-0.06, 0.06, 13))
    with jax.enable_x64(True):
        one = jax.tree_util.tree_map(lambda a: jnp.asarray(a[0]), state)
        assert np.abs(np.asarray(sand.ground_height(one, x, y)) - t.ground_height(x, y)).max() <= 1e-12
        assert np.abs(np.asarray(sand.ground_packing(one, x, y)) - t.ground_packing(x, y)).max() <= 1e-12
    # controls, which the comparison's 1e-9 rejects by orders of magnitude: the same drag on the terrain without the
    # memory, and on the memory without its packing rows (every element with its region's prepared row)
    m0, plain = rig(memory=False)
    assert relative(drag(m0, plain)[3], runs[0][3]) > 1e-2
    tm = t.terrain_model
    unpacked = dataclasses.replace(tm, ground=tm.ground._replace(dparams=np.zeros_like(tm.ground.dparams)))
    assert relative(drag(m0, mjrft.GranularTerrain.from_model(m0, unpacked))[3], runs[0][3]) > 1e-3


def test_the_hybrid_laws_wake_equals_the_kernels():
    """The rig's scene with the hybrid law in the dry strip (x < 0; the inertial regime is the dry laws'): the foot
    pressed in and dragged on, its bottom's elements behind its leading face moving through the slabs that face passed
    through, lifted and pressed in on its own track. Two worlds under ``vmap`` (the second's track 13 mm further
    along x) give the kernel's wrench at every step, its cells and its wake (the slabs' times, float32) at the end;
    a reset empties the wake. Control: the kernel with the wake emptied (the hybrid law without its
    undisturbed-grain rule) gives forces the comparison's 1e-9 rejects by orders of magnitude."""
    runs = [drag(*rig(law="hybrid", inertial=False), shift) for shift in (0.0, 0.013)]
    m, t = runs[0][0], runs[0][1]
    sand = rmjx.Sand.from_terrain(t, guards=False)
    assert sand.general and sand.ground.wake
    state, w = replay(sand, m, runs, x64=True)
    for k, (_, tk, _, wrench) in enumerate(runs):
        cpu = tk.terrain_state
        assert np.isfinite(cpu.g_wake).sum() > 100 and np.isinf(cpu.g_wake).any()  # marked, and cleared or untouched
        assert relative(w[k], wrench) <= 1e-9, (k, relative(w[k], wrench))
        assert cell_errors(state.ground.cells[k], cpu.g_cells) <= 1e-9, k
        np.testing.assert_array_equal(state.ground.wake[k], cpu.g_wake)
        assert state.ground.now[k] == pytest.approx(cpu.g_since[1], rel=1e-12)
    assert not np.array_equal(runs[0][1].terrain_state.g_wake, runs[1][1].terrain_state.g_wake)
    with jax.enable_x64(True):
        fresh = rmjx.Sand.reset(jax.tree_util.tree_map(lambda a: jnp.asarray(a[0]), state)).ground
        assert bool(jnp.all(jnp.isinf(fresh.wake))) and float(fresh.now) == 0.0
    # control: the same drag on the kernel with its wake emptied
    empty = mjrft.GranularTerrain.from_model(m, t.terrain_model)
    empty.terrain_state = empty.terrain_state._replace(g_wake=np.zeros((0, 0, 0), np.float32))
    assert relative(drag(m, empty)[3], runs[0][3]) > 1e-2

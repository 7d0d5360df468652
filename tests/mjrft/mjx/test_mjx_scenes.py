"""The whole terrain in MJX: strips and maps of every law, the water layer, buoyancy, the inertial regime, the
solidify option and a height-field surface take the kernel's general pass in JAX (mjrft.mjx.forces), and its wrench
and memory equal the numba kernel's on recorded states (float64 <= 1e-9 of the largest value, float32 <= 1e-4);
a terrain with its stresses doubled is rejected by the same comparison, and the implicit step's applied wrench
equals the CPU's with the inertial regime (whose dampers join the springs in the implicit solve)."""

from __future__ import annotations

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
from mjrft.mjx.compare import record_states, replay_steps, wrench_errors  # noqa: E402
from mjrft.models import hexapod_model, hexapod_shoal_model  # noqa: E402
from mjrft.regions import RegionMap  # noqa: E402

pytestmark = pytest.mark.slow  # every test compiles MJX programs (5-30 s each on 2 cores)

HFIELD = """<mujoco><option timestep="0.001"/><asset><hfield name="hf" nrow="3" ncol="4" size="0.3 0.2 0.05 0.1"
elevation="0.8 0.9 1.0 0.0  0.4 0.5 0.6 0.7  0 0.1 0.2 0.3"/></asset><worldbody>
<geom name="ground" type="hfield" hfield="hf" pos="0.1 -0.05 0.01" euler="0 0 0.4" contype="0" conaffinity="0"/>
<body name="b" pos="0 0 0.09"><freejoint/><geom name="g" type="box" size="0.03 0.02 0.004" mass="0.1"/></body>
</worldbody></mujoco>"""
# label -> (model, start x, terrain keywords, steps): together they use every law, strips and a map with their
# transitions, a water layer over saturated sand, open water, buoyancy, the inertial regime, solidify, a height field
SCENES = {
    "shoal strips, water, buoyancy": (hexapod_shoal_model, 0.9, {"buoyancy": True}, 200),
    "map of rft, rft3d, hybrid, inertial": (hexapod_model, 0.0, {
        "regions": [("poppy_lp", "rft3d"), ("poppy_cp", "hybrid")], "inertial": True, "transition": 0.02,
        "region_map": RegionMap(np.array([[0, 1, 2], [2, 1, 0]]), -0.1, -0.15, (0.1, 0.15))}, 200),
    "height field, solidify": (lambda: mujoco.MjModel.from_xml_string(HFIELD), 0.0,
                               {"surface": "ground", "resolution": 0.004, "solidify": 2.0}, 300),
}


def tripod(m):
    return (lambda t: 2 * np.pi * 2.0 * t + np.arange(m.nu) % 2 * np.pi) if m.nu else None


def record(label, stress_scale=1.0):
    make, x0, kw, steps = SCENES[label]
    m = make()
    d = mujoco.MjData(m)
    d.qpos[0] = x0
    if not m.nu:
        d.qvel[0] = 0.2  # the box slides across the height field
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t = mjrft.GranularTerrain(m, **kw)
        if stress_scale != 1.0:
            t.set_medium(stress_scale=stress_scale)
        states = record_states(m, t, steps, steps // 6, ctrl=tripod(m), data=d)
    return m, t, states


@pytest.fixture(scope="module", params=list(SCENES))
def scene(request):
    return request.param, *record(request.param)


def test_the_general_pass_equals_the_kernel_on_recorded_states(scene):
    label, m, t, states = scene
    assert sum(np.abs(s.wrench).max() > 0 for s in states) >= len(states) // 2  # mostly on the grains
    sand = rmjx.Sand.from_terrain(t)
    assert sand.general
    wrench, memory = wrench_errors(sand, m, states, x64=True)
    assert wrench <= 1e-9 and memory <= 1e-9, (label, wrench, memory)
    if label.startswith("shoal"):  # float32 on one scene (each dtype compiles its own program)
        wrench, memory = wrench_errors(sand, m, states, x64=False)
        assert wrench <= 1e-4 and memory <= 1e-4, (label, wrench, memory)
    # control: the same comparison rejects the terrain with its granular stresses doubled
    doubled = rmjx.Sand.from_terrain(record(label, stress_scale=2.0)[1])
    assert wrench_errors(doubled, m, states, x64=True)[0] > 0.1


def test_the_implicit_step_with_the_inertial_regime_equals_the_cpus():
    model = hexapod_model()  # the inertial regime's dampers join the springs in the implicit solve
    kw = {"medium": "glass3_cp", "inertial": True}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        states = replay_steps(model, kw, 300, 50, ctrl=tripod(model))
        terrain = mjrft.GranularTerrain(model, implicit=True, **kw)
    with jax.enable_x64(True):
        mx = mjx.put_model(model)
        sand = rmjx.Sand.from_terrain(terrain)
        step = jax.jit(sand.step)
        for before, u, f_implicit, _, qvel in states:
            d, state = step(mx, mjx.put_data(model, before), sand.init()._replace(u=jnp.asarray(u)))
            scale = np.abs(f_implicit).max()
            assert np.abs(np.asarray(state.wrench) - f_implicit).max() <= 1e-9 * scale
            assert np.abs(np.asarray(d.qvel) - qvel).max() <= 1e-9 * np.abs(qvel).max()

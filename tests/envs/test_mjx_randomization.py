"""The MJX envs' per-world terrain randomisation (``randomization``: media, stress scale, surface raise, a rough
height field, strips of media along x) against the gymnasium env's draws (:mod:`mjrft.envs.randomization`): the
statistics of what each world draws, and the granular wrench on a drawn terrain against the CPU terrain given the
same surface and regions."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

jax = pytest.importorskip("jax", reason="the MJX env needs the optional extra mjrft[mjx] (JAX)")
pytest.importorskip("brax", reason="the MJX env needs Brax (mjrft[mjx])")

import jax.numpy as jnp  # noqa: E402
from mujoco import mjx  # noqa: E402

import mjrft.mjx.envs as envs  # noqa: E402
from mjrft import Region  # noqa: E402
from mjrft.envs.mjx.locomotion import UNUSED_STRIP_X  # noqa: E402
from mjrft.envs.randomization import rough_field  # noqa: E402
from mjrft.mjx.compare import _relative, record_states  # noqa: E402

pytestmark = pytest.mark.slow  # compiles the MJX reset and the general element pass

MEDIA = ["poppy_cp", "glass03_cp"]
ROUGH, CORR = 0.003, 0.05
OPTIONS = {"randomization.media": MEDIA, "randomization.stress_scale": [0.7, 1.3],
           "randomization.surface_height": [-0.004, 0.004], "randomization.roughness": ROUGH,
           "randomization.correlation_length": CORR, "randomization.strips": [0, 3],
           "randomization.strip_length": [0.05, 0.15], "randomization.strip_start": -0.3}


@pytest.fixture(scope="module")
def env():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return envs.load("HexapodSand", config_overrides=OPTIONS)


def _correlation(h: np.ndarray, lag: int) -> float:
    """``<h(x) h(x + lag)> / <h^2>`` along x (the columns), over every world's field."""
    return float(np.mean(h[..., :-lag] * h[..., lag:]) / np.mean(h * h))


def test_each_world_draws_a_rough_field_and_strips_repeatably(env):
    assert env.sand.general and env.sand.hfield and env.sand.bounds.shape == (3,)  # the most strips, a height field
    keys = jax.random.split(jax.random.PRNGKey(0), 8)
    reset = jax.jit(jax.vmap(env.reset))
    a, b = reset(keys), reset(keys)
    for k in ("medium", "stress_scale", "surface_height", "roughness", "strips", "strip_x_min", "strip_medium"):
        np.testing.assert_array_equal(np.asarray(a.info[k]), np.asarray(b.info[k]))
    np.testing.assert_array_equal(np.asarray(a.info["sand"].surface), np.asarray(b.info["sand"].surface))
    # the field: the surface less the model's own and the raise; mean 0 and RMS exactly `roughness` per world
    base = np.asarray(env.sand.surface_init)
    field = np.asarray(a.info["sand"].surface) - base - np.asarray(a.info["surface_height"])[:, None, None]
    assert field.shape == (8, *base.shape)
    np.testing.assert_allclose(np.sqrt(np.mean(field ** 2, axis=(1, 2))), ROUGH, rtol=1e-5)
    np.testing.assert_allclose(np.asarray(a.info["roughness"]), ROUGH, rtol=1e-5)
    assert np.all(np.abs(np.mean(field, axis=(1, 2))) < 1e-6 * ROUGH)
    assert min(np.abs(field[i] - field[j]).max() for i in range(8) for j in range(i)) > ROUGH  # worlds differ
    # the correlation model: the CPU's numpy fields' correlation at a lag of one and two correlation lengths
    grid = 0.01
    lag = int(round(CORR / grid))
    rng = np.random.default_rng(0)
    cpu = np.stack([rough_field(rng, base.shape, (grid, grid), ROUGH, CORR) for _ in range(8)])
    for n in (1, 2):
        theirs, ours = _correlation(cpu, n * lag), _correlation(field, n * lag)
        assert abs(ours - theirs) < 0.05 and abs(ours - math.exp(-n * n)) < 0.08, (n, ours, theirs)
    # the strips: count in [0, 3], increasing x_min whose gaps are strip lengths, the unused ones beyond any bed
    n = np.asarray(a.info["strips"])
    x = np.asarray(a.info["strip_x_min"])
    med = np.asarray(a.info["strip_medium"])
    bounds = np.asarray(a.info["sand"].bounds)
    assert set(n) >= {1, 2, 3} and np.all(n <= 3)
    for i in range(8):
        used = x[i, :n[i]]
        steps = np.diff(np.concatenate([[-0.3], used]))
        assert np.all((steps >= 0.05 - 1e-7) & (steps <= 0.15 + 1e-7))
        assert np.all(np.isinf(x[i, n[i]:])) and np.all(med[i, n[i]:] == -1) and np.all(med[i, :n[i]] >= 0)
        np.testing.assert_array_equal(bounds[i, :n[i]], used)
        assert np.all(bounds[i, n[i]:] >= UNUSED_STRIP_X) and np.all(np.diff(bounds[i]) > 0)
    assert len({tuple(np.round(r, 6)) for r in x}) == 8  # every world its own layout
    # the region rows: region 0 the bed's medium, each strip its own, all with the stress scale
    sand = a.info["sand"]
    i = int(np.argmax(n))
    scale = float(a.info["stress_scale"][i])
    rows = [env.sand.params_of(MEDIA[int(a.info["medium"][i])], scale),
            *(env.sand.params_of(MEDIA[k], scale) for k in med[i, :n[i]])]
    np.testing.assert_allclose(np.asarray(sand.params[i, :n[i] + 1]), rows, rtol=1e-6)


def _cpu_twin(env, drawn, media):
    """The gymnasium env of ``env``'s configuration with its terrain set to the drawn one of ``drawn`` (one world's
    reset State): medium, stress scale, strips, surface."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cpu = env.gym_env()
    t = cpu.unwrapped.terrain
    info = drawn.info
    n = int(info["strips"])
    t.set_regions([Region(float(x), media[int(k)], t.law)
                   for x, k in zip(np.asarray(info["strip_x_min"])[:n], np.asarray(info["strip_medium"])[:n])])
    t.set_medium(media[int(info["medium"])], float(info["stress_scale"]))
    t.set_surface(np.asarray(info["sand"].surface, dtype=np.float64))
    return cpu


def test_a_drawn_terrain_gives_the_cpu_terrains_wrench(env):
    """In float64, on CPU states of the hexapod settling into a drawn terrain (rough surface, strips under its legs),
    the MJX sand of the drawn state gives the CPU terrain's wrench to 1e-9 when the CPU terrain has the same surface
    and regions set; controls: another world's surface, or another world's strips, are rejected."""
    with jax.enable_x64(True):
        keys = jax.random.split(jax.random.PRNGKey(0), 8)
        reset = jax.jit(env.reset)
        worlds = [reset(k) for k in keys[:4]]
        drawn = next(w for w in worlds if int(w.info["strips"]) >= 2)
        other = next(w for w in worlds if w is not drawn)
        cpu = _cpu_twin(env, drawn, env.media)
        u = cpu.unwrapped
        t = u.terrain
        states = record_states(u.model, t, steps=240, every=60)
        cpu.close()
        buried = t.terrain_state.depth > 0
        assert len(np.unique(t.terrain_state.region[buried])) >= 2  # the legs stand in more than one strip
        wrench = jax.jit(env.sand.wrench)
        mine, theirs = drawn.info["sand"], other.info["sand"]
        cases = {"drawn": mine, "another surface": mine._replace(surface=theirs.surface),
                 "another layout": mine._replace(bounds=theirs.bounds, params=theirs.params)}
        errors = {name: 0.0 for name in cases}
        for s in states:
            d = mjx.put_data(u.model, s.data)
            for name, sand in cases.items():
                w, _ = wrench(d, sand._replace(u=jnp.asarray(s.u_before)), u.model.opt.timestep)
                errors[name] = max(errors[name], _relative(np.asarray(w), s.wrench))
    assert max(np.abs(s.wrench).max() for s in states) > 0.1  # the legs carry the robot
    assert errors["drawn"] <= 1e-9, errors
    assert errors["another surface"] > 1e-3 and errors["another layout"] > 1e-3, errors


@pytest.mark.parametrize("override, match", [
    ({"randomization.roughness": -0.001}, "roughness"),
    ({"randomization.strips": [1, 2]}, "strips need media"),
    ({"randomization.strips": [3, 1], "randomization.media": MEDIA}, "strips must be"),
    ({"randomization.strip_length": [0.2, 0.1], "randomization.strips": 1, "randomization.media": MEDIA},
     "strip_length"),
    ({"randomization.roughness": 0.002, "randomization.correlation_length": 0.01}, "correlation_length"),
])
def test_bad_options_are_refused_when_the_env_is_made(override, match):
    with pytest.raises(ValueError, match=match), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        envs.load("HexapodSand", config_overrides=override)

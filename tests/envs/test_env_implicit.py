"""The envs' ``implicit`` keyword: the implicit granular step in the gymnasium env, its vector env and its MJX twin."""

import gymnasium
import numpy as np
import pytest

import mjrft.envs  # noqa: F401
from mjrft.tools.gaits import make_gait


def _walk(steps: int = 30, **kw) -> np.ndarray:
    env = gymnasium.make("mjrft/HexapodSand-v0", **kw)
    gait = make_gait("tripod:f=2.0", env)
    obs, _ = env.reset(seed=0)
    for _ in range(steps):
        obs, *_ = env.step(gait.predict(obs)[0])
    qpos = env.unwrapped.data.qpos.copy()
    env.close()
    return qpos


def test_implicit_builds_the_implicit_terrain_and_changes_the_step():
    env = gymnasium.make("mjrft/HexapodSand-v0", implicit=True)
    assert env.unwrapped.terrain.implicit
    assert not gymnasium.make("mjrft/HexapodSand-v0").unwrapped.terrain.implicit
    implicit, explicit = _walk(implicit=True), _walk()
    assert np.all(np.isfinite(implicit))
    # the same walk, a different integration: within a few mm after 0.3 s, not the same bits
    assert 0.0 < np.max(np.abs(implicit[:3] - explicit[:3])) < 0.01


def test_implicit_takes_a_step_the_explicit_coupling_cannot():
    # 4 ms passes the legs' explicit stability limit (~1 ms): the explicit step warns, the implicit one does not
    from mjrft import TerrainStabilityWarning

    with pytest.warns(TerrainStabilityWarning):
        _walk(60, timestep=0.004, frame_skip=2, implicit=False)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error", TerrainStabilityWarning)
        assert np.all(np.isfinite(_walk(60, timestep=0.004, frame_skip=2, implicit=True)))


def test_implicit_must_be_a_bool_or_none():
    with pytest.raises(TypeError, match=r"implicit must be True, False or None \(the robot's own\), got 'yes'"):
        gymnasium.make("mjrft/HexapodRigid-v0", implicit="yes")


def test_the_vector_env_steps_implicit_envs_as_single_envs():
    from mjrft.envs.vector import GranularVectorEnv

    vec = GranularVectorEnv("mjrft/HexapodSand-v0", 2, implicit=True)
    singles = [gymnasium.make("mjrft/HexapodSand-v0", implicit=True) for _ in range(2)]
    vec.reset(seed=[3, 4])
    for e, s in zip(singles, (3, 4)):
        e.reset(seed=s)
    rng = np.random.default_rng(0)
    for _ in range(5):
        a = rng.uniform(-1, 1, (2, 6)).astype(np.float32)
        vobs = vec.step(a)[0]
        sobs = np.stack([e.step(a[i])[0] for i, e in enumerate(singles)])
    np.testing.assert_array_equal(vobs, sobs)


def test_the_mjx_env_takes_the_implicit_step_of_its_configuration():
    pytest.importorskip("jax")
    from mjrft.envs import mjx as envs

    assert envs.get_default_config("HexapodSand").terrain.implicit is False
    env = envs.load("HexapodSand", config_overrides={"terrain.implicit": True})
    assert env.sand.implicit and env.gym_kwargs == {"implicit": True}
    assert not envs.load("HexapodSand").sand.implicit

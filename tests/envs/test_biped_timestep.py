"""The sand biped's default physics step: the implicit step at 2 ms, stable under random actions where the explicit
step passes the feet's granular-stiffness limit (mjrft.stability)."""

import warnings

import gymnasium
import numpy as np
import pytest

import mjrft.envs  # noqa: F401
from mjrft import TerrainStabilityWarning
from mjrft.envs.biped import SAND_FRAME_SKIP, SAND_TIMESTEP


def test_sand_biped_default_step_keeps_the_10_ms_control_period():
    u = gymnasium.make("mjrft/BipedSand-v0").unwrapped
    assert (u.model.opt.timestep, u.frame_skip) == (SAND_TIMESTEP, SAND_FRAME_SKIP) == (0.002, 5)
    assert u.dt == pytest.approx(0.01) and u.terrain.implicit
    assert not gymnasium.make("mjrft/BipedSand-v0", implicit=False).unwrapped.terrain.implicit
    rigid = gymnasium.make("mjrft/BipedRigid-v0").unwrapped
    assert (rigid.model.opt.timestep, rigid.frame_skip) == (0.001, 10)


def _stability_warnings(**kw) -> int:
    """TerrainStabilityWarnings over 300 env steps of uniformly random actions (``action_space.sample()``,
    seed 0), the episodes reset when they end."""
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always", TerrainStabilityWarning)
        env = gymnasium.make("mjrft/BipedSand-v0", **kw)
        env.action_space.seed(0)
        env.reset(seed=0)
        for _ in range(300):
            _, _, terminated, truncated, _ = env.step(env.action_space.sample())
            if terminated or truncated:
                env.reset()
    return sum(issubclass(w.category, TerrainStabilityWarning) for w in rec)


@pytest.mark.slow
def test_random_actions_stay_inside_the_feet_stability_limit():
    # control: the explicit step at the model's own 1 ms (the same 10 ms control period) passes the feet's limit
    # (0.98 ms here); the default implicit step at 2 ms does not warn
    assert _stability_warnings(timestep=0.001, frame_skip=10, implicit=False) > 0
    assert _stability_warnings() == 0

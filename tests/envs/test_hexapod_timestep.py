"""The sand hexapods' default physics step stays under the legs' granular-stiffness limit (mjrft.stability)."""

import warnings

import gymnasium
import numpy as np
import pytest

import mjrft.envs  # noqa: F401
from mjrft import TerrainStabilityWarning
from mjrft.envs.hexapod import SAND_FRAME_SKIP, SAND_TIMESTEP


def test_sand_hexapod_default_step_keeps_the_10_ms_control_period():
    u = gymnasium.make("mjrft/HexapodSand-v0").unwrapped
    assert (u.model.opt.timestep, u.frame_skip) == (SAND_TIMESTEP, SAND_FRAME_SKIP)
    assert u.dt == pytest.approx(0.01)
    rigid = gymnasium.make("mjrft/HexapodRigid-v0").unwrapped
    assert (rigid.model.opt.timestep, rigid.frame_skip) == (0.001, 10)


def test_a_preset_keeps_the_own_step_and_an_explicit_step_wins():
    u = gymnasium.make("mjrft/HexapodSand-v0", preset="fast").unwrapped
    assert (u.model.opt.timestep, u.frame_skip) == (SAND_TIMESTEP, SAND_FRAME_SKIP)
    u = gymnasium.make("mjrft/HexapodSand-v0", timestep=0.00025, frame_skip=40).unwrapped
    assert (u.model.opt.timestep, u.frame_skip) == (0.00025, 40)


def _stability_warnings(**kw) -> int:
    """TerrainStabilityWarnings over 2 s of the initial PPO policy's actions (mean 0, s.d. 0.6, clipped)."""
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always", TerrainStabilityWarning)
        env = gymnasium.make("mjrft/HexapodSand-v0", **kw)
        rng = np.random.default_rng(1)
        env.reset(seed=1)
        for _ in range(200):
            env.step(np.clip(rng.normal(0.0, 0.6, 6), -1.0, 1.0).astype(np.float32))
    return sum(issubclass(w.category, TerrainStabilityWarning) for w in rec)


@pytest.mark.slow
def test_random_actions_stay_inside_the_legs_stability_limit():
    # control: a 2 ms step (the same 10 ms control period) passes the legs' limit (0.93-1.2 ms here) within these 2 s
    assert _stability_warnings(timestep=0.002, frame_skip=5) > 0
    assert _stability_warnings() == 0

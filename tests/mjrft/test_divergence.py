"""A diverged simulation is never silently restarted: MuJoCo's reset is detected, named and ends the episode."""

from __future__ import annotations

import warnings

import gymnasium
import mujoco
import numpy as np
import pytest

import mjrft
from mjrft.models import hexapod_model

pytestmark = pytest.mark.filterwarnings("ignore::mjrft.TerrainStabilityWarning",
                                        "ignore::mjrft.ValidityRangeWarning")


def _walking_hexapod():
    m = hexapod_model()
    d = mujoco.MjData(m)
    t = mjrft.GranularTerrain(m, resolution=0.01)
    t.step(d, 100)
    return m, d, t


def test_terrain_step_raises_when_mujoco_resets_a_huge_velocity():
    m, d, t = _walking_hexapod()
    d.qvel[:] = 1e3
    with pytest.raises(mjrft.NonFiniteError, match=r"diverged: MuJoCo found a non-finite or huge acceleration "
                                                    r".* on body '\w+' between t = 0\.1 s .* reset the state"):
        t.step(d, 10)


def test_terrain_step_raises_when_mujoco_resets_a_nan_position():
    m, d, t = _walking_hexapod()
    d.qpos[7] = np.nan  # a leg joint
    with pytest.raises(mjrft.NonFiniteError, match=r"non-finite or huge position \(qpos\[7\]\) on body 'leg_"):
        t.step(d, 1)


def test_callback_mode_raises_from_the_step_that_mujoco_reset():
    m, d, t = _walking_hexapod()
    with t:
        mujoco.mj_step(m, d)
        d.qpos[7] = np.nan  # mj_step resets the state before its forward pass, which calls the terrain
        with pytest.raises(mjrft.NonFiniteError, match=r"diverged: .* position \(qpos\[7\]\) on body 'leg_"):
            mujoco.mj_step(m, d)
        mujoco.mj_step(m, d)  # raised once: the next step goes on from MuJoCo's reset state


def test_a_fresh_reset_by_the_user_is_not_a_divergence():
    m, d, t = _walking_hexapod()
    mujoco.mj_resetData(m, d)
    t.step(d, 10)  # no error: mj_resetData clears MuJoCo's counters
    assert d.time == pytest.approx(0.01)


@pytest.mark.parametrize("env_id", ["mjrft/HexapodSand-v0", "mjrft/HexapodRigid-v0"])
def test_env_ends_a_diverged_episode_with_the_reason(env_id):
    env = gymnasium.make(env_id)
    env.reset(seed=0)
    for _ in range(30):
        env.step(np.zeros(env.action_space.shape))
    env.unwrapped.data.qvel[:] = 1e3
    obs, reward, terminated, truncated, info = env.step(np.zeros(env.action_space.shape))
    assert terminated and not truncated and reward == 0.0 and info["x_velocity"] == 0.0
    assert "diverged" in info["diverged"] and "between t = 0.3 s" in info["diverged"]
    assert np.all(np.isfinite(obs))
    obs, info = env.reset(seed=1)
    assert "diverged" not in info
    obs, reward, terminated, truncated, info = env.step(np.zeros(env.action_space.shape))
    assert not terminated and "diverged" not in info
    env.close()


@pytest.mark.slow
def test_vector_env_ends_only_the_diverged_episode():
    from mjrft.envs.vector import GranularVectorEnv

    venv = GranularVectorEnv("mjrft/HexapodSand-v0", 2)
    venv.reset(seed=0)
    zeros = np.zeros((2, *venv.single_action_space.shape))
    for _ in range(5):
        venv.step(zeros)
    venv.envs[1].data.qvel[:] = 1e3
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        obs, reward, terminated, truncated, info = venv.step(zeros)
    assert list(terminated) == [False, True] and reward[1] == 0.0
    assert "diverged" in info and info["_diverged"][1] and not info["_diverged"][0]
    assert "diverged" in info["diverged"][1]
    venv.close()


def test_rollout_and_eval_say_a_run_diverged_instead_of_printing_numbers(capsys):
    from mjrft.tools import cli
    from mjrft.train.evaluate import evaluate
    from mjrft.train.rollout import rollout

    s = rollout("mjrft/HexapodSand-v0", "tripod", seconds=1.0, env_kwargs={"timestep": 0.1})
    assert "diverged" in s["diverged"] and not s["fell"]
    rows, summary = evaluate("tripod", "mjrft/HexapodSand-v0", episodes=2,
                             env_kwargs={"timestep": 0.1, "max_episode_steps": 5})
    assert summary["diverged"] == 2 and np.isnan(summary["speed"]) and all(r["diverged"] for r in rows)
    assert cli.main(["rollout", "--env", "mjrft/HexapodSand-v0", "--policy", "tripod", "--seconds", "1",
                     "--no-progress", "timestep=0.1"]) == 1  # every episode diverged: exit status 1
    out = capsys.readouterr().out
    assert "DIVERGED after 1 steps" in out and "no distance, speed or sinkage" in out and " cm" not in out
    assert cli.main(["eval", "--env", "mjrft/HexapodSand-v0", "--policy", "tripod", "--episodes", "2", "--no-progress",
                     "timestep=0.1", "max_episode_steps=5"]) == 1
    out = capsys.readouterr().out
    assert "DIVERGED: 2 of 2 episodes" in out and "nan" not in out

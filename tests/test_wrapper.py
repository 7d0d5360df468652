"""GranularWrapper and the sand variants of gymnasium's five MuJoCo robots (kept fast: a few steps each)."""

from __future__ import annotations

import copy
import warnings

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")
pytest.importorskip("imageio")  # gymnasium.envs.mujoco needs it (gymnasium[mujoco])

import mujoco  # noqa: E402

import mjrft  # noqa: E402
from mjrft.envs import GYM_SAND_IDS, GranularWrapper  # noqa: E402
from mjrft.envs.wrapper import SAND_RGBA  # noqa: E402

IDS = list(GYM_SAND_IDS)


def quiet_make(env_id, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return gymnasium.make(env_id, **kw)


@pytest.mark.parametrize("env_id", IDS)
def test_robot_resets_steps_and_passes_both_checkers(env_id):
    from gymnasium.utils.env_checker import check_env

    env = quiet_make(env_id, max_episode_steps=5)
    obs, info = env.reset(seed=0)
    assert env.observation_space.contains(obs)
    w = env.env
    while not isinstance(w, GranularWrapper):
        w = w.env
    n = len(w.body_names)
    assert info["sinkage"].shape == (n,) and info["granular_force"].shape == (n, 3)
    stock = gymnasium.make(GYM_SAND_IDS[env_id])
    assert env.unwrapped.dt == pytest.approx(stock.unwrapped.dt)  # the control period is gymnasium's
    t0 = env.unwrapped.data.time
    for _ in range(3):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert np.all(np.isfinite(obs)) and np.isfinite(reward) and "diverged" not in info
        assert info["substeps"] >= 1
    assert env.unwrapped.data.time - t0 == pytest.approx(3 * stock.unwrapped.dt)
    assert env.unwrapped.model.opt.timestep == stock.unwrapped.model.opt.timestep  # restored between steps
    # the floor is the sand: its contacts are gone in the loaded model, and it is drawn as sand
    m = env.unwrapped.model
    assert w.floor_geoms and all(m.geom_contype[g] == 0 and m.geom_conaffinity[g] == 0 for g in w.floor_geoms)
    assert np.allclose(m.geom_rgba[w.floor_geoms[0]], SAND_RGBA)
    stock.close()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        check_env(w, skip_render_check=True)
        from stable_baselines3.common.env_checker import check_env as sb3_check_env

        sb3_check_env(w, warn=False)
    env.close()


def _ant(**kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return GranularWrapper(gymnasium.make("Ant-v5"), "poppy_cp", **kw)


def test_cfrc_ext_carries_the_sand_force_in_mujocos_convention():
    env = _ant()
    env.reset(seed=0)
    u = env.unwrapped
    zero = np.zeros(u.model.nu)
    for _ in range(40):  # 2 s: the ant falls onto the sand and comes to rest
        env.step(zero)
    m, d = u.model, u.data
    # MuJoCo's own mapping of the same wrench, applied as xfrc_applied, gives the same cfrc_ext
    d2 = copy.copy(d)
    d2.xfrc_applied[:] = 0.0
    d2.xfrc_applied[env.body_ids] = env.terrain.wrench[env.body_ids]
    mujoco.mj_rnePostConstraint(m, d2)
    np.testing.assert_allclose(d.cfrc_ext, d2.cfrc_ext, rtol=1e-9, atol=1e-9)
    # at rest on sand (no rigid floor) the sand carries the weight, and the observation's cfrc_ext part sees it
    weight = m.body_subtreemass[0] * -m.opt.gravity[2]
    assert d.cfrc_ext[:, 5].sum() / weight == pytest.approx(1.0, abs=0.02)
    obs, *_ = env.step(zero)
    assert np.any(obs[-d.cfrc_ext[1:].size:] != 0.0)
    assert np.any(env.sinkage() > 0)


def test_substeps_keep_dt_and_follow_the_rule():
    env = _ant()
    u = env.unwrapped
    h, frame_skip = u.model.opt.timestep, u.frame_skip
    env.reset(seed=0)
    ks = [env.step(np.zeros(u.model.nu))[4]["substeps"] for _ in range(10)]
    assert min(ks) > 1  # Ant-v5's 10 ms step is beyond the sand's stable limit
    assert u.model.opt.timestep == h and u.frame_skip == frame_skip and u.dt == h * frame_skip
    assert "EULER" in env.integrator and u.model.opt.integrator == mujoco.mjtIntegrator.mjINT_EULER  # was RK4
    fixed = _ant(substeps=3)
    fixed.reset(seed=0)
    t0 = fixed.unwrapped.data.time
    info = fixed.step(np.zeros(u.model.nu))[4]
    assert info["substeps"] == 3 and fixed.unwrapped.data.time - t0 == pytest.approx(u.dt)
    # reproducible: the rule depends on the state only
    again = _ant()
    again.reset(seed=0)
    assert [again.step(np.zeros(u.model.nu))[4]["substeps"] for _ in range(10)] == ks


def test_the_implicit_step_takes_fewer_substeps_than_the_explicit_one():
    """Ant-v5 at its 10 ms step (benchmarks/implicit_accuracy.py): the default implicit step resolves the stiffest
    spring at omega dt <= 1 in fewer sub-steps than the explicit step needs for stability; spring_step=0.5 takes at
    least as many as the default; both carry the resting ant."""
    counts = {}
    for name, kw in (("implicit", {}), ("finer", {"spring_step": 0.5}), ("explicit", {"implicit": False})):
        env = _ant(**kw)
        assert env.terrain.implicit == (name != "explicit")
        env.reset(seed=0)
        zero = np.zeros(env.unwrapped.model.nu)
        counts[name] = [env.step(zero)[4]["substeps"] for _ in range(40)]
        weight = env.unwrapped.model.body_subtreemass[0] * 9.81
        assert env.granular_force()[:, 2].sum() / weight == pytest.approx(1.0, abs=0.02)
    assert np.mean(counts["implicit"]) < np.mean(counts["explicit"])
    assert np.mean(counts["finer"]) >= np.mean(counts["implicit"])


def test_a_diverged_step_terminates_with_the_reason():
    env = _ant()
    env.reset(seed=0)
    u = env.unwrapped
    u.data.xfrc_applied[1, 2] = 1e40  # MuJoCo finds a huge acceleration and resets the state
    obs, reward, terminated, truncated, info = env.step(np.zeros(u.model.nu))
    assert terminated and reward == 0.0 and "diverged" in info and "torso" in info["diverged"]
    assert np.all(np.isfinite(obs))
    t = u.data.time
    assert env.step(np.zeros(u.model.nu))[2]  # stays ended: the physics does not go on from the reset state
    assert u.data.time == t
    u.data.xfrc_applied[:] = 0.0
    env.reset(seed=1)
    obs, reward, terminated, truncated, info = env.step(np.zeros(u.model.nu))
    assert "diverged" not in info and not terminated


def test_bad_wrapper_arguments():
    cart = gymnasium.make("CartPole-v1")
    with pytest.raises(TypeError, match="MujocoEnv"):
        GranularWrapper(cart)
    with pytest.raises(TypeError, match="gymnasium.Env"):
        GranularWrapper("Ant-v5")
    ant = gymnasium.make("Ant-v5")
    with pytest.raises(ValueError, match="unknown GranularWrapper option 'resolutoin'.*resolution"):
        GranularWrapper(ant, resolutoin=0.01)
    for bad in (0, -1, 2.5, True, "many"):
        with pytest.raises(ValueError, match="substeps must be 'auto' or an integer >= 1"):
            GranularWrapper(ant, substeps=bad)
    with pytest.raises(ValueError, match="max_substeps"):
        GranularWrapper(ant, max_substeps=0)
    for bad in (0, -1.0, float("nan"), float("inf"), True, "1"):
        with pytest.raises(ValueError, match="spring_step must be a finite number > 0"):
            GranularWrapper(ant, spring_step=bad)
    for bad in ((1, 0, 0), (1, 0, 0, 2), "red"):
        with pytest.raises(ValueError, match="sand_rgba"):
            GranularWrapper(ant, sand_rgba=bad)
    with pytest.raises(ValueError, match="unknown medium"):
        GranularWrapper(ant, medium="quicksand")
    m = ant.unwrapped.model  # a refused setting leaves the env as it was
    assert m.opt.integrator == mujoco.mjtIntegrator.mjINT_RK4 and m.geom_contype[0] + m.geom_conaffinity[0] > 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        GranularWrapper(ant)
        with pytest.raises(ValueError, match="only once"):
            GranularWrapper(ant)
        with pytest.raises(ValueError, match="mjrft's own environments"):
            GranularWrapper(gymnasium.make("mjrft/HexapodSand-v0"))
    with pytest.raises(ValueError, match="unknown keyword argument of Hopper-v5 on sand 'medum'"):
        gymnasium.make("mjrft/HopperSand-v5", medum="poppy_cp")


def test_kwargs_split_and_make_vec():
    env = quiet_make("mjrft/HopperSand-v5", medium="poppy_lp", resolution=0.02, frame_skip=2, substeps=2)
    w = env.env
    while not isinstance(w, GranularWrapper):
        w = w.env
    assert w.terrain.medium.name == "poppy_lp" and w.terrain.resolution == 0.02 and w.substeps == 2
    assert env.unwrapped.frame_skip == 2
    envs = gymnasium.make_vec("mjrft/HopperSand-v5", num_envs=2, vectorization_mode="sync")
    obs, infos = envs.reset(seed=0)
    obs, rewards, terminated, truncated, infos = envs.step(envs.action_space.sample())
    assert obs.shape == (2, 11) and infos["sinkage"].shape[0] == 2
    envs.close()


class _Zero:
    """A policy object (``predict``) holding every actuator at zero."""

    def __init__(self, n):
        self.n = n

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        return np.zeros(self.n, dtype=np.float32), None


def test_eval_and_rollout_on_a_sand_variant():
    from mjrft.train.evaluate import evaluate
    from mjrft.train.rollout import rollout
    from mjrft.train.train import check_env_id, valid_env_kwargs

    check_env_id("mjrft/HopperSand-v5")
    names = valid_env_kwargs("mjrft/HopperSand-v5")
    assert {"medium", "resolution", "substeps", "frame_skip", "max_episode_steps"} <= set(names)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rows, summary = evaluate(_Zero(3), "mjrft/HopperSand-v5", episodes=1, env_kwargs={"max_episode_steps": 20})
        result = rollout("mjrft/HopperSand-v5", _Zero(3), steps=60)
    assert rows[0]["steps"] > 0 and rows[0]["sink_peak_mm"] > 0 and np.isfinite(rows[0]["cot"])
    assert not rows[0]["diverged"] and result["steps"] > 0 and result["peak_sinkage_mm"] > 0

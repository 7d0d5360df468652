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


def test_resolution_scale_alone_scales_the_auto_element_size():
    t1, t2 = (quiet_make("mjrft/HopperSand-v5", **kw).get_wrapper_attr("terrain")
              for kw in ({}, {"resolution_scale": 2}))
    assert t1.resolution_auto and t2.resolution_auto
    assert t2.resolution == pytest.approx(2.0 * t1.resolution)
    assert t2.n_elements < t1.n_elements / 3
    with pytest.raises(ValueError, match="both set the element size"):
        GranularWrapper(gymnasium.make("Hopper-v5"), resolution=0.02, resolution_scale=2.0)


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


MUJOCO_V5 = sorted(i for i, s in gymnasium.registry.items()
                   if i.endswith("-v5") and "gymnasium.envs.mujoco" in str(s.entry_point))
REFUSED = {"Reacher-v5": "floor='auto' found no collision plane",  # its ground is visual-only
           "InvertedPendulum-v5": "floor='auto' found no collision plane",  # no floor geom at all
           "Swimmer-v5": "no geoms selected for the granular terrain"}  # every geom is visual-only


@pytest.mark.parametrize("gym_id", MUJOCO_V5)
def test_every_accepted_gymnasium_robot_passes_check_env_and_rebuilds_from_its_spec(gym_id):
    from gymnasium.utils.env_checker import check_env

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if gym_id in REFUSED:
            with pytest.raises(ValueError, match=REFUSED[gym_id]):
                GranularWrapper(gymnasium.make(gym_id))
            return
        env = GranularWrapper(gymnasium.make(gym_id), "poppy_lp", substeps=2)
        check_env(env, skip_render_check=True)
        again = gymnasium.make(env.spec)  # the spec records the wrapper and its arguments
    assert isinstance(again, GranularWrapper) and again.spec == env.spec
    assert again.terrain.medium.name == "poppy_lp" and again.substeps == 2  # not the defaults
    again.close()
    env.close()


def test_a_registered_sand_variant_rebuilds_from_its_spec():
    env = quiet_make("mjrft/HopperSand-v5", medium="poppy_lp", sand_rgba=np.array([1.0, 0.0, 0.0, 1.0]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        again = gymnasium.make(env.spec)
    w = again.env
    while not isinstance(w, GranularWrapper):
        w = w.env
    assert w.terrain.medium.name == "poppy_lp" and np.allclose(w.unwrapped.model.geom_rgba[w.floor_geoms[0]],
                                                               [1, 0, 0, 1])


def test_non_finite_or_misshapen_actions_are_refused_before_anything_is_simulated():
    env = quiet_make("mjrft/AntSand-v5")
    env.reset(seed=0)
    t = env.unwrapped.data.time
    last = np.r_[np.zeros(7), 1.0]
    for bad in (np.full(8, np.nan), np.r_[np.zeros(7), np.inf], np.r_[np.zeros(7), -np.inf],
                np.full(8, np.nan, dtype=np.float32), (last * np.inf).astype(np.float16),
                (last * np.nan).astype(np.longdouble), last * complex(0, np.inf)):  # every float kind and width
        with pytest.raises(ValueError, match="action contains NaN or infinite values"):
            env.step(bad)
    with pytest.raises(ValueError, match=r"action must be numbers of shape \(8,\), got float64 of shape \(7,\)"):
        env.step(np.zeros(7))
    assert env.unwrapped.data.time == t
    obs, reward, terminated, truncated, info = env.step(np.zeros(8))  # control: a finite action steps
    assert np.isfinite(reward) and env.unwrapped.data.time > t and "diverged" not in info
    env.close()


def _sand(env):
    w = env
    while not isinstance(w, GranularWrapper):
        w = w.env
    return w


def _trajectory(env, seed: int = 0, steps: int = 30):
    obs, info = env.reset(seed=seed)
    actions = np.random.default_rng(1).uniform(-1, 1, (steps,) + env.action_space.shape)
    out = [obs]
    for a in actions:
        out.append(env.step(a)[0])
    return np.array(out), info


RANDOMIZATION = {"media": ["poppy_cp", "poppy_lp", "glass03_lp"], "stress_scale": (0.7, 1.3),
                 "surface_height": [-0.01, 0.01]}


def test_terrain_randomization_on_a_sand_variant_draws_from_the_seed():
    env = quiet_make("mjrft/HopperSand-v5", terrain_randomization=RANDOMIZATION)
    w = _sand(env)
    floor = w.floor_geoms[0]
    draws = []
    for seed in range(5):
        info = env.reset(seed=seed)[1]["terrain"]
        draws.append(info)
        # what info says is what the terrain and its rendering are
        assert w.terrain.medium.name == info["medium"] and w.terrain.stress_scale == info["stress_scale"]
        assert w.terrain.surface == pytest.approx(info["surface_height"])
        assert w.unwrapped.model.geom_pos[floor, 2] == pytest.approx(info["surface_height"])
    assert len({(d["medium"], d["stress_scale"], d["surface_height"]) for d in draws}) == 5  # seeds differ
    assert env.reset(seed=3)[1]["terrain"] == draws[3]  # the same seed, the same terrain
    assert env.step(env.action_space.sample())[4]["terrain"] == draws[3]
    env.close()
    with pytest.raises(mjrft.errors.UnknownNameError, match="unknown terrain_randomization medium 'quicksand'"):
        quiet_make("mjrft/HopperSand-v5", terrain_randomization={"media": ["quicksand"]})
    hopper = gymnasium.make("Hopper-v5")
    with pytest.raises(ValueError, match="roughness needs a height-field sand surface: .*floor geom 'floor'"):
        GranularWrapper(hopper, terrain_randomization={"roughness": 0.005})
    m = hopper.unwrapped.model  # refused after the terrain was built: the env is left as it was
    assert (m.geom_contype[0], m.geom_conaffinity[0]) == (1, 1) and m.opt.integrator == mujoco.mjtIntegrator.mjINT_RK4


def test_terrain_randomization_off_or_drawing_the_own_terrain_steps_the_same_trajectory():
    plain, info = _trajectory(quiet_make("mjrft/HopperSand-v5"))
    assert "terrain" not in info
    for option in (None, {}, {"media": ["poppy_cp"], "stress_scale": 1.0}):
        env = quiet_make("mjrft/HopperSand-v5", terrain_randomization=option)
        traj, info = _trajectory(env)
        assert np.array_equal(traj, plain), option  # bit for bit: the draws come after the env's own noise
        assert ("terrain" in info) == bool(option)
    # control: a drawn terrain does change the trajectory
    traj, _ = _trajectory(quiet_make("mjrft/HopperSand-v5", terrain_randomization=RANDOMIZATION))
    assert not np.allclose(traj, plain)


def _sand_warnings(make):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        env = make()
    return env, [str(w.message) for w in caught if issubclass(w.category, mjrft.SandContactWarning)]


def test_a_robot_that_never_meets_the_sand_is_named_in_a_warning():
    # InvertedDoublePendulum: its floor (the sand) is 3 m below a cart on a rail carrying 1.2 m of poles
    env, notes = _sand_warnings(lambda: GranularWrapper(gymnasium.make("InvertedDoublePendulum-v5")))
    assert len(notes) == 1 and "never reach the sand surface at -3 m (the top of 'floor')" in notes[0]
    assert "'cpole2' (body 'pole2', bottom 0.555 m, reach -1.245 m)" in notes[0]
    # Pusher: a fixed arm in zero gravity above its table, and a puck that only slides across it
    env, notes = _sand_warnings(lambda: GranularWrapper(gymnasium.make("Pusher-v5")))
    assert len(notes) == 1 and "fixed to the world" in notes[0] and "gravity does not pull down" in notes[0]
    assert "(body 'object', bottom -0.325 m, reach -0.325 m)" in notes[0]
    assert "body 'r_wrist_roll_link'" in notes[0]
    # controls: robots that fall onto the sand (a vertical slide, a free joint) give no such warning
    for gym_id in ("Hopper-v5", "Ant-v5"):
        env, notes = _sand_warnings(lambda: GranularWrapper(gymnasium.make(gym_id)))
        assert not notes, gym_id


def test_a_model_with_visual_only_geoms_gets_an_error_that_says_how_to_select_them():
    with pytest.raises(ValueError, match=r"all 3 of its box, capsule, .* geoms are visual-only \(contype = "
                                         r"conaffinity = 0\): '#1' \(body 'torso'\), '#2' \(body 'mid'\), '#3' "
                                         r"\(body 'back'\); select them: bodies=\['torso', 'mid', 'back'\]"):
        GranularWrapper(gymnasium.make("Swimmer-v5"))
    # the selection the error gives works (with the floor named: Swimmer's is visual-only too)
    env, notes = _sand_warnings(lambda: GranularWrapper(gymnasium.make("Swimmer-v5"), bodies=["torso", "mid", "back"],
                                                        floor="floor"))
    assert env.terrain.n_elements > 0 and env.terrain.surface == -0.1


@pytest.mark.parametrize("joint, reach, falls", [
    ('<joint type="slide" axis="0 0 1" range="-0.3 0"/>', 0.65, True),  # the 0.95 m bottom slides 0.3 m down
    ('<joint type="slide" axis="0 0 1" range="0 0.3"/>', 0.95, False),  # ... only up
    ('<joint type="slide" axis="1 0 0"/>', 0.95, False),  # across, unlimited
    ('<joint type="slide" axis="0 0 1"/>', -np.inf, True),  # down, unlimited
    ('<joint type="hinge" axis="0 1 0" pos="-0.5 0 0"/>', 0.45, False),  # a 0.5 m arm swings the box through 0.45 m
    ('<freejoint/>', -np.inf, True)])
def test_lowest_reach_bounds_what_the_joints_allow(joint, reach, falls):
    from mjrft.reach import lowest_reach

    m = mujoco.MjModel.from_xml_string(f'<mujoco><worldbody><body pos="0 0 1">{joint}<geom type="sphere" '
                                       f'size="0.05"/></body></worldbody></mujoco>')
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)
    assert lowest_reach(m, d, 0, 0.95) == pytest.approx((reach, falls))
    m.opt.gravity[2] = 0.0  # nothing falls without gravity
    assert lowest_reach(m, d, 0, 0.95) == pytest.approx((reach, False))

"""Tests of the Gymnasium environments in mjrft.envs (kept fast: short episodes)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")
pytest.importorskip("imageio")  # gymnasium.envs.mujoco needs it (gymnasium[mujoco])

import mjrft.envs  # noqa: E402
from mjrft.envs import ENV_IDS, register_envs  # noqa: E402
from mjrft.envs.hexapod import HexapodSand  # noqa: E402
from mjrft.envs.humanoid import HumanoidSand  # noqa: E402

ALL_IDS = list(ENV_IDS)


def make(env_id, **kw):
    kw.setdefault("max_episode_steps", 20)
    return gymnasium.make(env_id, **kw)


def test_registration_idempotent():
    register_envs()
    register_envs()
    for env_id in ALL_IDS:
        assert env_id in gymnasium.registry
        assert gymnasium.registry[env_id].max_episode_steps == mjrft.envs.MAX_EPISODE_STEPS
    env = gymnasium.make("mjrft.envs:mjrft/HexapodRigid-v0", max_episode_steps=5)
    env.close()


@pytest.mark.parametrize("env_id", ALL_IDS)
def test_env_checkers(env_id):
    from gymnasium.utils.env_checker import check_env

    env = make(env_id)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        check_env(env.unwrapped, skip_render_check=True)
    try:
        from stable_baselines3.common.env_checker import check_env as sb3_check_env
    except ImportError:
        sb3_check_env = None
    if sb3_check_env is not None:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sb3_check_env(env, warn=False)
    env.close()


@pytest.mark.parametrize("env_id", ALL_IDS)
def test_step_info_and_spaces(env_id):
    env = make(env_id)
    obs, info = env.reset(seed=1)
    assert env.observation_space.contains(obs)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
    n_feet = len(env.unwrapped.foot_names)
    assert np.isfinite(reward)
    assert isinstance(info["x_velocity"], float)
    assert info["sinkage"].shape == (n_feet,)
    assert info["granular_force"].shape == (n_feet, 3)
    if "Rigid" in env_id:
        assert env.unwrapped.terrain is None and not info["granular_force"].any()
    else:
        assert env.unwrapped.terrain is not None
    env.close()


@pytest.mark.parametrize("env_id", ["mjrft/HexapodSand-v0", "mjrft/BipedSand-v0", "mjrft/HumanoidRigid-v0"])
def test_seeding_reproduces_trajectories(env_id):
    envs = [make(env_id), make(env_id)]
    rng = np.random.default_rng(3)
    actions = rng.uniform(-1, 1, size=(15,) + envs[0].action_space.shape).astype(np.float32)
    runs = []
    for env in envs:
        obs, _ = env.reset(seed=42)
        traj = [obs]
        for a in actions:
            obs, *_ = env.step(a)
            traj.append(obs)
        runs.append(np.array(traj))
    np.testing.assert_array_equal(runs[0], runs[1])
    # a reset with the same seed on a used env (terrain memory cleared) reproduces it as well
    obs, _ = envs[0].reset(seed=42)
    np.testing.assert_array_equal(obs, runs[0][0])
    for i, a in enumerate(actions[:5]):
        obs, *_ = envs[0].step(a)
        np.testing.assert_array_equal(obs, runs[0][i + 1])
    # a different seed gives a different start
    obs, _ = envs[1].reset(seed=43)
    assert not np.array_equal(obs, runs[0][0])


@pytest.mark.parametrize("kwargs, match", [
    ({"medium": "quicksand"}, "quicksand"),
    ({"law": "magic"}, "magic"),
    ({"resolution": -0.01}, "resolution"),
    ({"frame_skip": 0}, "frame_skip"),
    ({"frame_skip": -3}, "frame_skip"),
    ({"bed_depth": -1.0}, "bed_depth"),
    ({"render_mode": "ascii"}, "render_mode"),
])
def test_bad_kwargs_raise(kwargs, match):
    with pytest.raises(ValueError, match=match):
        HexapodSand(**kwargs)


def test_bad_kwargs_other_envs():
    with pytest.raises(ValueError, match="valid choices"):
        gymnasium.make("mjrft/BipedRigid-v0", medium="mud")
    with pytest.raises(ValueError, match="task"):
        gymnasium.make("mjrft/HumanoidSand-v0", task="dance")
    with pytest.raises(ValueError, match="foot_width"):
        gymnasium.make("mjrft/HumanoidSand-v0", foot_width=-0.3)


@pytest.mark.parametrize("env_id", ["mjrft/HexapodSand-v0", "mjrft/BipedRigid-v0", "mjrft/HumanoidSand-v0"])
def test_nan_action_raises(env_id):
    env = make(env_id)
    env.reset(seed=0)
    state = env.unwrapped.data.qpos.copy()
    action = np.zeros(env.action_space.shape, np.float32)
    action[0] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        env.step(action)
    np.testing.assert_array_equal(env.unwrapped.data.qpos, state)  # nothing was simulated
    env.close()


def test_render_mode_accepted():
    env = HexapodSand(sand=False, render_mode="rgb_array")  # rendering itself needs MUJOCO_GL=egl/osmesa
    assert env.render_mode == "rgb_array"
    env.close()


@pytest.mark.parametrize("kwargs, match", [
    ({"width": 0}, "width"), ({"height": 12.5}, "height"), ({"healthy_z_range": (0.5, 0.1)}, "healthy_z_range"),
    ({"max_tilt": -1.0}, "max_tilt"),
])
def test_bad_render_and_health_kwargs_raise(kwargs, match):
    with pytest.raises(ValueError, match=match):
        gymnasium.make("mjrft/BipedSand-v0", **kwargs)


def test_common_kwargs_reach_every_env():
    """Rendering size and the health thresholds are accepted by every robot; the robot's own
    defaults apply where they are not given."""
    for env_id in ("mjrft/HexapodSand-v0", "mjrft/BipedRigid-v0", "mjrft/HumanoidSand-v0", "mjrft/HexapodShoal-v0"):
        env = gymnasium.make(env_id, render_mode="rgb_array", width=64, height=48, max_tilt=0.7)
        u = env.unwrapped
        assert (u.width, u.height, u.task.max_tilt) == (64, 48, 0.7)
        assert u.task.healthy_z_range == tuple(u.defaults["healthy_z_range"])
        env.close()


RENDER_SCRIPT = """
import sys
import mujoco
try:
    mujoco.GLContext(8, 8).make_current()
except Exception as exc:
    print("NO-GL", type(exc).__name__, exc)
    sys.exit(0)
import gymnasium, numpy as np, mjrft
env = gymnasium.make("mjrft/HexapodSand-v0", render_mode="rgb_array", width=160, height=120)
env.reset(seed=0)
for _ in range(3):
    env.step(np.full(6, 0.5, np.float32))
img = env.render()
print("SHAPE", img.shape, img.dtype, int(img.std() > 5.0), int(img.reshape(-1, 3).max(axis=1).min() < 255))
env.close()
"""


def test_rgb_array_renders_headless_with_egl():
    """``render_mode="rgb_array"`` off-screen through EGL (``MUJOCO_GL=egl``; Mesa's EGL works without a
    GPU). In a subprocess: the GL backend is fixed when mujoco is first imported. Skipped only where
    no EGL context can be created at all."""
    import os
    import subprocess
    import sys
    env = dict(os.environ, MUJOCO_GL="egl", PYOPENGL_PLATFORM="egl")
    out = subprocess.run([sys.executable, "-c", RENDER_SCRIPT], env=env, capture_output=True, text=True,
                         timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    if "NO-GL" in out.stdout:
        pytest.skip(f"no EGL context on this machine: {out.stdout.strip()}")
    assert "SHAPE (120, 160, 3) uint8 1 1" in out.stdout, out.stdout + out.stderr[-2000:]


def test_time_limits():
    env = make("mjrft/BipedRigid-v0", max_episode_steps=3)
    env.reset(seed=0)
    truncated = [env.step(np.zeros(8, np.float32))[3] for _ in range(3)]
    assert truncated == [False, False, True]
    env = HexapodSand(sand=False, episode_seconds=0.05)
    env.reset(seed=0)
    truncated = [env.step(np.zeros(6, np.float32))[3] for _ in range(5)]
    assert truncated == [False] * 4 + [True]


def test_hexapod_alternating_tripod_moves_forward_on_poppy_seeds():
    """Open-loop alternating tripod at 2 Hz (tripods half a turn apart) walks forward on poppy seeds."""
    env = HexapodSand(medium="poppy_lp")
    env.reset(seed=0)
    u = env.unwrapped
    a_run = 2 * np.pi * 2.0 / u.task.max_hip_speed  # 2 Hz
    n_offset = int(round(np.pi / (u.task.max_hip_speed * u.dt)))  # tripod B half a turn ahead at full speed
    x0 = u.data.qpos[0]
    steps = int(round(2.0 / u.dt))
    for k in range(steps):
        a = np.full(6, a_run, np.float32)
        if k < n_offset:
            a[:] = 0.0
            a[list(u.TRIPOD_B_IDX)] = 1.0
        obs, reward, terminated, truncated, info = env.step(a)
        assert not terminated
    dx = u.data.qpos[0] - x0
    assert u.data.time == pytest.approx(2.0)
    assert dx > 0.02, dx
    assert np.all(info["sinkage"] >= 0)


def test_humanoid_stands_on_wide_feet():
    """HumanoidSand, task stand, 30 cm wide feet on poppy_cp: holding the initial targets stays up 2 s."""
    env = HumanoidSand(task="stand", foot_width=0.30, medium="poppy_cp")
    env.reset(seed=0)
    hold = np.zeros(19, np.float32)  # a = 0: the initial joint targets
    for _ in range(int(round(2.0 / env.dt))):
        obs, reward, terminated, truncated, info = env.step(hold)
        assert not terminated
    assert env.torso_height() > 0.7
    assert env.torso_tilt() < 0.1
    assert np.all(info["sinkage"] > 0)
    # the feet carry the weight through the grains
    total_fz = info["granular_force"][:, 2].sum()
    assert total_fz == pytest.approx(50 * 9.81, rel=0.2)


def test_each_physics_step_calls_after_every_physics_step_and_changes_no_step():
    """``each_physics_step(fn)``: fn sees every physics step (frame_skip per env step, time advancing by the timestep,
    the step's own wrench) and the trajectory is the one without it; a rigid env, which has no terrain, refuses it."""
    runs = {}
    for hooked in (False, True):
        env = gymnasium.make("mjrft/HexapodSand-v0")
        u = env.unwrapped
        env.reset(seed=0)
        seen = []
        if hooked:
            u.each_physics_step(lambda data: seen.append((data.time, u.terrain.wrench[u.task.torso, 2])))
        for _ in range(3):
            env.step(np.full(6, 0.5, dtype=np.float32))
        runs[hooked] = (u.data.qpos.copy(), seen, u.frame_skip, u.model.opt.timestep)
        env.close()
    qpos, seen, frame_skip, dt = runs[True]
    assert np.array_equal(qpos, runs[False][0])
    assert len(seen) == 3 * frame_skip and np.allclose(np.diff([t for t, _ in seen]), dt)
    assert all(np.isfinite(fz) for _, fz in seen)
    rigid = gymnasium.make("mjrft/HexapodRigid-v0").unwrapped
    with pytest.raises(ValueError, match="each_physics_step needs the granular terrain"):
        rigid.each_physics_step(print)


@pytest.mark.parametrize("env_id", ["mjrft/HexapodSand-v0", "mjrft/HexapodRigid-v0", "mjrft/BipedRigid-v0"])
def test_power_is_the_mean_over_every_physics_step_of_the_step(env_id):
    """``info["power"]`` (the energy term's and ``mjrft eval``'s power) is the actuators' ``sum |force x velocity|``
    averaged over every physics step of the env step, here computed independently from each physics step's
    ``MjData`` (on sand by a twin env calling back after every physics step, on rigid ground by ``mj_step`` on a
    copy of the data). Control: the power at the step's last physics step, a sample at the end of the step,
    is not it (the servo targets jump at the start of each step)."""
    import copy

    import mujoco

    env, twin = (gymnasium.make(env_id).unwrapped for _ in range(2))
    env.reset(seed=3)
    twin.reset(seed=3)
    per = []

    def power(d):
        return float(np.sum(np.abs(d.actuator_force * d.actuator_velocity)))

    if env.terrain is not None:
        twin.each_physics_step(lambda d: per.append(power(d)))
    rng = np.random.default_rng(0)
    gaps = []
    for _ in range(6):
        action = rng.uniform(-1.0, 1.0, env.action_space.shape).astype(np.float32)
        per.clear()
        before = copy.copy(env.data)
        _, reward, _, _, info = env.step(action)
        if env.terrain is not None:
            twin_info = twin.step(action)[4]
            assert twin_info["power"] == pytest.approx(info["power"], rel=1e-12)
        else:  # the same physics steps on a copy, the power read after each
            before.ctrl[:] = env.data.ctrl
            for _ in range(env.frame_skip):
                mujoco.mj_step(env.model, before)
                per.append(power(before))
            assert np.array_equal(before.qpos, env.data.qpos)
        assert len(per) == env.frame_skip
        assert info["power"] == pytest.approx(np.mean(per), rel=1e-12)
        assert info["reward_energy"] == pytest.approx(-0.05 * np.mean(per) / env.task.weight, rel=1e-12)
        gaps.append(abs(per[-1] - np.mean(per)) / np.mean(per))
        assert env.power() == pytest.approx(per[-1], rel=1e-12)  # power(): the state's own, the last step's
    assert max(gaps) > 0.1  # control: the end-of-step sample is another number
    env.close()
    twin.close()

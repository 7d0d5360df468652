"""The registry of MJX environments (``mjrft.mjx.envs``) in MuJoCo Playground's form, checked without compiling an
environment: names, configurations and their errors, the interface, and that each MJX env is its gymnasium env's
task (the same model, step and task); the task's functions give the same values with NumPy on ``MjData`` as with
JAX on ``mjx.Data``. (Stepping the MJX envs: tests/envs/test_mjx_env.py.)"""

from __future__ import annotations

import warnings

import mujoco
import numpy as np
import pytest

jax = pytest.importorskip("jax", reason="the MJX envs need the optional extra mjrft[mjx] (JAX)")
pytest.importorskip("brax", reason="the MJX envs need Brax (mjrft[mjx])")
gymnasium = pytest.importorskip("gymnasium")

import jax.numpy as jnp  # noqa: E402
from brax.envs.base import Env as BraxEnv  # noqa: E402
from ml_collections import config_dict  # noqa: E402
from mujoco import mjx  # noqa: E402

import mjrft.envs  # noqa: E402,F401  (registers the ids)
import mjrft.mjx.envs as envs  # noqa: E402
from mjrft.envs.hexapod_mjx import HexapodSandMJX, config_of  # noqa: E402
from mjrft.envs.mjx import Hexapod, State  # noqa: E402

NAMES = ("BipedRigid", "BipedSand", "HexapodRigid", "HexapodSand", "HumanoidRigid", "HumanoidSand")  # gymnasium's
QUADRUPED = ("Go2JoystickRigid", "Go2JoystickSand")  # Playground's joystick task (tests/mjrft/mjx/test_sand_env.py)


@pytest.fixture(autouse=True)
def _quiet():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the terrain's range notes are not these tests'
        yield


def test_every_env_is_its_gymnasium_env_in_playgrounds_form():
    assert envs.names() == tuple(sorted(NAMES + QUADRUPED)) == envs.ALL_ENVS
    for name in NAMES:
        cfg = envs.get_default_config(name)
        assert isinstance(cfg, config_dict.ConfigDict) and not cfg.is_locked
        assert {"ctrl_dt", "sim_dt", "episode_length", "reward_config", "impl"} <= set(cfg)
        assert set(cfg.reward_config.scales) == {"forward", "healthy", "energy", "ctrl"}
        env = envs.load(name)
        gym = gymnasium.make(env.gym_id).unwrapped
        assert env.name == name and env.gym_kwargs == {} and env.config.is_locked
        assert isinstance(env, BraxEnv) and env.unwrapped is env and env.backend == "mjx"
        assert isinstance(env.mj_model, mujoco.MjModel) and isinstance(env.mjx_model, mjx.Model)
        assert (env.dt, env.sim_dt, env.n_substeps) == (gym.dt, gym.model.opt.timestep, gym.frame_skip)
        assert env.dt == pytest.approx(cfg.ctrl_dt, rel=1e-12) and env.sim_dt == cfg.sim_dt
        assert (env.observation_size, env.action_size) == (gym.observation_space.shape[0], gym.action_space.shape[0])
        assert type(env.task) is type(gym.task) and env.task.scales == gym.task.scales
        assert (env.task.healthy_z_range, env.task.max_tilt) == (gym.task.healthy_z_range, gym.task.max_tilt)
        assert env.mj_model.nq == gym.model.nq and np.array_equal(env.mj_model.body_mass, gym.model.body_mass)
        assert (env.sand is None) == (gym.terrain is None) == name.endswith("Rigid")
        if env.sand is not None:
            assert env.sand.n_elements == gym.terrain.n_elements
        gym.close()
    # Playground's own way of sizing the observation: the shape of reset's output, traced without compiling
    shape = jax.eval_shape(env.reset, jax.random.PRNGKey(0))
    assert isinstance(shape, State) and shape.obs.shape == (env.observation_size,)
    assert shape.data.qpos.shape == (env.mj_model.nq,) and shape.pipeline_state.qpos.shape == (env.mj_model.nq,)


def test_config_overrides_reach_the_gymnasium_env_and_bad_ones_are_refused():
    env = envs.load("BipedRigid", config_overrides={"reward_config.scales.energy": -0.1, "ctrl_dt": 0.02,
                                                     "robot.foot": "wedge", "max_tilt": 0.9})
    assert env.gym_kwargs == {"timestep": 0.001, "frame_skip": 20, "energy_cost_weight": 0.1, "max_tilt": 0.9,
                              "foot": "wedge"}
    gym = env.gym_env()
    assert gym.unwrapped.dt == env.dt == pytest.approx(0.02) and env.n_substeps == 20
    assert gym.unwrapped.task.scales == env.task.scales and env.task.scales["energy"] == -0.1
    assert env.task.max_tilt == 0.9 and env.mj_model.ngeom == gym.unwrapped.model.ngeom
    gym.close()
    cfg = envs.get_default_config("HexapodSand")
    cfg.model.bed_length = 1.5  # a keyword of the MJCF generator, added to the unlocked default
    assert envs.load("HexapodSand", config=cfg).gym_kwargs == {"bed_length": 1.5}
    with pytest.raises(ValueError, match="unknown MJX environment 'HexapodSandy'; valid choices: BipedRigid"):
        envs.load("HexapodSandy")
    with pytest.raises(KeyError, match="nonsense"):
        envs.load("HexapodSand", config_overrides={"nonsense": 1})
    with pytest.raises(ValueError, match=r"reward_config.scales.energy must be <= 0 \(a cost\), got 0.1"):
        envs.load("HexapodSand", config_overrides={"reward_config.scales.energy": 0.1})
    with pytest.raises(ValueError, match="ctrl_dt / sim_dt must be a whole number"):
        envs.load("HexapodSand", config_overrides={"ctrl_dt": 0.0101})
    with pytest.raises(ValueError, match="max_tilt must be"):  # checked once, by the gymnasium env
        envs.load("HumanoidSand", config_overrides={"max_tilt": -1.0})
    with pytest.raises(ValueError, match="unknown terrain_randomization medium .poppy_cpx."):
        envs.load("HexapodSand", config_overrides={"randomization.media": ["poppy_cpx"]})
    with pytest.raises(TypeError, match="ConfigDict"):
        Hexapod("sand", config={"ctrl_dt": 0.01})
    with pytest.raises(NotImplementedError, match="planar"):
        envs.load("HexapodSand", config_overrides={"robot.planar": True})


def test_deprecated_hexapod_env_takes_the_gymnasium_kwargs():
    with pytest.warns(DeprecationWarning, match="mjrft.mjx.envs.load"):
        env = HexapodSandMJX(max_tilt=1.0, energy_cost_weight=0.1, medium="poppy_lp", frame_skip=10)
    assert isinstance(env, Hexapod) and env.name == "HexapodSand"
    # frame_skip alone: the gymnasium env's rule, the model's 1 ms step (its own 0.5 ms x 20 only when neither is given)
    assert env.gym_kwargs == {"max_tilt": 1.0, "energy_cost_weight": 0.1, "medium": "poppy_lp", "timestep": 0.001,
                              "frame_skip": 10}
    assert (env.model, env.mx, env.frame_skip) == (env.mj_model, env.mjx_model, 10)
    fast = config_of(preset="fast")  # a preset's law and element size become explicit
    assert config_of().terrain.resolution is None  # the model's own
    own = gymnasium.make("mjrft/HexapodSand-v0").unwrapped.terrain.resolution
    assert fast.terrain.law == "rft" and fast.terrain.resolution == pytest.approx(4 * own, rel=1e-12)
    assert config_of(sand=False).sim_dt == 0.001 and "terrain" not in config_of(sand=False)
    rough = config_of(terrain_randomization={"roughness": 0.002, "strips": [1, 2], "media": ["poppy_lp"]})
    assert (rough.randomization.roughness, tuple(rough.randomization.strips)) == (0.002, (1, 2))
    with pytest.raises(ValueError, match="unknown terrain_randomization medium .poppy_cpx."):
        config_of(terrain_randomization={"media": ["poppy_cpx"]})


@pytest.mark.parametrize("env_id, kwargs", [
    ("mjrft/HexapodSand-v0", {"ctrl_cost_weight": 0.2}),
    ("mjrft/BipedSand-v0", {}),
    ("mjrft/HumanoidRigid-v0", {"task": "stand", "terminate_when_unhealthy": False}),
])
def test_task_gives_the_same_values_on_numpy_and_jax(env_id, kwargs):
    """The task's functions on the gymnasium env's state with NumPy (as the gymnasium env calls them) and on the same
    state put on the device with JAX (as the MJX env calls them) agree to float32 rounding, and the NumPy ones are
    what the gymnasium env returned."""
    env = gymnasium.make(env_id, **kwargs).unwrapped
    task = env.task
    env.reset(seed=1)
    rng = np.random.default_rng(0)
    for _ in range(4):
        action = rng.uniform(-1.2, 1.2, env.action_space.shape)
        ctrl_before = env.data.ctrl.copy()
        obs, reward, terminated, _, info = env.step(action)
    d, dx = env.data, mjx.put_data(env.model, env.data)
    ctrl = getattr(env, "target", d.ctrl)
    close = dict(rtol=2e-6, atol=2e-6)
    np.testing.assert_array_equal(task.observation(np, d, ctrl), obs)
    np.testing.assert_allclose(task.observation(jnp, dx, jnp.asarray(ctrl)), obs, **close)
    for name in ("torso_height", "torso_tilt", "is_healthy", "power"):
        a, b = getattr(task, name)(np, d), getattr(task, name)(jnp, dx)
        np.testing.assert_allclose(np.asarray(b), a, rtol=1e-5, atol=2e-5, err_msg=name)  # arccos near 1: 5e-6
    assert bool(task.is_healthy(np, d)) == info["is_healthy"]
    a = rng.uniform(-1.2, 1.2, env.action_space.shape)
    np.testing.assert_allclose(task.action_to_ctrl(jnp, dx.qpos, jnp.asarray(ctrl_before), jnp.asarray(a)),
                               task.action_to_ctrl(np, d.qpos, ctrl_before, a), **close)
    np.testing.assert_allclose(task.reset_ctrl(jnp, dx.qpos), task.reset_ctrl(np, d.qpos), **close)
    q = d.qpos + 0.01
    np.testing.assert_allclose(task.normalise_quaternions(jnp, jnp.asarray(q)), task.normalise_quaternions(np, q), **close)
    step = dict(x_velocity=info["x_velocity"], xy_velocity=np.array([info["x_velocity"], -0.02]),
                power=info["power"], action=action, healthy=np.bool_(info["is_healthy"]))
    rewards = task.rewards(np, **step)
    metrics = task.metrics(np, x_velocity=step["x_velocity"], power=step["power"], rewards=rewards)
    jrewards = task.rewards(jnp, **{k: jnp.asarray(v) for k, v in step.items()})
    jmetrics = task.metrics(jnp, x_velocity=jnp.asarray(step["x_velocity"]), power=jnp.asarray(step["power"]),
                            rewards=jrewards)
    assert list(jrewards) == list(rewards) == ["forward", "healthy", "energy", "ctrl"]
    for name, value in {**rewards, **metrics, "total": task.total(rewards)}.items():
        other = {**jrewards, **jmetrics, "total": task.total(jrewards)}[name]
        assert float(other) == pytest.approx(float(value), rel=1e-5, abs=1e-6), name
    for name in ("x_velocity", "power", "cost_of_transport", "reward_energy", "reward_ctrl", "reward_healthy"):
        assert metrics[name] == info[name], name
    if task.scales["ctrl"] != 0.0:  # control: the ctrl term is the one computed here, not a constant
        assert rewards["ctrl"] == pytest.approx(task.scales["ctrl"] * np.sum(np.square(action)), rel=1e-12)
        assert rewards["ctrl"] < 0.0
    assert bool(task.terminated(np, np.bool_(False))) == task.terminate_when_unhealthy
    env.close()


RENDER_SCRIPT = """
import sys, warnings
warnings.simplefilter("ignore")
import mujoco
try:
    mujoco.GLContext(8, 8).make_current()
except Exception as exc:
    print("NO-GL", type(exc).__name__, exc)
    sys.exit(0)
import numpy as np, jax.numpy as jnp
from mujoco import mjx
import mjrft.mjx.envs as envs
env = envs.load("HexapodSand")
m = env.mj_model
states = []
for x in (0.0, 0.1):  # two poses of one world, the second 10 cm further along x
    d = mujoco.MjData(m)
    d.qpos[0] = x
    mujoco.mj_forward(m, d)
    states.append(envs.State(mjx.put_data(m, d), jnp.zeros(env.observation_size), jnp.zeros(()), jnp.zeros(()), {}, {}))
images = env.render(states, height=120, width=160, camera="track")
one = env.render(states[0], height=120, width=160, camera="track")
print("SHAPE", len(images), images[0].shape, images[0].dtype, int(images[0].std() > 5.0),
      int(np.array_equal(one, images[0])), int(np.abs(images[0].astype(int) - images[1]).mean() > 0.5))
"""


@pytest.mark.slow  # a subprocess that imports JAX and builds the env (about 10 s)
def test_render_draws_a_worlds_states_headless_with_egl():
    """``env.render(trajectory)`` (Playground's signature) draws one world's states from ``mj_model`` off screen
    (``MUJOCO_GL=egl``; in a subprocess, since the GL backend is fixed when mujoco is imported): one image per
    state, a single state gives a single image, and two poses give two different images. Skipped only where no EGL
    context can be made."""
    import os
    import subprocess
    import sys

    env = dict(os.environ, MUJOCO_GL="egl", PYOPENGL_PLATFORM="egl")
    out = subprocess.run([sys.executable, "-c", RENDER_SCRIPT], env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    if "NO-GL" in out.stdout:
        pytest.skip(f"no EGL context on this machine: {out.stdout.strip()}")
    assert "SHAPE 2 (120, 160, 3) uint8 1 1 1" in out.stdout, out.stdout + out.stderr[-2000:]

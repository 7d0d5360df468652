"""``mjrft.mjx.on_sand``: an environment in MuJoCo Playground's form on sand. A block pushed by a motor rests on the
grains (the granular force carries its weight, its floor contact sensor reads the sand) where the same block with
the floor's contacts removed and no sand falls through; each episode draws its medium and stress scale; an
auto-reset starts a world on fresh sand (memory and the sticky bad-state record cleared, a new draw) where a step
within the episode keeps them; the wrong orders and environments are refused; the Go2 joystick tasks are
registered in Playground's form; Playground's own CheetahRun goes on sand where the ``playground`` package is
installed."""

from __future__ import annotations

import numpy as np
import pytest

jax = pytest.importorskip("jax", reason="mjrft.mjx needs the optional extra mjrft[mjx] (JAX)")
pytest.importorskip("mujoco.mjx", reason="mjrft.mjx needs mujoco-mjx (mjrft[mjx])")
pytest.importorskip("ml_collections", reason="the MJX environments need ml_collections (mjrft[mjx])")

import jax.numpy as jnp  # noqa: E402
import mujoco  # noqa: E402
from mujoco import mjx  # noqa: E402
from mjx_helpers import BlockEnv  # noqa: E402

import mjrft.mjx  # noqa: E402
from mjrft.mjx import envs as registry  # noqa: E402
from mjrft.train.mjx_ppo import wrap_for_training  # noqa: E402

G = 9.81
MEDIA = ("poppy_cp", "glass03_cp")
SCALE = (0.5, 2.0)
WORLDS = 16
STEPS = 25  # 0.5 s: the block settles in the grains well within this
LENGTH = STEPS + 5  # control steps per episode


def block_on_sand():
    return mjrft.mjx.on_sand(BlockEnv(), "poppy_cp", resolution=0.025, media=MEDIA, stress_scale=SCALE)


@pytest.fixture(scope="module")
def sand():
    return block_on_sand()


@pytest.fixture(scope="module")
def batch(sand):
    """(reset, step) of WORLDS blocks on sand under the training wrappers (episodes of LENGTH steps), compiled once."""
    env = wrap_for_training(sand, episode_length=LENGTH)
    return jax.jit(env.reset), jax.jit(env.step)


@pytest.fixture(scope="module")
def settled(batch):
    reset, step = batch
    states = [reset(jax.random.split(jax.random.PRNGKey(1), WORLDS))]
    for _ in range(STEPS):
        states.append(step(states[-1], jnp.zeros((WORLDS, 1))))
    return states


def test_blocks_rest_on_sand_and_their_floor_sensor_reads_the_sand(sand, settled):
    state = settled[-1]
    s = state.info["sand"]
    assert np.all(np.asarray(s.bad_body) == -1) and np.all(np.asarray(state.done) == 0.0)
    assert np.all(np.asarray(state.metrics["sand/diverged"]) == 0.0)
    load = np.asarray(jnp.sum(s.wrench[..., 2], axis=-1)) / (float(sand.mj_model.body_subtreemass[0]) * G)
    assert np.all(np.abs(load - 1.0) < 0.02), load  # the grains carry the weight, in every medium and scale
    depth = np.asarray(sand.sinkage(state, "block"))[:, 0]
    assert np.all((depth > 0.0) & (depth < 0.05)) and np.all(np.asarray(state.data.qpos[:, 1]) > -0.05), depth
    assert np.all(np.asarray(state.metrics["contact"]) == 1.0)  # the env's own contact sensor reads the sand
    np.testing.assert_allclose(sand.force(state, ["block"])[:, 0], s.wrench[:, 1, :3])
    assert sand.contact_sensors == ("block_floor_found",) and state.data.userdata.shape == (WORLDS, 0)
    # control: the block with the floor's contacts removed and no sand falls through, its sensor reads nothing
    m = BlockEnv().mj_model
    m.geom_contype[m.geom("floor").id] = m.geom_conaffinity[m.geom("floor").id] = 0
    d = mujoco.MjData(m)
    mujoco.mj_step(m, d, STEPS * 5)
    assert d.qpos[1] < -0.05 and d.sensordata[0] == 0.0


def test_each_reset_draws_a_medium_and_a_stress_scale(sand, settled):
    states = settled[0]
    medium, scale = np.asarray(states.info["sand_medium"]), np.asarray(states.info["sand_stress_scale"])
    assert sand.media == MEDIA and set(medium.tolist()) == {0, 1}
    assert np.all((scale >= SCALE[0]) & (scale <= SCALE[1])) and np.unique(scale).size == WORLDS
    for i in range(WORLDS):
        want = sand.sand.params_of(MEDIA[medium[i]], float(scale[i]))
        np.testing.assert_allclose(states.info["sand"].params[i], want, rtol=1e-6)
    assert np.all(np.asarray(settled[-1].info["sand_stress_scale"]) == scale)  # within the episode: the same sand


def test_auto_reset_starts_a_world_on_fresh_sand(batch, settled):
    _, step = batch
    action = jnp.zeros((WORLDS, 1))

    def poisoned(state):  # a bad-state record, which stays until the terrain is reset
        bad = jnp.full(WORLDS, 5, dtype=jnp.int32)
        return state.replace(info={**state.info, "sand": state.info["sand"]._replace(bad_body=bad)})

    state = settled[-1]
    scale0 = np.asarray(state.info["sand_stress_scale"])
    for _ in range(LENGTH - STEPS - 1):
        state = step(state, action)
    ended = step(poisoned(state), action)  # the last step of the episode
    assert np.all(np.asarray(ended.done) == 1.0) and np.all(np.asarray(ended.info["sand"].bad_body) == 5)
    assert np.all(np.asarray(ended.data.time) == 0.0)  # the auto-reset restored the first data
    fresh = step(ended, action)
    assert np.all(np.asarray(fresh.info["sand"].bad_body) == -1) and np.all(np.asarray(fresh.done) == 0.0)
    assert np.all(np.asarray(fresh.info["sand_stress_scale"]) != scale0)  # a new draw
    np.testing.assert_allclose(fresh.info["sand"].u, settled[1].info["sand"].u, atol=1e-9)  # memory from zero
    # control: a step within the episode keeps the sticky record and ends the episode on it
    mid = step(poisoned(fresh), action)
    assert np.all(np.asarray(mid.info["sand"].bad_body) == 5) and np.all(np.asarray(mid.done) == 1.0)
    assert np.all(np.asarray(mid.metrics["sand/diverged"]) == 1.0)


def test_wrong_orders_and_environments_are_refused(sand):
    env = BlockEnv()
    with pytest.raises(ValueError, match="already on sand"):
        mjrft.mjx.on_sand(sand)
    with pytest.raises(ValueError, match="put the sand on the environment itself first"):
        mjrft.mjx.on_sand(wrap_for_training(env, episode_length=10))

    class DeviceOnly(BlockEnv):
        mj_model = property(lambda self: self._mjx_model)

    with pytest.raises(TypeError, match="BEFORE mjx.put_model"):
        mjrft.mjx.on_sand(DeviceOnly())
    stale = block_on_sand()
    state = jax.eval_shape(stale.reset, jax.random.PRNGKey(0))
    stale._mjx_model = env.mjx_model  # put before the sand removed the floor's contacts
    with pytest.raises(ValueError, match="put on the device before the sand removed the floor's contacts"):
        jax.eval_shape(stale.step, state, jnp.zeros(1))

    class NoStep(BlockEnv):
        def step(self, state, action):
            return state.replace(data=mjx.forward(self._mjx_model, state.data))

    nostep = mjrft.mjx.on_sand(NoStep(), resolution=0.025)
    state = jax.eval_shape(nostep.reset, jax.random.PRNGKey(0))
    with pytest.raises(RuntimeError, match="made no mujoco.mjx.step call"):
        jax.eval_shape(nostep.step, state, jnp.zeros(1))
    with pytest.raises(NotImplementedError, match="reads 'found' only"):
        mjrft.mjx.on_sand(BlockEnv(config_overrides={"sensor_data": "found force"}), resolution=0.025)
    with pytest.raises(ValueError, match="stress_scale"):
        mjrft.mjx.on_sand(BlockEnv(), resolution=0.025, stress_scale=(2.0, 1.0))


def test_go2_joystick_is_registered_in_playground_form():
    assert {"Go2JoystickRigid", "Go2JoystickSand"} <= set(registry.names())
    cfg = registry.get_default_config("Go2JoystickSand")
    assert (cfg.ctrl_dt, cfg.sim_dt, cfg.sand.medium, cfg.sand.implicit) == (0.02, 0.002, "poppy_cp", True)
    assert "sand" not in registry.get_default_config("Go2JoystickRigid")
    env = registry.load("Go2JoystickSand", config_overrides={"sand.stress_scale": [0.8, 1.2]})
    assert env.n_substeps == 10 and env.action_size == 12 and env.stress_range == (0.8, 1.2)
    assert env.contact_sensors == ("FR_floor_found", "FL_floor_found", "RR_floor_found", "RL_floor_found")
    assert env.mj_model.geom_contype[env.floor] == 0 and env.sand.n_elements > 2000  # every collision primitive
    state = jax.eval_shape(env.reset, jax.random.PRNGKey(0))
    after = jax.eval_shape(env.step, state, jnp.zeros(12))
    assert state.obs.shape == after.obs.shape == (48,) and env.observation_size == 48
    assert set(state.metrics) == set(after.metrics) and "reward/tracking_lin_vel" in after.metrics
    assert {"command", "sand", "sand_medium", "last_contact"} <= set(after.info)
    with pytest.raises(ValueError, match="unknown MJX environment"):
        registry.load("Go1JoystickFlatTerrain")


@pytest.mark.slow
def test_playground_cheetah_on_sand_with_playground_wrappers():
    pytest.importorskip("mujoco_playground", reason="needs the optional extra mjrft[playground]")
    from mujoco_playground import registry as playground
    from mujoco_playground import wrapper

    env = mjrft.mjx.on_sand(playground.load("CheetahRun", config_overrides={"impl": "jax"}), "poppy_cp",
                            stress_scale=(0.8, 1.2))
    train_env = wrapper.wrap_for_brax_training(env, episode_length=2)
    state = jax.jit(train_env.reset)(jax.random.split(jax.random.PRNGKey(0), 2))
    weight = float(env.mj_model.body_subtreemass[0]) * G
    load = np.asarray(jnp.sum(state.info["sand"].wrench[..., 2], axis=-1)) / weight
    assert np.all(np.abs(load - 1.0) < 0.02), load  # Playground's reset lets it settle 2 s: on the grains
    step = jax.jit(train_env.step)
    for _ in range(3):  # the second step ends the episode; the third starts a new one on fresh sand
        state = step(state, jnp.zeros((2, env.action_size)))
    assert np.all(np.asarray(state.info["sand"].bad_body) == -1) and np.all(np.asarray(state.done) == 0.0)
    assert np.all(np.asarray(state.metrics["sand/diverged"]) == 0.0)

"""MJX helpers shared by the test modules that need the optional extra mjrft[mjx] (importing this module imports JAX,
so only tests that skip without it import it): a small environment in MuJoCo Playground's form."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import mujoco
from flax import struct
from ml_collections import config_dict
from mujoco import mjx

#: a 1 kg block (10 cm cube) on two slide joints (x, z), pushed along x by a motor, above a floor plane, with a
#: contact sensor of the block against the floor (Playground's foot sensors: ``data="found"``)
BLOCK = """<mujoco><option timestep="0.004"/>
<worldbody><geom name="floor" type="plane" size="2 2 0.1"/>
<body name="block" pos="0 0 0.06"><joint name="x" type="slide" axis="1 0 0"/><joint name="z" type="slide" axis="0 0 1"/>
<geom name="cube" type="box" size="0.05 0.05 0.05" mass="1"/></body></worldbody>
<actuator><motor joint="x" gear="5" ctrlrange="-1 1"/></actuator>
<sensor><contact name="block_floor_found" geom1="cube" geom2="floor" num="1" data="{data}"/></sensor>
</mujoco>"""


@struct.dataclass
class State:
    data: mjx.Data
    obs: jax.Array
    reward: jax.Array
    done: jax.Array
    metrics: dict
    info: dict


def block_config() -> config_dict.ConfigDict:
    """``floor``: False takes the floor's contacts away (the block slides on its joints, which compiles fastest)."""
    return config_dict.create(ctrl_dt=0.02, sim_dt=0.004, sensor_data="found", floor=True)


class BlockEnv:
    """The block pushed along x (reward: its speed), in MuJoCo Playground's form, its physics through ``mjx.step``."""

    def __init__(self, config=None, config_overrides=None):
        self._config = (block_config() if config is None else config).lock()
        if config_overrides:
            self._config.update_from_flattened_dict(config_overrides)
        self._mj_model = mujoco.MjModel.from_xml_string(BLOCK.format(data=self._config.sensor_data))
        self._mj_model.opt.timestep = self._config.sim_dt
        if not self._config.floor:
            self._mj_model.geom_contype[0] = self._mj_model.geom_conaffinity[0] = 0
            self._mj_model.opt.gravity[:] = 0.0
        self._mjx_model = mjx.put_model(self._mj_model)
        self.dt, self.sim_dt = self._config.ctrl_dt, self._config.sim_dt
        self.n_substeps = int(round(self.dt / self.sim_dt))

    mj_model = property(lambda self: self._mj_model)
    mjx_model = property(lambda self: self._mjx_model)
    action_size = property(lambda self: 1)
    observation_size = property(lambda self: 5)
    unwrapped = property(lambda self: self)

    def reset(self, rng):
        z = jax.random.uniform(rng, (), minval=0.0, maxval=0.005)
        data = mjx.make_data(self._mjx_model).replace(qpos=jnp.array([0.0, z]))
        data = mjx.forward(self._mjx_model, data)
        metrics = {"contact": jnp.zeros(())}
        return State(data, self._obs(data), jnp.zeros(()), jnp.zeros(()), metrics, {"rng": rng})

    def step(self, state, action):
        def one(d, _):
            return mjx.step(self._mjx_model, d.replace(ctrl=action)), None

        x0 = state.data.qpos[0]
        data = jax.lax.scan(one, state.data, None, length=self.n_substeps)[0]
        done = (data.qpos[1] < -0.3).astype(jnp.float32)
        metrics = {**state.metrics, "contact": data.sensordata[0]}
        return state.replace(data=data, obs=self._obs(data), reward=(data.qpos[0] - x0) / self.dt, done=done,
                             metrics=metrics)

    def _obs(self, data):
        return jnp.concatenate([data.qpos, data.qvel, data.sensordata[:1]])

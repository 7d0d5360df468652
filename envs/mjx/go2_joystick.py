"""The Unitree Go2 following velocity commands, MuJoCo Playground's Go1 joystick task, on rigid ground and on sand.

``Go2JoystickRigid`` and ``Go2JoystickSand`` (:data:`ENVS`, the entries of the MJX registry): the Go2 that mjrft
vendors from MuJoCo Menagerie (``models/third_party/unitree_go2/``, the MJX variant: 23 collision primitives, 12
position servos, 15.2 kg) in MuJoCo Playground's environment form (``reset(rng) -> State``,
``step(state, action) -> State``, :class:`State` with ``data``, ``obs``, ``reward``, ``done``, ``metrics``,
``info``; ``mj_model``, ``mjx_model``, ``dt``, ``sim_dt``; the configuration an ``ml_collections.ConfigDict``)
with the task of Playground's ``Go1JoystickFlatTerrain``:

* Action: 12 numbers; the servo targets are the home pose plus ``action_scale`` times the action (rad), held
  for the control step (``ctrl_dt``, ``ctrl_dt / sim_dt`` physics steps).
* Observation (48): the trunk's linear velocity in the IMU frame (3), the gyro (3), gravity in the IMU frame
  (3), the joint angles minus the home pose (12), the joint velocities (12), the last action (12), the command
  (3); each measured quantity with uniform noise of ``noise_config.level`` times its scale.
* Command (``info["command"]``): forward, sideways and yaw velocity, uniform in ``+-command_config.a`` at
  reset; re-drawn after an exponentially distributed time (mean 5 s), each component kept (probability
  ``1 - b``: zeroed, else replaced by a new uniform draw, each with probability one half).
* Reward: the sum of the terms of ``reward_config.scales`` (each a small function below, times its scale)
  times ``ctrl_dt``, clipped at 0 from below: velocity tracking (exp of the squared error over
  ``tracking_sigma``), vertical velocity, roll-pitch rate, tilt, joint-limit excursion, closeness to the home
  pose, termination, standing still at a zero command, torques, action rate, energy (the servos' power, its
  mean over every physics step of the control step), foot clearance, swing height, slip and air time. Each
  term's value (before the scale) is reported as ``metrics["reward/<term>"]``; ``metrics["power"]`` is the
  servos' mean power (W) over the control step.
* Foot contact: the contact sensors ``<foot>_floor_found`` (each foot sphere against the floor); on sand
  :func:`mjrft.mjx.on_sand` makes them read the sand (a foot below the surface).
* Start: the home keyframe moved by up to 0.5 m in x and y and turned by a uniform yaw, its trunk velocity
  uniform in +-0.5 (m/s, rad/s).
* Episode end: the trunk upside down (``done``); training wrappers cut episodes at ``episode_length``.

Contacts, as Playground's Go1 task (its ``feetonly`` model): on rigid ground only the four feet collide, with
the floor. ``Go2JoystickSand`` is :func:`mjrft.mjx.on_sand` of the rigid task with every collision primitive of
the robot in the sand (a foot sinks, the calves and the trunk meet the grains too), ``config.sand``'s medium
(default ``poppy_cp``), law, ``media`` and ``stress_scale`` (drawn per episode), the implicit granular step.

Differences from Playground's Go1 task: the robot (the Go2's own servo gains, kp 50 and kv 0.5, and its own
home pose), the physics step (the Go2 model's own 2 ms, on sand too: at 2 ms the implicit granular step carries
the standing robot's weight to within 6e-4 at every step, where the explicit step swings between 0.63 and 1.37
times it; ``benchmarks/go2_joystick.py``, docs/gpu.md), the energy term (the mean over every physics step instead
of the last one's), the soft joint limits (95 % of each joint's range about its middle) and the observation (the
policy's observation only: Playground's privileged critic observation is left out, as mjrft's saved policies take
one vector); perturbation kicks are not modelled.

>>> env = mjrft.mjx.envs.load("Go2JoystickSand")
>>> state = jax.jit(env.reset)(jax.random.PRNGKey(0))
>>> state = jax.jit(env.step)(state, jnp.zeros(env.action_size))
"""

from __future__ import annotations

import os

import jax
import jax.numpy as jnp
import mujoco
import numpy as np
from ml_collections import config_dict
from mujoco import mjx

import mjrft.models

from .env import State

XML = os.path.join(os.path.dirname(mjrft.models.__file__), "third_party", "unitree_go2", "scene_mjx.xml")
FEET = ("FR", "FL", "RR", "RL")  # the foot geoms; the foot sites are "<foot>_foot"
FLOOR = "floor"
IMU = "imu"
G = 9.81


def default_config() -> config_dict.ConfigDict:
    """The rigid task's configuration (``Go2JoystickRigid``)."""
    return config_dict.create(
        ctrl_dt=0.02,
        sim_dt=0.002,
        episode_length=1000,
        Kp=50.0,
        Kd=0.5,
        action_scale=0.5,
        soft_joint_pos_limit_factor=0.95,
        impl="jax",
        noise_config=config_dict.create(
            level=1.0,
            scales=config_dict.create(joint_pos=0.03, joint_vel=1.5, gyro=0.2, gravity=0.05, linvel=0.1),
        ),
        reward_config=config_dict.create(
            scales=config_dict.create(
                tracking_lin_vel=1.0, tracking_ang_vel=0.5,
                lin_vel_z=-0.5, ang_vel_xy=-0.05, orientation=-5.0,
                dof_pos_limits=-1.0, pose=0.5, termination=-1.0, stand_still=-1.0,
                torques=-0.0002, action_rate=-0.01, energy=-0.001,
                feet_clearance=-2.0, feet_height=-0.2, feet_slip=-0.1, feet_air_time=0.1,
            ),
            tracking_sigma=0.25,
            max_foot_height=0.1,
        ),
        command_config=config_dict.create(a=[1.5, 0.8, 1.2], b=[0.9, 0.25, 0.5]),
    )


def sand_config() -> config_dict.ConfigDict:
    """The sand task's configuration (``Go2JoystickSand``): the rigid task's and ``sand`` (:func:`mjrft.mjx.on_sand`:
    ``medium``, ``law``, ``media``, ``stress_scale`` as ``[low, high]``, ``resolution``, ``implicit``, ``cull``)."""
    cfg = default_config()
    cfg.sand = config_dict.create(medium="poppy_cp", law="rft", media=[], stress_scale=[1.0, 1.0],
                                  resolution=config_dict.placeholder(float), implicit=True,
                                  cull=config_dict.placeholder(int))
    return cfg


def load_model(config) -> mujoco.MjModel:
    """The Go2 scene for the task: feet-only collisions, the task's timestep and servo gains, and the sensors it
    reads (contact of each foot with the floor, the IMU's up vector and local velocity, the feet's positions and
    velocities), added to the vendored model (which stays unchanged on disk)."""
    spec = mujoco.MjSpec.from_file(XML)
    for g in spec.geoms:
        if g.name not in FEET and g.name != FLOOR:
            g.contype = g.conaffinity = 0
    site, geom = mujoco.mjtObj.mjOBJ_SITE, mujoco.mjtObj.mjOBJ_GEOM
    for f in FEET:
        spec.add_sensor(name=f"{f}_floor_found", type=mujoco.mjtSensor.mjSENS_CONTACT, objtype=geom, objname=f,
                        reftype=geom, refname=FLOOR, intprm=[1, 0, 1])  # data "found", one slot
        spec.add_sensor(name=f"{f}_pos", type=mujoco.mjtSensor.mjSENS_FRAMEPOS, objtype=site, objname=f"{f}_foot")
        spec.add_sensor(name=f"{f}_global_linvel", type=mujoco.mjtSensor.mjSENS_FRAMELINVEL, objtype=site,
                        objname=f"{f}_foot")
    spec.add_sensor(name="upvector", type=mujoco.mjtSensor.mjSENS_FRAMEZAXIS, objtype=site, objname=IMU)
    spec.add_sensor(name="local_linvel", type=mujoco.mjtSensor.mjSENS_VELOCIMETER, objtype=site, objname=IMU)
    model = spec.compile()
    model.opt.timestep = config.sim_dt
    model.actuator_gainprm[:, 0] = config.Kp
    model.actuator_biasprm[:, 1] = -config.Kp
    model.actuator_biasprm[:, 2] = -config.Kd
    return model


class Go2Joystick:
    """``Go2JoystickRigid``: the Go2 following velocity commands on rigid ground (module docstring)."""

    def __init__(self, config: config_dict.ConfigDict | None = None, config_overrides: dict | None = None):
        config = default_config() if config is None else config
        self._config = config.lock()
        if config_overrides:
            self._config.update_from_flattened_dict(config_overrides)
        cfg = self._config
        steps = cfg.ctrl_dt / cfg.sim_dt
        if not (cfg.sim_dt > 0 and steps >= 1 and abs(steps - round(steps)) < 1e-9):
            raise ValueError(f"ctrl_dt ({cfg.ctrl_dt}) must be a whole multiple of sim_dt ({cfg.sim_dt})")
        self._ctrl_dt, self._sim_dt = float(cfg.ctrl_dt), float(cfg.sim_dt)
        self._mj_model = load_model(cfg)
        self._mjx_model = mjx.put_model(self._mj_model, impl=cfg.impl)
        m = self._mj_model
        home = m.keyframe("home")
        self._init_q = jnp.asarray(home.qpos)
        self._default_pose = jnp.asarray(home.qpos[7:])
        lo, hi = m.jnt_range[1:].T
        mid, half = (lo + hi) / 2, (hi - lo) / 2 * cfg.soft_joint_pos_limit_factor
        self._soft_lo, self._soft_hi = jnp.asarray(mid - half), jnp.asarray(mid + half)
        self._imu = m.site(IMU).id
        self._trunk = m.body("base").id
        self._foot_sites = np.array([m.site(f"{f}_foot").id for f in FEET])
        self._contact_adr = np.array([m.sensor_adr[m.sensor(f"{f}_floor_found").id] for f in FEET])
        self._foot_vel_adr = np.stack([m.sensor_adr[m.sensor(f"{f}_global_linvel").id] + np.arange(3) for f in FEET])
        self._cmd_a = jnp.asarray(cfg.command_config.a)
        self._cmd_b = jnp.asarray(cfg.command_config.b)
        self._mass = float(m.body_subtreemass[self._trunk])

    # ------------------------------------------------------------------ Playground's MjxEnv interface
    @property
    def mj_model(self) -> mujoco.MjModel:
        return self._mj_model

    @property
    def mjx_model(self) -> mjx.Model:
        return self._mjx_model

    @property
    def xml_path(self) -> str:
        return XML

    @property
    def dt(self) -> float:
        return self._ctrl_dt

    @property
    def sim_dt(self) -> float:
        return self._sim_dt

    @property
    def n_substeps(self) -> int:
        return int(round(self._ctrl_dt / self._sim_dt))

    @property
    def action_size(self) -> int:
        return self._mj_model.nu

    @property
    def observation_size(self) -> int:
        return 48

    @property
    def unwrapped(self) -> "Go2Joystick":
        return self

    def sensor(self, data, name: str) -> jax.Array:
        m = self._mj_model
        i = m.sensor(name).id
        return data.sensordata[m.sensor_adr[i]:m.sensor_adr[i] + m.sensor_dim[i]]

    # ------------------------------------------------------------------ episode
    def reset(self, rng: jax.Array) -> State:
        k_xy, k_yaw, k_vel, k_cmd, k_time, rng = jax.random.split(rng, 6)
        qpos = self._init_q.at[0:2].add(jax.random.uniform(k_xy, (2,), minval=-0.5, maxval=0.5))
        yaw = jax.random.uniform(k_yaw, (), minval=-3.14, maxval=3.14)
        qpos = qpos.at[3:7].set(jnp.array([jnp.cos(yaw / 2), 0.0, 0.0, jnp.sin(yaw / 2)]))  # home is upright
        qvel = jnp.zeros(self._mj_model.nv).at[0:6].set(jax.random.uniform(k_vel, (6,), minval=-0.5, maxval=0.5))
        data = mjx.make_data(self._mjx_model).replace(qpos=qpos, qvel=qvel, ctrl=qpos[7:])
        data = mjx.forward(self._mjx_model, data)
        info = {
            "rng": rng,
            "command": jax.random.uniform(k_cmd, (3,), minval=-self._cmd_a, maxval=self._cmd_a),
            "steps_until_next_cmd": self._command_hold(k_time),
            "last_act": jnp.zeros(self.action_size),
            "last_last_act": jnp.zeros(self.action_size),
            "feet_air_time": jnp.zeros(4),
            "last_contact": jnp.zeros(4, dtype=bool),
            "swing_peak": jnp.zeros(4),
        }
        metrics = {f"reward/{k}": jnp.zeros(()) for k in self._config.reward_config.scales.keys()}
        metrics.update(swing_peak=jnp.zeros(()), power=jnp.zeros(()))
        obs = self._obs(data, info)
        return State(data, obs, jnp.zeros(()), jnp.zeros(()), metrics, info)

    def step(self, state: State, action: jax.Array) -> State:
        info = dict(state.info)
        targets = self._default_pose + action * self._config.action_scale
        data, power = self._physics(state.data, targets)
        contact = data.sensordata[self._contact_adr] > 0
        seen = contact | info["last_contact"]
        first_contact = (info["feet_air_time"] > 0.0) & seen
        info["feet_air_time"] = info["feet_air_time"] + self.dt
        info["swing_peak"] = jnp.maximum(info["swing_peak"], data.site_xpos[self._foot_sites, 2])
        obs = self._obs(data, info)
        done = self.sensor(data, "upvector")[2] < 0.0
        terms = self._reward_terms(data, action, info, done, first_contact, contact, power)
        scales = self._config.reward_config.scales
        reward = jnp.clip(sum(v * scales[k] for k, v in terms.items()) * self.dt, 0.0, 1e4)
        info["last_last_act"], info["last_act"] = info["last_act"], action
        info["rng"], k_cmd, k_time = jax.random.split(info["rng"], 3)
        due = info["steps_until_next_cmd"] - 1 <= 0
        info["command"] = jnp.where(due, self.sample_command(k_cmd, info["command"]), info["command"])
        info["steps_until_next_cmd"] = jnp.where(due | done, self._command_hold(k_time),
                                                 info["steps_until_next_cmd"] - 1)
        info["feet_air_time"] = info["feet_air_time"] * ~contact
        info["last_contact"] = contact
        info["swing_peak"] = info["swing_peak"] * ~contact
        metrics = dict(state.metrics)
        metrics.update({f"reward/{k}": v for k, v in terms.items()})
        metrics.update(swing_peak=jnp.mean(info["swing_peak"]), power=power)
        return state.replace(data=data, obs=obs, reward=reward, done=done.astype(reward.dtype), metrics=metrics,
                             info=info)

    def _physics(self, data, targets):
        """``n_substeps`` steps of ``mjx.step`` with the servo targets; the servos' mean power over them (W)."""

        def one(carry, _):
            d, energy = carry
            d = mjx.step(self._mjx_model, d.replace(ctrl=targets))
            return (d, energy + jnp.sum(jnp.abs(d.qvel[6:] * d.actuator_force))), None

        (data, energy), _ = jax.lax.scan(one, (data, jnp.zeros(())), None, length=self.n_substeps)
        return data, energy / self.n_substeps

    def _command_hold(self, key) -> jax.Array:
        """Control steps until the next command: exponential, mean 5 s."""
        return jnp.round(jax.random.exponential(key) * 5.0 / self.dt).astype(jnp.int32)

    def sample_command(self, rng: jax.Array, command: jax.Array) -> jax.Array:
        """The next command: each component, with probability one half, is kept; else it becomes a new uniform draw
        in ``+-a`` (with probability ``b``) or zero."""
        k_new, k_keep, k_zero = jax.random.split(rng, 3)
        new = jax.random.uniform(k_new, (3,), minval=-self._cmd_a, maxval=self._cmd_a)
        new = jnp.where(jax.random.bernoulli(k_zero, self._cmd_b, (3,)), new, 0.0)
        return jnp.where(jax.random.bernoulli(k_keep, 0.5, (3,)), new, command)

    # ------------------------------------------------------------------ observation
    def _gravity(self, data) -> jax.Array:
        return data.site_xmat[self._imu].T @ jnp.array([0.0, 0.0, -1.0])

    def _obs(self, data, info) -> jax.Array:
        """The 48 observed numbers; draws the noise from (and advances) ``info["rng"]``."""
        scales, level = self._config.noise_config.scales, self._config.noise_config.level
        parts = [("linvel", self.sensor(data, "local_linvel")), ("gyro", self.sensor(data, "gyro")),
                 ("gravity", self._gravity(data)), ("joint_pos", data.qpos[7:] - self._default_pose),
                 ("joint_vel", data.qvel[6:])]
        out = []
        for name, value in parts:
            info["rng"], key = jax.random.split(info["rng"])
            out.append(value + level * scales[name] * jax.random.uniform(key, value.shape, minval=-1.0, maxval=1.0))
        return jnp.concatenate(out + [info["last_act"], info["command"]])

    # ------------------------------------------------------------------ reward terms
    def _reward_terms(self, data, action, info, done, first_contact, contact, power) -> dict[str, jax.Array]:
        cmd = info["command"]
        moving = jnp.linalg.norm(cmd) > 0.01
        sigma = self._config.reward_config.tracking_sigma
        local = self.sensor(data, "local_linvel")
        gyro = self.sensor(data, "gyro")
        up = self.sensor(data, "upvector")
        linvel, angvel = self.sensor(data, "global_linvel"), self.sensor(data, "global_angvel")
        q = data.qpos[7:]
        feet_vel = data.sensordata[self._foot_vel_adr]
        slip = jnp.sum(feet_vel[:, :2] ** 2, axis=-1)
        speed_xy = jnp.linalg.norm(feet_vel[:, :2], axis=-1)
        foot_z = data.site_xpos[self._foot_sites, 2]
        peak = self._config.reward_config.max_foot_height
        torques = data.actuator_force
        return {
            "tracking_lin_vel": jnp.exp(-jnp.sum((cmd[:2] - local[:2]) ** 2) / sigma),
            "tracking_ang_vel": jnp.exp(-(cmd[2] - gyro[2]) ** 2 / sigma),
            "lin_vel_z": linvel[2] ** 2,
            "ang_vel_xy": jnp.sum(angvel[:2] ** 2),
            "orientation": jnp.sum(up[:2] ** 2),
            "stand_still": jnp.sum(jnp.abs(q - self._default_pose)) * ~moving,
            "termination": done.astype(jnp.float32),
            "pose": jnp.exp(-jnp.sum((q - self._default_pose) ** 2 * jnp.array([1.0, 1.0, 0.1] * 4))),
            "torques": jnp.linalg.norm(torques) + jnp.sum(jnp.abs(torques)),
            "action_rate": jnp.sum((action - info["last_act"]) ** 2),
            "energy": power,
            "feet_slip": jnp.sum(slip * contact) * moving,
            "feet_clearance": jnp.sum(jnp.abs(foot_z - peak) * jnp.sqrt(speed_xy)),
            "feet_height": jnp.sum((info["swing_peak"] / peak - 1.0) ** 2 * first_contact) * moving,
            "feet_air_time": jnp.sum((info["feet_air_time"] - 0.1) * first_contact) * moving,
            "dof_pos_limits": jnp.sum(jnp.maximum(self._soft_lo - q, 0.0) + jnp.maximum(q - self._soft_hi, 0.0)),
        }


def robot_geoms(model: mujoco.MjModel) -> list[int]:
    """The robot's collision primitives (the Go2's ``collision`` class, geom group 3): the geoms in the sand."""
    return [g for g in range(model.ngeom) if model.geom_group[g] == 3 and model.geom_bodyid[g] != 0]


def make_sand(config: config_dict.ConfigDict | None = None, config_overrides: dict | None = None):
    """``Go2JoystickSand``: :func:`mjrft.mjx.on_sand` of :class:`Go2Joystick` with ``config.sand``."""
    from mjrft.mjx import on_sand

    config = sand_config() if config is None else config
    if "sand" not in config:
        raise ValueError("Go2JoystickSand's config needs a 'sand' section (sand_config())")
    env = Go2Joystick(config, config_overrides)
    s = env._config.sand
    extra = {k: s[k] for k in ("resolution",) if s[k] is not None}
    return on_sand(env, s.medium, s.law, media=list(s.media) or None, stress_scale=tuple(s.stress_scale),
                   implicit=s.implicit, cull=s.cull, geoms=robot_geoms(env.mj_model), **extra)


#: the registry's entries: name -> (make(config, config_overrides), default config)
ENVS = {
    "Go2JoystickRigid": (Go2Joystick, default_config),
    "Go2JoystickSand": (make_sand, sand_config),
}

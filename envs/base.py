"""Shared base class of the mjrft Gymnasium environments (a ``gymnasium.envs.mujoco.MujocoEnv``).

Every environment builds its MJCF with the parametric generators of :mod:`mjrft.models`
(``sand=True``: granular bed, forces from :class:`mjrft.GranularTerrain`; ``sand=False``: rigid floor,
plain MuJoCo contacts) and steps the simulation in :meth:`GranularMujocoEnv.do_simulation`, where
``frame_skip`` physics steps go through ONE ``terrain.step(data, frame_skip)`` call (each step is
``mj_step1`` / granular wrench / ``mj_step2``).

Common keyword arguments (all environments):

=========================  ============================================================================
``medium``                 granular medium name (``mjrft.MEDIA``) or :class:`mjrft.Medium`; default
                           from the model (``poppy_cp``). Checked also for rigid envs (then unused).
``law``                    ``"rft"``, ``"rft3d"`` or ``"depth_only"``; default from the model (``rft``).
``resolution``             surface element size (m, > 0); default from the model.
``frame_skip``             physics steps per ``step()`` (int >= 1); default 10 (or the preset's).
``timestep``               physics step (s, > 0); default the model's 1 ms (or the preset's).
``preset``                 ``"fast"``, ``"default"`` or ``"accurate"`` (:mod:`mjrft.tools.presets`): fills
                           ``law``, ``resolution`` (as a multiple of the model's own: x4, x1, x0.5, from the
                           speed/accuracy study ``mjrft bench``), ``timestep`` and ``frame_skip`` (the robot's
                           own step for ``default``, its measured ``fast_step`` and ``accurate_step``
                           for the others: always a 10 ms control period) where they are left as None;
                           explicit keyword arguments win.
``forward_reward_weight``  weight of the forward speed ``dx/dt`` (m/s) of the torso.
``energy_cost_weight``     weight of the dimensionless power ``P / (m g)`` in m/s; ``P`` (W) the actuators'
                           power ``sum_a |actuator_force_a x actuator_velocity_a|`` averaged over every
                           physics step of the control step (``info["power"]``). With weight 1 the ratio of
                           this cost to the forward reward is the cost of transport
                           (``info["cost_of_transport"]``).
``ctrl_cost_weight``       weight of ``sum(action**2)`` (default 0).
``healthy_reward``         reward per step while healthy (see each class for the thresholds).
``terminate_when_unhealthy``  end the episode (``terminated=True``) when not healthy.
``reset_noise_scale``      half width of the uniform noise added to ``qpos``/``qvel`` at reset.
``episode_seconds``        optional simulated-time limit: ``truncated=True`` once ``data.time`` reaches it
                           (the registered ids also carry ``max_episode_steps`` -> ``TimeLimit``).
``healthy_z_range``        (low, high) torso heights (m, sand surface at 0) counted as healthy.
``max_tilt``               largest healthy tilt of the torso's z axis from vertical (rad).
``render_mode``            ``None``, ``"human"``, ``"rgb_array"``, ``"depth_array"`` or ``"rgbd_tuple"``.
                           Off-screen rendering needs an OpenGL backend chosen before mujoco is
                           imported: ``MUJOCO_GL=egl`` (headless; a GPU, or Mesa's software EGL, which
                           works without a GPU) or ``MUJOCO_GL=osmesa`` (software).
``width``, ``height``      off-screen image size in pixels (default 480 x 480).
``camera_name``,           the camera to render from (a named MJCF camera, or its id); default: the
``camera_id``              free camera tracking the torso.
``terrain_randomization``  ``None`` (default: the same terrain every episode, nothing drawn), a dict of
                           options or a :class:`mjrft.envs.randomization.TerrainRandomization`: at each
                           ``reset()`` draw the medium from a list (``media``), a factor on the grains'
                           stresses (``stress_scale``), the sand surface's raise (``surface_height``)
                           and roughness (``roughness``, ``correlation_length``: a smooth random height
                           field) and a strip layout (``strips``, ``strip_length``, ``strip_start``),
                           from the env's ``np_random`` (``reset(seed=s)`` reproduces it). Sand
                           environments only. Options and their meaning: :mod:`mjrft.envs.randomization`.
``implicit``               ``True``: the implicit granular step (:class:`mjrft.GranularTerrain`'s ``implicit``; the
                           grains' springs stable at any physics step), ``False`` the explicit one; default the
                           robot's own (the biped: implicit; the hexapods and the humanoid: explicit). The
                           errors of each coupling against the physics step, per robot:
                           ``python benchmarks/env_timestep.py`` (docs/numerics.md, "Each env's physics step").
``ground_memory``          ``True`` (or a :class:`mjrft.ground.GroundOptions`): the ground remembers footprints,
                           ridges and the grains' packing within the episode (:class:`mjrft.GranularTerrain`'s
                           ``ground_memory``); ``reset()`` restores the prepared bed. Default False.
=========================  ============================================================================

Info dict (every ``step``): ``x_position``, ``x_velocity`` (m/s, torso), ``power`` (W, the actuators' mean
mechanical power over the step's physics steps: :meth:`GranularMujocoEnv.step_power`),
``cost_of_transport`` (``P / (m g max(|v_x|, 1e-3))``), ``reward_forward``, ``reward_energy``,
``reward_ctrl``, ``reward_healthy``, ``is_healthy``, ``sinkage`` (array (n_feet,), deepest element
depth below the surface of each foot/leg body in m, order ``foot_names``; zeros on rigid ground) and
``granular_force`` (array (n_feet, 3), net granular force on each foot/leg body in N, world frame;
zeros on rigid ground). With ``terrain_randomization``: ``terrain`` (also at reset), the terrain of this
episode: ``medium`` (name), ``stress_scale``, ``surface_height`` (m), ``roughness`` (m RMS) and ``strips``
(tuple of ``(x_min, medium)``).

Divergence: when the simulation diverges (a non-finite granular force or state, or MuJoCo resetting a
state it found non-finite or huge, on sand and on rigid ground alike), ``step`` does not go on from a
made-up state: it returns ``terminated=True``, reward 0, ``x_velocity`` 0 and ``info["diverged"]``
with the :class:`mjrft.NonFiniteError` message (body and time); ``reset()`` starts a new episode.
"""

from __future__ import annotations

import inspect
import math

import mujoco
import numpy as np
from gymnasium import spaces, utils
from gymnasium.envs.mujoco import MujocoEnv

from mjrft.coupler import GranularTerrain
from mjrft.divergence import mujoco_reset_error, mujoco_resets
from mjrft.errors import NonFiniteError, check_positive
from mjrft.stepping import actuator_power
from mjrft.models import model_path
from mjrft.tools.presets import FRAME_SKIP, resolve as resolve_preset

from .randomization import TerrainRandomization, TerrainRandomizer, upload_surface

G = 9.81


def rigid_steps(model: mujoco.MjModel, data: mujoco.MjData, nstep: int) -> float:
    """``nstep`` calls of ``mujoco.mj_step``; returns the actuators' power ``sum_a |actuator_force_a x
    actuator_velocity_a|`` (W) averaged over them, each step's of the state at its start, as
    :attr:`mjrft.GranularTerrain.actuator_power` averages the terrain's steps (the same compiled sum). The physics is
    ``mj_step(model, data, nstep)``'s, bit for bit."""
    force, velocity = data.actuator_force, data.actuator_velocity
    work = 0.0
    for _ in range(nstep):
        mujoco.mj_step(model, data)
        work += actuator_power(force, velocity)
    return work / nstep if nstep > 0 else 0.0


def split_env_kwargs(kwargs: dict) -> tuple[dict, dict]:
    """Split a robot env's ``**kwargs`` into the common environment arguments (those of
    :class:`GranularMujocoEnv`) and the rest, which go to the robot's MJCF generator."""
    env = {k: v for k, v in kwargs.items() if k in ENV_KWARGS}
    return env, {k: v for k, v in kwargs.items() if k not in ENV_KWARGS}


class GranularMujocoEnv(MujocoEnv, utils.EzPickle):
    """Base class; a robot's subclass builds its MJCF and its task (:meth:`_make_task`, :mod:`mjrft.envs.tasks`:
    observation, action mapping, reward terms, termination, metrics), which :attr:`task` holds; this class steps
    the physics and assembles ``step``'s return values from the task's functions."""

    metadata = {"render_modes": ["human", "rgb_array", "depth_array", "rgbd_tuple"]}
    #: committed model whose path is handed to MujocoEnv (the simulation itself is built from the XML)
    base_model = "hexapod"
    #: body names reported in ``info["sinkage"]`` / ``info["granular_force"]``
    foot_names: tuple[str, ...] = ()
    torso_name = "torso"
    default_camera_config = {"trackbodyid": 1, "distance": 1.0, "elevation": -20.0}

    #: per-robot defaults of the common keyword arguments (the robot's class docstring lists them)
    defaults: dict = {}
    #: the robot's own (timestep, frame_skip) on sand when neither preset, timestep nor frame_skip is given
    #: (None: the model's timestep and :data:`mjrft.tools.presets.FRAME_SKIP`)
    sand_step: tuple[float, int] | None = None
    #: the robot's own granular coupling on sand when ``implicit`` is not given (True: the implicit step)
    sand_implicit: bool = False
    #: the ``"accurate"`` preset's (timestep, frame_skip) on sand and on the rigid floor: the largest step within the
    #: 2 % gait budget of ``python benchmarks/env_timestep.py``, no coarser than the robot's own step (None: the own
    #: step, which is within it); the ``"default"`` preset takes the own step (:meth:`preset_steps`)
    accurate_step: tuple[float, int] | None = None
    rigid_accurate_step: tuple[float, int] | None = None
    #: the ``"fast"`` preset's (timestep, frame_skip) on sand: the own step, halved while the preset's coarse elements
    #: warn more than the default under ``python benchmarks/env_presets.py``'s controllers (None: the own step)
    fast_step: tuple[float, int] | None = None

    @classmethod
    def preset_steps(cls, sand: bool) -> dict[str, tuple[float | None, int]]:
        """The robot's physics step per preset (:func:`mjrft.tools.presets.resolve`'s ``preset_steps``): ``default`` at
        its own step (a timestep of None: the model's), ``fast`` and ``accurate`` at their measured ones."""
        own = (cls.sand_step if sand and cls.sand_step is not None else (None, FRAME_SKIP))
        fast = cls.fast_step if sand else None
        accurate = cls.accurate_step if sand else cls.rigid_accurate_step
        return {"fast": fast or own, "default": own, "accurate": accurate or own}

    def __init__(self, xml: str, *, sand: bool = True, healthy_z_range=(0.0, 1.0), max_tilt: float = 1.0,
                 medium=None, law=None, resolution=None,
                 frame_skip: int | None = None, forward_reward_weight: float = 1.0, energy_cost_weight: float = 0.1,
                 ctrl_cost_weight: float = 0.0, healthy_reward: float = 1.0,
                 terminate_when_unhealthy: bool = True, reset_noise_scale: float = 1e-3,
                 episode_seconds: float | None = None, render_mode: str | None = None,
                 width: int = 480, height: int = 480, camera_name: str | None = None,
                 camera_id: int | None = None, pickle_kwargs: dict | None = None,
                 preset: str | None = None, timestep: float | None = None, terrain_randomization=None,
                 ground_memory=False, implicit: bool | None = None):
        healthy_z_range = tuple(float(v) for v in healthy_z_range)
        if len(healthy_z_range) != 2 or not healthy_z_range[0] < healthy_z_range[1]:
            raise ValueError(f"healthy_z_range must be (low, high) with low < high, got {healthy_z_range!r}")
        max_tilt = check_positive("max_tilt", max_tilt)
        if implicit is None:
            implicit = self.sand_implicit and sand
        if not isinstance(implicit, (bool, np.bool_)):
            raise TypeError(f"implicit must be True, False or None (the robot's own), got {implicit!r}")
        for name, val in (("width", width), ("height", height)):
            if isinstance(val, bool) or not isinstance(val, (int, np.integer)) or val < 1:
                raise ValueError(f"{name} must be an integer >= 1 (pixels), got {val!r}")
        # the simulation settings, each checked once (rigid envs too): a preset fills what was left as None
        # (mjrft.tools.presets); explicit keyword arguments win
        sim = resolve_preset(preset, medium=medium, law=law, resolution=resolution, timestep=timestep,
                             frame_skip=frame_skip, own_step=self.sand_step if sand else None,
                             preset_steps=self.preset_steps(sand))
        self._timestep, frame_skip = sim.timestep, sim.frame_skip
        for name, val in (("forward_reward_weight", forward_reward_weight),
                          ("energy_cost_weight", energy_cost_weight), ("ctrl_cost_weight", ctrl_cost_weight),
                          ("reset_noise_scale", reset_noise_scale)):
            check_positive(name, val, allow_zero=True)
        if not math.isfinite(float(healthy_reward)):
            raise ValueError(f"healthy_reward must be finite, got {healthy_reward!r}")
        if episode_seconds is not None:
            check_positive("episode_seconds", episode_seconds)
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"unknown render_mode {render_mode!r}; valid choices: "
                             f"{', '.join(self.metadata['render_modes'])}")
        randomization = TerrainRandomization.from_value(terrain_randomization)
        if randomization is not None and not sand:
            raise ValueError(f"terrain_randomization needs a sand environment; {type(self).__name__} has rigid ground")

        self._xml = xml
        self.sand = bool(sand)
        #: the simulation settings as resolved (:func:`mjrft.tools.presets.resolve`; the MJX envs build their
        #: terrain from the same)
        self.settings = sim
        self._episode_seconds = None if episode_seconds is None else float(episode_seconds)
        # the task's arguments common to every robot (costs have negative scales, mjrft.envs.tasks.base)
        common = dict(scales={"forward": float(forward_reward_weight), "healthy": float(healthy_reward),
                              "energy": -float(energy_cost_weight), "ctrl": -float(ctrl_cost_weight)},
                      healthy_z_range=healthy_z_range, max_tilt=max_tilt,
                      terminate_when_unhealthy=terminate_when_unhealthy, reset_noise_scale=reset_noise_scale,
                      torso=self.torso_name, feet=self.foot_names)

        # per-instance metadata so MujocoEnv's render_fps check matches this frame_skip
        self.metadata = dict(self.metadata)
        timestep = self._timestep or mujoco.MjModel.from_xml_string(xml).opt.timestep
        self.metadata["render_fps"] = int(np.round(1.0 / (timestep * frame_skip)))

        MujocoEnv.__init__(self, model_path(self.base_model), frame_skip, observation_space=None,
                           render_mode=render_mode, width=int(width), height=int(height), camera_name=camera_name,
                           camera_id=camera_id, default_camera_config=self.default_camera_config)
        utils.EzPickle.__init__(self, **(pickle_kwargs or {}))

        self.terrain = (GranularTerrain(self.model, sim.medium, sim.law, resolution=sim.resolution,
                                        resolution_scale=sim.resolution_scale, ground_memory=ground_memory,
                                        implicit=implicit)
                        if self.sand else None)
        # terrain randomisation: None costs nothing (no draw, no info entry)
        self.randomizer = (None if randomization is None else
                           TerrainRandomizer(randomization, self.terrain, self.model))
        self.terrain_info: dict | None = None  # info["terrain"] of this episode (with terrain_randomization)
        self._each_step = None  # each_physics_step's function
        self._mean_power = 0.0  # the actuators' mean power over the last step's physics steps, where no terrain has it
        self.diverged: str | None = None  # the NonFiniteError message once the simulation diverged
        #: the robot's task (:mod:`mjrft.envs.tasks`), shared with its MJX env
        self.task = self._make_task(**common)

        self._setup_action()
        obs = self._get_obs()
        self.observation_space = spaces.Box(-np.inf, np.inf, shape=obs.shape, dtype=np.float64)

    # ------------------------------------------------------------------ simulation
    def _initialize_simulation(self):
        model = mujoco.MjModel.from_xml_string(self._xml)
        if self._timestep is not None:
            model.opt.timestep = self._timestep
        model.vis.global_.offwidth = max(model.vis.global_.offwidth, self.width)
        model.vis.global_.offheight = max(model.vis.global_.offheight, self.height)
        return model, mujoco.MjData(model)

    def _set_action_space(self):
        # replaced in _setup_action (normalised actions); MujocoEnv calls this before the subclass is ready
        nu = self.model.nu
        self.action_space = spaces.Box(-1.0, 1.0, shape=(nu,), dtype=np.float32)
        return self.action_space

    def _make_task(self, **common):
        """The robot's task (:mod:`mjrft.envs.tasks`) on ``self.model``; ``common``: the arguments of
        :class:`~mjrft.envs.tasks.LocomotionTask` from the common keyword arguments."""
        raise NotImplementedError

    def _setup_action(self) -> None:
        """The normalised action space ``Box(-1, 1, (nu,))`` (the task maps it to the servo targets)."""
        self.action_space = spaces.Box(-1.0, 1.0, shape=(self.model.nu,), dtype=np.float32)

    def action_to_ctrl(self, action: np.ndarray) -> np.ndarray:
        """The servo targets of ``action`` (the task's :meth:`action_to_ctrl`; for joint-angle targets the
        piecewise-linear map [-1, 0, 1] -> [ctrl_low, q_initial, ctrl_high] per actuator)."""
        return self.task.action_to_ctrl(np, self.data.qpos, self.data.ctrl, action)

    def ctrl_to_action(self, ctrl: np.ndarray) -> np.ndarray:
        """Inverse of :meth:`action_to_ctrl` for joint-angle targets (targets outside the ctrlrange are clipped)."""
        return self.task.ctrl_to_action(np, ctrl).astype(np.float32)

    def set_servo_targets(self, ctrl) -> None:
        """Set the servo targets ``data.ctrl`` (e.g. to go on from another backend's state; the hexapod keeps
        them as its integrated targets too)."""
        self.data.ctrl[:] = ctrl

    def do_simulation(self, ctrl, n_frames) -> None:
        """``n_frames`` physics steps with ``ctrl``: one ``terrain.step(data, n_frames)`` on sand."""
        self._set_ctrl(ctrl)
        self._advance(n_frames)

    def _set_ctrl(self, ctrl) -> None:
        ctrl = np.asarray(ctrl, dtype=np.float64)
        if ctrl.shape != (self.model.nu,):
            raise ValueError(f"Action dimension mismatch. Expected {(self.model.nu,)}, found {ctrl.shape}")
        if not np.all(np.isfinite(ctrl)):
            raise ValueError(f"control contains NaN or infinite values: {ctrl!r}")
        self.data.ctrl[:] = ctrl

    def _advance(self, n_frames) -> None:
        """The physics alone (``mjrft.envs.vector`` replaces this call by one batched call for all its envs).

        A divergence is noted in ``self.diverged`` (the error message) for :meth:`_end_step`."""
        try:
            if self.terrain is not None and self._each_step is None:
                self.terrain.step(self.data, n_frames)  # averages the actuators' power (terrain.actuator_power)
            elif self.terrain is not None:  # one physics step per call, each_physics_step's function after each
                work = 0.0
                for _ in range(n_frames):
                    self.terrain.step(self.data, 1)
                    work += self.terrain.actuator_power
                    self._each_step(self.data)
                self._mean_power = work / n_frames if n_frames > 0 else 0.0
            else:
                before, t0 = mujoco_resets(self.data), self.data.time
                self._mean_power = rigid_steps(self.model, self.data, n_frames)
                if mujoco_resets(self.data) > before:
                    raise mujoco_reset_error(self.model, self.data, f"between t = {t0:.6g} s and the end of "
                                                                    f"{n_frames} step(s)")
        except NonFiniteError as exc:
            self.diverged = str(exc)

    def step_power(self) -> float:
        """The actuators' mechanical power ``sum_a |actuator_force_a x actuator_velocity_a|`` (W) averaged over every
        physics step of the last ``step`` (``info["power"]``): the energy they delivered over the control step
        divided by its duration (on sand :attr:`mjrft.GranularTerrain.actuator_power`, on rigid ground the same
        mean over the ``mj_step`` calls)."""
        if self.terrain is not None and self._each_step is None:
            return self.terrain.actuator_power
        return self._mean_power

    # ------------------------------------------------------------------ measurements
    def each_physics_step(self, fn) -> None:
        """From now on call ``fn(data)`` after every physics step of the env's steps: the terrain then steps one
        physics step per call (the same steps), so ``terrain.wrench`` in ``fn`` is that step's own. For
        measurements averaged over every physics step; a rigid env has no terrain and refuses it."""
        if self.terrain is None:
            raise ValueError(f"each_physics_step needs the granular terrain; {type(self).__name__} with sand=False "
                             "has none (step the rigid env and read data after each env step instead)")
        self._each_step = fn

    def torso_height(self) -> float:
        return float(self.task.torso_height(np, self.data))

    def torso_tilt(self) -> float:
        """Angle (rad) between the torso's z axis and the world vertical."""
        return float(self.task.torso_tilt(np, self.data))

    def power(self) -> float:
        """The actuators' mechanical power ``sum_a |actuator_force_a x actuator_velocity_a|`` (W) at the current
        state (the integrand of ``info["power"]``, :meth:`step_power`)."""
        return float(self.task.power(np, self.data))

    def foot_sinkage(self) -> np.ndarray:
        if self.terrain is None:
            return np.zeros(len(self.task.feet))
        return self.terrain.sinkage()[self.task.feet].copy()

    def foot_granular_force(self) -> np.ndarray:
        if self.terrain is None:
            return np.zeros((len(self.task.feet), 3))
        return self.terrain.wrench[self.task.feet, :3].copy()

    @property
    def is_healthy(self) -> bool:
        """Torso height inside ``healthy_z_range``, tilt below ``max_tilt`` and a finite state."""
        return bool(self.task.is_healthy(np, self.data))

    # ------------------------------------------------------------------ gym API
    def _get_obs(self) -> np.ndarray:
        """The task's observation of the current state (float64)."""
        return self.task.observation(np, self.data, self.data.ctrl).astype(np.float64)

    def _check_action(self, action) -> np.ndarray:
        a = np.asarray(action, dtype=np.float64)
        if a.shape != self.action_space.shape:
            raise ValueError(f"action must have shape {self.action_space.shape}, got {a.shape}")
        if not np.all(np.isfinite(a)):
            raise ValueError(f"action contains NaN or infinite values: {a!r}")
        return a

    def step(self, action):
        before = self._begin_step(action)
        self._advance(self.frame_skip)
        return self._end_step(*before)

    def _begin_step(self, action) -> tuple:
        """``step`` before the physics: check the action, note the start state, set ``data.ctrl``."""
        a = self._check_action(action)
        x_before = self.data.qpos[0].copy()
        com_before = self.data.subtree_com[self.task.torso, :2].copy()
        self._set_ctrl(self.action_to_ctrl(a))
        return a, x_before, com_before

    def _end_step(self, a, x_before, com_before):
        """``step`` after the physics: observation, reward, termination, truncation and info."""
        if self.diverged is not None:
            return self._diverged_step(float(x_before))
        x_after = self.data.qpos[0]
        x_velocity = float((x_after - x_before) / self.dt)
        xy_velocity = (self.data.subtree_com[self.task.torso, :2] - com_before) / self.dt

        task = self.task
        power = self.step_power()
        healthy = task.is_healthy(np, self.data)
        rewards = task.rewards(np, x_velocity=x_velocity, xy_velocity=xy_velocity, power=power, action=a,
                               healthy=healthy)
        reward = task.total(rewards)
        terminated = task.terminated(np, healthy)
        truncated = self._episode_seconds is not None and self.data.time >= self._episode_seconds - 1e-9
        metrics = task.metrics(np, x_velocity=x_velocity, power=power, rewards=rewards)
        info = {
            "x_position": float(x_after),
            **{name: float(value) for name, value in metrics.items()},
            "is_healthy": bool(healthy),
            "sinkage": self.foot_sinkage(),
            "granular_force": self.foot_granular_force(),
        }
        if self.terrain_info is not None:
            info["terrain"] = dict(self.terrain_info)  # a new dict each call, as gymnasium asks
        if self.render_mode == "human":
            self.render()
        return self._get_obs(), float(reward), bool(terminated), bool(truncated), info

    def _diverged_step(self, x_before: float):
        """The step that ends a diverged episode: terminated, reward 0, the reason in ``info["diverged"]``;
        ``x_position`` is the last one before the divergence (the state after it is MuJoCo's reset)."""
        obs = self._get_obs()
        if not np.all(np.isfinite(obs)):
            obs = np.zeros_like(obs)
        info = {"x_position": x_before,
                "x_velocity": 0.0, "power": 0.0, "cost_of_transport": 0.0, "reward_forward": 0.0,
                "reward_energy": 0.0, "reward_ctrl": 0.0, "reward_healthy": 0.0, "is_healthy": False,
                "sinkage": np.zeros(len(self.task.feet)), "granular_force": np.zeros((len(self.task.feet), 3)),
                "diverged": self.diverged}
        if self.terrain_info is not None:
            info["terrain"] = dict(self.terrain_info)  # a new dict each call, as gymnasium asks
        return obs, 0.0, True, False, info

    def reset_model(self):
        self.diverged = None
        noise = self.task.reset_noise_scale
        qpos = self.init_qpos + self.np_random.uniform(-noise, noise, size=self.model.nq)
        qvel = self.init_qvel + self.np_random.uniform(-noise, noise, size=self.model.nv)
        qpos = self.task.normalise_quaternions(np, qpos)
        if self.randomizer is not None:  # after the start pose's noise: an unrandomised env draws the same noise
            self.terrain_info = self.randomizer.apply(self.np_random)
            upload_surface(self, self.terrain)  # the render contexts already made see the drawn surface
        self.set_state(qpos, qvel)
        if self.terrain is not None:
            self.terrain.reset()
        self._reset_extra()
        self.data.ctrl[:] = self.action_to_ctrl(np.zeros(self.model.nu))
        return self._get_obs()

    def _reset_extra(self) -> None:
        pass

    def _get_reset_info(self):
        info = {
            "x_position": float(self.data.qpos[0]),
            "sinkage": self.foot_sinkage(),
            "granular_force": self.foot_granular_force(),
        }
        if self.terrain_info is not None:
            info["terrain"] = dict(self.terrain_info)  # a new dict each call, as gymnasium asks
        return info


#: the keyword arguments every environment accepts (:class:`GranularMujocoEnv`), routed by :func:`split_env_kwargs`
ENV_KWARGS = frozenset(name for name, par in inspect.signature(GranularMujocoEnv.__init__).parameters.items()
                       if par.kind is par.KEYWORD_ONLY and name not in ("sand", "pickle_kwargs"))

"""mjrft's robots on sand (and their rigid twins) as MJX environments: the task of the gymnasium env
(:mod:`mjrft.envs.tasks`), the physics of :class:`mjrft.mjx.Sand` (or :func:`mjrft.mjx.step` on rigid ground).

Each environment is the gymnasium env of the same name run on MJX: :class:`LocomotionEnv` builds that env with the
keyword arguments its configuration stands for (:meth:`LocomotionEnv.gym_kwargs`; the one place where a setting is
resolved and checked), takes its model, its resolved terrain settings and its task, and steps the physics in JAX.
The same task functions make the observation, the servo targets, the reward terms, the termination and the metrics
on both backends, so the two cannot drift apart.

Configuration (``ConfigDict``; :meth:`LocomotionEnv.default_config` fills it from the gymnasium env's defaults):

=============================  ======================================================================================
key                            meaning (the gymnasium env's keyword argument)
=============================  ======================================================================================
``ctrl_dt``, ``sim_dt``        control and physics step (s): ``frame_skip = ctrl_dt / sim_dt`` (a whole number),
                               ``timestep = sim_dt``
``episode_length``             control steps per episode (the registered ``max_episode_steps``; for trainers)
``reward_config.scales``       ``forward``, ``healthy``, ``energy``, ``ctrl``: the reward terms' scales
                               (``forward_reward_weight``, ``healthy_reward``, ``-energy_cost_weight``,
                               ``-ctrl_cost_weight``: costs are negative)
``healthy_z_range``,           the healthy torso (m, rad), ``terminate_when_unhealthy``,
``max_tilt``, ...              ``reset_noise_scale``
``robot``                      the robot's own arguments (the hexapod's ``max_hip_speed``, ``max_lag``, ``variant``,
                               ``curvature``, ``planar``; the biped's ``foot``, ``foot_size``, ``pitch_free``; the
                               humanoid's ``task``, ``foot_length``, ``foot_width``, ``foot_cutout``)
``model``                      further keyword arguments of the robot's MJCF generator (empty; add keys to a
                               default configuration before ``load``)
``terrain`` (sand)             ``medium``, ``law``, ``resolution`` (None: the model's own), ``cull``
                               (:class:`mjrft.mjx.Sand`), ``implicit`` (the gymnasium env's: the implicit granular
                               step) and ``ground_memory`` (the gymnasium env's: the ground
                               remembers footprints, ridges and packing per world, :mod:`mjrft.mjx.ground`; reset
                               with each episode; not with ``randomization``)
``randomization`` (sand)       the gymnasium env's ``terrain_randomization`` (the fields of
                               :class:`~mjrft.envs.randomization.TerrainRandomization`, which checks them):
                               ``media`` (a list; empty: the terrain's own), ``stress_scale``, ``surface_height``,
                               ``roughness``, ``correlation_length``, ``strips``, ``strip_length``,
                               ``strip_start``, drawn per world at reset (:meth:`LocomotionEnv.reset`)
``impl``                       MJX's implementation (``"jax"``; ``"warp"`` where MuJoCo Warp is installed)
=============================  ======================================================================================

Differences from the gymnasium env, each by design: the sand bed's rigid bottom (30 cm below the surface, below
every healthy torso) has no contacts (a contact pair costs MJX's collision and constraint solver on every step of
every world); a non-finite action, state or granular force does not raise (nothing can inside ``jit``) but ends
the episode with reward 0 and ``metrics["diverged"] = 1``, and what the sand's guards find (a stability limit
exceeded, chatter, the law's depth or speed range left) is ``metrics["unstable"]`` and ``metrics["out_of_range"]``
(1 from the step it happened to the episode's end) with the warnings on the host from :meth:`LocomotionEnv.warn`;
terrain randomisation draws from JAX's random numbers (the gymnasium env's distributions, not numpy's draws), and
the media it draws among must share what the MJX terrain's element pass computes (a water layer, the inertial
regime, a buoyancy density: else ``NotImplementedError``).
"""

from __future__ import annotations

import inspect
from dataclasses import fields, replace

import jax
import jax.numpy as jnp
import mujoco
import numpy as np
from ml_collections import config_dict
from mujoco import mjx

from mjrft.laws.registry import STRESS_SLOTS
from mjrft.media import get_medium
from mjrft.models.scene import TIMESTEP
from mjrft.mjx import Sand
from mjrft.mjx.forces import Features
from mjrft.regions import Region, build_regions
from mjrft.mjx import step as rigid_step
from mjrft.mjx.guards import guard_metrics
from mjrft.tools.presets import FRAME_SKIP

from ..base import GranularMujocoEnv
from ..biped import BipedSand
from ..hexapod import HexapodSand
from ..humanoid import HumanoidSand
from ..randomization import TerrainRandomization, rough_gain
from ..tasks import METRICS
from .env import MjxEnv, State

#: the gymnasium env's keyword arguments that the configuration's top level carries under the same name
TOP_KEYS = ("healthy_z_range", "max_tilt", "terminate_when_unhealthy", "reset_noise_scale")
#: every step's ``state.metrics``: the task's metrics, whether the world diverged (1.0) in the step, and whether the
#: sand's guards found a stability limit exceeded (or chatter) or the law's range left since the episode began
#: (:func:`mjrft.mjx.guards.guard_metrics`; 0 on rigid ground)
STEP_METRICS = METRICS + ("diverged", "unstable", "out_of_range")
#: x_min (m) of the strip boundaries a world does not use (``randomization.strips``: a world with fewer strips than
#: the most): far beyond any bed, 1 m apart, so that no element is ever in or near them
UNUSED_STRIP_X = 1.0e6


def own_arguments(cls) -> dict:
    """The robot class's own keyword arguments and their defaults (those of its ``__init__`` but ``sand``)."""
    return {name: p.default for name, p in inspect.signature(cls.__init__).parameters.items()
            if p.kind is p.KEYWORD_ONLY}


def _common_defaults(cls) -> dict:
    """The common keyword arguments' defaults of a robot class (:class:`GranularMujocoEnv`'s, then its own)."""
    base = {name: p.default for name, p in inspect.signature(GranularMujocoEnv.__init__).parameters.items()
            if p.kind is p.KEYWORD_ONLY}
    return {**base, **cls.defaults}


def _same(a, b) -> bool:
    """Whether two keyword-argument values are the same (a value of another type is not)."""
    return type(a) is type(b) and bool(a == b)


class LocomotionEnv(MjxEnv):
    """A robot of mjrft walking on sand (``ground="sand"``) or rigid ground (``"rigid"``) in MJX; subclasses
    name the gymnasium class (``gym_class``) and the ids of its two grounds (``gym_ids``).

    ``reset(rng)``: the initial pose with uniform noise of ``reset_noise_scale`` on ``qpos`` and ``qvel`` (free
    joints' quaternions normalised), the servo targets of the task's reset, no memory in the sand, and with
    ``randomization`` this world's terrain drawn from the reset's key as the gymnasium env draws it
    (:mod:`mjrft.envs.randomization`): the medium, the stress scale, the surface's raise, with ``roughness`` a
    Gaussian-correlated height field (:func:`rough_field`: mean 0, RMS exactly ``roughness`` over the bed) on the
    height-field surface the gymnasium env builds, and with ``strips`` the strips' count, lengths and media (the
    terrain has the most strips a world can draw; those a world leaves unused start at :data:`UNUSED_STRIP_X` and
    beyond, where no element is). ``step(state, action)``: the task's servo targets from the action,
    ``n_substeps`` physics steps, then observation, reward, termination and metrics from the task. ``state.info``
    carries ``sand`` (the :class:`mjrft.mjx.SandState` on sand; its ``surface`` is the drawn field), ``sinkage``
    ((n_feet,) m) and ``granular_force`` ((n_feet, 3) N, world frame) of the task's feet, and with
    ``randomization`` ``medium`` (an index into :attr:`media`), ``stress_scale``, ``surface_height`` (m),
    ``roughness`` (the drawn field's RMS, m; 0 without), and with ``strips`` ``strips`` (the count),
    ``strip_x_min`` (the most strips' x_min, m; inf where unused) and ``strip_medium`` (indices into
    :attr:`media`; -1 where unused).

    A world whose ``data.time`` is 0 starts an episode: its sand memory is forgotten at the next step (the
    gymnasium env's terrain does the same when time goes back), so the auto-resets of Brax and Playground,
    which restore the first ``data`` and leave ``info`` alone, start each episode on fresh sand, in the terrain
    the world drew at its first reset."""

    gym_class: type = GranularMujocoEnv
    gym_ids: dict = {}

    def __init__(self, ground: str = "sand", config: config_dict.ConfigDict | None = None,
                 config_overrides: dict | None = None):
        if ground not in ("sand", "rigid"):
            raise ValueError(f"unknown ground {ground!r}; valid choices: sand, rigid")
        self.ground = ground
        #: the registry's name of this environment (``HexapodSand``, ``HexapodRigid``, ...)
        self.name = type(self).registry_name(ground)
        super().__init__(self.default_config(ground) if config is None else config, config_overrides)
        cfg = self._config
        defaults = self.gym_kwargs_of(self.default_config(ground), ground)
        #: the gymnasium env's keyword arguments of this configuration, those that differ from the gymnasium env's
        #: defaults (:meth:`gym_env` builds it; ``{}`` for the default configuration)
        full = self.gym_kwargs_of(cfg, ground)
        self.gym_kwargs = {k: v for k, v in full.items() if k not in defaults or not _same(v, defaults[k])}
        if {"timestep", "frame_skip"} & set(self.gym_kwargs):  # the robot's own step applies to neither or both
            self.gym_kwargs.update(timestep=full["timestep"], frame_skip=full["frame_skip"])
        #: the gymnasium id of the same task
        self.gym_id = self.gym_ids[ground]
        cpu = self.gym_class(sand=ground == "sand", **self.gym_kwargs)
        try:
            self._build(cpu, cull=cfg.terrain.cull if ground == "sand" else None, impl=cfg.impl)
        finally:
            cpu.close()
        self._dt = float(cpu.dt)  # ctrl_dt to rounding: n_substeps physics steps of the model's timestep

    def _build(self, cpu, cull, impl) -> None:
        model = cpu.model
        if getattr(cpu.task, "planar", False):
            raise NotImplementedError("robot.planar=True is an option of the gymnasium env only")
        #: the task (:mod:`mjrft.envs.tasks`): observation, servo targets, reward terms, termination, metrics
        self.task = cpu.task
        self._init_qpos = np.array(cpu.init_qpos)
        self._init_qvel = np.array(cpu.init_qvel)
        self._sim_dt = float(model.opt.timestep)
        self._substeps = int(cpu.frame_skip)
        self.sand = None
        self.randomization = None
        self._media = ()
        if cpu.terrain is not None:
            st = cpu.settings
            r = cpu.randomizer.options if cpu.randomizer is not None else None
            r = r if r is not None and r.active else None
            n_strips = r.strips[1] if r is not None and r.strips is not None else 0
            law = cpu.terrain.law
            # with strips the terrain has the most regions a world can draw (the ones a world leaves unused lie at
            # UNUSED_STRIP_X and beyond, 1 m apart)
            gap = max(1.0, 2.0 * cpu.terrain.transition)
            extra = {} if n_strips == 0 else {
                "regions": [Region(UNUSED_STRIP_X + gap * k, r.media[0], law) for k in range(n_strips)]}
            #: the JAX terrain (:class:`mjrft.mjx.Sand`), built on the model before it goes to the device
            memory = cpu.terrain.terrain_model.settings.ground  # the ground memory's options (None: off)
            if r is not None and memory is not None:
                raise NotImplementedError("terrain.ground_memory with randomization: a world's ground memory keeps "
                                          "the packing rows of the terrain's own medium; draw the terrain in the "
                                          "gymnasium env or leave randomization at its defaults")
            self.sand = Sand(model, st.medium, st.law, resolution=st.resolution,
                             resolution_scale=st.resolution_scale, cull=cull, implicit=cpu.terrain.implicit,
                             ground_memory=memory if memory is not None else False, **extra)
            bottom = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "bed_bottom")
            if bottom >= 0:
                model.geom_contype[bottom] = 0
                model.geom_conaffinity[bottom] = 0
            self._surface = np.asarray(self.sand.surface_init, dtype=np.float64)
            if r is not None:
                self.randomization = r
                self._media = tuple(r.media or (cpu.terrain.medium.name,))
                self._unused_bounds = UNUSED_STRIP_X + gap * np.arange(n_strips)
                self._media_params, self._strip_params = self._media_rows(cpu.terrain, law, n_strips > 0)
                if r.roughness > 0:
                    self._rough_gain = rough_gain(self._surface.shape, cpu.randomizer.spacing,
                                                   r.correlation_length)
        self._mj_model = model
        kw = {} if impl is None else {"impl": impl}
        self._mjx_model = self.sand.put_model(**kw) if self.sand is not None else mjx.put_model(model, **kw)

    def _media_rows(self, terrain, law, strips: bool):
        """The region rows (unscaled) of each of :attr:`media` as the bed's medium (region 0, its law and water depth
        kept: the CPU terrain's ``set_medium``) and, with ``strips``, as a strip of ``law`` (``set_regions``); checks
        that the terrain's element pass (:attr:`mjrft.mjx.Sand.features`, the buoyancy's densities) serves them
        all."""
        s = terrain.terrain_model.settings
        base, strip, rho0, rho1 = [], [], [], []
        for m in self._media:
            t = build_regions(replace(s, medium=get_medium(m)))[1]
            base.append(t.params[0])
            rho0.append(t.rho[0])
            if strips:
                t = build_regions(replace(s, regions=(Region(0.0, m, law),), region_map=None))[1]
                strip.append(t.params[1])
                rho1.append(t.rho[1])
        base = np.array(base)
        strip = np.array(strip) if strips else np.zeros((0, base.shape[1]))
        sand = self.sand
        rows = np.concatenate([base, strip])
        if sand.general:  # the direct pass (one dry region on a flat surface) reads the law's slots alone
            laws = np.concatenate([sand.reg_law, np.full(len(rows), sand.reg_law[0])])
            union = Features.of(laws, np.concatenate([np.atleast_2d(sand.params), rows]),
                                np.concatenate([sand.reg_rho, rho0, rho1]))
            if union != sand.features or len(set(rho0)) > 1 or len(set(rho1)) > 1:
                raise NotImplementedError(
                    f"randomization.media {list(map(str, self._media))}: the media differ in what the MJX terrain's "
                    "element pass computes (water layer, inertial regime or buoyancy); draw them in the gymnasium env "
                    "(terrain_randomization) or randomise among media that share it")
        return base, strip

    @classmethod
    def registry_name(cls, ground: str) -> str:
        """The registry's name of this robot on ``ground``: the first base class in :mod:`mjrft.envs.mjx`'s robots
        (``Hexapod``, ...) and the ground, ``HexapodSand``."""
        robot = next(c for c in cls.__mro__ if c.__module__ == __name__ and c is not LocomotionEnv)
        return robot.__name__ + ground.capitalize()

    # ------------------------------------------------------------------ configuration
    @classmethod
    def default_config(cls, ground: str = "sand") -> config_dict.ConfigDict:
        """The configuration of the gymnasium env's defaults on ``ground``."""
        common = _common_defaults(cls.gym_class)
        sand = ground == "sand"
        timestep, frame_skip = (cls.gym_class.sand_step if sand and cls.gym_class.sand_step is not None
                                else (TIMESTEP, FRAME_SKIP))
        scales = config_dict.create(forward=float(common["forward_reward_weight"]),
                                    healthy=float(common["healthy_reward"]),
                                    energy=-float(common["energy_cost_weight"]),
                                    ctrl=-float(common["ctrl_cost_weight"]))
        cfg = config_dict.create(
            ctrl_dt=timestep * frame_skip, sim_dt=timestep, episode_length=1000,
            reward_config=config_dict.create(scales=scales),
            healthy_z_range=tuple(float(v) for v in common["healthy_z_range"]),
            max_tilt=float(common["max_tilt"]),
            terminate_when_unhealthy=bool(common["terminate_when_unhealthy"]),
            reset_noise_scale=float(common["reset_noise_scale"]),
            robot=config_dict.create(**own_arguments(cls.gym_class)),
            model=config_dict.create(),
            impl="jax")
        if sand:
            cfg.terrain = config_dict.create(medium=None, law=None, resolution=None, cull=None, ground_memory=False,
                                             implicit=bool(cls.gym_class.sand_implicit))
            cfg.randomization = config_dict.create(**{f.name: f.default for f in fields(TerrainRandomization)})
        return cfg

    @classmethod
    def gym_kwargs_of(cls, config: config_dict.ConfigDict, ground: str = "sand") -> dict:
        """The gymnasium env's keyword arguments that ``config`` stands for (module docstring)."""
        ratio = float(config.ctrl_dt) / float(config.sim_dt)
        frame_skip = int(round(ratio))
        if frame_skip < 1 or abs(ratio - frame_skip) > 1e-6 * ratio:
            raise ValueError(f"ctrl_dt / sim_dt must be a whole number >= 1 (physics steps per control step), got "
                             f"ctrl_dt = {config.ctrl_dt!r}, sim_dt = {config.sim_dt!r}")
        s = config.reward_config.scales
        for cost in ("energy", "ctrl"):
            if not s[cost] <= 0.0:
                raise ValueError(f"reward_config.scales.{cost} must be <= 0 (a cost), got {s[cost]!r}")
        kwargs = dict(timestep=float(config.sim_dt), frame_skip=frame_skip,
                      forward_reward_weight=s.forward, healthy_reward=s.healthy, energy_cost_weight=-s.energy,
                      ctrl_cost_weight=-s.ctrl, **{k: config[k] for k in TOP_KEYS}, **config.robot.to_dict(),
                      **config.model.to_dict())
        kwargs["healthy_z_range"] = tuple(kwargs["healthy_z_range"])
        if ground == "sand":
            t = config.terrain
            kwargs.update(medium=t.medium, law=t.law, resolution=t.resolution,  # (.get: a configuration saved
                          ground_memory=t.get("ground_memory", False),
                          implicit=t.get("implicit", cls.gym_class.sand_implicit))  # without)
            r = config.randomization.to_dict()
            drawn = TerrainRandomization(**r)  # checked here, once for both backends
            plain = TerrainRandomization()
            options = {k: (list(v) if isinstance(v, tuple) else v) for k, v in r.items()
                       if getattr(drawn, k) != getattr(plain, k)}
            if options:
                kwargs["terrain_randomization"] = options
        return kwargs

    # ------------------------------------------------------------------ sizes
    @property
    def n_substeps(self) -> int:
        return self._substeps

    @property
    def observation_size(self) -> int:
        return int(self.task.observation_size)

    @property
    def action_size(self) -> int:
        return int(self.task.action_size)

    @property
    def media(self) -> tuple:
        """The media that ``info["medium"]`` indexes (with ``randomization``)."""
        return self._media

    # ------------------------------------------------------------------ reset and step
    def reset(self, rng: jax.Array) -> State:
        task = self.task
        k1, k2 = jax.random.split(rng)
        noise = task.reset_noise_scale
        m = self._mj_model
        qpos = jnp.asarray(self._init_qpos) + jax.random.uniform(k1, (m.nq,), minval=-noise, maxval=noise)
        qvel = jnp.asarray(self._init_qvel) + jax.random.uniform(k2, (m.nv,), minval=-noise, maxval=noise)
        qpos = task.normalise_quaternions(jnp, qpos)
        ctrl = task.reset_ctrl(jnp, qpos)
        data = mjx.make_data(self._mjx_model).replace(qpos=qpos, qvel=qvel, ctrl=ctrl)
        data = mjx.forward(self._mjx_model, data)
        info = {}
        if self.sand is not None:
            if self.randomization is None:
                info["sand"] = self.sand.init()
            else:
                info["sand"], drawn = self._draw_terrain(jax.random.fold_in(rng, 1))
                info.update(drawn)
        n_feet = len(task.feet)
        info["sinkage"] = jnp.zeros(n_feet)
        info["granular_force"] = jnp.zeros((n_feet, 3))
        zero = jnp.zeros(())
        obs = task.observation(jnp, data, ctrl)
        return State(data, obs, zero, zero, {name: zero for name in STEP_METRICS}, info)

    def _draw_terrain(self, rng):
        """A world's terrain: the medium drawn uniformly from :attr:`media`, then the stress scale and the surface's
        raise uniformly from their ranges, the rough height field and the strips (their count, lengths and media),
        as the gymnasium env draws them (:mod:`mjrft.envs.randomization`); returns the sand state and what was
        drawn."""
        r = self.randomization
        k_med, k_scale, k_surf = jax.random.split(rng, 3)
        idx = jax.random.randint(k_med, (), 0, len(self._media))
        params = jnp.asarray(self._media_params)[idx]
        scale = jnp.ones(())
        if r.stress_scale is not None:
            scale = jax.random.uniform(k_scale, (), minval=r.stress_scale[0], maxval=r.stress_scale[1])
        raise_ = jnp.zeros(())
        if r.surface_height is not None:
            raise_ = jax.random.uniform(k_surf, (), minval=r.surface_height[0], maxval=r.surface_height[1])
        surface = self._surface + raise_
        drawn = {"medium": idx, "stress_scale": scale, "surface_height": raise_, "roughness": jnp.zeros(())}
        if r.roughness > 0:
            field = rough_field(jax.random.fold_in(rng, 3), self._rough_gain, self._surface.shape, r.roughness)
            surface = surface + field
            drawn["roughness"] = jnp.sqrt(jnp.mean(field * field))
        bounds = None
        n_max = len(self._unused_bounds)
        if n_max:
            k_n, k_len, k_pick = jax.random.split(jax.random.fold_in(rng, 4), 3)
            n = jax.random.randint(k_n, (), r.strips[0], r.strips[1] + 1)
            lengths = jax.random.uniform(k_len, (n_max,), minval=r.strip_length[0], maxval=r.strip_length[1])
            picks = jax.random.randint(k_pick, (n_max,), 0, len(self._media))
            used = jnp.arange(n_max) < n
            bounds = jnp.where(used, r.strip_start + jnp.cumsum(lengths), jnp.asarray(self._unused_bounds))
            params = jnp.concatenate([params[None], jnp.asarray(self._strip_params)[picks]])
            drawn.update(strips=n, strip_x_min=jnp.where(used, bounds, jnp.inf),
                         strip_medium=jnp.where(used, picks, -1))
        if r.stress_scale is not None:  # every region's granular stresses (the CPU terrain's set_medium)
            slots = np.zeros(params.shape[-1], dtype=bool)
            slots[STRESS_SLOTS] = True
            params = jnp.where(jnp.asarray(slots), params * scale, params)
        state = self.sand.init(params=params, surface=surface, bounds=bounds)
        return state, drawn

    def step(self, state: State, action: jax.Array) -> State:
        task, mx = self.task, self._mjx_model
        d0 = state.data
        bad_action = ~jnp.all(jnp.isfinite(action))
        a = jnp.where(bad_action, 0.0, action)
        ctrl = task.action_to_ctrl(jnp, d0.qpos, d0.ctrl, a)
        info = dict(state.info)
        sand = info.get("sand")
        if sand is not None:  # a world at t = 0 starts an episode: no memory in its sand (class docstring)
            fresh = self.sand.reset(sand)
            sand = jax.tree_util.tree_map(lambda f, s: jnp.where(d0.time == 0.0, f, s), fresh, sand)

        def physics(carry, _):
            d, s, work = carry
            if s is None:
                d = rigid_step(mx, d)
            else:
                d, s = self.sand.step(mx, d, s)
            return (d, s, work + task.power(jnp, d)), None  # each step's force and velocity, of its start

        start = (d0.replace(ctrl=ctrl), sand, jnp.zeros((), d0.qpos.dtype))
        (d, sand, work), _ = jax.lax.scan(physics, start, None, length=self._substeps)
        x_velocity = (d.qpos[0] - d0.qpos[0]) / self._dt
        xy_velocity = (d.subtree_com[task.torso, :2] - d0.subtree_com[task.torso, :2]) / self._dt
        power = work / self._substeps  # the actuators' mean power over the control step
        finite = jnp.all(jnp.isfinite(d.qpos)) & jnp.all(jnp.isfinite(d.qvel))
        healthy = task.is_healthy(jnp, d) & finite
        diverged = bad_action | ~finite
        if sand is not None:
            diverged = diverged | (sand.bad_body != -1)
            info["sand"] = sand
            info["sinkage"] = sand.sinkage[task.feet]
            info["granular_force"] = sand.wrench[task.feet, :3]
        rewards = task.rewards(jnp, x_velocity=x_velocity, xy_velocity=xy_velocity, power=power, action=a,
                               healthy=healthy)
        reward = jnp.where(diverged, 0.0, task.total(rewards))
        done = diverged | task.terminated(jnp, healthy)
        obs = jnp.where(diverged, 0.0, task.observation(jnp, d, ctrl))
        metrics = task.metrics(jnp, x_velocity=x_velocity, power=power, rewards=rewards)
        # each metric in the reward's dtype, as reset makes them: a weakly typed one (a reward term of Python floats)
        # would give step's output another type than reset's, and jit would compile step twice
        metrics = {**state.metrics, **{k: jnp.where(diverged, 0.0, v).astype(reward.dtype) for k, v in metrics.items()},
                   "diverged": diverged.astype(reward.dtype)}
        if sand is not None:
            metrics.update(guard_metrics(sand, reward.dtype))
        return state.replace(data=d, obs=obs, reward=reward, done=done.astype(reward.dtype), metrics=metrics,
                             info=info)

    def warn(self, state: State) -> None:
        """On the host, for ``state`` (one world or a batch): warn for what the sand's guards recorded since each
        world's episode began (:meth:`mjrft.mjx.Sand.warn`: the world, body, time, steps and worst value, once per
        guard and body); nothing on rigid ground."""
        if self.sand is not None:
            self.sand.warn(state.info["sand"], stacklevel=4)

    # ------------------------------------------------------------------ the gymnasium twin
    def gym_env(self, state: State | None = None):
        """The gymnasium env of the same task and configuration (``gymnasium.make(gym_id, **gym_kwargs)``), reset;
        with ``state`` (one world) put in its pose, velocity and servo targets with its sand's memory empty (as
        after a reset): stepped with the same actions, the two backends' trajectories can be compared."""
        import gymnasium

        import mjrft.envs  # noqa: F401  (registers the ids)

        env = gymnasium.make(self.gym_id, **self.gym_kwargs)
        env.reset(seed=0)
        if state is not None:
            u = env.unwrapped
            d = state.data
            u.set_state(np.asarray(d.qpos, dtype=np.float64), np.asarray(d.qvel, dtype=np.float64))
            if u.terrain is not None:
                u.terrain.reset()
            u.set_servo_targets(np.asarray(d.ctrl, dtype=np.float64))
        return env


def rough_field(key: jax.Array, gain: tuple[np.ndarray, tuple[int, int]], shape: tuple[int, int],
                rms: float) -> jax.Array:
    """:func:`mjrft.envs.randomization.rough_field` in JAX from ``key``: white noise on the padded grid filtered with
    the Gaussian ``gain`` (:func:`mjrft.envs.randomization.rough_gain`: the gain and the padding), cropped to
    ``shape`` (nrow, ncol), shifted to mean 0 and scaled to RMS exactly ``rms``."""
    g, (py, px) = gain
    full = (shape[0] + 2 * py, shape[1] + 2 * px)
    noise = jax.random.normal(key, full)
    h = jnp.fft.irfft2(jnp.fft.rfft2(noise) * jnp.asarray(g, noise.dtype), s=full)
    h = h[py:py + shape[0], px:px + shape[1]]
    h = h - jnp.mean(h)
    norm = jnp.sqrt(jnp.mean(h * h))
    return jnp.where(norm > 0, h * (rms / jnp.where(norm > 0, norm, 1.0)), 0.0)


class Hexapod(LocomotionEnv):
    """The RHex-class hexapod (``mjrft/HexapodSand-v0`` / ``HexapodRigid-v0``; tables in
    :class:`mjrft.envs.hexapod.HexapodSand`)."""

    gym_class = HexapodSand
    gym_ids = {"sand": "mjrft/HexapodSand-v0", "rigid": "mjrft/HexapodRigid-v0"}


class Biped(LocomotionEnv):
    """The planar biped (``mjrft/BipedSand-v0`` / ``BipedRigid-v0``; tables in :class:`mjrft.envs.biped.BipedSand`)."""

    gym_class = BipedSand
    gym_ids = {"sand": "mjrft/BipedSand-v0", "rigid": "mjrft/BipedRigid-v0"}


class Humanoid(LocomotionEnv):
    """The HUBO-class humanoid (``mjrft/HumanoidSand-v0`` / ``HumanoidRigid-v0``; tables in
    :class:`mjrft.envs.humanoid.HumanoidSand`)."""

    gym_class = HumanoidSand
    gym_ids = {"sand": "mjrft/HumanoidSand-v0", "rigid": "mjrft/HumanoidRigid-v0"}


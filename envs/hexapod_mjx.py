"""The hexapod on sand as a batched MJX environment (Brax's ``Env`` interface, as MuJoCo Playground uses).

:class:`HexapodSandMJX` is ``mjrft/HexapodSand-v0`` on the GPU: the same robot (the CPU env's model and its
:class:`~mjrft.GranularTerrain`, evaluated by :class:`mjrft.mjx.Sand`), the same action, observation,
reward and termination (the tables of :class:`mjrft.envs.hexapod.HexapodSand`), written as pure functions
``reset(rng) -> State`` and ``step(state, action) -> State`` that ``jax.jit`` and ``jax.vmap`` batch over
thousands of worlds. Brax's training wrappers (``brax.envs.wrappers.training.wrap``: episode length,
auto-reset, vmap) and Brax's PPO take it as it is (:mod:`mjrft.train.mjx_ppo`).

>>> env = HexapodSandMJX()                                  # keyword arguments as mjrft/HexapodSand-v0
>>> state = jax.jit(env.reset)(jax.random.PRNGKey(0))
>>> state = jax.jit(env.step)(state, jnp.zeros(env.action_size))

Differences from the CPU env, each by design:

* the bed's rigid bottom (a plane 30 cm below the sand surface, below the healthy height range) has no
  contacts here: a contact pair costs MJX's collision and constraint solver on every step and every world,
  and no healthy episode reaches it;
* a non-finite action does not raise (nothing can inside ``jit``): it ends the episode like a divergence
  (``done``, reward 0, ``metrics["diverged"] = 1``), as does a non-finite state or granular force;
* ``info`` holds arrays only (Brax's ``State.metrics``: ``x_velocity``, ``power``, ``cost_of_transport``,
  the reward terms, ``diverged``); per-leg ``sinkage`` and ``granular_force`` are in
  ``state.pipeline_state.sand``.

The physics is MJX's (the same model, integrator and timestep) with the integrator stage as MuJoCo's C library
integrates a clamped servo (:mod:`mjrft.mjx.integrator`): in float64 a trajectory follows the CPU env's to rounding
(``tests/envs/test_mjx_env.py``, ``benchmarks/mjx_backends.py``); in float32 the two agree to rounding at first and
then drift apart as any two chaotic simulations do. The granular wrench on a given state equals the CPU kernel's
(``tests/mjrft/mjx/test_mjx.py``).
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
import mujoco
import numpy as np
from brax.envs.base import Env, State
from mujoco import mjx

from mjrft.coupler import STRESS_SLOTS
from mjrft.mjx import Sand, SandState
from mjrft.mjx import step as rigid_step

from .hexapod import HexapodSand
from .randomization import TerrainRandomization

G = 9.81


class HexapodPipeline(NamedTuple):
    """Per-world physics state: MJX's data, the terrain's state and the hip servo targets (rad)."""

    data: mjx.Data
    sand: SandState
    target: jax.Array


class HexapodSandMJX(Env):
    """``mjrft/HexapodSand-v0`` for MJX. Keyword arguments: those of :class:`~mjrft.envs.hexapod.HexapodSand`
    (``medium``, ``law``, ``curvature``, ``frame_skip``, reward weights, ...); ``cull`` goes to
    :class:`mjrft.mjx.Sand`; ``impl`` to ``mjx.put_model`` (``"jax"``, or ``"warp"`` where MuJoCo Warp is
    installed). ``sand=False`` gives the rigid twin (``mjrft/HexapodRigid-v0``: MJX's contacts on a rigid
    floor). ``terrain_randomization`` takes the CPU env's ``media``, ``stress_scale`` and ``surface_height``
    (:mod:`mjrft.envs.randomization`), drawn per world at reset (``state.info``: ``medium`` as an index into
    :attr:`media`, ``stress_scale``, ``surface_height``); roughness, strips and render modes are options of the
    CPU env only."""

    def __init__(self, sand: bool = True, *, cull: int | None = None, impl: str | None = None, **kwargs):
        randomization = TerrainRandomization.from_value(kwargs.pop("terrain_randomization", None))
        if randomization is not None:
            if not sand:
                raise ValueError("terrain_randomization needs a sand environment; sand=False is the rigid twin")
            cpu_only = [k for k in ("roughness", "strips") if getattr(randomization, k) not in (0.0, None, (0, 0))]
            if cpu_only:
                raise NotImplementedError(f"terrain_randomization {', '.join(cpu_only)}: the MJX env draws media, "
                                          "stress_scale and surface_height (a height field and strips are options "
                                          "of the CPU env)")
        cpu = HexapodSand(sand=sand, **kwargs)
        self.cpu_kwargs = dict(sand=sand, **kwargs)
        model = cpu.model
        bottom = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "bed_bottom")
        if sand and bottom >= 0:
            model.geom_contype[bottom] = 0
            model.geom_conaffinity[bottom] = 0
        self.sand = Sand.from_terrain(cpu.terrain, cull=cull) if sand else None
        self.randomization = randomization if randomization is not None and randomization.active else None
        if self.randomization is not None:
            media = self.randomization.media or (self.sand.terrain.medium.name,)
            self._media = tuple(media)
            self._media_params = np.stack([self.sand.params_of(m) for m in media])
        self.model = model
        self.mx = mjx.put_model(model) if impl is None else mjx.put_model(model, impl=impl)
        self.frame_skip = int(cpu.frame_skip)
        self.dt = float(cpu.dt)
        self.init_qpos = np.array(cpu.init_qpos)
        self.init_qvel = np.array(cpu.init_qvel)
        #: the task of the CPU env (:class:`mjrft.envs.tasks.HexapodTask`): observation, action, reward, termination
        self.task = cpu.task
        if cpu.planar:
            raise NotImplementedError("planar=True is an option of the CPU env only")
        cpu.close()

    # ------------------------------------------------------------------ Brax Env interface
    @property
    def observation_size(self) -> int:
        return 35

    @property
    def action_size(self) -> int:
        return 6

    @property
    def backend(self) -> str:
        return "mjx"

    def reset(self, rng: jax.Array) -> State:
        """A new episode: the initial pose with uniform noise of ``reset_noise_scale`` on qpos and qvel (the
        free joint's quaternion normalised), no memory in the sand, servo targets at the hip angles."""
        k1, k2 = jax.random.split(rng)
        nq, nv = self.model.nq, self.model.nv
        noise = self.task.reset_noise_scale
        qpos = jnp.asarray(self.init_qpos) + jax.random.uniform(k1, (nq,), minval=-noise, maxval=noise)
        qvel = jnp.asarray(self.init_qvel) + jax.random.uniform(k2, (nv,), minval=-noise, maxval=noise)
        qpos = self.task.normalise_quaternions(jnp, qpos)
        target = self.task.reset_ctrl(jnp, qpos)
        d = mjx.make_data(self.mx).replace(qpos=qpos, qvel=qvel, ctrl=target)
        d = mjx.forward(self.mx, d)
        info = {}
        if self.sand is None:
            sand = _no_sand(self.model.nbody)
        elif self.randomization is None:
            sand = self.sand.init()
        else:
            sand, info = self._draw_terrain(jax.random.fold_in(rng, 1))
        pipeline = HexapodPipeline(d, sand, target)
        zero = jnp.zeros(())
        metrics = {name: zero for name in METRICS}
        return State(pipeline, self._obs(d, target), zero, zero, metrics, info)

    def _draw_terrain(self, rng) -> tuple[SandState, dict]:
        """A world's terrain (``terrain_randomization``): the medium drawn uniformly from ``media``, then the
        stress scale and the surface's raise uniformly from their ranges; ``info`` holds what was drawn (the index
        into :attr:`media`). Brax's auto-reset returns a world to its first state, so each world keeps the terrain
        of its first reset."""
        r = self.randomization
        k_med, k_scale, k_surf = jax.random.split(rng, 3)
        idx = jax.random.randint(k_med, (), 0, len(self._media))
        params = jnp.asarray(self._media_params)[idx]
        scale = jnp.ones(())
        if r.stress_scale is not None:
            scale = jax.random.uniform(k_scale, (), minval=r.stress_scale[0], maxval=r.stress_scale[1])
            params = params.at[STRESS_SLOTS].multiply(scale)
        raise_ = jnp.zeros(())
        if r.surface_height is not None:
            raise_ = jax.random.uniform(k_surf, (), minval=r.surface_height[0], maxval=r.surface_height[1])
        state = self.sand.init(params=params, surface=self.sand.surface + raise_)
        return state, {"medium": idx, "stress_scale": scale, "surface_height": raise_}

    @property
    def media(self) -> tuple:
        """The media that ``info["medium"]`` indexes (with ``terrain_randomization``)."""
        return getattr(self, "_media", ())

    def step(self, state: State, action: jax.Array) -> State:
        """One control step: the hip-velocity command integrated into the servo targets, ``frame_skip`` physics
        steps with the granular wrench, then observation, reward and termination."""
        ps: HexapodPipeline = state.pipeline_state
        d0 = ps.data
        task = self.task
        bad_action = ~jnp.all(jnp.isfinite(action))
        a = jnp.where(bad_action, 0.0, action)
        target = task.action_to_ctrl(jnp, d0.qpos, ps.target, a)
        d = d0.replace(ctrl=target)
        sand = ps.sand

        def physics(_, carry):
            d, sand = carry
            if self.sand is None:
                return rigid_step(self.mx, d), sand
            return self.sand.step(self.mx, d, sand)

        d, sand = jax.lax.fori_loop(0, self.frame_skip, physics, (d, sand))
        x_velocity = (d.qpos[0] - d0.qpos[0]) / self.dt
        xy_velocity = (d.subtree_com[task.torso, :2] - d0.subtree_com[task.torso, :2]) / self.dt
        power = task.power(jnp, d)
        finite = jnp.all(jnp.isfinite(d.qpos)) & jnp.all(jnp.isfinite(d.qvel))
        healthy = task.is_healthy(jnp, d) & finite
        diverged = bad_action | ~finite | (sand.bad_body != -1)
        rewards = task.rewards(jnp, x_velocity=x_velocity, xy_velocity=xy_velocity, power=power, action=a,
                               healthy=healthy)
        reward = task.total(rewards)
        done = diverged | task.terminated(jnp, healthy)
        obs = self._obs(d, target)
        obs = jnp.where(diverged, 0.0, obs)
        reward = jnp.where(diverged, 0.0, reward)
        metrics = {**task.metrics(jnp, x_velocity=jnp.where(diverged, 0.0, x_velocity), power=power, rewards=rewards),
                   "diverged": diverged.astype(reward.dtype)}
        metrics = {**state.metrics,
                   **{k: jnp.where(diverged, 0.0, v) if k != "diverged" else v for k, v in metrics.items()}}
        pipeline = HexapodPipeline(d, sand, target)
        return state.replace(pipeline_state=pipeline, obs=obs, reward=reward, done=done.astype(reward.dtype),
                             metrics=metrics)

    # ------------------------------------------------------------------ pieces
    def _obs(self, d, target) -> jax.Array:
        return self.task.observation(jnp, d, target)

    def foot_sinkage(self, state: State) -> jax.Array:
        """Deepest element of each leg (m), order ``HexapodSand.foot_names`` (zeros on rigid ground)."""
        return state.pipeline_state.sand.sinkage[..., self.task.feet]

    def foot_granular_force(self, state: State) -> jax.Array:
        """Net granular force on each leg (N, world frame) applied by the last physics step."""
        return state.pipeline_state.sand.wrench[..., self.task.feet, :3]

    def cpu_env(self, state: State):
        """The CPU twin of one world: ``mjrft/HexapodSand-v0`` with this env's keyword arguments, put in ``state``'s
        pose, velocity and servo targets, its sand's memory empty (as after a reset): stepped with the same actions,
        the two backends' trajectories can be compared (``benchmarks/mjx_backends.py``)."""
        import gymnasium

        import mjrft.envs  # noqa: F401  (registers the ids)

        env = gymnasium.make("mjrft/HexapodSand-v0", **self.cpu_kwargs)
        env.reset(seed=0)
        u = env.unwrapped
        d = state.pipeline_state.data
        u.set_state(np.asarray(d.qpos, dtype=np.float64), np.asarray(d.qvel, dtype=np.float64))
        if u.terrain is not None:
            u.terrain.reset()
        u.target = np.asarray(state.pipeline_state.target, dtype=np.float64)
        u.data.ctrl[:] = u.target
        return env


#: the metrics every step reports (Brax's ``State.metrics``)
METRICS = ("x_velocity", "power", "cost_of_transport", "reward_forward", "reward_energy", "reward_ctrl",
           "reward_healthy", "diverged")


def _no_sand(nbody: int) -> SandState:
    """A placeholder terrain state for the rigid twin (no elements, no force)."""
    z = jnp.zeros(())
    return SandState(u=jnp.zeros((0, 3)), params=jnp.zeros(0), surface=z, wrench=jnp.zeros((nbody, 6)), sinkage=jnp.zeros(nbody),
                     bad_body=jnp.array(-1, dtype=jnp.int32), bad_time=z)

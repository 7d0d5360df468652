"""``HexapodSandMJX``: the hexapod on sand in MJX, built from the gymnasium env's keyword arguments (deprecated).

Use the registry instead: ``mjrft.mjx.envs.load("HexapodSand")`` (or ``"HexapodRigid"``), configured by a
``ConfigDict`` (:mod:`mjrft.envs.mjx`). :class:`HexapodSandMJX` is that environment
(:class:`mjrft.envs.mjx.Hexapod`), made from the keyword arguments of ``mjrft/HexapodSand-v0`` as before, with
the helpers it had (:meth:`~HexapodSandMJX.foot_sinkage`, :meth:`~HexapodSandMJX.foot_granular_force`,
:meth:`~HexapodSandMJX.cpu_env`, ``model``, ``mx``, ``frame_skip``). Its ``State`` is the registry's: MuJoCo
Playground's fields (``state.data`` is MJX's data; ``state.pipeline_state`` the same), the sand's state in
``state.info["sand"]``.

>>> env = HexapodSandMJX()                                  # keyword arguments as mjrft/HexapodSand-v0
>>> state = jax.jit(env.reset)(jax.random.PRNGKey(0))
>>> state = jax.jit(env.step)(state, jnp.zeros(env.action_size))
"""

from __future__ import annotations

import warnings
from dataclasses import fields

import jax

from .base import ENV_KWARGS
from .hexapod import HexapodRigid, HexapodSand
from .mjx.env import State
from .mjx.locomotion import TOP_KEYS, Hexapod, own_arguments
from .randomization import TerrainRandomization

#: keyword arguments of the gymnasium env that have no meaning for an MJX env (rendering, the time limit)
IGNORED = ("render_mode", "width", "height", "camera_name", "camera_id", "episode_seconds")


def config_of(sand: bool = True, cull: int | None = None, impl: str | None = None, **kwargs):
    """The registry configuration (``HexapodSand`` / ``HexapodRigid``) of the gymnasium env's keyword
    arguments ``kwargs``: the gymnasium env is built with them (which checks and resolves each, a ``preset``
    included) and the configuration is read from it."""
    cpu = (HexapodSand if sand else HexapodRigid)(**kwargs)
    try:
        ground = "sand" if sand else "rigid"
        cfg = Hexapod.default_config(ground)
        task = cpu.task
        cfg.sim_dt = float(cpu.model.opt.timestep)
        cfg.ctrl_dt = float(cpu.dt)
        for name, value in task.scales.items():
            cfg.reward_config.scales[name] = value
        for key in TOP_KEYS:
            cfg[key] = getattr(task, key)
        own = own_arguments(HexapodSand)
        for key in own:
            cfg.robot[key] = getattr(task, key) if hasattr(task, key) else kwargs.get(key, own[key])
        model_kw = {k: v for k, v in kwargs.items() if k not in ENV_KWARGS and k not in own and k != "sand"}
        cfg.model.update(model_kw)
        if cpu.terrain is not None:
            preset = kwargs.get("preset") is not None  # its law and element size become explicit
            cfg.terrain.medium = kwargs.get("medium")
            cfg.terrain.law = cpu.terrain.law if preset else kwargs.get("law")
            cfg.terrain.resolution = float(cpu.terrain.resolution) if preset else kwargs.get("resolution")
            cfg.terrain.cull = cull
            r = cpu.randomizer.options if cpu.randomizer is not None else None
            if r is not None and r.active:
                for f in fields(TerrainRandomization):
                    cfg.randomization[f.name] = getattr(r, f.name)
        if impl is not None:
            cfg.impl = impl
        return cfg
    finally:
        cpu.close()


class HexapodSandMJX(Hexapod):
    """``mjrft/HexapodSand-v0`` for MJX from the gymnasium env's keyword arguments (deprecated: use
    ``mjrft.mjx.envs.load("HexapodSand", config_overrides=...)``). ``sand=False`` gives the rigid twin; ``cull``
    goes to :class:`mjrft.mjx.Sand`, ``impl`` to ``mjx.put_model``; rendering arguments and ``episode_seconds``
    are ignored."""

    def __init__(self, sand: bool = True, *, cull: int | None = None, impl: str | None = None, **kwargs):
        warnings.warn("mjrft.envs.hexapod_mjx.HexapodSandMJX is deprecated: use mjrft.mjx.envs.load('HexapodSand') "
                      "(or 'HexapodRigid'), configured by a ConfigDict (docs/gpu.md)", DeprecationWarning,
                      stacklevel=2)
        kwargs = {k: v for k, v in kwargs.items() if k not in IGNORED}
        super().__init__("sand" if sand else "rigid", config=config_of(sand, cull, impl, **kwargs))

    @property
    def model(self):
        """``mj_model``."""
        return self.mj_model

    @property
    def mx(self):
        """``mjx_model``."""
        return self.mjx_model

    @property
    def frame_skip(self) -> int:
        """``n_substeps``."""
        return self.n_substeps

    def foot_sinkage(self, state: State) -> jax.Array:
        """Deepest element of each leg (m), order ``HexapodSand.foot_names`` (zeros on rigid ground)."""
        return state.info["sinkage"]

    def foot_granular_force(self, state: State) -> jax.Array:
        """Net granular force on each leg (N, world frame) applied by the last physics step."""
        return state.info["granular_force"]

    def cpu_env(self, state: State):
        """:meth:`gym_env` of ``state``: the gymnasium env in this world's state."""
        return self.gym_env(state)

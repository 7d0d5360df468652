"""mjrft's MJX environments in MuJoCo Playground's form, and their registry (also :mod:`mjrft.mjx.envs`).

>>> from mjrft.envs import mjx as envs          # or: import mjrft.mjx.envs as envs
>>> envs.names()
('BipedRigid', 'BipedSand', 'Go2JoystickRigid', 'Go2JoystickSand', 'HexapodRigid', 'HexapodSand', 'HumanoidRigid',
 'HumanoidSand')
>>> env = envs.load("HexapodSand", config_overrides={"reward_config.scales.energy": -0.1})
>>> state = jax.jit(env.reset)(jax.random.PRNGKey(0))
>>> state = jax.jit(env.step)(state, jnp.zeros(env.action_size))

Each name is a gymnasium env run on MJX (``HexapodSand`` is ``mjrft/HexapodSand-v0``, ``HexapodRigid`` its rigid
twin, ...): the same model and task (:mod:`mjrft.envs.tasks`), the physics of :class:`mjrft.mjx.Sand`
(:mod:`mjrft.envs.mjx.locomotion`); ``Go2JoystickRigid`` / ``Go2JoystickSand`` are MuJoCo Playground's joystick task
on the vendored Go2, the latter put on sand by :func:`mjrft.mjx.on_sand` (:mod:`mjrft.envs.mjx.go2_joystick`). Configurations are ``ml_collections.ConfigDict``\\ s
(:func:`get_default_config`); environments have Playground's ``reset(rng) -> State``, ``step(state, action) ->
State``, ``mj_model``, ``mjx_model``, ``dt``, ``sim_dt``, ``n_substeps``, ``observation_size``, ``action_size``,
``unwrapped`` and ``render`` (:mod:`mjrft.envs.mjx.env`). Needs the optional extra ``mjrft[mjx]``.
"""

from __future__ import annotations

import functools
from typing import Callable

from ml_collections import config_dict

from mjrft.errors import unknown

from . import go2_joystick
from .env import MjxEnv, State, render_array
from .locomotion import Biped, Hexapod, Humanoid, LocomotionEnv

_ENVS: dict[str, Callable[..., MjxEnv]] = {}
_CONFIGS: dict[str, Callable[[], config_dict.ConfigDict]] = {}


def register(name: str, env_class: Callable[..., MjxEnv], default_config: Callable[[], config_dict.ConfigDict]
             ) -> None:
    """Register ``env_class`` (called as ``env_class(config=..., config_overrides=...)``) under ``name``, with the
    function that makes its default configuration."""
    if not isinstance(name, str) or not name:
        raise ValueError(f"an environment's name must be a non-empty string, got {name!r}")
    _ENVS[name] = env_class
    _CONFIGS[name] = default_config


for _cls in (Hexapod, Biped, Humanoid):
    for _ground in ("sand", "rigid"):
        register(_cls.registry_name(_ground), functools.partial(_cls, _ground),
                 functools.partial(_cls.default_config, _ground))
for _name, (_make, _config) in go2_joystick.ENVS.items():  # the quadruped with Playground's joystick task
    register(_name, _make, _config)


def names() -> tuple[str, ...]:
    """The registered environments' names, sorted."""
    return tuple(sorted(_ENVS))


def _check(name: str) -> None:
    if name not in _ENVS:
        raise unknown("MJX environment", str(name), names())


def get_default_config(name: str) -> config_dict.ConfigDict:
    """A new copy of environment ``name``'s default configuration (unlocked: edit it, then :func:`load`)."""
    _check(name)
    return _CONFIGS[name]()


def load(name: str, config: config_dict.ConfigDict | None = None, config_overrides: dict | None = None) -> MjxEnv:
    """Environment ``name`` with ``config`` (default: :func:`get_default_config`) and ``config_overrides``
    (``{"dotted.key": value}``, applied to a locked copy: a key that does not exist is refused)."""
    _check(name)
    return _ENVS[name](config=get_default_config(name) if config is None else config,
                       config_overrides=config_overrides)


ALL_ENVS = names()

__all__ = ["ALL_ENVS", "Biped", "Hexapod", "Humanoid", "LocomotionEnv", "MjxEnv", "State", "get_default_config",
           "load", "names", "register", "render_array"]

"""The registry of mjrft's MJX environments, in MuJoCo Playground's form: ``names()``, ``load(name, config=None,
config_overrides=None)``, ``get_default_config(name)``, ``register(...)``.

The environments belong to the env layer (:mod:`mjrft.envs.mjx`, where they are documented); this module only
re-exports its names, so that ``mjrft.mjx.envs.load("HexapodSand")`` sits next to :class:`mjrft.mjx.Sand` as
``mujoco_playground.registry.load`` sits next to Playground's environments. ``import mjrft.mjx`` does not import it.
"""

import mjrft.envs.mjx as _registry

ALL_ENVS = _registry.ALL_ENVS
MjxEnv = _registry.MjxEnv
State = _registry.State
get_default_config = _registry.get_default_config
load = _registry.load
names = _registry.names
register = _registry.register
render_array = _registry.render_array

__all__ = ["ALL_ENVS", "MjxEnv", "State", "get_default_config", "load", "names", "register", "render_array"]

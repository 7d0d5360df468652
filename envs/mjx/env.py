"""The form of mjrft's MJX environments: MuJoCo Playground's ``State`` and ``MjxEnv``.

An environment is configured by an ``ml_collections.ConfigDict`` (``ctrl_dt``, ``sim_dt``, reward scales by
name under ``reward_config.scales``, ...), and is stepped by two pure functions, ``reset(rng) -> State`` and
``step(state, action) -> State``, that ``jax.jit`` and ``jax.vmap`` batch over worlds. Its attributes are
Playground's: ``mj_model`` / ``mjx_model``, ``dt`` (the control step), ``sim_dt``, ``n_substeps``,
``observation_size``, ``action_size``, ``unwrapped`` and ``render(trajectory, ...)``; a user's Playground
wrappers (``mujoco_playground.wrapper.wrap_for_brax_training``), Brax's training wrappers
(``brax.envs.wrappers.training.wrap``), Brax's PPO and Playground's ``render_array`` take it as it is.

:class:`MjxEnv` is also a Brax ``Env`` and :class:`State` answers to Brax's name of the physics state,
``pipeline_state`` (the same ``data``), so that Brax's own auto-reset, which restores ``pipeline_state``,
works unchanged.
"""

from __future__ import annotations

import copy
import dataclasses
from typing import Any, Callable, Sequence

import jax
import mujoco
import numpy as np
from brax.envs.base import Env
from flax import struct
from ml_collections import config_dict
from mujoco import mjx


@struct.dataclass
class State:
    """One world's state (a pytree: ``jax.vmap`` stacks it over worlds), with MuJoCo Playground's fields.

    ``data``: MJX's ``mjx.Data``; ``obs``: the observation; ``reward``, ``done``: of the last step (``done`` 1.0
    when the episode ended); ``metrics``: scalars of the last step; ``info``: what else the environment carries
    from step to step (arrays only)."""

    data: mjx.Data
    obs: jax.Array
    reward: jax.Array
    done: jax.Array
    metrics: dict[str, jax.Array]
    info: dict[str, Any]

    @property
    def pipeline_state(self) -> mjx.Data:
        """``data`` under Brax's name (Brax's wrappers read and replace ``pipeline_state``)."""
        return self.data

    def tree_replace(self, params: dict[str, Any]) -> "State":
        """A copy with the dotted paths of ``params`` replaced, e.g. ``{"data.qpos": qpos}`` (Playground's
        ``State.tree_replace``)."""
        new = self
        for path, value in params.items():
            new = _replace_path(new, path.split("."), value)
        return new


def _replace(self: State, **changes) -> State:
    """``dataclasses.replace``, with ``pipeline_state`` accepted as the name of ``data`` (Brax's wrappers)."""
    if "pipeline_state" in changes:
        changes["data"] = changes.pop("pipeline_state")
    return dataclasses.replace(self, **changes)


State.replace = _replace  # after flax's decorator, which sets its own


def _replace_path(obj, path: list[str], value):
    if len(path) == 1:
        return obj.replace(**{path[0]: value})
    return obj.replace(**{path[0]: _replace_path(getattr(obj, path[0]), path[1:], value)})


class MjxEnv(Env):
    """Base class of mjrft's MJX environments (MuJoCo Playground's ``MjxEnv``, and a Brax ``Env``).

    ``config``: the environment's ``ConfigDict`` (copied, then locked: a key that does not exist cannot be set);
    ``config_overrides``: ``{"dotted.key": value}`` applied to the copy (``{"reward_config.scales.energy":
    -0.1}``). Subclasses set ``_mj_model``, ``_mjx_model``, ``_dt``, ``_sim_dt`` and implement ``reset``,
    ``step``, ``observation_size`` and ``action_size``."""

    def __init__(self, config: config_dict.ConfigDict, config_overrides: dict | None = None):
        if not isinstance(config, config_dict.ConfigDict):
            raise TypeError(f"config must be an ml_collections.ConfigDict (get_default_config(name) gives one), "
                            f"got {type(config).__name__}")
        config = copy.deepcopy(config)
        config.lock()
        if config_overrides:
            config.update_from_flattened_dict(dict(config_overrides))
        self._config = config
        self._dt = float(config.ctrl_dt)
        self._sim_dt = float(config.sim_dt)

    @property
    def config(self) -> config_dict.ConfigDict:
        """The environment's configuration (locked)."""
        return self._config

    @property
    def dt(self) -> float:
        """The control step (s): ``n_substeps`` physics steps of ``sim_dt``."""
        return self._dt

    @property
    def sim_dt(self) -> float:
        """The physics step (s)."""
        return self._sim_dt

    @property
    def n_substeps(self) -> int:
        """Physics steps per control step."""
        return int(round(self.dt / self.sim_dt))

    @property
    def mj_model(self) -> mujoco.MjModel:
        """The MuJoCo model (on the host)."""
        return self._mj_model

    @property
    def mjx_model(self) -> mjx.Model:
        """The MJX model (on the device)."""
        return self._mjx_model

    @property
    def backend(self) -> str:
        return "mjx"

    @property
    def unwrapped(self) -> "MjxEnv":
        return self

    def render(self, trajectory: "State | Sequence[State]", height: int = 240, width: int = 320,
               camera: str | int | None = None, scene_option: mujoco.MjvOption | None = None,
               modify_scene_fns: Sequence[Callable[[mujoco.MjvScene], None]] | None = None):
        """Images (height, width, 3) uint8 of one world's states (a list of states, or one state), rendered from
        ``mj_model`` (Playground's ``render``). Needs an OpenGL backend chosen before mujoco is imported
        (``MUJOCO_GL=egl`` or ``osmesa`` where there is no display)."""
        return render_array(self.mj_model, trajectory, height, width, camera, scene_option, modify_scene_fns)


def render_array(mj_model: mujoco.MjModel, trajectory, height: int = 240, width: int = 320, camera=None,
                 scene_option=None, modify_scene_fns=None):
    """Render ``trajectory`` (one :class:`State` of one world, or a list of them): each state's positions,
    velocities, mocap poses and applied forces are put into an ``MjData`` of ``mj_model``, ``mj_forward``
    computes the rest, and ``mujoco.Renderer`` draws it from ``camera`` (a name or id; default the free camera).
    ``modify_scene_fns``: one function per state, called on the scene before drawing. Returns an image or a
    list of images."""
    states = trajectory if isinstance(trajectory, (list, tuple)) else [trajectory]
    if modify_scene_fns is not None and len(modify_scene_fns) != len(states):
        raise ValueError(f"modify_scene_fns must hold one function per state ({len(states)}), "
                         f"got {len(modify_scene_fns)}")
    renderer = mujoco.Renderer(mj_model, height=height, width=width)
    d = mujoco.MjData(mj_model)
    images = []
    try:
        for i, state in enumerate(states):
            data = state.data
            d.qpos[:] = np.asarray(data.qpos)
            d.qvel[:] = np.asarray(data.qvel)
            if mj_model.nmocap:
                d.mocap_pos[:] = np.asarray(data.mocap_pos)
                d.mocap_quat[:] = np.asarray(data.mocap_quat)
            d.xfrc_applied[:] = np.asarray(data.xfrc_applied)
            mujoco.mj_forward(mj_model, d)
            renderer.update_scene(d, camera=-1 if camera is None else camera, scene_option=scene_option)
            if modify_scene_fns is not None and modify_scene_fns[i] is not None:
                modify_scene_fns[i](renderer.scene)
            images.append(renderer.render())
    finally:
        renderer.close()
    return images if isinstance(trajectory, (list, tuple)) else images[0]

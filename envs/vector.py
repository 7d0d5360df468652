"""Vector environments whose physics for all sub-environments is one batched, compiled call.

>>> import gymnasium, mjrft
>>> envs = mjrft.envs.make_vector("mjrft/HexapodSand-v0", num_envs=8, medium="poppy_lp")
>>> envs = gymnasium.make_vec("mjrft/HexapodSand-v0", num_envs=8)   # the same (registered vector_entry_point)
>>> obs, infos = envs.reset(seed=0)                                 # env i seeded 0 + i
>>> obs, rewards, terminations, truncations, infos = envs.step(envs.action_space.sample())

:class:`GranularVectorEnv` follows gymnasium 1.x's ``VectorEnv`` API and behaves exactly like
``gymnasium.vector.SyncVectorEnv`` over ``gymnasium.make(env_id, ...)`` of the same id and keyword
arguments (same observations, rewards, flags and infos, bit for bit, tested), but each ``step``
advances the physics of every sub-environment in one :class:`mjrft.batch.BatchedTerrain` call
(optionally on several threads) instead of one ``terrain.step`` per environment. Observation, reward,
termination and info come from each sub-environment's own code (``GranularMujocoEnv._begin_step`` /
``_end_step``, the two halves of its ``step``). Rigid-ground ids work too (their physics is a
plain ``mj_step`` per environment).

* ``autoreset_mode``: ``"NextStep"`` (default, as gymnasium's vector envs), ``"SameStep"`` (ended
  environments reset inside the same ``step``; ``infos["final_obs"]`` / ``infos["final_info"]``) or
  ``"Disabled"`` (the caller resets ended ones with ``reset(options={"reset_mask": mask})``).
* ``max_episode_steps``: truncation after that many steps (gymnasium's ``TimeLimit``); default from
  the registration (1000), as ``gymnasium.make``.
* ``parallel``: ``True``: the batched physics on numba's threads; ``False`` (default): one thread
  (see :mod:`mjrft.batch` for the measurements behind the default).
* Any other keyword argument goes to every sub-environment (``medium``, ``frame_skip``, ...). With
  ``terrain_randomization`` each sub-environment draws its own terrain from its own ``np_random`` at
  each of its resets (sub-environment ``i`` of ``reset(seed=s)`` as a single env seeded ``s + i``);
  the batch steps each one's current terrain (:mod:`mjrft.envs.randomization`).

A non-finite action raises ``ValueError`` naming the environment index before anything is stepped.
A sub-environment whose simulation diverges (a non-finite granular force or state, or MuJoCo resetting
it) ends its episode as a single env does (``terminated``, reward 0, ``info["diverged"]`` with the
:class:`mjrft.NonFiniteError` message naming the body and time) and is reset by the autoreset; the
others step on undisturbed.

stable-baselines3: ``SB3VecEnv(env_id, num_envs, **kwargs)`` (or ``SB3VecEnv(vector_env)`` for a
gymnasium vector env in ``"SameStep"`` or ``"Disabled"`` mode) is a
``stable_baselines3.common.vec_env.VecEnv`` (immediate autoreset, ``terminal_observation`` and
``TimeLimit.truncated`` in the infos, seeds from ``venv.seed(s)``)::

    from mjrft.envs.vector import SB3VecEnv
    venv = SB3VecEnv("mjrft/HexapodSand-v0", num_envs=8)
    PPO("MlpPolicy", venv).learn(100_000)
"""

from __future__ import annotations

import functools
import importlib
from typing import Any

import gymnasium
import numpy as np
from gymnasium.envs.registration import load_env_creator
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from mjrft.batch import BatchedTerrain
from mjrft.errors import NonFiniteError, unknown

from .base import GranularMujocoEnv

__all__ = ["GranularVectorEnv", "SB3VecEnv", "unbatch_infos"]

_MODES = {m.value: m for m in AutoresetMode}


def _autoreset_mode(mode) -> AutoresetMode:
    if isinstance(mode, AutoresetMode):
        return mode
    if isinstance(mode, str):
        for m in AutoresetMode:
            if mode in (m.value, m.name):
                return m
    raise unknown("autoreset_mode", mode, list(_MODES))


def _env_class(env_id: str):
    """The registered spec and the environment class (or creator) of ``env_id`` (``"module:id"`` imports module first)."""
    if not isinstance(env_id, str):
        raise TypeError(f"env_id must be a string, got {type(env_id).__name__}")
    name = env_id
    if ":" in env_id:
        module, name = env_id.split(":", 1)
        importlib.import_module(module)
    if name not in gymnasium.registry:
        from . import ENV_IDS

        raise unknown("environment id", env_id, ENV_IDS)
    spec = gymnasium.registry[name]
    creator = spec.entry_point
    if creator is None:
        raise ValueError(f"environment id {name!r} has no entry_point to build its sub-environments from")
    if isinstance(creator, str):
        creator = load_env_creator(creator)
    return spec, creator


class GranularVectorEnv(VectorEnv):
    """``num_envs`` copies of a registered mjrft environment, stepped as one batch (see the module doc).

    Args:
        env_id: a registered id whose entry point builds a ``GranularMujocoEnv`` (``mjrft.envs.ENV_IDS``).
        num_envs: number of sub-environments (int >= 1).
        max_episode_steps: truncate after this many steps; ``None``: the registration's value.
        autoreset_mode: ``"NextStep"`` (default), ``"SameStep"`` or ``"Disabled"`` (or the AutoresetMode).
        parallel: ``True``: the batched physics on numba's threads; ``False`` (default): one thread.
        **env_kwargs: keyword arguments of every sub-environment.
    """

    def __init__(self, env_id: str, num_envs: int = 1, *, max_episode_steps: int | None = None,
                 autoreset_mode: str | AutoresetMode = AutoresetMode.NEXT_STEP, parallel: bool = False,
                 **env_kwargs):
        if isinstance(num_envs, bool) or not isinstance(num_envs, (int, np.integer)) or num_envs < 1:
            raise ValueError(f"num_envs must be an integer >= 1, got {num_envs!r}")
        self.autoreset_mode = _autoreset_mode(autoreset_mode)
        spec, creator = _env_class(env_id)
        if max_episode_steps is None:
            max_episode_steps = spec.max_episode_steps
        if max_episode_steps is not None and (isinstance(max_episode_steps, bool) or not isinstance(
                max_episode_steps, (int, np.integer)) or max_episode_steps < 1):
            raise ValueError(f"max_episode_steps must be an integer >= 1 or None, got {max_episode_steps!r}")
        self.max_episode_steps = None if max_episode_steps is None else int(max_episode_steps)
        kwargs = {**spec.kwargs, **env_kwargs}
        self.env_id = spec.id
        self.envs: list[GranularMujocoEnv] = []
        for _ in range(int(num_envs)):
            env = creator(**kwargs)
            if not isinstance(env, GranularMujocoEnv):
                env.close()
                self.close_extras()
                raise ValueError(f"{spec.id!r} builds {type(env).__name__}, not an mjrft GranularMujocoEnv; "
                                 "GranularVectorEnv batches only mjrft environments")
            self.envs.append(env)
        self.num_envs = len(self.envs)
        first = self.envs[0]
        self.metadata = dict(first.metadata)
        self.metadata["autoreset_mode"] = self.autoreset_mode
        self.render_mode = first.render_mode
        self.single_observation_space = first.observation_space
        self.single_action_space = first.action_space
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.frame_skip = first.frame_skip
        # physics: one batched call for the sand environments, mj_step per environment on rigid ground
        if first.terrain is not None:
            self.batch = BatchedTerrain([e.terrain for e in self.envs], [e.data for e in self.envs],
                                        parallel=parallel)
        else:
            self.batch = None
        n = self.num_envs
        self._obs = np.zeros((n, *self.single_observation_space.shape), dtype=self.single_observation_space.dtype)
        self._rewards = np.zeros(n, dtype=np.float64)
        self._terminations = np.zeros(n, dtype=np.bool_)
        self._truncations = np.zeros(n, dtype=np.bool_)
        self._autoreset_envs = np.zeros(n, dtype=np.bool_)
        self._elapsed = np.zeros(n, dtype=np.int64)
        self._needs_reset = np.ones(n, dtype=np.bool_)

    # ------------------------------------------------------------------ gymnasium vector API
    def reset(self, *, seed: int | list[int | None] | None = None, options: dict[str, Any] | None = None):
        """Reset every sub-environment (or those in ``options["reset_mask"]``, the only option; any other key
        raises ``ValueError`` naming it); ``seed``: int (env i gets seed + i), list of per-env seeds, or None."""
        n = self.num_envs
        if seed is None:
            seeds = [None] * n
        elif isinstance(seed, (int, np.integer)) and not isinstance(seed, bool):
            seeds = [int(seed) + i for i in range(n)]
        else:
            seeds = list(seed)
            if len(seeds) != n:
                raise ValueError(f"a list of seeds must have one per environment ({n}), got {len(seeds)}")
        options = dict(options) if options else {}
        mask = options.pop("reset_mask", None)
        if options:  # the sub-environments take no reset options: a misspelt reset_mask must not reset them all
            from mjrft.errors import unknown

            raise unknown("reset option", sorted(options)[0], ["reset_mask"])
        if mask is None:
            mask = np.ones(n, dtype=np.bool_)
        else:
            if not isinstance(mask, np.ndarray) or mask.dtype != np.bool_ or mask.shape != (n,):
                raise ValueError(f"options['reset_mask'] must be a numpy bool array of shape ({n},), got {mask!r}")
            if not mask.any():
                raise ValueError("options['reset_mask'] must select at least one environment, got all False")
        infos: dict[str, Any] = {}
        for i in np.flatnonzero(mask):
            obs, info = self.envs[i].reset(seed=seeds[i])
            self._obs[i] = obs
            self._elapsed[i] = 0
            infos = self._add_info(infos, info, i)
        self._terminations[mask] = False
        self._truncations[mask] = False
        self._autoreset_envs[mask] = False
        self._needs_reset[mask] = False
        return self._obs.copy(), infos

    def step(self, actions):
        """Step every sub-environment (NextStep mode: those that ended last step are reset instead)."""
        n = self.num_envs
        actions = np.asarray(actions)
        shape = (n, *self.single_action_space.shape)
        if actions.shape != shape:
            raise ValueError(f"actions must have shape {shape} (num_envs x action), got {actions.shape}")
        bad = np.flatnonzero(~np.all(np.isfinite(actions.reshape(n, -1)), axis=1))
        if bad.size:
            raise ValueError(f"actions of environment{'s' if bad.size > 1 else ''} "
                             f"{', '.join(str(i) for i in bad)} contain NaN or infinite values: {actions[bad[0]]!r}")
        if self._needs_reset.any():
            raise gymnasium.error.ResetNeeded(
                f"environments {', '.join(str(i) for i in np.flatnonzero(self._needs_reset))} need reset() "
                "before step()")
        if self.autoreset_mode == AutoresetMode.NEXT_STEP:
            resetting = self._autoreset_envs.copy()
        else:
            resetting = np.zeros(n, dtype=np.bool_)
            if self.autoreset_mode == AutoresetMode.DISABLED and self._autoreset_envs.any():
                ended = ", ".join(str(i) for i in np.flatnonzero(self._autoreset_envs))
                raise ValueError(f"autoreset_mode is Disabled and environments {ended} have ended; reset them with "
                                 "reset(options={'reset_mask': mask}) before stepping")
        stepping = ~resetting

        starts = {}
        for i in np.flatnonzero(stepping):
            starts[i] = self.envs[i]._begin_step(actions[i])
        if self.batch is not None:
            try:
                self.batch.step(np.where(stepping, self.frame_skip, 0))
            except NonFiniteError as exc:  # each failed environment ends its episode (info["diverged"])
                for i, message in exc.env_messages.items():
                    self.envs[i].diverged = message
        else:
            for i in starts:
                self.envs[i]._advance(self.frame_skip)

        infos: dict[str, Any] = {}
        for i in range(n):
            env = self.envs[i]
            if resetting[i]:
                obs, info = env.reset()
                self._elapsed[i] = 0
                self._rewards[i] = 0.0
                self._terminations[i] = False
                self._truncations[i] = False
            else:
                obs, reward, terminated, truncated, info = env._end_step(*starts[i])
                self._elapsed[i] += 1
                if self.max_episode_steps is not None and self._elapsed[i] >= self.max_episode_steps:
                    truncated = True
                self._rewards[i] = reward
                self._terminations[i] = terminated
                self._truncations[i] = truncated
                if self.autoreset_mode == AutoresetMode.SAME_STEP and (terminated or truncated):
                    infos = self._add_info(infos, {"final_obs": obs, "final_info": info}, i)
                    obs, info = env.reset()
                    self._elapsed[i] = 0
            self._obs[i] = obs
            infos = self._add_info(infos, info, i)
        self._autoreset_envs = self._terminations | self._truncations
        return (self._obs.copy(), self._rewards.copy(), self._terminations.copy(), self._truncations.copy(), infos)

    def render(self):
        """The sub-environments' frames (``render_mode`` of the sub-environments)."""
        return tuple(env.render() for env in self.envs)

    def close_extras(self, **kwargs) -> None:
        for env in getattr(self, "envs", []):
            env.close()

    # ------------------------------------------------------------------ helpers (as SyncVectorEnv)
    def call(self, name: str, *args, **kwargs) -> tuple:
        """Call method ``name`` of every sub-environment (or read the attribute) and return the results."""
        out = []
        for env in self.envs:
            value = getattr(env, name)
            out.append(value(*args, **kwargs) if callable(value) else value)
        return tuple(out)

    def get_attr(self, name: str) -> tuple:
        return tuple(getattr(env, name) for env in self.envs)

    def set_attr(self, name: str, values) -> None:
        if not isinstance(values, (list, tuple)):
            values = [values] * self.num_envs
        if len(values) != self.num_envs:
            raise ValueError(f"need one value per environment ({self.num_envs}), got {len(values)}")
        for env, value in zip(self.envs, values):
            setattr(env, name, value)

    @property
    def np_random_seed(self) -> tuple:
        return self.get_attr("np_random_seed")

    @property
    def np_random(self) -> tuple:
        return self.get_attr("np_random")


@functools.cache
def _vector_entry_point(env_id: str, name: str):
    def create(num_envs: int = 1, **kwargs) -> GranularVectorEnv:
        return GranularVectorEnv(env_id, num_envs, **kwargs)

    create.__name__ = create.__qualname__ = name
    create.__module__ = __name__
    create.__doc__ = f"The ``vector_entry_point`` of ``{env_id}``: ``GranularVectorEnv({env_id!r}, num_envs, **kwargs)``."
    return create


# ---------------------------------------------------------------------------------------------- stable-baselines3
def unbatch_infos(infos: dict, n: int) -> list[dict]:
    """gymnasium's batched info dict (values with ``_key`` masks, nested dicts) -> one dict per environment."""
    out: list[dict] = [{} for _ in range(n)]
    for key, value in infos.items():
        if key.startswith("_") and key[1:] in infos:
            continue
        mask = infos.get("_" + key)
        rows = range(n) if mask is None else np.flatnonzero(mask)
        if isinstance(value, dict):
            sub = unbatch_infos(value, n)
            for i in rows:
                out[i][key] = sub[i]
        else:
            for i in rows:
                out[i][key] = value[i]
    return out


@functools.cache
def _sb3_class():
    from stable_baselines3.common.env_util import is_wrapped
    from stable_baselines3.common.vec_env.base_vec_env import VecEnv

    class SB3VecEnv(VecEnv):
        """stable-baselines3 ``VecEnv`` over a gymnasium vector env (see :mod:`mjrft.envs.vector`).

        ``SB3VecEnv(env_id, num_envs=1, **kwargs)`` builds a :class:`GranularVectorEnv` in ``"SameStep"``
        mode; ``SB3VecEnv(vector_env)`` wraps any gymnasium ``VectorEnv`` with ``.envs`` in ``"SameStep"``
        or ``"Disabled"`` mode. Step infos carry ``terminal_observation`` (ended environments) and
        ``TimeLimit.truncated``, as SB3's ``DummyVecEnv``.
        """

        def __init__(self, env, num_envs: int | None = None, **kwargs):
            if isinstance(env, str):
                env = GranularVectorEnv(env, 1 if num_envs is None else num_envs,
                                        autoreset_mode=AutoresetMode.SAME_STEP, **kwargs)
            elif num_envs is not None or kwargs:
                raise ValueError("num_envs and keyword arguments are only for SB3VecEnv(env_id, ...), "
                                 "not for an existing vector env")
            if not isinstance(env, VectorEnv):
                raise TypeError(f"env must be an environment id or a gymnasium VectorEnv, got {type(env).__name__}")
            mode = env.metadata.get("autoreset_mode")
            if mode not in (AutoresetMode.SAME_STEP, AutoresetMode.DISABLED):
                raise ValueError(f"SB3VecEnv needs a vector env with autoreset_mode SameStep or Disabled (SB3 resets "
                                 f"ended environments at once), got {mode!r}")
            self.venv = env
            self._mode = mode
            self._actions = None
            super().__init__(env.num_envs, env.single_observation_space, env.single_action_space)

        def reset(self):
            seeds = None if all(s is None for s in self._seeds) else list(self._seeds)
            opts = [o for o in self._options if o]
            if opts and any(o != opts[0] for o in self._options):
                raise ValueError("SB3VecEnv passes one options dict to every environment; got different ones")
            obs, infos = self.venv.reset(seed=seeds, options=dict(opts[0]) if opts else None)
            self.reset_infos = unbatch_infos(infos, self.num_envs)
            self._reset_seeds()
            self._reset_options()
            return obs

        def step_async(self, actions: np.ndarray) -> None:
            self._actions = actions

        def step_wait(self):
            obs, rewards, terminated, truncated, infos = self.venv.step(self._actions)
            n = self.num_envs
            dones = terminated | truncated
            if self._mode == AutoresetMode.SAME_STEP:
                final_obs = infos.pop("final_obs", None)
                final_info = unbatch_infos(infos.pop("final_info", {}), n)
                infos.pop("_final_obs", None)
                infos.pop("_final_info", None)
                step_infos = unbatch_infos(infos, n)
                for i in np.flatnonzero(dones):
                    self.reset_infos[i] = step_infos[i]
                    step_infos[i] = dict(final_info[i])
                    step_infos[i]["terminal_observation"] = final_obs[i]
            else:
                step_infos = unbatch_infos(infos, n)
                if dones.any():
                    for i in np.flatnonzero(dones):
                        step_infos[i]["terminal_observation"] = obs[i].copy()
                    new_obs, reset_infos = self.venv.reset(options={"reset_mask": dones.copy()})
                    obs[dones] = new_obs[dones]
                    for i, info in enumerate(unbatch_infos(reset_infos, n)):
                        if dones[i]:
                            self.reset_infos[i] = info
            for i in range(n):
                step_infos[i]["TimeLimit.truncated"] = bool(truncated[i] and not terminated[i])
            return obs, rewards.astype(np.float32), dones, step_infos

        def close(self) -> None:
            self.venv.close()

        def get_images(self):
            return list(self.venv.render())

        def _targets(self, indices):
            return [self.venv.envs[i] for i in self._get_indices(indices)]

        def get_attr(self, attr_name: str, indices=None) -> list:
            return [env.get_wrapper_attr(attr_name) for env in self._targets(indices)]

        def set_attr(self, attr_name: str, value, indices=None) -> None:
            for env in self._targets(indices):
                env.set_wrapper_attr(attr_name, value)

        def env_method(self, method_name: str, *method_args, indices=None, **method_kwargs) -> list:
            return [env.get_wrapper_attr(method_name)(*method_args, **method_kwargs) for env in self._targets(indices)]

        def env_is_wrapped(self, wrapper_class, indices=None) -> list[bool]:
            return [is_wrapped(env, wrapper_class) for env in self._targets(indices)]

    SB3VecEnv.__module__ = __name__
    return SB3VecEnv


def __getattr__(name: str):
    if name == "SB3VecEnv":  # defined on first use: stable-baselines3 is an optional dependency
        return _sb3_class()
    # the registered vector entry points, "mjrft.envs.vector:<Name>Vector" (mjrft.envs.VECTOR_ENTRY_POINTS)
    from . import VECTOR_ENTRY_POINTS

    for env_id, entry_point in VECTOR_ENTRY_POINTS.items():
        if entry_point == f"{__name__}:{name}":
            return _vector_entry_point(env_id, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

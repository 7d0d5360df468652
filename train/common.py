"""Helpers shared by the training commands (train, vec envs, evaluation, rollouts, sweeps, plots): parsing
command-line values, making environments, the algorithms' classes and defaults, a progress bar. The modules of
:mod:`mjrft.train` import from here and from each other in one direction only (no import cycles)."""

from __future__ import annotations

import argparse
import inspect
import json
import math
import multiprocessing
import signal
import sys
import warnings

import numpy as np

from mjrft.errors import unknown

ALGOS = ("ppo", "sac")
#: constructor arguments of the algorithms that are not hyper-parameters (set by train() itself)
NOT_HYPERPARAMS = ("self", "policy", "env", "seed", "device", "verbose", "tensorboard_log", "_init_setup_model")
#: modules the vec-env fork server imports before forking workers
FORKSERVER_PRELOAD = ["__main__", "stable_baselines3.common.vec_env.subproc_vec_env", "mjrft.train.common",
                      "mjrft.envs.hexapod", "mjrft.envs.biped", "mjrft.envs.humanoid"]


# ---------------------------------------------------------------------------------------------- parsing
def parse_value(text: str):
    """A command-line value: JSON (numbers, ``true``/``false``/``null``, lists, dicts, quoted strings),
    Python's ``True``/``False``/``None``, otherwise the text itself (e.g. a medium name)."""
    literal = {"True": True, "False": False, "None": None}
    if text in literal:
        return literal[text]
    try:
        return json.loads(text)
    except json.JSONDecodeError:
        return text


def parse_kwargs(items, what: str = "env kwarg") -> dict:
    """``["resolution=0.02", "medium=poppy_lp"]`` -> ``{"resolution": 0.02, "medium": "poppy_lp"}``."""
    out = {}
    for item in items or ():
        key, sep, value = str(item).partition("=")
        key = key.strip()
        if not sep or not key.isidentifier():
            raise ValueError(f"{what} must be given as key=value (e.g. resolution=0.02), got {item!r}")
        out[key] = parse_value(value.strip())
    return out


def check_int(name: str, value, minimum: int) -> int:
    """``value`` as an int if it is a whole number >= ``minimum`` (``2e5`` as a float counts), else a ValueError
    naming ``name``."""
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def int_arg(text: str) -> int:
    """argparse type accepting ``200000``, ``2e5`` and ``200_000``."""
    try:
        v = float(text.replace("_", ""))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
    if not math.isfinite(v) or not v.is_integer():
        raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}")
    return int(v)


# ---------------------------------------------------------------------------------------------- envs
def check_env_id(env_id: str) -> str:
    """``env_id`` if gymnasium knows it (mjrft registers its ids on import), else an error listing them."""
    import gymnasium

    import mjrft  # noqa: F401  (registers the mjrft environments)
    from mjrft.envs import ENV_IDS, GYM_SAND_IDS

    if not isinstance(env_id, str) or env_id not in gymnasium.registry:
        raise unknown("env id", env_id, [*ENV_IDS, *GYM_SAND_IDS])
    return env_id


def check_mujoco_env(env, env_id: str) -> None:
    """Refuse an env that mjrft's commands cannot train, load without unpickling and evaluate: one that is not a
    MuJoCo env (its unwrapped env holds an ``mujoco.MjModel``) with array (``Box``) observations and continuous
    (``Box``) actions. The error names what the env has and what mjrft takes."""
    import mujoco
    from gymnasium import spaces

    problems = []
    if not isinstance(getattr(env.unwrapped, "model", None), mujoco.MjModel):
        problems.append(f"it is not a MuJoCo environment ({type(env.unwrapped).__name__})")
    for what, space, want in (("actions", env.action_space, "continuous"),
                              ("observations", env.observation_space, "an array")):
        if not isinstance(space, spaces.Box):
            problems.append(f"its {what} are {space}, not {want} (Box)")
    if problems:
        raise ValueError(f"{env_id}: {'; '.join(problems)}. mjrft trains and evaluates MuJoCo robots with continuous "
                         f"actions: mjrft's environments (mjrft/HexapodSand-v0, ...), gymnasium's MuJoCo robots on "
                         f"sand (mjrft/HopperSand-v5, ...) or on rigid ground (Hopper-v5, ...)")


def valid_env_kwargs(env_id: str) -> list[str]:
    """Keyword arguments the environment ``env_id`` accepts (plus gymnasium.make's ``max_episode_steps``)."""
    import gymnasium

    spec = gymnasium.spec(env_id)
    entry = spec.entry_point
    if isinstance(entry, str):
        module, _, attr = entry.partition(":")
        import importlib

        entry = getattr(importlib.import_module(module), attr)
    if hasattr(entry, "valid_kwargs"):  # a gymnasium robot on sand (mjrft.envs.wrapper.make_sand_env)
        return sorted(set(entry.valid_kwargs(**spec.kwargs)) - {"gym_id"} | {"max_episode_steps"})
    names = set()
    own = [c for c in getattr(entry, "__mro__", ()) if c.__module__.split(".")[0] == "mjrft"]
    for cls in own or [entry]:  # mjrft's env classes (not gymnasium's MujocoEnv internals)
        init = getattr(cls, "__init__", None)
        if init is None or cls is object:
            continue
        try:
            params = inspect.signature(init).parameters
        except (TypeError, ValueError):
            continue
        names.update(n for n, p in params.items()
                     if n != "self" and p.kind not in (p.VAR_KEYWORD, p.VAR_POSITIONAL))
    names.discard("pickle_kwargs")
    names.discard("xml")
    return sorted(names | {"max_episode_steps"})


class MujocoWarning(RuntimeWarning):
    """A warning of MuJoCo's own (e.g. "Nan, Inf or huge value in QACC"), issued as a Python warning."""


def route_mujoco_warnings() -> None:
    """Issue MuJoCo's warnings as :class:`MujocoWarning` instead of MuJoCo's default, which appends them to
    ``MUJOCO_LOG.TXT`` in the current folder. While training they land in the run's ``warnings.csv``
    (:mod:`mjrft.train.run_warnings`). A warning handler installed by the caller is left in place."""
    import mujoco

    if mujoco.get_mju_user_warning() is None:
        mujoco.set_mju_user_warning(_mujoco_warning)


def _mujoco_warning(message: str) -> None:
    try:
        warnings.warn(f"MuJoCo: {message}", MujocoWarning, stacklevel=2)
    except Exception:  # warnings turned into errors: an exception cannot cross MuJoCo's C code
        sys.stderr.write(f"MuJoCo warning: {message}\n")


def make_env(env_id: str, env_kwargs: dict | None = None, rank: int = 0):
    """One environment: ``gymnasium.make(env_id, **env_kwargs)`` (``max_episode_steps`` goes to the
    time limit). Inside a vec-env worker process SIGINT is ignored, so Ctrl-C stops only the trainer,
    which then saves cleanly and closes the workers. MuJoCo's warnings become Python warnings
    (:func:`route_mujoco_warnings`)."""
    import gymnasium

    import mjrft  # noqa: F401  (registers the mjrft environments in a fresh worker process)

    if multiprocessing.parent_process() is not None:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    route_mujoco_warnings()
    try:
        return gymnasium.make(env_id, **dict(env_kwargs or {}))
    except TypeError as exc:
        if "keyword argument" not in str(exc):
            raise
        raise ValueError(f"bad env kwarg for {env_id}: {exc}; valid keyword arguments: "
                         f"{', '.join(valid_env_kwargs(env_id))}") from None


def make_training_env(env_id: str, env_kwargs: dict | None = None, rank: int = 0):
    """:func:`make_env` with its warnings put into ``info["warnings"]`` for the trainer's tally
    (:mod:`mjrft.train.run_warnings`)."""
    from .run_warnings import CaptureWarnings

    return CaptureWarnings(make_env(env_id, env_kwargs, rank))


def start_method() -> str:
    """``forkserver`` where available (Linux), else ``spawn``: safe with threads (torch, numba)."""
    return "forkserver" if "forkserver" in multiprocessing.get_all_start_methods() else "spawn"


# ---------------------------------------------------------------------------------------------- algorithms
def algo_class(algo: str):
    """The stable-baselines3 class of ``algo`` (``"ppo"`` or ``"sac"``, case-insensitive)."""
    name = str(algo).lower()
    if name not in ALGOS:
        raise unknown("algorithm", algo, ALGOS)
    import stable_baselines3

    return getattr(stable_baselines3, name.upper())


def _jsonable(value):
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if value is None or isinstance(value, (bool, int, str)):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else repr(value)
    if isinstance(value, type):
        return f"{value.__module__}.{value.__qualname__}"
    return repr(value)


def default_hyperparams(algo: str) -> dict:
    """Every hyper-parameter of ``algo``'s constructor with SB3's default."""
    sig = inspect.signature(algo_class(algo).__init__)
    return {n: p.default for n, p in sig.parameters.items()
            if n not in NOT_HYPERPARAMS and p.default is not inspect.Parameter.empty}




# ---------------------------------------------------------------------------------------------- progress
def progress_bar(total: int, what: str, enabled: bool):
    """A tqdm bar over ``total`` env steps on stderr (a no-op bar when not ``enabled``)."""
    from tqdm import tqdm

    return tqdm(total=total, desc=what, unit="step", disable=not enabled, dynamic_ncols=True)

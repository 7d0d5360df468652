"""The training environments: ``n_envs`` copies of an env as one stable-baselines3 ``VecEnv``.

>>> from mjrft.train.vecenv import make_vec_env
>>> venv = make_vec_env("mjrft/HexapodSand-v0", 4, seed=0, monitor_file="runs/hex/monitor.csv")
>>> venv = make_vec_env("mjrft/HexapodSand-v0", 4, seed=0, kind="batched")

Kinds (``kind``):

===========  =========================================================================================
``subproc``  SB3's ``SubprocVecEnv``: one worker process per env (``forkserver`` start method on Linux,
             ``spawn`` elsewhere; the workers ignore SIGINT, so Ctrl-C reaches only the trainer)
``dummy``    SB3's ``DummyVecEnv``: the envs one after the other in the trainer's process
``batched``  mjrft's :class:`mjrft.envs.vector.SB3VecEnv`: the envs in the trainer's process, the physics
             of all of them in one compiled call (:mod:`mjrft.batch`); only the mjrft envs
             (``mjrft.envs.ENV_IDS``), not gymnasium's robots on sand
``auto``     :func:`resolve_kind`: ``dummy`` for one env, ``subproc`` with more cores than envs or with 4
             cores or more, else ``batched`` (mjrft envs) or ``dummy`` (others)
===========  =========================================================================================

Every kind seeds env ``i`` with ``seed + i`` (at the first reset), puts the warnings the envs raise
into ``info["warnings"]`` for :func:`mjrft.train.run_warnings.warning_tally`, and is wrapped in SB3's
``VecMonitor`` appending one row per finished episode to ``monitor_file``: return ``r``, length ``l``,
wall time ``t`` and the episode's forward speed ``speed`` (m/s): the mean of ``info["x_velocity"]`` over
its steps, which is the torso's x displacement over the episode divided by its duration (the
``speed`` of ``mjrft eval``), NaN for an env whose info has no ``x_velocity``. A monitor file
written without the ``speed`` column keeps its columns when a resumed run appends to it.

With ``batched`` the envs' warnings come from one call for all of them, so they cannot be told apart:
they go into env 0's ``info["warnings"]``, each message prefixed ``(batched step of N envs)``.
"""

from __future__ import annotations

import functools
import multiprocessing
import os
import warnings
from pathlib import Path

import numpy as np

from mjrft.errors import unknown

from .common import FORKSERVER_PRELOAD, check_int, make_training_env, start_method, valid_env_kwargs

KINDS = ("auto", "subproc", "dummy", "batched")
#: from this many cores on, ``auto`` steps the envs in worker processes whatever their number (:func:`resolve_kind`)
PARALLEL_CORES = 4
#: the monitor column holding each episode's forward speed (m/s)
SPEED_KEY = "speed"
MONITOR_COLUMNS = ("r", "l", "t")


def check_kind(kind) -> str:
    """``kind`` if it is one of :data:`KINDS`, else an error naming the valid choices."""
    if not isinstance(kind, str) or kind not in KINDS:
        raise unknown("vec env kind", kind, KINDS)
    return kind


def batchable(env_id: str) -> bool:
    """True for the mjrft envs (:data:`mjrft.envs.ENV_IDS`), which the ``batched`` kind can step."""
    from mjrft.envs import ENV_IDS

    return env_id in ENV_IDS


def resolve_kind(kind: str, env_id: str, n_envs: int, cpu_count: int | None = None) -> str:
    """The concrete kind ``make_vec_env`` builds for ``kind`` (``auto`` resolved; ``cpu_count`` defaults
    to ``os.cpu_count()``).

    ``auto``:

    1. one env: ``dummy`` (nothing to run side by side);
    2. more cores than envs, or at least :data:`PARALLEL_CORES` cores: ``subproc``. Its workers' physics runs
       on as many cores as there are envs (up to the cores), while ``batched`` and ``dummy`` step every env
       in the trainer's process on one core: with many cores that single core is the limit;
    3. otherwise (2 or 3 cores, at least as many envs) ``batched`` for the mjrft envs (:func:`batchable`),
       ``dummy`` for the others.

    Measured by ``benchmarks/bench_training.py`` (PPO on 2 cores with 2, 4 and 8 envs; the numbers in
    docs/training.md, "Throughput"): on HexapodSand-v0 ``batched`` and ``dummy`` train within 14 % of
    each other and ``subproc`` is the slowest kind on 2 cores.
    """
    kind = check_kind(kind)
    if kind != "auto":
        return kind
    cpus = cpu_count or os.cpu_count() or 1
    if n_envs == 1:
        return "dummy"
    if cpus > n_envs or cpus >= PARALLEL_CORES:
        return "subproc"
    return "batched" if batchable(env_id) else "dummy"


# ---------------------------------------------------------------------------------------------- wrappers
def _sb3_wrappers():
    from stable_baselines3.common.vec_env import VecEnvWrapper

    class VecEpisodeSpeed(VecEnvWrapper):
        """Adds ``info["speed"]`` (m/s) to the info of each finished episode's last step: the mean of
        ``info["x_velocity"]`` over the episode's steps (NaN when the env gives no ``x_velocity``)."""

        def __init__(self, venv):
            super().__init__(venv)
            self._sum = np.zeros(self.num_envs)
            self._steps = np.zeros(self.num_envs, dtype=np.int64)

        def reset(self):
            obs = self.venv.reset()
            self._sum[:] = 0.0
            self._steps[:] = 0
            return obs

        def step_wait(self):
            obs, rewards, dones, infos = self.venv.step_wait()
            infos = list(infos)
            self._sum += [float(info.get("x_velocity", np.nan)) for info in infos]
            self._steps += 1
            for i in np.flatnonzero(dones):
                infos[i] = {**infos[i], SPEED_KEY: float(self._sum[i] / self._steps[i])}
                self._sum[i] = 0.0
                self._steps[i] = 0
            return obs, rewards, dones, infos

    class VecCaptureWarnings(VecEnvWrapper):
        """The warnings raised while the wrapped vec env steps or resets go into env 0's ``info["warnings"]``
        (category name, message prefixed ``(batched step of N envs)``) instead of being printed."""

        def _caught(self, caught) -> list:
            prefix = f"(batched step of {self.num_envs} envs) "
            return [(w.category.__name__, prefix + str(w.message)) for w in caught]

        def reset(self):
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                obs = self.venv.reset()
            if caught:
                self.venv.reset_infos[0] = {**self.venv.reset_infos[0], "warnings": self._caught(caught)}
            return obs

        def step_wait(self):
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                obs, rewards, dones, infos = self.venv.step_wait()
            if caught:
                infos = list(infos)
                infos[0] = {**infos[0], "warnings": [*infos[0].get("warnings", ()), *self._caught(caught)]}
            return obs, rewards, dones, infos

    return VecEpisodeSpeed, VecCaptureWarnings


def monitor_keys(monitor_file) -> tuple[str, ...]:
    """The extra monitor columns to write: ``("speed",)``, or those of an existing file being appended to."""
    path = Path(monitor_file)
    if not path.exists() or path.stat().st_size == 0:
        return (SPEED_KEY,)
    with open(path) as fh:
        header = next((line.strip() for line in fh if line.strip() and not line.startswith("#")), "")
    columns = tuple(header.split(","))
    extras = columns[len(MONITOR_COLUMNS):]
    if columns[:len(MONITOR_COLUMNS)] != MONITOR_COLUMNS or extras not in ((), (SPEED_KEY,)):
        raise ValueError(f"{path} has columns {header!r}; a training monitor has "
                         f"{','.join(MONITOR_COLUMNS)} or {','.join((*MONITOR_COLUMNS, SPEED_KEY))} (use another run folder)")
    return extras


# ---------------------------------------------------------------------------------------------- building
def _batched(env_id: str, n_envs: int, env_kwargs: dict):
    from mjrft.envs.vector import SB3VecEnv

    if not batchable(env_id):
        from mjrft.envs import ENV_IDS

        raise ValueError(f"vec env kind 'batched' steps only mjrft's own envs, not {env_id!r}; use 'subproc' or "
                         f"'dummy' for it, or one of: {', '.join(sorted(ENV_IDS))}")
    try:
        return SB3VecEnv(env_id, n_envs, **env_kwargs)
    except TypeError as exc:
        if "keyword argument" not in str(exc):
            raise
        raise ValueError(f"bad env kwarg for {env_id}: {exc}; valid keyword arguments: "
                         f"{', '.join(valid_env_kwargs(env_id))}") from None


def _subproc(env_id: str, n_envs: int, env_kwargs: dict):
    from stable_baselines3.common.vec_env import SubprocVecEnv

    fns = [functools.partial(make_training_env, env_id, env_kwargs, i) for i in range(n_envs)]
    if start_method() == "forkserver":
        # the fork server imports these once; each worker forks from it instead of importing torch, SB3,
        # gymnasium and mjrft again (no effect once this process's fork server is running)
        multiprocessing.get_context("forkserver").set_forkserver_preload(FORKSERVER_PRELOAD)
    return SubprocVecEnv(fns, start_method=start_method())


def _dummy(env_id: str, n_envs: int, env_kwargs: dict):
    from stable_baselines3.common.vec_env import DummyVecEnv

    return DummyVecEnv([functools.partial(make_training_env, env_id, env_kwargs, i) for i in range(n_envs)])


def make_vec_env(env_id: str, n_envs: int, seed: int, env_kwargs: dict | None = None, monitor_file=None,
                 kind: str = "auto"):
    """``n_envs`` envs of ``env_id`` as one SB3 ``VecEnv`` of ``kind`` (module doc), seeded ``seed, seed+1, ...``,
    under a ``VecMonitor`` that appends finished episodes (``r``, ``l``, ``t``, ``speed``) to ``monitor_file``."""
    from stable_baselines3.common.monitor import ResultsWriter
    from stable_baselines3.common.vec_env import VecMonitor

    n_envs = check_int("n_envs", n_envs, 1)
    seed = check_int("seed", seed, 0)
    kind = resolve_kind(kind, env_id, n_envs)
    env_kwargs = dict(env_kwargs or {})
    keys = monitor_keys(monitor_file) if monitor_file is not None else (SPEED_KEY,)
    speed, capture = _sb3_wrappers()
    build = {"subproc": _subproc, "dummy": _dummy, "batched": _batched}[kind]
    venv = build(env_id, n_envs, env_kwargs)
    if kind == "batched":
        venv = capture(venv)
    venv.seed(seed)
    venv = VecMonitor(speed(venv), info_keywords=keys)
    if monitor_file is not None:
        monitor_file = Path(monitor_file)
        append = monitor_file.exists() and monitor_file.stat().st_size > 0
        if append:
            _drop_torn_line(monitor_file)
        venv.results_writer = ResultsWriter(str(monitor_file), header={"t_start": venv.t_start, "env_id": env_id},
                                            extra_keys=keys, override_existing=not append)
    return venv


def _drop_torn_line(path: Path) -> None:
    """Cut a last line that a stopped process left without its newline, so appended rows start a line."""
    with open(path, "rb+") as fh:
        data = fh.read()
        if data and not data.endswith(b"\n"):
            fh.truncate(data.rfind(b"\n") + 1)

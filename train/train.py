"""``mjrft train``: stable-baselines3 (PPO or SAC) on the mjrft environments, resumable (the command line:
:mod:`mjrft.train.train_command`).

>>> from mjrft.train.train import train
>>> result = train("mjrft/HexapodSand-v0", "ppo", timesteps=200_000, n_envs=4, seed=0, out_dir="runs/hex",
...                env_kwargs={"resolution": 0.02})
>>> result.model_path, result.num_timesteps

Run folder (``out_dir``):

==============================================  ==========================================================
``config.json``                                 the full configuration: env id and kwargs, algorithm, every
                                                hyper-parameter (SB3 defaults filled in), seed, n_envs,
                                                package versions, the step count and a history of runs
``model.zip``                                   the policy after the last run (normal end or Ctrl-C)
``model_vecnormalize.npz``                      observation/reward statistics (only with ``normalize``)
``checkpoints/step_<N>.zip``                    periodic checkpoints, N = ``num_timesteps`` (10 digits)
``checkpoints/step_<N>_vecnormalize.npz``       their VecNormalize statistics (only with ``normalize``)
``checkpoints/step_<N>_replay_buffer.npz``      SAC's replay buffer, kept for the newest checkpoint only
``checkpoints/step_<N>_monitor.json``           the length of ``monitor.csv`` when the checkpoint was saved
``monitor.csv``                                 one row per finished episode (return, length, wall time);
                                                a resumed run appends to it (after dropping what a killed
                                                run recorded past the checkpoint it resumes from)
``logs/from_<N>/progress.csv``                  SB3's training log of the run that started at step N
``warnings.csv``                                every warning the environments raised while training (step,
                                                env, category, message); each kind is printed once, with
                                                counts at the end (:mod:`mjrft.train.run_warnings`)
==============================================  ==========================================================

Choices:

* ``timesteps`` is the TOTAL budget of the run folder, not an increment: calling :func:`train` again on
  the same folder resumes from the newest checkpoint (``reset_num_timesteps=False``) and trains until
  ``num_timesteps`` reaches ``timesteps`` (PPO stops at the end of the rollout that reaches it, so it
  may pass the budget by less than ``n_steps x n_envs``); a finished run is left alone.
* Every save is atomic: each file is written under a temporary name, flushed to disk and renamed, and
  a checkpoint's ``.zip`` is written after its side files, so an interruption at any moment leaves the
  newest complete checkpoint intact (at worst a stray ``.tmp`` file, removed when the run next starts).
  No file of a run folder is unpickled when it is loaded (:mod:`mjrft.train.artefacts`).
* Resuming takes the newest checkpoint that loads: an unreadable one (truncated, corrupt, its
  VecNormalize statistics missing) is reported by name and the one before it is tried. ``config.json``
  is rewritten only after the model has loaded. Each run appends an entry to its ``runs`` with a final
  ``status``: ``finished``, ``interrupted`` (Ctrl-C, SIGTERM) or ``crashed`` (an exception, with its
  ``error``); an entry still ``running`` when the next run starts belonged to a process that was killed
  outright and becomes ``crashed``.
* Resuming uses the saved configuration: every setting left out (``None``; an option not given on the
  command line) is the one ``config.json`` recorded, the budget ``timesteps`` included. A different env id,
  algorithm, env kwarg, hyper-parameter, ``normalize`` or ``seed`` raises a ``ValueError`` naming the
  difference. ``n_envs`` (PPO only: SAC's replay buffer is laid out per environment), ``checkpoint_every``,
  ``vec_env``, ``device`` and ``torch_threads`` may be changed on purpose by giving them: each change is
  said (``report``, else a warning) and recorded in the run's entry of ``runs`` (``changed``: from, to),
  and the top-level keys hold the values in use (the saved run's package versions, when they differ, are
  kept as ``versions_before``). The environments are re-seeded with ``seed + num_timesteps`` so a
  resumed run does not replay the episodes it already saw.
* A resume first drops what the previous run recorded after the checkpoint it resumes from (a killed or
  crashed run lost those steps, and they are trained again): ``monitor.csv`` is cut back to its length at
  that checkpoint (``checkpoints/step_<N>_monitor.json``), and the rows after step N leave
  ``logs/*/progress.csv`` and ``warnings.csv``; the run says so and counts them in its entry's ``dropped``.
* SAC's ``buffer_size`` defaults to ``min(1_000_000, timesteps)``: a checkpoint stores the whole
  buffer array, so a 1e6 buffer for a 50k-step run would write ~0.5 GB per checkpoint for nothing.
* The ``n_envs`` environments are stepped as ``vec_env`` says (:mod:`mjrft.train.vecenv`: subprocesses,
  one after the other, or mjrft's batched physics; ``auto`` picks the fastest measured on a machine
  with that many cores). Ctrl-C reaches only the trainer (subprocess workers ignore SIGINT), which
  saves ``model.zip``, a checkpoint and ``config.json`` and returns (``interrupted=True``). SIGTERM
  (e.g. a cluster scheduler stopping the job) is handled the same way.
"""

from __future__ import annotations

import datetime
import inspect
import json
import math
import multiprocessing
import os
import re
import signal
import sys
import warnings
from dataclasses import dataclass, field
from pathlib import Path

from mjrft.errors import unknown

from .common import (ALGOS, FORKSERVER_PRELOAD, NOT_HYPERPARAMS, MujocoWarning, _jsonable,  # noqa: F401
                     algo_class, check_env_id, check_int, check_mujoco_env, default_hyperparams, int_arg, make_env,
                     make_training_env, parse_kwargs, parse_value, route_mujoco_warnings, start_method,
                     valid_env_kwargs)
from .config import DEFAULTS
from .vecenv import check_kind, make_vec_env, resolve_kind

_check_int, _int_arg = check_int, int_arg  # the names the commands' modules used

POLICY = "MlpPolicy"
CHECKPOINT_DIR = "checkpoints"
CONFIG_NAME = "config.json"
MODEL_NAME = "model.zip"
VECNORM_SUFFIX = "_vecnormalize.npz"
BUFFER_SUFFIX = "_replay_buffer.npz"
#: the pickled side files SB3's own ``save`` writes (loaded only with ``trust=True``)
PICKLE_VECNORM_SUFFIX = "_vecnormalize.pkl"
PICKLE_BUFFER_SUFFIX = "_replay_buffer.pkl"
#: beside a checkpoint: the length of monitor.csv when it was saved (a resume from it drops what came after)
MARK_SUFFIX = "_monitor.json"
MONITOR_NAME = "monitor.csv"
WARNINGS_NAME = "warnings.csv"
LOGS_DIR = "logs"
SAC_MAX_BUFFER = 1_000_000
_CKPT_RE = re.compile(r"^step_(\d+)\.zip$")


# ---------------------------------------------------------------------------------------------- algorithms
# hyper-parameters whose SB3 default is None, and what they take instead
_OPTIONAL_HYPERPARAMS = {"policy_kwargs": dict, "target_kl": float, "clip_range_vf": float, "stats_window_size": int,
                         "replay_buffer_kwargs": dict, "action_noise": None, "replay_buffer_class": None,
                         "rollout_buffer_class": None, "rollout_buffer_kwargs": dict, "target_entropy": float}
_KINDS = {dict: "a JSON object, e.g. '{\"net_arch\": [64, 64]}'", float: "a number", int: "an integer",
          bool: "true or false"}


def check_hyperparam(algo: str, name: str, value, default):
    """``value`` for hyper-parameter ``name`` of ``algo``, checked against the kind of SB3's default.

    Integers (``n_steps``), numbers (``learning_rate``; an integer value is accepted), booleans and the
    JSON objects of ``*_kwargs`` are checked here, so a bad value is one error line naming the
    parameter and what it takes, before any environment is built. Parameters whose default is a string
    (e.g. SAC's ``ent_coef="auto"``) or a tuple take a number or that kind.
    """
    want = _OPTIONAL_HYPERPARAMS.get(name, "any") if default is None else type(default)
    if name == "train_freq" and isinstance(value, (list, tuple)):  # SB3 also takes (n, "step" | "episode")
        return value
    if want is None or want == "any" or (value is None and default is None):
        return value
    if want is bool:
        ok = isinstance(value, bool)
    elif want is int:
        if isinstance(value, float) and value.is_integer():
            value = int(value)
        ok = isinstance(value, int) and not isinstance(value, bool)
    elif want is float:
        ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
        value = float(value) if ok else value
    elif want is dict:
        ok = isinstance(value, dict)
    elif want is str:
        ok = isinstance(value, str) or (isinstance(value, (int, float)) and not isinstance(value, bool))
    elif want in (tuple, list):
        ok = isinstance(value, (int, list, tuple)) and not isinstance(value, bool)
    else:
        return value
    if not ok:
        kind = _KINDS.get(want, f"a {want.__name__}")
        if default is None:
            kind += " or null"
        raise ValueError(f"{algo.upper()} hyper-parameter {name} takes {kind}, got {value!r}")
    return value


def resolve_hyperparams(algo: str, hyperparams: dict | None, timesteps: int) -> tuple[dict, dict]:
    """(arguments to pass to the constructor, the full effective set for config.json)."""
    defaults = default_hyperparams(algo)
    given = dict(hyperparams or {})
    for name in given:
        if name not in defaults:
            raise unknown(f"{algo.upper()} hyper-parameter", name, defaults)
        given[name] = check_hyperparam(algo, name, given[name], defaults[name])
    if algo == "sac" and "buffer_size" not in given:
        given["buffer_size"] = int(min(SAC_MAX_BUFFER, timesteps))
    return given, _jsonable({**defaults, **given})


# ---------------------------------------------------------------------------------------------- files
def _fsync(path: Path) -> None:
    with open(path, "rb+") as fh:
        os.fsync(fh.fileno())


def atomic_write(path, write) -> Path:
    """Call ``write(tmp_path)``, flush the file to disk, then rename it to ``path`` (atomic on POSIX)."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        write(tmp)
        _fsync(tmp)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return path


def write_json(path, data: dict) -> Path:
    def write(tmp):
        with open(tmp, "w") as fh:
            json.dump(data, fh, indent=2, sort_keys=False)
            fh.write("\n")
    return atomic_write(path, write)


def checkpoint_path(out_dir, step: int) -> Path:
    return Path(out_dir) / CHECKPOINT_DIR / f"step_{int(step):010d}.zip"


def side_file(model_path, suffix: str) -> Path:
    """``.../step_N.zip`` -> ``.../step_N<suffix>`` (VecNormalize statistics, replay buffer)."""
    model_path = Path(model_path)
    return model_path.with_name(model_path.name[: -len(".zip")] + suffix)


def list_checkpoints(out_dir) -> list[tuple[int, Path]]:
    """Complete checkpoints in ``out_dir`` as ``(num_timesteps, path)``, oldest first."""
    folder = Path(out_dir) / CHECKPOINT_DIR
    if not folder.is_dir():
        return []
    found = []
    for p in folder.iterdir():
        m = _CKPT_RE.match(p.name)
        if m and p.is_file():
            found.append((int(m.group(1)), p))
    return sorted(found)


def find_config(model_path) -> Path | None:
    """The ``config.json`` of the run a model belongs to (its folder, or the parent of ``checkpoints/``)."""
    model_path = Path(model_path)
    for folder in (model_path.parent, model_path.parent.parent):
        if (folder / CONFIG_NAME).is_file():
            return folder / CONFIG_NAME
    return None


def load_config(path) -> dict:
    """A run's ``config.json``; a missing, truncated or corrupt file is one error naming it."""
    from .artefacts import ArtefactError, read_json

    data = read_json(path, "run config")
    missing = [k for k in ("env_id", "algo") if not isinstance(data.get(k), str)]
    if missing:
        raise ArtefactError(f"{path}: run config lacks {', '.join(missing)} (not a config.json written by mjrft train?)")
    return data


def versions() -> dict:
    from importlib import metadata

    out = {"python": sys.version.split()[0]}
    for pkg in ("mjrft", "stable-baselines3", "torch", "gymnasium", "mujoco", "numpy", "numba"):
        try:
            out[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            out[pkg] = None
    return out


def save_checkpoint(model, out_dir, final: bool = False) -> Path:
    """Save ``model`` as ``checkpoints/step_<num_timesteps>.zip`` (with VecNormalize statistics and, for
    off-policy algorithms, the replay buffer; older checkpoints' buffers are deleted), and also as
    ``model.zip`` when ``final``. Every file is written atomically, the ``.zip`` last."""
    step = int(model.num_timesteps)
    ckpt = checkpoint_path(out_dir, step)
    ckpt.parent.mkdir(parents=True, exist_ok=True)
    from .artefacts import save_replay_buffer, save_vecnormalize

    vecnorm = model.get_vec_normalize_env()
    targets = [ckpt] + ([Path(out_dir) / MODEL_NAME] if final else [])
    for target in targets:
        if vecnorm is not None:
            atomic_write(side_file(target, VECNORM_SUFFIX), lambda tmp: save_vecnormalize(vecnorm, tmp))
        buffer = getattr(model, "replay_buffer", None) if target == ckpt else None
        if buffer is not None:
            atomic_write(side_file(target, BUFFER_SUFFIX), lambda tmp: save_replay_buffer(buffer, tmp))
        monitor = Path(out_dir) / MONITOR_NAME
        if target == ckpt and monitor.is_file():  # every episode finished so far is in it (a row is flushed at once)
            write_json(side_file(ckpt, MARK_SUFFIX), {"num_timesteps": step, "monitor_bytes": monitor.stat().st_size})
        atomic_write(target, model.save)
        for suffix in (PICKLE_VECNORM_SUFFIX, PICKLE_BUFFER_SUFFIX):  # superseded by the files just written
            side_file(target, suffix).unlink(missing_ok=True)
    if hasattr(model, "replay_buffer"):
        for _, old in list_checkpoints(out_dir):
            if old != ckpt:
                side_file(old, BUFFER_SUFFIX).unlink(missing_ok=True)
                side_file(old, PICKLE_BUFFER_SUFFIX).unlink(missing_ok=True)
    return ckpt


def _periodic_save_callback(out_dir, every: int, on_save):
    from stable_baselines3.common.callbacks import BaseCallback

    class PeriodicSave(BaseCallback):
        """Checkpoint each time ``num_timesteps`` crosses a multiple of ``every`` (aligned across resumes)."""

        def _on_training_start(self) -> None:
            self._next = (self.model.num_timesteps // every + 1) * every

        def _on_step(self) -> bool:
            if self.model.num_timesteps >= self._next:
                on_save(save_checkpoint(self.model, out_dir))
                self._next = (self.model.num_timesteps // every + 1) * every
            return True

    return PeriodicSave()


# ---------------------------------------------------------------------------------------------- training
@dataclass
class TrainResult:
    out_dir: Path
    model_path: Path
    config_path: Path
    num_timesteps: int
    interrupted: bool = False
    resumed_from: Path | None = None
    checkpoints: list = field(default_factory=list)
    saved: bool = True  # False: interrupted before training started, nothing was written


def _check_same(saved: dict, name: str, given, saved_value) -> None:
    if given is not None and _jsonable(given) != _jsonable(saved_value):
        raise ValueError(f"{name} {given!r} differs from the run being resumed ({saved_value!r} in "
                         f"{saved['_path']}); use a new --out folder or pass resume=False (--no-resume) to start over")


#: the settings of a new run left ``None``
NEW_RUN = {"timesteps": DEFAULTS["timesteps"], "n_envs": DEFAULTS["n_envs"], "seed": DEFAULTS["seed"],
           "checkpoint_every": DEFAULTS["checkpoint_every"], "vec_env": DEFAULTS["vec_env"], "device": "cpu",
           "torch_threads": 1}
#: settings that a resumed run may change when they are given (each change is said and recorded in the run's
#: entry of config.json); env id, algorithm, env kwargs, hyper-parameters, normalize and seed must match the run
CHANGEABLE = ("n_envs", "checkpoint_every", "vec_env", "device", "torch_threads")


def _saved_setting(saved: dict, name: str):
    """A setting of the saved run (its default when an older config.json lacks it; saved torch_threads null: 0)."""
    value = saved.get(name)
    if value is None:
        return 0 if name == "torch_threads" and name in saved else NEW_RUN[name]
    return value


def resumed_config(out_dir, env_id: str | None = None, algo: str | None = None, env_kwargs: dict | None = None,
                   normalize: bool | None = None, seed: int | None = None, hyperparams: dict | None = None,
                   n_envs: int | None = None) -> dict | None:
    """The ``config.json`` of the run in ``out_dir`` that :func:`train` with these settings resumes (its path as
    ``"_path"``), or None when the folder holds no checkpoint.

    A setting given (not None) that differs from the saved run's (env id, algorithm, env kwargs, normalize, seed, a
    hyper-parameter; ``n_envs`` of a SAC run, whose replay buffer is laid out per environment) raises a
    ``ValueError`` naming the difference, as does a folder with checkpoints but no ``config.json``.
    """
    out_dir = Path(out_dir)
    if not list_checkpoints(out_dir):
        return None
    config_path = out_dir / CONFIG_NAME
    if not config_path.is_file():
        raise ValueError(f"{out_dir} has checkpoints but no {CONFIG_NAME}; cannot resume (use another --out)")
    saved = load_config(config_path)
    saved["_path"] = str(config_path)
    _check_same(saved, "env id", env_id, saved["env_id"])
    _check_same(saved, "algorithm", None if algo is None else algo.lower(), saved["algo"])
    _check_same(saved, "env kwargs", env_kwargs or None, saved["env_kwargs"])
    _check_same(saved, "normalize", normalize, saved["normalize"])
    _check_same(saved, "seed", seed, saved.get("seed", DEFAULTS["seed"]))
    if hyperparams:
        for k, v in hyperparams.items():
            _check_same(saved, f"hyper-parameter {k}", v, saved["hyperparams"].get(k))
    before = _saved_setting(saved, "n_envs")
    if saved["algo"] == "sac" and n_envs is not None and _jsonable(n_envs) != _jsonable(before):
        raise ValueError(f"n_envs {n_envs} differs from the SAC run being resumed ({before} in {saved['_path']}): its "
                         f"replay buffer is laid out per environment; omit --n-envs")
    return saved


def train(env_id: str | None = None, algo: str | None = None, timesteps: int | None = None,
          n_envs: int | None = None, seed: int | None = None, out_dir="runs/mjrft", env_kwargs: dict | None = None,
          checkpoint_every: int | None = None, resume: bool = True, *, hyperparams: dict | None = None,
          normalize: bool | None = None, device: str | None = None, torch_threads: int | None = None,
          progress_bar: bool = False, verbose: int = 0, callback=None, config_name: str | None = None,
          vec_env: str | None = None, trust: bool = False, report=None) -> TrainResult:
    """Train ``algo`` on ``env_id`` until ``num_timesteps`` reaches ``timesteps``; resumable (see module doc).

    Every setting left ``None`` is, when the folder holds a run to resume, the one its ``config.json`` saved
    (those of :data:`CHANGEABLE` may be given to change them, the others must match), else the default given
    below.

    Args:
        env_id: registered gymnasium id of a MuJoCo env (``mjrft.envs.ENV_IDS``, gymnasium's MuJoCo robots).
        algo: ``"ppo"`` or ``"sac"`` (default ``"ppo"``).
        timesteps: total environment steps of the run folder (over all environments and resumes; default 1e5).
        n_envs: environments stepped together (see ``vec_env``; default 1).
        seed: seeds the algorithm (torch, numpy) and the environments (``seed + i`` for env ``i``; default 0).
        out_dir: run folder (created).
        env_kwargs: keyword arguments of the environment (``max_episode_steps`` sets the time limit).
        checkpoint_every: save a checkpoint each time the step count crosses a multiple of this (default 10,000).
        resume: continue from the newest checkpoint in ``out_dir`` if there is one (else start over,
            replacing the folder's config and checkpoints).
        hyperparams: constructor arguments of the SB3 algorithm (``n_steps``, ``learning_rate``, ...).
        normalize: wrap the environments in ``VecNormalize`` (observations and rewards); default False.
        device: torch device (``"cpu"``, the default, ``"cuda"``, ``"auto"``).
        torch_threads: torch CPU threads while training (restored afterwards); 0 leaves torch's setting.
            Default 1: the policies are small MLPs, and on a busy 2-core machine one thread ran SAC's updates
            3.7x faster than two (measured: 100 SAC steps 2.2 s vs 8.2 s).
        progress_bar: SB3's progress bar (tqdm + rich).
        verbose: SB3 verbosity (1 prints the training log).
        callback: extra SB3 callback(s) (a ``BaseCallback`` or a list).
        vec_env: how the ``n_envs`` environments are stepped: ``"subproc"``, ``"dummy"``, ``"batched"`` or
            ``"auto"`` (the default; :mod:`mjrft.train.vecenv`); any kind gives the same episodes for the same seed.
        config_name: the training configuration the settings came from (``mjrft train --config``),
            recorded as ``config`` in ``config.json``.
        trust: on resume, also load checkpoint files that can only be unpickled (SB3's ``.pkl`` side files, a
            zip with custom classes; :mod:`mjrft.train.artefacts`). Only for files from a trusted source.
        report: called with a line of text for what the run decides on its own (the checkpoint it resumes
            from, a setting changed on resume, an unreadable checkpoint skipped, a missing replay buffer);
            None: those become warnings.

    Returns:
        :class:`TrainResult`; ``interrupted`` is True when a ``KeyboardInterrupt`` stopped training (the
        model, a checkpoint and the config were saved first; an interrupt while the environments are still
        being built saves no model and records the run as interrupted).
    """
    out_dir = Path(out_dir)
    given = {"timesteps": timesteps, "n_envs": n_envs, "seed": seed, "checkpoint_every": checkpoint_every,
             "vec_env": vec_env, "device": device, "torch_threads": torch_threads}
    for name, minimum in (("timesteps", 1), ("n_envs", 1), ("seed", 0), ("checkpoint_every", 1), ("torch_threads", 0)):
        if given[name] is not None:
            given[name] = _check_int(name, given[name], minimum)
    if vec_env is not None:
        check_kind(vec_env)
    if device is not None and not isinstance(device, str):
        raise ValueError(f"device must be a torch device name such as 'cpu' or 'cuda', got {device!r}")
    if algo is not None:
        algo_class(algo)
    if env_id is not None:
        check_env_id(env_id)
    if env_kwargs is not None and not isinstance(env_kwargs, dict):
        raise ValueError(f"env_kwargs must be a dict, got {env_kwargs!r}")

    config_path = out_dir / CONFIG_NAME
    checkpoints = list_checkpoints(out_dir) if resume else []
    saved = None
    changes = {}  # setting -> (saved value, value of this run): what a resume changes on purpose
    if checkpoints:
        saved = resumed_config(out_dir, env_id, algo, env_kwargs, normalize, given["seed"], hyperparams,
                               given["n_envs"])
        env_id, algo, env_kwargs = saved["env_id"], saved["algo"], saved["env_kwargs"]
        normalize = saved["normalize"]
        ctor_kwargs = dict(saved.get("hyperparams_given", {}))
        effective = saved["hyperparams"]
        settings = {k: _saved_setting(saved, k) if v is None else v for k, v in given.items()}
    else:
        if env_id is None and resume and config_path.is_file():
            raise ValueError(f"{out_dir} holds no checkpoint to resume from; start its run again with its settings: "
                             f"mjrft train --config {config_path} --out {out_dir}")
        if env_id is None:
            raise ValueError(f"env id is required to start a new run in {out_dir} (valid choices: "
                             f"{', '.join(_mjrft_env_ids())})")
        if resume and config_path.is_file():
            _notify(report, f"{out_dir} holds no checkpoint to resume from: a new run starts there and replaces its "
                            f"{CONFIG_NAME}", UserWarning)
        settings = {k: NEW_RUN[k] if v is None else v for k, v in given.items()}
        algo = (algo or "ppo").lower()
        env_kwargs = dict(env_kwargs or {})
        normalize = bool(normalize)
        ctor_kwargs, effective = resolve_hyperparams(algo, hyperparams, settings["timesteps"])
    settings["vec_env"] = resolve_kind(settings["vec_env"], env_id, settings["n_envs"])
    if saved:
        for name in CHANGEABLE:
            if _jsonable(settings[name]) != _jsonable(_saved_setting(saved, name)):
                changes[name] = (_saved_setting(saved, name), settings[name])
    timesteps, n_envs, seed, kind = (settings[k] for k in ("timesteps", "n_envs", "seed", "vec_env"))
    checkpoint_every, device, torch_threads = (settings[k] for k in ("checkpoint_every", "device", "torch_threads"))
    cls = algo_class(algo)

    # validate the env kwargs and the env in this process (clear error before any worker starts)
    probe = make_env(env_id, env_kwargs)
    try:
        check_mujoco_env(probe, env_id)
    except ValueError:
        probe.close()
        raise
    if n_envs > 1:  # compile (or load) the numba kernels once here, not in every worker at the same time
        import numpy as np

        probe.reset(seed=seed)
        probe.step(np.zeros(probe.action_space.shape, dtype=probe.action_space.dtype))
    spaces = (probe.observation_space, probe.action_space)
    probe.close()

    model = vecnorm_stats = resumed_from = None
    start_step = 0
    if checkpoints:  # the newest checkpoint that loads, before anything in the folder changes
        model, vecnorm_stats, resumed_from = _load_newest(algo, checkpoints, spaces, device, n_envs, normalize,
                                                          effective, trust, report)
        start_step = int(model.num_timesteps)
        if report is not None:
            report(f"resuming {out_dir} from {resumed_from.relative_to(out_dir)} at {start_step} steps (target {timesteps})")
    history = list(saved.get("runs", [])) if saved else []
    config = {
        "env_id": env_id,
        "env_kwargs": _jsonable(env_kwargs),
        "algo": algo,
        "policy": POLICY,
        "hyperparams": effective,
        "hyperparams_given": _jsonable(ctor_kwargs),
        "normalize": normalize,
        "seed": seed,
        "n_envs": n_envs,
        "timesteps": timesteps,
        "checkpoint_every": checkpoint_every,
        "device": device,
        "torch_threads": torch_threads,
        "vec_env": kind,
        "start_method": start_method() if kind == "subproc" else None,
        "versions": versions(),
        "created": saved["created"] if saved else _now(),
        "num_timesteps": start_step,
        "model": saved.get("model") if saved else None,
        "runs": history,
        "config": config_name if config_name is not None else (saved or {}).get("config"),
    }
    if saved and saved.get("checkpoint"):
        config["checkpoint"] = saved["checkpoint"]
    if start_step >= timesteps:  # nothing to do: the run already reached its budget
        model_path = out_dir / MODEL_NAME
        return TrainResult(out_dir, model_path if model_path.exists() else resumed_from, config_path,
                           start_step, resumed_from=resumed_from,
                           checkpoints=[p for _, p in list_checkpoints(out_dir)])

    out_dir.mkdir(parents=True, exist_ok=True)
    if not checkpoints:  # a fresh run replaces what a previous one left (resume=False or no checkpoint)
        for _, old in list_checkpoints(out_dir):
            for p in (old, *_side_files(old)):
                p.unlink(missing_ok=True)
        for p in (out_dir / MODEL_NAME, *_side_files(out_dir / MODEL_NAME), out_dir / MONITOR_NAME,
                  out_dir / WARNINGS_NAME):
            p.unlink(missing_ok=True)
        for log in (out_dir / LOGS_DIR).glob("from_*/progress.csv"):
            log.unlink()
            _rmdir_if_empty(log.parent)
    _remove_stray_tmp(out_dir)
    dropped = _drop_lost_records(out_dir, resumed_from, start_step) if resumed_from is not None else {}
    for old in history:  # a run that never recorded its end was killed (SIGKILL, power loss)
        if old.get("status") == "running":
            old.update(status="crashed", note="the process ended without recording its end (killed, or the "
                                              "machine stopped); steps after its last checkpoint were lost")
    run = {"started": _now(), "from_step": start_step, "target": timesteps, "n_envs": n_envs, "seed": seed,
           "status": "running", "pid": os.getpid()}
    if changes:  # settings this resume changes on purpose (given, and not the saved ones): recorded and said
        run["changed"] = {k: {"from": _jsonable(old), "to": _jsonable(new)} for k, (old, new) in changes.items()}
        said = ", ".join(f"{k} {old!r} -> {new!r}" for k, (old, new) in changes.items())
        _notify(report, f"resuming with changed settings: {said} (recorded in {config_path}, runs[-1].changed)",
                UserWarning)
    if dropped:  # what a killed (or crashed) run recorded after the checkpoint this run resumes from
        run["dropped"] = dropped
        what = ", ".join(f"{n} {name}" for name, n in dropped.items())
        _notify(report, f"dropped what the previous run recorded after step {start_step} (its steps after that "
                        f"checkpoint were lost): {what}", UserWarning)
    if saved and saved.get("versions") and saved["versions"] != config["versions"]:
        run["versions_before"] = saved["versions"]  # the packages changed: the bits of the run may too
    config["runs"].append(run)
    write_json(config_path, config)

    def finish(status: str, step: int, **extra) -> None:
        run.update(status=status, ended=_now(), to_step=int(step), **extra)
        config["num_timesteps"] = max(int(step), config["num_timesteps"])
        write_json(config_path, config)

    import torch

    env_seed = seed + start_step
    threads_before = torch.get_num_threads()
    venv = None
    saved_paths = []  # the checkpoints this run wrote

    def last_saved() -> int:
        return max([start_step, *(int(_CKPT_RE.match(p.name).group(1)) for p in saved_paths)])

    try:
        venv = make_vec_env(env_id, n_envs, env_seed, env_kwargs, out_dir / "monitor.csv", kind=kind)
        if torch_threads:
            torch.set_num_threads(torch_threads)
        if model is not None:
            if vecnorm_stats is not None:
                venv = vecnorm_stats.wrap(venv, training=True)
            model.set_env(venv)
            model.set_random_seed(env_seed)
        else:
            if normalize:
                from stable_baselines3.common.vec_env import VecNormalize

                venv = VecNormalize(venv, gamma=float(effective.get("gamma", 0.99)))
            model = cls(POLICY, venv, seed=seed, device=device, verbose=verbose, **ctor_kwargs)
        from stable_baselines3.common.logger import configure

        log_dir = out_dir / "logs" / f"from_{start_step:010d}"
        model.set_logger(configure(str(log_dir), ["csv"] + (["stdout"] if verbose else [])))

        from .run_warnings import warning_tally

        callbacks = [_periodic_save_callback(out_dir, checkpoint_every, saved_paths.append), warning_tally(out_dir)]
        if callback is not None:
            callbacks += list(callback) if isinstance(callback, (list, tuple)) else [callback]
        interrupted = False
        old_term = _catch_sigterm()
        try:
            model.learn(total_timesteps=timesteps - start_step, callback=callbacks, reset_num_timesteps=False,
                        progress_bar=progress_bar)
        except KeyboardInterrupt:
            interrupted = True
        finally:
            if old_term is not None:
                signal.signal(signal.SIGTERM, old_term)
        ckpt = save_checkpoint(model, out_dir, final=True)
        config.update(model=MODEL_NAME, checkpoint=ckpt.name)
        finish("interrupted" if interrupted else "finished", model.num_timesteps)
        return TrainResult(out_dir, out_dir / MODEL_NAME, config_path, int(model.num_timesteps), interrupted,
                           resumed_from, [p for _, p in list_checkpoints(out_dir)])
    except KeyboardInterrupt:  # before training started (while the environments were built) or while saving
        finish("interrupted", last_saved())
        model_path = out_dir / MODEL_NAME
        return TrainResult(out_dir, model_path if model_path.exists() else resumed_from, config_path, start_step,
                           True, resumed_from, [p for _, p in list_checkpoints(out_dir)], saved=False)
    except BaseException as exc:
        finish("crashed", last_saved(), error=_reason(exc))
        raise
    finally:
        torch.set_num_threads(threads_before)
        if model is not None and getattr(model, "_logger", None) is not None:
            model.logger.close()  # the progress.csv of this run
        if venv is not None:
            try:
                venv.close()
            except (EOFError, BrokenPipeError, ConnectionResetError):  # a worker already gone
                pass


def train_settings(cfg: dict, out_dir, **options) -> TrainResult:
    """:func:`train` with the settings ``cfg`` of a training configuration with the command line's overrides
    (:func:`mjrft.train.train_command.run_settings`); ``options``: its other keywords (resume, device, report, ...)."""
    return train(cfg["env_id"], cfg["algo"], cfg["timesteps"], cfg["n_envs"], cfg["seed"], out_dir,
                 cfg["env_kwargs"] or None, cfg["checkpoint_every"], hyperparams=cfg["hyperparams"] or None,
                 normalize=cfg["normalize"], vec_env=cfg["vec_env"], **options)


def _sigterm(signum, frame):
    raise KeyboardInterrupt(f"signal {signum}")


def _catch_sigterm():
    """Treat SIGTERM (a scheduler's stop) like Ctrl-C while training; returns the previous handler."""
    import threading

    if threading.current_thread() is not threading.main_thread():
        return None
    return signal.signal(signal.SIGTERM, _sigterm)


def _rmdir_if_empty(folder: Path) -> None:
    try:
        folder.rmdir()
    except OSError:
        pass


def _keep_rows(path: Path, column: str, last_step: int) -> int:
    """Rewrite the CSV ``path`` (atomically) without the rows whose ``column`` is a step after ``last_step``;
    returns how many were dropped (0 and the file untouched when it lacks the column or has none)."""
    import csv
    import io

    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError):
        return 0
    lines = text.splitlines(keepends=True)
    if not lines:
        return 0
    header = next(csv.reader([lines[0]]))
    if column not in header:
        return 0
    k = header.index(column)
    keep, dropped = [lines[0]], 0
    for line, cells in zip(lines[1:], csv.reader(lines[1:])):
        try:
            late = float(cells[k]) > last_step
        except (IndexError, ValueError):
            late = False  # not a row of steps: left for the readers to report
        dropped += late
        if not late:
            keep.append(line)
    if dropped:
        atomic_write(path, lambda tmp: Path(tmp).write_text("".join(keep)))
    return dropped


def _drop_lost_records(out_dir: Path, checkpoint: Path, step: int) -> dict:
    """Remove from the run folder's records what a previous run wrote after the checkpoint this run resumes
    from: those steps were lost with that run (killed, or crashed), and the resumed run trains them again.

    * ``monitor.csv``: cut back to its length when the checkpoint was saved (``step_<N>_monitor.json``);
    * ``logs/from_<M>/progress.csv``: the rows after ``step`` (a log of a run that started at or after it:
      all of it);
    * ``warnings.csv``: the rows after ``step``.

    Returns ``{what: count}`` of what was dropped (empty when nothing was lost).
    """
    from .artefacts import ArtefactError, read_json

    dropped = {}
    monitor, mark = out_dir / MONITOR_NAME, side_file(checkpoint, MARK_SUFFIX)
    if monitor.is_file() and mark.is_file():
        try:
            size = int(read_json(mark, "monitor mark")["monitor_bytes"])
        except (ArtefactError, KeyError, TypeError, ValueError):
            size = None
        if size is not None and 0 < size < monitor.stat().st_size:
            with open(monitor, "rb+") as fh:
                fh.seek(size)
                episodes = sum(1 for line in fh.read().split(b"\n") if line.strip())
                fh.truncate(size)
                fh.flush()
                os.fsync(fh.fileno())
            dropped["episodes of monitor.csv"] = episodes
    rows = 0
    for log in sorted((out_dir / LOGS_DIR).glob("from_*/progress.csv")):
        m = re.match(r"from_(\d+)$", log.parent.name)
        if m and int(m.group(1)) >= step:
            rows += max(0, len(log.read_bytes().splitlines()) - 1)
            log.unlink()
            _rmdir_if_empty(log.parent)
        elif m:
            rows += _keep_rows(log, "time/total_timesteps", step)
    if rows:
        dropped["rows of logs/*/progress.csv"] = rows
    warned = _keep_rows(out_dir / WARNINGS_NAME, "step", step) if (out_dir / WARNINGS_NAME).is_file() else 0
    if warned:
        dropped["rows of warnings.csv"] = warned
    return dropped


def _remove_stray_tmp(out_dir: Path) -> None:
    """Delete the temporary files of :func:`atomic_write` that a killed process left behind."""
    for folder in (out_dir, out_dir / CHECKPOINT_DIR):
        if folder.is_dir():
            for p in folder.glob(".*.tmp"):
                p.unlink(missing_ok=True)


def _side_files(model_path) -> list[Path]:
    """The VecNormalize statistics, replay buffer (mjrft's and SB3's pickled ones) and monitor mark of a model zip."""
    return [side_file(model_path, s) for s in (VECNORM_SUFFIX, BUFFER_SUFFIX, PICKLE_VECNORM_SUFFIX,
                                               PICKLE_BUFFER_SUFFIX, MARK_SUFFIX)]


def vecnormalize_file(model_path) -> Path | None:
    """The VecNormalize statistics saved with a model zip: ``*_vecnormalize.npz``, else an SB3 ``.pkl``, else None."""
    for suffix in (VECNORM_SUFFIX, PICKLE_VECNORM_SUFFIX):
        if side_file(model_path, suffix).is_file():
            return side_file(model_path, suffix)
    return None


def _load_newest(algo, checkpoints, spaces, device, n_envs, normalize, hyperparams, trust, say):
    """(model, VecNormalize statistics, path) of the newest checkpoint that loads; an unreadable one is
    reported and the previous one tried."""
    from .artefacts import ArtefactError, SkippedArtefactWarning

    errors = []
    for _, path in reversed(checkpoints):
        try:
            return (*_load_checkpoint(algo, path, spaces, device, n_envs, normalize, hyperparams, trust, say), path)
        except ArtefactError as exc:
            errors.append(str(exc))
            _notify(say, f"{exc}; trying the previous checkpoint", SkippedArtefactWarning)
    raise ValueError(f"none of the {len(checkpoints)} checkpoint(s) in {checkpoints[0][1].parent} loads (newest: "
                     f"{errors[0]}); start over with --no-resume (resume=False) or use another --out")


def _load_checkpoint(algo, path: Path, spaces, device: str, n_envs: int, normalize: bool, hyperparams, trust, say):
    from .artefacts import ArtefactError, load_model, load_replay_buffer, load_vecnormalize

    stats = None
    if normalize:
        vn_path = vecnormalize_file(path)
        if vn_path is None:
            raise ArtefactError(f"{side_file(path, VECNORM_SUFFIX)}: VecNormalize statistics of the checkpoint "
                                f"are missing")
        stats = load_vecnormalize(vn_path, trust)
    model = load_model(algo, path, spaces=spaces, device=device, hyperparams=hyperparams, n_envs=n_envs, trust=trust)
    if hasattr(model, "replay_buffer"):
        buf = next((p for p in (side_file(path, BUFFER_SUFFIX), side_file(path, PICKLE_BUFFER_SUFFIX)) if p.is_file()),
                   None)
        problem = f"{side_file(path, BUFFER_SUFFIX).name} is missing"
        if buf is not None:
            try:
                load_replay_buffer(model, buf, trust)
                problem = None
            except ArtefactError as exc:
                problem = str(exc)
        if problem:
            msg = (f"{problem}: SAC resumes with an empty replay buffer and refills it with "
                   f"{model.learning_starts} random steps first")
            _notify(say, msg, RuntimeWarning)
            model.learning_starts = model.num_timesteps + model.learning_starts
    return model, stats


def _notify(report, msg: str, category) -> None:
    """``report(msg)`` when the caller gave a reporter (the CLI prints), else a warning."""
    if report is not None:
        report(msg)
    else:
        warnings.warn(msg, category, stacklevel=4)


def _reason(exc: BaseException) -> str:
    from .artefacts import _reason as reason

    return reason(exc)


def _now() -> str:
    return datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")


def _mjrft_env_ids() -> list[str]:
    from mjrft.envs import ENV_IDS, GYM_SAND_IDS

    return sorted([*ENV_IDS, *GYM_SAND_IDS])

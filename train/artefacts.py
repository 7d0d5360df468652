"""The files of a run folder, written so they are never half-written and loaded without running code from them.

Loading a Python pickle can run any code its author put in it, so mjrft's own files hold data only:

==================================  ====================================================================
``model.zip``, ``step_<N>.zip``     stable-baselines3's zip: a JSON ``data`` member and torch state dicts
                                    (``policy.pth``, optimiser states), which are read with torch's
                                    weights-only loader. SB3 also cloudpickles a few entries of ``data``
                                    (the policy and buffer classes, the observation and action spaces,
                                    the schedules, the last observation); :func:`load_model` never
                                    unpickles them: it rebuilds each one from its JSON description (an
                                    SB3 class by module and name, a ``Box`` from its bounds or the env's
                                    spaces, a constant or linear schedule from its text, ``train_freq``
                                    from the run's hyper-parameters) and drops the runtime state that the
                                    next ``learn()`` resets (last observation, episode-info buffers).
``*_vecnormalize.npz``              VecNormalize statistics (:func:`save_vecnormalize`), numpy arrays
                                    read with ``allow_pickle=False``
``*_replay_buffer.npz``             SAC's replay buffer (:func:`save_replay_buffer`), the same way
``config.json``                     JSON (:func:`read_json`)
==================================  ====================================================================

A file that can only be loaded by unpickling it (an SB3 zip with a custom class or a callable
schedule of its own, a ``*_vecnormalize.pkl`` or ``*_replay_buffer.pkl`` written by SB3's ``save``)
raises :class:`NeedsTrustError` unless the caller passes ``trust=True`` (``--trust`` on the command
line): load such a file only when you trust whoever made it.

Every file that is missing, truncated or corrupt raises :class:`ArtefactError`, one line that names the
file and what is wrong with it; :func:`check_model` runs the cheap checks (the zip's central directory,
every member's CRC, the JSON ``data``, the torch archives inside) without building a model.
"""

from __future__ import annotations

import io
import json
import re
import zipfile
import zlib
from pathlib import Path

from .common import algo_class, default_hyperparams

import numpy as np

VECNORM_FORMAT = "mjrft.vecnormalize/1"
BUFFER_FORMAT = "mjrft.replay_buffer/1"
#: ``data`` entries of an SB3 zip that hold runtime state which the next ``learn()`` rebuilds
RUNTIME_STATE = ("_last_obs", "_last_episode_starts", "_last_original_obs", "ep_info_buffer", "ep_success_buffer")
#: ``--trust`` help of the commands that load a policy
TRUST_HELP = ("also load model files that can only be unpickled (SB3's VecNormalize .pkl, a zip with custom "
              "classes): they can run code, so only for files from a trusted source")
TRUST_HINT = ("unpickling can run arbitrary code, so load it only if you trust where it came from: "
              "pass --trust (trust=True in Python)")


class ArtefactError(ValueError):
    """A run file that is missing, truncated or corrupt; the message names the file and what is wrong."""


class NeedsTrustError(ValueError):
    """A file that can only be loaded by unpickling it; pass ``trust=True`` (``--trust``) to load it anyway."""


class SkippedArtefactWarning(RuntimeWarning):
    """A newer file was unreadable and an older one is used instead (named in the message)."""


def _reason(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    text = text[0] if text else ""
    text = text[:200] + ("..." if len(text) > 200 else "")
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


# ---------------------------------------------------------------------------------------------- JSON
def read_json(path, what: str = "JSON file") -> dict:
    """The JSON object in ``path``; :class:`ArtefactError` naming the file when it is unreadable or no object."""
    path = Path(path)
    try:
        data = json.loads(path.read_text())
    except FileNotFoundError:
        raise ArtefactError(f"{path}: {what} is missing") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ArtefactError(f"{path}: {what} cannot be read ({_reason(exc)})") from None
    except json.JSONDecodeError as exc:
        raise ArtefactError(f"{path}: {what} is not valid JSON (truncated or corrupt? {exc})") from None
    if not isinstance(data, dict):
        raise ArtefactError(f"{path}: {what} must hold a JSON object, got {type(data).__name__}")
    return data


# ---------------------------------------------------------------------------------------------- model zips
def zip_data(path) -> dict:
    """The JSON ``data`` of an SB3 model zip after checking the archive: every member's CRC, the members a
    model needs (``data``, ``policy.pth``) and the torch archives inside. :class:`ArtefactError` otherwise."""
    path = Path(path)
    if not path.is_file():
        raise ArtefactError(f"{path}: model file is missing")
    try:
        with zipfile.ZipFile(path) as zf:
            names = zf.namelist()
            bad = zf.testzip()
            if bad is not None:
                raise ArtefactError(f"{path}: member {bad!r} is corrupt (CRC mismatch)")
            missing = [n for n in ("data", "policy.pth") if n not in names]
            if missing:
                raise ArtefactError(f"{path}: not a complete stable-baselines3 model zip (no {' or '.join(missing)} "
                                    f"member: truncated, or another kind of zip)")
            for name in names:
                if name.endswith(".pth"):  # torch's own zip format: a cut file has no central directory
                    try:
                        with zipfile.ZipFile(io.BytesIO(zf.read(name))) as inner:
                            if inner.testzip() is not None:
                                raise zipfile.BadZipFile("CRC mismatch")
                    except zipfile.BadZipFile as exc:
                        raise ArtefactError(f"{path}: member {name!r} is truncated or corrupt ({exc})") from None
            raw = zf.read("data")
    except ArtefactError:
        raise
    except (zipfile.BadZipFile, zlib.error, EOFError, OSError) as exc:
        raise ArtefactError(f"{path}: not a readable zip file, truncated or corrupt ({_reason(exc)})") from None
    try:
        data = json.loads(raw)
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise ArtefactError(f"{path}: its 'data' member is not valid JSON ({exc})") from None
    if not isinstance(data, dict) or not isinstance(data.get("num_timesteps", 0), int):
        raise ArtefactError(f"{path}: its 'data' member is not a stable-baselines3 parameter record")
    return data


def check_model(path) -> int:
    """Cheap integrity check of a model zip (:func:`zip_data`); returns its ``num_timesteps``."""
    return int(zip_data(path).get("num_timesteps", 0))


def _serialized(value) -> bool:
    return isinstance(value, dict) and ":serialized:" in value


def _type_name(desc: dict) -> str:
    m = re.match(r"<class '([\w.]+)'>", str(desc.get(":type:", "")))
    return m.group(1) if m else ""


class _Unsafe(Exception):
    """This entry cannot be rebuilt from its JSON description."""


def _box(desc: dict, name: str):
    """A gymnasium ``Box`` from the JSON description SB3 writes next to the pickled space."""
    from gymnasium import spaces

    try:
        shape = tuple(int(n) for n in desc["_shape"])
        dtype = np.dtype(desc["dtype"])
        bounds = []
        for key in ("low", "high"):
            words = str(desc[key]).replace("[", " ").replace("]", " ").split()
            if "..." in words:
                raise _Unsafe(name)  # numpy abbreviated a long array
            values = np.array([float(w) for w in words], dtype=np.float64)
            bounds.append(values.reshape(shape))
    except (KeyError, TypeError, ValueError):
        raise _Unsafe(name) from None
    return spaces.Box(bounds[0].astype(dtype), bounds[1].astype(dtype), shape=shape, dtype=dtype)


def _schedule(desc: dict, name: str):
    """A constant (a float) or linear schedule from the text SB3 writes next to the pickled one."""
    from stable_baselines3.common.utils import FloatSchedule, LinearSchedule

    text = " ".join(str(v) for k, v in desc.items() if k != ":serialized:" and isinstance(v, str))
    num = r"([-+0-9.eE]+|inf|-inf)"
    m = re.search(rf"LinearSchedule\(start={num}, end={num}, end_fraction={num}\)", text)
    if m:
        return FloatSchedule(LinearSchedule(*(float(g) for g in m.groups())))
    m = re.search(rf"ConstantSchedule\(val={num}\)", text)
    if m:
        return float(m.group(1))
    raise _Unsafe(name)


def _sb3_class(desc: dict, name: str, base: type):
    """The stable-baselines3 class a pickled class entry names (its module and the methods it defines)."""
    import importlib

    module = str(desc.get("__module__", ""))
    owners = {m.group(1) for v in desc.values() if isinstance(v, str) for m in re.finditer(r"<function (\w+)\.", v)}
    if not module.startswith("stable_baselines3.") or len(owners) != 1:
        raise _Unsafe(name)
    try:
        cls = getattr(importlib.import_module(module), owners.pop())
    except (ImportError, AttributeError):
        raise _Unsafe(name) from None
    if not (isinstance(cls, type) and issubclass(cls, base)):
        raise _Unsafe(name)
    return cls


def safe_objects(path, data: dict, algo: str, spaces=None, hyperparams: dict | None = None) -> dict:
    """Replacements for every cloudpickled entry of an SB3 zip's ``data`` (see the module doc), so that SB3's
    loader unpickles nothing. ``spaces``: (observation space, action space) of the env the model will run
    on (else the ``Box`` bounds are read from the zip). :class:`NeedsTrustError` names any entry that can
    only be unpickled."""
    from stable_baselines3.common.buffers import BaseBuffer
    from stable_baselines3.common.policies import BasePolicy


    hp = {**default_hyperparams(algo), **(hyperparams or {})}
    out, unsafe = {}, []
    for key, desc in data.items():
        if not _serialized(desc):
            continue
        kind = _type_name(desc)
        try:
            if key in RUNTIME_STATE and kind in ("numpy.ndarray", "collections.deque"):
                out[key] = None
            elif key in ("observation_space", "action_space"):
                if not kind.endswith("spaces.box.Box"):
                    raise _Unsafe(key)
                space = _box(desc, key)
                if spaces is not None:
                    given = spaces[0] if key == "observation_space" else spaces[1]
                    if tuple(given.shape) != space.shape:
                        what = "observations" if key == "observation_space" else "actions"
                        raise ValueError(f"policy {path} expects {what} of shape {space.shape}, but the env "
                                         f"gives {tuple(given.shape)}")
                    space = given
                out[key] = space
            elif kind.rsplit(".", 1)[-1] in ("FloatSchedule", "ConstantSchedule", "LinearSchedule"):
                out[key] = _schedule(desc, key)
            elif key == "policy_class":
                out[key] = _sb3_class(desc, key, BasePolicy)
            elif key in ("rollout_buffer_class", "replay_buffer_class"):
                out[key] = _sb3_class(desc, key, BaseBuffer)
            elif key == "train_freq" and kind.endswith("TrainFreq"):
                freq = hp.get("train_freq", 1)
                out[key] = tuple(freq) if isinstance(freq, list) else freq
            else:
                raise _Unsafe(key)
        except _Unsafe:
            unsafe.append(key)
    if unsafe:
        raise NeedsTrustError(f"{path} stores {', '.join(unsafe)} only as pickled Python objects; {TRUST_HINT}")
    return out


def load_model(algo: str, path, *, env=None, spaces=None, device: str = "cpu", hyperparams: dict | None = None,
               n_envs: int | None = None, trust: bool = False):
    """Load an SB3 model zip without unpickling anything (module doc); ``trust=True``: SB3's own loader.

    ``env``: the (vec) env to attach (its spaces are used); ``spaces``: (observation, action) space to use
    without attaching an env; ``hyperparams``: the run's hyper-parameters (``train_freq`` of SAC);
    ``n_envs``: the number of environments the model will be attached to later with ``set_env``.
    """

    cls = algo_class(algo)
    data = zip_data(path)
    custom = {}
    if not trust:
        if spaces is None and env is not None:
            spaces = (env.observation_space, env.action_space)
        custom = safe_objects(path, data, algo, spaces, hyperparams)
    if n_envs is not None:
        custom["n_envs"] = int(n_envs)
    try:
        return cls.load(str(path), env=env, device=device, custom_objects=custom)
    except NeedsTrustError:
        raise
    except Exception as exc:  # torch / SB3 / cloudpickle errors on a damaged or foreign file
        raise ArtefactError(f"{path}: cannot be loaded as a {algo.upper()} model ({_reason(exc)})") from None


# ---------------------------------------------------------------------------------------------- VecNormalize
class VecNormalizeStats:
    """VecNormalize statistics read from a file: frozen observation normalisation (the same arithmetic as
    SB3's ``VecNormalize.normalize_obs``) and :meth:`wrap` to continue training with them."""

    training = False

    def __init__(self, obs_rms, ret_rms, *, norm_obs: bool, norm_reward: bool, clip_obs: float, clip_reward: float,
                 gamma: float, epsilon: float, norm_obs_keys=None):
        self.obs_rms, self.ret_rms = obs_rms, ret_rms
        self.norm_obs, self.norm_reward = bool(norm_obs), bool(norm_reward)
        self.clip_obs, self.clip_reward = float(clip_obs), float(clip_reward)
        self.gamma, self.epsilon = float(gamma), float(epsilon)
        self.norm_obs_keys = norm_obs_keys

    @classmethod
    def of(cls, vecnorm) -> VecNormalizeStats:
        """The statistics of an SB3 ``VecNormalize``."""
        return cls(vecnorm.obs_rms, vecnorm.ret_rms, norm_obs=vecnorm.norm_obs, norm_reward=vecnorm.norm_reward,
                   clip_obs=vecnorm.clip_obs, clip_reward=vecnorm.clip_reward, gamma=vecnorm.gamma,
                   epsilon=vecnorm.epsilon, norm_obs_keys=getattr(vecnorm, "norm_obs_keys", None))

    def _normalize(self, obs, rms):
        return np.clip((obs - rms.mean) / np.sqrt(rms.var + self.epsilon), -self.clip_obs, self.clip_obs)

    def normalize_obs(self, obs):
        if not self.norm_obs:
            return obs
        if isinstance(obs, dict) and isinstance(self.obs_rms, dict):
            out = dict(obs)
            for key in self.norm_obs_keys or self.obs_rms:
                out[key] = self._normalize(obs[key], self.obs_rms[key]).astype(np.float32)
            return out
        return self._normalize(obs, self.obs_rms).astype(np.float32)

    def wrap(self, venv, training: bool = True):
        """An SB3 ``VecNormalize`` around ``venv`` holding these statistics."""
        from stable_baselines3.common.vec_env import VecNormalize

        vn = VecNormalize(venv, training=training, norm_obs=self.norm_obs, norm_reward=self.norm_reward,
                          clip_obs=self.clip_obs, clip_reward=self.clip_reward, gamma=self.gamma,
                          epsilon=self.epsilon, norm_obs_keys=self.norm_obs_keys)
        vn.obs_rms, vn.ret_rms = self.obs_rms, self.ret_rms
        return vn


def _rms_arrays(prefix: str, rms) -> dict:
    return {f"{prefix}_mean": np.asarray(rms.mean, dtype=np.float64), f"{prefix}_var": np.asarray(rms.var, dtype=np.float64),
            f"{prefix}_count": np.asarray(rms.count, dtype=np.float64)}


def save_vecnormalize(vecnorm, file) -> None:
    """Write the statistics of an SB3 ``VecNormalize`` (or :class:`VecNormalizeStats`) to ``file`` as npz."""
    arrays = {"format": np.array(VECNORM_FORMAT), "norm_obs": np.array(bool(vecnorm.norm_obs)),
              "norm_reward": np.array(bool(vecnorm.norm_reward)), "clip_obs": np.array(float(vecnorm.clip_obs)),
              "clip_reward": np.array(float(vecnorm.clip_reward)), "gamma": np.array(float(vecnorm.gamma)),
              "epsilon": np.array(float(vecnorm.epsilon)), **_rms_arrays("ret", vecnorm.ret_rms)}
    if isinstance(vecnorm.obs_rms, dict):
        keys = list(vecnorm.obs_rms)
        arrays["obs_keys"] = np.array(keys, dtype=str)
        arrays["norm_obs_keys"] = np.array(list(vecnorm.norm_obs_keys or keys), dtype=str)
        for i, key in enumerate(keys):
            arrays.update(_rms_arrays(f"obs{i}", vecnorm.obs_rms[key]))
    else:
        arrays.update(_rms_arrays("obs", vecnorm.obs_rms))
    _savez(file, arrays)


def _savez(file, arrays: dict) -> None:
    if isinstance(file, (str, Path)):  # np.savez would append ".npz" to a temporary name
        with open(file, "wb") as fh:
            np.savez(fh, **arrays)
    else:
        np.savez(file, **arrays)


def _load_npz(path, what: str, fmt: str) -> dict:
    path = Path(path)
    if not path.is_file():
        raise ArtefactError(f"{path}: {what} file is missing")
    if not zipfile.is_zipfile(path):  # np.load would take any other bytes for a pickle
        raise ArtefactError(f"{path}: {what} file is not an npz archive (truncated or corrupt)")
    try:
        with np.load(path, allow_pickle=False) as npz:
            arrays = {k: npz[k] for k in npz.files}
    except ValueError as exc:
        if "allow_pickle" in str(exc):
            raise ArtefactError(f"{path}: {what} file holds Python objects, which mjrft never writes") from None
        raise ArtefactError(f"{path}: {what} file is truncated or corrupt ({_reason(exc)})") from None
    except (OSError, EOFError, zipfile.BadZipFile, zlib.error, KeyError) as exc:
        raise ArtefactError(f"{path}: {what} file is truncated or corrupt ({_reason(exc)})") from None
    if str(arrays.get("format", "")) != fmt:
        raise ArtefactError(f"{path}: not an mjrft {what} file (format {str(arrays.get('format', 'missing'))!r}, "
                            f"expected {fmt!r})")
    return arrays


def _rms(arrays: dict, prefix: str, path):
    from stable_baselines3.common.running_mean_std import RunningMeanStd

    try:
        mean, var, count = (arrays[f"{prefix}_{k}"] for k in ("mean", "var", "count"))
    except KeyError as exc:
        raise ArtefactError(f"{path}: VecNormalize statistics lack {exc.args[0]!r}") from None
    if mean.shape != var.shape or count.shape != () or not (np.all(np.isfinite(mean)) and np.all(var >= 0)):
        raise ArtefactError(f"{path}: VecNormalize statistics {prefix!r} are inconsistent (shapes {mean.shape}, "
                            f"{var.shape}, or non-finite values)")
    rms = RunningMeanStd(shape=mean.shape)
    rms.mean, rms.var, rms.count = mean, var, float(count)
    return rms


def load_vecnormalize(path, trust: bool = False) -> VecNormalizeStats:
    """VecNormalize statistics from ``*_vecnormalize.npz``, or (``trust=True`` only) an SB3 ``.pkl``."""
    path = Path(path)
    if path.suffix == ".pkl":
        saved = _unpickle(path, "VecNormalize statistics", trust)
        rms = [getattr(saved, "ret_rms", None)]
        obs = getattr(saved, "obs_rms", None)
        rms += list(obs.values()) if isinstance(obs, dict) else [obs]
        if not all(hasattr(r, a) for r in rms for a in ("mean", "var", "count")) or not all(
                hasattr(saved, a) for a in ("norm_obs", "norm_reward", "clip_obs", "clip_reward", "gamma", "epsilon")):
            raise ArtefactError(f"{path}: the pickle holds {_what_object(saved)}, not stable-baselines3's VecNormalize "
                                f"statistics")
        return VecNormalizeStats.of(saved)
    arrays = _load_npz(path, "VecNormalize statistics", VECNORM_FORMAT)
    try:
        if "obs_keys" in arrays:
            keys = [str(k) for k in arrays["obs_keys"]]
            obs_rms = {k: _rms(arrays, f"obs{i}", path) for i, k in enumerate(keys)}
            norm_keys = [str(k) for k in arrays["norm_obs_keys"]]
        else:
            obs_rms, norm_keys = _rms(arrays, "obs", path), None
        return VecNormalizeStats(obs_rms, _rms(arrays, "ret", path), norm_obs=bool(arrays["norm_obs"]),
                                 norm_reward=bool(arrays["norm_reward"]), clip_obs=float(arrays["clip_obs"]),
                                 clip_reward=float(arrays["clip_reward"]), gamma=float(arrays["gamma"]),
                                 epsilon=float(arrays["epsilon"]), norm_obs_keys=norm_keys)
    except KeyError as exc:
        raise ArtefactError(f"{path}: VecNormalize statistics lack {exc.args[0]!r}") from None


def _what_object(obj) -> str:
    """``a dict``, ``the class collections.OrderedDict``: what an unpickled object is, for an error message."""
    if isinstance(obj, type):
        return f"the class {obj.__module__}.{obj.__qualname__}"
    return f"a {type(obj).__module__}.{type(obj).__qualname__}".replace("a builtins.", "a ")


def _unpickle(path: Path, what: str, trust: bool):
    if not trust:
        raise NeedsTrustError(f"{path}: {what} stored as a Python pickle; {TRUST_HINT}. (mjrft writes "
                              f"{path.stem}.npz instead since it loads without running code.)")
    import pickle

    try:
        with open(path, "rb") as fh:
            return pickle.load(fh)
    except Exception as exc:  # UnpicklingError, EOFError, AttributeError, ... on a damaged file
        raise ArtefactError(f"{path}: {what} pickle is truncated or corrupt ({_reason(exc)})") from None


# ---------------------------------------------------------------------------------------------- replay buffer
_BUFFER_ARRAYS = ("observations", "next_observations", "actions", "rewards", "dones", "timeouts")


def save_replay_buffer(buffer, file) -> None:
    """Write an SB3 replay buffer (``ReplayBuffer`` or ``DictReplayBuffer``) to ``file`` as npz."""
    arrays = {"format": np.array(BUFFER_FORMAT), "pos": np.array(int(buffer.pos)), "full": np.array(bool(buffer.full)),
              "buffer_size": np.array(int(buffer.buffer_size)), "n_envs": np.array(int(buffer.n_envs))}
    for name in _BUFFER_ARRAYS:
        value = getattr(buffer, name, None)
        if isinstance(value, dict):
            for key, arr in value.items():
                arrays[f"{name}.{key}"] = arr
        elif value is not None:
            arrays[name] = value
    _savez(file, arrays)


def load_replay_buffer(model, path, trust: bool = False) -> None:
    """Fill ``model.replay_buffer`` from ``*_replay_buffer.npz`` (or, ``trust=True`` only, SB3's ``.pkl``).
    Raises ``ValueError`` when the buffer was laid out for another number of environments."""
    path = Path(path)
    buffer = model.replay_buffer
    if path.suffix == ".pkl":
        saved = _unpickle(path, "replay buffer", trust)
        if not all(hasattr(saved, a) for a in ("n_envs", "pos", "full", "buffer_size", "observations", "actions")):
            raise ArtefactError(f"{path}: the pickle holds {_what_object(saved)}, not a stable-baselines3 replay buffer")
        arrays = {"n_envs": np.array(saved.n_envs), "pos": np.array(saved.pos), "full": np.array(saved.full),
                  "buffer_size": np.array(saved.buffer_size)}
        for name in _BUFFER_ARRAYS:
            value = getattr(saved, name, None)
            if isinstance(value, dict):
                arrays.update({f"{name}.{k}": v for k, v in value.items()})
            elif value is not None:
                arrays[name] = value
    else:
        arrays = _load_npz(path, "replay buffer", BUFFER_FORMAT)
    n_envs = int(arrays.get("n_envs", -1))
    if n_envs != buffer.n_envs:
        raise ValueError(f"the SAC run was trained with n_envs={n_envs} (its replay buffer is laid out per "
                         f"environment); resume with n_envs={n_envs}")
    fills = {}
    for name in _BUFFER_ARRAYS:
        mine = getattr(buffer, name, None)
        targets = mine.items() if isinstance(mine, dict) else ([(None, mine)] if mine is not None else [])
        for key, arr in targets:
            label = name if key is None else f"{name}.{key}"
            if label not in arrays:
                raise ArtefactError(f"{path}: replay buffer lacks {label!r}")
            if arrays[label].shape != arr.shape:
                raise ArtefactError(f"{path}: replay buffer {label!r} has shape {arrays[label].shape}, the model's "
                                    f"buffer {arr.shape} (another buffer_size or env?)")
            fills[(name, key)] = arrays[label]
    for (name, key), arr in fills.items():
        if key is None:
            setattr(buffer, name, arr.astype(getattr(buffer, name).dtype, copy=False))
        else:
            getattr(buffer, name)[key] = arr
    buffer.pos, buffer.full = int(arrays["pos"]), bool(arrays["full"])

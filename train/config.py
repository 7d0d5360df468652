"""Training configurations: the named recipes shipped with mjrft and a user's own YAML or JSON files.

>>> from mjrft.train.config import load_training_config, named_configs
>>> named_configs()
['hexapod-sand', ...]
>>> cfg = load_training_config("hexapod-sand")          # or a path: "my_run.yaml", "runs/hex/config.json"
>>> cfg["env_id"], cfg["timesteps"], cfg["hyperparams"]["n_steps"]

``mjrft train --config hexapod-sand`` trains with such a configuration; options given on the command
line override its values (``--timesteps 20000``, ``--seed 3``, ``--hp learning_rate=1e-4``, ``KEY=VALUE``
env kwargs are merged into its ``env_kwargs``). A run folder's ``config.json`` is itself a valid
configuration (its training keys are read, the bookkeeping keys ignored), so a run can be repeated
with ``mjrft train --config runs/hex/config.json --out runs/hex2``.

Keys (all but ``env_id`` optional; :data:`DEFAULTS` gives the defaults):

=====================  =================================================================================
``env_id``             registered environment id, e.g. ``mjrft/HexapodSand-v0``
``algo``               ``ppo`` or ``sac``
``timesteps``          total environment steps of the run
``n_envs``             environments stepped together
``seed``               seeds the algorithm and the environments
``normalize``          ``VecNormalize`` observations and rewards
``hyperparams``        constructor arguments of the SB3 algorithm (``n_steps``, ``learning_rate``, ...)
``env_kwargs``         keyword arguments of the environment (``max_episode_steps`` included)
``checkpoint_every``   steps between checkpoints
``vec_env``            how the environments are stepped (:mod:`mjrft.train.vecenv`): ``auto``, ``subproc``,
                       ``dummy`` or ``batched``. Each kind adds up the physics in its own order, and PPO
                       amplifies the last-bit differences, so a recipe names the kind that reproduces its
                       policy bit for bit on the machine that trained it (with the same kind, seed, n_envs
                       and torch threads a run repeats itself there; on another CPU it need not).
``description``        free text (why the recipe is as it is)
=====================  =================================================================================
"""

from __future__ import annotations

import json
from pathlib import Path

from mjrft.errors import unknown

from .vecenv import check_kind

#: folder of the named configurations shipped in the package (``<name>.yaml``)
CONFIG_DIR = Path(__file__).resolve().parent / "configs"
DEFAULTS = {"algo": "ppo", "timesteps": 100_000, "n_envs": 1, "seed": 0, "normalize": False, "hyperparams": {},
            "env_kwargs": {}, "checkpoint_every": 10_000, "vec_env": "auto", "description": ""}
KEYS = ("env_id", *DEFAULTS)
#: keys of a run folder's config.json that are bookkeeping, not training settings
RUN_KEYS = ("policy", "hyperparams_given", "device", "torch_threads", "start_method", "versions",
            "created", "num_timesteps", "model", "runs", "checkpoint", "config")


def named_in(folder: Path) -> list[str]:
    """Names of the recipes in ``folder`` (its ``<name>.yaml`` files)."""
    return sorted(p.stem for p in Path(folder).glob("*.yaml"))


def find_recipe(name_or_path, folder: Path, what: str) -> Path:
    """The file of the recipe ``name_or_path``: a path ending in .yaml / .yml / .json (or any existing file), else
    ``folder/<name>.yaml``; ``what`` names the kind in the errors (e.g. ``"training config"``). The one lookup of
    both trainers' recipes (``mjrft train`` and ``mjrft train-mjx``)."""
    path = Path(name_or_path)
    if path.suffix.lower() in (".yaml", ".yml", ".json") or path.is_file():
        if not path.is_file():
            raise ValueError(f"{what} file {str(path)!r} does not exist")
        return path
    named = Path(folder) / f"{name_or_path}.yaml"
    if not named.is_file():
        err = unknown(what, str(name_or_path), named_in(folder))
        raise type(err)(f"{err}; or give the path of a .yaml / .json file") from None
    return named


def read_recipe(path: Path, what: str):
    """The contents of a YAML or JSON recipe file (by its suffix); a file that does not parse is refused with
    the parser's reason and the file's name."""
    text = Path(path).read_text()
    try:
        if Path(path).suffix.lower() == ".json":
            return json.loads(text)
        import yaml

        return yaml.safe_load(text)
    except Exception as exc:  # yaml.YAMLError / json.JSONDecodeError: name the file and the parser's reason
        raise ValueError(f"{what} {str(path)!r} cannot be read: {exc}") from None


def named_configs() -> list[str]:
    """Names of the configurations shipped with mjrft (``mjrft train --config NAME``)."""
    return named_in(CONFIG_DIR)


def config_path(name_or_path) -> Path:
    """The file of a named configuration, or the given path (which must exist)."""
    return find_recipe(name_or_path, CONFIG_DIR, "training config")


def _read(path: Path) -> dict:
    data = read_recipe(path, "training config")
    if not isinstance(data, dict):
        raise ValueError(f"training config {str(path)!r} must hold a mapping of keys ({', '.join(KEYS)}), "
                         f"got {type(data).__name__}")
    return data


def check_training_config(data: dict, source: str = "training config") -> dict:
    """Validate the keys and value types of a configuration; return it with the defaults filled in."""
    is_run = "runs" in data and "hyperparams_given" in data
    if is_run:  # a run folder's config.json: the hyper-parameters as given, not SB3's filled-in defaults
        data = {**{k: v for k, v in data.items() if k not in RUN_KEYS and k != "hyperparams"},
                "hyperparams": data.get("hyperparams_given") or {}}
    bad = sorted(set(data) - set(KEYS))
    if bad:
        raise ValueError(f"{source}: unknown key(s) {', '.join(map(repr, bad))}; valid keys: {', '.join(KEYS)}")
    if not isinstance(data.get("env_id"), str):
        raise ValueError(f"{source}: 'env_id' (a registered environment id) is required, got {data.get('env_id')!r}")
    for key in ("hyperparams", "env_kwargs"):
        if not isinstance(data.get(key, {}) or {}, dict):
            raise ValueError(f"{source}: {key!r} must be a mapping, got {data[key]!r}")
    cfg = {**DEFAULTS, **{k: v for k, v in data.items() if v is not None}}
    cfg["hyperparams"], cfg["env_kwargs"] = dict(cfg["hyperparams"]), dict(cfg["env_kwargs"])
    for key in ("timesteps", "n_envs", "seed", "checkpoint_every"):
        value = cfg[key] = integer_value(cfg[key])
        if isinstance(value, bool) or not isinstance(value, int) or value < (0 if key == "seed" else 1):
            raise ValueError(f"{source}: {key!r} must be an integer >= {0 if key == 'seed' else 1}, got {value!r}")
    check_kind(cfg["vec_env"])
    if not isinstance(cfg["normalize"], bool):
        raise ValueError(f"{source}: 'normalize' must be true or false, got {cfg['normalize']!r}")
    return {k: cfg[k] for k in KEYS}


def integer_value(value):
    """An integer written as a number in any notation: ``100000``, ``1e5`` (YAML reads it as a string),
    ``1.0e+5`` (a float) or ``100_000``; anything else is returned unchanged (and refused by the caller)."""
    if isinstance(value, float) and value.is_integer():
        return int(value)
    if isinstance(value, str):
        try:
            number = float(value.replace("_", ""))
        except ValueError:
            return value
        if number.is_integer():
            return int(number)
    return value


def load_training_config(name_or_path) -> dict:
    """A named configuration (:func:`named_configs`) or a YAML / JSON file, validated, defaults filled in."""
    path = config_path(name_or_path)
    return check_training_config(_read(path), f"training config {str(path)!r}")


def save_training_config(cfg: dict, path) -> Path:
    """Write ``cfg`` (validated) as YAML or JSON by the file's suffix; :func:`load_training_config` reads it back."""
    path = Path(path)
    cfg = check_training_config(cfg)
    if path.suffix.lower() == ".json":
        path.write_text(json.dumps(cfg, indent=2) + "\n")
    else:
        import yaml

        path.write_text(yaml.safe_dump(cfg, sort_keys=False))
    return path

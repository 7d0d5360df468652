"""Brax PPO on mjrft's MJX environments: thousands of worlds per GPU, the policy saved for ``mjrft eval`` on the
CPU env.

``mjrft train-mjx --config hexapod-sand --out runs/hex-mjx`` trains an environment of the registry
(:mod:`mjrft.mjx.envs`: ``load(env, config_overrides=env_config)``, here ``HexapodSand``, ``mjrft/HexapodSand-v0``
on MJX) with ``brax.training.agents.ppo.train`` and Brax's own training wrappers under a named recipe
(``train/configs/mjx/<name>.yaml``) or a YAML / JSON file, and writes to the run folder:

* ``policy.npz`` (the observation normaliser and the policy and value networks' weights, plain arrays,
  loaded with ``allow_pickle=False``) and ``policy.json`` (the networks' layout, the recipe, the env's
  keyword arguments, the training summary): no pickled code, so a shared run folder is safe to load;
* ``progress.csv``: steps, wall time, mean episode return, speed and length of each evaluation, and the mean
  number of steps per evaluation episode after the sand's guards found a stability limit exceeded
  (``unstable_steps``) or the law's range left (``out_of_range_steps``; NaN for an env without these metrics);
* ``checkpoints/<steps>/``: the policy of each evaluation (``policy.npz`` and ``policy.json``, steps in 11
  digits), each a run folder that ``mjrft eval --policy`` runs, so that any point of the learning curve can be
  evaluated on the CPU env.

The policy files are rewritten (whole, then renamed into place) at each evaluation with ``"complete": false``
and at the end with ``"complete": true``, so an interrupted run keeps the policy of its last evaluation.

:func:`load_policy` rebuilds the deterministic policy (the mean action of Brax's tanh-normal) as a plain
function of one observation; ``mjrft eval --policy runs/hex-mjx`` runs it on the CPU env
(:mod:`mjrft.train.evaluate`) and ``--backend mjx`` on the MJX env (:func:`evaluate_mjx`): the same policy on
both backends is the cross-check of the two physics paths.

Every environment of the registry has a named recipe (:func:`named_recipes`; docs/gpu.md lists them).
``mjrft train-mjx --config biped-sand --out runs/biped --seeds 0 1 2`` (:mod:`mjrft.train.train_mjx`, the command
line) trains one run folder per seed, evaluates each final policy on the MJX env and on the CPU env of the same task
(the cross-check of the two backends) and writes the mean and spread over the seeds (:mod:`mjrft.train.seeds`).

Recipe keys (:data:`RECIPE_KEYS`): ``env`` (a name of :func:`mjrft.mjx.envs.names`), ``env_config`` (its
configuration overrides, ``{"dotted.key": value}``, e.g. ``{"reward_config.scales.energy": -0.1}``),
``num_timesteps``, ``num_envs``,
``episode_length`` (control steps), ``seed``, ``network`` (``policy_hidden_layer_sizes``,
``value_hidden_layer_sizes``), ``ppo`` (keyword arguments of Brax's ``ppo.train``: ``learning_rate``,
``unroll_length``, ``batch_size``, ``num_minibatches``, ``num_updates_per_batch``, ``entropy_cost``,
``discounting``, ``num_evals``, ...) and ``description``.
"""

from __future__ import annotations

import contextlib
import csv
import functools
import json
import math
import os
import time
import warnings
from pathlib import Path

import numpy as np

from .config import find_recipe, integer_value, named_in, read_recipe

#: folder of the named MJX recipes (``<name>.yaml``)
RECIPE_DIR = Path(__file__).resolve().parent / "configs" / "mjx"
RECIPE_DEFAULTS = {"env": "HexapodSand", "env_config": {}, "num_timesteps": 10_000_000, "num_envs": 2048, "episode_length": 1000,
                   "seed": 0, "network": {}, "ppo": {}, "description": ""}
RECIPE_KEYS = tuple(RECIPE_DEFAULTS)
NETWORK_KEYS = ("policy_hidden_layer_sizes", "value_hidden_layer_sizes")
#: Brax ppo.train arguments that the recipe sets itself (from its own keys) or that mjrft does not support
PPO_RESERVED = ("environment", "num_timesteps", "num_envs", "episode_length", "seed", "network_factory",
                "progress_fn", "policy_params_fn", "wrap_env", "wrap_env_fn", "eval_env", "randomization_fn",
                "save_checkpoint_path", "restore_checkpoint_path", "restore_params", "vision")
POLICY_FILE, META_FILE, PROGRESS_FILE = "policy.npz", "policy.json", "progress.csv"
CHECKPOINTS = "checkpoints"  # a run folder's checkpoints/<steps>/: the policy of each evaluation, a run folder itself
FORMAT = "mjrft-brax-ppo/1"


def require_extra() -> None:
    """Raise a one-line ``ValueError`` (the CLI prints it) when the optional extra ``mjrft[mjx]`` is missing."""
    import importlib.util

    missing = [m for m in ("jax", "brax", "flax") if importlib.util.find_spec(m) is None]
    try:
        if importlib.util.find_spec("mujoco.mjx") is None:
            missing.append("mujoco-mjx")
    except ModuleNotFoundError:
        missing.append("mujoco-mjx")
    if missing:
        raise ValueError(f"MJX training and MJX policies need the optional extra mjrft[mjx] ({', '.join(missing)} "
                         "not installed): pip install 'mjrft[mjx]' (Python >= 3.11; docs/gpu.md)")
    import_mjx_quietly()


#: what ``import mujoco.mjx`` prints when its optional Warp backend (NVIDIA Warp) is not installed
WARP_NOTICES = ("Failed to import warp:", "Failed to import mujoco_warp:")


def import_mjx_quietly() -> None:
    """Import ``mujoco.mjx`` (Brax imports it too) without the lines it prints when NVIDIA Warp is not installed
    (:data:`WARP_NOTICES`): mjrft runs MJX's JAX implementation, which does not use Warp. Anything else the
    import prints is passed on."""
    import io
    import sys

    if "mujoco.mjx" in sys.modules:
        return
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        import mujoco.mjx  # noqa: F401
    for line in printed.getvalue().splitlines():
        if not line.startswith(WARP_NOTICES):
            print(line)


# ---------------------------------------------------------------------- recipes
def named_recipes() -> list[str]:
    """Names of the MJX recipes shipped with mjrft (``mjrft train-mjx --config NAME``)."""
    return named_in(RECIPE_DIR)


def load_recipe(name_or_path) -> dict:
    """A named recipe or a YAML / JSON file, checked, with :data:`RECIPE_DEFAULTS` filled in (found and read by
    :mod:`mjrft.train.config`, as ``mjrft train``'s configurations)."""
    path = find_recipe(name_or_path, RECIPE_DIR, "MJX training recipe")
    return check_recipe(read_recipe(path, "MJX training recipe"), f"MJX training recipe {str(path)!r}")


def check_recipe(data, source: str = "MJX training recipe") -> dict:
    """Validate a recipe's keys and values (before anything is compiled); return it with the defaults filled in."""
    if not isinstance(data, dict):
        raise ValueError(f"{source} must hold a mapping of keys ({', '.join(RECIPE_KEYS)}), got {type(data).__name__}")
    if "env_kwargs" in data:
        raise ValueError(f"{source}: 'env_kwargs' is replaced by 'env' (a name of mjrft.mjx.envs.names()) and "
                         "'env_config' (its configuration overrides, e.g. {'reward_config.scales.energy': -0.1})")
    bad = sorted(set(data) - set(RECIPE_KEYS))
    if bad:
        raise ValueError(f"{source}: unknown key(s) {', '.join(map(repr, bad))}; valid keys: {', '.join(RECIPE_KEYS)}")
    cfg = {**RECIPE_DEFAULTS, **{k: v for k, v in data.items() if v is not None}}
    for key in ("env_config", "network", "ppo"):
        if not isinstance(cfg[key], dict):
            raise ValueError(f"{source}: {key!r} must be a mapping, got {cfg[key]!r}")
        cfg[key] = dict(cfg[key])
    for key in ("num_timesteps", "num_envs", "episode_length", "seed"):
        value = cfg[key] = integer_value(cfg[key])
        if isinstance(value, bool) or not isinstance(value, int) or value < (0 if key == "seed" else 1):
            raise ValueError(f"{source}: {key!r} must be an integer >= {0 if key == 'seed' else 1}, got {value!r}")
    bad = sorted(set(cfg["network"]) - set(NETWORK_KEYS))
    if bad:
        raise ValueError(f"{source}: unknown network key(s) {', '.join(map(repr, bad))}; valid: {', '.join(NETWORK_KEYS)}")
    for key, sizes in cfg["network"].items():
        if not (isinstance(sizes, (list, tuple)) and sizes and all(isinstance(s, int) and s > 0 for s in sizes)):
            raise ValueError(f"{source}: network {key!r} must be a list of layer sizes (integers > 0), got {sizes!r}")
    reserved = sorted(set(cfg["ppo"]) & set(PPO_RESERVED))
    if reserved:
        raise ValueError(f"{source}: ppo key(s) {', '.join(map(repr, reserved))} are set by mjrft from the recipe's "
                         f"own keys ({', '.join(RECIPE_KEYS)}) and cannot be given under 'ppo'")
    require_extra()
    import inspect

    from brax.training.agents.ppo import train as ppo

    from mjrft.envs import mjx as envs

    if cfg["env"] not in envs.names():
        raise ValueError(f"{source}: unknown env {cfg['env']!r}; valid choices: {', '.join(envs.names())}")

    valid = set(inspect.signature(ppo.train).parameters) - set(PPO_RESERVED)
    bad = sorted(set(cfg["ppo"]) - valid)
    if bad:
        raise ValueError(f"{source}: unknown ppo key(s) {', '.join(map(repr, bad))}; Brax's ppo.train takes "
                         f"{', '.join(sorted(valid))}")
    batch = cfg["ppo"].get("batch_size", 32) * cfg["ppo"].get("num_minibatches", 16)
    if batch % cfg["num_envs"] and cfg["num_envs"] % batch:
        raise ValueError(f"{source}: batch_size x num_minibatches = {batch} and num_envs = {cfg['num_envs']} must "
                         "divide one another (Brax's PPO splits the rollout of every env into minibatches)")
    return {k: cfg[k] for k in RECIPE_KEYS}


# ---------------------------------------------------------------------- networks and files
def _networks(meta: dict):
    from brax.training.acme import running_statistics
    from brax.training.agents.ppo import networks as ppo_networks

    kw = {k: tuple(v) for k, v in meta.get("network", {}).items()}
    return ppo_networks.make_ppo_networks(meta["observation_size"], meta["action_size"],
                                          preprocess_observations_fn=running_statistics.normalize, **kw)


def _template(meta: dict):
    """Brax's (normaliser, policy, value) parameter tree for ``meta``'s networks, with fresh values."""
    import jax
    import jax.numpy as jnp
    from brax.training import acme

    nets = _networks(meta)
    key = jax.random.PRNGKey(0)
    norm = acme.running_statistics.init_state(acme.specs.Array((meta["observation_size"],), jnp.dtype("float32")))
    return nets, (norm, nets.policy_network.init(key), nets.value_network.init(key))


def _flat(tree) -> dict:
    import jax

    leaves = jax.tree_util.tree_flatten_with_path(tree)[0]
    return {jax.tree_util.keystr(path): np.asarray(leaf) for path, leaf in leaves}


def save_policy(out: Path, params, meta: dict) -> tuple[Path, Path]:
    """Write ``params`` (Brax's (normaliser, policy, value) tuple) to ``out/policy.npz`` and ``meta`` to
    ``out/policy.json``; each file is written whole to a temporary name and renamed into place."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    npz, js = out / POLICY_FILE, out / META_FILE
    tmp = out / (POLICY_FILE + ".tmp.npz")
    np.savez(tmp, **_flat(params))
    os.replace(tmp, npz)
    tmp = out / (META_FILE + ".tmp")
    tmp.write_text(json.dumps({"format": FORMAT, **meta}, indent=2) + "\n")
    os.replace(tmp, js)
    return npz, js


def is_mjx_policy(path) -> bool:
    """Whether ``path`` is a run folder (or its ``policy.json``) of :func:`train_recipe`."""
    path = Path(path)
    meta = path / META_FILE if path.is_dir() else path
    return meta.name == META_FILE and meta.is_file() and (meta.parent / POLICY_FILE).is_file()


class MjxPolicy:
    """A policy trained by :func:`train_recipe`: ``policy(obs) -> action`` (deterministic: the mean of Brax's
    tanh-normal), for one observation (35,) or a batch (k, 35); ``meta`` is its ``policy.json``."""

    def __init__(self, meta: dict, params):
        import jax

        from brax.training.agents.ppo import networks as ppo_networks

        self.meta = meta
        self.params = params
        nets = _networks(meta)
        self._fn = jax.jit(ppo_networks.make_inference_fn(nets)(params, deterministic=True))
        self._key = jax.random.PRNGKey(0)

    def __call__(self, obs) -> np.ndarray:
        import jax.numpy as jnp

        action, _ = self._fn(jnp.asarray(obs, dtype=jnp.float32), self._key)
        return np.asarray(action, dtype=np.float64)

    def predict(self, observation, state=None, episode_start=None, deterministic: bool = True):
        """SB3's ``predict`` signature (``mjrft eval`` on the CPU env): the deterministic action and no state."""
        return self(observation), None

    def jax_fn(self):
        """The jitted ``(obs, key) -> (action, extras)`` function, for use inside JAX code."""
        return self._fn


def read_meta(path) -> dict:
    """The ``policy.json`` of a run folder (or the file itself), checked; one line naming the file if malformed."""
    path = Path(path)
    meta_path = path / META_FILE if path.is_dir() else path
    if not meta_path.is_file():
        raise ValueError(f"{meta_path} is missing: an MJX run folder holds {META_FILE} and {POLICY_FILE}")
    try:
        meta = json.loads(meta_path.read_text())
    except (OSError, ValueError) as exc:
        raise ValueError(f"{meta_path} is not valid JSON ({exc})") from None
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        raise ValueError(f"{meta_path} is not an mjrft MJX policy (format {FORMAT!r} expected)")
    for key in ("env_id", "observation_size", "action_size"):
        if key not in meta:
            raise ValueError(f"{meta_path} lacks {key!r}")
    return meta


def load_policy(path) -> MjxPolicy:
    """The policy of a run folder (or its ``policy.json``); one line naming the file on anything malformed."""
    path = Path(path)
    folder = path if path.is_dir() else path.parent
    meta_path, npz_path = folder / META_FILE, folder / POLICY_FILE
    meta = read_meta(meta_path)
    require_extra()
    if not npz_path.is_file():
        raise ValueError(f"{npz_path} is missing: an MJX run folder holds {META_FILE} and {POLICY_FILE}")
    import jax

    _, template = _template(meta)
    try:
        with np.load(npz_path, allow_pickle=False) as z:
            stored = {k: z[k] for k in z.files}
    except Exception as exc:  # zipfile.BadZipFile, ValueError, EOFError: a truncated or foreign file
        raise ValueError(f"{npz_path} cannot be read as an npz archive ({type(exc).__name__}: {exc})") from None
    leaves, treedef = jax.tree_util.tree_flatten_with_path(template)
    values = []
    for path_, leaf in leaves:
        key = jax.tree_util.keystr(path_)
        if key not in stored or np.shape(stored[key]) != np.shape(leaf):
            raise ValueError(f"{npz_path}: array {key!r} is missing or has the wrong shape for the networks in "
                             f"{meta_path}")
        values.append(jax.numpy.asarray(np.asarray(stored[key]).astype(jax.numpy.asarray(leaf).dtype)))
    return MjxPolicy(meta, jax.tree_util.tree_unflatten(treedef, values))


# ---------------------------------------------------------------------- training
def device_put_replicated(x, devices):
    """A copy of each leaf of ``x`` per device, stacked on a new leading axis sharded over ``devices``.

    The public-API form of ``jax.device_put_replicated`` under ``jax.pmap``'s shard_map implementation (the
    default since jax 0.8); jax 0.10 removed the function itself."""
    import jax

    devices = list(devices)
    mesh = jax.sharding.Mesh(np.array(devices), ("devices",))
    sharding = jax.sharding.NamedSharding(mesh, jax.sharding.PartitionSpec("devices"))

    def put(leaf):
        leaf = jax.numpy.asarray(leaf)
        return jax.device_put(jax.numpy.broadcast_to(leaf[None], (len(devices),) + leaf.shape), sharding)

    return jax.tree_util.tree_map(put, x)


@contextlib.contextmanager
def _replicated_put(jax_module=None):
    """Provide ``jax.device_put_replicated`` (:func:`device_put_replicated`) while Brax's PPO runs, where jax no
    longer has it: Brax 0.14.2's ``ppo.train`` replicates its training state with it, and jax 0.10 removed it
    (the ``mjx`` extra pins jax 0.11 on Python 3.12+). Under a jax that has it, nothing changes."""
    if jax_module is None:
        import jax as jax_module

    with warnings.catch_warnings():  # jax 0.8-0.9 warn on the lookup: Brax's call warns once more by itself
        warnings.simplefilter("ignore", DeprecationWarning)
        has_own = hasattr(jax_module, "device_put_replicated")
    if has_own:
        yield
        return
    jax_module.device_put_replicated = device_put_replicated
    try:
        yield
    finally:
        del jax_module.device_put_replicated


def committed_inputs(tree, device):
    """``tree`` with every array strongly typed (its own dtype) and placed on ``device``: the form that keys one
    compiled function the same way whatever made its inputs (a Python float, an uncommitted array, another jit)."""
    import jax
    import jax.numpy as jnp

    def put(x):
        x = jnp.asarray(x)
        if not jax.dtypes.issubdtype(x.dtype, jax.dtypes.prng_key):  # typed keys have no weak form
            x = jnp.asarray(x, dtype=x.dtype)
        return jax.device_put(x, device)

    return jax.tree_util.tree_map(put, tree)


@contextlib.contextmanager
def _evaluations_compile_once():
    """Compile Brax's evaluation unroll once per run while its PPO trains. Brax 0.14.2's ``acting.Evaluator`` calls
    one jitted unroll (the whole evaluation episode of ``num_eval_envs`` worlds: the run's largest compile after the
    training step) first on the reset state and the initial parameters, then on its own output and the trained
    parameters; the two differ in what jit's cache keys on (the first call's arrays are uncommitted and its
    normaliser's ``std_eps`` is a weakly typed Python float, the later ones committed and strongly typed), so it
    compiled twice. Here every call's inputs go through :func:`committed_inputs` on the first local device (where
    Brax's unpmapped parameters and the unroll's output live), so every evaluation has the first one's key."""
    import jax
    from brax.training import acting

    own_init = acting.Evaluator.__init__

    def init(self, *args, **kwargs):
        own_init(self, *args, **kwargs)
        unroll, device = self._generate_eval_unroll, jax.local_devices()[0]
        self._generate_eval_unroll = lambda *inputs: unroll(*committed_inputs(inputs, device))

    acting.Evaluator.__init__ = init
    try:
        yield
    finally:
        acting.Evaluator.__init__ = own_init


def train_recipe(cfg: dict, out, *, report=print) -> dict:
    """Train with the checked recipe ``cfg`` (:func:`check_recipe`) into the run folder ``out``; returns the
    summary written into ``policy.json``."""
    import jax
    from brax.training.agents.ppo import networks as ppo_networks
    from brax.training.agents.ppo import train as ppo

    from mjrft.envs import mjx as envs

    cfg = check_recipe(cfg)
    if not cfg["ppo"].get("normalize_observations", False):
        raise ValueError("the MJX recipes normalise observations (ppo: normalize_observations: true): the saved "
                         "policy stores the normaliser with the networks")
    check_devices(cfg)
    writer_process = jax.process_index() == 0  # several hosts: the first one writes the run folder
    out = Path(out)
    if writer_process:
        out.mkdir(parents=True, exist_ok=True)
    env = envs.load(cfg["env"], config_overrides=cfg["env_config"])
    # an environment whose State keeps Brax's pipeline_state takes Brax's own training wrappers; one in MuJoCo
    # Playground's form (data only) takes wrap_for_training
    wrap = {} if _has_pipeline_state(env) else {"wrap_env_fn": wrap_for_training}
    net_kw = {k: tuple(v) for k, v in cfg["network"].items()}
    factory = functools.partial(ppo_networks.make_ppo_networks, **net_kw)
    rows = []
    t0 = time.perf_counter()
    progress_path = out / PROGRESS_FILE
    with (progress_path.open("w", newline="") if writer_process else contextlib.nullcontext(_NoFile())) as fh:
        writer = csv.writer(fh)
        writer.writerow(["steps", "wall_s", "episode_return", "speed", "episode_length", "unstable_steps",
                         "out_of_range_steps"])
        fh.flush()

        def progress(step, metrics):
            ret = float(metrics.get("eval/episode_reward", math.nan))
            length = float(metrics.get("eval/avg_episode_length", math.nan))
            speed = float(metrics.get("eval/episode_x_velocity", math.nan)) / max(length, 1.0)
            # the sand's guards: the mean number of steps per evaluation episode after a stability limit was
            # exceeded (or chatter began) / the law's range was left (the env's metrics "unstable", "out_of_range")
            unstable, out_of_range = (float(metrics.get(f"eval/episode_{k}", math.nan))
                                      for k in ("unstable", "out_of_range"))
            row = [int(step), round(time.perf_counter() - t0, 3), ret, speed, length, unstable, out_of_range]
            rows.append(row)
            writer.writerow(row)
            fh.flush()
            guards = "" if not unstable > 0 else (f"  UNSTABLE: the sand's stability guards fired, {unstable:.0f} "
                                                  "steps per evaluation episode (mjrft.mjx.guards)")
            report(f"  {int(step):>10d} steps  {row[1]:8.1f} s  return {ret:9.3f}  speed {speed:.3f} m/s  "
                   f"length {length:.0f}{guards}")

        def meta(steps: int, complete: bool) -> dict:
            return {"env": cfg["env"], "env_config": cfg["env_config"], "env_id": getattr(env, "gym_id", None),
                    "env_kwargs": getattr(env, "gym_kwargs", None), "recipe": cfg,
                    "observation_size": env.observation_size, "action_size": env.action_size,
                    "network": {k: list(v) for k, v in net_kw.items()}, "normalize_observations": True,
                    "num_timesteps": int(steps), "complete": complete, "wall_s": round(time.perf_counter() - t0, 1),
                    "device": str(jax.devices()[0]), "devices": jax.device_count(), "processes": jax.process_count(),
                    "jax": jax.__version__}

        def checkpoint(step, make_policy, params):  # at each evaluation: an interrupted run keeps its last policy
            if not writer_process:
                return
            now = meta(step, complete=False)
            save_policy(out, params, now)
            save_policy(out / CHECKPOINTS / f"{int(step):011d}", params, now)

        ppo_kw = {"num_evals": 2, **cfg["ppo"]}
        with _replicated_put(), _evaluations_compile_once():
            make_policy, params, metrics = ppo.train(
                environment=env, num_timesteps=cfg["num_timesteps"], num_envs=cfg["num_envs"],
                episode_length=cfg["episode_length"], seed=cfg["seed"], network_factory=factory,
                progress_fn=progress, policy_params_fn=checkpoint, **wrap, **ppo_kw)
    del make_policy
    summary = {**meta(cfg["num_timesteps"], complete=True),
               "final": {k: float(v) for k, v in metrics.items() if np.ndim(v) == 0}}
    if writer_process:
        save_policy(out, params, summary)
    return summary


# ---------------------------------------------------------------------- evaluation on MJX
def mjx_env_of(meta: dict, config_overrides=None):
    """The MJX environment a policy was trained on (its ``policy.json``: ``env`` and ``env_config``), with
    ``config_overrides`` on top. A run folder from before the registry (no ``env``) trained ``HexapodSand``."""
    from mjrft.envs import mjx as envs

    if "env" not in meta and meta.get("env_kwargs"):
        raise ValueError(f"this policy's environment is given by the keyword arguments {meta['env_kwargs']!r} of "
                         "mjrft/HexapodSand-v0; evaluate it on the CPU env (mjrft eval without --backend mjx)")
    overrides = {**(meta.get("env_config") or {}), **(config_overrides or {})}
    return envs.load(meta.get("env", "HexapodSand"), config_overrides=overrides)


def evaluate_mjx(policy: MjxPolicy, episodes: int = 10, seconds: float = 10.0, seed: int = 0,
                 config_overrides=None) -> dict:
    """The policy on its MJX env (:func:`mjx_env_of`), ``episodes`` worlds in one batch, each for ``seconds`` or
    until it ends (a fall or a divergence): the metrics of ``mjrft eval`` on the CPU env, computed the same way per
    episode (speed = torso x displacement / time, CoT = actuator energy / (m g max(|dx|, 1e-3 t)), fell = ended
    without diverging) and averaged over the episodes that did not diverge; ``unstable`` and ``out_of_range`` count
    the episodes in which the sand's guards fired (the env's metrics of the same names), whose warnings are
    issued on the host."""
    import jax
    import jax.numpy as jnp

    env = mjx_env_of(policy.meta, config_overrides)
    if getattr(env, "gym_id", None) is None:
        raise ValueError(f"{policy.meta.get('env')} has no gymnasium env of the same task (only mjrft's robots have "
                         "one): mjrft eval measures their speed and cost of transport; this run's results are Brax's "
                         "evaluations in its progress.csv")
    steps = int(round(seconds / env.dt))
    act = policy.jax_fn()
    key = jax.random.PRNGKey(0)

    def run(rng):
        state = env.reset(rng)
        x0 = state.data.qpos[0]

        def body(carry, _):
            state, alive, energy, n, diverged = carry
            action, _ = act(state.obs, key)
            nxt = env.step(state, action)
            state = jax.tree_util.tree_map(lambda a, b: jnp.where(alive, a, b), nxt, state)
            energy = energy + jnp.where(alive, nxt.metrics["power"] * env.dt, 0.0)
            n = n + alive
            diverged = diverged | (alive & (nxt.metrics["diverged"] > 0.5))
            alive = alive & (nxt.done < 0.5)
            return (state, alive, energy, n, diverged), None

        init = (state, jnp.array(True), jnp.zeros(()), jnp.zeros(()), jnp.array(False))
        (state, alive, energy, n, diverged), _ = jax.lax.scan(body, init, None, length=steps)
        return (state.data.qpos[0] - x0, energy, n, alive, diverged, state.metrics.get("unstable", jnp.zeros(())),
                state.metrics.get("out_of_range", jnp.zeros(()))), state

    keys = jax.random.split(jax.random.PRNGKey(seed), episodes)
    numbers, last = jax.jit(jax.vmap(run))(keys)
    dx, energy, n, alive, diverged, unstable, out_of_range = map(np.asarray, numbers)
    if hasattr(env, "warn"):
        env.warn(last)  # what the sand's guards recorded, on the host (TerrainStabilityWarning, ValidityRangeWarning)
    t = n * env.dt
    ok = ~diverged
    speed = np.where(t > 0, dx / np.maximum(t, 1e-12), 0.0)
    cot = energy / (env.task.mass * 9.81 * np.maximum(np.maximum(np.abs(dx), 1e-3 * t), 1e-12))
    mean = (lambda v: float(v[ok].mean())) if ok.any() else (lambda v: math.nan)
    std = (lambda v: float(v[ok].std())) if ok.any() else (lambda v: math.nan)
    return {"episodes": int(episodes), "diverged": int(diverged.sum()), "speed": mean(speed), "speed_std": std(speed),
            "cost_of_transport": mean(cot), "cost_of_transport_std": std(cot),
            "fell": mean((~alive).astype(float)), "seconds": mean(t), "unstable": int((unstable > 0.5).sum()),
            "out_of_range": int((out_of_range > 0.5).sum()), "backend": "mjx", "env": env.name,
            "device": str(jax.devices()[0])}


# ---------------------------------------------------------------------- command line
class _NoFile:
    """The progress file of a host that does not write the run folder."""

    def write(self, _):
        return 0

    def flush(self):
        pass


def check_devices(cfg: dict) -> None:
    """Refuse, before compiling, a world count that Brax's PPO cannot split over every device of every host."""
    import jax

    devices = jax.device_count()
    if cfg["num_envs"] % devices:
        raise ValueError(f"num_envs = {cfg['num_envs']} must be a multiple of the {devices} devices "
                         f"({jax.process_count()} host(s) x {jax.local_device_count()} local): Brax's PPO gives each "
                         "device the same number of worlds")


def _has_pipeline_state(env) -> bool:
    """Whether ``env``'s state keeps Brax's ``pipeline_state`` (mjrft's own MJX envs; Brax's wrappers then work as
    they are), judged from the shape of a reset traced without running it."""
    import jax

    state = jax.eval_shape(env.reset, jax.random.PRNGKey(0))
    return hasattr(state, "pipeline_state")


def wrap_for_training(env, episode_length: int = 1000, action_repeat: int = 1, randomization_fn=None):
    """Brax's training wrappers for an environment in MuJoCo Playground's form (its state keeps ``data``, not Brax's
    ``pipeline_state``): vmap over worlds, episodes of ``episode_length`` control steps, and an auto-reset that
    returns a finished world to the ``data`` and ``obs`` of its first reset (Playground's
    ``wrap_for_brax_training``). ``randomization_fn`` is not supported."""
    from brax.envs.wrappers import training

    if randomization_fn is not None:
        raise NotImplementedError("mjrft train-mjx does not randomise the MJX model (randomization_fn)")
    return _AutoReset(training.EpisodeWrapper(training.VmapWrapper(env), episode_length, action_repeat))


class _AutoReset:
    """Brax's ``AutoResetWrapper`` for states that keep ``data`` (see :func:`wrap_for_training`)."""

    def __init__(self, env):
        self.env = env

    def __getattr__(self, name):
        if name == "env":
            raise AttributeError(name)
        return getattr(self.env, name)

    def reset(self, rng):
        state = self.env.reset(rng)
        state.info["first_data"] = state.data
        state.info["first_obs"] = state.obs
        return state

    def step(self, state, action):
        import jax
        import jax.numpy as jnp

        if "steps" in state.info:
            state.info["steps"] = jnp.where(state.done, jnp.zeros_like(state.info["steps"]), state.info["steps"])
        state = self.env.step(state.replace(done=jnp.zeros_like(state.done)), action)

        def where_done(first, now):
            done = jnp.reshape(state.done, state.done.shape + (1,) * (now.ndim - state.done.ndim))
            return jnp.where(done, first, now)

        data = jax.tree_util.tree_map(where_done, state.info["first_data"], state.data)
        obs = jax.tree_util.tree_map(where_done, state.info["first_obs"], state.obs)
        return state.replace(data=data, obs=obs)


def start_distributed(coordinator, num_processes, process_id) -> None:
    """``jax.distributed.initialize`` for a run over several hosts (all three arguments given), before JAX touches a
    device; nothing with none of them. Each process then trains on its local devices and Brax's PPO averages the
    gradients over all of them."""
    given = [a is not None for a in (coordinator, num_processes, process_id)]
    if not any(given):
        return
    if not all(given):
        raise ValueError("--coordinator, --num-processes and --process-id go together (one run over several hosts)")
    if num_processes < 1 or not 0 <= process_id < num_processes:
        raise ValueError(f"--process-id must be from 0 to --num-processes - 1 = {num_processes - 1}, got {process_id}")
    import jax

    jax.distributed.initialize(coordinator_address=coordinator, num_processes=num_processes, process_id=process_id)

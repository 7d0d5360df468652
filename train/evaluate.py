"""``mjrft eval``: deterministic evaluation of a trained policy or an open-loop gait.

>>> from mjrft.train.evaluate import evaluate
>>> rows, summary = evaluate("runs/hex/model.zip", episodes=5, seed=0)        # env from the run's config.json
>>> rows, summary = evaluate("tripod:f=2", "mjrft/HexapodSand-v0", episodes=3, env_kwargs={"max_episode_steps": 300})

Episode ``i`` starts from ``env.reset(seed=seed + i)``; with ``deterministic=True`` (the default) a
trained policy acts on its mean action, so the same seed gives the same rows bit for bit. With
``deterministic=False`` the policy's sampling is seeded with ``seed`` as well.

Metrics (one row per episode; the summary holds their mean and standard deviation and the fall rate):

==================  =====================================================================================
``return``          sum of the env's rewards
``steps``           env steps; ``seconds`` = steps x ``env.dt``
``speed``           forward speed (m/s): torso displacement along +x over the episode / its duration
                    (``info["x_position"]`` at reset and at the last step; for an env without it, the first
                    coordinate of its root joint, ``qpos[0]``)
``cot``             cost of transport (dimensionless): actuator energy ``sum(info["power"]) x dt``
                    divided by ``m g |dx|`` (m: total mass, dx: the x displacement); ``|dx|`` is floored
                    at 1 mm/s x duration, the same floor as the env's per-step ``info["cost_of_transport"]``.
                    ``info["power"]`` is the actuators' mean power over every physics step of the env step,
                    so the sum is the energy they delivered; a third-party env on sand (``GranularWrapper``,
                    no ``power`` in its info) gives the same mean (``terrain.actuator_power``), any other env
                    the power ``sum |force x velocity|`` at the end of each step
``sink_mean_mm``    mean sinkage (mm) of the feet that are in the sand: the average of ``info["sinkage"]``
                    (deepest element of each foot/leg body) over every step and every foot whose sinkage
                    is > 0 (a foot in the air does not dilute it); 0 when no foot ever entered the sand (or the
                    env reports no ``sinkage``, e.g. gymnasium's own MuJoCo robots on rigid ground)
``sink_peak_mm``    the largest ``info["sinkage"]`` over the episode and the feet (mm)
``slip``            foot slip (m/s): the mean horizontal speed of the foot surface that is in contact
                    with the ground, weighted by contact area and time. On sand the grains are at rest
                    (RFT), so every buried foot element's horizontal speed is its slip:
                    ``sum(area |v_xy|) / sum(area)`` over the buried elements of the foot/leg bodies
                    (``terrain.depth > 0``, ``terrain.vel``, ``terrain.area``, ``terrain.elem_body``) at every
                    step. On rigid ground: the mean horizontal speed of the foot's material point at each
                    foot-floor contact (MuJoCo contacts, velocity from ``mj_jac``). 0 without contact, and for
                    an env whose feet mjrft does not know (gymnasium's robots on rigid ground)
``fell``            the episode ended by termination (unhealthy: fallen over or sunk), not by the time limit;
                    the fall rate is the fraction of such episodes
==================  =====================================================================================

A policy is a gait spec (``tripod:f=2.0``, see :mod:`mjrft.tools.gaits`), a stable-baselines3 ``.zip``
saved by :mod:`mjrft.train.train` (or by ``PPO.save``/``SAC.save``), a run folder (its ``model.zip``),
a policy shipped with mjrft (``pretrained:HexapodSand-v0``: :func:`pretrained_names`), or any object
with SB3's ``predict``. For a zip the ``config.json`` of its run (its folder, or the
folder above ``checkpoints/``) gives the algorithm, the env id and env kwargs (those given here
override them) and whether observations were normalised (then the saved VecNormalize statistics
are applied, frozen). Without a config the algorithm is read from the zip itself.
"""

from __future__ import annotations

import csv
import json
import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mjrft.tools.outputs import number
from mjrft.tools.rerun_log import LOG_EVERY

from .artefacts import TRUST_HELP
from .common import (ALGOS, check_env_id, check_int, check_mujoco_env, default_hyperparams, int_arg, make_env,
                     parse_kwargs, progress_bar)
from .train import MODEL_NAME, VECNORM_SUFFIX, find_config, list_checkpoints, load_config, side_file, vecnormalize_file

G = 9.81
COLUMNS = ("episode", "return", "steps", "seconds", "speed", "cot", "sink_mean_mm", "sink_peak_mm", "slip", "fell")
#: the metric columns (averaged over the episodes that did not diverge)
METRICS = COLUMNS[1:-1]
#: printed headers (name, unit) of the metric columns
HEADERS = {
    "return": ("return", ""), "steps": ("steps", ""), "speed": ("speed", "m/s"), "cot": ("CoT", ""),
    "sink_mean_mm": ("sink mean", "mm"), "sink_peak_mm": ("sink peak", "mm"), "slip": ("foot slip", "m/s"),
    "fell": ("fell", ""),
}


# ---------------------------------------------------------------------------------------------- policies
@dataclass
class LoadedPolicy:
    """What :func:`load_policy` returns: a gait spec still to be bound, or an SB3 model (+ its run config)."""

    source: str
    kind: str  # "gait", "ppo", "sac" or "object"
    model: object = None
    config: dict | None = None
    vecnormalize: object = None  # frozen VecNormalize statistics applied to observations
    note: str = ""  # which file of a run folder is used, when it is not model.zip, and why

    def bind(self, env):
        """A ``predict``-able policy for ``env`` (gaits are bound to the env's simulation clock)."""
        if self.kind == "gait":
            from mjrft.tools.gaits import make_gait

            return make_gait(self.source, env)
        space = getattr(self.model, "observation_space", None)
        if space is not None and space.shape != env.observation_space.shape:
            raise ValueError(f"policy {self.source} expects observations of shape {space.shape}, but "
                             f"{env.spec.id if env.spec else env} gives {env.observation_space.shape}")
        return self

    def predict(self, observation, state=None, episode_start=None, deterministic: bool = True):
        if self.vecnormalize is not None:
            observation = self.vecnormalize.normalize_obs(np.asarray(observation))
        return self.model.predict(observation, state=state, episode_start=episode_start, deterministic=deterministic)


def algo_of_zip(path) -> str:
    """``"ppo"`` or ``"sac"`` from a saved SB3 zip (the algorithm whose hyper-parameters it stores)."""
    from .artefacts import zip_data

    data = zip_data(path)
    missing = {a: sum(k not in data and f"_{k}" not in data for k in default_hyperparams(a)) for a in ALGOS}
    return min(missing, key=missing.get)


#: policy spec prefix of the policies shipped with mjrft: ``pretrained:HexapodSand-v0``
PRETRAINED = "pretrained:"
PRETRAINED_DIR = Path(__file__).resolve().parent / "pretrained"


def pretrained_names() -> list[str]:
    """Names of the bundled policies (``pretrained:<name>``): one run folder each in ``mjrft/train/pretrained``."""
    return sorted(p.name for p in PRETRAINED_DIR.glob("*") if (p / MODEL_NAME).is_file())


def pretrained_path(spec: str) -> Path:
    """The run folder of ``pretrained:<name>`` (``<name>`` may carry the ``mjrft/`` prefix of the env id)."""
    name = spec[len(PRETRAINED):].removeprefix("mjrft/")
    if name not in pretrained_names():
        from mjrft.errors import unknown

        raise unknown("pretrained policy", spec, [PRETRAINED + n for n in pretrained_names()])
    return PRETRAINED_DIR / name


def model_file(policy) -> Path:
    """The model zip of a zip path (``.zip`` may be left out), a run folder or ``pretrained:<name>`` (for a
    folder: the newest complete model, :func:`resolve_model`)."""
    return resolve_model(policy)[0]


def resolve_model(policy) -> tuple[Path, str]:
    """(model zip, note) of a zip path, a run folder or ``pretrained:<name>``.

    For a run folder this is the newest model that is complete: ``model.zip`` unless a checkpoint is newer
    (the run was killed after its last checkpoint) or ``model.zip`` is missing or damaged; the note then
    says which file is used and why (else it is empty). A damaged or incomplete file given by its own path
    raises :class:`mjrft.train.artefacts.ArtefactError` naming it.
    """
    from .artefacts import check_model

    path = pretrained_path(policy) if isinstance(policy, str) and policy.startswith(PRETRAINED) else Path(policy)
    if path.is_dir():
        return _newest_model(path)
    if not path.is_file() and path.suffix != ".zip" and path.with_name(path.name + ".zip").is_file():
        path = path.with_name(path.name + ".zip")
    if not path.is_file():
        from mjrft.tools.gaits import GAITS

        raise ValueError(f"policy {str(policy)!r} is neither a file nor a gait spec; give a model .zip, a run "
                         f"folder or a gait ({', '.join(sorted(GAITS))}, e.g. tripod:f=2.0)")
    check_model(path)
    _check_vecnormalize(path)
    return path, ""


def _check_vecnormalize(path: Path) -> None:
    """A model of a run trained with ``normalize`` needs its VecNormalize statistics next to it."""
    from .artefacts import ArtefactError

    cfg = run_config(path)
    if cfg is not None and cfg.get("normalize") and vecnormalize_file(path) is None:
        raise ArtefactError(f"{side_file(path, VECNORM_SUFFIX)}: missing, but {path.name} was trained with "
                            f"normalised observations ({find_config(path)} says normalize: true)")


#: damaged config.json files already reported in this process (each is said once)
_REPORTED_CONFIGS: set = set()


def run_config(model_path) -> dict | None:
    """The ``config.json`` of the run a model zip belongs to; None when it has none, and None (with one warning
    naming the file, once) when it is damaged: the model stays usable, its algorithm read from the zip, its
    env given with ``--env``. Resuming such a run is refused (:func:`mjrft.train.train.train`)."""
    import warnings

    from .artefacts import ArtefactError, SkippedArtefactWarning

    cfg_path = find_config(model_path)
    if cfg_path is None:
        return None
    try:
        return load_config(cfg_path)
    except ArtefactError as exc:
        if str(cfg_path.resolve()) not in _REPORTED_CONFIGS:
            _REPORTED_CONFIGS.add(str(cfg_path.resolve()))
            warnings.warn(f"{exc}; the model is used without it (its algorithm read from the zip; give the env "
                          f"with --env)", SkippedArtefactWarning, stacklevel=3)
        return None


def _newest_model(folder: Path) -> tuple[Path, str]:
    from .artefacts import ArtefactError, check_model

    main = folder / MODEL_NAME
    candidates = [(step, 1, p) for step, p in list_checkpoints(folder)]
    problems = {}
    if main.is_file():
        try:
            candidates.append((check_model(main), 2, main))  # on a tie model.zip wins
        except ArtefactError as exc:
            problems[main] = str(exc)
    for step, _, path in sorted(candidates, reverse=True):
        try:
            check_model(path)
            _check_vecnormalize(path)
        except ArtefactError as exc:
            problems[path] = str(exc)
            continue
        if path == main:
            return path, ""
        used = f"using {path.relative_to(folder)} ({step} steps)"
        if main in problems:
            why = problems[main]
        elif not main.is_file():
            why = f"{main} is missing (the run did not end cleanly)"
        else:
            main_step = next(s for s, _, p in candidates if p == main)
            why = f"{main} ({main_step} steps) is older (the run did not end cleanly)"
        skipped = [problems[p] for p in problems if p != main]
        return path, "; ".join([why, *skipped, used])
    if not candidates and not problems:
        raise ValueError(f"policy folder {str(folder)!r} holds no {MODEL_NAME} and no checkpoints; give a model "
                         f".zip, a run folder of 'mjrft train' or a gait spec")
    raise ArtefactError(f"{folder}: no model in it loads: " + "; ".join(problems.values()))


def trained_env(policy) -> tuple[str, dict]:
    """(env id, env kwargs) a model zip / run folder / ``pretrained:`` policy was trained on (its config.json)."""
    from mjrft.tools.gaits import is_gait_spec

    if isinstance(policy, str) and is_gait_spec(policy):
        raise ValueError(f"give the env id (--env) for the gait {policy!r}")
    model = model_file(policy)
    cfg = run_config(model)
    if cfg is None:
        what = "readable " if find_config(model) is not None else ""
        raise ValueError(f"{str(policy)!r} has no {what}config.json of its run to take the env from; give the env "
                         f"id (--env)")
    return cfg["env_id"], dict(cfg.get("env_kwargs") or {})


def load_policy(policy, device: str = "cpu", *, env=None, trust: bool = False) -> LoadedPolicy:
    """A gait spec, an SB3 zip / run folder (see the module doc), or an object with ``predict``.

    Nothing is unpickled (:mod:`mjrft.train.artefacts`): the model's spaces are those of ``env`` when it
    is given (else read from the zip), and a file that needs pickle raises
    :class:`~mjrft.train.artefacts.NeedsTrustError` unless ``trust=True``. For a run folder the newest
    complete model is used (:func:`resolve_model`); ``LoadedPolicy.note`` says so when it is not model.zip.
    """
    from mjrft.tools.gaits import is_gait_spec

    from .artefacts import load_model, load_vecnormalize

    if hasattr(policy, "predict") and not isinstance(policy, (str, Path)):
        return LoadedPolicy(type(policy).__name__, "object", model=policy)
    if isinstance(policy, str) and is_gait_spec(policy):
        from mjrft.tools.gaits import parse_gait_spec

        parse_gait_spec(policy)  # a bad parameter fails here, before any env is built
        return LoadedPolicy(policy, "gait")
    if _is_mjx_policy(policy):  # a run folder of `mjrft train-mjx` (Brax PPO): plain arrays, nothing unpickled
        from .mjx_ppo import load_policy as load_mjx_policy

        mjx_policy = load_mjx_policy(policy)
        return LoadedPolicy(str(policy), "brax-ppo", model=mjx_policy, config=mjx_policy.meta)
    path, note = resolve_model(policy)
    config = run_config(path)
    algo = config["algo"] if config and "algo" in config else algo_of_zip(path)
    vn_path = vecnormalize_file(path)
    vecnorm = load_vecnormalize(vn_path, trust) if vn_path is not None else None
    spaces = None if env is None else (env.observation_space, env.action_space)
    model = load_model(algo, path, spaces=spaces, device=device, hyperparams=(config or {}).get("hyperparams"),
                       trust=trust)
    return LoadedPolicy(str(path), algo, model=model, config=config, vecnormalize=vecnorm, note=note)


def policy_config(policy) -> dict | None:
    """The run config (config.json) of a model zip / run folder / ``pretrained:`` policy; None for a gait,
    an object or a zip without one. Checks the model file (:func:`resolve_model`) on the way."""
    from mjrft.tools.gaits import is_gait_spec

    if not isinstance(policy, (str, Path)) or (isinstance(policy, str) and is_gait_spec(policy)):
        return None
    if _is_mjx_policy(policy):
        from .mjx_ppo import read_meta

        meta = read_meta(policy)
        if meta["env_id"] is None:  # an MJX env without a gymnasium twin (the Go2 joystick task)
            raise ValueError(f"{policy} was trained on {meta.get('env')}, an MJX env with no gymnasium env of the same "
                             "task: mjrft eval has no CPU env to run it on (its results are Brax's evaluations in "
                             "its progress.csv)")
        return {"env_id": meta["env_id"], "env_kwargs": meta.get("env_kwargs") or {}}
    return run_config(resolve_model(policy)[0])


# ---------------------------------------------------------------------------------------------- metrics
def _granular_wrapper(env):
    """The :class:`mjrft.envs.wrapper.GranularWrapper` in ``env``'s wrapper chain, or None."""
    from mjrft.envs.wrapper import GranularWrapper

    while env is not None:
        if isinstance(env, GranularWrapper):
            return env
        env = getattr(env, "env", None)
    return None


class _Meter:
    """Accumulates one episode's metrics from the env's info dicts and terrain state."""

    def __init__(self, env):
        u = env.unwrapped
        self.env = u
        self.dt = float(u.dt)
        self.mass = float(u.model.body_subtreemass[0])
        sand = _granular_wrapper(env)  # a third-party env on sand: its selected bodies are the feet
        self.sand_terrain = None if sand is None else sand.terrain
        if sand is not None:
            self.foot_ids, terrain = np.asarray(sand.body_ids, dtype=np.int64), sand.terrain
        else:  # mjrft's envs name their feet; another MuJoCo env has none to measure
            self.foot_ids = np.array([u.model.body(n).id for n in getattr(u, "foot_names", ())], dtype=np.int64)
            terrain = getattr(u, "terrain", None)
        self.terrain = terrain
        self.foot_elems = None if terrain is None else np.flatnonzero(np.isin(terrain.elem_body, self.foot_ids))
        self._jac = np.zeros((3, u.model.nv))

    def _x(self, info) -> float:
        """The torso's x: ``info["x_position"]``, else the first coordinate of the root joint (``qpos[0]``)."""
        return float(info["x_position"]) if "x_position" in info else float(self.env.data.qpos[0])

    def start(self, info) -> None:
        self.x0 = self._x(info)
        self.x = self.x0
        self.ret = 0.0
        self.steps = 0
        self.energy = 0.0
        self.sink_sum = 0.0
        self.sink_n = 0
        self.sink_peak = 0.0
        self.slip_num = 0.0
        self.slip_den = 0.0
        self.diverged = ""

    def step(self, reward, info) -> None:
        if info.get("diverged"):
            self.diverged = str(info["diverged"])
        self.ret += float(reward)
        self.steps += 1
        self.x = self._x(info)
        power = info["power"] if "power" in info else self._step_power()
        self.energy += float(power) * self.dt
        sink = np.asarray(info.get("sinkage", ()), dtype=float)
        inside = sink > 0
        self.sink_sum += float(sink[inside].sum())
        self.sink_n += int(inside.sum())
        if sink.size:
            self.sink_peak = max(self.sink_peak, float(sink.max()))
        num, den = self._slip()
        self.slip_num += num
        self.slip_den += den

    def _step_power(self) -> float:
        """The actuators' mechanical power (W) of the last step, for envs whose info has no ``power``: on sand
        (``GranularWrapper``) its mean over the step's physics steps, else ``sum |force x velocity|`` now."""
        if self.sand_terrain is not None:
            return self.sand_terrain.actuator_power
        return self._power()

    def _power(self) -> float:
        """Mechanical power (W) of the actuators, ``sum |force x velocity|`` at the current state."""
        d = self.env.data
        return float(np.sum(np.abs(d.actuator_force * d.actuator_velocity)))

    def _slip(self) -> tuple[float, float]:
        u = self.env
        if self.foot_elems is not None:
            t = self.terrain
            e = self.foot_elems[t.depth[self.foot_elems] > 0]
            if e.size == 0:
                return 0.0, 0.0
            speed = np.hypot(t.vel[e, 0], t.vel[e, 1])
            return float(np.sum(t.area[e] * speed)), float(np.sum(t.area[e]))
        import mujoco

        m, d = u.model, u.data
        num = den = 0.0
        for c in d.contact[: d.ncon]:
            b1, b2 = m.geom_bodyid[c.geom1], m.geom_bodyid[c.geom2]
            for foot, other in ((b1, b2), (b2, b1)):
                if other == 0 and foot in self.foot_ids:
                    mujoco.mj_jac(m, d, self._jac, None, c.pos, foot)
                    v = self._jac @ d.qvel
                    num += float(np.hypot(v[0], v[1]))
                    den += 1.0
        return num, den

    def row(self, episode: int, terminated: bool) -> dict:
        seconds = self.steps * self.dt
        dx = self.x - self.x0
        return {
            "episode": episode,
            "return": self.ret,
            "steps": self.steps,
            "seconds": seconds,
            "speed": dx / seconds if seconds > 0 else 0.0,
            "cot": self.energy / (self.mass * G * max(abs(dx), 1e-3 * seconds, 1e-12)),
            "sink_mean_mm": 1e3 * self.sink_sum / self.sink_n if self.sink_n else 0.0,
            "sink_peak_mm": 1e3 * self.sink_peak,
            "slip": self.slip_num / self.slip_den if self.slip_den > 0 else 0.0,
            "fell": bool(terminated) and not self.diverged,
            "diverged": self.diverged,  # the NonFiniteError message when the simulation diverged, else ""
        }


def summarize(rows: list[dict]) -> dict:
    """Mean and standard deviation (population) of every metric and the fall rate, over the episodes that
    did not diverge (NaN when none is left), and the count of diverged ones."""
    ok = [r for r in rows if not r.get("diverged")]
    out = {"episodes": len(rows), "diverged": len(rows) - len(ok)}
    for key in METRICS:
        vals = np.array([r[key] for r in ok], dtype=float)
        out[key] = float(vals.mean()) if ok else math.nan
        out[key + "_std"] = float(vals.std()) if ok else math.nan
    out["fall_rate"] = float(np.mean([r["fell"] for r in ok])) if ok else math.nan
    return out


# ---------------------------------------------------------------------------------------------- evaluation
def evaluate(policy_or_spec, env_id: str | None = None, episodes: int = 10, seed: int = 0,
             env_kwargs: dict | None = None, deterministic: bool = True, rrd=None, *, device: str = "cpu",
             log_every: int = LOG_EVERY, progress: bool = False, trust: bool = False) -> tuple[list[dict], dict]:
    """Run ``episodes`` episodes of a policy or gait; return (per-episode rows, summary) (module doc).

    ``env_id`` / ``env_kwargs`` default to those of the run a model zip belongs to (given kwargs
    override the saved ones); a gait needs ``env_id``. ``rrd``: log the first episode to this rerun
    file (every ``log_every``-th step) with :mod:`mjrft.tools.rerun_log`. ``progress``: a progress bar (tqdm,
    on stderr) over the episodes' env steps (an episode that ends early jumps to its end). ``trust``: also
    load model files that need pickle (:func:`load_policy`). The summary's ``note`` says which file of a
    run folder was used when it is not its model.zip.
    """
    from mjrft.tools.gaits import is_gait_spec

    episodes = check_int("episodes", episodes, 1)
    seed = check_int("seed", seed, 0)
    log_every = check_int("log_every", log_every, 1)
    is_file = isinstance(policy_or_spec, (str, Path)) and not (isinstance(policy_or_spec, str)
                                                               and is_gait_spec(policy_or_spec))
    # a gait or an object is checked now; a model file is checked now (cheaply) and loaded with the env's spaces
    loaded = None if is_file else load_policy(policy_or_spec, device=device)
    cfg = policy_config(policy_or_spec) or {}
    env_id = env_id or cfg.get("env_id")
    if env_id is None:
        from mjrft.envs import ENV_IDS

        damaged = is_file and not cfg and find_config(model_file(policy_or_spec)) is not None
        why = " (its run's config.json cannot be read)" if damaged else ""
        raise ValueError(f"give the env id for policy {str(policy_or_spec)!r}{why} (valid choices: "
                         f"{', '.join(sorted(ENV_IDS))})")
    check_env_id(env_id)
    kwargs = {**(cfg.get("env_kwargs") or {}), **(env_kwargs or {})}
    if is_file:  # importing torch changes the last bits of the env's construction: import it first, always
        import stable_baselines3  # noqa: F401
    env = make_env(env_id, kwargs)
    rows = []
    try:
        check_mujoco_env(env, env_id)
        if loaded is None:
            loaded = load_policy(policy_or_spec, device=device, env=env, trust=trust)
        policy = loaded.bind(env)
        if loaded.model is not None and hasattr(loaded.model, "set_random_seed"):
            loaded.model.set_random_seed(seed)
        meter = _Meter(env)
        limit = env.spec.max_episode_steps if env.spec is not None else None
        bar = progress_bar(episodes * limit if limit else None, f"eval ({episodes} episodes)", progress)
        for ep in range(episodes):
            logger = _open_logger(rrd, env, loaded.source) if (rrd is not None and ep == 0) else None
            try:
                rows.append(_episode(env, policy, meter, ep, seed + ep, deterministic, logger, log_every, bar))
            finally:
                if logger is not None:
                    logger.close()
            if limit:
                bar.update((ep + 1) * limit - bar.n)
        bar.close()
    finally:
        env.close()
    summary = summarize(rows)
    summary.update(policy=loaded.source, kind=loaded.kind, env_id=env_id, env_kwargs=kwargs, seed=seed,
                   deterministic=bool(deterministic), note=loaded.note)
    return rows, summary


def _episode(env, policy, meter, ep, seed, deterministic, logger, log_every, bar) -> dict:
    obs, info = env.reset(seed=seed)
    meter.start(info)
    state, start = None, np.ones(1, dtype=bool)
    terminated = truncated = False
    if logger is not None:
        logger.log(env)
    while not (terminated or truncated):
        action, state = policy.predict(obs, state=state, episode_start=start, deterministic=deterministic)
        start = np.zeros(1, dtype=bool)
        obs, reward, terminated, truncated, info = env.step(action)
        meter.step(reward, info)
        bar.update(1)
        if logger is not None and meter.steps % log_every == 0:
            logger.log(env)
    return meter.row(ep, terminated)


def _open_logger(rrd, env, source):
    """The rerun logger of :mod:`mjrft.tools.rerun_log` writing ``rrd`` (see that module)."""
    from mjrft.tools import rerun_log

    return rerun_log.episode_logger(rrd, env, name=f"mjrft eval {source}")


# ---------------------------------------------------------------------------------------------- output
def format_table(rows: list[dict], summary: dict) -> str:
    keys = [k for k in COLUMNS[1:] if k != "seconds"]
    heads = [HEADERS[k][0] for k in keys]
    units = [HEADERS[k][1] for k in keys]
    width = [max(9, len(h) + 1) for h in heads]

    def fmt(key, v):
        if isinstance(v, float) and math.isnan(v):
            return "-"  # every episode diverged: no mean
        if key == "fell":
            return "yes" if v else "no"
        if key == "steps":
            return f"{v:.0f}" if float(v).is_integer() else f"{v:.1f}"
        if key in ("cot",) and abs(v) >= 1e3:
            return number(v, ".3g")
        return number(v, ".3f" if key in ("speed", "slip") else ".2f")

    lines = ["episode " + "".join(f"{h:>{w}s}" for h, w in zip(heads, width)),
             "        " + "".join(f"{u:>{w}s}" for u, w in zip(units, width))]
    for r in rows:
        if r.get("diverged"):
            lines.append(f"{r['episode']:>7d}  DIVERGED after {r['steps']} steps (no metrics): {r['diverged']}")
            continue
        lines.append(f"{r['episode']:>7d} " + "".join(f"{fmt(k, r[k]):>{w}s}" for k, w in zip(keys, width)))
    for label, suffix in (("mean", ""), ("std", "_std")):
        cells = []
        for k, w in zip(keys, width):
            if k == "fell":
                rate = summary["fall_rate"]
                cells.append(("-" if math.isnan(rate) else f"{rate:.0%}") if label == "mean" else "")
            else:
                cells.append(fmt(k, summary[k + suffix]))
        lines.append(f"{label:>7s} " + "".join(f"{c:>{w}s}" for c, w in zip(cells, width)))
    n_fell = sum(r["fell"] for r in rows)
    n_ok = len(rows) - summary.get("diverged", 0)
    if n_ok:
        lines.append(f"fall rate {summary['fall_rate']:.0%} ({n_fell} of {n_ok} episodes terminated before the "
                     f"time limit)")
    if summary.get("diverged"):
        lines.append(f"DIVERGED: {summary['diverged']} of {len(rows)} episodes (left out of mean and std)")
    return "\n".join(lines)


def write_csv(path, rows: list[dict], summary: dict) -> None:
    """Per-episode rows, then ``mean`` and ``std`` rows (``fell`` of the mean row is the fall rate)."""
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=(*COLUMNS, "diverged"))
        w.writeheader()
        for r in rows:
            w.writerow({**r, "fell": int(r["fell"])})
        w.writerow({"episode": "mean", **{k: summary[k] for k in METRICS}, "fell": summary["fall_rate"],
                    "diverged": summary["diverged"]})
        w.writerow({"episode": "std", **{k: summary[k + "_std"] for k in METRICS}, "fell": ""})


def write_json(path, rows: list[dict], summary: dict) -> None:
    def clean(v):
        return v if not isinstance(v, float) or math.isfinite(v) else repr(v)

    data = {"summary": {k: clean(v) for k, v in summary.items()},
            "episodes": [{k: clean(v) for k, v in r.items()} for r in rows]}
    with open(path, "w") as fh:
        json.dump(data, fh, indent=2)
        fh.write("\n")


# ---------------------------------------------------------------------------------------------- CLI
def add_arguments(parser) -> None:
    parser.add_argument("--policy", required=True,
                        help="model .zip or run folder from 'mjrft train', pretrained:HexapodSand-v0 (a policy shipped "
                             "with mjrft), or a gait spec such as tripod:f=2.0")
    parser.add_argument("--env", dest="env_id", default=None,
                        help="environment id (default: the one the model was trained on; required for a gait)")
    parser.add_argument("--episodes", type=int_arg, default=10, help="episodes (default 10)")
    parser.add_argument("--seed", type=int_arg, default=0, help="episode i resets with seed + i (default 0)")
    parser.add_argument("--stochastic", action="store_true", help="sample actions instead of the mean action")
    parser.add_argument("--device", default="cpu", help="torch device for a model (default cpu)")
    parser.add_argument("--csv", default=None, metavar="FILE", help="also write the table as CSV")
    parser.add_argument("--json", default=None, metavar="FILE", help="also write rows and summary as JSON")
    parser.add_argument("--rrd", default=None, metavar="FILE", help="log the first episode to a rerun file")
    parser.add_argument("--log-every", type=int_arg, default=LOG_EVERY,
                        help=f"with --rrd: log every N-th env step (default {LOG_EVERY})")
    parser.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar")
    parser.add_argument("--trust", action="store_true", help=TRUST_HELP)
    parser.add_argument("--backend", choices=("cpu", "mjx"), default="cpu",
                        help="cpu: the gymnasium env (default); mjx: a policy of 'mjrft train-mjx' on the MJX env, "
                             "all episodes as one batch (mjrft.train.mjx_ppo.evaluate_mjx)")
    parser.add_argument("env_kwargs", nargs="*", metavar="KEY=VALUE",
                        help="environment keyword arguments (override the run's), e.g. max_episode_steps=500; "
                             "with --backend mjx the MJX env's configuration overrides, e.g. terrain.medium=poppy_lp")



def main(args) -> int:
    from mjrft.tools.outputs import WarningNotes, output_file

    env_kwargs = parse_kwargs(args.env_kwargs, "env kwarg")
    if args.backend == "mjx":
        return _main_mjx(args, env_kwargs)
    for option in ("csv", "json", "rrd"):
        if getattr(args, option):
            output_file(getattr(args, option), f"--{option}")
    with WarningNotes() as notes:  # the warnings become notes under the table, as for mjrft demo
        announce_model(args.policy)
        rows, summary = evaluate(args.policy, args.env_id, args.episodes, args.seed, env_kwargs,
                                 deterministic=not args.stochastic, rrd=args.rrd, device=args.device,
                                 log_every=args.log_every, progress=args.progress, trust=args.trust)
    kw = ", ".join(f"{k}={v}" for k, v in summary["env_kwargs"].items())
    print(f"{summary['policy']} on {summary['env_id']}" + (f" ({kw})" if kw else "")
          + f", {len(rows)} episode(s), seed {args.seed}, {'deterministic' if not args.stochastic else 'stochastic'}")
    print(format_table(rows, summary))
    notes.print()
    for path, writer in ((args.csv, write_csv), (args.json, write_json)):
        if path:
            writer(path, rows, summary)
            print(f"wrote {path}")
    if args.rrd:
        print(f"wrote {args.rrd} (first episode); open it with: rerun {args.rrd}")
    if rows and summary["diverged"] == len(rows):
        print(f"mjrft eval: every episode ({len(rows)}) diverged: no metrics (exit status {DIVERGED_EXIT})",
              file=sys.stderr)
        return DIVERGED_EXIT
    return 0


def _main_mjx(args, overrides: dict) -> int:
    """``mjrft eval --backend mjx``: the policy of an MJX run folder on its MJX env, every episode in one batch;
    ``overrides``: the command line's KEY=VALUE, configuration overrides of the MJX env (``terrain.medium=...``)."""
    if not _is_mjx_policy(args.policy):
        raise ValueError(f"--backend mjx evaluates a run folder of 'mjrft train-mjx' (policy.json + policy.npz); "
                         f"{args.policy!r} is not one")
    for option in ("csv", "rrd", "env_id"):
        if getattr(args, option):
            raise ValueError(f"--{option.replace('_id', '')} is an option of the CPU backend only")
    from .mjx_ppo import evaluate_mjx, load_policy as load_mjx_policy

    policy = load_mjx_policy(args.policy)
    res = evaluate_mjx(policy, episodes=args.episodes, seed=args.seed, config_overrides=overrides)
    print(f"{args.policy} on the MJX env {res['env']} ({res['device']}), {res['episodes']} episode(s), seed "
          f"{args.seed}, deterministic")
    print(f"  speed {res['speed']:.3f} +- {res['speed_std']:.3f} m/s   CoT {res['cost_of_transport']:.2f}   "
          f"fell {res['fell']:.0%}   diverged {res['diverged']}   sand unstable {res['unstable']}, "
          f"out of its law's range {res['out_of_range']} (episodes)")
    if args.json:
        Path(args.json).write_text(json.dumps(res, indent=2) + "\n")
        print(f"wrote {args.json}")
    return DIVERGED_EXIT if res["diverged"] == res["episodes"] else 0


#: exit status of ``mjrft eval`` / ``mjrft rollout`` when the simulation diverged in every episode
DIVERGED_EXIT = 1


def _is_mjx_policy(policy) -> bool:
    """Whether ``policy`` names a run folder of ``mjrft train-mjx`` (:mod:`mjrft.train.mjx_ppo`)."""
    from .mjx_ppo import is_mjx_policy

    return isinstance(policy, (str, Path)) and not str(policy).startswith(PRETRAINED) and is_mjx_policy(policy)


def announce_model(policy) -> None:
    """Print which file of a run folder a command uses when it is not its model.zip (and why)."""
    from mjrft.tools.gaits import is_gait_spec

    if isinstance(policy, str) and not is_gait_spec(policy) and not _is_mjx_policy(policy):
        note = resolve_model(policy)[1]
        if note:
            print(f"note: {note}")

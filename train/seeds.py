"""A recipe over several seeds: one run per seed, the spread of each result over the seeds and the table that
reports it.

Each seed is a run of its own (``mjrft train --seed S`` / ``mjrft train-mjx --seed S``, each in its own run folder);
:func:`spread` gives a measure's mean, sample standard deviation and range over the seeds, and :func:`seeds_table`
writes one row per seed and the mean, sample standard deviation, minimum and maximum of every column, as
``benchmarks/results/learning/recipe_seeds.txt`` reports the SB3 recipe ``hexapod-sand`` over three seeds.

``--seeds`` of either trainer runs the loop :func:`run_seeds`: each seed's run in ``OUT/seed-<S>/`` (the run folder
of the one-seed command with ``--seed S --out OUT/seed-<S>``; a folder that holds a complete run of the same recipe
and seed is not trained again, a folder of another recipe is refused before any seed trains), each final policy
evaluated (kept in the seed's ``evaluation.json``), and after every seed the summary over the seeds in
``OUT/seeds.txt`` (the table and the equivalent one-seed commands) and ``OUT/seeds.json`` (the rows and each
column's spread):

* ``mjrft train --config hexapod-sand --out runs/hexapod-sand-seeds --seeds 0 1 2`` (:func:`train_sb3_seeds`):
  stable-baselines3; an interrupted seed resumes from its newest checkpoint; each policy evaluated as ``mjrft eval``
  does (:func:`evaluate_sb3_run`: 10 deterministic episodes by default), with the training's wall time and the
  warnings it raised;
* ``mjrft train-mjx --config biped-sand --out runs/biped --seeds 0 1 2`` (:func:`train_seeds`): Brax PPO; each
  policy evaluated on the MJX env and on the CPU env of the same task (:func:`evaluate_run`, the cross-check of the
  two backends).
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import numpy as np

from .mjx_ppo import evaluate_mjx, is_mjx_policy, load_policy, read_meta, train_recipe

#: a several-seed run: the summary over the seeds (JSON, text); each seed's evaluation in its run folder
SEEDS_FILE, SEEDS_TABLE, EVALUATION_FILE = "seeds.json", "seeds.txt", "evaluation.json"


def spread(values) -> dict:
    """Mean, sample standard deviation (``ddof=1``; NaN for fewer than two values), minimum and maximum of the
    finite ``values``, and their count ``n`` (a seed whose measure is NaN or None, e.g. every episode diverged, as
    an ``evaluation.json`` read back holds it, is left out and counted out of ``n``); NaN everywhere when none is
    finite."""
    v = np.asarray([math.nan if x is None else float(x) for x in values], dtype=float)
    v = v[np.isfinite(v)]
    if not v.size:
        return {"n": 0, "mean": math.nan, "sd": math.nan, "min": math.nan, "max": math.nan}
    return {"n": int(v.size), "mean": float(v.mean()), "sd": float(v.std(ddof=1)) if v.size > 1 else math.nan,
            "min": float(v.min()), "max": float(v.max())}


def _cell(value, digits: int, width: int) -> str:
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return f"{'-':>{width}}"
    return f"{value:>{width}.{digits}f}"


def seeds_table(rows: list[dict], columns: list[tuple[str, str, int]]) -> str:
    """One line per seed (``row["seed"]``) and the mean, sample standard deviation, minimum and maximum over the
    seeds of every column; ``columns``: (key, header, decimals). A missing or non-finite value prints ``-``."""
    width = max([10] + [len(h) + 1 for _, h, _ in columns])
    lines = ["seed  " + "".join(f"{h:>{width}}" for _, h, _ in columns)]
    for row in rows:
        lines.append(f"{row['seed']:>4}  " + "".join(_cell(row.get(k), d, width) for k, _, d in columns))
    stats = {k: spread([r.get(k, math.nan) for r in rows]) for k, _, _ in columns}
    for name in ("mean", "sd", "min", "max"):
        lines.append(f"{name:>4}  " + "".join(_cell(stats[k][name], d, width) for k, _, d in columns))
    lines.append("(sd: the sample standard deviation over the seeds; '-': not measured, or fewer than two seeds)")
    return "\n".join(lines)


def check_seeds(seeds) -> list[int]:
    """``--seeds``: integers >= 0, each once."""
    seeds = list(seeds)
    if not seeds or any(isinstance(s, bool) or not isinstance(s, int) or s < 0 for s in seeds):
        raise ValueError(f"--seeds must be integers >= 0, got {seeds!r}")
    if len(set(seeds)) != len(seeds):
        raise ValueError(f"--seeds must name each seed once, got {seeds!r}")
    return seeds


def seed_folder(out, seed: int) -> Path:
    """The run folder of ``seed`` in a several-seed run ``out`` (``out/seed-<seed>``)."""
    return Path(out) / f"seed-{int(seed)}"


def run_seeds(out, seeds, done: dict, train_one, evaluate_one, evaluation: dict, summarize, describe, lines, *,
              report=print, writer: bool = True) -> dict:
    """The several-seed run of either trainer (``mjrft train --seeds``, ``mjrft train-mjx --seeds``): for each seed
    in turn, ``train_one(seed, folder)`` trains its :func:`seed_folder` unless ``done[seed]`` (a complete run of
    the same recipe and seed), then ``evaluate_one(folder)`` gives its row of results, kept in the folder's
    ``evaluation.json`` with the ``evaluation`` settings (the episode counts; a later invocation with the same
    settings reuses it, a seed trained again drops it), and ``summarize(rows)`` / ``describe(summary)`` give
    ``out/seeds.json`` and the text of ``out/seeds.txt``, both rewritten after every seed. ``lines(row)``: the
    lines that report a seed's row. ``writer`` False (a host of a multi-host run other than the first): train
    only. Returns the summary over the seeds that finished."""
    out = Path(out)
    rows, summary = [], {}
    for s in seeds:
        folder = seed_folder(out, s)
        saved = folder / EVALUATION_FILE
        if done[s]:
            report(f"seed {s}: {folder} holds the complete run of this recipe; not trained again")
        else:
            if writer and saved.exists():
                saved.unlink()
            train_one(s, folder)
        if not writer:
            continue
        row = None
        if saved.is_file():  # an earlier invocation's evaluation of this complete run, with the same episodes
            kept = json.loads(saved.read_text())
            if all(kept.get(k) == v for k, v in evaluation.items()):
                row = kept["row"]
        if row is None:
            row = evaluate_one(folder)
            _write_json(saved, {**evaluation, "row": row})
        rows.append({"seed": s, **row})
        for line in lines(row):
            report(f"seed {s}: {line}")
        summary = summarize(rows)
        _write_json(out / SEEDS_FILE, summary)
        tmp = out / (SEEDS_TABLE + ".tmp")
        tmp.write_text(describe(summary) + "\n")
        os.replace(tmp, out / SEEDS_TABLE)
    if writer:
        report(describe(summary))
        report(f"wrote {out / SEEDS_TABLE} and {out / SEEDS_FILE}")
    return summary


# ---------------------------------------------------------------------- MJX recipes over several seeds
def _same_recipe(meta: dict, cfg: dict) -> bool:
    """Whether a run's recipe (its ``policy.json``) is ``cfg``, the description aside."""
    def settings(recipe):
        return {k: v for k, v in (recipe or {}).items() if k != "description"}

    return settings(meta.get("recipe")) == settings(json.loads(json.dumps(cfg)))


def completed_run(folder, cfg: dict) -> bool:
    """Whether ``folder`` holds a complete run of the recipe ``cfg`` (``policy.json``: ``"complete": true`` and
    the same recipe); a complete run of another recipe is refused (one line naming the folder), an incomplete or
    missing one is trained (again)."""
    folder = Path(folder)
    if not is_mjx_policy(folder):
        return False
    meta = read_meta(folder)
    if not meta.get("complete"):
        return False
    if not _same_recipe(meta, cfg):
        raise ValueError(f"{folder} holds a complete run of another recipe (or seed); give another --out")
    return True


def evaluate_run(folder, eval_episodes: int = 8, cpu_episodes: int = 10) -> dict:
    """The results of a finished run folder: the return of Brax's final evaluation (``eval/episode_reward`` of
    ``policy.json``), the training's wall time, and the deterministic policy's speed, cost of transport, fall rate
    and diverged episodes over ``eval_episodes`` episodes of 10 s on its MJX env (:func:`evaluate_mjx`, ``mjx_*``)
    and over ``cpu_episodes`` on the gymnasium env of the same task (``mjrft eval``'s
    :func:`mjrft.train.evaluate.evaluate`, ``cpu_*``): the cross-check of the two backends. An environment without
    a gymnasium twin (the Go2 joystick task) has the return and the wall time only."""
    meta = read_meta(folder)
    row = {"return": float((meta.get("final") or {}).get("eval/episode_reward", math.nan)),
           "train_s": float(meta.get("wall_s", math.nan)), "eval_episodes": 0, "cpu_episodes": 0}
    if meta.get("env_id") is None:
        return row
    policy = load_policy(folder)
    if eval_episodes > 0:
        res = evaluate_mjx(policy, episodes=eval_episodes)
        row.update(eval_episodes=eval_episodes, mjx_speed=res["speed"], mjx_cot=res["cost_of_transport"],
                   mjx_fell=res["fell"], mjx_diverged=res["diverged"], mjx_unstable=res["unstable"],
                   mjx_out_of_range=res["out_of_range"])
    if cpu_episodes > 0:
        from .evaluate import evaluate

        _, res = evaluate(str(folder), episodes=cpu_episodes)
        row.update(cpu_episodes=cpu_episodes, cpu_speed=res["speed"], cpu_cot=res["cot"], cpu_fell=res["fall_rate"],
                   cpu_diverged=res["diverged"])
    return row


def evaluation_lines(row: dict) -> list[str]:
    """The lines that say a row of :func:`evaluate_run` (one per backend evaluated)."""
    lines = []
    if row.get("eval_episodes"):
        lines.append(f"MJX evaluation ({row['eval_episodes']} episodes of 10 s): speed {row['mjx_speed']:.3f} m/s, "
                     f"CoT {row['mjx_cot']:.2f}, fell {row['mjx_fell']:.0%}, diverged {row['mjx_diverged']}, sand "
                     f"unstable in {row['mjx_unstable']}, out of its law's range in {row['mjx_out_of_range']} episodes")
    if row.get("cpu_episodes"):
        lines.append(f"CPU evaluation ({row['cpu_episodes']} episodes of 10 s, mjrft eval): speed "
                     f"{row['cpu_speed']:.3f} m/s, CoT {row['cpu_cot']:.2f}, fell {row['cpu_fell']:.0%}, "
                     f"diverged {row['cpu_diverged']}")
    return lines


#: the columns of the several-seed summary: (key, header, decimals)
SEED_COLUMNS = [("return", "return", 2), ("train_s", "train s", 1), ("mjx_speed", "MJX m/s", 3),
                ("mjx_cot", "MJX CoT", 2), ("mjx_fell", "MJX fell", 2), ("cpu_speed", "CPU m/s", 3),
                ("cpu_cot", "CPU CoT", 2), ("cpu_fell", "CPU fell", 2)]


def train_seeds(cfg: dict, out, seeds, *, eval_episodes: int = 8, cpu_episodes: int = 10, name: str = "",
                command: str = "", report=print) -> dict:
    """The recipe ``cfg`` once per seed, each run in :func:`seed_folder` (the run of ``mjrft train-mjx --seed S
    --out OUT/seed-S``; a folder that holds a complete run of the same recipe and seed is not trained again),
    each final policy evaluated (:func:`evaluate_run`, kept in the run folder's ``evaluation.json``), and the
    summary over the seeds (:mod:`mjrft.train.seeds`: each seed's row, then mean, sample standard deviation,
    minimum and maximum) written to ``out/seeds.txt`` and ``out/seeds.json`` after every seed; returns the
    summary. ``name``: the recipe's name; ``command``: the ``mjrft train-mjx`` command line of the recipe and its
    overrides, which ``seeds.txt`` repeats for each seed. Over several hosts every host trains each seed and the
    first one evaluates and writes."""
    import jax

    seeds = check_seeds(seeds)
    out = Path(out)
    runs = {s: {**cfg, "seed": s} for s in seeds}
    writer = jax.process_index() == 0
    # which seeds are done (a foreign folder refused before anything trains) is the first host's view, which every
    # host follows, so that all of them train the same seeds
    done = {s: writer and completed_run(seed_folder(out, s), c) for s, c in runs.items()}
    if jax.process_count() > 1:
        from jax.experimental import multihost_utils

        flags = multihost_utils.broadcast_one_to_all(np.array([done[s] for s in seeds]))
        done = {s: bool(f) for s, f in zip(seeds, np.asarray(flags))}

    def train_one(s, folder):
        report(f"seed {s}: Brax PPO on {cfg['env']} ({cfg['num_envs']} worlds, {cfg['num_timesteps']:,} steps) on "
               f"{jax.device_count()} device(s) ({jax.devices()[0].platform}); run folder {folder}")
        train_recipe(runs[s], folder, report=report)

    command = command or f"mjrft train-mjx --config {name}"
    return run_seeds(out, seeds, done, train_one, lambda folder: evaluate_run(folder, eval_episodes, cpu_episodes),
                     {"eval_episodes": eval_episodes, "cpu_episodes": cpu_episodes},
                     lambda rows: _seed_summary(cfg, name, command, out, seeds, rows, eval_episodes, cpu_episodes),
                     _seed_report, evaluation_lines, report=report, writer=writer)


def _strict(value):
    """``value`` with every non-finite float (a spread of one seed, a task without a CPU env) as None, so that the
    file is strict JSON, which every JSON reader takes."""
    if isinstance(value, dict):
        return {k: _strict(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_strict(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _write_json(path: Path, data) -> None:
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(json.dumps(_strict(data), indent=2, allow_nan=False) + "\n")
    os.replace(tmp, path)


def _seed_summary(cfg, name, command, out, seeds, rows, eval_episodes, cpu_episodes) -> dict:
    meta = read_meta(seed_folder(out, rows[0]["seed"]))
    keys = [k for k, _, _ in SEED_COLUMNS]
    return {"recipe": name, "command": command, "out": str(out), "env": cfg["env"], "env_id": meta.get("env_id"),
            "seeds": list(seeds), "finished": [r["seed"] for r in rows], "num_timesteps": cfg["num_timesteps"],
            "num_envs": cfg["num_envs"],
            "eval_episodes": eval_episodes, "cpu_episodes": cpu_episodes, "device": meta.get("device"),
            "devices": meta.get("devices"), "rows": rows,
            "spread": {k: spread([r.get(k, math.nan) for r in rows]) for k in keys}}


def _seed_report(summary: dict) -> str:
    """The text of ``seeds.txt``: what was run, the table, the equivalent commands of each seed."""
    name, env, env_id = summary["recipe"] or "(recipe)", summary["env"], summary["env_id"]
    rows = summary["rows"]
    head = (f"Recipe {name} over {len(summary['seeds'])} seeds ({', '.join(map(str, summary['seeds']))}; "
            f"{len(rows)} finished) on {env}: {summary['num_envs']:,} worlds, {summary['num_timesteps']:,} steps each "
            f"on {summary['devices']} device(s) ({summary['device']})")
    lines = [head, "return: the mean episode return of Brax's final evaluation during training; train s: training "
                   "wall time"]
    if env_id is None:
        lines.append(f"{env} has no gymnasium env of the same task: no MJX or CPU evaluation of speed and cost of "
                     "transport")
    else:
        lines.append(f"MJX: {summary['eval_episodes']} deterministic episodes of 10 s on the MJX env {env} "
                     f"(mjrft eval --backend mjx); CPU: {summary['cpu_episodes']} on the CPU env {env_id} "
                     "(mjrft eval), "
                     "the cross-check of the two backends; CoT from the actuators' power over every physics step; "
                     "fell: the fraction of episodes that ended in a fall")
    lines += ["", seeds_table(rows, SEED_COLUMNS), "", "the same runs and evaluations, one seed at a time:"]
    for s in summary["seeds"]:
        folder = seed_folder(summary["out"], s)
        lines.append(f"$ {summary['command']} --seed {s} --out {folder}")
        if env_id is not None:
            if summary["eval_episodes"]:
                lines.append(f"$ mjrft eval --policy {folder} --episodes {summary['eval_episodes']} --backend mjx")
            if summary["cpu_episodes"]:
                lines.append(f"$ mjrft eval --policy {folder} --episodes {summary['cpu_episodes']}")
    return "\n".join(lines)


# ---------------------------------------------------------------------- SB3 recipes over several seeds
def _wall_seconds(runs) -> float:
    """The wall time of a run folder's training sessions (``config.json``'s ``runs``: started to ended, to the
    second), summed over its resumes; a session killed outright (no end recorded) is not counted."""
    import datetime

    total = 0.0
    for run in runs or ():
        if run.get("started") and run.get("ended"):
            total += (datetime.datetime.fromisoformat(run["ended"])
                      - datetime.datetime.fromisoformat(run["started"])).total_seconds()
    return total


def _warning_counts(folder) -> tuple[int | None, int | None]:
    """(every warning, the terrain's stability warnings) the environments raised while a run trained: the rows of
    its ``warnings.csv`` (None, None when the run has none)."""
    import csv

    from .run_warnings import WARNINGS_CSV

    path = Path(folder) / WARNINGS_CSV
    if not path.is_file():
        return None, None
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    return len(rows), sum(r.get("category") == "TerrainStabilityWarning" for r in rows)


def evaluate_sb3_run(folder, episodes: int = 10) -> dict:
    """The results of a finished ``mjrft train`` run folder: its steps, the training's wall time
    (:func:`_wall_seconds`), the warnings its environments raised while training (``warnings``: all of them,
    ``unstable``: the terrain's stability warnings) and, over ``episodes`` deterministic episodes of its final
    policy on its env (``mjrft eval``'s :func:`mjrft.train.evaluate.evaluate`; 0: none), the mean return, speed,
    cost of transport, sinkage and foot slip, the fall rate and the diverged episodes."""
    from .train import CONFIG_NAME, load_config

    cfg = load_config(Path(folder) / CONFIG_NAME)
    warned, unstable = _warning_counts(folder)
    row = {"num_timesteps": int(cfg["num_timesteps"]), "train_s": _wall_seconds(cfg.get("runs")),
           "warnings": warned, "unstable": unstable, "episodes": episodes}
    if episodes > 0:
        from .evaluate import evaluate

        _, res = evaluate(str(folder), episodes=episodes)
        row.update({k: res[k] for k in ("return", "steps", "speed", "cot", "sink_mean_mm", "sink_peak_mm", "slip")},
                   fell=res["fall_rate"], diverged=res["diverged"])
    return row


def sb3_evaluation_lines(row: dict) -> list[str]:
    """The line that says a row of :func:`evaluate_sb3_run`."""
    warned = "" if row.get("warnings") is None else (f"; {row['warnings']} warning(s) while training, "
                                                      f"{row['unstable']} of the terrain's stability")
    if not row.get("episodes"):
        return [f"{row['num_timesteps']:,} steps trained in {row['train_s']:.0f} s{warned}"]
    return [f"{row['num_timesteps']:,} steps trained in {row['train_s']:.0f} s{warned}; evaluation "
            f"({row['episodes']} deterministic episodes, mjrft eval): return {row['return']:.2f}, speed "
            f"{row['speed']:.3f} m/s, CoT {row['cot']:.2f}, fell {row['fell']:.0%}, sinkage {row['sink_mean_mm']:.2f} "
            f"mm, foot slip {row['slip']:.3f} m/s, diverged {row['diverged']}"]


#: the columns of an SB3 recipe's summary over the seeds: (key, header, decimals)
SB3_SEED_COLUMNS = [("return", "return", 2), ("speed", "m/s", 3), ("cot", "CoT", 2), ("fell", "fell", 2),
                    ("sink_mean_mm", "sink mm", 2), ("slip", "slip m/s", 3), ("train_s", "train s", 0),
                    ("warnings", "warnings", 0), ("unstable", "unstable", 0)]


def train_sb3_seeds(cfg: dict, out, seeds, *, episodes: int = 10, resume: bool = True, name: str = "",
                    command: str = "", report=print, **options) -> dict:
    """The SB3 training settings ``cfg`` (:func:`mjrft.train.train_command.run_settings`) once per seed, each run in
    :func:`seed_folder`: the run of ``mjrft train --seed S --out OUT/seed-S`` (the same settings, checkpoints and
    resume: an interrupted seed resumes from its newest checkpoint, a folder whose run reached its budget is not
    trained again, and a folder of other settings is refused before any seed trains), each final policy
    evaluated (:func:`evaluate_sb3_run`, kept in the run folder's ``evaluation.json``) and the summary over the
    seeds written to ``out/seeds.txt`` and ``out/seeds.json`` after every seed (:func:`run_seeds`); returns the
    summary. ``resume`` False starts every seed over (``--no-resume``). ``name``: the recipe's name;
    ``command``: the ``mjrft train`` command line of the recipe and its overrides, which ``seeds.txt`` repeats for
    each seed; ``options``: the other keywords of :func:`mjrft.train.train.train` (device, torch_threads,
    progress_bar, verbose, config_name, trust). A Ctrl-C stops the seed in training the way it stops ``mjrft
    train`` (a checkpoint saved) and then the whole run (``KeyboardInterrupt``); the same call resumes it."""
    from .common import check_int
    from .train import MODEL_NAME, resumed_config, train_settings

    seeds = check_seeds(seeds)
    episodes = check_int("episodes", episodes, 0)
    out = Path(out)
    done = {}
    for s in seeds:  # every seed's folder is checked before any of them trains
        folder = seed_folder(out, s)
        saved = resumed_config(folder, cfg["env_id"], cfg["algo"], cfg["env_kwargs"] or None, cfg["normalize"], s,
                               cfg["hyperparams"] or None, cfg["n_envs"]) if resume else None
        if saved is None and cfg["env_id"] is None:
            raise ValueError(f"{folder} holds no run to resume: give --config or --env to start seed {s}")
        budget = cfg["timesteps"] if cfg["timesteps"] is not None else (saved or {}).get("timesteps")
        done[s] = (saved is not None and (folder / MODEL_NAME).is_file() and budget is not None
                   and int(saved.get("num_timesteps") or 0) >= budget)

    def train_one(s, folder):
        report(f"seed {s}: run folder {folder}")
        result = train_settings({**cfg, "seed": s}, folder, resume=resume, report=report, **options)
        if result.interrupted:
            report(f"seed {s}: interrupted at {result.num_timesteps} steps; run the same command to resume")
            raise KeyboardInterrupt(f"seed {s}")

    command = command or f"mjrft train --config {name}"
    return run_seeds(out, seeds, done, train_one, lambda folder: evaluate_sb3_run(folder, episodes),
                     {"episodes": episodes}, lambda rows: _sb3_summary(name, command, out, seeds, rows, episodes),
                     _sb3_report, sb3_evaluation_lines, report=report)


def _sb3_summary(name, command, out, seeds, rows, episodes) -> dict:
    from .train import CONFIG_NAME, load_config

    cfg = load_config(seed_folder(out, rows[0]["seed"]) / CONFIG_NAME)
    keys = [k for k, _, _ in SB3_SEED_COLUMNS]
    return {"recipe": name, "command": command, "out": str(out), "env_id": cfg["env_id"],
            "env_kwargs": cfg.get("env_kwargs") or {}, "algo": cfg["algo"], "seeds": list(seeds),
            "finished": [r["seed"] for r in rows], "timesteps": cfg["timesteps"], "n_envs": cfg["n_envs"],
            "episodes": episodes, "rows": rows,
            "spread": {k: spread([r.get(k) for r in rows]) for k in keys}}


def _sb3_report(summary: dict) -> str:
    """The text of ``seeds.txt`` of an SB3 recipe: what was run, the table, the equivalent commands of each seed."""
    kwargs = " ".join(f"{k}={v}" for k, v in summary["env_kwargs"].items())
    rows = summary["rows"]
    lines = [f"Recipe {summary['recipe'] or '(recipe)'} over {len(summary['seeds'])} seeds "
             f"({', '.join(map(str, summary['seeds']))}; {len(rows)} finished) on {summary['env_id']}"
             + (f" ({kwargs})" if kwargs else "") + f": {summary['algo'].upper()}, {summary['timesteps']:,} steps "
             f"each, {summary['n_envs']} env(s)"]
    if summary["episodes"]:
        lines.append(f"{summary['episodes']} deterministic episodes of each final policy on its env (mjrft eval): "
                     "the mean return, forward speed (m/s) and cost of transport (the actuators' energy over every "
                     "physics step), the fraction of episodes that ended in a fall, the mean sinkage of the feet in "
                     "the sand and their slip")
    lines.append("train s: the training's wall time (config.json's runs, summed over resumes); warnings: those the "
                 "environments raised while training (warnings.csv), unstable: of them the terrain's stability "
                 "warnings (TerrainStabilityWarning)")
    lines += ["", seeds_table(rows, SB3_SEED_COLUMNS), "", "the same runs and evaluations, one seed at a time:"]
    for s in summary["seeds"]:
        folder = seed_folder(summary["out"], s)
        lines.append(f"$ {summary['command']} --seed {s} --out {folder}")
        if summary["episodes"]:
            lines.append(f"$ mjrft eval --policy {folder} --episodes {summary['episodes']}")
    return "\n".join(lines)

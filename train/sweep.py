"""``mjrft sweep``: a grid of environment or rig parameters, run in local processes or on Ray, resumable.

>>> from mjrft.train.sweep import sweep
>>> rows = sweep({"f": [1, 2, 3], "curvature": [-48.78, 0, 48.78]}, "runs/hex_grid",
...              env="mjrft/HexapodSand-v0", gait="tripod", seconds=2.0, workers=4)
>>> rows = sweep({"shape": ["c", "flat", "reversed_c"], "omega": [0.2, 2.0]}, "runs/legs", rig="leg")

Command line (the same)::

    mjrft sweep --env mjrft/HexapodSand-v0 --gait tripod --grid "f=1,2,2.5" --grid "curvature=-48.78,0,48.78" \\
        --seconds 2 --out runs/hex_grid --workers 4
    mjrft sweep --rig leg --grid "shape=c,flat,reversed_c" --grid "omega=0.2,2" --out runs/legs
    mjrft sweep ... --address ray://head-node:10001        # the same grid as Ray tasks on a cluster

Grid. Each ``--grid NAME=V1,V2,...`` is one axis (``NAME=START:STOP:COUNT`` gives COUNT evenly spaced
values from START to STOP); the points are every combination, in the order given. Values are read
like ``mjrft train`` kwargs (numbers, ``true``/``false``, otherwise text such as a medium name).

* Environment sweeps (``--env`` with ``--gait``): a name is a parameter of the gait (``f``, ``duty``,
  ... see ``mjrft.tools.gaits.describe()``) or a keyword argument of the environment (``curvature``,
  ``medium``, ``resolution``, ...); ``gait.NAME`` / ``env.NAME`` say which when both have it. The
  hexapod's ``curvature`` is signed 1/r in 1/m within [-1/R', 1/R'] (R' = 2.05 cm, 1/R' = 48.78):
  positive is Li 2013's C-leg, negative the reversed C-leg (convention:
  :mod:`mjrft.geometry.curved_leg`), so the grid above is reversed C, flat and C-legs. Each
  point runs ``episodes`` episodes of ``seconds`` simulated seconds (``episode_seconds``; an episode
  that falls ends early) with :func:`mjrft.train.evaluate.evaluate` and records ``distance_m`` (torso
  x displacement), ``speed_m_s``, ``cot`` (cost of transport), ``sink_mean_mm``, ``sink_peak_mm``,
  ``fall_rate`` and ``return`` (means over the episodes; definitions in :mod:`mjrft.train.evaluate`).
  ``--gait`` also takes a model zip (then only environment names can vary).
* Rig sweeps (``--rig leg`` or ``--rig plate``): a name is a keyword argument of
  :func:`mjrft.tools.rigs.rotating_leg` (with the leg shape's ``chord``, ``curvature``, ``a``, ``b``, ...) or
  :func:`mjrft.tools.rigs.plate_intrusion` (angles in radians, as in the Python API); each point records the
  peak (largest magnitude, signed) force and torque and the deepest point: ``forward_peak_N``,
  ``support_peak_N``, ``torque_peak_Nm``, ``depth_max_mm`` for the leg, ``lift_peak_N``, ``drag_peak_N``,
  ``torque_peak_Nm``, ``depth_max_mm`` for the plate.

Output folder (``--out``):

=================  ====================================================================================
``sweep.json``     the fixed settings (env, gait, seconds, episodes, seed, fixed kwargs or the rig) and
                   the last grid; a rerun with different fixed settings is refused (use another folder)
``results.jsonl``  one JSON line per finished point, appended (flushed and synced) as it finishes:
                   ``key``, ``params``, ``status`` (``ok`` or ``error``), ``result`` or ``error``, ``wall_s``
``table.md``       one Markdown table of the grid's points (parameters, metrics), in grid order
``table.csv``      the same table as CSV
=================  ====================================================================================

Behaviour:

* Resume: a point whose parameters already have a line in ``results.jsonl`` is not run again, so an
  interrupted sweep, or a grid with added values, runs only the missing points. A point that raised
  (e.g. a gait frequency beyond the hip speed limit) is recorded as ``error`` and counts as finished;
  ``--retry-errors`` runs those again (the command exits with status 1 while any point is an error).
  A torn last line (a crash mid-write) is skipped and rewritten.
  Numbers are compared as floats (``f=2`` and ``f=2.0`` are the same point).
* Local: ``--workers N`` processes (``concurrent.futures.ProcessPoolExecutor``, ``forkserver`` start
  method where available, else ``spawn``); ``--workers 1`` runs in this process. The default is the
  number of CPUs less one. Only the parent process writes the results file.
* Ray: with ``--address`` (``ray://host:10001``, ``auto``, or ``local`` for a throw-away local Ray),
  ``ray.init(address=...)`` connects to the existing cluster and every missing point is one Ray task
  (``ray.remote``), collected with ``ray.wait`` as it finishes and appended by this process; the
  cluster's workers need mjrft installed (same version). Ray is optional: ``pip install "mjrft[ray]"``.
"""

from __future__ import annotations

import csv
import importlib
import inspect
import itertools
import json
import math
import multiprocessing
import os
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

from .common import check_env_id, check_int, int_arg, parse_kwargs, parse_value, start_method, valid_env_kwargs

ENV_METRICS = ("distance_m", "speed_m_s", "cot", "sink_mean_mm", "sink_peak_mm", "fall_rate", "return")
RIG_METRICS = {"leg": ("forward_peak_N", "support_peak_N", "torque_peak_Nm", "depth_max_mm"),
               "plate": ("lift_peak_N", "drag_peak_N", "torque_peak_Nm", "depth_max_mm")}
RIGS = tuple(RIG_METRICS)
RESULTS, SETTINGS, TABLE_MD, TABLE_CSV = "results.jsonl", "sweep.json", "table.md", "table.csv"
RAY_HINT = 'Ray is not installed: pip install "mjrft[ray]" (or pip install "ray>=2.9")'


# ---------------------------------------------------------------------------------------------- the grid
def _value(text: str):
    try:
        number = float(text)
    except ValueError:
        number = 0.0
    if not math.isfinite(number):
        raise ValueError(f"grid value {text.strip()!r} is not finite")
    return parse_value(text.strip())


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def parse_grid(items) -> dict[str, list]:
    """``["f=1,2,3", "curvature=-50:50:5"]`` -> ``{"f": [1, 2, 3], "curvature": [-50.0, -25.0, ...]}``."""
    grid: dict[str, list] = {}
    for item in items or ():
        name, sep, values = str(item).partition("=")
        name = name.strip()
        if not sep or not all(part.isidentifier() for part in name.split(".")) or not values.strip():
            raise ValueError(f"grid axis must be NAME=V1,V2,... or NAME=START:STOP:COUNT (e.g. f=1,2,3), got {item!r}")
        if name in grid:
            raise ValueError(f"grid axis {name!r} given twice")
        text = values.strip()
        if ":" in text and "," not in text:
            parts = text.split(":")
            try:
                start, stop, count = float(parts[0]), float(parts[1]), parts[2]
                count = int(count)
            except (IndexError, ValueError):
                raise ValueError(f"grid axis {name!r}: expected START:STOP:COUNT with numbers and an integer "
                                 f"COUNT >= 2, got {text!r}") from None
            if len(parts) != 3 or count < 2 or not (math.isfinite(start) and math.isfinite(stop)):
                raise ValueError(f"grid axis {name!r}: expected START:STOP:COUNT with finite numbers and an integer "
                                 f"COUNT >= 2, got {text!r}")
            grid[name] = [start + (stop - start) * i / (count - 1) for i in range(count)]
        else:
            grid[name] = [_value(v) for v in text.split(",")]
            if any(isinstance(v, str) and not v for v in grid[name]):
                raise ValueError(f"grid axis {name!r} has an empty value in {text!r}")
    return check_grid(grid)


def check_grid(grid) -> dict[str, list]:
    """A grid as ``{name: [values]}`` (checked: names, at least one value each, no value twice)."""
    if not isinstance(grid, dict) or not grid:
        raise ValueError(f"the grid needs at least one axis, e.g. {{'f': [1, 2, 3]}}, got {grid!r}")
    out = {}
    for name, values in grid.items():
        if not isinstance(name, str) or not all(p.isidentifier() for p in name.split(".")):
            raise ValueError(f"grid axis names must be identifiers (optionally gait.NAME / env.NAME), got {name!r}")
        values = list(values) if isinstance(values, (list, tuple, range)) or hasattr(values, "tolist") else [values]
        values = [v.item() if type(v).__module__ == "numpy" and hasattr(v, "item") else v for v in values]
        if not values:
            raise ValueError(f"grid axis {name!r} has no values")
        for v in values:
            if _is_number(v) and not math.isfinite(v):
                raise ValueError(f"grid axis {name!r}: value {v!r} is not finite")
        keys = [_canonical(v) for v in values]
        if len(set(keys)) != len(keys):
            raise ValueError(f"grid axis {name!r} lists a value twice: {values!r}")
        out[name] = values
    return out


def grid_points(grid) -> list[dict]:
    """Every combination of the axes, the first axis varying slowest."""
    names = list(grid)
    return [dict(zip(names, combo)) for combo in itertools.product(*(grid[n] for n in names))]


def _canonical(v):
    return float(v) if _is_number(v) else v


def point_key(params: dict) -> str:
    """The identity of a point in the results file (numbers as floats, names sorted)."""
    return json.dumps({k: _canonical(v) for k, v in params.items()}, sort_keys=True)


# ---------------------------------------------------------------------------------------------- settings
def _gait_params(gait: str) -> tuple[str | None, dict]:
    """(gait name, parameters) of a gait spec, or (None, {}) for a model zip / run folder."""
    from mjrft.tools.gaits import GAITS, is_gait_spec, parse_gait_spec

    if not is_gait_spec(gait):
        if not Path(gait).exists():
            raise ValueError(f"--gait {gait!r} is neither a gait ({', '.join(sorted(GAITS))}) nor a model zip / run folder")
        from .evaluate import resolve_model

        resolve_model(gait)  # a damaged or incomplete model file: one error naming it, before any point runs
        return None, {}
    name, given = parse_gait_spec(gait)
    return name, given


def _rig_names(rig: str) -> list[str]:
    from mjrft.tools import rigs
    from mjrft.models.rigs import leg_geometry

    fns = [rigs.rotating_leg, leg_geometry] if rig == "leg" else [rigs.plate_intrusion]
    names = []
    for fn in fns:
        for p in inspect.signature(fn).parameters.values():
            if p.kind not in (p.VAR_KEYWORD, p.VAR_POSITIONAL) and p.name not in names:
                names.append(p.name)
    return names


def roles(settings: dict, names) -> dict[str, str]:
    """What each grid name sets: ``"gait"``, ``"env"`` or ``"rig"`` (ValueError listing the valid names)."""
    out = {}
    if settings["kind"] == "rig":
        valid = _rig_names(settings["rig"])
        for n in names:
            if n not in valid:
                raise ValueError(f"rig {settings['rig']!r} has no parameter {n!r}; valid: {', '.join(valid)}")
            out[n] = "rig"
        return out
    gait_name, _ = _gait_params(settings["gait"])
    gait_valid = []
    if gait_name is not None:
        from mjrft.tools.gaits import GAITS

        gait_valid = list(GAITS[gait_name].params)
    env_valid = [k for k in valid_env_kwargs(settings["env"]) if k not in ("max_episode_steps", "episode_seconds")]
    for n in names:
        prefix, _, bare = n.rpartition(".")
        if prefix not in ("", "gait", "env"):
            raise ValueError(f"grid name {n!r}: the prefix must be gait. or env.")
        in_gait, in_env = bare in gait_valid, bare in env_valid
        if prefix == "gait" or (not prefix and in_gait and not in_env):
            if not in_gait:
                raise ValueError(f"gait {settings['gait']!r} has no parameter {bare!r}; valid: {', '.join(gait_valid) or 'none'}")
            out[n] = "gait"
        elif prefix == "env" or (not prefix and in_env and not in_gait):
            if not in_env:
                raise ValueError(f"{settings['env']} has no keyword argument {bare!r}; valid: {', '.join(env_valid)}")
            out[n] = "env"
        elif in_gait and in_env:
            raise ValueError(f"grid name {n!r} is both a gait parameter and an env keyword argument: "
                             f"write gait.{n} or env.{n}")
        else:
            raise ValueError(f"grid name {n!r} is neither a parameter of gait {settings['gait']!r} "
                             f"({', '.join(gait_valid) or 'none'}) nor a keyword argument of {settings['env']} "
                             f"({', '.join(env_valid)})")
    return out


def make_settings(*, env=None, gait=None, rig=None, seconds=2.0, episodes=1, seed=0, env_kwargs=None,
                  rig_kwargs=None) -> dict:
    """The fixed settings of a sweep (checked); saved as ``sweep.json``."""
    from mjrft.errors import check_positive, unknown

    if (env is None) == (rig is None):
        raise ValueError("give either an environment (env=..., with gait=...) or a rig (rig='leg' or 'plate')")
    if rig is not None:
        if rig not in RIGS:
            raise unknown("rig", rig, RIGS)
        if env_kwargs or gait:
            raise ValueError("a rig sweep takes rig_kwargs, not gait or env_kwargs")
        return {"kind": "rig", "rig": rig, "rig_kwargs": dict(rig_kwargs or {})}
    check_env_id(env)
    if not gait:
        raise ValueError(f"an environment sweep needs a gait (e.g. tripod) or a model zip to drive {env}")
    if rig_kwargs:
        raise ValueError("an environment sweep takes env_kwargs, not rig_kwargs")
    _gait_params(gait)
    env_kwargs = dict(env_kwargs or {})
    for k in ("episode_seconds", "max_episode_steps"):
        if k in env_kwargs:
            raise ValueError(f"{k} is set by the sweep's seconds; do not pass it as an env kwarg")
    return {"kind": "env", "env": env, "gait": gait, "seconds": check_positive("seconds", seconds),
            "episodes": check_int("episodes", episodes, 1), "seed": check_int("seed", seed, 0),
            "env_kwargs": env_kwargs}


# ---------------------------------------------------------------------------------------------- one point
def _peak(values) -> float:
    import numpy as np

    a = np.asarray(values, dtype=float)
    return float(a[np.argmax(np.abs(a))]) if a.size else 0.0


def _run_env(settings: dict, params: dict, role: dict) -> dict:
    from .evaluate import evaluate

    gait_params = {k.rpartition(".")[2]: v for k, v in params.items() if role[k] == "gait"}
    env_params = {k.rpartition(".")[2]: v for k, v in params.items() if role[k] == "env"}
    spec = settings["gait"]
    if gait_params:
        name, fixed = _gait_params(spec)
        both = sorted(set(fixed) & set(gait_params))
        if both:
            raise ValueError(f"gait parameter(s) {', '.join(both)} both fixed in {spec!r} and on the grid")
        spec = f"{name}:" + ",".join(f"{k}={v}" for k, v in {**fixed, **gait_params}.items())
    kwargs = {**settings["env_kwargs"], **env_params, "episode_seconds": settings["seconds"],
              "max_episode_steps": 10**9}
    rows, summary = evaluate(spec, settings["env"], settings["episodes"], settings["seed"], kwargs,
                             trust=settings.get("trust", False))
    distance = sum(r["speed"] * r["seconds"] for r in rows) / len(rows)
    return {"distance_m": distance, "speed_m_s": summary["speed"], "cot": summary["cot"],
            "sink_mean_mm": summary["sink_mean_mm"], "sink_peak_mm": summary["sink_peak_mm"],
            "fall_rate": summary["fall_rate"], "return": summary["return"]}


def _run_rig(settings: dict, params: dict) -> dict:
    import numpy as np

    from mjrft.tools import rigs

    kw = {**settings["rig_kwargs"], **params}
    if settings["rig"] == "leg":
        p = rigs.rotating_leg(**kw)
        out = {"forward_peak_N": _peak(p.forward), "support_peak_N": _peak(p.support)}
    else:
        p = rigs.plate_intrusion(**kw)
        out = {"lift_peak_N": _peak(p.lift), "drag_peak_N": _peak(p.drag)}
    out["torque_peak_Nm"] = _peak(p.torque)
    out["depth_max_mm"] = 1e3 * float(np.max(p.depth)) if len(p.depth) else 0.0
    return out


def run_point(settings: dict, params: dict, role: dict) -> dict:
    """Run one grid point; never raises for a bad point (the record says ``error``). Picklable for
    worker processes and Ray tasks."""
    t0 = time.perf_counter()
    record = {"key": point_key(params), "params": params}
    try:
        if settings["kind"] == "rig":
            result = _run_rig(settings, params)
        else:
            result = _run_env(settings, params, role)
        record.update(status="ok", result=result)
    except Exception as exc:  # one bad point must not stop the grid: it is recorded
        record.update(status="error", error=f"{type(exc).__name__}: {exc}")
    record["wall_s"] = time.perf_counter() - t0
    return record


# ---------------------------------------------------------------------------------------------- results file
def read_results(path) -> dict[str, dict]:
    """Records of ``results.jsonl`` by key (the last one of a key wins; a torn line is skipped)."""
    out = {}
    path = Path(path)
    if not path.exists():
        return out
    with open(path) as fh:
        for line in fh:
            line = line.strip()
            if not line:
                continue
            try:
                rec = json.loads(line)
            except json.JSONDecodeError:
                continue  # a line cut short by a crash; its point runs again
            if isinstance(rec, dict) and "key" in rec:
                out[rec["key"]] = rec
    return out


class _ResultsFile:
    """Appends one record per line, flushed and synced, so a finished point is never lost."""

    def __init__(self, path):
        self.path = Path(path)
        torn = self.path.exists() and self.path.stat().st_size > 0 and not self.path.read_bytes().endswith(b"\n")
        self.fh = open(self.path, "a")
        if torn:
            self.fh.write("\n")

    def append(self, record: dict) -> None:
        self.fh.write(json.dumps(record) + "\n")
        self.fh.flush()
        os.fsync(self.fh.fileno())

    def close(self) -> None:
        self.fh.close()


def _write_settings(out_dir: Path, settings: dict, grid: dict) -> None:
    path = out_dir / SETTINGS
    if path.exists():
        try:
            saved = json.loads(path.read_text())["settings"]
        except (json.JSONDecodeError, KeyError, TypeError):
            saved = None
        if saved is not None and saved != json.loads(json.dumps(settings)):
            diff = sorted(k for k in set(saved) | set(settings) if saved.get(k) != settings.get(k))
            raise ValueError(f"{out_dir} holds a sweep with other settings (differs in: {', '.join(diff)}; saved "
                             f"{ {k: saved.get(k) for k in diff} }); use another --out folder")
    tmp = path.with_suffix(".json.tmp")
    tmp.write_text(json.dumps({"settings": settings, "grid": grid}, indent=2) + "\n")
    os.replace(tmp, path)


# ---------------------------------------------------------------------------------------------- running
def _run_local(todo, settings, role, workers, record) -> None:
    if workers == 1:
        for params in todo:
            record(run_point(settings, params, role))
        return
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context(start_method()))
    try:
        futures = [pool.submit(run_point, settings, p, role) for p in todo]
        for fut in as_completed(futures):
            record(fut.result())
    except BaseException:
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    pool.shutdown()


def import_ray():
    """The ``ray`` module, or a ValueError saying how to install it."""
    try:
        return importlib.import_module("ray")
    except ImportError:
        raise ValueError(RAY_HINT) from None


def _run_ray(todo, settings, role, address, record) -> None:
    ray = import_ray()
    ray.init(address=None if address == "local" else address, ignore_reinit_error=True)
    try:
        task = ray.remote(run_point)
        pending = [task.remote(settings, p, role) for p in todo]
        while pending:
            done, pending = ray.wait(pending, num_returns=1)
            for ref in done:
                record(ray.get(ref))
    finally:
        ray.shutdown()


def sweep(grid, out_dir, *, env=None, gait=None, rig=None, seconds=2.0, episodes=1, seed=0, env_kwargs=None,
          rig_kwargs=None, workers=None, address=None, retry_errors=False, progress=print, trust=False) -> list[dict]:
    """Run every point of ``grid`` not yet in ``out_dir``; write the table; return its rows.

    ``grid``: ``{name: [values]}`` (every combination), a list of point dicts, or a callable returning
    either. Either ``env`` + ``gait`` (a gait spec or model zip) with ``seconds``, ``episodes``,
    ``seed`` and fixed ``env_kwargs``, or ``rig`` (``"leg"``/``"plate"``) with fixed ``rig_kwargs``.
    ``workers``: local processes (default: CPUs - 1); ``address``: run on Ray instead (module doc).
    ``progress``: called with one line per finished point (None: quiet). ``trust``: also load a model file
    that needs pickle (:func:`mjrft.train.evaluate.load_policy`); not part of the saved settings.
    """
    settings = make_settings(env=env, gait=gait, rig=rig, seconds=seconds, episodes=episodes, seed=seed,
                             env_kwargs=env_kwargs, rig_kwargs=rig_kwargs)
    if callable(grid):
        grid = grid()
    if isinstance(grid, dict):
        grid = check_grid(grid)
        points = grid_points(grid)
        names = list(grid)
    else:
        points = [dict(p) for p in grid] if isinstance(grid, (list, tuple)) else []
        if not points or not all(p for p in points):
            raise ValueError("the grid must be {name: [values]} or a non-empty list of non-empty point dicts")
        names = list(dict.fromkeys(k for p in points for k in p))
        points = [{k: check_grid({k: [v]})[k][0] for k, v in p.items()} for p in points]  # checked, numpy -> Python
    role = roles(settings, names)
    if workers is None:
        workers = max(1, (os.cpu_count() or 2) - 1)
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ValueError(f"workers must be an integer >= 1, got {workers!r}")
    if address is not None and (not isinstance(address, str) or not address.strip()):
        raise ValueError(f"address must be a Ray address such as ray://host:10001, auto or local, got {address!r}")
    if address is not None:
        import_ray()  # fail before anything is written

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    _write_settings(out_dir, settings, grid if isinstance(grid, dict) else {"points": points})
    done = read_results(out_dir / RESULTS)
    keys, todo = set(), []
    for p in points:
        k = point_key(p)
        if k in keys:
            continue
        keys.add(k)
        rec = done.get(k)
        if rec is None or (retry_errors and rec.get("status") != "ok"):
            todo.append(p)
    say = progress or (lambda _msg: None)
    say(f"{len(points)} points, {len(points) - len(todo)} already in {out_dir / RESULTS}, running {len(todo)}"
        + (f" on Ray ({address})" if address else f" in {min(workers, max(len(todo), 1))} process(es)"))

    results = _ResultsFile(out_dir / RESULTS)
    count = [0]

    def record(rec: dict) -> None:
        results.append(rec)
        done[rec["key"]] = rec
        count[0] += 1
        what = ", ".join(f"{k}={v}" for k, v in rec["params"].items())
        if rec["status"] == "ok":
            body = ", ".join(f"{k} {v:.4g}" for k, v in rec["result"].items())
        else:
            body = rec["error"]
        say(f"[{count[0]}/{len(todo)}] {what}: {body} ({rec['wall_s']:.1f} s)")

    run = {**settings, "trust": True} if trust else settings  # what each point runs with (trust is not saved)
    try:
        if todo:
            if address is not None:
                _run_ray(todo, run, role, address, record)
            else:
                _run_local(todo, run, role, min(workers, len(todo)), record)
    finally:
        results.close()
    metrics = ENV_METRICS if settings["kind"] == "env" else RIG_METRICS[settings["rig"]]
    rows = []
    for p in points:
        rec = done.get(point_key(p), {})
        row = dict(p)
        for m in metrics:
            row[m] = rec.get("result", {}).get(m) if rec.get("status") == "ok" else None
        row["status"] = rec.get("status", "missing")
        row["error"] = rec.get("error", "")
        rows.append(row)
    write_table(rows, names, metrics, out_dir)
    return rows


# ---------------------------------------------------------------------------------------------- the table
def _fmt(v) -> str:
    if v is None:
        return ""
    if isinstance(v, float):
        return f"{v:.4g}"
    return str(v)


def markdown_table(rows: list[dict], names, metrics) -> str:
    cols = list(names) + list(metrics) + (["error"] if any(r["error"] for r in rows) else [])
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for r in rows:
        lines.append("| " + " | ".join(_fmt(r.get(c)).replace("|", "/") for c in cols) + " |")
    return "\n".join(lines)


def write_table(rows: list[dict], names, metrics, out_dir) -> tuple[Path, Path]:
    """``table.md`` and ``table.csv`` in ``out_dir`` (written whole, atomically)."""
    out_dir = Path(out_dir)
    md, cs = out_dir / TABLE_MD, out_dir / TABLE_CSV
    tmp = md.with_suffix(".md.tmp")
    tmp.write_text(markdown_table(rows, names, metrics) + "\n")
    os.replace(tmp, md)
    tmp = cs.with_suffix(".csv.tmp")
    with open(tmp, "w", newline="") as fh:
        w = csv.writer(fh)
        cols = list(names) + list(metrics) + ["status", "error"]
        w.writerow(cols)
        for r in rows:
            w.writerow(["" if r.get(c) is None else r.get(c) for c in cols])
    os.replace(tmp, cs)
    return md, cs


# ---------------------------------------------------------------------------------------------- CLI
def add_arguments(parser) -> None:
    from .artefacts import TRUST_HELP
    parser.add_argument("--env", default=None, help="environment id, e.g. mjrft/HexapodSand-v0 (with --gait)")
    parser.add_argument("--gait", "--policy", dest="gait", default=None,
                        help="gait spec driving the env (e.g. tripod or tripod:duty=0.5), or a model zip")
    parser.add_argument("--rig", default=None, choices=RIGS, help="sweep a measurement rig instead of an env")
    parser.add_argument("--grid", action="append", default=[], metavar="NAME=V1,V2,...",
                        help="one grid axis (repeat for more); NAME=START:STOP:COUNT for evenly spaced values")
    parser.add_argument("--seconds", type=float, default=2.0, help="simulated seconds per episode (default 2)")
    parser.add_argument("--episodes", type=int_arg, default=1, help="episodes per point (default 1)")
    parser.add_argument("--seed", type=int_arg, default=0, help="episode i resets with seed + i (default 0)")
    parser.add_argument("--out", default="runs/sweep", help="output folder (default runs/sweep); rerun to resume")
    parser.add_argument("--workers", type=int_arg, default=None,
                        help="local worker processes (default: CPUs - 1; 1 runs in this process)")
    parser.add_argument("--address", default=None,
                        help="Ray cluster address (ray://host:10001, auto, or local): run the points as Ray tasks")
    parser.add_argument("--retry-errors", action="store_true", help="run again the points recorded as errors")
    parser.add_argument("--trust", action="store_true", help=TRUST_HELP)
    parser.add_argument("kwargs", nargs="*", metavar="KEY=VALUE",
                        help="fixed keyword arguments of the env (or of the rig), e.g. medium=poppy_lp")


def main(args) -> int:
    from mjrft.tools.outputs import output_dir

    grid = parse_grid(args.grid)
    fixed = parse_kwargs(args.kwargs, "fixed kwarg")
    output_dir(args.out)
    kind = {"rig_kwargs": fixed} if args.rig else {"env_kwargs": fixed}
    rows = sweep(grid, args.out, env=args.env, gait=args.gait, rig=args.rig, seconds=args.seconds,
                 episodes=args.episodes, seed=args.seed, workers=args.workers, address=args.address,
                 retry_errors=args.retry_errors, trust=args.trust, **kind)
    metrics = ENV_METRICS if not args.rig else RIG_METRICS[args.rig]
    print(markdown_table(rows, list(grid), metrics))
    out = Path(args.out)
    print(f"wrote {out / TABLE_MD}, {out / TABLE_CSV} (results: {out / RESULTS})")
    return 0 if all(r["status"] == "ok" for r in rows) else 1

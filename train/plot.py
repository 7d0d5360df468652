"""``mjrft plot``: learning curves of training runs (episode return and forward speed against env steps).

>>> from mjrft.train.plot import plot_runs
>>> result = plot_runs(["runs/hexapod-sand", "runs/hexapod-rigid"], "curves.png", baselines=["tripod:f=2.5"])
>>> result = plot_runs(["runs/hex"], "curves.png", baselines=["return=338,speed=0.30"], csv_path="curves.csv")

    mjrft plot runs/hexapod-sand runs/hexapod-rigid --out curves.png --baseline tripod:f=2.5 --csv curves.csv

What is read from each run folder (written by ``mjrft train``):

* ``monitor.csv``: one row per finished episode in the order the episodes finished (a resumed run appends):
  return ``r``, length ``l`` and, when the run recorded it, ``speed`` (m/s, the torso's x displacement over
  the episode / its duration, :mod:`mjrft.train.vecenv`). An episode's env step is the cumulative sum of
  the lengths up to and including it, as SB3's results plotter counts; episodes cut off by an
  interruption are not in the file, so this count can trail ``time/total_timesteps`` by up to
  ``n_envs`` episodes per resume. Each series is drawn raw (faint) and as a trailing mean over the last
  ``window`` episodes (solid).
* ``logs/from_<N>/progress.csv`` (every resume's, in order), where present: SB3's ``rollout/ep_rew_mean``
  (the mean return of the last 100 episodes) against ``time/total_timesteps``, dashed.
* ``config.json``: the env id and env kwargs, for a gait baseline.

A run whose ``monitor.csv`` has no ``speed`` column (or only NaN, an env without ``x_velocity``) is
plotted for its return only, and the figure says so under the panels; with no speed in any run the
figure has the return panel only.

Baselines (``--baseline``, repeatable), drawn as horizontal lines:

* a gait spec (``tripod:f=2.5``, :mod:`mjrft.tools.gaits`): evaluated with :func:`mjrft.train.evaluate.evaluate`
  on each distinct env of the runs (env id and kwargs from ``config.json``) for ``episodes`` episodes
  (seeds ``seed``, ``seed + 1``, ...); the line is the mean return / mean speed of those episodes;
* numbers ``return=R,speed=S`` (either key alone works): drawn as given.

``--csv FILE`` writes every plotted series in long form: ``label, run, series, env_steps, value`` with
``series`` one of ``return``, ``return_smoothed``, ``speed``, ``speed_smoothed``, ``ep_rew_mean``,
``baseline_return``, ``baseline_speed`` (baseline rows have an empty ``env_steps`` and ``run``).
"""

from __future__ import annotations

import csv
import io
import json
import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from mjrft.tools.outputs import number

from .common import check_int, int_arg

MONITOR = "monitor.csv"
CONFIG = "config.json"
#: default smoothing window (episodes) of the trailing mean
WINDOW = 20
BASELINE_KEYS = ("return", "speed")
CSV_COLUMNS = ("label", "run", "series", "env_steps", "value")


# ---------------------------------------------------------------------------------------------- reading
@dataclass
class Monitor:
    """The finished episodes of a run, in the order they finished."""

    returns: np.ndarray
    lengths: np.ndarray
    speed: np.ndarray | None  # m/s per episode; None when the run did not record it

    @property
    def steps(self) -> np.ndarray:
        """Env steps at the end of each episode: the cumulative episode lengths."""
        return np.cumsum(self.lengths)


@dataclass
class Run:
    path: Path
    label: str
    monitor: Monitor
    progress: tuple[np.ndarray, np.ndarray] | None  # (time/total_timesteps, rollout/ep_rew_mean)
    env_id: str | None = None
    env_kwargs: dict = field(default_factory=dict)


@dataclass
class Baseline:
    label: str
    ret: float | None = None
    speed: float | None = None
    env_id: str | None = None  # the env a gait was evaluated on (None for given numbers)


def _float(text: str) -> float:
    return float(text) if text.strip() else math.nan


def _read_text(path: Path, what: str) -> str:
    """The text of ``path``; one ValueError naming the file when it is not a text file (binary, another encoding)."""
    try:
        with open(path, newline="") as fh:
            text = fh.read()
    except UnicodeDecodeError as exc:
        raise ValueError(f"{path}: {what} is not a text file (byte {exc.start} is not UTF-8: binary or "
                         f"damaged)") from None
    except OSError as exc:
        raise ValueError(f"{path}: {what} cannot be read ({exc.strerror or exc})") from None
    if "\0" in text:
        raise ValueError(f"{path}: {what} is not a text file (it holds NUL bytes: binary or damaged)")
    return text


def _left_out(path, skipped: list[tuple[int, str]], what: str) -> None:
    """Warn once for the lines of ``path`` that were left out (line number, reason), naming the first."""
    if skipped:
        lineno, why = skipped[0]
        more = f" (and {len(skipped) - 1} more)" if len(skipped) > 1 else ""
        warnings.warn(f"{path}: {len(skipped)} {what} left out; line {lineno} {why}{more}", RuntimeWarning,
                      stacklevel=3)


def read_monitor(path) -> Monitor:
    """The episodes of a ``monitor.csv`` (``r``, ``l`` and the optional ``speed`` column).

    A line that is not an episode row (a field count other than the header's, a return or length that is not
    a number) is left out with one warning naming the file, how many and the first; a binary file, a file
    without the ``r`` and ``l`` columns or without any episode is an error naming the file.
    """
    path = Path(path)
    text = _read_text(path, "monitor file")
    lines = [(i, line) for i, line in enumerate(text.splitlines(keepends=True), 1)
             if line.strip() and not line.startswith("#")]
    if not lines:
        raise ValueError(f"{path} is empty: no header line r,l,t")
    if len(lines) > 1 and not lines[-1][1].endswith("\n"):  # the process was stopped while writing it
        lineno, _ = lines.pop()
        warnings.warn(f"{path} line {lineno} is incomplete (the run stopped while writing it); left out",
                      RuntimeWarning, stacklevel=2)
    header = next(csv.reader([lines[0][1]]))
    missing = [c for c in ("r", "l") if c not in header]
    if missing:
        raise ValueError(f"{path} has columns {','.join(header)}; a monitor file has r, l and t (missing: "
                         f"{', '.join(missing)})")
    col = {name: k for k, name in enumerate(header)}
    returns, lengths, speed, skipped = [], [], [], []
    for (lineno, line), cells in zip(lines[1:], csv.reader(line for _, line in lines[1:])):
        if cells == header:  # a header repeated by a writer that restarted the file's table
            continue
        if len(cells) != len(header):
            skipped.append((lineno, f"has {len(cells)} fields, the header {len(header)}"))
            continue
        try:
            r, n = _float(cells[col["r"]]), float(cells[col["l"]])
            v = _float(cells[col["speed"]]) if "speed" in col else math.nan
        except ValueError:
            skipped.append((lineno, f"holds a value that is not a number: {line.strip()[:80]!r}"))
            continue
        if not (math.isfinite(n) and n >= 0 and n.is_integer()):
            skipped.append((lineno, f"has episode length {cells[col['l']]!r}, not a whole number of steps"))
            continue
        returns.append(r)
        lengths.append(int(n))
        speed.append(v)
    _left_out(path, skipped, "line(s) that are not episode rows")
    if not returns:
        raise ValueError(f"{path} has no finished episode yet")
    speeds = np.array(speed) if "speed" in col else None
    if speeds is not None and not np.isfinite(speeds).any():
        speeds = None
    return Monitor(np.array(returns), np.array(lengths, dtype=np.int64), speeds)


def _log_start(path: Path) -> int:
    """N of ``logs/from_<N>/progress.csv``."""
    return int(path.parent.name.removeprefix("from_"))


def read_progress(run_dir) -> tuple[np.ndarray, np.ndarray] | None:
    """SB3's ``rollout/ep_rew_mean`` against ``time/total_timesteps`` from every ``logs/from_<N>/progress.csv``
    of the run (resumes in order of N), or None when no file has both columns with values.

    A run resumed from the checkpoint at step N trains again what a killed run logged after N: the rows of an
    earlier log after the start of the next one are left out, with a warning (``mjrft train`` itself drops
    them when it resumes). Rows with another field count than the header's, or values that are not
    numbers, are left out with a warning naming the file; a binary file is an error naming it.
    """
    logs = sorted(Path(run_dir).glob("logs/from_*/progress.csv"),
                  key=lambda p: (_log_start(p) if p.parent.name.removeprefix("from_").isdigit() else -1, p.name))
    steps, means = [], []
    for k, path in enumerate(logs):
        text = _read_text(path, "training log")
        if text and not text.endswith("\n"):  # a line cut by a stopped process
            text = text[: text.rfind("\n") + 1]
        nxt = next((_log_start(p) for p in logs[k + 1:] if p.parent.name.removeprefix("from_").isdigit()), None)
        rows = list(csv.reader(io.StringIO(text)))
        if not rows:
            continue
        header, skipped, later = rows[0], [], 0
        col = {name: i for i, name in enumerate(header)}
        for lineno, cells in enumerate(rows[1:], 2):
            if len(cells) != len(header):
                skipped.append((lineno, f"has {len(cells)} fields, the header {len(header)}"))
                continue
            if "time/total_timesteps" not in col or "rollout/ep_rew_mean" not in col:
                continue
            s, m = cells[col["time/total_timesteps"]], cells[col["rollout/ep_rew_mean"]]
            if not (s and m):
                continue
            try:
                step, mean = float(s), float(m)
            except ValueError:
                skipped.append((lineno, f"has time/total_timesteps {s!r} or rollout/ep_rew_mean {m!r}, not a number"))
                continue
            if nxt is not None and step > nxt:
                later += 1
                continue
            steps.append(step)
            means.append(mean)
        _left_out(path, skipped, "row(s) that do not fit the header")
        if later:
            warnings.warn(f"{path}: {later} row(s) after step {nxt} left out: the run was resumed from the checkpoint "
                          f"at step {nxt}, so what it logged after it was lost and trained again", RuntimeWarning,
                          stacklevel=2)
    if not steps:
        return None
    order = np.argsort(steps, kind="stable")
    return np.asarray(steps)[order], np.asarray(means)[order]


def load_run(path, label: str | None = None) -> Run:
    """A run folder's episodes, training log and env (module doc); errors name a missing folder or file.

    When the run's last entry in ``config.json`` has ended and its finished episodes add up to more env steps
    than it trained, the monitor holds episodes that a killed run finished after its last checkpoint (lost
    with it): a warning says so (``mjrft train`` drops them when it resumes).
    """
    path = Path(path)
    if not path.is_dir():
        raise ValueError(f"run folder {str(path)!r} does not exist" if not path.exists()
                         else f"{str(path)!r} is a file, not a run folder (give the folder 'mjrft train --out' wrote)")
    if not (path / MONITOR).is_file():
        raise ValueError(f"run folder {str(path)!r} has no {MONITOR} (no episode finished yet, or not a folder "
                         f"written by 'mjrft train')")
    env_id, env_kwargs, cfg = None, {}, {}
    if (path / CONFIG).is_file():
        from .artefacts import read_json

        cfg = read_json(path / CONFIG, "run config")
        env_id, env_kwargs = cfg.get("env_id"), dict(cfg.get("env_kwargs") or {})
    monitor = read_monitor(path / MONITOR)
    runs = cfg.get("runs") if isinstance(cfg.get("runs"), list) else []
    trained = cfg.get("num_timesteps")
    ended = bool(runs) and isinstance(runs[-1], dict) and runs[-1].get("status") in ("finished", "interrupted",
                                                                                     "crashed")
    if ended and isinstance(trained, int) and monitor.steps[-1] > trained:
        warnings.warn(f"{path / MONITOR}: its episodes add up to {int(monitor.steps[-1])} env steps, more than the "
                      f"{trained} the run trained: it holds episodes a killed run finished after its last checkpoint "
                      f"(lost with it), drawn as they are", RuntimeWarning, stacklevel=2)
    return Run(path, label or path.resolve().name, monitor, read_progress(path), env_id, env_kwargs)


def rolling_mean(values, window: int) -> np.ndarray:
    """Trailing mean over the last ``window`` values (fewer at the start); NaN values are left out."""
    x = np.asarray(values, dtype=float)
    ok = np.isfinite(x)
    total = np.concatenate(([0.0], np.cumsum(np.where(ok, x, 0.0))))
    count = np.concatenate(([0], np.cumsum(ok)))
    end = np.arange(1, x.size + 1)
    start = np.maximum(end - int(window), 0)
    n = count[end] - count[start]
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(n > 0, (total[end] - total[start]) / np.maximum(n, 1), np.nan)


# ---------------------------------------------------------------------------------------------- baselines
def parse_baseline(text: str) -> str | Baseline:
    """A gait spec (returned as the string, evaluated later) or ``return=R,speed=S`` (a :class:`Baseline`)."""
    from mjrft.tools.gaits import GAITS, is_gait_spec, parse_gait_spec

    if is_gait_spec(text):
        parse_gait_spec(text)  # a bad parameter fails here, before anything is read or run
        return text
    values = {}
    for part in str(text).split(","):
        key, sep, value = part.partition("=")
        key = key.strip()
        try:
            v = float(value) if sep else math.nan
        except ValueError:
            v = math.nan
        if key not in BASELINE_KEYS or not math.isfinite(v) or key in values:
            raise ValueError(f"--baseline {text!r} is neither a gait spec ({', '.join(sorted(GAITS))}, e.g. "
                             f"tripod:f=2.5) nor numbers return=R,speed=S (keys {', '.join(BASELINE_KEYS)}, "
                             f"each once, finite values)")
        values[key] = v
    return Baseline(f"baseline ({text})", values.get("return"), values.get("speed"))


def evaluate_baseline(spec: str, runs: list[Run], episodes: int = 3, seed: int = 0) -> list[Baseline]:
    """The gait ``spec`` evaluated on each distinct env (id and kwargs) of ``runs``: one :class:`Baseline` each."""
    from .evaluate import evaluate

    envs = {}
    for run in runs:
        if run.env_id is None:
            raise ValueError(f"run folder {str(run.path)!r} has no {CONFIG} to take the env from for the gait "
                             f"baseline {spec!r}; give the baseline as numbers (return=R,speed=S)")
        envs.setdefault(json.dumps([run.env_id, run.env_kwargs], sort_keys=True), (run.env_id, run.env_kwargs))
    out = []
    for env_id, kwargs in envs.values():
        _, summary = evaluate(spec, env_id, episodes=episodes, seed=seed, env_kwargs=kwargs)
        where = f" on {env_id.split('/')[-1]}" if len(envs) > 1 else ""
        out.append(Baseline(f"{spec}{where} (open loop, {episodes} episodes)", summary["return"], summary["speed"],
                            env_id))
    return out


# ---------------------------------------------------------------------------------------------- series
def series_rows(runs: list[Run], baselines: list[Baseline], window: int = WINDOW) -> list[dict]:
    """Every plotted series as CSV rows (module doc)."""
    rows = []

    def add(run, series, steps, values):
        for s, v in zip(steps, values):
            rows.append({"label": run.label, "run": str(run.path), "series": series, "env_steps": int(s),
                         "value": float(v)})

    for run in runs:
        m = run.monitor
        add(run, "return", m.steps, m.returns)
        add(run, "return_smoothed", m.steps, rolling_mean(m.returns, window))
        if m.speed is not None:
            add(run, "speed", m.steps, m.speed)
            add(run, "speed_smoothed", m.steps, rolling_mean(m.speed, window))
        if run.progress is not None:
            add(run, "ep_rew_mean", *run.progress)
    for b in baselines:
        for series, value in (("baseline_return", b.ret), ("baseline_speed", b.speed)):
            if value is not None:
                rows.append({"label": b.label, "run": "", "series": series, "env_steps": "", "value": value})
    return rows


def write_csv(path, rows: list[dict]) -> str:
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=CSV_COLUMNS)
        w.writeheader()
        for r in rows:
            w.writerow({**r, "value": format(r["value"], ".9g")})
    return str(path)


# ---------------------------------------------------------------------------------------------- figure
def supported_formats() -> list[str]:
    """File suffixes matplotlib's Agg canvas writes (``png``, ``pdf``, ``svg``, ...)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    return sorted(FigureCanvasAgg(Figure()).get_supported_filetypes())


def plot(runs: list[Run], baselines: list[Baseline], out, window: int = WINDOW) -> str:
    """Write the figure (return panel, and a speed panel when any run recorded speed) to ``out``."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    with_speed = [r for r in runs if r.monitor.speed is not None]
    panels = ["return"] + (["speed"] if with_speed else [])
    fig = Figure(figsize=(8.0, 3.2 * len(panels) + 0.4), constrained_layout=True)
    FigureCanvasAgg(fig)
    axes = np.atleast_1d(fig.subplots(len(panels), 1, sharex=True))
    colors = [f"C{k % 10}" for k in range(len(runs))]
    for run, c in zip(runs, colors):
        m = run.monitor
        for ax, values in zip(axes, (m.returns, m.speed)):
            if values is None:
                continue
            ax.plot(m.steps, values, color=c, lw=0.6, alpha=0.25)
            ax.plot(m.steps, rolling_mean(values, window), color=c, lw=1.6,
                    label=f"{run.label} ({m.lengths.size} episodes, mean of {window})")
        if run.progress is not None:
            axes[0].plot(*run.progress, color=c, lw=1.0, ls="--", label=f"{run.label}: SB3 rollout/ep_rew_mean")
    grays = ("0.15", "0.45", "0.65")
    styles = (":", "-.", (0, (5, 2)))
    for k, b in enumerate(baselines):
        look = {"color": grays[k % len(grays)], "ls": styles[k % len(styles)], "lw": 1.3}
        for ax, name, value in zip(axes, panels, (b.ret, b.speed)):
            if value is not None:
                unit = " m/s" if name == "speed" else ""
                ax.axhline(value, label=f"{b.label}: {number(value, '.3g')}{unit}", **look)
    axes[0].set_ylabel("episode return")
    axes[0].set_title("episode return (raw: faint; trailing mean: solid)", fontsize=10)
    if with_speed:
        axes[1].set_ylabel("forward speed (m/s)")
        axes[1].set_title("episode forward speed: x displacement / duration", fontsize=10)
    axes[-1].set_xlabel("env steps (cumulative episode lengths)")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="best")
    without = [r.label for r in runs if r.monitor.speed is None]
    if without:
        fig.text(0.01, 0.002, f"forward speed not plotted for {', '.join(without)}: its monitor.csv has no speed "
                 "column", fontsize=8, color="0.3", va="bottom")
        fig.get_layout_engine().set(rect=(0, 0.03, 1, 0.97))
    fig.savefig(out, dpi=110)
    return str(out)


# ---------------------------------------------------------------------------------------------- API
@dataclass
class PlotResult:
    out: str
    csv: str | None
    runs: list[Run]
    baselines: list[Baseline]


def plot_runs(runs, out, baselines=(), labels=None, window: int = WINDOW, csv_path=None, episodes: int = 3,
              seed: int = 0) -> PlotResult:
    """Plot the learning curves of the run folders ``runs`` to ``out`` (module doc); every input is checked
    before any gait is evaluated or file written."""
    from mjrft.tools.outputs import output_file

    runs = [runs] if isinstance(runs, (str, Path)) else list(runs)
    if not runs:
        raise ValueError("give at least one run folder")
    window = check_int("window", window, 1)
    episodes = check_int("episodes", episodes, 1)
    seed = check_int("seed", seed, 0)
    if labels is not None and len(labels) != len(runs):
        raise ValueError(f"--labels takes one label per run: {len(runs)} run(s), {len(labels)} label(s)")
    suffix = Path(out).suffix.lstrip(".").lower()
    formats = supported_formats()
    if suffix not in formats:
        raise ValueError(f"--out {str(out)!r}: unknown image type {suffix or '(no suffix)'!r}; valid suffixes: "
                         f"{', '.join(formats)}")
    output_file(out, "--out")
    if csv_path is not None:
        output_file(csv_path, "--csv")
    specs = [parse_baseline(b) for b in baselines]
    loaded = [load_run(p, None if labels is None else labels[k]) for k, p in enumerate(runs)]
    resolved = []
    for spec in specs:
        resolved += evaluate_baseline(spec, loaded, episodes, seed) if isinstance(spec, str) else [spec]
    plot(loaded, resolved, out, window)
    if csv_path is not None:
        write_csv(csv_path, series_rows(loaded, resolved, window))
    return PlotResult(str(out), None if csv_path is None else str(csv_path), loaded, resolved)


# ---------------------------------------------------------------------------------------------- CLI
def add_arguments(parser) -> None:
    parser.add_argument("runs", nargs="+", metavar="RUN", help="run folders written by 'mjrft train --out'")
    parser.add_argument("--out", required=True, metavar="FILE", help="figure file (.png, .pdf, .svg, ...)")
    parser.add_argument("--baseline", action="append", default=[], metavar="SPEC_OR_NUMBERS",
                        help="horizontal line, repeatable: a gait evaluated on the runs' env (tripod:f=2.5) or "
                             "numbers (return=338,speed=0.30)")
    parser.add_argument("--labels", nargs="+", default=None, help="one legend label per run (default: folder names)")
    parser.add_argument("--window", type=int_arg, default=WINDOW,
                        help=f"episodes in the trailing mean (default {WINDOW})")
    parser.add_argument("--episodes", type=int_arg, default=3,
                        help="episodes of a gait baseline's evaluation (default 3)")
    parser.add_argument("--seed", type=int_arg, default=0, help="a gait baseline's episode i resets with seed + i")
    parser.add_argument("--csv", default=None, metavar="FILE", help="also write the plotted series as CSV")


def main(args) -> int:
    from mjrft.tools.outputs import WarningNotes

    with WarningNotes() as notes:  # left-out lines, a gait baseline's terrain warnings: notes, as for mjrft demo
        result = plot_runs(args.runs, args.out, args.baseline, args.labels, args.window, args.csv, args.episodes,
                           args.seed)
    for run in result.runs:
        m = run.monitor
        tail = m.returns[-args.window:]
        line = (f"{run.label}: {m.lengths.size} episodes, {int(m.steps[-1])} env steps; last {tail.size}: "
                f"return {number(float(np.mean(tail)), '.4g')}")
        if m.speed is not None:
            line += f", speed {number(float(np.nanmean(m.speed[-args.window:])), '.3f')} m/s"
        else:
            line += " (no speed column in monitor.csv)"
        print(line)
    for b in result.baselines:
        parts = [f"return {number(b.ret, '.4g')}" if b.ret is not None else "",
                 f"speed {number(b.speed, '.3f')} m/s" if b.speed is not None else ""]
        print(f"baseline {b.label}: {', '.join(p for p in parts if p)}")
    notes.print()
    print(f"wrote {result.out}" + (f" and {result.csv}" if result.csv else ""))
    return 0

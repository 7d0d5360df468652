"""Learned hexapod gaits against the open-loop tripod, on sand and on rigid ground (the transfer table).

    python benchmarks/learning_transfer.py --policy sand=pretrained:HexapodSand-v0 \
        --policy rigid=runs/hexapod-rigid --policy randomised=runs/hexapod-sand-random

1. The tripod's best frequency on each of the two training grounds (``mjrft/HexapodSand-v0`` on
   poppy seeds and ``mjrft/HexapodRigid-v0``): the open-loop ``tripod`` gait at each of ``--frequencies``,
   ``--episodes`` deterministic episodes each, best = highest mean forward speed among the frequencies
   without a fall (``tripod_sweep.csv``).
2. Every policy, and the tripod at its best frequency on sand, evaluated with ``mjrft eval``'s metrics
   (:mod:`mjrft.train.evaluate`: speed, cost of transport, sinkage, foot slip, falls) on rigid ground and
   on each dry medium of :data:`MEDIA` (``transfer.csv``, ``transfer.md``). A policy trained with terrain
   randomisation is evaluated on each fixed ground (its randomisation switched off).

Every evaluation is the registered env (1000 steps = 10 s episodes), episode ``i`` reset with seed ``i``.
Writes to ``--out`` (default ``benchmarks/results/learning``).
"""

from __future__ import annotations

import argparse
import csv
import multiprocessing
import sys
import time
from pathlib import Path

SAND, RIGID = "mjrft/HexapodSand-v0", "mjrft/HexapodRigid-v0"
#: the dry media a policy is carried to (mjrft.MEDIA; the hexapod env's default is poppy_cp)
MEDIA = ("poppy_cp", "poppy_lp", "glass03_cp", "glass03_lp", "glass3_cp")
FREQUENCIES = (1.0, 1.5, 2.0, 2.25, 2.5, 2.75, 3.0)
METRICS = ("speed", "cot", "sink_mean_mm", "slip", "fall_rate", "return")


def grounds() -> list[tuple[str, str, dict]]:
    """(label, env id, env kwargs) of every ground of the table."""
    return [("rigid", RIGID, {})] + [(m, SAND, {"medium": m}) for m in MEDIA]


def _evaluate(job: tuple) -> dict:
    label, spec, ground, env_id, env_kwargs, episodes = job
    from mjrft.tools.gaits import is_gait_spec
    from mjrft.train.evaluate import evaluate, trained_env

    kwargs = dict(env_kwargs)
    if not is_gait_spec(spec) and trained_env(spec)[1].get("terrain_randomization") is not None:
        kwargs["terrain_randomization"] = None  # each ground of the table is one fixed terrain
    _, summary = evaluate(spec, env_id, episodes=episodes, seed=0, env_kwargs=kwargs)
    row = {"policy": label, "spec": spec, "ground": ground}
    row.update({m: summary[m] for m in METRICS})
    return row


def best_frequency(rows: list[dict]) -> float:
    """The tripod frequency with the highest mean speed among those whose episodes never fell (among all of
    them when every frequency falls)."""
    standing = [r for r in rows if r["fall_rate"] == 0.0] or rows
    return max(standing, key=lambda r: r["speed"])["f_hz"]


def _run(jobs: list[tuple], workers: int) -> list[dict]:
    if workers <= 1:
        return [_evaluate(j) for j in jobs]
    with multiprocessing.get_context("forkserver").Pool(workers) as pool:
        return pool.map(_evaluate, jobs, chunksize=1)


def _write_csv(path: Path, rows: list[dict]) -> None:
    with open(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
        fh.flush()


def _fmt(value: float, digits: int) -> str:
    return f"{value:.{digits}f}"


def transfer_markdown(rows: list[dict], best: dict[str, float], episodes: int) -> str:
    labels = list(dict.fromkeys(r["policy"] for r in rows))
    by = {(r["policy"], r["ground"]): r for r in rows}
    lines = [f"Mean of {episodes} deterministic 10 s episodes per cell (seeds 0..{episodes - 1}); "
             f"tripod at its best frequency on poppy_cp sand ({best[SAND]:g} Hz; on rigid ground its best is "
             f"{best[RIGID]:g} Hz). speed m/s, CoT dimensionless, sinkage mm (mean of the buried feet), slip m/s, "
             "falls = fraction of episodes ended by a fall.", ""]
    header = "| ground | " + " | ".join(f"{label}: speed / CoT / sink / slip / falls" for label in labels) + " |"
    lines += [header, "|" + "---|" * (len(labels) + 1)]
    for ground, _, _ in grounds():
        cells = []
        for label in labels:
            r = by[(label, ground)]
            cells.append(f"{_fmt(r['speed'], 3)} / {_fmt(r['cot'], 2)} / {_fmt(r['sink_mean_mm'], 1)} / "
                         f"{_fmt(r['slip'], 3)} / {_fmt(r['fall_rate'], 1)}")
        lines.append(f"| {ground} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--policy", action="append", default=[], metavar="LABEL=SPEC", required=True,
                        help="a policy to evaluate (model zip, run folder, pretrained:NAME), repeatable")
    parser.add_argument("--episodes", type=int, default=10)
    parser.add_argument("--frequencies", type=float, nargs="+", default=list(FREQUENCIES))
    parser.add_argument("--workers", type=int, default=2, help="evaluation processes (default 2)")
    parser.add_argument("--out", default="benchmarks/results/learning")
    args = parser.parse_args(argv)

    from mjrft.tools.outputs import output_dir
    from mjrft.train.evaluate import load_policy

    policies = []
    for item in args.policy:
        label, sep, spec = item.partition("=")
        if not sep or not label or not spec:
            parser.error(f"--policy takes LABEL=SPEC, got {item!r}")
        load_policy(spec)  # a bad path fails here, before any evaluation
        policies.append((label, spec))
    if args.episodes < 1:
        parser.error(f"--episodes must be >= 1, got {args.episodes}")
    out = Path(output_dir(args.out))
    t0 = time.perf_counter()

    sweep_jobs = [(f"tripod f={f:g}", f"tripod:f={f:g}", env_id, env_id, {}, args.episodes)
                  for env_id in (SAND, RIGID) for f in args.frequencies]
    sweep = _run(sweep_jobs, args.workers)
    for row, f in zip(sweep, [f for _ in (SAND, RIGID) for f in args.frequencies]):
        row["f_hz"] = f
    _write_csv(out / "tripod_sweep.csv", sweep)
    best = {env_id: best_frequency([r for r in sweep if r["ground"] == env_id]) for env_id in (SAND, RIGID)}
    for env_id in (SAND, RIGID):
        print(f"tripod on {env_id}: " + ", ".join(f"{r['f_hz']:g} Hz {r['speed']:.3f} m/s (CoT {r['cot']:.2f})"
                                                  for r in sweep if r["ground"] == env_id)
              + f"; best {best[env_id]:g} Hz")

    tripod = (f"tripod {best[SAND]:g} Hz", f"tripod:f={best[SAND]:g}")
    jobs = [(label, spec, ground, env_id, kwargs, args.episodes)
            for label, spec in [*policies, tripod] for ground, env_id, kwargs in grounds()]
    rows = _run(jobs, args.workers)
    _write_csv(out / "transfer.csv", rows)
    table = transfer_markdown(rows, best, args.episodes)
    (out / "transfer.md").write_text(table)
    print(table)
    print(f"wrote {out / 'tripod_sweep.csv'}, {out / 'transfer.csv'}, {out / 'transfer.md'} "
          f"({time.perf_counter() - t0:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())

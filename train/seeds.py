"""A recipe over several seeds: the spread of each result over the seeds and the table that reports it.

Each seed is a run of its own (``mjrft train --seed S`` / ``mjrft train-mjx --seed S``, each in its own run folder);
:func:`spread` gives a measure's mean, sample standard deviation and range over the seeds, and :func:`seeds_table`
writes one row per seed and the mean, sample standard deviation, minimum and maximum of every column, as
``benchmarks/results/learning/recipe_seeds.txt`` reports the SB3 recipe ``hexapod-sand`` over three seeds.
``mjrft train-mjx --seeds 0 1 2`` (:mod:`mjrft.train.mjx_ppo`) writes its summary with them.
"""

from __future__ import annotations

import math

import numpy as np


def spread(values) -> dict:
    """Mean, sample standard deviation (``ddof=1``; NaN for fewer than two values), minimum and maximum of the
    finite ``values``, and their count ``n`` (a seed whose measure is NaN, e.g. every episode diverged, is left
    out and counted out of ``n``); NaN everywhere when none is finite."""
    v = np.asarray([float(x) for x in values], dtype=float)
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


__all__ = ["seeds_table", "spread"]

"""Calibration from measurements: the wet-sand speed factor and the hybrid model's bar-drag constants.

Both fitters take either a CSV file (a header row naming the columns, then one sample per row; SI
units; blank lines and lines starting with ``#`` are skipped; extra columns are ignored) or arrays.
Malformed input raises ``ValueError`` naming the file (or array), the row and the column.

* :func:`fit_wet_speed_coefficient` - columns ``depth`` (m), ``speed`` (m/s), ``force`` (N): a plate
  dragged at several speeds and depths. The model is the one of :mod:`mjrft.laws.wet`,
  ``force = alpha_base x depth x (1 + eps_v (speed - v_base) / dv)``, fitted the paper's way as a
  straight line (ordinary least squares of force / depth on (speed - v_base) / dv: intercept
  alpha_base, eps_v = slope / intercept). Samples shallower than ``min_depth`` (default 10 mm: the
  paper finds the top 10 mm fluctuating while the surface yields) are left out. The result's
  :meth:`WetSpeedFit.extra` goes into ``Medium.with_extra``; [v_min, v_max] is the measured speed
  range (the calibrated range, reported by the validity checks; it does not change the force).
* :func:`fit_hybrid_constants` - columns ``psi`` (radians; or ``psi_deg`` in degrees), ``depth``
  (m), ``F_perp``, ``F_par`` (N per metre of bar): bar-drag tests. At each depth (samples grouped by
  depth rounded to 1 um), linear least squares of the bar-drag fit of :mod:`mjrft.laws.hybrid`:
  F_perp = C_perp^h + (C_perp - C_perp^h) sin psi, and
  F_par = C_par^h (1 - sin psi / sin 36deg) + C_par sin psi / sin 36deg (psi <= 36 deg),
  C_par cos psi / cos 36deg (beyond). C_par / C_perp is the least-squares slope through the origin
  over all depths. :meth:`mjrft.laws.hybrid.HybridModel.from_fit` uses the result.
"""

from __future__ import annotations

import csv
import math
import os
from dataclasses import dataclass

import numpy as np

from mjrft.errors import check_positive
from mjrft.laws.hybrid import COS_BREAK, SIN_BREAK
from mjrft.laws.wet import DV, V_BASE, speed_factor

__all__ = ["HybridFit", "WetSpeedFit", "fit_hybrid_constants", "fit_wet_speed_coefficient", "read_columns"]


# ------------------------------------------------------------------------------------------------
# input
# ------------------------------------------------------------------------------------------------
def _is_path(x) -> bool:
    return isinstance(x, (str, bytes, os.PathLike))


def read_columns(path, columns, *, alternatives=None, min_rows=1) -> dict:
    """Read numeric ``columns`` from the CSV file ``path``; errors name the file, line and column.

    ``alternatives`` maps a column to another accepted header (e.g. ``{"psi": "psi_deg"}``); the
    returned dict is keyed by the header actually found.
    """
    alternatives = alternatives or {}
    try:
        fh = open(path, newline="")
    except OSError as exc:
        raise FileNotFoundError(f"{path}: cannot open calibration file ({exc.strerror})") from None
    with fh:
        rows = [(i + 1, r) for i, r in enumerate(csv.reader(fh))]
    rows = [(ln, [c.strip() for c in r]) for ln, r in rows if r and any(c.strip() for c in r)
            and not r[0].lstrip().startswith("#")]
    if not rows:
        raise ValueError(f"{path}: empty file, expected a header row with columns {', '.join(columns)}")
    head_line, header = rows[0]
    index = {}
    for col in columns:
        names = [col] + ([alternatives[col]] if col in alternatives else [])
        found = [n for n in names if n in header]
        if not found:
            alt = f" (or {alternatives[col]!r})" if col in alternatives else ""
            raise ValueError(f"{path}: missing column {col!r}{alt} in the header on line {head_line}; "
                             f"found columns {header!r}")
        index[found[0]] = header.index(found[0])
    data = {k: [] for k in index}
    for ln, r in rows[1:]:
        for name, j in index.items():
            if j >= len(r) or r[j] == "":
                raise ValueError(f"{path}, line {ln}, column {name!r}: missing value")
            try:
                v = float(r[j])
            except ValueError:
                raise ValueError(f"{path}, line {ln}, column {name!r}: {r[j]!r} is not a number") from None
            if not math.isfinite(v):
                raise ValueError(f"{path}, line {ln}, column {name!r}: {r[j]!r} is not finite")
            data[name].append(v)
    n = len(rows) - 1
    if n < min_rows:
        raise ValueError(f"{path}: too few data rows, need at least {min_rows}, got {n}")
    out = {k: np.array(v) for k, v in data.items()}
    out["_lines"] = np.array([ln for ln, _ in rows[1:]])
    out["_source"] = str(path)
    return out


def _array(name, values, n=None):
    try:
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be an array of numbers, got {values!r}") from None
    if arr.ndim != 1:
        arr = arr.ravel()
    if n is not None and arr.size != n:
        raise ValueError(f"{name} has {arr.size} values, expected {n} (one per sample)")
    bad = np.flatnonzero(~np.isfinite(arr))
    if bad.size:
        raise ValueError(f"{name}[{bad[0]}] = {float(arr[bad[0]])!r} is not finite")
    return arr


class _Where:
    """Names a sample in messages: 'file, line L' for CSV input or 'sample i' for arrays."""

    def __init__(self, source, lines):
        self.source, self.lines = source, lines

    def __call__(self, i, col):
        if self.lines is not None:
            return f"{self.source}, line {int(self.lines[i])}, column {col!r}"
        return f"{col}[{i}]"

    def whole(self):
        return self.source if self.lines is not None else "the data"


def _load(first, rest, columns, alternatives=None, min_rows=1):
    if _is_path(first):
        if any(r is not None for r in rest):
            raise TypeError("pass either a CSV path or the arrays, not both")
        d = read_columns(first, columns, alternatives=alternatives, min_rows=min_rows)
        return d, _Where(d["_source"], d["_lines"])
    if first is None or any(r is None for r in rest):
        raise TypeError(f"pass a CSV path or all of the arrays {', '.join(columns)}")
    vals = [first, *rest]
    n = np.asarray(first).size
    d = {c: _array(c, v, n) for c, v in zip(columns, vals)}
    if n < min_rows:
        raise ValueError(f"too few samples, need at least {min_rows}, got {n}")
    return d, _Where("arrays", None)


# ------------------------------------------------------------------------------------------------
# wet sand
# ------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class WetSpeedFit:
    """Result of :func:`fit_wet_speed_coefficient` (SI)."""

    eps_v: float  # relative force increase per dv
    v_base: float  # m/s
    dv: float  # m/s
    alpha_base: float  # force per depth at v_base, N/m
    v_min: float  # measured speed range, m/s
    v_max: float
    r2: float  # of the straight-line fit
    n: int  # samples used

    def extra(self) -> dict:
        """The ``Medium.with_extra`` constants of :mod:`mjrft.laws.wet`."""
        return {"wet_eps_v": self.eps_v, "wet_v_base": self.v_base, "wet_dv": self.dv,
                "wet_v_min": self.v_min, "wet_v_max": self.v_max}

    def factor(self, speed):
        """The wet law's speed factor with these constants (:func:`mjrft.laws.wet.speed_factor`)."""
        return speed_factor(speed, self.eps_v, self.v_base, self.dv)


def fit_wet_speed_coefficient(data, speed=None, force=None, *, v_base=V_BASE, dv=DV, min_depth=0.01) -> WetSpeedFit:
    """Velocity coefficient eps_v (per ``dv``) and base force per depth from plate drags.

    ``data``: a CSV path (columns ``depth``, ``speed``, ``force``) or the ``depth`` array, with
    ``speed`` and ``force`` arrays. See the module docstring for the model.
    """
    d, where = _load(data, (speed, force), ("depth", "speed", "force"), min_rows=3)
    v_base = check_positive("v_base", v_base, allow_zero=True)
    dv = check_positive("dv", dv)
    min_depth = check_positive("min_depth", min_depth, allow_zero=True)
    dep, spd, frc = d["depth"], d["speed"], d["force"]
    for i in range(dep.size):
        if dep[i] < 0:
            raise ValueError(f"{where(i, 'depth')}: depth must be >= 0 (below the surface), got {float(dep[i])!r}")
        if spd[i] < 0:
            raise ValueError(f"{where(i, 'speed')}: speed must be >= 0, got {float(spd[i])!r}")
        if dep[i] >= min_depth and dep[i] > 0 and frc[i] <= 0:
            raise ValueError(f"{where(i, 'force')}: force must be > 0 below min_depth, got {float(frc[i])!r}")
    keep = (dep >= min_depth) & (dep > 0)
    if np.count_nonzero(keep) < 3:
        raise ValueError(f"{where.whole()}: need at least 3 samples at depth >= min_depth = {min_depth!r} m, "
                         f"got {int(np.count_nonzero(keep))}")
    dep, spd, frc = dep[keep], spd[keep], frc[keep]
    if np.unique(spd).size < 2:
        raise ValueError(f"{where.whole()}: need at least 2 different speeds to fit a speed coefficient, "
                         f"got only {float(spd[0])!r} m/s")
    x = (spd - v_base) / dv
    y = frc / dep
    a = np.stack([np.ones_like(x), x], axis=1)
    (c0, c1), *_ = np.linalg.lstsq(a, y, rcond=None)
    resid = y - a @ np.array([c0, c1])
    ss = float(np.sum((y - y.mean()) ** 2))
    r2 = 1.0 - float(np.sum(resid ** 2)) / ss if ss > 0 else 1.0
    if not c0 > 0:
        raise ValueError(f"{where.whole()}: the fitted force per depth at v_base = {v_base!r} m/s is {float(c0):.4g} "
                         "N/m, not > 0; the data do not fit force = alpha_base x depth x (1 + eps_v (v - v_base) / dv)")
    return WetSpeedFit(eps_v=float(c1 / c0), v_base=v_base, dv=dv, alpha_base=float(c0),
                       v_min=float(spd.min()), v_max=float(spd.max()), r2=r2, n=int(dep.size))


# ------------------------------------------------------------------------------------------------
# hybrid bar drag
# ------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class HybridFit:
    """Result of :func:`fit_hybrid_constants`: per-depth constants (N/m) and the C_par/C_perp ratio."""

    depth: np.ndarray
    c_perp: np.ndarray
    c_perp_h: np.ndarray
    c_par: np.ndarray
    c_par_h: np.ndarray
    c_par_ratio: float
    n: int


def fit_hybrid_constants(data, depth=None, f_perp=None, f_par=None) -> HybridFit:
    """C_perp, C_par and the C^h values at each depth from bar-drag samples (module docstring).

    ``data``: a CSV path (columns ``psi`` in radians or ``psi_deg`` in degrees, ``depth``, ``F_perp``,
    ``F_par``) or the ``psi`` array (radians), with ``depth``, ``f_perp`` and ``f_par`` arrays.
    """
    d, where = _load(data, (depth, f_perp, f_par), ("psi", "depth", "F_perp", "F_par"),
                     alternatives={"psi": "psi_deg"}, min_rows=4)
    if "psi_deg" in d:
        psi_col, psi = "psi_deg", np.radians(d["psi_deg"])
        raw = d["psi_deg"]
        limit = 90.0
    else:
        psi_col, psi = "psi", d["psi"]
        raw = psi
        limit = math.pi / 2
    dep, fp, fq = d["depth"], d["F_perp"], d["F_par"]
    for i in range(dep.size):
        if not (0.0 <= raw[i] <= limit * (1 + 1e-12)):
            raise ValueError(f"{where(i, psi_col)}: psi must be in [0, {limit:g}], got {float(raw[i])!r}")
        if dep[i] <= 0:
            raise ValueError(f"{where(i, 'depth')}: depth must be > 0 (below the surface), got {float(dep[i])!r}")
    key = np.round(dep, 6)
    depths = np.unique(key)
    out = {k: np.empty(depths.size) for k in ("c_perp", "c_perp_h", "c_par", "c_par_h")}
    for k, dd in enumerate(depths):
        idx = np.flatnonzero(key == dd)
        sp = np.sin(psi[idx])
        cp = np.cos(psi[idx])
        if np.unique(np.round(sp, 12)).size < 2:
            raise ValueError(f"{where.whole()}: depth {float(dd)!r} m needs samples at 2 or more different psi, "
                             f"got {idx.size} sample(s) at psi = {float(psi[idx[0]])!r} rad")
        a = np.stack([1.0 - sp, sp], axis=1)  # C_perp^h (1 - sin psi) + C_perp sin psi
        (ch, c), *_ = np.linalg.lstsq(a, fp[idx], rcond=None)
        reg1 = sp <= SIN_BREAK
        b = np.stack([np.where(reg1, 1.0 - sp / SIN_BREAK, 0.0), np.where(reg1, sp / SIN_BREAK, cp / COS_BREAK)],
                     axis=1)
        sol, _, rank, _ = np.linalg.lstsq(b, fq[idx], rcond=None)
        if rank < 2:
            raise ValueError(f"{where.whole()}: depth {float(dd)!r} m: F_par needs a sample below 36 deg and one at a "
                             f"different psi to separate C_par^h from C_par")
        out["c_perp_h"][k], out["c_perp"][k] = ch, c
        out["c_par_h"][k], out["c_par"][k] = sol
    cp_all = out["c_perp"]
    denom = float(np.dot(cp_all, cp_all))
    if denom <= 0:
        raise ValueError(f"{where.whole()}: fitted C_perp is zero at every depth, can not form C_par / C_perp")
    ratio = float(np.dot(out["c_par"], cp_all) / denom)
    return HybridFit(depth=depths.astype(float), c_perp=out["c_perp"], c_perp_h=out["c_perp_h"], c_par=out["c_par"],
                     c_par_h=out["c_par_h"], c_par_ratio=ratio, n=int(dep.size))

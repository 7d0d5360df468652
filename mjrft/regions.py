"""Regions of the surface with their own medium, law and water depth: strips along x or a map over (x, y), and
the kernel's per-region tables built from them.

:class:`Region` and :class:`RegionMap` are the user's description; :func:`build_regions` turns a terrain's
settings into :class:`~mjrft.types.RegionTables` (law ids, each region's parameter row with its water layer, drag and
inertial constants, the buoyancy's water density, the strips' bounds or the map); each law's part of them comes
from its entry in :mod:`mjrft.laws.registry`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .errors import UnknownNameError, check_finite, check_positive, unknown
from .laws.inertial import set_inertial
from .laws.registry import DRY_LAWS, LAW_IDS, LAWS, STRESS_SLOTS, get_law, parameter_vector
from .laws.wet import wet_constants
from .params import P_WATER_DEPTH, P_WATER_DRAG
from .media import MEDIA, Medium, get_medium
from .types import RegionTables

if TYPE_CHECKING:
    from .settings import TerrainSettings


LAW_WATER = LAW_IDS["water"]
_SATURATED_LAWS = tuple(law.id for law in LAWS if law.saturated)


@dataclass(frozen=True)
class Region:
    """Part of the surface with its own medium, law and water depth (see :class:`GranularTerrain`).

    ``x_min``: start of the strip ``x_min <= x < next x_min`` (strips along x); ``None`` for a region
    used through a :class:`RegionMap`. ``water_depth`` (m, >= 0): free water standing above the sand;
    ``None`` takes the medium's own ``water_depth`` constant (0 unless set, ``mjrft.laws.wet``).
    """

    x_min: float | None
    medium: Medium | str
    law: str
    water_depth: float | None = None


@dataclass(frozen=True)
class RegionMap:
    """A grid of region ids over the (x, y) plane: ``ids[j, i]`` covers the cell
    ``x_min + i cell_x <= x < x_min + (i + 1) cell_x``, ``y_min + j cell_y <= y < ...``; id 0 is the
    terrain's own medium/law/water depth and id k the terrain's ``regions[k - 1]``. Outside the grid the
    border cells continue."""

    ids: np.ndarray
    x_min: float
    y_min: float
    cell: float | tuple


def _region_entries(regions, mapped: bool) -> list[Region]:
    """Normalise ``regions`` (Region objects, tuples or the MJCF text) to a list of :class:`Region`."""
    if regions is None:
        return []
    if isinstance(regions, str):
        items = [tuple(part.split()) for part in regions.split(";") if part.strip()]
    else:
        items = list(regions)
    out = []
    shape = "(medium, law[, water_depth])" if mapped else "(x_min, medium, law[, water_depth])"
    for k, item in enumerate(items, start=1):
        if isinstance(item, Region):
            reg = item
        else:
            item = tuple(item)
            n0 = 0 if mapped else 1
            if mapped and item and isinstance(item[0], (int, float, np.number)) and not isinstance(item[0], bool):
                raise ValueError(f"region {k}: regions used by a region_map take no x_min, got {item!r}; give {shape}")
            if len(item) not in (n0 + 2, n0 + 3):
                raise ValueError(f"region {k}: expected {shape}, got {item!r}")
            reg = Region(None if mapped else item[0], item[n0], item[n0 + 1], item[n0 + 2] if len(item) > n0 + 2 else None)
        if mapped and reg.x_min is not None:
            raise ValueError(f"region {k}: regions used by a region_map take no x_min, got x_min={reg.x_min!r}; "
                             f"give {shape}")
        if not mapped and reg.x_min is None:
            raise ValueError(f"region {k}: strips along x need x_min (or pass region_map=...); give {shape}")
        out.append(reg)
    return out


def _region_map(value, n_regions: int, transition: float) -> tuple[np.ndarray, np.ndarray]:
    """(ids (ny, nx) int64, frame [x_min, y_min, cell_x, cell_y]) from a RegionMap or the MJCF numeric
    ``x_min y_min cell_x cell_y nx ny ids...``."""
    if isinstance(value, RegionMap):
        ids, x0, y0, cell = value.ids, value.x_min, value.y_min, value.cell
        cx, cy = (cell, cell) if np.ndim(cell) == 0 else tuple(cell)
    else:
        vals = np.atleast_1d(np.asarray(value, dtype=float))
        if vals.size < 7:
            raise ValueError("region_map from <custom> needs 'x_min y_min cell_x cell_y nx ny id...', "
                             f"got {vals.size} numbers")
        x0, y0, cx, cy, nx, ny = vals[:6]
        if nx != int(nx) or ny != int(ny) or nx < 1 or ny < 1 or vals.size != 6 + int(nx) * int(ny):
            raise ValueError(f"region_map: nx = {nx:g}, ny = {ny:g} must be integers >= 1 followed by nx x ny ids, "
                             f"got {vals.size - 6} ids")
        ids = vals[6:].reshape(int(ny), int(nx))
    x0, y0 = check_finite("region_map x_min", x0), check_finite("region_map y_min", y0)
    cx, cy = check_positive("region_map cell_x", cx), check_positive("region_map cell_y", cy)
    arr = np.asarray(ids)
    if arr.ndim != 2 or arr.size == 0:
        raise ValueError(f"region_map ids must be a non-empty 2D array (ny, nx), got shape {arr.shape}")
    if not np.all(np.isfinite(arr.astype(float))) or np.any(arr != np.round(arr)):
        raise ValueError("region_map ids must be integers")
    arr = arr.astype(np.int64)
    bad = np.argwhere((arr < 0) | (arr > n_regions))
    if len(bad):
        j, i = bad[0]
        raise ValueError(f"region_map id {arr[j, i]} at row {j}, column {i} is not a region: valid ids 0..{n_regions} "
                         "(0 = the terrain's own medium and law, k = regions[k - 1])")
    if transition > min(cx, cy):
        raise ValueError(f"transition width {transition:g} m exceeds the region_map cell {min(cx, cy):g} m; "
                         "pass transition <= the cell size")
    return np.ascontiguousarray(arr), np.array([x0, y0, cx, cy], dtype=np.float64)


def _region_row(k: int, reg: Region, s: TerrainSettings) -> tuple[Medium, int, np.ndarray, float, float]:
    """(medium, law id, parameter row, water depth, buoyancy's water density) of region ``k``."""
    where = "" if k == 0 else f"region {k} "
    try:
        med = get_medium(reg.medium)
    except UnknownNameError:
        raise unknown(f"{where}medium", reg.medium, MEDIA) from None
    try:
        law = get_law(reg.law)
    except UnknownNameError:
        raise unknown(f"{where}law", reg.law, LAW_IDS) from None
    wc = wet_constants(med)
    hw = wc["water_depth"] if reg.water_depth is None else reg.water_depth
    hw = check_positive(f"{where}water_depth", hw, allow_zero=True)
    rho = wc["water_density"] if s.water_density is None else s.water_density
    cd = wc["drag_coefficient"] if s.drag_coefficient is None else s.drag_coefficient
    p = parameter_vector(med)
    p[P_WATER_DEPTH] = hw
    p[P_WATER_DRAG] = cd * rho
    if s.inertial and law.dry:
        try:
            set_inertial(p, med, s.inertial_drag)
        except ValueError as exc:
            raise ValueError(f"{where}inertial=True: {exc}") from None
    return med, law.id, p, hw, (rho if s.buoyancy and (hw > 0 or law.id in _SATURATED_LAWS) else 0.0)


def _next_strip(k: int, x_min, bounds: list, transition: float) -> float:
    """Region ``k``'s strip start, checked against the strips before it (sorted, at least ``transition`` wide)."""
    x_min = check_finite(f"region {k} x_min", x_min)
    if bounds and x_min <= bounds[-1]:
        raise ValueError(f"regions must be sorted by increasing x_min, got {x_min!r} after {bounds[-1]!r}")
    if bounds and x_min - bounds[-1] < transition:
        raise ValueError(f"region {k - 1} is {x_min - bounds[-1]:g} m wide (x_min {bounds[-1]!r} to "
                         f"{x_min!r}), less than the transition width {transition:g} m; "
                         "widen it or pass a smaller transition")
    return x_min


def build_regions(s: TerrainSettings, stress_scale: float = 1.0) -> tuple[tuple[Region, ...], RegionTables, bool]:
    """The regions of the settings' own region and its strips or mapped regions: (the resolved :class:`Region` of
    each row, the kernel's :class:`~mjrft.types.RegionTables` with every granular stress times ``stress_scale``
    (:data:`~mjrft.laws.registry.STRESS_SLOTS`), whether the inertial regime applies: off for a scene file's
    ``mjrft:inertial`` when no region has a dry law). Raises on the first bad region, naming it."""
    base = Region(None, s.medium, s.law, s.water_depth)
    laws, params, rhos, bounds, regions = [], [], [], [], []
    for k, reg in enumerate([base, *s.regions]):
        med, lid, p, hw, rho = _region_row(k, reg, s)
        laws.append(lid)
        params.append(p)
        rhos.append(rho)
        x_min = None
        if k > 0 and s.region_map is None:
            x_min = _next_strip(k, reg.x_min, bounds, s.transition)
            bounds.append(x_min)
        regions.append(Region(x_min, med, str(reg.law), hw))
    rmap, rframe = np.zeros((0, 0), dtype=np.int64), np.zeros(4)
    if s.region_map is not None:
        rmap, rframe = _region_map(s.region_map, len(s.regions), s.transition)
    inertial = s.inertial
    if inertial and not any(str(r.law) in DRY_LAWS for r in regions):
        if not s.inertial_given:  # a scene file's mjrft:inertial applies to its dry regions; here there are none
            inertial = False
        else:
            raise ValueError(f"inertial=True needs a region with a dry law ({', '.join(DRY_LAWS)}); the terrain's "
                             f"laws are {', '.join(sorted({str(r.law) for r in regions}))}")
    params = np.ascontiguousarray(np.array(params, dtype=np.float64))
    if stress_scale != 1.0:
        params[:, STRESS_SLOTS] *= stress_scale
    tables = RegionTables(np.array(bounds, dtype=np.float64), np.array(laws, dtype=np.int64), params,
                          np.array(rhos, dtype=np.float64), rmap, rframe, float(s.transition))
    return tuple(regions), tables, inertial

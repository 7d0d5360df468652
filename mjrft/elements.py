"""The surface elements of the selected geoms as the kernel reads them, in cull groups.

:func:`build_elements` cuts the geoms into elements of about the resolution (:mod:`mjrft.geometry`), keeps the
exposed ones and groups them into cull boxes of at most :data:`CULL_GROUP` elements of one geom, which the kernel
skips while they lie above the surface; :func:`check_element_count` refuses a resolution that would build more
than :data:`MAX_ELEMENTS` before anything is built.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from .errors import check_positive
from .geometry import Elements, discretize_geom, estimate_elements, exposed_elements, to_geom_frame


#: largest element count a terrain builds unless told otherwise (``max_elements``): about 15 s and 0.4 GB
#: to build on a 2-core machine, and far past where a finer resolution changes a robot's forces
MAX_ELEMENTS = 1_000_000
CULL_GROUP = 32  # elements per cull box (the kernel skips a box lying wholly above the surface)
CULL_PAD = 1e-9  # m, added to each cull box's half sizes: rounding never culls an element at the surface


def check_element_count(model: mujoco.MjModel, geom_ids, resolution: float, max_elements) -> None:
    """Refuse, before building anything, a resolution that would make more than ``max_elements`` elements
    (default :data:`MAX_ELEMENTS`)."""
    limit = MAX_ELEMENTS if max_elements is None else int(check_positive("max_elements", max_elements))
    n = estimate_elements(model, geom_ids, resolution)
    if n > limit:
        area = n * resolution**2
        suggest = math.sqrt(area / 1e5)
        raise ValueError(f"resolution {resolution:g} m would cut the {len(geom_ids)} selected geoms into about "
                         f"{n:,} elements, more than max_elements = {limit:,} (minutes and gigabytes to build); "
                         f"use a coarser resolution (about {suggest:.2g} m gives 100,000 elements) or pass "
                         "max_elements=... if you mean it")


@dataclass
class ElementTables:
    """The surface elements of the selected geoms, as the kernel reads them: per element its position and
    normal in its geom's frame (``lpos``, ``lnrm``), ``area``, geom and body; per cull group (runs of at most
    :data:`CULL_GROUP` consecutive elements of one geom) its geom, body, first element (``g_start``, one past
    the last at the end) and the box of its element points in the geom frame (``g_aabb``: centre, half sizes,
    what MuJoCo's geom_aabb is for the whole geom), so the part of a leg above the sand costs no element work."""

    elements: Elements
    geom_ids: np.ndarray  # the geoms with exposed elements, in element order
    lpos: np.ndarray
    lnrm: np.ndarray
    area: np.ndarray
    elem_geom: np.ndarray
    elem_body: np.ndarray
    body_ids: np.ndarray  # the bodies that own elements, sorted
    g_geom: np.ndarray
    g_body: np.ndarray
    g_start: np.ndarray
    g_aabb: np.ndarray


def _cull_groups(model: mujoco.MjModel, groups) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(geom, body, start, aabb) of the cull groups of ``groups`` = [(geom id, Elements), ...] (see ElementTables)."""
    g_geom, g_start, g_aabb = [], [0], []
    for gid, el in groups:
        local = to_geom_frame(model, gid, el.pos)
        for a in range(0, len(el), CULL_GROUP):
            pts = local[a:a + CULL_GROUP]
            lo, hi = pts.min(axis=0), pts.max(axis=0)
            g_geom.append(gid)
            g_start.append(g_start[-1] + len(pts))
            g_aabb.append(np.concatenate([(lo + hi) / 2, (hi - lo) / 2 + CULL_PAD]))
    g_geom = np.array(g_geom, dtype=np.int64)
    return (g_geom, np.ascontiguousarray(model.geom_bodyid[g_geom], dtype=np.int64), np.array(g_start, dtype=np.int64),
            np.ascontiguousarray(np.array(g_aabb, dtype=np.float64).reshape(-1, 6)))


def build_elements(model: mujoco.MjModel, geom_ids, resolution: float) -> ElementTables:
    """Cut the geoms into elements of about ``resolution`` and keep the exposed ones (only the exposed surface
    of each body's union of geoms meets grains, see :func:`~mjrft.geometry.exposed_elements`)."""
    parts = [discretize_geom(model, gid, resolution) for gid in geom_ids]
    groups = list(zip(geom_ids, exposed_elements(model, geom_ids, parts, resolution)))
    if not groups:
        raise ValueError("no geoms selected for the granular terrain")
    ids = np.array([g for g, _ in groups], dtype=np.int64)
    g_geom, g_body, g_start, g_aabb = _cull_groups(model, groups)
    elements = Elements.concatenate([el for _, el in groups])
    elem_geom = np.repeat(ids, [len(el) for _, el in groups])
    return ElementTables(elements, ids, np.ascontiguousarray(elements.pos, dtype=np.float64),
                         np.ascontiguousarray(elements.normal, dtype=np.float64),
                         np.ascontiguousarray(elements.area, dtype=np.float64), elem_geom,
                         np.ascontiguousarray(model.geom_bodyid[elem_geom], dtype=np.int64), np.unique(g_body),
                         g_geom, g_body, g_start, g_aabb)

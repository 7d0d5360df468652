"""The surface elements of the selected geoms as the kernel reads them, in cull groups.

:func:`build_elements` cuts the geoms into elements of about the resolution (:mod:`mjrft.geometry`), keeps the
exposed ones, orders each geom's elements so that runs of :data:`CULL_GROUP` are compact (:func:`compact_order`)
and groups them into those runs' cull boxes, which the kernel skips while they lie above the surface;
:func:`check_element_count` refuses a resolution that would build more than :data:`MAX_ELEMENTS` before anything
is built.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from .errors import check_positive
from .geometry import Elements, discretize_geom, estimate_elements, exposed_elements, to_geom_frame
from .types import ElementTables


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


def compact_order(points: np.ndarray, size: int = CULL_GROUP) -> np.ndarray:
    """An order of ``points`` (k, 3) whose consecutive runs of ``size`` are compact: the points are split along the
    longest side of their box, the first part a multiple of ``size`` long (half the runs), and each part again (a
    k-d tree whose leaves are the runs; stable sorts, so equal coordinates keep their order). A run's box then
    stays small in every direction, so however a geom turns, the runs above the sand are culled whole."""
    def split(idx: np.ndarray) -> list[np.ndarray]:
        if len(idx) <= size:
            return [idx]
        p = points[idx]
        axis = int(np.argmax(p.max(axis=0) - p.min(axis=0)))
        idx = idx[np.argsort(p[:, axis], kind="stable")]
        first = (-(-len(idx) // size) // 2) * size
        return split(idx[:first]) + split(idx[first:])

    return np.concatenate(split(np.arange(len(points))))


def _cull_groups(model: mujoco.MjModel, groups) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(geom, body, start, aabb) of the cull groups of ``groups`` = [(geom id, Elements), ...] (see
    :class:`~mjrft.types.ElementTables`)."""
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


def check_mesh_winding(model: mujoco.MjModel, geom_ids) -> None:
    """Refuse a closed mesh geom whose faces wind clockwise seen from outside (its normals point inward, its
    signed volume is negative): MuJoCo compiles it (it takes the volume's magnitude for the inertia), but every
    element's normal would be reversed and the grains would push the wrong way. Open meshes are not checked."""
    for g in geom_ids:
        if int(model.geom_type[g]) != int(mujoco.mjtGeom.mjGEOM_MESH):
            continue
        mid = int(model.geom_dataid[g])
        va, fa = int(model.mesh_vertadr[mid]), int(model.mesh_faceadr[mid])
        v = np.asarray(model.mesh_vert[va:va + int(model.mesh_vertnum[mid])], dtype=np.float64)
        f = np.asarray(model.mesh_face[fa:fa + int(model.mesh_facenum[mid])], dtype=np.int64)
        if len(f) == 0:
            continue
        # closed: every edge is walked both ways (vertices at the same place count as one: float32 positions)
        _, same = np.unique(np.round(v * 1e6), axis=0, return_inverse=True)
        w = same.reshape(-1)[f]
        edges = np.concatenate([w[:, [0, 1]], w[:, [1, 2]], w[:, [2, 0]]]) @ np.array([len(v), 1])
        reverse = np.concatenate([w[:, [1, 0]], w[:, [2, 1]], w[:, [0, 2]]]) @ np.array([len(v), 1])
        if not np.isin(reverse, edges).all():
            continue  # open: no inside to point to
        a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
        volume = float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum()) / 6.0
        area = 0.5 * float(np.linalg.norm(np.cross(b - a, c - a), axis=1).sum())
        if volume < -1e-6 * area**1.5:
            name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, int(g))
            mesh = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_MESH, mid)
            raise ValueError(f"mesh geom {int(g)}{f' {name!r}' if name else ''} (mesh {mesh!r}) is inside out: its "
                             f"faces wind clockwise seen from outside (signed volume {volume:.3g} m^3), so its "
                             "normals point inward and the grains would push it the wrong way; reverse the order "
                             "of each face's vertices")


def _compact(model: mujoco.MjModel, gid: int, el: Elements) -> Elements:
    """``el`` (elements of geom ``gid``) in :func:`compact_order` of their positions in the geom's frame."""
    order = compact_order(to_geom_frame(model, gid, el.pos))
    return Elements(el.pos[order], el.normal[order], el.area[order])


def build_elements(model: mujoco.MjModel, geom_ids, resolution: float) -> tuple[Elements, ElementTables]:
    """Cut the geoms into elements of about ``resolution`` and keep the exposed ones (only the exposed surface
    of each body's union of geoms meets grains, see :func:`~mjrft.geometry.exposed_elements`): the elements as
    the geometry cut them and the kernel's :class:`~mjrft.types.ElementTables` of them. A closed mesh turned
    inside out is refused (:func:`check_mesh_winding`)."""
    check_mesh_winding(model, geom_ids)
    parts = [discretize_geom(model, gid, resolution) for gid in geom_ids]
    exposed = exposed_elements(model, geom_ids, parts, resolution)
    groups = [(gid, _compact(model, gid, el)) for gid, el in zip(geom_ids, exposed)]
    if not groups:
        raise ValueError("no geoms selected for the granular terrain")
    ids = np.array([g for g, _ in groups], dtype=np.int64)
    g_geom, g_body, g_start, g_aabb = _cull_groups(model, groups)
    elements = Elements.concatenate([el for _, el in groups])
    elem_geom = np.repeat(ids, [len(el) for _, el in groups])
    tables = ElementTables(lpos=np.ascontiguousarray(elements.pos, dtype=np.float64),
                           lnrm=np.ascontiguousarray(elements.normal, dtype=np.float64),
                           area=np.ascontiguousarray(elements.area, dtype=np.float64), geom=elem_geom,
                           body=np.ascontiguousarray(model.geom_bodyid[elem_geom], dtype=np.int64),
                           body_ids=np.unique(g_body), geom_ids=ids, group_geom=g_geom, group_body=g_body,
                           group_start=g_start, group_aabb=g_aabb,
                           body_root=np.ascontiguousarray(model.body_rootid, dtype=np.int64))
    return elements, tables

"""Cut MuJoCo geoms into flat surface elements (centroid, unit outward normal, area) for resistive force theory.

``resolution`` is the target element edge length in metres: every face or patch is cut into
``max(1, ceil(extent / resolution))`` cells per direction (with small per-shape minimums), so even a
tiny primitive gets at least one element per face. A mesh's triangles larger than half the resolution
are cut the same way; smaller ones, and the sliver pieces of long thin triangles, are merged into
elements of about the resolution (see :func:`_mesh`), so a detailed or CAD-exported mesh costs what its
size calls for, not what its triangle count or triangle shapes do.
Element areas sum to :func:`surface_area` exactly for box, sphere, capsule, cylinder and mesh, and to
within ~1e-3 for ellipsoids.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import mujoco
import numpy as np

from ..errors import UnknownNameError, check_positive, unknown

__all__ = ["Elements", "GEOM_TYPES", "discretize_geom", "geom_elements", "mesh_element_count", "surface_area"]

GEOM_TYPES = ("box", "capsule", "cylinder", "sphere", "ellipsoid", "mesh")

_TYPE_BY_ENUM = {
    int(mujoco.mjtGeom.mjGEOM_BOX): "box",
    int(mujoco.mjtGeom.mjGEOM_CAPSULE): "capsule",
    int(mujoco.mjtGeom.mjGEOM_CYLINDER): "cylinder",
    int(mujoco.mjtGeom.mjGEOM_SPHERE): "sphere",
    int(mujoco.mjtGeom.mjGEOM_ELLIPSOID): "ellipsoid",
    int(mujoco.mjtGeom.mjGEOM_MESH): "mesh",
}
_NSIZE = {"box": 3, "capsule": 2, "cylinder": 2, "sphere": 1, "ellipsoid": 3, "mesh": 0}
_MIN_SECTORS = 4  # longitude sectors around any axis of revolution
_MIN_BANDS = 2  # latitude bands per hemisphere
_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(4)  # ellipsoid patch sub-quadrature


@dataclass(frozen=True, eq=False)
class Elements:
    """Flat surface elements: ``pos`` (N, 3) centroids, ``normal`` (N, 3) unit outward normals, ``area`` (N,)."""

    pos: np.ndarray
    normal: np.ndarray
    area: np.ndarray

    def __post_init__(self) -> None:
        pos = np.ascontiguousarray(self.pos, dtype=np.float64).reshape(-1, 3)
        normal = np.ascontiguousarray(self.normal, dtype=np.float64).reshape(-1, 3)
        area = np.ascontiguousarray(self.area, dtype=np.float64).reshape(-1)
        if not (len(pos) == len(normal) == len(area)):
            raise ValueError(
                f"Elements arrays disagree in length: pos {len(pos)}, normal {len(normal)}, area {len(area)}"
            )
        object.__setattr__(self, "pos", pos)
        object.__setattr__(self, "normal", normal)
        object.__setattr__(self, "area", area)

    def __len__(self) -> int:
        return len(self.area)

    @property
    def total_area(self) -> float:
        """Sum of the element areas."""
        return float(self.area.sum())

    @classmethod
    def empty(cls) -> Elements:
        """No elements."""
        return cls(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0))

    @classmethod
    def concatenate(cls, parts: Iterable[Elements]) -> Elements:
        """Join a sequence of Elements into one, in order."""
        parts = list(parts)
        if not parts:
            return cls.empty()
        return cls(
            np.concatenate([p.pos for p in parts]),
            np.concatenate([p.normal for p in parts]),
            np.concatenate([p.area for p in parts]),
        )

    def transform(self, rotation, translation) -> Elements:
        """Return the elements moved by ``x -> rotation @ x + translation`` (rotation a 3x3 matrix)."""
        rot = np.asarray(rotation, dtype=np.float64).reshape(3, 3)
        trans = np.asarray(translation, dtype=np.float64).reshape(3)
        return Elements(self.pos @ rot.T + trans, self.normal @ rot.T, self.area.copy())


# --------------------------------------------------------------------------- validation helpers


def _geom_name(geom_type) -> str:
    """Map a MuJoCo geom type (name, mjtGeom or int) to its entry in GEOM_TYPES, else raise ValueError."""
    if isinstance(geom_type, str):
        name = geom_type.strip().lower()
        if name.startswith("mjgeom_"):
            name = name[len("mjgeom_"):]
        if name in GEOM_TYPES:
            return name
    elif isinstance(geom_type, (int, np.integer, mujoco.mjtGeom)) and not isinstance(geom_type, bool):
        name = _TYPE_BY_ENUM.get(int(geom_type))
        if name is not None:
            return name
        try:
            enum_name = mujoco.mjtGeom(int(geom_type)).name
            geom_type = f"{enum_name[len('mjGEOM_'):].lower()} (mjtGeom {int(geom_type)})"
        except (ValueError, TypeError):
            geom_type = int(geom_type)
    raise unknown("geom type", geom_type, GEOM_TYPES)


def _check_resolution(resolution) -> float:
    return check_positive("resolution", resolution)


def _check_size(name: str, size) -> np.ndarray:
    n = _NSIZE[name]
    s = np.asarray(size if size is not None else [], dtype=np.float64).reshape(-1)
    if s.size < n:
        raise ValueError(f"{name} geom needs {n} size value(s), got {size!r}")
    s = s[:n]
    if not np.all(np.isfinite(s)) or np.any(s < 0):
        raise ValueError(f"{name} geom size must be finite and >= 0, got {size!r}")
    return s


def _check_mesh(vertices, faces) -> tuple[np.ndarray, np.ndarray]:
    if vertices is None or faces is None:
        raise ValueError("mesh geom needs mesh_vertices (V, 3) and mesh_faces (F, 3)")
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces)
    if v.size == 0:
        v = v.reshape(0, 3)
    if f.size == 0:
        f = f.reshape(0, 3)
    if v.ndim != 2 or v.shape[1] != 3:
        raise ValueError(f"mesh_vertices must have shape (V, 3), got {v.shape}")
    if f.ndim != 2 or f.shape[1] != 3:
        raise ValueError(f"mesh_faces must have shape (F, 3), got {f.shape}")
    if not np.all(np.isfinite(v)):
        raise ValueError("mesh_vertices must be finite")
    if f.size and (not np.issubdtype(f.dtype, np.integer) or f.min() < 0 or f.max() >= len(v)):
        raise ValueError(f"mesh_faces must be integer indices in [0, {len(v)}), got range [{f.min()}, {f.max()}]")
    return v, f.astype(np.intp)


def _ncells(extent, resolution: float, minimum: int = 1):
    """max(minimum, ceil(extent / resolution)), elementwise, tolerant of round-off just above an integer."""
    n = np.ceil(np.asarray(extent, dtype=np.float64) / resolution - 1e-9)
    return np.maximum(minimum, n).astype(np.intp)


def _unit(v: np.ndarray, fallback: np.ndarray) -> np.ndarray:
    """Row-normalise ``v``; rows of zero length take the matching (unit) row of ``fallback``."""
    norm = np.linalg.norm(v, axis=1, keepdims=True)
    ok = norm > 0
    return np.where(ok, v / np.where(ok, norm, 1.0), fallback)


def _ragged(counts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For groups of sizes ``counts``: (group index, index within the group) of every member."""
    group = np.repeat(np.arange(len(counts)), counts)
    start = np.cumsum(counts) - counts
    return group, np.arange(int(counts.sum())) - start[group]


# --------------------------------------------------------------------------- primitive patches


def _box_cells(h: np.ndarray, res: float, k: int) -> tuple[int, int]:
    """Cells (along u, along v) of the box's two faces normal to axis ``k``."""
    u, v = (k + 1) % 3, (k + 2) % 3
    return int(_ncells(2 * h[u], res)), int(_ncells(2 * h[v], res))


def _box(h: np.ndarray, res: float) -> Elements:
    parts = []
    for k in range(3):
        u, v = (k + 1) % 3, (k + 2) % 3
        nu, nv = _box_cells(h, res, k)
        cu = -h[u] + (np.arange(nu) + 0.5) * (2 * h[u] / nu)
        cv = -h[v] + (np.arange(nv) + 0.5) * (2 * h[v] / nv)
        gu, gv = (g.ravel() for g in np.meshgrid(cu, cv, indexing="ij"))
        area = np.full(nu * nv, 4 * h[u] * h[v] / (nu * nv))
        for sign in (1.0, -1.0):
            pos = np.zeros((nu * nv, 3))
            pos[:, k], pos[:, u], pos[:, v] = sign * h[k], gu, gv
            normal = np.zeros((nu * nv, 3))
            normal[:, k] = sign
            parts.append(Elements(pos, normal, area))
    return Elements.concatenate(parts)


def _hemisphere_cells(radius: float, res: float) -> tuple[np.ndarray, np.ndarray]:
    """(polar-angle band edges, sectors per band) of a hemisphere."""
    nb = int(_ncells(0.5 * math.pi * radius, res, _MIN_BANDS))
    edges = np.linspace(0.0, 0.5 * math.pi, nb + 1)
    return edges, _ncells(2 * math.pi * radius * np.sin(edges[1:]), res, _MIN_SECTORS)


def _hemisphere(radius: float, res: float, center_z: float, up: bool) -> Elements:
    """Upper (or lower) hemisphere: equal polar-angle bands, per-band sector counts, exact zone areas."""
    edges, ns = _hemisphere_cells(radius, res)
    band_area = 2 * math.pi * radius**2 * (np.cos(edges[:-1]) - np.cos(edges[1:]))
    band, j = _ragged(ns)
    # Polar angle of the band's area centre (mean height of the zone): depth-linear loads and projected
    # areas (sum of n_z * area) then come out exact; the azimuth is the sector's mid angle.
    theta = np.arccos(0.5 * (np.cos(edges[:-1]) + np.cos(edges[1:])))[band]
    phi = (j + 0.5) * (2 * math.pi / ns[band])
    sign = 1.0 if up else -1.0
    d = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), sign * np.cos(theta)], axis=1)
    pos = radius * d
    pos[:, 2] += center_z
    return Elements(pos, d, (band_area / ns)[band])


def _cylinder_cells(radius: float, half: float, res: float) -> tuple[int, int]:
    """(rings along z, sectors) of a cylinder's side."""
    return int(_ncells(2 * half, res)), int(_ncells(2 * math.pi * radius, res, _MIN_SECTORS))


def _cylinder_side(radius: float, half: float, res: float) -> Elements:
    nz, ns = _cylinder_cells(radius, half, res)
    z = -half + (np.arange(nz) + 0.5) * (2 * half / nz)
    phi = (np.arange(ns) + 0.5) * (2 * math.pi / ns)
    gz, gp = (g.ravel() for g in np.meshgrid(z, phi, indexing="ij"))
    normal = np.stack([np.cos(gp), np.sin(gp), np.zeros_like(gp)], axis=1)
    pos = radius * normal
    pos[:, 2] = gz
    return Elements(pos, normal, np.full(nz * ns, 4 * math.pi * radius * half / (nz * ns)))


def _disk_cells(radius: float, res: float) -> tuple[np.ndarray, np.ndarray]:
    """(ring edges, sectors per ring) of a flat cap."""
    nr = int(_ncells(radius, res))
    edges = np.linspace(0.0, radius, nr + 1)
    return edges, _ncells(2 * math.pi * edges[1:], res, _MIN_SECTORS)


def _disk(radius: float, res: float, z: float, up: bool) -> Elements:
    """Flat cap at height z: rings x per-ring sectors, exact annulus-sector areas, true sector centroids."""
    edges, ns = _disk_cells(radius, res)
    r1, r2 = edges[:-1], edges[1:]
    ring_area = math.pi * (r2**2 - r1**2)
    half_angle = math.pi / ns
    den = r2**2 - r1**2
    rc = np.where(den > 0, (2.0 / 3.0) * (r2**3 - r1**3) / np.where(den > 0, den, 1.0), r1)
    rc = rc * np.sin(half_angle) / half_angle
    ring, j = _ragged(ns)
    phi = (j + 0.5) * (2 * math.pi / ns[ring])
    pos = np.stack([rc[ring] * np.cos(phi), rc[ring] * np.sin(phi), np.full(len(phi), z)], axis=1)
    normal = np.zeros_like(pos)
    normal[:, 2] = 1.0 if up else -1.0
    return Elements(pos, normal, (ring_area / ns)[ring])


def _ellipsoid_cells(axes: np.ndarray, res: float) -> tuple[int, int]:
    """(polar-angle bands, azimuth sectors) of an ellipsoid's grid."""
    a, b, c = axes
    nth = 2 * int(_ncells(0.5 * math.pi * max(a, b, c), res, _MIN_BANDS))
    nph = int(_ncells(2 * math.pi * max(a, b), res, _MIN_SECTORS))
    nph += -nph % 4  # multiple of 4: grid symmetric under x -> -x and y -> -y
    return nth, nph


def _ellipsoid(axes: np.ndarray, res: float) -> Elements:
    """(polar angle, azimuth) grid; 4x4 Gauss sub-quadrature of |r_theta x r_phi| per patch."""
    a, b, c = axes
    nth, nph = _ellipsoid_cells(axes, res)
    dth, dph = math.pi / nth, 2 * math.pi / nph
    th = ((np.arange(nth) + 0.5)[:, None] + 0.5 * _GAUSS_X[None, :]) * dth  # (nth, 4)
    ph = ((np.arange(nph) + 0.5)[:, None] + 0.5 * _GAUSS_X[None, :]) * dph  # (nph, 4)
    st, ct = np.sin(th)[:, :, None, None], np.cos(th)[:, :, None, None]
    sp, cp = np.sin(ph)[None, None], np.cos(ph)[None, None]
    jac = st * np.sqrt((b * c * st * cp) ** 2 + (a * c * st * sp) ** 2 + (a * b * ct) ** 2)  # (nth,4,nph,4)
    wj = jac * (_GAUSS_W[None, :, None, None] * _GAUSS_W[None, None, None, :])
    wsum = wj.sum(axis=(1, 3))  # (nth, nph)
    area = wsum * (0.25 * dth * dph)
    ok = wsum > 0
    safe = np.where(ok, wsum, 1.0)
    mid_th = np.broadcast_to(((np.arange(nth) + 0.5) * dth)[:, None], wsum.shape)
    mid_ph = np.broadcast_to(((np.arange(nph) + 0.5) * dph)[None, :], wsum.shape)
    thc = np.where(ok, (wj * th[:, :, None, None]).sum(axis=(1, 3)) / safe, mid_th).ravel()
    phc = np.where(ok, (wj * ph[None, None]).sum(axis=(1, 3)) / safe, mid_ph).ravel()
    radial = np.stack([np.sin(thc) * np.cos(phc), np.sin(thc) * np.sin(phc), np.cos(thc)], axis=1)
    pos = radial * axes
    scale = max(a, b, c)
    an, bn, cn = (axes / scale) if scale > 0 else (0.0, 0.0, 0.0)
    grad = radial * np.array([bn * cn, an * cn, an * bn])  # parallel to (x/a^2, y/b^2, z/c^2), no division
    return Elements(pos, _unit(grad, radial), area.ravel())


MERGE_BELOW = 0.5  # a triangle whose longest edge is at most this many resolutions is merged with its neighbours
MERGE_BINS = 3  # normal-direction bins per cube face (6 x 3 x 3 = 54 directions) of the merged clusters
# A triangle whose height over its longest edge is below 2 SLIVER_ASPECT (area < SLIVER_ASPECT x longest edge^2:
# a sliver, as CAD exports are full of) is split like any other, but its pieces are merged like small triangles.
SLIVER_ASPECT = 0.025
MAX_PIECES = 20_000_000  # above this many split pieces, mesh_element_count gives an upper bound, unmerged


def _mesh_faces(vertices: np.ndarray, faces: np.ndarray, res: float):
    """Per triangle: (first vertex, two edge vectors, area, unit normal, pieces per edge k, small mask)."""
    v0, v1, v2 = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    e1, e2 = v1 - v0, v2 - v0
    cross = np.cross(e1, e2)
    tri_area = 0.5 * np.linalg.norm(cross, axis=1)
    normal = _unit(cross, np.array([0.0, 0.0, 1.0]))
    longest = np.max(np.linalg.norm(np.stack([e1, e2, v2 - v1]), axis=2), axis=0)
    small = longest <= MERGE_BELOW * res
    return v0, e1, e2, tri_area, normal, longest, small


def _split_kind(tri_area, longest, small, res):
    """Pieces per edge k of every triangle (0 for the small ones) and whether its pieces are slivers."""
    k = np.where(small, 0, np.ceil(longest / res - 1e-9).clip(min=1)).astype(np.int64)
    sliver = ~small & (tri_area < SLIVER_ASPECT * longest**2)
    return k, sliver


def _split(v0, e1, e2, idx, k):
    """Centroids (n, 3) of the k^2 congruent pieces of the triangles ``idx`` (k per triangle) and their triangle."""
    pos_parts, face_parts = [], []
    for kk in np.unique(k):
        sel = idx[k == kk]
        i, j = np.meshgrid(np.arange(kk), np.arange(kk), indexing="ij")
        up = i + j <= kk - 1
        down = i + j <= kk - 2
        s = np.concatenate([i[up] + 1 / 3, i[down] + 2 / 3]) / kk  # barycentric centroids of the k^2 pieces
        t = np.concatenate([j[up] + 1 / 3, j[down] + 2 / 3]) / kk
        p = v0[sel, None] + s[None, :, None] * e1[sel, None] + t[None, :, None] * e2[sel, None]
        pos_parts.append(p.reshape(-1, 3))
        face_parts.append(np.repeat(sel, len(s)))
    if not pos_parts:
        return np.zeros((0, 3)), np.zeros(0, dtype=np.intp)
    face = np.concatenate(face_parts)
    order = np.argsort(face, kind="stable")
    return np.concatenate(pos_parts)[order], face[order]


def _normal_bins(normal: np.ndarray) -> np.ndarray:
    """Direction bin (0 .. 6 MERGE_BINS^2 - 1) of unit normals: the cube face the normal points through
    (dominant axis and sign), cut into MERGE_BINS x MERGE_BINS equal squares."""
    axis = np.argmax(np.abs(normal), axis=1)
    rows = np.arange(len(normal))
    major = normal[rows, axis]
    u = normal[rows, (axis + 1) % 3] / np.abs(major)
    v = normal[rows, (axis + 2) % 3] / np.abs(major)
    iu = np.clip(np.floor((u + 1.0) * 0.5 * MERGE_BINS), 0, MERGE_BINS - 1).astype(np.int64)
    iv = np.clip(np.floor((v + 1.0) * 0.5 * MERGE_BINS), 0, MERGE_BINS - 1).astype(np.int64)
    face = 2 * axis + (major < 0)
    return (face * MERGE_BINS + iu) * MERGE_BINS + iv


def _spread_bits(x: np.ndarray) -> np.ndarray:
    """The low 21 bits of ``x`` (uint64) spread to every third bit (for a Morton code)."""
    x = x & np.uint64(0x1FFFFF)
    for shift, mask in ((32, 0x1F00000000FFFF), (16, 0x1F0000FF0000FF), (8, 0x100F00F00F00F00F),
                        (4, 0x10C30C30C30C30C3), (2, 0x1249249249249249)):
        x = (x | (x << np.uint64(shift))) & np.uint64(mask)
    return x


def _clusters(centroid: np.ndarray, normal: np.ndarray, res: float) -> tuple[np.ndarray, int]:
    """Cluster id of each small triangle (ids numbered along a Morton curve of the cells), and the count:
    triangles whose centroids share a cube of edge ``res`` and whose normals share a direction bin."""
    cell = np.floor(centroid / res).astype(np.int64)
    keys = np.column_stack([cell - cell.min(axis=0), _normal_bins(normal)])
    uniq, inverse = np.unique(keys, axis=0, return_inverse=True)
    c = uniq[:, :3].astype(np.uint64)
    morton = _spread_bits(c[:, 0]) | (_spread_bits(c[:, 1]) << np.uint64(1)) | (_spread_bits(c[:, 2]) << np.uint64(2))
    order = np.lexsort((uniq[:, 3], morton))
    rank = np.empty(len(uniq), dtype=np.int64)
    rank[order] = np.arange(len(uniq))
    return rank[inverse.reshape(-1)], len(uniq)


def _mesh(vertices: np.ndarray, faces: np.ndarray, res: float) -> Elements:
    """Elements of a triangle mesh at resolution ``res``.

    A triangle whose longest edge exceeds ``MERGE_BELOW res`` is split into k^2 congruent sub-triangles
    with k = ceil(longest edge / res) (k = 1: the triangle itself); the pieces are elements. Smaller
    triangles, and the pieces of slivers (a triangle whose area is below ``SLIVER_ASPECT`` times its
    longest edge squared, its height under 5 % of that edge: the long thin triangles of CAD exports), are
    merged: those whose centroids lie in the same cube of edge ``res`` (a grid fixed in the mesh
    frame) and whose normals fall in the same direction bin (:func:`_normal_bins`, normals within about
    50 degrees of each other) form one element with their total area, area-weighted centroid and the
    unit vector of their summed area vectors; a cluster therefore spans about ``res`` to ``2 res`` (its
    cube plus the reach of its triangles or pieces). So a mesh costs about what its area calls for, not
    what its triangle count or the shape of its triangles does. Total area is exact; so are the sums of
    area x any quantity linear in position (depth-linear loads); a curved cluster's projected area is
    its total area times the unit normal, at most 1 - cos(spread) above the exact |sum of area vectors|.
    Kept pieces come first, in face order, then the merged clusters along a Morton curve of their cubes.
    """
    if len(faces) == 0:
        return Elements.empty()
    v0, e1, e2, tri_area, normal, longest, small = _mesh_faces(vertices, faces, res)
    k, sliver = _split_kind(tri_area, longest, small, res)
    parts = []
    keep = np.flatnonzero(~small & ~sliver)
    if len(keep):
        pos, face = _split(v0, e1, e2, keep, k[keep])
        parts.append(Elements(pos, normal[face], (tri_area / np.maximum(k, 1) ** 2)[face]))
    thin = np.flatnonzero(sliver)
    sm = np.flatnonzero(small)
    if len(sm) or len(thin):
        pos, face = _split(v0, e1, e2, thin, k[thin])
        cen = np.concatenate([v0[sm] + (e1[sm] + e2[sm]) / 3.0, pos])
        face = np.concatenate([sm, face])
        a = (tri_area / np.maximum(k, 1) ** 2)[face]
        nrm = normal[face]
        cid, n = _clusters(cen, nrm, res)
        area = np.bincount(cid, a, minlength=n)
        count = np.bincount(cid, minlength=n)
        ok = area > 0
        pos = np.empty((n, 3))
        vec = np.empty((n, 3))
        for d in range(3):
            mean = np.bincount(cid, cen[:, d], minlength=n) / count  # zero-area clusters: the plain mean
            pos[:, d] = np.where(ok, np.bincount(cid, a * cen[:, d], minlength=n) / np.where(ok, area, 1.0), mean)
            vec[:, d] = np.bincount(cid, a * nrm[:, d], minlength=n)
        first = np.full(n, len(face))
        np.minimum.at(first, cid, np.arange(len(face)))
        parts.append(Elements(pos, _unit(vec, nrm[first]), area))
    return Elements.concatenate(parts)


def mesh_element_count(vertices, faces, resolution: float) -> int:
    """How many elements :func:`geom_elements` makes of this mesh at ``resolution``: the kept pieces counted,
    the merged clusters found from the centroids alone (no element is built). Above ``MAX_PIECES`` sliver
    pieces it returns an upper bound instead (every piece its own element), so a hopeless resolution is
    refused cheaply."""
    res = _check_resolution(resolution)
    v, f = _check_mesh(vertices, faces)
    if len(f) == 0:
        return 0
    v0, e1, e2, tri_area, normal, longest, small = _mesh_faces(v, f, res)
    k, sliver = _split_kind(tri_area, longest, small, res)
    kept = float(np.sum(k[~small & ~sliver].astype(np.float64) ** 2))
    n_thin = float(np.sum(k[sliver].astype(np.float64) ** 2))
    if n_thin > MAX_PIECES:
        return int(min(kept + n_thin + np.count_nonzero(small), 2**62))
    if not (small.any() or sliver.any()):
        return int(min(kept, 2**62))
    thin = np.flatnonzero(sliver)
    pos, face = _split(v0, e1, e2, thin, k[thin])
    sm = np.flatnonzero(small)
    cen = np.concatenate([v0[sm] + (e1[sm] + e2[sm]) / 3.0, pos])
    return int(min(kept + _clusters(cen, normal[np.concatenate([sm, face])], res)[1], 2**62))


# --------------------------------------------------------------------------- public API


def geom_elements(geom_type, size, resolution: float, mesh_vertices=None, mesh_faces=None) -> Elements:
    """Surface elements of a geom in its own frame.

    ``size`` follows MuJoCo's ``geom_size``: box half-sizes; capsule/cylinder (radius, half-length along z);
    sphere (radius,); ellipsoid semi-axes.  Meshes take ``mesh_vertices`` (V, 3) and counter-clockwise
    ``mesh_faces`` (F, 3) instead.  ``resolution`` is the target element edge length in metres.
    """
    name = _geom_name(geom_type)
    res = _check_resolution(resolution)
    if name == "mesh":
        return _mesh(*_check_mesh(mesh_vertices, mesh_faces), res)
    s = _check_size(name, size)
    if name == "box":
        return _box(s, res)
    if name == "sphere":
        return Elements.concatenate([_hemisphere(s[0], res, 0.0, True), _hemisphere(s[0], res, 0.0, False)])
    if name == "cylinder":
        r, h = s
        return Elements.concatenate([_cylinder_side(r, h, res), _disk(r, res, h, True), _disk(r, res, -h, False)])
    if name == "capsule":
        r, h = s
        return Elements.concatenate(
            [_cylinder_side(r, h, res), _hemisphere(r, res, h, True), _hemisphere(r, res, -h, False)]
        )
    return _ellipsoid(s, res)


def element_count(geom_type, size, resolution: float, mesh_vertices=None, mesh_faces=None) -> int:
    """How many elements :func:`geom_elements` makes of this geom (same arguments), counted from the cells the
    shapes are cut into, without making them (a mesh: :func:`mesh_element_count`)."""
    name = _geom_name(geom_type)
    res = _check_resolution(resolution)
    if name == "mesh":
        return mesh_element_count(mesh_vertices, mesh_faces, res)
    s = _check_size(name, size)
    if name == "box":
        return sum(2 * nu * nv for nu, nv in (_box_cells(s, res, k) for k in range(3)))
    if name == "ellipsoid":
        nth, nph = _ellipsoid_cells(s, res)
        return nth * nph
    cap = int(_hemisphere_cells(s[0], res)[1].sum())
    if name == "sphere":
        return 2 * cap
    nz, ns = _cylinder_cells(s[0], s[1], res)
    if name == "cylinder":
        cap = int(_disk_cells(s[0], res)[1].sum())
    return nz * ns + 2 * cap


def _mesh_arrays(model: mujoco.MjModel, mesh_id: int) -> tuple[np.ndarray, np.ndarray]:
    va, vn = model.mesh_vertadr[mesh_id], model.mesh_vertnum[mesh_id]
    fa, fn = model.mesh_faceadr[mesh_id], model.mesh_facenum[mesh_id]
    return model.mesh_vert[va : va + vn], model.mesh_face[fa : fa + fn]


def _geom_frame(model: mujoco.MjModel, gid: int) -> tuple[np.ndarray, np.ndarray]:
    """(rotation (3, 3) geom -> body, position) of geom ``gid`` in its body frame."""
    rot = np.empty(9)
    mujoco.mju_quat2Mat(rot, np.asarray(model.geom_quat[gid], dtype=np.float64))
    return rot.reshape(3, 3), np.asarray(model.geom_pos[gid], dtype=np.float64)


def to_geom_frame(model: mujoco.MjModel, geom_id: int, points) -> np.ndarray:
    """Body-frame ``points`` (N, 3) in the frame of geom ``geom_id`` (that of ``geom_size``, ``geom_aabb``)."""
    R, c = _geom_frame(model, int(geom_id))
    return (np.asarray(points, dtype=np.float64).reshape(-1, 3) - c) @ R


def discretize_geom(model: mujoco.MjModel, geom_id: int, resolution: float) -> Elements:
    """Surface elements of ``model``'s geom ``geom_id`` in its BODY frame (applies geom_pos and geom_quat)."""
    geom_id = int(geom_id)
    if not 0 <= geom_id < model.ngeom:
        raise ValueError(f"geom_id must be in [0, {model.ngeom}), got {geom_id}")
    geom_type = int(model.geom_type[geom_id])
    try:
        name = _geom_name(geom_type)
    except UnknownNameError as err:
        label = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, geom_id)
        raise UnknownNameError(f"geom {geom_id}{f' {label!r}' if label else ''}: {err}") from None
    verts = faces = None
    if name == "mesh":
        verts, faces = _mesh_arrays(model, int(model.geom_dataid[geom_id]))
    local = geom_elements(geom_type, model.geom_size[geom_id], resolution, verts, faces)
    return local.transform(*_geom_frame(model, geom_id))


def geom_element_count(model: mujoco.MjModel, geom_id: int, resolution: float) -> int:
    """How many elements :func:`discretize_geom` makes of ``model``'s geom ``geom_id`` (:func:`element_count`)."""
    geom_id = int(geom_id)
    geom_type = int(model.geom_type[geom_id])
    if _geom_name(geom_type) == "mesh":
        return element_count(geom_type, None, resolution, *_mesh_arrays(model, int(model.geom_dataid[geom_id])))
    return element_count(geom_type, model.geom_size[geom_id], resolution)


def estimate_elements(model: mujoco.MjModel, geom_ids, resolution: float) -> int:
    """About how many elements :func:`discretize_geom` makes of these geoms, without making them:
    surface area / resolution^2 per primitive geom, the exact count of a mesh (:func:`mesh_element_count`).
    Cheap: use it to refuse a resolution that would take minutes and gigabytes before any element is built."""
    res = _check_resolution(resolution)
    total = 0.0
    for g in geom_ids:
        g = int(g)
        geom_type = int(model.geom_type[g])
        if _geom_name(geom_type) == "mesh":
            v, f = _mesh_arrays(model, int(model.geom_dataid[g]))
            total += mesh_element_count(v, f, res)
        else:
            total += surface_area(geom_type, model.geom_size[g]) / res**2
    return int(math.ceil(total))


def inside_geom(model: mujoco.MjModel, geom_id: int, points, tol: float = 1e-9) -> np.ndarray:
    """Which ``points`` (N, 3), given in the geom's BODY frame, lie strictly inside geom ``geom_id``.

    Strictly means deeper than ``tol`` (m) below its surface, so a point on the surface (e.g. where two
    geoms touch face to face) is not inside. Boxes, spheres, capsules, cylinders and ellipsoids are
    exact; a mesh is treated as containing nothing (its interior is not known without a solid model).
    """
    geom_id = int(geom_id)
    local = to_geom_frame(model, geom_id, points)
    s = model.geom_size[geom_id]
    x, y, z = local[:, 0], local[:, 1], local[:, 2]
    t = int(model.geom_type[geom_id])
    if t == mujoco.mjtGeom.mjGEOM_BOX:
        return (np.abs(x) < s[0] - tol) & (np.abs(y) < s[1] - tol) & (np.abs(z) < s[2] - tol)
    if t == mujoco.mjtGeom.mjGEOM_SPHERE:
        return np.sqrt(x * x + y * y + z * z) < s[0] - tol
    if t == mujoco.mjtGeom.mjGEOM_CAPSULE:
        zc = np.clip(z, -s[1], s[1])
        return np.sqrt(x * x + y * y + (z - zc) ** 2) < s[0] - tol
    if t == mujoco.mjtGeom.mjGEOM_CYLINDER:
        return (np.sqrt(x * x + y * y) < s[0] - tol) & (np.abs(z) < s[1] - tol)
    if t == mujoco.mjtGeom.mjGEOM_ELLIPSOID:
        shrunk = np.maximum(s - tol, 0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            q = (x / shrunk[0]) ** 2 + (y / shrunk[1]) ** 2 + (z / shrunk[2]) ** 2
        return np.nan_to_num(q, nan=np.inf) < 1.0
    return np.zeros(len(local), dtype=bool)


def _on_box_face(model: mujoco.MjModel, geom_id: int, points, normals, tol: float = 1e-9) -> np.ndarray:
    """Which points (body frame) lie on a face of box ``geom_id`` whose outward normal equals theirs."""
    R, _ = _geom_frame(model, geom_id)
    local = to_geom_frame(model, geom_id, points)
    nloc = np.asarray(normals) @ R
    s = model.geom_size[geom_id]
    within = np.all(np.abs(local) <= s + tol, axis=1)
    out = np.zeros(len(local), dtype=bool)
    for i in range(3):
        for sign in (1.0, -1.0):
            out |= within & (np.abs(sign * local[:, i] - s[i]) <= tol) & (sign * nloc[:, i] > 1.0 - 1e-9)
    return out


def exposed(model: mujoco.MjModel, geom_ids, parts) -> list[np.ndarray]:
    """For each geom's Elements in ``parts`` (body frame), a mask of the elements on the exposed
    surface of the union of ``geom_ids`` that share its body.

    A leg or foot built from several overlapping primitives (a C-leg as a chain of boxes) has end
    faces inside its neighbours; the laws would count each as an extra plate across the leg. Only the
    exposed surface of the union can push on grains. Dropped: elements strictly inside another geom
    of the same body, and (boxes) elements lying on a face of an earlier geom with the same outward
    normal (coplanar overlapping faces count once). Two geoms touching face to face keep both faces.
    """
    geom_ids = [int(g) for g in geom_ids]
    return [~_covered(model, geom_ids, k, el.pos, el.normal) for k, el in enumerate(parts)]


EXPOSED_SAMPLES = 8  # per cell edge, for the part of a box-face cell covered by a geom other than a box
EXPOSED_MIN_FRACTION = 1e-6  # a cell keeping less of its area than this is dropped


def _covered(model: mujoco.MjModel, geom_ids, k: int, points, normals) -> np.ndarray:
    """Which points (with their normals) of geom ``geom_ids[k]`` are covered by another geom of the same
    body: strictly inside it, or (boxes) on a face of an earlier geom with the same outward normal."""
    g = geom_ids[k]
    out = np.zeros(len(points), dtype=bool)
    for j, h in enumerate(geom_ids):
        if j == k or model.geom_bodyid[h] != model.geom_bodyid[g] or not len(points):
            continue
        out |= inside_geom(model, h, points)
        if j < k and model.geom_type[h] == mujoco.mjtGeom.mjGEOM_BOX:
            out |= _on_box_face(model, h, points, normals)
    return out


def _clip(poly: list, normal: np.ndarray, offset: float) -> list:
    """Sutherland-Hodgman: the part of the convex polygon ``poly`` (list of 3D points) where
    ``normal . p <= offset``."""
    out = []
    n = len(poly)
    for i in range(n):
        p, q = poly[i], poly[(i + 1) % n]
        dp, dq = normal @ p - offset, normal @ q - offset
        if dp <= 0.0:
            out.append(p)
        if (dp < 0.0 < dq) or (dq < 0.0 < dp):
            out.append(p + (q - p) * (dp / (dp - dq)))
    return out


def _polygon_area_centroid(poly: list, normal: np.ndarray) -> tuple[float, np.ndarray]:
    """Area and centroid of the planar convex polygon ``poly`` with unit ``normal``."""
    if len(poly) < 3:
        return 0.0, np.zeros(3)
    p0 = poly[0]
    area = 0.0
    cen = np.zeros(3)
    for i in range(1, len(poly) - 1):
        a = 0.5 * float(normal @ np.cross(poly[i] - p0, poly[i + 1] - p0))
        area += a
        cen += a * (p0 + poly[i] + poly[i + 1]) / 3.0
    if area == 0.0:
        return 0.0, np.zeros(3)
    return abs(area), cen / area  # (either winding)


def _box_cover(cell: list, normal: np.ndarray, R: np.ndarray, c: np.ndarray, s: np.ndarray, earlier: bool,
               tol: float = 1e-9) -> tuple[float, np.ndarray]:
    """Area and centroid of the part of the planar ``cell`` (outward ``normal``) that a box (rotation
    ``R``, centre ``c`` in the body frame, half sizes ``s``) covers: the part strictly inside it; where
    the cell lies in the plane of one of the box's faces, the part on that face if the box is
    ``earlier`` and the face's outward normal is the cell's (coplanar faces count once; two boxes
    touching face to face keep both faces)."""
    poly = list(cell)
    for i in range(3):
        a = R[:, i]
        for sign in (1.0, -1.0):
            ax = sign * a
            off = float(ax @ c + s[i])
            if abs(float(ax @ normal)) > 1.0 - 1e-9 and all(abs(float(ax @ p) - off) <= tol for p in cell):
                if not (earlier and float(ax @ normal) > 0.0):
                    return 0.0, np.zeros(3)  # on this face: covered only as a coplanar face of an earlier box
                continue
            poly = _clip(poly, ax, off)
            if len(poly) < 3:
                return 0.0, np.zeros(3)
    return _polygon_area_centroid(poly, normal)


def exposed_elements(model: mujoco.MjModel, geom_ids, parts, resolution: float) -> list[Elements]:
    """The elements of each geom in ``parts`` (from :func:`discretize_geom` at ``resolution``) that lie on
    the exposed surface of the union of ``geom_ids`` sharing its body, with partly covered box-face
    cells trimmed.

    :func:`exposed` judges an element by its centroid, so where a box's face runs into a neighbouring
    geom (the concave side of a C-leg's joints, coplanar side faces of a box chain) a whole cell is
    kept or dropped, and the union's area converges only as the cells shrink below the overlap (a
    RHex C-leg of 8 boxes: 18.32 cm^2 at 2.5-20 mm, 17.74 at 1.25 mm, 17.21 at 0.625 mm). Here each
    box-face cell (a rectangle of :func:`geom_elements`' grid) loses the part another box of the body
    covers, computed exactly by clipping the rectangle against that box (coplanar faces: the rule of
    :func:`exposed`), and the part another geom type covers, estimated on ``EXPOSED_SAMPLES`` squared
    points; a partly covered cell keeps the rest of its area at the centroid of the rest, a wholly
    covered one is dropped. (The covered parts from different geoms are assumed not to overlap inside
    one cell: true for chains of boxes longer than their joints' overlap.) Elements of other geom
    types are judged by their centroid as in :func:`exposed`.
    """
    res = float(resolution)
    geom_ids = [int(g) for g in geom_ids]
    n = EXPOSED_SAMPLES
    offsets = (np.arange(n) + 0.5) / n - 0.5
    ou, ov = (o.ravel() for o in np.meshgrid(offsets, offsets, indexing="ij"))
    out = []
    for k, (g, el) in enumerate(zip(geom_ids, parts)):
        others = [(j, h) for j, h in enumerate(geom_ids) if j != k and model.geom_bodyid[h] == model.geom_bodyid[g]]
        if not len(el) or not others:
            out.append(el)
            continue
        if model.geom_type[g] != mujoco.mjtGeom.mjGEOM_BOX:
            keep = ~_covered(model, geom_ids, k, el.pos, el.normal)
            out.append(Elements(el.pos[keep], el.normal[keep], el.area[keep]))
            continue
        R, _ = _geom_frame(model, g)
        size = model.geom_size[g]
        axis = np.argmax(np.abs(el.normal @ R), axis=1)  # the face's normal axis in the geom frame
        u_ax, v_ax = (axis + 1) % 3, (axis + 2) % 3
        du = 2 * size[u_ax] / _ncells(2 * size[u_ax], res)  # the cell sizes of _box
        dv = 2 * size[v_ax] / _ncells(2 * size[v_ax], res)
        eu = R.T[u_ax] * (0.5 * du)[:, None]  # half cell edges, body frame
        ev = R.T[v_ax] * (0.5 * dv)[:, None]
        radius = np.sqrt(np.sum(eu * eu, axis=1) + np.sum(ev * ev, axis=1))
        area = el.area.copy()
        pos = el.pos.copy()
        for j, h in others:
            Rh, ch = _geom_frame(model, h)
            reach = float(np.linalg.norm(model.geom_aabb[h, 3:])) + float(np.linalg.norm(Rh @ model.geom_aabb[h, :3]))
            near = np.flatnonzero(np.linalg.norm(el.pos - ch, axis=1) <= reach + radius)
            if model.geom_type[h] == mujoco.mjtGeom.mjGEOM_BOX:
                for i in near:
                    c = el.pos[i]
                    cell = [c - eu[i] - ev[i], c + eu[i] - ev[i], c + eu[i] + ev[i], c - eu[i] + ev[i]]
                    a, cen = _box_cover(cell, el.normal[i], Rh, ch, model.geom_size[h], j < k)
                    if a > 0.0:
                        rest = area[i] - a
                        pos[i] = (pos[i] * area[i] - cen * a) / rest if rest > EXPOSED_MIN_FRACTION * el.area[i] else pos[i]
                        area[i] = max(rest, 0.0)
            elif len(near):
                pts = (el.pos[near, None, :] + 2 * ou[None, :, None] * eu[near, None, :]
                       + 2 * ov[None, :, None] * ev[near, None, :])
                cov = inside_geom(model, h, pts.reshape(-1, 3)).reshape(len(near), n * n)
                frac = cov.mean(axis=1)
                cen = (pts * cov[:, :, None]).sum(axis=1) / np.maximum(cov.sum(axis=1), 1)[:, None]
                a = el.area[near] * frac
                rest = area[near] - a
                ok = rest > EXPOSED_MIN_FRACTION * el.area[near]
                pos[near] = np.where(ok[:, None], (pos[near] * area[near, None] - cen * a[:, None])
                                     / np.where(ok, rest, 1.0)[:, None], pos[near])
                area[near] = np.maximum(rest, 0.0)
        keep = area > EXPOSED_MIN_FRACTION * el.area  # (rounding leaves slivers of ~1e-8 of fully covered cells)
        out.append(Elements(pos[keep], el.normal[keep], area[keep]))
    return out


def _carlson_rf(x: float, y: float, z: float) -> float:
    """Carlson's R_F(x, y, z) by duplication (at most one argument zero)."""
    for _ in range(200):
        sx, sy, sz = math.sqrt(x), math.sqrt(y), math.sqrt(z)
        lam = sx * (sy + sz) + sy * sz
        x, y, z = 0.25 * (x + lam), 0.25 * (y + lam), 0.25 * (z + lam)
        ave = (x + y + z) / 3.0
        dx, dy, dz = (ave - x) / ave, (ave - y) / ave, (ave - z) / ave
        if max(abs(dx), abs(dy), abs(dz)) < 1e-4:
            break
    e2, e3 = dx * dy - dz * dz, dx * dy * dz
    return (1.0 + (e2 / 24.0 - 0.1 - 3.0 / 44.0 * e3) * e2 + e3 / 14.0) / math.sqrt(ave)


def _carlson_rd(x: float, y: float, z: float) -> float:
    """Carlson's R_D(x, y, z) by duplication (z > 0, at most one of x, y zero)."""
    total, fac = 0.0, 1.0
    for _ in range(200):
        sx, sy, sz = math.sqrt(x), math.sqrt(y), math.sqrt(z)
        lam = sx * (sy + sz) + sy * sz
        total += fac / (sz * (z + lam))
        fac *= 0.25
        x, y, z = 0.25 * (x + lam), 0.25 * (y + lam), 0.25 * (z + lam)
        ave = 0.2 * (x + y + 3.0 * z)
        dx, dy, dz = (ave - x) / ave, (ave - y) / ave, (ave - z) / ave
        if max(abs(dx), abs(dy), abs(dz)) < 1e-4:
            break
    c1, c2, c3, c4 = 3.0 / 14.0, 1.0 / 6.0, 9.0 / 22.0, 3.0 / 26.0
    c5, c6 = 0.25 * c3, 1.5 * c4
    ea, eb = dx * dy, dz * dz
    ec, ed = ea - eb, ea - 6.0 * eb
    ee = ed + 2.0 * ec
    series = 1.0 + ed * (-c1 + c5 * ed - c6 * dz * ee) + dz * (c2 * ee + dz * (-c3 * ec + dz * c4 * ea))
    return 3.0 * total + fac * series / (ave * math.sqrt(ave))


def _carlson_rg(x: float, y: float, z: float) -> float:
    """Carlson's symmetric R_G(x, y, z) = (1/4pi) * integral over the unit sphere of sqrt(x n1^2 + y n2^2 + z n3^2)."""
    lo, mid, hi = sorted((x, y, z))
    if mid <= 0.0:  # at most one non-zero argument
        return 0.5 * math.sqrt(hi)
    # DLMF 19.21.10 with the middle value as z, so (x - z)(y - z) <= 0 and nothing cancels.
    return 0.5 * (
        mid * _carlson_rf(lo, hi, mid) - (lo - mid) * (hi - mid) * _carlson_rd(lo, hi, mid) / 3.0
        + math.sqrt(lo * hi / mid)
    )


def surface_area(geom_type, size, mesh_vertices=None, mesh_faces=None) -> float:
    """Exact surface area of a geom (ellipsoid via Carlson's elliptic integral R_G, to ~1e-12)."""
    name = _geom_name(geom_type)
    if name == "mesh":
        v, f = _check_mesh(mesh_vertices, mesh_faces)
        if len(f) == 0:
            return 0.0
        cross = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
        return float(0.5 * np.linalg.norm(cross, axis=1).sum())
    s = _check_size(name, size)
    if name == "box":
        x, y, z = s
        return float(8.0 * (x * y + y * z + z * x))
    if name == "sphere":
        return float(4.0 * math.pi * s[0] ** 2)
    if name == "cylinder":
        r, h = s
        return float(4.0 * math.pi * r * h + 2.0 * math.pi * r * r)
    if name == "capsule":
        r, h = s
        return float(4.0 * math.pi * r * h + 4.0 * math.pi * r * r)
    a, b, c = (float(v) for v in s)
    return 4.0 * math.pi * _carlson_rg((b * c) ** 2, (a * c) ** 2, (a * b) ** 2)

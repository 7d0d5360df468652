"""Curved ("C") legs built from MuJoCo box geoms approximating a circular arc.

The leg curvature convention (the one place it is defined)
----------------------------------------------------------
Every leg in mjrft turns about the +y axis of its parent, and a positive angle swings the tip
backward (toward -x): the hexapod's hips rotate that way to walk forward (+x), the leg rig turns
that way at ``omega > 0``, and in both the buried part of the leg moves toward -x through the
grains. ``curvature`` ``k = 1/r`` (1/m) is signed:

* ``k > 0``: Li, Zhang & Goldman's (2013) **C-leg**, the RHex / SandBot leg. Hanging straight down
  it bows toward -x, so while it is buried its convex side leads: the leg bulges toward where it
  moves, and the robot rolls over the convex side, "pivoted about the center of the curve of the
  leg" (the rotary walking of SandBot and DynaRoACH; robophysics thesis, sec. 1.4.1). Its deep elements move with their leading faces
  looking down and into the motion, which Li's stresses lift several times harder than faces
  looking up (a plate dragged at attack angle +45 deg against -45 deg), hence the supplement's
  "larger vertical ground reaction forces produced by the C-legs relative to those by the reversed
  c-legs" (Li 2013 suppl., fig. S14 text; at the leg rig, Li RFT, measured: C-leg peak lift 2.8x
  the reversed C-leg's, ``tests/mjrft/tools/test_rigs.py``).
* ``k < 0``: the **reversed C-leg**, bowing toward +x when hanging: concave side leading.
* ``k = 0``: a straight (flat) leg.

Li 2013's robot legs are ``k in [-1, -0.92, -0.60, 0, 0.60, 0.92, 1] / R'`` (``R' = chord/2``).
The semi-elliptic legs of the hybrid paper follow the same sign with their bulge ``b``: ``b > 0``
bows toward -x (convex side leading, the paper's legs: their entry into the grains depends on
``b`` while their exit does not, hybrid paper sec. 4), and ``a = b = chord/2`` is exactly the C-leg ``k = 2/chord``.

Frame and discretisation
------------------------
* Frame: everything is expressed in the *leg body frame*. The hip (the leg's
  rotation axis, normally a hinge about y) is at the body origin; the leg hangs
  straight down and its tip is at ``(0, 0, -chord)``.
* ``chord`` is the straight hip-to-tip distance (e.g. ``2 R' = 0.041`` m for the
  RHex-class leg of Li, Zhang & Goldman 2013).
* The leg's centre line lies in the x-z plane. ``width`` is measured along y,
  ``thickness`` across the arc (in the x-z plane).
* ``|k| <= 2/chord`` (``|k| = 2/chord`` is a semicircle); a larger ``|k|``
  raises ``ValueError``.
* Discretisation: the arc is cut into ``n_segments`` pieces of equal arc
  length. Each piece becomes one box whose long axis (local z) is the *chord*
  of that piece of arc, whose local x is across the arc (half size
  ``thickness/2``) and whose local y is the leg width (half size ``width/2``).
  Boxes are placed end to end; at the internal joints each box is lengthened
  by ``thickness/2 * tan(dtheta/2)`` (``dtheta = |k| L / n`` the turn per
  segment) so that the outer side of every bend is closed (no gaps; the inner
  side overlaps slightly). The two leg ends are not extended, so the first box
  starts exactly at the hip and the last one ends exactly at the tip.
* Quaternions are MuJoCo's ``(w, x, y, z)``; box sizes are MuJoCo half sizes.
"""

from __future__ import annotations

import math
from numbers import Real

import numpy as np

from ..errors import check_finite, check_positive

__all__ = [
    "arc_length",
    "arc_points",
    "curved_leg_boxes",
    "curved_leg_xml",
    "add_curved_leg",
    "max_curvature",
    "semi_ellipse_points",
    "semi_ellipse_length",
    "semi_ellipse_boxes",
    "semi_ellipse_xml",
    "add_semi_ellipse_leg",
    "semi_ellipse_family",
]


def max_curvature(chord: float) -> float:
    """Largest allowed ``|curvature|`` (1/m) for ``chord``: ``2/chord`` (a semicircle)."""
    return 2.0 / check_positive("chord", chord)


def _check_curvature(chord: float, curvature) -> float:
    k = check_finite("curvature", curvature)
    kmax = 2.0 / chord
    # Tolerate round-off at the semicircle limit (e.g. 1/R' with R' = chord/2).
    if abs(k) > kmax * (1.0 + 1e-9):
        raise ValueError(
            f"curvature {k!r} 1/m is out of range for chord {chord!r} m: "
            f"|curvature| must be <= 2/chord = {kmax!r} 1/m "
            f"(valid range [{-kmax!r}, {kmax!r}]; 2/chord is a semicircle)"
        )
    return max(-kmax, min(kmax, k))


def _half_angle(chord: float, k: float) -> float:
    """Half of the angle subtended by the arc (rad), >= 0."""
    s = min(1.0, abs(k) * chord / 2.0)
    return math.asin(s)


def arc_length(chord: float, curvature: float) -> float:
    """Length (m) of the circular arc of signed ``curvature`` spanning ``chord``.

    ``chord`` for a straight leg, ``pi/2 * chord`` for a semicircle.
    """
    c = check_positive("chord", chord)
    k = _check_curvature(c, curvature)
    if k == 0.0:
        return c
    return 2.0 * _half_angle(c, k) / abs(k)


def _start_angle(chord: float, k: float) -> float:
    """Leg angle (from -z toward +x) of the centre line at the hip: negative for ``k > 0``, whose arc
    leaves the hip toward -x and turns back (by ``k`` per unit length) to reach the tip on the z axis."""
    return -math.copysign(_half_angle(chord, k), k) if k != 0.0 else 0.0


def _direction(alpha: float) -> np.ndarray:
    """Unit tangent at leg angle ``alpha`` (measured from -z toward +x)."""
    return np.array([math.sin(alpha), 0.0, -math.cos(alpha)])


def arc_points(chord: float, curvature: float, n: int = 64) -> np.ndarray:
    """``(n+1, 3)`` points on the leg centre line from hip (0,0,0) to tip (0,0,-chord)."""
    c = check_positive("chord", chord)
    k = _check_curvature(c, curvature)
    n = int(n)
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n!r}")
    L = arc_length(c, k)
    alpha0 = _start_angle(c, k)
    ds = L / n
    seg_chord = ds if k == 0.0 else 2.0 * math.sin(k * ds / 2.0) / k
    pts = np.zeros((n + 1, 3))
    for i in range(n):
        amid = alpha0 + k * (i + 0.5) * ds
        pts[i + 1] = pts[i] + seg_chord * _direction(amid)
    pts[-1] = (0.0, 0.0, -c)  # remove round-off at the tip
    return pts


def curved_leg_boxes(
    chord: float,
    curvature: float,
    width: float,
    thickness: float,
    n_segments: int = 8,
) -> list[dict]:
    """Boxes approximating the curved leg, in the leg body frame.

    Returns a list of ``n_segments`` dicts ``{"pos": (3,), "quat": (4,) wxyz,
    "size": (3,) half sizes}`` ordered from hip to tip. See the module
    docstring for the conventions.
    """
    c = check_positive("chord", chord)
    w = check_positive("width", width)
    t = check_positive("thickness", thickness)
    n = _n_segments(n_segments)
    k = _check_curvature(c, curvature)

    L = arc_length(c, k)
    ds = L / n
    alpha0 = _start_angle(c, k)
    dtheta = abs(k) * ds
    ext = 0.5 * t * math.tan(dtheta / 2.0)  # lengthening at each internal joint
    pts = arc_points(c, k, n)

    boxes = []
    for i in range(n):
        amid = alpha0 + k * (i + 0.5) * ds
        d = _direction(amid)
        e_start = ext if i > 0 else 0.0
        e_end = ext if i < n - 1 else 0.0
        p0 = pts[i] - e_start * d
        p1 = pts[i + 1] + e_end * d
        seg_len = float(np.linalg.norm(p1 - p0))
        center = 0.5 * (p0 + p1)
        # Rotation about y by beta = -amid maps local z onto -d (box symmetric).
        quat = np.array([math.cos(amid / 2.0), 0.0, -math.sin(amid / 2.0), 0.0])
        boxes.append(
            {
                "pos": center,
                "quat": quat,
                "size": np.array([t / 2.0, w / 2.0, seg_len / 2.0]),
            }
        )
    return boxes


def _n_segments(n_segments) -> int:
    if isinstance(n_segments, bool) or not isinstance(n_segments, (int, np.integer, Real)):
        raise ValueError(f"n_segments must be an integer >= 1, got {n_segments!r}")
    if float(n_segments) != int(n_segments) or int(n_segments) < 1:
        raise ValueError(f"n_segments must be an integer >= 1, got {n_segments!r}")
    return int(n_segments)


def _fmt(v) -> str:
    return " ".join(f"{float(x):.9g}" for x in np.ravel(v))


def _attr_value(v) -> str:
    if isinstance(v, str):
        return v
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (list, tuple, np.ndarray)):
        return _fmt(v)
    if isinstance(v, Real):
        return f"{float(v):.9g}"
    return str(v)


def curved_leg_xml(
    chord: float,
    curvature: float,
    width: float,
    thickness: float,
    n_segments: int = 8,
    name_prefix: str | None = "leg",
    **geom_attrs,
) -> str:
    """MJCF ``<geom type="box" .../>`` lines (one per segment) for a curved leg.

    Geoms are named ``{name_prefix}_seg{i}`` (no name if ``name_prefix`` is
    None or empty). Extra keyword arguments become XML attributes
    (``rgba=(1, 0, 0, 1)``, ``mass=0.0005``, ``contype=1``, ``class_="leg"`` ->
    ``class="leg"``; a trailing underscore is stripped).
    """
    return _boxes_xml(curved_leg_boxes(chord, curvature, width, thickness, n_segments), name_prefix, geom_attrs)


def _boxes_xml(boxes, name_prefix, geom_attrs) -> str:
    lines = []
    extra = ""
    for key, val in geom_attrs.items():
        if val is None:
            continue
        extra += f' {key.rstrip("_")}="{_attr_value(val)}"'
    for i, b in enumerate(boxes):
        name = f' name="{name_prefix}_seg{i}"' if name_prefix else ""
        lines.append(
            f'<geom{name} type="box" pos="{_fmt(b["pos"])}" quat="{_fmt(b["quat"])}" '
            f'size="{_fmt(b["size"])}"{extra}/>'
        )
    return "\n".join(lines)


def add_curved_leg(
    body,
    chord: float,
    curvature: float,
    width: float,
    thickness: float,
    n_segments: int = 8,
    name_prefix: str | None = None,
    **geom_kwargs,
) -> list:
    """Add the leg's box geoms to an ``mujoco.MjsBody`` (MjSpec API).

    ``geom_kwargs`` are passed to ``body.add_geom`` (e.g. ``rgba=[...]``,
    ``mass=...`` per box, ``contype=...``). If ``name_prefix`` is given the
    geoms are named ``{name_prefix}_seg{i}``. Returns the new ``MjsGeom`` list.
    """
    return _add_boxes(body, curved_leg_boxes(chord, curvature, width, thickness, n_segments), name_prefix,
                      geom_kwargs)


def _add_boxes(body, boxes, name_prefix, geom_kwargs) -> list:
    import mujoco

    geoms = []
    for i, b in enumerate(boxes):
        kw = dict(geom_kwargs)
        if name_prefix:
            kw["name"] = f"{name_prefix}_seg{i}"
        g = body.add_geom(
            type=mujoco.mjtGeom.mjGEOM_BOX,
            pos=[float(x) for x in b["pos"]],
            quat=[float(x) for x in b["quat"]],
            size=[float(x) for x in b["size"]],
            **kw,
        )
        geoms.append(g)
    return geoms


# ================================================================================================
# Semi-elliptic legs (hybrid curved-leg model, reference section 4)
# ================================================================================================
# Same frame and box conventions as the C-legs above: hip at the origin, leg hanging along -z, tip at
# (0, 0, -2a), centre line in the x-z plane. The profile is x = -b sin t, z = -a (1 - cos t), t in
# [0, pi]: ``a`` is half the hip-to-tip length and ``b`` the bulge, SIGNED like ``curvature`` (module
# docstring: b > 0 bows toward -x, convex side leading; b < 0 toward +x; b = 0 is a straight bar), so
# a = b = chord/2 is exactly the semicircular C-leg ``curvature = 2/chord``. The leg is cut into
# ``n_segments`` pieces of equal arc length, one box per piece along its chord; at every internal
# joint both boxes are lengthened by ``thickness/2 * tan(turn/2)`` (``turn`` the angle between the two
# pieces' chords) so the outer side of each bend is closed, and the two leg ends are not extended.


def semi_ellipse_points(a: float, b: float, n: int = 64) -> np.ndarray:
    """``(n+1, 3)`` points of equal arc-length spacing on the semi-elliptic centre line, hip to tip."""
    return _semi_ellipse(a, b, n)[0]


def semi_ellipse_length(a: float, b: float) -> float:
    """Arc length (m) of the semi-elliptic leg (half the ellipse's perimeter; relative error < 1e-8)."""
    return _semi_ellipse(a, b, 1)[1]


def _semi_ellipse(a, b, n):
    a = check_positive("a", a)
    b = check_finite("b", b)  # the signed bulge (m)
    n = _n_segments(n)
    t = np.linspace(0.0, math.pi, max(40000, 200 * n) + 1)
    x = -b * np.sin(t)
    z = -a * (1.0 - np.cos(t))
    s = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(x), np.diff(z)))])
    ts = np.interp(np.linspace(0.0, s[-1], n + 1), s, t)
    pts = np.stack([-b * np.sin(ts), np.zeros(n + 1), -a * (1.0 - np.cos(ts))], axis=1)
    pts[0] = 0.0
    pts[-1] = (0.0, 0.0, -2.0 * a)  # remove round-off at the ends
    return pts, float(s[-1])


def semi_ellipse_boxes(a: float, b: float, width: float, thickness: float, n_segments: int = 16) -> list[dict]:
    """Boxes approximating a semi-elliptic leg (semi-axes ``a`` along the leg, signed ``b`` across).

    Same output and conventions as :func:`curved_leg_boxes`; see the comment above this function.
    """
    w = check_positive("width", width)
    t = check_positive("thickness", thickness)
    n = _n_segments(n_segments)
    pts = semi_ellipse_points(a, b, n)
    d = np.diff(pts, axis=0)
    d /= np.linalg.norm(d, axis=1)[:, None]
    # turn angle at each internal joint -> lengthening of both neighbouring boxes there
    cosang = np.clip(np.sum(d[:-1] * d[1:], axis=1), -1.0, 1.0)
    ext = 0.5 * t * np.tan(0.5 * np.arccos(cosang))
    boxes = []
    for i in range(n):
        e_start = ext[i - 1] if i > 0 else 0.0
        e_end = ext[i] if i < n - 1 else 0.0
        p0 = pts[i] - e_start * d[i]
        p1 = pts[i + 1] + e_end * d[i]
        alpha = math.atan2(d[i, 0], -d[i, 2])  # direction (sin alpha, 0, -cos alpha)
        boxes.append(
            {
                "pos": 0.5 * (p0 + p1),
                "quat": np.array([math.cos(alpha / 2.0), 0.0, -math.sin(alpha / 2.0), 0.0]),
                "size": np.array([t / 2.0, w / 2.0, float(np.linalg.norm(p1 - p0)) / 2.0]),
            }
        )
    return boxes


def semi_ellipse_xml(a: float, b: float, width: float, thickness: float, n_segments: int = 16,
                     name_prefix: str | None = "leg", **geom_attrs) -> str:
    """MJCF ``<geom type="box" .../>`` lines of a semi-elliptic leg (as :func:`curved_leg_xml`)."""
    return _boxes_xml(semi_ellipse_boxes(a, b, width, thickness, n_segments), name_prefix, geom_attrs)


def add_semi_ellipse_leg(body, a: float, b: float, width: float, thickness: float, n_segments: int = 16,
                         name_prefix: str | None = None, **geom_kwargs) -> list:
    """Add a semi-elliptic leg's box geoms to an ``mujoco.MjsBody`` (as :func:`add_curved_leg`)."""
    return _add_boxes(body, semi_ellipse_boxes(a, b, width, thickness, n_segments), name_prefix, geom_kwargs)


def semi_ellipse_family(a: float | None = None) -> dict[str, tuple[float, float]]:
    """The hybrid paper's five test legs, name -> ``(a, b)`` in m: ``a`` fixed (default 4.5 cm, the
    semicircle case), ``b = a / ratio`` for a/b = 9 (straight), 2 (less straight), 1 (semicircle),
    0.67 (bent), 0.5 (very bent); the values live in :data:`mjrft.laws.hybrid.LEG_FAMILY`."""
    from mjrft.laws.hybrid import LEG_A, LEG_FAMILY

    a = LEG_A if a is None else check_positive("a", a)
    return {name: (a, a / ratio) for name, ratio in LEG_FAMILY.items()}


# ================================================================================================
# Legs as one closed mesh
# ================================================================================================
# A leg made of overlapping boxes has the boxes' end faces INSIDE the leg at every joint; a surface-
# element force law sees each such pair of faces as an extra thin plate (a rib) across the leg, and
# the force then grows with n_segments. The mesh below is the same centre line swept as ONE closed
# surface: the two long faces are offset by +-thickness/2 along the in-plane normal (mitred at the
# joints, so the thickness is exact along each piece), the two sides at +-width/2 along y, and the
# two ends are capped. Triangles are counter-clockwise seen from outside (outward normals).


def leg_mesh(points, width: float, thickness: float) -> tuple[np.ndarray, np.ndarray]:
    """Closed triangle mesh ``(vertices (V, 3), faces (F, 3))`` of a leg whose centre line is the
    polyline ``points`` ((n+1, 3), in the x-z plane, hip to tip).

    The width and thickness are split into pieces no longer than the mean piece of the centre line,
    so the triangles stay close to isotropic; each end cap is a fan around its centre.
    """
    w = check_positive("width", width)
    t = check_positive("thickness", thickness)
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 3 or p.shape[0] < 2 or not np.all(np.isfinite(p)):
        raise ValueError(f"points must be a finite (n+1, 3) array with n >= 1, got shape {p.shape}")
    if np.any(np.abs(p[:, 1]) > 0):
        raise ValueError("points must lie in the x-z plane (y = 0)")
    d = np.diff(p, axis=0)
    seg = np.linalg.norm(d, axis=1)
    if np.any(seg <= 0):
        raise ValueError("points must not repeat (zero-length piece)")
    d /= seg[:, None]
    tan = np.concatenate([d[:1], d[:-1] + d[1:], d[-1:]])
    tan /= np.linalg.norm(tan, axis=1)[:, None]
    cos_half = np.concatenate([[1.0], np.sum(tan[1:-1] * d[1:], axis=1), [1.0]])
    if np.any(cos_half < 0.2):
        raise ValueError("the centre line turns by more than ~157 degrees at one joint; use more points")
    nrm = np.stack([-tan[:, 2], np.zeros(len(p)), tan[:, 0]], axis=1)  # in-plane normal
    half_t = (0.5 * t / cos_half)[:, None] * nrm  # mitred: exact thickness along each piece
    ds = float(seg.mean())
    mw, mt = max(1, math.ceil(w / ds - 1e-9)), max(1, math.ceil(t / ds - 1e-9))
    # cross-section ring (coefficients of half_t and of y), counter-clockwise; side k of each ring edge
    yw = np.linspace(-0.5 * w, 0.5 * w, mw + 1)
    ct = np.linspace(1.0, -1.0, mt + 1)
    ring = ([(1.0, yy, 0) for yy in yw[:-1]] + [(c, 0.5 * w, 1) for c in ct[:-1]]
            + [(-1.0, yy, 2) for yy in yw[::-1][:-1]] + [(c, -0.5 * w, 3) for c in ct[::-1][:-1]])
    r = len(ring)
    cn = np.array([c for c, _, _ in ring])
    cy = np.array([yy for _, yy, _ in ring])
    side = [k for _, _, k in ring]
    ey = np.array([0.0, 1.0, 0.0])
    verts = p[:, None, :] + cn[None, :, None] * half_t[:, None, :] + cy[None, :, None] * ey
    flat = np.concatenate([verts.reshape(-1, 3), p[[0, -1]]])  # + the two cap centres
    outward = {0: nrm, 1: np.tile(ey, (len(p), 1)), 2: -nrm, 3: -np.tile(ey, (len(p), 1))}
    faces = []

    def add(tri, expect):
        a, b, c = flat[list(tri)]
        if np.dot(np.cross(b - a, c - a), expect) < 0:
            tri = (tri[0], tri[2], tri[1])
        faces.append(tri)

    n = len(p) - 1
    for i in range(n):
        for j in range(r):
            j1 = (j + 1) % r
            a, b, c, e = r * i + j, r * i + j1, r * (i + 1) + j1, r * (i + 1) + j
            expect = outward[side[j]][i] + outward[side[j]][i + 1]
            add((a, b, c), expect)
            add((a, c, e), expect)
    for i, centre, expect in ((0, len(flat) - 2, -tan[0]), (n, len(flat) - 1, tan[n])):
        for j in range(r):
            add((centre, r * i + j, r * i + (j + 1) % r), expect)
    return flat, np.array(faces, dtype=np.int64)


def curved_leg_mesh(chord: float, curvature: float, width: float, thickness: float,
                    n_segments: int = 16) -> tuple[np.ndarray, np.ndarray]:
    """:func:`leg_mesh` of the circular-arc leg (conventions of :func:`curved_leg_boxes`)."""
    return leg_mesh(arc_points(chord, curvature, _n_segments(n_segments)), width, thickness)


def semi_ellipse_mesh(a: float, b: float, width: float, thickness: float,
                      n_segments: int = 16) -> tuple[np.ndarray, np.ndarray]:
    """:func:`leg_mesh` of the semi-elliptic leg (conventions of :func:`semi_ellipse_boxes`)."""
    return leg_mesh(semi_ellipse_points(a, b, n_segments), width, thickness)

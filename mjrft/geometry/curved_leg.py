"""Curved ("C") legs built from MuJoCo box geoms approximating a circular arc.

Conventions
-----------
* Frame: everything is expressed in the *leg body frame*. The hip (the leg's
  rotation axis, normally a hinge about y) is at the body origin; the leg hangs
  straight down and its tip is at ``(0, 0, -chord)``.
* ``chord`` is the straight hip-to-tip distance (e.g. ``2 R' = 0.041`` m for the
  RHex-class leg of Li, Zhang & Goldman 2013).
* The leg's centre line lies in the x-z plane. ``width`` is measured along y,
  ``thickness`` across the arc (in the x-z plane).
* ``curvature`` ``k = 1/r`` (1/m) is signed:

  - ``k = 0``: a straight bar;
  - ``k > 0``: a "C-leg" bowing toward +x (forward) when hanging down;
  - ``k < 0``: a reversed C-leg bowing toward -x.

  ``|k| <= 2/chord`` (``|k| = 2/chord`` is a semicircle); a larger ``|k|``
  raises ``ValueError``. With ``R' = chord/2`` the RHex family
  ``k in [-1, -0.92, -0.60, 0, 0.60, 0.92, 1] / R'`` is all valid.
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

__all__ = [
    "arc_length",
    "arc_points",
    "curved_leg_boxes",
    "curved_leg_xml",
    "add_curved_leg",
    "max_curvature",
]


def positive_finite(name: str, value) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a positive finite number, got {value!r}") from None
    if not math.isfinite(v) or v <= 0.0:
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    return v


def max_curvature(chord: float) -> float:
    """Largest allowed ``|curvature|`` (1/m) for ``chord``: ``2/chord`` (a semicircle)."""
    return 2.0 / positive_finite("chord", chord)


def _check_curvature(chord: float, curvature) -> float:
    try:
        k = float(curvature)
    except (TypeError, ValueError):
        raise ValueError(f"curvature must be a finite number, got {curvature!r}") from None
    if not math.isfinite(k):
        raise ValueError(f"curvature must be a finite number, got {curvature!r}")
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
    c = positive_finite("chord", chord)
    k = _check_curvature(c, curvature)
    if k == 0.0:
        return c
    return 2.0 * _half_angle(c, k) / abs(k)


def _direction(alpha: float) -> np.ndarray:
    """Unit tangent at leg angle ``alpha`` (measured from -z toward +x)."""
    return np.array([math.sin(alpha), 0.0, -math.cos(alpha)])


def arc_points(chord: float, curvature: float, n: int = 64) -> np.ndarray:
    """``(n+1, 3)`` points on the leg centre line from hip (0,0,0) to tip (0,0,-chord)."""
    c = positive_finite("chord", chord)
    k = _check_curvature(c, curvature)
    n = int(n)
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n!r}")
    L = arc_length(c, k)
    alpha0 = math.copysign(_half_angle(c, k), k) if k != 0.0 else 0.0
    ds = L / n
    seg_chord = ds if k == 0.0 else 2.0 * math.sin(k * ds / 2.0) / k
    pts = np.zeros((n + 1, 3))
    for i in range(n):
        amid = alpha0 - k * (i + 0.5) * ds
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
    c = positive_finite("chord", chord)
    w = positive_finite("width", width)
    t = positive_finite("thickness", thickness)
    if isinstance(n_segments, bool) or not isinstance(n_segments, (int, np.integer, Real)):
        raise ValueError(f"n_segments must be an integer >= 1, got {n_segments!r}")
    if float(n_segments) != int(n_segments) or int(n_segments) < 1:
        raise ValueError(f"n_segments must be an integer >= 1, got {n_segments!r}")
    n = int(n_segments)
    k = _check_curvature(c, curvature)

    L = arc_length(c, k)
    ds = L / n
    alpha0 = math.copysign(_half_angle(c, k), k) if k != 0.0 else 0.0
    dtheta = abs(k) * ds
    ext = 0.5 * t * math.tan(dtheta / 2.0)  # lengthening at each internal joint
    pts = arc_points(c, k, n)

    boxes = []
    for i in range(n):
        amid = alpha0 - k * (i + 0.5) * ds
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
    lines = []
    extra = ""
    for key, val in geom_attrs.items():
        if val is None:
            continue
        extra += f' {key.rstrip("_")}="{_attr_value(val)}"'
    for i, b in enumerate(curved_leg_boxes(chord, curvature, width, thickness, n_segments)):
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
    import mujoco

    geoms = []
    for i, b in enumerate(curved_leg_boxes(chord, curvature, width, thickness, n_segments)):
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

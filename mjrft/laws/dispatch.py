"""One compiled entry point for every law: ``element_stress(law_id, ...)``, and the vectorised loop.

:func:`element_stress` is generated from the table of laws (:data:`mjrft.laws.registry.LAWS`): one branch per law,
``if law == <id>: return <its stress function>(...)``, compiled by numba like the rest (a new law is an entry in
the table, not an edit here). An unknown id gives zero stress.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .registry import LAWS

_ARGS = "depth, nx, ny, nz, mx, my, mz, speed, p"


def _dispatch_source() -> str:
    """The source of :func:`element_stress`: one branch per entry of the table."""
    lines = [f"def element_stress(law, {_ARGS}):"]
    for law in LAWS:
        lines += [f"    if law == {law.id}:", f"        return _stress_{law.id}({_ARGS})"]
    lines.append("    return 0.0, 0.0, 0.0")
    return "\n".join(lines) + "\n"


_namespace = {"__name__": __name__, **{f"_stress_{law.id}": law.stress for law in LAWS}}
exec(compile(_dispatch_source(), __file__, "exec"), _namespace)  # its code objects name this file (numba's cache)
element_stress = njit(cache=True, error_model="numpy")(_namespace["element_stress"])


@njit(cache=True, error_model="numpy")
def evaluate(law, depth, normal, velocity, area, p, out):
    """Forces (N) on every element into ``out`` (n, 3). Zero velocity or zero normal -> zero force."""
    for i in range(depth.shape[0]):
        nx, ny, nz = normal[i, 0], normal[i, 1], normal[i, 2]
        nl = math.sqrt(nx * nx + ny * ny + nz * nz)
        vx, vy, vz = velocity[i, 0], velocity[i, 1], velocity[i, 2]
        speed = math.sqrt(vx * vx + vy * vy + vz * vz)
        out[i, 0] = 0.0
        out[i, 1] = 0.0
        out[i, 2] = 0.0
        if nl == 0.0 or speed == 0.0:
            continue
        sx, sy, sz = element_stress(law, depth[i], nx / nl, ny / nl, nz / nl, vx / speed, vy / speed, vz / speed,
                                    speed, p)
        out[i, 0] = sx * area[i]
        out[i, 1] = sy * area[i]
        out[i, 2] = sz * area[i]
    return out


def as_elements(depth, normal, velocity, area):
    """Validate and broadcast element arrays to float64 (n,), (n,3), (n,3), (n,)."""
    depth = np.atleast_1d(np.asarray(depth, dtype=np.float64))
    normal = np.atleast_2d(np.asarray(normal, dtype=np.float64))
    velocity = np.atleast_2d(np.asarray(velocity, dtype=np.float64))
    area = np.atleast_1d(np.asarray(area, dtype=np.float64))
    n = max(depth.shape[0], normal.shape[0], velocity.shape[0], area.shape[0])
    if normal.shape[-1] != 3 or velocity.shape[-1] != 3:
        raise ValueError(f"normal and velocity must have 3 components, got shapes {normal.shape} and {velocity.shape}")
    try:
        depth = np.ascontiguousarray(np.broadcast_to(depth, (n,)))
        area = np.ascontiguousarray(np.broadcast_to(area, (n,)))
        normal = np.ascontiguousarray(np.broadcast_to(normal, (n, 3)))
        velocity = np.ascontiguousarray(np.broadcast_to(velocity, (n, 3)))
    except ValueError:
        raise ValueError("depth, normal, velocity and area do not broadcast to one element count") from None
    for name, arr in (("depth", depth), ("normal", normal), ("velocity", velocity), ("area", area)):
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"{name} contains NaN or inf")
    if np.any(area < 0):
        raise ValueError(f"area must be >= 0, got min {area.min()!r}")
    return depth, normal, velocity, area

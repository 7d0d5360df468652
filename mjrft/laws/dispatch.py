"""One compiled entry point for every law: ``element_stress(law_id, ...)``, and the vectorised loop.

Adding a law: write its ``*_stress(depth, nx, ny, nz, mx, my, mz, speed, p)`` function (stress in Pa
on one element, m the unit motion direction, speed in m/s, p the medium's parameter vector), give it
the next id in :mod:`mjrft.laws.registry` and a branch here.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .depth_only import depth_only_stress
from .hybrid import hybrid_stress
from .rft import rft_stress
from .rft3d import rft3d_stress
from .wet import water_stress, wet_stress


@njit(cache=True, error_model="numpy")
def element_stress(law, depth, nx, ny, nz, mx, my, mz, speed, p):
    if law == 0:
        return rft_stress(depth, nx, ny, nz, mx, my, mz, speed, p)
    if law == 1:
        return rft3d_stress(depth, nx, ny, nz, mx, my, mz, speed, p)
    if law == 2:
        return depth_only_stress(depth, nx, ny, nz, mx, my, mz, speed, p)
    if law == 3:
        return wet_stress(depth, nx, ny, nz, mx, my, mz, speed, p)
    if law == 4:
        return water_stress(depth, nx, ny, nz, mx, my, mz, speed, p)
    if law == 5:
        return hybrid_stress(depth, nx, ny, nz, mx, my, mz, speed, p)
    return 0.0, 0.0, 0.0


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

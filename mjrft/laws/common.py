"""Small compiled helpers shared by the force laws (no MuJoCo here).

Leading-surface rule, smoothed: an element counts with weight
``clip(0.5 + (n . v_hat) / (2 LEAD_EPS), 0, 1)``, i.e. fully when its outward normal faces the motion
by more than ~3 degrees, not at all when it faces away, and half when the motion is exactly along
the face. Two opposite faces of a thin plate therefore always add up to one plate, and the force on
a closed body is continuous when a face turns from leading to trailing (Li's fit is continuous in
(beta, gamma), the hard rule would not be).
"""

from __future__ import annotations

import math

from numba import njit

LEAD_EPS = 0.05
TINY = 1e-12


@njit(cache=True, error_model="numpy", inline="always")
def lead_weight(n_dot_v):
    w = 0.5 + n_dot_v / (2.0 * LEAD_EPS)
    if w <= 0.0:
        return 0.0
    if w >= 1.0:
        return 1.0
    return w


@njit(cache=True, error_model="numpy", inline="always")
def motion_plane(nx, ny, mx, my):
    """Unit horizontal axis r of the vertical plane of motion.

    The horizontal direction of the motion; if the motion is vertical, the horizontal direction of
    the normal; if both are vertical, +x.
    """
    h = math.sqrt(mx * mx + my * my)
    if h > TINY:
        return mx / h, my / h
    hn = math.sqrt(nx * nx + ny * ny)
    if hn > TINY:
        return nx / hn, ny / hn
    return 1.0, 0.0


@njit(cache=True, error_model="numpy", inline="always")
def smooth_sign(x, eps):
    if x >= eps:
        return 1.0
    if x <= -eps:
        return -1.0
    return x / eps

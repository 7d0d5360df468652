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
PLANE_EPS = 0.05  # see motion_plane
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
    """Unit horizontal axis r of the element's vertical plane of motion.

    ``normalize(m_h + PLANE_EPS n_h)`` for the unit motion m and unit normal n (h: horizontal part):
    the horizontal direction of the motion, turning smoothly to that of the normal when the motion is
    within a few degrees of vertical (|m_h| ~ PLANE_EPS), and +x if both vanish. Choice: a hard
    switch at exactly vertical motion (r = m_h / |m_h| however small m_h is) makes the force on a
    vertical face that moves (almost) vertically depend on rounding noise in m_h, from full (plane
    through n) to nothing (plane across n); a body resting on sand then creeps. The blend keeps the
    force continuous in m; it changes nothing once the motion is more than ~10 degrees off vertical
    (every reference-table case is exactly horizontal or exactly vertical motion).
    """
    hx = mx + PLANE_EPS * nx
    hy = my + PLANE_EPS * ny
    h = math.sqrt(hx * hx + hy * hy)
    if h > TINY:
        return hx / h, hy / h
    return 1.0, 0.0


@njit(cache=True, error_model="numpy", inline="always")
def smooth_sign(x, eps):
    if x >= eps:
        return 1.0
    if x <= -eps:
        return -1.0
    return x / eps

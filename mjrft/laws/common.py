"""Small compiled helpers shared by the force laws, and the rest memory's update shared by the kernel and the
solidify option (no MuJoCo here).

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
PLANE_FADE = math.sin(math.radians(10.0))  # see motion_plane
INV_PLANE_FADE2 = 1.0 / (PLANE_FADE * PLANE_FADE)
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
def plane_weight(mx, my):
    """Weight of the normal in :func:`motion_plane`: ``PLANE_EPS (1 - q)^2``, ``q = min(1, |m_h|^2 / PLANE_FADE^2)``."""
    q = min(1.0, (mx * mx + my * my) * INV_PLANE_FADE2)
    return PLANE_EPS * (1.0 - q) * (1.0 - q)


@njit(cache=True, error_model="numpy", inline="always")
def motion_plane(nx, ny, mx, my):
    """Unit horizontal axis r of the element's vertical plane of motion.

    ``normalize(m_h + w n_h)`` for the unit motion m and unit normal n (h: horizontal part), with the
    normal's weight ``w = PLANE_EPS (1 - q)^2``, ``q = min(1, |m_h|^2 / PLANE_FADE^2)``
    (:func:`plane_weight`): the horizontal direction of the motion, turning smoothly to that of the
    normal when the motion is within a few degrees of vertical (|m_h| ~ PLANE_EPS = 0.05), and +x if
    both vanish. Choice: a hard switch at exactly vertical motion (r = m_h / |m_h| however small m_h
    is) makes the force on a vertical face that moves (almost) vertically depend on rounding noise in
    m_h, from full (plane through n) to nothing (plane across n); a body resting on sand then creeps.
    The blend keeps the force continuous in m (w and its slope are continuous); its weight fades to
    exactly zero at |m_h| = PLANE_FADE = sin 10 deg, so motion more than 10 degrees off vertical
    (every horizontal drag, every reference-table case) uses the plane of the motion itself.
    """
    w = plane_weight(mx, my)
    hx = mx + w * nx
    hy = my + w * ny
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


@njit(cache=True, error_model="numpy", inline="always")
def relax_memory(u, i, vx, vy, vz, speed, a, delta):
    """The rest memory's flowing update of element ``i`` (docs/numerics.md, "Rest regularisation"; ``speed = |v|
    > 0``): ``u <- delta v_hat + (u - delta v_hat) a``, ``a = exp(-|v| dt / delta)`` computed by the caller
    (:func:`mjrft.kernel._rest_memory`, :func:`mjrft.laws.solidify.solid_memory`)."""
    s = delta / speed
    u[i, 0] = s * vx + (u[i, 0] - s * vx) * a
    u[i, 1] = s * vy + (u[i, 1] - s * vy) * a
    u[i, 2] = s * vz + (u[i, 2] - s * vz) * a


@njit(cache=True, error_model="numpy", inline="always")
def memory_motion(u, i, vx, vy, vz, tau):
    """The regularised motion the law sees from element ``i``'s memory: ``m = u + tau v`` and ``|m|``."""
    mx = u[i, 0] + tau * vx
    my = u[i, 1] + tau * vy
    mz = u[i, 2] + tau * vz
    return mx, my, mz, math.sqrt(mx * mx + my * my + mz * mz)

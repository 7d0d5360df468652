"""Li, Zhang & Goldman 2013 resistive force theory, evaluated in each element's vertical plane of motion.

For an element with outward unit normal n moving along unit direction m at depth |z|:

* the plane is spanned by z_hat and r_hat, the horizontal direction of m (see
  :func:`mjrft.laws.common.motion_plane`: within a few degrees of vertical motion it turns smoothly
  to the horizontal direction of the normal);
* the intrusion angle gamma has cos(gamma) = m . r_hat, sin(gamma) = -m_z (positive downward);
* the attack angle beta is the angle of the element's plane line in that plane: the faces of a plate
  at beta are +-(sin beta, -cos beta) in (r, z), so with (n_r, n_z) the in-plane part of n,
  cos 2beta = (n_z^2 - n_r^2) / w^2 and sin 2beta = -2 n_r n_z / w^2, w = |(n_r, n_z)|
  (beta is defined modulo pi, like the fit, so no branch cut);
* (alpha_z, alpha_x) from the medium's Fourier fit (supplement eq. S8, evaluated with the angle-sum
  identities, no trigonometric calls);
* stress = lead_weight x w x |z| x (-alpha_x r_hat + alpha_z z_hat).

Choice where the paper is silent (its fit is planar): a normal with a component out of the plane of
motion is projected onto the plane, and the stress is weighted by the projected length w, so an
element sliding edge-on (normal perpendicular to the plane) feels nothing from this law. Use
``rft3d`` for motion where such elements matter.

Speed: rate-independent by default. The dry inertial regime (:mod:`mjrft.laws.inertial`, an option that
is off unless a scene turns it on) adds ``C rho_bulk (u^2 - v_c^2)`` on leading faces above the critical
speed ``v_c = sqrt(2 g d)``.
"""

from __future__ import annotations

import math

from numba import njit

from .common import INV_PLANE_FADE2, LEAD_EPS, PLANE_EPS, TINY, lead_weight, motion_plane


@njit(cache=True, error_model="numpy")
def rft_stress(depth, nx, ny, nz, mx, my, mz, speed, p):
    """Stress vector (Pa) on one element; ``m`` unit motion direction, ``p`` the medium parameters."""
    if depth <= 0.0:
        return 0.0, 0.0, 0.0
    lw = lead_weight(nx * mx + ny * my + nz * mz)
    if lw == 0.0:
        return 0.0, 0.0, 0.0
    rx, ry = motion_plane(nx, ny, mx, my)
    vr = mx * rx + my * ry
    vn = math.sqrt(vr * vr + mz * mz)
    if vn < TINY:
        return 0.0, 0.0, 0.0
    cg = vr / vn
    sg = -mz / vn
    nr = nx * rx + ny * ry
    w2 = nr * nr + nz * nz
    if w2 < TINY * TINY:
        return 0.0, 0.0, 0.0
    c2 = (nz * nz - nr * nr) / w2
    s2 = -2.0 * nr * nz / w2
    az = (p[0] + p[1] * c2 + p[2] * (s2 * cg + c2 * sg) + p[3] * sg + p[4] * (c2 * sg - s2 * cg))
    ax = (p[5] * (c2 * cg - s2 * sg) + p[6] * cg + p[7] * (c2 * cg + s2 * sg) + p[8] * s2)
    k = lw * math.sqrt(w2) * depth
    return -ax * rx * k, -ax * ry * k, az * k


#: :func:`trails`' bound on ``n . m``: ``LEAD_EPS`` and a margin far above rounding, so that the lead weight that
#: :func:`rft_stress_batch` computes for such an element is 0 however its arithmetic rounds.
TRAIL_DOT = LEAD_EPS * (1.0 + 1e-6)


@njit(cache=True, error_model="numpy", inline="always")
def trails(nx, ny, nz, mx, my, mz):
    """Whether an element with unit normal ``n`` moving along the unit direction ``m`` faces away from its motion
    (``n . m < -TRAIL_DOT``): its lead weight is 0, so this law gives it no stress and no stiffness."""
    return nx * mx + ny * my + nz * mz < -TRAIL_DOT


@njit(cache=True, error_model="numpy", inline="always")
def _batch_stress(nx, ny, nz, mx, my, mz, depth, p0, p1, p2, p3, p4, p5, p6, p7, p8):
    """The body of the batched law (:func:`rft_stress_batch`, :func:`rft_stress_batch_packed`): the stress on one
    element with unit normal ``n``, unit motion direction ``m``, depth ``depth`` (clamped at 0) and Li's nine
    coefficients ``p0``-``p8``, without a branch (:func:`motion_plane` written with selects)."""
    lw = min(1.0, max(0.0, 0.5 + (nx * mx + ny * my + nz * mz) * (0.5 / LEAD_EPS)))
    q = min(1.0, (mx * mx + my * my) * INV_PLANE_FADE2)
    pw = PLANE_EPS * (1.0 - q) * (1.0 - q)  # plane_weight
    hx = mx + pw * nx
    hy = my + pw * ny
    h2 = hx * hx + hy * hy
    use = h2 > TINY * TINY
    inv = 1.0 / math.sqrt(h2 if use else 1.0)
    rx = hx * inv if use else 1.0
    ry = hy * inv if use else 0.0
    vr = mx * rx + my * ry
    ivn = 1.0 / math.sqrt(max(vr * vr + mz * mz, TINY * TINY))
    cg = vr * ivn
    sg = -mz * ivn
    nr = nx * rx + ny * ry
    w2 = nr * nr + nz * nz
    iw = 1.0 / max(w2, TINY * TINY)
    c2 = (nz * nz - nr * nr) * iw
    s2 = -2.0 * nr * nz * iw
    az = (p0 + p1 * c2 + p2 * (s2 * cg + c2 * sg) + p3 * sg + p4 * (c2 * sg - s2 * cg))
    ax = (p5 * (c2 * cg - s2 * sg) + p6 * cg + p7 * (c2 * cg + s2 * sg) + p8 * s2)
    k = lw * math.sqrt(w2) * max(depth, 0.0) if w2 >= TINY * TINY else 0.0
    return -ax * rx * k, -ax * ry * k, az * k


@njit(cache=True, error_model="numpy", fastmath={"contract", "arcp", "nsz"})
def rft_stress_batch(count, depth, n, m, p, out):
    """:func:`rft_stress` on ``count`` elements at once, branch-free so the compiler vectorises it.

    Structure-of-arrays: ``depth`` (>= count,) positive depths, ``n`` and ``m`` (3, >= count) unit
    normals and unit motion directions (rows x, y, z), ``out`` (3, >= count) receives the stresses.
    Equal to :func:`rft_stress` to rounding (:func:`motion_plane` written with selects).
    About 7x faster per element than the scalar function (measured on a 2-core machine).
    """
    for i in range(count):
        out[0, i], out[1, i], out[2, i] = _batch_stress(n[0, i], n[1, i], n[2, i], m[0, i], m[1, i], m[2, i],
                                                        depth[i], p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7],
                                                        p[8])


@njit(cache=True, error_model="numpy", fastmath={"contract", "arcp", "nsz"})
def rft_stress_batch_packed(count, depth, n, m, p, dp, t, out):
    """:func:`rft_stress_batch` with each element's coefficients at its packing (the ground memory,
    :mod:`mjrft.ground`): element ``j`` takes ``p[k] + t[j] dp[k]`` for the nine coefficients (``dp``: the closely
    minus loosely packed row; ``t`` (>= count,): the change of its loose-to-close weight from the prepared state).
    Li's stress is linear in the coefficients, so this is the law of the interpolated row; with ``t = 0`` it is
    :func:`rft_stress_batch` bit for bit."""
    for i in range(count):
        tt = t[i]
        out[0, i], out[1, i], out[2, i] = _batch_stress(n[0, i], n[1, i], n[2, i], m[0, i], m[1, i], m[2, i],
                                                        depth[i], p[0] + tt * dp[0], p[1] + tt * dp[1],
                                                        p[2] + tt * dp[2], p[3] + tt * dp[3], p[4] + tt * dp[4],
                                                        p[5] + tt * dp[5], p[6] + tt * dp[6], p[7] + tt * dp[7],
                                                        p[8] + tt * dp[8])

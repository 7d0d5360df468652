"""Three-dimensional RFT (Agarwal, Goldman & Kamrin, PNAS 2023; Treers et al. RA-L 2021).

Per element: local frame z_hat (up), r_hat (horizontal direction of motion, turning smoothly to that of
the normal within a few degrees of vertical motion: :func:`mjrft.laws.common.motion_plane`), theta_hat = z_hat x r_hat. Angles beta (from n), gamma (from
the motion, negative when moving up) and psi (normal's horizontal part against r_hat) feed three
cubic fits f1, f2, f3 in x1 = sin gamma, x2 = cos beta, x3 = cos psi cos gamma sin beta +
sin gamma cos beta, giving the generic response

    alpha_r = f1 sin(beta) cos(psi) + f2 cos(gamma)
    alpha_theta = f1 sin(beta) sin(psi)
    alpha_z = -f1 cos(beta) - f2 sin(gamma) - f3

which is split into a part along the normal and a tangential part; the tangential part is capped at
mu_surface x the normal part and the result scaled by xi_n (N/m^3) and the depth.

Choices where the reference is ambiguous (documented and tested):

* psi when the normal's horizontal part is perpendicular to r_hat: the limit of atan(n_theta / n_r)
  from n_r -> 0+ (+-pi/2), not 0, so that the force is continuous there (beta switches branch at the
  same place and the two sign flips cancel). psi = 0 when the normal is vertical.
* beta jumps by pi where the normal crosses the horizontal (published branches -acos(n_z) for
  n_z >= 0 and pi - acos(n_z) below), and the cubic fit is not symmetric there, so the published law
  jumps by ~20% at vertical faces. We blend the two branches linearly over
  -VERTICAL_BAND < n_z < 0 (about 3 degrees below horizontal): exactly the published value at and
  above the horizontal (the reference table's vertical plate is reproduced), continuous everywhere.
* "tangential part turned to oppose the motion": the tangential part keeps its direction except for
  its component along the element's tangential sliding direction, which is reflected when it points
  along the sliding (friction never pushes a surface the way it slides); the reflection is ramped in
  over 0.05 of tangential motion so the force stays continuous. The published table values (generic
  response, no cap) are unaffected.
* No tension: the part of alpha_gen along the outward normal is clamped to zero (grains without
  cohesion cannot pull on a face), and with it the tangential part, which the friction cap bounds by
  mu_surface x the normal part. The fit gives such tensile values on faces that the motion slides
  along, e.g. the top face of a plate dragged horizontally (alpha_gen = 0.110 up, along its outward
  normal, the same value as on the bottom face), where it lifted Li's plate dragged at 5 cm depth by
  1.3 of its 3.2 N. Clamping keeps the force continuous (it is zero where the normal part changes
  sign) and leaves every leading face whose normal part is compressive, the whole reference table
  included, unchanged.

Speed: rate-independent by default. The dry inertial regime (:mod:`mjrft.laws.inertial`, an option that
is off unless a scene turns it on) adds ``C rho_bulk (u^2 - v_c^2)`` on leading faces above the critical
speed ``v_c = sqrt(2 g d)``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .common import TINY, lead_weight, motion_plane

C1 = np.array([0.00212, -0.02320, -0.20890, -0.43083, -0.00259, 0.48872, -0.00415, 0.07204, -0.02750, -0.08772,
               0.01992, -0.45961, 0.40799, -0.10107, -0.06576, 0.05664, -0.09269, 0.01892, 0.01033, 0.15120])
C2 = np.array([-0.06796, -0.10941, 0.04725, -0.06914, -0.05835, -0.65880, -0.11985, -0.25739, -0.26834, 0.02692,
               -0.00736, 0.63758, 0.08997, 0.21069, 0.04748, 0.20406, 0.18589, 0.04934, 0.13527, -0.33207])
C3 = np.array([-0.02634, -0.03436, 0.45256, 0.00835, 0.02553, -1.31290, -0.05532, 0.06790, -0.16404, 0.02287,
               0.02927, 0.95406, -0.00131, -0.11028, 0.01487, -0.02730, 0.10911, -0.04097, 0.07881, -0.27519])
TANGENT_EPS = 0.05
VERTICAL_BAND = 0.05


@njit(cache=True, error_model="numpy", inline="always")
def _poly(c, x1, x2, x3):
    return (c[0] + c[1] * x1 + c[2] * x2 + c[3] * x3 + c[4] * x1 * x1 + c[5] * x2 * x2 + c[6] * x3 * x3
            + c[7] * x1 * x2 + c[8] * x2 * x3 + c[9] * x3 * x1 + c[10] * x1 ** 3 + c[11] * x2 ** 3 + c[12] * x3 ** 3
            + c[13] * x1 * x2 * x2 + c[14] * x2 * x1 * x1 + c[15] * x2 * x3 * x3 + c[16] * x3 * x2 * x2
            + c[17] * x3 * x1 * x1 + c[18] * x1 * x3 * x3 + c[19] * x1 * x2 * x3)


@njit(cache=True, error_model="numpy", inline="always")
def _response(beta, gamma, psi):
    """(alpha_r, alpha_theta, alpha_z) of the generic fit at the given angles."""
    sb, cb = math.sin(beta), math.cos(beta)
    sg, cgm = math.sin(gamma), math.cos(gamma)
    sp, cp = math.sin(psi), math.cos(psi)
    x1 = sg
    x2 = cb
    x3 = cp * cgm * sb + sg * cb
    f1 = _poly(C1, x1, x2, x3)
    f2 = _poly(C2, x1, x2, x3)
    f3 = _poly(C3, x1, x2, x3)
    return f1 * sb * cp + f2 * cgm, f1 * sb * sp, -f1 * cb - f2 * sg - f3


@njit(cache=True, error_model="numpy")
def rft3d_generic(nx, ny, nz, mx, my, mz):
    """Dimensionless generic response alpha_gen (world frame) for unit normal n and unit motion m."""
    rx, ry = motion_plane(nx, ny, mx, my)
    tx, ty = -ry, rx  # theta_hat = z_hat x r_hat
    nr = nx * rx + ny * ry
    cz = min(1.0, max(-1.0, nz))
    # beta's two branches (normal tilted up / down); see VERTICAL_BAND
    if nr >= 0.0:
        b_up, b_dn = -math.acos(cz), math.pi - math.acos(cz)
    else:
        b_up, b_dn = math.acos(cz), -math.pi + math.acos(cz)
    gamma = math.acos(min(1.0, max(-1.0, mx * rx + my * ry)))
    if mz > 0.0:
        gamma = -gamma
    nt = nx * tx + ny * ty
    nh = math.sqrt(nx * nx + ny * ny)
    if nh < TINY:
        psi = 0.0
    elif abs(nr) < TINY * nh:
        psi = math.copysign(0.5 * math.pi, nt)
    else:
        psi = math.atan(nt / nr)
    w_up = 1.0 if cz >= 0.0 else max(0.0, 1.0 + cz / VERTICAL_BAND)
    ar, at, az = 0.0, 0.0, 0.0
    if w_up > 0.0:
        r1, t1, z1 = _response(b_up, gamma, psi)
        ar, at, az = w_up * r1, w_up * t1, w_up * z1
    if w_up < 1.0:
        r2, t2, z2 = _response(b_dn, gamma, psi)
        ar += (1.0 - w_up) * r2
        at += (1.0 - w_up) * t2
        az += (1.0 - w_up) * z2
    return ar * rx + at * tx, ar * ry + at * ty, az


@njit(cache=True, error_model="numpy")
def rft3d_stress(depth, nx, ny, nz, mx, my, mz, speed, p):
    if depth <= 0.0:
        return 0.0, 0.0, 0.0
    lw = lead_weight(nx * mx + ny * my + nz * mz)
    if lw == 0.0:
        return 0.0, 0.0, 0.0
    gx, gy, gz = rft3d_generic(nx, ny, nz, mx, my, mz)
    an = gx * nx + gy * ny + gz * nz
    tx, ty, tz = gx - an * nx, gy - an * ny, gz - an * nz
    if an > 0.0:  # no tension: cohesionless grains only push on a face (module docstring, "No tension")
        an = 0.0
    # tangential sliding direction of the element
    mn = mx * nx + my * ny + mz * nz
    sx, sy, sz = mx - mn * nx, my - mn * ny, mz - mn * nz
    sl = math.sqrt(sx * sx + sy * sy + sz * sz)
    if sl > TINY:
        along = (tx * sx + ty * sy + tz * sz) / sl
        if along > 0.0:
            k = 2.0 * along * min(1.0, sl / TANGENT_EPS) / sl
            tx -= k * sx
            ty -= k * sy
            tz -= k * sz
    tl = math.sqrt(tx * tx + ty * ty + tz * tz)
    cap = 1.0
    if tl > TINY:
        cap = min(1.0, p[10] * abs(an) / tl)
    k = p[9] * depth * lw
    return (an * nx + cap * tx) * k, (an * ny + cap * ty) * k, (an * nz + cap * tz) * k

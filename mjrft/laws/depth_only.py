"""The flat-plate (depth-only) baseline that RFT replaced (Li 2013 supplement, section 1).

The vertical stress uses the area projected on the horizontal (|n_z|), the horizontal stress the
area projected on the vertical plane across the motion (|n . r_hat|), and each opposes its own
velocity component:

    sigma_z = -sign(m_z) alpha_z(0, sign(gamma) pi/2) |n_z| |z|
    sigma_h = -alpha_x(pi/2, 0) |n . r_hat| |z| r_hat

Choice: the signs are smoothed over 0.05 of the unit motion (about 3 degrees) so the force is
continuous when a velocity component changes sign; alpha_z uses the medium's pushed-down value for
downward motion and the magnitude of its pulled-up value for upward motion. Only leading elements
count (same smoothed rule as the other laws).
"""

from __future__ import annotations

import math

from numba import njit

from .common import lead_weight, smooth_sign

SIGN_EPS = 0.05


@njit(cache=True, error_model="numpy")
def depth_only_stress(depth, nx, ny, nz, mx, my, mz, speed, p):
    if depth <= 0.0:
        return 0.0, 0.0, 0.0
    lw = lead_weight(nx * mx + ny * my + nz * mz)
    if lw == 0.0:
        return 0.0, 0.0, 0.0
    az = p[12] if mz < 0.0 else p[13]
    fz = -smooth_sign(mz, SIGN_EPS) * az * abs(nz)
    h = math.sqrt(mx * mx + my * my)
    fx = 0.0
    fy = 0.0
    if h > 0.0:
        rx = mx / h
        ry = my / h
        fh = -smooth_sign(h, SIGN_EPS) * p[14] * abs(nx * rx + ny * ry)
        fx = fh * rx
        fy = fh * ry
    k = lw * depth
    return fx * k, fy * k, fz * k

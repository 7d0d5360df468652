"""The flat-plate (depth-only) baseline that RFT replaced (Li 2013 supplement, section 1, eqs. S3-S7).

A horizontal plate moving vertically feels f_z = alpha_z(0, sgn pi/2) |z| A (eq. S3), a vertical
plate dragged horizontally f_x = alpha_x(pi/2, 0) |z| A (eq. S4); a leg element of any attack angle
takes the vertical force on its area projected on the horizontal, |cos beta| dA (eq. S5), and the
horizontal force on its area projected on the vertical plane across the motion, |sin beta| dA
(eq. S6), each always opposing its own velocity component (eq. S7 and the text after it). In 3D,
with n the outward normal, m the unit motion and r_hat its horizontal direction:

    sigma_z = -sign(m_z) alpha_z(0, sign(gamma) pi/2) |n_z| |z|
    sigma_h = -alpha_x(pi/2, 0) |n . r_hat| |z| r_hat

Constants (:attr:`mjrft.media.Medium.depth_only_alphas`, parameter slots ``P_AZ_DOWN``,
``P_AZ_UP``, ``P_AX_DRAG``): the paper builds the model from the MEASURED plate stresses, so
alpha_z(0, pi/2) is the medium's measured value (table S3 for the Li media, the fitted slope for a
:func:`mjrft.calibrate` medium), 1.05-1.37 times the Fourier fit's; a medium with no measured value
(the generic profile and its scaled copies, 3D-RFT media, saturated sand) uses its fit's value. The
pulled-up |alpha_z(0, -pi/2)| and alpha_x(pi/2, 0) are printed only in the paper's Fig. 2 C-D (lost
in the text, data table S5 not available), so they come from the medium's Fourier fit.

Choices: the signs are smoothed over 0.05 of the unit motion (about 3 degrees) so the force is
continuous when a velocity component changes sign (eq. S7's sgn jumps there); only leading
elements count (same smoothed rule as the other laws), so a thin plate's two faces add up to one
plate.

Speed: rate-independent by default. The dry inertial regime (:mod:`mjrft.laws.inertial`, an option that
is off unless a scene turns it on) adds ``C rho_bulk (u^2 - v_c^2)`` on leading faces above the critical
speed ``v_c = sqrt(2 g d)``.
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

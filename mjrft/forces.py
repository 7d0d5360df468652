"""One element's granular force, as the compiled kernel (:mod:`mjrft.kernel`) evaluates it.

:func:`element_force` is one region's force on one element: its law through the rest regularisation (the law's
stress at the element's memory direction, times its area and its mobility), the inertial regime on the element's
real velocity, the water layer's drag and the hydrostatic pressure below the water's surface; :func:`blended_force`
sums it over the regions an element straddles with their weights. :func:`linear_stiffness` is the linearised
stiffness of an element's force that the stability check and the implicit step read (docs/numerics.md,
"Stability limit"). Pure scalar code (numba); the JAX twins are in :mod:`mjrft.mjx.forces`.
"""

from __future__ import annotations

import math

from numba import njit

from .laws.dispatch import element_stress
from .laws.inertial import inertial_force
from .laws.registry import LAW_IDS
from .laws.wet import water_stress
from .params import P_INERTIA, P_WATER_DEPTH, P_WATER_SKIN

LAW_WATER = LAW_IDS["water"]  # a region of open water: no sand law below it


@njit(cache=True, error_model="numpy")
def isfinite3(x, y, z):
    return math.isfinite(x) and math.isfinite(y) and math.isfinite(z)


@njit(cache=True, error_model="numpy", inline="always")
def linear_stiffness(fx, fy, fz, ml, delta, v_eps):
    """Linearised stiffness of an element force ``|F| / max(|m|, delta)`` (the damping
    ``|F| / max(|v|, v_eps)`` in the viscous mode), see docs/numerics.md, "Stability limit"."""
    return stiffness_of(math.sqrt(fx * fx + fy * fy + fz * fz), ml, delta, v_eps)


@njit(cache=True, error_model="numpy", inline="always")
def stiffness_of(f_mag, ml, delta, v_eps):
    """:func:`linear_stiffness` from the force's size ``f_mag``."""
    if delta > 0.0:
        return f_mag / max(ml, delta)
    if v_eps > 0.0:
        return f_mag / max(ml, v_eps)
    return 0.0


@njit(cache=True, error_model="numpy", fastmath={"contract", "arcp", "nsz"})
def element_force(law, p, rho_w, gravity, k, depth, nx, ny, nz, mx, my, mz, ml, mob, vx, vy, vz, speed, delta,
                   v_eps):
    """Force (N) of one region on one element of area ``k`` (area x the region's weight); see terrain_kernel.

    Returns (fx, fy, fz, stiffness (damping in the viscous mode) of the sand part, water damping,
    inertial damping (mjrft.laws.inertial), finite).
    """
    fx, fy, fz, kk, cw, ci = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    if ml > 0.0 and law != LAW_WATER:  # the sand, through the rest regularisation
        iml = 1.0 / ml
        sx, sy, sz = element_stress(law, depth, nx, ny, nz, mx * iml, my * iml, mz * iml, speed, p)
        fx, fy, fz = sx * k, sy * k, sz * k
        if not isfinite3(fx, fy, fz):
            return fx, fy, fz, kk, cw, ci, False
        kk = linear_stiffness(fx, fy, fz, ml, delta, v_eps)
        fx *= mob
        fy *= mob
        fz *= mob
    if p[P_INERTIA] > 0.0 and law != LAW_WATER:  # the inertial regime (on the real velocity, no memory)
        gx, gy, gz, ci = inertial_force(p, depth, nx, ny, nz, vx, vy, vz, k)
        if not isfinite3(gx, gy, gz):
            return gx, gy, gz, kk, cw, ci, False
        fx += gx
        fy += gy
        fz += gz
    hw = p[P_WATER_DEPTH]
    if hw > 0.0 and speed > 0.0 and depth > -hw and depth < p[P_WATER_SKIN]:  # the water layer's drag
        iv = 1.0 / speed
        sx, sy, sz = water_stress(depth, nx, ny, nz, vx * iv, vy * iv, vz * iv, speed, p)
        gx, gy, gz = sx * k, sy * k, sz * k
        if not isfinite3(gx, gy, gz):
            return gx, gy, gz, kk, cw, ci, False
        cw = 2.0 * math.sqrt(gx * gx + gy * gy + gz * gz) * iv  # d|F|/d|v| of a v^2 drag
        fx += gx
        fy += gy
        fz += gz
    if rho_w > 0.0:  # hydrostatic pressure below the water surface (sand surface + hw)
        pres = rho_w * gravity * (depth + hw)
        if pres > 0.0:
            kp = -pres * k
            fx += kp * nx
            fy += kp * ny
            fz += kp * nz
    return fx, fy, fz, kk, cw, ci, True


@njit(cache=True, error_model="numpy", fastmath={"contract", "arcp", "nsz"})
def blended_force(regs, wts, reg_law, reg_params, reg_rho, gravity, area, depth, nx, ny, nz, mx, my, mz, ml, mob,
                   vx, vy, vz, speed, delta, v_eps):
    """:func:`element_force` summed over the regions ``regs`` with weights ``wts`` (same returns)."""
    fx, fy, fz, kk, cw, ci, ok = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, True
    for q in range(4):
        w = wts[q]
        if w > 0.0:
            reg = regs[q]
            gx, gy, gz, kq, cq, iq, okq = element_force(reg_law[reg], reg_params[reg], reg_rho[reg], gravity, area * w,
                                                     depth, nx, ny, nz, mx, my, mz, ml, mob, vx, vy, vz, speed,
                                                     delta, v_eps)
            fx += gx
            fy += gy
            fz += gz
            kk += kq
            cw += cq
            ci += iq
            ok = ok and okq
    return fx, fy, fz, kk, cw, ci, ok

"""The implicit granular step (``GranularTerrain(implicit=True)``): the wrench of the buried bodies made linearly
implicit in the grains' springs, so that they are stable at every timestep.

After ``mj_step1`` and :func:`mjrft.kernel.terrain_kernel`, :func:`implicit_wrench` replaces the explicit wrench
``F`` of each body with springs by the ``F'`` that solves ``(I + dt G W) F' = F - G dV_o`` (``G`` the body's
springs below yield, ``W`` the bodies' mobility, ``dV_o`` the velocity change every other force makes in the
step). The derivation, what stays explicit and why, is in docs/numerics.md, "Implicit step".
"""

from __future__ import annotations

import math

from numba import njit

from .mujoco_c import call_mj, call_mj_arrays
from .stability import add_k6

#: An element whose memory ``|u|`` is within this fraction of ``yield_displacement`` holds (it has slid less than
#: about ``-ln(1 - 0.9) = 2.3`` yield displacements since it last rested or turned): its spring enters the implicit
#: step even when its damping term ``tau v`` takes ``|u + tau v|`` past yield (docs/numerics.md, "Implicit step").
HOLD_FRACTION = 0.9

#: MuJoCo functions the implicit step calls (:func:`implicit_wrench`), in the order of its first arguments
IMPLICIT_FUNCTIONS = ("mj_fwdActuation", "mj_fwdAcceleration", "mj_jacBodyCom", "mj_solveM")


@njit(cache=True, error_model="numpy", _nrt=False)
def implicit_wrench(f_act, f_acc, f_jac, f_solve, m_addr, d_addr, qacc_smooth, bodies, wrench, imp, inert,
                    use_inert, dt, jac, minv_jac, blocks, a, rhs, rows):
    """Replace the explicit wrench of the buried bodies by the linearly implicit one (docs/numerics.md,
    "Implicit step").

    Called after ``mj_step1`` and :func:`mjrft.kernel.terrain_kernel`, before the wrench is added to
    ``xfrc_applied``: MuJoCo's ``mj_fwdActuation`` and ``mj_fwdAcceleration`` give ``qacc_smooth`` (every force but the
    grains' and the constraints'), ``mj_jacBodyCom`` the buried bodies' 6 x nv CoM jacobians ``J`` (stacked),
    ``mj_solveM`` ``M^-1 J^T``. Scratch: ``jac``, ``minv_jac`` (6 nb x nv), ``blocks`` (nb, 6, 6), ``a``
    (6 nb x 6 nb), ``rhs`` (12 nb + 6: the right-hand side, then room for a column of ``W`` and for ``dV_o``),
    ``rows`` (nb), with nb the number of selected bodies; nothing is allocated, so the fused loop that calls it
    compiles without numba's reference counting (:func:`mjrft.stepping.run_steps`). Returns -1, or the first body
    whose implicit wrench is not finite (its ``wrench`` row is then left as it is)."""
    nv = jac.shape[1]
    nb = bodies.shape[0]
    w = rhs[6 * nb:12 * nb]
    dv = rhs[12 * nb:12 * nb + 6]
    n = 0
    for i in range(nb):
        b = bodies[i]
        if imp[b, 0] > 0 or (use_inert and inert[b, 0] > 0):
            rows[n] = b
            n += 1
    if n == 0:
        return -1
    call_mj(f_act, m_addr, d_addr)
    call_mj(f_acc, m_addr, d_addr)
    for i in range(n):
        at = jac.ctypes.data + 6 * i * nv * 8
        call_mj_arrays(f_jac, m_addr, d_addr, at, at + 3 * nv * 8, rows[i])
    m6 = 6 * n
    call_mj_arrays(f_solve, m_addr, d_addr, minv_jac.ctypes.data, jac.ctypes.data, m6)
    # G_b: the 6x6 of the kernel's implicit spring moments + the inertial dampers' C6
    for i in range(n):
        g = blocks[i]
        g[:, :] = 0.0
        add_k6(g, imp[rows[i]], 1.0)
        if use_inert and inert[rows[i], 0] > 0:
            add_k6(g, inert[rows[i]], 1.0)
    # rhs = F - G dV_other, dV_other = dt J qacc_smooth
    for i in range(n):
        for r in range(6):
            acc = 0.0
            for k in range(nv):
                acc += jac[6 * i + r, k] * qacc_smooth[k]
            dv[r] = dt * acc
        g = blocks[i]
        for r in range(6):
            acc = wrench[rows[i], r]
            for c in range(6):
                acc -= g[r, c] * dv[c]
            rhs[6 * i + r] = acc
    # a = I + dt G W, W = J M^-1 J^T (symmetric; W[p, q] = jac[p] . minv_jac[q])
    for q in range(m6):
        _mobility_column(jac, minv_jac, q, m6, nv, w)
        for i in range(n):
            g = blocks[i]
            for r in range(6):
                acc = 0.0
                for c in range(6):
                    acc += g[r, c] * w[6 * i + c]
                a[6 * i + r, q] = dt * acc
        a[q, q] += 1.0
    _solve_in_place(a, rhs, m6)
    for i in range(n):
        for r in range(6):
            if not math.isfinite(rhs[6 * i + r]):
                return rows[i]
    for i in range(n):
        for r in range(6):
            wrench[rows[i], r] = rhs[6 * i + r]
    return -1


@njit(cache=True, error_model="numpy", _nrt=False)
def _mobility_column(jac, minv_jac, q, m, nv, w):
    """Column ``q`` of ``W = J M^-1 J^T`` into ``w[:m]``: ``w[p] = jac[p] . minv_jac[q]``, each a sum over ``k`` in
    order. Four rows at a time: their four sums are independent, so the processor overlaps them instead of
    waiting on one chain of additions (the same sums, term by term, as one row at a time)."""
    p = 0
    while p + 4 <= m:
        a0 = a1 = a2 = a3 = 0.0
        for k in range(nv):
            c = minv_jac[q, k]
            a0 += jac[p, k] * c
            a1 += jac[p + 1, k] * c
            a2 += jac[p + 2, k] * c
            a3 += jac[p + 3, k] * c
        w[p], w[p + 1], w[p + 2], w[p + 3] = a0, a1, a2, a3
        p += 4
    while p < m:
        acc = 0.0
        for k in range(nv):
            acc += jac[p, k] * minv_jac[q, k]
        w[p] = acc
        p += 1


@njit(cache=True, error_model="numpy", _nrt=False)
def _solve_in_place(a, x, n):
    """Solve ``a[:n, :n] y = x[:n]`` into ``x`` (Gaussian elimination with partial pivoting; ``a`` is
    overwritten). ``a = I + dt G W`` is a P-matrix here (G, W positive semi-definite), so no pivot is 0."""
    for k in range(n):
        p = k
        big = abs(a[k, k])
        for i in range(k + 1, n):
            if abs(a[i, k]) > big:
                big = abs(a[i, k])
                p = i
        if p != k:
            for j in range(n):
                a[k, j], a[p, j] = a[p, j], a[k, j]
            x[k], x[p] = x[p], x[k]
        piv = a[k, k]
        pivot_row = a[k, k + 1:n]  # rows as slices: loops from 0 over them vectorise (a range from k + 1 does not)
        for i in range(k + 1, n):
            f = a[i, k] / piv
            if f != 0.0:
                row = a[i, k + 1:n]
                for j in range(n - k - 1):
                    row[j] -= f * pivot_row[j]
                x[i] -= f * x[k]
    for k in range(n - 1, -1, -1):
        acc = x[k]
        for j in range(k + 1, n):
            acc -= a[k, j] * x[j]
        x[k] = acc / a[k, k]

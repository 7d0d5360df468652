"""The explicit step's stability limit: the largest stable timestep of the grains' linearised springs and
dampers per body, and the warnings when a step exceeds it.

The per-step kernel (:func:`mjrft.kernel.terrain_kernel`) sums, per body, the moments of its elements'
stiffness about the body's centre of mass (``sum k``, ``sum k r``, ``sum k r r^T``: ten numbers), of the
inertial regime's dampers and of the depth stiffness's vertical springs. From these and the body's mobility
``W6 = J M^-1 J^T`` this module gives the stiffest mode's rate (:func:`largest_rate`), the growth of a
perturbation in one semi-implicit Euler step (:func:`step_growth`) and the largest stable timestep
(:func:`max_stable_dt`, :func:`depth_stable_dt`). The derivations (the spring and damper of an element, the
depth stiffness, the inertial regime's dampers, why a held state and a single spike are told apart) are in
docs/numerics.md, "Stability limit".
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .errors import TerrainStabilityWarning
from .mujoco_c import call_mj_arrays

HELD_STEPS = 3  # consecutive steps beyond the stability limit that warn (docs/numerics.md, "Stability limit")
SPIKE_GROWTH = 2.0  # growth of a perturbation in a single step that warns even for a shorter spike
# Chatter (docs/numerics.md, "Chatter"): a body whose granular force reverses its change on CHATTER_STEPS consecutive
# steps, each change larger than CHATTER_AMPLITUDE of the force, oscillates with the step's period 2, not the physics'
CHATTER_STEPS = 50
CHATTER_AMPLITUDE = 0.05
# ... or, at timesteps above CHATTER_SPAN / CHATTER_STEPS, for CHATTER_SPAN of simulated time (at least
# CHATTER_MIN_STEPS steps): at a 20 ms step, 50 steps would be a second of alternating forces before a warning
CHATTER_SPAN = 0.2
CHATTER_MIN_STEPS = 10
CHATTER_SLOT = HELD_STEPS + 1  # the slot of ``stiff_max`` (nbody, TRACK_SLOTS, 10) that track_chatter keeps
TRACK_SLOTS = HELD_STEPS + 2


@njit(cache=True, error_model="numpy", _nrt=False)
def track_stiffness(stiff, stiff_max, damp, damp_max, inert, inert_max):
    """After a step, per body, from this step's stiffness moments ``stiff`` (nbody, 10): ``stiff_max``
    (nbody, HELD_STEPS + 1, 10) keeps in ``[:, 0]`` the stiffest state held for HELD_STEPS consecutive
    steps (the least stiff of the last HELD_STEPS steps), in ``[:, 1]`` the stiffest single step (both
    since the coupler last cleared them) and in ``[:, 2:]`` the previous steps; ``damp_max`` the largest
    summed damping; ``inert_max`` (nbody, 10) the inertial damping moments ``inert`` of the step with the
    largest summed inertial damping (only when some body has any). ``stiff_max[:, CHATTER_SLOT]`` is
    :func:`track_chatter`'s."""
    n = HELD_STEPS + 1
    for b in range(stiff.shape[0]):
        if inert[b, 0] > inert_max[b, 0]:
            for j in range(10):
                inert_max[b, j] = inert[b, j]
        if stiff[b, 0] > stiff_max[b, 1, 0]:
            for j in range(10):
                stiff_max[b, 1, j] = stiff[b, j]
        low = stiff[b, 0]
        src = -1
        for h in range(2, n):
            if stiff_max[b, h, 0] < low:
                low = stiff_max[b, h, 0]
                src = h
        if low > stiff_max[b, 0, 0]:
            for j in range(10):
                stiff_max[b, 0, j] = stiff[b, j] if src < 0 else stiff_max[b, src, j]
        for h in range(n - 1, 2, -1):
            for j in range(10):
                stiff_max[b, h, j] = stiff_max[b, h - 1, j]
        if n > 2:
            for j in range(10):
                stiff_max[b, 2, j] = stiff[b, j]
        damp_max[b] = max(damp_max[b], damp[b])


@njit(cache=True, error_model="numpy", _nrt=False)
def track_chatter(wrench, bodies, stiff_max):
    """After a step, per body ``b`` of ``bodies``, from its granular force ``wrench[b, :3]`` (as applied): count
    the consecutive steps on which the force's change reversed (``dF_k . dF_k-1 < -|dF_k| |dF_k-1| / 2``) with
    ``|dF_k| > CHATTER_AMPLITUDE`` of the force. ``stiff_max[b, CHATTER_SLOT]`` holds the last force (0:3) and
    change (3:6), the current run (6), the longest run since the coupler last cleared it (7), the largest
    relative change in such a run (8) and the force's size then (9)."""
    for i in range(bodies.shape[0]):
        b = bodies[i]
        c = stiff_max[b, CHATTER_SLOT]
        fx, fy, fz = wrench[b, 0], wrench[b, 1], wrench[b, 2]
        dx, dy, dz = fx - c[0], fy - c[1], fz - c[2]
        d2 = dx * dx + dy * dy + dz * dz
        p2 = c[3] * c[3] + c[4] * c[4] + c[5] * c[5]
        f2 = max(fx * fx + fy * fy + fz * fz, c[0] * c[0] + c[1] * c[1] + c[2] * c[2])
        big = d2 > CHATTER_AMPLITUDE * CHATTER_AMPLITUDE * f2 and f2 > 0.0
        turned = dx * c[3] + dy * c[4] + dz * c[5] < -0.5 * math.sqrt(d2 * p2)
        if big and turned:
            c[6] += 1.0
            if c[6] >= c[7]:
                c[7] = c[6]
                c[8] = max(c[8], math.sqrt(d2 / f2))
                c[9] = math.sqrt(f2)
        else:
            c[6] = 0.0
        c[0], c[1], c[2] = fx, fy, fz
        c[3], c[4], c[5] = dx, dy, dz


def chatter_steps(dt: float) -> int:
    """How many consecutive reversals make a body chatter at timestep ``dt``: ``CHATTER_STEPS``, or the steps of
    ``CHATTER_SPAN`` of simulated time when that is fewer (at least ``CHATTER_MIN_STEPS``)."""
    span = math.ceil(CHATTER_SPAN / dt - 1e-9) if dt > 0 else CHATTER_STEPS
    return max(CHATTER_MIN_STEPS, min(CHATTER_STEPS, span))


def chattering(stiff_max, bodies, steps: int = CHATTER_STEPS) -> list[tuple[int, int, float, float]]:
    """(body, steps, relative change, force in N) of each of ``bodies`` that :func:`track_chatter` saw reverse
    its force's change on at least ``steps`` consecutive steps since the last call (:func:`chatter_steps`); clears
    those records."""
    out = []
    for b in bodies:
        c = stiff_max[b, CHATTER_SLOT]
        if c[7] >= steps:
            out.append((int(b), int(c[7]), float(c[8]), float(c[9])))
        c[7:] = 0.0
    return out


def chatter_warning(body: str, time: float, dt: float, steps: int, change: float, force: float,
                    implicit: bool, springs_limit: float = math.inf, depth_limit: float = math.inf
                    ) -> TerrainStabilityWarning:
    """The :class:`TerrainStabilityWarning` for ``body`` (its name) whose granular force alternated for ``steps``
    steps by ``change`` (relative) of ``force`` (N) at timestep ``dt``: what it is and the cure that holds at this
    step, from the body's explicit limits now (s) of its springs and of its depth stiffness."""
    if dt > depth_limit:
        cure = (f"use a timestep below {depth_limit:.3g} s (GranularWrapper: substeps), the limit of its depth "
                "stiffness, which is explicit in every mode (the implicit step does not remove it)")
    elif not implicit and dt > springs_limit:
        cure = ("use the implicit granular step (GranularTerrain(..., implicit=True)), which removes the springs' "
                f"limit, or a timestep below {springs_limit:.3g} s (terrain.stable_timestep(data, 'springs'))")
    elif implicit:
        cure = ("halve the timestep (GranularWrapper: substeps) until it stops: the elements that slide or enter "
                "the grains stay explicit in the implicit step")
    else:
        cure = ("use the implicit granular step (GranularTerrain(..., implicit=True)) or halve the timestep until it "
                "stops")
    return TerrainStabilityWarning(
        f"mjrft: body '{body}' chatters at timestep {dt:g} s: its granular force ({force:.3g} N) reversed its change "
        f"on {steps} consecutive steps, by up to {100 * change:.3g} % of it, before t = {time:.4g} s; this "
        f"period-2 oscillation is the {'implicit' if implicit else 'explicit'} step's, not the physics' "
        f"(docs/numerics.md, \"Chatter\"); {cure}")


@njit(cache=True, error_model="numpy", _nrt=False)
def track_depth_springs(dstiff, dstiff_max):
    """Per body, keep in ``dstiff_max`` (nbody, 10) the depth-stiffness moments ``dstiff`` of the step with the
    largest summed depth stiffness (since the coupler last cleared it)."""
    for b in range(dstiff.shape[0]):
        if dstiff[b, 0] > dstiff_max[b, 0]:
            for j in range(10):
                dstiff_max[b, j] = dstiff[b, j]


def stable_step(K: float, c: float, w: float, dt: float) -> bool:
    """True if a spring K (N/m) with damper c (N s/m) on inverse mass w (1/kg) is stable at dt."""
    if K <= 0.0:
        return c * w * dt < 2.0
    omega = math.sqrt(K * w)
    zeta = 0.5 * c * w / omega
    return omega * dt < 2.0 * (math.sqrt(1.0 + zeta * zeta) - zeta)


@njit(cache=True, error_model="numpy")
def _largest_symmetric_eigenvalue(a):
    """Largest eigenvalue of the symmetric matrix ``a`` (cyclic Jacobi; ``a`` is overwritten)."""
    n = a.shape[0]
    for _ in range(60):
        off = 0.0
        scale = 0.0
        for p in range(n):
            scale += a[p, p] * a[p, p]
            for q in range(p + 1, n):
                off += a[p, q] * a[p, q]
        if off <= 1e-28 * scale or off == 0.0:
            break
        for p in range(n - 1):
            for q in range(p + 1, n):
                apq = a[p, q]
                if apq == 0.0:
                    continue
                theta = (a[q, q] - a[p, p]) / (2.0 * apq)
                if abs(theta) > 1e150:
                    t = 0.5 / theta
                else:
                    t = (1.0 if theta >= 0.0 else -1.0) / (abs(theta) + math.sqrt(theta * theta + 1.0))
                c = 1.0 / math.sqrt(t * t + 1.0)
                s = t * c
                for k in range(n):
                    akp, akq = a[k, p], a[k, q]
                    a[k, p] = c * akp - s * akq
                    a[k, q] = s * akp + c * akq
                for k in range(n):
                    apk, aqk = a[p, k], a[q, k]
                    a[p, k] = c * apk - s * aqk
                    a[q, k] = s * apk + c * aqk
    top = a[0, 0]
    for p in range(1, n):
        top = max(top, a[p, p])
    return top


@njit(cache=True, error_model="numpy", inline="always")
def add_k6(out, moments, scale):
    """``out += scale K6``: the 6x6 stiffness (translation rows/columns 0-2, rotation 3-5, about the CoM) of
    springs acting in every direction with the kernel's ``moments`` (``sum k``, ``sum k r``, ``sum k r r^T``)::

        K6 = [[ s0 I,    -[S1]x           ],
              [ [S1]x,   tr(S2) I - S2    ]]
    """
    s0 = scale * moments[0]
    x, y, z = scale * moments[1], scale * moments[2], scale * moments[3]
    sxx, sxy, sxz = scale * moments[4], scale * moments[5], scale * moments[6]
    syy, syz, szz = scale * moments[7], scale * moments[8], scale * moments[9]
    tr = sxx + syy + szz
    for i in range(3):
        out[i, i] += s0
    # off-diagonal blocks: -[S1]x (upper right) and [S1]x (lower left)
    out[0, 4] += z
    out[0, 5] -= y
    out[1, 3] -= z
    out[1, 5] += x
    out[2, 3] += y
    out[2, 4] -= x
    out[4, 0] += z
    out[5, 0] -= y
    out[3, 1] -= z
    out[5, 1] += x
    out[3, 2] += y
    out[4, 2] -= x
    out[3, 3] += tr - sxx
    out[4, 4] += tr - syy
    out[5, 5] += tr - szz
    out[3, 4] -= sxy
    out[4, 3] -= sxy
    out[3, 5] -= sxz
    out[5, 3] -= sxz
    out[4, 5] -= syz
    out[5, 4] -= syz


@njit(cache=True, error_model="numpy", inline="always")
def add_vertical_k6(out, moments):
    """``out += K6`` of vertical springs with the kernel's ``moments`` (the same ten sums as :func:`add_k6`; those
    with z do not enter): ``phi = (e_z, r x e_z)``, ``r x e_z = (r_y, -r_x, 0)``, ``K6 = sum k phi phi^T``."""
    s0, x, y = moments[0], moments[1], moments[2]
    sxx, sxy, syy = moments[4], moments[5], moments[7]
    out[2, 2] += s0
    out[2, 3] += y
    out[3, 2] += y
    out[2, 4] -= x
    out[4, 2] -= x
    out[3, 3] += syy
    out[3, 4] -= sxy
    out[4, 3] -= sxy
    out[4, 4] += sxx


@njit(cache=True, error_model="numpy")
def largest_rate(jac, minv_jac, moments, vertical=False):
    """Largest eigenvalue of ``W6 K6`` (docs/numerics.md, "Stability limit"): ``W6 = jac minv_jac^T`` (``jac``
    the 6 x nv jacobian of a body's CoM translation and rotation, ``minv_jac = M^-1 jac^T`` transposed) and ``K6``
    the stiffness of springs in every direction with the kernel's ``moments`` about the CoM (``vertical``:
    of vertical springs, :func:`add_vertical_k6`)."""
    nv = jac.shape[1]
    w = np.empty((6, 6))
    for i in range(6):
        for j in range(i, 6):
            acc = 0.0
            for k in range(nv):
                acc += jac[i, k] * minv_jac[j, k] + jac[j, k] * minv_jac[i, k]
            w[i, j] = 0.5 * acc
            w[j, i] = 0.5 * acc
    k6 = np.zeros((6, 6))
    if vertical:
        add_vertical_k6(k6, moments)
    else:
        add_k6(k6, moments, 1.0)
    # W6 = L L^T (a tiny ridge: a hinged body's W6 is singular), then the symmetric L^T K6 L
    ridge = 1e-12 * (w[0, 0] + w[1, 1] + w[2, 2] + w[3, 3] + w[4, 4] + w[5, 5]) + 1e-300
    low = np.zeros((6, 6))
    for j in range(6):
        d = w[j, j] + ridge
        for k in range(j):
            d -= low[j, k] * low[j, k]
        d = math.sqrt(d) if d > 0.0 else 0.0
        low[j, j] = d
        for i in range(j + 1, 6):
            acc = w[i, j]
            for k in range(j):
                acc -= low[i, k] * low[j, k]
            low[i, j] = acc / d if d > 0.0 else 0.0
    sym = np.zeros((6, 6))  # L^T K6 L in loops: numba's @ needs scipy's BLAS
    for i in range(6):
        for j in range(i, 6):
            acc = 0.0
            for k in range(i, 6):
                row = 0.0
                for q in range(j, 6):
                    row += k6[k, q] * low[q, j]
                acc += low[k, i] * row
            sym[i, j] = acc
            sym[j, i] = acc
    return max(0.0, _largest_symmetric_eigenvalue(sym))


def step_growth(K: float, c: float, w: float, dt: float) -> float:
    """Factor by which one semi-implicit Euler step multiplies a perturbation of a spring K (N/m) with
    damper c (N s/m) on inverse mass w (1/kg): the spectral radius of the step (> 1: unstable)."""
    a2, b = K * w * dt * dt, c * w * dt
    # x' = x + dt v', v' = v - dt w (K x + c v): lambda^2 - p lambda + q = 0
    p, q = 2.0 - a2 - b, 1.0 - b
    disc = p * p - 4.0 * q
    if disc >= 0.0:
        r = math.sqrt(disc)
        return 0.5 * max(abs(p + r), abs(p - r))
    return math.sqrt(q)  # a complex pair: |lambda|^2 = q


@njit(cache=True, error_model="numpy")
def depth_stable_dt(lam: float) -> float:
    """Largest timestep (s) of the depth stiffness with ``omega^2 = lam`` (docs/numerics.md, "Depth stiffness"):
    ``sqrt(2) / omega`` (inf without stiffness)."""
    return math.sqrt(2.0 / lam) if lam > 0.0 else np.inf


def max_stable_dt(K: float, c: float, w: float) -> float:
    """Largest stable timestep for :func:`stable_step` (inf when there is no stiffness or damping)."""
    if K <= 0.0:
        return 2.0 / (c * w) if c > 0 else np.inf
    omega = math.sqrt(K * w)
    zeta = 0.5 * c * w / omega
    return 2.0 * (math.sqrt(1.0 + zeta * zeta) - zeta) / omega


_max_stable_dt = njit(cache=True, error_model="numpy")(max_stable_dt)  # the same formula, callable compiled


@njit(cache=True, error_model="numpy")
def _stable_dts(jac, minv_jac, rows, stiff, inert, use_inert, delta, tau, vertical, out):
    """``out[b]`` for each body ``b = rows[i]``: the largest stable timestep of its granular stiffness
    (``stiff[b]``) and, with ``use_inert``, its inertial dampers (``inert[b]``), from its 6 x nv jacobian rows
    ``jac[6 i:6 i + 6]`` and ``minv_jac`` (= ``(M^-1 jac^T)^T``): what :meth:`GranularTerrain.stable_timestep`
    computes body by body (largest_rate, :func:`spring`, max_stable_dt), in one call; ``out[b]``
    keeps a smaller value it already holds. With ``vertical``, ``stiff`` holds the moments of the depth stiffness's
    vertical springs (depth_stable_dt)."""
    for i in range(rows.shape[0]):
        b = rows[i]
        jac_b, minv_b = jac[6 * i:6 * i + 6], minv_jac[6 * i:6 * i + 6]
        if vertical:
            if stiff[b, 0] > 0:
                out[b] = min(out[b], depth_stable_dt(largest_rate(jac_b, minv_b, stiff[b], True)))
            continue
        lam_c = largest_rate(jac_b, minv_b, inert[b]) if use_inert and inert[b, 0] > 0 else 0.0
        if stiff[b, 0] > 0 or lam_c > 0:
            lam = largest_rate(jac_b, minv_b, stiff[b]) if stiff[b, 0] > 0 else 0.0
            if delta == 0:
                out[b] = min(out[b], _max_stable_dt(0.0, lam + lam_c, 1.0))
            else:
                out[b] = min(out[b], _max_stable_dt(lam, tau * lam + lam_c, 1.0))


@njit(cache=True, error_model="numpy")
def _buried_jacobians(f_jac, f_solve, m_addr, d_addr, bodies, stiff, dstiff, inert, use_inert, jac, minv_jac, rows):
    """Stack the CoM jacobian (``mj_jacBodyCom``) of each body of ``bodies`` with moments in ``stiff`` or ``dstiff``
    (with ``use_inert``, or inertial dampers in ``inert``) in ``jac``, its id in ``rows``, and solve all rows with
    ``M^-1`` in one ``mj_solveM`` into ``minv_jac``; returns how many bodies (their rows ``jac[:6 n]``)."""
    nv = jac.shape[1]
    n = 0
    for i in range(bodies.shape[0]):
        b = bodies[i]
        if stiff[b, 0] > 0 or dstiff[b, 0] > 0 or (use_inert and inert[b, 0] > 0):
            at = jac.ctypes.data + 6 * n * nv * 8
            call_mj_arrays(f_jac, m_addr, d_addr, at, at + 3 * nv * 8, b)
            rows[n] = b
            n += 1
    if n > 0:
        call_mj_arrays(f_solve, m_addr, d_addr, minv_jac.ctypes.data, jac.ctypes.data, 6 * n)
    return n


@njit(cache=True, error_model="numpy")
def _stable_timesteps(f_jac, f_solve, m_addr, d_addr, bodies, stiff, inert, use_inert, delta, tau, vertical, jac,
                      minv_jac, rows, out):
    """:meth:`GranularTerrain.stable_timestep` in one compiled call: each buried body's CoM jacobian
    (``mj_jacBodyCom``) stacked in ``jac``, one ``mj_solveM`` of all rows (:func:`_buried_jacobians`), then
    :func:`_stable_dts`."""
    n = _buried_jacobians(f_jac, f_solve, m_addr, d_addr, bodies, stiff, stiff, inert, use_inert, jac, minv_jac, rows)
    if n == 0:
        return
    _stable_dts(jac, minv_jac, rows[:n], stiff, inert, use_inert, delta, tau, vertical, out)


@njit(cache=True, error_model="numpy")
def _smallest_of(out, rows):
    """The smallest ``out[b]`` over the bodies ``b`` in ``rows`` (inf if none)."""
    least = np.inf
    for i in range(rows.shape[0]):
        least = min(least, out[rows[i]])
    return least


@njit(cache=True, error_model="numpy")
def _stable_timestep_pair(f_jac, f_solve, m_addr, d_addr, bodies, stiff, dstiff, inert, use_inert, delta, tau, jac,
                          minv_jac, rows, out):
    """The smallest stable timestep over ``bodies`` of the springs (``stiff``, with ``use_inert`` the inertial
    dampers ``inert``) and of the depth stiffness (``dstiff``), as (springs, depth): :func:`_stable_timesteps`
    of both parts from one set of jacobians (each body's rows are the same in both, so the limits are equal to
    two separate calls'). ``out`` (nbody) is scratch."""
    n = _buried_jacobians(f_jac, f_solve, m_addr, d_addr, bodies, stiff, dstiff, inert, use_inert, jac, minv_jac,
                          rows)
    if n == 0:
        return np.inf, np.inf
    out[:] = np.inf
    _stable_dts(jac, minv_jac, rows[:n], stiff, inert, use_inert, delta, tau, False, out)
    springs = _smallest_of(out, rows[:n])
    out[:] = np.inf
    _stable_dts(jac, minv_jac, rows[:n], dstiff, inert, False, delta, tau, True, out)
    return springs, _smallest_of(out, rows[:n])


def spring(lam: float, lam_c: float, yield_displacement: float, damping_time: float) -> tuple[float, float]:
    """(K, c) per unit mass of the stiffest mode, for :func:`stable_step` / :func:`max_stable_dt` with w = 1:
    ``lam`` the largest rate of the granular stiffness (the damping's in the viscous mode, ``yield_displacement``
    = 0), ``lam_c`` the inertial regime's largest damping rate (1/s), added to the damping (docs/numerics.md,
    "Stability limit")."""
    return (0.0, lam + lam_c) if yield_displacement == 0 else (lam, damping_time * lam + lam_c)


def unstable_mode(jac, minv_jac, held, spike, inert, yield_displacement: float, damping_time: float,
                  dt: float) -> tuple[float, float, float] | None:
    """(stiffness moment 0, lam, lam_c) of the first unstable state of one body at timestep ``dt``, or None.

    The states are the stiffness moments ``held`` for ``HELD_STEPS`` steps (unstable when a step amplifies
    at all) and, when it has any, the single step's ``spike`` (unstable past ``SPIKE_GROWTH``); ``inert``
    the inertial dampers' moments (None: none), whose rate is added to both. ``jac``, ``minv_jac``: the body's
    CoM jacobian and ``(M^-1 J^T)^T``.
    """
    lam_c = largest_rate(jac, minv_jac, inert) if inert is not None else 0.0
    states = [(held, 1.0), (spike, SPIKE_GROWTH)] if spike[0] > 0 else [(held, 1.0)]
    for moments, growth in states:
        if moments[0] <= 0 and lam_c <= 0:
            continue
        lam = largest_rate(jac, minv_jac, moments) if moments[0] > 0 else 0.0
        K, c = spring(lam, lam_c, yield_displacement, damping_time)
        if step_growth(K, c, 1.0, dt) > growth * (1.0 + 1e-12):
            return moments[0], lam, lam_c
    return None


def stability_warning(body: str, time: float, dt: float, s0: float, damp: float, lam: float, lam_c: float,
                      yield_displacement: float, damping_time: float,
                      depth_limit: float = math.inf) -> TerrainStabilityWarning:
    """The :class:`TerrainStabilityWarning` for ``body`` (its name) whose :func:`unstable_mode` is
    (``s0``, ``lam``, ``lam_c``) at timestep ``dt``; ``damp`` its damping (N s/m); ``depth_limit`` the explicit limit
    of its depth stiffness (s), which the implicit step does not remove: beyond it the advice is the timestep."""
    K, c = spring(lam, lam_c, yield_displacement, damping_time)
    what = (f"damping {s0:.3g} N s/m" if yield_displacement == 0 else
            f"stiffness {s0:.3g} N/m, damping {damp:.3g} N s/m")
    mode = f"effective mass {s0 / lam:.3g} kg in its stiffest mode" if lam > 0 else "no stiffness"
    if lam_c > 0:
        mode += f"; inertial-regime damping rate {lam_c:.3g} 1/s"
    if dt > depth_limit:
        cure = (f"reduce the timestep below {depth_limit:.3g} s: the body's depth stiffness (explicit in every mode) "
                f"limits it there too, so the implicit step (implicit=True) alone would not make this step stable")
    else:
        cure = ("reduce the timestep, increase yield_displacement, or step the grains' springs implicitly "
                "(GranularTerrain(..., implicit=True), which removes this limit"
                + (f"; the body's depth stiffness, explicit in every mode, allows up to {depth_limit:.3g} s)"
                   if math.isfinite(depth_limit) else ")"))
    return TerrainStabilityWarning(
        f"mjrft: timestep {dt:g} s exceeds the stability limit {max_stable_dt(K, c, 1.0):.3g} s of the "
        f"granular stiffness on body '{body}' at t = {time:.4g} s ({what}, {mode}); {cure}"
        + (" (the inertial regime's explicit limit is dt < 2 / its rate)" if lam_c > 0 else ""))

"""The compiled per-step kernel of the coupler: kinematics -> rest regularisation -> law -> wrench.

Pure array code (numba); :mod:`mjrft.coupler` hands it a terrain's records (:mod:`mjrft.types`) and views of
``mjData``, and owns all MuJoCo calls made from Python. :func:`terrain_kernel` evaluates every surface element that
can reach the grains and sums each body's wrench and the moments the stability check (:mod:`mjrft.stability`) and
the implicit step (:mod:`mjrft.implicit_step`) need; :mod:`mjrft.stepping` runs it between ``mj_step1`` and
``mj_step2`` in one compiled loop; :mod:`mjrft.surface` is the surface and the regions as it sees them.

The numerics (the rest regularisation of each element, its linearised spring and damper, the depth stiffness,
the inertial regime's dampers, the implicit step) are derived in docs/numerics.md.
"""

from __future__ import annotations

import math

from numba import njit

from .implicit_step import HOLD_FRACTION
from .forces import blended_force, element_force, isfinite3, linear_stiffness, stiffness_of
from .laws.common import memory_motion, relax_memory
from .laws.dispatch import element_stress
from .laws.inertial import inertial_force
from .laws.registry import LAW_IDS
from .ground import ground_sample, ground_step, ground_top, in_wake
from .laws.rft import rft_stress_batch, rft_stress_batch_packed, trails
from .laws.solidify import solid_memory
from .params import P_INERTIA, P_WATER_DEPTH
from .surface import heaviest_region, map_cell, region_weights, strip_of, surface_height

OK = 0
BAD_FORCE = 1
BAD_STATE = 2
LAW_RFT = LAW_IDS["rft"]  # Li RFT: the law whose elements are gathered for one vectorised call
LAW_HYBRID = LAW_IDS["hybrid"]  # with a ground memory: its undisturbed-grain rule (mjrft.ground.in_wake)


@njit(cache=True, error_model="numpy", inline="always")
def _clear(u, out_force, i):
    """Element ``i`` has no force and no memory."""
    for j in range(3):
        u[i, j] = 0.0
        out_force[i, j] = 0.0


@njit(cache=True, error_model="numpy", inline="always")
def _normal_velocity(i, e_lnrm, out_pos, out_vel, out_nrm, rot, com, spin, lin):
    """Element ``i``'s world normal (body rotation ``rot``, row-major) and velocity (from the body's
    ``cvel``: angular ``spin``, linear ``lin`` at the subtree centre of mass ``com``), written to
    ``out_nrm`` / ``out_vel`` and returned as (nx, ny, nz, vx, vy, vz)."""
    ax, ay, az = e_lnrm[i, 0], e_lnrm[i, 1], e_lnrm[i, 2]
    nx = rot[0] * ax + rot[1] * ay + rot[2] * az
    ny = rot[3] * ax + rot[4] * ay + rot[5] * az
    nz = rot[6] * ax + rot[7] * ay + rot[8] * az
    dx, dy, dz = out_pos[i, 0] - com[0], out_pos[i, 1] - com[1], out_pos[i, 2] - com[2]
    vx = lin[0] + spin[1] * dz - spin[2] * dy
    vy = lin[1] + spin[2] * dx - spin[0] * dz
    vz = lin[2] + spin[0] * dy - spin[1] * dx
    out_vel[i, 0], out_vel[i, 1], out_vel[i, 2] = vx, vy, vz
    out_nrm[i, 0], out_nrm[i, 1], out_nrm[i, 2] = nx, ny, nz
    return nx, ny, nz, vx, vy, vz


@njit(cache=True, error_model="numpy", inline="always")
def _gather(scr_f, scr_i, nbat, out_force, i, b, nx, ny, nz, mx, my, mz, ml, mob, depth, all_faces, t_mem):
    """Put element ``i`` (body ``b``) into the batch for the vectorised law at slot ``nbat`` (normal, unit
    motion, depth, mobilisation, |m|, and in row 12 the implicit step's memory time ``t_mem``,
    :func:`_memory_time`); returns the new batch size. An element without motion (``|m| = 0``)
    has no force and is not gathered, nor, unless ``all_faces``, a trailing face
    (:func:`~mjrft.laws.rft.trails`: the law gives it no force and no stiffness): its force is zeroed, and every
    sum the batch feeds misses only its zeros."""
    if ml > 0.0:
        iml = 1.0 / ml
        ux, uy, uz = mx * iml, my * iml, mz * iml
        if all_faces or not trails(nx, ny, nz, ux, uy, uz):
            scr_f[0, nbat] = nx
            scr_f[1, nbat] = ny
            scr_f[2, nbat] = nz
            scr_f[3, nbat] = ux
            scr_f[4, nbat] = uy
            scr_f[5, nbat] = uz
            scr_f[6, nbat] = depth
            scr_f[7, nbat] = mob
            scr_f[8, nbat] = ml
            scr_f[12, nbat] = t_mem
            scr_i[0, nbat] = i
            scr_i[1, nbat] = b
            return nbat + 1
    out_force[i, 0] = 0.0
    out_force[i, 1] = 0.0
    out_force[i, 2] = 0.0
    return nbat


@njit(cache=True, error_model="numpy", inline="always")
def _rest_memory(u, i, vx, vy, vz, speed, relax, dt_d, inv_d, delta, tau, v_eps, solid, stick):
    """Advance element ``i``'s rest memory ``u[i]`` by ``dt`` (``dt_d`` = dt / delta, ``inv_d`` = 1 / delta,
    hoisted out of the element loop) at velocity ``v`` and return the regularised motion (mx, my, mz, |m|,
    mobilisation) that the law sees (docs/numerics.md, "Rest regularisation"): with ``delta > 0``
    ``u <- delta v_hat + (u - delta v_hat) exp(-|v| dt / delta)``, ``m = u + tau v``, mobilisation
    ``min(1, |m| / delta)``; in the viscous mode ``m = v``, ``min(1, |v| / v_eps)``. ``solid > 0``: the
    solidify option's memory instead (:func:`mjrft.laws.solidify.solid_memory`, static yield factor ``solid``,
    at rest below the speed ``stick``). ``relax``: the factor ``exp(-|v| dt / delta)``, computed by the caller
    (read only with ``delta > 0``, ``solid <= 0`` and ``|v| > 0``: see :func:`_dry_pass` on why)."""
    if delta > 0.0:
        if solid > 0.0:
            return solid_memory(u, i, vx, vy, vz, speed, dt_d * delta, delta, tau, solid, stick)
        if speed > 0.0:
            relax_memory(u, i, vx, vy, vz, speed, relax, delta)
        mx, my, mz, ml = memory_motion(u, i, vx, vy, vz, tau)
        return mx, my, mz, ml, min(1.0, ml * inv_d)
    return vx, vy, vz, speed, (min(1.0, speed / v_eps) if v_eps > 0.0 else 1.0)


@njit(cache=True, error_model="numpy", inline="always")
def _add_moments(arr, b, rx, ry, rz, kk, at=0):
    """Add the moments of a spring or damper ``kk`` at ``r`` from body ``b``'s CoM to ``arr[b, at:at + 10]``
    (10 sums)."""
    arr[b, at] += kk
    arr[b, at + 1] += kk * rx
    arr[b, at + 2] += kk * ry
    arr[b, at + 3] += kk * rz
    arr[b, at + 4] += kk * rx * rx
    arr[b, at + 5] += kk * rx * ry
    arr[b, at + 6] += kk * rx * rz
    arr[b, at + 7] += kk * ry * ry
    arr[b, at + 8] += kk * ry * rz
    arr[b, at + 9] += kk * rz * rz


@njit(cache=True, error_model="numpy", inline="always")
def _memory_time(speed, relax, dt, dt_d, delta, tau):
    """How much a velocity change ``dv`` over the step moves an element's regularised motion ``m = u + tau v``,
    ``dm = T dv`` (s): ``tau`` plus the memory's response ``delta (1 - exp(-|v| dt / delta)) / |v|`` (``dt`` at
    rest, ``delta / |v|`` in fast sliding; :func:`_rest_memory`); 1 in the viscous mode (``m = v``). ``relax``:
    the rest memory's factor ``exp(-|v| dt / delta)`` of the element (``dt_d`` = dt / delta), which the kernel
    has computed already (read only with ``delta > 0``)."""
    if delta <= 0.0:
        return 1.0
    if speed * dt_d < 1e-6:
        return tau + dt
    return tau + delta * (1.0 - relax) / speed


@njit(cache=True, error_model="numpy", inline="always")
def _holds(ml, limit, ux, uy, uz, delta):
    """Whether an element's spring enters the implicit step (docs/numerics.md, "Implicit step"): below yield
    (``|m| <= limit``), or, with the rest memory, holding: its memory ``u`` within ``HOLD_FRACTION`` of ``delta``
    (it has not slid about ``2.3 delta`` since it last rested or turned), however far its damping term ``tau v``
    takes ``|m|`` past yield."""
    if ml <= limit:
        return True
    hold = HOLD_FRACTION * delta
    return delta > 0.0 and ux * ux + uy * uy + uz * uz <= hold * hold


@njit(cache=True, error_model="numpy", inline="always")
def _add_implicit(imp, b, rx, ry, rz, held, kk, t):
    """The implicit step's spring of one element (docs/numerics.md, "Implicit step"): an element that
    :func:`_holds` (``held``) adds the moments of ``t kk`` about body ``b``'s CoM to ``imp[b]`` (as
    :func:`_add_moments`); a sliding element adds nothing (its force only turns, and stays explicit)."""
    if held and kk > 0.0:
        _add_moments(imp, b, rx, ry, rz, t * kk)


@njit(cache=True, error_model="numpy", inline="always")
def _add_depth_spring(dstiff, b, rx, ry, rz, fx, fy, fz, depth):
    """An element's force grows with its depth (RFT's stresses are proportional to it): a vertical spring
    ``|F| / depth``, whose moments about body ``b``'s CoM go to ``dstiff[b]`` (as :func:`_add_moments`;
    docs/numerics.md, "Depth stiffness")."""
    if depth > 0.0:
        kd = math.sqrt(fx * fx + fy * fy + fz * fz) / depth
        if kd > 0.0:
            _add_moments(dstiff, b, rx, ry, rz, kd)


@njit(cache=True, error_model="numpy", inline="always")
def _add_to_body(wrench, stiff, b, fx, fy, fz, rx, ry, rz, kk):
    """Add an element's force (at ``r`` from body ``b``'s CoM) to its wrench, and the moments of its
    stiffness ``kk`` about the CoM (``sum k``, ``sum k r``, ``sum k r r^T``) to ``stiff``."""
    wrench[b, 0] += fx
    wrench[b, 1] += fy
    wrench[b, 2] += fz
    wrench[b, 3] += ry * fz - rz * fy
    wrench[b, 4] += rz * fx - rx * fz
    wrench[b, 5] += rx * fy - ry * fx
    if kk > 0.0:
        _add_moments(stiff, b, rx, ry, rz, kk)


@njit(cache=True, error_model="numpy", inline="always")
def _scene(reg_law, reg_params, reg_rho):
    """(deepest water layer of any region, whether some region has the inertial regime on, the batched
    region: the first dry Li-RFT region, or -1). Li RFT on a dry region is gathered for one vectorised law
    call (with several regions the first dry Li-RFT one: a scene's dry strip keeps the batched cost)."""
    wmax = 0.0
    inertia = False
    breg = -1
    for r in range(reg_law.shape[0]):
        hw = reg_params[r, P_WATER_DEPTH]
        wmax = max(wmax, hw)
        inertia = inertia or reg_params[r, P_INERTIA] > 0.0
        if breg < 0 and reg_law[r] == LAW_RFT and not (hw > 0.0 or reg_rho[r] > 0.0):
            breg = r
    return wmax, inertia, breg


@njit(cache=True, error_model="numpy", inline="always")
def _region_constants(reg, reg_law, reg_params, reg_rho):
    """(parameter vector, law id, water depth, dry) of region ``reg``; dry: no water layer and no buoyancy."""
    p = reg_params[reg]
    hw = p[P_WATER_DEPTH]
    return p, reg_law[reg], hw, not (hw > 0.0 or reg_rho[reg] > 0.0)


@njit(cache=True, error_model="numpy", inline="always")
def _zero_body_sums(wrench, stiff, damp, inert, inertia, imp, dstiff):
    """Zero every body's wrench, stiffness and depth-stiffness moments, damping, (with the inertial regime)
    inertial moments and (for the implicit step) its spring moments."""
    for b in range(imp.shape[0]):
        for j in range(10):
            imp[b, j] = 0.0
    for b in range(dstiff.shape[0]):
        for j in range(10):
            dstiff[b, j] = 0.0
    for b in range(wrench.shape[0]):
        for j in range(6):
            wrench[b, j] = 0.0
        for j in range(10):
            stiff[b, j] = 0.0
        damp[b] = 0.0
        if inertia:
            for j in range(10):
                inert[b, j] = 0.0


@njit(cache=True, error_model="numpy", inline="always")
def _lowest_corner(geom_xpos, G, g_aabb, g, gid):
    """World height of the lowest corner of cull group ``g``'s box (geom ``gid``, rotation ``G``)."""
    return (geom_xpos[gid, 2] + G[6] * g_aabb[g, 0] + G[7] * g_aabb[g, 1] + G[8] * g_aabb[g, 2]
            - abs(G[6]) * g_aabb[g, 3] - abs(G[7]) * g_aabb[g, 4] - abs(G[8]) * g_aabb[g, 5])


@njit(cache=True, error_model="numpy", inline="always")
def _group_ground_top(geom_xpos, G, g_aabb, g, gid, frame, blocks):
    """(the ground memory's highest surface (m, above the undisturbed one) under cull group ``g``'s box (geom ``gid``,
    rotation ``G``), the last update that changed the ground there: :func:`mjrft.ground.ground_top` of the box's
    horizontal extent; the box's centre x, y)."""
    cx = geom_xpos[gid, 0] + G[0] * g_aabb[g, 0] + G[1] * g_aabb[g, 1] + G[2] * g_aabb[g, 2]
    cy = geom_xpos[gid, 1] + G[3] * g_aabb[g, 0] + G[4] * g_aabb[g, 1] + G[5] * g_aabb[g, 2]
    ex = abs(G[0]) * g_aabb[g, 3] + abs(G[1]) * g_aabb[g, 4] + abs(G[2]) * g_aabb[g, 5]
    ey = abs(G[3]) * g_aabb[g, 3] + abs(G[4]) * g_aabb[g, 4] + abs(G[5]) * g_aabb[g, 5]
    top, newest = ground_top(cx, cy, ex, ey, frame, blocks)
    return top, newest, cx, cy


@njit(cache=True, error_model="numpy", inline="always")
def _inside_strip(geom_xpos, G, g_aabb, g, gid, reg_bounds, breg, blend):
    """Whether cull group ``g``'s box lies wholly inside strip ``breg``, farther than ``blend / 2`` from its edges."""
    gxc = geom_xpos[gid, 0] + G[0] * g_aabb[g, 0] + G[1] * g_aabb[g, 1] + G[2] * g_aabb[g, 2]
    gxh = abs(G[0]) * g_aabb[g, 3] + abs(G[1]) * g_aabb[g, 4] + abs(G[2]) * g_aabb[g, 5]
    xlo = gxc - gxh - 0.5 * blend
    xhi = gxc + gxh + 0.5 * blend
    greg = strip_of(xlo, reg_bounds)
    return greg == breg and (greg == reg_bounds.shape[0] or xhi < reg_bounds[greg])


@njit(cache=True, error_model="numpy", inline="always")
def _dry_pass(nbat, nlist, b, nreg, breg, e_lnrm, e_area, rot, com, spin, lin, dt_d, inv_d, delta, tau, v_eps,
              solid, stick, u, out_pos, out_vel, out_nrm, out_depth, out_force, out_region, scr_f, scr_i, all_faces,
              implicit, dt):
    """Pass 2 of a dry group (one dry Li-RFT region everywhere, or a group inside such a strip): the listed
    elements ``scr_i[0, nbat:nlist]`` through the rest memory into the law's batch, without the region and
    water branches of the general pass (about 9% of the kernel's time; tested equal to it). ``rot``, ``com``,
    ``spin``, ``lin``: body ``b``'s rotation and velocity (see :func:`_normal_velocity`). With ``implicit``, each
    gathered element carries its memory time (:func:`_memory_time`, from the same relaxation factor as its
    memory). Returns (status, new batch size).

    In three loops: the velocities (their speeds kept in ``scr_f[10]``), the rest memory's relaxation factors
    ``exp(-|v| dt / delta)`` (in ``scr_f[9]``, where :func:`_rest_memory` and :func:`_memory_time` read them),
    then the memory and the gathering. A call to ``exp`` inside the element loop makes the compiler save and
    restore the loop's registers around it on every element; in a loop of its own it costs the kernel less
    (``python benchmarks/kernel_ab.py REV`` against the one-loop form), with the same results bit for bit. (Rows 9
    and 10 from ``nbat`` on are free: the gathering writes only rows 0-8 and 12, at slots no later than the one it
    reads, and the law writes rows 9-11 after the element loop.)"""
    for q in range(nbat, nlist):
        i = scr_i[0, q]
        nx, ny, nz, vx, vy, vz = _normal_velocity(i, e_lnrm, out_pos, out_vel, out_nrm, rot, com, spin, lin)
        if not isfinite3(vx, vy, vz):
            return BAD_STATE, nbat
        scr_f[10, q] = math.sqrt(vx * vx + vy * vy + vz * vz)
    if delta > 0.0 and (solid <= 0.0 or implicit):  # the factors that _rest_memory and _memory_time read
        for q in range(nbat, nlist):
            scr_f[9, q] = math.exp(-scr_f[10, q] * dt_d)
    for q in range(nbat, nlist):
        i = scr_i[0, q]
        if nreg > 1:
            out_region[i] = breg
        if e_area[i] <= 0.0:
            _clear(u, out_force, i)
            continue
        speed, relax = scr_f[10, q], scr_f[9, q]
        mx, my, mz, ml, mob = _rest_memory(u, i, out_vel[i, 0], out_vel[i, 1], out_vel[i, 2], speed, relax, dt_d,
                                           inv_d, delta, tau, v_eps, solid, stick)
        t_mem = _memory_time(speed, relax, dt, dt_d, delta, tau) if implicit else 0.0
        nbat = _gather(scr_f, scr_i, nbat, out_force, i, b, out_nrm[i, 0], out_nrm[i, 1], out_nrm[i, 2], mx, my, mz,
                       ml, mob, out_depth[i], all_faces, t_mem)
    return OK, nbat


@njit(cache=True, error_model="numpy", inline="always")
def _packed_rows(rows, reg_params, dparams, t, reg):
    """The regions' parameter rows at an element's packing ``t`` (the change of its loose-to-close weight from the
    prepared state, :mod:`mjrft.ground`): ``rows[r] = reg_params[r] + t dparams[r]`` for region ``reg`` (``-1``:
    every region, for a blended element); returns ``rows``."""
    for r in range(reg_params.shape[0]):
        if reg < 0 or r == reg:
            for k in range(reg_params.shape[1]):
                rows[r, k] = reg_params[r, k] + t * dparams[r, k]
    return rows


@njit(cache=True, error_model="numpy", inline="always")
def _with_water_damping(kk, cw, delta, tau):
    """(stiffness, damping) of an element whose sand part has stiffness ``kk`` and whose water drag has damping
    ``cw``: with the rest memory (``delta > 0``) the drag adds to the damping only; in the viscous mode the
    sand's "stiffness" is itself a damping and the drag adds to it."""
    if delta > 0.0:
        return kk, kk * tau + cw
    kk += cw
    return kk, kk


# contract (FMA), arcp (multiply by reciprocals), nsz: a few % faster; no nnan/ninf, so the finiteness
# checks stay exact. Pass 1 and the general pass 2 stay written out in terrain_kernel: an inlined numba
# helper takes a reference (an atomic increment and decrement) on each array it is given per call, which the
# reference-count pruning does not remove around a loop; as helpers they cost 2-5 % of the kernel
# (benchmarks/kernel_ab.py). The helpers above are the ones measured free of that cost.
@njit(cache=True, error_model="numpy", fastmath={"contract", "arcp", "nsz"}, _nrt=False)
def terrain_kernel(tables, mjd, gravity, dt, st):
    """Evaluate every element of every geom that can reach below ``top``; returns (status, body).

    Elements come in cull groups (``g_*``: runs of up to ``elements.CULL_GROUP`` elements of one geom).
    A group is skipped (no element work at all; on the step it is first skipped its elements' force,
    memory and depth are zeroed) while the lowest corner of its box (``g_aabb``: centre and half sizes
    in the geom frame of ``g_geom``, around the group's element points) is at or above ``top`` (the
    highest sand or water surface anywhere), so a torso riding just above the sand and the upper half
    of a leg cost nothing. In a group that is not skipped, pass 1 updates every element's position and
    depth without branching and lists those within reach of grains or water (``depth > -max water
    depth``); pass 2 does the rest below for the listed ones only.

    Per element: ``depth`` = local sand surface height (:func:`surface_height`) - z, positive in the
    sand; the regions at its (x, y) (:func:`region_weights`; with one region no region work at all)
    each give, with the region's parameter vector ``reg_params[r]`` (its ``P_WATER_DEPTH`` slot is the
    region's water depth):

    * the sand law ``reg_law[r]`` (depth > 0; through the rest regularisation; law ``water`` (4) as a
      region's law means open water without a granular bottom, so no sand law),
    * the water drag ``water_stress`` (:mod:`mjrft.laws.wet`) inside the water layer and its skin, on
      the element's real velocity (a rate-dependent drag needs no rest memory); its linearised damping
      ``2 |F| / |v|`` is added to ``damp`` (in the viscous mode also to the moments),
    * hydrostatic pressure ``reg_rho[r] x gravity x (water surface - z)`` pushing along ``-n`` when
      ``reg_rho[r] > 0`` (buoyancy; the pressure is zero at the water surface, so it is continuous),

    and the element's stress is the weighted sum over its regions.

    Speed: in a dry region under Li RFT (the common case; with several regions the first such one) the
    buried elements lying wholly in that region are gathered into the scratch arrays ``scr_f`` (13, n)
    and ``scr_i`` (2, n) and the law runs once over all of them (:func:`mjrft.laws.rft.rft_stress_batch`,
    vectorised); the forces are then scattered back. Trailing faces (:func:`mjrft.laws.rft.trails`: no force, no
    stiffness) are not gathered, their force set to zero, unless that region's inertial regime is on.

    ``stiff`` (nbody, 10) receives per body the moments of the element stiffness ``k_i`` (of the
    damping ``c_i`` in the viscous mode) about its CoM: ``sum k``, ``sum k r`` (x, y, z) and
    ``sum k r r^T`` (xx, xy, xz, yy, yz, zz); ``damp`` (nbody,) the summed damping ``sum c_i``;
    ``inert`` (nbody, 10) the same moments of the inertial regime's dampers (:mod:`mjrft.laws.inertial`),
    written only when a region has the regime on.

    Inertial regime: when a region's ``p[P_INERTIA] > 0`` every buried element of it adds
    :func:`mjrft.laws.inertial.inertial_force` on its real velocity (no rest memory: a rate-dependent
    drag needs none). With the regime off in every region nothing of it runs (one flag per step).

    ``solid``, ``stick``: the solidify option (:mod:`mjrft.laws.solidify`; ``solid = 0`` off).

    Arguments: ``tables`` (model in: :attr:`mjrft.types.TerrainModel.tables`), ``mjd`` (data in:
    :class:`mjrft.types.MjViews` after ``mj_step1``), ``gravity`` (m/s^2, downward), ``dt`` (s, the step the memory
    advances by), ``st`` (state in and out: :class:`mjrft.types.TerrainState`).
    """
    return _kernel(tables, mjd, gravity, dt, st, False)


@njit(cache=True, error_model="numpy", fastmath={"contract", "arcp", "nsz"}, _nrt=False)
def terrain_kernel_ground(tables, mjd, gravity, dt, st):
    """:func:`terrain_kernel` of a terrain with a ground memory (:mod:`mjrft.ground`; ``tables.ground.on``): the
    elements read their depth and packing from it, and it is updated once per its period. A separate compiled
    function, so that the kernel of a terrain without one compiles to the code it had before the memory existed."""
    return _kernel(tables, mjd, gravity, dt, st, True)


@njit(cache=True, error_model="numpy", fastmath={"contract", "arcp", "nsz"}, _nrt=False, inline="always")
def _kernel(tables, mjd, gravity, dt, st, gr_on):
    """The body of :func:`terrain_kernel` (``gr_on`` False) and :func:`terrain_kernel_ground` (True): inlined into
    each with ``gr_on`` a constant, every ground branch is removed from the first."""
    # Model
    el, sf, rg, cs, gr = tables
    g_geom, g_body, g_start, g_aabb = el.group_geom, el.group_body, el.group_start, el.group_aabb
    e_lpos, e_lnrm, e_area, rootid = el.lpos, el.lnrm, el.area, el.body_root
    surface, top, hf_z, hf_frame = sf.height, sf.top, sf.hfield_z, sf.hfield_frame
    reg_bounds, reg_law, reg_params, reg_rho = rg.bounds, rg.law, rg.params, rg.rho
    reg_map, reg_map_frame, blend = rg.map, rg.map_frame, rg.transition
    delta, tau, v_eps, solid, stick = cs.delta, cs.tau, cs.v_eps, cs.solid, cs.stick
    # Data in
    geom_xpos, geom_xmat, xpos, xmat, xipos, cvel, subtree_com = mjd
    # State in and out
    u, g_active = st.u, st.group_active
    out_pos, out_vel, out_nrm, out_depth = st.pos, st.vel, st.normal, st.depth
    out_force, out_region = st.force, st.region
    wrench, stiff, damp, inert, dstiff, imp = st.wrench, st.stiff, st.damp, st.inert, st.dstiff, st.imp
    scr_f, scr_i = st.scr_f, st.scr_i
    # the ground memory (mjrft.ground): the surface and packing each element reads
    g_frame, g_el, g_dp = gr.frame, st.g_elem, gr.dparams
    g_clock = st.g_clock[0]
    g_drift2 = 0.25 * gr.frame[2] * gr.frame[2]  # (half a cell)^2
    g_phi0, g_inv_range = gr.pack[3], gr.pack[4]
    g_wake_on = gr_on and st.g_wake.shape[0] > 0  # the hybrid law's undisturbed-grain rule (mjrft.ground.in_wake)
    nreg = reg_law.shape[0]
    nb = reg_bounds.shape[0]
    has_hf = hf_z.shape[0] > 0
    has_map = reg_map.shape[0] > 0
    wmax, inertia, breg = _scene(reg_law, reg_params, reg_rho)
    # the current single region's constants, switched only when an element lies in another region
    cur_reg = 0
    p, law, hw, dry = _region_constants(0, reg_law, reg_params, reg_rho)
    map_ny, map_nx = reg_map.shape[0], reg_map.shape[1]
    map_frame = (reg_map_frame[0], reg_map_frame[1], reg_map_frame[2], reg_map_frame[3]) if has_map else (
        0.0, 0.0, 1.0, 1.0)
    one_dry_rft = nreg == 1 and breg == 0
    # the batch leaves out trailing faces (_gather) unless the batched region's inertial regime, which acts on the
    # real velocity rather than the law's motion, may give them a force
    all_faces = breg >= 0 and reg_params[breg, P_INERTIA] > 0.0
    dt_d = dt / delta if delta > 0.0 else 0.0
    inv_d = 1.0 / delta if delta > 0.0 else 0.0
    nbat = 0
    regs, wts = (0, 0, 0, 0), (1.0, 0.0, 0.0, 0.0)
    _zero_body_sums(wrench, stiff, damp, inert, inertia, imp, dstiff)
    implicit = imp.shape[0] > 0
    ylim = delta if delta > 0.0 else v_eps
    for g in range(g_geom.shape[0]):
        e0 = g_start[g]
        e1 = g_start[g + 1]
        gid = g_geom[g]
        G = geom_xmat[gid]
        lowest = _lowest_corner(geom_xpos, G, g_aabb, g, gid)
        # A group lying wholly inside the dry Li-RFT strip (farther than blend / 2 from its edges) is
        # treated as the one-region scene: no water over it, so it is culled at the sand's top, only
        # buried elements are within reach, and it takes the short pass 2.
        gtop = top
        g_new, gcx, gcy = 0, 0.0, 0.0
        if gr_on and lowest < top + st.g_blocks.peak[0]:  # the ground memory's highest surface around the group
            g_bump, g_new, gcx, gcy = _group_ground_top(geom_xpos, G, g_aabb, g, gid, g_frame, st.g_blocks)
            gtop = top + g_bump
        dry_group = one_dry_rft
        if not dry_group and breg >= 0 and nb > 0 and not has_map and lowest < gtop:
            dry_group = _inside_strip(geom_xpos, G, g_aabb, g, gid, reg_bounds, breg, blend)
        reach = 0.0 if dry_group else wmax
        if lowest >= gtop - wmax + reach:
            if g_active[g]:  # first step out of reach: no force, memory or depth
                for i in range(e0, e1):
                    _clear(u, out_force, i)
                    out_depth[i] = 0.0
                g_active[g] = False
            continue
        was_active = g_active[g]
        g_active[g] = True
        b = g_body[g]
        R = xmat[b]
        r = rootid[b]
        rot = (R[0], R[1], R[2], R[3], R[4], R[5], R[6], R[7], R[8])
        com = (subtree_com[r, 0], subtree_com[r, 1], subtree_com[r, 2])
        spin, lin = (cvel[b, 0], cvel[b, 1], cvel[b, 2]), (cvel[b, 3], cvel[b, 4], cvel[b, 5])
        bx, by, bz = xipos[b, 0], xipos[b, 1], xipos[b, 2]
        # Pass 1, every element of the group: its position and depth, with no branch the processor could
        # mispredict; the elements within reach of grains or water (depth > -reach) are listed in
        # scr_i[0] (from nbat on, so that the batch gathered in pass 2 can overwrite the list behind it).
        # Force and memory are cleared here only for an element out of reach that may have had them
        # (within reach of the deepest water on its last step); the others' are zero already.
        ox, oy, oz = xpos[b, 0], xpos[b, 1], xpos[b, 2]
        r0, r1, r2, r3, r4, r5, r6, r7, r8 = rot
        nlist = nbat
        bad = 0.0
        if gr_on:  # the same, from the ground memory's surface (mjrft.ground): what each element read from it at the
            # last update that changed the ground around the group (or when the group came within reach, or last moved
            # half a cell), carried to where it is now along the surface's gradient
            gg = st.g_group
            fresh = (not was_active or g_new > gg[g, 0]
                     or (gcx - gg[g, 1]) * (gcx - gg[g, 1]) + (gcy - gg[g, 2]) * (gcy - gg[g, 2]) > g_drift2)
            if fresh:
                gg[g, 0], gg[g, 1], gg[g, 2] = g_clock, gcx, gcy
            for i in range(e0, e1):
                ax, ay, az = e_lpos[i, 0], e_lpos[i, 1], e_lpos[i, 2]
                pz = oz + r6 * ax + r7 * ay + r8 * az
                px = ox + r0 * ax + r1 * ay + r2 * az
                py = oy + r3 * ax + r4 * ay + r5 * az
                if fresh:  # read the ground where the element is now (in the same pass: its position once)
                    g_h, g_hx, g_hy, g_f = ground_sample(px, py, g_frame, st.g_cells)
                    g_el[i, 0], g_el[i, 1], g_el[i, 2], g_el[i, 3], g_el[i, 4] = g_h, g_hx, g_hy, px, py
                    g_el[i, 5] = (g_f - g_phi0) * g_inv_range
                g_h = g_el[i, 0] + g_el[i, 1] * (px - g_el[i, 3]) + g_el[i, 2] * (py - g_el[i, 4])
                if has_hf:
                    depth = surface_height(px, py, surface, hf_z, hf_frame) + g_h - pz
                else:
                    depth = surface + g_h - pz
                bad += px * 0.0 + py * 0.0 + pz * 0.0
                if depth <= -reach and out_depth[i] > -wmax:
                    _clear(u, out_force, i)
                out_pos[i, 0], out_pos[i, 1], out_pos[i, 2] = px, py, pz
                out_depth[i] = depth
                scr_i[0, nlist] = i
                nlist += 1 if depth > -reach else 0
        else:
            for i in range(e0, e1):
                ax, ay, az = e_lpos[i, 0], e_lpos[i, 1], e_lpos[i, 2]
                pz = oz + r6 * ax + r7 * ay + r8 * az
                px = ox + r0 * ax + r1 * ay + r2 * az
                py = oy + r3 * ax + r4 * ay + r5 * az
                if has_hf:
                    depth = surface_height(px, py, surface, hf_z, hf_frame) - pz
                else:
                    depth = surface - pz
                bad += px * 0.0 + py * 0.0 + pz * 0.0  # NaN once any coordinate is not finite
                if depth <= -reach and out_depth[i] > -wmax:
                    _clear(u, out_force, i)
                out_pos[i, 0], out_pos[i, 1], out_pos[i, 2] = px, py, pz
                out_depth[i] = depth
                scr_i[0, nlist] = i
                nlist += 1 if depth > -reach else 0
        if bad != 0.0:
            return BAD_STATE, b
        # Pass 2, the listed elements: region, memory, law. First a dry group (one dry Li-RFT region
        # everywhere, or the group inside such a strip): the general loop's steps for it, without the
        # region and water branches (about 9% of the kernel's time); tested equal to the general loop.
        if dry_group:
            status, nbat = _dry_pass(nbat, nlist, b, nreg, breg, e_lnrm, e_area, rot, com, spin, lin, dt_d, inv_d,
                                     delta, tau, v_eps, solid, stick, u, out_pos, out_vel, out_nrm, out_depth,
                                     out_force, out_region, scr_f, scr_i, all_faces, implicit, dt)
            if status != OK:
                return status, b
            continue
        # Pass 2 of any other group: each listed element's region(s), memory and force.
        for q in range(nbat, nlist):
            i = scr_i[0, q]
            px, py, pz = out_pos[i, 0], out_pos[i, 1], out_pos[i, 2]
            depth = out_depth[i]
            single = True  # the element lies in one region (no blending)
            reg = 0
            if nreg > 1:
                if has_map:  # the blend only within blend / 2 of an edge to another cell
                    ci, cj, near = map_cell(px, py, map_frame, map_nx, map_ny, blend)
                    if near:
                        regs, wts = region_weights(px, py, reg_bounds, reg_map, reg_map_frame, blend)
                        reg = regs[0]
                        single = wts[0] >= 1.0
                    else:
                        reg = reg_map[cj, ci]
                else:  # strips: the blend only near a boundary
                    reg = strip_of(px, reg_bounds)
                    if blend > 0.0 and ((reg > 0 and px - reg_bounds[reg - 1] < 0.5 * blend)
                                        or (reg < nb and reg_bounds[reg] - px < 0.5 * blend)):
                        regs, wts = region_weights(px, py, reg_bounds, reg_map, reg_map_frame, blend)
                        single = False
                if not single:  # report the region with the largest weight
                    reg = heaviest_region(regs, wts)
            if single and reg != cur_reg:
                cur_reg = reg
                p = reg_params[reg]
                law = reg_law[reg]
                hw = p[P_WATER_DEPTH]
                dry = not (hw > 0.0 or reg_rho[reg] > 0.0)
            if single and depth <= -hw:  # above its region's grains and water: no force, no memory
                _clear(u, out_force, i)
                continue
            pe = p
            rows = reg_params
            if gr_on:  # the parameter rows at the element's packing (mjrft.ground)
                rows = _packed_rows(st.g_rows, reg_params, g_dp, g_el[i, 5], reg if single else -1)
                pe = rows[reg] if single else p
            nx, ny, nz, vx, vy, vz = _normal_velocity(i, e_lnrm, out_pos, out_vel, out_nrm, rot, com, spin, lin)
            if not isfinite3(vx, vy, vz):
                return BAD_STATE, b
            if nreg > 1:  # (with one region it stays 0)
                out_region[i] = reg
            speed = math.sqrt(vx * vx + vy * vy + vz * vz)
            if e_area[i] <= 0.0:
                _clear(u, out_force, i)
                continue
            relax = 1.0
            if depth <= 0.0:  # out of the grains (in the water above the sand): no memory
                u[i, 0] = 0.0
                u[i, 1] = 0.0
                u[i, 2] = 0.0
                mx, my, mz, ml, mob = 0.0, 0.0, 0.0, 0.0, 0.0
            else:
                if delta > 0.0 and (solid <= 0.0 or implicit) and speed > 0.0:
                    relax = math.exp(-speed * dt_d)
                mx, my, mz, ml, mob = _rest_memory(u, i, vx, vy, vz, speed, relax, dt_d, inv_d, delta, tau, v_eps,
                                                   solid, stick)
            t_mem = _memory_time(speed, relax, dt, dt_d, delta, tau) if implicit else 0.0
            if gr_on and g_wake_on and single and law == LAW_HYBRID and depth > 0.0 and speed > 0.0:
                # the hybrid law's undisturbed-grain rule: an element moving into a body's wake feels nothing
                isp = 1.0 / speed
                if in_wake(px, py, pz, vx * isp, vy * isp, vz * isp, speed, g_frame, gr.base, st.g_wake,
                           st.g_since[1] + dt, gr.period):
                    out_force[i, 0], out_force[i, 1], out_force[i, 2] = 0.0, 0.0, 0.0
                    continue
            if single and reg == breg:
                # gathered; force, wrench and stiffness after the loop (_scatter_batch)
                nbat = _gather(scr_f, scr_i, nbat, out_force, i, b, nx, ny, nz, mx, my, mz, ml, mob, depth,
                               all_faces, t_mem)
                continue
            fx = 0.0
            fy = 0.0
            fz = 0.0
            kk = 0.0
            if single and dry:  # one dry region, written out: costs what the kernel cost before regions and water
                if ml > 0.0:
                    iml = 1.0 / ml
                    sx, sy, sz = element_stress(law, depth, nx, ny, nz, mx * iml, my * iml, mz * iml, speed, pe)
                    k = e_area[i]
                    fx, fy, fz = sx * k, sy * k, sz * k
                    if not isfinite3(fx, fy, fz):
                        return BAD_FORCE, b
                    kk = linear_stiffness(fx, fy, fz, ml, delta, v_eps)
                    damp[b] += kk * tau if delta > 0.0 else kk
                    if implicit:
                        _add_implicit(imp, b, px - bx, py - by, pz - bz,
                                      _holds(ml, ylim, u[i, 0], u[i, 1], u[i, 2], delta), kk,
                                      t_mem)
                    fx *= mob
                    fy *= mob
                    fz *= mob
                if inertia and p[P_INERTIA] > 0.0:
                    gx, gy, gz, ci = inertial_force(pe, depth, nx, ny, nz, vx, vy, vz, e_area[i])
                    if not isfinite3(gx, gy, gz):
                        return BAD_FORCE, b
                    fx += gx
                    fy += gy
                    fz += gz
                    if ci > 0.0:
                        damp[b] += ci
                        _add_moments(inert, b, px - bx, py - by, pz - bz, ci)
            else:  # water, buoyancy or several regions
                if single:
                    fx, fy, fz, kk, cw, ci, ok = element_force(law, pe, reg_rho[reg], gravity, e_area[i], depth, nx, ny,
                                                            nz, mx, my, mz, ml, mob, vx, vy, vz, speed, delta, v_eps)
                else:
                    fx, fy, fz, kk, cw, ci, ok = blended_force(regs, wts, reg_law, rows, reg_rho, gravity,
                                                            e_area[i], depth, nx, ny, nz, mx, my, mz, ml, mob, vx,
                                                            vy, vz, speed, delta, v_eps)
                if not (ok and isfinite3(fx, fy, fz)):
                    return BAD_FORCE, b
                if implicit:
                    _add_implicit(imp, b, px - bx, py - by, pz - bz,
                                  _holds(ml, ylim, u[i, 0], u[i, 1], u[i, 2], delta), kk,
                                  t_mem)
                kk, cd = _with_water_damping(kk, cw, delta, tau)
                damp[b] += cd
                if ci > 0.0:
                    damp[b] += ci
                    _add_moments(inert, b, px - bx, py - by, pz - bz, ci)
            out_force[i, 0], out_force[i, 1], out_force[i, 2] = fx, fy, fz
            _add_to_body(wrench, stiff, b, fx, fy, fz, px - bx, py - by, pz - bz, kk)
            _add_depth_spring(dstiff, b, px - bx, py - by, pz - bz, fx, fy, fz, depth)
    if nbat > 0:
        pb = reg_params[max(breg, 0)]
        if gr_on:  # each gathered element's packing into scratch row 13 (the ground memory's states have it)
            for j in range(nbat):
                scr_f[13, j] = g_el[scr_i[0, j], 5]
            rft_stress_batch_packed(nbat, scr_f[6], scr_f[0:3], scr_f[3:6], pb, g_dp[max(breg, 0)], scr_f[13],
                                    scr_f[9:12])
        else:
            rft_stress_batch(nbat, scr_f[6], scr_f[0:3], scr_f[3:6], pb, scr_f[9:12])
        status, body = _scatter_batch(nbat, scr_f, scr_i, e_area, out_pos, out_force, xipos, delta, tau, v_eps,
                                      wrench, stiff, damp, pb if inertia and pb[P_INERTIA] > 0.0 else pb[:0], out_vel,
                                      out_nrm, inert, imp, dstiff)
        if status != OK or not gr_on:
            return status, body
    if gr_on and dt > 0.0:  # the ground memory, once per period of simulated time
        st.g_since[0] += dt
        st.g_since[1] += dt
        if st.g_since[0] >= gr.period * (1.0 - 1e-9):
            ground_step(gr, el, st, delta, v_eps, st.g_since[0])
            st.g_since[0] = 0.0
    return OK, -1


@njit(cache=True, error_model="numpy", inline="always")
def _add_run_moments(arr, b, scr_f, row, j0, j1):
    """Add to ``arr[b, 0:10]`` the moments (as :func:`_add_moments`) of the springs ``scr_f[row, j0:j1]`` at the lever
    arms in rows 0-2 of the same columns, summed in local variables over the run first; returns their sum
    (:func:`_scatter_batch`)."""
    s0 = s1 = s2 = s3 = s4 = s5 = s6 = s7 = s8 = s9 = 0.0
    for j in range(j0, j1):
        rx, ry, rz, kk = scr_f[0, j], scr_f[1, j], scr_f[2, j], scr_f[row, j]
        s0 += kk
        s1 += kk * rx
        s2 += kk * ry
        s3 += kk * rz
        s4 += kk * rx * rx
        s5 += kk * rx * ry
        s6 += kk * rx * rz
        s7 += kk * ry * ry
        s8 += kk * ry * rz
        s9 += kk * rz * rz
    arr[b, 0] += s0
    arr[b, 1] += s1
    arr[b, 2] += s2
    arr[b, 3] += s3
    arr[b, 4] += s4
    arr[b, 5] += s5
    arr[b, 6] += s6
    arr[b, 7] += s7
    arr[b, 8] += s8
    arr[b, 9] += s9
    return s0


@njit(cache=True, error_model="numpy", fastmath={"contract", "arcp", "nsz"}, _nrt=False)
def _scatter_batch(nbat, scr_f, scr_i, e_area, out_pos, out_force, xipos, delta, tau, v_eps, wrench, stiff, damp,
                   pin, out_vel, out_nrm, inert, imp, dstiff):
    """The batched elements' forces, wrench and stiffness moments (what the element loop does inline).

    ``pin``: the batched region's parameter vector when its inertial regime is on (the inertial force is
    added on the element's real velocity, its damping moments go to ``inert``), else an empty array.

    In two passes over each body's run of elements (they arrive grouped by body, geom by geom): the first
    finishes each element (its force, written to ``out_force``, its lever arm ``r`` from the body's CoM, its
    stiffness, the implicit step's spring ``T k`` (0 unless it :func:`_holds`) and its depth stiffness) into its
    column of the scratch rows it has read, the second sums the body's 33 moments from those rows in four loops
    of at most ten sums each and adds them to ``wrench``/``stiff``/``damp``/``dstiff`` (and, for the implicit step,
    ``imp``) once per run: in one loop the sums do not fit the processor's registers, and a sum kept in memory
    chains every element on its store. (Each sum adds the same terms in the elements' order as element by
    element; with each body's batched elements in one run, as for geoms selected in MuJoCo's order, and no
    element of it outside the batch, the sums equal the element-by-element ones bit for bit. An element that does
    not hold adds exact zeros to the implicit sums.)"""
    implicit = imp.shape[0] > 0
    ylim = delta if delta > 0.0 else v_eps
    j0 = 0
    while j0 < nbat:
        b = scr_i[1, j0]
        bx, by, bz = xipos[b, 0], xipos[b, 1], xipos[b, 2]
        cin = 0.0
        j1 = j0
        # pass 1: the run's elements, each into its own column (rows 0-2: r; 3: k; 4: T k; 5: depth stiffness;
        # 9-11: force), read before written
        while j1 < nbat and scr_i[1, j1] == b:
            j = j1
            i = scr_i[0, j]
            k = e_area[i]
            fx, fy, fz = scr_f[9, j] * k, scr_f[10, j] * k, scr_f[11, j] * k
            if not isfinite3(fx, fy, fz):
                return BAD_FORCE, b
            f_mag = math.sqrt(fx * fx + fy * fy + fz * fz)
            ml = scr_f[8, j]
            kk = stiffness_of(f_mag, ml, delta, v_eps)
            mob = scr_f[7, j]
            fx *= mob
            fy *= mob
            fz *= mob
            rx, ry, rz = out_pos[i, 0] - bx, out_pos[i, 1] - by, out_pos[i, 2] - bz
            tk = 0.0
            if implicit and kk > 0.0 and _holds(ml, ylim, ml * scr_f[3, j] - tau * out_vel[i, 0],
                                                ml * scr_f[4, j] - tau * out_vel[i, 1],
                                                ml * scr_f[5, j] - tau * out_vel[i, 2], delta):  # _add_implicit's T kk
                tk = scr_f[12, j] * kk
            if pin.shape[0] > 0:
                gx, gy, gz, ci = inertial_force(pin, scr_f[6, j], out_nrm[i, 0], out_nrm[i, 1], out_nrm[i, 2],
                                                out_vel[i, 0], out_vel[i, 1], out_vel[i, 2], k)
                if not isfinite3(gx, gy, gz):
                    return BAD_FORCE, b
                fx += gx
                fy += gy
                fz += gz
                if ci > 0.0:
                    cin += ci
                    _add_moments(inert, b, rx, ry, rz, ci)
            out_force[i, 0], out_force[i, 1], out_force[i, 2] = fx, fy, fz
            scr_f[5, j] = f_mag * mob / scr_f[6, j]  # the law's force (batched elements are below the surface)
            scr_f[0, j], scr_f[1, j], scr_f[2, j] = rx, ry, rz
            scr_f[3, j] = kk
            scr_f[4, j] = tk
            scr_f[9, j], scr_f[10, j], scr_f[11, j] = fx, fy, fz
            j1 += 1
        # pass 2: the run's sums
        f0 = f1 = f2 = t0 = t1 = t2 = 0.0
        for j in range(j0, j1):
            rx, ry, rz, fx, fy, fz = scr_f[0, j], scr_f[1, j], scr_f[2, j], scr_f[9, j], scr_f[10, j], scr_f[11, j]
            f0 += fx
            f1 += fy
            f2 += fz
            t0 += ry * fz - rz * fy
            t1 += rz * fx - rx * fz
            t2 += rx * fy - ry * fx
        d0 = d1 = d2 = d4 = d5 = d7 = 0.0  # depth stiffness: sum kd, kd r (x, y), kd r r^T (xx, xy, yy)
        for j in range(j0, j1):
            rx, ry, kd = scr_f[0, j], scr_f[1, j], scr_f[5, j]
            d0 += kd
            d1 += kd * rx
            d2 += kd * ry
            d4 += kd * rx * rx
            d5 += kd * rx * ry
            d7 += kd * ry * ry
        wrench[b, 0] += f0
        wrench[b, 1] += f1
        wrench[b, 2] += f2
        wrench[b, 3] += t0
        wrench[b, 4] += t1
        wrench[b, 5] += t2
        k0 = _add_run_moments(stiff, b, scr_f, 3, j0, j1)
        dstiff[b, 0] += d0  # the moments with z do not enter vertical springs (add_vertical_k6)
        dstiff[b, 1] += d1
        dstiff[b, 2] += d2
        dstiff[b, 4] += d4
        dstiff[b, 5] += d5
        dstiff[b, 7] += d7
        damp[b] += (k0 * tau if delta > 0.0 else k0) + cin  # sum kk, as k0
        if implicit:  # the implicit step's springs (_add_implicit)
            _add_run_moments(imp, b, scr_f, 4, j0, j1)
        j0 = j1
    return OK, -1

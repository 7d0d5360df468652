"""The fused stepping loop: ``mj_step1 -> terrain_kernel -> mj_step2`` in one compiled loop.

:func:`run_steps` calls MuJoCo's C functions through their addresses (passed at run time, so the compiled code
stays cacheable; :mod:`mjrft.mujoco_c`), which removes the per-step Python overhead that would otherwise dominate
small models. It and everything it calls per step (:func:`mjrft.kernel.terrain_kernel`, the stability tracking, the
implicit step) are compiled with ``_nrt=False``: they allocate nothing, and without numba's reference counting a
call no longer takes and drops a reference (two atomic operations) on each of its arrays, nor each inlined helper
on its arrays per cull group (``benchmarks/step_parts.py``; results equal bit for bit).
"""

from __future__ import annotations

from numba import njit

from .implicit_step import implicit_wrench
from .kernel import BAD_FORCE, OK, terrain_kernel, terrain_kernel_ground
from .mujoco_c import call_mj
from .stability import track_chatter, track_depth_springs, track_stiffness


@njit(cache=True, error_model="numpy", _nrt=False)
def actuator_power(act_force, act_vel):
    """The actuators' mechanical power ``sum_a |f_a v_a|`` (W) from ``data.actuator_force`` and
    ``data.actuator_velocity`` (force times velocity in the actuators' own units is the power they deliver to
    their transmission, whatever its gear)."""
    p = 0.0
    for a in range(act_force.shape[0]):
        p += abs(act_force[a] * act_vel[a])
    return p


@njit(cache=True, error_model="numpy", _nrt=False)
def add_rows(target, rows, values, saved):
    """saved[rows] = target[rows]; target[rows] += values[rows]."""
    for k in range(rows.shape[0]):
        b = rows[k]
        for j in range(values.shape[1]):
            saved[b, j] = target[b, j]
            target[b, j] += values[b, j]


@njit(cache=True, error_model="numpy", _nrt=False)
def restore_rows(target, rows, saved):
    """target[rows] = saved[rows]: exactly what other code had put there."""
    for k in range(rows.shape[0]):
        b = rows[k]
        for j in range(saved.shape[1]):
            target[b, j] = saved[b, j]


@njit(cache=True, error_model="numpy", _nrt=False)
def run_steps(nstep, f_step1, f_step2, m_addr, d_addr, f_implicit, tables, mjd, views, gravity, dt, st):
    """``nstep`` x (mj_step1, terrain_kernel, [implicit_wrench], xfrc_applied += wrench, mj_step2, restore
    xfrc_applied): see :func:`_steps`. A terrain with a ground memory steps with :func:`run_steps_ground`."""
    return _steps(nstep, f_step1, f_step2, m_addr, d_addr, f_implicit, tables, mjd, views, gravity, dt, st, False)


@njit(cache=True, error_model="numpy", _nrt=False)
def run_steps_ground(nstep, f_step1, f_step2, m_addr, d_addr, f_implicit, tables, mjd, views, gravity, dt, st):
    """:func:`run_steps` with :func:`mjrft.kernel.terrain_kernel_ground`: the loop of a terrain with a ground memory
    (:mod:`mjrft.ground`), compiled only when one steps."""
    return _steps(nstep, f_step1, f_step2, m_addr, d_addr, f_implicit, tables, mjd, views, gravity, dt, st, True)


@njit(cache=True, error_model="numpy", _nrt=False, inline="always")
def _steps(nstep, f_step1, f_step2, m_addr, d_addr, f_implicit, tables, mjd, views, gravity, dt, st, ground):
    """``nstep`` x (mj_step1, terrain_kernel, [implicit_wrench], xfrc_applied += wrench, mj_step2, restore
    xfrc_applied).

    Arguments: ``f_step1``, ``f_step2`` the addresses of MuJoCo's ``mj_step1`` / ``mj_step2``, ``m_addr`` /
    ``d_addr`` the ``mjModel`` / ``mjData`` pointers, ``f_implicit`` the addresses of
    :data:`mjrft.implicit_step.IMPLICIT_FUNCTIONS` (zeros without the implicit step); ``tables`` (model in:
    :attr:`mjrft.types.TerrainModel.tables`), ``mjd`` (data in: :class:`mjrft.types.MjViews`), ``views`` (data in
    and out: :class:`mjrft.types.StepViews`), ``gravity`` (m/s^2, downward), ``dt`` (s), ``st`` (state in and out:
    :class:`mjrft.types.TerrainState`).

    With the implicit step (``tables.constants.implicit``) the wrench of each step is made linearly implicit by
    :func:`~mjrft.implicit_step.implicit_wrench` (the ``imp_*`` arrays of ``st`` its scratch).

    ``st.power[0]`` receives the actuators' mechanical power ``sum_a |actuator_force_a actuator_velocity_a|`` (W;
    both of the state at the start of a step, read after its mj_step2) averaged over the steps completed
    (:func:`actuator_power`).

    Returns (status, body, steps completed); on a non-finite value it stops after mj_step1 of the
    failing step, before anything is written to xfrc_applied.
    """
    cs = tables.constants
    implicit, use_inert = cs.implicit, cs.inertial
    rows = tables.elements.body_ids
    xfrc, qacc_smooth, act_force, act_vel = views
    wrench, imp, inert, saved, power = st.wrench, st.imp, st.inert, st.saved, st.power
    work = 0.0
    power[0] = 0.0
    for s in range(nstep):
        call_mj(f_step1, m_addr, d_addr)
        if ground:
            status, body = terrain_kernel_ground(tables, mjd, gravity, dt, st)
        else:
            status, body = terrain_kernel(tables, mjd, gravity, dt, st)
        if status != OK:
            if s > 0:
                power[0] = work / s
            return status, body, s
        track_stiffness(st.stiff, st.stiff_max, st.damp, st.damp_max, inert, st.inert_max)
        track_depth_springs(st.dstiff, st.dstiff_max)
        if implicit:
            bad = implicit_wrench(f_implicit[0], f_implicit[1], f_implicit[2], f_implicit[3], m_addr, d_addr,
                                  qacc_smooth, rows, wrench, imp, inert, use_inert, dt, st.imp_jac, st.imp_minv_jac,
                                  st.imp_blocks, st.imp_a, st.imp_rhs, st.imp_rows)
            if bad >= 0:
                if s > 0:
                    power[0] = work / s
                return BAD_FORCE, bad, s
        track_chatter(wrench, rows, st.stiff_max)
        add_rows(xfrc, rows, wrench, saved)
        call_mj(f_step2, m_addr, d_addr)
        restore_rows(xfrc, rows, saved)
        work += actuator_power(act_force, act_vel)
    if nstep > 0:
        power[0] = work / nstep
    return OK, -1, nstep


class CompiledCall:
    """Calls a compiled function (a numba dispatcher) whose arguments are records (named tuples of arrays) with
    the compiled code of their types looked up once and called directly while the same record objects come back.

    numba's dispatcher types every argument on every call; it types an array in C, but a named tuple in Python
    (~10 us for a terrain's records, more than the kernel costs for a robot with its feet on the sand). The
    records of one terrain stay the same objects from step to step (a new medium or a replaced state is a new
    object), so their types are resolved when one of them changes (then ``dispatcher.typeof_pyval``, once) and
    the overload's entry point is called otherwise. Numbers must keep their Python type (int or float)."""

    __slots__ = ("dispatcher", "_records", "_entry")

    def __init__(self, dispatcher):
        self.dispatcher = dispatcher
        self._records: tuple = ()
        self._entry = None

    def __call__(self, *args):
        records = tuple(a for a in args if not isinstance(a, (int, float)))
        entry = self._entry
        if entry is not None and len(records) == len(self._records) and all(
                a is b for a, b in zip(records, self._records)):
            return entry(*args)
        out = self.dispatcher(*args)  # compiles the types if they are new
        sig = tuple(self.dispatcher.typeof_pyval(a) for a in args)
        self._entry = self.dispatcher.overloads[sig].entry_point
        self._records = records
        return out

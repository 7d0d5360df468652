"""Batched stepping: the physics and granular forces of many environments in one compiled call.

>>> batch = mjrft.batch.BatchedTerrain(terrains, datas)    # one GranularTerrain per MjData
>>> batch.step(10)                                         # every env: 10 x (mj_step1, wrench, mj_step2)
>>> batch.step(np.where(active, 10, 0))                    # per-env step counts (0: leave that env alone)

Each environment ``e`` is stepped by exactly the compiled loop that :meth:`GranularTerrain.step` runs
(:func:`mjrft.stepping.run_steps`), so the result equals stepping every environment on its own, bit for bit. What
the batch removes is the per-environment Python work: one call, not E calls each unboxing its records.

How the call stays generic. A terrain's per-step arguments are one tuple of records,
:meth:`GranularTerrain.step_arguments` (its terrain model's tables, the ``MjData`` views, its state, gravity and
the timestep); the batch keeps one such tuple per environment in a numba typed ``List`` (built once;
rebuilding it costs ~0.2 ms per environment) and the compiled loop star-unpacks item ``e`` into
:func:`~mjrft.stepping.run_steps`. Nothing here spells out the kernel's arguments, so they may grow without
this module changing. Before every call each environment's tuple is fetched again and compared item by item
(records and arrays by identity, numbers by value, ~1 us per environment); an environment whose tuple
changed (a new ``MjData`` bound, a new terrain model after ``set_medium``, a replaced state, a new timestep)
gets its list item replaced.

Parallel stepping. With ``parallel=True`` the environments are spread over numba's threads
(``numba.prange``; MuJoCo's ``mj_step1``/``mj_step2`` are thread-safe for separate ``mjData``;
``NUMBA_NUM_THREADS`` / ``numba.set_num_threads`` set how many). The default is one thread: on the
shared 2-core machine this was measured on (load average 4-6) two threads were as often slower
(0.16x-0.9x) as faster (up to 1.1x), because a parallel region waits for its slowest thread and
every thread competes with other processes (``benchmarks/bench_vector.py`` prints the ratio; try it
on a machine with idle cores). A Python MuJoCo callback (``mujoco.set_mjcb_*``) needs the GIL, which
numba's worker threads do not hold, so while one is installed the batch always steps on one thread.
Each environment's arithmetic is the same in either mode: serial and parallel results are identical.

Errors. A non-finite state or force stops that environment inside the failing step (nothing is
written to its ``xfrc_applied``, as in :meth:`GranularTerrain.step`); the other environments finish
their steps, every environment runs its terrain's bookkeeping (memory, stability check every
``STABILITY_CHECK_EVERY`` steps or ``STABILITY_CHECK_SPAN``, with the coupler's ``TerrainStabilityWarning``), and then a
:class:`~mjrft.errors.NonFiniteError` is raised whose message starts ``environment <index>:`` and
carries the coupler's body and time; its ``env_indices`` attribute lists every failed environment.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numba
import numpy as np
from numba import njit, prange, typed

from . import coupler, kernel
from .stepping import run_steps, run_steps_ground
from .coupler import GranularTerrain
from .errors import NonFiniteError

__all__ = ["BatchedTerrain", "python_callbacks_installed"]

_CALLBACK_GETTERS = tuple(getattr(mujoco, n) for n in sorted(dir(mujoco)) if n.startswith("get_mjcb_"))


def python_callbacks_installed() -> list[str]:
    """Names of the MuJoCo global callbacks (``mjcb_*``) currently set; threads cannot run them without the GIL."""
    return [g.__name__[4:] for g in _CALLBACK_GETTERS if g() is not None]


@njit(cache=True, error_model="numpy", inline="always")
def _step_one(e, nsteps, f_step1, f_step2, m_addr, d_addr, args, out, ground):
    n = nsteps[e]
    if n <= 0:
        out[e, 0], out[e, 1], out[e, 2] = kernel.OK, -1, 0
        return
    if ground:
        status, body, done = run_steps_ground(n, f_step1, f_step2, m_addr[e], d_addr[e], *args[e])
    else:
        status, body, done = run_steps(n, f_step1, f_step2, m_addr[e], d_addr[e], *args[e])
    out[e, 0], out[e, 1], out[e, 2] = status, body, done


@njit(cache=True, error_model="numpy")
def run_batch_serial(nsteps, f_step1, f_step2, m_addr, d_addr, args, out):
    """For each environment ``e``: ``run_steps(nsteps[e], f_step1, f_step2, m_addr[e], d_addr[e], *args[e])``;
    ``out[e] = (status, body, steps done)``."""
    for e in range(len(args)):
        _step_one(e, nsteps, f_step1, f_step2, m_addr, d_addr, args, out, False)


@njit(cache=True, error_model="numpy", parallel=True)
def run_batch_parallel(nsteps, f_step1, f_step2, m_addr, d_addr, args, out):
    """:func:`run_batch_serial` with the environments spread over numba's threads."""
    n = len(args)
    for k in prange(n):
        _step_one(np.int64(k), nsteps, f_step1, f_step2, m_addr, d_addr, args, out, False)


@njit(cache=True, error_model="numpy")
def run_batch_serial_ground(nsteps, f_step1, f_step2, m_addr, d_addr, args, out):
    """:func:`run_batch_serial` of terrains with a ground memory (:func:`mjrft.stepping.run_steps_ground`)."""
    for e in range(len(args)):
        _step_one(e, nsteps, f_step1, f_step2, m_addr, d_addr, args, out, True)


@njit(cache=True, error_model="numpy", parallel=True)
def run_batch_parallel_ground(nsteps, f_step1, f_step2, m_addr, d_addr, args, out):
    """:func:`run_batch_parallel` of terrains with a ground memory."""
    n = len(args)
    for k in prange(n):
        _step_one(np.int64(k), nsteps, f_step1, f_step2, m_addr, d_addr, args, out, True)


def _unchanged(old: tuple, args: tuple) -> bool:
    """Whether ``args`` holds the same records and arrays (the same objects) and equal numbers as ``old``."""
    if len(args) != len(old):
        return False
    for a, k in zip(args, old):
        if a is not k and not (isinstance(a, (int, float)) and isinstance(k, (int, float)) and a == k):
            return False
    return True


class BatchedTerrain:
    """Step ``E`` environments (one :class:`~mjrft.GranularTerrain` and one ``MjData`` each) in one compiled call.

    Args:
        terrains: one terrain per environment (normally each built on its environment's ``MjModel``;
            the models may be separate objects but must give the terrains' arrays the same types).
        datas: the environments' ``MjData``, in the same order; each belongs to its terrain's model.
        parallel: ``True``: spread the environments over numba's threads; ``False`` (default): one thread.

    The terrains stay usable on their own (``terrain.force``, ``terrain.wrench``, ... are filled by the
    batch exactly as by ``terrain.step``).
    """

    def __init__(self, terrains: Sequence[GranularTerrain], datas: Sequence[mujoco.MjData], *,
                 parallel: bool = False):
        self.terrains = list(terrains)
        self.datas = list(datas)
        if not self.terrains:
            raise ValueError("BatchedTerrain needs at least one (terrain, data) pair, got none")
        if len(self.terrains) != len(self.datas):
            raise ValueError(f"got {len(self.terrains)} terrains but {len(self.datas)} MjData; one of each per environment")
        seen_t, seen_d = {}, {}
        for e, (t, d) in enumerate(zip(self.terrains, self.datas)):
            if not isinstance(t, GranularTerrain):
                raise TypeError(f"environment {e}: terrain must be a mjrft.GranularTerrain, got {type(t).__name__}")
            if not isinstance(d, mujoco.MjData):
                raise TypeError(f"environment {e}: data must be a mujoco.MjData, got {type(d).__name__}")
            if d.xpos.shape[0] != t.model.nbody or d.qpos.shape[0] != t.model.nq:
                raise ValueError(f"environment {e}: data does not belong to its terrain's model")
            for seen, obj, what in ((seen_t, t, "terrain"), (seen_d, d, "MjData")):
                if id(obj) in seen:
                    raise ValueError(f"environments {seen[id(obj)]} and {e} share one {what}; each environment needs "
                                     f"its own")
                seen[id(obj)] = e
            if t.ground_memory != self.terrains[0].ground_memory:
                raise ValueError(f"environment {e}'s terrain {'has' if t.ground_memory else 'has no'} ground memory and "
                                 f"environment 0's {'has' if self.terrains[0].ground_memory else 'has none'}; batch "
                                 "terrains that all have one or all have none")
        self.ground = bool(self.terrains[0].ground_memory)
        if not isinstance(parallel, (bool, np.bool_)):
            raise ValueError(f"parallel must be True or False, got {parallel!r}")
        self.parallel = bool(parallel)
        n = len(self.terrains)
        self._m_addr = np.array([t.model._address for t in self.terrains], dtype=np.int64)
        self._d_addr = np.array([d._address for d in self.datas], dtype=np.int64)
        self._dt = [None] * n  # the timestep float each environment's tuple was built with
        self._args: list[tuple | None] = [None] * n
        self._list = None  # numba typed List of the tuples in self._args
        self._out = np.zeros((n, 3), dtype=np.int64)

    def __len__(self) -> int:
        return len(self.terrains)

    @property
    def n_envs(self) -> int:
        return len(self.terrains)

    # ------------------------------------------------------------------ argument tuples
    def _refresh(self, active: np.ndarray) -> None:
        """Fetch each stepping environment's argument tuple; replace the typed-list items that changed."""
        changed = []
        for e in active:
            t, d = self.terrains[e], self.datas[e]
            dt = self._dt[e]
            if dt is None or t.model.opt.timestep != dt:
                dt = self._dt[e] = t.model.opt.timestep
            args = t.step_arguments(d, dt)
            old = self._args[e]
            if old is None or not _unchanged(old, args):
                self._args[e] = args
                changed.append(e)
        if not changed:
            return
        if self._list is None or len(changed) == len(self.terrains):
            self._build_list()
            return
        for e in changed:
            try:
                self._list[e] = self._args[e]
            except Exception:  # the item's numba type changed (e.g. a dtype): rebuild and check every env
                self._build_list()
                return

    def _build_list(self) -> None:
        for e, (t, d) in enumerate(zip(self.terrains, self.datas)):
            if self._args[e] is None:  # an environment that has not stepped yet: bind it so its tuple exists
                t.bind(d)
                self._dt[e] = t.model.opt.timestep
                self._args[e] = t.step_arguments(d, self._dt[e])
        ref = numba.typeof(self._args[0])
        for e in range(1, len(self._args)):
            ty = numba.typeof(self._args[e])
            if ty != ref:
                bad = [i for i, (a, b) in enumerate(zip(ty.types, ref.types)) if a != b] if len(ty) == len(ref) else []
                detail = "; ".join(f"argument {i}: {ty.types[i]} vs {ref.types[i]}" for i in bad[:3])
                raise ValueError(f"environment {e}'s terrain arrays have different types from environment 0's "
                                 f"({detail or f'{len(ty)} vs {len(ref)} arguments'}); batch only like terrains")
        lst = typed.List()
        for args in self._args:
            lst.append(args)
        self._list = lst

    # ------------------------------------------------------------------ stepping
    def step(self, nstep=1) -> None:
        """Step every environment ``nstep`` times (an int, or one count >= 0 per environment).

        Each step of environment ``e`` is ``mj_step1``, its terrain's wrench added to ``xfrc_applied``,
        ``mj_step2``, ``xfrc_applied`` restored, exactly as ``terrains[e].step(datas[e], n)``. Raises
        :class:`NonFiniteError` (message ``environment <e>: ...``) after all environments have stepped
        when any of them produced a non-finite state or force.
        """
        n_envs = len(self.terrains)
        counts = np.asarray(nstep)
        if counts.ndim == 0:
            counts = np.full(n_envs, counts)
        if counts.shape != (n_envs,) or not np.issubdtype(counts.dtype, np.integer):
            raise ValueError(f"nstep must be an int or {n_envs} ints (one per environment), got {nstep!r}")
        counts = counts.astype(np.int64)
        if np.any(counts < 0):
            bad = np.flatnonzero(counts < 0)
            raise ValueError(f"nstep must be >= 0, got {counts[bad[0]]} for environment {bad[0]}")
        active = np.flatnonzero(counts)
        if active.size == 0:
            return
        for e in active:  # as GranularTerrain.step
            self.terrains[e].begin_steps(self.datas[e])
        functions = coupler._STEP_FUNCTIONS
        if functions is None:  # no libmujoco to call directly: each terrain's own (Python) stepping loop
            self._step_each(active, counts)
            return
        self._refresh(active)
        parallel = self.parallel and not python_callbacks_installed()
        if self.ground:
            run = run_batch_parallel_ground if parallel else run_batch_serial_ground
        else:
            run = run_batch_parallel if parallel else run_batch_serial
        out = self._out
        run(counts, functions[0], functions[1], self._m_addr, self._d_addr, self._list, out)
        errors = []
        for e in active:
            t, d = self.terrains[e], self.datas[e]
            try:
                t.end_steps(d, int(out[e, 0]), int(out[e, 1]), self._dt[e], int(out[e, 2]))
            except NonFiniteError as exc:
                errors.append((int(e), exc))
        self._raise(errors)

    def _step_each(self, active, counts) -> None:
        errors = []
        for e in active:
            try:
                self.terrains[e].step(self.datas[e], int(counts[e]))
            except NonFiniteError as exc:
                errors.append((int(e), exc))
        self._raise(errors)

    @staticmethod
    def _raise(errors) -> None:
        if not errors:
            return
        e, exc = errors[0]
        more = ""
        if len(errors) > 1:
            more = f" (also failed: environments {', '.join(str(i) for i, _ in errors[1:])})"
        err = NonFiniteError(f"environment {e}: {exc}{more}")
        err.env_indices = [i for i, _ in errors]
        err.env_messages = {i: str(x) for i, x in errors}  # each failed environment's own error
        raise err from exc

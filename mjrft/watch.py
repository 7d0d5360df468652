"""What a terrain says while it steps: the checks :class:`~mjrft.GranularTerrain` runs on its records.

:class:`ValidityWatch` warns once per (law, quantity) when a terrain leaves a law's calibrated range
(:mod:`mjrft.laws.validity`); :class:`StabilityWatch` warns once per body when the timestep exceeds the explicit
stability limit of the grains' springs or of their depth stiffness, or when the granular force alternates from
step to step (chatter), and computes the stable timesteps (:meth:`mjrft.GranularTerrain.stable_timestep`) from
the stiffness moments the kernel sums (:mod:`mjrft.stability` holds the formulas; docs/numerics.md derives them).
"""

from __future__ import annotations

import warnings

import mujoco
import numpy as np

from .errors import TerrainStabilityWarning, ValidityRangeWarning
from .laws import validity
from .mujoco_c import mujoco_functions
from .stability import (_stable_dts, _stable_timestep_pair, _stable_timesteps, chatter_steps, chatter_warning,
                        chattering, stability_warning, unstable_mode)
from .types import TerrainModel, TerrainState

_JACOBIAN_FUNCTIONS = mujoco_functions("mj_jacBodyCom", "mj_solveM")  # None -> through the bindings


class ValidityWatch:
    """Warns once per (law, quantity) when a terrain leaves a law's calibrated range (:mod:`mjrft.laws.validity`):
    at construction for the static quantities (grain size, ...) of each region's medium, afterwards through
    :meth:`check` for the deepest and the fastest buried element. ``dynamic`` holds (region mask, law name,
    range) for each dynamic range in use not yet warned about (empty: nothing left to check). ``warned``: the
    (law, quantity) pairs already warned about (a terrain whose regions change keeps them: no second warning).
    ``stacklevel``: as :func:`warnings.warn` counts from the constructor's caller (1 names it) for the static
    warnings."""

    def __init__(self, regions, inertial: bool, warned: set | None = None, stacklevel: int = 1):
        self.warned: set[tuple[str, str]] = set() if warned is None else warned
        groups: dict[str, list[int]] = {}
        for k, reg in enumerate(regions):
            groups.setdefault(str(reg.law), []).append(k)
            for r, v in validity.check_static(str(reg.law), reg.medium):
                self.warn(str(reg.law), r, v, f" (medium '{reg.medium.name}')", stacklevel=stacklevel + 2)
            note = validity.check_medium(str(reg.law), reg.medium)
            if note is not None and (str(reg.law), reg.medium.name) not in self.warned:
                self.warned.add((str(reg.law), reg.medium.name))
                warnings.warn(ValidityRangeWarning(note), stacklevel=stacklevel + 1)
        self.dynamic = [(validity.group_mask(len(regions), ks), law, r) for law, ks in groups.items()
                        for r in validity.dynamic_ranges(law, inertial)]

    def warn(self, law: str, r, value: float, where: str, stacklevel: int) -> None:
        if (law, r.quantity) in self.warned:
            return
        self.warned.add((law, r.quantity))
        warnings.warn(ValidityRangeWarning(r.message(law, value, where)), stacklevel=stacklevel)

    def check(self, depth, vel, region, time: float, stacklevel: int = 5) -> None:
        """Warn for the buried elements (``depth`` > 0, velocities ``vel``, region ids ``region``) of the step at
        ``time`` that are deeper or faster than their law's range."""
        extremes = {}
        for mask, law, r in self.dynamic:
            if (law, r.quantity) in self.warned:
                continue
            if law not in extremes:  # one compiled pass per law: (deepest, fastest) buried element
                extremes[law] = validity.buried_extremes(depth, vel, region, mask)
            dmax, vmax = extremes[law]
            if dmax <= 0.0:
                continue
            v = dmax if r.quantity == "depth" else vmax
            if not r.contains(v):
                self.warn(law, r, v, f" at t = {time:.4g} s", stacklevel=stacklevel)
        self.dynamic = [d for d in self.dynamic if (d[1], d[2].quantity) not in self.warned]


class StabilityWatch:
    """The stability and chatter checks of one terrain on ``model`` (one warning per body), and the stable
    timesteps of its bodies, from the moments the kernel sums into a :class:`~mjrft.types.TerrainState`.
    ``body_ids``: the bodies with elements; the scratch arrays are sized for them."""

    def __init__(self, model: mujoco.MjModel, body_ids: np.ndarray):
        self.model = model
        self.body_ids = body_ids
        nb = len(body_ids)
        self.warned: set[int] = set()  # bodies warned about stability
        self.chatter_warned: set[int] = set()  # bodies warned about chatter
        self._jac6 = (np.zeros((6, model.nv)), np.zeros((6, model.nv)))
        self._jac_rows = (np.zeros((6 * nb, model.nv)), np.zeros((6 * nb, model.nv)))
        self.dt_scratch = np.full(model.nbody, np.inf)
        self._rows_scratch = np.zeros(nb, dtype=np.int64)

    # ------------------------------------------------------------------ the checks
    def check(self, data: mujoco.MjData, dt: float, tm: TerrainModel, st: TerrainState) -> None:
        """The checks of the steps since the last call (what :meth:`mjrft.GranularTerrain.step` runs on schedule):
        the springs' explicit limit (not with the implicit step, which it does not bound), the depth stiffness's
        (explicit in every mode), and chatter; each warning's advice is the one that holds at this step."""
        depth = self.depth_limits(data, tm, st)
        if not tm.constants.implicit:
            self.check_springs(data, dt, tm, st, depth)
        self.check_depth_springs(data, dt, tm, depth)
        self.check_chatter(data, dt, tm, st, depth)

    def depth_limits(self, data, tm: TerrainModel, st: TerrainState) -> np.ndarray:
        """Each body's explicit limit (s) of the depth stiffness of its stiffest step since the last call (``inf``
        without one); clears that record."""
        peak = st.dstiff_max.copy()
        st.dstiff_max[:] = 0.0
        limits = np.full(self.model.nbody, np.inf)
        if np.any(peak[self.body_ids, 0] > 0):
            self.limits_into(data, limits, tm, st, peak, vertical=True)
        return limits

    def check_springs(self, data, dt: float, tm: TerrainModel, st: TerrainState, depth: np.ndarray) -> None:
        """Warn once per body when dt exceeds the explicit stability limit (:mod:`mjrft.stability`, docs/numerics.md):
        for a stiffness held ``HELD_STEPS`` steps, or a single step that amplifies by ``SPIKE_GROWTH``;
        with the inertial regime on, its largest damping rate since the last check is added to both
        (:func:`~mjrft.stability.unstable_mode`)."""
        cs = tm.constants
        held, spike, damp = st.stiff_max[:, 0].copy(), st.stiff_max[:, 1].copy(), st.damp_max.copy()
        inert = st.inert_max.copy() if cs.inertial else None
        st.stiff_max[:, :2] = 0.0
        st.damp_max[:] = 0.0
        if cs.inertial:
            st.inert_max[:] = 0.0
        for b in self.body_ids:
            has_inert = inert is not None and inert[b, 0] > 0
            if (spike[b, 0] <= 0 and not has_inert) or b in self.warned:
                continue
            jac, minv_jac = self.jacobians(data, int(b))
            mode = unstable_mode(jac, minv_jac, held[b], spike[b], inert[b] if has_inert else None, cs.delta, cs.tau,
                                 dt)
            if mode is not None:
                self._warn(int(b), tm, lambda name: stability_warning(
                    name, data.time, dt, mode[0], damp[b], mode[1], mode[2], cs.delta, cs.tau, depth[b]))

    def check_depth_springs(self, data, dt: float, tm: TerrainModel, limits: np.ndarray) -> None:
        """Warn once per body when dt exceeds the explicit limit of the depth stiffness ``|F| / depth`` of its
        elements (vertical springs, docs/numerics.md, "Depth stiffness"), ``dt <= sqrt(2) / omega`` with
        ``omega^2 = lambda_max(W6 Kd6)``, for the stiffest step since the last check (``limits``:
        :meth:`depth_limits`)."""
        for b in self.body_ids:
            if dt > limits[b] and b not in self.warned:
                self._warn(int(b), tm, lambda name: TerrainStabilityWarning(
                    f"mjrft: at t = {data.time:.6g} s the timestep {dt:.3g} s exceeds the stability limit "
                    f"{limits[b]:.3g} s of the grains' depth stiffness on body '{name}' (its force grows with its "
                    "depth, explicitly in every mode: a light body on a large area sunk shallow); use a smaller "
                    "timestep (GranularWrapper: substeps)"))

    def check_chatter(self, data, dt: float, tm: TerrainModel, st: TerrainState, depth: np.ndarray) -> None:
        """Warn once per body whose granular force alternated from step to step since the last check
        (:func:`mjrft.stability.track_chatter`, for :func:`~mjrft.stability.chatter_steps` steps), in either mode;
        the cure named is the one that holds at this step (``depth``: the bodies' depth-stiffness limits)."""
        found = [c for c in chattering(st.stiff_max, self.body_ids, chatter_steps(dt))
                 if c[0] not in self.chatter_warned]
        if not found:
            return
        springs = np.full(self.model.nbody, np.inf)
        self.limits_into(data, springs, tm, st, st.stiff, vertical=False)
        for b, steps, change, force in found:
            self.chatter_warned.add(b)
            name = mujoco.mj_id2name(self.model, mujoco.mjtObj.mjOBJ_BODY, b) or f"#{b}"
            warnings.warn(chatter_warning(name, data.time, dt, steps, change, force, tm.constants.implicit,
                                          springs[b], depth[b]), stacklevel=5)

    def _warn(self, b: int, tm: TerrainModel, warning_of) -> None:
        """Warn once about body ``b``: ``warning_of(its name)`` is the :class:`TerrainStabilityWarning`; a stress
        scale other than 1 is named (the stiffness grows with it)."""
        self.warned.add(b)
        name = mujoco.mj_id2name(self.model, mujoco.mjtObj.mjOBJ_BODY, b) or f"#{b}"
        w = warning_of(name)
        if tm.stress_scale != 1.0:
            w = TerrainStabilityWarning(f"{w} (the granular stresses are scaled x{tm.stress_scale:.4g}, "
                                        "set_medium: the stiffness grows with the scale)")
        warnings.warn(w, stacklevel=5)

    # ------------------------------------------------------------------ stable timesteps
    def stable_into(self, data, out: np.ndarray, tm: TerrainModel, st: TerrainState, part: str) -> None:
        """Write each buried body's stable timestep of ``part`` (:meth:`mjrft.GranularTerrain.stable_timestep`)
        into ``out`` (nbody), keeping a smaller value it holds."""
        if part == "step":
            if not tm.constants.implicit:
                self.stable_into(data, out, tm, st, "springs")
            part = "depth"  # with implicit=False the smaller of both: written into the same out
        vertical = part == "depth"
        self.limits_into(data, out, tm, st, st.dstiff if vertical else st.stiff, vertical)

    def stable_pair(self, data, tm: TerrainModel, st: TerrainState) -> tuple[float, float]:
        """The smallest stable timestep of the springs and of the depth stiffness over the bodies, in one compiled
        call that builds the buried bodies' jacobians once (:meth:`mjrft.GranularTerrain.min_stable_timesteps`)."""
        cs = tm.constants
        jac, minv_jac = self._jac_rows
        return _stable_timestep_pair(*_JACOBIAN_FUNCTIONS, self.model._address, data._address, self.body_ids,
                                     st.stiff, st.dstiff, st.inert, cs.inertial, cs.delta, cs.tau, jac, minv_jac,
                                     self._rows_scratch, self.dt_scratch)

    def limits_into(self, data, out: np.ndarray, tm: TerrainModel, st: TerrainState, stiff: np.ndarray,
                    vertical: bool) -> None:
        """Each body's limit for the moments ``stiff`` (the springs', with the inertial dampers; with ``vertical``
        the depth stiffness's) into ``out``, keeping a smaller value it holds: the buried bodies' CoM jacobian rows
        stacked, solved with ``M^-1`` in one ``mj_solveM`` and reduced in one compiled call."""
        cs = tm.constants
        use_inert = cs.inertial and not vertical
        jac, minv_jac = self._jac_rows
        if _JACOBIAN_FUNCTIONS is not None:
            _stable_timesteps(*_JACOBIAN_FUNCTIONS, self.model._address, data._address, self.body_ids, stiff,
                              st.inert, use_inert, cs.delta, cs.tau, vertical, jac, minv_jac, self._rows_scratch,
                              out)
            return
        bodies = self.body_ids
        buried = stiff[bodies, 0] > 0
        if use_inert:
            buried |= st.inert[bodies, 0] > 0
        rows = bodies[buried]
        n = rows.shape[0]
        if n == 0:
            return
        m = self.model
        for i in range(n):
            mujoco.mj_jacBodyCom(m, data, jac[6 * i:6 * i + 3], jac[6 * i + 3:6 * i + 6], int(rows[i]))
        mujoco.mj_solveM(m, data, minv_jac[:6 * n], jac[:6 * n])
        _stable_dts(jac, minv_jac, rows, stiff, st.inert, use_inert, cs.delta, cs.tau, vertical, out)

    def jacobians(self, data, body: int) -> tuple[np.ndarray, np.ndarray]:
        """(J, (M^-1 J^T)^T) of ``body``'s CoM translation (rows 0-2) and rotation (3-5), in scratch arrays."""
        jac, minv_jac = self._jac6
        mujoco.mj_jacBodyCom(self.model, data, jac[:3], jac[3:], body)
        mujoco.mj_solveM(self.model, data, minv_jac, jac)
        return jac, minv_jac

    @staticmethod
    def has_compiled_jacobians() -> bool:
        return _JACOBIAN_FUNCTIONS is not None

"""The MuJoCo coupler: the only place in mjrft that reads ``mjData``.

>>> terrain = mjrft.GranularTerrain(model, medium="poppy_cp", law="rft", bodies=["foot"])
>>> terrain.step(data, 10)          # 10 x (mj_step1, granular wrench, mj_step2)

Each step the terrain reads the current kinematics (after ``mj_step1``), evaluates the law on every
surface element of every selected geom that can reach the grains, and adds each body's summed force
and torque (about the body's centre of mass, world frame) to ``data.xfrc_applied`` for ``mj_step2``;
afterwards it takes exactly that contribution out again, so ``xfrc_applied`` holds only what other
code put there. For code that calls ``mj_step`` itself (or MuJoCo's viewer), :meth:`install`
registers a passive-force callback that adds the same wrench to ``qfrc_passive`` instead.

Settings left as ``None`` are read from the model's MJCF ``<custom>`` section, so a scene file can
carry its terrain::

    <custom>
      <text name="mjrft:medium" data="poppy_cp"/>      <text name="mjrft:law" data="rft"/>
      <text name="mjrft:bodies" data="leg1 leg2"/>     <text name="mjrft:geoms" data="foot_geom"/>
      <numeric name="mjrft:surface" data="0"/>          <numeric name="mjrft:resolution" data="0.005"/>
      <numeric name="mjrft:yield_displacement" data="0.001"/>
    </custom>

and otherwise from the defaults below. One terrain serves one ``MjData`` at a time: stepping a
different ``MjData``, or one whose time went backwards (a reset), clears the elements' memory.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import mujoco
import numpy as np

from . import kernel
from .errors import NonFiniteError, TerrainStabilityWarning, check_finite, check_positive, unknown
from .geometry import Elements, discretize_geom
from .laws import law_id
from .media import Medium, get_medium

DEFAULTS = {
    "medium": "poppy_cp",
    "law": "rft",
    "surface": 0.0,
    "resolution": 0.005,
    "yield_displacement": 1e-3,
    "v_eps": 1e-3,
}
CUSTOM_PREFIX = "mjrft:"
_SUPPORTED_GEOMS = {
    int(mujoco.mjtGeom.mjGEOM_BOX), int(mujoco.mjtGeom.mjGEOM_CAPSULE), int(mujoco.mjtGeom.mjGEOM_CYLINDER),
    int(mujoco.mjtGeom.mjGEOM_SPHERE), int(mujoco.mjtGeom.mjGEOM_ELLIPSOID), int(mujoco.mjtGeom.mjGEOM_MESH),
}
STABILITY_CHECK_EVERY = 50
_STEP_FUNCTIONS = kernel.mujoco_step_functions()  # None -> the plain Python stepping loop is used


def _custom(model: mujoco.MjModel) -> dict:
    """The ``mjrft:*`` entries of the model's <custom> section (text as str, numeric as float)."""
    out = {}
    for i in range(model.ntext):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_TEXT, i) or ""
        if name.startswith(CUSTOM_PREFIX):
            adr, size = model.text_adr[i], model.text_size[i]
            out[name[len(CUSTOM_PREFIX):]] = bytes(model.text_data[adr:adr + size]).split(b"\0")[0].decode()
    for i in range(model.nnumeric):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_NUMERIC, i) or ""
        if name.startswith(CUSTOM_PREFIX):
            adr = model.numeric_adr[i]
            out[name[len(CUSTOM_PREFIX):]] = float(model.numeric_data[adr])
    return out


def _ids(model, kind: mujoco.mjtObj, names, label: str, count: int) -> list[int]:
    if isinstance(names, (str, int, np.integer)):
        names = [names]
    ids = []
    for n in names:
        if isinstance(n, (int, np.integer)):
            if not 0 <= int(n) < count:
                raise ValueError(f"{label} id {int(n)} out of range [0, {count})")
            ids.append(int(n))
            continue
        i = mujoco.mj_name2id(model, kind, str(n))
        if i < 0:
            valid = [mujoco.mj_id2name(model, kind, k) for k in range(count)]
            raise unknown(label, n, [v for v in valid if v])
        ids.append(i)
    return ids


@dataclass(frozen=True)
class Region:
    """A strip of the surface ``x_min <= x < x_max`` with its own medium and law (see GranularTerrain)."""

    x_min: float
    medium: Medium | str
    law: str


class GranularTerrain:
    """Granular forces on selected geoms of a MuJoCo model, applied through ``xfrc_applied``.

    Args:
        model: the ``MjModel``.
        medium: a :class:`~mjrft.media.Medium` or catalogue name (``mjrft.media.MEDIA``).
        law: ``"rft"``, ``"rft3d"`` or ``"depth_only"`` (``mjrft.laws.LAW_IDS``).
        bodies: body names/ids whose geoms feel the grains (all their supported geoms).
        geoms: geom names/ids (added to those of ``bodies``). With neither (and nothing in the MJCF),
            every supported geom of every non-world body.
        surface: height of the flat free surface (m).
        resolution: target element edge length (m), the one discretisation knob.
        yield_displacement: ``delta`` of the rest regularisation (m); 0 switches it to a viscous ramp.
        damping_time: ``tau`` (s) of the Kelvin-Voigt damping below yield; default ``0.5 sqrt(delta/g)``
            (5 ms for delta = 1 mm): critical damping at omega = 2 / tau = 400 rad/s, which keeps the
            damper inside the explicit limit for light legs carrying a robot (effective mass ~10 g,
            load ~2 N) at a 1 ms step; a body resting at its yield load gets zeta = 0.25, and the
            memory's own hysteresis dissipates the rest.
        v_eps: speed (m/s) of the viscous ramp used when ``yield_displacement`` is 0.
        regions: optional strips along x, ``[(x_min, medium, law), ...]`` sorted by ``x_min``;
            elements with x below the first ``x_min`` use ``medium``/``law``.
    """

    def __init__(self, model: mujoco.MjModel, medium=None, law=None, *, bodies=None, geoms=None, surface=None,
                 resolution=None, yield_displacement=None, damping_time=None, v_eps=None, regions=None):
        if not isinstance(model, mujoco.MjModel):
            raise TypeError(f"model must be a mujoco.MjModel, got {type(model).__name__}")
        self.model = model
        cfg = _custom(model)

        def pick(key, value):
            if value is not None:
                return value
            return cfg.get(key, DEFAULTS.get(key))

        self.medium = get_medium(pick("medium", medium))
        self.law = str(pick("law", law))
        lid = law_id(self.law)
        self.surface = check_finite("surface", pick("surface", surface))
        self.resolution = check_positive("resolution", pick("resolution", resolution))
        self.yield_displacement = check_positive("yield_displacement",
                                                 pick("yield_displacement", yield_displacement), allow_zero=True)
        self.v_eps = check_positive("v_eps", pick("v_eps", v_eps), allow_zero=True)
        if self.yield_displacement == 0 and self.v_eps == 0:
            raise ValueError("yield_displacement and v_eps cannot both be 0 (the force at rest would be undefined)")
        if damping_time is None:
            damping_time = cfg.get("damping_time", 0.5 * math.sqrt(self.yield_displacement / 9.81))
        self.damping_time = check_positive("damping_time", damping_time, allow_zero=True)

        # --- regions (strips along x) ---
        laws, params, bounds = [lid], [self.medium.params()], []
        for reg in regions or []:
            x_min, med, lname = (reg.x_min, reg.medium, reg.law) if isinstance(reg, Region) else reg
            x_min = check_finite("region x_min", x_min)
            if bounds and x_min <= bounds[-1]:
                raise ValueError(f"regions must be sorted by increasing x_min, got {x_min!r} after {bounds[-1]!r}")
            bounds.append(x_min)
            laws.append(law_id(lname))
            params.append(get_medium(med).params())
        self._reg_bounds = np.array(bounds, dtype=np.float64)
        self._reg_law = np.array(laws, dtype=np.int64)
        self._reg_params = np.ascontiguousarray(np.array(params, dtype=np.float64))

        # --- geoms ---
        geom_ids = self._select_geoms(pick("bodies", bodies), pick("geoms", geoms))
        groups = []
        for gid in geom_ids:
            el = discretize_geom(model, gid, self.resolution)
            groups.append((gid, el))
        if not groups:
            raise ValueError("no geoms selected for the granular terrain")
        self.geom_ids = np.array([g for g, _ in groups], dtype=np.int64)
        self._g_body = np.array([model.geom_bodyid[g] for g in self.geom_ids], dtype=np.int64)
        counts = [len(el) for _, el in groups]
        self._g_start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
        # per-geom cull box (centre, half sizes in the geom frame); elements lie on the geom's surface, inside it
        self._g_aabb = np.ascontiguousarray(model.geom_aabb[self.geom_ids], dtype=np.float64).reshape(-1, 6)
        self.elements = Elements.concatenate([el for _, el in groups])
        n = len(self.elements)
        self._e_lpos = np.ascontiguousarray(self.elements.pos, dtype=np.float64)
        self._e_lnrm = np.ascontiguousarray(self.elements.normal, dtype=np.float64)
        self.area = np.ascontiguousarray(self.elements.area, dtype=np.float64)
        self.elem_geom = np.repeat(self.geom_ids, counts)
        self.elem_body = np.repeat(self._g_body, counts)
        self.body_ids = np.unique(self._g_body)
        self._rootid = np.ascontiguousarray(model.body_rootid, dtype=np.int64)

        # --- per-step state and outputs ---
        self._g_active = np.zeros(len(self.geom_ids), dtype=np.bool_)
        self._u = np.zeros((n, 3))
        self.pos = np.zeros((n, 3))
        self.vel = np.zeros((n, 3))
        self.normal = np.zeros((n, 3))
        self.depth = np.zeros(n)
        self.force = np.zeros((n, 3))
        self.region = np.zeros(n, dtype=np.int64)
        self.wrench = np.zeros((model.nbody, 6))
        self._saved = np.zeros((model.nbody, 6))
        self._stiff = np.zeros((model.nbody, 10))  # moments of the element stiffness (kernel.terrain_kernel)
        self._damp = np.zeros(model.nbody)
        self._stiff_max = np.zeros((model.nbody, 10))  # the stiffest step since the last stability check
        self._damp_max = np.zeros(model.nbody)
        self._data = None
        self._last_time = -np.inf
        self._steps = 0
        self._warned: set[int] = set()
        self._cb_prev = None
        if model.opt.integrator == mujoco.mjtIntegrator.mjINT_RK4:
            warnings.warn("mjrft: the RK4 integrator evaluates forces at intermediate stages; GranularTerrain "
                          "applies one wrench per step (use Euler or implicitfast)", stacklevel=2)

    # ------------------------------------------------------------------ set-up helpers
    def _select_geoms(self, bodies, geoms) -> list[int]:
        m = self.model
        if isinstance(bodies, str):
            bodies = bodies.split()
        if isinstance(geoms, str):
            geoms = geoms.split()
        selected: list[int] = []
        if bodies:
            bids = set(_ids(m, mujoco.mjtObj.mjOBJ_BODY, bodies, "body", m.nbody))
            selected += [g for g in range(m.ngeom) if m.geom_bodyid[g] in bids and m.geom_type[g] in _SUPPORTED_GEOMS]
        if geoms:
            for g in _ids(m, mujoco.mjtObj.mjOBJ_GEOM, geoms, "geom", m.ngeom):
                if m.geom_type[g] not in _SUPPORTED_GEOMS:
                    name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, g)
                    raise ValueError(f"geom {name or g!r} has type {mujoco.mjtGeom(m.geom_type[g]).name}; "
                                     "supported: box, capsule, cylinder, sphere, ellipsoid, mesh")
                if g not in selected:
                    selected.append(g)
        if not bodies and not geoms:
            selected = [g for g in range(m.ngeom) if m.geom_bodyid[g] != 0 and m.geom_type[g] in _SUPPORTED_GEOMS]
        return sorted(selected)

    def _bind(self, data: mujoco.MjData) -> None:
        if data is self._data:
            return
        if data.xpos.shape[0] != self.model.nbody or data.qpos.shape[0] != self.model.nq:
            raise ValueError("data does not belong to this terrain's model")
        self._data = data
        self._views = (data.geom_xpos, data.geom_xmat, data.xpos, data.xmat, data.xipos, data.cvel, data.subtree_com)
        self.reset()

    def reset(self) -> None:
        """Forget every element's memory (call after changing the state by hand)."""
        self._u[:] = 0.0
        self.force[:] = 0.0
        self.depth[:] = 0.0
        self.wrench[:] = 0.0
        self._g_active[:] = False
        self._last_time = -np.inf

    # ------------------------------------------------------------------ per-step work
    @property
    def n_elements(self) -> int:
        return int(self.area.shape[0])

    def compute(self, data: mujoco.MjData, dt: float | None = None) -> np.ndarray:
        """Evaluate the granular wrench from ``data``'s current kinematics (positions, ``cvel``).

        Advances the elements' memory by ``dt`` (default: the model timestep) and fills ``pos``,
        ``depth`` (every element of a geom that can reach the grains), ``vel``, ``normal`` (elements
        below the surface), ``force`` (zero above) and ``wrench`` (nbody x 6: force, torque about
        each body's centre of mass, world frame). Raises :class:`NonFiniteError` naming the body and time
        on a non-finite state or force. Does not touch ``data``.
        """
        self._bind(data)
        if data.time < self._last_time:
            self.reset()
        if dt is None:
            dt = self.model.opt.timestep
        status, body = kernel.terrain_kernel(*self._kernel_args(dt))
        stiffer = self._stiff[:, 0] > self._stiff_max[:, 0]
        self._stiff_max[stiffer] = self._stiff[stiffer]
        np.maximum(self._damp_max, self._damp, out=self._damp_max)
        self._last_time = data.time
        self._finish(data, status, body, dt, 1)
        return self.wrench

    def _kernel_args(self, dt) -> tuple:
        return (self.geom_ids, self._g_body, self._g_start, self._g_aabb, self._g_active,
                self._e_lpos, self._e_lnrm, self.area, *self._views, self._rootid,
                self.surface, self.surface, self._reg_bounds, self._reg_law, self._reg_params,
                dt, self.yield_displacement, self.damping_time, self.v_eps,
                self._u, self.pos, self.vel, self.normal, self.depth, self.force, self.region,
                self.wrench, self._stiff, self._damp)

    def _step_args(self, data, dt) -> tuple:
        """Arguments of ``kernel.run_steps`` after ``(nstep, f_step1, f_step2, m_addr, d_addr)`` (also used by
        :mod:`mjrft.batch`, which keeps one such tuple per environment: the only list of them is here)."""
        return (data.xfrc_applied, self.body_ids, self._saved, *self._kernel_args(dt), self._stiff_max,
                self._damp_max)

    def _finish(self, data, status, body, dt, nstep) -> None:
        """Raise on a non-finite result; run the stability check every STABILITY_CHECK_EVERY steps."""
        if status != kernel.OK:
            name = mujoco.mj_id2name(self.model, mujoco.mjtObj.mjOBJ_BODY, body) or f"#{body}"
            what = "granular force" if status == kernel.BAD_FORCE else "state (position or velocity)"
            self.wrench[:] = 0.0
            raise NonFiniteError(f"non-finite {what} on body '{name}' at t = {data.time:.6g} s; "
                                 "nothing was written to mjData")
        before = self._steps
        self._steps += nstep
        if before == 0 or before // STABILITY_CHECK_EVERY != self._steps // STABILITY_CHECK_EVERY:
            self._check_stability(data, dt)

    def step(self, data: mujoco.MjData, nstep: int = 1) -> None:
        """``nstep`` times: ``mj_step1``, add the granular wrench to ``xfrc_applied``, ``mj_step2``."""
        nstep = int(nstep)
        if nstep < 0:
            raise ValueError(f"nstep must be >= 0, got {nstep}")
        m = self.model
        self._bind(data)
        if data.time < self._last_time:
            self.reset()
        xfrc = data.xfrc_applied
        rows = self.body_ids
        if _STEP_FUNCTIONS is not None and nstep > 0:
            dt = m.opt.timestep
            status, body, done = kernel.run_steps(nstep, *_STEP_FUNCTIONS, m._address, data._address,
                                                  *self._step_args(data, dt))
            self._last_time = data.time
            self._finish(data, status, body, dt, done)
            return
        for _ in range(nstep):
            mujoco.mj_step1(m, data)
            self.compute(data)
            kernel.add_rows(xfrc, rows, self.wrench, self._saved)
            try:
                mujoco.mj_step2(m, data)
            finally:
                kernel.restore_rows(xfrc, rows, self._saved)

    # ------------------------------------------------------------------ callback mode
    def install(self) -> "GranularTerrain":
        """Register a MuJoCo passive-force callback so that plain ``mj_step`` / the viewer feel the terrain.

        The callback adds the wrench to ``qfrc_passive`` (equivalent to ``xfrc_applied``, but
        nothing is left behind for other code to see). MuJoCo has one global passive callback:
        only one terrain can be installed at a time, and it serves only its own model. Calls at an
        unchanged ``data.time`` (e.g. ``mj_forward``) recompute the force without advancing memory.
        """
        current = mujoco.get_mjcb_passive()
        if current is not None and current != self._callback:
            raise RuntimeError("another MuJoCo passive callback is installed; call its uninstall first")
        mujoco.set_mjcb_passive(self._callback)
        return self

    def uninstall(self) -> None:
        """Remove the callback registered by :meth:`install`."""
        if mujoco.get_mjcb_passive() == self._callback:
            mujoco.set_mjcb_passive(None)

    def __enter__(self):
        return self.install()

    def __exit__(self, *exc):
        self.uninstall()

    def _callback(self, model, data) -> None:
        if model is not self.model:
            return
        dt = model.opt.timestep
        if data is self._data and data.time == self._last_time:
            dt = 0.0
        self.compute(data, dt)
        point = np.empty(3)
        for b in self.body_ids:
            w = self.wrench[b]
            if w[0] == 0 and w[1] == 0 and w[2] == 0 and w[3] == 0 and w[4] == 0 and w[5] == 0:
                continue
            point[:] = data.xipos[b]
            mujoco.mj_applyFT(model, data, w[:3].copy(), w[3:].copy(), point, int(b), data.qfrc_passive)

    # ------------------------------------------------------------------ diagnostics
    def _check_stability(self, data, dt) -> None:
        """Warn once per body when dt exceeds the explicit stability limit (see :mod:`mjrft.kernel`)."""
        m = self.model
        stiff, damp = self._stiff_max.copy(), self._damp_max.copy()
        self._stiff_max[:] = 0.0
        self._damp_max[:] = 0.0
        viscous = self.yield_displacement == 0
        for b in self.body_ids:
            if stiff[b, 0] <= 0 or b in self._warned:
                continue
            lam = self.critical_rate(data, int(b), stiff[b])
            K, c = self._spring(lam)
            if not kernel.stable_step(K, c, 1.0, dt):
                self._warned.add(int(b))
                name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, int(b)) or f"#{b}"
                what = (f"damping {stiff[b, 0]:.3g} N s/m" if viscous else
                        f"stiffness {stiff[b, 0]:.3g} N/m, damping {damp[b]:.3g} N s/m")
                warnings.warn(TerrainStabilityWarning(
                    f"mjrft: timestep {dt:g} s exceeds the stability limit "
                    f"{kernel.max_stable_dt(K, c, 1.0):.3g} s of the granular stiffness on body '{name}' at "
                    f"t = {data.time:.4g} s ({what}, effective mass {stiff[b, 0] / lam:.3g} kg in its stiffest "
                    "mode); reduce the timestep or increase yield_displacement"), stacklevel=3)

    def _spring(self, lam: float) -> tuple[float, float]:
        """(K, c) per unit mass of the stiffest mode, for kernel.stable_step / max_stable_dt with w = 1."""
        return (0.0, lam) if self.yield_displacement == 0 else (lam, self.damping_time * lam)

    def stable_timestep(self, data: mujoco.MjData) -> np.ndarray:
        """Largest stable timestep (s) of each body for the granular stiffness of the last step, shape (nbody,).

        The limit the stability check warns about (see :mod:`mjrft.kernel`), evaluated now; ``inf``
        for bodies with nothing below the surface.
        """
        if data is not self._data:
            raise ValueError("stable_timestep needs the MjData this terrain last stepped")
        out = np.full(self.model.nbody, np.inf)
        for b in self.body_ids:
            if self._stiff[b, 0] > 0:
                out[b] = kernel.max_stable_dt(*self._spring(self.critical_rate(data, int(b), self._stiff[b])), 1.0)
        return out

    def critical_rate(self, data, body: int, moments) -> float:
        """Largest eigenvalue of ``W6 K6`` for ``body``: omega^2 (1/s^2), or 1/s in the viscous mode.

        ``moments`` are the kernel's stiffness moments of the body (see :mod:`mjrft.kernel`), ``K6``
        the 6x6 stiffness they describe and ``W6`` the body's :meth:`mobility`.
        """
        s0, s1, s2 = moments[0], moments[1:4], moments[4:10]
        cross = np.array([[0.0, -s1[2], s1[1]], [s1[2], 0.0, -s1[0]], [-s1[1], s1[0], 0.0]])
        second = np.array([[s2[0], s2[1], s2[2]], [s2[1], s2[3], s2[4]], [s2[2], s2[4], s2[5]]])
        k6 = np.zeros((6, 6))
        k6[:3, :3] = s0 * np.eye(3)
        k6[:3, 3:] = -cross
        k6[3:, :3] = cross
        k6[3:, 3:] = np.trace(second) * np.eye(3) - second
        ev, vec = np.linalg.eigh(self.mobility(data, body))
        half = (vec * np.sqrt(np.clip(ev, 0.0, None))) @ vec.T
        return float(np.linalg.eigvalsh(half @ k6 @ half)[-1])

    def mobility(self, data, body: int) -> np.ndarray:
        """6x6 ``J M^-1 J^T`` of ``body``'s CoM translation (rows 0-2, 1/kg) and rotation (3-5), world frame."""
        m = self.model
        jac = np.zeros((6, m.nv))
        mujoco.mj_jacBodyCom(m, data, jac[:3], jac[3:], body)
        x = np.zeros((6, m.nv))
        mujoco.mj_solveM(m, data, x, jac)
        a = jac @ x.T
        return 0.5 * (a + a.T)

    def inverse_mass(self, data, body: int) -> float:
        """Largest eigenvalue of J M^-1 J^T for the translation of ``body``'s centre of mass (1/kg)."""
        return float(np.linalg.eigvalsh(self.mobility(data, body)[:3, :3])[-1])

    def sinkage(self) -> np.ndarray:
        """Deepest element depth (m, >= 0) of each body, shape (nbody,), from the last step."""
        out = np.zeros(self.model.nbody)
        np.maximum.at(out, self.elem_body, np.maximum(self.depth, 0.0))
        return out

    def contact_mask(self) -> np.ndarray:
        """Elements below the surface at the last step."""
        return self.depth > 0.0

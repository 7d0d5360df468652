"""Granular terrain for MJX: the element tables of :class:`mjrft.GranularTerrain` evaluated as pure JAX functions.

:class:`Sand` is built on a ``mujoco.MjModel`` with :class:`~mjrft.GranularTerrain`'s arguments (so its
settings, element cutting, floor handling and ``<custom>`` keys are the same), keeps the element tables as
arrays and evaluates the granular wrench of one world as a pure function of an ``mjx.Data``:

* :meth:`Sand.wrench` ``(d, state, dt) -> (wrench, state)``: every element's position, normal and velocity
  from the current kinematics (``xpos``, ``xmat``, ``cvel``, ``subtree_com``), the rest memory advanced by
  ``dt``, the law, and the sum per body (force, torque about the body's centre of mass, world frame), the
  same quantities as :meth:`mjrft.GranularTerrain.compute` (the numba kernel stays the reference:
  ``tests/test_mjx.py`` compares them on recorded walking states);
* :meth:`Sand.step` ``(m, d, state) -> (d, state)``: one physics step with the wrench computed from the
  state at the start of the step and applied through ``xfrc_applied`` (MJX's ``fwd_position`` and
  ``fwd_velocity``, the wrench, then ``fwd_actuation``, ``fwd_acceleration``, the constraint solver and
  the model's integrator: the order of ``mj_step1`` / wrench / ``mj_step2`` of the CPU path).

Both are ``jit``-, ``vmap``- and ``scan``-friendly; the elements' memory lives in :class:`SandState`, which
the caller carries (one per world; :meth:`Sand.init` makes it, batched with ``jax.vmap`` or a leading
shape). Nothing non-finite is written into ``xfrc_applied``: a world whose element state or force is not
finite gets no granular wrench, keeps its memory, and records the body in ``state.bad_body`` (and the time
in ``state.bad_time``), which stays set until :meth:`Sand.reset`; :meth:`Sand.check` raises
:class:`~mjrft.NonFiniteError` naming them on the host.

Supported: one region (the terrain's own medium and law), laws ``rft``, ``rft3d`` and ``depth_only``
(:mod:`mjrft.mjx.laws`), the rest memory or the viscous ramp, a flat surface (also from ``floor=...``),
``stress_scale``, and a per-world medium and surface height through ``state.params`` / ``state.surface``. Refused with an error naming the option:
regions, water, buoyancy, the inertial regime, a height-field surface, laws without a JAX twin.

Culling: the CPU kernel skips elements above the surface in groups; here every element's position is
computed each step (a few multiply-adds), and the rest (velocity, memory, law) runs on all elements
with the ones above the surface masked. ``cull=K`` instead gathers at most ``K`` elements below the surface
per world (``jnp.nonzero(..., size=K)``) and evaluates only those: it pays where the law's arithmetic
dominates and most elements are out of the sand (``benchmarks/bench_mjx.py --cull`` measures it); a world
with more than ``K`` buried elements is flagged as bad (``state.bad_body = -2``) instead of losing force.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import jax
import jax.numpy as jnp
import mujoco
import numpy as np
from mujoco import mjx

from ..coupler import STRESS_SLOTS, GranularTerrain
from ..errors import NonFiniteError, check_positive
from ..media import get_medium
from .laws import law_function

HIGHEST = jax.lax.Precision.HIGHEST  # f32 sums in full precision (GPUs default to TF32 for f32 matmuls)
OVERFLOW = -2  # state.bad_body when more than `cull` elements are buried


class SandState(NamedTuple):
    """The per-world state of :class:`Sand` (a pytree: stack it over worlds with ``jax.vmap``).

    ``u`` (n, 3): each element's elastic displacement (the rest memory, m); ``params`` (P_SIZE,): the
    medium's parameter vector (stresses times ``stress_scale``); ``surface``: the sand surface's height (m);
    ``wrench`` (nbody, 6) and ``sinkage``
    (nbody,): the granular wrench applied by the last step and each body's deepest element (m, >= 0);
    ``bad_body``: -1 while every state and force was finite, else the first body with a non-finite one
    (-2: more than ``cull`` buried elements); ``bad_time``: the simulation time when it happened."""

    u: jax.Array
    params: jax.Array
    surface: jax.Array
    wrench: jax.Array
    sinkage: jax.Array
    bad_body: jax.Array
    bad_time: jax.Array


def _unsupported(terrain: GranularTerrain) -> list[str]:
    """The options of ``terrain`` that the JAX path does not model."""
    out = []
    if len(terrain.regions) > 1:
        out.append(f"{len(terrain.regions) - 1} extra region(s)")
    if terrain.water_depth > 0:
        out.append(f"water_depth = {terrain.water_depth:g} m")
    if np.any(terrain._reg_rho > 0):
        out.append("buoyancy")
    if terrain.inertial:
        out.append("the inertial regime (inertial=True)")
    if terrain.surface_hfield is not None:
        out.append("a height-field surface")
    if terrain.implicit:
        out.append("implicit=True (the implicit granular step)")
    return out


class Sand:
    """The granular terrain of ``model`` for MJX; arguments as :class:`mjrft.GranularTerrain` (see there), plus
    ``cull`` (None, or the most buried elements per world evaluated each step; module docstring).

    Build it BEFORE ``mjx.put_model(model)``: like the CPU terrain it removes the floor's contacts from the
    loaded ``model`` when ``floor`` is given (:meth:`put_model` does both in order).

    >>> sand = mjrft.mjx.Sand(model, floor="auto")          # model: a mujoco.MjModel
    >>> mx, step = sand.put_model(), jax.jit(sand.step)     # step(mx, d, state) -> (d, state)
    """

    def __init__(self, model: mujoco.MjModel, medium=None, law=None, *, cull: int | None = None, **kwargs):
        self._init_from(GranularTerrain(model, medium, law, **kwargs), cull)

    @classmethod
    def from_terrain(cls, terrain: GranularTerrain, cull: int | None = None) -> "Sand":
        """The JAX twin of an existing CPU terrain (same elements, medium, law, memory settings, stress scale)."""
        self = cls.__new__(cls)
        self._init_from(terrain, cull)
        return self

    def _init_from(self, terrain: GranularTerrain, cull) -> None:
        if not isinstance(terrain, GranularTerrain):
            raise TypeError(f"terrain must be a mjrft.GranularTerrain, got {type(terrain).__name__}")
        missing = _unsupported(terrain)
        if missing:
            raise NotImplementedError(f"mjrft.mjx does not model {', '.join(missing)}; supported: one region with "
                                      "law rft, rft3d or depth_only on a flat surface (mjrft.mjx.terrain docstring)")
        self.law = terrain.law
        self._stress = law_function(terrain.law)
        self.terrain = terrain
        self.model = terrain.model
        n = terrain.n_elements
        if cull is not None:
            if isinstance(cull, bool) or not isinstance(cull, (int, np.integer)) or not 1 <= cull <= n:
                raise ValueError(f"cull must be None or an integer from 1 to the element count {n}, got {cull!r}")
            cull = int(cull)
        self.cull = cull
        self.n_elements = n
        self.nbody = terrain.model.nbody
        self.body_ids = np.asarray(terrain.body_ids)
        self.surface = float(terrain.surface)
        self.delta = float(terrain.yield_displacement)
        self.tau = float(terrain.damping_time)
        self.v_eps = float(terrain.v_eps)
        self.params = np.array(terrain._reg_params[0], dtype=np.float64)
        # element tables (body frame); per element its body and the root of its kinematic tree
        self.lpos = np.array(terrain._e_lpos)
        self.lnrm = np.array(terrain._e_lnrm)
        self.area = np.array(terrain.area)
        self.elem_body = np.array(terrain.elem_body, dtype=np.int32)
        self.elem_root = np.array(terrain._rootid[terrain.elem_body], dtype=np.int32)
        onehot = np.zeros((self.nbody, n))
        onehot[self.elem_body, np.arange(n)] = 1.0
        self.onehot = onehot  # body-from-element sums as one matrix product (no scatter)

    # ------------------------------------------------------------------ state
    def init(self, params=None, surface=None) -> SandState:
        """A fresh state (no memory) with the terrain's medium parameters or ``params`` (a medium's
        :meth:`~mjrft.media.Medium.params` vector, already scaled: :meth:`params_of`) and its surface height or
        ``surface`` (m)."""
        p = self.params if params is None else params
        z = self.surface if surface is None else surface
        return SandState(u=jnp.zeros((self.n_elements, 3)), params=jnp.asarray(p), surface=jnp.asarray(z),
                         wrench=jnp.zeros((self.nbody, 6)), sinkage=jnp.zeros(self.nbody),
                         bad_body=jnp.array(-1, dtype=jnp.int32), bad_time=jnp.array(0.0))

    @staticmethod
    def reset(state: SandState) -> SandState:
        """``state`` with its memory forgotten and its bad-state record cleared (the medium kept)."""
        return state._replace(u=jnp.zeros_like(state.u), wrench=jnp.zeros_like(state.wrench),
                              sinkage=jnp.zeros_like(state.sinkage), bad_body=jnp.full_like(state.bad_body, -1),
                              bad_time=jnp.zeros_like(state.bad_time))

    def params_of(self, medium, stress_scale: float = 1.0) -> np.ndarray:
        """The parameter vector of another ``medium`` (name or :class:`~mjrft.Medium`) with ``stress_scale``, for
        :meth:`init` or ``state._replace(params=...)``: the CPU terrain's :meth:`~mjrft.GranularTerrain.set_medium`."""
        p = get_medium(medium).params()
        p[STRESS_SLOTS] *= check_positive("stress_scale", stress_scale)
        return p

    # ------------------------------------------------------------------ physics
    def element_kinematics(self, d):
        """World position, normal and velocity (each (n, 3)) of every element from ``d``'s kinematics."""
        dtype = d.xpos.dtype
        R = d.xmat[self.elem_body]  # (n, 3, 3)
        pos = d.xpos[self.elem_body] + jnp.einsum("nij,nj->ni", R, jnp.asarray(self.lpos, dtype), precision=HIGHEST)
        nrm = jnp.einsum("nij,nj->ni", R, jnp.asarray(self.lnrm, dtype), precision=HIGHEST)
        cvel = d.cvel[self.elem_body]  # (angular, linear at the subtree CoM of the root)
        r = pos - d.subtree_com[self.elem_root]
        vel = cvel[:, 3:] + jnp.cross(cvel[:, :3], r)
        return pos, nrm, vel

    def _memory(self, u, vel, buried, dt):
        """The rest memory advanced by ``dt`` and the regularised motion: (u', m, |m|, mobilisation)."""
        speed = jnp.sqrt(jnp.sum(vel * vel, axis=-1))
        if self.delta > 0.0:
            moving = speed > 0.0
            a = jnp.exp(-speed * (dt / self.delta))
            s = self.delta / jnp.where(moving, speed, 1.0)
            sv = s[:, None] * vel
            u = jnp.where(moving[:, None], sv + (u - sv) * a[:, None], u)
            u = jnp.where(buried[:, None], u, 0.0)
            m = u + self.tau * vel
            ml = jnp.sqrt(jnp.sum(m * m, axis=-1))
            return u, m, ml, jnp.minimum(1.0, ml * (1.0 / self.delta))
        mob = jnp.minimum(1.0, speed / self.v_eps) if self.v_eps > 0.0 else jnp.ones_like(speed)
        return jnp.zeros_like(u), vel, speed, mob

    def _forces(self, depth, nrm, vel, u, area, params, dt):
        """Element forces (k, 3) and new memory (k, 3) of elements at ``depth`` (> 0: buried)."""
        buried = (depth > 0.0) & (area > 0.0)
        u, m, ml, mob = self._memory(u, vel, buried, dt)
        moving = buried & (ml > 0.0)
        mhat = m / jnp.where(moving, ml, 1.0)[:, None]
        stress = self._stress(depth, nrm, mhat, params)
        f = jnp.where(moving[:, None], stress * (area * mob)[:, None], 0.0)
        return f, u

    def wrench(self, d, state: SandState, dt) -> tuple[jax.Array, SandState]:
        """The granular wrench (nbody, 6: force, torque about each body's CoM, world frame) on ``d``'s current
        kinematics, and the state advanced by ``dt``. A non-finite element state or force gives a zero wrench
        and the unchanged memory, with the body recorded in ``bad_body``."""
        pos, nrm, vel = self.element_kinematics(d)
        dtype = pos.dtype
        dt = jnp.asarray(dt, dtype)
        area = jnp.asarray(self.area, dtype)
        onehot = jnp.asarray(self.onehot, dtype)
        params = state.params.astype(dtype)
        depth = state.surface.astype(dtype) - pos[:, 2]
        if self.cull is None:
            f, u = self._forces(depth, nrm, vel, state.u, area, params, dt)
            over = jnp.array(False)
        else:
            idx = jnp.nonzero(depth > 0.0, size=self.cull, fill_value=self.n_elements)[0]
            over = jnp.sum(depth > 0.0) > self.cull
            take = jnp.minimum(idx, self.n_elements - 1)
            valid = idx < self.n_elements
            fk, uk = self._forces(jnp.where(valid, depth[take], 0.0), nrm[take], vel[take], state.u[take],
                                  jnp.where(valid, area[take], 0.0), params, dt)
            f = jnp.zeros_like(pos).at[idx].set(fk, mode="drop")
            u = jnp.zeros_like(state.u).at[idx].set(uk, mode="drop")
        r = pos - d.xipos[self.elem_body]
        per_elem = jnp.concatenate([f, jnp.cross(r, f)], axis=-1)  # (n, 6)
        w = jnp.matmul(onehot, per_elem, precision=HIGHEST)
        elem_bad = ~(jnp.all(jnp.isfinite(pos), axis=-1) & jnp.all(jnp.isfinite(vel), axis=-1)
                     & jnp.all(jnp.isfinite(f), axis=-1))
        body_bad = jnp.matmul(onehot, elem_bad.astype(w.dtype), precision=HIGHEST) > 0.0
        bad = jnp.any(body_bad) | over
        first = jnp.where(jnp.any(body_bad), jnp.argmax(body_bad).astype(jnp.int32), jnp.int32(OVERFLOW))
        w = jnp.where(bad, 0.0, w)
        u = jnp.where(bad, state.u, u)
        sink = jnp.max(jnp.where(onehot > 0.0, jnp.maximum(depth, 0.0)[None, :], 0.0), axis=1)
        new_bad = jnp.where(state.bad_body != -1, state.bad_body, jnp.where(bad, first, -1)).astype(jnp.int32)
        new_time = jnp.where((state.bad_body == -1) & bad, d.time, state.bad_time)
        return w, state._replace(u=u, wrench=w, sinkage=jnp.where(bad, 0.0, sink), bad_body=new_bad,
                                 bad_time=new_time.astype(state.bad_time.dtype))

    def step(self, m, d, state: SandState):
        """One physics step of MJX model ``m`` with the granular wrench added to ``xfrc_applied`` for the step (the
        caller's ``xfrc_applied`` is kept); returns ``(d, state)``. With MJX's JAX implementation the wrench is
        computed between the velocity and the actuation stages (MuJoCo's ``mj_step1`` / ``mj_step2`` split);
        with another implementation (``impl="warp"``) ``mjx.forward`` computes the kinematics first and
        ``mjx.step`` then runs the whole step."""
        xfrc = d.xfrc_applied
        dt = m.opt.timestep
        if m.impl != mjx.Impl.JAX:
            w, state = self.wrench(mjx.forward(m, d), state, dt)
            d = mjx.step(m, d.replace(xfrc_applied=xfrc + w))
            return d.replace(xfrc_applied=xfrc), state
        d = mjx.fwd_position(m, d)
        d = mjx.sensor_pos(m, d)
        d = mjx.fwd_velocity(m, d)
        d = mjx.sensor_vel(m, d)
        w, state = self.wrench(d, state, dt)
        d = d.replace(xfrc_applied=xfrc + w)
        d = mjx.fwd_actuation(m, d)
        d = mjx.fwd_acceleration(m, d)
        if d._impl.efc_J.size == 0:
            d = d.replace(qacc=d.qacc_smooth)
        else:
            d = mjx.solve(m, d)
            d = mjx.sensor_acc(m, d)
        integrator = m.opt.integrator
        if integrator == mjx.IntegratorType.EULER:
            d = mjx.euler(m, d)
        elif integrator == mjx.IntegratorType.IMPLICITFAST:
            d = mjx.implicit(m, d)
        else:
            raise NotImplementedError(f"integrator {mjx.IntegratorType(integrator).name}: mjrft.mjx steps Euler and "
                                      "implicitfast models (RK4 would evaluate the memory four times per step)")
        return d.replace(xfrc_applied=xfrc), state

    def put_model(self, **kwargs):
        """``mjx.put_model`` of the terrain's model (its floor contacts already removed); ``kwargs`` go to it
        (e.g. ``impl="warp"``)."""
        return mjx.put_model(self.model, **kwargs)

    def check(self, state: SandState) -> None:
        """Raise :class:`~mjrft.NonFiniteError` naming the body and time when ``state`` (one world or a batch)
        recorded a non-finite state or force, or more buried elements than ``cull``."""
        bad = np.atleast_1d(np.asarray(state.bad_body))
        times = np.atleast_1d(np.asarray(state.bad_time))
        hit = np.flatnonzero(bad != -1)
        if hit.size == 0:
            return
        k = int(hit[0])
        where = "" if bad.size == 1 else f" in world {k} ({hit.size} of {bad.size} worlds)"
        if bad[k] == OVERFLOW:
            raise NonFiniteError(f"more than cull = {self.cull} elements below the surface at t = {times[k]:.6g} s"
                                 f"{where}; raise cull or pass cull=None; no granular wrench was applied")
        name = mujoco.mj_id2name(self.model, mujoco.mjtObj.mjOBJ_BODY, int(bad[k])) or f"#{int(bad[k])}"
        raise NonFiniteError(f"non-finite state or granular force on body '{name}' at t = {times[k]:.6g} s{where}; "
                             "no granular wrench was applied from then on")


def resting_load(sand: Sand, state: SandState) -> float:
    """Net vertical granular force over the model's weight (1 for a body resting on the grains)."""
    m = sand.model
    weight = float(m.body_subtreemass[0]) * -float(m.opt.gravity[2])
    return float(np.sum(np.asarray(state.wrench)[..., 2], axis=-1).mean()) / weight if weight > 0 else math.nan

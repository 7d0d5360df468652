"""Granular terrain for MJX: the element tables of :class:`mjrft.GranularTerrain` evaluated as pure JAX functions.

:class:`Sand` is built on a ``mujoco.MjModel`` with :class:`~mjrft.GranularTerrain`'s arguments (so its
settings, element cutting, floor handling and ``<custom>`` keys are the same), keeps the element tables as
arrays and evaluates the granular wrench of one world as a pure function of an ``mjx.Data``:

* :meth:`Sand.wrench` ``(d, state, dt) -> (wrench, state)``: every element's position, normal and velocity
  from the current kinematics (``xpos``, ``xmat``, ``cvel``, ``subtree_com``), the rest memory advanced by
  ``dt``, the law, and the sum per body (force, torque about the body's centre of mass, world frame), the
  same quantities as :meth:`mjrft.GranularTerrain.compute` (the numba kernel stays the reference:
  ``tests/mjrft/mjx/test_mjx.py`` compares them on recorded walking states);
* :meth:`Sand.step` ``(m, d, state) -> (d, state)``: one physics step with the wrench computed from the
  state at the start of the step and applied through ``xfrc_applied`` (MJX's ``fwd_position`` and
  ``fwd_velocity``, the wrench, then ``fwd_actuation``, ``fwd_acceleration``, the constraint solver and
  the model's integrator as MuJoCo's C library integrates (:func:`mjrft.mjx.integrator.integrate`): the order
  of ``mj_step1`` / wrench / ``mj_step2`` of the CPU path).

Implicit step (a terrain built with ``implicit=True``, as :class:`~mjrft.GranularTerrain`'s; docs/numerics.md,
"Implicit step"): :meth:`Sand.step` applies the linearly implicit wrench instead, which keeps the
grains' springs stable at any timestep. The element pass also sums per body the moments of ``T k`` of its
elements that hold (the 6x6 ``G``), ``fwd_actuation`` and ``fwd_acceleration`` give the smooth acceleration
without the grains, and the bodies with elements have their wrench solve ``(I + dt G W) F' = F - G dV_o``
(:meth:`Sand.implicit_wrench`: one ``6 nb`` linear system per world, ``nb`` the bodies with elements); the
memory is the explicit evaluation's, and ``state.wrench`` holds ``F'``. :meth:`Sand.wrench` stays explicit.
With ``implicit=False`` the step is the explicit one, unchanged. ``tests/mjrft/mjx/test_mjx_implicit.py`` compares the
applied wrench with the CPU implicit step's on recorded walking states.

Both are ``jit``-, ``vmap``- and ``scan``-friendly; the elements' memory lives in :class:`SandState`, which
the caller carries (one per world; :meth:`Sand.init` makes it, batched with ``jax.vmap`` or a leading
shape). Nothing non-finite is written into ``xfrc_applied``: a world whose element state or force is not
finite gets no granular wrench, keeps its memory, and records the body in ``state.bad_body`` (and the time
in ``state.bad_time``), which stays set until :meth:`Sand.reset`; :meth:`Sand.check` raises
:class:`~mjrft.NonFiniteError` naming them on the host.

The whole terrain of the CPU path: every law (:mod:`mjrft.mjx.laws`), strips and maps of regions with their
transitions, the water layer, buoyancy, the inertial regime, the rest memory with its solidify option or the
viscous ramp, a flat or height-field surface (also from ``floor=...``), ``stress_scale``, and the implicit granular
step (MJX's JAX implementation). One dry region of ``rft``, ``rft3d`` or ``depth_only`` on a flat surface takes
the direct pass (the law alone); any other scene the kernel's general pass (:func:`mjrft.mjx.forces.region_force`,
with only the parts the scene uses traced: ``Sand.features``), which ``tests/mjrft/mjx/test_mjx_scenes.py``
compares with the numba kernel on recorded states. Per world: the medium (``state.params``: one row, or one per
region), the surface (``state.surface``: a height, or the height field's samples) and the strips' x_min
(``state.bounds``), drawn per episode by an environment (:meth:`init`). The buoyancy's gravity is the model's at
construction.

Ground memory (a terrain built with ``ground_memory``; :mod:`mjrft.ground`, docs/terrain.md "Ground memory"): on the
direct and the general pass, ``state.ground`` (:class:`mjrft.mjx.ground.GroundState`) holds each world's height map
and packing, which the elements read (their depth from the undisturbed surface, flat or the height field, plus the
remembered one; their parameter row, on the general pass each region's, at the local packing; with the hybrid law its
undisturbed-grain rule from the ground's wake) and every step updates as the numba kernel does
(:mod:`mjrft.mjx.ground`; ``tests/mjrft/mjx/test_mjx_ground.py`` compares them);
:meth:`Sand.ground_height` and :meth:`Sand.ground_packing` read it; :meth:`Sand.reset` restores the prepared bed. Not
with ``cull``, nor a world's own height field (``init(surface=)``). A terrain without it traces none of it.

Culling: the CPU kernel skips elements above the surface in groups; here every element's position is
computed each step (a few multiply-adds), and the rest (velocity, memory, law) runs on all elements
with the ones above the surface masked. ``cull=K`` instead gathers at most ``K`` elements below the surface
per world (``jnp.nonzero(..., size=K)``) and evaluates only those: it pays where the law's arithmetic
dominates and most elements are out of the sand (``benchmarks/bench_mjx.py --cull`` measures it); a world
with more than ``K`` buried elements is flagged as bad (``state.bad_body = -2``) instead of losing force.

Guards (:mod:`mjrft.mjx.guards`; ``guards=False`` leaves them out): every step also checks each world's explicit
stability limits (the grains' springs and their depth stiffness, from per-body stiffness moments that the element
pass sums and the bodies' mobility), period-2 chatter of each body's force, and the law's calibrated depth and
speed ranges, and keeps per world what fired, on how many steps, where and when (the ``guard_*`` fields of
:class:`SandState`). :meth:`Sand.flags` gives the per-world flags inside ``jit``; :meth:`Sand.check` warns on the
host (:class:`~mjrft.TerrainStabilityWarning`, :class:`~mjrft.ValidityRangeWarning`) and raises
:class:`~mjrft.NonFiniteError`; :meth:`Sand.auto_step` sub-steps each world below its limits
(:class:`mjrft.envs.GranularWrapper`'s rule). :meth:`Sand.step` refuses an MJX model that still has the floor's
contacts (put on the device before the terrain was built), and computes the acceleration sensors also when the
model has no constraint rows (MJX's own ``forward`` skips them then).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import jax
import jax.numpy as jnp
import mujoco
import numpy as np
from mujoco import mjx
from mujoco.mjx._src import support
from mujoco.mjx._src.smooth import solve_m

from ..build import build_model, remove_floor_contacts, water_depth
from ..coupler import GranularTerrain
from ..laws.registry import STRESS_SLOTS
from ..errors import NonFiniteError, check_positive
from ..implicit_step import HOLD_FRACTION
from ..laws.registry import parameter_vector
from ..media import get_medium
from ..types import TerrainModel
from .forces import Features, region_force
from ..ground import C_H, C_PHI
from .ground import Ground, GroundState
from .ground import reset as reset_ground
from . import guards as _guards
from .guards import Guards, k6, mobilities, monomials
from .integrator import integrate
from .laws import law_function
from .memory import rest_memory
from .surface import surface_height

#: the laws of the direct pass (one dry region on a flat surface): their stress alone, the batched law's twin
_DIRECT = ("rft", "rft3d", "depth_only")
HIGHEST = jax.lax.Precision.HIGHEST  # f32 sums in full precision (GPUs default to TF32 for f32 matmuls)
OVERFLOW = -2  # state.bad_body when more than `cull` elements are buried


class SandState(NamedTuple):
    """The per-world state of :class:`Sand` (a pytree: stack it over worlds with ``jax.vmap``).

    ``u`` (n, 3): each element's elastic displacement (the rest memory, m); ``params``: the medium's parameter
    vector (P_SIZE,) (stresses times ``stress_scale``), or with several regions one row per region (R, P_SIZE);
    ``surface``: the sand surface's height (m), or with a height-field surface its world heights (nrow, ncol);
    ``bounds`` (R - 1,): the strips' x_min (m; empty without strips);
    ``wrench`` (nbody, 6) and ``sinkage``
    (nbody,): the granular wrench applied by the last step (the implicit one with ``implicit``) and each body's
    deepest element (m, >= 0);
    ``bad_body``: -1 while every state and force was finite, else the first body with a non-finite one
    (-2: more than ``cull`` buried elements); ``bad_time``: the simulation time when it happened.

    The guards (:mod:`mjrft.mjx.guards`; :meth:`Sand.init` fills them, :meth:`Sand.reset` clears them; None in a
    state built without them): ``rates`` (nb, HELD_STEPS): the springs' rate ``lambda_max(W6 K6)`` (1/s^2) of each
    body with elements (``Sand.imp_rows``) over the last steps, newest first; ``chatter`` (nb, 8): each such body's
    last applied force, its last change, the current run of reversals and the largest relative change in it;
    ``stable_dt`` (2,): the last
    step's smallest stable timestep of the springs and of the depth stiffness (s, inf with nothing buried);
    ``substeps``: the sub-steps of the last :meth:`Sand.auto_step` (1 otherwise); and per guard of
    :data:`mjrft.mjx.guards.GUARDS` (springs, depth_stiffness, chatter, depth_range, speed_range):
    ``guard_count`` (5,) the steps on which it fired, ``guard_body`` (5,) the first body (-1: never),
    ``guard_time`` (5,) the time then, ``guard_value`` (5, 2) its worst step
    (:data:`~mjrft.mjx.guards.VALUE_COLUMNS`).

    ``ground``: the ground memory (:class:`mjrft.mjx.ground.GroundState`) of a terrain built with
    ``ground_memory``, else None."""

    u: jax.Array
    params: jax.Array
    surface: jax.Array
    bounds: jax.Array
    wrench: jax.Array
    sinkage: jax.Array
    bad_body: jax.Array
    bad_time: jax.Array
    rates: jax.Array | None = None
    chatter: jax.Array | None = None
    stable_dt: jax.Array | None = None
    substeps: jax.Array | None = None
    guard_count: jax.Array | None = None
    guard_body: jax.Array | None = None
    guard_time: jax.Array | None = None
    guard_value: jax.Array | None = None
    ground: GroundState | None = None


class _Pass(NamedTuple):
    """One element pass (:meth:`Sand._evaluate`): the wrench (nbody, 6), the new memory (n, 3), the sinkage
    (nbody,), the bodies with a non-finite result (nbody, bool), more than ``cull`` buried (bool), the moments
    (nbody, 10) of the implicit step's ``T k`` (None without it), and for the guards (None without them) the moments
    (nb, 10) of the springs' and of the depth stiffness's ``k`` of the bodies with elements and the buried
    extremes (:func:`mjrft.mjx.guards.buried_extremes`)."""

    w: jax.Array
    u: jax.Array
    sink: jax.Array
    body_bad: jax.Array
    over: jax.Array
    moments: jax.Array | None
    stiff: jax.Array | None
    dstiff: jax.Array | None
    extremes: tuple | None
    ground: GroundState | None = None


class Sand:
    """The granular terrain of ``model`` for MJX; arguments as :class:`mjrft.GranularTerrain` (see there), plus
    ``cull`` (None, or the most buried elements per world evaluated each step; module docstring) and ``guards``
    (False: no stability, chatter or range checks, :mod:`mjrft.mjx.guards`). With ``implicit=True`` (or
    :meth:`from_terrain` of such a terrain) :meth:`step` is the implicit granular step.

    Build it BEFORE ``mjx.put_model(model)``: like the CPU terrain it removes the floor's contacts from the
    loaded ``model`` when ``floor`` is given (:meth:`put_model` does both in order).

    >>> sand = mjrft.mjx.Sand(model, floor="auto")          # model: a mujoco.MjModel
    >>> mx, step = sand.put_model(), jax.jit(sand.step)     # step(mx, d, state) -> (d, state)
    """

    def __init__(self, model: mujoco.MjModel, medium=None, law=None, *, cull: int | None = None, guards: bool = True,
                 **kwargs):
        if not isinstance(model, mujoco.MjModel):
            raise TypeError(f"model must be a mujoco.MjModel, got {type(model).__name__}")
        tm = build_model(model, medium, law, stacklevel=3, **kwargs)
        self._init_from(model, tm, cull, guards)
        self.floor_contacts = remove_floor_contacts(model, tm)  # last: an error above leaves the model as it was

    @classmethod
    def from_model(cls, model: mujoco.MjModel, terrain_model: TerrainModel, cull: int | None = None,
                   guards: bool = True) -> "Sand":
        """The JAX terrain of the records ``terrain_model`` (:func:`mjrft.build.build_model`, or a CPU terrain's
        :attr:`~mjrft.GranularTerrain.terrain_model`) on ``model``: the floor that became the surface loses its
        contacts in ``model`` as in the constructor."""
        if not isinstance(terrain_model, TerrainModel):
            raise TypeError(f"terrain_model must be a mjrft.TerrainModel, got {type(terrain_model).__name__}")
        self = cls.__new__(cls)
        self._init_from(model, terrain_model, cull, guards)
        self.floor_contacts = remove_floor_contacts(model, terrain_model)
        return self

    @classmethod
    def from_terrain(cls, terrain: GranularTerrain, cull: int | None = None, guards: bool = True) -> "Sand":
        """The JAX twin of an existing CPU terrain (same elements, medium, law, memory settings, stress scale)."""
        if not isinstance(terrain, GranularTerrain):
            raise TypeError(f"terrain must be a mjrft.GranularTerrain, got {type(terrain).__name__}")
        self = cls.__new__(cls)
        self._init_from(terrain.model, terrain.terrain_model, cull, guards)
        self.floor_contacts = terrain.floor_contacts
        return self

    def _init_from(self, model: mujoco.MjModel, tm: TerrainModel, cull, guards: bool = True) -> None:
        if int(tm.elements.body_root.shape[0]) != model.nbody:
            raise ValueError(f"terrain_model was built on a model with {tm.elements.body_root.shape[0]} bodies, not "
                             f"this one ({model.nbody})")
        self.law = tm.settings.law
        rg, sf, cs0 = tm.regions, tm.surface, tm.constants
        # the scene's regions, surface and options: one dry region of rft, rft3d or depth_only on a flat surface
        # takes the direct pass (the law alone, _forces); anything else the kernel's general pass
        # (mjrft.mjx.forces.region_force), with only the parts the scene uses traced (Features)
        self.features = Features.of(rg.law, rg.params, rg.rho)
        self.general = bool(rg.law.shape[0] > 1 or self.law not in _DIRECT or cs0.inertial or cs0.solid > 0.0
                            or water_depth(rg.params) > 0.0 or np.any(rg.rho > 0.0) or sf.hfield_z.size > 0)
        self._stress = None if self.general else law_function(self.law)
        #: the ground memory (:class:`mjrft.mjx.ground.Ground`; None without ``ground_memory``)
        self.ground = None
        if tm.ground.on:
            if cull is not None:
                raise NotImplementedError("cull is not available with the ground memory (ground_memory=True): "
                                          "pass cull=None")
            self.ground = Ground(tm)
            assert self.general or not self.ground.wake  # the hybrid law is a law of the general pass
        self.reg_law = np.asarray(rg.law, dtype=np.int32)
        self.reg_rho = np.array(rg.rho, dtype=np.float64)
        self.reg_map = np.asarray(rg.map)
        self.reg_map_frame = np.array(rg.map_frame, dtype=np.float64)
        self.bounds = np.array(rg.bounds, dtype=np.float64)
        self.transition = float(rg.transition)
        self.hf_frame = np.array(sf.hfield_frame, dtype=np.float64)
        self.hfield = sf.hfield_z.size > 0
        self.reach = water_depth(rg.params)  # the deepest water: elements above the sand within it feel its drag
        self.solid, self.stick = float(cs0.solid), float(cs0.stick)
        # the buoyancy's gravity, the model's when the terrain is built (MuJoCo's CPU path reads it each step)
        self.gravity = max(0.0, -float(model.opt.gravity[2]))
        self.terrain_model = tm
        self.model = model
        n = tm.n_elements
        if cull is not None:
            if isinstance(cull, bool) or not isinstance(cull, (int, np.integer)) or not 1 <= cull <= n:
                raise ValueError(f"cull must be None or an integer from 1 to the element count {n}, got {cull!r}")
            cull = int(cull)
        self.cull = cull
        self.n_elements = n
        self.nbody = model.nbody
        el, cs = tm.elements, tm.constants
        self.body_ids = np.asarray(el.body_ids)
        self.surface = float(tm.surface.height)
        self.delta = float(cs.delta)
        self.tau = float(cs.tau)
        self.v_eps = float(cs.v_eps)
        self.params = np.array(rg.params[0] if rg.law.shape[0] == 1 else rg.params, dtype=np.float64)
        self.surface_init = np.array(sf.hfield_z) if self.hfield else self.surface
        # element tables (body frame); per element its body and the root of its kinematic tree
        self.lpos = np.array(el.lpos)
        self.lnrm = np.array(el.lnrm)
        self.area = np.array(el.area)
        self.elem_body = np.array(el.body, dtype=np.int32)
        self.elem_root = np.array(el.body_root[el.body], dtype=np.int32)
        onehot = np.zeros((self.nbody, n))
        onehot[self.elem_body, np.arange(n)] = 1.0
        self.onehot = onehot  # body-from-element sums as one matrix product (no scatter)
        self.implicit = bool(cs.implicit)
        # the implicit step's bodies (those with elements), their kinematic roots and the dofs that move them
        rows = np.unique(self.elem_body)
        self.imp_rows = rows.astype(np.int32)
        self.imp_root = np.asarray(el.body_root)[rows].astype(np.int32)
        mask = np.zeros((rows.size, model.nv))
        for i, b in enumerate(rows):
            while b > 0:  # the body and its ancestors: the dofs whose motion moves it
                mask[i, model.dof_bodyid == b] = 1.0
                b = model.body_parentid[b]
        self.imp_dof_mask = mask
        place = np.zeros((self.nbody, rows.size))
        place[rows, np.arange(rows.size)] = 1.0
        self.imp_place = place  # (nbody, nb): the bodies' rows back into (nbody, ...) as a product (no scatter)
        if not isinstance(guards, bool):
            raise TypeError(f"guards must be True or False, got {guards!r}")
        self.guards = Guards(rows, self.nbody, self.delta, self.tau, self.implicit, self.law,
                             bool(cs.inertial)) if guards else None
        # the guards' moments: per-element weights on constant tables of the lever arms (body frame)
        self.moment_table = _guards.moment_table(model, self.elem_body, self.lpos, rows) if guards else None
        self.warned: set = set()  # the (guard, body) pairs check() warned about
        self._static_limit = None

    # ------------------------------------------------------------------ state
    def init(self, params=None, surface=None, bounds=None) -> SandState:
        """A fresh state (no memory) with the terrain's parameters or ``params`` (a medium's
        :func:`~mjrft.laws.registry.parameter_vector`, already scaled: :meth:`params_of`; with several regions one
        row per region, or one row, which replaces region 0's, the terrain's own medium), its surface or ``surface``
        (m: a height, or a height-field surface's world heights, shaped as its samples) and its strips' x_min or
        ``bounds``."""
        p = self.params if params is None else np.asarray(params) if not isinstance(params, jax.Array) else params
        if self.params.ndim == 2 and jnp.ndim(p) == 1:
            p = jnp.asarray(self.params).at[0].set(p)
        z = self.surface_init if surface is None else surface
        if self.hfield and jnp.shape(z) != self.surface_init.shape:
            raise ValueError(f"surface must be the height field's world heights, shape {self.surface_init.shape}, "
                             f"got shape {jnp.shape(z)}")
        b = self.bounds if bounds is None else bounds
        if jnp.shape(b) != self.bounds.shape:
            raise ValueError(f"bounds must hold the terrain's {self.bounds.size} strips' x_min, got shape "
                             f"{jnp.shape(b)}")
        extra = {} if self.guards is None else self.guards.init_fields()
        if self.ground is not None:
            if surface is not None and self.hfield:
                raise ValueError("a height-field surface with a ground memory keeps the height field it was built on "
                                 "(the ground's undisturbed surface under its cells, mjrft.ground): init(surface=...) "
                                 "is not available with ground_memory on a height field; build the Sand on the "
                                 "height field")
            if params is not None:
                raise ValueError("a terrain with a ground memory keeps its medium's packing rows (mjrft.ground): "
                                 "init(params=...) is not available with ground_memory; build the Sand on the medium")
            extra["ground"] = self.ground.init()
        return SandState(u=jnp.zeros((self.n_elements, 3)), params=jnp.asarray(p), surface=jnp.asarray(z),
                         bounds=jnp.asarray(b), wrench=jnp.zeros((self.nbody, 6)), sinkage=jnp.zeros(self.nbody),
                         bad_body=jnp.array(-1, dtype=jnp.int32), bad_time=jnp.zeros((), jnp.asarray(0.0).dtype),
                         **extra)

    @staticmethod
    def reset(state: SandState) -> SandState:
        """``state`` with its memory forgotten, its ground memory back at the prepared bed and its bad-state and
        guards' records cleared (the medium kept)."""
        if state.ground is not None:
            state = state._replace(ground=reset_ground(state.ground))
        state = state._replace(u=jnp.zeros_like(state.u), wrench=jnp.zeros_like(state.wrench),
                               sinkage=jnp.zeros_like(state.sinkage), bad_body=jnp.full_like(state.bad_body, -1),
                               bad_time=jnp.zeros_like(state.bad_time))
        if state.guard_count is None:
            return state
        limits = (jnp.arange(state.guard_value.shape[-2]) == _guards.SPRINGS) | (
            jnp.arange(state.guard_value.shape[-2]) == _guards.DEPTH_STIFFNESS)
        value = jnp.where(limits[:, None], jnp.array([jnp.inf, 1.0], state.guard_value.dtype), 0.0)
        return state._replace(rates=jnp.zeros_like(state.rates), chatter=jnp.zeros_like(state.chatter),
                              stable_dt=jnp.full_like(state.stable_dt, jnp.inf), substeps=jnp.ones_like(state.substeps),
                              guard_count=jnp.zeros_like(state.guard_count),
                              guard_body=jnp.full_like(state.guard_body, -1),
                              guard_time=jnp.zeros_like(state.guard_time),
                              guard_value=jnp.broadcast_to(value, state.guard_value.shape).astype(
                                  state.guard_value.dtype))

    def params_of(self, medium, stress_scale: float = 1.0) -> np.ndarray:
        """The parameter vector of another ``medium`` (name or :class:`~mjrft.Medium`) with ``stress_scale``, for
        :meth:`init` or ``state._replace(params=...)``: the CPU terrain's :meth:`~mjrft.GranularTerrain.set_medium`."""
        p = parameter_vector(get_medium(medium))
        p[STRESS_SLOTS] *= check_positive("stress_scale", stress_scale)
        return p

    def ground_height(self, state: SandState, x, y) -> jax.Array:
        """Height (m) of the grains' surface at world ``(x, y)`` (arrays broadcast) in one world's ``state``: the
        undisturbed surface plus the ground memory's footprints, ridges and packing change, bilinear between the cell
        centres (:meth:`mjrft.GranularTerrain.ground_height`); without a ground memory the sand surface. Inside
        ``jit``; ``jax.vmap`` it over a batch of states."""
        dtype = jnp.asarray(state.u).dtype
        x, y = jnp.broadcast_arrays(jnp.asarray(x, dtype), jnp.asarray(y, dtype))
        if state.ground is not None:
            h = self.ground.sample(state.ground.cells, x, y, C_H, True)
            return h if self.hfield else h + (jnp.asarray(state.surface, dtype) - self.surface)
        if self.hfield:
            return surface_height(x, y, 0.0, jnp.asarray(state.surface, dtype), self.hf_frame)
        return jnp.broadcast_to(jnp.asarray(state.surface, dtype), x.shape)

    def ground_packing(self, state: SandState, x, y) -> jax.Array:
        """Volume fraction of the grains at world ``(x, y)`` (arrays broadcast) in one world's ``state``, bilinear
        between the ground memory's cell centres (:meth:`mjrft.GranularTerrain.ground_packing`); without a ground
        memory the medium's prepared volume fraction (NaN when the medium has none)."""
        dtype = jnp.asarray(state.u).dtype
        x, y = jnp.broadcast_arrays(jnp.asarray(x, dtype), jnp.asarray(y, dtype))
        if state.ground is not None:
            return self.ground.sample(state.ground.cells, x, y, C_PHI, False)
        vf = self.terrain_model.settings.medium.volume_fraction
        return jnp.full(x.shape, jnp.nan if vf is None else float(vf), dtype)

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

    def _forces(self, depth, nrm, vel, u, area, params, dt, implicit=False, px=None, py=None, bounds=None,
                pack=None, wake=None):
        """Element forces (k, 3), new memory (k, 3) and each element's ``|m|`` (k,; its regularised motion, the
        speed in the viscous mode; 0 where it does not move) of elements at ``depth`` (> 0: buried); with ``implicit``
        also each element's ``T k`` (k,) for the implicit step (:meth:`_spring_tk`), else None; and the inertial
        regime's damping (k,) for the implicit step and whether each element's parts were finite (k,) in the
        general pass (:meth:`_general_forces`, which takes the elements' ``px``, ``py``, the strips' ``bounds`` and
        with a ground memory the elements' packing ``pack`` and with its wake whether each element moves into it
        ``wake``), else None, None."""
        if self.general:
            return self._general_forces(depth, nrm, vel, u, area, params, dt, implicit, px, py, bounds, pack, wake)
        buried = (depth > 0.0) & (area > 0.0)
        u, m, ml, mob = self._memory(u, vel, buried, dt)
        moving = buried & (ml > 0.0)
        mhat = m / jnp.where(moving, ml, 1.0)[:, None]
        stress = self._stress(depth, nrm, mhat, params)
        f = jnp.where(moving[:, None], stress * (area * mob)[:, None], 0.0)
        tk = None
        if implicit:  # the springs' stiffness comes from the force at full mobilisation
            tk = self._spring_tk(jnp.where(moving[:, None], stress * area[:, None], 0.0), ml, vel, dt, u)
        return f, u, jnp.where(moving, ml, 0.0), tk, None, None

    def _general_forces(self, depth, nrm, vel, u, area, params, dt, implicit, px, py, bounds, pack=None, wake=None):
        """:meth:`_forces` by the kernel's general pass: the rest memory (:func:`mjrft.mjx.memory.rest_memory`, the
        solidify option included), then each element's regions and their laws, water drag, buoyancy and inertial
        regime (:func:`mjrft.mjx.forces.region_force`; with a ground memory each region's row at the element's
        packing ``pack``; with its wake, ``wake`` (k,) whether each element moves into a body's wake, where a
        buried element of the hybrid law gets nothing, as the kernel's undisturbed-grain rule); elements above the sand
        and its deepest water get nothing and keep no memory."""
        speed = jnp.sqrt(jnp.sum(vel * vel, axis=-1))
        buried = (depth > 0.0) & (area > 0.0)
        u, m, ml, mob = rest_memory(u, vel, speed, buried, dt, self.delta, self.tau, self.v_eps, self.solid,
                                    self.stick)
        table = params if params.ndim == 2 else params[None]
        f, kk, _, ci, ok, _ = region_force(self.features, px, py, depth, nrm, m, ml, mob, vel, speed, area,
                                           reg_law=self.reg_law, reg_params=table, reg_rho=self.reg_rho,
                                           reg_bounds=bounds, reg_map=self.reg_map, reg_map_frame=self.reg_map_frame,
                                           blend=self.transition, gravity=self.gravity, delta=self.delta,
                                           v_eps=self.v_eps, pack=pack,
                                           reg_dparams=None if pack is None else self.ground.dparams, wake=wake)
        within = (area > 0.0) & (depth > -self.reach) if self.reach > 0.0 else buried
        f = jnp.where(within[:, None], f, 0.0)
        tk = self._holding_tk(kk, ml, speed, dt, u) if implicit else None
        moving = buried & (ml > 0.0)
        return f, u, jnp.where(moving, ml, 0.0), tk, (ci if self.features.inertia else None), ok | ~within

    def _spring_tk(self, f_yield, ml, vel, dt, u):
        """Each element's ``T k`` for the implicit step (mjrft.kernel's ``_add_implicit``; docs/numerics.md,
        "Implicit step"): the linearised stiffness ``k = |F_yield| / max(|m|, delta)`` (the damper
        ``|F| / max(|v|, v_eps)`` in the viscous mode) times ``T = tau + delta (1 - exp(-|v| dt / delta)) / |v|``
        (``tau + dt`` at rest; 1 in the viscous mode) for elements that hold: below yield (``|m| <= delta``;
        viscous: ``|v| <= v_eps``) or with their memory ``u`` within ``HOLD_FRACTION`` of ``delta`` (mjrft.kernel's
        ``_holds``); 0 for the sliding others (their force only turns and stays explicit)."""
        f_mag = jnp.sqrt(jnp.sum(f_yield * f_yield, axis=-1))
        if self.delta <= 0.0 and self.v_eps <= 0.0:
            return jnp.zeros_like(f_mag)
        k = f_mag / jnp.maximum(ml, self.delta if self.delta > 0.0 else self.v_eps)
        return self._holding_tk(k, ml, jnp.sqrt(jnp.sum(vel * vel, axis=-1)), dt, u)

    def _holding_tk(self, k, ml, speed, dt, u):
        """``T k`` of elements with linearised stiffness ``k`` (:meth:`_spring_tk`) that hold, 0 for the others."""
        if self.delta > 0.0:
            limit = self.delta
            x = speed * (dt / self.delta)
            small = x < 1e-6
            t = jnp.where(small, self.tau + dt,
                          self.tau - self.delta * jnp.expm1(-x) / jnp.where(small, 1.0, speed))
        elif self.v_eps > 0.0:
            limit, t = self.v_eps, 1.0
        else:
            return jnp.zeros_like(k)
        holds = ml <= limit
        if self.delta > 0.0:
            holds = holds | (jnp.sum(u * u, axis=-1) <= (HOLD_FRACTION * self.delta) ** 2)
        return jnp.where(holds & (k > 0.0), t * k, 0.0)

    def wrench(self, d, state: SandState, dt) -> tuple[jax.Array, SandState]:
        """The granular wrench (nbody, 6: force, torque about each body's CoM, world frame) on ``d``'s current
        kinematics, and the state advanced by ``dt``. A non-finite element state or force gives a zero wrench
        and the unchanged memory, with the body recorded in ``bad_body``. This is the explicit wrench (the
        CPU terrain's :meth:`~mjrft.GranularTerrain.compute`) also for an implicit terrain: the implicit step
        needs the model's dynamics, which :meth:`step` runs. The guards that need no dynamics (chatter, the
        ranges) are advanced; the stability limits need the model's mass matrix, which :meth:`step` has."""
        ev = self._evaluate(d, state, dt, implicit=False)
        w, state = self._finish(d, state, ev.w, ev.u, ev.sink, ev.body_bad, ev.over, ev.ground)
        return w, self._guard(d, state, ev, dt)

    def _evaluate(self, d, state: SandState, dt, implicit: bool) -> _Pass:
        """The element pass (:class:`_Pass`): the wrench, the new memory, the sinkage, the non-finite bodies, the
        overflow of ``cull``; with ``implicit`` the per-body moments (nbody, 10) of the elements' ``T k`` that hold
        (``sum Tk``, ``sum Tk r``, ``sum Tk r r^T`` as ``xx xy xz yy yz zz``, r from the body's CoM); with the
        guards the moments of the springs' ``k`` and of the depth stiffness ``|F| / depth`` of the bodies with
        elements, and the deepest and fastest buried elements."""
        pos, nrm, vel = self.element_kinematics(d)
        dtype = pos.dtype
        dt = jnp.asarray(dt, dtype)
        area = jnp.asarray(self.area, dtype)
        onehot = jnp.asarray(self.onehot, dtype)
        params = state.params.astype(dtype)
        ground = pack = wake = None
        if self.ground is not None:  # the grains' surface and packing as the ground memory holds them
            surface = state.surface.astype(dtype)
            if self.hfield:  # the height field under each element, its highest sample the top
                under = surface_height(pos[:, 0], pos[:, 1], 0.0, surface, self.hf_frame)
                top = jnp.max(surface) + self.reach
            else:
                under, top = surface, (surface + self.reach if self.reach > 0.0 else surface)
            depth, t, ground = self.ground.read(state.ground, d.geom_xpos, d.geom_xmat, pos, under, top,
                                                state.bounds.astype(dtype))
            if self.general:  # each region's row at the element's packing (region_force)
                pack = t
            else:
                params = params[None, :] + t[:, None] * jnp.asarray(self.ground.dparams[0], dtype)[None, :]
            if self.ground.wake:  # the hybrid law's undisturbed-grain rule (mjrft.ground.in_wake)
                wake = self.ground.in_wake(state.ground, pos, vel, jnp.sqrt(jnp.sum(vel * vel, axis=-1)), dt)
        elif self.hfield:
            depth = surface_height(pos[:, 0], pos[:, 1], 0.0, state.surface.astype(dtype), self.hf_frame) - pos[:, 2]
        else:
            depth = state.surface.astype(dtype) - pos[:, 2]
        bounds = state.bounds.astype(dtype)
        within = depth > -self.reach if self.reach > 0.0 else depth > 0.0  # of the grains or the water above them
        if self.cull is None:
            f, u, ml, tk, ci, ok = self._forces(depth, nrm, vel, state.u, area, params, dt, implicit, pos[:, 0],
                                                pos[:, 1], bounds, pack, wake)
            over = jnp.array(False)
        else:
            idx = jnp.nonzero(within, size=self.cull, fill_value=self.n_elements)[0]
            over = jnp.sum(within) > self.cull
            take = jnp.minimum(idx, self.n_elements - 1)
            valid = idx < self.n_elements
            fk, uk, mlk, tkk, cik, okk = self._forces(jnp.where(valid, depth[take], -self.reach - 1.0), nrm[take],
                                                      vel[take], state.u[take], jnp.where(valid, area[take], 0.0),
                                                      params, dt, implicit, pos[take, 0], pos[take, 1], bounds)
            f = jnp.zeros_like(pos).at[idx].set(fk, mode="drop")
            u = jnp.zeros_like(state.u).at[idx].set(uk, mode="drop")
            ml = jnp.zeros_like(depth).at[idx].set(mlk, mode="drop")
            tk = jnp.zeros_like(depth).at[idx].set(tkk, mode="drop") if implicit else None
            ci = None if cik is None else jnp.zeros_like(depth).at[idx].set(cik, mode="drop")
            ok = None if okk is None else jnp.ones(depth.shape, bool).at[idx].set(okk, mode="drop")
        r = pos - d.xipos[self.elem_body]
        per_elem = jnp.concatenate([f, jnp.cross(r, f)], axis=-1)  # (n, 6)
        w = jnp.matmul(onehot, per_elem, precision=HIGHEST)
        elem_bad = ~(jnp.all(jnp.isfinite(pos), axis=-1) & jnp.all(jnp.isfinite(vel), axis=-1)
                     & jnp.all(jnp.isfinite(f), axis=-1))
        if ok is not None:
            elem_bad = elem_bad | ~ok
        body_bad = jnp.matmul(onehot, elem_bad.astype(w.dtype), precision=HIGHEST) > 0.0
        if ground is not None:  # the footprints, ridges, packing and slopes, once per period (not in a bad world)
            ground = self.ground.update(ground, pos, vel, nrm, depth, u, area, dt, ~jnp.any(elem_bad))
        sink = jnp.max(jnp.where(onehot > 0.0, jnp.maximum(depth, 0.0)[None, :], 0.0), axis=1)
        moments = None
        if implicit:  # with the inertial regime its dampers join the springs in G (mjrft.implicit_step)
            g = tk if ci is None else tk + ci
            moments = jnp.matmul(onehot, g[:, None] * monomials(r), precision=HIGHEST)
        stiff = dstiff = extremes = None
        if self.guards is not None:
            buried = (depth > 0.0) & (area > 0.0)
            local = _guards.body_moments(_guards.element_weights(f, ml, depth, buried), self.moment_table)
            stiff, dstiff = _guards.rotate_moments(local, d.xmat[self.imp_rows][None])  # (nb, 10) each, world frame
            extremes = _guards.buried_extremes(sink, jnp.where(buried, jnp.sum(vel * vel, axis=-1), 0.0),
                                               self.moment_table, self.imp_rows)
        return _Pass(w, u, sink, body_bad, over, moments, stiff, dstiff, extremes, ground)

    def _guard(self, d, state: SandState, ev: _Pass, dt, w6=None) -> SandState:
        """``state`` with the guards advanced by the step whose element pass is ``ev`` (the applied wrench in
        ``state.wrench``), with the stability limits when the bodies' mobilities ``w6`` (nb, 6, 6) are given."""
        if self.guards is None:
            return state
        lam = lam_d = None
        if w6 is not None:
            lam, lam_d = self.guards.limits(w6, ev.stiff, ev.dstiff)
        return self.guards.update(state, d.time, dt, state.wrench, ev.extremes, lam, lam_d)

    def mobility(self, m, d) -> tuple[jax.Array, jax.Array]:
        """The stacked CoM jacobians ``J`` (6 nb, nv) of the bodies with elements (:meth:`com_jacobians`) and
        ``M^-1 J^T`` (nv, 6 nb) from MJX's mass-matrix factor of ``d`` (after ``fwd_position``): ``M^-1`` from the
        factor (``nv`` back-substitutions), then one product. (Back-substituting the ``6 nb`` columns of ``J^T``
        instead costs up to a hundred times more on a CPU: LAPACK's batched solves of many narrow right-hand
        sides.)"""
        jac = self.com_jacobians(d)
        eye = jnp.eye(m.nv, dtype=jac.dtype)
        if support.is_sparse(m):
            minv = jax.vmap(lambda col: solve_m(m, d, col), in_axes=1, out_axes=1)(eye)
        else:
            minv = jax.scipy.linalg.cho_solve((d._impl.qLD, False), eye)
        return jac, jnp.matmul(minv, jac.T, precision=HIGHEST)

    @staticmethod
    def _finish(d, state: SandState, w, u, sink, body_bad, over, ground=None) -> tuple[jax.Array, SandState]:
        """The wrench and the new state from an evaluation: a world with a non-finite body (or more than ``cull``
        buried elements) gets a zero wrench and keeps its memory, and the first such body (or ``OVERFLOW``) and
        the time are recorded unless an earlier one is."""
        bad = jnp.any(body_bad) | over
        first = jnp.where(jnp.any(body_bad), jnp.argmax(body_bad).astype(jnp.int32), jnp.int32(OVERFLOW))
        w = jnp.where(bad, 0.0, w)
        u = jnp.where(bad, state.u, u)
        new_bad = jnp.where(state.bad_body != -1, state.bad_body, jnp.where(bad, first, -1)).astype(jnp.int32)
        new_time = jnp.where((state.bad_body == -1) & bad, d.time, state.bad_time)
        if ground is not None:
            state = state._replace(ground=ground)
        return w, state._replace(u=u, wrench=w, sinkage=jnp.where(bad, 0.0, sink), bad_body=new_bad,
                                 bad_time=new_time.astype(state.bad_time.dtype))

    def step(self, m, d, state: SandState):
        """One physics step of MJX model ``m`` with the granular wrench added to ``xfrc_applied`` for the step (the
        caller's ``xfrc_applied`` is kept); returns ``(d, state)``. With MJX's JAX implementation the wrench is
        computed between the velocity and the actuation stages (MuJoCo's ``mj_step1`` / ``mj_step2`` split);
        with another implementation (``impl="warp"``) ``mjx.forward`` computes the kinematics first and
        ``mjx.step`` then runs the whole step.

        With ``implicit`` (a terrain built with ``implicit=True``; JAX implementation only) the applied wrench is
        the linearly implicit one of :meth:`implicit_wrench` (the CPU terrain's implicit step), computed after
        ``fwd_actuation`` and ``fwd_acceleration`` have given the smooth acceleration without the grains;
        ``state.wrench`` holds it, the memory is that of the explicit evaluation.

        The guards advance with the step (with MJX's JAX implementation all of them; with another the chatter and
        range guards). The acceleration sensors are computed also when the model has no constraint rows. A model
        ``m`` that still has the contacts of the floor that became the sand surface (put on the device before this
        terrain was built) is refused with a ValueError when the step is traced."""
        self._check_device_model(m)
        if self.implicit and m.impl != mjx.Impl.JAX:
            raise NotImplementedError("the implicit granular step runs with MJX's JAX implementation only "
                                      "(it needs MJX's mass-matrix factor); build the terrain with "
                                      "implicit=False for impl='warp'")
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
        if not self.implicit:
            ev = self._evaluate(d, state, dt, implicit=False)
            w, state = self._finish(d, state, ev.w, ev.u, ev.sink, ev.body_bad, ev.over, ev.ground)
            if self.guards is not None:
                jac, minv_jt = self.mobility(m, d)
                state = self._guard(d, state, ev, dt, mobilities(jac, minv_jt, self.imp_rows.size))
            d = d.replace(xfrc_applied=xfrc + w)
            d = mjx.fwd_actuation(m, d)
            d = mjx.fwd_acceleration(m, d)
        else:
            d, state = self._implicit_stage(m, d, state, dt)
        if d._impl.efc_J.size == 0:
            d = d.replace(qacc=d.qacc_smooth)
            d = _acceleration_sensors(m, d)  # MJX's forward skips them without constraint rows
        else:
            d = mjx.solve(m, d)
            d = mjx.sensor_acc(m, d)
        d = integrate(m, d)
        return d.replace(xfrc_applied=xfrc), state

    def _check_device_model(self, m) -> None:
        """Refuse an MJX model whose floor geom (the one that became the sand surface) still collides: it was put on
        the device before this terrain removed the floor's contacts from the loaded model."""
        floor = self.terrain_model.settings.floor
        if floor is None or self.floor_contacts is None or self.floor_contacts == (0, 0):
            return
        ct, ca = getattr(m, "geom_contype", None), getattr(m, "geom_conaffinity", None)
        if not isinstance(ct, np.ndarray) or not isinstance(ca, np.ndarray) or floor >= ct.shape[0]:
            return  # not known on the host: nothing to check at trace time
        if ct[floor] != 0 or ca[floor] != 0:
            name = mujoco.mj_id2name(self.model, mujoco.mjtObj.mjOBJ_GEOM, floor) or f"#{floor}"
            raise ValueError(
                f"the MJX model still has the contacts of the floor geom '{name}' (contype {int(ct[floor])}, "
                f"conaffinity {int(ca[floor])}), which is the sand surface: it was put on the device (mjx.put_model) "
                "before mjrft.mjx.Sand was built, so the robot would stand on the rigid floor with no granular load; "
                "build the Sand first and then put the model on the device (mx = sand.put_model())")

    def auto_step(self, m, d, state: SandState, max_substeps: int = _guards.MAX_SUBSTEPS):
        """One step of ``m``'s timestep ``h`` split into ``k`` equal sub-steps (:meth:`step` each) chosen per world from
        its last step's stable timesteps (``state.stable_dt``) and :meth:`static_limit`, by
        :class:`mjrft.envs.GranularWrapper`'s rule (:func:`mjrft.mjx.guards.substeps_for`: half the explicit limit,
        or with the implicit step one radian of the stiffest spring and half the depth stiffness's limit), ``1 <=
        k <= max_substeps``; ``state.substeps`` holds ``k``. A ``jax.lax.while_loop``: under ``vmap`` a batch runs
        as many sub-steps as its world that needs most, the others masked. Needs the guards and MJX's JAX
        implementation."""
        if self.guards is None:
            raise ValueError("auto_step needs the guards' stable timesteps: build the Sand with guards=True")
        if m.impl != mjx.Impl.JAX:
            raise NotImplementedError("auto_step needs MJX's JAX implementation (the stability limits use its "
                                      "mass-matrix factor)")
        if isinstance(max_substeps, bool) or not isinstance(max_substeps, (int, np.integer)) or max_substeps < 1:
            raise ValueError(f"max_substeps must be an integer >= 1, got {max_substeps!r}")
        h = m.opt.timestep
        k = _guards.substeps_for(state.stable_dt, self.static_limit(), h, self.implicit, self.tau, int(max_substeps))
        sub = m.replace(opt=m.opt.replace(timestep=h / k.astype(jnp.asarray(h).dtype)))

        def body(carry):
            i, d, s = carry
            d, s = self.step(sub, d, s)
            return i + 1, d, s

        _, d, state = jax.lax.while_loop(lambda c: c[0] < k, body, (jnp.int32(0), d, state))
        return d, state._replace(substeps=k)

    def static_limit(self) -> float:
        """The springs' stable timestep (s) when any one body with elements carries the model's whole weight at
        yield in the model's ``qpos0`` (:func:`mjrft.mjx.guards.static_timestep_limit`; GranularWrapper's static
        limit), computed once."""
        if self._static_limit is None:
            self._static_limit = _guards.static_timestep_limit(self.model, self.imp_rows, self.delta, self.tau,
                                                               self.v_eps)
        return self._static_limit

    def flags(self, state: SandState) -> dict:
        """Per-world flags of ``state`` (one world or a batch), inside ``jit``: ``nonfinite`` and one per guard
        (``springs``, ``depth_stiffness``, ``chatter``, ``depth_range``, ``speed_range``), each a bool array of the
        batch's shape, True when it fired since the last reset (:func:`mjrft.mjx.guards.flags`; docs/gpu.md,
        "Guards")."""
        if state.guard_count is None:
            raise ValueError("this state has no guards' record: it was made by a Sand built with guards=False")
        return _guards.flags(state)

    def _implicit_stage(self, m, d, state: SandState, dt):
        """The actuation and smooth-acceleration stages of :meth:`step` with the implicit wrench: ``d`` after
        ``fwd_velocity`` -> ``d`` with ``xfrc_applied``, ``qfrc_smooth`` and ``qacc_smooth`` including the
        applied wrench, and the new state. The granular part of the smooth force is added as ``J^T F'`` and
        ``M^-1 J^T F'`` (what ``fwd_acceleration`` would add for it through ``xfrc_applied``, without a second
        pass over every body)."""
        ev = self._evaluate(d, state, dt, implicit=True)
        d = mjx.fwd_actuation(m, d)
        d = mjx.fwd_acceleration(m, d)  # qacc_smooth: every force but the grains' (and the constraints')
        f_new, jac, minv_jt = self.implicit_wrench(m, d, ev.w, ev.moments, dt)
        place = jnp.asarray(self.imp_place, ev.w.dtype)
        rows_bad = ~jnp.all(jnp.isfinite(f_new), axis=-1)  # (nb,)
        imp_bad = jnp.matmul(place, rows_bad.astype(ev.w.dtype), precision=HIGHEST) > 0.0
        body_bad = jnp.where(jnp.any(ev.body_bad), ev.body_bad, imp_bad)  # the explicit failure first, as on the CPU
        w = jnp.matmul(place, jnp.where(rows_bad[:, None], 0.0, f_new), precision=HIGHEST)
        w, state = self._finish(d, state, w, ev.u, ev.sink, body_bad, ev.over, ev.ground)
        if self.guards is not None:
            state = self._guard(d, state, ev, dt, mobilities(jac, minv_jt, self.imp_rows.size))
        f_flat = w[self.imp_rows].reshape(-1)  # zero where the world went bad
        return d.replace(xfrc_applied=d.xfrc_applied + w,
                         qfrc_smooth=d.qfrc_smooth + jnp.matmul(f_flat, jac, precision=HIGHEST),
                         qacc_smooth=d.qacc_smooth + jnp.matmul(minv_jt, f_flat, precision=HIGHEST)), state

    def com_jacobians(self, d) -> jax.Array:
        """The stacked CoM jacobians (6 nb, nv) of the bodies with elements (``imp_rows``; per body 3 rows of the
        translation of its centre of mass ``xipos``, then 3 of its rotation, world frame), from ``d``'s ``cdof``,
        ``xipos`` and ``subtree_com``: MuJoCo's ``mj_jacBodyCom`` (MJX's ``support.jac`` at ``xipos``)."""
        dtype = d.cdof.dtype
        mask = jnp.asarray(self.imp_dof_mask, dtype)  # (nb, nv)
        offset = d.xipos[self.imp_rows] - d.subtree_com[self.imp_root]  # (nb, 3)
        ang, lin = d.cdof[:, :3], d.cdof[:, 3:]  # (nv, 3)
        jacp = lin[None, :, :] + jnp.cross(ang[None, :, :], offset[:, None, :])  # (nb, nv, 3)
        jacr = jnp.broadcast_to(ang[None, :, :], jacp.shape)
        jac = jnp.concatenate([jacp, jacr], axis=-1) * mask[:, :, None]  # (nb, nv, 6)
        return jnp.swapaxes(jac, 1, 2).reshape(-1, d.cdof.shape[0])

    def implicit_wrench(self, m, d, w, moments, dt):
        """The linearly implicit wrench (the CPU terrain's implicit step, mjrft.implicit_step; docs/numerics.md,
        "Implicit step") of the bodies with elements, from the explicit wrench ``w`` (nbody, 6) and the moments
        (nbody, 10) of their elements' ``T k`` that hold, on ``d`` after ``fwd_acceleration`` without the grains (its
        ``qacc_smooth``, ``cdof`` and mass-matrix factor). Per body ``G_b`` is the 6x6 of the moments
        (:func:`k6`); the bodies with springs (``sum T k > 0``) have their wrench ``F'`` solve
        ``(I + dt G W) F' = F - G dV_o``, ``W = J M^-1 J^T`` (their CoM jacobians :meth:`com_jacobians`) and
        ``dV_o = dt J qacc_smooth``; a body without springs keeps ``F`` (its row of the system is the identity and
        its column of ``W`` is left out, as the CPU step leaves the body out). Returns ``(F' (nb, 6), J (6 nb,
        nv), M^-1 J^T (nv, 6 nb))`` with the rows in ``imp_rows`` order; nothing is checked for finiteness."""
        rows = self.imp_rows
        nb = rows.size
        dtype = w.dtype
        dt = jnp.asarray(dt, dtype)
        mom = moments[rows]
        g = k6(mom)  # (nb, 6, 6)
        springs = jnp.repeat(mom[:, 0] > 0.0, 6).astype(dtype)  # (6 nb,)
        jac, minv_jt = self.mobility(m, d)  # (6 nb, nv), (nv, 6 nb)
        mob = jnp.matmul(jac, minv_jt, precision=HIGHEST) * springs[None, :]  # W, only the bodies with springs
        dv = dt * jnp.matmul(jac, d.qacc_smooth, precision=HIGHEST).reshape(nb, 6)
        rhs = w[rows] - jnp.einsum("bij,bj->bi", g, dv, precision=HIGHEST)
        gw = jnp.einsum("bij,bjq->biq", g, mob.reshape(nb, 6, 6 * nb), precision=HIGHEST).reshape(6 * nb, 6 * nb)
        a = jnp.eye(6 * nb, dtype=dtype) + dt * gw
        return jnp.linalg.solve(a, rhs.reshape(-1)).reshape(nb, 6), jac, minv_jt

    def put_model(self, **kwargs):
        """``mjx.put_model`` of the terrain's model (its floor contacts already removed); ``kwargs`` go to it
        (e.g. ``impl="warp"``)."""
        return mjx.put_model(self.model, **kwargs)

    def warn(self, state: SandState, stacklevel: int = 3) -> None:
        """On the host, for ``state`` (one world or a batch): the warnings of :meth:`check` (once per guard and
        body), without raising for a non-finite world (an environment ends that episode and reports it)."""
        if self.guards is not None and state.guard_count is not None:
            _guards.check_guards(self.model, self.guards, state, self.terrain_model.stress_scale, self.warned,
                                 stacklevel)

    def check(self, state: SandState) -> None:
        """On the host, for ``state`` (one world or a batch): warn (once per guard and body) for what the guards
        recorded, naming the first world with it, the body, the time, the steps and the worst value
        (:class:`~mjrft.TerrainStabilityWarning` for the stability limits and chatter,
        :class:`~mjrft.ValidityRangeWarning` for the depth and speed ranges), then raise
        :class:`~mjrft.NonFiniteError` naming the world, body and time when a world recorded a non-finite state or
        force, or more buried elements than ``cull``."""
        self.warn(state, stacklevel=4)
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


def _acceleration_sensors(m, d):
    """``mjx.sensor_acc`` of ``d`` (its ``qacc`` set) for a model without constraint rows: the accelerometers,
    force, torque and frame-acceleration sensors from ``mjx.rne_postconstraint``; touch and contact sensors,
    which read contacts, stay 0 (there are none) and are left out (MJX cannot gather an empty contact set)."""
    stage = np.asarray(m.sensor_needstage)
    acc = stage == mujoco.mjtStage.mjSTAGE_ACC
    contact = acc & np.isin(np.asarray(m.sensor_type), [mujoco.mjtSensor.mjSENS_TOUCH, mujoco.mjtSensor.mjSENS_CONTACT])
    if not (acc & ~contact).any():
        return d
    if contact.any():
        m = m.replace(sensor_needstage=np.where(contact, mujoco.mjtStage.mjSTAGE_POS, stage))
    return mjx.sensor_acc(m, d)


def resting_load(sand: Sand, state: SandState) -> float:
    """Net vertical granular force over the model's weight (1 for a body resting on the grains)."""
    m = sand.model
    weight = float(m.body_subtreemass[0]) * -float(m.opt.gravity[2])
    return float(np.sum(np.asarray(state.wrench)[..., 2], axis=-1).mean()) / weight if weight > 0 else math.nan

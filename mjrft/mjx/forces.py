"""An element's whole force in JAX: the twins of the numba kernel's general pass (:mod:`mjrft.kernel`).

Pure, branch-free functions of element arrays (k elements), for ``jit`` and ``vmap`` on any JAX device in float32
or float64:

* :func:`inertial_force`: the dry inertial regime and its damper (:func:`mjrft.laws.inertial.inertial_force`);
* :func:`buoyancy`: the hydrostatic pressure below the water surface;
* :func:`element_force`: one region's force on each element (:func:`mjrft.forces.element_force`): its sand law
  through the rest regularisation (the stress at the unit motion ``m / |m|`` times area and mobilisation), the
  inertial regime on the real velocity, the water layer's drag (:func:`mjrft.mjx.laws.water`) and buoyancy;
* :func:`blended_force`: :func:`element_force` summed over each element's regions with their weights
  (:func:`mjrft.forces.blended_force`);
* :func:`region_force`: the general pass of one world's elements from their positions: the regions and weights
  at each (x, y) (:func:`mjrft.mjx.surface.region_weights`), their blended force and the region each reports;
  with a ground memory each region's parameter row at the element's packing (:func:`packed`).

Each returns what its numba twin returns: the force (k, 3) in N, the sand part's linearised stiffness ``|F| /
max(|m|, delta)`` (its damping ``|F| / max(|v|, v_eps)`` in the viscous mode; docs/numerics.md), the water drag's
damping ``2 |F_w| / |v|``, the inertial damping ``dF/du`` (all (k,)) and whether each part was finite (k,) bool
(the kernel's ``ok``; the caller also checks the total, as the kernel does, since buoyancy is not among the
parts). :func:`water_damping` combines the stiffness and the drag's damping as the kernel does.

What a scene uses is fixed when the step is traced: :class:`Features` lists the law ids present and whether any
region has the inertial regime, a water layer or buoyancy. Only those are computed (the laws by a select over
the ids present, so a scene with one law computes that law alone); a feature a scene does not use costs
nothing. :meth:`Features.of` reads them from the region tables; a parameter row given at run time (a world's
own medium) must stay within them.
"""

from __future__ import annotations

from dataclasses import dataclass

import jax.numpy as jnp
import numpy as np

from ..laws.registry import LAW_IDS
from ..laws.registry import LAWS as _TABLE
from ..params import P_INERTIA, P_INERTIA_SKIN, P_INERTIA_VC2, P_WATER_DEPTH, P_WATER_SKIN
from . import laws as _laws
from .surface import heaviest_region, region_weights

LAW_WATER = LAW_IDS["water"]  # a region of open water: no sand law below it
LAW_HYBRID = LAW_IDS["hybrid"]  # with a ground memory: its undisturbed-grain rule (mjrft.ground.in_wake)
#: law id -> its JAX stress function (the laws of the table that name a twin)
TWINS = {law.id: getattr(_laws, law.jax) for law in _TABLE if law.jax is not None}


@dataclass(frozen=True)
class Features:
    """What a scene's regions use (static: it decides what the traced step computes). ``laws``: the law ids
    present (:data:`mjrft.laws.registry.LAW_IDS`); ``inertia``: some region has the inertial regime on
    (``p[P_INERTIA] > 0``); ``water``: some region has a water layer (``p[P_WATER_DEPTH] > 0``); ``buoyancy``: some
    region has a buoyancy density (``reg_rho > 0``)."""

    laws: tuple[int, ...]
    inertia: bool = False
    water: bool = False
    buoyancy: bool = False

    def __post_init__(self):
        laws = tuple(sorted({int(x) for x in self.laws}))
        bad = [x for x in laws if x not in TWINS and x != LAW_WATER]
        if not laws or bad:
            names = ", ".join(f"{law.name} ({law.id})" for law in _TABLE if law.id in TWINS)
            raise ValueError(f"Features.laws must name at least one law with a JAX twin, got {self.laws!r}; "
                             f"valid ids: {names}")
        object.__setattr__(self, "laws", laws)

    @classmethod
    def of(cls, reg_law, reg_params, reg_rho) -> "Features":
        """The features of the region tables (host arrays: law ids (R,), parameter rows (R, P_SIZE), buoyancy
        densities (R,); :class:`mjrft.regions.RegionTables`' ``law``, ``params``, ``rho``)."""
        params = np.atleast_2d(np.asarray(reg_params, dtype=np.float64))
        return cls(tuple(int(x) for x in np.unique(np.asarray(reg_law))), bool(np.any(params[:, P_INERTIA] > 0.0)),
                   bool(np.any(params[:, P_WATER_DEPTH] > 0.0)), bool(np.any(np.asarray(reg_rho) > 0.0)))


def _norm3(f):
    """``sqrt(fx^2 + fy^2 + fz^2)`` of each row, summed in the kernel's order."""
    return jnp.sqrt(f[:, 0] * f[:, 0] + f[:, 1] * f[:, 1] + f[:, 2] * f[:, 2])


def _finite3(f):
    return jnp.all(jnp.isfinite(f), axis=-1)


def inertial_force(p, depth, n, vel, area):
    """The inertial regime's force (k, 3) and its damper ``dF/du`` (k,) along the normal
    (:func:`mjrft.laws.inertial.inertial_force`): ``-min(1, depth / skin) C rho_bulk A (u^2 - v_c^2) n`` for a face
    pushed into the grains faster than ``v_c`` (``u = v . n``), zero when the regime is off (``p[P_INERTIA] = 0``),
    above the surface or slower."""
    cr = p[..., P_INERTIA]
    vc2 = p[..., P_INERTIA_VC2]
    u = vel[:, 0] * n[:, 0] + vel[:, 1] * n[:, 1] + vel[:, 2] * n[:, 2]
    on = ~((cr <= 0.0) | (depth <= 0.0) | (u * u <= vc2) | (u <= 0.0))
    w = jnp.minimum(1.0, depth / p[..., P_INERTIA_SKIN])
    k = w * cr * area
    f = k * (u * u - vc2)
    return jnp.where(on[:, None], -f[:, None] * n, 0.0), jnp.where(on, 2.0 * k * u, 0.0)


def buoyancy(rho_w, gravity, hw, depth, n, area):
    """Hydrostatic pressure on each element (k, 3): ``-rho_w g (depth + hw) A n`` below the water surface (``hw``
    above the sand), zero above it or without a buoyancy density (``rho_w = 0``)."""
    pres = rho_w * gravity * (depth + hw)
    return jnp.where((rho_w > 0.0) & (pres > 0.0), -pres * area, 0.0)[:, None] * n


def stiffness_of(f_mag, ml, delta, v_eps):
    """The linearised stiffness of an element force of size ``f_mag``: ``|F| / max(|m|, delta)``; in the viscous
    mode (``delta = 0``) the damping ``|F| / max(|v|, v_eps)``, 0 with ``v_eps = 0`` too
    (:func:`mjrft.forces.stiffness_of`)."""
    viscous = jnp.where(v_eps > 0.0, f_mag / jnp.maximum(ml, v_eps), 0.0)
    return jnp.where(delta > 0.0, f_mag / jnp.maximum(ml, delta), viscous)


def water_damping(kk, cw, delta, tau):
    """(stiffness, damping) of elements whose sand part has stiffness ``kk`` and water drag damping ``cw``
    (:func:`mjrft.kernel._with_water_damping`): with the rest memory the drag adds to the damping only
    (``kk tau + cw``); in the viscous mode ``kk`` is itself a damping and the drag adds to it."""
    memory = delta > 0.0
    both = kk + cw
    return jnp.where(memory, kk, both), jnp.where(memory, kk * tau + cw, both)


def _sand_stress(laws, law, depth, n, mhat, p, speed):
    """The stress of each element's sand law ``law`` among ``laws`` (ids without water): the one law alone, or a
    select over those present; an id outside them gives zero (as the kernel's dispatch gives an unknown id)."""
    if len(laws) == 1:
        return TWINS[laws[0]](depth, n, mhat, p, speed)
    out = jnp.zeros_like(n)
    for lid in laws:
        out = jnp.where((law == lid)[..., None], TWINS[lid](depth, n, mhat, p, speed), out)
    return out


def element_force(features: Features, law, p, rho_w, gravity, area, depth, n, m, ml, mob, vel, speed, delta, v_eps):
    """One region's force on each element (:func:`mjrft.forces.element_force`; module docstring for the returns).

    ``law`` the region's law id and ``p`` its parameter row (one for all elements, or one per element: (k,),
    (k, P_SIZE)), ``rho_w`` its buoyancy density (kg/m^3, 0: none), ``gravity`` (m/s^2), ``area`` (k,) the
    elements' area times the region's weight (m^2), ``depth`` (k,) below the sand surface (m), ``n`` (k, 3) unit
    outward normals, ``m`` (k, 3) the regularised motion with its length ``ml`` (k,) and mobilisation ``mob``
    (k,) (:func:`mjrft.mjx.memory.rest_memory`; ``ml = 0``: no sand force), ``vel`` (k, 3) and ``speed`` (k,)
    the real velocity and its size, ``delta`` / ``v_eps`` the rest memory's yield displacement / the viscous
    ramp's speed. Returns ``(force, stiffness, water damping, inertial damping, finite)``."""
    f = jnp.zeros_like(n)
    zero = jnp.zeros_like(depth)
    kk = cw = ci = zero
    ok = jnp.ones(depth.shape, bool)
    sand = tuple(x for x in features.laws if x != LAW_WATER)
    grains = (law != LAW_WATER) if LAW_WATER in features.laws else True  # open water has no sand law below it
    if sand:  # the sand, through the rest regularisation
        on = (ml > 0.0) & grains
        iml = 1.0 / jnp.where(on, ml, 1.0)
        fs = _sand_stress(sand, law, depth, n, m * iml[:, None], p, speed) * area[:, None]
        ok = ~on | _finite3(fs)
        kk = jnp.where(on, stiffness_of(_norm3(fs), ml, delta, v_eps), 0.0)
        f = jnp.where(on[:, None], fs * mob[:, None], 0.0)
    if features.inertia:  # the inertial regime (on the real velocity, no memory)
        on = jnp.broadcast_to((p[..., P_INERTIA] > 0.0) & grains, depth.shape)
        g, c = inertial_force(p, depth, n, vel, area)
        ok = ok & (~on | _finite3(g))
        f = f + jnp.where(on[:, None], g, 0.0)
        ci = jnp.where(on, c, 0.0)
    hw = p[..., P_WATER_DEPTH]
    if features.water:  # the water layer's drag
        on = (hw > 0.0) & (speed > 0.0) & (depth > -hw) & (depth < p[..., P_WATER_SKIN])
        iv = 1.0 / jnp.where(on, speed, 1.0)
        g = _laws.water(depth, n, vel * iv[:, None], p, speed) * area[:, None]
        ok = ok & (~on | _finite3(g))
        cw = jnp.where(on, 2.0 * _norm3(g) * iv, 0.0)  # d|F|/d|v| of a v^2 drag
        f = f + jnp.where(on[:, None], g, 0.0)
    if features.buoyancy:  # hydrostatic pressure below the water surface (sand surface + hw)
        f = f + buoyancy(rho_w, gravity, hw, depth, n, area)
    return f, kk, cw, ci, ok


def packed(reg_params, reg_dparams, r, pack):
    """The parameter rows of regions ``r`` (k,; or one region for all) at the elements' packing ``pack`` (k,; the
    ground memory's change of the loose-to-close weight from the prepared state, :mod:`mjrft.ground`):
    ``reg_params[r] + pack reg_dparams[r]`` (the kernel's ``_packed_rows``); ``reg_params[r]`` itself when ``pack``
    is None (no ground memory: nothing traced)."""
    if pack is None:
        return reg_params[r]
    return reg_params[r] + pack[:, None] * reg_dparams[r]  # (one region r: its row broadcast over the elements)


def blended_force(features: Features, regs, wts, reg_law, reg_params, reg_rho, gravity, area, depth, n, m, ml, mob,
                  vel, speed, delta, v_eps, pack=None, reg_dparams=None):
    """:func:`element_force` summed over each element's regions ``regs`` (k, S) with weights ``wts`` (k, S)
    (:func:`mjrft.mjx.surface.region_weights`; a slot of weight 0 adds nothing), the region tables ``reg_law``
    (R,), ``reg_params`` (R, P_SIZE), ``reg_rho`` (R,) (:func:`mjrft.forces.blended_force`; same returns). With a
    ground memory each region's row is taken at the element's packing ``pack`` (k,) with the regions' closely minus
    loosely packed rows ``reg_dparams`` (R, P_SIZE) (:func:`packed`).

    The S slots are evaluated as one batch of S k elements (each law traced once, whatever S) and summed slot by
    slot in the kernel's order."""
    k, slots = regs.shape
    r = regs.T.reshape(-1)  # slot-major: slot q of element i at q k + i
    w = wts.T.reshape(-1)

    def rep(x):
        return jnp.concatenate([x] * slots, axis=0)

    rows = packed(reg_params, reg_dparams, r, None if pack is None else rep(pack))
    out = element_force(features, reg_law[r], rows, reg_rho[r], gravity, rep(area) * w, rep(depth), rep(n),
                        rep(m), rep(ml), rep(mob), rep(vel), rep(speed), delta, v_eps)
    use = (w > 0.0).reshape(slots, k)
    f, kk, cw, ci = (jnp.where(use.reshape(slots, k, *([1] * (x.ndim - 1))), x.reshape(slots, k, *x.shape[1:]), 0.0)
                     for x in out[:4])
    ok = ~use | out[4].reshape(slots, k)
    tf, tk, tw, ti, tok = f[0], kk[0], cw[0], ci[0], ok[0]
    for q in range(1, slots):
        tf, tk, tw, ti, tok = tf + f[q], tk + kk[q], tw + cw[q], ti + ci[q], tok & ok[q]
    return tf, tk, tw, ti, tok


def region_force(features: Features, px, py, depth, n, m, ml, mob, vel, speed, area, *, reg_law, reg_params, reg_rho,
                 reg_bounds, reg_map, reg_map_frame, blend, gravity, delta, v_eps, pack=None, reg_dparams=None,
                 wake=None):
    """The general pass of the numba kernel on elements at ``(px, py)`` (k,): their regions and weights
    (:func:`mjrft.mjx.surface.region_weights`: strips or a map with transitions of width ``blend``) and the
    weighted sum of each region's :func:`element_force` (:func:`blended_force`). The region tables are the
    kernel's (:class:`mjrft.regions.RegionTables`: ``law``, ``params``, ``rho``, ``bounds``, ``map``,
    ``map_frame``); with one region there is no region work at all. Element arguments as :func:`element_force`
    (``area`` the elements' own). With a ground memory (:mod:`mjrft.ground`) ``pack`` (k,) is each element's packing
    as it read it and ``reg_dparams`` (R, P_SIZE) the regions' closely minus loosely packed rows: every region's row
    is taken at the element's packing (:func:`packed`, the kernel's ``_packed_rows``). With the ground memory's wake
    ``wake`` (k,) bool is whether each element moves into a body's wake (:meth:`mjrft.mjx.ground.Ground.in_wake`):
    a buried, moving element that lies in one region of the hybrid law and in the wake gets nothing (the hybrid law's
    undisturbed-grain rule as the kernel applies it: no force, stiffness or damping; None: no wake, nothing traced).
    Returns ``(force, stiffness, water damping, inertial damping, finite, region)``, ``region`` (k,) the region of
    each element's largest weight (the kernel's ``out_region``)."""
    dtype = depth.dtype
    reg_law = jnp.asarray(reg_law, jnp.int32)
    reg_params = jnp.asarray(reg_params, dtype)
    reg_rho = jnp.asarray(reg_rho, dtype)
    if pack is not None:
        reg_dparams = jnp.asarray(reg_dparams, dtype)
    if reg_law.shape[0] == 1:
        f, kk, cw, ci, ok = element_force(features, reg_law[0], packed(reg_params, reg_dparams, 0, pack), reg_rho[0],
                                          gravity, area, depth, n, m, ml, mob, vel, speed, delta, v_eps)
        out = (f, kk, cw, ci, ok)
        if wake is not None:
            out = _without_wake(out, wake & (reg_law[0] == LAW_HYBRID), depth, speed)
        return (*out, jnp.zeros(depth.shape, jnp.int32))
    regs, wts = region_weights(px, py, reg_bounds, reg_map, reg_map_frame, blend)
    out = blended_force(features, regs, wts, reg_law, reg_params, reg_rho, gravity, area, depth, n, m, ml, mob, vel,
                        speed, delta, v_eps, pack, reg_dparams)
    if wake is not None:  # an element in one region (weight 1 in its first slot) of the hybrid law
        out = _without_wake(out, wake & (wts[:, 0] >= 1.0) & (reg_law[regs[:, 0]] == LAW_HYBRID), depth, speed)
    return (*out, heaviest_region(regs, wts))


def _without_wake(out, hybrid_wake, depth, speed):
    """``(force, stiffness, water damping, inertial damping, finite)`` with nothing for the buried, moving elements
    in the wake of a hybrid region ``hybrid_wake`` (the kernel skips the rest of such an element: finite)."""
    skip = hybrid_wake & (depth > 0.0) & (speed > 0.0)
    f, kk, cw, ci, ok = out
    return (jnp.where(skip[:, None], 0.0, f), jnp.where(skip, 0.0, kk), jnp.where(skip, 0.0, cw),
            jnp.where(skip, 0.0, ci), ok | skip)


__all__ = ["Features", "LAW_WATER", "TWINS", "blended_force", "buoyancy", "element_force", "inertial_force",
           "packed", "region_force", "stiffness_of", "water_damping"]

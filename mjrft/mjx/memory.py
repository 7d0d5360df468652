"""The elements' rest memory in JAX, with the solidify option: the twins of :func:`mjrft.kernel._rest_memory` and
:func:`mjrft.laws.solidify.solid_memory`.

Pure, branch-free functions of element arrays (k elements), for ``jit`` and ``vmap`` in float32 or float64. The
memory's settings (``delta``, ``solid``) are Python numbers: they choose the mode when the step is traced (the
rest memory, its solidify option, or the viscous ramp), so a mode a terrain does not use costs nothing.
"""

from __future__ import annotations

import jax.numpy as jnp

from ..laws.solidify import STICK_SPEED


def _norm3(v):
    return jnp.sqrt(v[:, 0] * v[:, 0] + v[:, 1] * v[:, 1] + v[:, 2] * v[:, 2])


def _relaxed(u, vel, speed, a, delta):
    """The flowing update ``u <- delta v_hat + (u - delta v_hat) a`` where ``speed > 0`` (:func:`mjrft.laws.common.
    relax_memory`), ``u`` elsewhere."""
    moving = speed > 0.0
    sv = (delta / jnp.where(moving, speed, 1.0))[:, None] * vel
    return jnp.where(moving[:, None], sv + (u - sv) * a[:, None], u)


def solid_memory(u, vel, speed, dt, delta, tau, factor, stick=STICK_SPEED):
    """The memory under the solidify option (:func:`mjrft.laws.solidify.solid_memory`; ``delta > 0``, static yield
    factor ``factor >= 1``, at rest below the speed ``stick``): ``(u', m, |m|, mobilisation)``. At rest the memory
    follows the displacement, capped at ``factor delta``; moving, it relaxes as the rest memory does; the
    mobilisation is ``min(factor, |m| / delta, max(1, |u'| / delta))``, and a resting element below its static yield
    reports ``|m|`` shortened to ``delta`` (same direction). "Below" is by the kernel's relative margin of 1e-9, or in
    float32 by 16 ulp (1.9e-6): a memory capped at ``factor delta`` has its length rounded by about 1e-7 there, and
    it is at its static yield (reported as yielding, ``|m|`` kept)."""
    cap = factor * delta
    rest = speed < stick
    us = u + vel * dt
    ul = _norm3(us)
    over = ul > cap
    us = jnp.where(over[:, None], us * (cap / jnp.where(over, ul, 1.0))[:, None], us)
    flowing = _relaxed(u, vel, jnp.where(rest, 0.0, speed), jnp.exp(-speed * dt / delta), delta)
    u = jnp.where(rest[:, None], us, flowing)
    m = u + tau * vel
    ml = _norm3(m)
    mob = jnp.minimum(jnp.minimum(factor, ml / delta), jnp.maximum(1.0, _norm3(u) / delta))
    margin = max(1e-9, 16.0 * float(jnp.finfo(ml.dtype).eps))  # 1e-9, or 16 ulp: float32 rounds |u| at the cap
    below = rest & (ml > delta) & (ml < cap * (1.0 - margin))
    s = delta / jnp.where(below, ml, 1.0)
    return u, jnp.where(below[:, None], m * s[:, None], m), jnp.where(below, delta, ml), mob


def rest_memory(u, vel, speed, buried, dt, delta, tau, v_eps, solid=0.0, stick=STICK_SPEED):
    """Advance each element's memory ``u`` (k, 3) by ``dt`` at velocity ``vel`` (k, 3), ``speed`` = ``|vel|`` (k,),
    and return ``(u', m, |m|, mobilisation)``, what the law sees (docs/numerics.md, "Rest regularisation";
    :func:`mjrft.kernel._rest_memory` and the general pass around it): with ``delta > 0``
    ``u <- delta v_hat + (u - delta v_hat) exp(-|v| dt / delta)``, ``m = u + tau v``, mobilisation
    ``min(1, |m| / delta)``; with ``solid > 0`` the solidify option's memory instead (:func:`solid_memory`); in
    the viscous mode (``delta = 0``) ``m = v``, mobilisation ``min(1, |v| / v_eps)`` (1 with ``v_eps = 0``). An
    element not ``buried`` (k,) bool (out of the grains: depth <= 0) has no memory and no motion (all zero)."""
    delta = float(delta)
    if delta > 0.0:
        if float(solid) > 0.0:
            u, m, ml, mob = solid_memory(u, vel, speed, dt, delta, tau, float(solid), stick)
        else:
            u = _relaxed(u, vel, speed, jnp.exp(-speed * (dt / delta)), delta)
            m = u + tau * vel
            ml = _norm3(m)
            mob = jnp.minimum(1.0, ml * (1.0 / delta))
    else:
        m, ml = vel, speed
        mob = jnp.minimum(1.0, speed / v_eps) if float(v_eps) > 0.0 else jnp.ones_like(speed)
    b = buried[:, None]
    return (jnp.where(b, u, 0.0), jnp.where(b, m, 0.0), jnp.where(buried, ml, 0.0), jnp.where(buried, mob, 0.0))


__all__ = ["rest_memory", "solid_memory"]

"""Solidification under a resting intruder: a static yield above the flowing law (opt-in, every dry law).

RFT gives the stress of grains that flow around an intruder. Where an intruder comes to rest the grains
stop flowing and hold it as a solid until the stress exceeds their yield stress (robophysics thesis,
sec. 2 and 4.4.1: "granular media remains in a solid-like state providing constraint forces until the
external stress exceeds the yield stress of the material"). mjrft's rest memory (docs/numerics.md, "Rest
regularisation") already holds a resting element like a solid below yield, with the yield equal to the law's
flowing stress at the element's depth; an element that arrived by flowing is therefore held exactly at its
yield and the smallest extra load makes it flow again.

``GranularTerrain(solidify=f)`` (``f >= 1``; ``0``, the default, is off) lets an element that has come to
rest (speed below ``stick_speed``) hold up to ``f`` times the law's stress at its depth in the direction of
its displacement from where it stopped (its anchor):

```text
|v| <  v_s:  u <- u + v dt,  |u| <= f delta                    (solid: elastic about the anchor, capped)
|v| >= v_s:  u <- delta v_hat + (u - delta v_hat) exp(-|v| dt / delta)     (flowing: the rest memory)
m = u + tau v,   F = law(depth, n, m / |m|) * area * min(f, |m| / delta, max(1, |u| / delta))
```

Below the static yield the element is the rest memory's solid spring (stiffness ``|F_law| / delta``); at
``f delta`` it slides at ``f`` times the law; once it moves faster than ``v_s`` its memory relaxes back to
``delta`` over ``delta`` of travel, so a flowing element feels the law itself (steady intrusion, drag and
every validation rig that moves faster than ``v_s`` are unchanged) and softens from the static yield to the
flowing stress as it breaks loose. ``f = 1`` is the rest memory with an anchor that does not relax while at
rest (the thesis's own criterion, sec. 4.4.1: the RFT force is the yield criterion of a planted foot).

Stability: a solid element is the memory's spring ``k = |F_law| / delta`` (``F_law`` the law's stress at its
depth times its area); holding ``mu`` times ``F_law`` (``mu = |u| / delta`` up to ``f``) a body resting on such
elements has ``omega^2 = g / (mu delta)``, as the memory's resting body has below yield (docs/numerics.md,
"Stability limit"): stiffest below ``mu = 1``, as before, and softer between 1 and ``f``, so the explicit limit
is the memory's. The kernel reports a solid element below its static yield with ``|m|`` shortened to
``min(|m|, delta)`` (same direction), so its spring ``|F_law| / delta`` enters the stability check
(:mod:`mjrft.stability`) and the implicit step's springs like any element below yield; one at its static yield
is reported as yielding (``|m| = f delta``).

Cost: with ``solidify=0`` the kernel's rest memory runs one comparison more per buried element; the update
below runs only when it is on. CPU kernel only (mjrft.mjx refuses it).
"""

from __future__ import annotations

import math

from numba import njit

from .common import memory_motion, relax_memory

#: speed (m/s) below which an element counts as at rest: the rest memory's resting drift bound
#: (docs/numerics.md, "Rest": a placed body holds with drift < 1 mm/s); a documented choice for every scene
STICK_SPEED = 1e-3


def check_solidify(solidify, stick_speed):
    """Validate the option's two numbers; returns them as floats (``solidify`` 0 = off)."""
    try:
        f = float(solidify)
        vs = float(stick_speed)
    except (TypeError, ValueError):
        raise ValueError(f"solidify must be 0 (off) or a static yield factor >= 1 and stick_speed a speed > 0 "
                         f"(m/s), got solidify={solidify!r}, stick_speed={stick_speed!r}") from None
    if not (math.isfinite(f) and (f == 0.0 or f >= 1.0)):
        raise ValueError(f"solidify must be 0 (off) or a static yield factor >= 1 (times the law's stress), "
                         f"got {solidify!r}")
    if not (math.isfinite(vs) and vs > 0.0):
        raise ValueError(f"stick_speed must be a speed > 0 (m/s), got {stick_speed!r}")
    return f, vs


@njit(cache=True, error_model="numpy", inline="always")
def solid_memory(u, i, vx, vy, vz, speed, dt, delta, tau, factor, stick):
    """Advance element ``i``'s memory ``u[i]`` under the solidify option (module docstring; ``delta > 0``) and
    return what the law sees, as the rest memory does: (mx, my, mz, |m|, mobilisation ``min(factor, |m| /
    delta, max(1, |u| / delta))``). Below the static yield at rest the returned ``|m|`` is ``min(|m|, delta)`` (the direction is
    unchanged): the element is a spring of stiffness ``|F_law| / delta`` for the stability check and the
    implicit step."""
    cap = factor * delta
    if speed < stick:
        ux = u[i, 0] + vx * dt
        uy = u[i, 1] + vy * dt
        uz = u[i, 2] + vz * dt
        ul = math.sqrt(ux * ux + uy * uy + uz * uz)
        if ul > cap:
            s = cap / ul
            ux *= s
            uy *= s
            uz *= s
        u[i, 0], u[i, 1], u[i, 2] = ux, uy, uz
    elif speed > 0.0:
        relax_memory(u, i, vx, vy, vz, speed, math.exp(-speed * dt / delta), delta)
    mx, my, mz, ml = memory_motion(u, i, vx, vy, vz, tau)
    # above 1 only as far as the memory itself is (the damping term tau v never lifts a flowing element above the law)
    ul = math.sqrt(u[i, 0] * u[i, 0] + u[i, 1] * u[i, 1] + u[i, 2] * u[i, 2])
    mob = min(factor, ml / delta, max(1.0, ul / delta))
    if speed < stick and ml > delta and ml < cap * (1.0 - 1e-9):
        s = delta / ml  # a solid element below its static yield: a spring of stiffness |F_law| / delta
        return mx * s, my * s, mz * s, delta, mob
    return mx, my, mz, ml, mob

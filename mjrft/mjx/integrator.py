"""The integrator stage of an MJX step, as MuJoCo's C library integrates: :func:`integrate` and :func:`step`.

Under ``implicitfast`` MuJoCo treats the actuators' velocity feedback (a position servo's ``kv``, a velocity
servo's gain) implicitly: the step solves ``(M - dt D) qacc = f`` with ``D`` the derivative of the actuator
and damping forces with respect to ``qvel``. An actuator whose force is clamped by its ``forcerange`` exerts a
force that does not change with the velocity, and MuJoCo's C library leaves it out of ``D``; MJX's JAX
implementation (``mjx.implicit``, ``mujoco-mjx`` 3.17) keeps it. For a servo that saturates (the hexapod's
hips at ±0.3 N m, every time a leg is commanded ahead of its lag limit) the two then integrate different
dynamics: a hip under a clamped ``kv = 0.02`` with 1e-5 kg m^2 of armature ends milliradians apart after a
single 0.5 ms step. :func:`integrate` is MJX's integrator with MuJoCo's rule, so that :meth:`mjrft.mjx.Sand.step`
and the rigid twin (:func:`step`) follow the CPU path (``tests/mjrft/mjx/test_mjx.py`` steps a clamped servo
against ``mujoco.mj_step``, and the MJX hexapod env against the CPU env).
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np
from mujoco import mjx


def unclamped_model(m, d):
    """``m`` with the velocity gain of every actuator whose force ``d.actuator_force`` is clamped by its
    ``forcerange`` set to zero (``gainprm[2]`` and ``biasprm[2]``): what MuJoCo's C library differentiates.
    Only the integrator reads it; the forces are those of ``d``."""
    limited = m.actuator_forcelimited
    if isinstance(limited, np.ndarray) and not limited.any():  # (MJX keeps it as a host array: known at trace time)
        return m
    lo, hi = m.actuator_forcerange[:, 0], m.actuator_forcerange[:, 1]
    force = d.actuator_force
    clamped = jnp.asarray(limited, dtype=bool) & ((force <= lo) | (force >= hi))
    gain = jnp.asarray(m.actuator_gainprm)
    bias = jnp.asarray(m.actuator_biasprm)
    return m.replace(actuator_gainprm=gain.at[:, 2].set(jnp.where(clamped, 0.0, gain[:, 2])),
                     actuator_biasprm=bias.at[:, 2].set(jnp.where(clamped, 0.0, bias[:, 2])))


def integrate(m, d):
    """The model's integrator on ``d`` after the forward stages (``qacc`` computed): ``mjx.euler``, or
    ``mjx.implicit`` on :func:`unclamped_model` for ``implicitfast``. Refused: RK4 (the granular step would
    evaluate the rest memory four times per step) and the full ``implicit`` integrator (MJX has none)."""
    integrator = m.opt.integrator
    if integrator == mjx.IntegratorType.EULER:
        return mjx.euler(m, d)
    if integrator == mjx.IntegratorType.IMPLICITFAST:
        return mjx.implicit(unclamped_model(m, d), d)
    raise NotImplementedError(f"integrator {mjx.IntegratorType(integrator).name}: mjrft.mjx steps Euler and "
                              "implicitfast models (RK4 would evaluate the memory four times per step)")


def step(m, d):
    """``mjx.step`` that follows MuJoCo's C library for clamped servos (:func:`integrate` for an ``implicitfast``
    model under MJX's JAX implementation; ``mjx.step`` itself otherwise): the rigid twin of
    :meth:`mjrft.mjx.Sand.step`."""
    if m.impl != mjx.Impl.JAX or m.opt.integrator != mjx.IntegratorType.IMPLICITFAST:
        return mjx.step(m, d)
    return integrate(m, mjx.forward(m, d))

"""Check a JAX terrain against the CPU path on one's own model: record states on the CPU, evaluate them in JAX.

>>> states = record_states(model, terrain, steps=400, every=40, ctrl=lambda t: ...)   # CPU path (numba)
>>> errors = wrench_errors(Sand.from_terrain(terrain), model, states, x64=True)       # max relative differences

:func:`record_states` steps ``mj_step1`` / :meth:`~mjrft.GranularTerrain.compute` / ``mj_step2`` (the CPU path
with the wrench applied for the step) and keeps, every ``every`` steps, a copy of the ``MjData`` after
``mj_step1``, the elements' memory before the evaluation, and the kernel's wrench and memory after it.
:func:`wrench_errors` evaluates :meth:`Sand.wrench` on each recorded state with the recorded memory and returns
the largest difference of the wrench and of the memory, each relative to the largest value of the CPU result.
``benchmarks/mjx_accuracy.py`` and ``tests/mjrft/mjx/test_mjx.py`` use them on the hexapod.
"""

from __future__ import annotations

import functools

import copy
from typing import Callable, NamedTuple

import mujoco
import numpy as np

from ..coupler import GranularTerrain


class RecordedState(NamedTuple):
    """One recorded CPU step: ``data`` (a copy of the MjData after ``mj_step1``), ``u_before`` (the memory it was
    evaluated with), ``wrench`` and ``u_after`` (the kernel's result)."""

    data: mujoco.MjData
    u_before: np.ndarray
    wrench: np.ndarray
    u_after: np.ndarray


def record_states(model: mujoco.MjModel, terrain: GranularTerrain, steps: int, every: int,
                  ctrl: Callable[[float], np.ndarray] | None = None, data: mujoco.MjData | None = None
                  ) -> list[RecordedState]:
    """``steps`` CPU steps of ``model`` on ``terrain`` with ``data.ctrl = ctrl(time)`` before each (when given);
    a :class:`RecordedState` every ``every`` steps."""
    data = mujoco.MjData(model) if data is None else data
    out = []
    for k in range(steps):
        if ctrl is not None:
            data.ctrl[:] = ctrl(data.time)
        mujoco.mj_step1(model, data)
        u0 = terrain.terrain_state.u.copy()
        terrain.compute(data)
        if k % every == every - 1:
            out.append(RecordedState(copy.copy(data), u0, terrain.wrench.copy(), terrain.terrain_state.u.copy()))
        saved = data.xfrc_applied.copy()
        data.xfrc_applied[:] += terrain.wrench
        mujoco.mj_step2(model, data)
        data.xfrc_applied[:] = saved
    return out


def wrench_errors(sand, model: mujoco.MjModel, states: list[RecordedState], x64: bool) -> tuple[float, float]:
    """(wrench, memory): the largest ``|JAX - CPU|`` over the recorded states, each over the largest ``|CPU|``, with
    the JAX arrays in float64 (``x64``) or float32."""
    import jax
    import jax.numpy as jnp
    from mujoco import mjx

    ew = eu = 0.0
    with jax.enable_x64(x64):
        f = jax.jit(sand.wrench)
        for s in states:
            d = mjx.put_data(model, s.data)
            w, new = f(d, sand.init()._replace(u=jnp.asarray(s.u_before, d.xpos.dtype)), model.opt.timestep)
            ew = max(ew, _relative(np.asarray(w), s.wrench))
            eu = max(eu, _relative(np.asarray(new.u), s.u_after))
    return ew, eu


def _relative(a: np.ndarray, ref: np.ndarray) -> float:
    """``max |a - ref|`` over ``max |ref|``; where ``ref`` is all zero, 0 if ``a`` is too, else inf."""
    err, scale = float(np.abs(a - ref).max()), float(np.abs(ref).max())
    return err / scale if scale > 0.0 else (0.0 if err == 0.0 else np.inf)


def replay_steps(model: mujoco.MjModel, terrain_kwargs: dict, steps: int, every: int,
                 ctrl: Callable[[float], np.ndarray] | None = None) -> list[tuple]:
    """Walk ``model`` on the CPU path with the implicit granular step (``terrain.step(data, 1)``) for ``steps``
    steps; every ``every`` steps, replay that step from a copy of the MjData before it with the same memory on a
    second implicit terrain and on an explicit one. Returns ``[(data before, memory, implicit wrench, explicit
    wrench, qvel after the implicit step), ...]`` (the wrenches as applied: ``GranularTerrain.wrench``)."""
    walker, implicit, explicit = (GranularTerrain(model, implicit=i, **terrain_kwargs) for i in (True, True, False))
    data = mujoco.MjData(model)
    out = []
    for k in range(steps):
        if ctrl is not None:
            data.ctrl[:] = ctrl(data.time)
        if k % every == every - 1:
            before, u = copy.copy(data), walker.terrain_state.u.copy()
            rows = []
            for terrain in (implicit, explicit):
                replay = copy.copy(before)
                terrain.bind(replay)  # binding to another MjData forgets the memory: set it after
                terrain.terrain_state.u[:] = u
                terrain.step(replay, 1)
                rows.append((terrain.wrench.copy(), replay.qvel.copy()))
            out.append((before, u, rows[0][0], rows[1][0], rows[0][1]))
        walker.step(data, 1)
    return out


@functools.lru_cache(maxsize=8)
def _stand_run(sand, steps: int):
    """The jitted ``lax.scan`` of ``steps`` ``sand.step`` calls (one per terrain and length: a second :func:`stand`
    with them compiles nothing)."""
    import jax

    def body(carry, mx):
        d, state = sand.step(mx, *carry)
        return (d, state), state.wrench[:, 2].sum()

    return jax.jit(lambda mx, d, s: jax.lax.scan(lambda c, _: body(c, mx), (d, s), None, length=steps))


def stand(sand, model: mujoco.MjModel, qpos, ctrl, seconds: float, state=None):
    """Hold ``ctrl`` from ``qpos`` for ``seconds`` with ``sand.step`` (one jitted ``lax.scan``, compiled once per
    terrain and length) from ``state`` (default ``sand.init()``); returns (the last mjx.Data, the last SandState, the
    net vertical granular force over the weight at every step)."""
    import jax.numpy as jnp
    from mujoco import mjx

    mx = sand.put_model()
    d0 = mjx.make_data(mx).replace(qpos=jnp.asarray(qpos), ctrl=jnp.asarray(ctrl))
    steps = int(round(seconds / model.opt.timestep))
    (d, state), fz = _stand_run(sand, steps)(mx, d0, sand.init() if state is None else state)
    weight = float(model.body_subtreemass[0]) * -float(model.opt.gravity[2])
    return d, state, np.asarray(fz) / weight

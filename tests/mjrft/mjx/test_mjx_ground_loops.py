"""The ground memory's batched control flow (mjrft.mjx.ground): ``when`` runs its update for a batch only on a step
where some world updates, and gives each world what ``lax.cond`` would; JAX's own batched ``lax.cond`` (the control)
runs the update on every step."""

from __future__ import annotations

import numpy as np
import pytest

jax = pytest.importorskip("jax", reason="mjrft.mjx needs the optional extra mjrft[mjx] (JAX)")
pytest.importorskip("mujoco.mjx", reason="mjrft.mjx needs mujoco-mjx (mjrft[mjx])")

import jax.numpy as jnp  # noqa: E402

from mjrft.mjx.ground import when  # noqa: E402

CALLS = []


def _update(g, args):
    """A stand-in for the ground's update: records that it ran, and leaves ``g`` unchanged where
    the world's ``do`` is False, as the update must."""
    x, do = args
    jax.debug.callback(lambda: CALLS.append(1))
    return jnp.where(do, g * 2.0 + x, g)


def _run(step, do):
    CALLS.clear()
    g = jnp.arange(4.0)
    out = jax.jit(jax.vmap(step))(g, (jnp.full(4, 0.5), jnp.asarray(do)))
    jax.block_until_ready(out)
    jax.effects_barrier()
    return np.asarray(out), len(CALLS)


def test_when_skips_the_update_where_no_world_updates_and_equals_lax_cond():
    def ours(g, args):
        return when(args[1], _update, g, args)

    def lax_cond(g, args):  # the control: JAX's batched rule for a condition with a batched predicate
        return jax.lax.cond(args[1], _update, lambda g, _: g, g, args)

    out, calls = _run(ours, [False] * 4)
    np.testing.assert_array_equal(out, np.arange(4.0))
    assert calls == 0  # no world updates: the update never ran
    ref, ref_calls = _run(lax_cond, [False] * 4)
    np.testing.assert_array_equal(ref, out)
    assert ref_calls > 0  # JAX's rule runs it anyway and selects: what when avoids

    mixed = [True, False, True, False]
    out, calls = _run(ours, mixed)
    ref, _ = _run(lax_cond, mixed)
    np.testing.assert_array_equal(out, [0.5, 1.0, 4.5, 3.0])  # 2 g + 0.5 where the world updates, g elsewhere
    np.testing.assert_array_equal(out, ref)
    assert calls > 0  # some world updates: the whole batch runs it

    # without vmap, a plain lax.cond
    one = jax.jit(lambda g, x, do: when(do, _update, g, (x, do)))
    assert float(one(3.0, 0.5, True)) == 6.5 and float(one(3.0, 0.5, False)) == 3.0

"""The JAX path's guards: what :class:`mjrft.mjx.Sand` watches inside every step, and reports on the host.

The CPU terrain's checks (:mod:`mjrft.watch`, :mod:`mjrft.stability`, :mod:`mjrft.laws.validity`; derived in
docs/numerics.md) as pure, branch-free JAX functions of one world's step, so that they run inside ``jit``,
``vmap`` and ``scan`` with every world's record kept in its :class:`~mjrft.mjx.SandState`:

* ``springs``: the explicit step's stability limit of the grains' springs. The element pass sums per body the
  moments of each element's linearised stiffness ``k = |F_yield| / max(|m|, delta)`` (the damper
  ``|F_yield| / max(|v|, v_eps)`` in the viscous mode) about its centre of mass, as the numba kernel does; with
  the body's 6x6 mobility ``W6 = J M^-1 J^T`` (its CoM jacobian and MJX's mass-matrix factor) the rate of its
  stiffest mode is ``lambda = lambda_max(W6 K6)`` (:func:`largest_rate`). A body fires when a stiffness held
  ``HELD_STEPS`` steps (the smallest rate of the last ``HELD_STEPS`` steps) makes a step amplify a perturbation
  at all (its timestep beyond :func:`max_stable_dt`: the growth factor's threshold 1 without the cancellation
  float32 would add to it), or a single step amplifies it more than ``SPIKE_GROWTH`` (:func:`step_growth`), the
  CPU terrain's rule.
  Not with the implicit step, which it does not bound (the CPU terrain's rule too).
* ``depth_stiffness``: the depth stiffness's limit (vertical springs ``|F| / depth``, explicit in every mode):
  a step fires when its timestep exceeds ``sqrt(2) / omega``, ``omega^2 = lambda_max(W6 Kd6)``.
* ``chatter``: a body whose applied granular force reversed its change on ``CHATTER_STEPS`` consecutive steps,
  each change above ``CHATTER_AMPLITUDE`` of the force (:func:`track_chatter`, the CPU's rule), in either mode.
* ``depth_range`` and ``speed_range``: the deepest and the fastest buried element beyond the law's calibrated
  range (:func:`mjrft.laws.validity.dynamic_ranges`), counted on every step.

The difference from the CPU terrain: the CPU terrain sums the moments every step and evaluates the limits every
``STABILITY_CHECK_EVERY`` steps with the mobility of that moment (the least stiff of the last ``HELD_STEPS``
steps' moments, the stiffest single step's); here every step's limit is evaluated with that step's mobility, and
the held state is the smallest of the last ``HELD_STEPS`` steps' rates. The largest eigenvalue comes from
``SQUARINGS`` repeated squarings of ``W6 K6`` (6x6 matrix products only, no eigensolver): it is a weighted mean of
the eigenvalues with weights ``lambda_i^N``, ``N = 2^SQUARINGS``, low by at most ``1 / (e N)`` of the largest
(1.4e-3 with 8 squarings; the limits by half that).

Per world the state keeps, for each guard of :data:`GUARDS`, the number of steps on which it fired
(``guard_count``), the first body and time (``guard_body``, ``guard_time``), and its worst value
(``guard_value``, two numbers per guard: :data:`VALUE_COLUMNS`); ``stable_dt`` holds the last step's smallest
limits (springs, depth stiffness), which :meth:`mjrft.mjx.Sand.auto_step` sub-steps with
(:func:`substeps_for`, the rule of :class:`mjrft.envs.GranularWrapper`). :func:`flags` gives the per-world
flags inside ``jit`` (for an environment's ``done`` and ``metrics``), :func:`check_guards` the host's warnings.
"""

from __future__ import annotations

import math
import warnings
from typing import NamedTuple

import jax
import jax.numpy as jnp
import mujoco
import numpy as np

from ..errors import TerrainStabilityWarning, ValidityRangeWarning
from ..laws import validity
from ..stability import CHATTER_AMPLITUDE, CHATTER_STEPS, HELD_STEPS, SPIKE_GROWTH

HIGHEST = jax.lax.Precision.HIGHEST

#: the guards, in the order of the state's ``guard_*`` arrays
GUARDS = ("springs", "depth_stiffness", "chatter", "depth_range", "speed_range")
SPRINGS, DEPTH_STIFFNESS, CHATTER, DEPTH_RANGE, SPEED_RANGE = range(len(GUARDS))
#: what the two columns of ``guard_value`` hold per guard (the worst step's)
VALUE_COLUMNS = {"springs": ("stable timestep (s)", "timestep (s)"),
                 "depth_stiffness": ("stable timestep (s)", "timestep (s)"),
                 "chatter": ("largest change / force", "force (N)"),
                 "depth_range": ("deepest buried element (m)", "time (s)"),
                 "speed_range": ("fastest buried element (m/s)", "time (s)")}
#: squarings of W6 K6 for its largest eigenvalue (module docstring: low by at most 1 / (e 2^SQUARINGS))
SQUARINGS = 8
#: entries of the normalised power below this are set to zero (their products stay normal numbers in float32)
FLUSH = 1e-18
#: the automatic sub-step's fraction of the stable timestep and, with the implicit step, the largest angle of
#: the stiffest spring per sub-step: the values of :class:`mjrft.envs.GranularWrapper`'s rule (its SAFETY and
#: SPRING_STEP; ``tests/mjrft/mjx/test_mjx_guards.py`` keeps them equal)
SAFETY = 0.5
SPRING_STEP = 1.0
#: the most sub-steps :meth:`mjrft.mjx.Sand.auto_step` takes by default (GranularWrapper's ``max_substeps``)
MAX_SUBSTEPS = 64
#: the per-body chatter record: last force (0:3), its last change (3:6), the current run of reversals (6), the
#: largest relative change in that run (7)
CHATTER_SLOTS = 8


# ---------------------------------------------------------------------------------------------- the stiffness
def monomials(r: jax.Array) -> jax.Array:
    """(n, 10): ``1, r_x, r_y, r_z, r_x r_x, r_x r_y, r_x r_z, r_y r_y, r_y r_z, r_z r_z`` of lever arms ``r``
    (n, 3): the kernel's moments (:func:`mjrft.kernel._add_moments`) of unit springs."""
    rx, ry, rz = r[:, 0], r[:, 1], r[:, 2]
    return jnp.stack([jnp.ones_like(rx), rx, ry, rz, rx * rx, rx * ry, rx * rz, ry * ry, ry * rz, rz * rz], axis=-1)


class MomentTable(NamedTuple):
    """The constant tables of :func:`body_moments` and :func:`buried_extremes`: the elements are sorted by body (as
    :mod:`mjrft.build` makes them), ``spans`` holds each body's (first, last + 1) element (``rows`` order) and
    ``mono`` (n, 10) each element's ``(1, rho, rho rho^T)`` (:func:`monomials` of its lever arm ``rho`` from its
    body's centre of mass, in the body's frame)."""

    spans: tuple
    mono: np.ndarray


def moment_table(model, elem_body: np.ndarray, lpos: np.ndarray, rows: np.ndarray) -> MomentTable:
    """The :class:`MomentTable` of elements on bodies ``elem_body`` (sorted) at ``lpos`` (body frame), for the bodies
    ``rows``: ``rho_i = lpos_i - body_ipos_b`` (``r_i = R_b rho_i`` in the world)."""
    elem_body = np.asarray(elem_body)
    if np.any(np.diff(elem_body) < 0):
        raise ValueError("the guards' tables need the elements sorted by body")
    rho = np.asarray(lpos, dtype=np.float64) - np.asarray(model.body_ipos)[elem_body]
    x, y, z = rho[:, 0], rho[:, 1], rho[:, 2]
    mono = np.stack([np.ones_like(x), x, y, z, x * x, x * y, x * z, y * y, y * z, z * z], axis=-1)
    spans = tuple((int(np.searchsorted(elem_body, b)), int(np.searchsorted(elem_body, b, side="right")))
                  for b in rows)
    return MomentTable(spans, mono)


def element_weights(f: jax.Array, ml: jax.Array, depth: jax.Array, buried: jax.Array) -> jax.Array:
    """(2, n): each element's linearised stiffness ``k`` and its depth stiffness ``kd = |F| / depth`` (0 where not
    buried), from its force ``f`` (n, 3) as applied, ``|m|`` ``ml`` (n,; 0 for an element that does not move) and
    ``depth``. mjrft.kernel's ``_linear_stiffness`` is ``|F_yield| / max(|m|, delta)`` with the force at full
    mobilisation ``F = F_yield min(1, |m| / delta)``: that is ``|F| / |m|`` (the damper ``|F_yield| / max(|v|,
    v_eps)`` of the viscous mode too, ``|m| = |v|``)."""
    fm = jnp.sqrt(jnp.sum(f * f, axis=-1))
    moving = ml > 0.0
    return jnp.stack([jnp.where(moving, fm / jnp.where(moving, ml, 1.0), 0.0),
                      jnp.where(buried, fm / jnp.where(buried, depth, 1.0), 0.0)])


def body_moments(weights: jax.Array, table: MomentTable) -> jax.Array:
    """Each body's moments (w, nb, 10) in its own frame (``sum k``, ``sum k rho``, ``sum k rho rho^T``) of per-element
    weights (w, n): one small product per body over its span of elements with their constant monomials (20
    multiply-adds per element and weight pair; no per-element array of moments, no gather, no scatter)."""
    mono = jnp.asarray(table.mono, weights.dtype)
    return jnp.stack([jnp.matmul(weights[:, a:b], mono[a:b], precision=HIGHEST) for a, b in table.spans], axis=1)


def buried_extremes(sinkage: jax.Array, speed2: jax.Array, table: MomentTable, rows: np.ndarray):
    """(deepest depth, its body, largest speed, its body) of the buried elements, from each body's deepest element
    ``sinkage`` (nbody,) and the buried elements' squared speed ``speed2`` (n,; 0 elsewhere): mjrft.laws.validity's
    ``buried_extremes``, by each body's maximum over its span (no reduction with an index over the elements);
    (0, -1) with nothing buried."""
    per_body = jnp.stack([sinkage[jnp.asarray(rows)],
                          jnp.stack([jnp.max(speed2[a:b]) for a, b in table.spans])])  # (2, nb)
    k = jnp.argmax(per_body, axis=1)
    top = per_body[jnp.arange(2), k]
    bodies = jnp.where(top > 0.0, jnp.asarray(rows, jnp.int32)[k], -1)
    return top[0], bodies[0], jnp.sqrt(top[1]), bodies[1]


def rotate_moments(local: jax.Array, rot: jax.Array) -> jax.Array:
    """Moments (..., 10) about the centre of mass in the world frame from those in the body's frame ``local`` and
    the body's orientation ``rot`` (..., 3, 3): ``sum k`` unchanged, ``sum k r = R sum k rho``, ``sum k r r^T =
    R (sum k rho rho^T) R^T``."""
    s0 = local[..., 0]
    s1 = jnp.sum(rot * local[..., None, 1:4], axis=-1)
    xx, xy, xz, yy, yz, zz = (local[..., i] for i in range(4, 10))
    s2 = jnp.stack([jnp.stack([xx, xy, xz], -1), jnp.stack([xy, yy, yz], -1), jnp.stack([xz, yz, zz], -1)], -2)
    w = _mm(_mm(rot, s2), jnp.swapaxes(rot, -1, -2))
    return jnp.stack([s0, s1[..., 0], s1[..., 1], s1[..., 2], w[..., 0, 0], w[..., 0, 1], w[..., 0, 2], w[..., 1, 1],
                      w[..., 1, 2], w[..., 2, 2]], axis=-1)


def k6(moments: jax.Array) -> jax.Array:
    """The 6x6 (..., 6, 6) of springs acting in every direction with the moments (..., 10) ``sum k``,
    ``sum k r``, ``sum k r r^T`` (``xx xy xz yy yz zz``) about a body's CoM: rows and columns 0-2 translation,
    3-5 rotation (mjrft.stability's ``add_k6``)::

        K6 = [[ s0 I,    -[S1]x           ],
              [ [S1]x,   tr(S2) I - S2    ]]
    """
    s0 = moments[..., 0]
    x, y, z = moments[..., 1], moments[..., 2], moments[..., 3]
    xx, xy, xz, yy, yz, zz = (moments[..., i] for i in range(4, 10))
    o = jnp.zeros_like(s0)
    tr = xx + yy + zz
    rows = [[s0, o, o, o, z, -y],
            [o, s0, o, -z, o, x],
            [o, o, s0, y, -x, o],
            [o, -z, y, tr - xx, -xy, -xz],
            [z, o, -x, -xy, tr - yy, -yz],
            [-y, x, o, -xz, -yz, tr - zz]]
    return jnp.stack([jnp.stack(r, axis=-1) for r in rows], axis=-2)


def vertical_k6(moments: jax.Array) -> jax.Array:
    """The 6x6 (..., 6, 6) of vertical springs with the moments (..., 10) (those with z do not enter):
    mjrft.stability's ``add_vertical_k6``, ``phi = (e_z, r x e_z)``, ``K6 = sum k phi phi^T``."""
    s0, x, y = moments[..., 0], moments[..., 1], moments[..., 2]
    xx, xy, yy = moments[..., 4], moments[..., 5], moments[..., 7]
    o = jnp.zeros_like(s0)
    rows = [[o, o, o, o, o, o],
            [o, o, o, o, o, o],
            [o, o, s0, y, -x, o],
            [o, o, y, yy, -xy, o],
            [o, o, -x, -xy, xx, o],
            [o, o, o, o, o, o]]
    return jnp.stack([jnp.stack(r, axis=-1) for r in rows], axis=-2)


def mobilities(jac: jax.Array, minv_jt: jax.Array, nb: int) -> jax.Array:
    """Each body's 6x6 mobility ``W6 = J_b M^-1 J_b^T`` (nb, 6, 6) from the stacked CoM jacobians ``jac``
    (6 nb, nv) and ``M^-1 J^T`` (nv, 6 nb) (:meth:`mjrft.mjx.Sand.com_jacobians`), symmetrised."""
    j = jac.reshape(nb, 6, -1)
    mj = minv_jt.T.reshape(nb, 6, -1)
    w = jnp.sum(j[:, :, None, :] * mj[:, None, :, :], axis=-1)
    return 0.5 * (w + jnp.swapaxes(w, -1, -2))


def _mm(a: jax.Array, b: jax.Array) -> jax.Array:
    """``a @ b`` of small matrices (..., n, n) as a broadcast product and sum: one fused loop (XLA's batched dot
    costs ten times more on a CPU for 6x6 matrices), in full precision on any device."""
    return jnp.sum(a[..., :, :, None] * b[..., None, :, :], axis=-2)


def largest_rate(w6: jax.Array, k6m: jax.Array) -> jax.Array:
    """Largest eigenvalue (...,) of ``W K`` (both (..., n, n), symmetric positive semi-definite, so its
    eigenvalues are real and >= 0; ``n = 6`` for W6 K6): mjrft.stability's ``largest_rate``, by ``SQUARINGS``
    normalised squarings ``Q = P^N / tr(P^N)`` of ``P = W K`` and ``tr(P Q) = sum lambda^(N+1) / sum lambda^N``
    (module docstring); 0 without stiffness."""
    p = _mm(w6, k6m)
    scale = jnp.trace(p, axis1=-2, axis2=-1)
    live = scale > 0.0
    q = p / jnp.where(live, scale, 1.0)[..., None, None]
    for _ in range(SQUARINGS):
        q = _mm(q, q)
        t = jnp.trace(q, axis1=-2, axis2=-1)
        q = q / jnp.where(t > 0.0, t, 1.0)[..., None, None]
        # entries below FLUSH of a matrix of trace 1 go to zero: they weigh nothing in the estimate, and the powers of
        # the small eigenvalues would otherwise pass through subnormal numbers, which CPUs compute far slower
        q = jnp.where(jnp.abs(q) < FLUSH, 0.0, q)
    lam = jnp.sum(p * jnp.swapaxes(q, -1, -2), axis=(-2, -1))  # tr(P Q)
    return jnp.where(live, jnp.maximum(lam, 0.0), 0.0)


def vertical_k3(moments: jax.Array) -> jax.Array:
    """The nonzero 3x3 block (..., 3, 3) of :func:`vertical_k6` (rows and columns 2, 3, 4: z, rotation about x and
    y): ``lambda_max(W6 Kd6) = lambda_max(W3 Kd3)`` with ``W3`` the same block of ``W6``."""
    s0, x, y = moments[..., 0], moments[..., 1], moments[..., 2]
    xx, xy, yy = moments[..., 4], moments[..., 5], moments[..., 7]
    rows = [[s0, y, -x], [y, yy, -xy], [-x, -xy, xx]]
    return jnp.stack([jnp.stack(r, axis=-1) for r in rows], axis=-2)


def spring(lam, delta: float, tau: float):
    """(K, c) per unit mass of the stiffest mode of rate ``lam``: mjrft.stability's ``spring`` (the viscous mode,
    ``delta = 0``: a damper of rate ``lam``)."""
    if delta > 0.0:
        return lam, tau * lam
    return jnp.zeros_like(lam), lam


def max_stable_dt(K, c):
    """mjrft.stability's ``max_stable_dt`` with ``w = 1``: ``2 (sqrt(1 + zeta^2) - zeta) / omega`` (written
    ``2 / (omega (sqrt(1 + zeta^2) + zeta))``, exact for a large ``zeta``), ``2 / c`` without stiffness, ``inf``
    with neither."""
    stiff = K > 0.0
    omega = jnp.sqrt(jnp.where(stiff, K, 1.0))
    zeta = 0.5 * c / omega
    with_k = 2.0 / (omega * (jnp.sqrt(1.0 + zeta * zeta) + zeta))
    damped = c > 0.0
    without = jnp.where(damped, 2.0 / jnp.where(damped, c, 1.0), jnp.inf)
    return jnp.where(stiff, with_k, without)


def step_growth(K, c, dt):
    """mjrft.stability's ``step_growth`` with ``w = 1``: the spectral radius of one semi-implicit Euler step of a
    spring ``K`` with damper ``c`` (> 1: unstable)."""
    a2, b = K * dt * dt, c * dt
    p, q = 2.0 - a2 - b, 1.0 - b
    disc = p * p - 4.0 * q
    real = disc >= 0.0
    r = jnp.sqrt(jnp.where(real, disc, 0.0))
    return jnp.where(real, 0.5 * jnp.maximum(jnp.abs(p + r), jnp.abs(p - r)), jnp.sqrt(jnp.where(real, 1.0, q)))


def depth_stable_dt(lam):
    """mjrft.stability's ``depth_stable_dt``: ``sqrt(2 / lam)`` (inf without stiffness)."""
    live = lam > 0.0
    return jnp.where(live, jnp.sqrt(2.0 / jnp.where(live, lam, 1.0)), jnp.inf)


# ---------------------------------------------------------------------------------------------- the trackers
def track_chatter(record: jax.Array, force: jax.Array) -> jax.Array:
    """mjrft.stability's ``track_chatter`` for every body at once: the new record (nbody, CHATTER_SLOTS) from the
    last one and this step's applied granular force (nbody, 3)."""
    last, change = record[:, 0:3], record[:, 3:6]
    d = force - last
    d2 = jnp.sum(d * d, axis=-1)
    p2 = jnp.sum(change * change, axis=-1)
    f2 = jnp.maximum(jnp.sum(force * force, axis=-1), jnp.sum(last * last, axis=-1))
    big = (d2 > CHATTER_AMPLITUDE * CHATTER_AMPLITUDE * f2) & (f2 > 0.0)
    turned = jnp.sum(d * change, axis=-1) < -0.5 * jnp.sqrt(d2 * p2)
    rev = big & turned
    rel = jnp.sqrt(d2 / jnp.where(f2 > 0.0, f2, 1.0))
    run = jnp.where(rev, record[:, 6] + 1.0, 0.0)
    peak = jnp.where(rev, jnp.maximum(record[:, 7], rel), 0.0)
    return jnp.concatenate([force, d, run[:, None], peak[:, None]], axis=-1)


def _first(mask: jax.Array, ids) -> jax.Array:
    """The first id whose ``mask`` is set (-1 if none), int32."""
    return jnp.where(jnp.any(mask), jnp.asarray(ids, jnp.int32)[jnp.argmax(mask)], -1).astype(jnp.int32)


def record(state, fired: jax.Array, body: jax.Array, value: jax.Array, worse: jax.Array, time):
    """``state`` with its guards' record advanced by one step: per guard (:data:`GUARDS`) ``fired`` (bool),
    the body (int32), the two values (2,) of this step and whether they are worse than the ones kept."""
    first = fired & (state.guard_body == -1)
    keep = fired & worse
    return state._replace(
        guard_count=state.guard_count + fired.astype(state.guard_count.dtype),
        guard_body=jnp.where(first, body, state.guard_body).astype(jnp.int32),
        guard_time=jnp.where(first, jnp.asarray(time, state.guard_time.dtype), state.guard_time),
        guard_value=jnp.where(keep[:, None], value.astype(state.guard_value.dtype), state.guard_value))


class Guards:
    """The static settings of one terrain's guards (built by :class:`mjrft.mjx.Sand`): ``rows`` the bodies with
    elements, ``delta`` / ``tau`` the rest memory's settings (``delta = 0``: the viscous mode), ``implicit``,
    and the law's dynamic ranges."""

    def __init__(self, rows: np.ndarray, nbody: int, delta: float, tau: float, implicit: bool, law: str,
                 inertial: bool = False):
        self.rows = np.asarray(rows, dtype=np.int32)
        self.nbody = int(nbody)
        self.delta = float(delta)
        self.tau = float(tau)
        self.implicit = bool(implicit)
        self.law = law
        ranges = {r.quantity: r for r in validity.dynamic_ranges(law, inertial)}
        self.ranges = ranges
        inf = math.inf
        self.depth_bounds = (ranges["depth"].low if "depth" in ranges and ranges["depth"].low is not None else -inf,
                             ranges["depth"].high if "depth" in ranges and ranges["depth"].high is not None else inf)
        self.speed_bounds = (ranges["speed"].low if "speed" in ranges and ranges["speed"].low is not None else -inf,
                             ranges["speed"].high if "speed" in ranges and ranges["speed"].high is not None else inf)

    def init_fields(self, dtype=None) -> dict:
        """The guard fields of a fresh :class:`~mjrft.mjx.SandState`."""
        f = jnp.zeros(()).dtype if dtype is None else dtype
        n = len(GUARDS)
        value = jnp.zeros((n, 2), f).at[SPRINGS].set(jnp.array([jnp.inf, 1.0], f)).at[DEPTH_STIFFNESS].set(
            jnp.array([jnp.inf, 1.0], f))
        nb = self.rows.size
        return dict(rates=jnp.zeros((nb, HELD_STEPS), f), chatter=jnp.zeros((nb, CHATTER_SLOTS), f),
                    stable_dt=jnp.full(2, jnp.inf, f), substeps=jnp.array(1, jnp.int32),
                    guard_count=jnp.zeros(n, jnp.int32), guard_body=jnp.full(n, -1, jnp.int32),
                    guard_time=jnp.zeros(n, f), guard_value=value)

    def limits(self, w6: jax.Array, stiff: jax.Array, dstiff: jax.Array) -> tuple[jax.Array, jax.Array]:
        """Per body with elements (``rows`` order) the springs' rate ``lambda`` and the depth stiffness's
        ``omega^2``, from the mobilities ``w6`` (nb, 6, 6) and the moments ``stiff``, ``dstiff`` (nb, 10)."""
        return largest_rate(w6, k6(stiff)), largest_rate(w6[..., 2:5, 2:5], vertical_k3(dstiff))

    def update(self, state, time, dt, wrench: jax.Array, extremes, lam=None, lam_d=None):
        """``state`` after one step at ``time`` (its start) with timestep ``dt``: the applied ``wrench`` (nbody, 6)
        for chatter, ``extremes`` = (deepest buried depth, its body, fastest buried speed, its body) for the
        ranges, and (with the model's dynamics; None otherwise) the rates ``lam`` and ``lam_d`` of the bodies with
        elements (:meth:`limits`) for the stability limits."""
        dtype = state.guard_value.dtype
        rows = self.rows
        dt = jnp.asarray(dt, dtype)
        n = len(GUARDS)
        fired = [jnp.array(False)] * n
        body = [jnp.array(-1, jnp.int32)] * n
        value = [jnp.zeros(2, dtype)] * n
        worse = [jnp.array(False)] * n
        if lam is not None:
            hist = jnp.concatenate([lam[:, None].astype(dtype), state.rates[:, :-1]], axis=1)  # newest first
            K, c = spring(lam, self.delta, self.tau)
            limit = max_stable_dt(K, c)
            limit_d = depth_stable_dt(lam_d)
            state = state._replace(rates=hist,
                                   stable_dt=jnp.stack([jnp.min(limit, initial=jnp.inf),
                                                        jnp.min(limit_d, initial=jnp.inf)]).astype(dtype))
            if not self.implicit:
                held = jnp.min(hist, axis=1)  # a step amplifies at all (growth > 1) iff it exceeds the limit:
                bad = (dt > max_stable_dt(*spring(held, self.delta, self.tau))) & (held > 0.0)  # no cancellation
                bad = bad | ((step_growth(K, c, dt) > SPIKE_GROWTH * (1.0 + 1e-12)) & (lam > 0.0))
                worst = jnp.min(jnp.where(bad, limit, jnp.inf))
                fired[SPRINGS], body[SPRINGS] = jnp.any(bad), _first(bad, rows)
                value[SPRINGS] = jnp.stack([worst, dt])
                worse[SPRINGS] = worst / dt < state.guard_value[SPRINGS, 0] / state.guard_value[SPRINGS, 1]
            bad_d = dt > limit_d
            worst_d = jnp.min(jnp.where(bad_d, limit_d, jnp.inf))
            fired[DEPTH_STIFFNESS], body[DEPTH_STIFFNESS] = jnp.any(bad_d), _first(bad_d, rows)
            value[DEPTH_STIFFNESS] = jnp.stack([worst_d, dt])
            worse[DEPTH_STIFFNESS] = (worst_d / dt < state.guard_value[DEPTH_STIFFNESS, 0]
                                      / state.guard_value[DEPTH_STIFFNESS, 1])
        chat = track_chatter(state.chatter, wrench[rows, :3].astype(dtype))
        state = state._replace(chatter=chat)
        on = chat[:, 6] >= CHATTER_STEPS
        k = jnp.argmax(jnp.where(on, chat[:, 7], -1.0))
        fired[CHATTER], body[CHATTER] = jnp.any(on), _first(on, rows)
        value[CHATTER] = jnp.stack([chat[k, 7], jnp.sqrt(jnp.sum(chat[k, 0:3] ** 2))])
        worse[CHATTER] = chat[k, 7] > state.guard_value[CHATTER, 0]
        depth, depth_body, speed, speed_body = extremes
        buried = depth > 0.0
        for g, v, b, (lo, hi) in ((DEPTH_RANGE, depth, depth_body, self.depth_bounds),
                                  (SPEED_RANGE, speed, speed_body, self.speed_bounds)):
            out = buried & ((v > hi) | (v < lo))
            fired[g], body[g] = out, jnp.where(out, b, -1).astype(jnp.int32)
            value[g] = jnp.stack([v.astype(dtype), jnp.asarray(time, dtype)])
            worse[g] = v > state.guard_value[g, 0]
        return record(state, jnp.stack(fired), jnp.stack(body), jnp.stack(value), jnp.stack(worse), time)


# ---------------------------------------------------------------------------------------------- sub-steps
def static_timestep_limit(model: mujoco.MjModel, body_ids, delta: float, tau: float, v_eps: float,
                          qpos=None) -> float:
    """Largest stable timestep (s) when any one of ``body_ids`` carries the model's whole weight at yield, in the
    pose ``qpos`` (default ``qpos0``): :func:`mjrft.envs.wrapper.static_timestep_limit` from the terrain's
    settings (stiffness ``K = M g / delta`` with damper ``tau K``, or the viscous ``c = M g / v_eps``, on the
    largest inverse mass of each body's CoM translation)."""
    from ..stability import max_stable_dt as host_limit

    weight = float(model.body_subtreemass[0]) * max(0.0, -float(model.opt.gravity[2]))
    if weight <= 0.0:
        return math.inf
    data = mujoco.MjData(model)
    if qpos is not None:
        data.qpos[:] = qpos
    mujoco.mj_forward(model, data)
    jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    out = math.inf
    for b in body_ids:
        mujoco.mj_jacBodyCom(model, data, jacp, jacr, int(b))
        minv = np.zeros((3, model.nv))
        mujoco.mj_solveM(model, data, minv, jacp)
        w = float(np.linalg.eigvalsh(0.5 * (jacp @ minv.T + minv @ jacp.T))[-1])
        if not w > 0.0:
            continue
        if delta > 0.0:
            K = weight / delta
            out = min(out, host_limit(K, tau * K, w))
        elif v_eps > 0.0:
            out = min(out, host_limit(0.0, weight / v_eps, w))
    return out


def spring_rate(limit, tau: float):
    """:func:`mjrft.envs.wrapper.spring_rate`: the rate ``omega`` (1/s) of the spring whose explicit limit is
    ``limit`` (s) with damping time ``tau``, ``2 / sqrt(limit (limit + 2 tau))`` (0 for an infinite limit)."""
    finite = jnp.isfinite(limit)
    safe = jnp.where(finite, limit, 1.0)
    return jnp.where(finite, 2.0 / jnp.sqrt(safe * (safe + 2.0 * tau)), 0.0)


def substeps_for(stable_dt: jax.Array, static_limit: float, h, implicit: bool, tau: float,
                 max_substeps: int) -> jax.Array:
    """Sub-steps (int32, 1 to ``max_substeps``) of a step ``h`` from the last step's limits ``stable_dt`` (springs,
    depth stiffness) and the static limit: :class:`mjrft.envs.GranularWrapper`'s rule. Explicit step:
    ``dt_s = SAFETY min(springs, static, depth)``; implicit step: ``dt_s = min(SPRING_STEP / omega, SAFETY depth)``
    with ``omega`` the rate of the springs whose limit is ``min(springs, static)``; ``k = ceil(h / dt_s)``."""
    springs = jnp.minimum(stable_dt[0], static_limit)
    depth = stable_dt[1]
    if implicit:
        rate = spring_rate(springs, tau)
        dt_s = jnp.minimum(jnp.where(rate > 0.0, SPRING_STEP / jnp.where(rate > 0.0, rate, 1.0), jnp.inf),
                           SAFETY * depth)
    else:
        dt_s = SAFETY * jnp.minimum(springs, depth)
    k = jnp.where(jnp.isfinite(dt_s), jnp.ceil(h / jnp.where(jnp.isfinite(dt_s), dt_s, 1.0) - 1e-9), 1.0)
    return jnp.clip(k, 1, max_substeps).astype(jnp.int32)


# ---------------------------------------------------------------------------------------------- reports
def flags(state) -> dict[str, jax.Array]:
    """Per-world flags of ``state`` (one world or a batch; bool arrays of the batch's shape), usable inside
    ``jit``: ``nonfinite`` (a non-finite state or force, or more than ``cull`` buried elements: no wrench was
    applied), and one per guard of :data:`GUARDS` (it fired on some step since the last reset)."""
    out = {"nonfinite": state.bad_body != -1}
    for g, name in enumerate(GUARDS):
        out[name] = state.guard_count[..., g] > 0
    return out


#: the guards that :func:`guard_metrics` counts as a stability problem and as a law's range exceeded
STABILITY_GUARDS, RANGE_GUARDS = ("springs", "depth_stiffness", "chatter"), ("depth_range", "speed_range")


def guard_metrics(state, dtype=jnp.float32) -> dict[str, jax.Array]:
    """An environment's per-world metrics of ``state`` (usable inside ``jit``): ``unstable`` 1.0 when a stability
    limit or chatter guard fired since the last reset, ``out_of_range`` 1.0 when the law's depth or speed range was
    left; zeros for a state without the guards' record (``Sand(guards=False)``)."""
    shape = jnp.shape(state.bad_body)
    if state.guard_count is None:
        return {"unstable": jnp.zeros(shape, dtype), "out_of_range": jnp.zeros(shape, dtype)}
    f = flags(state)
    any_of = lambda names: jnp.any(jnp.stack([f[n] for n in names]), axis=0).astype(dtype)  # noqa: E731
    return {"unstable": any_of(STABILITY_GUARDS), "out_of_range": any_of(RANGE_GUARDS)}


def _body_name(model, b: int) -> str:
    return mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, int(b)) or f"#{int(b)}"


def guard_messages(model: mujoco.MjModel, guards: Guards, state, stress_scale: float = 1.0) -> list:
    """The warnings (:class:`~mjrft.TerrainStabilityWarning`, :class:`~mjrft.ValidityRangeWarning`) for the
    guards ``state`` (one world or a batch) recorded, one per guard, naming the first world with it, its body and
    time, how many steps fired, how many worlds, and the cure."""
    count = np.asarray(state.guard_count).reshape(-1, len(GUARDS))
    bodies = np.asarray(state.guard_body).reshape(-1, len(GUARDS))
    times = np.asarray(state.guard_time).reshape(-1, len(GUARDS))
    values = np.asarray(state.guard_value).reshape(-1, len(GUARDS), 2)
    out = []
    implicit = guards.implicit
    for g, name in enumerate(GUARDS):
        hit = np.flatnonzero(count[:, g] > 0)
        if hit.size == 0:
            continue
        k = int(hit[0])
        where = "" if count.shape[0] == 1 else f" in world {k} ({hit.size} of {count.shape[0]} worlds)"
        body = _body_name(model, bodies[k, g])
        t, steps, (v0, v1) = float(times[k, g]), int(count[k, g]), values[k, g]
        scaled = ("" if stress_scale == 1.0 else
                  f" (the granular stresses are scaled x{stress_scale:.4g}: the stiffness grows with the scale)")
        if g == SPRINGS:
            msg = TerrainStabilityWarning(
                f"mjrft.mjx: the timestep exceeded the stability limit of the granular stiffness on body '{body}' "
                f"from t = {t:.6g} s{where}, on {steps} step(s); at worst a step of {v1:.3g} s against a limit of "
                f"{v0:.3g} s; reduce the timestep (Sand.auto_step sub-steps to half the limit), increase "
                "yield_displacement, or step the grains' springs implicitly (Sand(..., implicit=True), stable at any "
                f"timestep){scaled}")
        elif g == DEPTH_STIFFNESS:
            msg = TerrainStabilityWarning(
                f"mjrft.mjx: the timestep exceeded the stability limit of the grains' depth stiffness on body "
                f"'{body}' from t = {t:.6g} s{where}, on {steps} step(s); at worst a step of {v1:.3g} s against a "
                f"limit of {v0:.3g} s (its force grows with its depth, explicitly in every mode: a light body on a "
                f"large area sunk shallow); use a smaller timestep (Sand.auto_step sub-steps){scaled}")
        elif g == CHATTER:
            cure = ("halve the timestep (Sand.auto_step sub-steps) until it stops" if implicit else
                    "use the implicit granular step (Sand(..., implicit=True)) or a timestep below the springs' "
                    "stability limit (Sand.auto_step sub-steps to half of it)")
            msg = TerrainStabilityWarning(
                f"mjrft.mjx: body '{body}' chatters{where}: its granular force ({v1:.3g} N) reversed its change on "
                f"at least {CHATTER_STEPS} consecutive steps, by up to {100 * v0:.3g} % of it, from t = {t:.6g} s "
                f"({steps} step(s) in such runs); this period-2 oscillation is the "
                f"{'implicit' if implicit else 'explicit'} step's, not the physics' (docs/numerics.md, \"Chatter\"); "
                f"{cure}")
        else:
            r = guards.ranges["depth" if g == DEPTH_RANGE else "speed"]
            msg = ValidityRangeWarning(
                r.message(guards.law, float(v0), f" on body '{body}' (first at t = {t:.6g} s{where}, on {steps} "
                                                 f"step(s); the largest at t = {float(v1):.6g} s)"))
        out.append(msg)
    return out


def check_guards(model, guards: Guards, state, stress_scale: float = 1.0, warned: set | None = None,
                 stacklevel: int = 3) -> None:
    """Warn (once per guard and body when ``warned`` is given: the set of (guard, body) already warned about)
    for what ``state`` recorded (:func:`guard_messages`)."""
    bodies = np.asarray(state.guard_body).reshape(-1, len(GUARDS))
    count = np.asarray(state.guard_count).reshape(-1, len(GUARDS))
    msgs = iter(guard_messages(model, guards, state, stress_scale))
    for g in range(len(GUARDS)):
        hit = np.flatnonzero(count[:, g] > 0)
        if hit.size == 0:
            continue
        msg = next(msgs)
        key = (GUARDS[g], int(bodies[hit[0], g]))
        if warned is not None:
            if key in warned:
                continue
            warned.add(key)
        warnings.warn(msg, stacklevel=stacklevel)

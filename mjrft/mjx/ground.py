"""The ground memory in JAX: the twin of :mod:`mjrft.ground` for :class:`mjrft.mjx.Sand` (one height map per world).

:class:`GroundState` holds what the CPU terrain keeps in its ``g_*`` arrays (:class:`mjrft.types.TerrainState`), with
the same layout and meaning: the cells' records (ny, nx, 8; fields :data:`mjrft.ground.C_PHI` ...), what each
element read from the ground and when its cull group last read it, the cells a body was in at the last update, the
relaxation sweeps' two lists, the clocks and each block's last change. :class:`Ground` reads and updates it as the
numba kernel does (:func:`mjrft.kernel.terrain_kernel_ground` and :func:`mjrft.ground.ground_step`):

* each step (:meth:`Ground.read`): the cull groups within reach of the surface (their box's lowest corner below the
  highest sand surface plus the highest rise of the blocks around it, and the deepest water unless the group lies in
  the dry Li-RFT strip, as the kernel culls), and for each group that came within reach, moved half a cell or whose
  blocks changed since it last read the ground, its elements' surface, gradient and packing afresh (bilinear between
  cell centres, :func:`mjrft.ground.ground_sample`); every element's depth is then that reading carried along the
  gradient to where it is (so the elements read exactly what the CPU kernel's read);
* once per ``period`` of simulated time (:meth:`Ground.update`): the buried elements' cells and their displaced and
  swept volumes (vectorised over elements), then the footprints' compaction and ridges, the cells the bodies left
  and one Gauss-Seidel relaxation sweep in the CPU's order: the sweeps move grains between neighbours one listed
  cell after the other, each move reading the heights the moves before it left, so they run as ``lax`` loops over
  the touched cells and the listed (cell, neighbour) pairs (the few tens to hundreds of cells an update lists, not
  the grid), each iteration reading and updating the grid once, which XLA does in place. A column that reaches more
  than :data:`TAKE_UNROLLED` layers deeper in one take gets the further layers at once (the CPU adds them one by one:
  the same grains, equal to rounding). The result equals the numba kernel's to rounding
  (``tests/mjrft/mjx/test_mjx_ground.py``);
* with the hybrid law (:func:`mjrft.ground.uses_wake`) the wake of its undisturbed-grain rule: at each update the
  slabs the flowing leading faces pass through keep the earliest time (a scatter-min over the elements into cell x
  slab, :func:`mjrft.ground._wake_mark`) and the cells the bodies left are emptied, and each step the general pass
  leaves without force a buried element of the hybrid law moving into a slab passed through earlier than it could
  have itself (:meth:`Ground.in_wake`, :func:`mjrft.ground.in_wake`), with the kernel's clock, order and float32
  times: the wrench, cells and wake equal the kernel's to rounding. A terrain without the hybrid law keeps no wake
  and traces none of it.

Under ``jax.vmap`` a loop whose trip count differs between worlds would select the whole carry (every world's grid)
on each iteration; :func:`serial_loop` instead runs the longest world's count with each iteration's writes masked
where a world is done (``jax.custom_batching.custom_vmap``), so a batch pays its busiest world's cells only. A step
on which no world updates skips the update altogether (:func:`when`: a ``lax.cond`` that under ``jax.vmap`` asks
whether any world updates, instead of JAX's rule for a batched condition, which runs both branches every step).
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ..ground import (BLOCK_SHIFT, C_COL, C_H, C_MARK, C_PEND, C_PHI, C_STAMP, C_SUB, C_SWEPT, DEEPEN_TOL, FLOWING,
                      N_FIELDS, RELAX, RELAX_TOL, WAKE_ABOVE, WAKE_LAG_CELLS, WAKE_SLABS, uses_wake)
from ..laws.registry import LAW_IDS
from ..params import P_WATER_DEPTH
from ..types import TerrainModel

LAW_RFT = LAW_IDS["rft"]  # the law of the kernel's batched (dry) region

_DIRS8 = ((1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1), (0, -1), (1, -1))  # (di, dj), mjrft.ground._ridge
_DIRS4 = ((1, 0), (-1, 0), (0, 1), (0, -1))  # mjrft.ground.relax_sweep
TAKE_UNROLLED = 2  # the layers a column reaches deeper by in one take step by step as the CPU does (_take)


class GroundState(NamedTuple):
    """One world's ground memory (a pytree; :class:`mjrft.types.TerrainState`'s ``g_*`` arrays): ``cells`` (ny, nx,
    8) the cells' records; ``elem`` (n, 6) what each element read (surface, its gradient along x and y, where it
    read it, its packing weight); ``group`` (g, 3) the update each cull group last read at (-1: never) and where its
    box's centre was; ``active`` (g,) whether each group was within reach on its last step; ``held`` (2, n) the flat
    indices of the cells a body was in at the last update (row 0) and at this one (row 1); ``dirty`` (2, cells) the
    relaxation sweeps' lists; ``count`` (3,) their lengths (held, dirty 0, dirty 1); ``clock`` (2,) (updates, sweeps);
    ``since`` the simulated time since the last update (s); ``stamp`` (nby, nbx) the last update that changed each
    block of 4 x 4 cells; ``top`` (nby, nbx) each block's highest surface a cell reads above the undisturbed one (at
    least 0: what the culling reads; each update sets it from its cells); ``bed`` (8,) the record of a cell of the
    prepared bed (what :func:`reset` restores; its surface is the undisturbed one, so its blocks' ``top`` is 0). With
    the hybrid law's wake (:attr:`Ground.wake`; else None, nothing of it traced): ``wake`` (ny, nx,
    :data:`mjrft.ground.WAKE_SLABS`) float32 per cell and depth slab the earliest time a body's leading face passed
    through it while the bodies stayed in the cell (inf: none; :func:`mjrft.ground.wake_array`) and ``now`` the
    simulated time since the prepared bed (s; the CPU's ``g_since[1]``)."""

    cells: jax.Array
    elem: jax.Array
    group: jax.Array
    active: jax.Array
    held: jax.Array
    dirty: jax.Array
    count: jax.Array
    clock: jax.Array
    since: jax.Array
    stamp: jax.Array
    top: jax.Array
    bed: jax.Array
    wake: jax.Array | None = None
    now: jax.Array | None = None


def reset(g: GroundState) -> GroundState:
    """``g`` back at the prepared bed (one world's state or a batch): every cell the record ``g.bed``, no reading, no
    list, the clocks and the blocks' tops at 0 (:meth:`mjrft.types.TerrainState.forget`)."""
    zero = jax.tree_util.tree_map(jnp.zeros_like, g)
    return zero._replace(cells=jnp.broadcast_to(g.bed[..., None, None, :], g.cells.shape),
                         group=jnp.full_like(g.group, -1.0), bed=g.bed,
                         wake=None if g.wake is None else jnp.full_like(g.wake, jnp.inf))


def _get(a, *idx):
    """``a[idx]`` for scalar indices (a dynamic slice: inside the loops a gather or scatter on the grid may copy it)."""
    k = len(idx)
    start = tuple(jnp.asarray(v, jnp.int32) for v in idx) + (jnp.int32(0),) * (a.ndim - k)
    return jax.lax.dynamic_slice(a, start, (1,) * k + a.shape[k:]).reshape(a.shape[k:])


def _put(a, value, *idx):
    """``a`` with ``a[idx] = value`` for scalar indices, in place (a dynamic update slice)."""
    k = len(idx)
    start = tuple(jnp.asarray(v, jnp.int32) for v in idx) + (jnp.int32(0),) * (a.ndim - k)
    return jax.lax.dynamic_update_slice(a, jnp.reshape(jnp.asarray(value, a.dtype), (1,) * k + a.shape[k:]), start)


def _batch_of(axis_size: int):
    """In a ``custom_vmap`` rule: ``full(x, batched)``, ``x`` with the batch axis (broadcast where it has none)."""

    def full(x, batched):
        return x if batched else jnp.broadcast_to(x, (axis_size,) + jnp.shape(x))

    return full


def serial_loop(body, n, aux, carry):
    """``carry`` after ``body(k, live, aux, carry)`` for ``k = 0 .. n - 1`` (``live`` True), a ``lax.while_loop``.
    ``body`` must leave ``carry`` unchanged where ``live`` is False. Under ``jax.vmap`` the loop runs the batch's
    largest ``n`` with ``live = k < n`` per world, instead of JAX's rule for a batched loop, which selects the whole
    carry of every world on every iteration."""

    def run(n, aux, carry):
        def step(state):
            k, c = state
            return k + 1, body(k, jnp.bool_(True), aux, c)

        return jax.lax.while_loop(lambda s: s[0] < n, step, (jnp.int32(0), carry))[1]

    looped = jax.custom_batching.custom_vmap(run)

    @looped.def_vmap
    def _batched(axis_size, in_batched, n, aux, carry):
        n_b, aux_b, carry_b = in_batched
        full = _batch_of(axis_size)
        n = full(n, n_b)
        aux = jax.tree_util.tree_map(full, aux, aux_b)
        carry = jax.tree_util.tree_map(full, carry, carry_b)
        one = jax.vmap(lambda k, nn, a, c: body(k, k < nn, a, c), in_axes=(None, 0, 0, 0))

        def step(state):
            k, c = state
            return k + 1, one(k, n, aux, c)

        out = jax.lax.while_loop(lambda s: s[0] < jnp.max(n), step, (jnp.int32(0), carry))[1]
        return out, jax.tree_util.tree_map(lambda _: True, out)

    return looped(jnp.asarray(n, jnp.int32), aux, carry)


def when(do, fn, g, args):
    """``fn(g, args)`` where ``do``, else ``g`` (a ``lax.cond``). Under ``jax.vmap`` ``fn`` runs for the whole batch
    on a step where any world's ``do`` is True, and not at all where none is, instead of JAX's rule for a batched
    condition, which runs ``fn`` on every step and selects; ``fn`` must return ``g`` unchanged where ``do`` is
    False."""

    def run(do, g, args):
        return jax.lax.cond(do, fn, lambda g, _: g, g, args)

    cond = jax.custom_batching.custom_vmap(run)

    @cond.def_vmap
    def _batched(axis_size, in_batched, do, g, args):
        full = _batch_of(axis_size)
        do_b, g_b, args_b = in_batched
        g = jax.tree_util.tree_map(full, g, g_b)
        args = jax.tree_util.tree_map(full, args, args_b)
        out = jax.lax.cond(jnp.any(full(do, do_b)), jax.vmap(fn), lambda g, _: g, g, args)
        return out, jax.tree_util.tree_map(lambda _: True, out)

    return cond(jnp.asarray(do), g, args)


class Ground:
    """The ground memory of a :class:`~mjrft.types.TerrainModel` built with ``ground_memory`` (its
    :class:`~mjrft.types.GroundTables` and element tables as constants) and the JAX functions that read and update a
    :class:`GroundState`. ``mjrft.mjx.Sand`` holds one (``sand.ground``) when its terrain has the memory."""

    def __init__(self, tm: TerrainModel):
        gt, el, cs = tm.ground, tm.elements, tm.constants
        self.frame = np.array(gt.frame, dtype=np.float64)
        self.ny, self.nx = (int(v) for v in gt.shape)
        self.ncell = self.ny * self.nx
        self.base = np.array(gt.base, dtype=np.float64)
        (self.phi_lp, self.phi_cp, self.crit, self.phi0, self.inv_range, self.tan_lp, self.tan_cp,
         self.layer) = (float(v) for v in gt.pack)
        self.dparams = np.array(gt.dparams, dtype=np.float64)
        self.ridge = int(gt.ridge)
        self.period = float(gt.period)
        self.nby, self.nbx = (self.ny >> BLOCK_SHIFT) + 1, (self.nx >> BLOCK_SHIFT) + 1
        self.g_geom = np.asarray(el.group_geom, dtype=np.int32)
        self.g_aabb = np.array(el.group_aabb, dtype=np.float64)
        start = np.asarray(el.group_start)
        self.n_groups = int(self.g_geom.shape[0])
        self.n = int(start[-1])
        self.elem_group = np.repeat(np.arange(self.n_groups), np.diff(start)).astype(np.int32)
        self.delta, self.v_eps = float(cs.delta), float(cs.v_eps)
        # the scene as the kernel's cull sees it (mjrft.kernel._scene): the deepest water, the batched region (the
        # first dry Li-RFT one, -1: none) and whether every group is a dry one (one dry Li-RFT region) or a group may
        # be one by lying inside the batched region's strip
        rg = tm.regions
        law, params, rho = np.asarray(rg.law), np.asarray(rg.params), np.asarray(rg.rho)
        self.wmax = max(0.0, float(params[:, P_WATER_DEPTH].max()))
        dry = [r for r in range(law.shape[0]) if law[r] == LAW_RFT and not (params[r, P_WATER_DEPTH] > 0.0
                                                                              or rho[r] > 0.0)]
        self.breg = dry[0] if dry else -1
        self.dry_all = law.shape[0] == 1 and self.breg == 0
        self.strips = self.breg >= 0 and np.asarray(rg.bounds).shape[0] > 0 and np.asarray(rg.map).shape[0] == 0
        self.blend = float(rg.transition)
        #: the depth (m) an element of a group out of reach gets: none of its force, memory or footprint counts
        #: (0, as the CPU kernel leaves it, without water; below the deepest water's reach with it)
        self.outside = 0.0 if self.wmax == 0.0 else -(self.wmax + 1.0)
        # the blocks a group's box (grown by a cell on each side) can span along an axis, at any rotation
        cell = self.frame[2]
        reach = 2.0 * float(np.max(np.sum(self.g_aabb[:, 3:6], axis=1))) + 2.0 * cell if self.n_groups else 0.0
        self.window = int(reach / (cell * (1 << BLOCK_SHIFT))) + 2
        #: whether the memory keeps the hybrid law's wake (a region of the hybrid law, :func:`mjrft.ground.uses_wake`)
        self.wake = uses_wake(law)
        # the most slabs one element's leading face can cover (its extent sqrt(area) over half a cell, and the ends)
        size = float(np.sqrt(np.max(np.asarray(el.area)))) if self.n else 0.0
        self.wake_span = int(2.0 * size / cell) + 2

    # ------------------------------------------------------------------ state
    def init(self, dtype=None) -> GroundState:
        """The prepared bed: every cell at the medium's prepared volume fraction, its column the layer's depth
        (:func:`mjrft.ground.make_ground_state`; after ``reset``, :meth:`mjrft.types.TerrainState.forget`)."""
        dtype = jnp.asarray(0.0).dtype if dtype is None else dtype
        cells = jnp.zeros((self.ny, self.nx, N_FIELDS), dtype)
        cells = cells.at[:, :, C_PHI].set(self.phi0).at[:, :, C_COL].set(self.layer)
        n = max(1, self.n)
        bed = jnp.zeros(N_FIELDS, dtype).at[C_PHI].set(self.phi0).at[C_COL].set(self.layer)
        return GroundState(cells=cells, elem=jnp.zeros((self.n, 6), dtype),
                           group=jnp.full((self.n_groups, 3), -1.0, dtype),
                           active=jnp.zeros(self.n_groups, bool), held=jnp.zeros((2, n), jnp.int32),
                           dirty=jnp.zeros((2, self.ncell), jnp.int32), count=jnp.zeros(3, jnp.int32),
                           clock=jnp.zeros(2, jnp.int32), since=jnp.zeros((), dtype),
                           stamp=jnp.zeros((self.nby, self.nbx), jnp.int32),
                           top=jnp.zeros((self.nby, self.nbx), dtype), bed=bed,
                           wake=jnp.full((self.ny, self.nx, WAKE_SLABS), jnp.inf, jnp.float32) if self.wake else None,
                           now=jnp.zeros((), dtype) if self.wake else None)

    # ------------------------------------------------------------------ readers
    def sample(self, cells, x, y, field: int, add_base: bool):
        """Field ``field`` of the cells bilinear at world ``(x, y)`` (arrays of one shape), plus the undisturbed
        surface when ``add_base``: :func:`mjrft.ground.sample_many` (the CPU terrain's ``ground_height`` /
        ``ground_packing``)."""
        f = self.frame
        fx = jnp.clip((x - f[0]) * f[3] - 0.5, 0.0, self.nx - 1.0)
        fy = jnp.clip((y - f[1]) * f[3] - 0.5, 0.0, self.ny - 1.0)
        i = jnp.minimum(fx.astype(jnp.int32), self.nx - 2)
        j = jnp.minimum(fy.astype(jnp.int32), self.ny - 2)
        tx, ty = fx - i, fy - j

        def lerp(a):
            v0 = a[j, i] + tx * (a[j, i + 1] - a[j, i])
            v1 = a[j + 1, i] + tx * (a[j + 1, i + 1] - a[j + 1, i])
            return v0 + ty * (v1 - v0)

        v = lerp(cells[:, :, field])
        if add_base:
            v = v + lerp(jnp.asarray(self.base, cells.dtype))
        return v

    def _element_sample(self, cells, px, py):
        """:func:`mjrft.ground.ground_sample` at each element: (surface, d/dx, d/dy, volume fraction)."""
        f = self.frame
        inv = f[3]
        fx = (px - f[0]) * inv - 0.5
        fy = (py - f[1]) * inv - 0.5
        lo_x, lo_y = ~(fx > 0.0), ~(fy > 0.0)
        hi_x, hi_y = fx > self.nx - 1.0, fy > self.ny - 1.0
        kx = jnp.where(lo_x | hi_x, 0.0, inv)
        ky = jnp.where(lo_y | hi_y, 0.0, inv)
        fx = jnp.where(lo_x, 0.0, jnp.where(hi_x, self.nx - 1.0, fx))
        fy = jnp.where(lo_y, 0.0, jnp.where(hi_y, self.ny - 1.0, fy))
        i = jnp.minimum(fx.astype(jnp.int32), self.nx - 2)
        j = jnp.minimum(fy.astype(jnp.int32), self.ny - 2)
        tx, ty = fx - i, fy - j
        hp = cells[:, :, C_H] + cells[:, :, C_PEND]
        a00, a01, a10, a11 = hp[j, i], hp[j, i + 1], hp[j + 1, i], hp[j + 1, i + 1]
        d0 = a01 - a00
        d1 = a11 - a10
        r0 = a00 + tx * d0
        r1 = a10 + tx * d1
        ph = cells[:, :, C_PHI]
        f0 = ph[j, i] + tx * (ph[j, i + 1] - ph[j, i])
        f1 = ph[j + 1, i] + tx * (ph[j + 1, i + 1] - ph[j + 1, i])
        return r0 + ty * (r1 - r0), (d0 + ty * (d1 - d0)) * kx, (r1 - r0) * ky, f0 + ty * (f1 - f0)

    def _block_top(self, cells):
        """Each block's highest surface a cell reads above the undisturbed one, at least 0 (``GroundState.top``;
        :func:`mjrft.ground._blocks`)."""
        hp = cells[:, :, C_H] + cells[:, :, C_PEND]
        pad = jnp.zeros((self.nby << BLOCK_SHIFT, self.nbx << BLOCK_SHIFT), cells.dtype).at[:self.ny, :self.nx].set(hp)
        return jnp.maximum(0.0, pad.reshape(self.nby, 1 << BLOCK_SHIFT, self.nbx, 1 << BLOCK_SHIFT).max(axis=(1, 3)))

    def _block(self, x, x0, n):
        f = (x - x0) * self.frame[3]
        b = jnp.minimum(jnp.clip(f, 0.0, 4.0 * n + 8.0).astype(jnp.int32) >> BLOCK_SHIFT, n - 1)
        return jnp.where(f > 0.0, b, 0)

    def read(self, g: GroundState, geom_xpos, geom_xmat, pos, surface, top=None, bounds=None):
        """What the elements read this step (the CPU kernel's cull and pass 1 with the ground): ``surface`` the
        undisturbed surface's height (m; one, or one per element: a height field's under each), ``top`` the highest
        sand surface anywhere (m; default ``surface``), ``bounds`` the strips' x_min (a group inside the batched
        region's strip is a dry one, culled at the sand). A group is within reach while its box's lowest corner is
        below ``top`` plus the ground's highest rise around it, less the deepest water unless it is a dry group
        (the kernel's ``gtop - wmax + reach``). Returns (each element's depth below the grains' surface
        (:attr:`outside` for an element of a group out of reach), its packing weight ``t`` (the change of its
        loose-to-close weight from the prepared state), ``g`` with the groups' readings and reach updated)."""
        dtype = pos.dtype
        cells = g.cells
        c = self.frame[2]
        btop = g.top.astype(dtype)  # the blocks' highest surface read (mjrft.ground._blocks)
        # each cull group's box (mjrft.kernel._lowest_corner, _group_ground_top)
        G = geom_xmat[self.g_geom].reshape(-1, 9)
        xp = geom_xpos[self.g_geom]
        a = jnp.asarray(self.g_aabb, dtype)
        lowest = (xp[:, 2] + G[:, 6] * a[:, 0] + G[:, 7] * a[:, 1] + G[:, 8] * a[:, 2]
                  - jnp.abs(G[:, 6]) * a[:, 3] - jnp.abs(G[:, 7]) * a[:, 4] - jnp.abs(G[:, 8]) * a[:, 5])
        cx = xp[:, 0] + G[:, 0] * a[:, 0] + G[:, 1] * a[:, 1] + G[:, 2] * a[:, 2]
        cy = xp[:, 1] + G[:, 3] * a[:, 0] + G[:, 4] * a[:, 1] + G[:, 5] * a[:, 2]
        ex = jnp.abs(G[:, 0]) * a[:, 3] + jnp.abs(G[:, 1]) * a[:, 4] + jnp.abs(G[:, 2]) * a[:, 5]
        ey = jnp.abs(G[:, 3]) * a[:, 3] + jnp.abs(G[:, 4]) * a[:, 4] + jnp.abs(G[:, 5]) * a[:, 5]
        i0, i1 = self._block(cx - ex - c, self.frame[0], self.nbx), self._block(cx + ex + c, self.frame[0], self.nbx)
        j0, j1 = self._block(cy - ey - c, self.frame[1], self.nby), self._block(cy + ey + c, self.frame[1], self.nby)
        w = jnp.arange(self.window, dtype=jnp.int32)
        jj, ii = j0[:, None] + w[None, :], i0[:, None] + w[None, :]  # (g, window)
        inside = (jj <= j1[:, None])[:, :, None] & (ii <= i1[:, None])[:, None, :]
        jc, ic = jnp.minimum(jj, self.nby - 1), jnp.minimum(ii, self.nbx - 1)
        bump = jnp.max(jnp.where(inside, btop[jc[:, :, None], ic[:, None, :]], 0.0), axis=(1, 2))
        newest = jnp.max(jnp.where(inside, g.stamp[jc[:, :, None], ic[:, None, :]], 0), axis=(1, 2))
        gtop = (surface if top is None else top) + bump
        if self.wmax == 0.0:  # no water: every group is culled at the sand (gtop - 0 + 0)
            active = lowest < gtop
        else:
            dry = jnp.bool_(self.dry_all)
            if self.strips and not self.dry_all:  # mjrft.kernel._inside_strip
                b = jnp.asarray(bounds, dtype)
                xlo, xhi = cx - ex - 0.5 * self.blend, cx + ex + 0.5 * self.blend
                greg = jnp.sum(xlo[:, None] >= b[None, :], axis=1)
                inside = (greg == self.breg) & ((greg == b.shape[0])
                                                | (xhi < b[jnp.minimum(greg, b.shape[0] - 1)]))
                dry = (lowest < gtop) & inside
            active = lowest < gtop - self.wmax + jnp.where(dry, 0.0, self.wmax)
        # the groups that read the ground afresh (kernel pass 1 with gr_on)
        gg = g.group
        moved = (cx - gg[:, 1]) * (cx - gg[:, 1]) + (cy - gg[:, 2]) * (cy - gg[:, 2]) > 0.25 * c * c
        fresh = active & (~g.active | (newest > gg[:, 0]) | moved)
        group = jnp.where(fresh[:, None], jnp.stack([jnp.broadcast_to(g.clock[0].astype(dtype), cx.shape), cx, cy],
                                                    axis=1), gg)
        px, py, pz = pos[:, 0], pos[:, 1], pos[:, 2]
        h, hx, hy, phi = self._element_sample(cells, px, py)
        read = jnp.stack([h, hx, hy, px, py, (phi - self.phi0) * self.inv_range], axis=1)
        elem = jnp.where(fresh[self.elem_group][:, None], read, g.elem)
        gh = elem[:, 0] + elem[:, 1] * (px - elem[:, 3]) + elem[:, 2] * (py - elem[:, 4])
        depth = jnp.where(active[self.elem_group], surface + gh - pz, self.outside)
        return depth, elem[:, 5], g._replace(elem=elem, group=group, active=active)

    # ------------------------------------------------------------------ the update
    def update(self, g: GroundState, pos, vel, nrm, depth, u, area, dt, ok):
        """``g`` advanced by a physics step of ``dt`` (s) from the elements' outputs of this step (positions,
        velocities, normals, depths as :meth:`read` gave them, the new rest memory ``u``): once ``period`` of
        simulated time has passed since the last update (and ``ok``: the world's step was finite),
        :func:`mjrft.ground.ground_step`."""
        dtype = g.cells.dtype
        since = g.since + dt
        do = ok & (dt > 0.0) & (since >= self.period * (1.0 - 1e-9))
        if self.wake:  # the clock since the prepared bed, as the kernel advances it (a finite step of dt > 0)
            g = g._replace(now=jnp.where(ok & (dt > 0.0), g.now + dt, g.now).astype(dtype))
        g = when(do, lambda g, a: self._ground_step(g, *a), g, (pos, vel, nrm, depth, u, area, since, do))
        return g._replace(since=jnp.where(do, 0.0, since).astype(dtype))

    def in_wake(self, g: GroundState, pos, vel, speed, dt):
        """Whether each element at ``pos`` (n, 3) moving at ``vel`` (n, 3) of size ``speed`` (n,) moves into a body's
        wake (:func:`mjrft.ground.in_wake`, at the time ``g.now + dt`` the kernel reads): the point half a cell ahead
        along its motion lies in a depth slab of its cell that a leading face passed through more than
        ``WAKE_LAG_CELLS cell / speed + period`` before; False outside the grid, at rest and below the slabs."""
        dtype = pos.dtype
        f = self.frame
        c = float(f[2])
        moving = speed > 0.0
        isp = 1.0 / jnp.where(moving, speed, 1.0)
        ax = pos[:, 0] + 0.5 * c * (vel[:, 0] * isp)
        ay = pos[:, 1] + 0.5 * c * (vel[:, 1] * isp)
        az = pos[:, 2] + 0.5 * c * (vel[:, 2] * isp)
        fx = (ax - f[0]) * f[3]
        fy = (ay - f[1]) * f[3]
        inside = (fx >= 0.0) & (fy >= 0.0) & (fx < self.nx) & (fy < self.ny)
        i = jnp.clip(fx, 0.0, self.nx - 1.0).astype(jnp.int32)
        j = jnp.clip(fy, 0.0, self.ny - 1.0).astype(jnp.int32)
        fk = (jnp.asarray(self.base, dtype)[j, i] - az) / (0.5 * c) + WAKE_ABOVE
        slab = (fk >= 0.0) & (fk < WAKE_SLABS)
        k = jnp.clip(fk, 0.0, WAKE_SLABS - 1.0).astype(jnp.int32)
        now = g.now + dt
        lag = WAKE_LAG_CELLS * c / jnp.where(moving, speed, 1.0) + self.period
        return moving & inside & slab & (now - g.wake[j, i, k].astype(dtype) > lag)

    def _wake_mark(self, wake, j, i, z, area, now, lead):
        """``wake`` with the slabs each leading face (``lead``, at height ``z`` in cell (j, i), extent sqrt(area))
        covers keeping the earliest time ``now`` (:func:`mjrft.ground._wake_mark`, a scatter-min over the
        elements)."""
        dtype = z.dtype
        inv = 2.0 / float(self.frame[2])
        base = jnp.asarray(self.base, dtype)[j, i]
        size = jnp.sqrt(area)
        lo = (base - z - 0.5 * size) * inv + WAKE_ABOVE
        hi = (base - z + 0.5 * size) * inv + WAKE_ABOVE
        on = lead & (hi >= 0.0) & (lo < WAKE_SLABS)
        k0 = jnp.clip(jnp.maximum(lo, 0.0), 0.0, WAKE_SLABS).astype(jnp.int32)
        k1 = jnp.clip(jnp.minimum(hi, WAKE_SLABS - 1.0), 0.0, WAKE_SLABS).astype(jnp.int32)
        ks = k0[:, None] + jnp.arange(self.wake_span, dtype=jnp.int32)[None, :]  # (n, span)
        put = on[:, None] & (ks <= k1[:, None])
        t = jnp.broadcast_to(jnp.asarray(now, jnp.float32), ks.shape)
        rows = jnp.where(put, j[:, None], self.ny)  # out of bounds: dropped
        return wake.at[rows, jnp.broadcast_to(i[:, None], ks.shape), ks].min(t, mode="drop")

    def _ground_step(self, g, pos, vel, nrm, depth, u, area, dt, do):
        dtype = g.cells.dtype
        nx, ny, ncell, n = self.nx, self.ny, self.ncell, self.n
        x0, y0, cell, inv = (float(v) for v in self.frame)
        inv_a = 1.0 / (cell * cell)
        clock = g.clock
        step = jnp.where(do, clock[0] + 1, clock[0])
        sweep = clock[1] + 1
        slot = clock[1] % 2
        stepf = step.astype(dtype)
        # 1. the buried elements of the groups within reach: their cells (in the order the CPU lists them: by each
        # cell's first element), the bodies' volume below the surface and the swept volume per cell
        fx = (pos[:, 0] - x0) * inv
        fy = (pos[:, 1] - y0) * inv
        live = (do & g.active[self.elem_group] & (depth > 0.0) & (fx >= 0.0) & (fy >= 0.0) & (fx < nx) & (fy < ny))
        i = jnp.clip(fx, 0.0, nx - 1.0).astype(jnp.int32)
        j = jnp.clip(fy, 0.0, ny - 1.0).astype(jnp.int32)
        c = jnp.where(live, j * nx + i, ncell)
        e = jnp.arange(n, dtype=jnp.int32)
        first_of = jnp.full(ncell + 1, n, jnp.int32).at[c].min(e)
        first = live & (first_of[c] == e)
        rank = jnp.cumsum(first, dtype=jnp.int32) - 1
        ntouch = rank[-1] + 1 if n else jnp.int32(0)
        slot_e = jnp.where(live, rank[jnp.minimum(first_of[c], n - 1)], n)
        order = jnp.nonzero(first, size=n, fill_value=n)[0]
        touched = jnp.where(order < n, c[jnp.minimum(order, n - 1)], 0).astype(jnp.int32)
        sub = jnp.zeros(n + 1, dtype).at[slot_e].add(-(depth * area * nrm[:, 2]))[:n]
        if self.delta > 0.0:
            flowing = jnp.sum(u * u, axis=1) > (FLOWING * self.delta) * (FLOWING * self.delta)
        else:
            flowing = jnp.sum(vel * vel, axis=1) > self.v_eps * self.v_eps
        vn = jnp.sum(vel * nrm, axis=1)
        sw = jnp.where(flowing & (vn > 0.0), area * vn * dt, 0.0)
        swept = jnp.zeros(n + 1, dtype).at[jnp.where(flowing & (vn > 0.0), slot_e, n)].add(sw)[:n]
        wake = g.wake
        if self.wake:  # the slabs the flowing leading faces pass through (the hybrid law's wake)
            wake = self._wake_mark(wake, j, i, pos[:, 2], area, g.now, live & flowing & (vn > 0.0))
        tj, ti = touched // nx, touched % nx
        tmask = jnp.arange(n) < ntouch
        tj_w = jnp.where(tmask, tj, ny)  # out of bounds: dropped
        cells = g.cells.at[tj_w, ti, C_STAMP].set(stepf, mode="drop").at[tj_w, ti, C_SUB].set(sub, mode="drop")
        flags = jnp.zeros((self.nby, self.nbx), bool)
        carry = (cells, g.dirty, g.count, flags)
        aux = (touched, sub, swept, stepf, sweep, slot)
        carry = serial_loop(self._touched_body, ntouch, aux, carry)
        cells, dirty, count, flags = carry
        # 3. the cells the bodies left (each listed once): the footprint stays open and may avalanche
        held0 = g.held[0]
        nheld = jnp.where(do, count[0], 0)
        hj, hi = held0 // nx, held0 % nx
        left = (jnp.arange(held0.shape[0]) < nheld) & (cells[hj, hi, C_STAMP] != stepf)
        cells = cells.at[jnp.where(left, hj, ny), hi, C_PEND].set(0.0, mode="drop")
        if self.wake:  # the grains close over the wake the bodies leave
            wake = wake.at[jnp.where(left, hj, ny), hi, :].set(jnp.inf, mode="drop")
        flags = flags.at[jnp.where(left, hj >> BLOCK_SHIFT, self.nby), hi >> BLOCK_SHIFT].set(True, mode="drop")
        need = left & (cells[hj, hi, C_MARK] != sweep.astype(dtype))
        pos_in = count[1 + slot] + jnp.cumsum(need, dtype=jnp.int32) - 1
        cells = cells.at[jnp.where(need, hj, ny), hi, C_MARK].set(sweep.astype(dtype), mode="drop")
        dirty = dirty.at[slot, jnp.where(need, pos_in, ncell)].set(held0, mode="drop")
        count = count.at[1 + slot].add(jnp.sum(need, dtype=jnp.int32))
        held = jnp.where(do, jnp.stack([touched, touched]), g.held)
        count = count.at[0].set(jnp.where(do, ntouch, count[0]))
        # 4. one relaxation sweep over the listed cells (when any), then the blocks' stamps
        nsweep = jnp.where(do, count[1 + slot], 0)
        relax = nsweep > 0
        nxt = 1 - slot
        count = count.at[1 + nxt].set(jnp.where(relax, 0, count[1 + nxt]))
        carry = serial_loop(self._relax_body, 4 * nsweep, (stepf, sweep, slot), (cells, dirty, count, flags))
        cells, dirty, count, flags = carry
        count = count.at[1 + slot].set(jnp.where(relax, 0, count[1 + slot]))
        clock = jnp.stack([step, jnp.where(relax, sweep, clock[1])])
        stamp = jnp.where(flags, step, g.stamp)
        return g._replace(cells=cells, held=held, dirty=dirty, count=count, clock=clock, stamp=stamp,
                          top=self._block_top(cells).astype(g.top.dtype), wake=wake)

    # the loops' bodies: one touched cell (step 2 of mjrft.ground.ground_step), one listed cell (relax_sweep)
    def _take(self, col, h, phi, bulk):
        """:func:`mjrft.ground._take` on a cell's (column, surface, volume fraction)."""
        h = h - bulk
        layer, phi0 = self.layer, self.phi0

        def deeper(s):
            col, h, phi = s
            m = phi * (col + h) + phi0 * layer
            col = col + layer
            return col, h, m / (col + h)

        state = (col, h, phi)
        for _ in range(TAKE_UNROLLED):  # the CPU's steps, one layer each, without a loop (XLA copies the grid at one)
            more = state[0] + state[1] < 0.5 * layer
            state = tuple(jnp.where(more, a, b) for a, b in zip(deeper(state), state))
        # any further layers at once (the same grains; equal to the CPU's steps up to rounding)
        col, h, phi = state
        k = jnp.maximum(0.0, jnp.ceil((0.5 * layer - (col + h)) / layer))
        more = k > 0.0
        m = phi * (col + h) + k * (phi0 * layer)
        col_k = col + k * layer
        return (jnp.where(more, col_k, col), h,
                jnp.where(more, m / jnp.where(more, col_k + h, 1.0), phi))

    @staticmethod
    def _mix_in(col, h, phi, bulk, solid):
        m = phi * (col + h) + solid
        h = h + bulk
        return h, m / (col + h)

    def _write(self, cells, dirty, rows, js, is_, need, at, value, slot):
        """``cells`` with ``rows[t]`` (m, 8) at cells ``(js[t], is_[t])`` and ``dirty`` with ``value[t]`` at
        ``(slot, at[t])`` where ``need[t]``, in the order of ``t``: a loop with one update of each array per
        iteration, which XLA makes in place (several updates of a loop-carried array in one iteration make it copy
        the whole grid)."""

        # the barrier keeps XLA from sinking the rows' reads of ``cells`` into the loop (which would then copy it)
        rows, js, is_, need, at, value = jax.lax.optimization_barrier((rows, js, is_, need, at, value))

        def one(t, c):
            cells, dirty = c
            cells = _put(cells, rows[t], js[t], is_[t])
            p = jnp.minimum(at[t], self.ncell - 1)  # (a list holds each cell once: never clamped)
            return cells, _put(dirty, jnp.where(need[t], value[t], _get(dirty, slot, p)), slot, p)

        return jax.lax.fori_loop(0, rows.shape[0], one, (cells, dirty))

    def _flags(self, flags, js, is_, when):
        """The blocks of cells ``(js, is_)`` listed where ``when`` (mjrft.ground._raise_block)."""
        return flags.at[jnp.where(when, js >> BLOCK_SHIFT, self.nby), is_ >> BLOCK_SHIFT].set(True, mode="drop")

    def _touched_body(self, k, live, aux, carry):
        touched, sub, swept, stepf, sweep, slot = aux
        cells, dirty, count, flags = carry
        nx, ny = self.nx, self.ny
        dtype = cells.dtype
        crit, phi_cp = self.crit, self.phi_cp
        inv_a = 1.0 / (self.frame[2] * self.frame[2])
        c = _get(touched, k)
        j, i = c // nx, c % nx
        row = _get(cells, j, i)
        col, h, phi, pend = row[C_COL], row[C_H], row[C_PHI], row[C_PEND]
        # shear: the grains moved through are left at the critical state
        f = _get(swept, k) * inv_a / (col + h)
        shear = (f > 0.0) & (phi != crit)
        m = phi * (col + h)
        phi_s = phi + jnp.minimum(f, 1.0) * (crit - phi)
        h = jnp.where(shear, m / phi_s - col, h)
        phi = jnp.where(shear, phi_s, phi)
        # the footprint deepens by dv: compaction of loose grains, then the rest on the rim
        dv = _get(sub, k) * inv_a - pend
        deepen = dv > float(DEEPEN_TOL * self.frame[2])  # mjrft.ground.DEEPEN_TOL
        pend = jnp.where(deepen, pend + dv, pend)
        va = jnp.where(deepen & (phi < phi_cp), jnp.minimum(dv, (col + h) * (1.0 - phi / phi_cp)), 0.0)
        compact = va > 0.0
        m = phi * (col + h)
        h_c = h - va
        phi = jnp.where(compact, m / jnp.where(compact, col + h_c, 1.0), phi)
        h = jnp.where(compact, h_c, h)
        vr = dv - va
        rim = deepen & (vr > 0.0)
        # the ridge (mjrft.ground._ridge): along each of 8 directions the first cell within reach no body is in
        r = jnp.arange(1, self.ridge + 1, dtype=jnp.int32)
        dirs = jnp.asarray(_DIRS8, jnp.int32)
        ii, jj = i + dirs[:, :1] * r[None, :], j + dirs[:, 1:] * r[None, :]  # (8, reach)
        inb = (ii >= 0) & (jj >= 0) & (ii < nx) & (jj < ny)
        free = inb & (cells[jnp.clip(jj, 0, ny - 1), jnp.clip(ii, 0, nx - 1), C_STAMP] != stepf)
        first = jnp.argmax(free, axis=1)
        found = jnp.any(free, axis=1)
        nfound = jnp.sum(found, dtype=jnp.int32)
        to_rim = live & rim & (nfound > 0)
        put = to_rim & found  # (8,): the rim cells, in the directions' order
        rj = jnp.where(put, jnp.take_along_axis(jj, first[:, None], axis=1)[:, 0], j)
        ri = jnp.where(put, jnp.take_along_axis(ii, first[:, None], axis=1)[:, 0], i)
        share = phi * vr / jnp.maximum(nfound, 1).astype(dtype)
        rims = cells[rj, ri]  # (8, 8); where no share lands, the touched cell's own row (rewritten below)
        m_r = rims[:, C_PHI] * (rims[:, C_COL] + rims[:, C_H]) + share
        h_r = rims[:, C_H] + share / crit
        sweepf = sweep.astype(dtype)
        need = put & (rims[:, C_MARK] != sweepf)
        new_rims = rims.at[:, C_H].set(h_r).at[:, C_PHI].set(m_r / (rims[:, C_COL] + h_r))
        new_rims = jnp.where(put[:, None], new_rims.at[:, C_MARK].set(jnp.where(need, sweepf, rims[:, C_MARK])), rims)
        at = _get(count, 1 + slot) + jnp.cumsum(need, dtype=jnp.int32) - 1
        col_t, h_t, phi_t = self._take(col, h, phi, jnp.where(to_rim, vr, 0.0))
        col = jnp.where(to_rim, col_t, col)
        h = jnp.where(to_rim, h_t, h)
        phi = jnp.where(to_rim, phi_t, phi)
        pend = jnp.where(rim & ~to_rim, pend - vr, pend)
        new = row.at[C_COL].set(col).at[C_H].set(h).at[C_PHI].set(phi).at[C_PEND].set(pend).at[C_SWEPT].set(0.0)
        rows = jnp.concatenate([new_rims, jnp.where(live, new, row)[None]])
        js, is_ = jnp.concatenate([rj, j[None]]), jnp.concatenate([ri, i[None]])
        cells, dirty = self._write(cells, dirty, rows, js, is_, jnp.concatenate([need, jnp.zeros(1, bool)]),
                                   jnp.concatenate([at, jnp.zeros(1, jnp.int32)]), js * nx + is_, slot)
        count = count + jnp.where(jnp.arange(3) == 1 + slot, jnp.sum(need, dtype=jnp.int32), 0).astype(count.dtype)
        flags = self._flags(flags, js, is_, jnp.concatenate([put, live[None]]))
        return cells, dirty, count, flags

    def _relax_body(self, k, live, aux, carry):
        """One (listed cell, neighbour) pair of the sweep: ``k = 4 * (the cell's place in the list) + neighbour``, in
        the CPU's order, each move seeing the ones before. The pair is read and written as the 2 x 2 cells around it
        and its two marks as two places of the list: one read and one update of each array per pair, which XLA
        makes in place (it copies a loop-carried grid updated twice in an iteration, or in a nested loop)."""
        stepf, sweep, slot = aux
        cells, dirty, count, flags = carry
        nx, ny = self.nx, self.ny
        dtype = cells.dtype
        cell = float(self.frame[2])
        base = jnp.asarray(self.base, dtype)
        nxt = 1 - slot
        mark = (sweep + 1).astype(dtype)
        c = _get(dirty, slot, k // 4)
        j, i = c // nx, c % nx
        d = k % 4
        dirs = jnp.asarray(_DIRS4, jnp.int32)
        ii, jj = i + dirs[d, 0], j + dirs[d, 1]
        ok = live & (ii >= 0) & (jj >= 0) & (ii < nx) & (jj < ny)
        ii, jj = jnp.clip(ii, 0, nx - 1), jnp.clip(jj, 0, ny - 1)
        wj = jnp.clip(jnp.minimum(j, jj), 0, ny - 2)
        wi = jnp.clip(jnp.minimum(i, ii), 0, nx - 2)
        win = jax.lax.dynamic_slice(cells, (wj, wi, jnp.int32(0)), (2, 2, N_FIELDS))
        rc, rn = win[j - wj, i - wi], win[jj - wj, ii - wi]
        ok = ok & (rc[C_STAMP] != stepf) & (rn[C_STAMP] != stepf)
        hc = _get(base, j, i) + rc[C_H]
        hn = _get(base, jj, ii) + rn[C_H]
        high = hc >= hn
        rh, rl = jnp.where(high, rc, rn), jnp.where(high, rn, rc)
        jh, ih = jnp.where(high, j, jj), jnp.where(high, i, ii)
        jl, il = jnp.where(high, jj, j), jnp.where(high, ii, i)
        drop = jnp.where(high, hc - hn, hn - hc)
        s = jnp.minimum(1.0, jnp.maximum(0.0, (rh[C_PHI] - self.phi_lp) * self.inv_range))
        excess = drop - cell * (self.tan_lp + s * (self.tan_cp - self.tan_lp))
        move = ok & (excess > RELAX_TOL * cell)
        q = jnp.where(move, 0.5 * RELAX * excess, 0.0)
        solid = rh[C_PHI] * q
        col_h, h_h, phi_h = self._take(rh[C_COL], rh[C_H], rh[C_PHI], q)
        h_l, phi_l = self._mix_in(rl[C_COL], rl[C_H], rl[C_PHI], q, solid)
        old = jnp.stack([rh, rl])
        need = move & (old[:, C_MARK] != mark)  # both listed for the next sweep, the high one first
        new = jnp.stack([rh.at[C_COL].set(col_h).at[C_H].set(h_h).at[C_PHI].set(phi_h),
                         rl.at[C_H].set(h_l).at[C_PHI].set(phi_l)])
        rows = jnp.where(move, new.at[:, C_MARK].set(jnp.where(need, mark, old[:, C_MARK])), old)
        js, is_ = jnp.stack([jh, jl]), jnp.stack([ih, il])
        win = win.at[jh - wj, ih - wi].set(rows[0]).at[jl - wj, il - wi].set(rows[1])
        cells = jax.lax.dynamic_update_slice(cells, win, (wj, wi, jnp.int32(0)))
        at = jnp.minimum(_get(count, 1 + nxt), self.ncell - 2)  # (a list holds each cell once: never clamped)
        two = jax.lax.dynamic_slice(dirty, (nxt, at), (1, 2))[0]
        flat = js * nx + is_
        two = jnp.where(need[0], jnp.where(need[1], flat, jnp.stack([flat[0], two[1]])),
                        jnp.where(need[1], jnp.stack([flat[1], two[1]]), two))
        dirty = jax.lax.dynamic_update_slice(dirty, two[None], (nxt, at))
        count = count + jnp.where(jnp.arange(3) == 1 + nxt, jnp.sum(need, dtype=jnp.int32), 0).astype(count.dtype)
        flags = self._flags(flags, js, is_, jnp.stack([move, move]))
        return cells, dirty, count, flags

    # ------------------------------------------------------------------ accounting
    def volumes(self, g: GroundState):
        """(the grains' solid volume in the grid's columns down to the layer's depth, the bulk volume above the
        undisturbed surface), m^3: :func:`mjrft.ground.ground_volumes` (the first is conserved by every update)."""
        a = self.frame[2] ** 2
        c = g.cells
        solid = jnp.sum(c[..., C_PHI] * (c[..., C_COL] + c[..., C_H]) - self.phi0 * (c[..., C_COL] - self.layer),
                        axis=(-2, -1))
        return solid * a, jnp.sum(c[..., C_H], axis=(-2, -1)) * a

"""The surface and the regions as the kernel sees them, in JAX: the twins of :func:`mjrft.kernel.surface_height`
and :func:`mjrft.kernel.region_weights`.

Pure, branch-free functions of point arrays ``px``, ``py`` (k,), for ``jit`` and ``vmap`` on any JAX device in
float32 or float64. The tables are the kernel's (:class:`mjrft.regions.RegionTables` and the coupler's height
field): their shapes decide at trace time which code runs (no height field: the flat surface; no strips and no
map: one region, no region work), so a scene pays only for what it has.
"""

from __future__ import annotations

import jax.numpy as jnp


def surface_height(px, py, surface, hf_z, hf_frame):
    """Height of the free (sand) surface at each point (k,): ``surface``, or with a height field (``hf_z`` nrow x
    ncol world heights, ``nrow > 0``) its bilinear interpolation, as :func:`mjrft.kernel.surface_height`:
    ``hf_frame`` = (x, y of the hfield geom, cos, sin of its yaw, rx, ry, 1/cell_x, 1/cell_y); row j at local
    y = -ry + j cell_y, column i at local x = -rx + i cell_x; outside the grid the border heights continue (the
    point is clamped onto it; a NaN coordinate counts as the grid's first row or column, as in the kernel)."""
    nrow, ncol = hf_z.shape
    if nrow == 0:
        return jnp.broadcast_to(jnp.asarray(surface, px.dtype), px.shape)
    hf_z = jnp.asarray(hf_z, px.dtype)
    fr = jnp.asarray(hf_frame, px.dtype)
    dx = px - fr[0]
    dy = py - fr[1]
    c, s = fr[2], fr[3]
    fx = (c * dx + s * dy + fr[4]) * fr[6]
    fy = (c * dy - s * dx + fr[5]) * fr[7]
    fx = jnp.where(fx > 0.0, jnp.minimum(fx, ncol - 1.0), 0.0)
    fy = jnp.where(fy > 0.0, jnp.minimum(fy, nrow - 1.0), 0.0)
    i = jnp.minimum(fx.astype(jnp.int32), ncol - 2)
    j = jnp.minimum(fy.astype(jnp.int32), nrow - 2)
    tx = fx - i
    ty = fy - j
    z00, z01 = hf_z[j, i], hf_z[j, i + 1]
    z10, z11 = hf_z[j + 1, i], hf_z[j + 1, i + 1]
    z0 = z00 + tx * (z01 - z00)
    z1 = z10 + tx * (z11 - z10)
    return z0 + ty * (z1 - z0)


def region_slots(reg_bounds, reg_map) -> int:
    """How many (region, weight) slots :func:`region_weights` returns for these tables: 4 with a region map (up to
    four cells meet at a corner), 2 with strips (two neighbours meet at a boundary), 1 with neither (one
    region)."""
    if reg_map.shape[0] > 0:
        return 4
    return 2 if reg_bounds.shape[0] > 0 else 1


def _map_axis(x, origin, cell, n: int, blend):
    """:func:`mjrft.kernel._map_axis`: cells (i0, i1) either side of ``x`` along one axis of a region map and the
    weight of i1."""
    zero = jnp.zeros(x.shape, jnp.int32)
    if n == 1:
        return zero, zero, jnp.zeros_like(x)
    t = (x - origin) / cell - 0.5  # in cell-centre units
    low = ~(t > 0.0)  # also NaN
    high = t >= n - 1.0
    i0 = jnp.where(low | high, 0.0, t).astype(jnp.int32)
    f = t - i0
    s_blend = jnp.clip(0.5 + (f - 0.5) * cell / jnp.where(blend > 0.0, blend, 1.0), 0.0, 1.0)
    s = jnp.where(blend > 0.0, s_blend, jnp.where(f >= 0.5, 1.0, 0.0))
    i1 = jnp.where(low, 1, jnp.where(high, n - 1, i0 + 1))
    i0 = jnp.where(low, 0, jnp.where(high, n - 1, i0))
    return i0, i1, jnp.where(low | high, 0.0, s)


def region_weights(px, py, reg_bounds, reg_map, reg_map_frame, blend):
    """Regions at each point and their weights, as :func:`mjrft.kernel.region_weights`: ``(regs (k, S) int32,
    wts (k, S))`` with ``S`` = :func:`region_slots` (the kernel's four slots without those that always weigh 0;
    each row's weights sum to 1, an unused slot weighs 0).

    Strips along x (``reg_bounds``, sorted x_min of regions 1..): region k covers ``[bounds[k-1], bounds[k])``;
    within ``blend / 2`` of a boundary the two neighbours are mixed linearly (half and half on the boundary).
    Region map (``reg_map`` ny x nx region ids, ``reg_map_frame`` = x_min, y_min, cell_x, cell_y): along each axis
    the weight moves from one cell to the next over ``blend`` centred on their common edge (bilinear in x and y,
    up to four regions; a region met twice has its weights merged into its first slot). ``blend = 0``: a hard
    switch."""
    dtype = px.dtype
    blend = jnp.asarray(blend, dtype)
    if reg_map.shape[0] > 0:
        ny, nx = reg_map.shape
        fr = jnp.asarray(reg_map_frame, dtype)
        rmap = jnp.asarray(reg_map, jnp.int32)
        i0, i1, sx = _map_axis(px, fr[0], fr[2], nx, blend)
        j0, j1, sy = _map_axis(py, fr[1], fr[3], ny, blend)
        r0, r1, r2, r3 = rmap[j0, i0], rmap[j0, i1], rmap[j1, i0], rmap[j1, i1]
        w0, w1, w2, w3 = (1.0 - sx) * (1.0 - sy), sx * (1.0 - sy), (1.0 - sx) * sy, sx * sy
        m = r1 == r0  # merge repeated regions into their first slot
        w0, w1 = jnp.where(m, w0 + w1, w0), jnp.where(m, 0.0, w1)
        m0 = r2 == r0
        m1 = ~m0 & (r2 == r1)
        w0, w1, w2 = jnp.where(m0, w0 + w2, w0), jnp.where(m1, w1 + w2, w1), jnp.where(m0 | m1, 0.0, w2)
        m0 = r3 == r0
        m1 = ~m0 & (r3 == r1)
        m2 = ~m0 & ~m1 & (r3 == r2)
        w0, w1, w2 = jnp.where(m0, w0 + w3, w0), jnp.where(m1, w1 + w3, w1), jnp.where(m2, w2 + w3, w2)
        w3 = jnp.where(m0 | m1 | m2, 0.0, w3)
        return jnp.stack([r0, r1, r2, r3], axis=-1), jnp.stack([w0, w1, w2, w3], axis=-1)
    nb = reg_bounds.shape[0]
    if nb == 0:
        return jnp.zeros(px.shape + (1,), jnp.int32), jnp.ones(px.shape + (1,), dtype)
    bounds = jnp.asarray(reg_bounds, dtype)
    k = jnp.sum(px[:, None] >= bounds[None, :], axis=-1).astype(jnp.int32)  # the strip holding x (NaN: 0)
    lo = bounds[jnp.maximum(k - 1, 0)]
    hi = bounds[jnp.minimum(k, nb - 1)]
    b = jnp.where(blend > 0.0, blend, 1.0)
    near_lo = (blend > 0.0) & (k > 0) & (px - lo < 0.5 * blend)
    near_hi = (blend > 0.0) & ~near_lo & (k < nb) & (hi - px < 0.5 * blend)
    s_lo = 0.5 + (px - lo) / b
    s_hi = 0.5 + (px - hi) / b
    s = jnp.where(near_lo, s_lo, jnp.where(near_hi, s_hi, 1.0))
    r0 = jnp.where(near_hi, k + 1, k)
    r1 = jnp.where(near_lo, k - 1, jnp.where(near_hi, k, 0))
    w1 = jnp.where(near_lo | near_hi, 1.0 - s, 0.0)
    return jnp.stack([r0, r1], axis=-1), jnp.stack([s, w1], axis=-1)


def heaviest_region(regs, wts):
    """The region of each row's largest weight (the first of equal ones), the one an element reports
    (:func:`mjrft.kernel._heaviest`)."""
    return jnp.take_along_axis(regs, jnp.argmax(wts, axis=-1)[:, None], axis=-1)[:, 0]


__all__ = ["heaviest_region", "region_slots", "region_weights", "surface_height"]

"""The sand surface and the regions as the compiled kernels see them.

:func:`surface_height` is the free surface's height at a point (flat, or a height field interpolated bilinearly
between its samples); :func:`region_weights` the regions at a point and their weights (strips along x or a map
over (x, y), neighbours blended over the transition width). :func:`surface_heights` and
:func:`region_weights_many` evaluate them at many points (:meth:`mjrft.GranularTerrain.surface_height`,
:meth:`mjrft.GranularTerrain.region_weights`); the kernel (:mod:`mjrft.kernel`) calls them per element.
"""

from __future__ import annotations

from numba import njit


@njit(cache=True, error_model="numpy")
def surface_height(px, py, surface, hf_z, hf_frame):
    """Height of the free (sand) surface at ``(px, py)``: ``surface``, or with a height field the bilinear
    interpolation of ``hf_z`` (nrow x ncol world heights; row j at local y = -ry + j cell_y, column i at
    local x = -rx + i cell_x). ``hf_frame`` = (x, y of the hfield geom, cos, sin of its yaw, rx, ry,
    1/cell_x, 1/cell_y). Outside the grid the border heights continue (the point is clamped onto it)."""
    nrow = hf_z.shape[0]
    if nrow == 0:
        return surface
    ncol = hf_z.shape[1]
    dx = px - hf_frame[0]
    dy = py - hf_frame[1]
    c, s = hf_frame[2], hf_frame[3]
    fx = (c * dx + s * dy + hf_frame[4]) * hf_frame[6]
    fy = (c * dy - s * dx + hf_frame[5]) * hf_frame[7]
    if not fx > 0.0:  # also NaN: the caller's finiteness check reports the state
        fx = 0.0
    elif fx > ncol - 1.0:
        fx = ncol - 1.0
    if not fy > 0.0:
        fy = 0.0
    elif fy > nrow - 1.0:
        fy = nrow - 1.0
    i = min(int(fx), ncol - 2)
    j = min(int(fy), nrow - 2)
    tx = fx - i
    ty = fy - j
    z0 = hf_z[j, i] + tx * (hf_z[j, i + 1] - hf_z[j, i])
    z1 = hf_z[j + 1, i] + tx * (hf_z[j + 1, i + 1] - hf_z[j + 1, i])
    return z0 + ty * (z1 - z0)

@njit(cache=True, error_model="numpy")
def _map_axis(x, origin, cell, n, blend):
    """Cells (i0, i1) either side of ``x`` along one axis of a region map and the weight of i1."""
    t = (x - origin) / cell - 0.5  # in cell-centre units
    if n == 1 or not t > 0.0:
        return 0, min(1, n - 1), 0.0
    if t >= n - 1.0:
        return n - 1, n - 1, 0.0
    i0 = int(t)
    f = t - i0
    if blend > 0.0:
        s = 0.5 + (f - 0.5) * cell / blend
        s = min(1.0, max(0.0, s))
    else:
        s = 1.0 if f >= 0.5 else 0.0
    return i0, i0 + 1, s

@njit(cache=True, error_model="numpy", inline="always")
def strip_of(x, reg_bounds):
    """The strip region containing ``x``: the number of strip starts ``reg_bounds`` (sorted) at or below it."""
    k = 0
    while k < reg_bounds.shape[0] and x >= reg_bounds[k]:
        k += 1
    return k

@njit(cache=True, error_model="numpy")
def region_weights(px, py, reg_bounds, reg_map, reg_map_frame, blend):
    """Regions at ``(px, py)`` and their weights (four slots, unused ones weigh 0; the weights sum to 1).

    Strips along x (``reg_bounds``, sorted x_min of regions 1..): region k covers
    ``[bounds[k-1], bounds[k])``; within ``blend / 2`` of a boundary the two neighbours are mixed
    linearly (half and half on the boundary). Region map (``reg_map`` ny x nx region ids,
    ``reg_map_frame`` = x_min, y_min, cell_x, cell_y): along each axis the weight moves from one cell to
    the next over ``blend`` centred on their common edge (bilinear in x and y, up to four regions).
    ``blend = 0``: hard switch.
    """
    if reg_map.shape[0] > 0:
        i0, i1, sx = _map_axis(px, reg_map_frame[0], reg_map_frame[2], reg_map.shape[1], blend)
        j0, j1, sy = _map_axis(py, reg_map_frame[1], reg_map_frame[3], reg_map.shape[0], blend)
        r0, r1, r2, r3 = reg_map[j0, i0], reg_map[j0, i1], reg_map[j1, i0], reg_map[j1, i1]
        w0, w1, w2, w3 = (1.0 - sx) * (1.0 - sy), sx * (1.0 - sy), (1.0 - sx) * sy, sx * sy
        if r1 == r0:  # merge repeated regions into their first slot
            w0 += w1
            w1 = 0.0
        if r2 == r0:
            w0 += w2
            w2 = 0.0
        elif r2 == r1:
            w1 += w2
            w2 = 0.0
        if r3 == r0:
            w0 += w3
            w3 = 0.0
        elif r3 == r1:
            w1 += w3
            w3 = 0.0
        elif r3 == r2:
            w2 += w3
            w3 = 0.0
        return (r0, r1, r2, r3), (w0, w1, w2, w3)
    nb = reg_bounds.shape[0]
    k = strip_of(px, reg_bounds)
    if blend > 0.0:
        if k > 0 and px - reg_bounds[k - 1] < 0.5 * blend:
            s = 0.5 + (px - reg_bounds[k - 1]) / blend
            return (k, k - 1, 0, 0), (s, 1.0 - s, 0.0, 0.0)
        if k < nb and reg_bounds[k] - px < 0.5 * blend:
            s = 0.5 + (px - reg_bounds[k]) / blend
            return (k + 1, k, 0, 0), (s, 1.0 - s, 0.0, 0.0)
    return (k, 0, 0, 0), (1.0, 0.0, 0.0, 0.0)

@njit(cache=True, error_model="numpy")
def surface_heights(xs, ys, surface, hf_z, hf_frame, out):
    """:func:`surface_height` at many points (``out[i]`` for ``(xs[i], ys[i])``)."""
    for i in range(xs.shape[0]):
        out[i] = surface_height(xs[i], ys[i], surface, hf_z, hf_frame)

@njit(cache=True, error_model="numpy")
def region_weights_many(xs, ys, reg_bounds, reg_map, reg_map_frame, blend, out):
    """:func:`region_weights` at many points, accumulated into ``out[i, region]`` (zeroed by the caller)."""
    for i in range(xs.shape[0]):
        regs, wts = region_weights(xs[i], ys[i], reg_bounds, reg_map, reg_map_frame, blend)
        for q in range(4):
            out[i, regs[q]] += wts[q]

@njit(cache=True, error_model="numpy", inline="always")
def map_cell(px, py, frame, nx, ny, blend):
    """Cell (i, j) of a region map (``frame`` = x_min, y_min, cell_x, cell_y; ``nx`` x ``ny`` cells) holding
    ``(px, py)``, clamped onto the grid (NaN -> 0, reported as a bad state by the caller), and whether the
    point lies within ``blend / 2`` of an edge to another cell (where the regions are blended)."""
    x0, y0, cx, cy = frame
    fx = (px - x0) / cx
    fy = (py - y0) / cy
    ci = min(int(fx), nx - 1) if fx > 0.0 else 0
    cj = min(int(fy), ny - 1) if fy > 0.0 else 0
    hx = 0.5 * blend / cx
    hy = 0.5 * blend / cy
    near = ((ci > 0 and fx - ci < hx) or (ci < nx - 1 and ci + 1 - fx < hx)
            or (cj > 0 and fy - cj < hy) or (cj < ny - 1 and cj + 1 - fy < hy))
    return ci, cj, near

@njit(cache=True, error_model="numpy", inline="always")
def heaviest_region(regs, wts):
    """The region of the largest of the four weights (:func:`region_weights`), the one an element reports."""
    top_q = 0
    for slot in range(1, 4):
        if wts[slot] > wts[top_q]:
            top_q = slot
    return regs[top_q]

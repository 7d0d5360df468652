"""The ground memory: a height map of the sand surface and a packing per cell that remember what the legs did.

Off by default; ``GranularTerrain(model, ground_memory=True)`` (or a :class:`GroundOptions`) turns it on. Without it
every element meets fresh grains at the medium's prepared packing and a level surface. With it:

* a grid of square cells over the ground the robot can reach (:class:`GroundOptions`: the cell is the elements'
  size, the extent the robot's footprint at the initial pose grown by ``reach`` = 1 m on every side) holds the
  grains' surface above the undisturbed one and their volume fraction ``phi``;
* an element's depth is measured from that surface (bilinear between cell centres), and its law's parameter row
  is the one of the local packing: ``p = p_0 + (s - s_0) (p_CP - p_LP)``, ``s = (phi - phi_LP) / (phi_CP -
  phi_LP)`` the position between the medium's loosely (LP) and closely packed (CP) states (Li, Zhang & Goldman,
  Science 2013, suppl. tables S1-S2: poppy seeds and 0.3 mm glass measured in both), ``p_0`` the terrain's own
  row (the prepared state ``s_0``), so a cell as prepared gives the same force as a terrain without memory;
* after each step (:func:`ground_step`) a body's footprint sinks into the cells it is in, the volume it displaces
  first compacts loose grains beneath it (up to the closely packed state) and the rest heaps up as a ridge on the
  cells around the footprint; the grains the flowing elements' leading faces move through are left at the
  critical state (loose grains contract, close ones dilate); slopes between free cells steeper than the medium's
  angle of repose avalanche (:func:`relax_sweep`);
* on a terrain whose regions use the hybrid law, each cell also keeps its wake: per depth slab the earliest time a
  leading face passed through it while bodies are in the cell, from which the law's undisturbed-grain rule decides
  per element whether it moves into grains a body has already pushed away (:func:`in_wake`).

The model's equations, its constants and their sources, and the choices where the papers are silent are in
docs/terrain.md ("Ground memory"). The records are :class:`~mjrft.types.GroundTables` (in the terrain model) and the
``g_*`` arrays of :class:`~mjrft.types.TerrainState`; the compiled kernel (:mod:`mjrft.kernel`) reads the surface and
packing per element and calls :func:`ground_step` after its element loop.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import mujoco
import numpy as np
from numba import njit

from .errors import check_finite, check_positive
from .media import Medium, get_medium
from .params import P_INERTIA, P_INERTIA_SKIN, P_INERTIA_VC2, P_SIZE, P_WATER_DEPTH, P_WATER_DRAG, P_WATER_SKIN
from .surface import surface_height
from .types import GroundBlocks, GroundTables, no_ground

#: the default cell as a multiple of the elements' size: a cell holds a few elements of a foot, so a footprint is
#: resolved to two elements; halving it doubles the memory's cost (benchmarks/bench_ground.py: 97 % of the kernel at
#: 10 mm cells on the hexapod, 188 % at 5 mm)
CELL_ELEMENTS = 2.0
#: default distance (m) the grid reaches beyond the robot's footprint at the initial pose, on every side
GROUND_REACH = 1.0
#: default thickness (m) of the layer whose packing a cell holds (and which compacts or dilates)
GROUND_LAYER = 0.03
#: how far (m) from a footprint cell the rim that takes its displaced grains is searched for
RIDGE_REACH = 0.2
#: the most cells a grid may have (a finer cell or a larger extent is refused, naming the count)
MAX_GROUND_CELLS = 2_000_000
#: the share of a slope's excess over the angle of repose that one relaxation sweep moves (stable below 1)
RELAX = 0.5
#: the rest memory's saturation above which an element counts as flowing (the implicit step's HOLD_FRACTION)
FLOWING = 0.9
#: the ground updates once per this much simulated time (s; every step when the timestep is longer): a leg moving at
#: 2.5 m/s crosses one 1 cm cell (the hexapod's) between updates
GROUND_PERIOD = 0.004
#: cells per side of the blocks whose highest surface the kernel's culling reads, as a power of 2 (4 cells)
BLOCK_SHIFT = 2
#: a slope's excess over the angle of repose (in cells' edge lengths) below which the relaxation leaves it: the
#: excess decays geometrically, and a cell moving less than this drops off the sweeps' list
RELAX_TOL = 1e-4
#: the least deepening of a footprint (m, the bodies' volume below the surface per cell area beyond what the cell has
#: taken, as a share of the cell's edge) that an update acts on: a body held at one depth or dragged level leaves a
#: difference of rounding alone (the kernel's and mjrft.mjx's sums, float64 or float32, would take different branches
#: on its sign), while any real deepening passes it or adds up until it does (the cell's displaced volume is the
#: bodies' total, not a per-update step); 1e-5 of a 1 cm cell is 0.1 um, a thousandth of the finest grains'
#: diameter
DEEPEN_TOL = 1e-5
#: the wake (the hybrid law's undisturbed-grain rule, :func:`in_wake`): the depth slabs per cell, each half a cell
#: thick, of which the first WAKE_ABOVE lie above the undisturbed surface (ridges): 48 slabs of 5 mm cells reach
#: 10 cm below the surface and 2 cm above it (a time in float32 per slab: 192 bytes per cell)
WAKE_SLABS = 48
WAKE_ABOVE = 8
#: an element is in the wake of slabs passed through more than this many cells' crossing times (cell / speed) and one
#: update before: its own cell and the one ahead, which its own leading face and the parts of the body moving with it
#: may have passed through themselves
WAKE_LAG_CELLS = 2.0

# Li 2013, table S2: the ratio of the closely to the loosely packed scaling factor zeta per unit of volume fraction,
# ln(zeta_CP / zeta_LP) / (phi_CP - phi_LP), of the two media measured in both states (poppy seeds 0.488 / 0.248,
# 0.3 mm glass 0.371 / 0.194, both phi 0.58 -> 0.62): 16.92 and 16.21 per unit phi; their mean gives the loose state of
# a medium measured only closely packed.
_ZETA_PER_PHI = 0.5 * (math.log(0.488 / 0.248) + math.log(0.371 / 0.194)) / 0.04


@dataclass(frozen=True)
class Packing:
    """A medium's loosely and closely packed states: the two media (``loose``, ``close``), their volume fractions,
    the critical state's ``phi_crit`` (where shear neither dilates nor compacts the grains), the angles of repose
    (deg) and where each number comes from."""

    loose: Medium
    close: Medium
    phi_lp: float
    phi_cp: float
    phi_crit: float
    repose_lp: float
    repose_cp: float
    source: str

    @property
    def paired(self) -> bool:
        return self.phi_cp > self.phi_lp


def _derived_loose(close: Medium, phi_lp: float) -> Medium:
    """The loose state of a medium measured only closely packed: its own fit times exp(-k (phi_CP - phi_LP)),
    ``k`` the mean of Li's two measured pairs (:data:`_ZETA_PER_PHI`)."""
    r = math.exp(-_ZETA_PER_PHI * (close.volume_fraction - phi_lp))
    return dataclasses.replace(
        close, name=close.name.replace("_cp", "_lp") + "_derived", coeffs=tuple(c * r for c in close.coeffs),
        zeta=close.zeta * r, alpha_z_measured=None if close.alpha_z_measured is None else close.alpha_z_measured * r,
        volume_fraction=phi_lp, mu_int=None,
        description=f"{close.name} scaled by {r:.3f} to volume fraction {phi_lp:g} (mjrft.ground)")


def _pairs() -> dict[str, tuple]:
    """Medium name -> (loose name or derived medium, close name, phi_crit, repose LP, repose CP, source)."""
    poppy = ("Li 2013 suppl. tables S1-S2 (LP 0.58, CP 0.62, repose 36 / 47 deg); phi_crit 0.60: the thesis "
             "'A robophysics approach to bipedal walking in granular media', secs. 1.3.3 and 2.3.1")
    glass = ("Li 2013 suppl. tables S1-S2 (LP 0.58, CP 0.62, repose 25 / 35 deg); phi_crit 0.60: the middle of "
             "the pair, as for poppy seeds (a choice)")
    glass3 = ("CP: Li 2013 suppl. tables S1-S2 (0.63, repose 21 deg); LP 0.61: Zhang et al., 'Ground fluidization "
              "promotes rapid running of a lightweight robot', sec. 2.1.2 (0.61 < phi < 0.63 achievable); its "
              "strength from Li's two measured pairs (exp(-16.6 x 0.02) = 0.718 of CP), repose 21 deg and phi_crit "
              "0.62 the middle (choices)")
    return {"poppy_lp": ("poppy_lp", "poppy_cp", 0.60, 36.0, 47.0, poppy),
            "poppy_cp": ("poppy_lp", "poppy_cp", 0.60, 36.0, 47.0, poppy),
            "glass03_lp": ("glass03_lp", "glass03_cp", 0.60, 25.0, 35.0, glass),
            "glass03_cp": ("glass03_lp", "glass03_cp", 0.60, 25.0, 35.0, glass),
            "glass3_cp": (0.61, "glass3_cp", 0.62, 21.0, 21.0, glass3)}


def packing_of(medium, repose_angle: float | None = None) -> Packing:
    """The :class:`Packing` of ``medium`` (a :class:`~mjrft.media.Medium` or catalogue name). Poppy seeds and 0.3 mm
    glass have Li's measured pairs; 3 mm glass a derived loose state; a medium air-fluidised by
    :func:`mjrft.media.fluidized` the pair of its base medium under the same flow. Any other medium has one state
    (``paired`` False: the height map remembers, the strength does not change); its angle of repose is its
    ``repose_angle``, else ``atan(mu_int)`` of a 3D-RFT medium, else ``repose_angle`` here, else a ``ValueError``."""
    from .media import fluidized

    m = get_medium(medium)
    base, flow = m.get("fluidized_from"), float(m.get("air_flow", 0.0))
    entry = _pairs().get(base if base is not None else m.name)
    if entry is not None:
        lo, hi, crit, rep_lp, rep_cp, src = entry
        close = get_medium(hi)
        loose = _derived_loose(close, lo) if isinstance(lo, float) else get_medium(lo)
        if flow > 0.0:
            loose, close = fluidized(loose, flow), fluidized(close, flow)
            src += f"; both under an air flow of {flow:g} of the onset of fluidisation (mjrft.media.fluidized)"
        if repose_angle is not None:
            rep_lp = rep_cp = float(repose_angle)
        return Packing(loose, close, float(loose.volume_fraction), float(close.volume_fraction), crit, rep_lp, rep_cp,
                       src)
    rep = repose_angle if repose_angle is not None else m.repose_angle
    if rep is None and m.mu_int is not None and m.volume_fraction == 1.0:  # a 3D-RFT medium (mjrft.media.medium_3d)
        rep = math.degrees(math.atan(m.mu_int))
    if rep is None:
        raise ValueError(f"ground_memory needs the angle of repose of medium {m.name!r}, which it does not carry: "
                         "pass ground_memory=GroundOptions(repose_angle=<deg>), or use a medium with one (poppy_lp, "
                         "poppy_cp, glass03_lp, glass03_cp, glass3_cp)")
    phi = float(m.volume_fraction) if m.volume_fraction is not None else 1.0
    return Packing(m, m, phi, phi, phi, float(rep), float(rep), "one state: the medium's own")


@dataclass(frozen=True)
class GroundOptions:
    """The ground memory's grid and layer (``GranularTerrain(model, ground_memory=GroundOptions(...))``; ``True`` is
    ``GroundOptions()``).

    Args:
        cell: the cells' edge (m); default :data:`CELL_ELEMENTS` = 2 times the elements' resolution.
        extent: ``(x_min, x_max, y_min, y_max)`` of the grid (m); default the selected geoms' box at the model's
            initial pose grown by ``reach`` on every side. Outside it the ground keeps no memory (the border cells'
            values continue).
        reach: see ``extent`` (m, default :data:`GROUND_REACH` = 1).
        layer: the thickness (m) of the layer whose packing a cell holds: the layer that compacts under a load and
            dilates or contracts under shear (default :data:`GROUND_LAYER` = 3 cm, the depth range of the bundled
            robots' feet).
        repose_angle: the angle of repose (deg) of both states, instead of the medium's (Li 2013 table S1).
        period: the simulated time (s) between two updates of the ground (default :data:`GROUND_PERIOD`; every step
            when the timestep is longer).
    """

    cell: float | None = None
    extent: tuple | None = None
    reach: float = GROUND_REACH
    layer: float = GROUND_LAYER
    repose_angle: float | None = None
    period: float = GROUND_PERIOD

    def __post_init__(self):
        if self.cell is not None:
            check_positive("ground cell", self.cell)
        check_positive("ground reach", self.reach, allow_zero=True)
        check_positive("ground layer", self.layer)
        check_positive("ground period", self.period)
        if self.repose_angle is not None:
            a = check_finite("ground repose_angle", self.repose_angle)
            if not 0.0 < a < 90.0:
                raise ValueError(f"ground repose_angle must be in (0, 90) deg, got {a!r}")
        if self.extent is not None:
            e = tuple(float(v) for v in self.extent)
            if len(e) != 4 or not all(math.isfinite(v) for v in e) or not (e[0] < e[1] and e[2] < e[3]):
                raise ValueError(f"ground extent must be (x_min, x_max, y_min, y_max) with x_min < x_max and "
                                 f"y_min < y_max, got {self.extent!r}")
            object.__setattr__(self, "extent", e)

    @classmethod
    def from_value(cls, value) -> "GroundOptions | None":
        """``ground_memory`` as given: False or None (off), True (the defaults), or a :class:`GroundOptions`."""
        if value is None or value is False:
            return None
        if value is True:
            return cls()
        if isinstance(value, cls):
            return value
        if isinstance(value, dict):
            return cls(**value)
        raise TypeError(f"ground_memory must be True, False or a mjrft.ground.GroundOptions, got {value!r}")


def _footprint(model: mujoco.MjModel, geom_ids) -> tuple[float, float, float, float]:
    """(x_min, x_max, y_min, y_max) of the selected geoms' bounding boxes at the model's initial pose."""
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    lo, hi = np.full(2, np.inf), np.full(2, -np.inf)
    for g in geom_ids:
        r = float(model.geom_rbound[g]) if model.geom_rbound[g] > 0 else 0.0
        c = data.geom_xpos[g, :2]
        lo, hi = np.minimum(lo, c - r), np.maximum(hi, c + r)
    if not np.all(np.isfinite(lo)):
        return 0.0, 0.0, 0.0, 0.0
    return float(lo[0]), float(hi[0]), float(lo[1]), float(hi[1])


def build_ground(model: mujoco.MjModel, options: GroundOptions | None, settings, region_list, stress_scale: float,
                 surface) -> GroundTables:
    """The :class:`~mjrft.types.GroundTables` of a terrain (``settings``: its resolved
    :class:`~mjrft.settings.TerrainSettings`; ``region_list``: its resolved regions; ``surface``: its
    :class:`~mjrft.types.SurfaceTables`), or the empty tables when ``options`` is None."""
    if options is None:
        return no_ground()
    cell = float(options.cell) if options.cell is not None else CELL_ELEMENTS * float(settings.resolution)
    if options.extent is not None:
        x0, x1, y0, y1 = options.extent
    else:
        x0, x1, y0, y1 = _footprint(model, settings.geom_ids)
        x0, x1, y0, y1 = x0 - options.reach, x1 + options.reach, y0 - options.reach, y1 + options.reach
    nx, ny = max(2, int(math.ceil((x1 - x0) / cell))), max(2, int(math.ceil((y1 - y0) / cell)))
    if nx * ny > MAX_GROUND_CELLS:
        raise ValueError(f"the ground memory's grid would have {nx} x {ny} = {nx * ny:,} cells of {cell:g} m, more than "
                         f"MAX_GROUND_CELLS = {MAX_GROUND_CELLS:,}: pass ground_memory=GroundOptions(cell=...) with a "
                         f"larger cell, or a smaller extent or reach")
    frame = np.array([x0, y0, cell, 1.0 / cell])
    gt = GroundTables(frame, np.array([ny, nx], dtype=np.int64), ground_base(frame, (ny, nx), surface), np.zeros(8),
                      np.zeros((0, P_SIZE)), max(1, int(math.ceil(RIDGE_REACH / cell))), float(options.period), True)
    return build_ground_packing(gt, settings, region_list, stress_scale)


def build_ground_packing(gt: GroundTables, settings, region_list, stress_scale: float) -> GroundTables:
    """``gt`` with the packing constants of ``settings``' own medium (and its ground options' angle of repose) and the
    packing rows of the regions ``region_list`` with stresses times ``stress_scale`` (a new medium or new regions)."""
    options = settings.ground
    pack = packing_of(settings.medium, options.repose_angle)
    tan_lp, tan_cp = math.tan(math.radians(pack.repose_lp)), math.tan(math.radians(pack.repose_cp))
    phi0 = float(settings.medium.volume_fraction) if pack.paired else pack.phi_lp
    inv_range = 1.0 / (pack.phi_cp - pack.phi_lp) if pack.paired else 0.0
    consts = np.array([pack.phi_lp, pack.phi_cp, pack.phi_crit, phi0, inv_range, tan_lp, tan_cp, float(options.layer)])
    return gt._replace(pack=consts, dparams=packing_rows(settings, region_list, stress_scale))


def ground_base(frame: np.ndarray, shape, surface) -> np.ndarray:
    """The undisturbed surface's height (m) at the centres of a grid (``frame``: x_min, y_min, cell, 1 / cell;
    ``shape``: (ny, nx)) under the :class:`~mjrft.types.SurfaceTables` ``surface``."""
    ny, nx = shape
    xs = frame[0] + (np.arange(nx) + 0.5) * frame[2]
    ys = frame[1] + (np.arange(ny) + 0.5) * frame[2]
    if surface.hfield_z.size == 0:
        return np.full((ny, nx), float(surface.height))
    out = np.empty((ny, nx))
    for j in range(ny):
        for i in range(nx):
            out[j, i] = surface_height(xs[i], ys[j], surface.height, surface.hfield_z, surface.hfield_frame)
    return out


def packing_rows(settings, region_list, stress_scale: float) -> np.ndarray:
    """Each region's closely minus loosely packed parameter row (nregion, P_SIZE), stresses times ``stress_scale``;
    zeros for a region whose medium has one state. The water layer's and the inertial regime's slots are zero: the
    water is the same over either state, and the regime keeps the prepared bed's bulk density (a choice: 3 %
    between the states)."""
    from .regions import build_regions

    rows = np.zeros((len(region_list), P_SIZE))
    for k, reg in enumerate(region_list):
        pk = packing_of(reg.medium, None) if _has_repose(reg.medium) else None
        if pk is None or not pk.paired:
            continue
        one = []
        for med in (pk.loose, pk.close):
            s = dataclasses.replace(settings, medium=med, law=reg.law, regions=[], region_map=None,
                                    water_depth=reg.water_depth)
            one.append(build_regions(s, stress_scale)[1].params[0])
        rows[k] = one[1] - one[0]
    for slot in (P_WATER_DEPTH, P_WATER_DRAG, P_WATER_SKIN, P_INERTIA, P_INERTIA_VC2, P_INERTIA_SKIN):
        rows[:, slot] = 0.0
    return rows


def _has_repose(medium) -> bool:
    try:
        packing_of(medium)
    except ValueError:
        return False
    return True


def with_ground_surface(gt: GroundTables, surface) -> GroundTables:
    """``gt`` over a new undisturbed surface (``surface``: :class:`~mjrft.types.SurfaceTables`)."""
    if not gt.on:
        return gt
    return gt._replace(base=ground_base(gt.frame, tuple(gt.shape), surface))


# ------------------------------------------------------------------------------------------------
# the compiled part: what the kernel reads per element, and the update
# ------------------------------------------------------------------------------------------------
#: the fields of a cell's record in :attr:`~mjrft.types.TerrainState.g_cells` (one cache line per cell): the volume
#: fraction of its column, the grains' surface above the undisturbed one (m), the volume a body has displaced from
#: the cell during its contact (m, per cell area; the elements read the surface ``C_H + C_PEND``: the level before
#: the body came), the volume the flowing leading faces moved through since the last update (m^3), the bodies'
#: volume below the surface now (m^3), the last update a body was in the cell, the last relaxation sweep that
#: listed it, and the depth below the undisturbed surface down to which the cell's column is held (m; the layer, or
#: deeper under a deep hole)
C_PHI, C_H, C_PEND, C_SWEPT, C_SUB, C_STAMP, C_MARK, C_COL = 0, 1, 2, 3, 4, 5, 6, 7
N_FIELDS = 8


@njit(cache=True, error_model="numpy", inline="always")
def ground_sample(px, py, frame, cells):
    """What an element at ``(px, py)`` reads from the ground memory: the surface (m, above the undisturbed one), its
    gradient along x and y (bilinear between the cell centres of ``cells`` (ny, nx, N_FIELDS); 0 along an axis where
    the point lies beyond the border cells' centres, whose values continue outside the grid) and the volume fraction.
    A NaN coordinate reads cell 0 (the kernel's finiteness check reports the state)."""
    ny, nx = cells.shape[0], cells.shape[1]
    inv = frame[3]
    fx = (px - frame[0]) * inv - 0.5
    fy = (py - frame[1]) * inv - 0.5
    kx = inv
    ky = inv
    if not fx > 0.0:
        fx = 0.0
        kx = 0.0
    elif fx > nx - 1.0:
        fx = nx - 1.0
        kx = 0.0
    if not fy > 0.0:
        fy = 0.0
        ky = 0.0
    elif fy > ny - 1.0:
        fy = ny - 1.0
        ky = 0.0
    i = min(int(fx), nx - 2)
    j = min(int(fy), ny - 2)
    tx = fx - i
    ty = fy - j
    a00 = cells[j, i, C_H] + cells[j, i, C_PEND]
    a01 = cells[j, i + 1, C_H] + cells[j, i + 1, C_PEND]
    a10 = cells[j + 1, i, C_H] + cells[j + 1, i, C_PEND]
    a11 = cells[j + 1, i + 1, C_H] + cells[j + 1, i + 1, C_PEND]
    d0 = a01 - a00
    d1 = a11 - a10
    r0 = a00 + tx * d0
    r1 = a10 + tx * d1
    f0 = cells[j, i, C_PHI] + tx * (cells[j, i + 1, C_PHI] - cells[j, i, C_PHI])
    f1 = cells[j + 1, i, C_PHI] + tx * (cells[j + 1, i + 1, C_PHI] - cells[j + 1, i, C_PHI])
    return r0 + ty * (r1 - r0), (d0 + ty * (d1 - d0)) * kx, (r1 - r0) * ky, f0 + ty * (f1 - f0)


@njit(cache=True, error_model="numpy", inline="always")
def ground_top(cx, cy, ex, ey, frame, blocks):
    """(the highest surface (m, above the undisturbed one) an element within the box ``cx +- ex``, ``cy +- ey`` may
    read, the last update at which any of it changed): over the blocks within one cell of the box (the bilinear
    reaches one cell beyond the element's own); outside the grid the border blocks (the border cells continue)."""
    nby, nbx = blocks.top.shape
    inv = frame[3]
    c = frame[2]
    i0 = _block(cx - ex - c, frame[0], inv, nbx)
    i1 = _block(cx + ex + c, frame[0], inv, nbx)
    j0 = _block(cy - ey - c, frame[1], inv, nby)
    j1 = _block(cy + ey + c, frame[1], inv, nby)
    top = 0.0
    newest = 0
    for jb in range(j0, j1 + 1):
        for ib in range(i0, i1 + 1):
            top = max(top, blocks.top[jb, ib])
            newest = max(newest, blocks.stamp[jb, ib])
    return top, newest


@njit(cache=True, error_model="numpy", inline="always")
def _block(x, x0, inv, n):
    """The block along one axis holding ``x`` (clamped onto the grid; NaN -> 0)."""
    f = (x - x0) * inv
    if not f > 0.0:
        return 0
    return min(int(f) >> BLOCK_SHIFT, n - 1)


@njit(cache=True, error_model="numpy")
def sample_many(xs, ys, frame, base, cells, field, add_base, out):
    """Field ``field`` of the cells' records bilinear at many points (``out[i]`` for ``(xs[i], ys[i])``), plus the
    undisturbed surface ``base`` (bilinear too) when ``add_base`` (:meth:`mjrft.GranularTerrain.ground_height`,
    ``ground_packing``); clamped onto the grid as :func:`ground_sample`."""
    ny, nx = base.shape
    for k in range(xs.shape[0]):
        fx = min(max((xs[k] - frame[0]) * frame[3] - 0.5, 0.0), nx - 1.0)
        fy = min(max((ys[k] - frame[1]) * frame[3] - 0.5, 0.0), ny - 1.0)
        i = min(int(fx), nx - 2)
        j = min(int(fy), ny - 2)
        tx, ty = fx - i, fy - j
        v0 = cells[j, i, field] + tx * (cells[j, i + 1, field] - cells[j, i, field])
        v1 = cells[j + 1, i, field] + tx * (cells[j + 1, i + 1, field] - cells[j + 1, i, field])
        v = v0 + ty * (v1 - v0)
        if add_base:
            b0 = base[j, i] + tx * (base[j, i + 1] - base[j, i])
            b1 = base[j + 1, i] + tx * (base[j + 1, i + 1] - base[j + 1, i])
            v += b0 + ty * (b1 - b0)
        out[k] = v


@njit(cache=True, error_model="numpy", inline="always")
def _mix_in(cells, j, i, bulk, solid):
    """Add ``bulk`` (m, over the cell's area) of grains holding ``solid`` (m, likewise) on top of cell (j, i): its
    surface rises by ``bulk`` and its column's volume fraction becomes the mix."""
    m = cells[j, i, C_PHI] * (cells[j, i, C_COL] + cells[j, i, C_H]) + solid
    cells[j, i, C_H] += bulk
    cells[j, i, C_PHI] = m / (cells[j, i, C_COL] + cells[j, i, C_H])


@njit(cache=True, error_model="numpy", inline="always")
def _take(cells, j, i, bulk, layer, phi0):
    """Take ``bulk`` (m, over the cell's area) of grains off the top of cell (j, i) (at its packing); a column left
    thinner than half the layer reaches one layer deeper into the prepared bed (its grains, at ``phi0``, join the
    column: they are counted, not made, :func:`ground_volumes`)."""
    cells[j, i, C_H] -= bulk
    while cells[j, i, C_COL] + cells[j, i, C_H] < 0.5 * layer:
        m = cells[j, i, C_PHI] * (cells[j, i, C_COL] + cells[j, i, C_H]) + phi0 * layer
        cells[j, i, C_COL] += layer
        cells[j, i, C_PHI] = m / (cells[j, i, C_COL] + cells[j, i, C_H])


@njit(cache=True, error_model="numpy", inline="always")
def _mark(dirty, count, cells, nx, j, i, sweep, slot):
    """List cell (j, i) for the relaxation sweep ``sweep`` (list ``slot``) unless it is listed already."""
    if cells[j, i, C_MARK] != sweep and count[1 + slot] < dirty.shape[1]:
        cells[j, i, C_MARK] = sweep
        dirty[slot, count[1 + slot]] = j * nx + i
        count[1 + slot] += 1


@njit(cache=True, error_model="numpy", inline="always")
def _raise_block(blocks, cells, j, i):
    """Cell (j, i)'s surface changed: a rise shows at once in its block's highest surface (``blocks.top``), and the
    block is listed (``blocks.flag``, ``blocks.list``, its length ``blocks.count[0]``) for :func:`_blocks` to
    recompute at the end of the update (a fall shows then); ``blocks.peak[0]`` follows every rise."""
    jb, ib = j >> BLOCK_SHIFT, i >> BLOCK_SHIFT
    v = cells[j, i, C_H] + cells[j, i, C_PEND]
    if v > blocks.top[jb, ib]:
        blocks.top[jb, ib] = v
        if v > blocks.peak[0]:
            blocks.peak[0] = v
    if blocks.flag[jb, ib] == 0:
        blocks.flag[jb, ib] = 1
        blocks.list[blocks.count[0]] = jb * blocks.top.shape[1] + ib
        blocks.count[0] += 1


@njit(cache=True, error_model="numpy", inline="always")
def _blocks(blocks, cells, update):
    """Recompute the highest surface read in every listed block, note that it changed at ``update`` (``blocks.stamp``)
    and empty the list."""
    nbx = blocks.top.shape[1]
    ny, nx = cells.shape[0], cells.shape[1]
    for k in range(blocks.count[0]):
        b = blocks.list[k]
        jb = b // nbx
        ib = b - jb * nbx
        blocks.flag[jb, ib] = 0
        blocks.stamp[jb, ib] = update
        m = 0.0
        for j in range(jb << BLOCK_SHIFT, min(ny, (jb + 1) << BLOCK_SHIFT)):
            for i in range(ib << BLOCK_SHIFT, min(nx, (ib + 1) << BLOCK_SHIFT)):
                m = max(m, cells[j, i, C_H] + cells[j, i, C_PEND])
        blocks.top[jb, ib] = m
    blocks.count[0] = 0


@njit(cache=True, error_model="numpy")
def _ridge(cells, dirty, count, blocks, rim, j, i, solid, step, reach, crit, sweep, slot):
    """Put the grains (``solid``: their solid volume over one cell's area, m) that a footprint displaces from cell
    (j, i) on its rim: along each of the 8 grid directions the first cell within ``reach`` cells that no body is in
    takes an equal share, landing at the critical state ``crit`` (sheared grains). ``rim`` (8,): scratch. Returns
    False when no such cell is found (the caller then keeps the grains in place)."""
    ny, nx = cells.shape[0], cells.shape[1]
    found = 0
    for d in range(8):
        di = (1, 1, 0, -1, -1, -1, 0, 1)[d]
        dj = (0, 1, 1, 1, 0, -1, -1, -1)[d]
        ii, jj = i, j
        for r in range(reach):
            ii += di
            jj += dj
            if ii < 0 or jj < 0 or ii >= nx or jj >= ny:
                break
            if cells[jj, ii, C_STAMP] != step:
                rim[found] = jj * nx + ii
                found += 1
                break
    if found == 0:
        return False
    share = solid / found
    for k in range(found):
        jj = rim[k] // nx
        ii = rim[k] - jj * nx
        _mix_in(cells, jj, ii, share / crit, share)
        _raise_block(blocks, cells, jj, ii)
        _mark(dirty, count, cells, nx, jj, ii, sweep, slot)
    return True


@njit(cache=True, error_model="numpy", _nrt=False)
def relax_sweep(base, cells, dirty, count, clock, blocks, step, cell, tan_lp, tan_cp, phi_lp, inv_range, layer, phi0):
    """One sweep of the slopes' relaxation over the listed cells (Gauss-Seidel): between a listed cell no body is in
    and each of its four neighbours no body is in, when the drop ``d = H_high - H_low`` (``H`` = undisturbed surface +
    grains' surface) exceeds ``cell tan(theta)`` (``theta`` the angle of repose at the high cell's packing, between
    the loose and close states' angles), grains move from the high cell to the low one, ``RELAX / 2`` of the excess
    in height each way (bulk and solid volume kept; the low cell's packing becomes the mix). Each move lowers the
    sum of the squared heights, so the sweeps cannot oscillate, and the fixed point has every such slope at or below
    the angle of repose (docs/terrain.md, "Ground memory"), to within ``RELAX_TOL`` cell edges. The cells that moved
    are listed for the next sweep."""
    ny, nx = cells.shape[0], cells.shape[1]
    sweep = clock[1] + 1
    cur = clock[1] % 2
    nxt = 1 - cur
    n = count[1 + cur]
    count[1 + nxt] = 0
    for k in range(n):
        c = dirty[cur, k]
        j = c // nx
        i = c - j * nx
        if cells[j, i, C_STAMP] == step:
            continue
        for d in range(4):
            ii = i + (1, -1, 0, 0)[d]
            jj = j + (0, 0, 1, -1)[d]
            if ii < 0 or jj < 0 or ii >= nx or jj >= ny or cells[jj, ii, C_STAMP] == step:
                continue
            hc = base[j, i] + cells[j, i, C_H]
            hn = base[jj, ii] + cells[jj, ii, C_H]
            if hc >= hn:
                jh, ih, jl, il, drop = j, i, jj, ii, hc - hn
            else:
                jh, ih, jl, il, drop = jj, ii, j, i, hn - hc
            s = min(1.0, max(0.0, (cells[jh, ih, C_PHI] - phi_lp) * inv_range))
            excess = drop - cell * (tan_lp + s * (tan_cp - tan_lp))
            if excess > RELAX_TOL * cell:
                q = 0.5 * RELAX * excess
                solid = cells[jh, ih, C_PHI] * q
                _take(cells, jh, ih, q, layer, phi0)
                _raise_block(blocks, cells, jh, ih)
                _mix_in(cells, jl, il, q, solid)
                _raise_block(blocks, cells, jl, il)
                _mark(dirty, count, cells, nx, jh, ih, sweep + 1, nxt)
                _mark(dirty, count, cells, nx, jl, il, sweep + 1, nxt)
    count[1 + cur] = 0
    clock[1] = sweep


@njit(cache=True, error_model="numpy", inline="always")
def _wake_slab(base, z, cell):
    """The wake's depth slab (half a cell thick, :data:`WAKE_ABOVE` of them above the undisturbed surface ``base``)
    holding height ``z``; -1 outside the :data:`WAKE_SLABS`."""
    f = (base - z) / (0.5 * cell) + WAKE_ABOVE
    if not (f >= 0.0 and f < WAKE_SLABS):
        return -1
    return int(f)


@njit(cache=True, error_model="numpy", inline="always")
def _wake_mark(wake, j, i, base, z, size, cell, now):
    """A leading face of extent ``size`` (m) at height ``z`` passed through cell (j, i) at time ``now`` (s): each
    slab it covers keeps the earliest time a face passed through it during the bodies' stay in the cell."""
    inv = 2.0 / cell
    lo = (base - z - 0.5 * size) * inv + WAKE_ABOVE
    hi = (base - z + 0.5 * size) * inv + WAKE_ABOVE
    if not (hi >= 0.0 and lo < WAKE_SLABS):
        return
    for k in range(int(max(lo, 0.0)), int(min(hi, WAKE_SLABS - 1.0)) + 1):
        if now < wake[j, i, k]:
            wake[j, i, k] = now


@njit(cache=True, error_model="numpy", inline="always")
def in_wake(px, py, pz, mx, my, mz, speed, frame, base, wake, now, period):
    """Whether an element at ``(px, py, pz)`` moving along the unit ``(mx, my, mz)`` at ``speed`` moves into grains a
    body still in the cell has already pushed away (the hybrid law's undisturbed-grain rule, docs/terrain.md,
    "Ground memory"): the point half a cell ahead lies in a depth slab of its cell that a leading face passed through
    earlier than the element itself could have, more than ``2 cell / speed + period`` (s) before ``now`` (the time the
    element needs to cross its own cell and the one ahead, plus one update of the ground). Outside the grid: no."""
    c = frame[2]
    ax = px + 0.5 * c * mx
    ay = py + 0.5 * c * my
    az = pz + 0.5 * c * mz
    fx = (ax - frame[0]) * frame[3]
    fy = (ay - frame[1]) * frame[3]
    if not (fx >= 0.0 and fy >= 0.0 and fx < wake.shape[1] and fy < wake.shape[0]):
        return False
    i = int(fx)
    j = int(fy)
    k = _wake_slab(base[j, i], az, c)
    if k < 0:
        return False
    return now - wake[j, i, k] > WAKE_LAG_CELLS * c / speed + period


@njit(cache=True, error_model="numpy", _nrt=False)
def ground_step(gr, el, st, delta, v_eps, dt):
    """Advance the ground memory by ``dt`` (s, the time since its last update) from the element outputs the kernel has
    just written (positions, velocities, normals, depths of the elements within reach, their rest memory ``u``):
    footprints, compaction and ridges, the critical state of sheared grains, released footprints and one relaxation
    sweep (module docstring; the equations in docs/terrain.md, "Ground memory"). ``gr``: the model's
    :class:`~mjrft.types.GroundTables`; ``el``: its :class:`~mjrft.types.ElementTables`; ``st``: the
    :class:`~mjrft.types.TerrainState`; ``delta``, ``v_eps``: the rest memory's yield displacement and viscous speed
    (which elements flow)."""
    x0, y0, cell, inv = gr.frame[0], gr.frame[1], gr.frame[2], gr.frame[3]
    phi_cp, crit = gr.pack[1], gr.pack[2]
    phi_lp, inv_range, tan_lp, tan_cp, layer = gr.pack[0], gr.pack[4], gr.pack[5], gr.pack[6], gr.pack[7]
    phi0 = gr.pack[3]
    base, cells = gr.base, st.g_cells
    held, dirty, count, clock, blocks, rim = st.g_held, st.g_dirty, st.g_count, st.g_clock, st.g_blocks, st.g_rim
    ny, nx = cells.shape[0], cells.shape[1]
    area_c = cell * cell
    inv_a = 1.0 / area_c
    clock[0] += 1
    step = clock[0]
    sweep = clock[1] + 1
    slot = clock[1] % 2
    hold2 = (FLOWING * delta) * (FLOWING * delta)
    wake, now = st.g_wake, st.g_since[1]
    # 1. the buried elements: the cells they are in, the bodies' volume below the surface there (the divergence
    # theorem: a closed body's volume below the surface is the sum of depth x area x -n_z over its buried faces) and
    # the volume the flowing elements' leading faces move through
    g_start, e_area, active = el.group_start, el.area, st.group_active
    pos, vel, nrm, depth, u = st.pos, st.vel, st.normal, st.depth, st.u
    ntouch = 0
    for g in range(active.shape[0]):
        if not active[g]:
            continue
        for e in range(g_start[g], g_start[g + 1]):
            if not depth[e] > 0.0:
                continue
            fx = (pos[e, 0] - x0) * inv
            fy = (pos[e, 1] - y0) * inv
            if not (fx >= 0.0 and fy >= 0.0 and fx < nx and fy < ny):
                continue
            i = int(fx)
            j = int(fy)
            if cells[j, i, C_STAMP] != step:
                cells[j, i, C_STAMP] = step
                cells[j, i, C_SUB] = 0.0
                held[1, ntouch] = j * nx + i
                ntouch += 1
            cells[j, i, C_SUB] -= depth[e] * e_area[e] * nrm[e, 2]
            if delta > 0.0:
                flowing = u[e, 0] * u[e, 0] + u[e, 1] * u[e, 1] + u[e, 2] * u[e, 2] > hold2
            else:
                flowing = vel[e, 0] * vel[e, 0] + vel[e, 1] * vel[e, 1] + vel[e, 2] * vel[e, 2] > v_eps * v_eps
            if flowing:
                vn = vel[e, 0] * nrm[e, 0] + vel[e, 1] * nrm[e, 1] + vel[e, 2] * nrm[e, 2]
                if vn > 0.0:
                    cells[j, i, C_SWEPT] += e_area[e] * vn * dt
                    if wake.shape[0] > 0:  # the slabs its leading face passes through (the hybrid law's wake)
                        _wake_mark(wake, j, i, base[j, i], pos[e, 2], math.sqrt(e_area[e]), cell, now)
    # 2. the cells a body is in: shear to the critical state, the footprint's displaced volume (compaction, ridge)
    for k in range(ntouch):
        c = held[1, k]
        j = c // nx
        i = c - j * nx
        col = cells[j, i, C_COL]
        h = cells[j, i, C_H]
        phi = cells[j, i, C_PHI]
        f = cells[j, i, C_SWEPT] * inv_a / (col + h)
        if f > 0.0 and phi != crit:  # the grains moved through are left at the critical state
            m = phi * (col + h)
            phi += min(f, 1.0) * (crit - phi)
            h = m / phi - col
        cells[j, i, C_SWEPT] = 0.0
        dv = cells[j, i, C_SUB] * inv_a - cells[j, i, C_PEND]  # m over the cell's area: the footprint deepens
        if dv > DEEPEN_TOL * cell:
            cells[j, i, C_PEND] += dv
            va = min(dv, (col + h) * (1.0 - phi / phi_cp)) if phi < phi_cp else 0.0
            if va > 0.0:  # compaction of loose grains under the load
                m = phi * (col + h)
                h -= va
                phi = m / (col + h)
            cells[j, i, C_H] = h
            cells[j, i, C_PHI] = phi
            vr = dv - va
            if vr > 0.0:  # the rest heaps up on the rim
                if _ridge(cells, dirty, count, blocks, rim, j, i, phi * vr, step, gr.ridge, crit, sweep, slot):
                    _take(cells, j, i, vr, layer, phi0)
                else:
                    cells[j, i, C_PEND] -= vr
        else:
            cells[j, i, C_H] = h
            cells[j, i, C_PHI] = phi
        _raise_block(blocks, cells, j, i)
    # 3. the cells the bodies left: the footprint stays open, and may avalanche
    for k in range(count[0]):
        c = held[0, k]
        j = c // nx
        i = c - j * nx
        if cells[j, i, C_STAMP] != step:
            cells[j, i, C_PEND] = 0.0
            if wake.shape[0] > 0:  # the grains close over the wake the body leaves
                wake[j, i, :] = np.inf
            _raise_block(blocks, cells, j, i)
            _mark(dirty, count, cells, nx, j, i, sweep, slot)
    for k in range(ntouch):
        held[0, k] = held[1, k]
    count[0] = ntouch
    # 4. one relaxation sweep, and the blocks' highest surfaces for the culling
    if count[1 + slot] > 0:
        relax_sweep(base, cells, dirty, count, clock, blocks, step, cell, tan_lp, tan_cp, phi_lp, inv_range, layer,
                    phi0)
    _blocks(blocks, cells, step)


def make_ground_state(gt: GroundTables, n_elements: int, n_groups: int, wake: bool = False) -> dict:
    """The ``g_*`` arrays of a :class:`~mjrft.types.TerrainState` for the ground tables ``gt`` (empty when off),
    ``n_elements`` elements in ``n_groups`` cull groups, at the prepared state; ``wake``: whether the terrain keeps
    the wake of the hybrid law's undisturbed-grain rule (:func:`wake_array`)."""
    if not gt.on:
        cells = np.zeros((0, 0, N_FIELDS))
        return dict(g_cells=cells, g_height=cells[:, :, C_H], g_phi=cells[:, :, C_PHI], g_elem=np.zeros((0, 6)),
                    g_group=np.zeros((0, 3)),
                    g_held=np.zeros((2, 0), dtype=np.int64), g_dirty=np.zeros((2, 0), dtype=np.int64),
                    g_count=np.zeros(3, dtype=np.int64), g_clock=np.zeros(2, dtype=np.int64), g_since=np.zeros(1),
                    g_blocks=_block_arrays(0, 0), g_rim=np.zeros(0, dtype=np.int64), g_rows=np.zeros((0, P_SIZE)),
                    g_wake=wake_array(gt, False))
    ny, nx = (int(v) for v in gt.shape)
    cells = np.zeros((ny, nx, N_FIELDS))
    cells[:, :, C_PHI] = gt.pack[3]
    cells[:, :, C_COL] = gt.pack[7]
    return dict(g_cells=cells, g_height=cells[:, :, C_H], g_phi=cells[:, :, C_PHI], g_elem=np.zeros((n_elements, 6)),
                g_group=np.full((n_groups, 3), -1.0),
                g_held=np.zeros((2, max(1, n_elements)), dtype=np.int64),
                g_dirty=np.zeros((2, nx * ny), dtype=np.int64), g_count=np.zeros(3, dtype=np.int64),
                g_clock=np.zeros(2, dtype=np.int64), g_since=np.zeros(2),
                g_blocks=_block_arrays((ny >> BLOCK_SHIFT) + 1, (nx >> BLOCK_SHIFT) + 1), g_rim=np.zeros(8, dtype=np.int64),
                g_rows=np.zeros((gt.dparams.shape[0], P_SIZE)), g_wake=wake_array(gt, wake))


def wake_array(gt: GroundTables, wake: bool) -> np.ndarray:
    """The wake of a ground memory whose scene uses the hybrid law (``wake``; docs/terrain.md, "Ground memory"): per
    cell and depth slab the earliest time (s since the prepared bed, float32) a body's leading face passed through it
    during the bodies' stay in the cell (inf: none); (0, 0, 0) without a ground memory or without the hybrid law
    (nothing of it runs)."""
    if not (gt.on and wake):
        return np.zeros((0, 0, 0), dtype=np.float32)
    ny, nx = (int(v) for v in gt.shape)
    return np.full((ny, nx, WAKE_SLABS), np.inf, dtype=np.float32)


def uses_wake(region_law) -> bool:
    """Whether a terrain whose regions have the law ids ``region_law`` keeps the wake (a region of the hybrid law)."""
    from .laws.registry import LAW_IDS

    return bool(np.any(np.asarray(region_law) == LAW_IDS["hybrid"]))


def _block_arrays(nby: int, nbx: int) -> GroundBlocks:
    return GroundBlocks(np.zeros((nby, nbx)), np.zeros((nby, nbx), dtype=np.int64), np.zeros(nby * nbx, dtype=np.int64),
                        np.zeros(1, dtype=np.int64), np.zeros(1), np.zeros((nby, nbx), dtype=np.int64))


def ground_volumes(gt: GroundTables, st) -> tuple[float, float]:
    """(the grains' solid volume in the grid's columns down to the layer's depth, the bulk volume above the
    undisturbed surface), m^3. Grains a deep hole's column took in from below the layer (at the prepared packing)
    are counted as they were there, so the first is conserved by every update of the ground memory (grains are
    moved, never made or lost); the second changes only with the packing (compaction and dilation). What the
    conservation tests check."""
    a = gt.frame[2] ** 2
    layer, phi0 = gt.pack[7], gt.pack[3]
    c = st.g_cells
    solid = np.sum(c[:, :, C_PHI] * (c[:, :, C_COL] + c[:, :, C_H]) - phi0 * (c[:, :, C_COL] - layer))
    return float(solid * a), float(np.sum(c[:, :, C_H]) * a)

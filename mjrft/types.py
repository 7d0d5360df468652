"""The records that the CPU, batched and GPU paths share: what a terrain is, and what it remembers.

As MJX splits ``Model`` from ``Data``, mjrft splits a terrain in two:

* :class:`TerrainModel` (frozen): everything that does not change while the robot moves: the resolved settings
  (:class:`~mjrft.settings.TerrainSettings`), the surface elements of the selected geoms in cull groups
  (:class:`ElementTables`), the sand surface (:class:`SurfaceTables`), the regions with one parameter row each
  (:class:`RegionTables`, the row's layout in :mod:`mjrft.params`) and the scalar constants
  (:class:`TerrainConstants`). :func:`mjrft.build.build_model` makes it from a ``mujoco.MjModel``;
  changing the medium, the regions or the surface makes a new one (:func:`mjrft.build.with_regions`,
  :func:`mjrft.build.with_surface`).
* :class:`TerrainState`: what one world's terrain remembers and writes each step: each element's rest memory,
  the per-element and per-body outputs of the last step, and the stepping loop's trackers and scratch
  (:func:`mjrft.build.make_state`). The JAX path keeps its own per-world state (:class:`mjrft.mjx.SandState`).

:class:`~mjrft.GranularTerrain` (numba), :class:`~mjrft.batch.BatchedTerrain` and :class:`mjrft.mjx.Sand` differ
only in how they step these records; a test can hand the same :class:`TerrainModel` to two of them
(``GranularTerrain.from_model``, ``Sand.from_model``).

The compiled kernels read the model through :attr:`TerrainModel.tables` (its four numba-typed groups) and the
MuJoCo data through :class:`MjViews` and :class:`StepViews`; their arguments come in those groups (model in, data
in, state in and out), as mujoco_warp groups its kernels' arguments.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

if TYPE_CHECKING:
    from .geometry import Elements
    from .settings import TerrainSettings


class ElementTables(NamedTuple):
    """Model: the surface elements of the selected geoms (:func:`mjrft.elements.build_elements`).

    Per element: ``lpos`` (n, 3) its centre and ``lnrm`` (n, 3) its outward unit normal in its body's frame,
    ``area`` (n,) m^2, ``geom`` and ``body`` (n,) its geom and body ids. Per cull group (a run of at most
    :data:`mjrft.elements.CULL_GROUP` consecutive elements of one geom, compact in space, which the kernel skips
    while it lies above the surface): ``group_geom``, ``group_body``, ``group_start`` (its first element; one
    past the last at the end) and ``group_aabb`` (the box of its element points in the geom frame: centre, half
    sizes). ``body_ids``: the bodies that own elements, sorted; ``geom_ids``: the geoms with exposed elements,
    in element order; ``body_root`` (nbody,): each body's kinematic root (``mjModel.body_rootid``)."""

    lpos: np.ndarray
    lnrm: np.ndarray
    area: np.ndarray
    geom: np.ndarray
    body: np.ndarray
    body_ids: np.ndarray
    geom_ids: np.ndarray
    group_geom: np.ndarray
    group_body: np.ndarray
    group_start: np.ndarray
    group_aabb: np.ndarray
    body_root: np.ndarray


class SurfaceTables(NamedTuple):
    """Model: the free sand surface. ``height`` (m): the flat surface's height (with a height field, the mean of
    its samples, for display); ``hfield_z`` (nrow, ncol): the height field's world heights, row j along the
    hfield geom's y, column i along its x ((0, 0) for a flat surface); ``hfield_frame`` (8,): the hfield geom's
    x, y, the cos and sin of its yaw, its half sizes rx, ry and 1 / cell_x, 1 / cell_y; ``top`` (m): the highest
    sand or water surface anywhere, below which the kernel evaluates elements."""

    height: float
    hfield_z: np.ndarray
    hfield_frame: np.ndarray
    top: float


class RegionTables(NamedTuple):
    """Model: the regions, row 0 the terrain's own medium and law, row k its ``k``-th extra region
    (:func:`mjrft.regions.build_regions`). ``bounds``: the strips' x_min (sorted); ``law``: law ids; ``params``
    (nregion, P_SIZE): each region's parameter row (:mod:`mjrft.params`; stresses times the stress scale);
    ``rho``: the buoyancy's water density (0: none); ``map`` (ny, nx) / ``map_frame`` (x_min, y_min, cell_x,
    cell_y): a region map (empty for strips); ``transition`` (m): the width over which neighbours blend."""

    bounds: np.ndarray
    law: np.ndarray
    params: np.ndarray
    rho: np.ndarray
    map: np.ndarray
    map_frame: np.ndarray
    transition: float


class TerrainConstants(NamedTuple):
    """Model: the scalar constants. The rest memory's ``delta`` (yield displacement, m; 0: the viscous ramp),
    ``tau`` (damping time, s) and ``v_eps`` (the viscous ramp's speed, m/s); the solidify option's factor
    ``solid`` (0: off) and ``stick`` speed (m/s); whether the step is ``implicit`` in the grains' springs and
    whether the ``inertial`` regime is on in some region."""

    delta: float
    tau: float
    v_eps: float
    solid: float
    stick: float
    implicit: bool
    inertial: bool


class GroundTables(NamedTuple):
    """Model: the ground memory (:mod:`mjrft.ground`; all arrays empty when it is off, ``on`` False).

    ``frame`` (4,): the grid's x_min, y_min, cell size and 1 / cell size (cell (j, i) covers
    ``x_min + i cell <= x < x_min + (i + 1) cell`` and the same in y, its value sits at its centre); ``shape``
    (2,): (ny, nx); ``base`` (ny, nx): the undisturbed surface's height at each cell centre (the flat surface or
    the height field); ``pack`` (8,): the packing constants of the terrain's own medium: volume fractions
    phi_LP, phi_CP, phi_crit (the critical state) and phi_0 (as prepared), 1 / (phi_CP - phi_LP) (0 without a
    pair), tan of the angle of repose when loosely and closely packed, and the active layer's thickness (m);
    ``dparams`` (nregion, P_SIZE): each region's closely minus loosely packed parameter row (stresses times the
    stress scale; zeros for a medium without a pair); ``ridge`` (cells): how far from a footprint the rim is
    searched for; ``period`` (s): the simulated time between two updates; ``on``: whether the terrain has a ground
    memory."""

    frame: np.ndarray
    shape: np.ndarray
    base: np.ndarray
    pack: np.ndarray
    dparams: np.ndarray
    ridge: int
    period: float
    on: bool


class TerrainTables(NamedTuple):
    """The part of a :class:`TerrainModel` that the compiled kernels read (:attr:`TerrainModel.tables`)."""

    elements: ElementTables
    surface: SurfaceTables
    regions: RegionTables
    constants: TerrainConstants
    ground: GroundTables


@dataclass(frozen=True, eq=False)
class TerrainModel:
    """What a terrain is (module docstring): made by :func:`mjrft.build.build_model`, read by every path.

    ``settings``: the resolved settings; ``elements``, ``surface``, ``regions``, ``constants``: the tables the
    kernels read; ``region_list``: the resolved :class:`~mjrft.regions.Region` of each row of ``regions``;
    ``geometry``: the elements as the geometry cut them (:class:`~mjrft.geometry.Elements`: positions, normals,
    areas in their body's frame); ``stress_scale``: the factor already applied to every granular stress of
    ``regions.params`` (:data:`mjrft.laws.registry.STRESS_SLOTS`); ``ground``: the ground memory's tables
    (:class:`GroundTables`, off unless built with ``ground_memory``)."""

    settings: TerrainSettings
    elements: ElementTables
    surface: SurfaceTables
    regions: RegionTables
    constants: TerrainConstants
    region_list: tuple
    geometry: Elements
    stress_scale: float = 1.0
    ground: GroundTables = None

    def __post_init__(self):
        if self.ground is None:
            object.__setattr__(self, "ground", no_ground())

    @cached_property
    def tables(self) -> TerrainTables:
        """The kernels' view: ``(elements, surface, regions, constants, ground)`` (one object per model, so that a
        caller can tell a new model from the same one by identity)."""
        return TerrainTables(self.elements, self.surface, self.regions, self.constants, self.ground)

    @property
    def n_elements(self) -> int:
        return int(self.elements.area.shape[0])


class MjViews(NamedTuple):
    """Data in: the views of an ``mjData`` that the kernel reads after ``mj_step1`` (positions, orientations,
    centres of mass and ``cvel``)."""

    geom_xpos: np.ndarray
    geom_xmat: np.ndarray
    xpos: np.ndarray
    xmat: np.ndarray
    xipos: np.ndarray
    cvel: np.ndarray
    subtree_com: np.ndarray


class StepViews(NamedTuple):
    """Data in and out of the stepping loop (:func:`mjrft.stepping.run_steps`): ``xfrc_applied`` (the wrench is
    added for ``mj_step2`` and taken out again), ``qacc_smooth`` (the implicit step's), ``actuator_force`` and
    ``actuator_velocity`` (the actuators' power)."""

    xfrc_applied: np.ndarray
    qacc_smooth: np.ndarray
    actuator_force: np.ndarray
    actuator_velocity: np.ndarray


class GroundBlocks(NamedTuple):
    """State: the ground memory's blocks of cells (:mod:`mjrft.ground`, ``BLOCK_SHIFT``), which the kernel's culling
    reads: ``top`` (nby, nbx) the highest surface a cell of the block reads above the undisturbed one (m; a rise
    shows at once, a fall at the end of the update), ``flag`` (nby, nbx) whether the block is listed, ``list`` its
    flat index among the listed ones, ``count`` (1,) how many, ``peak`` (1,) the highest rise since the reset (what
    a cull group is compared with before the blocks are read), ``stamp`` (nby, nbx) the last update that changed the
    block (whether the elements above it read the ground afresh)."""

    top: np.ndarray
    flag: np.ndarray
    list: np.ndarray
    count: np.ndarray
    peak: np.ndarray
    stamp: np.ndarray


class TerrainState(NamedTuple):
    """What one terrain remembers and writes (module docstring), all arrays, zeroed by
    :func:`mjrft.build.make_state`. ``n`` elements, ``g`` cull groups, ``nbody`` bodies, ``nb`` bodies with elements.

    Memory: ``u`` (n, 3) each element's elastic displacement (the rest memory, m); ``group_active`` (g,) whether a
    cull group was within reach on its last step. Element outputs of the last step: ``pos``, ``vel``, ``normal``
    (n, 3; velocity and normal of elements within reach), ``depth`` (n,), ``force`` (n, 3), ``region`` (n,).
    Body outputs: ``wrench`` (nbody, 6: force, torque about the body's centre of mass, world frame), the
    moments (nbody, 10) of the element stiffness ``stiff``, of the inertial dampers ``inert``, of the depth
    stiffness ``dstiff`` and (implicit step, else (0, 10)) of the implicit springs ``imp``, and the damping
    ``damp`` (nbody,). The stepping loop's: ``saved`` (nbody, 6) what other code had in ``xfrc_applied``;
    ``stiff_max`` (nbody, TRACK_SLOTS, 10), ``damp_max``, ``inert_max``, ``dstiff_max``: the stability checks'
    trackers (:mod:`mjrft.stability`); ``power`` (1,): the actuators' mean power over the last step call.
    Scratch: ``scr_f`` (13, n; 14 with a ground memory: row 13 the gathered elements' packing) and ``scr_i`` (2,
    n) the batched law's gather, and the implicit step's
    ``imp_jac``, ``imp_minv_jac`` (6 nb, nv), ``imp_blocks`` (nb, 6, 6), ``imp_a`` (6 nb, 6 nb), ``imp_rhs``
    (12 nb + 6), ``imp_rows`` (nb) (all empty with ``implicit=False``).

    The ground memory (:mod:`mjrft.ground`; every array empty when it is off): ``g_cells`` (ny, nx, 8) one record per
    cell (:data:`mjrft.ground.C_PHI` ...: its column's volume fraction, the grains' surface, the volume displaced
    during a body's contact, the swept and the submerged volume, the last update a body was in it, the last
    relaxation sweep that listed it, its column's depth), with the views ``g_height`` (ny, nx: the grains' surface above
    the undisturbed one, m) and ``g_phi`` (ny, nx: their volume fraction); per element ``g_elem`` (n, 6) what it read
    from the ground at the last update (or when its cull group came within reach): the surface (m), its gradient
    along x and y, the point (x, y) it was read at, and the packing as the law reads it (the change of the
    loose-to-close weight from the prepared state); per cull group ``g_group`` the update its elements last read
    the ground at (-1: never); lists of flat cell indices
    ``g_held`` (2, n: row 0 the cells a body was in at the last update, row 1 those of this one) and ``g_dirty`` (2,
    cells: the relaxation sweeps' two lists, alternating), their counts in ``g_count`` (held, dirty list 0, dirty
    list 1); ``g_clock`` (updates, sweeps); ``g_since`` (2,) the time since the last update and since the prepared
    bed (s); ``g_blocks``
    (:class:`GroundBlocks`) the highest surface read in each block of 4 x 4 cells, which the kernel's culling adds;
    ``g_rim`` (8,) scratch of the ridge; ``g_rows``
    (nregion, P_SIZE) scratch: the regions' parameter rows at an element's packing (the general pass); ``g_wake``
    (ny, nx, :data:`mjrft.ground.WAKE_SLABS`; (0, 0, 0) unless a region uses the hybrid law) the earliest time a
    body's leading face passed through each depth slab of each cell during the bodies' stay there (inf: none), which
    the hybrid law's undisturbed-grain rule reads (:func:`mjrft.ground.in_wake`)."""

    u: np.ndarray
    group_active: np.ndarray
    pos: np.ndarray
    vel: np.ndarray
    normal: np.ndarray
    depth: np.ndarray
    force: np.ndarray
    region: np.ndarray
    wrench: np.ndarray
    stiff: np.ndarray
    damp: np.ndarray
    inert: np.ndarray
    dstiff: np.ndarray
    imp: np.ndarray
    saved: np.ndarray
    stiff_max: np.ndarray
    damp_max: np.ndarray
    inert_max: np.ndarray
    dstiff_max: np.ndarray
    power: np.ndarray
    scr_f: np.ndarray
    scr_i: np.ndarray
    imp_jac: np.ndarray
    imp_minv_jac: np.ndarray
    imp_blocks: np.ndarray
    imp_a: np.ndarray
    imp_rhs: np.ndarray
    imp_rows: np.ndarray
    g_cells: np.ndarray
    g_height: np.ndarray
    g_phi: np.ndarray
    g_elem: np.ndarray
    g_group: np.ndarray
    g_held: np.ndarray
    g_dirty: np.ndarray
    g_count: np.ndarray
    g_clock: np.ndarray
    g_since: np.ndarray
    g_blocks: GroundBlocks
    g_rim: np.ndarray
    g_rows: np.ndarray
    g_wake: np.ndarray

    def forget(self, ground: GroundTables | None = None) -> None:
        """Zero the memory and the last step's outputs (a reset): what :meth:`mjrft.GranularTerrain.reset` does. A
        ground memory (its tables ``ground``) returns to the undisturbed surface, every cell at the prepared volume
        fraction with its column the layer's depth."""
        self.u[:] = 0.0
        self.force[:] = 0.0
        self.depth[:] = 0.0
        self.wrench[:] = 0.0
        self.group_active[:] = False
        self.stiff_max[:] = 0.0
        self.inert_max[:] = 0.0
        if self.g_cells.size:
            self.g_cells[:] = 0.0
            self.g_cells[:, :, 0] = ground.pack[3]  # mjrft.ground.C_PHI, C_COL
            self.g_cells[:, :, 7] = ground.pack[7]
            self.g_elem[:] = 0.0
            self.g_group[:] = -1.0
            self.g_count[:] = 0
            self.g_clock[:] = 0
            self.g_since[:] = 0.0
            self.g_wake[:] = np.inf
            for a in self.g_blocks:
                a[...] = 0


def no_ground() -> GroundTables:
    """The :class:`GroundTables` of a terrain without a ground memory (every array empty)."""
    return GroundTables(np.zeros(4), np.zeros(2, dtype=np.int64), np.zeros((0, 0)), np.zeros(8), np.zeros((0, 0)), 0,
                        0.0, False)

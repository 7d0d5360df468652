"""The MuJoCo coupler: the only place in mjrft that reads ``mjData``.

>>> terrain = mjrft.GranularTerrain(model, medium="poppy_cp", law="rft", bodies=["foot"])
>>> terrain.step(data, 10)          # 10 x (mj_step1, granular wrench, mj_step2)

Each step the terrain reads the current kinematics (after ``mj_step1``), evaluates the law on every
surface element of every selected geom that can reach the grains, and adds each body's summed force
and torque (about the body's centre of mass, world frame) to ``data.xfrc_applied`` for ``mj_step2``;
afterwards it takes exactly that contribution out again, so ``xfrc_applied`` holds only what other
code put there. For code that calls ``mj_step`` itself (or MuJoCo's viewer), :meth:`install`
registers a passive-force callback that adds the same wrench to ``qfrc_passive`` instead.

Settings left as ``None`` are read from the model's MJCF ``<custom>`` section, so a scene file can
carry its terrain::

    <custom>
      <text name="mjrft:medium" data="poppy_cp"/>      <text name="mjrft:law" data="rft"/>
      <text name="mjrft:bodies" data="leg1 leg2"/>     <text name="mjrft:geoms" data="foot_geom"/>
      <numeric name="mjrft:surface" data="0"/>          <numeric name="mjrft:resolution" data="0.005"/>
      <numeric name="mjrft:yield_displacement" data="0.001"/>
      <text name="mjrft:floor" data="auto"/>            <text name="mjrft:resolution" data="auto"/>
    </custom>

and otherwise from :data:`mjrft.settings.DEFAULTS`. A terrain is two records (:mod:`mjrft.types`): what it is
(:attr:`GranularTerrain.terrain_model`, a :class:`~mjrft.types.TerrainModel`) and what it remembers
(:attr:`GranularTerrain.terrain_state`, a :class:`~mjrft.types.TerrainState`); the compiled kernel
(:mod:`mjrft.kernel`, :mod:`mjrft.stepping`) steps them. One terrain serves one ``MjData`` at a time: stepping a
different ``MjData``, or one whose time went backwards (a reset), clears the elements' memory.
"""

from __future__ import annotations

import warnings
from dataclasses import replace

import mujoco
import numpy as np

from . import kernel
from ._jit_cache import load_cached_callees_first
from .build import (build_model, check_model, make_state, remove_floor_contacts, water_depth, with_regions,
                    with_surface)
from .divergence import mujoco_reset_error, nonfinite_error, reset_count, whole_steps
from .errors import SandContactWarning, check_finite, check_positive, unknown
from .ground import C_H, C_PHI, sample_many, uses_wake, wake_array
from .implicit_step import IMPLICIT_FUNCTIONS
from .laws.solidify import STICK_SPEED
from .media import get_medium
from .mujoco_c import mujoco_functions, mujoco_step_functions
from .reach import reach_warning, sinking_warning
from .regions import Region, _region_entries
from .stability import largest_rate, track_chatter, track_depth_springs, track_stiffness
from .stepping import CompiledCall, actuator_power, add_rows, restore_rows, run_steps, run_steps_ground
from .surface import region_weights_many, surface_heights
from .types import MjViews, StepViews, TerrainModel, TerrainState
from .watch import StabilityWatch, ValidityWatch

STABILITY_CHECK_EVERY = 50  # physics steps between the checks ...
STABILITY_CHECK_SPAN = 0.05  # ... or this much simulated time (s), whichever comes first
_STEP_FUNCTIONS = mujoco_step_functions()  # None -> the plain Python stepping loop is used
_IMPLICIT_FUNCTIONS = mujoco_functions(*IMPLICIT_FUNCTIONS)  # None -> implicit=True is refused
_NO_IMPLICIT = np.zeros(4, dtype=np.int64)
_RK4 = int(mujoco.mjtIntegrator.mjINT_RK4)


class GranularTerrain:
    """Granular forces on selected geoms of a MuJoCo model, applied through ``xfrc_applied``.

    Args:
        model: the ``MjModel``.
        medium: a :class:`~mjrft.media.Medium` or catalogue name (``mjrft.media.MEDIA``).
        law: ``"rft"``, ``"rft3d"`` or ``"depth_only"`` (``mjrft.laws.LAW_IDS``).
        bodies: body names/ids whose geoms feel the grains: their supported collision geoms (contype or
            conaffinity non-zero); a named body with no collision geom contributes its visual-only ones
            (contype = conaffinity = 0), which are then all it has (mjrft's kinematic rigs).
        geoms: geom names/ids (added to those of ``bodies``), taken as named, visual-only ones included.
            With neither (and nothing in the MJCF), every supported collision geom of every non-world
            body: a third-party model's visual meshes do not feel the grains (a model whose geoms are all
            visual-only gets an error naming them and the ``bodies=`` / ``geoms=`` that select them).
        floor: ``None`` (default), the name of a geom of the world (a plane, box or hfield with a
            horizontal top; a geom on a body welded to the world counts), or ``"auto"``: the floor the
            robot stands on, i.e. of the world's collision planes / boxes / hfields with a horizontal top
            under the selected geoms' centre (at the model's initial pose), the one whose top is highest
            among those that collide with the selected geoms (contype/conaffinity bits or an explicit
            ``<pair>``; if none does, the highest collision one). Tilted planes and boxes (walls) are never
            chosen; an error lists the candidates when there is none or when two share the highest top.
            Its top becomes the sand surface (an hfield floor: the height-field surface, as
            ``surface="<geom>"`` does) and its contacts are removed from the LOADED ``model`` (never the
            file): its ``geom_contype`` and ``geom_conaffinity`` are set to 0 and an explicit ``<pair>``
            with it gets a margin of ``-1e10`` (never within reach), so NOTHING rests on that floor any
            more, robot or not (a body the terrain does not select falls through it). The values it had
            are kept in ``floor_contacts``. Every OTHER such floor under the robot that collides with the
            selected geoms keeps its contacts and is named in a :class:`~mjrft.errors.SandContactWarning`
            (its top, and how to remove its contacts) when the robot can stand on it: its top is at or
            above the sand surface (a named floor below another), or below it by less than the robot's
            size (the largest extent of the selected geoms' bounding box at the initial pose: a geom that
            sinks that deep meets it). A deeper one is the bed's rigid bottom. Exclusive with
            ``surface``. See "Your own robot" below.
        surface: height of the flat free surface (m), or the name of an ``hfield`` geom whose height
            field is the free surface (bilinear between its samples; see "Height-field surface" below).
        resolution: target element edge length (m), the one discretisation knob, or ``"auto"`` (the
            default when neither the argument nor the MJCF's ``mjrft:resolution`` gives one): the size
            that cuts the selected geoms into about ``AUTO_ELEMENTS`` = 3,000 elements (surface area /
            size^2; the measured choice is documented at the constant), but not finer than
            ``AUTO_MIN_RESOLUTION`` = 5 mm (see :func:`auto_resolution`).
        resolution_scale: a factor (> 0) on the resolution the terrain takes from the model when ``resolution`` is
            None (its ``mjrft:resolution``, or ``"auto"``'s size): the environments' presets use it
            (:mod:`mjrft.tools.presets`); default 1. Exclusive with ``resolution``.
        yield_displacement: ``delta`` of the rest regularisation (m); 0 switches it to a viscous ramp.
        damping_time: ``tau`` (s) of the Kelvin-Voigt damping below yield; default ``0.5 sqrt(delta/g)``
            (5 ms for delta = 1 mm): critical damping at omega = 2 / tau = 400 rad/s, which keeps the
            damper inside the explicit limit for light legs carrying a robot (effective mass ~10 g,
            load ~2 N) at a 1 ms step; a body resting at its yield load gets zeta = 0.25, and the
            memory's own hysteresis dissipates the rest.
        v_eps: speed (m/s) of the viscous ramp used when ``yield_displacement`` is 0.
        water_depth: free water standing above the sand (m) where the terrain's own medium applies;
            default the medium's ``water_depth`` constant (0: dry).
        regions: optional strips along x, ``[Region(x_min, medium, law, water_depth), ...]`` (or tuples
            ``(x_min, medium, law[, water_depth])``) sorted by ``x_min``; x below the first ``x_min`` uses
            ``medium``/``law``/``water_depth``. With ``region_map``: ``(medium, law[, water_depth])`` entries.
        region_map: a :class:`RegionMap` (grid of region ids over x, y) instead of strips.
        transition: width (m) over which two neighbouring regions are blended (default 0.01; 0 = a hard
            switch). Strips must be at least this wide, map cells at least this large.
        buoyancy: apply the water's hydrostatic pressure (Archimedes) where there is water (default False).
        drag_coefficient: the water drag's ``C`` in ``C rho_w v^2 S`` for every region (default: each
            medium's constant, 0.585 unless set; ``mjrft.laws.wet``).
        water_density: ``rho_w`` (kg/m^3) of the drag and the buoyancy (default: each medium's, 1000).
        inertial: add the dry inertial (speed-dependent) regime to every region with a dry law (``rft``,
            ``rft3d``, ``depth_only``): above the critical speed ``v_c = sqrt(2 g d)`` a buried face pushed
            along its normal at speed ``u`` feels ``C rho_bulk (u^2 - v_c^2)`` (:mod:`mjrft.laws.inertial`,
            Zhang et al. DynaRoACH paper). Default False: the laws stay rate-independent and the regime costs
            nothing. The medium needs a grain diameter and a bulk density.
        inertial_drag: its coefficient ``C`` (default ``mjrft.laws.inertial.INERTIAL_DRAG`` = 2.20, derived
            from the DynaRoACH paper's numbers; the same for every medium).
        solidify: ``f``, the static yield factor of elements at rest (:mod:`mjrft.laws.solidify`): an element
            that has stopped holds up to ``f`` times the law's stress at its depth before it flows again (0, the
            default, is off; needs the rest memory, ``yield_displacement > 0``). CPU kernel only.
        stick_speed: the speed (m/s) below which an element counts as at rest under ``solidify`` (default
            ``mjrft.laws.solidify.STICK_SPEED`` = 1 mm/s).
        max_elements: the most elements the terrain may build (default ``MAX_ELEMENTS`` = 1,000,000). The
            count is estimated from the geoms' surface areas before anything is built, and a finer
            ``resolution`` raises a ``ValueError`` naming the count and the setting to change.
        ground_memory: ``True`` (or a :class:`mjrft.ground.GroundOptions`) gives the ground a memory: a height map
            with footprints and ridges, slopes relaxed to the angle of repose, and a packing per cell between the
            medium's loosely and closely packed states that shear and load change; the elements read their depth
            and parameter row from it (:mod:`mjrft.ground`; read it with :meth:`ground_height` and
            :meth:`ground_packing`; :meth:`reset` restores the prepared bed). Default False: every element meets a
            level surface at the prepared packing, and the option costs nothing. CPU kernel only.

    Water layer. Where a region has ``water_depth`` ``h_w > 0``, an element between the sand surface
    and the water surface (``-h_w < depth <= 0``) feels the SGRFT water drag ``C rho_w v^2 S`` on its
    leading projected area (law ``water`` of :mod:`mjrft.laws.wet`, evaluated on the element's real
    velocity: it fades to zero over the 1 mm ``water_skin`` below the water surface and over the same
    skin into the sand, where the sand law takes over from zero); above the water nothing. Culling
    uses the highest surface, sand or water, except for cull groups wholly inside a dry Li-RFT strip
    (beyond the blend), culled at the sand's top: a dry scene and a scene's dry strip keep their cost. A region whose law is
    ``water`` is open water with no granular bottom response (the scene's rigid bed bottom holds).

    Buoyancy (``buoyancy=True``). Every element below the local water surface feels the hydrostatic
    pressure ``rho_w g (z_water - z)`` along its inward normal. Summed over a closed surface this is,
    by the divergence theorem, exactly ``rho_w g V_submerged`` upward through the submerged centroid
    (the pressure is 0 at the water surface, so the cut through the waterline adds nothing and the
    force grows continuously as a geom sinks); with flat elements the midpoint rule is exact for a
    fully submerged geom and off by O(element size) at the waterline. ``g`` is ``-gravity_z`` of the
    model at each step. Which water: regions with ``water_depth > 0`` or the law ``wet``/``water``
    (saturated sand: the water table is at least at the sand surface). The pressure continues INTO
    saturated sand (pore water carries it; SGRFT's plate stresses, measured on 2 mm plates, hold no
    buoyancy of the intruder, so nothing is counted twice). Dry regions get none: the RFT
    coefficients of dry media are measured with the grains' own weight and air buoyancy is negligible.

    Regions. Elements are evaluated with the law of the region they are in. Within ``transition / 2``
    of a strip boundary (or of a map cell edge, bilinearly in x and y) the stresses of the
    neighbouring regions (sand law, water drag and pressure, each with its own water depth) are mixed
    linearly, so an element crossing the boundary at speed ``v`` sees the force change by
    ``|sigma_a - sigma_b| v dt / transition`` per step instead of jumping. With a single region the
    kernel does no region work at all, and a law a scene does not use is never called.

    Height-field surface. ``surface="name"`` (or ``<text name="mjrft:surface_hfield">``) makes the
    free surface the height field of that ``hfield`` geom: the geom's z plus ``elevation x sample``,
    bilinear between samples (MuJoCo itself collides with the two triangles of each cell; the robot
    does not collide with the sand here, so only mjrft's surface matters), in the geom's frame
    (turned about the vertical axis allowed; tilted geoms and geoms on moving bodies are rejected),
    read once at construction; outside the grid the border heights continue. Depth is measured
    vertically, ``depth = surface_height(x, y) - z``, and the laws are evaluated as for a horizontal
    free surface at that depth: the usual RFT choice on gentle slopes (the fits were made under a
    level surface; a slope's lower downhill confinement is not modelled). ``surface`` (the attribute)
    is then the mean height, for display.

    Changing the terrain in place. :meth:`set_medium` (the own medium and/or ``stress_scale``, a factor on
    every granular stress), :meth:`set_regions` (new strips, or a map's entries) and :meth:`set_surface` (a
    flat height, or new height-field samples, also written into the model's hfield) update the kernel's
    parameter arrays without rebuilding the elements, so that an environment can draw a new terrain at
    each reset (:mod:`mjrft.envs.randomization`); the result equals a terrain built with those settings.

    Calibrated ranges. Each law knows the speed, depth and grain-size range its source calibrated
    (:mod:`mjrft.laws.validity`). The terrain warns once per (law, quantity) with
    :class:`~mjrft.errors.ValidityRangeWarning`, naming the law, the quantity, the value and the range:
    for the medium's grain size (and 3D-RFT's bulk density and internal friction) at construction,
    and for the deepest and the fastest buried element of the last step every
    ``STABILITY_CHECK_EVERY`` steps or ``STABILITY_CHECK_SPAN`` of simulated time, alongside the stability check.

    Your own robot. A third-party model goes on sand unchanged with
    ``GranularTerrain(model, floor="auto")``: collision geoms only, the floor's top as the surface (its
    contacts removed in the loaded model), an element size from the robot's size. A mesh's small
    triangles are merged into elements of about the resolution (:mod:`mjrft.geometry.discretize`), so a
    detailed mesh does not cost one element per triangle. The terrain's force is explicit (computed from
    the state at the start of each step), so its stability limit is the explicit one whatever the
    integrator; :meth:`step` and :meth:`install` refuse RK4 (see there).

    MJCF ``<custom>`` keys for all of this: text ``mjrft:floor`` (geom name or ``auto``), text
    ``mjrft:resolution`` ``auto``, text ``mjrft:surface_hfield`` (geom name), text
    ``mjrft:regions`` (``"x_min medium law [water_depth]; ..."``, or ``"medium law [water_depth]; ..."``
    with a map), numeric ``mjrft:region_map`` (``x_min y_min cell_x cell_y nx ny`` then the nx x ny
    ids row by row, rows along y), numeric ``mjrft:water_depth``, ``mjrft:transition``,
    ``mjrft:buoyancy`` (0/1), ``mjrft:drag_coefficient``, ``mjrft:water_density``, ``mjrft:inertial`` (0/1),
    ``mjrft:inertial_drag``.
    """

    def __init__(self, model: mujoco.MjModel, medium=None, law=None, *, bodies=None, geoms=None, floor=None,
                 surface=None, resolution=None, resolution_scale=1.0, yield_displacement=None, damping_time=None,
                 v_eps=None, water_depth=None, regions=None, region_map=None, transition=None, buoyancy=None,
                 drag_coefficient=None, water_density=None, inertial=None, inertial_drag=None, max_elements=None,
                 implicit=False, solidify=0.0, stick_speed=STICK_SPEED, ground_memory=False):
        if not isinstance(model, mujoco.MjModel):
            raise TypeError(f"model must be a mujoco.MjModel, got {type(model).__name__}")
        if not isinstance(implicit, (bool, np.bool_)):
            raise TypeError(f"implicit must be True or False, got {implicit!r}")
        if implicit and (_IMPLICIT_FUNCTIONS is None or _STEP_FUNCTIONS is None):
            raise RuntimeError("implicit=True calls MuJoCo's C functions (mj_step1, mj_step2, "
                               f"{', '.join(IMPLICIT_FUNCTIONS)}) and they were not found in the library the "
                               "mujoco bindings loaded; use implicit=False")
        tm = build_model(model, medium, law, bodies=bodies, geoms=geoms, floor=floor, surface=surface,
                         resolution=resolution, resolution_scale=resolution_scale,
                         yield_displacement=yield_displacement, damping_time=damping_time, v_eps=v_eps,
                         water_depth=water_depth, regions=regions, region_map=region_map, transition=transition,
                         buoyancy=buoyancy, drag_coefficient=drag_coefficient, water_density=water_density,
                         inertial=inertial, inertial_drag=inertial_drag, max_elements=max_elements,
                         implicit=implicit, solidify=solidify, stick_speed=stick_speed, ground_memory=ground_memory,
                         stacklevel=3)
        self._setup(model, tm)

    @classmethod
    def from_model(cls, model: mujoco.MjModel, terrain_model: TerrainModel) -> "GranularTerrain":
        """The terrain of the records ``terrain_model`` (:func:`mjrft.build.build_model`, or another terrain's
        :attr:`terrain_model`) on ``model``, with a fresh state: the same forces as a terrain built with the same
        arguments. The floor that became the surface loses its contacts in ``model`` as in the constructor."""
        if not isinstance(model, mujoco.MjModel):
            raise TypeError(f"model must be a mujoco.MjModel, got {type(model).__name__}")
        if not isinstance(terrain_model, TerrainModel):
            raise TypeError(f"terrain_model must be a mjrft.TerrainModel, got {type(terrain_model).__name__}")
        if int(terrain_model.elements.body_root.shape[0]) != model.nbody:
            raise ValueError(f"terrain_model was built on a model with {terrain_model.elements.body_root.shape[0]} "
                             f"bodies, not this one ({model.nbody})")
        if terrain_model.constants.implicit and (_IMPLICIT_FUNCTIONS is None or _STEP_FUNCTIONS is None):
            raise RuntimeError("implicit=True calls MuJoCo's C functions, which were not found; use implicit=False")
        self = cls.__new__(cls)
        self._setup(model, terrain_model)
        return self

    def _setup(self, model: mujoco.MjModel, tm: TerrainModel) -> None:
        """The terrain of ``tm`` on ``model``, called by the constructor and :meth:`from_model` (warnings name their
        caller's caller)."""
        load_cached_callees_first()  # every process then runs the same compiled code (see its docstring)
        self.model = model
        # the model's options (a view of its struct, kept alive with it): read per step, ~1 us cheaper than model.opt
        self._opt = model.opt
        self.terrain_model = tm
        self.terrain_state = make_state(tm, model)
        self._f_implicit = (np.array(_IMPLICIT_FUNCTIONS, dtype=np.int64) if tm.constants.implicit
                            else _NO_IMPLICIT)
        # a terrain with a ground memory steps through its own compiled loop and kernel (compiled only when used)
        self._run_steps = CompiledCall(run_steps_ground if tm.ground.on else run_steps)
        self._kernel = CompiledCall(kernel.terrain_kernel_ground if tm.ground.on else kernel.terrain_kernel)
        self._stability = StabilityWatch(model, tm.elements.body_ids)
        self._validity = ValidityWatch(tm.region_list, tm.constants.inertial, stacklevel=3)
        self._data = None
        self._resets_seen = 0  # MuJoCo's reset-after-divergence count of the bound data, when last seen
        self._t_begin = 0.0
        self._last_time = -np.inf
        self._steps = 0
        self._check_time = -np.inf  # the simulation time of the last check
        self._hf_geom_z = None  # the hfield geom's height (set_surface of a height field)
        # last: a constructor that raises leaves the model as it was
        self.floor_contacts = remove_floor_contacts(model, tm)  # the floor's (contype, conaffinity) before
        for note in tm.settings.floor_warnings:
            warnings.warn(SandContactWarning(note), stacklevel=4)
        pose = mujoco.MjData(model)  # the model's initial pose: can the selected geoms ever meet the sand?
        mujoco.mj_kinematics(model, pose)
        for note in (reach_warning(self, pose), sinking_warning(model, pose, tm.elements.geom_ids)):
            if note is not None:
                warnings.warn(SandContactWarning(note), stacklevel=4)

    # ------------------------------------------------------------------ what the terrain is (its TerrainModel)
    @property
    def medium(self):
        """The terrain's own medium (region 0)."""
        return self.terrain_model.settings.medium

    @property
    def law(self) -> str:
        return self.terrain_model.settings.law

    @property
    def floor(self) -> int | None:
        """Geom id of the floor that became the surface (None without one)."""
        return self.terrain_model.settings.floor

    @property
    def surface_hfield(self) -> int | None:
        """Geom id of the height-field surface (None for a flat surface)."""
        return self.terrain_model.settings.surface_hfield

    @property
    def surface(self) -> float:
        """Height of the flat surface (m); with a height field, the mean of its samples."""
        return self.terrain_model.surface.height

    @property
    def resolution(self) -> float:
        return self.terrain_model.settings.resolution

    @property
    def resolution_auto(self) -> bool:
        return self.terrain_model.settings.resolution_auto

    @property
    def yield_displacement(self) -> float:
        return self.terrain_model.constants.delta

    @property
    def damping_time(self) -> float:
        return self.terrain_model.constants.tau

    @property
    def v_eps(self) -> float:
        return self.terrain_model.constants.v_eps

    @property
    def solidify(self) -> float:
        return self.terrain_model.constants.solid

    @property
    def stick_speed(self) -> float:
        return self.terrain_model.constants.stick

    @property
    def implicit(self) -> bool:
        return self.terrain_model.constants.implicit

    @property
    def inertial(self) -> bool:
        """Whether the inertial regime applies (in the regions with a dry law)."""
        return self.terrain_model.constants.inertial

    @property
    def transition(self) -> float:
        return self.terrain_model.regions.transition

    @property
    def buoyancy(self) -> bool:
        return self.terrain_model.settings.buoyancy

    @property
    def inertial_drag(self) -> float:
        return self.terrain_model.settings.inertial_drag

    @property
    def regions(self) -> list[Region]:
        """The regions, region 0 (the terrain's own) first, each resolved with its water depth."""
        return list(self.terrain_model.region_list)

    @property
    def water_depth(self) -> float:
        """The deepest water standing over the sand anywhere (m)."""
        return water_depth(self.terrain_model.regions.params)

    @property
    def stress_scale(self) -> float:
        """The factor on every granular stress (:meth:`set_medium`)."""
        return self.terrain_model.stress_scale

    @property
    def elements(self):
        """The elements as the geometry cut them (:class:`~mjrft.geometry.Elements`: positions, normals, areas in
        their body's frame)."""
        return self.terrain_model.geometry

    @property
    def geom_ids(self) -> np.ndarray:
        return self.terrain_model.elements.geom_ids

    @property
    def area(self) -> np.ndarray:
        return self.terrain_model.elements.area

    @property
    def elem_geom(self) -> np.ndarray:
        return self.terrain_model.elements.geom

    @property
    def elem_body(self) -> np.ndarray:
        return self.terrain_model.elements.body

    @property
    def body_ids(self) -> np.ndarray:
        """The bodies that own elements, sorted."""
        return self.terrain_model.elements.body_ids

    @property
    def n_elements(self) -> int:
        return self.terrain_model.n_elements

    # ------------------------------------------------------------------ what it wrote (its TerrainState)
    @property
    def pos(self) -> np.ndarray:
        """World position of each element within reach at the last step (n, 3)."""
        return self.terrain_state.pos

    @property
    def vel(self) -> np.ndarray:
        return self.terrain_state.vel

    @property
    def normal(self) -> np.ndarray:
        return self.terrain_state.normal

    @property
    def depth(self) -> np.ndarray:
        return self.terrain_state.depth

    @property
    def force(self) -> np.ndarray:
        return self.terrain_state.force

    @property
    def region(self) -> np.ndarray:
        return self.terrain_state.region

    @property
    def wrench(self) -> np.ndarray:
        """Each body's granular wrench of the last step (nbody, 6: force, torque about its centre of mass, world
        frame)."""
        return self.terrain_state.wrench

    @property
    def actuator_power(self) -> float:
        """The actuators' mechanical power ``sum_a |actuator_force_a x actuator_velocity_a|`` (W), averaged over
        every physics step of the last :meth:`step` call (each step's force and velocity are of the state at its
        start), so that an environment's control step reports the energy its actuators delivered, not a sample.
        0 before the first step."""
        return float(self.terrain_state.power[0])

    # ------------------------------------------------------------------ binding and resetting
    def _bind(self, data: mujoco.MjData) -> None:
        if data is self._data:
            return
        if data.xpos.shape[0] != self.model.nbody or data.qpos.shape[0] != self.model.nq:
            raise ValueError("data does not belong to this terrain's model")
        self._data = data
        self._warning_numbers = data.warning.number  # a view: MuJoCo's counters as they change
        self._resets_seen = reset_count(self._warning_numbers)
        self._views = MjViews(data.geom_xpos, data.geom_xmat, data.xpos, data.xmat, data.xipos, data.cvel,
                              data.subtree_com)
        self._step_views = StepViews(data.xfrc_applied, data.qacc_smooth, data.actuator_force,
                                     data.actuator_velocity)
        self.reset()

    def bind(self, data: mujoco.MjData) -> None:
        """Make ``data`` the ``MjData`` this terrain steps (what stepping a new one does first); binding another
        one forgets the elements' memory (:meth:`reset`)."""
        self._bind(data)

    def reset(self) -> None:
        """Forget every element's memory (call after changing the state by hand); a ground memory returns to the
        prepared bed (level, every cell at the medium's prepared packing). A model edited since into a non-finite
        mass, inertia, gravity or timestep is refused here (:func:`mjrft.build.check_model`), before MuJoCo steps
        it."""
        check_model(self.model)
        self.terrain_state.forget(self.terrain_model.ground)
        self._last_time = -np.inf
        self._check_time = -np.inf

    # ------------------------------------------------------------------ changing the terrain in place
    def set_medium(self, medium=None, stress_scale=None) -> None:
        """Change the terrain's own medium (region 0: where no other region applies; its law and water
        depth stay) and/or the factor ``stress_scale`` (> 0) on the granular stresses of every region,
        without rebuilding the elements. ``None`` keeps the current value.

        ``stress_scale`` multiplies the stress slots of each region's parameters
        (:data:`~mjrft.laws.registry.STRESS_SLOTS`: every stress of the sand laws and of the inertial regime), so
        every buried element's granular force scales by it; the water layer's drag and the buoyancy keep theirs.
        It is relative to the media's own stresses (``set_medium(stress_scale=1)`` restores them), and it stays
        when the medium or the regions change. A larger scale stiffens the grains in proportion: the stability
        check sees the scaled stiffness, and its warning names the scale. The elements' memory is
        kept (:meth:`reset` forgets it). A bad medium raises as in the constructor (an unknown name
        lists the catalogue) and leaves the terrain as it was.
        """
        tm = self.terrain_model
        s = tm.settings if medium is None else replace(tm.settings, medium=get_medium(medium))
        scale = tm.stress_scale if stress_scale is None else check_positive("stress_scale", stress_scale)
        self._set_regions(s, scale)

    def set_regions(self, regions) -> None:
        """Replace the terrain's extra regions without rebuilding the elements: strips along x in the
        constructor's form (``[Region(x_min, medium, law, water_depth), ...]`` or tuples, sorted by
        ``x_min``; ``None`` or ``[]``: the terrain's own medium everywhere), or, on a terrain with a
        ``region_map``, its ``(medium, law[, water_depth])`` entries (at least as many as the map's ids
        name). Checked as in the constructor; on an error the terrain is left as it was. The current
        ``stress_scale`` applies to the new regions; the elements' memory is kept."""
        tm = self.terrain_model
        s = tm.settings
        self._set_regions(replace(s, regions=_region_entries(regions, mapped=s.region_map is not None)),
                          tm.stress_scale)

    def _set_regions(self, s, scale: float) -> None:
        """The terrain model with the regions of ``s`` and the stresses times ``scale`` (raises before anything
        changes); the elements' region ids are zeroed when the region count changes (ids of the old layout would
        index past the new tables), and the validity ranges follow."""
        tm = with_regions(self.terrain_model, s, scale)
        if len(tm.region_list) != len(self.terrain_model.region_list):
            self.terrain_state.region[:] = 0
        wake = uses_wake(tm.regions.law)
        if tm.ground.on and wake != (self.terrain_state.g_wake.size > 0):  # the hybrid law's wake comes or goes
            self.terrain_state = self.terrain_state._replace(g_wake=wake_array(tm.ground, wake))
        self.terrain_model = tm
        self._validity = ValidityWatch(tm.region_list, tm.constants.inertial, self._validity.warned, stacklevel=4)

    def set_surface(self, surface) -> None:
        """Move the free sand surface without rebuilding the elements.

        Flat surface: ``surface`` is its new height (m). Height-field surface (``surface="<hfield geom>"``):
        the new world heights of the samples, an array shaped like :meth:`surface_samples`' (``(nrow,
        ncol)``: row j along the geom's y, column i along its x), or one number for a level field. The
        hfield's data in the loaded model are rewritten to the same heights (through its elevation and
        the geom's height), so MuJoCo's collisions with it and its rendering (after
        ``mujoco.mjr_uploadHField`` on a render context made before) show the surface the grains have.
        Water stands the same depth above the new surface. The elements' memory is kept.
        """
        hf_z = self.terrain_model.surface.hfield_z
        if hf_z.size == 0:
            if np.ndim(surface) != 0:
                raise ValueError(f"this terrain's surface is flat (height {self.surface:g} m): set_surface takes one "
                                 f"height in m, got an array of shape {np.shape(surface)}; a height field needs an "
                                 "hfield geom as the surface (surface='<hfield geom>')")
            self.terrain_model = with_surface(self.terrain_model, check_finite("surface", surface))
            return
        z = np.asarray(surface, dtype=np.float64)
        if z.ndim == 0:
            z = np.full(hf_z.shape, check_finite("surface", z))
        if z.shape != hf_z.shape:
            raise ValueError(f"surface heights must have the height field's shape {hf_z.shape} "
                             f"(nrow, ncol), got {z.shape}")
        if not np.all(np.isfinite(z)):
            raise ValueError("surface heights must be finite")
        z = np.array(z, dtype=np.float64, order="C")
        self.terrain_model = with_surface(self.terrain_model, float(z.mean()), z)
        self._write_hfield()

    def surface_samples(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """World ``(x, y, z)`` of the height-field surface's samples, each ``(nrow, ncol)`` (copies); raises
        on a flat surface."""
        sf = self.terrain_model.surface
        if sf.hfield_z.size == 0:
            raise ValueError(f"this terrain's surface is flat (height {self.surface:g} m), it has no samples; "
                             "a height field needs an hfield geom as the surface (surface='<hfield geom>')")
        nrow, ncol = sf.hfield_z.shape
        x0, y0, c, sn, rx, ry, kx, ky = sf.hfield_frame
        lx, ly = np.meshgrid(np.arange(ncol) / kx - rx, np.arange(nrow) / ky - ry)
        return x0 + c * lx - sn * ly, y0 + sn * lx + c * ly, sf.hfield_z.copy()

    def _write_hfield(self) -> None:
        """Write the surface heights into the loaded model's hfield samples (z = geom z + elevation x sample)."""
        m, g = self.model, self.surface_hfield
        h = int(m.geom_dataid[g])
        elev = float(m.hfield_size[h, 2])
        if not elev > 0:
            return
        if self._hf_geom_z is None:
            d = mujoco.MjData(m)
            mujoco.mj_kinematics(m, d)
            self._hf_geom_z = float(d.geom_xpos[g, 2])
        z = self.terrain_model.surface.hfield_z
        adr, n = int(m.hfield_adr[h]), z.size
        m.hfield_data[adr:adr + n] = ((z - self._hf_geom_z) / elev).ravel()


    # ------------------------------------------------------------------ per-step work
    def compute(self, data: mujoco.MjData, dt: float | None = None) -> np.ndarray:
        """Evaluate the granular wrench from ``data``'s current kinematics (positions, ``cvel``).

        Advances the elements' memory by ``dt`` (default: the model timestep) and fills ``pos``,
        ``depth`` (every element of a geom that can reach the grains), ``vel``, ``normal`` (elements
        below the surface), ``force`` (zero above) and ``wrench`` (nbody x 6: force, torque about
        each body's centre of mass, world frame). Raises :class:`NonFiniteError` naming the body and time
        on a non-finite state or force. Does not touch ``data``.
        """
        self._begin(data)
        if dt is None:
            dt = self._opt.timestep
        st = self.terrain_state
        status, body = self._kernel(self.terrain_model.tables, self._views, self._gravity(), float(dt), st)
        track_stiffness(st.stiff, st.stiff_max, st.damp, st.damp_max, st.inert, st.inert_max)
        track_depth_springs(st.dstiff, st.dstiff_max)
        track_chatter(st.wrench, self.body_ids, st.stiff_max)
        self._finish(data, status, body, dt, 1)
        return st.wrench

    def _gravity(self) -> float:
        """The downward gravity (m/s^2) of the model now (the buoyancy's)."""
        return max(0.0, -float(self._opt.gravity[2]))

    def step_arguments(self, data: mujoco.MjData, dt: float) -> tuple:
        """The arguments of :func:`mjrft.stepping.run_steps` after ``(nstep, f_step1, f_step2, m_addr, d_addr)`` for
        stepping ``data`` (bound) at the timestep ``dt``: ``(f_implicit, tables, mjd, views, gravity, dt, state)``.
        :class:`~mjrft.batch.BatchedTerrain` keeps one such tuple per environment; its groups are the same objects
        from call to call until something changes (a new ``MjData`` bound, a new terrain model or state)."""
        return (self._f_implicit, self.terrain_model.tables, self._views, self._step_views, self._gravity(), dt,
                self.terrain_state)

    def _begin(self, data) -> None:
        """Before evaluating on ``data``: bind to it, raise if MuJoCo reset it after a divergence since the
        terrain last saw it, and forget the memory if its time went back (a reset)."""
        if data is not self._data:
            self._bind(data)
        if reset_count(self._warning_numbers) != self._resets_seen:
            self._check_mujoco_reset(data, f"after t = {self._last_time:.6g} s")
        t = data.time
        self._t_begin = t
        if t < self._last_time:
            self.reset()

    def begin_steps(self, data: mujoco.MjData) -> None:
        """What :meth:`step` does before its compiled steps (bind ``data``, raise if MuJoCo reset it after a
        divergence, forget the memory after a reset): for a caller that runs them itself
        (:class:`~mjrft.batch.BatchedTerrain`), with :meth:`step_arguments` and then :meth:`end_steps`."""
        self._begin(data)

    def end_steps(self, data: mujoco.MjData, status: int, body: int, dt: float, nstep: int) -> None:
        """What :meth:`step` does after ``nstep`` compiled steps that returned ``(status, body)``: note the time,
        raise :class:`~mjrft.errors.NonFiniteError` on a non-finite result, run the checks on schedule."""
        self._finish(data, status, body, dt, nstep)

    def _check_mujoco_reset(self, data, since: str) -> None:
        """Raise :class:`NonFiniteError` when MuJoCo's reset-after-divergence counters grew since last seen;
        note them either way (they fall to 0 on ``mj_resetData``). Callers call it only when
        ``reset_count(self._warning_numbers) != self._resets_seen``, so the message ``since`` is formatted
        only then."""
        n = reset_count(self._warning_numbers)
        grew = n > self._resets_seen
        self._resets_seen = n
        if grew:
            self.terrain_state.wrench[:] = 0.0
            raise mujoco_reset_error(self.model, data, since)

    def _finish(self, data, status, body, dt, nstep) -> None:
        """After ``nstep`` evaluations on ``data``: note its time; raise on a non-finite result; run the checks
        (:meth:`mjrft.watch.StabilityWatch.check`, the validity ranges) on the first call after a reset and
        then every ``STABILITY_CHECK_EVERY`` steps or ``STABILITY_CHECK_SPAN`` of simulated time, whichever comes
        first (every step at a timestep of 50 ms or more)."""
        self._last_time = data.time
        if reset_count(self._warning_numbers) != self._resets_seen:
            self._check_mujoco_reset(data, f"between t = {self._t_begin:.6g} s and the end of {nstep} step(s)")
        if status != kernel.OK:
            self.terrain_state.wrench[:] = 0.0
            raise nonfinite_error(self.model, status, body, data.time)
        before = self._steps
        self._steps += nstep
        if (before // STABILITY_CHECK_EVERY != self._steps // STABILITY_CHECK_EVERY
                or not data.time - self._check_time < STABILITY_CHECK_SPAN - 1e-12):
            self._check_time = data.time
            st = self.terrain_state
            self._stability.check(data, dt, self.terrain_model, st)
            if self._validity.dynamic:
                self._validity.check(st.depth, st.vel, st.region, data.time)

    def step(self, data: mujoco.MjData, nstep: int = 1) -> None:
        """``nstep`` times: ``mj_step1``, add the granular wrench to ``xfrc_applied``, ``mj_step2``.

        Integrators: Euler, implicit and implicitfast step as usual; the granular wrench is explicit (a
        constant external force over the step, computed from the state after ``mj_step1``): the implicit
        integrators treat the model's own damping and actuator derivatives implicitly, not the grains'
        stiffness, so the stability limit the terrain warns about is the same for all three. RK4 is
        refused: MuJoCo's ``mj_step1``/``mj_step2`` split integrates an RK4 model with Euler, which
        would silently change the model's integrator.
        """
        self._check_integrator("step")
        nstep = whole_steps(nstep)
        m = self.model
        self._begin(data)
        if _STEP_FUNCTIONS is not None and nstep > 0:
            dt = self._opt.timestep
            status, body, done = self._run_steps(nstep, *_STEP_FUNCTIONS, m._address, data._address,
                                                 *self.step_arguments(data, dt))
            self._finish(data, status, body, dt, done)
            return
        if self.implicit:
            raise RuntimeError("implicit=True steps through MuJoCo's C functions, which were not found")
        st = self.terrain_state
        xfrc = data.xfrc_applied
        rows = self.body_ids
        work = 0.0
        st.power[0] = 0.0
        for k in range(nstep):
            mujoco.mj_step1(m, data)
            self.compute(data)
            add_rows(xfrc, rows, st.wrench, st.saved)
            try:
                mujoco.mj_step2(m, data)
            finally:
                restore_rows(xfrc, rows, st.saved)
            work += actuator_power(data.actuator_force, data.actuator_velocity)
            st.power[0] = work / (k + 1)

    def _check_integrator(self, what: str) -> None:
        if self._opt.integrator == _RK4:
            why = ("MuJoCo's mj_step1/mj_step2 split (which applies the granular wrench between them) integrates an "
                   "RK4 model with semi-implicit Euler" if what == "step" else
                   "the passive callback runs at each of RK4's four stages and would advance the elements' "
                   "memory four times per step")
            raise ValueError(f"GranularTerrain.{what} does not support the RK4 integrator: {why}. Set "
                             "model.opt.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST (or EULER / IMPLICIT; "
                             "the granular wrench is explicit in all of them)")

    # ------------------------------------------------------------------ callback mode
    def install(self) -> "GranularTerrain":
        """Register a MuJoCo passive-force callback so that plain ``mj_step`` / the viewer feel the terrain.

        The callback adds the wrench to ``qfrc_passive`` (equivalent to ``xfrc_applied``, but
        nothing is left behind for other code to see). MuJoCo has one global passive callback:
        only one terrain can be installed at a time, and it serves only its own model. Calls at an
        unchanged ``data.time`` (e.g. ``mj_forward``) recompute the force without advancing memory.
        """
        self._check_integrator("install")
        if self.implicit:
            raise ValueError("GranularTerrain.install does not support implicit=True: the implicit wrench needs "
                             "MuJoCo's smooth acceleration (actuators included), which the passive callback runs "
                             "before; step with terrain.step(data, n), or build the terrain with implicit=False")
        current = mujoco.get_mjcb_passive()
        if current is not None and current != self._callback:
            raise RuntimeError("another MuJoCo passive callback is installed; call its uninstall first")
        mujoco.set_mjcb_passive(self._callback)
        return self

    def uninstall(self) -> None:
        """Remove the callback registered by :meth:`install`."""
        if mujoco.get_mjcb_passive() == self._callback:
            mujoco.set_mjcb_passive(None)

    def __enter__(self):
        return self.install()

    def __exit__(self, *exc):
        self.uninstall()

    def _callback(self, model, data) -> None:
        if model is not self.model:
            return
        dt = self._opt.timestep
        if data is self._data and data.time == self._last_time:
            dt = 0.0
        self.compute(data, dt)
        point = np.empty(3)
        wrench = self.terrain_state.wrench
        for b in self.body_ids:
            w = wrench[b]
            if w[0] == 0 and w[1] == 0 and w[2] == 0 and w[3] == 0 and w[4] == 0 and w[5] == 0:
                continue
            point[:] = data.xipos[b]
            mujoco.mj_applyFT(model, data, w[:3].copy(), w[3:].copy(), point, int(b), data.qfrc_passive)

    # ------------------------------------------------------------------ diagnostics
    def stable_timestep(self, data: mujoco.MjData, part: str = "step") -> np.ndarray:
        """Largest stable timestep (s) of each body for the granular stiffness of the last step, shape (nbody,).

        ``part``: ``"springs"``, the explicit limit of the grains' springs (with the inertial regime on, its
        dampers included), whether the step integrates them explicitly or not; ``"depth"``, that of the depth
        stiffness (explicit in every mode); ``"step"`` (default), what bounds this terrain's step: the smaller
        of the two with ``implicit=False``, the depth stiffness's with ``implicit=True`` (see
        docs/numerics.md, "Implicit step"). Evaluated now; ``inf`` for bodies with nothing below the surface.
        """
        out = np.full(self.model.nbody, np.inf)
        self._stable_into(data, out, "stable_timestep", part)
        return out

    def min_stable_timestep(self, data: mujoco.MjData, part: str = "step") -> float:
        """The smallest of :meth:`stable_timestep` over the selected bodies (s; ``inf`` when nothing is buried),
        without allocating: the per-step query of a caller that picks its timestep from it."""
        out = self._stability.dt_scratch
        out[:] = np.inf
        self._stable_into(data, out, "min_stable_timestep", part)
        return float(out.min())

    def min_stable_timesteps(self, data: mujoco.MjData) -> tuple[float, float]:
        """``(min_stable_timestep(data, "springs"), min_stable_timestep(data, "depth"))`` (s) in one compiled call
        that builds the buried bodies' jacobians once: the per-step query of a caller that needs both (equal to
        the two calls)."""
        if data is not self._data:
            raise ValueError("min_stable_timesteps needs the MjData this terrain last stepped")
        if not self._stability.has_compiled_jacobians():
            return self.min_stable_timestep(data, "springs"), self.min_stable_timestep(data, "depth")
        springs, depth = self._stability.stable_pair(data, self.terrain_model, self.terrain_state)
        return float(springs), float(depth)

    def _stable_into(self, data, out: np.ndarray, what: str, part: str) -> None:
        """Write each buried body's stable timestep of ``part`` (:meth:`stable_timestep`) into ``out`` (nbody)."""
        if data is not self._data:
            raise ValueError(f"{what} needs the MjData this terrain last stepped")
        if part not in ("step", "springs", "depth"):
            raise unknown(f"{what} part", part, ["step", "springs", "depth"])
        self._stability.stable_into(data, out, self.terrain_model, self.terrain_state, part)

    def critical_rate(self, data, body: int, moments) -> float:
        """Largest eigenvalue of ``W6 K6`` for ``body``: omega^2 (1/s^2), or 1/s in the viscous mode.

        ``moments`` are the kernel's stiffness moments of the body (:func:`mjrft.kernel.terrain_kernel`), ``K6``
        the 6x6 stiffness they describe and ``W6`` the body's :meth:`mobility`.
        """
        return largest_rate(*self._stability.jacobians(data, body),
                            np.ascontiguousarray(moments, dtype=np.float64))

    def mobility(self, data, body: int) -> np.ndarray:
        """6x6 ``J M^-1 J^T`` of ``body``'s CoM translation (rows 0-2, 1/kg) and rotation (3-5), world frame."""
        m = self.model
        jac = np.zeros((6, m.nv))
        mujoco.mj_jacBodyCom(m, data, jac[:3], jac[3:], body)
        x = np.zeros((6, m.nv))
        mujoco.mj_solveM(m, data, x, jac)
        a = jac @ x.T
        return 0.5 * (a + a.T)

    def inverse_mass(self, data, body: int) -> float:
        """Largest eigenvalue of J M^-1 J^T for the translation of ``body``'s centre of mass (1/kg)."""
        return float(np.linalg.eigvalsh(self.mobility(data, body)[:3, :3])[-1])

    def surface_height(self, x, y) -> np.ndarray:
        """Height (m) of the free sand surface at world ``(x, y)`` (arrays broadcast), as the kernel sees it."""
        x, y = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
        out = np.empty(x.shape)
        sf = self.terrain_model.surface
        surface_heights(np.ascontiguousarray(x).ravel(), np.ascontiguousarray(y).ravel(), sf.height, sf.hfield_z,
                        sf.hfield_frame, out.reshape(-1))
        return out

    @property
    def ground_memory(self) -> bool:
        """Whether the ground remembers (``ground_memory=``)."""
        return bool(self.terrain_model.ground.on)

    def ground_height(self, x, y) -> np.ndarray:
        """Height (m) of the grains' surface at world ``(x, y)`` (arrays broadcast) as the ground memory holds it now:
        the undisturbed surface (:meth:`surface_height`) plus the footprints, ridges and the packing's change, bilinear
        between the cell centres (a footprint a body still stands in shows; the body's own elements read the level
        the cell had before it came, docs/terrain.md). Without a ground memory, :meth:`surface_height`."""
        gt = self.terrain_model.ground
        if not gt.on:
            return self.surface_height(x, y)
        return self._sample_ground(x, y, C_H, True)

    def ground_packing(self, x, y) -> np.ndarray:
        """Volume fraction of the grains at world ``(x, y)`` (arrays broadcast), bilinear between the cell centres of
        the ground memory; without one, the medium's prepared volume fraction (NaN when the medium has none)."""
        gt = self.terrain_model.ground
        if not gt.on:
            x, y = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
            vf = self.medium.volume_fraction
            return np.full(x.shape, np.nan if vf is None else float(vf))
        return self._sample_ground(x, y, C_PHI, False)

    def _sample_ground(self, x, y, field: int, add_base: bool) -> np.ndarray:
        x, y = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
        out = np.empty(x.shape)
        gt = self.terrain_model.ground
        sample_many(np.ascontiguousarray(x).ravel(), np.ascontiguousarray(y).ravel(), gt.frame, gt.base,
                    self.terrain_state.g_cells, field, add_base, out.reshape(-1))
        return out

    def region_weights(self, x, y) -> np.ndarray:
        """Weight of each region (columns: 0 = the terrain's own, k = ``regions[k]``) at world ``(x, y)``."""
        x, y = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
        rg = self.terrain_model.regions
        out = np.zeros((x.size, rg.law.shape[0]))
        region_weights_many(np.ascontiguousarray(x).ravel(), np.ascontiguousarray(y).ravel(), rg.bounds, rg.map,
                            rg.map_frame, rg.transition, out)
        return out.reshape(*x.shape, rg.law.shape[0])

    def sinkage(self) -> np.ndarray:
        """Deepest element depth (m, >= 0) of each body, shape (nbody,), from the last step."""
        out = np.zeros(self.model.nbody)
        np.maximum.at(out, self.elem_body, np.maximum(self.terrain_state.depth, 0.0))
        return out

    def contact_mask(self) -> np.ndarray:
        """Elements below the surface at the last step."""
        return self.terrain_state.depth > 0.0

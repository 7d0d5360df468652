"""A terrain's records from a MuJoCo model: :func:`build_model` -> :class:`~mjrft.types.TerrainModel`,
:func:`make_state` -> :class:`~mjrft.types.TerrainState`, and the new model after a change of medium, regions or
surface (:func:`with_regions`, :func:`with_surface`).

:func:`build_model` resolves the settings (:func:`mjrft.settings.resolve_settings`: each from its argument, the
model's ``<custom>`` ``mjrft:*`` entry or the defaults, checked once), builds the regions' parameter rows
(:func:`mjrft.regions.build_regions`) and cuts the selected geoms into elements (:func:`mjrft.elements.build_elements`).
It does not change the MuJoCo model: a terrain whose sand surface is a floor geom removes that floor's contacts
with :func:`remove_floor_contacts` (:class:`~mjrft.GranularTerrain` and :class:`mjrft.mjx.Sand` do it when they
are built).
"""

from __future__ import annotations

from dataclasses import replace

import mujoco
import numpy as np

from .elements import build_elements, check_element_count
from .floor import remove_contacts
from .ground import build_ground_packing, build_ground, make_ground_state, uses_wake, with_ground_surface
from .laws.solidify import STICK_SPEED, check_solidify
from .params import P_WATER_DEPTH
from .regions import build_regions
from .settings import TerrainSettings, resolve_settings
from .stability import TRACK_SLOTS
from .types import SurfaceTables, TerrainConstants, TerrainModel, TerrainState


def build_model(model: mujoco.MjModel, medium=None, law=None, *, bodies=None, geoms=None, floor=None, surface=None,
                resolution=None, resolution_scale=1.0, yield_displacement=None, damping_time=None, v_eps=None,
                water_depth=None, regions=None, region_map=None, transition=None, buoyancy=None,
                drag_coefficient=None, water_density=None, inertial=None, inertial_drag=None, max_elements=None,
                implicit=False, solidify=0.0, stick_speed=STICK_SPEED, ground_memory=False,
                stacklevel: int = 2) -> TerrainModel:
    """The :class:`~mjrft.types.TerrainModel` of a terrain on ``model``; the arguments are
    :class:`~mjrft.GranularTerrain`'s (see there). Raises on the first bad or conflicting value, naming it, before
    anything is built. ``stacklevel``: as :func:`warnings.warn` counts from here (2 names the caller) for the
    warnings the settings give (an unknown ``mjrft:*`` key, ``"auto"``'s resolution)."""
    if not isinstance(model, mujoco.MjModel):
        raise TypeError(f"model must be a mujoco.MjModel, got {type(model).__name__}")
    if not isinstance(implicit, (bool, np.bool_)):
        raise TypeError(f"implicit must be True or False, got {implicit!r}")
    check_model(model)
    solid, stick = check_solidify(solidify, stick_speed)
    s = resolve_settings(model, medium=medium, law=law, bodies=bodies, geoms=geoms, floor=floor, surface=surface,
                         resolution=resolution, resolution_scale=resolution_scale,
                         yield_displacement=yield_displacement, damping_time=damping_time, v_eps=v_eps,
                         water_depth=water_depth, regions=regions, region_map=region_map, transition=transition,
                         buoyancy=buoyancy, drag_coefficient=drag_coefficient, water_density=water_density,
                         inertial=inertial, inertial_drag=inertial_drag, ground_memory=ground_memory,
                         stacklevel=stacklevel + 1)
    if solid > 0.0 and s.yield_displacement <= 0.0:
        raise ValueError(f"solidify={solid:g} needs the rest memory (yield_displacement > 0); "
                         "the viscous mode (yield_displacement=0) has no memory to solidify")
    region_list, region_tables, inertial_on = build_regions(s)
    check_element_count(model, s.geom_ids, s.resolution, max_elements)
    geometry, element_tables = build_elements(model, s.geom_ids, s.resolution)
    constants = TerrainConstants(float(s.yield_displacement), float(s.damping_time), float(s.v_eps), float(solid),
                                 float(stick), bool(implicit), bool(inertial_on))
    sf = surface_tables(s.surface, s.hf_z, s.hf_frame, region_tables.params)
    ground = build_ground(model, s.ground, s, region_list, 1.0, sf)
    return TerrainModel(s, element_tables, sf, region_tables, constants, region_list, geometry, 1.0, ground)


def check_model(model: mujoco.MjModel) -> None:
    """Refuse a model whose timestep, gravity or a body's mass or inertia is not finite (MuJoCo steps it, printing a
    warning at every step, until its state is NaN): a ``ValueError`` naming the value, before anything is built."""
    if not (np.isfinite(model.opt.timestep) and model.opt.timestep > 0):
        raise ValueError(f"the model's timestep must be a finite number > 0, got {model.opt.timestep!r}")
    if not np.all(np.isfinite(model.opt.gravity)):
        raise ValueError(f"the model's gravity must be finite, got {model.opt.gravity.tolist()}")
    for what, values in (("mass", model.body_mass[:, None]), ("inertia", model.body_inertia),
                         ("centre of mass", model.body_ipos)):
        bad = np.flatnonzero(~np.all(np.isfinite(values), axis=1))
        if bad.size:
            b = int(bad[0])
            name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, b) or f"#{b}"
            more = f" (and {bad.size - 1} other bodies)" if bad.size > 1 else ""
            raise ValueError(f"body '{name}' has a non-finite {what} ({values[b].tolist()}){more}; fix the model "
                             "(a NaN mass or inertia makes every step NaN)")


def surface_tables(height: float, hfield_z: np.ndarray, hfield_frame: np.ndarray, params: np.ndarray) -> SurfaceTables:
    """The :class:`~mjrft.types.SurfaceTables` of a surface at ``height`` (or the height field ``hfield_z``) under the
    regions' parameter rows ``params`` (their deepest water decides the top)."""
    top = float(hfield_z.max() if hfield_z.size else height) + water_depth(params)
    return SurfaceTables(float(height), hfield_z, hfield_frame, top)


def water_depth(params: np.ndarray) -> float:
    """The deepest water standing over the sand in any region (m) of the parameter rows ``params``."""
    return float(params[:, P_WATER_DEPTH].max())


def with_regions(tm: TerrainModel, settings: TerrainSettings, stress_scale: float) -> TerrainModel:
    """``tm`` with the regions of ``settings`` (a changed medium or changed extra regions) and every granular stress
    times ``stress_scale``: the regions' rows, the surface's top (the water depth may change) and the inertial
    switch follow; the elements are kept. Raises before anything is made when a region is bad."""
    region_list, region_tables, inertial_on = build_regions(settings, stress_scale)
    sf = tm.surface
    ground = tm.ground
    if ground.on:  # the packing constants of the new medium, the packing rows of the new regions
        fresh = build_ground_packing(ground, settings, region_list, stress_scale)
        ground = ground._replace(pack=fresh.pack, dparams=fresh.dparams)
    return replace(tm, settings=settings, regions=region_tables, region_list=region_list,
                   surface=surface_tables(sf.height, sf.hfield_z, sf.hfield_frame, region_tables.params),
                   constants=tm.constants._replace(inertial=bool(inertial_on)), stress_scale=float(stress_scale),
                   ground=ground)


def with_surface(tm: TerrainModel, height: float, hfield_z: np.ndarray | None = None) -> TerrainModel:
    """``tm`` with the flat surface at ``height`` (m), or with the height field's world heights ``hfield_z`` (same
    shape as the model's; ``height`` is then their mean)."""
    sf = tm.surface
    z = sf.hfield_z if hfield_z is None else hfield_z
    surface = surface_tables(height, z, sf.hfield_frame, tm.regions.params)
    return replace(tm, surface=surface, ground=with_ground_surface(tm.ground, surface))


def remove_floor_contacts(model: mujoco.MjModel, tm: TerrainModel) -> tuple[int, int] | None:
    """Remove the contacts of ``tm``'s floor geom (the one that became the sand surface) from the LOADED ``model``;
    returns its (contype, conaffinity) before, or None when the terrain has no floor (see
    :func:`mjrft.floor.remove_contacts`)."""
    floor = tm.settings.floor
    return None if floor is None else remove_contacts(model, floor)


def make_state(tm: TerrainModel, model: mujoco.MjModel) -> TerrainState:
    """A zeroed :class:`~mjrft.types.TerrainState` for ``tm`` on ``model`` (its body and dof counts size the
    per-body outputs and the implicit step's scratch)."""
    n, nbody, nv = tm.n_elements, model.nbody, model.nv
    nb = len(tm.elements.body_ids) if tm.constants.implicit else 0
    return TerrainState(
        u=np.zeros((n, 3)), group_active=np.zeros(len(tm.elements.group_geom), dtype=np.bool_),
        pos=np.zeros((n, 3)), vel=np.zeros((n, 3)), normal=np.zeros((n, 3)), depth=np.zeros(n),
        force=np.zeros((n, 3)), region=np.zeros(n, dtype=np.int64),
        wrench=np.zeros((nbody, 6)), stiff=np.zeros((nbody, 10)), damp=np.zeros(nbody), inert=np.zeros((nbody, 10)),
        dstiff=np.zeros((nbody, 10)), imp=np.zeros((nbody if tm.constants.implicit else 0, 10)),
        saved=np.zeros((nbody, 6)), stiff_max=np.zeros((nbody, TRACK_SLOTS, 10)), damp_max=np.zeros(nbody),
        inert_max=np.zeros((nbody, 10)), dstiff_max=np.zeros((nbody, 10)), power=np.zeros(1),
        scr_f=np.zeros((14 if tm.ground.on else 13, n)), scr_i=np.zeros((2, n), dtype=np.int64),
        imp_jac=np.zeros((6 * nb, nv)), imp_minv_jac=np.zeros((6 * nb, nv)), imp_blocks=np.zeros((nb, 6, 6)),
        imp_a=np.zeros((6 * nb, 6 * nb)), imp_rhs=np.zeros(12 * nb + 6), imp_rows=np.zeros(nb, dtype=np.int64),
        **make_ground_state(tm.ground, n, len(tm.elements.group_geom), uses_wake(tm.regions.law)))

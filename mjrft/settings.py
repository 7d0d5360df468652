"""A terrain's settings: each from its argument, else the model's MJCF ``<custom>`` ``mjrft:*`` entry, else
:data:`DEFAULTS`, checked and resolved in one place (:func:`resolve_settings` -> :class:`TerrainSettings`, frozen;
the coupler and everything after it read only that).

:data:`CUSTOM_KEYS` are the ``mjrft:*`` keys a model may carry (:func:`check_custom_keys` warns about any other);
:func:`custom_entries` reads them, once per :func:`resolve_settings`.
"""

from __future__ import annotations

import difflib
import math
import warnings
from dataclasses import dataclass

import mujoco
import numpy as np

from .errors import check_finite, check_positive
from .floor import _find_floor, _hfield_surface, rigid_support_notes
from .ground import GroundOptions
from .laws import law_id
from .laws.inertial import INERTIAL_DRAG
from .media import Medium, get_medium
from .regions import _region_entries
from .selection import _check_selection, _nothing_selected, auto_resolution, select_geoms


DEFAULTS = {
    "medium": "poppy_cp",
    "law": "rft",
    "surface": 0.0,
    "resolution": "auto",
    "yield_displacement": 1e-3,
    "v_eps": 1e-3,
    "transition": 0.01,
    "buoyancy": 0.0,
    "inertial": 0.0,
    "inertial_drag": INERTIAL_DRAG,
}
CUSTOM_PREFIX = "mjrft:"
#: the ``mjrft:*`` keys a model's <custom> section may hold (any other one is warned about as a misspelling)
CUSTOM_KEYS = ("medium", "law", "bodies", "geoms", "floor", "surface", "surface_hfield", "resolution",
               "yield_displacement", "damping_time", "v_eps", "water_depth", "regions", "region_map", "transition",
               "buoyancy", "drag_coefficient", "water_density", "inertial", "inertial_drag")


@dataclass(frozen=True)
class TerrainSettings:
    """The settings of a :class:`GranularTerrain`, each from its argument, else the model's ``mjrft:*`` entry, else
    :data:`DEFAULTS`, checked (:func:`resolve_settings`). ``regions`` are the extra regions as given (region 0,
    the terrain's own medium and law, is not among them); ``water_depth`` is region 0's (None: the medium's).
    ``resolution_auto``: the element size came from ``"auto"`` (:func:`~mjrft.selection.auto_resolution`, times
    ``resolution_scale``)."""

    medium: Medium
    law: str
    geom_ids: list
    floor: int | None  # geom id of the floor that becomes the surface
    surface: float
    surface_hfield: int | None  # geom id of the hfield surface
    hf_z: np.ndarray  # its world heights (nrow, ncol); (0, 0) for a flat surface
    hf_frame: np.ndarray
    resolution: float
    resolution_auto: bool
    yield_displacement: float
    v_eps: float
    damping_time: float
    transition: float
    buoyancy: bool
    inertial: bool
    inertial_given: bool  # passed as an argument (not read from the model or the defaults)
    inertial_drag: float
    drag_coefficient: float | None
    water_density: float | None
    water_depth: float | None
    regions: list
    region_map: object
    floor_warnings: tuple = ()  # the rigid geoms the robot can still stand on (:func:`mjrft.floor._rigid_floors_left`)
    ground: object = None  # the ground memory's options (:class:`mjrft.ground.GroundOptions`), None when off


def check_custom_keys(cfg: dict, stacklevel: int = 3) -> None:
    """Warn about each ``mjrft:*`` key that mjrft does not read (a misspelling would otherwise be ignored)."""
    for key in cfg:
        if key not in CUSTOM_KEYS:
            close = difflib.get_close_matches(key, CUSTOM_KEYS, n=1)
            hint = f"did you mean 'mjrft:{close[0]}'? " if close else ""
            warnings.warn(f"mjrft: the model's <custom> key 'mjrft:{key}' is not an mjrft setting and is ignored; "
                          f"{hint}valid keys: {', '.join('mjrft:' + k for k in CUSTOM_KEYS)}", stacklevel=stacklevel)


def custom_entries(model: mujoco.MjModel) -> dict:
    """The ``mjrft:*`` entries of the model's <custom> section (text as str, numeric as float)."""
    out = {}
    for i in range(model.ntext):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_TEXT, i) or ""
        if name.startswith(CUSTOM_PREFIX):
            adr, size = model.text_adr[i], model.text_size[i]
            out[name[len(CUSTOM_PREFIX):]] = bytes(model.text_data[adr:adr + size]).split(b"\0")[0].decode()
    for i in range(model.nnumeric):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_NUMERIC, i) or ""
        if name.startswith(CUSTOM_PREFIX):
            adr, size = model.numeric_adr[i], model.numeric_size[i]
            vals = model.numeric_data[adr:adr + size]
            out[name[len(CUSTOM_PREFIX):]] = float(vals[0]) if size == 1 else tuple(float(v) for v in vals)
    return out


def _resolve_surface(model: mujoco.MjModel, cfg: dict, floor, surface, geom_ids) -> tuple:
    """(floor geom id or None, surface height, hfield geom id or None, hfield heights, hfield frame, the floor's
    warnings) from the ``floor`` / ``surface`` arguments (at most one given) or the model's ``mjrft:floor`` /
    ``mjrft:surface`` / ``mjrft:surface_hfield``."""
    floor_id, hfield, hf_z, hf_frame, notes = None, None, np.zeros((0, 0)), np.zeros(8), []
    if floor is not None:
        floor_id, surface, notes = _find_floor(model, floor, geom_ids)
    elif surface is None and "surface_hfield" in cfg:
        surface = cfg["surface_hfield"]
    if surface is None:
        surface = cfg.get("surface", DEFAULTS["surface"])
    if isinstance(surface, str):
        try:
            surface = float(surface)
        except ValueError:
            hfield, hf_z, hf_frame = _hfield_surface(model, surface)
            surface = float(hf_z.mean())
    surface = check_finite("surface", surface)
    if floor_id is None:  # a surface given as a height: the rigid floors are the model's own business, but named
        notes = rigid_support_notes(model, surface, geom_ids, skip=hfield)
    return floor_id, surface, hfield, hf_z, hf_frame, tuple(notes)


def element_size_scale(resolution, resolution_scale) -> float:
    """The factor that applies to the model's own element size: ``resolution_scale`` (checked, > 0) when no
    ``resolution`` is given, 1 when one is (it is the element size itself). The one statement of that rule: the
    terrain's settings and the environments' presets (:func:`mjrft.tools.presets.resolve`) apply it."""
    return check_positive("resolution_scale", resolution_scale) if resolution is None else 1.0


def _resolve_resolution(model: mujoco.MjModel, cfg: dict, resolution, scale, geom_ids,
                        stacklevel: int) -> tuple[float, bool]:
    """(element size in m, whether it was chosen by ``"auto"``): the ``resolution`` argument as given, else
    ``scale`` times the model's own (its ``mjrft:resolution``, a length or ``"auto"``; default ``"auto"``).
    ``stacklevel``: as :func:`warnings.warn` counts from here, for ``"auto"``'s warning."""
    scale = check_positive("resolution_scale", scale)
    if resolution is not None and scale != 1.0:
        raise ValueError(f"resolution={resolution!r} and resolution_scale={scale!r} both set the element size; pass "
                         "resolution_scale (a factor on the model's own resolution) or resolution, not both")
    scale = element_size_scale(resolution, scale)
    if resolution is None:
        resolution = cfg.get("resolution", DEFAULTS["resolution"])
    auto = isinstance(resolution, str) and resolution.strip().lower() == "auto"
    if auto:
        resolution = auto_resolution(model, geom_ids, stacklevel=stacklevel + 1)
    elif isinstance(resolution, str):
        raise ValueError(f"resolution must be a length in m or 'auto', got {resolution!r}")
    resolution = check_positive("resolution", resolution)
    return (resolution if scale == 1.0 else scale * resolution), auto


def resolve_settings(model: mujoco.MjModel, *, medium=None, law=None, bodies=None, geoms=None, floor=None,
                     surface=None, resolution=None, resolution_scale=1.0, yield_displacement=None, damping_time=None,
                     v_eps=None, water_depth=None, regions=None, region_map=None, transition=None, buoyancy=None,
                     drag_coefficient=None, water_density=None, inertial=None, inertial_drag=None,
                     ground_memory=False, stacklevel: int = 2) -> TerrainSettings:
    """The :class:`TerrainSettings` of a terrain on ``model`` (keyword arguments as :class:`GranularTerrain`'s): the
    model's ``<custom>`` entries are read once here (an unknown ``mjrft:*`` key is warned about, ``stacklevel``
    counted as :func:`warnings.warn` counts from here: 2 names the caller); raises on the first bad or conflicting
    value, naming it."""
    _check_selection(bodies, geoms)
    cfg = custom_entries(model)
    check_custom_keys(cfg, stacklevel=stacklevel + 1)

    def pick(key, value):
        if value is not None:
            return value
        return cfg.get(key, DEFAULTS.get(key))

    medium = get_medium(pick("medium", medium))
    law = str(pick("law", law))
    law_id(law)
    if floor is not None and surface is not None:
        raise ValueError(f"floor={floor!r} and surface={surface!r} both give the sand surface; pass one of them")
    if floor is None and surface is None:
        floor = cfg.get("floor")
        if floor is not None and ("surface" in cfg or "surface_hfield" in cfg):
            raise ValueError("the model's <custom> gives both mjrft:floor and mjrft:surface"
                             f"{'_hfield' if 'surface_hfield' in cfg else ''}; keep one of them")
    geom_ids = select_geoms(model, pick("bodies", bodies), pick("geoms", geoms))
    if not geom_ids:
        raise _nothing_selected(model, pick("bodies", bodies), pick("geoms", geoms))
    floor_id, surface, hfield, hf_z, hf_frame, floor_warnings = _resolve_surface(model, cfg, floor, surface, geom_ids)
    resolution, resolution_auto = _resolve_resolution(model, cfg, resolution, resolution_scale, geom_ids,
                                                      stacklevel=stacklevel + 1)
    yield_displacement = check_positive("yield_displacement", pick("yield_displacement", yield_displacement),
                                        allow_zero=True)
    v_eps = check_positive("v_eps", pick("v_eps", v_eps), allow_zero=True)
    if yield_displacement == 0 and v_eps == 0:
        raise ValueError("yield_displacement and v_eps cannot both be 0 (the force at rest would be undefined)")
    if damping_time is None:
        damping_time = cfg.get("damping_time", 0.5 * math.sqrt(yield_displacement / 9.81))
    damping_time = check_positive("damping_time", damping_time, allow_zero=True)
    transition = check_positive("transition", pick("transition", transition), allow_zero=True)
    buoyancy = bool(pick("buoyancy", buoyancy))
    inertial_given = inertial is not None
    inertial = pick("inertial", inertial)
    if not isinstance(inertial, (bool, np.bool_)) and inertial not in (0, 1):
        raise ValueError(f"inertial must be True/False (mjrft:inertial 0 or 1), got {inertial!r}")
    inertial_drag = check_positive("inertial_drag", pick("inertial_drag", inertial_drag))
    if drag_coefficient is None:
        drag_coefficient = cfg.get("drag_coefficient")
    if water_density is None:
        water_density = cfg.get("water_density")
    if drag_coefficient is not None:
        drag_coefficient = check_positive("drag_coefficient", drag_coefficient, allow_zero=True)
    if water_density is not None:
        water_density = check_positive("water_density", water_density, allow_zero=True)
    if region_map is None:
        region_map = cfg.get("region_map")
    entries = _region_entries(pick("regions", regions), mapped=region_map is not None)
    ground = GroundOptions.from_value(ground_memory)
    return TerrainSettings(medium, law, geom_ids, floor_id, surface, hfield, hf_z, hf_frame, resolution,
                           resolution_auto, yield_displacement, v_eps, damping_time, transition, buoyancy,
                           bool(inertial), inertial_given, inertial_drag, drag_coefficient, water_density,
                           pick("water_depth", water_depth), entries, region_map, floor_warnings, ground)

"""Which geoms of a model feel the grains, and the element size ``resolution="auto"`` picks for them.

:func:`select_geoms` turns a terrain's ``bodies`` / ``geoms`` settings into geom ids (by default every supported
collision geom of every body but the world), :func:`auto_resolution` gives the element size that cuts them into
about :data:`AUTO_ELEMENTS` elements; the errors name what the model has when nothing is selected.
"""

from __future__ import annotations

import math
import warnings

import mujoco
import numpy as np

from .errors import unknown
from .geometry import estimate_elements, geom_element_count


_SUPPORTED_GEOMS = {
    int(mujoco.mjtGeom.mjGEOM_BOX), int(mujoco.mjtGeom.mjGEOM_CAPSULE), int(mujoco.mjtGeom.mjGEOM_CYLINDER),
    int(mujoco.mjtGeom.mjGEOM_SPHERE), int(mujoco.mjtGeom.mjGEOM_ELLIPSOID), int(mujoco.mjtGeom.mjGEOM_MESH),
}
#: ``resolution="auto"``: the element count the automatic element size aims at (the selected geoms' surface
#: area / resolution^2), and the finest size it picks (a small robot keeps this size and fewer elements).
#: 3,000 is measured (``benchmarks/element_budget.py``): the coarsest budget of its ladder (250 to 8,000 elements)
#: at which the net granular force of gymnasium's HalfCheetah, Hopper, Walker2d and Humanoid, replayed along a
#: random-action rollout, stays within 2 % (RMS) of a 32,000-element reference, far inside the laws' own errors;
#: the kernel's cost grows with the buried element count. A light robot on large geoms (Ant: 0.9 kg on 8 cm
#: capsules) needs an explicit finer ``resolution``. The numbers: docs/own-robot.md, "The element budget".
AUTO_ELEMENTS = 3000
UNBOUNDED_SIZE = 1e6  # m: an element size far above any robot (auto_resolution's floor of elements)
AUTO_MIN_RESOLUTION = 0.005


def _collides(model: mujoco.MjModel, g: int) -> bool:
    """Whether geom ``g`` takes part in collisions: contype or conaffinity non-zero, or named in an explicit
    ``<pair>`` (feet that meet the floor only through pairs, as MuJoCo Playground's Apollo); else visual-only."""
    return bool(model.geom_contype[g] or model.geom_conaffinity[g]
                or (model.npair and (np.any(model.pair_geom1 == g) or np.any(model.pair_geom2 == g))))


def _geom_label(model: mujoco.MjModel, g: int) -> str:
    return mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) or f"#{g}"


def _ids(model, kind: mujoco.mjtObj, names, label: str, count: int) -> list[int]:
    if isinstance(names, (str, int, np.integer)):
        names = [names]
    ids = []
    for n in names:
        if isinstance(n, (int, np.integer)):
            if not 0 <= int(n) < count:
                raise ValueError(f"{label} id {int(n)} out of range [0, {count})")
            ids.append(int(n))
            continue
        i = mujoco.mj_name2id(model, kind, str(n))
        if i < 0:
            valid = [mujoco.mj_id2name(model, kind, k) for k in range(count)]
            raise unknown(label, n, [v for v in valid if v])
        ids.append(i)
    return ids


def select_geoms(model: mujoco.MjModel, bodies, geoms) -> list[int]:
    """Geom ids a terrain with these ``bodies`` / ``geoms`` selects (see :class:`GranularTerrain`)."""
    m = model
    if isinstance(bodies, str):
        bodies = bodies.split()
    if isinstance(geoms, str):
        geoms = geoms.split()
    selected: list[int] = []
    if bodies:
        for b in dict.fromkeys(_ids(m, mujoco.mjtObj.mjOBJ_BODY, bodies, "body", m.nbody)):
            if b == 0:
                static = sum(1 for g in range(m.ngeom) if m.geom_bodyid[g] == 0)
                raise ValueError(f"bodies names the world body, whose {static} geom(s) are the static scene (floor, "
                                 "bed, walls), not a part of the robot: the grains act on moving bodies; name the "
                                 "robot's bodies (or pass geoms=[...] for a particular geom)")
            own = [g for g in range(m.ngeom) if m.geom_bodyid[g] == b and m.geom_type[g] in _SUPPORTED_GEOMS]
            colliding = [g for g in own if _collides(m, g)]
            selected += colliding or own  # a body with visual geoms only: they are all it has
    if geoms:
        for g in _ids(m, mujoco.mjtObj.mjOBJ_GEOM, geoms, "geom", m.ngeom):
            if m.geom_type[g] not in _SUPPORTED_GEOMS:
                name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, g)
                raise ValueError(f"geom {name or g!r} has type {mujoco.mjtGeom(m.geom_type[g]).name}; "
                                 "supported: box, capsule, cylinder, sphere, ellipsoid, mesh")
            if g not in selected:
                selected.append(g)
    if not bodies and not geoms:
        selected = [g for g in range(m.ngeom)
                    if m.geom_bodyid[g] != 0 and m.geom_type[g] in _SUPPORTED_GEOMS and _collides(m, g)]
    return sorted(set(selected))


def _nothing_selected(model: mujoco.MjModel, bodies, geoms) -> ValueError:
    """The error for a selection (:func:`select_geoms`) that holds no geom: what the model's bodies have, and how
    to select it."""
    m = model
    supported = [g for g in range(m.ngeom) if m.geom_bodyid[g] != 0 and m.geom_type[g] in _SUPPORTED_GEOMS]
    types = "box, capsule, cylinder, sphere, ellipsoid or mesh"
    if bodies or geoms:
        return ValueError(f"no geoms selected for the granular terrain: bodies={bodies!r} have no {types} geom "
                          f"and geoms={geoms!r} names none")
    if not supported:
        return ValueError(f"no geoms selected for the granular terrain: no body of the model but the world has a "
                          f"{types} geom")
    shown = supported[:12]
    more = f" and {len(supported) - len(shown)} more" if len(supported) > len(shown) else ""

    def body(g):
        b = int(m.geom_bodyid[g])
        return mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b) or f"#{b}"

    listing = ", ".join(f"'{_geom_label(m, g)}' (body '{body(g)}')" for g in shown) + more
    geom_names = ", ".join(repr(mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, g) or g) for g in shown)
    body_names = ", ".join(repr(b) for b in dict.fromkeys(body(g) for g in supported))
    return ValueError(f"no geoms selected for the granular terrain: by default only collision geoms (contype or "
                      f"conaffinity non-zero, or in a <pair>) of the model's bodies feel the grains, and all "
                      f"{len(supported)} of its {types} geoms are visual-only (contype = conaffinity = 0): {listing}; "
                      "select them: "
                      f"bodies=[{body_names}] (a named body whose geoms are all visual-only gives them all) or "
                      f"geoms=[{geom_names}] (names or ids; a named geom is taken even when visual-only)")


def _check_selection(bodies, geoms) -> None:
    """Refuse an empty ``bodies``/``geoms`` list (None means: read the model's, or select the default)."""
    for name, value in (("bodies", bodies), ("geoms", geoms)):
        if value is not None and not isinstance(value, (str, int, np.integer)) and len(value) == 0:
            raise ValueError(f"{name}=[] selects nothing; name the {name} to cut into elements, or pass None "
                             "to use the model's mjrft:bodies / mjrft:geoms (default: every geom not on the "
                             "world body)")


def auto_resolution(model: mujoco.MjModel, geom_ids, target: int = AUTO_ELEMENTS,
                    finest: float = AUTO_MIN_RESOLUTION, stacklevel: int = 2) -> float:
    """The element size of ``resolution="auto"`` for these geoms: ``sqrt(area / target)`` for their total
    surface area, not finer than ``finest``, then coarsened until the elements :func:`~mjrft.geometry.discretize_geom`
    makes of them are at most 10 % more than ``target``: first by :func:`~mjrft.geometry.estimate_elements`
    (area / size^2 per primitive, a mesh's count exactly), then by the count the discretiser builds (it rounds
    each face, ring and cap up to whole elements: ~10 % more than the area estimate at a few thousand elements),
    counted from its cells without building the elements (:func:`~mjrft.geometry.geom_element_count`). The
    count before :func:`~mjrft.geometry.exposed_elements` drops the faces hidden inside neighbouring geoms, so
    a terrain's ``n_elements`` is at most ``1.1 target`` (or fewer, at ``finest``), unless the geoms' meshes alone
    give more at any size: then they are the budget, with a warning (``stacklevel`` as :func:`warnings.warn` counts
    from here)."""
    from .geometry.discretize import _mesh_arrays, surface_area
    area = 0.0
    for g in geom_ids:
        g = int(g)
        if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH:
            area += surface_area(int(model.geom_type[g]), None, *_mesh_arrays(model, int(model.geom_dataid[g])))
        else:
            area += surface_area(int(model.geom_type[g]), model.geom_size[g])
    # no element size gives fewer than the count at a size far above the robot: a mesh keeps one element per
    # direction bin of its faces' normals however large the size; when that floor exceeds the target, it is the budget
    least = sum(geom_element_count(model, g, UNBOUNDED_SIZE) for g in geom_ids)
    budget = max(target, least)
    res = max(float(finest), math.sqrt(area / target))
    for _ in range(8):
        n = estimate_elements(model, geom_ids, res)
        if n <= 1.1 * budget:
            break
        res *= math.sqrt(n / budget)
    for _ in range(8):
        n = sum(geom_element_count(model, g, res) for g in geom_ids)
        if n <= 1.1 * budget:
            break
        res *= math.sqrt(n / budget)
    if budget > target:
        n = sum(geom_element_count(model, g, res) for g in geom_ids)
        warnings.warn(f"mjrft: resolution='auto' cannot keep these geoms to about {target} elements: at any element "
                      f"size they give at least {least} (a mesh keeps one element per direction bin of its faces' "
                      f"normals, however large the size); using {res:.3g} m, which gives {n}. Pass resolution= (m) to "
                      "choose the size yourself, or select fewer geoms (geoms=[...], bodies=[...])", UserWarning,
                      stacklevel=stacklevel)
    return res

"""The sand surface taken from the model: a world floor geom (``floor=``), a height-field surface
(``surface="<hfield geom>"``), and the rigid contacts the terrain removes from the floor or warns about.

:func:`_find_floor` picks the floor (a named geom, or ``"auto"``: the highest horizontal collision plane, box or
hfield under the robot), :func:`_rigid_floors_left` names the other rigid geoms of the world the robot can still
stand on (:func:`rigid_support_notes` does it for a surface given as a height),
:func:`remove_contacts` takes the chosen floor out of MuJoCo's collisions in the loaded model, and
:func:`_hfield_surface` reads an hfield geom's world heights for the kernel (:func:`mjrft.surface.surface_height`).
"""

from __future__ import annotations

import mujoco
import numpy as np

from .errors import UnknownNameError, unknown
from .selection import _collides, _geom_label, _ids
from .surface import surface_heights


_FLOOR_TYPES = {int(mujoco.mjtGeom.mjGEOM_PLANE): "plane", int(mujoco.mjtGeom.mjGEOM_BOX): "box",
                int(mujoco.mjtGeom.mjGEOM_HFIELD): "hfield"}
FLOOR_PAIR_MARGIN = -1e10  # m: an explicit <pair> with the floor gets this margin (no contact within reach)


def _floor_top(model: mujoco.MjModel, d: mujoco.MjData, g: int, xy: np.ndarray):
    """(top height under ``xy`` or None, why not a floor or None) of a plane / box / hfield geom of the world."""
    kind = _FLOOR_TYPES.get(int(model.geom_type[g]))
    if kind is None:
        return None, f"a {mujoco.mjtGeom(model.geom_type[g]).name[len('mjGEOM_'):].lower()}, not a plane, box or hfield"
    if model.body_weldid[model.geom_bodyid[g]] != 0:
        return None, "on a moving body"
    R = d.geom_xmat[g].reshape(3, 3)
    p = d.geom_xpos[g]
    if kind == "box":
        vertical = np.flatnonzero(np.abs(np.abs(R[2]) - 1.0) <= 1e-9)
        if not len(vertical):
            return None, "tilted (no face is horizontal)"
        i = int(vertical[0])
        local = R.T @ np.array([xy[0] - p[0], xy[1] - p[1], 0.0])
        under = all(abs(local[j]) <= model.geom_size[g, j] for j in range(3) if j != i)
        return p[2] + model.geom_size[g, i], (None if under else "not under the robot")
    if abs(R[2, 2] - 1.0) > 1e-9:
        return None, "tilted (its z axis is not vertical up)"
    if kind == "plane":
        return float(p[2]), None
    h = model.geom_dataid[g]
    rx, ry = model.hfield_size[h, :2]
    local = R.T @ np.array([xy[0] - p[0], xy[1] - p[1], 0.0])
    if abs(local[0]) > rx or abs(local[1]) > ry:
        return None, "not under the robot"
    _, z, frame = _hfield_surface(model, _geom_label(model, g))
    out = np.empty(1)
    surface_heights(np.array([xy[0]]), np.array([xy[1]]), 0.0, z, frame, out)
    return float(out[0]), None


def geom_world_boxes(model: mujoco.MjModel, d: mujoco.MjData, geom_ids) -> tuple[np.ndarray, np.ndarray]:
    """(lower, upper) corners, shape (n, 3), of the world-aligned bounding boxes of ``geom_ids`` in ``d``'s pose
    (each geom's own bounding box, ``geom_aabb``, turned into the world)."""
    ids = np.asarray(geom_ids, dtype=np.int64)
    R = d.geom_xmat[ids].reshape(-1, 3, 3)
    c = d.geom_xpos[ids] + np.einsum("nij,nj->ni", R, model.geom_aabb[ids, :3])
    h = np.einsum("nij,nj->ni", np.abs(R), model.geom_aabb[ids, 3:])
    return c - h, c + h


def _collides_with(model: mujoco.MjModel, f: int, geom_ids) -> bool:
    """Whether MuJoCo collides geom ``f`` with any of ``geom_ids``: their contype/conaffinity bits match (either
    way round) or an explicit ``<pair>`` joins them (one not already taken out of reach)."""
    ids = np.asarray(geom_ids, dtype=np.int64)
    ct, ca = int(model.geom_contype[f]), int(model.geom_conaffinity[f])
    if np.any((model.geom_contype[ids] & ca) | (model.geom_conaffinity[ids] & ct)):
        return True
    chosen = set(int(g) for g in ids)
    for p in range(model.npair):
        g1, g2 = int(model.pair_geom1[p]), int(model.pair_geom2[p])
        if model.pair_margin[p] > FLOOR_PAIR_MARGIN and ((g1 == f and g2 in chosen) or (g2 == f and g1 in chosen)):
            return True
    return False


def _find_floor(model: mujoco.MjModel, floor, geom_ids) -> tuple[int, object, list[str]]:
    """(geom id, surface: its top height, or its name for an hfield, warnings) of ``floor`` (a geom name/id or
    ``"auto"``), judged at the model's initial pose under the centre of the selected geoms. ``"auto"`` takes the
    highest horizontal collision floor under the robot that collides with the selected geoms (else the highest
    collision floor); the warnings name the other collision floors the robot can still stand on
    (:func:`_rigid_floors_left`)."""
    if isinstance(floor, (bool, np.bool_)) or not isinstance(floor, (str, int, np.integer)):
        raise ValueError(f"floor must be None, 'auto' or a geom name/id, got {floor!r}")
    d, xy = _initial_pose(model, geom_ids)
    world = _world_floors(model)
    if isinstance(floor, str) and floor.strip().lower() == "auto":
        tops, rejected = [], []
        for g in world:
            top, why = _floor_top(model, d, g, xy)
            if why is None and not _collides(model, g):
                why = "visual-only (contype = conaffinity = 0)"
            (rejected if why else tops).append((g, top, why))
        listing = "; ".join(f"'{_geom_label(model, g)}' ({_FLOOR_TYPES[int(model.geom_type[g])]}, "
                            + (f"top {t:.6g} m" if w is None else w) + ")" for g, t, w in tops + rejected)
        where = f"under the selected geoms' centre (x, y) = ({xy[0]:.4g}, {xy[1]:.4g}) m at the initial pose"
        if not tops:
            raise ValueError(f"floor='auto' found no collision plane, box or hfield of the world with a horizontal "
                             f"top {where}; candidates: {listing or '(none)'}; name the floor (floor='<geom>') or "
                             "give the sand's height (surface=<m>)")
        pool = [(g, t) for g, t, _ in tops if _collides_with(model, g, geom_ids)] or [(g, t) for g, t, _ in tops]
        high = max(t for _, t in pool)
        highest = [g for g, t in pool if t >= high - 1e-9]
        if len(highest) > 1:
            raise ValueError(f"floor='auto' is ambiguous: {len(highest)} geoms have the highest top {high:.6g} m "
                             f"{where}: {', '.join(repr(_geom_label(model, g)) for g in highest)}; candidates: "
                             f"{listing}; name the floor (floor='<geom>')")
        g, top = highest[0], high
    else:
        names = [_geom_label(model, g) for g in world]
        try:
            g = _ids(model, mujoco.mjtObj.mjOBJ_GEOM, floor, "floor geom", model.ngeom)[0]
        except UnknownNameError:
            raise unknown("floor geom", floor, ["auto", *names]) from None
        top, why = _floor_top(model, d, g, xy)
        if why is not None and why != "not under the robot":
            raise ValueError(f"floor geom {_geom_label(model, g)!r} cannot be the sand surface: it is {why}; "
                             f"world planes, boxes and hfields: {', '.join(names) or '(none)'}")
    small = _footprint_note(model, d, g, geom_ids, auto=isinstance(floor, str))
    notes = [] if top is None else _rigid_floors_left(model, d, g, float(top), world, xy, geom_ids, small is not None)
    if small is not None:
        notes.insert(0, small)
    if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_HFIELD:
        return g, _geom_label(model, g), notes
    return g, float(top), notes


def _footprint_note(model: mujoco.MjModel, d: mujoco.MjData, g: int, geom_ids, auto: bool) -> str | None:
    """The warning for a floor (box or hfield; a plane is unbounded) smaller in x or y than the robot's footprint,
    the (x, y) extent of the selected geoms' bounding box at the initial pose, or None: its top becomes the sand
    surface everywhere, also beyond its edges, so a small obstacle taken for the floor lifts the sand to its top."""
    if int(model.geom_type[g]) == int(mujoco.mjtGeom.mjGEOM_PLANE):
        return None
    lo, hi = geom_world_boxes(model, d, geom_ids)
    robot = hi.max(axis=0)[:2] - lo.min(axis=0)[:2]
    flo, fhi = geom_world_boxes(model, d, [g])
    extent = (fhi - flo)[0, :2]
    if np.all(extent >= robot - 1e-9):
        return None
    chose = "floor='auto' chose" if auto else "the floor is"
    kind = _FLOOR_TYPES[int(model.geom_type[g])]
    return (f"mjrft: {chose} geom '{_geom_label(model, g)}' ({kind}, {extent[0]:.4g} x {extent[1]:.4g} m in x and y), "
            f"smaller than the robot's footprint ({robot[0]:.4g} x {robot[1]:.4g} m, the selected geoms at the "
            "initial pose): its top becomes the sand surface everywhere, beyond its edges too; if it is an obstacle "
            "on the floor you mean, name that floor (floor='<geom>') or give the sand's height (surface=<m>)")


def _world_floors(model: mujoco.MjModel) -> list[int]:
    """The planes, boxes and hfields fixed to the world: the floor candidates."""
    return [g for g in range(model.ngeom) if model.body_weldid[model.geom_bodyid[g]] == 0
            and int(model.geom_type[g]) in _FLOOR_TYPES]


def _initial_pose(model: mujoco.MjModel, geom_ids) -> tuple[mujoco.MjData, np.ndarray]:
    """(data at the model's initial pose, kinematics only; the (x, y) centre of the selected geoms there)."""
    d = mujoco.MjData(model)
    mujoco.mj_kinematics(model, d)
    return d, d.geom_xpos[np.asarray(geom_ids, dtype=np.int64), :2].mean(axis=0)


def rigid_support_notes(model: mujoco.MjModel, top: float, geom_ids, skip=None) -> list[str]:
    """The warnings of :func:`_rigid_floors_left` for a sand surface at height ``top`` that no floor geom gives
    (``floor=None``; ``skip``: the hfield geom of a height-field surface)."""
    d, xy = _initial_pose(model, geom_ids)
    return _rigid_floors_left(model, d, skip, float(top), _world_floors(model), xy, geom_ids)


def _rigid_floors_left(model: mujoco.MjModel, d: mujoco.MjData, g, top: float, world, xy, geom_ids,
                       small_floor: bool = False) -> list[str]:
    """The warnings for the rigid geoms of the world other than ``g`` (the floor whose top ``top`` is the sand
    surface; None when the surface is a given height) that the robot can still stand on, among those that collide
    with the selected geoms: every plane, box or hfield of ``world`` with a horizontal top under ``xy``, and every
    other geom of the world but a plane or hfield (a cylinder, a sphere, a mesh, a tilted box) whose bounding box
    overlaps the selected geoms' in (x, y); each when its top is at or above the surface, or, below a floor's surface,
    below it by less than the robot's size (the largest extent of the selected geoms' bounding box at the initial
    pose): a geom that sinks that deep meets it. ``small_floor``: ``g`` is smaller than the robot's footprint
    (:func:`_footprint_note`), so a larger floor below it is more likely the one meant, and the advice names it."""
    lo, hi = geom_world_boxes(model, d, geom_ids)
    lo, hi = lo.min(axis=0), hi.max(axis=0)
    size = float((hi - lo).max())
    where = f"{top:.6g} m, " + ("the surface height" if g is None else f"the top of '{_geom_label(model, g)}'")
    auto = ", or floor='auto'" if g is None else ""
    out = []
    floors = set()  # the horizontal floors under xy, judged by their top here whether they collide or not
    for f in world:
        if f == g:
            continue
        t, why = _floor_top(model, d, f, xy)
        if why is not None:
            continue
        floors.add(f)
        if not _collides_with(model, f, geom_ids):
            continue
        out += _support_note(model, f, _FLOOR_TYPES[int(model.geom_type[f])], "collision floor", t, top, where, size,
                             auto, below=g is not None, small_floor=small_floor)
    skip = (int(mujoco.mjtGeom.mjGEOM_PLANE), int(mujoco.mjtGeom.mjGEOM_HFIELD))
    others = [f for f in range(model.ngeom) if f != g and f not in floors and int(model.geom_type[f]) not in skip
              and model.body_weldid[model.geom_bodyid[f]] == 0]
    if others:
        flo, fhi = geom_world_boxes(model, d, others)
        for f, a, b in zip(others, flo, fhi):
            if a[0] > hi[0] or b[0] < lo[0] or a[1] > hi[1] or b[1] < lo[1] or not _collides_with(model, f, geom_ids):
                continue
            kind = mujoco.mjtGeom(model.geom_type[f]).name[len("mjGEOM_"):].lower()
            out += _support_note(model, f, kind, "rigid collision geom of the world", float(b[2]), top, where, size,
                                 None, below=g is not None)
    return out


def _support_note(model, f: int, kind: str, what: str, t: float, top: float, where: str, size: float, auto,
                  below: bool, small_floor: bool = False) -> list[str]:
    """The warning (a list of none or one) for the rigid geom ``f`` of type ``kind`` whose top is ``t`` under the
    robot, against the sand surface ``top`` (``where``: how the surface was given) and the robot's ``size``.
    ``auto``: None for a geom that cannot be the floor, else what follows ``floor='<name>'`` in the advice;
    ``below``: also warn about a geom below the surface by less than the robot's size (not for a surface given as
    a height, where a rigid bottom below it is the model's design); ``small_floor``: the surface's floor is smaller
    than the robot's footprint, so this floor below it may be the one meant (the advice names it)."""
    name = _geom_label(model, f)
    remove = f"model.geom_contype[{f}] = model.geom_conaffinity[{f}] = 0"
    if t >= top - 1e-9:
        name_it = "" if auto is None else f"name it as the floor (floor='{name}'{auto}) or "
        return [f"mjrft: geom '{name}' ({kind}, top {t:.6g} m) is a {what} under the robot at or above the sand "
                f"surface ({where}): it keeps its rigid contacts, so the robot stands on it and not on the sand; "
                f"{name_it}remove its contacts ({remove})"]
    if below and top - t < size:
        if small_floor and auto is not None:
            return [f"mjrft: geom '{name}' ({kind}, top {t:.6g} m) is a {what} {top - t:.4g} m below the sand surface "
                    f"({where}, a geom smaller than the robot's footprint): it keeps its rigid contacts and the robot "
                    f"stands on it; if the sand lies on it, name it as the floor (floor='{name}')"]
        keep = "" if auto is None else ", or keep it as the bed's rigid bottom"
        return [f"mjrft: geom '{name}' ({kind}, top {t:.6g} m) is a {what} {top - t:.4g} m below the sand surface "
                f"({where}), less than the robot's size ({size:.4g} m): it keeps its rigid contacts, "
                f"so a geom that sinks {top - t:.4g} m stands on it; remove its contacts ({remove}) for deeper "
                f"sand{keep}"]
    return []


def remove_contacts(model: mujoco.MjModel, g: int) -> tuple[int, int]:
    """Take geom ``g`` out of MuJoCo's collisions in the loaded model (contype = conaffinity = 0, explicit
    pairs with it out of reach); returns its former (contype, conaffinity)."""
    before = (int(model.geom_contype[g]), int(model.geom_conaffinity[g]))
    model.geom_contype[g] = 0
    model.geom_conaffinity[g] = 0
    for p in range(model.npair):
        if g in (model.pair_geom1[p], model.pair_geom2[p]):
            model.pair_margin[p] = FLOOR_PAIR_MARGIN
    return before


def _hfield_surface(model: mujoco.MjModel, name) -> tuple[int, np.ndarray, np.ndarray]:
    """(geom id, world heights (nrow, ncol), frame) of the hfield geom ``name`` (see
    :func:`mjrft.surface.surface_height`)."""
    hgeoms = [g for g in range(model.ngeom) if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_HFIELD]
    hnames = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) or f"#{g}" for g in hgeoms]
    g = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, str(name))
    if g < 0:
        raise UnknownNameError(f"surface {name!r} is neither a number nor a geom of the model; hfield geoms: "
                               f"{', '.join(hnames) or '(none)'}")
    if model.geom_type[g] != mujoco.mjtGeom.mjGEOM_HFIELD:
        raise ValueError(f"surface geom {name!r} has type {mujoco.mjtGeom(model.geom_type[g]).name}, not an hfield; "
                         f"hfield geoms: {', '.join(hnames) or '(none)'}")
    if model.body_weldid[model.geom_bodyid[g]] != 0:
        raise ValueError(f"surface hfield geom {name!r} is on a moving body; the free surface must be fixed to the world")
    d = mujoco.MjData(model)
    mujoco.mj_kinematics(model, d)
    R = d.geom_xmat[g].reshape(3, 3)
    if abs(R[2, 2] - 1.0) > 1e-9:
        raise ValueError(f"surface hfield geom {name!r} is tilted (its z axis is {np.round(R[:, 2], 6).tolist()}); "
                         "only hfields turned about the vertical axis are supported")
    h = model.geom_dataid[g]
    nrow, ncol = int(model.hfield_nrow[h]), int(model.hfield_ncol[h])
    if nrow < 2 or ncol < 2:
        raise ValueError(f"surface hfield geom {name!r} needs at least 2 x 2 samples, got {nrow} x {ncol}")
    rx, ry, elev, _ = model.hfield_size[h]
    adr = model.hfield_adr[h]
    z = d.geom_xpos[g, 2] + elev * np.asarray(model.hfield_data[adr:adr + nrow * ncol], dtype=np.float64)
    frame = np.array([d.geom_xpos[g, 0], d.geom_xpos[g, 1], R[0, 0], R[1, 0], rx, ry,
                      (ncol - 1) / (2 * rx), (nrow - 1) / (2 * ry)], dtype=np.float64)
    return g, np.ascontiguousarray(z.reshape(nrow, ncol)), frame

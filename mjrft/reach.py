"""Whether a terrain's selected geoms can ever meet the sand: :func:`reach_warning` (what a terrain says at
construction when none can) and the bound it rests on, :func:`lowest_reach`; and :func:`sinking_warning`, for the
bodies that will sink through it because no geom of theirs feels the grains."""

from __future__ import annotations

import math

import mujoco
import numpy as np

from .floor import geom_world_boxes
from .selection import _collides

REACH_TOLERANCE = 1e-6  # m


def lowest_reach(model: mujoco.MjModel, data: mujoco.MjData, g: int, bottom: float) -> tuple[float, bool]:
    """(a lower bound on the height geom ``g`` can reach by any motion of its joints, whether gravity alone can
    move it down) from the pose in ``data`` (kinematics done), where the geom's lowest point is ``bottom``.

    The bound follows the geom up its chain of bodies to the world: a slide joint moves it along its axis by
    at most its range (its downward part is counted exactly while no joint above turns it); a hinge or ball
    joint turns everything below it about its anchor, so from the first one on the geom is followed as a
    sphere (its bounding sphere, ``geom_rbound`` about its centre, plus the slides' travel below the turn) that
    grows to the sphere about the anchor holding it (radius ``|c - anchor| + r``, the same in every pose). A
    free joint, a mocap body or an unlimited slide with a vertical component gives ``-inf``. The geom can fall
    by itself when its chain holds a free joint or a slide with a vertical component that may move down, and
    the model's gravity points down."""
    gz = float(model.opt.gravity[2])
    c, r = data.geom_xpos[g].copy(), float(model.geom_rbound[g])
    slack = down = 0.0  # any-direction and downward travel of the slides since the last turn
    falls = turned = False
    b = int(model.geom_bodyid[g])
    while b != 0:
        if model.body_mocapid[b] >= 0:
            return -math.inf, falls
        first, n = int(model.body_jntadr[b]), int(model.body_jntnum[b])
        for j in range(first + n - 1, first - 1, -1):
            kind = model.jnt_type[j]
            if kind == mujoco.mjtJoint.mjJNT_FREE:
                return -math.inf, falls or gz < 0
            if kind == mujoco.mjtJoint.mjJNT_SLIDE:
                q = float(data.qpos[model.jnt_qposadr[j]])
                lo, hi = (model.jnt_range[j] - q) if model.jnt_limited[j] else (-math.inf, math.inf)
                az = float(data.xaxis[j, 2])
                dn = 0.0 if abs(az) < 1e-12 else max(-lo * az, -hi * az, 0.0)
                slack += max(abs(lo), abs(hi))
                down += dn
                falls = falls or (dn > 0 and gz < 0)
            else:
                a = data.xanchor[j]
                r = float(np.linalg.norm(c - a)) + r + slack
                c, slack, down, turned = a.copy(), 0.0, 0.0, True
        b = int(model.body_parentid[b])
    return float((c[2] - r if turned else bottom) - down), falls


def reach_warning(terrain, data: mujoco.MjData) -> str | None:
    """The warning for a robot whose selected geoms may never meet the sand, judged in ``data``'s pose (kinematics
    done), or None: no selected geom is below the sand surface (or its water) in that pose, and none can fall onto
    it (:func:`lowest_reach`); then either none can reach it by any motion of its joints, or the robot is fixed
    to the world and meets the grains only where its actuators drive a geom down."""
    m = terrain.model
    ids = np.asarray(terrain.geom_ids, dtype=np.int64)
    lo, _ = geom_world_boxes(m, data, ids)
    xy = data.geom_xpos[ids, :2]
    local = terrain.surface_height(xy[:, 0], xy[:, 1]) + terrain.water_depth
    if np.any(lo[:, 2] < local - REACH_TOLERANCE):
        return None
    reach = [lowest_reach(m, data, int(g), float(z)) for g, z in zip(ids, lo[:, 2])]
    if any(falls for _, falls in reach):
        return None
    top = (float(terrain.surface_samples()[2].max()) if terrain.surface_hfield is not None
           else float(terrain.surface)) + terrain.water_depth
    what = "the sand surface" + (" and its water" if terrain.water_depth > 0 else "")
    rows = sorted(zip(lo[:, 2], (z for z, _ in reach), ids), key=lambda row: row[0])

    def label(g):
        body = int(m.geom_bodyid[g])
        return (f"'{mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, g) or f'#{g}'}' (body "
                f"'{mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, body) or f'#{body}'}'")

    listing = ", ".join(f"{label(int(g))}, bottom {b:.4g} m, reach {z:.4g} m)" for b, z, g in rows[:8])
    listing += f" and {len(rows) - 8} more" if len(rows) > 8 else ""
    floor = f" (the top of '{mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, terrain.floor)}')" \
        if terrain.floor is not None else ""
    if all(z >= top - REACH_TOLERANCE for _, z, _ in rows):
        return (f"mjrft: the robot's selected geoms never reach {what} at {top:.4g} m{floor}: none is below it at the "
                "initial pose, none can fall, and the lowest each can reach by any motion of its joints stays above "
                f"it; they will feel no granular force. Geoms (body, lowest point at the initial pose, lowest point "
                f"any motion of the joints can bring it to): {listing}. Check the floor (floor='<geom>') or the "
                "sand's height (surface=<m>)")
    return (f"mjrft: the robot is fixed to the world (no free joint or vertical slide lets it fall onto the sand"
            f"{'' if m.opt.gravity[2] < 0 else ', and gravity does not pull down'}) and none of its selected "
            f"geoms is below {what} at {top:.4g} m{floor} at the initial pose: it feels granular force only where "
            f"its actuators drive a geom below the surface. Geoms (body, lowest point at the initial pose, lowest "
            f"point any motion of the joints can bring it to): {listing}")


def sinking_warning(model: mujoco.MjModel, data: mujoco.MjData, geom_ids) -> str | None:
    """The warning for the bodies that feel no grains and can fall (judged in ``data``'s pose): each group of
    bodies welded together with a mass and geoms, none of them selected (``geom_ids``) and none colliding
    (contype = conaffinity = 0), whose chain lets gravity move it down (:func:`lowest_reach`); or None. Such a body
    sinks through the sand as it would through any floor, which a user who sees its visual geoms may not expect."""
    selected = set(int(g) for g in geom_ids)
    groups: dict[int, list[int]] = {}
    for g in range(model.ngeom):
        w = int(model.body_weldid[model.geom_bodyid[g]])
        if w != 0:
            groups.setdefault(w, []).append(g)
    names = []
    for w, gs in groups.items():
        if any(g in selected or _collides(model, g) for g in gs):
            continue
        if model.body_mass[model.body_weldid == w].sum() <= 0:
            continue
        if lowest_reach(model, data, gs[0], 0.0)[1]:
            names.append(mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, w) or f"#{w}")
    if not names:
        return None
    shown = ", ".join(f"'{n}'" for n in names[:8]) + (f" and {len(names) - 8} more" if len(names) > 8 else "")
    return (f"mjrft: bodies {shown} have no collision geom (contype = conaffinity = 0) and can fall: they feel no "
            "grains and sink through the sand, as through any floor; select them (bodies=[...]: their visual geoms "
            "then get elements) or give them collision geoms")

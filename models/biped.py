"""Planar robophysics biped (reference section 6): 30.3 cm tall, 1.6 kg.

Frame: x forward, y left, z up. The robot is constrained to the sagittal (x-z)
plane by its root joints on the ``torso`` body: ``rootx`` (slide x), ``rootz``
(slide z) and, with ``pitch_free=True`` (default), ``rooty`` (hinge y, pitch);
``pitch_free=False`` removes the pitch joint (torso kept upright).

Legs: four pitch servos per leg, all hinges about y (the planar model cannot
use roll joints, so the fourth servo is a *double knee*, the two-servo knee of
common hobby-servo bipeds):

    torso -[left_hip]- left_thigh (7 cm) -[left_knee_upper]- left_knee_link (2.5 cm)
          -[left_knee_lower]- left_shank (7 cm) -[left_ankle]- left_foot

(and the same with ``right_``). Sign convention (hinge about +y): a positive
hip angle swings the leg backward, positive knee angles flex the knee
(shank backward), a positive ankle angle turns the toe DOWN (so the ankle
angle is directly the toe "presentation angle", positive toe-down).
Joint ranges: hip +-2.0 rad, each knee joint [-0.3, 1.6] rad, ankle +-1.2 rad.

Feet (``foot=``), each with its sole centre ``foot_size/2`` below the ankle axis:

* ``"cone"`` (default): the experiment's foot, a 3-D printed conical foot with a circular sole of
  diameter ``foot_size`` (default 8.5 cm; the thesis also tested 7 to 10 cm, section 2.3.2), flat
  sole down and apex up (a mesh of ~1 cm triangles whose rim polygon has the area of the circle). The thesis
  gives no height for it; we give it the height of the simulation's wedge, ``foot_size * 7.5/8.5``,
  because the thesis modelled the conical disks "as wedges of the same area" (section 3.3.1): the
  wedge is this cone's side profile (an 8.5 cm base, 7.5 cm tall triangle) extruded across;
* ``"wedge"``: the simulation's foot (thesis fig. 18: 8.5 cm long, 8.5 wide, 7.5 tall), a
  triangular-prism mesh, sole ``foot_size`` long (x) by ``foot_width`` wide (y), apex line
  ``foot_size * 7.5/8.5`` above the sole, flat sole down;
* ``"roller"``: a cylinder of diameter ``foot_size`` with its axis along y (lying across the
  robot), ``foot_width`` long (not a foot of the thesis; a rolling contact for comparison).

``foot_width`` (y extent of the wedge and the roller, default ``foot_size``) does not apply to the
circular cone. The name ``"round"`` is refused with the valid choices (a round foot is either the
cone or the roller).

The ankle axis is ``foot_size/2`` above the sole, so the default robot (every foot) is 30.3 cm
from sole to torso top: ankle 4.25 cm + shank 7 cm + knee link 2.5 cm + thigh 7 cm + torso top
9.55 cm above the hip. Other foot sizes change the height by the change in ``foot_size/2``.
The site ``<side>_sole`` marks the sole centre (the point the ``rect`` gait moves on its
rectangle, :mod:`mjrft.tools.gaits`). The legs sit at y = +-(foot_width/2 + 5 mm) so the feet do not
overlap.

Masses (sum 1.6 kg): torso 0.56 kg (electronics, battery), per leg thigh
0.14, knee link 0.08, shank 0.14, foot 0.16 kg (HSR-5980SG servos are 68 g
each and sit in the links). Foot mass is kept at 0.16 kg for all foot sizes.

Servos: the thesis' simulation drove each joint with a PD controller whose torque saturates at
the servos' limit (section 3.3.2, fig. 14B) and gives neither the gains ("tuned ... so the
controller was stable and responsive") nor the limit in numbers. Here: MuJoCo ``<position>``
actuators named after their joints, kp = 30 N m/rad, kv = 0.5 N m s/rad, torque limit
(forcerange) +-2.5 N m (HSR-5980SG class: about 24 kg cm = 2.35 N m stall at 6 V and 30 kg cm =
2.9 N m at 7.4 V by the maker's rating), ctrlrange = joint range; joint armature 1e-3 kg m^2
(gear-train reflected inertia), damping 0.05 N m s/rad.

Granular bodies: ``left_foot right_foot`` (plus the shanks with
``granular_shanks=True``); element size 1 cm.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from .scene import (
    ROBOT_CONTACT,
    assemble,
    check_positive,
    fmt,
    look_at,
    pop_scene_options,
    reject_unknown,
)

HEIGHT = 0.303
TOTAL_MASS = 1.6
DEFAULT_FOOT_SIZE = 0.085
WEDGE_HEIGHT_RATIO = 7.5 / 8.5
FOOT_TYPES = ("cone", "wedge", "roller")
#: the biped's element size (m). Choice: 2 cm, the coarsest at which the thesis case's rect gait on poppy
#: seeds keeps its 1 cm numbers (step and slip at -30, 30 and 55 deg equal to 0.01 cm, sinkage within 3 %),
#: so the default BipedSand has as few elements as before the cone feet (748; 2992 at 1 cm)
RESOLUTION = 0.02
THIGH = 0.07
KNEE_LINK = 0.025
SHANK = 0.07
TORSO_TOP = HEIGHT - DEFAULT_FOOT_SIZE / 2 - (THIGH + KNEE_LINK + SHANK)  # above the hip axis
TORSO_BOTTOM = -0.015
MASS = {"torso": 0.56, "thigh": 0.14, "knee_link": 0.08, "shank": 0.14, "foot": 0.16}
KP, KV, TORQUE_LIMIT = 30.0, 0.5, 2.5
ARMATURE, DAMPING = 1e-3, 0.05
RANGES = {
    "hip": (-2.0, 2.0),
    "knee_upper": (-0.3, 1.6),
    "knee_lower": (-0.3, 1.6),
    "ankle": (-1.2, 1.2),
}
JOINTS = tuple(RANGES)
CLEARANCE = 0.0005


def biped_leg_ik(x: float, z: float, thigh: float, link: float, shank: float) -> tuple[float, float]:
    """Hip angle and total knee bend putting the ankle at (x, z) from the hip (x forward, z up).

    The two knee servos share the bend equally, so the chain thigh-link-shank is symmetric and the
    ankle lies at distance ``r = (thigh + shank) cos(k / 2) + link`` (for thigh = shank) along the
    knee link's direction. Positive hip angle swings the leg backward; positive knee flexes.
    """
    r = math.hypot(x, z)
    leg = 0.5 * (thigh + shank)
    c = (r - link) / (2.0 * leg)
    if not -1.0 <= c <= 1.0:
        raise ValueError(f"point ({x:.3f}, {z:.3f}) m is out of the biped leg's reach "
                         f"({link:.3f} to {link + 2 * leg:.3f} m from the hip)")
    k = 2.0 * math.acos(c)
    phi = math.atan2(-x, -z)
    return phi - k / 2.0, k


def _wedge_vertices(length: float, width: float, size: float) -> np.ndarray:
    """Triangular prism in the foot (ankle) frame: sole at z = -size/2, apex up."""
    h = size * WEDGE_HEIGHT_RATIO
    zs = -size / 2.0
    verts = []
    for y in (-width / 2.0, width / 2.0):
        verts += [(-length / 2.0, y, zs), (length / 2.0, y, zs), (0.0, y, zs + h)]
    return np.array(verts)


def _cone_mesh(diameter: float, size: float, edge: float = RESOLUTION) -> tuple[np.ndarray, np.ndarray]:
    """Cone in the foot (ankle) frame, circular sole of ``diameter`` at z = -size/2, apex
    ``size * 7.5/8.5`` above it: (vertices (V, 3), outward counter-clockwise faces (F, 3)).

    The surface is cut into small triangles (rings on the sole and on the side, about ``edge`` long;
    ``edge`` is the scene's resolution, so the mjrft surface elements are these triangles, one each, with
    no thin slivers). The rim is a regular polygon whose area equals the circle's (circumradius scaled
    by sqrt(pi / (n/2 sin(2 pi/n)))), so the sole bears on the circular foot's area."""
    h = size * WEDGE_HEIGHT_RATIO
    zs = -size / 2.0
    r0 = diameter / 2.0
    n = max(12, math.ceil(2.0 * math.pi * r0 / (0.8 * edge)))  # sectors: rim chord ~0.8 edge
    r = r0 * math.sqrt(math.pi / (0.5 * n * math.sin(2.0 * math.pi / n)))
    nb = max(1, math.ceil(r / (0.6 * edge)))  # sole rings
    ns = max(1, math.ceil(math.hypot(r, h) / (0.6 * edge)))  # side rings
    a = 2.0 * math.pi * np.arange(n) / n
    cs = np.column_stack([np.cos(a), np.sin(a)])
    verts = [(0.0, 0.0, zs)]  # sole centre
    sole_rings = []
    for j in range(1, nb + 1):
        sole_rings.append(len(verts) + np.arange(n))
        verts += [(rr * c, rr * s_, zs) for c, s_ in cs for rr in (r * j / nb,)]
    side_rings = [sole_rings[-1]]  # the rim is shared
    for j in range(1, ns):
        f = 1.0 - j / ns
        side_rings.append(len(verts) + np.arange(n))
        verts += [(r * f * c, r * f * s_, zs + h * (1.0 - f)) for c, s_ in cs]
    apex = len(verts)
    verts.append((0.0, 0.0, zs + h))
    faces = []

    def band(inner, outer, up):  # quads between two rings, two triangles each, outward
        for i in range(n):
            k = (i + 1) % n
            if up:  # side: outward = away from the axis, counter-clockwise seen from outside
                faces.extend([(outer[i], outer[k], inner[k]), (outer[i], inner[k], inner[i])])
            else:  # sole: outward = down
                faces.extend([(inner[i], inner[k], outer[k]), (inner[i], outer[k], outer[i])])

    for i in range(n):  # sole centre fan (normal down)
        faces.append((0, sole_rings[0][(i + 1) % n], sole_rings[0][i]))
    for j in range(1, nb):
        band(sole_rings[j - 1], sole_rings[j], up=False)
    for j in range(1, ns):
        band(side_rings[j], side_rings[j - 1], up=True)
    top = side_rings[-1]
    for i in range(n):  # apex fan (normal out and up)
        faces.append((top[i], top[(i + 1) % n], apex))
    return np.array(verts), np.array(faces, dtype=int)


def biped_xml(
    foot: str = "cone",
    foot_size: float = DEFAULT_FOOT_SIZE,
    pitch_free: bool = True,
    sand: bool = True,
    **kw,
) -> str:
    """MJCF text of the planar biped.

    Parameters
    ----------
    foot: ``"cone"`` (the experiment's conical foot), ``"wedge"`` (the simulation's) or ``"roller"``
        (a cylinder lying across).
    foot_size: sole diameter (cone), sole length (wedge) or diameter (roller) in m (default 0.085).
    pitch_free: include the torso pitch joint ``rooty``.
    sand: granular bed (True) or rigid floor (False).
    **kw: ``foot_width`` (m, wedge and roller only, default = foot_size), ``granular_shanks`` (bool),
        ``kp``, ``kv``, ``torque_limit``, and the scene options of
        :func:`mjrft.models.scene.pop_scene_options` (``bed_depth``, ``medium``, ...).
    """
    if foot == "round":
        raise ValueError("biped foot 'round' is ambiguous: 'cone' is the thesis robot's circular (conical) foot, "
                         f"'roller' a cylinder lying across; valid: {', '.join(FOOT_TYPES)}")
    if foot not in FOOT_TYPES:
        raise ValueError(f"unknown biped foot {foot!r}; valid: {', '.join(FOOT_TYPES)}")
    size = check_positive("foot_size", foot_size)
    kw = dict(kw)
    width = kw.pop("foot_width", None)
    if foot == "cone" and width is not None:
        raise ValueError(f"foot_width={width!r} does not apply to the circular 'cone' foot (its diameter is "
                         "foot_size); foot_width is for the 'wedge' and 'roller' feet")
    width = size if width is None else check_positive("foot_width", width)
    granular_shanks = bool(kw.pop("granular_shanks", False))
    kp = check_positive("kp", kw.pop("kp", KP))
    kv = check_positive("kv", kw.pop("kv", KV))
    tl = check_positive("torque_limit", kw.pop("torque_limit", TORQUE_LIMIT))
    bodies = ["left_foot", "right_foot"] + (["left_shank", "right_shank"] if granular_shanks else [])
    opts = pop_scene_options(kw, resolution=RESOLUTION, bed_length=2.0, bed_width=0.5,
                             granular_bodies=bodies, sand=sand)
    reject_unknown(kw, "biped_xml")

    ankle_h = size / 2.0
    z_hip = ankle_h + SHANK + KNEE_LINK + THIGH + CLEARANCE + opts.surface
    hip_y = width / 2.0 + 0.005
    torso_half = (0.03, max(0.04, hip_y - 0.015), (TORSO_TOP - TORSO_BOTTOM) / 2.0)
    torso_cz = (TORSO_TOP + TORSO_BOTTOM) / 2.0
    cam = np.array([0.0, -0.8, 0.0])
    cam_iso = np.array([0.45, -0.6, 0.25])

    assets = ""
    if foot == "wedge":
        assets = f'    <mesh name="wedge_foot" vertex="{fmt(_wedge_vertices(size, width, size))}"/>'
    elif foot == "cone":
        cv, cf = _cone_mesh(size, size, opts.resolution)  # elements one per triangle at the scene's resolution
        assets = f'    <mesh name="cone_foot" vertex="{fmt(cv)}" face="{" ".join(map(str, cf.ravel()))}"/>'

    def foot_geom(side: str) -> str:
        if foot == "cone":
            return (f'<geom name="{side}_foot" type="mesh" mesh="cone_foot" mass="{fmt(MASS["foot"])}" '
                    f'material="foot" {ROBOT_CONTACT}/>')
        if foot == "roller":
            return (f'<geom name="{side}_foot" type="cylinder" size="{fmt(size / 2, width / 2)}" '
                    f'zaxis="0 1 0" mass="{fmt(MASS["foot"])}" material="foot" {ROBOT_CONTACT}/>')
        return (f'<geom name="{side}_foot" type="mesh" mesh="wedge_foot" mass="{fmt(MASS["foot"])}" '
                f'material="foot" {ROBOT_CONTACT}/>')

    def joint(name: str) -> str:
        lo, hi = RANGES[name.split("_", 1)[1]]
        return (f'<joint name="{name}" type="hinge" axis="0 1 0" range="{fmt(lo, hi)}" '
                f'armature="{fmt(ARMATURE)}" damping="{fmt(DAMPING)}"/>')

    lines = [
        f'    <body name="torso" pos="{fmt(0, 0, z_hip)}">',
        '      <joint name="rootx" type="slide" axis="1 0 0"/>',
        '      <joint name="rootz" type="slide" axis="0 0 1"/>',
    ]
    if pitch_free:
        lines.append('      <joint name="rooty" type="hinge" axis="0 1 0"/>')
    lines += [
        f'      <camera name="track" mode="trackcom" pos="{fmt(cam)}" xyaxes="1 0 0 0 0 1"/>',
        f'      <camera name="track_iso" mode="trackcom" pos="{fmt(cam_iso)}" xyaxes="{look_at(cam_iso)}"/>',
        '      <light name="spot" mode="trackcom" pos="0 0 2" dir="0 0 -1" diffuse="0.5 0.5 0.5"/>',
        f'      <geom name="torso" type="box" pos="{fmt(0, 0, torso_cz)}" size="{fmt(torso_half)}" '
        f'mass="{fmt(MASS["torso"])}" material="body" {ROBOT_CONTACT}/>',
        '      <site name="imu" pos="0 0 0" size="0.01" rgba="1 0 0 0.5" group="4"/>',
    ]
    for side, sy in (("left", 1.0), ("right", -1.0)):
        i = "      "
        lines += [
            f'{i}<body name="{side}_thigh" pos="{fmt(0, sy * hip_y, 0)}">',
            f"{i}  {joint(side + '_hip')}",
            f'{i}  <geom name="{side}_thigh" type="box" pos="{fmt(0, 0, -THIGH / 2)}" '
            f'size="{fmt(0.015, 0.02, THIGH / 2)}" mass="{fmt(MASS["thigh"])}" material="limb" {ROBOT_CONTACT}/>',
            f'{i}  <body name="{side}_knee_link" pos="{fmt(0, 0, -THIGH)}">',
            f"{i}    {joint(side + '_knee_upper')}",
            f'{i}    <geom name="{side}_knee_link" type="box" pos="{fmt(0, 0, -KNEE_LINK / 2)}" '
            f'size="{fmt(0.012, 0.018, KNEE_LINK / 2)}" mass="{fmt(MASS["knee_link"])}" material="body" {ROBOT_CONTACT}/>',
            f'{i}    <body name="{side}_shank" pos="{fmt(0, 0, -KNEE_LINK)}">',
            f"{i}      {joint(side + '_knee_lower')}",
            f'{i}      <geom name="{side}_shank" type="box" pos="{fmt(0, 0, -SHANK / 2)}" '
            f'size="{fmt(0.015, 0.02, SHANK / 2)}" mass="{fmt(MASS["shank"])}" material="limb" {ROBOT_CONTACT}/>',
            f'{i}      <body name="{side}_foot" pos="{fmt(0, 0, -SHANK)}">',
            f"{i}        {joint(side + '_ankle')}",
            f"{i}        {foot_geom(side)}",
            f'{i}        <site name="{side}_sole" pos="{fmt(0, 0, -ankle_h)}" size="0.005" rgba="0 1 0 0.5" group="4"/>',
            f"{i}      </body>",
            f"{i}    </body>",
            f"{i}  </body>",
            f"{i}</body>",
        ]
    lines.append("    </body>")

    acts = []
    for side in ("left", "right"):
        for j in JOINTS:
            lo, hi = RANGES[j]
            name = f"{side}_{j}"
            acts.append(
                f'    <position name="{name}" joint="{name}" kp="{fmt(kp)}" kv="{fmt(kv)}" '
                f'ctrlrange="{fmt(lo, hi)}" forcerange="{fmt(-tl, tl)}"/>'
            )
    comment = (
        f"Planar biped ({'granular bed' if opts.sand else 'rigid floor'}), {foot} feet "
        f"{size * 100:g} cm (width {width * 100:g} cm), pitch {'free' if pitch_free else 'fixed'}.\n"
        f"Height {(HEIGHT - DEFAULT_FOOT_SIZE / 2 + size / 2) * 100:g} cm, mass {TOTAL_MASS:g} kg; "
        f"4 pitch servos per leg (hip, knee_upper, knee_lower, ankle; ankle > 0 = toe down):\n"
        f"position actuators kp {kp:g} N m/rad, kv {kv:g} N m s/rad, torque limit +-{tl:g} N m "
        "(HSR-5980SG class). See mjrft/models/biped.py."
    )
    return assemble(
        model="biped" + ("" if opts.sand else "_rigid"),
        comment=comment,
        opts=opts,
        robot="\n".join(lines),
        actuators="\n".join(acts),
        extent=1.0,
        center=(0.0, 0.0, 0.15),
        assets=assets,
    )


def biped_model(foot: str = "cone", foot_size: float = DEFAULT_FOOT_SIZE, pitch_free: bool = True,
                sand: bool = True, **kw) -> mujoco.MjModel:
    """Compiled :class:`mujoco.MjModel` of :func:`biped_xml`."""
    return mujoco.MjModel.from_xml_string(
        biped_xml(foot=foot, foot_size=foot_size, pitch_free=pitch_free, sand=sand, **kw)
    )

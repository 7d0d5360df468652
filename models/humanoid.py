"""HUBO-class humanoid (reference section 6): 1.2 m tall, 50 kg, free joint.

Frame: x forward, y left, z up; the root body ``pelvis`` carries the free
joint ``root``. Actuated joints (19, every one a ``<position>`` actuator
named after its joint):

* per leg (``left_`` / ``right_``): ``hip_yaw`` (z), ``hip_roll`` (x),
  ``hip_pitch`` (y), ``knee`` (y), ``ankle_pitch`` (y), ``ankle_roll`` (x);
* ``waist_yaw`` (z) between ``pelvis`` and ``torso``;
* per arm: ``shoulder_pitch`` (y), ``shoulder_roll`` (x), ``elbow`` (y).

Signs (right-hand rule about the joint axis): pitch > 0 swings a hanging
limb backward (so knee > 0 flexes the knee, ankle_pitch > 0 is toe down,
elbow < 0 flexes the elbow); roll > 0 moves a hanging limb toward +y (left).

Body chain of a leg: ``pelvis`` -> ``left_hip_yaw`` -> ``left_hip_roll`` ->
``left_thigh`` -> ``left_shank`` -> ``left_ankle`` -> ``left_foot``.

Dimensions at qpos 0 (standing straight, soles at z = 0): ankle axes 8 cm,
knees 38 cm, hip pitch/roll axes 68 cm, hip yaw 72 cm, pelvis centre 78 cm,
waist 85 cm, torso top 1.06 m, head top 1.20 m; shoulders at 1.04 m,
upper arm 22 cm, forearm + hand 22 cm; hips at y = +-9 cm, shoulders at +-19 cm.

Feet: a rectangular aluminium plate ``foot_length x foot_width`` (default
22.9 x 15.2 cm, 2 cm thick) with the ankle axes above the plate centre (a
heel-ward ankle makes the zero-control stance on sand tip backward).
Plates wider or narrower than 15.2 cm keep their inner edge where the default
plate has it (2.8 cm gap between the feet) and grow / shrink outward, so the
17.8 to 30.4 cm boards of the reference never overlap.
``foot_cutout=True`` builds the same outline with a central rectangular hole
of the same aspect ratio and half the area (a frame of 4 box strips: front
and rear strips full width, two side strips between them), i.e. half the
sole area of the solid foot.

Masses (kg, sum 50): pelvis 7, torso 13, head 2; per leg hip-yaw link 0.5,
hip-roll link 0.5, thigh 5, shank 3, ankle link 0.5, foot 1.5 (11 per leg);
per arm upper arm 2, forearm + hand 1. Foot mass does not change with the
foot size or the cut-out (distributed over the strips by area).

Actuators: kp (N m/rad) / kv (N m s/rad) / torque limit (N m)
hip_yaw 800/25/60, hip_roll 1500/50/150, hip_pitch 1500/50/150,
knee 1500/50/200, ankle_pitch 1000/35/120, ankle_roll 800/25/80,
waist_yaw 800/25/60, shoulder_pitch 300/10/40, shoulder_roll 300/10/40,
elbow 200/6/30 (stiff, like HUBO's high-gain joint position control: with
softer legs the servo chain plus the sand's compliance cannot hold the 1.2 m
inverted pendulum up);
joint armature 0.05 kg m^2 (harmonic-drive reflected inertia) and damping
0.5 N m s/rad; ctrlrange = joint range. Robot self-collision is off.

Granular bodies: ``left_foot right_foot``; element size 2 cm.
"""

from __future__ import annotations

import math

import mujoco

from .scene import (
    ROBOT_CONTACT,
    assemble,
    check_positive,
    fmt,
    look_at,
    pop_scene_options,
    reject_unknown,
)

HEIGHT = 1.2
TOTAL_MASS = 50.0
FOOT_LENGTH = 0.229
FOOT_WIDTH = 0.152
FOOT_THICKNESS = 0.02
ANKLE_HEIGHT = 0.08
PLATE_FORWARD = 0.0  # foot-plate centre ahead of the ankle axis (m); 0: ankle above the centre
SHANK = 0.30
THIGH = 0.30
HIP_Y = 0.09
SHOULDER_Y = 0.19
UPPER_ARM = 0.22
FOREARM = 0.22
CLEARANCE = 0.0005

MASS = {
    "pelvis": 7.0, "torso": 13.0, "head": 2.0,
    "hip_yaw": 0.5, "hip_roll": 0.5, "thigh": 5.0, "shank": 3.0, "ankle": 0.5, "foot": 1.5,
    "upper_arm": 2.0, "forearm": 1.0,
}

# joint: (axis, range, kp, kv, torque limit)
JOINTS = {
    "hip_yaw": ("0 0 1", (-0.8, 0.8), 800.0, 25.0, 60.0),
    "hip_roll": ("1 0 0", (-0.5, 0.5), 1500.0, 50.0, 150.0),
    "hip_pitch": ("0 1 0", (-1.8, 0.6), 1500.0, 50.0, 150.0),
    "knee": ("0 1 0", (-0.05, 2.5), 1500.0, 50.0, 200.0),
    "ankle_pitch": ("0 1 0", (-1.0, 1.0), 1000.0, 35.0, 120.0),
    "ankle_roll": ("1 0 0", (-0.5, 0.5), 800.0, 25.0, 80.0),
    "waist_yaw": ("0 0 1", (-1.5, 1.5), 800.0, 25.0, 60.0),
    "shoulder_pitch": ("0 1 0", (-3.0, 3.0), 300.0, 10.0, 40.0),
    "shoulder_roll": ("1 0 0", (-1.6, 1.6), 300.0, 10.0, 40.0),
    "elbow": ("0 1 0", (-2.5, 0.1), 200.0, 6.0, 30.0),
}
ARMATURE, DAMPING = 0.05, 0.5


def humanoid_leg_ik(x: float, y: float, z: float, thigh: float, shank: float) -> dict[str, float]:
    """Joint angles of one humanoid leg putting the ankle at (x, y, z) from the hip, foot flat.

    Chain: hip_roll (x) then hip_pitch, knee, ankle_pitch (y, in the rolled plane) then ankle_roll.
    Roll > 0 moves the foot toward +y; pitch > 0 swings the leg backward; knee > 0 flexes it.
    """
    roll = math.atan2(y, -z)
    zs = -math.hypot(y, z)
    r = math.hypot(x, zs)
    reach = (thigh + shank) * 0.9995
    if r > reach:  # fully stretched: keep the direction, stop at the reach
        x, zs, r = x * reach / r, zs * reach / r, reach
    # law of cosines for the knee
    c = (thigh ** 2 + shank ** 2 - r ** 2) / (2.0 * thigh * shank)
    knee = math.pi - math.acos(min(max(c, -1.0), 1.0))
    phi = math.atan2(-x, -zs)
    a = math.asin(min(max(shank * math.sin(knee) / max(r, 1e-9), -1.0), 1.0))
    hip = phi - a
    return {"hip_roll": roll, "hip_pitch": hip, "knee": knee, "ankle_pitch": -(hip + knee), "ankle_roll": -roll}


def foot_boxes(length: float, width: float, cutout: bool) -> list[tuple[tuple, tuple]]:
    """``[(center_xy, half_size_xy), ...]`` of the sole plate(s) in the plate frame."""
    if not cutout:
        return [((0.0, 0.0), (length / 2, width / 2))]
    s = 2 ** -0.5  # hole = outline scaled by 1/sqrt(2): half the area
    hl, hw = length * s / 2, width * s / 2  # hole half sizes
    end = (length / 2 - hl) / 2  # half thickness of the front/rear strips (along x)
    side = (width / 2 - hw) / 2  # half thickness of the side strips (along y)
    return [
        ((length / 2 - end, 0.0), (end, width / 2)),  # front
        ((-(length / 2 - end), 0.0), (end, width / 2)),  # rear
        ((0.0, width / 2 - side), (hl, side)),  # left
        ((0.0, -(width / 2 - side)), (hl, side)),  # right
    ]


def humanoid_xml(
    foot_length: float = FOOT_LENGTH,
    foot_width: float = FOOT_WIDTH,
    foot_cutout: bool = False,
    sand: bool = True,
    **kw,
) -> str:
    """MJCF text of the HUBO-class humanoid.

    ``foot_length`` / ``foot_width`` in m (defaults 0.229 / 0.152),
    ``foot_cutout`` (frame foot, half the area), ``sand`` (granular bed or
    rigid floor). ``**kw``: ``foot_thickness`` and the scene options of
    :func:`mjrft.models.scene.pop_scene_options`.
    """
    fl = check_positive("foot_length", foot_length)
    fw = check_positive("foot_width", foot_width)
    kw = dict(kw)
    ft = check_positive("foot_thickness", kw.pop("foot_thickness", FOOT_THICKNESS))
    if ft >= ANKLE_HEIGHT:
        raise ValueError(f"foot_thickness must be < {ANKLE_HEIGHT} m, got {ft!r}")
    opts = pop_scene_options(kw, resolution=0.02, bed_length=2.0, bed_width=1.0,
                             granular_bodies=["left_foot", "right_foot"], sand=sand)
    reject_unknown(kw, "humanoid_xml")

    pelvis_z = 0.78 + CLEARANCE + opts.surface
    rc = ROBOT_CONTACT

    def joint(name: str, key: str) -> str:
        axis, (lo, hi), *_ = JOINTS[key]
        return (f'<joint name="{name}" type="hinge" axis="{axis}" range="{fmt(lo, hi)}" '
                f'armature="{fmt(ARMATURE)}" damping="{fmt(DAMPING)}"/>')

    boxes = foot_boxes(fl, fw, foot_cutout)
    areas = [4 * h[0] * h[1] for _, h in boxes]

    def foot_geoms(side: str, ind: str) -> list[str]:
        out = []
        zc = -ANKLE_HEIGHT + ft / 2
        # keep the plate's inner edge where the default foot has it (wide boards grow outward)
        dy = (fw - FOOT_WIDTH) / 2 * (1.0 if side == "left" else -1.0)
        for i, ((cx, cy), (hx, hy)) in enumerate(boxes):
            cy += dy
            name = f"{side}_foot" if len(boxes) == 1 else f"{side}_foot_{('front', 'rear', 'left', 'right')[i]}"
            m = MASS["foot"] * areas[i] / sum(areas)
            out.append(f'{ind}<geom name="{name}" type="box" pos="{fmt(cx + PLATE_FORWARD, cy, zc)}" '
                       f'size="{fmt(hx, hy, ft / 2)}" mass="{fmt(m)}" material="foot" {rc}/>')
        return out

    cam = (1.6, -2.2, 0.6)
    L = [
        f'    <body name="pelvis" pos="{fmt(0, 0, pelvis_z)}">',
        '      <freejoint name="root"/>',
        f'      <camera name="track" mode="trackcom" pos="{fmt(cam)}" xyaxes="{look_at(cam)}"/>',
        '      <camera name="side" mode="trackcom" pos="0 -3 0" xyaxes="1 0 0 0 0 1"/>',
        '      <light name="spot" mode="trackcom" pos="0 0 4" dir="0 0 -1" diffuse="0.5 0.5 0.5"/>',
        f'      <geom name="pelvis" type="box" size="0.08 0.13 0.05" mass="{fmt(MASS["pelvis"])}" material="body" {rc}/>',
        '      <site name="imu" pos="0 0 0" size="0.02" rgba="1 0 0 0.5" group="4"/>',
        '      <body name="torso" pos="0 0 0.07">',
        f"        {joint('waist_yaw', 'waist_yaw')}",
        f'        <geom name="torso" type="box" pos="0 0 0.105" size="0.09 0.15 0.105" mass="{fmt(MASS["torso"])}" material="body" {rc}/>',
        '        <body name="head" pos="0 0 0.28">',
        f'          <geom name="head" type="box" size="0.07 0.065 0.07" mass="{fmt(MASS["head"])}" material="body" {rc}/>',
        "        </body>",
    ]
    for side, s in (("left", 1.0), ("right", -1.0)):
        i = "        "
        L += [
            f'{i}<body name="{side}_upper_arm" pos="{fmt(0, s * SHOULDER_Y, 0.19)}">',
            f"{i}  {joint(side + '_shoulder_pitch', 'shoulder_pitch')}",
            f"{i}  {joint(side + '_shoulder_roll', 'shoulder_roll')}",
            f'{i}  <geom name="{side}_upper_arm" type="capsule" fromto="0 0 0 0 0 {fmt(-UPPER_ARM)}" size="0.04" '
            f'mass="{fmt(MASS["upper_arm"])}" material="limb" {rc}/>',
            f'{i}  <body name="{side}_forearm" pos="{fmt(0, 0, -UPPER_ARM)}">',
            f"{i}    {joint(side + '_elbow', 'elbow')}",
            f'{i}    <geom name="{side}_forearm" type="capsule" fromto="0 0 0 0 0 {fmt(-FOREARM + 0.035)}" size="0.035" '
            f'mass="{fmt(MASS["forearm"])}" material="limb" {rc}/>',
            f"{i}  </body>",
            f"{i}</body>",
        ]
    L.append("      </body>")
    for side, s in (("left", 1.0), ("right", -1.0)):
        i = "      "
        L += [
            f'{i}<body name="{side}_hip_yaw" pos="{fmt(0, s * HIP_Y, -0.06)}">',
            f"{i}  {joint(side + '_hip_yaw', 'hip_yaw')}",
            f'{i}  <geom name="{side}_hip_yaw" type="cylinder" fromto="0 0 0.01 0 0 -0.03" size="0.04" '
            f'mass="{fmt(MASS["hip_yaw"])}" material="body" {rc}/>',
            f'{i}  <body name="{side}_hip_roll" pos="0 0 -0.04">',
            f"{i}    {joint(side + '_hip_roll', 'hip_roll')}",
            f'{i}    <geom name="{side}_hip_roll" type="cylinder" fromto="-0.05 0 0 0.05 0 0" size="0.035" '
            f'mass="{fmt(MASS["hip_roll"])}" material="body" {rc}/>',
            f'{i}    <body name="{side}_thigh" pos="0 0 0">',
            f"{i}      {joint(side + '_hip_pitch', 'hip_pitch')}",
            f'{i}      <geom name="{side}_thigh" type="capsule" fromto="0 0 -0.03 0 0 {fmt(-THIGH + 0.03)}" size="0.055" '
            f'mass="{fmt(MASS["thigh"])}" material="limb" {rc}/>',
            f'{i}      <body name="{side}_shank" pos="{fmt(0, 0, -THIGH)}">',
            f"{i}        {joint(side + '_knee', 'knee')}",
            f'{i}        <geom name="{side}_shank" type="capsule" fromto="0 0 -0.03 0 0 {fmt(-SHANK + 0.045)}" size="0.045" '
            f'mass="{fmt(MASS["shank"])}" material="limb" {rc}/>',
            f'{i}        <body name="{side}_ankle" pos="{fmt(0, 0, -SHANK)}">',
            f"{i}          {joint(side + '_ankle_pitch', 'ankle_pitch')}",
            f'{i}          <geom name="{side}_ankle" type="cylinder" fromto="0 -0.03 0 0 0.03 0" size="0.03" '
            f'mass="{fmt(MASS["ankle"])}" material="body" {rc}/>',
            f'{i}          <body name="{side}_foot" pos="0 0 0">',
            f"{i}            {joint(side + '_ankle_roll', 'ankle_roll')}",
            *foot_geoms(side, i + "            "),
            f'{i}            <site name="{side}_sole" pos="{fmt(PLATE_FORWARD, s * (fw - FOOT_WIDTH) / 2, -ANKLE_HEIGHT)}" size="0.01" rgba="0 1 0 0.5" group="4"/>',
            f"{i}          </body>",
            f"{i}        </body>",
            f"{i}      </body>",
            f"{i}    </body>",
            f"{i}  </body>",
            f"{i}</body>",
        ]
    L.append("    </body>")

    order = ["waist_yaw"]
    for side in ("left", "right"):
        order += [f"{side}_{j}" for j in ("hip_yaw", "hip_roll", "hip_pitch", "knee", "ankle_pitch", "ankle_roll")]
    for side in ("left", "right"):
        order += [f"{side}_{j}" for j in ("shoulder_pitch", "shoulder_roll", "elbow")]
    acts = []
    for name in order:
        key = name.split("_", 1)[1] if name.startswith(("left_", "right_")) else name
        _, (lo, hi), kp, kv, tl = JOINTS[key]
        acts.append(f'    <position name="{name}" joint="{name}" kp="{fmt(kp)}" kv="{fmt(kv)}" '
                    f'ctrlrange="{fmt(lo, hi)}" forcerange="{fmt(-tl, tl)}"/>')

    comment = (
        f"HUBO-class humanoid ({'granular bed' if opts.sand else 'rigid floor'}): 1.2 m, 50 kg, "
        f"19 position-servo DOF + free joint.\nFeet {fl * 100:g} x {fw * 100:g} cm"
        f"{' with central cut-out (half area)' if foot_cutout else ''}. See mjrft/models/humanoid.py."
    )
    return assemble(
        model="humanoid" + ("" if opts.sand else "_rigid"),
        comment=comment,
        opts=opts,
        robot="\n".join(L),
        actuators="\n".join(acts),
        extent=3.0,
        center=(0.0, 0.0, 0.6),
    )


def humanoid_model(foot_length: float = FOOT_LENGTH, foot_width: float = FOOT_WIDTH,
                   foot_cutout: bool = False, sand: bool = True, **kw) -> mujoco.MjModel:
    """Compiled :class:`mujoco.MjModel` of :func:`humanoid_xml`."""
    return mujoco.MjModel.from_xml_string(
        humanoid_xml(foot_length=foot_length, foot_width=foot_width, foot_cutout=foot_cutout, sand=sand, **kw)
    )

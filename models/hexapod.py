"""Hexapod models: RHex-class (Li, Zhang & Goldman 2013) and a small DynaRoACH-like variant.

Frame: x forward, y left, z up. The torso is a box; six legs hang from hips
on the sides at front / middle / rear; each hip is a 1-DOF hinge about the
body's lateral (y) axis. Positive hip angle rotates a hanging leg backward
(the tip moves toward -x), i.e. the forward-walking direction for a leg
rotating in stance is *positive* hip angle. Legs hang straight down at qpos 0
and are curved legs built with :mod:`mjrft.geometry.curved_leg`, whose module
docstring defines the sign of ``curvature``: ``k > 0`` is Li 2013's C-leg
(bowing toward -x when hanging, so its convex side leads through the grains
in stance, the RHex leg), ``k < 0`` the reversed C-leg (concave side leading).

Names: body ``torso``; leg bodies ``leg_{lf,lm,lr,rf,rm,rr}`` (l/r = left/right,
f/m/r = front/middle/rear); hinge joints ``hip_{...}``; position actuators
named after their joints. Alternating tripods: A = lf, rm, lr and
B = rf, lm, rr (also stored as ``<custom>`` texts ``robot:tripod_a`` / ``_b``).

Variant ``"rhex"`` (RHex-class, reference section 6):

* torso box 13 cm long x 4.9 cm wide x 3.7 cm tall, hips at x = +5, 0, -5 cm at the torso's
  mid-height (1.85 cm above the belly), at y = +-3.15 cm (just outside the body, 2 mm clearance).
  Li 2013 gives the 13 cm length, the 150 g mass, the pitch inertia and the centre of mass at the
  geometric centre, not the width, height or hip height; those are RHex's (Saranli, Buehler &
  Koditschek 2001; RHex 0.0, U. Michigan's RHex platform page: body 53 x 20 x 15 cm, 17.5 cm legs,
  10 cm ground clearance, so the hip axles sit 7.5 cm above the belly, at the body's mid-height),
  scaled by the body length 13 / 53: 20 -> 4.9 cm wide, 15 -> 3.7 cm tall, hips at mid-height
  (the scaled 17.5 cm leg, 4.3 cm, is Li's 4.1 cm leg within 5 %). The belly is therefore 13 x 4.9 cm
  where Li's robot, stripped of its shell, had 13 x 2 cm: a 2 cm wide torso on the same hips rolls over
  under the open-loop tripod (the RHex frame's width carries the roll);
* legs: chord 2R' = 4.1 cm, width 1.0 cm, thickness 0.3 cm, 8 box segments,
  2 g each; curvature in [-1/R', 1/R'] (R' = 2.05 cm), default 1/R' (the
  semicircular C-leg);
* total mass 150 g (torso 138 g + 6 x 2 g); total pitch inertia about the
  robot CoM at qpos 0 = 2.08e3 g cm^2 = 2.08e-4 kg m^2, set through the
  torso's ``<inertial>`` (ixx from the box, iyy solved so the whole robot has
  the reference pitch inertia, izz = min(box value, ixx + iyy));
* hip servos: ``<position>`` kp = 2 N m/rad, kv = 0.02 N m s/rad, torque
  limit (forcerange) +-0.3 N m (the body weighs 1.47 N: one leg at full
  4.1 cm lever needs 0.06 N m), joint armature 1e-5 kg m^2 (motor + gearbox),
  damping 1e-4 N m s/rad. Hips rotate continuously (RHex legs recirculate),
  so joints are unlimited and the actuators have no ``ctrlrange``.
* granular bodies (``mjrft:bodies``): torso and the six legs; element size
  5 mm.

Variant ``"small"`` (DynaRoACH-like): torso 10 x 4.5 x 1.5 cm, hips at
x = +4, 0, -4 cm, y = +-2.8 cm; C-legs of radius 1 cm (chord 2 cm, k = 1/0.01
semicircle; curvature range [-100, 100] 1/m), width 0.7 cm, thickness 0.2 cm,
0.4 g each; total 25 g; torso inertia of a uniform box (no reference pitch
inertia); servos kp = 0.2 N m/rad, kv = 1e-3, limit +-0.05 N m, armature 1e-6.
Its sand scene turns on the dry laws' inertial regime (``mjrft:inertial``,
:mod:`mjrft.laws.inertial`): a 25 g robot striding at up to 12 Hz drives its
legs into the grains above the critical speed (Zhang et al., DynaRoACH paper);
``inertial=False`` turns it off. The RHex-class variant leaves it off.

The torso starts so that the lowest leg point is 0.5 mm above z = 0 (the
sand surface or the rigid floor), i.e. the belly of the RHex-class robot is 2.3 cm up
(the leg chord below the hips, less the hips' height above the belly; the small one's, with its hips in
the belly plane, one leg chord).

Root joint: a free joint ``root`` (default), or with ``planar=True`` the body
held in the sagittal (x-z) plane as Li 2013's robot simulation held it
(suppl., "Robot simulation": fore-aft and dorso-ventral translation and
pitch): slide ``rootx`` (x), slide ``rootz`` (z, measured from the initial
height), hinge ``rooty`` (pitch about y, positive nose down), in that qpos
order; the legs' hips stay hinges about y, so every leg moves in a plane
parallel to x-z. Left and right legs keep their lateral offsets (their
granular forces' roll and yaw moments are taken by the constraint).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from mjrft.errors import check_finite
from mjrft.geometry.curved_leg import curved_leg_boxes, curved_leg_xml

from .scene import (
    ROBOT_CONTACT,
    assemble,
    box_inertia,
    check_positive,
    fmt,
    look_at,
    pop_scene_options,
    reject_unknown,
)

LEG_NAMES = ("lf", "lm", "lr", "rf", "rm", "rr")
TRIPOD_A = ("lf", "rm", "lr")
TRIPOD_B = ("rf", "lm", "rr")
CLEARANCE = 0.0005  # m between the lowest leg point and z = 0 at qpos 0


@dataclass(frozen=True)
class HexapodVariant:
    body_length: float
    body_width: float
    body_height: float
    total_mass: float
    leg_chord: float
    leg_width: float
    leg_thickness: float
    leg_mass: float
    hip_x: float  # front hip at +hip_x, middle at 0, rear at -hip_x
    hip_gap: float  # lateral clearance between body side and leg
    hip_height: float  # hip axles above the belly (the torso's bottom face)
    pitch_inertia: float | None  # whole-robot pitch inertia about the CoM (kg m^2)
    kp: float
    kv: float
    torque_limit: float
    armature: float
    damping: float
    resolution: float
    default_curvature: float


VARIANTS: dict[str, HexapodVariant] = {
    "rhex": HexapodVariant(
        body_length=0.13, body_width=0.049, body_height=0.037, total_mass=0.150,
        leg_chord=0.041, leg_width=0.010, leg_thickness=0.003, leg_mass=0.002,
        hip_x=0.05, hip_gap=0.002, hip_height=0.0185, pitch_inertia=2.08e-4,
        kp=2.0, kv=0.02, torque_limit=0.3, armature=1e-5, damping=1e-4,
        resolution=0.005, default_curvature=1.0 / 0.0205,
    ),
    "small": HexapodVariant(
        body_length=0.10, body_width=0.045, body_height=0.015, total_mass=0.025,
        leg_chord=0.02, leg_width=0.007, leg_thickness=0.002, leg_mass=0.0004,
        hip_x=0.04, hip_gap=0.0015, hip_height=0.0, pitch_inertia=None,
        kp=0.2, kv=1e-3, torque_limit=0.05, armature=1e-6, damping=1e-5,
        resolution=0.005, default_curvature=1.0 / 0.01,
    ),
}

#: R' (half the leg chord) per variant; curvature range is [-1/R', 1/R'].
R_PRIME = {name: v.leg_chord / 2.0 for name, v in VARIANTS.items()}


def _hip_positions(v: HexapodVariant) -> dict[str, tuple[float, float, float]]:
    y = v.body_width / 2.0 + v.hip_gap + v.leg_width / 2.0
    z = -v.body_height / 2.0 + v.hip_height
    xs = {"f": v.hip_x, "m": 0.0, "r": -v.hip_x}
    return {name: (xs[name[1]], y if name[0] == "l" else -y, z) for name in LEG_NAMES}


def lowest_leg_point(chord, curvature, width, thickness, n_segments) -> float:
    """Height (m, <= 0) of the lowest point of a curved leg's boxes (:func:`mjrft.geometry.curved_leg_boxes`, with
    their thickness) below its hip, the leg hanging straight down; the boxes turn about y only, so their corners'
    y does not change their height."""
    zmin = 0.0
    for b in curved_leg_boxes(chord, curvature, width, thickness, n_segments):
        R = np.zeros(9)
        mujoco.mju_quat2Mat(R, np.asarray(b["quat"], float))
        R = R.reshape(3, 3)
        for sx in (-1, 1):
            for sz in (-1, 1):
                corner = b["pos"] + R @ (np.array([sx, 0.0, sz]) * b["size"])
                zmin = min(zmin, corner[2])
    return zmin


def pitch_inertia(model: mujoco.MjModel, data: mujoco.MjData | None = None) -> float:
    """Whole-robot moment of inertia about the world y axis through the CoM (kg m^2)."""
    if data is None:
        data = mujoco.MjData(model)
        mujoco.mj_forward(model, data)
    masses = model.body_mass[1:]
    com = (masses[:, None] * data.xipos[1:]).sum(0) / masses.sum()
    total = 0.0
    for b in range(1, model.nbody):
        R = data.ximat[b].reshape(3, 3)
        Iw = R @ np.diag(model.body_inertia[b]) @ R.T
        d = data.xipos[b] - com
        total += Iw[1, 1] + model.body_mass[b] * (d[0] ** 2 + d[2] ** 2)
    return float(total)


def _leg_kind(k: float) -> str:
    """Li 2013's name of a leg of signed curvature ``k`` (convention: :mod:`mjrft.geometry.curved_leg`)."""
    if k > 0:
        return "C-leg, convex side leading in stance"
    return "reversed C-leg, concave side leading in stance" if k < 0 else "flat leg"


def _build(v, variant, curvature, n_segments, opts, torso_inertia, kp, kv, torque_limit, planar=False) -> str:
    k = curvature
    leg_z_min = lowest_leg_point(v.leg_chord, k, v.leg_width, v.leg_thickness, n_segments)
    lowest = min(-v.body_height / 2.0, -v.body_height / 2.0 + v.hip_height + leg_z_min)  # torso frame
    z0 = -lowest + CLEARANCE + opts.surface
    torso_mass = v.total_mass - 6 * v.leg_mass
    half = (v.body_length / 2.0, v.body_width / 2.0, v.body_height / 2.0)
    cam_pos = np.array([0.25, -0.35, 0.18]) * v.body_length / 0.13
    ind = "    "
    lines = [
        f'{ind}<body name="torso" pos="{fmt(0, 0, z0)}">',
        *([f'{ind}  <joint name="rootx" type="slide" axis="1 0 0"/>',
           f'{ind}  <joint name="rootz" type="slide" axis="0 0 1"/>',
           f'{ind}  <joint name="rooty" type="hinge" axis="0 1 0"/>'] if planar
          else [f'{ind}  <freejoint name="root"/>']),
        f'{ind}  <camera name="track" mode="trackcom" pos="{fmt(cam_pos)}" xyaxes="{look_at(cam_pos)}"/>',
        f'{ind}  <camera name="side" mode="trackcom" pos="{fmt(0, -4 * v.body_length, 0)}" xyaxes="1 0 0 0 0 1"/>',
        f'{ind}  <light name="spot" mode="trackcom" pos="{fmt(0, 0, 8 * v.body_length)}" dir="0 0 -1" diffuse="0.5 0.5 0.5"/>',
        f'{ind}  <inertial pos="0 0 0" mass="{fmt(torso_mass)}" diaginertia="{fmt(torso_inertia)}"/>',
        f'{ind}  <geom name="torso" type="box" size="{fmt(half)}" material="body" {ROBOT_CONTACT}/>',
        f'{ind}  <site name="imu" pos="0 0 0" size="{fmt(v.body_height / 4)}" rgba="1 0 0 0.5" group="4"/>',
    ]
    for name, pos in _hip_positions(v).items():
        legxml = curved_leg_xml(
            v.leg_chord, k, v.leg_width, v.leg_thickness, n_segments,
            name_prefix=f"leg_{name}", mass=v.leg_mass / n_segments, material="limb",
            contype=1, conaffinity=0,
        )
        legxml = "\n".join(f"{ind}    {ln}" for ln in legxml.splitlines())
        lines += [
            f'{ind}  <body name="leg_{name}" pos="{fmt(pos)}">',
            f'{ind}    <joint name="hip_{name}" type="hinge" axis="0 1 0" limited="false" '
            f'armature="{fmt(v.armature)}" damping="{fmt(v.damping)}"/>',
            legxml,
            f"{ind}  </body>",
        ]
    lines.append(f"{ind}</body>")
    robot = "\n".join(lines)

    actuators = "\n".join(
        f'    <position name="hip_{n}" joint="hip_{n}" kp="{fmt(kp)}" kv="{fmt(kv)}" '
        f'ctrllimited="false" forcelimited="true" forcerange="{fmt(-torque_limit, torque_limit)}"/>'
        for n in LEG_NAMES
    )
    custom_extra = "\n".join(
        [
            f'    <text name="robot:tripod_a" data="{" ".join("leg_" + n for n in TRIPOD_A)}"/>',
            f'    <text name="robot:tripod_b" data="{" ".join("leg_" + n for n in TRIPOD_B)}"/>',
            f'    <numeric name="robot:curvature" data="{fmt(k)}"/>',
        ]
    )
    comment = (
        f"Hexapod, variant '{variant}' ({'granular bed' if opts.sand else 'rigid floor'}).\n"
        f"Body {v.body_length * 100:g} x {v.body_width * 100:g} x {v.body_height * 100:g} cm, "
        f"total mass {v.total_mass * 1000:g} g; legs chord {v.leg_chord * 100:g} cm, "
        f"width {v.leg_width * 100:g} cm, thickness {v.leg_thickness * 100:g} cm, "
        f"curvature {k:.6g} 1/m ({_leg_kind(k)}; R' = {v.leg_chord * 50:g} cm, range +-{2 / v.leg_chord:.6g}).\n"
        f"Hip position servos: kp {kp:g} N m/rad, kv {kv:g} N m s/rad, torque limit +-{torque_limit:g} N m.\n"
        "Tripod A = leg_lf leg_rm leg_lr, tripod B = leg_rf leg_lm leg_rr. See mjrft/models/hexapod.py."
        + ("\nPlanar: torso held in the x-z plane (rootx, rootz slides, rooty pitch hinge)." if planar else "")
    )
    return assemble(
        model=f"hexapod_{variant}" + ("" if opts.sand else "_rigid") + ("_planar" if planar else ""),
        comment=comment,
        opts=opts,
        robot=robot,
        actuators=actuators,
        extent=6 * v.body_length,
        center=(0.0, 0.0, z0 / 2),
        custom_extra=custom_extra,
    )


def hexapod_xml(curvature: float | None = None, variant: str = "rhex", sand: bool = True, **kw) -> str:
    """MJCF text of the hexapod.

    Parameters
    ----------
    curvature:
        Signed leg curvature 1/r in 1/m, within [-1/R', 1/R'] (R' = chord/2):
        positive = C-leg (convex side leading in stance), negative = reversed
        C-leg (sign convention: :mod:`mjrft.geometry.curved_leg`); default: the
        variant's semicircular C-leg 1/R' (48.78 for ``"rhex"``, 100 for ``"small"``).
    variant:
        ``"rhex"`` (RHex-class, 150 g) or ``"small"`` (DynaRoACH-like, 25 g).
    sand:
        Granular bed scene (True) or rigid floor (False); see :mod:`.scene`.
    **kw:
        ``n_segments`` (leg boxes, default 8), ``kp``, ``kv``, ``torque_limit``
        (override the servo values), ``planar`` (default False: a free joint;
        True: the torso held in the sagittal x-z plane, joints ``rootx``,
        ``rootz``, ``rooty``, see the module docstring), scene options ``bed_depth``, ``bed_length``,
        ``bed_width``, ``medium``, ``law``, ``resolution``, ``surface``,
        ``granular_bodies``.
    """
    if variant not in VARIANTS:
        raise ValueError(f"unknown hexapod variant {variant!r}; valid: {', '.join(VARIANTS)}")
    v = VARIANTS[variant]
    k = check_finite("curvature", v.default_curvature if curvature is None else curvature)
    kmax = 2.0 / v.leg_chord
    if abs(k) > kmax * (1 + 1e-9):
        raise ValueError(
            f"curvature {curvature!r} 1/m out of range for the {variant!r} hexapod: "
            f"valid range [-1/R', 1/R'] = [{-kmax:.6g}, {kmax:.6g}] 1/m (R' = {v.leg_chord / 2:g} m)"
        )
    k = max(-kmax, min(kmax, k))
    kw = dict(kw)
    kw.setdefault("inertial", variant == "small")  # the small robot's scene models the inertial regime
    n_segments = kw.pop("n_segments", 8)
    kp = check_positive("kp", kw.pop("kp", v.kp))
    kv = check_positive("kv", kw.pop("kv", v.kv))
    torque_limit = check_positive("torque_limit", kw.pop("torque_limit", v.torque_limit))
    planar = kw.pop("planar", False)
    if not isinstance(planar, (bool, np.bool_)):
        raise ValueError(f"planar must be True or False, got {planar!r}")
    opts = pop_scene_options(
        kw, resolution=v.resolution, bed_length=2.0, bed_width=1.0,
        granular_bodies=["torso"] + [f"leg_{n}" for n in LEG_NAMES], sand=sand,
    )
    reject_unknown(kw, "hexapod_xml")

    torso_mass = v.total_mass - 6 * v.leg_mass
    inertia = box_inertia(torso_mass, (v.body_length / 2, v.body_width / 2, v.body_height / 2))
    args = (v, variant, k, n_segments, opts)
    if v.pitch_inertia is not None:
        # Solve the torso's iyy so the whole robot has the reference pitch inertia.
        xml = _build(*args, inertia, kp, kv, torque_limit, planar)
        total = pitch_inertia(mujoco.MjModel.from_xml_string(xml))
        iyy = inertia[1] + (v.pitch_inertia - total)
        if iyy <= 0:
            raise ValueError("pitch inertia target too small for the leg masses")
        inertia = np.array([inertia[0], iyy, min(inertia[2], inertia[0] + iyy)])
    return _build(*args, inertia, kp, kv, torque_limit, planar)


def hexapod_model(curvature: float | None = None, variant: str = "rhex", sand: bool = True, **kw) -> mujoco.MjModel:
    """Compiled :class:`mujoco.MjModel` of :func:`hexapod_xml`."""
    return mujoco.MjModel.from_xml_string(hexapod_xml(curvature, variant=variant, sand=sand, **kw))

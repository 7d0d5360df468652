"""DynaRoACH (Zhang et al., "Ground fluidization promotes rapid running of a lightweight robot"): the 25 g
hexapod with swing-and-lift legs.

What the paper states (Zhang, Qian, Li, Masarati, Hoover, Birkmeyer, Pullin, Fearing & Goldman, IJRR 2013):

* 10 cm long, 25 g; six C-shaped legs of radius 1 cm (sec. 2.1.1), 0.7 cm wide (fig. 7 caption:
  "original foot width of 0.7 cm"), projected area ~1.4 cm^2 each (sec. 3.2; a 2 cm chord x 0.7 cm);
  standing body height 1.2 cm (sec. 3.1.1, "38% of the standing body height 1.2 cm").
* Alternating tripod; "all six legs are driven by a single motor through body linkages" (sec. 2.1.1).
* "During a cycle, each leg rotated backward about the hip (retraction), lifted-up sideways, and swung
  forward (protraction)" (sec. 2.1.4, fig. 1B); the stride period T is "the time between the start of two
  consecutive retraction phases".
* The paper's own multibody model (sec. 2.2.2): one box body, six C-legs and six linking plates; "the
  joints between the link plates and c-shaped legs allowed front-back swing of the legs while the
  plate-body joints allowed sideways lifting of the legs".
* "The DynaRoACH robot instead uses protraction-retraction leg trajectories, which result in stance phases
  that begin during protraction phases of the legs" (sec. 3.1.1), unlike SandBot's recirculating legs.

This model is that multibody model: per leg a *lift* hinge between the torso and a link plate (about the
body's long axis x, positive lifts the leg's tip up and outward) and a *swing* hinge between the plate and
the C-leg (about the plate's y axis; positive swings the tip backward, the sign convention of
:mod:`mjrft.geometry.curved_leg`, so the C-leg's convex side leads in retraction as in the hexapod).

Choices where the paper is silent (its leg angles are in fig. 1B, E, which the text copy lost):

* The motor turns at constant speed (its PID holds the stride frequency, sec. 2.1.1) and the linkage
  is a crank, so both joint angles are sinusoids of the crank phase ``phi = 2 pi f t`` (tripod B at
  ``phi + pi``, the alternating tripod):

      swing(phi) = -A cos(phi)               retraction (tip moving back) for phi in (0, pi)
      lift(phi)  = B (1 - sin(phi)) / 2      lowest at mid-retraction, highest at mid-protraction

  so the tip goes round one loop per period: down and back (retraction), up (the sideways lift at the
  end of retraction), forward while lifted (protraction), and down again before protraction ends, which
  is where stance begins when the legs meet the ground ("stance phases that begin during protraction
  phases"). ``phi = 0``, the front end of the swing, is the start of retraction (the paper's T).
* Swing amplitude ``A = 30 deg`` (a 60 deg fore-aft sweep). The paper gives the stride at low frequency,
  "near 2r, the maximal value of the stride length for rotary walking (where r is the leg radius)"
  (sec. 4.2). In rotary walking the body pivots about the centre of the buried C-leg's curve (Li et al.
  2009; robophysics thesis sec. 1.4.1), radius r from the hip, so a sweep of +-A advances the body
  ``2 r sin A`` per step and ``4 r sin A`` per period (two tripods): the paper's 2r at A = 30 deg.
  This is geometry on the paper's statement, not a fit to a simulated speed.
* Lift range ``B = 60 deg``: at lift 0 the leg hangs straight down, and at mid-protraction the sideways
  lift raises its tip by ``2 r (1 - cos B)`` = one leg radius (1 cm). Not in the text.
* Hips: the lift hinge sits on the torso's side at the CoM's height. The paper's heights are above the
  granular surface ("1.86 cm above the surface", sec. 3.1.2), where the robot stands on legs sunk "only a
  few particle diameters" (sec. 2.1.2): with the hips at the CoM and 2 cm legs, a standing height of 1.2 cm
  (sec. 3.1.1) is legs sunk 0.8 cm, 2.7 grain diameters. mjrft's own static sinkage then gives the
  standing height (case ``dynaroach_legs`` compares it with 1.2 cm; on a rigid floor the robot stands 2 cm
  high). The torso (10 x 4.5 x 1.5 cm box) and the hips' fore-aft places (+-4 cm) are the small hexapod's
  (:mod:`mjrft.models.hexapod`, ``variant="small"``); the link plates weigh 0.05 g each, the legs 0.4 g
  (0.2 cm thick), the torso the rest of 25 g.
* The servos stand in for the rigid linkage: position servos kp 0.2 N m/rad, kv 1e-3 N m s/rad, limit
  +-0.05 N m (the paper's peak hip torque at 12 Hz is 10 mN m, sec. 3.2) on both joints, armature
  1e-6 kg m^2; :func:`dynaroach_ctrl` feeds the targets' speed forward (``ctrl = q* + kv/kp dq*/dt``:
  the servo force ``kp (q* - q) + kv (dq* - dq)``), so the legs follow the crank without the lag a
  pure position target would have at 12 Hz.

Names: body ``torso``; plates ``plate_{n}``; legs ``leg_{n}`` (n in lf, lm, lr, rf, rm, rr); joints and
position actuators ``lift_{n}`` and ``swing_{n}``, in that order per leg; tripods as the hexapod's
(A = lf, rm, lr; B = rf, lm, rr; also ``<custom>`` texts ``robot:tripod_a`` / ``_b``). Its sand scene turns
on the dry laws' inertial regime like the small hexapod's (``inertial=False`` turns it off).
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from mjrft.geometry.curved_leg import curved_leg_xml

from .hexapod import CLEARANCE, LEG_NAMES, TRIPOD_A, TRIPOD_B, lowest_leg_point
from .scene import ROBOT_CONTACT, assemble, box_inertia, fmt, look_at, pop_scene_options, reject_unknown

BODY = (0.10, 0.045, 0.015)  # m: length (paper), width and thickness (the small hexapod's choice)
MASS = 0.025  # kg (paper)
LEG_RADIUS = 0.01  # m (paper)
LEG_CHORD = 2 * LEG_RADIUS  # semicircular C-leg: hip and tip at the ends of its diameter
LEG_WIDTH = 0.007  # m (paper, fig. 7 caption)
LEG_THICKNESS = 0.002  # m (choice)
LEG_MASS = 0.0004  # kg (choice)
PLATE_MASS = 0.00005  # kg (choice)
HIP_X = 0.04  # m, front and rear hips (choice, the small hexapod's)
HIP_GAP = 0.0015  # m between the torso's side and the lift hinge (choice)
HIP_Z = 0.0  # m above the CoM: the lift hinges at the CoM's height (module docstring)
SWING_AMPLITUDE = math.radians(30.0)  # A (module docstring)
LIFT_RANGE = math.radians(60.0)  # B (module docstring)
KP, KV, TORQUE_LIMIT, ARMATURE, DAMPING = 0.2, 1e-3, 0.05, 1e-6, 1e-5
RESOLUTION = 0.005


def leg_angles(phase, swing=SWING_AMPLITUDE, lift=LIFT_RANGE, lift_phase=0.0):
    """(swing, lift, d swing / d phase, d lift / d phase) of a leg at crank ``phase`` (rad; 0 = start of
    retraction): the sinusoids of the module docstring. ``lift_phase`` delays the lift against the swing (0:
    the model; pi/2 puts the lowest point at the end of retraction, a stance that begins while retracting, as a
    control). Works on arrays."""
    phase = np.asarray(phase, float) - lift_phase
    return (-swing * np.cos(phase + lift_phase), 0.5 * lift * (1.0 - np.sin(phase)),
            swing * np.sin(phase + lift_phase), -0.5 * lift * np.cos(phase))


def tripod_phase(model: mujoco.MjModel) -> np.ndarray:
    """Per actuator, its leg's phase offset: 0 for tripod A, pi for tripod B."""
    off = np.zeros(model.nu)
    a = {f"leg_{n}" for n in TRIPOD_A}
    for i in range(model.nu):
        body = model.jnt_bodyid[model.actuator_trnid[i, 0]]
        leg = body if mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, body).startswith("leg_") else None
        if leg is None:  # the lift joint is on the plate: its leg is the plate's child
            leg = next(b for b in range(model.nbody) if model.body_parentid[b] == body)
        off[i] = 0.0 if mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, leg) in a else math.pi
    return off


def dynaroach_ctrl(model: mujoco.MjModel, t: float, freq: float, offsets: np.ndarray | None = None,
                   swing: float = SWING_AMPLITUDE, lift: float = LIFT_RANGE, lift_phase: float = 0.0) -> np.ndarray:
    """Servo targets at time ``t`` for stride frequency ``freq`` (Hz): each joint's crank angle with its
    speed fed forward (``q* + kv/kp dq*/dt``, module docstring). ``offsets``: :func:`tripod_phase` (computed
    when None; pass it in a loop); ``swing``, ``lift``, ``lift_phase``: :func:`leg_angles`."""
    if offsets is None:
        offsets = tripod_phase(model)
    phase = 2 * math.pi * freq * t + offsets
    s, l, ds, dl = leg_angles(phase, swing, lift, lift_phase)
    is_lift = np.array([mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_ACTUATOR, i).startswith("lift_")
                        for i in range(model.nu)])
    q = np.where(is_lift, l, s)
    dq = np.where(is_lift, dl, ds) * 2 * math.pi * freq
    return q + model.actuator_gainprm[:, 0] ** -1 * (-model.actuator_biasprm[:, 2]) * dq


def _lowest_tip(curvature: float, n_segments: int) -> float:
    """Lowest point of a leg (with its thickness) below its hip at swing 0, lift 0 (hanging straight down)."""
    return lowest_leg_point(LEG_CHORD, curvature, LEG_WIDTH, LEG_THICKNESS, n_segments)


def dynaroach_xml(sand: bool = True, **kw) -> str:
    """MJCF text of DynaRoACH (module docstring).

    Keyword arguments: ``curvature`` (signed 1/m, default 1/r = 100, the C-leg; within +-100),
    ``n_segments`` (leg boxes, default 8), ``kp``, ``kv``, ``torque_limit`` (both joints' servos), and
    the scene options of :func:`mjrft.models.hexapod_xml` (``medium``, ``law``, ``resolution``,
    ``inertial`` (default True on sand), ``surface``, ...).
    """
    kw = dict(kw)
    kw.setdefault("inertial", bool(sand))
    k = float(kw.pop("curvature", 1.0 / LEG_RADIUS))
    if not math.isfinite(k) or abs(k) > 1.0 / LEG_RADIUS * (1 + 1e-9):
        raise ValueError(f"curvature {k!r} 1/m out of range for DynaRoACH's legs: valid range "
                         f"[-{1 / LEG_RADIUS:g}, {1 / LEG_RADIUS:g}] 1/m (leg radius {LEG_RADIUS:g} m)")
    k = max(-1.0 / LEG_RADIUS, min(1.0 / LEG_RADIUS, k))
    n_segments = kw.pop("n_segments", 8)
    kp, kv, limit = (float(kw.pop(name, val)) for name, val in (("kp", KP), ("kv", KV), ("torque_limit", TORQUE_LIMIT)))
    for name, val in (("kp", kp), ("kv", kv), ("torque_limit", limit)):
        if not (math.isfinite(val) and val > 0):
            raise ValueError(f"{name} must be a positive finite number, got {val!r}")
    opts = pop_scene_options(kw, resolution=RESOLUTION, bed_length=2.0, bed_width=1.0,
                             granular_bodies=["torso"] + [f"leg_{n}" for n in LEG_NAMES], sand=sand)
    reject_unknown(kw, "dynaroach_xml")

    half = tuple(s / 2 for s in BODY)
    z0 = -_lowest_tip(k, n_segments) - HIP_Z + CLEARANCE + opts.surface  # torso centre (the CoM)
    torso_mass = MASS - 6 * (LEG_MASS + PLATE_MASS)
    inertia = box_inertia(torso_mass, half)
    cam = np.array([0.2, -0.28, 0.14])
    ind = "    "
    lines = [
        f'{ind}<body name="torso" pos="{fmt(0, 0, z0)}">',
        f'{ind}  <freejoint name="root"/>',
        f'{ind}  <camera name="track" mode="trackcom" pos="{fmt(cam)}" xyaxes="{look_at(cam)}"/>',
        f'{ind}  <camera name="side" mode="trackcom" pos="{fmt(0, -0.4, 0)}" xyaxes="1 0 0 0 0 1"/>',
        f'{ind}  <inertial pos="0 0 0" mass="{fmt(torso_mass)}" diaginertia="{fmt(inertia)}"/>',
        f'{ind}  <geom name="torso" type="box" size="{fmt(half)}" material="body" {ROBOT_CONTACT}/>',
        f'{ind}  <site name="imu" pos="0 0 0" size="{fmt(BODY[2] / 4)}" rgba="1 0 0 0.5" group="4"/>',
    ]
    y_hip = BODY[1] / 2 + HIP_GAP
    for name in LEG_NAMES:
        side = 1.0 if name[0] == "l" else -1.0
        x = {"f": HIP_X, "m": 0.0, "r": -HIP_X}[name[1]]
        legxml = curved_leg_xml(LEG_CHORD, k, LEG_WIDTH, LEG_THICKNESS, n_segments, name_prefix=f"leg_{name}",
                                mass=LEG_MASS / n_segments, material="limb", contype=1, conaffinity=0)
        legxml = "\n".join(f"{ind}      {ln}" for ln in legxml.splitlines())
        jattr = f'limited="false" armature="{fmt(ARMATURE)}" damping="{fmt(DAMPING)}"'
        lines += [
            f'{ind}  <body name="plate_{name}" pos="{fmt(x, side * y_hip, HIP_Z)}">',
            f'{ind}    <joint name="lift_{name}" type="hinge" axis="{fmt(side, 0, 0)}" {jattr}/>',
            f'{ind}    <inertial pos="0 0 0" mass="{fmt(PLATE_MASS)}" diaginertia="1e-10 1e-10 1e-10"/>',
            f'{ind}    <body name="leg_{name}" pos="0 0 0">',
            f'{ind}      <joint name="swing_{name}" type="hinge" axis="0 1 0" {jattr}/>',
            legxml,
            f"{ind}    </body>",
            f"{ind}  </body>",
        ]
    lines.append(f"{ind}</body>")
    actuators = "\n".join(
        f'    <position name="{j}_{n}" joint="{j}_{n}" kp="{fmt(kp)}" kv="{fmt(kv)}" ctrllimited="false" '
        f'forcelimited="true" forcerange="{fmt(-limit, limit)}"/>'
        for n in LEG_NAMES for j in ("lift", "swing"))
    custom_extra = "\n".join([
        f'    <text name="robot:tripod_a" data="{" ".join("leg_" + n for n in TRIPOD_A)}"/>',
        f'    <text name="robot:tripod_b" data="{" ".join("leg_" + n for n in TRIPOD_B)}"/>',
        f'    <numeric name="robot:curvature" data="{fmt(k)}"/>',
    ])
    comment = (
        f"DynaRoACH ({'granular bed' if opts.sand else 'rigid floor'}): torso {BODY[0] * 100:g} x {BODY[1] * 100:g} x "
        f"{BODY[2] * 100:g} cm, {MASS * 1000:g} g; six C-legs radius {LEG_RADIUS * 100:g} cm, width {LEG_WIDTH * 100:g} cm, "
        f"curvature {k:.6g} 1/m, each on a lift hinge (torso-plate, about x) and a swing hinge (plate-leg, about y), "
        f"hips {HIP_Z * 100:g} cm above the CoM.\nServos kp {kp:g} N m/rad, kv {kv:g} N m s/rad, "
        f"limit +-{limit:g} N m; gait: mjrft.models.dynaroach.dynaroach_ctrl. See mjrft/models/dynaroach.py.")
    return assemble(model="dynaroach" + ("" if opts.sand else "_rigid"), comment=comment, opts=opts, robot="\n".join(lines),
                    actuators=actuators, extent=0.6, center=(0.0, 0.0, z0 / 2), custom_extra=custom_extra)


def dynaroach_model(sand: bool = True, **kw) -> mujoco.MjModel:
    """Compiled :class:`mujoco.MjModel` of :func:`dynaroach_xml`."""
    return mujoco.MjModel.from_xml_string(dynaroach_xml(sand, **kw))

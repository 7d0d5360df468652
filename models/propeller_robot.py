"""The SGRFT paper's propeller-leg robot: two driven propeller-legs at the front, two passive wheels at the rear.

Source: "Granular Resistive Force Theory Extension for Saturated Wet Sand Ground" (Machines 10, 721, 2022),
sec. 4 and fig. 9: "The two propeller-legs at the front of the robot are driven to rotate at the same speed
by a waterproof motor and a reducer, and the two wheels at the rear of the robot are passive wheels"; the
propeller-leg: "Three arc-shaped legs are evenly distributed on a circle with a radius of 110 mm, and the arc
is 0.5 rad" (:func:`mjrft.models.rigs.propeller_geometry`, mjrft's reading of it). The paper gives nothing
else: no mass, body size, blade width or thickness, track, wheelbase or wheel size (its robot is described
in its ref. [32]). Everything below that is not those two sentences is mjrft's choice, named here:

* body: a box ``body_length`` 300 x ``body_width`` 200 x ``body_height`` 60 mm, with the propeller axles at
  its front corners and the wheel axles at its rear corners (wheelbase = body length, the propellers and
  wheels just outside the body sides, 5 mm clearance);
* mass: ``mass`` (kg, the whole robot) defaults to the mass of water filling the body box, 3.6 kg: an
  amphibious robot that also swims (the propeller-leg is a propeller too, paper sec. 4 and its ref. [32])
  is built close to neutral buoyancy. The paper gives no mass; it is a parameter;
* blades: 25 mm wide (the paper's R/V/T legs all project to 25 mm, sec. 3.2) and 2 mm thick (its plate
  intruder, table 1), 40 g per propeller-leg;
* rear wheels: solid cylinders of radius 110 mm (the propeller's radius, so the body is level when a blade
  hangs straight down) and 25 mm wide, 100 g each, on free hinges (damping 1e-3 N m s/rad, armature
  2e-3 kg m^2, the hub and bearing: without it the rim's effective mass, I / r^2 = 0.05 kg, puts the sand's
  stiffness under a sunk wheel beyond the explicit limit of the 1 ms step, measured 0.94 ms);
* drive: the paper's motor and reducer turn both propellers at one set speed; here each hub has a velocity
  servo (``<velocity>``, ``kv`` 50 N m s/rad, torque limit +-``torque_limit`` 20 N m, armature 0.01 kg m^2):
  ``ctrl`` is the hub speed in rad/s (positive: the buried blades sweep backward and the robot moves +x).
  Its tracking error under the granular load is measured by the validation case that uses it.

How it meets the sand: every robot geom is a granular body (``mjrft:bodies`` = body, both propeller-legs,
both wheels), so the rear wheels sink and roll through the grains under the same law as the blades (their
cylinder surface is cut into elements like any other geom); nothing collides with the sand surface, and
the rigid bed bottom 0.3 m down stops a robot that sinks through the bed. Frame: x forward, y left, z up.
Names: bodies ``body``, ``prop_l``/``prop_r`` (hinges and actuators ``hub_l``/``hub_r``), ``wheel_l``/
``wheel_r`` (hinges ``wheel_l``/``wheel_r``). At ``qpos0`` one blade of each propeller hangs straight down
with its tip ``clearance`` (1 mm) above the surface, and the wheels' lowest points are at the same height.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from .rigs import PROPELLER_ARC, PROPELLER_BLADES, PROPELLER_RADIUS, propeller_geometry
from .scene import ROBOT_CONTACT, assemble, box_inertia, check_positive, fmt, look_at, pop_scene_options, reject_unknown

BODY_SIZE = (0.30, 0.20, 0.06)  # m, length x width x height
BLADE_WIDTH = 0.025  # m (SGRFT sec. 3.2: legs 25 mm wide in projection)
BLADE_THICKNESS = 0.002  # m (SGRFT table 1: the 2 mm plate intruder)
PROPELLER_MASS = 0.040  # kg per propeller-leg (three blades)
WHEEL_RADIUS = PROPELLER_RADIUS
WHEEL_WIDTH = 0.025
WHEEL_MASS = 0.100
WATER_DENSITY = 1000.0
SIDE_GAP = 0.005  # m between the body side and a propeller or wheel
CLEARANCE = 0.001  # m between the lowest point and the surface at qpos0
KV = 50.0  # N m s/rad
TORQUE_LIMIT = 20.0  # N m
ARMATURE = 0.01  # kg m^2
WHEEL_DAMPING = 1e-3  # N m s/rad
WHEEL_ARMATURE = 2e-3  # kg m^2
RESOLUTION = 0.005  # m
GRANULAR_BODIES = ["body", "prop_l", "prop_r", "wheel_l", "wheel_r"]


def default_mass(body_size=BODY_SIZE) -> float:
    """The default robot mass (kg): water filling the body box (module docstring)."""
    return WATER_DENSITY * float(np.prod(body_size))


def propeller_robot_xml(*, mass: float | None = None, arc: float = PROPELLER_ARC, radius: float = PROPELLER_RADIUS,
                        blade_width: float = BLADE_WIDTH, blade_thickness: float = BLADE_THICKNESS,
                        wheel_radius: float | None = None, wheel_width: float = WHEEL_WIDTH,
                        torque_limit: float = TORQUE_LIMIT, kv: float = KV, **kw) -> str:
    """MJCF text of the propeller-leg robot (module docstring); lengths in m, mass in kg, angles in rad.

    ``mass`` is the whole robot's (default :func:`default_mass`); it must exceed the propellers' and wheels'
    0.28 kg. Scene options (``medium``, ``law``, ``water_depth``, ``resolution``, ``bed_length``, ...) as for
    the other models (:mod:`.scene`); the defaults here are a 2 m bed of ``poppy_cp`` with the ``rft`` law.
    """
    mass = default_mass() if mass is None else check_positive("mass", mass)
    radius = check_positive("radius", radius)
    wheel_radius = radius if wheel_radius is None else check_positive("wheel_radius", wheel_radius)
    wheel_width = check_positive("wheel_width", wheel_width)
    torque_limit = check_positive("torque_limit", torque_limit)
    kv = check_positive("kv", kv)
    parts = 2 * PROPELLER_MASS + 2 * WHEEL_MASS
    if not mass > parts:
        raise ValueError(f"mass {mass!r} kg must exceed the propellers' and wheels' {parts:g} kg")
    geo = propeller_geometry(radius, arc, PROPELLER_BLADES, blade_width, blade_thickness)
    kw = dict(kw)
    kw.setdefault("bed_length", 2.0)
    kw.setdefault("bed_width", 0.8)
    opts = pop_scene_options(kw, resolution=RESOLUTION, bed_length=kw.pop("bed_length"), bed_width=kw.pop("bed_width"),
                             granular_bodies=GRANULAR_BODIES, sand=True)
    reject_unknown(kw, "propeller_robot_xml")

    L, W, H = BODY_SIZE
    body_mass = mass - parts
    hub_z = float(opts.surface) + max(radius, wheel_radius) + CLEARANCE  # world height of the axles
    y_prop = W / 2 + SIDE_GAP + blade_width / 2
    y_wheel = W / 2 + SIDE_GAP + wheel_width / 2
    verts, faces = geo["mesh"]
    ind = "    "
    cam = np.array([0.6, -0.9, 0.45])

    def propeller(side: str, y: float) -> list[str]:
        out = [f'{ind}  <body name="prop_{side}" pos="{fmt(L / 2, y, 0)}">',
               f'{ind}    <joint name="hub_{side}" type="hinge" axis="0 1 0" armature="{fmt(ARMATURE)}"/>']
        for j, phi in enumerate(geo["blade_angles"]):  # blade j at leg angle phi (tip toward -x for phi > 0)
            out.append(f'{ind}    <geom name="blade_{side}{j + 1}" type="mesh" mesh="blade" '
                       f'quat="{fmt(math.cos(phi / 2), 0, math.sin(phi / 2), 0)}" '
                       f'mass="{fmt(PROPELLER_MASS / len(geo["blade_angles"]))}" material="limb" {ROBOT_CONTACT}/>')
        out.append(f"{ind}  </body>")
        return out

    def wheel(side: str, y: float) -> list[str]:
        z = float(opts.surface) + wheel_radius + CLEARANCE - hub_z  # lowest point CLEARANCE above the surface
        return [f'{ind}  <body name="wheel_{side}" pos="{fmt(-L / 2, y, z)}">',
                f'{ind}    <joint name="wheel_{side}" type="hinge" axis="0 1 0" damping="{fmt(WHEEL_DAMPING)}" '
                f'armature="{fmt(WHEEL_ARMATURE)}"/>',
                f'{ind}    <geom name="wheel_{side}" type="cylinder" size="{fmt(wheel_radius, wheel_width / 2)}" '
                f'quat="{fmt(math.sqrt(0.5), math.sqrt(0.5), 0, 0)}" mass="{fmt(WHEEL_MASS)}" material="foot" '
                f'{ROBOT_CONTACT}/>',
                f"{ind}  </body>"]

    lines = [
        f'{ind}<body name="body" pos="{fmt(0, 0, hub_z)}">',
        f'{ind}  <freejoint name="root"/>',
        f'{ind}  <camera name="track" mode="trackcom" pos="{fmt(cam)}" xyaxes="{look_at(cam)}"/>',
        f'{ind}  <camera name="side" mode="trackcom" pos="{fmt(0, -1.5, 0)}" xyaxes="1 0 0 0 0 1"/>',
        f'{ind}  <inertial pos="0 0 0" mass="{fmt(body_mass)}" '
        f'diaginertia="{fmt(box_inertia(body_mass, (L / 2, W / 2, H / 2)))}"/>',
        f'{ind}  <geom name="body" type="box" size="{fmt(L / 2, W / 2, H / 2)}" material="body" {ROBOT_CONTACT}/>',
        f'{ind}  <site name="marker" pos="0 0 {fmt(H / 2)}" size="0.01" rgba="1 0 0 1"/>',
        *propeller("l", y_prop), *propeller("r", -y_prop),
        *wheel("l", y_wheel), *wheel("r", -y_wheel),
        f"{ind}</body>",
    ]
    actuators = "\n".join(
        f'    <velocity name="hub_{s}" joint="hub_{s}" kv="{fmt(kv)}" ctrllimited="false" forcelimited="true" '
        f'forcerange="{fmt(-torque_limit, torque_limit)}"/>' for s in ("l", "r"))
    assets = f'    <mesh name="blade" vertex="{fmt(verts)}" face="{" ".join(str(int(f)) for f in faces.ravel())}"/>'
    comment = (
        f"SGRFT propeller-leg robot (Machines 2022, sec. 4, fig. 9): two driven propeller-legs at the front "
        f"({geo['blades']} arc blades, arc {geo['arc']:.6g} rad, on a {radius * 1000:g} mm circle, blades "
        f"{blade_width * 1000:g} x {blade_thickness * 1000:g} mm), two passive wheels at the rear (radius "
        f"{wheel_radius * 1000:g} mm, width {wheel_width * 1000:g} mm).\n"
        f"Body {L * 1000:g} x {W * 1000:g} x {H * 1000:g} mm, total mass {mass:g} kg; hub velocity servos kv {kv:g} "
        f"N m s/rad, torque limit +-{torque_limit:g} N m (ctrl = hub speed, rad/s). Everything but the propeller-leg "
        "is mjrft's choice (see mjrft/models/propeller_robot.py)."
    )
    custom = "\n".join([f'    <numeric name="robot:mass" data="{fmt(mass)}"/>',
                        f'    <numeric name="robot:propeller_radius" data="{fmt(radius)}"/>'])
    return assemble(model="propeller_robot", comment=comment, opts=opts, robot="\n".join(lines), actuators=actuators,
                    extent=1.0, center=(0.0, 0.0, hub_z / 2), assets=assets, custom_extra=custom)


def propeller_robot_model(**kw) -> mujoco.MjModel:
    """Compiled :class:`mujoco.MjModel` of :func:`propeller_robot_xml`."""
    return mujoco.MjModel.from_xml_string(propeller_robot_xml(**kw))

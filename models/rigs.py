"""MJCF builders of the two measurement rigs: a plate intruder and a rotating-leg rig.

Both rigs are *kinematic*: :mod:`mjrft.tools.rigs` prescribes ``qpos``/``qvel`` exactly at every sample
(no integration, no actuators), recomputes the kinematics and reads the granular wrench from
:class:`mjrft.GranularTerrain`. The sand is the usual visual-only bed with its top at ``surface``
(default z = 0); the rig geoms have ``contype = conaffinity = 0``. Frame: x forward, y left, z up;
the plane of motion is x-z.

Plate intruder (:func:`plate_rig_xml`, committed default ``plate_rig.xml``)
---------------------------------------------------------------------------
Body ``plate`` (origin at the plate centre) with three joints, in this ``qpos`` order:
``plate_x`` (slide along +x), ``plate_z`` (slide along +z) and ``plate_attack`` (hinge about -y,
``qpos`` = the attack angle beta). Geom ``plate``: a box ``length`` (local x, in the plane of motion)
x ``width`` (y, across it) x ``thickness``. At beta = 0 the plate is horizontal; at beta its faces'
normals are +-(sin beta, 0, -cos beta), Li 2013's convention: with beta > 0 the face that leads when
dragged toward +x faces forward-and-down. Defaults: Li 2013's plate rig, 3.81 x 2.54 x 0.64 cm
(which side lies in the plane of motion is not stated; we put the 3.81 cm side in it).

Rotating leg (:func:`leg_rig_xml`, committed default ``leg_rig.xml``)
---------------------------------------------------------------------
A fixed body ``axle`` at height ``axle_height`` above the surface and a child body ``leg`` on the
hinge ``axle`` (axis +y, ``qpos`` = leg angle theta, measured from straight down; theta > 0 has
swung the tip backward, toward -x, so a leg turning at omega > 0 sweeps its buried part backward
and the grains push it forward). The leg hangs along -z from the axle at theta = 0; the model's
initial pose ``qpos0`` is theta = pi (pointing up, out of the sand: the body is built upside down
and the hinge has ``ref = pi``). Shapes (their curvature follows the convention of
:mod:`mjrft.geometry.curved_leg`: at omega > 0 the buried part sweeps toward -x, and Li 2013's C-leg
is the one whose convex side leads):

=================  ===================================================================================
``flat``           straight bar of length ``chord`` (one box)
``c``              Li 2013's C-leg: circular arc, hip-to-tip ``chord``, curvature ``+curvature``
                   (default the semicircle 2/chord), bowing toward -x when hanging, so its convex side
                   leads when omega > 0 (the hexapod's default leg, :mod:`.hexapod`)
``reversed_c``     Li 2013's reversed C-leg: the same arc bowing toward +x (curvature ``-curvature``),
                   concave side leading
``semi_ellipse``   semi-ellipse, semi-axes ``a`` along the leg (hip-to-tip 2a) and ``b`` across, convex
                   side leading (``bulge=+1``: signed bulge ``+b``, bowing toward -x like the C-leg) or
                   trailing (``bulge=-1``), the hybrid paper's legs and the convention of
                   :func:`mjrft.laws.hybrid.rotating_leg_profile`
``v_section``      straight leg (default hip to tip ``chord`` = 11 cm) with a V cross-section of two
                   plates 90 deg apart, open side leading (:func:`section_leg_mesh`): SGRFT's V-leg
``triangle_section`` the same with a solid equilateral-triangle cross-section, apex leading: SGRFT's T-leg
``propeller``      SGRFT's propeller-leg (:func:`propeller_geometry`): ``blades`` (default 3) circular-arc
                   blades evenly around the axle, each from the axle to a tip on the circle of radius
                   ``chord`` (default 110 mm), subtending ``arc`` (default 0.5 rad) of its own circle,
                   convex side leading like the C-leg
=================  ===================================================================================

Defaults: Li 2013's leg rotation rig for ``flat``/``c``/``reversed_c`` (legs 7.62 cm hip to tip,
2.54 cm wide, 0.64 cm thick, axle 2 cm above the surface) and the hybrid paper's rig for
``semi_ellipse`` (a = b = 4.5 cm, axle 5 cm above the surface; width 2.54 cm and thickness 0.64 cm
are our assumptions, the paper's reference values give neither); the ``propeller``'s axle is 8 cm above the
surface (its 11 cm radius less the 30 mm sinkage of SGRFT's fast leg tests), its blades as wide and thick as
the other legs unless given (SGRFT's validation case passes its 25 x 2 mm).

Curved legs are one closed triangle mesh (geom ``leg``, mesh asset ``leg``, built by
:func:`mjrft.geometry.curved_leg.leg_mesh`), not the chain of boxes the robots use: the boxes' end
faces lie inside the leg at every joint, and a surface-element law counts each pair as an extra thin
plate across the leg, so the box leg's force grows with the number of boxes (Li RFT on the C-leg
rig, closely packed poppy seeds, with every element kept: peak thrust 9.0 / 13.6 / 31.2 N with 4 / 16 /
64 boxes; the coupler's exposed-surface clipping, :func:`mjrft.geometry.exposed_elements`, brings them
to 7.79 / 8.11 / 8.14 N against 8.14 N for the mesh; the reversed C-leg 6.9 / 13.0 / 36.9 N, clipped
4.91 / 4.75 / 4.69 N, mesh 4.71 N). The mesh leg has no inner faces.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from mjrft.geometry.curved_leg import curved_leg_boxes, curved_leg_mesh, semi_ellipse_mesh

from .scene import SceneOptions, assemble, check_positive, fmt

# Li 2013 plate rig (reference section 6)
PLATE_LENGTH = 0.0381
PLATE_WIDTH = 0.0254
PLATE_THICKNESS = 0.0064
# Li 2013 leg rotation rig
LEG_CHORD = 0.0762
LEG_WIDTH = 0.0254
LEG_THICKNESS = 0.0064
LI_AXLE_HEIGHT = 0.02
# hybrid paper's rig (semicircle case a = b = 4.5 cm, axle 5 cm above the surface)
HYBRID_A = 0.045
HYBRID_AXLE_HEIGHT = 0.05

LEG_SHAPES = ("flat", "c", "reversed_c", "semi_ellipse", "v_section", "triangle_section", "propeller")
# SGRFT's straight legs (Machines 2022, sec. 3.2): projection on the direction of motion 25 x 110 mm
SGRFT_LEG_LENGTH = 0.110
SECTION_SHAPES = ("v_section", "triangle_section")
# SGRFT's propeller-leg (sec. 4, fig. 9 caption): three arc-shaped legs evenly on a 110 mm circle, arc 0.5 rad
PROPELLER_RADIUS = 0.110
PROPELLER_ARC = 0.5
PROPELLER_BLADES = 3
PROPELLER_SINKAGE = 0.030  # default tip sinkage on the rig: SGRFT's 30 / 40 rpm leg tests (sec. 3.2)
ALUMINIUM = 2700.0  # kg/m^3, only for the (unused) inertia of the kinematic bodies
RIG_RESOLUTION = 0.005
NO_CONTACT = 'contype="0" conaffinity="0"'
NO_ACTUATORS = "    <!-- none: mjrft.tools.rigs drives the joints kinematically (qpos and qvel prescribed) -->"


def _scene(medium, law, resolution, surface, bodies, bed_length, bed_width, bed_depth) -> SceneOptions:
    opts = SceneOptions(sand=True, bed_depth=bed_depth, bed_length=bed_length, bed_width=bed_width,
                        medium=medium, law=law, resolution=resolution, surface=surface, granular_bodies=bodies)
    opts.validate()
    return opts


def plate_rig_xml(length: float = PLATE_LENGTH, width: float = PLATE_WIDTH, thickness: float = PLATE_THICKNESS,
                  *, medium: str = "poppy_cp", law: str = "rft", resolution: float = RIG_RESOLUTION,
                  surface: float = 0.0) -> str:
    """MJCF text of the plate intruder (module docstring); at ``qpos = 0`` the plate lies flat on the
    surface (beta = 0, centre half a thickness above it)."""
    length = check_positive("plate length", length)
    width = check_positive("plate width", width)
    thickness = check_positive("plate thickness", thickness)
    opts = _scene(medium, law, resolution, surface, ["plate"], 1.0, 0.4, 0.2)
    half = (length / 2, width / 2, thickness / 2)
    mass = ALUMINIUM * length * width * thickness
    z0 = float(surface) + thickness / 2
    robot = "\n".join([
        f'    <body name="plate" pos="{fmt(0, 0, z0)}">',
        f'      <camera name="track" mode="trackcom" pos="{fmt(0, -0.3, 0)}" xyaxes="1 0 0 0 0 1"/>',
        '      <joint name="plate_x" type="slide" axis="1 0 0"/>',
        '      <joint name="plate_z" type="slide" axis="0 0 1"/>',
        '      <joint name="plate_attack" type="hinge" axis="0 -1 0"/>',
        f'      <geom name="plate" type="box" size="{fmt(half)}" mass="{fmt(mass)}" material="limb" {NO_CONTACT}/>',
        "    </body>",
    ])
    comment = (
        f"Plate intruder rig: plate {length * 100:g} x {width * 100:g} x {thickness * 100:g} cm "
        "(length in the plane of motion x width x thickness), moved kinematically by mjrft.tools.rigs.plate_intrusion.\n"
        "Joints (qpos order): plate_x slide +x, plate_z slide +z, plate_attack hinge about -y (= beta).\n"
        "See mjrft/models/rigs.py."
    )
    return assemble(model="plate_rig", comment=comment, opts=opts, robot=robot, actuators=NO_ACTUATORS,
                    extent=0.3, center=(0.0, 0.0, 0.0), custom_extra='    <text name="rig:kind" data="plate"/>')


def leg_geometry(shape: str = "c", *, chord: float | None = None, curvature: float | None = None,
                 a: float | None = None, b: float | None = None, bulge: int = 1, width: float = LEG_WIDTH,
                 thickness: float = LEG_THICKNESS, n_segments: int = 32, arc: float | None = None,
                 blades: int | None = None) -> dict:
    """Checked leg parameters with the shape's defaults filled in, and the leg's surface.

    A flat leg is one box; curved legs are ONE closed mesh (:func:`mjrft.geometry.curved_leg.leg_mesh`
    of a centre line of ``n_segments`` pieces), not a chain of boxes, whose internal end faces would
    act as extra plates across the leg. Returns ``shape``, ``length`` (hip to tip, m), ``width``,
    ``thickness``, the shape's own numbers (``chord``, ``curvature`` or ``a``, ``b``, ``bulge``),
    ``vertices`` (surface points in the leg body frame: the mesh vertices or the box corners) and
    ``mesh`` (``(vertices, faces)``, None for the flat leg). The ``propeller`` also returns ``arc``,
    ``blades`` and ``blade_angles`` (its mesh is one blade, repeated at each of those angles about y;
    ``vertices`` holds every blade's).
    """
    if shape not in LEG_SHAPES:
        raise ValueError(f"unknown leg shape {shape!r}; valid choices: {', '.join(LEG_SHAPES)}")
    width = check_positive("leg width", width)
    thickness = check_positive("leg thickness", thickness)
    out = {"shape": shape, "width": width, "thickness": thickness}
    if shape == "semi_ellipse":
        if chord is not None or curvature is not None:
            raise ValueError("shape 'semi_ellipse' takes the semi-axes a and b, not chord or curvature")
        if bulge not in (1, -1):
            raise ValueError(f"bulge must be +1 (convex side leading) or -1 (trailing), got {bulge!r}")
        a = check_positive("semi-axis a", HYBRID_A if a is None else a)
        b = check_positive("semi-axis b", HYBRID_A if b is None else b)
        signed_b = bulge * b  # +1: convex side toward -x, the side that leads when omega > 0
        mesh = semi_ellipse_mesh(a, signed_b, width, thickness, n_segments)
        out.update(a=a, b=b, bulge=bulge, length=2 * a, mesh=mesh, vertices=mesh[0])
        return out
    if a is not None or b is not None:
        raise ValueError(f"the semi-axes a and b apply to shape 'semi_ellipse' only, not {shape!r}")
    if shape == "propeller":
        if curvature is not None:
            raise ValueError("shape 'propeller' takes the blade's arc angle (arc, rad), not curvature")
        out.update(propeller_geometry(PROPELLER_RADIUS if chord is None else chord,
                                      PROPELLER_ARC if arc is None else arc,
                                      PROPELLER_BLADES if blades is None else blades, width, thickness, n_segments))
        return out
    if arc is not None or blades is not None:
        raise ValueError(f"arc and blades apply to shape 'propeller' only, not {shape!r}")
    if shape in SECTION_SHAPES:
        if curvature not in (None, 0, 0.0):
            raise ValueError(f"shape {shape!r} is straight (no curvature), got {curvature!r}")
        chord = check_positive("leg chord", SGRFT_LEG_LENGTH if chord is None else chord)
        mesh = section_leg_mesh(shape, chord, width, thickness)
        out.update(chord=chord, length=chord, curvature=0.0, mesh=mesh, vertices=mesh[0])
        return out
    chord = check_positive("leg chord", LEG_CHORD if chord is None else chord)
    out.update(chord=chord, length=chord)
    if shape == "flat":
        if curvature not in (None, 0, 0.0):
            raise ValueError(f"shape 'flat' has no curvature, got {curvature!r}")
        box = curved_leg_boxes(chord, 0.0, width, thickness, 1)[0]
        corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * box["size"]
        out.update(curvature=0.0, mesh=None, box=box, vertices=corners + box["pos"])
        return out
    kmax = 2.0 / chord
    k = kmax if curvature is None else check_positive("curvature", curvature)
    if k > kmax * (1 + 1e-9):
        raise ValueError(f"curvature {curvature!r} 1/m out of range for chord {chord!r} m: valid (0, 2/chord] = "
                         f"(0, {kmax:.6g}] 1/m (the sign comes from the shape: 'c' or 'reversed_c')")
    k = min(k, kmax) * (1.0 if shape == "c" else -1.0)
    mesh = curved_leg_mesh(chord, k, width, thickness, n_segments)
    out.update(curvature=k, mesh=mesh, vertices=mesh[0])
    return out


def section_leg_mesh(shape: str, length: float, width: float, thickness: float) -> tuple[np.ndarray, np.ndarray]:
    """Closed mesh ``(vertices, faces)`` of a straight leg from the hip (0, 0, 0) to the tip (0, 0, -length)
    whose cross-section (x along the motion, y along the axle) is

    * ``v_section``: a V of two plates ``thickness`` thick, 90 degrees apart, opening ``width`` wide and
      ``width / 2`` deep, open side toward -x (the side that leads when omega > 0: a scoop);
    * ``triangle_section``: a solid equilateral triangle of side ``width``, apex toward -x (leading: a wedge).

    Both project on the direction of motion to ``width`` x ``length`` like a flat leg (the SGRFT paper's
    R/V/T legs; it gives no cross-section, these are mjrft's reading). Rings every ``width / 2`` along the
    leg keep the triangles near isotropic.
    """
    w, t = check_positive("leg width", width), check_positive("leg thickness", thickness)
    if shape == "v_section":
        d, s = w / 2, t * math.sqrt(2.0)  # depth of the V; offset of the inner V along x for thickness t
        if not s < d:
            raise ValueError(f"v_section: thickness {thickness!r} m too large for width {width!r} m "
                             f"(needs thickness < width / (2 sqrt 2) = {d / math.sqrt(2.0):.6g} m)")
        x0 = -d / 2  # x from -d/2 (open side) to +d/2 (apex)
        poly = [(x0, -w / 2), (x0 + d, 0.0), (x0, w / 2), (x0, w / 2 - s), (x0 + d - s, 0.0), (x0, -w / 2 + s)]
        caps = [(0, 1, 4, 5), (1, 2, 3, 4)]  # the two arms, each convex
    elif shape == "triangle_section":
        h = w * math.sqrt(3.0) / 2
        poly = [(-h / 2, 0.0), (h / 2, -w / 2), (h / 2, w / 2)]
        caps = [(0, 1, 2)]
    else:
        raise ValueError(f"unknown section leg {shape!r}; valid choices: {', '.join(SECTION_SHAPES)}")
    poly = np.array(poly)
    k = len(poly)
    rings = max(1, math.ceil(length / (w / 2) - 1e-9))
    zs = np.linspace(0.0, -length, rings + 1)
    verts = np.array([(x, y, z) for z in zs for x, y in poly])
    faces = []
    ccw = np.sum(poly[:, 0] * np.roll(poly[:, 1], -1) - np.roll(poly[:, 0], -1) * poly[:, 1]) > 0
    for r in range(rings):
        for i in range(k):
            j = (i + 1) % k
            a, b, c, e = r * k + i, r * k + j, (r + 1) * k + j, (r + 1) * k + i
            faces += [(a, e, c), (a, c, b)] if ccw else [(a, c, e), (a, b, c)]
    for cap in caps:  # top cap faces +z, bottom cap -z
        top = [cap[0], cap[1], cap[2]] if ccw else [cap[0], cap[2], cap[1]]
        quads = [top] if len(cap) == 3 else [top, [cap[0], cap[2], cap[3]] if ccw else [cap[0], cap[3], cap[2]]]
        for tri in quads:
            faces.append(tuple(tri))
            faces.append(tuple(rings * k + i for i in tri[::-1]))
    return verts, np.array(faces, dtype=int)


def propeller_geometry(radius: float = PROPELLER_RADIUS, arc: float = PROPELLER_ARC, blades: int = PROPELLER_BLADES,
                       width: float = LEG_WIDTH, thickness: float = LEG_THICKNESS, n_segments: int = 32) -> dict:
    """SGRFT's propeller-leg (sec. 4, fig. 9): ``blades`` circular-arc blades evenly around the axle.

    The paper's caption: "Three arc-shaped legs are evenly distributed on a circle with a radius of 110 mm,
    and the arc is 0.5 rad" (sec. 4.1's text calls "the radian of the foot" 0.5 pi rad instead; the caption's
    number is the default, ``arc`` takes either). mjrft's reading: each blade is a circular arc from the axle
    (the hub) to a tip on the ``radius`` circle, subtending ``arc`` rad of its own circle (hip-to-tip chord =
    ``radius``, curvature ``2 sin(arc / 2) / radius``), bowing like Li 2013's C-leg (convex side leading when
    the propeller turns at omega > 0, :mod:`mjrft.geometry.curved_leg`); blade ``j`` hangs at leg angle
    ``2 pi j / blades``. The hub and the blades' mounting are not described and are not modelled.

    Returns ``chord`` (= radius), ``length``, ``curvature``, ``arc``, ``blades``, ``blade_angles`` (rad),
    ``mesh`` (one blade, hip at the origin, tip at (0, 0, -radius)) and ``vertices`` (all blades).
    """
    radius = check_positive("propeller radius", radius)
    arc = check_positive("propeller blade arc", arc)
    if arc > math.pi:
        raise ValueError(f"propeller blade arc {arc!r} rad out of range: valid (0, pi] (pi = a semicircular blade)")
    if isinstance(blades, bool) or not isinstance(blades, (int, np.integer)) or blades < 1:
        raise ValueError(f"propeller blades must be a positive integer, got {blades!r}")
    k = min(2.0 * math.sin(arc / 2.0) / radius, 2.0 / radius)
    mesh = curved_leg_mesh(radius, k, width, thickness, n_segments)
    angles = [2.0 * math.pi * j / int(blades) for j in range(int(blades))]
    verts = []
    for phi in angles:  # the leg angle phi swings the tip toward -x: x' = x cos + z sin, z' = -x sin + z cos
        c, s = math.cos(phi), math.sin(phi)
        v = mesh[0]
        verts.append(np.column_stack([c * v[:, 0] + s * v[:, 2], v[:, 1], -s * v[:, 0] + c * v[:, 2]]))
    return {"chord": radius, "length": radius, "curvature": k, "arc": arc, "blades": int(blades),
            "blade_angles": angles, "mesh": mesh, "vertices": np.concatenate(verts)}


def default_axle_height(shape: str) -> float:
    """Axle height above the surface (m) when none is given: 2 cm (Li 2013), 5 cm (``semi_ellipse``), or for the
    ``propeller`` its radius less SGRFT's 30 mm sinkage of the fast leg tests (8 cm; sec. 3.2)."""
    if shape == "propeller":
        return PROPELLER_RADIUS - PROPELLER_SINKAGE
    return HYBRID_AXLE_HEIGHT if shape == "semi_ellipse" else LI_AXLE_HEIGHT


def leg_rig_xml(shape: str = "c", *, axle_height: float | None = None, medium: str = "poppy_cp", law: str = "rft",
                resolution: float = RIG_RESOLUTION, surface: float = 0.0, **leg) -> str:
    """MJCF text of the rotating-leg rig (module docstring); ``**leg`` goes to :func:`leg_geometry`."""
    geo = leg_geometry(shape, **leg)
    h = default_axle_height(shape) if axle_height is None else check_positive("axle_height", axle_height)
    opts = _scene(medium, law, resolution, surface, ["leg"], 1.0, 0.4, 0.3)
    mass = ALUMINIUM * geo["width"] * geo["thickness"] * geo["length"]
    if geo["mesh"] is None:
        bx = geo["box"]
        legxml = (f'        <geom name="leg" type="box" pos="{fmt(bx["pos"])}" size="{fmt(bx["size"])}" '
                  f'mass="{fmt(mass)}" material="limb" {NO_CONTACT}/>')
        assets = ""
    else:
        verts, faces = geo["mesh"]
        legxml = f'        <geom name="leg" type="mesh" mesh="leg" mass="{fmt(mass)}" material="limb" {NO_CONTACT}/>'
        if shape == "propeller":  # one geom per blade, the same mesh turned about y by the blade's leg angle
            legxml = "\n".join(
                f'        <geom name="{"leg" if j == 0 else f"leg_{j + 1}"}" type="mesh" mesh="leg" '
                f'quat="{fmt(math.cos(phi / 2), 0, math.sin(phi / 2), 0)}" mass="{fmt(mass)}" material="limb" '
                f'{NO_CONTACT}/>' for j, phi in enumerate(geo["blade_angles"]))
        assets = f'    <mesh name="leg" vertex="{fmt(verts)}" face="{" ".join(str(int(f)) for f in faces.ravel())}"/>'
    axle_r = 0.004
    half_w = geo["width"] / 2 + 0.01
    z_axle = float(surface) + h
    robot = "\n".join([
        f'    <body name="axle" pos="{fmt(0, 0, z_axle)}">',
        f'      <geom name="axle" type="cylinder" fromto="{fmt(0, -half_w, 0, 0, half_w, 0)}" size="{fmt(axle_r)}" '
        f'material="body" {NO_CONTACT} mass="0.1"/>',
        f'      <camera name="track" mode="track" pos="{fmt(0, -0.45, -0.02)}" xyaxes="1 0 0 0 0 1"/>',
        # built pointing up (out of the sand) with ref = pi, so qpos is still the angle from straight down
        '      <body name="leg" pos="0 0 0" quat="0 0 1 0">',
        f'        <joint name="axle" type="hinge" axis="0 1 0" ref="{math.pi!r}"/>',
        legxml,
        "      </body>",
        "    </body>",
    ])
    if shape == "propeller":
        what = (f"propeller-leg, {geo['blades']} arc blades (arc {geo['arc']:.6g} rad) on a "
                f"{geo['chord'] * 100:g} cm circle, curvature {geo['curvature']:.6g} 1/m")
    elif shape == "semi_ellipse":
        what = (f"semi-ellipse a = {geo['a'] * 100:g} cm, b = {geo['b'] * 100:g} cm, convex side "
                f"{'leading' if geo['bulge'] == 1 else 'trailing'}")
    else:
        kind = {"flat": "flat", "c": "C-leg, convex side leading", "reversed_c": "reversed C-leg, concave side leading",
                "v_section": "V-section, open side leading", "triangle_section": "triangle-section, apex leading"}
        what = f"{kind.get(shape, shape)}, hip to tip {geo['chord'] * 100:g} cm, curvature {geo['curvature']:.6g} 1/m"
    comment = (
        f"Rotating-leg rig: leg {what}, width {geo['width'] * 100:g} cm, thickness {geo['thickness'] * 100:g} cm;\n"
        f"axle {h * 100:g} cm above the sand surface, hinge 'axle' about +y (qpos = leg angle from straight down,\n"
        "positive = tip swung toward -x). Driven kinematically by mjrft.tools.rigs.rotating_leg. See mjrft/models/rigs.py."
    )
    custom = "\n".join([
        '    <text name="rig:kind" data="leg"/>',
        f'    <text name="rig:shape" data="{shape}"/>',
        f'    <numeric name="rig:axle_height" data="{fmt(h)}"/>',
    ])
    return assemble(model=f"leg_rig_{shape}", comment=comment, opts=opts, robot=robot, actuators=NO_ACTUATORS,
                    extent=0.4, center=(0.0, 0.0, 0.0), custom_extra=custom, assets=assets)


def plate_rig_model(*args, **kw) -> mujoco.MjModel:
    """Compiled :func:`plate_rig_xml`."""
    return mujoco.MjModel.from_xml_string(plate_rig_xml(*args, **kw))


def leg_rig_model(shape: str = "c", **kw) -> mujoco.MjModel:
    """Compiled :func:`leg_rig_xml`."""
    return mujoco.MjModel.from_xml_string(leg_rig_xml(shape, **kw))

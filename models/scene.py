"""Shared MJCF scaffolding for the mjrft robot models (string templating).

Scene convention
----------------
``sand=True`` (granular scenes):

* the robot does NOT collide with the sand surface: granular forces come from
  the mjrft terrain, not from MuJoCo contacts;
* ``sand_surface`` is a visual-only, semi-transparent box filling the bed,
  top face at ``z = 0`` (``contype = conaffinity = 0``);
* ``bed_bottom`` is a rigid plane at ``z = -bed_depth`` (default 0.3 m) that
  does collide, so a robot that sinks through the whole bed stops there;
* the model carries its terrain set-up in ``<custom>``::

      <text    name="mjrft:medium"     data="poppy_cp"/>
      <text    name="mjrft:law"        data="rft"/>
      <text    name="mjrft:bodies"     data="torso leg_lf ..."/>   (granular bodies)
      <numeric name="mjrft:surface"    data="0"/>                  (surface height, m)
      <numeric name="mjrft:resolution" data="0.005"/>              (element size, m)
      <numeric name="scene:bed_depth"  data="0.3"/>                (bed depth, m; not an mjrft setting)

  and, for mixed terrain (``regions=[(x_min, medium, law, water_depth), ...]``: strips along x
  after the base ``medium``/``law``, see :class:`mjrft.GranularTerrain`)::

      <text    name="mjrft:regions"    data="0.3 sea_sand_saturated wet 0; 0.6 ..."/>
      <numeric name="mjrft:transition" data="0.01"/>                (only if given)
      <numeric name="mjrft:buoyancy"   data="1"/>                   (only if buoyancy=True)
      <numeric name="mjrft:water_depth" data="..."/>                (only if water_depth > 0)

  Each strip gets its own visual sand box (darker for the saturated-sand law ``wet``) and, where it
  has standing water, a translucent visual water box on top (``water_<k>``).

  ``surface_grid=<m>`` makes the sand surface a height field instead (for a rough surface, e.g. the
  environments' ``terrain_randomization``): ``sand_surface`` is then a visual-only ``hfield`` geom
  over the bed (asset ``sand``, samples ``surface_grid`` apart, all at ``surface`` until something
  writes them, elevation scale ``HFIELD_ELEVATION``), and the terrain reads its free surface from it::

      <text    name="mjrft:surface_hfield" data="sand_surface"/>     (instead of mjrft:surface)

  The strips' sand boxes are then not drawn (their water boxes are).

``sand=False`` (rigid comparison scenes, the ``...Rigid-v0`` environments):
``floor`` is a rigid plane at ``z = 0`` that collides; no ``mjrft:*`` custom
entries are written.

Collision filtering: robot geoms use ``contype=1 conaffinity=0`` and the
ground planes ``contype=0 conaffinity=1``, so the robot collides with the
ground/bed bottom but never with itself (legs of the hexapod sweep overlapping
circles, and the planar biped's legs share a plane).

All models use ``timestep = 1 ms`` and the ``implicitfast`` integrator.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from mjrft.errors import check_finite, check_positive

TIMESTEP = 0.001
DEFAULT_BED_DEPTH = 0.3
DEFAULT_MEDIUM = "poppy_cp"
DEFAULT_LAW = "rft"
SAND_RGBA = "0.86 0.74 0.52 0.45"
WET_SAND_RGBA = "0.55 0.45 0.30 0.55"
WATER_RGBA = "0.25 0.45 0.75 0.35"
HFIELD_ELEVATION = 0.1  # m per unit of a height-field surface's samples (hfield size[2]); any height can be written
MAX_SURFACE_SAMPLES = 4_000_000  # most samples a surface_grid may make (16 MB of float32)

#: Collision bits: robot geoms collide with the ground only (never with each other).
ROBOT_CONTACT = 'contype="1" conaffinity="0"'
GROUND_CONTACT = 'contype="0" conaffinity="1"'
VISUAL_ONLY = 'contype="0" conaffinity="0"'


def fmt(*values) -> str:
    """Space separated, compact, deterministic number formatting."""
    flat = []
    for v in values:
        flat.extend(np.ravel(v).tolist())
    out = []
    for x in flat:
        s = f"{float(x):.6g}"
        if s == "-0":
            s = "0"
        out.append(s)
    return " ".join(out)


def look_at(pos, target=(0.0, 0.0, 0.0)) -> str:
    """``xyaxes`` string for a camera at ``pos`` looking at ``target`` (z up)."""
    p = np.asarray(pos, float)
    t = np.asarray(target, float)
    z = p - t
    z /= np.linalg.norm(z)
    x = np.cross([0.0, 0.0, 1.0], z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    return fmt(x, y)


@dataclass
class SceneOptions:
    """Terrain / scene options shared by all robot generators."""

    sand: bool = True
    bed_depth: float = DEFAULT_BED_DEPTH
    bed_length: float = 2.0  # m, along x (visual only); bed spans [-0.5, bed_length - 0.5]
    bed_width: float = 1.0  # m, along y (visual only)
    medium: str = DEFAULT_MEDIUM
    law: str = DEFAULT_LAW
    resolution: float = 0.01
    surface: float = 0.0
    granular_bodies: list[str] = field(default_factory=list)
    #: mixed terrain: strips ``(x_min, medium, law, water_depth)`` sorted by x_min (see module docstring)
    regions: list = field(default_factory=list)
    water_depth: float = 0.0  # standing water over the base medium (m)
    transition: float | None = None  # region blend width (m); None: mjrft's default
    buoyancy: bool = False
    inertial: bool = False  # the dry laws' inertial regime (mjrft:inertial; mjrft.laws.inertial)
    surface_grid: float | None = None  # sample spacing (m) of a height-field sand surface; None: flat box

    def surface_shape(self) -> tuple[int, int]:
        """(nrow, ncol) of the height-field surface: samples ``surface_grid`` apart (or closer) over the bed."""
        return (int(math.ceil(self.bed_width / self.surface_grid - 1e-9)) + 1,
                int(math.ceil(self.bed_length / self.surface_grid - 1e-9)) + 1)

    def validate(self) -> None:
        check_positive("bed_depth", self.bed_depth)
        check_positive("bed_length", self.bed_length)
        check_positive("bed_width", self.bed_width)
        check_positive("resolution", self.resolution)
        if not math.isfinite(float(self.surface)):
            raise ValueError(f"surface must be finite, got {self.surface!r}")
        for name, val in (("medium", self.medium), ("law", self.law)):
            _check_identifier(name, val)
        check_positive("water_depth", self.water_depth, allow_zero=True)
        if self.surface_grid is not None:
            check_positive("surface_grid", self.surface_grid)
            nrow, ncol = self.surface_shape()
            if nrow * ncol > MAX_SURFACE_SAMPLES:
                raise ValueError(f"surface_grid {self.surface_grid:g} m makes {nrow} x {ncol} height-field samples over "
                                 f"the {self.bed_length:g} x {self.bed_width:g} m bed, more than {MAX_SURFACE_SAMPLES:,}; "
                                 "use a coarser surface_grid")
        if self.transition is not None:
            check_positive("transition", self.transition, allow_zero=True)
        regions = []
        for k, reg in enumerate(self.regions, start=1):
            reg = tuple(reg)
            if len(reg) not in (3, 4):
                raise ValueError(f"region {k}: expected (x_min, medium, law[, water_depth]), got {reg!r}")
            x_min, medium, law = reg[:3]
            water = reg[3] if len(reg) == 4 else 0.0
            x_min = check_finite(f"region {k} x_min", x_min)
            if regions and x_min <= regions[-1][0]:
                raise ValueError(f"regions must be sorted by increasing x_min, got {x_min!r} after {regions[-1][0]!r}")
            _check_identifier(f"region {k} medium", medium)
            _check_identifier(f"region {k} law", law)
            regions.append((x_min, medium, law, check_positive(f"region {k} water_depth", water, allow_zero=True)))
        self.regions = regions


def _check_identifier(name: str, val) -> None:
    if not isinstance(val, str) or not val or any(c.isspace() or c in '"<>&;' for c in val):
        raise ValueError(f"{name} must be a non-empty identifier string, got {val!r}")


def pop_scene_options(kw: dict, *, resolution: float, bed_length: float, bed_width: float,
                      granular_bodies: list[str], sand: bool) -> SceneOptions:
    """Build SceneOptions from generator keyword arguments (removing them from ``kw``)."""
    opts = SceneOptions(
        sand=bool(sand),
        bed_depth=kw.pop("bed_depth", DEFAULT_BED_DEPTH),
        bed_length=kw.pop("bed_length", bed_length),
        bed_width=kw.pop("bed_width", bed_width),
        medium=kw.pop("medium", DEFAULT_MEDIUM),
        law=kw.pop("law", DEFAULT_LAW),
        resolution=kw.pop("resolution", resolution),
        surface=kw.pop("surface", 0.0),
        granular_bodies=list(kw.pop("granular_bodies", granular_bodies)),
        regions=list(kw.pop("regions", [])),
        water_depth=kw.pop("water_depth", 0.0),
        transition=kw.pop("transition", None),
        buoyancy=bool(kw.pop("buoyancy", False)),
        inertial=bool(kw.pop("inertial", False)),
        surface_grid=kw.pop("surface_grid", None),
    )
    opts.validate()
    return opts


SCENE_OPTIONS = ("bed_depth", "bed_length", "bed_width", "medium", "law", "resolution", "surface", "granular_bodies",
                 "regions", "water_depth", "transition", "buoyancy", "inertial", "surface_grid")


def reject_unknown(kw: dict, func: str) -> None:
    if kw:
        raise TypeError(f"{func}() got unexpected keyword argument(s): {', '.join(sorted(kw))}; "
                        f"valid scene options: {', '.join(SCENE_OPTIONS)}")


def _ground_xml(opts: SceneOptions) -> str:
    if not opts.sand:
        return (
            f'    <geom name="floor" type="plane" size="0 0 0.05" material="grid" {GROUND_CONTACT}/>'
        )
    hx = opts.bed_length / 2.0
    hy = opts.bed_width / 2.0
    hz = opts.bed_depth / 2.0
    cx = hx - 0.5
    top = float(opts.surface)
    lines = ["    <!-- granular bed: visual-only sand (forces come from mjrft), rigid bottom -->"]
    if opts.surface_grid is not None:  # a height field (the strips' boxes are not drawn over it)
        lines.append(f'    <geom name="sand_surface" type="hfield" hfield="sand" pos="{fmt(cx, 0, top)}" '
                     f'material="sand" {VISUAL_ONLY} group="1"/>')
    if opts.surface_grid is None and not opts.regions:
        lines.append(f'    <geom name="sand_surface" type="box" pos="{fmt(cx, 0, top - hz)}" '
                     f'size="{fmt(hx, hy, hz)}" material="sand" {VISUAL_ONLY} group="1"/>')
        strips = []
    else:  # one visual box per strip, clipped to the bed
        x0, x1 = -0.5, opts.bed_length - 0.5
        edges = [x0] + [min(max(r[0], x0), x1) for r in opts.regions] + [x1]
        strips = [(opts.law, opts.water_depth)] + [(r[2], r[3]) for r in opts.regions]
        for k, (law, _) in enumerate(strips):
            a, b = edges[k], edges[k + 1]
            if b <= a or opts.surface_grid is not None:
                continue
            name = "sand_surface" if k == 0 else f"sand_{k}"
            rgba = WET_SAND_RGBA if law == "wet" else SAND_RGBA
            lines.append(f'    <geom name="{name}" type="box" pos="{fmt((a + b) / 2, 0, top - hz)}" '
                         f'size="{fmt((b - a) / 2, hy, hz)}" rgba="{rgba}" {VISUAL_ONLY} group="1"/>')
    for k, (_, water) in enumerate(strips):
        a, b = edges[k], edges[k + 1]
        if water > 0 and b > a:
            lines.append(f'    <geom name="water_{k}" type="box" pos="{fmt((a + b) / 2, 0, top + water / 2)}" '
                         f'size="{fmt((b - a) / 2, hy, water / 2)}" rgba="{WATER_RGBA}" {VISUAL_ONLY} group="1"/>')
    lines.append(f'    <geom name="bed_bottom" type="plane" pos="{fmt(0, 0, top - opts.bed_depth)}" '
                 f'size="0 0 0.05" material="grid" {GROUND_CONTACT}/>')
    return "\n".join(lines)


def _custom_xml(opts: SceneOptions, extra: str = "") -> str:
    lines = []
    if opts.sand:
        lines += [
            f'    <text name="mjrft:medium" data="{opts.medium}"/>',
            f'    <text name="mjrft:law" data="{opts.law}"/>',
            f'    <text name="mjrft:bodies" data="{" ".join(opts.granular_bodies)}"/>',
            (f'    <numeric name="mjrft:surface" data="{fmt(opts.surface)}"/>' if opts.surface_grid is None else
             '    <text name="mjrft:surface_hfield" data="sand_surface"/>'),
            f'    <numeric name="mjrft:resolution" data="{fmt(opts.resolution)}"/>',
            f'    <numeric name="scene:bed_depth" data="{fmt(opts.bed_depth)}"/>',
        ]
        if opts.regions:
            text = "; ".join(f"{fmt(x)} {med} {law} {fmt(w)}" for x, med, law, w in opts.regions)
            lines.append(f'    <text name="mjrft:regions" data="{text}"/>')
        if opts.water_depth > 0:
            lines.append(f'    <numeric name="mjrft:water_depth" data="{fmt(opts.water_depth)}"/>')
        if opts.transition is not None:
            lines.append(f'    <numeric name="mjrft:transition" data="{fmt(opts.transition)}"/>')
        if opts.buoyancy:
            lines.append('    <numeric name="mjrft:buoyancy" data="1"/>')
        if opts.inertial:
            lines.append('    <numeric name="mjrft:inertial" data="1"/>')
    if extra:
        lines.append(extra.rstrip("\n"))
    if not lines:
        return ""
    return "  <custom>\n" + "\n".join(lines) + "\n  </custom>\n"


def assemble(
    *,
    model: str,
    comment: str,
    opts: SceneOptions,
    robot: str,
    actuators: str,
    extent: float,
    center=(0.0, 0.0, 0.0),
    assets: str = "",
    defaults: str = "",
    custom_extra: str = "",
    contact: str = "",
) -> str:
    """Assemble a complete MJCF document around the robot's ``<body>`` tree."""
    comment = comment.strip().replace("--", "-")
    parts = [
        f'<mujoco model="{model}">',
        "<!--",
        comment,
        "",
        "Generated by `python -m mjrft.models.generate`; do not edit by hand.",
        "-->",
        '  <compiler angle="radian" autolimits="true"/>',
        f'  <option timestep="{fmt(TIMESTEP)}" integrator="implicitfast"/>',
        f'  <statistic center="{fmt(center)}" extent="{fmt(extent)}"/>',
        "  <visual>",
        '    <headlight diffuse="0.6 0.6 0.6" ambient="0.3 0.3 0.3" specular="0 0 0"/>',
        '    <global azimuth="140" elevation="-20"/>',
        f'    <map znear="{fmt(0.01)}"/>',
        "  </visual>",
        "  <asset>",
        '    <texture type="skybox" builtin="gradient" rgb1="0.3 0.5 0.7" rgb2="0 0 0" width="512" height="512"/>',
        '    <texture name="grid" type="2d" builtin="checker" rgb1="0.2 0.3 0.4" rgb2="0.1 0.2 0.3" '
        'width="512" height="512" mark="edge" markrgb="0.8 0.8 0.8"/>',
        f'    <material name="grid" texture="grid" texrepeat="{fmt(max(1.0, 4.0 / extent))} '
        f'{fmt(max(1.0, 4.0 / extent))}" texuniform="true" reflectance="0.1"/>',
        f'    <material name="sand" rgba="{SAND_RGBA}"/>',
        '    <material name="body" rgba="0.25 0.3 0.35 1"/>',
        '    <material name="limb" rgba="0.75 0.45 0.15 1"/>',
        '    <material name="foot" rgba="0.55 0.2 0.15 1"/>',
    ]
    if assets:
        parts.append(assets.rstrip("\n"))
    if opts.sand and opts.surface_grid is not None:
        nrow, ncol = opts.surface_shape()
        parts.append(f'    <hfield name="sand" nrow="{nrow}" ncol="{ncol}" '
                     f'size="{fmt(opts.bed_length / 2, opts.bed_width / 2, HFIELD_ELEVATION, opts.bed_depth)}"/>')
    parts.append("  </asset>")
    if defaults:
        parts += ["  <default>", defaults.rstrip("\n"), "  </default>"]
    parts += [
        "  <worldbody>",
        '    <light name="sun" directional="true" pos="0 0 3" dir="-0.3 0.2 -1" diffuse="0.7 0.7 0.7" castshadow="true"/>',
        _ground_xml(opts),
        robot.rstrip("\n"),
        "  </worldbody>",
    ]
    if contact:
        parts += ["  <contact>", contact.rstrip("\n"), "  </contact>"]
    parts += ["  <actuator>", actuators.rstrip("\n"), "  </actuator>"]
    custom = _custom_xml(opts, custom_extra)
    if custom:
        parts.append(custom.rstrip("\n"))
    parts.append("</mujoco>")
    return "\n".join(parts) + "\n"


def box_inertia(mass: float, size) -> np.ndarray:
    """Principal inertia of a solid box (``size`` = MuJoCo half sizes)."""
    a, b, c = (2.0 * float(s) for s in size)
    return mass / 12.0 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])

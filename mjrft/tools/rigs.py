"""Measurement rigs: a plate intruder and a rotating leg, run through MuJoCo and :class:`GranularTerrain`.

>>> from mjrft.tools import rigs
>>> p = rigs.plate_intrusion(beta=0.0, gamma=math.pi / 2, depth=0.05)   # horizontal plate pushed down
>>> p.depth, p.lift, p.drag, p.torque                                   # numpy arrays, one row per sample
>>> leg = rigs.rotating_leg("c", omega=0.2)                              # Li 2013's C-leg rig
>>> leg.angle, leg.forward, leg.support, leg.torque
>>> fam = rigs.rotating_leg_family(law="hybrid")                        # the hybrid paper's five legs
>>> rigs.plot_leg(fam, "family.png"); rigs.write_csv(fam, "family.csv")

Command line: ``mjrft rig plate ...`` / ``mjrft rig leg ...`` (``--help``) write a CSV and a PNG.

How the rigs move
-----------------
Both rigs are kinematic (models in :mod:`mjrft.models.rigs`): at every sample the rig writes the
exact ``qpos``/``qvel`` of its path, recomputes the kinematics (``mj_fwdPosition``,
``mj_fwdVelocity``) and calls :meth:`GranularTerrain.compute` with the time since the previous sample,
so the force is the terrain's own force on the moving body, nothing is integrated, and the path is
exact at any sample spacing (the elements' rest-regularisation memory advances by the exact travel
of each sample, see docs/numerics.md, "Rest regularisation"). The first ``yield_displacement`` (1 mm) or so of travel
after an element enters the grains is the grains loading up; after that the force is the law's.
The stability check of the terrain is irrelevant here (no dynamics) and its warning is silenced.

Plate intruder (:func:`plate_intrusion`)
----------------------------------------
A plate ``length`` (in the plane of motion) x ``width`` x ``thickness`` at attack angle ``beta``
moves in a straight line at intrusion angle ``gamma`` (Li 2013's angles, radians: the plate's faces
have normals +-(sin beta, 0, -cos beta); the motion is (cos gamma, 0, -sin gamma), gamma = pi/2
straight down, -pi/2 straight up, 0 along +x) at ``speed``. ``depth`` is always the deepest point of
the path, measured at the plate's centre (Li's |z| is the depth of each element's centre; for a
thin horizontal plate the centre is its bottom face):

* going down (sin gamma > 0): the path ends with the centre at ``depth`` and starts where the
  plate's lowest point touches the surface (or ``distance`` before the end);
* going up (sin gamma < 0): it starts with the centre at ``depth`` and ends when the plate has just
  left the grains (or after ``distance``);
* horizontal (gamma = 0 or pi): at ``depth`` for ``distance`` (default three plate lengths).

Outputs per sample: ``depth`` of the centre, ``lift`` = F_z (grains on plate, up positive),
``drag`` = the force against the horizontal part of the motion (-F_x when moving toward +x or
straight up/down, +F_x when moving toward -x), ``torque`` = torque about +y through the plate
centre (N m).

Rotating leg (:func:`rotating_leg`)
-----------------------------------
A leg on an axle ``axle_height`` above the surface turns at constant ``omega`` (rad/s) from leg angle
``start`` to ``stop`` (radians from straight down, positive = tip swung toward -x; default Li's
-3pi/4 .. 3pi/4 at 0.2 rad/s). Shapes and defaults: :mod:`mjrft.models.rigs`. Outputs per angle:
``forward`` = F_x (thrust when the buried part sweeps backward), ``support`` = F_z, ``torque`` = the
drive torque about the axle that the grains resist, -(sum r x F)_y (positive = resisting when
omega > 0, the convention of :func:`mjrft.laws.hybrid.rotating_leg_profile`), ``depth`` = deepest
point of the leg below the surface.

The ``hybrid`` law (per element, :mod:`mjrft.laws.hybrid`) needs the leg's width and the stroke's
maximum penetration depth Delta d (its density correction): unless the medium already carries
``hybrid_width`` / ``hybrid_max_depth``, the rigs add the leg's (plate's) width and, for the leg, the
deepest any point of the leg reaches over a turn (``settings["stroke_depth"]``: its largest distance
from the axle minus the axle height, whatever ``start``/``stop`` cover), for the plate the deepest
point of its path. The undisturbed-grain (shadow) rule of the whole-leg model is not a function of one
element's inputs (:mod:`mjrft.laws.hybrid`, item 3): without a ground memory the part of a bent leg
(b > sqrt(2) a) that moves into its own wake pushes here and not in
:func:`~mjrft.laws.hybrid.rotating_leg_profile` (``mjrft validate --case hybrid_leg_family`` measures the
difference); with ``ground_memory=True`` (``--ground-memory``) the memory's wake applies the rule per element
(:func:`mjrft.ground.in_wake`; ``mjrft validate --case hybrid_leg_family_memory``).
"""

from __future__ import annotations

import csv
import dataclasses
import math
import os
import warnings
from dataclasses import dataclass, field

import mujoco
import numpy as np

from mjrft.coupler import GranularTerrain
from mjrft.errors import TerrainStabilityWarning, check_finite, check_positive, unknown
from mjrft.laws import law_id
from mjrft.media import MEDIA, Medium, get_medium

from .outputs import number, output_dir

__all__ = ["LegProfile", "PlateProfile", "plate_intrusion", "plot_leg", "plot_plate", "rotating_leg",
           "rotating_leg_family", "write_csv", "add_arguments", "main"]

DEFAULT_RESOLUTION = 0.0025  # m: 15 x 10 elements on Li's plate face
DEFAULT_STEP = 5e-4  # m of plate travel per sample (half the default yield displacement)
DEFAULT_DTHETA = 0.005  # rad per sample (0.5 mm at 10 cm from the axle)
LI_LEG_OMEGA = 0.2  # rad/s (Li 2013)
LI_LEG_SWEEP = (-3 * math.pi / 4, 3 * math.pi / 4)
MAX_SAMPLES = 200_000
_HORIZONTAL = 1e-9  # |sin gamma| below this is a horizontal drag


@dataclass(frozen=True)
class PlateProfile:
    """Forces on the plate along its path (one entry per sample, SI units; see the module docstring)."""

    time: np.ndarray  # s
    travel: np.ndarray  # m along the path
    x: np.ndarray  # m, plate centre
    depth: np.ndarray  # m, plate centre below the surface (negative above)
    lift: np.ndarray  # N, F_z
    drag: np.ndarray  # N, against the horizontal part of the motion
    torque: np.ndarray  # N m, about +y through the plate centre
    settings: dict = field(default_factory=dict)
    label: str = "plate"

    columns = ("time", "travel", "x", "depth", "lift", "drag", "torque")


@dataclass(frozen=True)
class LegProfile:
    """Forces on the rotating leg against leg angle (one entry per sample, SI units, radians)."""

    angle: np.ndarray  # rad from straight down
    time: np.ndarray  # s
    depth: np.ndarray  # m, deepest point of the leg below the surface (0 when clear)
    forward: np.ndarray  # N, F_x
    support: np.ndarray  # N, F_z
    torque: np.ndarray  # N m, drive torque about the axle resisted by the grains
    settings: dict = field(default_factory=dict)
    label: str = "leg"

    columns = ("angle", "time", "depth", "forward", "support", "torque")


# ------------------------------------------------------------------------------------------------
# shared machinery
# ------------------------------------------------------------------------------------------------
def _medium_for(med: Medium, law: str, width: float, max_depth: float) -> Medium:
    """The medium (looked up and checked with the law by the rig's first lines), with the hybrid law's leg width and
    stroke depth added when it needs them."""
    if law == "hybrid":
        extra = {}
        if med.get("hybrid_width") is None:
            extra["hybrid_width"] = width
        if med.get("hybrid_max_depth") is None:
            extra["hybrid_max_depth"] = max(0.0, max_depth)
        if extra:
            med = med.with_extra(**extra)
    return med


def _xml_medium_name(medium) -> str:
    return medium.name if isinstance(medium, Medium) else str(medium)


def _samples(length: float, step: float, what: str) -> int:
    n = int(math.ceil(length / step - 1e-9)) + 1
    if n > MAX_SAMPLES:
        raise ValueError(f"{what}: {n} samples exceed the limit of {MAX_SAMPLES}; use a larger step")
    return max(n, 2)


def _sweep(model, terrain, body: int, qpos: np.ndarray, qvel: np.ndarray, times: np.ndarray, observer=None):
    """Prescribe (qpos, qvel) at each time, evaluate the terrain (then ``observer(terrain, data)``, if given); returns
    wrench rows (n, 6) and CoMs (n, 3)."""
    data = mujoco.MjData(model)
    n = len(times)
    wrench = np.empty((n, 6))
    com = np.empty((n, 3))
    dt0 = times[1] - times[0] if n > 1 else 0.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TerrainStabilityWarning)
        for i in range(n):
            data.time = times[i]
            data.qpos[:] = qpos[i]
            data.qvel[:] = qvel[i]
            mujoco.mj_fwdPosition(model, data)
            mujoco.mj_fwdVelocity(model, data)
            terrain.compute(data, times[i] - times[i - 1] if i else dt0)
            wrench[i] = terrain.wrench[body]
            com[i] = data.xipos[body]
            if observer is not None:
                observer(terrain, data)
    return wrench, com


def _ground_options(ground_memory, med: Medium, law: str):
    """``ground_memory`` as given, except ``True`` under the hybrid law on a medium that carries no angle of repose
    (:func:`mjrft.ground.packing_of`): the memory's defaults with the law's internal friction angle ``hybrid_phi`` as
    the angle of repose (about equal for a cohesionless sand; the hybrid paper gives neither for its river sand)."""
    if ground_memory is True and law == "hybrid":
        from mjrft.ground import GroundOptions, packing_of
        from mjrft.laws.hybrid import hybrid_constants

        try:
            packing_of(med)
        except ValueError:
            return GroundOptions(repose_angle=math.degrees(hybrid_constants(med)["hybrid_phi"]))
    return ground_memory


def _terrain(model, medium, law, resolution, surface, yield_displacement, body_name, ground_memory=False):
    ground_memory = _ground_options(ground_memory, medium, law)
    return GranularTerrain(model, medium, law, bodies=[body_name], surface=surface, resolution=resolution,
                           yield_displacement=yield_displacement, ground_memory=ground_memory)


# ------------------------------------------------------------------------------------------------
# plate intruder
# ------------------------------------------------------------------------------------------------
def plate_intrusion(*, beta: float = 0.0, gamma: float = math.pi / 2, speed: float = 0.01, depth: float = 0.076,
                    distance: float | None = None, length: float | None = None, width: float | None = None,
                    thickness: float | None = None, medium="poppy_cp", law: str = "rft",
                    resolution: float = DEFAULT_RESOLUTION, step: float = DEFAULT_STEP, surface: float = 0.0,
                    yield_displacement: float | None = None, ground_memory=False) -> PlateProfile:
    """Run the plate intruder along its straight path (module docstring); angles in radians, SI units.

    Defaults: Li 2013's plate (3.81 x 2.54 x 0.64 cm) pushed straight down at 1 cm/s to 7.6 cm.
    ``step`` is the travel between samples (m); ``resolution`` the element size (m); ``ground_memory`` as
    :func:`rotating_leg`'s.
    """
    from mjrft.models.rigs import PLATE_LENGTH, PLATE_THICKNESS, PLATE_WIDTH, plate_rig_xml

    length = check_positive("plate length", PLATE_LENGTH if length is None else length)
    width = check_positive("plate width", PLATE_WIDTH if width is None else width)
    thickness = check_positive("plate thickness", PLATE_THICKNESS if thickness is None else thickness)
    beta = check_finite("beta", beta)
    gamma = check_finite("gamma", gamma)
    speed = check_positive("speed", speed)
    depth = check_positive("depth", depth)
    step = check_positive("step", step)
    surface = check_finite("surface", surface)
    resolution = check_positive("resolution", resolution)
    med = get_medium(medium)
    law_id(law)

    sb, cb = math.sin(beta), math.cos(beta)
    half_z = 0.5 * (length * abs(sb) + thickness * abs(cb))  # half the plate's vertical extent
    u = np.array([math.cos(gamma), -math.sin(gamma)])  # (x, z) direction of motion
    sg = math.sin(gamma)
    if sg > _HORIZONTAL:
        kind = "down"
        dist = (depth + half_z) / sg if distance is None else check_positive("distance", distance)
        end = np.array([0.0, surface - depth])
        start = end - dist * u
    elif sg < -_HORIZONTAL:
        kind = "up"
        dist = (depth + half_z) / -sg if distance is None else check_positive("distance", distance)
        start = np.array([0.0, surface - depth])
    else:
        kind = "horizontal"
        dist = 3.0 * length if distance is None else check_positive("distance", distance)
        start = np.array([0.0, surface - depth])
    n = _samples(dist, step, "plate path")
    s = np.linspace(0.0, dist, n)
    centre = start[None, :] + s[:, None] * u[None, :]
    times = s / speed
    max_depth = float(np.max(surface - centre[:, 1])) + half_z  # deepest point of the plate surface

    med = _medium_for(med, law, width, max_depth)
    model = mujoco.MjModel.from_xml_string(plate_rig_xml(length, width, thickness, medium=_xml_medium_name(med),
                                                         law=law, resolution=resolution, surface=surface))
    body = model.body("plate").id
    x0, _, z0 = model.body_pos[body]
    qpos = np.column_stack([centre[:, 0] - x0, centre[:, 1] - z0, np.full(n, beta)])
    qvel = np.tile([speed * u[0], speed * u[1], 0.0], (n, 1))
    terrain = _terrain(model, med, law, resolution, surface, yield_displacement, "plate", ground_memory)
    wrench, _ = _sweep(model, terrain, body, qpos, qvel, times)

    h = -1.0 if u[0] < -_HORIZONTAL else 1.0  # horizontal direction the drag opposes
    settings = {"rig": "plate", "path": kind, "beta": beta, "gamma": gamma, "speed": speed, "depth": depth,
                "distance": dist, "length": length, "width": width, "thickness": thickness,
                "medium": med.name, "law": law, "resolution": resolution, "step": step, "surface": surface,
                "yield_displacement": terrain.yield_displacement, "elements": terrain.n_elements,
                "ground_memory": terrain.ground_memory, "area": length * width}
    label = f"beta {math.degrees(beta):g} deg, gamma {math.degrees(gamma):g} deg"
    return PlateProfile(time=times, travel=s, x=centre[:, 0], depth=surface - centre[:, 1], lift=wrench[:, 2].copy(),
                        drag=-h * wrench[:, 0], torque=wrench[:, 4].copy(), settings=settings, label=label)


# ------------------------------------------------------------------------------------------------
# rotating leg
# ------------------------------------------------------------------------------------------------
def _leg_depths(corners: np.ndarray, angles: np.ndarray, z_axle: float, surface: float) -> np.ndarray:
    """Deepest point (m, >= 0) of the leg (box corners in the leg frame) at each leg angle."""
    s, c = np.sin(angles)[:, None], np.cos(angles)[:, None]
    z = z_axle - s * corners[None, :, 0] + c * corners[None, :, 2]
    return np.maximum(surface - z.min(axis=1), 0.0)


def rotating_leg(shape: str = "c", *, omega: float | None = None, start: float = LI_LEG_SWEEP[0],
                 stop: float = LI_LEG_SWEEP[1], dtheta: float = DEFAULT_DTHETA, axle_height: float | None = None,
                 medium="poppy_cp", law: str = "rft", resolution: float = DEFAULT_RESOLUTION, surface: float = 0.0,
                 yield_displacement: float | None = None, ground_memory=False, observer=None, **leg) -> LegProfile:
    """Run the rotating-leg rig (module docstring); angles in radians, SI units.

    ``shape``: ``"flat"``, ``"c"``, ``"reversed_c"``, ``"semi_ellipse"``, ``"v_section"`` or
    ``"triangle_section"``; ``**leg``: ``chord``,
    ``curvature``, ``a``, ``b``, ``bulge``, ``width``, ``thickness``, ``n_segments``
    (:func:`mjrft.models.rigs.leg_geometry`). ``omega`` (rad/s, non-zero; default 0.2, Li 2013)
    turns the leg from ``start`` to ``stop``, which must lie in the direction of ``omega``;
    ``dtheta`` is the angle between samples; ``axle_height`` defaults per shape (2 cm, or 5 cm for
    ``semi_ellipse``). ``ground_memory``: as :class:`~mjrft.coupler.GranularTerrain`'s (the sand remembers the
    leg's hole, the ridges it heaps and, under the hybrid law, the wake its leading faces leave; default off).
    ``True`` under the hybrid law on a medium without an angle of repose takes the law's friction angle
    ``hybrid_phi`` for it. ``observer(terrain, data)``: called after each sample's evaluation (the terrain's
    per-element outputs and state are then the sample's).
    """
    from mjrft.models.rigs import default_axle_height, leg_geometry, leg_rig_xml

    geo = leg_geometry(shape, **leg)
    omega = LI_LEG_OMEGA if omega is None else check_finite("omega", omega)
    if omega == 0:
        raise ValueError("omega must be non-zero (rad/s), got 0")
    start = check_finite("start", start)
    stop = check_finite("stop", stop)
    if (stop - start) * omega <= 0:
        raise ValueError(f"stop ({stop!r} rad) must lie beyond start ({start!r} rad) in the direction of omega "
                         f"({omega!r} rad/s)")
    dtheta = check_positive("dtheta", dtheta)
    h = default_axle_height(shape) if axle_height is None else check_positive("axle_height", axle_height)
    surface = check_finite("surface", surface)
    resolution = check_positive("resolution", resolution)
    med = get_medium(medium)
    law_id(law)

    n = _samples(abs(stop - start), dtheta, "leg sweep")
    angles = np.linspace(start, stop, n)
    times = (angles - start) / omega
    z_axle = surface + h
    depth = _leg_depths(geo["vertices"], angles, z_axle, surface)
    # the hybrid law's Delta d: the deepest the leg reaches over a turn, whatever the sweep covers
    stroke = max(0.0, float(np.max(np.hypot(geo["vertices"][:, 0], geo["vertices"][:, 2]))) - h)
    med = _medium_for(med, law, geo["width"], stroke)
    model = mujoco.MjModel.from_xml_string(leg_rig_xml(shape, axle_height=h, medium=_xml_medium_name(med), law=law,
                                                       resolution=resolution, surface=surface, **leg))
    body = model.body("leg").id
    terrain = _terrain(model, med, law, resolution, surface, yield_displacement, "leg", ground_memory)
    wrench, com = _sweep(model, terrain, body, angles[:, None], np.full((n, 1), omega), times, observer)

    force = wrench[:, :3]
    r = com - np.array([0.0, 0.0, z_axle])[None, :]
    tau_axle = wrench[:, 3:] + np.cross(r, force)
    settings = {"rig": "leg", "shape": shape, "omega": omega, "start": start, "stop": stop, "dtheta": dtheta,
                "axle_height": h, "medium": med.name, "law": law, "resolution": resolution, "surface": surface,
                "yield_displacement": terrain.yield_displacement, "elements": terrain.n_elements,
                "ground_memory": terrain.ground_memory, "max_depth": float(depth.max()), "stroke_depth": stroke, "width": geo["width"],
                "thickness": geo["thickness"],
                "length": geo["length"]}
    for key in ("chord", "curvature", "a", "b", "bulge"):
        if key in geo:
            settings[key] = geo[key]
    if shape == "semi_ellipse":
        label = f"semi-ellipse a {geo['a'] * 100:g} cm, b {geo['b'] * 100:.3g} cm"
    else:
        label = {"flat": "flat", "c": "C-leg", "reversed_c": "reversed C-leg", "v_section": "V-section leg",
                 "triangle_section": "triangle-section leg", "propeller": "propeller-leg"}[shape]
    return LegProfile(angle=angles, time=times, depth=depth, forward=force[:, 0].copy(), support=force[:, 2].copy(),
                      torque=0.0 - tau_axle[:, 1], settings=settings, label=label)


def rotating_leg_family(a: float | None = None, **kw) -> dict[str, LegProfile]:
    """:func:`rotating_leg` for each of the hybrid paper's five semi-elliptic legs (a fixed, default
    4.5 cm; b = a/9 ... 2a, :func:`mjrft.geometry.curved_leg.semi_ellipse_family`), by name."""
    from mjrft.geometry.curved_leg import semi_ellipse_family

    if "shape" in kw or "b" in kw:
        raise ValueError("rotating_leg_family sets the shape ('semi_ellipse') and b itself")
    out = {}
    for name, (aa, bb) in semi_ellipse_family(a).items():
        p = rotating_leg("semi_ellipse", a=aa, b=bb, **kw)
        out[name] = dataclasses.replace(p, label=f"{name} (a/b = {aa / bb:.3g})")
    return out


# ------------------------------------------------------------------------------------------------
# output: CSV and plots
# ------------------------------------------------------------------------------------------------
def _as_dict(profiles) -> dict:
    if isinstance(profiles, (PlateProfile, LegProfile)):
        return {profiles.label: profiles}
    if isinstance(profiles, dict) and profiles and all(isinstance(p, (PlateProfile, LegProfile))
                                                        for p in profiles.values()):
        return profiles
    raise TypeError("expected a PlateProfile, a LegProfile or a non-empty dict of them")


def write_csv(profiles, path) -> str:
    """Write one profile or a dict of them (long format: a ``label`` column, then the profile's
    columns in SI units and radians) to ``path``; returns the path."""
    profs = _as_dict(profiles)
    kinds = {type(p) for p in profs.values()}
    if len(kinds) != 1:
        raise TypeError("write_csv: cannot mix plate and leg profiles in one file")
    cols = next(iter(profs.values())).columns
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["label", *cols])
        for p in profs.values():
            arrays = [getattr(p, c) for c in cols]
            for row in zip(*arrays):
                w.writerow([p.label, *(f"{float(v):.9g}" for v in row)])
        f.flush()
    return str(path)


def _figure(nrows):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.0, 2.4 * nrows), constrained_layout=True)
    FigureCanvasAgg(fig)
    return fig, fig.subplots(nrows, 1, sharex=True)


def _title(s: dict) -> str:
    return f"{s.get('medium', '?')}, law {s.get('law', '?')}, elements {s.get('resolution', 0) * 1000:g} mm"


def _plot_three(profs: dict, path, kind, x_of, series_of, names, xlabel: str, title: str) -> str:
    """Three stacked panels (``names``) of ``series_of(p)`` against ``x_of(p)``, one line per profile."""
    if not all(isinstance(p, kind) for p in profs.values()):
        raise TypeError(f"expected {kind.__name__} objects")
    fig, ax = _figure(3)
    for p in profs.values():
        for a, y in zip(ax, series_of(p)):
            a.plot(x_of(p), y, label=p.label)
    for a, name in zip(ax, names):
        a.set_ylabel(name)
        a.axhline(0.0, color="0.7", lw=0.8)
        a.grid(alpha=0.3)
    ax[-1].set_xlabel(xlabel)
    ax[0].legend(fontsize=8)
    ax[0].set_title(f"{title}; {_title(next(iter(profs.values())).settings)}", fontsize=9)
    fig.savefig(path, dpi=110)
    return str(path)


def plot_plate(profiles, path) -> str:
    """PNG of lift, drag and torque against plate-centre depth (against travel for horizontal drags);
    one profile or a dict of them overlaid. Returns the path."""
    profs = _as_dict(profiles)
    horizontal = all(isinstance(p, PlateProfile) and p.settings.get("path") == "horizontal" for p in profs.values())
    first = next(iter(profs.values())).settings
    return _plot_three(profs, path, PlateProfile, lambda p: (p.travel if horizontal else p.depth) * 100,
                       lambda p: (p.lift, p.drag, p.torque * 1000),
                       ("lift F_z (N)", "drag (N)", "torque about +y (N mm)"),
                       "travel (cm)" if horizontal else "plate centre depth (cm)",
                       f"plate {first.get('length', 0) * 100:g} x {first.get('width', 0) * 100:g} cm, "
                       f"{first.get('speed', 0) * 100:g} cm/s")


def plot_leg(profiles, path) -> str:
    """PNG of forward force, support force and drive torque against leg angle (degrees); one profile
    or a dict of them overlaid. Returns the path."""
    profs = _as_dict(profiles)
    first = next(iter(profs.values())).settings
    return _plot_three(profs, path, LegProfile, lambda p: np.degrees(p.angle),
                       lambda p: (p.forward, p.support, p.torque * 1000),
                       ("forward F_x (N)", "support F_z (N)", "drive torque (N mm)"),
                       "leg angle from straight down (deg; + = tip swung backward)",
                       f"axle {first.get('axle_height', 0) * 100:g} cm above the surface, "
                       f"omega {first.get('omega', 0):g} rad/s")


# ------------------------------------------------------------------------------------------------
# command line: mjrft rig plate|leg
# ------------------------------------------------------------------------------------------------
def add_arguments(parser) -> None:
    sub = parser.add_subparsers(dest="rig", required=True, metavar="RIG")
    common = dict(medium=("poppy_cp", f"medium name ({', '.join(sorted(MEDIA))})"),
                  law=("rft", "force law (mjrft.laws.LAW_IDS)"))

    def shared(p, resolution_help):
        p.add_argument("--medium", default=common["medium"][0], help=common["medium"][1])
        p.add_argument("--law", default=common["law"][0], help=common["law"][1])
        p.add_argument("--resolution", type=float, default=DEFAULT_RESOLUTION, help=resolution_help)
        p.add_argument("--ground-memory", action="store_true",
                       help="the sand remembers the rig's footprint, ridges and (hybrid law) wake (default off)")
        p.add_argument("--out", default="rig_output", help="output folder for the CSV and PNG (created)")

    p = sub.add_parser("plate", help="plate intruder: lift, drag and torque against depth",
                       description="Plate intruder (Li 2013 rig). Angles in DEGREES; lengths in m.")
    p.add_argument("--beta", type=float, nargs="+", default=[0.0], help="attack angle(s), degrees (default 0)")
    p.add_argument("--gamma", type=float, nargs="+", default=[90.0],
                   help="intrusion angle(s), degrees; 90 = straight down, 0 = horizontal toward +x (default 90)")
    p.add_argument("--speed", type=float, default=0.01, help="m/s (default 0.01)")
    p.add_argument("--depth", type=float, default=0.076, help="deepest plate-centre depth of the path, m")
    p.add_argument("--distance", type=float, default=None, help="path length, m (default: see mjrft.tools.rigs)")
    p.add_argument("--length", type=float, default=None, help="plate length in the plane of motion, m (0.0381)")
    p.add_argument("--width", type=float, default=None, help="plate width across the plane of motion, m (0.0254)")
    p.add_argument("--thickness", type=float, default=None, help="plate thickness, m (0.0064)")
    p.add_argument("--step", type=float, default=DEFAULT_STEP, help="travel between samples, m")
    shared(p, "element size, m")

    q = sub.add_parser("leg", help="rotating leg: forward force, support force and torque against angle",
                       description="Rotating-leg rig (Li 2013 / hybrid paper). Angles in DEGREES; lengths in m.")
    q.add_argument("--shape", default="c", help="flat, c, reversed_c, semi_ellipse, or family (the hybrid "
                                                "paper's five semi-elliptic legs)")
    q.add_argument("--chord", type=float, default=None, help="hip-to-tip length, m (flat/c/reversed_c; 0.0762)")
    q.add_argument("--curvature", type=float, default=None, help="|1/r|, 1/m (c/reversed_c; default 2/chord)")
    q.add_argument("--a", type=float, default=None, help="semi-axis along the leg, m (semi_ellipse/family; 0.045)")
    q.add_argument("--b", type=float, default=None, help="semi-axis across the leg, m (semi_ellipse; 0.045)")
    q.add_argument("--bulge", type=int, default=1, help="+1 convex side leading (default), -1 trailing")
    q.add_argument("--width", type=float, default=None, help="leg width along the axle, m (0.0254)")
    q.add_argument("--thickness", type=float, default=None, help="leg thickness, m (0.0064)")
    q.add_argument("--axle-height", type=float, default=None, help="m above the surface (0.02; 0.05 semi-ellipse)")
    q.add_argument("--omega", type=float, default=None, help="rad/s (default 0.2)")
    q.add_argument("--start", type=float, default=-135.0, help="first leg angle, degrees (default -135)")
    q.add_argument("--stop", type=float, default=135.0, help="last leg angle, degrees (default 135)")
    q.add_argument("--dtheta", type=float, default=math.degrees(DEFAULT_DTHETA), help="degrees between samples")
    shared(q, "element size, m")


def _leg_kwargs(args) -> dict:
    kw = {}
    for key in ("chord", "curvature", "a", "b", "width", "thickness"):
        v = getattr(args, key)
        if v is not None:
            kw[key] = v
    if args.shape in ("semi_ellipse", "family"):
        kw["bulge"] = args.bulge
    elif args.bulge != 1:
        raise ValueError("--bulge applies to --shape semi_ellipse or family only")
    return kw


def main(args) -> int:
    output_dir(args.out)
    if args.rig == "plate":
        profs = {}
        for b in args.beta:
            for g in args.gamma:
                p = plate_intrusion(beta=math.radians(b), gamma=math.radians(g), speed=args.speed, depth=args.depth,
                                    distance=args.distance, length=args.length, width=args.width,
                                    thickness=args.thickness, medium=args.medium, law=args.law,
                                    resolution=args.resolution, step=args.step, ground_memory=args.ground_memory)
                profs[p.label] = p
        stem = "plate" if len(profs) > 1 else f"plate_beta{args.beta[0]:g}_gamma{args.gamma[0]:g}"
        csv_path = write_csv(profs, os.path.join(args.out, stem + ".csv"))
        png_path = plot_plate(profs, os.path.join(args.out, stem + ".png"))
        for p in profs.values():
            i = int(np.argmax(p.depth))
            scale = max(abs(p.lift[i]), abs(p.drag[i]))  # forces below round-off of the larger one print as 0
            print(f"{p.label}: at depth {p.depth[i] * 100:.2f} cm lift {number(p.lift[i], scale=scale)} N, "
                  f"drag {number(p.drag[i], scale=scale)} N, torque {number(p.torque[i] * 1000, scale=scale * 1000)} "
                  f"N mm ({len(p.depth)} samples, {p.settings['elements']} elements)")
    elif args.rig == "leg":
        kw = dict(omega=args.omega, start=math.radians(args.start), stop=math.radians(args.stop),
                  dtheta=math.radians(args.dtheta), axle_height=args.axle_height, medium=args.medium, law=args.law,
                  resolution=args.resolution, ground_memory=args.ground_memory, **_leg_kwargs(args))
        if args.shape == "family":
            if args.b is not None:
                raise ValueError("--b is set by the family (b = a / ratio); drop it or use --shape semi_ellipse")
            profs = rotating_leg_family(**kw)
        else:
            from mjrft.models.rigs import LEG_SHAPES

            if args.shape not in LEG_SHAPES:
                raise unknown("leg shape", args.shape, [*LEG_SHAPES, "family"])
            p = rotating_leg(args.shape, **kw)
            profs = {p.label: p}
        stem = f"leg_{args.shape}"
        csv_path = write_csv(profs, os.path.join(args.out, stem + ".csv"))
        png_path = plot_leg(profs, os.path.join(args.out, stem + ".png"))
        for p in profs.values():
            scale = max(np.abs(p.forward).max(), np.abs(p.support).max())
            print(f"{p.label}: peak forward {number(p.forward.max(), scale=scale)} N, peak support "
                  f"{number(p.support.max(), scale=scale)} N, peak torque {number(p.torque.max() * 1000)} N mm, "
                  f"max depth {p.depth.max() * 100:.2f} cm "
                  f"({len(p.angle)} angles, {p.settings['elements']} elements)")
    else:  # argparse enforces the choice; kept for direct calls
        raise unknown("rig", args.rig, ["leg", "plate"])
    print(f"wrote {csv_path}")
    print(f"wrote {png_path}")
    return 0

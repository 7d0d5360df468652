"""Measurement rigs (plate intruder, rotating leg), semi-elliptic legs and closed leg meshes."""

import csv
import math

import mujoco
import numpy as np
import pytest

import mjrft
from mjrft.tools import rigs
from mjrft.tools.cli import main as cli_main
from mjrft.geometry import geom_elements
from mjrft.geometry.curved_leg import (arc_length, arc_points, curved_leg_boxes, curved_leg_mesh, leg_mesh,
                                       semi_ellipse_boxes, semi_ellipse_family, semi_ellipse_length,
                                       semi_ellipse_mesh, semi_ellipse_points)
from mjrft.laws.hybrid import LEG_A, LEG_FAMILY, G, HybridModel, rotating_leg_profile, semi_ellipse_leg
from mjrft.models import MODEL_NAMES, model_path
from mjrft.models.rigs import LEG_SHAPES, default_axle_height, PLATE_LENGTH, PLATE_THICKNESS, PLATE_WIDTH, leg_rig_model

COARSE = dict(resolution=0.005)
LEG_FAST = dict(resolution=0.005, dtheta=0.03)
AREA = PLATE_LENGTH * PLATE_WIDTH


# ----------------------------------------------------------------- semi-elliptic legs and meshes
def test_semicircle_semi_ellipse_is_the_c_leg():
    chord = 0.041
    for sign in (1, -1):
        c_leg = curved_leg_boxes(chord, sign * 2 / chord, 0.01, 0.003, 8)
        ellipse = semi_ellipse_boxes(chord / 2, sign * chord / 2, 0.01, 0.003, 8)
        for x, y in zip(c_leg, ellipse):
            for key in ("pos", "quat", "size"):
                np.testing.assert_allclose(x[key], y[key], atol=1e-8)


def test_semi_ellipse_points_and_length():
    a, b = 0.045, 0.09
    p = semi_ellipse_points(a, b, 40)
    np.testing.assert_allclose(p[0], 0, atol=1e-15)
    np.testing.assert_allclose(p[-1], [0, 0, -2 * a], atol=1e-15)
    # b > 0 bows toward -x like the C-leg (convention: mjrft.geometry.curved_leg)
    assert np.all(p[:, 1] == 0) and np.all(p[:, 0] <= 0) and -p[:, 0].min() == pytest.approx(b, rel=1e-3)
    # on the ellipse, equal arc-length pieces (chords of equal arcs differ only by curvature)
    np.testing.assert_allclose((p[:, 0] / b) ** 2 + ((p[:, 2] + a) / a) ** 2, 1.0, atol=1e-9)
    pieces = np.linalg.norm(np.diff(p, axis=0), axis=1)
    assert pieces.max() / pieces.min() < 1.01
    # half perimeters: semicircle pi a; a/b = 0.5 against the complete elliptic integral E(m = 3/4)
    assert semi_ellipse_length(a, a) == pytest.approx(math.pi * a, rel=1e-8)
    assert semi_ellipse_length(a, b) == pytest.approx(2 * b * 1.2110560275684595, rel=1e-8)
    assert semi_ellipse_length(a, 0.0) == pytest.approx(2 * a, rel=1e-9)  # b = 0: straight bar
    np.testing.assert_allclose(semi_ellipse_points(a, -b, 8)[:, 0], -semi_ellipse_points(a, b, 8)[:, 0])
    assert semi_ellipse_length(a, b) > 2 * a


def test_five_leg_family():
    fam = semi_ellipse_family()
    assert list(fam) == ["straight", "less_straight", "semicircle", "bent", "very_bent"] == list(LEG_FAMILY)
    ratios = [9.0, 2.0, 1.0, 0.67, 0.5]
    for (a, b), r in zip(fam.values(), ratios):
        assert a == LEG_A == 0.045 and a / b == pytest.approx(r)
    assert semi_ellipse_family(0.02)["semicircle"] == (0.02, 0.02)


@pytest.mark.parametrize("mesh, length", [
    (semi_ellipse_mesh(0.045, 0.09, 0.0254, 0.0064, 24), semi_ellipse_length(0.045, 0.09)),
    (curved_leg_mesh(0.0762, 2 / 0.0762, 0.0254, 0.0064, 24), arc_length(0.0762, 2 / 0.0762)),
    (curved_leg_mesh(0.041, -0.6 / 0.0205, 0.01, 0.003, 8), arc_length(0.041, -0.6 / 0.0205)),
])
def test_leg_mesh_is_closed_and_outward(mesh, length):
    v, f = mesh
    w, t = (0.0254, 0.0064) if length > 0.05 else (0.01, 0.003)
    e = geom_elements("mesh", None, 0.004, v, f)
    np.testing.assert_allclose((e.area[:, None] * e.normal).sum(0), 0, atol=1e-12)  # closed
    vol = np.einsum("ij,ij->i", v[f[:, 0]], np.cross(v[f[:, 1]], v[f[:, 2]])).sum() / 6
    assert vol == pytest.approx(length * w * t, rel=5e-3)  # positive: normals point outward
    assert e.area.sum() == pytest.approx(2 * length * (w + t) + 2 * w * t, rel=5e-3)
    xml = (f'<mujoco><asset><mesh name="m" vertex="{" ".join(map(str, v.ravel()))}" '
           f'face="{" ".join(map(str, f.ravel()))}"/></asset><worldbody><body><joint type="hinge"/>'
           '<geom type="mesh" mesh="m" mass="0.01"/></body></worldbody></mujoco>')
    assert mujoco.MjModel.from_xml_string(xml).nmeshface == len(f)


def test_leg_mesh_errors():
    with pytest.raises(ValueError, match="x-z plane"):
        leg_mesh([[0, 0.1, 0], [0, 0, -1]], 0.01, 0.003)
    with pytest.raises(ValueError, match="width"):
        leg_mesh(arc_points(0.04, 0), -0.01, 0.003)
    with pytest.raises(ValueError, match="repeat"):
        leg_mesh([[0, 0, 0], [0, 0, 0]], 0.01, 0.003)
    with pytest.raises(ValueError, match="a must be"):
        semi_ellipse_points(-0.01, 0.01)
    with pytest.raises(ValueError, match="b must be"):
        semi_ellipse_points(0.01, float("nan"))


# ----------------------------------------------------------------- plate intruder
@pytest.mark.parametrize("depth", [0.015, 0.03, 0.05])
def test_horizontal_plate_lift_is_alpha_area_depth(depth):
    """Li RFT is exact for a plate pushed down: F_z = alpha_z(0, pi/2) x area x depth of its bottom face."""
    az = mjrft.get_medium("poppy_cp").alpha_z_down
    p = rigs.plate_intrusion(depth=depth, step=0.001, **COARSE)
    assert p.settings["path"] == "down" and np.all(np.isfinite(p.lift))
    assert p.depth[-1] == pytest.approx(depth) and p.depth[0] == pytest.approx(-PLATE_THICKNESS / 2)
    # bottom face at the centre depth + t/2; the plate's edge faces add ~2 % (edge-on, half weight each)
    assert p.lift[-1] == pytest.approx(az * AREA * (depth + PLATE_THICKNESS / 2), rel=0.03)
    thin = rigs.plate_intrusion(depth=depth, step=0.001, thickness=2e-4, **COARSE)
    assert thin.lift[-1] == pytest.approx(az * AREA * (depth + 1e-4), rel=0.005)
    assert np.all(np.diff(thin.lift) >= -1e-9)  # grows with depth
    np.testing.assert_allclose(p.drag, 0, atol=1e-9)
    np.testing.assert_allclose(p.torque, 0, atol=1e-9)


# the reference table (generic medium, N/cm^3): beta, gamma, alpha_z, alpha_x
TABLE = {
    "pushed down": (0.0, math.pi / 2, 1.000, 0.0),
    "pulled up": (0.0, -math.pi / 2, -0.250, 0.0),
    "vertical dragged": (math.pi / 2, 0.0, 0.037, 0.370),
    "45 forward-down dragged": (math.pi / 4, 0.0, 0.363, 0.341),
    "45 forward-up dragged": (-math.pi / 4, 0.0, 0.049, 0.165),
}


@pytest.mark.parametrize("case", list(TABLE))
def test_plate_signs_and_values_match_the_reference_table(case):
    beta, gamma, az, ax = TABLE[case]
    p = rigs.plate_intrusion(beta=beta, gamma=gamma, depth=0.04, thickness=1e-4, medium="generic", step=0.001,
                             distance=0.02 if gamma >= 0 else None, **COARSE)
    i = -1 if gamma >= 0 else 8  # going up: after 8 mm of travel (the grains' memory has loaded)
    d = p.depth[i]
    assert d > 0.02 and np.all(np.isfinite([p.lift, p.drag, p.torque]))
    scale = 1e6 * AREA * d  # N/cm^3 -> N
    assert np.sign(p.lift[i]) == np.sign(az)
    assert p.lift[i] == pytest.approx(az * scale, rel=0.03)
    if ax:
        assert p.drag[i] > 0  # against the motion
        assert p.drag[i] == pytest.approx(ax * scale, rel=0.03)
    else:
        assert abs(p.drag[i]) < 1e-9


def test_drag_opposes_motion_in_both_directions():
    fwd = rigs.plate_intrusion(beta=math.pi / 2, gamma=0.0, depth=0.04, distance=0.01, step=0.001, **COARSE)
    back = rigs.plate_intrusion(beta=math.pi / 2, gamma=math.pi, depth=0.04, distance=0.01, step=0.001, **COARSE)
    assert fwd.settings["path"] == back.settings["path"] == "horizontal"
    assert fwd.drag[-1] > 1.0 and back.drag[-1] == pytest.approx(fwd.drag[-1], rel=1e-9)
    assert np.all(np.diff(fwd.x) > 0) and np.all(np.diff(back.x) < 0)
    np.testing.assert_allclose(back.torque, -fwd.torque, atol=1e-12)  # mirror images
    np.testing.assert_allclose(fwd.depth, 0.04)
    # the force grows over the first millimetres (the grains load over the yield displacement), then holds
    assert fwd.drag[0] < 0.8 * fwd.drag[-1] and fwd.drag[-2] == pytest.approx(fwd.drag[-1], rel=1e-3)


def test_plate_paths():
    up = rigs.plate_intrusion(gamma=-math.pi / 3, depth=0.02, step=0.002, **COARSE)
    assert up.settings["path"] == "up" and up.depth[0] == pytest.approx(0.02)
    assert up.depth[-1] == pytest.approx(-PLATE_THICKNESS / 2)  # just clear of the grains at the end
    assert up.lift[-1] == 0.0 and np.all(np.isfinite(up.lift))
    down = rigs.plate_intrusion(gamma=math.pi / 6, depth=0.02, speed=0.05, step=0.002, **COARSE)
    assert down.x[-1] - down.x[0] == pytest.approx((0.02 + PLATE_THICKNESS / 2) / math.tan(math.pi / 6))
    assert down.time[-1] == pytest.approx(down.travel[-1] / 0.05)
    assert down.lift[-1] > 0 and down.drag[-1] > 0


# ----------------------------------------------------------------- rotating leg
@pytest.mark.parametrize("shape", LEG_SHAPES)
def test_every_leg_shape_runs_through_the_rig(shape):
    p = rigs.rotating_leg(shape, **LEG_FAST)
    for name in ("angle", "forward", "support", "torque", "depth"):
        assert np.all(np.isfinite(getattr(p, name))), name
    assert p.angle[0] == pytest.approx(-3 * math.pi / 4) and p.angle[-1] == pytest.approx(3 * math.pi / 4)
    buried = p.depth > 0
    assert buried.any() and (~buried).any()
    assert np.all(p.forward[~buried] == 0) and np.all(p.support[~buried] == 0)
    # the buried part sweeps backward: the grains push the leg forward and resist the drive
    assert p.forward.max() > 0.5 and p.forward.min() > -0.05 * p.forward.max()
    assert np.abs(p.support).max() > 0.5
    assert p.torque.max() > 0 and np.trapezoid(p.torque, p.angle) > 0  # work done on the grains
    h = p.settings["axle_height"]
    assert h == default_axle_height(shape)
    assert p.depth.max() >= p.settings["length"] - h  # the tip passes straight down


def _deep_leading_faces(shape, angle, resolution):
    """Area-weighted mean unit normal of the deepest quarter (by depth) of the leg surface that leads at
    ``angle`` when the rig turns at omega > 0 (outward normal . velocity > 0; the side faces excluded)."""
    from mjrft.models.rigs import LI_AXLE_HEIGHT, leg_geometry
    v, f = leg_geometry(shape)["mesh"]
    e = geom_elements("mesh", None, resolution, v, f)
    c, s = math.cos(angle), math.sin(angle)
    rot = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])  # the leg body at qpos = angle (hinge about +y)
    r, n = e.pos @ rot.T, e.normal @ rot.T
    vel = np.cross([0.0, 1.0, 0.0], r)  # omega = +1 about +y, r from the axle
    depth = -(r[:, 2] + LI_AXLE_HEIGHT)
    lead = (np.einsum("ij,ij->i", n, vel) > 0) & (depth > 0) & (np.abs(n[:, 1]) < 0.5)
    deep = lead & (depth >= np.quantile(depth[lead], 0.75))
    return np.average(n[deep], axis=0, weights=e.area[deep])


def test_c_leg_leads_with_its_convex_side_and_lifts_more():
    """The leg curvature convention, pinned physically (mjrft.geometry.curved_leg). At Li 2013's leg rig
    (loosely packed poppy seeds, the medium of its robot runs, Li RFT with the poppy fit), the C-leg
    ('c', positive curvature) turning at omega > 0 leads with its convex side: its deepest leading
    faces look down (and into the motion) all through the stroke, the orientation whose stress pushes
    up hardest, while the reversed C-leg's look up by the time it is deepest (straight down). So the
    C-leg's peak lift is the larger, as Li's supplement says of the robot's legs (larger vertical ground
    reaction forces with C-legs than with reversed C-legs, fig. S14 text); measured here 10.45 vs 3.74 N
    (2.8x) with the default 2.5 mm elements, and the same with these coarse settings."""
    res = LEG_FAST["resolution"]
    c = rigs.rotating_leg("c", medium="poppy_lp", **LEG_FAST)
    rc = rigs.rotating_leg("reversed_c", medium="poppy_lp", **LEG_FAST)
    assert c.settings["curvature"] > 0 > rc.settings["curvature"]
    assert c.support.max() > rc.support.max()
    for angle in c.angle[c.depth > 0.01]:
        assert _deep_leading_faces("c", angle, res)[2] < 0, angle  # looking down
    n_peak = _deep_leading_faces("c", c.angle[np.argmax(c.support)], res)
    assert n_peak[2] < -0.9  # at the peak lift: facing (almost straight) down
    assert _deep_leading_faces("reversed_c", 0.0, res)[2] > 0  # deepest pose: the concave side looks up


def test_c_leg_force_does_not_depend_on_the_mesh_pieces():
    """Curved legs are one closed mesh: no inner faces, so the force converges with n_segments."""
    peaks = [rigs.rotating_leg("c", n_segments=n, **LEG_FAST).forward.max() for n in (12, 48)]
    assert peaks[1] == pytest.approx(peaks[0], rel=0.03)


def test_five_leg_family_runs_through_the_rig():
    fam = rigs.rotating_leg_family(law="hybrid", resolution=0.006, dtheta=0.05)
    assert list(fam) == list(LEG_FAMILY)
    for name, p in fam.items():
        assert p.settings["shape"] == "semi_ellipse" and p.settings["a"] == LEG_A
        for arr in (p.forward, p.support, p.torque):
            assert np.all(np.isfinite(arr)) and np.abs(arr).max() > 0.05, name
        assert p.torque.max() > 0
    assert fam["very_bent"].depth.max() > fam["straight"].depth.max()


def test_hybrid_rig_matches_the_whole_leg_model():
    """Coupler + per-element hybrid law on a thin leg = the whole-leg hybrid model where no element is
    shadowed (a/b = 9 and 1); measured RMS differences 1-3 % of the peak."""
    med = mjrft.get_medium("poppy_cp")
    model = HybridModel(gamma_s=G * med.rho_bulk)
    for ratio in (9.0, 1.0):
        a, b = LEG_A, LEG_A / ratio
        p = rigs.rotating_leg("semi_ellipse", a=a, b=b, thickness=1e-3, law="hybrid", omega=1.0,
                              resolution=0.004, start=-1.6, stop=0.9, dtheta=0.025)
        ref = rotating_leg_profile(semi_ellipse_leg(a, b, 200), 0.05, 1.0, p.angle, model=model,
                                   max_depth=p.settings["max_depth"])
        assert not ref["shadowed"].any()
        for mine, theirs in ((p.forward, ref["F_f"]), (p.support, ref["F_s"]), (p.torque, ref["torque"])):
            peak = np.abs(theirs).max()
            assert peak > (0.01 if theirs is ref["torque"] else 0.1)  # N m / N: the reference is not trivial
            assert np.sqrt(np.mean((mine - theirs) ** 2)) < 0.05 * peak


def test_ground_memory_in_the_rig_gives_the_hybrid_law_its_undisturbed_grain_rule(tmp_path):
    """With ``ground_memory=True`` the very bent leg's parts in its own wake feel nothing (the memory's wake); a medium
    without an angle of repose takes the hybrid law's friction angle for it, under that law only. Control: the same
    rig without the memory, where every buried leading element pushes."""
    from mjrft.ground import GroundOptions
    from mjrft.tools.validation.cases.hybrid import WakeShare

    generic = mjrft.get_medium("generic")
    opts = rigs._ground_options(True, generic, "hybrid")
    assert isinstance(opts, GroundOptions) and opts.repose_angle == pytest.approx(35.0)
    assert rigs._ground_options(True, mjrft.get_medium("poppy_cp"), "hybrid") is True  # its own angle of repose
    assert rigs._ground_options(True, generic, "rft") is True
    with pytest.raises(ValueError, match="angle of repose"):
        rigs.rotating_leg("semi_ellipse", a=LEG_A, b=2 * LEG_A, medium="generic", ground_memory=True, **LEG_FAST)
    shares = {}
    for memory in (True, False):
        share = WakeShare()
        p = rigs.rotating_leg("semi_ellipse", a=LEG_A, b=2 * LEG_A, law="hybrid", medium="generic", omega=1.0,
                              start=-2.36, stop=1.06, resolution=0.006, dtheta=0.05, ground_memory=memory,
                              observer=share)
        assert p.settings["ground_memory"] is memory and len(share.runs) == 1 and len(share.runs[0]) == len(p.angle)
        shares[memory] = share.runs[0][int(np.argmax(p.forward))]
    assert shares[True] > 0.3 and shares[False] == 0.0  # measured 0.48: the part beyond the leg's widest reach


# ----------------------------------------------------------------- output and command line
def test_plots_and_csv(tmp_path):
    p1 = rigs.plate_intrusion(depth=0.02, step=0.002, **COARSE)
    p2 = rigs.plate_intrusion(beta=0.5, depth=0.02, step=0.002, **COARSE)
    leg = rigs.rotating_leg("flat", **LEG_FAST)
    for path in (rigs.plot_plate({"a": p1, "b": p2}, tmp_path / "plate.png"),
                 rigs.plot_plate(rigs.plate_intrusion(gamma=0.0, depth=0.02, distance=0.01, **COARSE),
                                 tmp_path / "drag.png"),
                 rigs.plot_leg(leg, tmp_path / "leg.png")):
        with open(path, "rb") as f:
            data = f.read()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
    rigs.write_csv({"a": p1, "b": p2}, tmp_path / "plate.csv")
    with open(tmp_path / "plate.csv") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["label", *rigs.PlateProfile.columns] and len(rows) == 1 + len(p1.depth) + len(p2.depth)
    assert float(rows[-1][rows[0].index("lift")]) == pytest.approx(p2.lift[-1], rel=1e-8)
    with pytest.raises(TypeError, match="mix"):
        rigs.write_csv({"a": p1, "b": leg}, tmp_path / "x.csv")
    with pytest.raises(TypeError):
        rigs.plot_leg(p1, tmp_path / "x.png")


def test_cli_writes_csv_and_png(tmp_path, capsys):
    out = tmp_path / "out"
    assert cli_main(["rig", "plate", "--beta", "0", "30", "--depth", "0.02", "--step", "0.002",
                     "--resolution", "0.006", "--out", str(out)]) == 0
    assert cli_main(["rig", "leg", "--shape", "semi_ellipse", "--b", "0.03", "--law", "hybrid", "--dtheta", "3",
                     "--resolution", "0.006", "--ground-memory", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    for name in ("plate.csv", "plate.png", "leg_semi_ellipse.csv", "leg_semi_ellipse.png"):
        assert (out / name).stat().st_size > 1000 and str(out / name) in text


@pytest.mark.parametrize("argv, message", [
    (["rig", "leg", "--shape", "oval"], "unknown leg shape 'oval'; valid choices: c, family, flat"),
    (["rig", "plate", "--medium", "mud"], "unknown medium 'mud'; valid choices:"),
    (["rig", "plate", "--law", "magic"], "unknown law 'magic'; valid choices: depth_only"),
    (["rig", "plate", "--width", "-0.01"], "plate width must be finite and > 0"),
    (["rig", "leg", "--shape", "c", "--bulge", "-1"], "--bulge applies"),
])
def test_cli_bad_input(tmp_path, capsys, argv, message):
    with pytest.raises(SystemExit) as err:
        cli_main([*argv, "--out", str(tmp_path)])
    assert err.value.code == 2 and message in capsys.readouterr().err


def test_bad_parameters():
    with pytest.raises(ValueError, match="plate length must be finite and > 0, got -0.02"):
        rigs.plate_intrusion(length=-0.02)
    with pytest.raises(ValueError, match="speed"):
        rigs.plate_intrusion(speed=0)
    with pytest.raises(ValueError, match="depth"):
        rigs.plate_intrusion(depth=-0.01)
    with pytest.raises(ValueError, match="unknown medium 'clay'; valid choices: generic, glass03_cp"):
        rigs.plate_intrusion(medium="clay")
    with pytest.raises(ValueError, match="unknown law 'x'; valid choices: depth_only, hybrid"):
        rigs.rotating_leg("c", law="x")
    with pytest.raises(ValueError, match="unknown leg shape 'zigzag'; valid choices: flat, c, reversed_c"):
        rigs.rotating_leg("zigzag")
    with pytest.raises(ValueError, match="leg width"):
        rigs.rotating_leg("flat", width=-1)
    with pytest.raises(ValueError, match="semi-axis b"):
        rigs.rotating_leg("semi_ellipse", b=0)
    with pytest.raises(ValueError, match="not chord"):
        rigs.rotating_leg("semi_ellipse", chord=0.05)
    with pytest.raises(ValueError, match="semi_ellipse' only"):
        rigs.rotating_leg("c", a=0.05)
    with pytest.raises(ValueError, match="no curvature"):
        rigs.rotating_leg("flat", curvature=10.0)
    with pytest.raises(ValueError, match=r"out of range .* \(0, 26.2467\]"):
        rigs.rotating_leg("c", curvature=30.0)
    with pytest.raises(ValueError, match="bulge"):
        rigs.rotating_leg("semi_ellipse", bulge=0)
    with pytest.raises(ValueError, match="omega must be non-zero"):
        rigs.rotating_leg("c", omega=0)
    with pytest.raises(ValueError, match="direction of omega"):
        rigs.rotating_leg("c", start=1.0, stop=0.0)
    with pytest.raises(ValueError, match="samples exceed"):
        rigs.rotating_leg("c", dtheta=1e-6)


def test_committed_rig_models():
    assert "plate_rig" in MODEL_NAMES and "leg_rig" in MODEL_NAMES
    for name, body in (("plate_rig", "plate"), ("leg_rig", "leg")):
        m = mujoco.MjModel.from_xml_path(model_path(name))
        t = mjrft.GranularTerrain(m)
        assert list(t.body_ids) == [m.body(body).id] and t.medium.name == "poppy_cp" and t.law == "rft"
    m = mujoco.MjModel.from_xml_path(model_path("leg_rig"))
    assert m.qpos0[0] == pytest.approx(math.pi)  # starts pointing up, out of the sand
    d = mujoco.MjData(m)
    d.qpos[0] = 0.0
    mujoco.mj_kinematics(m, d)
    leg = m.body("leg").id
    zmin = min(d.geom_xpos[g][2] for g in range(m.ngeom) if m.geom_bodyid[g] == leg)
    assert zmin < 0  # hanging straight down at qpos = 0 (the mesh centre is below the surface)
    assert leg_rig_model("semi_ellipse", a=0.03, b=0.05).nmesh == 1

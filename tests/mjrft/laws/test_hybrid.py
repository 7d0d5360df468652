"""Hybrid curved-leg model: wedge, bar-drag fit, undisturbed-grain rule, density correction, leg family."""

import math

import numpy as np
import pytest

import mjrft
from mjrft.laws import LAW_IDS, LAWS, hybrid
from mjrft.laws.common import LEAD_EPS
from mjrft.laws.hybrid import (AXLE_HEIGHT, C_PAR_H_FRACTION, C_PAR_RATIO, GAMMA_S, LEG_A, LEG_FAMILY, LEG_WIDTH, PHI, PHI_W, PSI_BREAK,
                               HybridModel, active_angle, c_perp, hybrid_leg_forces, hybrid_stress, leg_family,
                               leg_family_profiles, leg_pose, passive_force, rotating_leg_profile, semi_ellipse_leg,
                               shadowed_elements, stroke_depth, wedge_force, wedge_shape)
from mjrft.laws.registry import parameter_vector

STEP = 0.1 * 1e-3  # one 1 ms step at 0.1 m/s
ANGLES = np.linspace(-3 * math.pi / 4, 3 * math.pi / 4, 121)


def coulomb_kp(phi, delta):
    return math.cos(phi) ** 2 / (math.cos(delta) * (1 - math.sqrt(math.sin(phi + delta) * math.sin(phi)
                                                                   / math.cos(delta))) ** 2)


def test_registered():
    assert LAW_IDS["hybrid"] == 5 and LAWS["hybrid"] is hybrid


def test_wedge_reduces_to_coulomb_passive():
    for phi_d, phiw_d in ((35, 20), (30, 10), (40, 25), (35, 0)):
        phi, phiw = math.radians(phi_d), math.radians(phiw_d)
        w = wedge_force(0.0, 0.02, GAMMA_S, phi, phiw)
        kp_h = 2 * float(w["F_w"]) / (GAMMA_S * 0.02 ** 2)
        assert kp_h == pytest.approx(coulomb_kp(phi, phiw) * math.cos(phiw), rel=1e-8)
    print(f"K_p cos(phi_w) (35, 20 deg) = {2 * float(wedge_force(0.0, 1.0, 1.0)['F_w']):.4f}")


def test_wedge_angles():
    a1 = active_angle(PHI)
    assert math.degrees(a1) == pytest.approx(57.396, abs=1e-3)
    assert math.tan(a1) == pytest.approx(math.tan(PHI) + 1 / (math.cos(PHI) * math.sqrt(2)))
    for h1 in (0.0, 0.01, 0.05, 0.3):
        w = wedge_force(h1, LEG_WIDTH)
        a2 = float(w["a2"])
        assert 0 < a2 < math.pi / 2 - PHI - PHI_W
        pw = float(w["P_w"])
        for da in (1e-3, -1e-3, 0.05, -0.05):
            assert passive_force(a2 + da, h1, LEG_WIDTH) >= pw * (1 - 1e-12)
        der = (passive_force(a2 + 1e-6, h1, LEG_WIDTH) - passive_force(a2 - 1e-6, h1, LEG_WIDTH)) / 2e-6
        assert abs(der) * 0.01 < 1e-6 * pw  # stationary
        assert float(w["F_w"]) == pytest.approx(pw * math.cos(PHI_W))
        assert float(w["W1"]) == pytest.approx(GAMMA_S / 2 * h1 ** 2 / math.tan(a1))
    # a deeper top edge (surcharge: active wedge) always needs more force
    f = wedge_force(np.linspace(0, 0.2, 21), LEG_WIDTH)["F_w"]
    assert np.all(np.diff(f) > 0)


def test_c_perp_depth_table():
    x, g, (g0, g1, g2), err = wedge_shape()
    print(f"G(x) quadratic fit g = ({g0:.4f}, {g1:.4f}, {g2:.4f}), max rel err {err:.2e}")
    assert err < 1e-3
    d = np.linspace(0, 0.5, 2001)
    c = c_perp(d)
    assert c[0] == 0 and np.all(np.diff(c) > 0) and np.all(np.isfinite(c))
    # exact wedge at a few depths (bottom-strip convention)
    for dd in (0.01, LEG_WIDTH, 0.04, 0.3):
        h1, face = max(0.0, dd - LEG_WIDTH), min(dd, LEG_WIDTH)
        assert c_perp(dd) == pytest.approx(float(wedge_force(h1, face)["F_w"]), rel=1e-5)
    # continuous at the surface and at d = W (one step of 0.1 mm changes it by less than 1 %)
    for d0 in (LEG_WIDTH,):
        assert abs(c_perp(d0 + STEP / 2) - c_perp(d0 - STEP / 2)) < 0.01 * c_perp(d0)
    assert c_perp(STEP) < 1e-3 * c_perp(0.03)
    # beyond the table: quadratic fit, no jump at x = 40
    x40 = LEG_WIDTH * 41
    assert c_perp(x40 * (1 + 1e-9)) == pytest.approx(c_perp(x40 * (1 - 1e-9)), rel=1e-3)
    assert np.isfinite(c_perp(1e6))


def test_bar_drag_fit():
    m = HybridModel(c_perp_h_coef=2000.0)
    d = 0.03
    cp = m.c_perp(d)
    assert m.f_perp(math.pi / 2, d) == pytest.approx(cp)
    assert m.f_perp(0.0, d) == pytest.approx(m.c_perp_h(d)) and m.c_perp_h(d) == pytest.approx(2000 * d * LEG_WIDTH)
    psi = np.radians(np.linspace(0, 90, 9001))
    fpar = m.f_par(psi, d)
    assert psi[np.argmax(fpar)] == pytest.approx(PSI_BREAK, abs=1e-3)
    assert fpar.max() == pytest.approx(C_PAR_RATIO * cp)
    assert m.f_par(0.0, d) == pytest.approx(m.c_par_h(d))
    assert m.f_par(math.pi / 2, d) == pytest.approx(0.0, abs=1e-12 * cp)
    assert np.max(np.abs(np.diff(fpar))) < 1e-3 * cp  # continuous at 36 deg
    # default C_par^h: eq. (4)'s two forms, amplitude C_par / cos 36, meeting at 36 deg
    amp = C_PAR_RATIO * cp / math.cos(PSI_BREAK)
    assert m.c_par_h(d) == pytest.approx(C_PAR_H_FRACTION * C_PAR_RATIO * cp)
    reg1 = m.c_par_h(d) + (amp - m.c_par_h(d)) * np.sin(psi)
    reg2 = amp * np.cos(psi)
    np.testing.assert_allclose(fpar, np.where(psi <= PSI_BREAK, reg1, reg2), rtol=1e-12, atol=1e-12 * cp)
    # fig. 3e in words: region I rises slowly, region II falls more rapidly (mean rates)
    i36 = np.argmax(fpar)
    assert (fpar[i36] - fpar[0]) / psi[i36] < (fpar[i36] - fpar[-1]) / (psi[-1] - psi[i36])
    lin = HybridModel(c_par_h_coef=3000.0)
    assert lin.c_par_h(d) == pytest.approx(3000 * d * LEG_WIDTH) and lin.f_par(0.0, d) == pytest.approx(lin.c_par_h(d))
    print(f"C_perp(30 mm) = {cp:.2f} N/m, C_par = {C_PAR_RATIO * cp:.2f} N/m, C_par^h = {m.c_par_h(d):.3f} N/m")


def test_semi_ellipse_leg():
    leg = semi_ellipse_leg(LEG_A, LEG_A, 200)
    assert leg["length"] == pytest.approx(math.pi * LEG_A, rel=1e-9)
    assert leg["dl"].sum() == pytest.approx(leg["length"])
    assert np.allclose(np.linalg.norm(leg["tangents"], axis=1), 1)
    assert np.allclose(np.linalg.norm(leg["points"] - [LEG_A, 0], axis=1), LEG_A, rtol=1e-4)
    a, b = 0.045, 0.005
    t = np.linspace(0, math.pi, 2_000_001)
    spd = np.hypot(a * np.sin(t), b * np.cos(t))
    half_perimeter = float(np.sum(spd[1:] + spd[:-1]) * (t[1] - t[0]) / 2)  # trapezoid, error ~1e-12
    assert semi_ellipse_leg(a, b, 50)["length"] == pytest.approx(half_perimeter, rel=1e-9)
    for bad in ({"a": 0.0, "b": 1.0}, {"a": 1.0, "b": -1.0}, {"a": math.nan, "b": 1.0}):
        with pytest.raises(ValueError, match=next(k for k, v in bad.items() if not v > 0)):
            semi_ellipse_leg(**bad)
    with pytest.raises(ValueError, match="n must"):
        semi_ellipse_leg(1.0, 1.0, 1)


def test_undisturbed_grain_rule_is_the_sign_rule():
    legs = leg_family()
    for name, leg in legs.items():
        for bulge in (1, -1):
            pts, tan = leg_pose(leg, 0.3, AXLE_HEIGHT, bulge)
            axle = np.array([0.0, AXLE_HEIGHT])
            sh = shadowed_elements(pts, axle, 1.0)
            r = pts - axle
            outward = np.sum(tan * r, axis=1) > 0
            if LEG_FAMILY[name] >= 1 / math.sqrt(2):  # b <= sqrt(2) a: distance from the axle is monotonic
                assert outward.all() and not sh.any(), (name, bulge)
            elif bulge == 1:
                # convex side leading: exactly the elements curving back toward the axle
                assert np.count_nonzero(sh != ~outward) <= 1, name
                assert sh.any()
    counts = {k: int(shadowed_elements(leg_pose(v, 0.0)[0], [0, AXLE_HEIGHT]).sum()) for k, v in legs.items()}
    print("shadowed elements (of 100):", counts)


def test_family_runs_and_is_finite():
    prof = leg_family_profiles(ANGLES, omega=5.0)
    assert set(prof) == set(LEG_FAMILY)
    for name, p in prof.items():
        for k in ("F_f", "F_s", "torque", "depth"):
            assert p[k].shape == ANGLES.shape and np.all(np.isfinite(p[k])), (name, k)
        out = p["depth"] == 0
        assert np.all(p["F_f"][out] == 0) and np.all(p["torque"][out] == 0)
        # Delta d is the leg's own deepest reach over a turn (element centres stay just above it)
        assert p["max_depth"] == pytest.approx(stroke_depth(leg_family()[name], AXLE_HEIGHT))
        assert p["depth"].max() <= p["max_depth"] <= p["depth"].max() + 2e-3
    semi = prof["semicircle"]
    # the density correction does not depend on the angles sampled (very bent: deepest at -55 deg)
    vb = leg_family()["very_bent"]
    part = rotating_leg_profile(vb, AXLE_HEIGHT, 5.0, ANGLES[60:62])  # theta = 0 and 2.25 deg only
    assert part["max_depth"] == pytest.approx(prof["very_bent"]["max_depth"]) and part["depth"].max() < 0.041
    np.testing.assert_allclose(part["F_f"], prof["very_bent"]["F_f"][60:62], rtol=1e-12)
    a, b = LEG_A, 2 * LEG_A  # closed form of the largest reach for b > sqrt(2) a: cos t = a^2 / (a^2 - b^2)
    c = a * a / (a * a - b * b)
    reach = math.hypot(a * (1 - c), b * math.sqrt(1 - c * c))
    assert stroke_depth(vb, AXLE_HEIGHT) == pytest.approx(reach - AXLE_HEIGHT, rel=1e-7)
    assert stroke_depth(vb, 0.2) == 0.0
    assert semi["max_depth"] == pytest.approx(2 * LEG_A - AXLE_HEIGHT, abs=2e-4)
    assert semi["k_forward"] == pytest.approx(0.0325 * 40, rel=1e-2)
    assert semi["k_support"] == pytest.approx(0.06 * 40, rel=1e-2)
    # a leg sweeping backward through the sand gets thrust and resists the drive
    st = prof["straight"]
    i0 = np.argmin(np.abs(ANGLES))
    assert st["F_f"][i0] > 0 and st["torque"][i0] > 0
    # omega does not matter with the flat default speed factor; reversing it flips F_f
    slow = rotating_leg_profile(leg_family()["straight"], AXLE_HEIGHT, 1.0, ANGLES)
    np.testing.assert_allclose(slow["F_f"], st["F_f"], rtol=1e-12, atol=1e-15)
    rev = rotating_leg_profile(leg_family()["straight"], AXLE_HEIGHT, -1.0, [0.0])
    assert rev["F_f"][0] == pytest.approx(-st["F_f"][i0], rel=1e-6)
    for name, p in prof.items():
        print(f"{name:14s} peak F_f {p['F_f'].max():7.3f} N  peak F_s {p['F_s'].max():7.3f} N  "
              f"peak torque {p['torque'].max():7.4f} N m  max depth {1000 * p['max_depth']:.1f} mm")


def test_speed_curve_and_density_switch():
    leg = semi_ellipse_leg(LEG_A, LEG_A, 60)
    base = rotating_leg_profile(leg, AXLE_HEIGHT, 2.0, ANGLES)
    doubled = rotating_leg_profile(leg, AXLE_HEIGHT, 2.0, ANGLES, model=HybridModel(speed_curve=[[0.0, 2.0], [1.0, 2.0]]))
    np.testing.assert_allclose(doubled["F_f"], 2 * base["F_f"], rtol=1e-12, atol=1e-15)
    ramp = HybridModel(speed_curve=[(0.01, 0.5), (0.1, 1.0)])
    assert ramp.speed_factor([0.0, 0.055, 10.0]) == pytest.approx([0.5, 0.75, 1.0])
    raw = rotating_leg_profile(leg, AXLE_HEIGHT, 2.0, ANGLES, density_correction=False)
    np.testing.assert_allclose(base["F_f"], raw["F_f"] * base["k_forward"], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(base["F_s"], raw["F_s"] * base["k_support"], rtol=1e-12, atol=1e-15)
    for bad, msg in (([[0.1, 1.0], [0.1, 2.0]], "row 1"), ([[0.1, -1.0]], "row 0"), ([1, 2, 3], "shape"),
                     ([[0.0, math.nan]], "row 0")):
        with pytest.raises(ValueError, match=msg):
            HybridModel(speed_curve=bad)


def test_leg_forces_match_bar_drag_and_per_element_law():
    """A vertical bar dragged horizontally: per metre it feels C_perp(d) (psi = 90 deg)."""
    depths = np.array([0.005, 0.02, 0.03, 0.06])
    pts = np.stack([np.zeros(4), -depths], axis=1)
    tan = np.tile([0.0, 1.0], (4, 1))
    vel = np.tile([-0.1, 0.0], (4, 1))
    res = hybrid_leg_forces(pts, tan, vel, 1.0, density_correction=False)
    np.testing.assert_allclose(res["forces"][:, 0], c_perp(depths), rtol=1e-12)
    assert np.allclose(res["forces"][:, 1], 0) and res["counted"].all()
    p = parameter_vector(mjrft.get_medium("generic"))  # no bulk density: river-sand unit weight
    for d in depths:
        s = hybrid_stress(d, -1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.1, p)
        assert s[0] * LEG_WIDTH == pytest.approx(c_perp(d), rel=2e-3)
    # tangential: a bar sliding along itself feels C_par^h, split over its two faces
    f = hybrid(0.03, [[1.0, 0, 0], [-1.0, 0, 0]], [0, 0, -0.1], 1.0, "generic").sum(axis=0)
    assert f[2] * LEG_WIDTH == pytest.approx(HybridModel().c_par_h(0.03), rel=2e-3)
    # every psi: the per-element law is the bar-drag fit (up to the quadratic C_perp(d) it stores)
    m = HybridModel()
    for psi in np.radians([0.0, 4.5, 20.0, 36.0, 50.0, 89.0, 90.0]):
        for d in (0.01, 0.03, 0.05):
            n_vec = np.array([math.sin(psi), math.cos(psi), 0.0])  # bar face normal; motion along +x
            sx, sy, _ = hybrid_stress(d, *n_vec, 1.0, 0.0, 0.0, 0.1, p)
            t_vec = np.array([math.cos(psi), -math.sin(psi), 0.0])
            fn = -(sx * n_vec[0] + sy * n_vec[1]) * LEG_WIDTH
            ft = -(sx * t_vec[0] + sy * t_vec[1]) * LEG_WIDTH
            lw = min(1.0, 0.5 + math.sin(psi) / (2 * LEAD_EPS))  # smoothed leading-surface weight
            assert fn == pytest.approx(lw * m.f_perp(psi, d), rel=2e-3, abs=1e-9)
            assert ft == pytest.approx(lw * m.f_par(psi, d), rel=2e-3, abs=1e-9)
    # undisturbed mask and the density correction from the deepest element
    masked = hybrid_leg_forces(pts, tan, vel, 1.0, undisturbed=[True, False, True, False], density_correction=False)
    assert masked["F_f"] == pytest.approx(c_perp(depths[[0, 2]]).sum())
    dens = hybrid_leg_forces(pts, tan, vel, 1.0)
    assert dens["k_forward"] == pytest.approx(32.5 * 0.06) and dens["F_f"] == pytest.approx(res["F_f"] * 32.5 * 0.06)


def test_per_element_law_extremes_and_continuity():
    m = mjrft.get_medium("poppy_cp").with_extra(hybrid_max_depth=0.04)
    p = parameter_vector(m)
    for speed in (0.0, 1e-9, 0.1, 10.0):
        for depth in (1e-300, 1e-9, 0.03, 1.0, 1e6):
            s = hybrid_stress(depth, 0.6, 0.0, -0.8, 0.8, 0.0, -0.6, speed, p)
            assert all(math.isfinite(c) for c in s)
    assert hybrid_stress(0.0, -1.0, 0, 0, -1.0, 0, 0, 0.1, p) == (0.0, 0.0, 0.0)
    assert hybrid_stress(0.03, 1.0, 0, 0, -1.0, 0, 0, 0.1, p) == (0.0, 0.0, 0.0)  # trailing face
    f = lambda d: np.array(hybrid_stress(d, 0.0, 0.0, -1.0, 0.0, 0.0, -1.0, 0.1, p))  # noqa: E731
    jump = np.linalg.norm(f(STEP / 2) - f(-STEP / 2))
    own = max(np.linalg.norm(f(z + STEP) - f(z)) for z in np.arange(STEP / 2, 3e-3, STEP))
    print(f"hybrid at the surface: jump {jump:.3g} Pa, own change per step {own:.3g} Pa")
    assert jump <= own
    # density factors land in the vertical and horizontal components
    s0 = np.array(hybrid_stress(0.03, 0.6, 0.0, -0.8, 0.8, 0.0, -0.6, 0.1, parameter_vector(mjrft.get_medium("poppy_cp"))))
    s1 = np.array(hybrid_stress(0.03, 0.6, 0.0, -0.8, 0.8, 0.0, -0.6, 0.1, p))
    np.testing.assert_allclose(s1, s0 * [32.5 * 0.04, 1, 60 * 0.04], rtol=1e-12)


def test_errors_name_the_bad_value():
    with pytest.raises(ValueError, match="phi"):
        wedge_force(0.0, 0.02, GAMMA_S, math.radians(60), math.radians(40))
    with pytest.raises(ValueError, match="h1"):
        wedge_force(-0.01, 0.02)
    leg = semi_ellipse_leg(LEG_A, LEG_A, 20)
    with pytest.raises(ValueError, match="nan"):
        rotating_leg_profile(leg, AXLE_HEIGHT, 1.0, [0.0, math.nan])
    with pytest.raises(ValueError, match="bulge"):
        rotating_leg_profile(leg, AXLE_HEIGHT, 1.0, [0.0], bulge=0)
    pts = np.array([[0.0, -0.01], [math.nan, -0.02]])
    with pytest.raises(ValueError, match="points row 1"):
        hybrid_leg_forces(pts, [[0, 1], [0, 1]], [[1, 0], [1, 0]], 0.01)
    with pytest.raises(ValueError, match="tangents row 0"):
        hybrid_leg_forces([[0, -0.01]], [[0, 0]], [[1, 0]], 0.01)
    with pytest.raises(ValueError, match="hybrid_width"):
        parameter_vector(mjrft.get_medium("generic").with_extra(hybrid_width=-1.0))
    with pytest.raises(ValueError, match="hybrid_phi"):
        parameter_vector(mjrft.get_medium("generic").with_extra(hybrid_phi=1.2, hybrid_phi_w=0.5))


def test_shadow_rule_is_not_a_function_of_the_per_element_inputs():
    """A shadowed element of the very bent leg and an element of a semicircle leg turning the other way
    about the axle mirrored through it have the same depth, normal, motion and speed: the per-element
    law cannot tell them apart, so the undisturbed-grain rule needs the whole leg (docstring item 3)."""
    vb = semi_ellipse_leg(LEG_A, 2 * LEG_A, 400)
    axle = np.array([0.0, AXLE_HEIGHT])
    theta = -0.6
    pts, tan = leg_pose(vb, theta)
    shadow = shadowed_elements(pts, axle, 1.0)
    depth = -pts[:, 1]
    rr = pts - axle
    sin_all = np.abs(tan[:, 0] * rr[:, 0] + tan[:, 1] * rr[:, 1]) / np.hypot(rr[:, 0], rr[:, 1])  # |sin psi|
    i = int(np.argmax(np.where(shadow & (depth > 0.01), sin_all, -1.0)))
    p, t = pts[i], tan[i]
    r = p - axle
    rho = float(np.hypot(*r))
    v = np.array([r[1], -r[0]])  # omega = +1
    m = v / np.linalg.norm(v)
    nrm = np.array([-t[1], t[0]])
    n_lead = nrm if nrm @ m > 0 else -nrm
    sin_psi = float(n_lead @ m)
    assert n_lead @ (r / rho) < 0  # the shadowed element's leading face looks toward its axle
    # semicircle about O' = 2p - O, omega' = -1 (same velocity at p); on a semicircle psi equals the
    # polar angle phi of the element from the chord (tangent-chord angle), and rho = 2 a' cos(phi)
    o2 = 2 * p - axle
    u_hat = (p - o2) / rho
    u_perp = np.array([-u_hat[1], u_hat[0]])
    phi = math.asin(sin_psi)
    a2 = rho / (2 * math.cos(phi))
    semi = semi_ellipse_leg(a2, a2, 4000)
    best = None
    for side in (1.0, -1.0):
        c_hat = math.cos(phi) * u_hat - side * math.sin(phi) * u_perp
        w_hat = math.sin(phi) * u_hat + side * math.cos(phi) * u_perp
        wp = o2 + semi["points"][:, :1] * c_hat + semi["points"][:, 1:] * w_hat
        wt = semi["tangents"][:, :1] * c_hat + semi["tangents"][:, 1:] * w_hat
        j = int(np.argmin(np.hypot(*(wp - p).T)))
        if best is None or abs(wt[j] @ nrm) < abs(best[2][best[3]] @ nrm):
            best = (wp, None, wt, j)
    wp, _, wt, j = best
    assert np.hypot(*(wp[j] - p)) < 1e-4 and abs(wt[j] @ nrm) < 2e-3  # same place, same tangent line
    r2 = wp[j] - o2
    v2 = -np.array([r2[1], -r2[0]])  # omega' = -1
    np.testing.assert_allclose(v2, v, atol=1e-4)
    assert not shadowed_elements(wp, o2, -1.0)[j]  # ... and it counts
    prm = parameter_vector(mjrft.get_medium("generic"))
    s1 = hybrid_stress(float(depth[i]), n_lead[0], 0.0, n_lead[1], m[0], 0.0, m[1], rho, prm)
    n2 = np.array([-wt[j][1], wt[j][0]])
    n2 = n2 if n2 @ v2 > 0 else -n2
    m2 = v2 / np.linalg.norm(v2)
    s2 = hybrid_stress(float(-wp[j][1]), n2[0], 0.0, n2[1], m2[0], 0.0, m2[1], float(np.hypot(*r2)), prm)
    np.testing.assert_allclose(s2, s1, rtol=3e-3, atol=1e-6 * np.abs(s1).max())
    assert np.abs(s1).max() > 10.0  # Pa: the element would push, were it not in the wake
    print(f"very bent element {i} (shadowed) at depth {1000 * depth[i]:.1f} mm, psi {math.degrees(phi):.1f} deg: "
          f"stress {np.round(s1, 1)} Pa; semicircle (a' = {1000 * a2:.1f} mm, not shadowed): {np.round(s2, 1)} Pa")

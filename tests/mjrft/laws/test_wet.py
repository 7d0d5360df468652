"""SGRFT saturated wet sand (law "wet") and the free-water layer (law "water"): reference facts, extremes."""

import math

import numpy as np
import pytest

import mjrft
from mjrft.laws import LAW_IDS, LAWS, apply_law, rft, water, wet
from mjrft.laws.wet import (DRAG_COEFFICIENT, DRY_CROSSOVER_SPEED, EPS_V, V_CAP, WATER_SKIN, dry_reference,
                            speed_factor, water_drag_stress, water_stress, wet_stress)
from mjrft.laws.registry import parameter_vector

SAND = "sea_sand_saturated"
STEP = 0.1 * 1e-3  # one 1 ms step of motion at 0.1 m/s


def plate(depth_centre=0.03, side=0.02, thick=0.002, n=10):
    """Elements of a side x side x thick plate, face normal +x, centred at ``depth_centre``."""
    h = side / n
    z = depth_centre - side / 2 + h * (np.arange(n) + 0.5)  # depths of the element rows
    y = -side / 2 + h * (np.arange(n) + 0.5)
    zz, _ = np.meshgrid(z, y, indexing="ij")
    d = zz.ravel()
    big = np.concatenate([d, d])
    nrm = np.concatenate([np.tile([1.0, 0, 0], (d.size, 1)), np.tile([-1.0, 0, 0], (d.size, 1))])
    area = np.full(big.size, h * h)
    # the four thin faces (edges), so the plate is closed
    edges_d = np.concatenate([z, z, np.full(n, depth_centre - side / 2), np.full(n, depth_centre + side / 2)])
    edges_n = np.concatenate([np.tile([0, 1.0, 0], (n, 1)), np.tile([0, -1.0, 0], (n, 1)),
                              np.tile([0, 0, 1.0], (n, 1)), np.tile([0, 0, -1.0], (n, 1))])
    return (np.concatenate([big, edges_d]), np.concatenate([nrm, edges_n]),
            np.concatenate([area, np.full(4 * n, h * thick)]))


def drag_x(law, speed, medium=SAND, depth_centre=0.03):
    d, n, a = plate(depth_centre)
    f = apply_law(law, d, n, np.tile([speed, 0.0, 0.0], (d.size, 1)), a, medium)
    return -f[:, 0].sum()


def test_registered():
    assert LAW_IDS["wet"] == 3 and LAW_IDS["water"] == 4
    assert LAWS["wet"] is wet and LAWS["water"] is water
    m = mjrft.get_medium(SAND)
    assert m.zeta == pytest.approx(0.47e6)
    assert m.alpha_z_down == pytest.approx(0.47e6, rel=1e-3)
    assert m.volume_fraction == 0.73
    assert m.get("water_mass_fraction") == 0.214
    assert m.get("wet_eps_v") == EPS_V


def test_plate_speed_line():
    """The paper's linear velocity coefficient: F(v) = F(30 mm/s) (1 + 0.16 (v - 30 mm/s) / 10 mm/s)."""
    base = drag_x("wet", 0.03)
    for v in (1e-6, 0.01, 0.02, 0.04, 0.05, 0.1, 0.3456, 0.4608, 1.0):
        assert drag_x("wet", v) / base == pytest.approx(1 + EPS_V * (v - 0.03) / 0.01, rel=1e-9), v
    ratio = drag_x("wet", 0.05) / drag_x("wet", 0.01)
    # the paper measured 1.786 (section 2.4); its line gives 1.32 / 0.68 (sgrft_plate_speed reports it)
    print(f"wet plate F(50)/F(10) = {ratio:.4f} (paper's measurement 1.786)")
    assert ratio == pytest.approx(1.32 / 0.68, rel=1e-9)


def test_force_roughly_linear_in_speed():
    v = np.linspace(0.01, 0.05, 9)
    f = np.array([drag_x("wet", s) for s in v])
    slope, icpt = np.polyfit(v, f, 1)
    r2 = 1 - np.sum((f - (slope * v + icpt)) ** 2) / np.sum((f - f.mean()) ** 2)
    chord = f[0] + (f[-1] - f[0]) * (v - v[0]) / (v[-1] - v[0])
    dev = np.max(np.abs(f - chord) / f)
    print(f"linear fit R^2 = {r2:.4f} (paper 0.952), max deviation from chord = {dev:.3f}")
    assert r2 > 0.952
    assert dev < 0.05


def test_wet_vs_dry_reference():
    dry_med = dry_reference()
    assert dry_med.zeta == pytest.approx(0.47e6 * 0.92)
    dry = drag_x("rft", 0.03, dry_med)
    assert drag_x("rft", 0.01, dry_med) == pytest.approx(dry)  # rate-independent
    for v in (0.001, 0.005, 0.01, 0.015, 0.02):
        assert drag_x("wet", v) < dry, v
    for v in (0.03, 0.04, 0.05, 0.5, 10.0):
        assert drag_x("wet", v) > dry, v
    cross = DRY_CROSSOVER_SPEED
    assert drag_x("wet", cross) == pytest.approx(dry, rel=1e-9)
    print(f"dry reference zeta = {dry_med.zeta / 1e6:.4f} N/cm^3; wet/dry at 10, 20, 30, 50 mm/s = "
          + ", ".join(f"{drag_x('wet', v) / dry:.3f}" for v in (0.01, 0.02, 0.03, 0.05)))


def test_wet_is_rft_times_factor():
    rng = np.random.default_rng(0)
    n = rng.normal(size=(200, 3))
    v = rng.normal(size=(200, 3)) * rng.uniform(0.0, 0.1, size=(200, 1))
    d = rng.uniform(-0.01, 0.1, size=200)
    for name in (SAND, "poppy_cp"):
        fw = wet(d, n, v, 1e-4, name)
        fr = rft(d, n, v, 1e-4, name)
        k = speed_factor(np.linalg.norm(v, axis=1))[:, None]
        np.testing.assert_allclose(fw, fr * k, rtol=1e-12, atol=1e-15)


def test_speed_factor_extremes():
    """Zero speed: the line's 0.52; above v_cap = 1 m/s (and inf): held at 16.52; NaN counts as 0."""
    p = parameter_vector(mjrft.get_medium(SAND))
    base = wet_stress(0.03, -1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.03, p)
    at_cap = 1 + 0.16 * (V_CAP - 0.03) / 0.01
    for speed, k in ((0.0, 0.52), (1e-300, 0.52), (1e-9, 0.52 + 16e-9), (0.005, 0.6), (0.05, 1.32), (0.5, 8.52),
                     (V_CAP, at_cap), (10.0, at_cap), (1e300, at_cap), (math.inf, at_cap), (math.nan, 0.52),
                     (-1.0, 0.52)):
        s = wet_stress(0.03, -1.0, 0.0, 0.0, -1.0, 0.0, 0.0, speed, p)
        assert all(math.isfinite(c) for c in s), speed
        np.testing.assert_allclose(s, np.array(base) * k, rtol=1e-12, err_msg=str(speed))
        np.testing.assert_allclose(speed_factor(speed), k, rtol=1e-12)
    # continuous at the cap
    below = wet_stress(0.03, -1.0, 0.0, 0.0, -1.0, 0.0, 0.0, V_CAP * (1 - 1e-12), p)
    np.testing.assert_allclose(below, np.array(base) * at_cap, rtol=1e-9)
    for depth in (1e-300, 1e-9, 1.0, 1e3, 1e6):
        for speed in (0.0, 10.0, math.inf):
            s = wet_stress(depth, 0.6, 0.0, -0.8, 0.0, 0.0, -1.0, speed, p)
            assert all(math.isfinite(c) for c in s)
    assert wet_stress(0.0, 0.0, 0.0, -1.0, 0.0, 0.0, -1.0, 0.1, p) == (0.0, 0.0, 0.0)
    assert wet_stress(-0.01, 0.0, 0.0, -1.0, 0.0, 0.0, -1.0, 0.1, p) == (0.0, 0.0, 0.0)


def test_speed_factor_other_constants():
    """A medium's own constants: cap and slope are used; a falling line that stays > 0 is allowed."""
    m = mjrft.get_medium(SAND).with_extra(wet_eps_v=-0.002, wet_v_cap=0.5)
    p = parameter_vector(m)
    for speed, k in ((0.0, 1.006), (0.03, 1.0), (0.5, 1 - 0.002 * 47), (100.0, 1 - 0.002 * 47)):
        s = wet_stress(0.03, -1.0, 0.0, 0.0, -1.0, 0.0, 0.0, speed, p)
        b = rft(0.03, [-1.0, 0, 0], [-max(speed, 1e-9), 0, 0], 1.0, m)[0]
        np.testing.assert_allclose(s, b * k, rtol=1e-9)


def _profile(fun, z0, span=3e-3):
    """Stress along a vertical path (depth = z) in steps of STEP; returns (jump at z0, largest other step)."""
    jump = np.linalg.norm(np.subtract(fun(z0 + STEP / 2), fun(z0 - STEP / 2)))
    zs = np.arange(z0 - span, z0 + span + STEP / 4, STEP) + STEP / 2  # steps that do not straddle z0
    s = np.array([fun(z) for z in zs])
    own = np.max(np.linalg.norm(np.diff(s, axis=0), axis=1)[np.abs(zs[:-1] + STEP / 2 - z0) > STEP / 4])
    return jump, own


def _assert_continuous(fun, z0, label):
    jump, own = _profile(fun, z0)
    print(f"{label}: jump {jump:.4g} Pa, element's own change per step {own:.4g} Pa")
    assert np.all(np.isfinite([jump, own]))
    assert jump <= own * (1 + 1e-9) + 1e-12


def test_continuity_at_sand_surface():
    m = mjrft.get_medium(SAND).with_extra(water_depth=0.02)
    p = parameter_vector(m)
    for nrm, mot in (((0.0, 0.0, -1.0), (0.0, 0.0, -1.0)), ((1.0, 0.0, 0.0), (1.0, 0.0, 0.0)),
                     ((0.6, 0.0, -0.8), (0.8, 0.0, -0.6))):
        for speed in (0.1, 10.0):
            def total(d, nrm=nrm, mot=mot, speed=speed):
                return np.add(wet_stress(d, *nrm, *mot, speed, p), water_stress(d, *nrm, *mot, speed, p))

            _assert_continuous(total, 0.0, f"sand surface n={nrm} v={speed}")
            _assert_continuous(lambda d: wet_stress(d, *nrm, *mot, speed, p), 0.0, "wet alone")


def test_continuity_at_water_surface():
    for hw in (0.02, 0.5e-3):
        p = parameter_vector(mjrft.get_medium(SAND).with_extra(water_depth=hw))
        for speed in (0.1, 10.0):
            _assert_continuous(lambda d: water_stress(d, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, speed, p), -hw,
                               f"water surface hw={hw} v={speed}")


def test_water_drag_values():
    hw = 0.02
    m = mjrft.get_medium(SAND).with_extra(water_depth=hw)
    area, v = 4e-4, 0.05
    # face-on plate in the middle of the layer: C rho v^2 A against the motion
    f = water(-0.01, [[1.0, 0, 0], [-1.0, 0, 0]], [v, 0, 0], area, m).sum(axis=0)
    np.testing.assert_allclose(f, [-DRAG_COEFFICIENT * 1000.0 * v * v * area, 0, 0], rtol=1e-12)
    # exactly at the sand surface (height 0): full drag, as 0 <= height
    np.testing.assert_allclose(water(0.0, [1.0, 0, 0], [v, 0, 0], area, m)[0, 0], f[0], rtol=1e-12)
    # projected area: a face at 60 deg gets cos 60 of it; edge-on and trailing faces nothing
    f60 = water(-0.01, [0.5, math.sqrt(0.75), 0], [v, 0, 0], area, m)
    np.testing.assert_allclose(f60[0], [0.5 * f[0], 0, 0], rtol=1e-12)
    assert np.all(water(-0.01, [[0, 1.0, 0], [-1.0, 0, 0]], [v, 0, 0], area, m) == 0)
    # above the water, deep in the sand, or no water layer: nothing
    assert np.all(water([-hw, -0.05, WATER_SKIN, 0.05], [1.0, 0, 0], [v, 0, 0], area, m) == 0)
    assert np.all(water(-0.01, [1.0, 0, 0], [v, 0, 0], area, SAND) == 0)
    # quadratic in speed; finite at 10 m/s and zero at rest
    f10 = water(-0.01, [1.0, 0, 0], [10.0, 0, 0], area, m)
    assert np.isfinite(f10).all() and f10[0, 0] == pytest.approx(f[0] * (10.0 / v) ** 2)
    assert np.all(water(-0.01, [1.0, 0, 0], [0.0, 0, 0], area, m) == 0)


def test_water_drag_helper_signature():
    s = water_drag_stress(0.01, 0.02, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.1, 1000.0, 1.0)
    assert s == pytest.approx((-10.0, 0.0, 0.0))
    assert water_drag_stress(0.03, 0.02, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.1, 1000.0, 1.0) == (0.0, 0.0, 0.0)
    assert water_drag_stress(0.01, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.1, 1000.0, 1.0) == (0.0, 0.0, 0.0)
    for h in (-1e6, -1e-300, 1e-300, 1e6):
        assert all(math.isfinite(c) for c in water_drag_stress(h, 0.02, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 10.0,
                                                                1000.0, 1.0))


@pytest.mark.parametrize("key,value", [("wet_v_min", 0.06), ("wet_eps_v", -2.0), ("wet_eps_v", "x"),
                                       ("wet_eps_v", 0.4), ("wet_eps_v", -0.011), ("wet_eps_v", math.inf),
                                       ("wet_v_cap", 0.0), ("wet_v_cap", math.inf), ("wet_v_base", -0.01),
                                       ("water_depth", -1.0), ("drag_coefficient", math.nan), ("wet_dv", 0.0),
                                       ("water_skin", 0.0)])
def test_bad_constants_named(key, value):
    m = mjrft.get_medium(SAND).with_extra(**{key: value})
    with pytest.raises(ValueError, match=key):
        parameter_vector(m)

"""Calibration of the wet-sand speed factor and the hybrid bar-drag constants; malformed input."""

import math

import numpy as np
import pytest

import mjrft
from mjrft.tools.calibration import fit_hybrid_constants, fit_wet_speed_coefficient, read_columns
from mjrft.laws import wet
from mjrft.laws.hybrid import HybridModel, rotating_leg_profile, semi_ellipse_leg


def wet_data(eps=0.16, alpha=1500.0, noise=0.03, seed=1):
    rng = np.random.default_rng(seed)
    depth, speed = np.meshgrid([0.005, 0.015, 0.02, 0.03, 0.04], [0.01, 0.02, 0.03, 0.04, 0.05], indexing="ij")
    depth, speed = depth.ravel().repeat(3), speed.ravel().repeat(3)
    force = alpha * depth * (1 + eps * (speed - 0.03) / 0.01) * np.exp(rng.normal(0, noise, depth.size))
    return depth, speed, force


def write_csv(path, header, rows):
    path.write_text(",".join(header) + "\n" + "".join(",".join(str(v) for v in r) + "\n" for r in rows))
    return path


def test_wet_fit_recovers_coefficient(tmp_path):
    depth, speed, force = wet_data()
    fit = fit_wet_speed_coefficient(depth, speed, force)
    print(f"recovered eps_v = {fit.eps_v:.4f} (true 0.16), alpha_base = {fit.alpha_base:.1f} N/m (true 1500), "
          f"R^2 {fit.r2:.3f}, n = {fit.n}")
    assert fit.eps_v == pytest.approx(0.16, abs=0.015)
    assert fit.alpha_base == pytest.approx(1500.0, rel=0.03)
    assert (fit.v_min, fit.v_max, fit.n) == (0.01, 0.05, 60)  # 5 mm samples dropped (top 10 mm)
    path = write_csv(tmp_path / "wet.csv", ["depth", "speed", "force"], zip(depth, speed, force))
    fit2 = fit_wet_speed_coefficient(path)
    assert fit2.eps_v == pytest.approx(fit.eps_v, rel=1e-12)
    # the fit plugs into the wet law
    m = mjrft.get_medium("sea_sand_saturated").with_extra(**fit.extra())
    f10 = wet(0.03, [1.0, 0, 0], [0.01, 0, 0], 1e-4, m)[0, 0]
    f50 = wet(0.03, [1.0, 0, 0], [0.05, 0, 0], 1e-4, m)[0, 0]
    assert f50 / f10 == pytest.approx((1 + 2 * fit.eps_v) / (1 - 2 * fit.eps_v), rel=1e-9)
    assert fit.factor(0.05) / fit.factor(0.01) == pytest.approx(f50 / f10)


def test_wet_fit_other_coefficient_and_base():
    depth, speed, force = wet_data(eps=0.30, noise=0.0)
    fit = fit_wet_speed_coefficient(depth, speed, force, v_base=0.02, min_depth=0.0)
    # the same line re-anchored at 20 mm/s: alpha_base x 0.7, eps_v 0.30 / 0.7 per 10 mm/s
    assert fit.eps_v == pytest.approx(0.30 / 0.7, rel=1e-9)
    assert fit.alpha_base == pytest.approx(1500.0 * 0.7, rel=1e-9) and fit.r2 == pytest.approx(1.0)


def hybrid_data(noise=0.02, seed=2):
    rng = np.random.default_rng(seed)
    model = HybridModel(c_perp_h_coef=1500.0)
    depths = np.array([0.01, 0.02, 0.03, 0.05])
    psi = np.radians(np.arange(0, 91, 5.0))
    d, s = np.meshgrid(depths, psi, indexing="ij")
    d, s = d.ravel(), s.ravel()
    fp = model.f_perp(s, d) * (1 + rng.normal(0, noise, d.size))
    fq = model.f_par(s, d) * (1 + rng.normal(0, noise, d.size))
    return model, depths, s, d, fp, fq


def test_hybrid_fit_recovers_constants(tmp_path):
    model, depths, psi, d, fp, fq = hybrid_data()
    fit = fit_hybrid_constants(psi, d, fp, fq)
    np.testing.assert_allclose(fit.depth, depths)
    np.testing.assert_allclose(fit.c_perp, model.c_perp(depths), rtol=0.03)
    np.testing.assert_allclose(fit.c_par, model.c_par(depths), rtol=0.03)
    # the psi = 0 values are small next to the maxima: judge their error on the scale of the maxima
    assert np.all(np.abs(fit.c_perp_h - model.c_perp_h(depths)) < 0.03 * model.c_perp(depths))
    assert np.all(np.abs(fit.c_par_h - model.c_par_h(depths)) < 0.03 * model.c_par(depths))
    assert fit.c_par_ratio == pytest.approx(0.37, abs=0.01)
    print(f"C_perp fit / true = {np.round(fit.c_perp / model.c_perp(depths), 4)}, C_par/C_perp = {fit.c_par_ratio:.4f}")
    # CSV with psi in degrees gives the same result
    path = write_csv(tmp_path / "bars.csv", ["psi_deg", "depth", "F_perp", "F_par"],
                     zip(np.degrees(psi), d, fp, fq))
    fit2 = fit_hybrid_constants(path)
    np.testing.assert_allclose(fit2.c_perp, fit.c_perp, rtol=1e-9)
    # noiseless data is recovered exactly
    _, _, psi0, d0, fp0, fq0 = hybrid_data(noise=0.0)
    exact = fit_hybrid_constants(psi0, d0, fp0, fq0)
    np.testing.assert_allclose(exact.c_perp, model.c_perp(depths), rtol=1e-9)
    np.testing.assert_allclose(exact.c_par_h, model.c_par_h(depths), rtol=1e-9)
    # a model built from the fit runs the leg
    fitted = HybridModel.from_fit(fit)
    np.testing.assert_allclose(fitted.c_perp(fit.depth), fit.c_perp, rtol=1e-12)
    assert fitted.c_perp(0.0) == 0 and fitted.c_perp(0.005) == pytest.approx(0.5 * fit.c_perp[0])
    leg = semi_ellipse_leg(0.045, 0.045, 40)
    prof = rotating_leg_profile(leg, 0.05, 2.0, np.linspace(-1, 1, 11), model=fitted)
    assert np.all(np.isfinite(prof["F_f"])) and prof["F_f"].max() > 0


WET_HEADER = ["depth", "speed", "force"]


@pytest.mark.parametrize("text,pattern", [
    ("depth,speed\n0.02,0.01\n", r"wet\.csv: missing column 'force'"),
    ("depth,speed,force\n0.02,0.01,1.0\n0.03,fast,1.2\n0.04,0.02,1.3\n", r"wet\.csv, line 3, column 'speed': 'fast' is not a number"),
    ("depth,speed,force\n0.02,0.01,1.0\n0.03,0.02,nan\n0.04,0.02,1.3\n", r"wet\.csv, line 3, column 'force': 'nan' is not finite"),
    ("depth,speed,force\n0.02,0.01,1.0\n0.03,0.02,\n0.04,0.02,1.3\n", r"wet\.csv, line 3, column 'force': missing value"),
    ("depth,speed,force\n0.02,0.01,1.0\n0.03,0.02,1.1\n", r"wet\.csv: too few data rows, need at least 3, got 2"),
    ("", r"wet\.csv: empty file"),
    ("depth,speed,force\n0.02,0.01,1.0\n0.03,0.02,-1.1\n0.04,0.02,1.3\n", r"wet\.csv, line 3, column 'force': force must be > 0"),
    ("depth,speed,force\n-0.02,0.01,1.0\n0.03,0.02,1.1\n0.04,0.02,1.3\n", r"wet\.csv, line 2, column 'depth'"),
    ("depth,speed,force\n0.02,0.01,1.0\n0.03,0.01,1.1\n0.04,0.01,1.3\n", r"wet\.csv: need at least 2 different speeds"),
    ("depth,speed,force\n0.002,0.01,1.0\n0.03,0.02,1.1\n0.04,0.01,1.3\n", r"wet\.csv: need at least 3 samples at depth >= min_depth"),
])
def test_wet_malformed_files(tmp_path, text, pattern):
    path = tmp_path / "wet.csv"
    path.write_text(text)
    with pytest.raises(ValueError, match=pattern):
        fit_wet_speed_coefficient(path)


def test_wet_malformed_arrays():
    with pytest.raises(ValueError, match=r"force\[1\] = nan is not finite"):
        fit_wet_speed_coefficient([0.02, 0.03, 0.04], [0.01, 0.02, 0.03], [1.0, math.nan, 2.0])
    with pytest.raises(ValueError, match=r"speed has 2 values, expected 3"):
        fit_wet_speed_coefficient([0.02, 0.03, 0.04], [0.01, 0.02], [1.0, 1.5, 2.0])
    with pytest.raises(ValueError, match=r"speed\[2\]: speed must be >= 0, got -0.03"):
        fit_wet_speed_coefficient([0.02, 0.03, 0.04], [0.01, 0.02, -0.03], [1.0, 1.5, 2.0])
    with pytest.raises(ValueError, match="speed must be an array of numbers"):
        fit_wet_speed_coefficient([0.02, 0.03, 0.04], ["a", "b", "c"], [1.0, 1.5, 2.0])
    with pytest.raises(TypeError, match="all of the arrays"):
        fit_wet_speed_coefficient([0.02, 0.03, 0.04], [0.01, 0.02, 0.03])
    with pytest.raises(FileNotFoundError, match="no_such.csv"):
        fit_wet_speed_coefficient("no_such.csv")


@pytest.mark.parametrize("text,pattern", [
    ("psi,depth,F_perp\n0,0.02,1\n", r"bars\.csv: missing column 'F_par' .* found columns"),
    ("depth,F_perp,F_par\n0.02,1,1\n", r"missing column 'psi' \(or 'psi_deg'\)"),
    ("psi_deg,depth,F_perp,F_par\n0,0.02,1,1\n30,0.02,2,2\n95,0.02,3,1\n90,0.02,3,0\n", r"bars\.csv, line 4, column 'psi_deg': psi must be in \[0, 90\]"),
    ("psi,depth,F_perp,F_par\n0,0.02,1,1\n0.5,0.02,x,2\n1,0.02,3,1\n1.5,0.02,3,0\n", r"bars\.csv, line 3, column 'F_perp': 'x' is not a number"),
    ("psi,depth,F_perp,F_par\n0,0.02,1,1\n0.5,0.02,inf,2\n1,0.02,3,1\n1.5,0.02,3,0\n", r"line 3, column 'F_perp': 'inf' is not finite"),
    ("psi,depth,F_perp,F_par\n0,0.02,1,1\n0.5,0.02,2,2\n", r"bars\.csv: too few data rows, need at least 4, got 2"),
    ("psi,depth,F_perp,F_par\n0,0.02,1,1\n0.5,0.02,2,2\n1,0.02,3,1\n1.5,0,3,0\n", r"line 5, column 'depth': depth must be > 0"),
    ("psi,depth,F_perp,F_par\n0,0.02,1,1\n0.5,0.02,2,2\n1,0.02,3,1\n1.5,0.04,3,0\n", r"depth 0.04 m needs samples at 2 or more different psi"),
    ("psi,depth,F_perp,F_par\n1.0,0.02,1,1\n1.2,0.02,2,2\n1.4,0.02,3,1\n1.5,0.02,3,0\n", r"F_par needs a sample below 36 deg"),
])
def test_hybrid_malformed_files(tmp_path, text, pattern):
    path = tmp_path / "bars.csv"
    path.write_text(text)
    with pytest.raises(ValueError, match=pattern):
        fit_hybrid_constants(path)


def test_hybrid_malformed_arrays_and_comments(tmp_path):
    with pytest.raises(ValueError, match=r"F_par\[0\] = nan"):
        fit_hybrid_constants([0, 0.5, 1, 1.5], [0.02] * 4, [1, 2, 3, 3], [math.nan, 1, 1, 0])
    with pytest.raises(ValueError, match=r"psi\[3\]: psi must be in \[0, 1.5708\]"):
        fit_hybrid_constants([0, 0.5, 1, 2.0], [0.02] * 4, [1, 2, 3, 3], [1, 1, 1, 0])
    path = tmp_path / "c.csv"
    path.write_text("# comment\n\ndepth, speed ,force,note\n0.02,0.01,1.0,a\n0.03,0.02,1.7,b\n\n0.04,0.03,2.6,c\n")
    cols = read_columns(path, ["depth", "speed", "force"])
    np.testing.assert_allclose(cols["force"], [1.0, 1.7, 2.6])
    assert list(cols["_lines"]) == [4, 5, 7]

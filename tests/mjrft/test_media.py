"""Media catalogue, scaling, 3D-RFT media and Li's calibration routine."""

import math

import numpy as np
import pytest

import mjrft
from mjrft.media import MEDIA, RFT3D_DOWN, fourier_alpha, read_plate_csv


def test_catalogue_names_and_lookup_errors():
    assert {"poppy_lp", "poppy_cp", "glass03_lp", "glass03_cp", "glass3_cp", "generic"} <= set(MEDIA)
    assert mjrft.get_medium("poppy_cp") is MEDIA["poppy_cp"]
    with pytest.raises(ValueError, match="unknown medium 'popy_cp'; valid choices: .*poppy_cp"):
        mjrft.get_medium("popy_cp")


def test_records_are_immutable_and_si():
    m = MEDIA["poppy_cp"]
    with pytest.raises(AttributeError):
        m.zeta = 1.0
    assert m.coeffs[0] == pytest.approx(0.094e6) and m.zeta == pytest.approx(0.488e6)
    assert m.rho_bulk == pytest.approx(1100 * 0.62) and m.grain_diameter == pytest.approx(0.7e-3)


def test_generic_scaled():
    s = mjrft.generic.scaled(0.488e6)
    assert s.alpha_z_down == pytest.approx(0.488e6)
    assert fourier_alpha(s.coeffs, math.pi / 2, 0)[1] == pytest.approx(0.37 * 0.488e6)
    with pytest.raises(ValueError, match="zeta must be finite and > 0"):
        mjrft.generic.scaled(-1.0)


def test_measured_plate_stress_table_s3():
    """Li table S3: measured alpha_z(0, pi/2) (N/cm^3) and its ratio chi to the fit's value (1.05-1.37)."""
    measured = {"poppy_lp": 0.35, "poppy_cp": 0.56, "glass03_lp": 0.24, "glass03_cp": 0.40, "glass3_cp": 0.29}
    for name, az in measured.items():
        m = MEDIA[name]
        assert m.alpha_z_measured == pytest.approx(az * 1e6)
        assert m.depth_only_alphas[0] == pytest.approx(az * 1e6)
        assert 1.04 < m.alpha_z_measured / m.alpha_z_down < 1.38  # table S3's chi row, 1.05 ... 1.37
    for m in (mjrft.generic, MEDIA["poppy_cp"].scaled(1e5), MEDIA["sea_sand_saturated"],
              mjrft.medium_3d("sand", rho_bulk=1500.0, mu_int=0.4, mu_surface=0.3)):
        assert m.alpha_z_measured is None and m.depth_only_alphas[0] == pytest.approx(m.alpha_z_down)
    with pytest.raises(ValueError, match="alpha_z_measured must be finite and > 0"):
        mjrft.Medium("bad", MEDIA["poppy_cp"].coeffs, 1.0, alpha_z_measured=-1.0)


def test_li_media_3d_consistency():
    """3D-RFT on a Li medium reproduces the medium's own pushed-down stress (documented choice)."""
    for name in ("poppy_lp", "poppy_cp", "glass03_lp", "glass03_cp", "glass3_cp"):
        m = MEDIA[name]
        f = mjrft.laws.rft3d(0.01, (0, 0, -1), (0, 0, -1), 1.0, m)[0, 2]
        assert f == pytest.approx(m.alpha_z_down * 0.01, rel=1e-4)  # the fit gives 0.87505, not 0.875
        assert 0.2 < m.mu_int < 0.7


def test_medium_3d_and_errors():
    m = mjrft.medium_3d("sand", rho_bulk=1500.0, mu_int=0.4, mu_surface=0.3)
    assert m.xi_n == pytest.approx(9.81 * 1500 * (894 * 0.064 - 386 * 0.16 + 89 * 0.4))
    assert m.alpha_z_down == pytest.approx(RFT3D_DOWN * m.xi_n)
    for kw, msg in [({"rho_bulk": -1.0}, "rho_bulk"), ({"mu_int": float("nan")}, "mu_int"),
                    ({"mu_surface": -0.1}, "mu_surface")]:
        args = {"rho_bulk": 1500.0, "mu_int": 0.4, "mu_surface": 0.3, **kw}
        with pytest.raises(ValueError, match=msg):
            mjrft.medium_3d("bad", **args)
    with pytest.raises(ValueError, match="coefficient A00 must be finite"):
        mjrft.Medium("bad", (float("nan"),) + (0.1,) * 8, 1.0)


def test_calibration_recovers_zeta_from_noisy_plate_data(tmp_path):
    rng = np.random.default_rng(0)
    true_slope = 0.464e6  # poppy_cp alpha_z(0, pi/2)
    depth = np.linspace(0.002, 0.05, 40)
    stress = true_slope * depth * (1 + 0.03 * rng.normal(size=depth.size))
    m = mjrft.calibrate(depth, stress, name="my_sand")
    assert m.zeta == pytest.approx(true_slope / 1.26, rel=0.02)
    assert m.alpha_z_down == pytest.approx(true_slope / 1.26, rel=0.02)
    assert m.alpha_z_measured == pytest.approx(true_slope, rel=0.02)  # the fitted slope, for the depth-only law
    # the same through a CSV file
    path = tmp_path / "plate.csv"
    path.write_text("depth,stress\n" + "\n".join(f"{d},{s}" for d, s in zip(depth, stress)))
    d2, s2 = read_plate_csv(path)
    assert mjrft.calibrate(d2, s2).zeta == pytest.approx(m.zeta)
    # only the shallow linear range is fitted when asked
    bent = np.where(depth > 0.03, stress * 2, stress)
    assert mjrft.calibrate(depth, bent, max_depth=0.03).zeta == pytest.approx(m.zeta, rel=0.03)


def test_calibration_errors(tmp_path):
    with pytest.raises(ValueError, match="same length"):
        mjrft.calibrate([0.01, 0.02], [1.0])
    with pytest.raises(ValueError, match="finite"):
        mjrft.calibrate([0.01, np.nan], [1.0, 2.0])
    with pytest.raises(ValueError, match="at least 2 samples"):
        mjrft.calibrate([0.01], [1.0])
    with pytest.raises(ValueError, match="slope must be > 0"):
        mjrft.calibrate([0.01, 0.02], [-1.0, -2.0])
    bad = tmp_path / "bad.csv"
    bad.write_text("depth,force\n0.01,2\n")
    with pytest.raises(ValueError, match="columns 'depth' and 'stress'"):
        read_plate_csv(bad)
    bad.write_text("depth,stress\n0.01,abc\n")
    with pytest.raises(ValueError, match="non-numeric"):
        read_plate_csv(bad)


def test_the_parameter_vector_comes_from_the_registry_and_medium_params_is_a_deprecated_alias():
    from mjrft.laws.registry import parameter_vector
    from mjrft.params import P_COEFF, P_SIZE, P_WATER_SKIN

    m = mjrft.get_medium("poppy_cp")
    p = parameter_vector(m)
    assert p.shape == (P_SIZE,) and np.array_equal(p[P_COEFF:P_COEFF + 9], m.coeffs)
    assert p[P_WATER_SKIN] > 0  # a law's own constant (the water layer's skin) is filled by its entry
    with pytest.warns(DeprecationWarning, match="parameter_vector"):
        assert np.array_equal(m.params(), p)

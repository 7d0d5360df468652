"""One element's force (mjrft.forces): a region's law on a buried element, as the vectorised law gives it, nothing
at or above the surface, the hydrostatic pressure below water, and the stiffness the stability check reads."""

from __future__ import annotations

import math

import numpy as np

from mjrft import laws
from mjrft.forces import element_force
from mjrft.laws.registry import LAW_IDS, parameter_vector
from mjrft.media import MEDIA

POPPY = MEDIA["poppy_cp"]
RFT = LAW_IDS["rft"]
G = 9.81
AREA = 1e-4  # m^2
DELTA, V_EPS = 1e-3, 1e-4


def force(depth, n, v, rho_w=0.0, mob=1.0, p=None):
    """element_force of a fully yielded element (memory along its velocity, |m| = |v|)."""
    speed = float(np.linalg.norm(v))
    p = parameter_vector(POPPY) if p is None else p
    return element_force(RFT, p, rho_w, G, AREA, depth, *n, *v, speed, mob, *v, speed, DELTA, V_EPS)


def test_a_buried_element_feels_the_law_and_nothing_at_or_above_the_surface():
    rng = np.random.default_rng(0)
    leading = 0
    for _ in range(20):
        n = rng.normal(size=3)
        n /= np.linalg.norm(n)
        v = rng.normal(size=3)
        v *= 0.1 / np.linalg.norm(v)
        fx, fy, fz, kk, cw, ci, ok = force(0.02, n, v)
        assert ok and np.all(np.isfinite([fx, fy, fz, kk]))
        expected = laws.rft(np.array([0.02]), n[None], v[None], np.array([AREA]), POPPY)[0]
        np.testing.assert_allclose([fx, fy, fz], expected, rtol=1e-9, atol=1e-15)
        assert math.isclose(kk, np.linalg.norm(expected) / max(0.1, DELTA), rel_tol=1e-9, abs_tol=1e-15)
        assert cw == ci == 0.0  # no water layer, no inertial regime
        leading += bool(np.any(expected != 0))
    assert leading >= 5  # the comparison saw real forces, not only faces turned away from their motion
    # a face pressed straight down: a force at 2 cm, none at the surface or above it
    down, push = np.array([0.0, 0.0, -1.0]), np.array([0.0, 0.0, -0.1])
    assert force(0.02, down, push)[2] > 0.5
    for depth in (0.0, -0.01):
        assert force(depth, down, push)[:3] == (0.0, 0.0, 0.0)


def test_water_adds_the_hydrostatic_pressure_and_mobility_scales_the_sand():
    down, push = np.array([0.0, 0.0, -1.0]), np.array([0.0, 0.0, -0.1])
    dry = np.array(force(0.02, down, push)[:3])
    wet = np.array(force(0.02, down, push, rho_w=1000.0)[:3])
    np.testing.assert_allclose(wet - dry, [0.0, 0.0, 1000.0 * G * 0.02 * AREA], rtol=1e-12)
    np.testing.assert_allclose(force(0.02, down, push, mob=0.25)[:3], 0.25 * dry, rtol=1e-12)
    # the stiffness is the sand's unscaled force over max(|m|, delta), whatever the mobility
    assert force(0.02, down, push, mob=0.25)[3] == force(0.02, down, push)[3]

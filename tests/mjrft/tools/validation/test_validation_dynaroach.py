"""DynaRoACH validation cases (Zhang et al., ground fluidization): quick runs assert the published outcomes."""

import math

import pytest

from mjrft.laws.inertial import INERTIAL_DRAG
from mjrft.tools.validation import published, run_case


def outcomes(r):
    assert r.outcomes and not r.failed_outcomes, (r.name, r.failed_outcomes)
    return r.by_name


def test_dynaroach_intrusion():
    r = run_case("dynaroach_intrusion", quick=True)
    checks = outcomes(r)
    off, on = r.panels[0].lines[0], r.panels[0].lines[1]
    vc = published("dynaroach", "v_c").value / 100
    # below v_c the regime adds nothing; off, the lift is the same at every speed
    for v, f0, f1 in zip(off.x, off.y, on.y):
        if v <= 0.99 * vc:
            assert f1 == f0
    assert max(off.y[1:]) - min(off.y[1:]) < 1e-6
    assert checks["regime on: onset of the speed-dependent lift"].value == pytest.approx(vc * 100, rel=0.02)
    # fig. 5's printed alpha is ~10x the regime's (the paper-internal inconsistency the case reports)
    a = checks["quadratic coefficient vs fig. 5's fit"]
    assert not a.passed and 8 < a.reference / a.value < 12 and "fig. 2J" in r.cause
    assert INERTIAL_DRAG == pytest.approx(2.20, abs=0.01)


def test_dynaroach_robot():
    r = run_case("dynaroach_robot", quick=True)
    checks = outcomes(r)
    for line in r.panels[0].lines[:2]:
        assert all(math.isfinite(v) and v > 0 for v in line.y)
    assert "swing-and-lift" in r.cause


@pytest.mark.xfail(strict=True, reason="measured: the one-hinge small hexapod turns its legs continuously (rotary "
                   "walking at every frequency); with the inertial regime on, the lift raises the body with frequency "
                   "and shortens the legs' reach, so the stride falls at 7-12 Hz instead of rising (fig. 3B), and the "
                   "legs sink deepest near 6 Hz, not 3 Hz (fig. 4A); DynaRoACH's swing-and-lift leg kinematics "
                   "(figs. 1B, E, lost) are not modelled")
@pytest.mark.slow
def test_dynaroach_robot_nonlinear_speed_and_sinkage():
    r = run_case("dynaroach_robot", quick=True)
    checks = r.by_name
    assert checks["regime on: stride length rises again at 7-12 Hz (speed super-linear)"].passed
    assert checks["regime on: penetration depth falls above ~3 Hz"].passed

"""SGRFT sec. 4 validation cases (propeller-leg rig and robot): quick runs assert the published outcomes."""

import math

import pytest

from mjrft.tools.validation import published, run_case


def outcomes(r):
    assert r.outcomes and not r.failed_outcomes, (r.name, r.failed_outcomes)
    return r.by_name


def test_sgrft_propeller_leg():
    r = run_case("sgrft_propeller_leg", quick=True)
    checks = outcomes(r)
    change = next(c for n, c in checks.items() if n.startswith("thrust change 30 -> 40 rpm"))
    # the same linear velocity coefficient as the R/V/T legs: the propeller's change is SGRFT's +30.33 %
    assert change.value == pytest.approx(published("sgrft", "thrust_change_predicted").value, rel=0.02)
    # the pi rad range and the shallow-depth shortfall are the documented disagreements (cause measured)
    rng = next(c for n, c in checks.items() if n.startswith("effective propulsion range at"))
    assert not rng.passed and 0 < rng.value < math.pi / 2
    assert "backfill" in r.cause and "2 acos" in r.cause
    for panel in r.panels:
        for line in panel.lines:
            assert all(math.isfinite(y) for y in line.y)


@pytest.mark.xfail(strict=True, reason="the wet law's linear speed factor makes saturated sand up to 4-12x stronger "
                                       "than the dry reference at the blade tips' 0.23-0.69 m/s (20-60 rpm), so the "
                                       "robot is already 1.4-1.7x faster on it below 60 rpm (measured: without the "
                                       "speed factor it runs within 3-13 % of the dry speed); the paper finds the "
                                       "speeds similar there")
def test_sgrft_robot():
    r = run_case("sgrft_robot", quick=True)
    v = [y for line in r.panels[0].lines for y in line.y]
    assert v and all(math.isfinite(y) and y > 0 for y in v)  # the robot runs forward on both grounds
    assert "speed factor" in r.cause
    outcomes(r)

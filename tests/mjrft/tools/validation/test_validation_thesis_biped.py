"""Thesis biped case (quick settings): the published presentation-angle outcomes that mjrft reproduces, and the
one it does not (the thesis simulation's sign of the volume-fraction effect at 55 deg) as a strict xfail."""

from __future__ import annotations

import pytest

from mjrft.tools import validation
from mjrft.tools.validation import published

SIM_VF = "55 deg: denser bed, shorter step (simulation)"
SIM_VF_CAUSE = ("mjrft shortens the 55 deg step on the looser bed, as the thesis' experiment did (sec. 2.5.2): on "
                "poppy_lp the planted foot sinks deeper and the steep toe of the swing foot ploughs the grains on "
                "its top edge (measured 30 vs 20 mm deep, drag impulse 1.7 vs 0.6 N s)")


@pytest.fixture(scope="module")
def result():
    return validation.run_case("thesis_biped", quick=True)


@pytest.mark.slow
def test_presentation_angle_outcomes(result):
    failures = [(c.name, c.published, c.simulated) for c in result.checks
                if c.qualitative and not c.passed and SIM_VF not in c.name]
    assert not failures
    by = result.by_name
    # the peak of step distance against angle is the published 30 deg within the quick grid (0 and 55 deg around it)
    peak = by["cone (experiment), CP: angle of the longest step"]
    assert peak.reference == published("thesis_biped", "peak_angle").value
    assert 0.0 < peak.value < 55.0
    # the experiment's sign of the volume-fraction effect at 55 deg holds, so the case has a measured cause
    assert by["cone (experiment), 55 deg: looser bed, step drops significantly (experiment)"].passed
    assert "swing foot" in result.cause
    # the check rejects the beds swapped (the looser bed stiffer) and a floor on which the bed does not matter
    from mjrft.tools.validation.cases.thesis_biped import looser_bed_drop_check

    lines = {line.label: line for line in result.panels[0].lines}
    cp, lp = lines["cone (experiment), poppy CP (phi 0.62)"], lines["cone (experiment), poppy LP (phi 0.58)"]
    rigid = lines["cone (experiment), rigid ground (mjrft control)"]
    assert looser_bed_drop_check("cone", cp.x, cp.y, lp.y).passed
    assert not looser_bed_drop_check("cone", cp.x, lp.y, cp.y).passed
    assert not looser_bed_drop_check("cone", cp.x, rigid.y, rigid.y).passed
    names = [p.title for p in result.panels]
    assert names[0] == "Step distance per 3 s step" and len(result.panels[0].lines) >= 4


@pytest.mark.xfail(strict=True, reason=SIM_VF_CAUSE)
@pytest.mark.slow
def test_simulation_volume_fraction_sign_at_55_deg(result):
    assert all(c.passed for c in result.checks if SIM_VF in c.name)

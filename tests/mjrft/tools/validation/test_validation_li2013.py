"""Validation cases li2013_plate, li2013_scaling and li2013_leg_rig (Li, Zhang & Goldman 2013 suppl.: plate, scaling
routine, leg rig): each case's outcome test, known disagreements and wrong-physics controls, registered by case name
(:class:`helpers.CaseTests`; ``tests/mjrft/tools/validation/test_validation.py`` holds the framework's tests and the
controls that rerun cases under a wrong physics)."""

from __future__ import annotations

import math

import pytest

from mjrft.media import MEDIA, N_CM3
from mjrft.tools.validation import published
from mjrft.tools.validation.case import SIMILAR
from mjrft.tools.validation.cases import li2013

from helpers import CaseTests

case_tests = CaseTests()
outcome, disagreement, control = case_tests.outcome, case_tests.disagreement, case_tests.control


# ------------------------------------------------------------------------------- Li 2013: plate, scaling, leg rig
@outcome("li2013_plate")
def li2013_plate(plate):
    assert not plate.failed_outcomes
    by = plate.by_name
    measured = dict(zip(published("li2013", "media").value, published("li2013", "alpha_z_measured").value))
    for name, az in measured.items():
        # the depth-only law reproduces table S3's measured plate stress; the fit stays below it
        c = by[f"{name}: alpha_z(0, pi/2), rig under the depth-only law"]
        assert c.value == pytest.approx(az, rel=0.01)
        assert by[f"{name}: measured / fit alpha_z(0, pi/2) = chi"].value > 1.0
    # every failing check carries its measured cause (the plate's side faces)
    if not plate.passed:
        assert "side faces" in plate.cause and "0.064 cm" in plate.cause
    assert len(plate.panels) == 3 and all(p.lines for p in plate.panels)


@outcome("li2013_scaling")
def li2013_scaling(r):
    assert not r.failed_outcomes
    assert r.passed  # the stress-profile RMS checks too
    zeta = dict(zip(published("li2013", "media").value, published("li2013", "zeta").value))
    chi = published("li2013", "chi").value
    for c in r.checks:
        if "zeta from one simulated plate test" in c.name:
            name = c.name.split(":")[0]
            # calibrate returns the measured slope / chi exactly (table S3 value / 1.26)
            assert c.value == pytest.approx(MEDIA[name].alpha_z_measured / N_CM3 / chi, rel=0.01)
            assert c.reference == pytest.approx(zeta[name])



DEPTH_ONLY_FZ = "peak F_z C / reversed C under the depth-only law: similar (every medium)"


@outcome("li2013_leg_rig", slow=True)
def li2013_leg_rig(leg):
    assert not [o for o in leg.failed_outcomes if o[0] != DEPTH_ONLY_FZ]
    largest = [c for c in leg.checks if c.name.startswith("largest depth-only over-prediction")]
    assert len(largest) == 1 and largest[0].reference == 1400.0
    assert math.isfinite(largest[0].value) and largest[0].value > 0  # over-predicts (by how much: see the report)
    if not leg.passed:
        assert leg.cause  # the 1400 % and the reversed-C thrust comparisons explain themselves
    assert len(leg.panels) == 4
    # the leg panels cover Li's sweep -3pi/4 .. 3pi/4 in degrees
    xs = leg.panels[0].lines[0].x
    assert min(xs) == pytest.approx(-135.0) and max(xs) == pytest.approx(135.0)


@disagreement("li2013_leg_rig", slow=True, reason=(
    "measured: mjrft's depth-only peak lift of the C-leg is 1.53x the reversed C-leg's in every medium (thrust the "
    "same within 1 %), outside the 20 % that 'similar' is read as (mjrft.tools.validation.case.SIMILAR); the cause "
    "within mjrft's depth-only law is not isolated"))
def li2013_leg_rig_depth_only_similar_peak_lift(leg):
    assert leg.by_name[DEPTH_ONLY_FZ].passed


@control("li2013_leg_rig", "similar peaks reject the fit")
def li2013_similar_peaks_rejects_the_fit():
    """Under the medium's fit (RFT), the C and reversed C legs' peaks differ: "similar" must reject them."""
    runs = li2013.leg_runs(True, ["poppy_lp"])
    fz = runs["poppy_lp", "c", "fit"].support.max() / runs["poppy_lp", "reversed_c", "fit"].support.max()
    assert fz > 1 + SIMILAR
    assert not li2013.similar_peaks_check("F_z", [fz]).passed
    fx = runs["poppy_lp", "c", "depth_only"].forward.max() / runs["poppy_lp", "reversed_c", "depth_only"].forward.max()
    assert li2013.similar_peaks_check("F_x", [fx]).passed  # depth-only thrust: the same within 1 %


test_case, test_known_disagreement, test_control = case_tests.runners()

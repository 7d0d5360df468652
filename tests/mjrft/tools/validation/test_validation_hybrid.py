"""Validation cases of the hybrid curved-leg paper (mjrft.tools.validation.cases.hybrid), quick settings."""

import math

import pytest

from mjrft.tools import validation
from mjrft.tools.validation import published

# the rig's checks that the per-element law cannot meet: they need the undisturbed-grain (shadow) rule
SHADOW_GAP = ("bent / semicircle", "vanishes long before it leaves", "goes most negative")


def _qualitative(result):
    return [c for c in result.checks if c.qualitative]


def _shadow_gap(check) -> bool:
    return check.name.startswith("per-element law (rig)") and any(k in check.name for k in SHADOW_GAP)


def test_hybrid_bar_drag():
    r = validation.run_case("hybrid_bar_drag", quick=True)
    bad = [c.name for c in _qualitative(r) if not c.passed]
    assert not bad, bad
    assert r.passed
    ratio = published("hybrid", "c_par_ratio").value
    for c in r.checks:
        if "max F_par / max F_perp" in c.name:
            assert c.value == pytest.approx(ratio, abs=1e-3)  # the paper's value, not just inside its band
    assert {len(p.lines) > 0 for p in r.panels} == {True}


def test_hybrid_leg_family():
    r = validation.run_case("hybrid_leg_family", quick=True)
    qual = _qualitative(r)
    assert len(qual) == 26
    bad = [c.name for c in qual if not c.passed and not _shadow_gap(c)]
    assert not bad, bad
    # the whole-leg model reproduces every published outcome; the rig misses only the shadow-rule ones
    assert all(c.passed for c in r.checks if c.name.startswith("whole-leg model"))
    gap = [c for c in r.checks if not c.passed]
    assert gap and all(_shadow_gap(c) for c in gap) and r.cause
    assert "undisturbed-grain rule" in r.cause


@pytest.mark.xfail(strict=True, reason="the per-element law has no undisturbed-grain (shadow) rule: an element's depth, "
                   "normal, motion and speed do not decide it (tests/mjrft/laws/test_hybrid.py), so through the rig "
                   "the bent and very bent legs' parts in their own wake push (very bent: F_f tail gap 34 vs 68 deg, "
                   "min F_s -4.7 vs -0.8 N; bent / semicircle peak F_f 1.38 vs 1.17)")
def test_hybrid_leg_family_rig_shadow_outcomes():
    r = validation.run_case("hybrid_leg_family", quick=True)
    assert all(c.passed for c in r.checks if _shadow_gap(c))


def test_hybrid_speed():
    r = validation.run_case("hybrid_speed", quick=True)
    bad = [c.name for c in _qualitative(r) if not c.passed]
    assert not bad, bad
    assert r.passed
    rig = [c.value for c in r.checks if c.name.startswith("per-element law (rig): spread")]
    assert len(rig) == 3 and all(math.isfinite(v) and v < 0.01 for v in rig)  # measured <= 0.3 %

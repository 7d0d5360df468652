"""Validation cases hybrid_bar_drag, hybrid_leg_family, hybrid_leg_family_memory and hybrid_speed (the hybrid curved-leg
paper): each case's
outcome test, known disagreements and wrong-physics controls, registered by case name (:class:`helpers.CaseTests`;
``tests/mjrft/tools/validation/test_validation.py`` holds the framework's tests and the controls that rerun cases
under a wrong physics)."""

from __future__ import annotations

import math

import pytest

from mjrft.tools.validation import published

from helpers import CaseTests, variant_run
from mjrft.tools.validation.cases.hybrid import (MEMORY_DEPTH_OUTCOMES, SHADOW_RULE_OUTCOMES, SHARE_CHECK,
                                                 SHARE_MODEL, _family_checks, _summary, memory_family)

case_tests = CaseTests()
outcome, disagreement, control = case_tests.outcome, case_tests.disagreement, case_tests.control


# ------------------------------------------------------------------------------------------- hybrid curved legs
# the rig's checks that the per-element law cannot meet: they need the undisturbed-grain (shadow) rule
SHADOW_GAP = ("bent / semicircle", "vanishes long before it leaves", "goes most negative")


def _qualitative(result):
    return [c for c in result.checks if c.qualitative]


def _shadow_gap(check) -> bool:
    return check.name.startswith("per-element law (rig)") and any(k in check.name for k in SHADOW_GAP)


@outcome("hybrid_bar_drag")
def hybrid_bar_drag(r):
    bad = [c.name for c in _qualitative(r) if not c.passed]
    assert not bad, bad
    assert r.passed
    ratio = published("hybrid", "c_par_ratio").value
    for c in r.checks:
        if "max F_par / max F_perp" in c.name:
            assert c.value == pytest.approx(ratio, abs=1e-3)  # the paper's value, not just inside its band
    assert {len(p.lines) > 0 for p in r.panels} == {True}


@outcome("hybrid_leg_family")
def hybrid_leg_family(r):
    qual = _qualitative(r)
    assert len(qual) == 26
    bad = [c.name for c in qual if not c.passed and not _shadow_gap(c)]
    assert not bad, bad
    # the whole-leg model reproduces every published outcome; the rig misses only the shadow-rule ones
    assert all(c.passed for c in r.checks if c.name.startswith("whole-leg model"))
    gap = [c for c in r.checks if not c.passed]
    assert gap and all(_shadow_gap(c) for c in gap) and r.cause
    assert "undisturbed-grain rule" in r.cause


@disagreement("hybrid_leg_family", reason=(
    "without the ground memory the per-element law has no undisturbed-grain (shadow) rule: an element's depth, normal, "
    "motion and speed do not decide it (tests/mjrft/laws/test_hybrid.py), so through the rig the bent and very bent "
    "legs' parts in their own "
    "wake push (very bent: F_f tail gap 34 vs 68 deg, min F_s -4.7 vs -0.8 N; bent / semicircle peak F_f 1.38 vs "
    "1.17)"))
def hybrid_leg_family_rig_shadow_outcomes(r):
    assert all(c.passed for c in r.checks if _shadow_gap(c))


@control("hybrid_leg_family", "geometric outcomes hold under every control (why they are consistency checks)",
         slow=True)
def hybrid_geometric_outcomes_hold_under_every_control():
    from mjrft.tools.validation.cases.hybrid import GEOMETRY_WHY

    for variant in ("no_undisturbed_rule", "depth_only"):
        r = variant_run("hybrid_leg_family", variant)
        geometric = [c for c in r.checks if c.why == GEOMETRY_WHY]
        assert len(geometric) == 18 and all(c.passed for c in geometric), (variant, [
            c.name for c in geometric if not c.passed])


@outcome("hybrid_leg_family_memory")
def hybrid_leg_family_memory(r):
    # with the ground memory's wake the rig reproduces every outcome the undisturbed-grain rule decides (at the quick
    # settings every stated outcome; at the full ones the memory's ridges fail two, the report's cause)
    rule = [c for c in r.checks if any(k in c.name for k in SHADOW_RULE_OUTCOMES + (SHARE_CHECK,))]
    assert len(rule) == 4 and all(c.is_validation and c.passed for c in rule), [(c.name, c.simulated) for c in rule]
    assert len(r.checks) == 15 and r.passed and not r.cause
    assert "pass / FAIL" in r.notes and len(r.panels) == 7
    # the bent and very bent legs' share in the wake at their peak F_f is the whole-leg model's in the shadow
    # (measured: 33 / 32 % and 50 / 51 %)
    model = next(c for c in r.checks if SHARE_MODEL in c.name)
    assert model.passed and not model.is_validation


@control("hybrid_leg_family_memory", "the same rig without the ground memory fails the four outcomes of the "
         "undisturbed-grain rule (figs. 10, 12); the ridge-sensitive outcomes reject a straight leg pushing hardest")
def hybrid_leg_family_without_memory():
    rig, checks = memory_family(True, memory=False)
    rule = [c for c in checks if any(k in c.name for k in SHADOW_RULE_OUTCOMES + (SHARE_CHECK,))]
    assert len(rule) == 4 and not any(c.passed for c in rule), [(c.name, c.simulated) for c in rule]
    assert not next(c for c in checks if SHARE_MODEL in c.name).passed  # no wake: 0 % against the model's 32 and 51
    depth = [c for c in checks if any(k in c.name for k in MEMORY_DEPTH_OUTCOMES)]
    assert len(depth) == 2 and all(c.passed and c.is_validation for c in depth)
    # the straight leg with three times its forces (what the memory's ridges do at 5 mm cells, 1.80 -> 3.92 N)
    strong = {n: (dict(p, F_f=3 * p["F_f"], torque=3 * p["torque"]) if n == "straight" else p) for n, p in rig.items()}
    wrong = [c for c in _family_checks(_summary(strong), "x3 straight", 2.3) if any(k in c.name
                                                                                   for k in MEMORY_DEPTH_OUTCOMES)]
    assert len(wrong) == 2 and not any(c.passed for c in wrong), [(c.name, c.simulated) for c in wrong]


@outcome("hybrid_speed")
def hybrid_speed(r):
    bad = [c.name for c in _qualitative(r) if not c.passed]
    assert not bad, bad
    assert r.passed
    rig = [c.value for c in r.checks if c.name.startswith("per-element law (rig): spread")]
    assert len(rig) == 3 and all(math.isfinite(v) and v < 0.01 for v in rig)  # measured <= 0.3 %


test_case, test_known_disagreement, test_control = case_tests.runners()

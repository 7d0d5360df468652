"""Validation case rft3d_generic (Agarwal, Goldman & Kamrin 2023 and Li 2013's generic responses): each case's outcome
test, known disagreements and wrong-physics controls, registered by case name (:class:`helpers.CaseTests`;
``tests/mjrft/tools/validation/test_validation.py`` holds the framework's tests and the controls that rerun cases
under a wrong physics)."""

from __future__ import annotations

from helpers import CaseTests

case_tests = CaseTests()
outcome, disagreement, control = case_tests.outcome, case_tests.disagreement, case_tests.control


# ------------------------------------------------------------------------------------------- 3D-RFT
@outcome("rft3d_generic")
def rft3d_generic(r):
    qual = [c for c in r.checks if c.qualitative]
    assert len(qual) == 4
    assert all(c.passed for c in qual), [(c.name, c.simulated) for c in qual if not c.passed]
    # every published number, through the laws and through the rig
    assert r.passed, [(c.name, c.published, c.simulated) for c in r.checks if not c.passed]
    assert sum(" law, " in c.name for c in r.checks) == 16 and sum(" rig, " in c.name for c in r.checks) == 16
    assert r.panels and all(any(line.is_paper for line in p.lines) for p in r.panels)


test_case, test_known_disagreement, test_control = case_tests.runners()

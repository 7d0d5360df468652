"""Fast test of the 3D-RFT validation case (mjrft.tools.validation.cases.rft3d)."""

from mjrft.tools.validation import run_case


def test_rft3d_generic():
    r = run_case("rft3d_generic", quick=True)
    qual = [c for c in r.checks if c.qualitative]
    assert len(qual) == 4
    assert all(c.passed for c in qual), [(c.name, c.simulated) for c in qual if not c.passed]
    # every published number, through the laws and through the rig
    assert r.passed, [(c.name, c.published, c.simulated) for c in r.checks if not c.passed]
    assert sum(" law, " in c.name for c in r.checks) == 16 and sum(" rig, " in c.name for c in r.checks) == 16
    assert r.panels and all(any(line.is_paper for line in p.lines) for p in r.panels)

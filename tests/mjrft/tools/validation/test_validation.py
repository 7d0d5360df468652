"""Validation (mjrft.tools.validation): the framework (published data, checks, the report, ``mjrft validate``), the
readings of the papers' words, and the tests every case shares, parametrised over the cases (pytest ids are the case
names):

* ``test_control[<case>: rejects <variant>]``: the case rerun at its quick settings under a wrong physics
  (:data:`mjrft.tools.validation.case.WRONG_PHYSICS`) fails the validation checks the variant must reject
  (:data:`WRONG_PHYSICS_CONTROLS`);
* ``test_every_validation_check_fails_a_control_or_the_case[<case>]``: in a case with wrong-physics variants, each
  validation check is rejected by one of them or fails on mjrft's own physics;
* every registered case has its outcome test.

The case-specific tests are in ``test_validation_<case module>.py``, one module per module of
mjrft/tools/validation/cases/, registered by case name (:class:`helpers.CaseTests`): ``test_case[<case>]`` (the
published outcomes its quick run shows and the numbers the test pins), ``test_known_disagreement[<case>]`` (the
outcomes mjrft does not reproduce: strict expected failures with the measured cause), ``test_control[<case>:
<control>]`` (the wrong-physics controls its own check functions must reject), and the models and gaits the case
drives. A case's quick run is made once per session (the fixture ``quick_run``) and shared by its tests."""

from __future__ import annotations

import ast
import csv
import importlib
import json
import math
import os
import pathlib
import pkgutil

import numpy as np
import pytest

import mjrft
from mjrft.laws.registry import parameter_vector
from mjrft.tools import cli, validation
from mjrft.tools.validation import cases as case_modules
from mjrft.tools.validation.case import (CASES, CONSISTENCY, SIMILAR, UPRIGHT_TILT, CaseResult, Check, Line, Panel,
                                         check_band, check_close, check_outcome, similar)
from mjrft.tools.validation.report import write_report

from helpers import named_checks, variant_run

case_mod = importlib.import_module("mjrft.tools.validation.case")  # the module (the package exports `case`)

#: the wrong-physics controls that rerun a case: (case, variant, the validation checks the variant must fail, slow);
#: ``*`` in a check's name stands for any text
PLATE_FIT_CHI = ("*: alpha_z^fit(0, pi/2), rig under the fit", "*: measured / fit alpha_z(0, pi/2) = chi")
RIG_VALUES = ("3D-RFT rig, *", "Li M0 rig, *")
WRONG_PHYSICS_CONTROLS = (
    ("hybrid_leg_family", "no_undisturbed_rule", (
        "whole-leg model: peak F_f, bent / semicircle*", "whole-leg model: very bent leg's F_f vanishes*",
        "whole-leg model: the straight leg's F_s goes most negative*"), False),
    ("hybrid_speed", "rate_dependent", ("per-element law (rig): spread of peak *",), False),
    ("li2013_plate", "x2", PLATE_FIT_CHI, False),
    ("li2013_plate", "x0.5", PLATE_FIT_CHI, False),
    ("li2013_plate", "depth_only", ("poppy_lp: depth-only alpha_z > fit*",), False),
    ("rft3d_generic", "x2", RIG_VALUES, True),
    ("rft3d_generic", "x0.5", RIG_VALUES, True),
    ("rft3d_generic", "depth_only", (
        "3D-RFT rig: every published sign", "3D-RFT rig: lift at beta = +pi/4*", "Li M0 rig: every published sign",
        "Li M0 rig: lift at beta = +pi/4*"), False),
    ("sgrft_plate_depth", "rate_independent", ("alpha^10*", "alpha^20*"), False),
    ("sgrft_plate_depth", "x2", ("alpha^10*", "alpha^20*"), False),
    ("sgrft_plate_depth", "x0.5", ("alpha^10*", "alpha^20*"), False),
    ("sgrft_legs", "depth_only", ("R-leg forward-force asymmetry*", "V-leg forward-force asymmetry*"), False),
    ("sgrft_rpm", "rate_independent", (
        "thrust grows from 30 to 40 rpm (R, V, T)", "R-leg thrust change vs SGRFT's prediction",
        "V-leg thrust change vs SGRFT's prediction", "R-leg thrust change vs measured",
        "V-leg thrust change vs measured"), False),
    ("sgrft_propeller_leg", "rate_independent", (
        "peak thrust grows from 30 to 40 rpm (every depth)", "thrust change 30 -> 40 rpm at 30 mm*"), False),
    ("sgrft_robot", "rate_independent", ("v_wet / v_dry above 60 rpm*",), True),
)
VARIANT_REJECTS: dict[str, list[str]] = {}  # case -> the checks its wrong-physics variants must fail
for _name, _variant, _rejects, _slow in WRONG_PHYSICS_CONTROLS:
    VARIANT_REJECTS.setdefault(_name, []).extend(_rejects)
#: the modules of the case-specific tests, one per case module
CASE_TEST_MODULES = sorted(pathlib.Path(__file__).parent.glob("test_validation_*.py"))


# ------------------------------------------------------------------------------------------- framework
@pytest.fixture
def toy_case():
    """A registered case with one passing and one failing check (removed after the test)."""

    @validation.case("toy_case", "a toy", "nobody 2000")
    def run(quick):
        x = [0.0, 1.0, 2.0]
        return CaseResult(
            name="toy_case", title="a toy", paper="nobody 2000", source="fig. 1", setup="none",
            checks=[check_close("slope", 2.0, 2.1, 0.1, source="fig. 1 caption", unit="N"),
                    check_outcome("order", False, published="a > b", simulated="a < b", source="text")],
            panels=[Panel("force", "x", "F", [Line(x, [0, 2.1, 4.2], "mjrft"),
                                              Line(x, [0, 2, 4], "paper", source="fig. 1")])],
            cause="b is measured larger because of the toy")

    yield "toy_case"
    CASES.pop("toy_case", None)


def test_every_published_datum_has_value_unit_and_source():
    for paper in validation.papers():
        path = os.path.join(os.path.dirname(case_mod.__file__), "data", f"{paper}.json")
        with open(path) as f:
            raw = json.load(f)
        assert isinstance(raw.get("_paper"), str) and raw["_paper"], paper
        for key, entry in raw.items():
            if key.startswith("_"):
                continue
            assert {"value", "unit", "source"} <= set(entry), (paper, key)
            assert entry["source"].strip(), (paper, key)
            d = validation.published(paper, key)
            assert d.value == entry["value"]


def test_published_names_bad_paper_and_key():
    with pytest.raises(ValueError, match="unknown paper 'nope'"):
        validation.published("nope", "x")
    for paper in validation.papers():
        with pytest.raises(ValueError, match="valid choices"):
            validation.published(paper, "no such key")


def test_every_case_is_registered_with_a_paper_that_has_data():
    cases = validation.load_cases()
    assert cases, "no validation case registered"
    for c in cases.values():
        assert c.title and c.paper and callable(c.run)


def test_checks():
    ok = check_close("x", 10.0, 10.9, 0.1, source="s")
    assert ok.passed and ok.metric == "relative error 9.0 %" and ok.tolerance == "<= 10 %"
    assert not check_close("x", 10.0, 11.1, 0.1, source="s").passed
    assert not check_close("x", 0.0, 1e-9, 0.5, source="s").passed  # zero reference: no relative error
    with pytest.raises(ValueError, match="source"):
        check_close("x", 1.0, 1.0, 0.1)
    assert check_band("r", 1.5, 1.2, 2.0, published="1.8", source="s").passed
    assert not check_band("r", 2.5, 1.2, 2.0, published="1.8", source="s").passed
    assert check_band("r", 1.5, 1.2, 2.0, published="1.8", source="s").qualitative
    d = case_mod.Datum("p", "k", 3.0, "N", "table 1")
    c = check_close("k", d, 3.3, 0.2)
    assert c.source == "table 1" and c.published == "3 N" and c.reference == 3.0


def test_report_writes_markdown_png_and_csv(toy_case, tmp_path):
    r = validation.run_case(toy_case)
    assert not r.passed and r.verdict == "FAIL (1 of 2 checks)" and r.seconds >= 0
    paths = write_report([r], str(tmp_path))
    md = open(paths["report"]).read()
    assert "| [toy_case](#toy_case) | nobody 2000 | fig. 1 | 1 of 2 | FAIL (1 of 2 checks)" in md
    assert "0 of 1 cases agree in every check; 1 of 2 validation checks pass; 0 consistency checks (0 pass)" in md
    assert "relative error 5.0 %" in md and "b is measured larger" in md and "![toy_case](toy_case.png)" in md
    assert os.path.getsize(paths["pngs"][0]) > 1000
    with open(paths["csv"]) as f:
        rows = list(csv.DictReader(f))
    kinds = {r["kind"] for r in rows}
    assert kinds == {"check", "mjrft", "paper"}
    slope = next(r for r in rows if r["name"] == "slope")
    assert math.isclose(float(slope["value"]), 2.1) and math.isclose(float(slope["published"]), 2.0)
    assert sum(r["kind"] == "paper" for r in rows) == 3


def test_report_counts_validation_and_consistency_checks_apart(tmp_path):
    from mjrft.tools.validation.report import counts, summary_line

    r = CaseResult(name="c", title="t", paper="p", source="-", setup="-", checks=[
        check_close("measured", 2.0, 2.1, 0.1, source="fig. 1"),
        check_close("calibrated", 3.0, 3.0, 0.01, source="table 1", consistency="the coefficient is fitted to it"),
        check_outcome("by construction", False, published="-", simulated="-", source="-",
                      consistency="linear by definition")])
    assert counts([r]) == {"cases": 1, "cases_pass": 0, "validation": 1, "validation_pass": 1, "consistency": 2,
                           "consistency_pass": 1}
    assert summary_line([r]) == ("0 of 1 cases agree in every check; 1 of 1 validation checks pass; 2 consistency "
                                 "checks (1 pass)")
    paths = write_report([r], str(tmp_path))
    md = open(paths["report"]).read()
    assert "| [c](#c) | p | - | 1 of 1 (+2) | FAIL (1 of 3 checks)" in md
    assert "calibrated (consistency: the coefficient is fitted to it)" in md
    with open(paths["csv"]) as f:
        kinds = [row["kind"] for row in csv.DictReader(f)]
    assert kinds == ["check", "consistency", "consistency"]


def test_cli_rejects_bad_case_and_unwritable_out_before_running(tmp_path, capsys):
    with pytest.raises(SystemExit) as e:
        cli.main(["validate", "--case", "no_such_case", "--out", str(tmp_path)])
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert "unknown validation case 'no_such_case'" in err and "valid choices" in err
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(SystemExit) as e:
        cli.main(["validate", "--out", str(blocker / "sub")])
    assert e.value.code == 2 and "cannot be written" in capsys.readouterr().err


def test_cli_runs_a_case_and_exit_status_follows_the_verdict(toy_case, tmp_path, capsys):
    assert cli.main(["validate", "--case", toy_case, "--out", str(tmp_path)]) == 1
    out = capsys.readouterr().out
    assert "toy_case" in out and "wrote" in out
    assert (tmp_path / "report.md").exists() and (tmp_path / "results.csv").exists()
    assert cli.main(["validate", "--list"]) == 0


def test_warnings_of_a_case_are_collected_once_per_kind_not_printed(tmp_path, recwarn):
    import warnings

    @validation.case("warning_case", "warns", "nobody 2000")
    def run(quick):
        for v in (1.2, 1.5, 2.0):
            warnings.warn(mjrft.ValidityRangeWarning(f"mjrft: law 'rft': speed {v} m/s is outside"))
        warnings.warn(UserWarning("something else"))
        return CaseResult(name="warning_case", title="warns", paper="nobody 2000", source="-", setup="-",
                          checks=[check_outcome("x", True, published="-", simulated="-", source="-")])

    try:
        r = validation.run_case("warning_case")
    finally:
        CASES.pop("warning_case", None)
    assert len(recwarn) == 0
    assert r.warnings == ["ValidityRangeWarning: law 'rft': speed 1.2 m/s is outside (and 2 more like it)",
                          "UserWarning: something else"]
    md = open(write_report([r], str(tmp_path))["report"]).read()
    assert "*Warnings during the run*" in md and "speed 1.2 m/s is outside (and 2 more like it)" in md


def test_report_names_the_command_run_and_the_real_data_path(tmp_path, capsys):
    """The report's header names the command line that produced it (as run) and the folder that really holds the
    published numbers; validate's --help states the exit statuses."""
    import pathlib

    from mjrft.tools.validation.report import DATA_PATH, run_command

    r = CaseResult(name="c", title="t", paper="p", source="-", setup="-",
                   checks=[check_outcome("x", True, published="-", simulated="-", source="-")])
    out = tmp_path / "rep"
    command = run_command(str(out), quick=True, cases=["c"])
    md = open(write_report([r], str(out), quick=True, command=command)["report"]).read()
    assert f"Produced by `mjrft validate --quick --case c --out {out}`" in md
    assert f"`{DATA_PATH}`" in md
    root = pathlib.Path(validation.__file__).resolve().parent / "data"
    assert root.is_dir() and any(root.glob("*.json")) and DATA_PATH.startswith("mjrft/tools/validation/data/")
    default = open(write_report([r], str(tmp_path / "d"))["report"]).read()
    assert f"Produced by `mjrft validate --out {tmp_path / 'd'}`" in default
    with pytest.raises(SystemExit):
        cli.main(["validate", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "exit status: 0 when every case agrees in every check, 1 when a case fails a check, 130" in text


# ------------------------------------------------------------------------------------------- readings
def test_readings_of_the_papers_words():
    assert similar(1.0) and similar(1.19) and similar(1 / 1.19)
    assert not similar(1.21) and not similar(1 / 1.21) and not similar(1.52) and not similar(0.0)
    assert SIMILAR == 0.2 and UPRIGHT_TILT == pytest.approx(math.radians(60))


def test_a_consistency_check_states_why_and_is_counted_apart():
    with pytest.raises(ValueError, match="needs the reason"):
        Check("x", "-", "-", "-", "-", True, "s", kind=CONSISTENCY)
    with pytest.raises(ValueError, match="check kind"):
        Check("x", "-", "-", "-", "-", True, "s", kind="other")
    c = check_close("k", 1.0, 1.0, 0.1, source="s", consistency="calibrated from it")
    assert c.kind == CONSISTENCY and not c.is_validation and c.why == "calibrated from it"
    tolerance = check_close("k", 1.0, 1.0, 0.1, source="s", basis="the paper's error").tolerance
    assert tolerance == "<= 10 % (the paper's error)"



def test_wrong_physics_variants():
    from mjrft.media import get_medium

    from mjrft.laws.registry import STRESS_SLOTS  # the slots GranularTerrain's stress_scale multiplies

    # x2 / x0.5 scale exactly the slots GranularTerrain's stress_scale multiplies, in every law's constants
    hybrid_sand = get_medium("generic").with_extra(hybrid_unit_weight=13000.0)
    for m in ("poppy_lp", "sea_sand_saturated", "generic", hybrid_sand):
        p = parameter_vector(get_medium(m))
        other = np.setdiff1d(np.arange(p.size), STRESS_SLOTS)
        for k in (2.0, 0.5):
            q = parameter_vector(case_mod.stress_scaled(m, k))
            assert np.allclose(q[STRESS_SLOTS], k * p[STRESS_SLOTS]) and np.array_equal(q[other], p[other])
    assert case_mod.wrong_physics(None, "poppy_lp", "rft") == ("poppy_lp", "rft")
    assert case_mod.wrong_physics("rate_independent", "sea_sand_saturated", "wet") == ("sea_sand_saturated", "rft")
    assert case_mod.wrong_physics("depth_only", "poppy_lp", "rft") == ("poppy_lp", "depth_only")
    with pytest.raises(ValueError, match="unknown wrong-physics variant 'x3'.*valid choices"):
        case_mod.wrong_physics("x3", "poppy_lp", "rft")
    with pytest.raises(ValueError, match="wrong-physics variant of case 'sgrft_rpm'.*valid choices"):
        validation.run_case("sgrft_rpm", quick=True, variant="x2")


# ------------------------------------------------------------------------------------------- every case
def registered_case_tests(kind: str) -> list[str]:
    """The case names that the case-specific test modules register as ``kind`` (``outcome``, ``disagreement`` or
    ``control``: the decorators of :class:`helpers.CaseTests`), read from their source."""
    out = []
    for path in CASE_TEST_MODULES:
        for node in ast.walk(ast.parse(path.read_text())):
            if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == kind and node.args
                    and isinstance(node.args[0], ast.Constant)):
                out.append(node.args[0].value)
    return out


def test_every_registered_case_has_its_outcome_test():
    cases = set(validation.load_cases())
    outcomes = registered_case_tests("outcome")
    assert len(outcomes) == len(set(outcomes)), sorted(outcomes)
    assert set(outcomes) == cases, (f"cases without an outcome test: {sorted(cases - set(outcomes))}; "
                                    f"outcome tests of no case: {sorted(set(outcomes) - cases)}")
    assert set(registered_case_tests("disagreement")) <= cases
    assert set(registered_case_tests("control")) | {c[0] for c in WRONG_PHYSICS_CONTROLS} <= cases
    modules = {m.name for m in pkgutil.iter_modules(case_modules.__path__)}
    assert {p.stem.removeprefix("test_validation_") for p in CASE_TEST_MODULES} == modules


@pytest.mark.parametrize("name, variant, rejects", [
    pytest.param(name, variant, rejects, id=f"{name}: rejects {variant}", marks=[pytest.mark.slow] if slow else [])
    for name, variant, rejects, slow in WRONG_PHYSICS_CONTROLS])
def test_control(name, variant, rejects):
    """Case ``name`` rerun at its quick settings under the wrong-physics ``variant`` fails every validation check named
    in ``rejects``."""
    r = variant_run(name, variant)
    named = named_checks(r, rejects)
    assert all(c.is_validation for c in named), [c.name for c in named if not c.is_validation]
    accepted = [(c.name, c.simulated) for c in named if c.passed]
    assert not accepted, (variant, accepted)


@pytest.mark.parametrize("name", [n for n, c in validation.load_cases().items() if c.variants])
def test_every_validation_check_fails_a_control_or_the_case(name, quick_run):
    """In a case with wrong-physics variants, each validation check is rejected by one of the case's variant controls,
    or fails on mjrft's own physics (a documented disagreement, so it can fail)."""
    r = quick_run(name)
    covered = {c.name for c in named_checks(r, VARIANT_REJECTS.get(name, ()))}
    bare = [c.name for c in r.validation_checks if c.passed and c.name not in covered]
    assert not bare, f"validation checks of {name} that no wrong-physics control rejects: {bare}"

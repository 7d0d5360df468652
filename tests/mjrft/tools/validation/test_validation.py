"""The validation framework: published data, checks, the report writer and the `mjrft validate` command."""

from __future__ import annotations

import csv
import importlib
import json
import math
import os

import pytest

import mjrft
from mjrft.tools import cli, validation
from mjrft.tools.validation.case import CASES, CaseResult, Line, Panel, check_band, check_close, check_outcome
from mjrft.tools.validation.report import write_report

case_mod = importlib.import_module("mjrft.tools.validation.case")  # the module (the package exports `case`)


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

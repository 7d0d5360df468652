"""Output paths are checked before any work starts, by one helper (mjrft.tools.outputs), in every command."""

from __future__ import annotations

import os
import time

import pytest

from mjrft.tools import cli
from mjrft.tools.outputs import output_dir, output_file


@pytest.fixture
def blocker(tmp_path):
    """A file; any path below it cannot be created."""
    f = tmp_path / "a_file"
    f.write_text("")
    return f


def test_output_dir_creates_and_probes(tmp_path, blocker):
    d = tmp_path / "new" / "deeper"
    assert output_dir(d) == str(d) and d.is_dir() and not os.listdir(d)
    with pytest.raises(ValueError, match=r"--out '.*a_file' cannot be written: it is a file"):
        output_dir(blocker)
    with pytest.raises(ValueError, match=r"--run .*sub' cannot be written"):
        output_dir(blocker / "sub", "--run")


def test_output_file_checks_folder_and_leaves_nothing(tmp_path, blocker):
    f = tmp_path / "out" / "table.csv"
    assert output_file(f, "--csv") == str(f)
    assert f.parent.is_dir() and not f.exists() and not os.listdir(f.parent)
    with pytest.raises(ValueError, match=r"--csv '.*' cannot be written: it is a folder"):
        output_file(tmp_path, "--csv")
    with pytest.raises(ValueError, match=r"--json '.*x.json' cannot be written"):
        output_file(blocker / "x.json", "--json")


COMMANDS = [
    (["demo", "--out", "{bad}/demo.rrd"], "--out"),
    (["eval", "--policy", "tripod", "--csv", "{bad}/t.csv"], "--csv"),
    (["eval", "--policy", "tripod", "--json", "{bad}/t.json"], "--json"),
    (["eval", "--policy", "tripod", "--rrd", "{bad}/t.rrd"], "--rrd"),
    (["rollout", "--env", "mjrft/HexapodSand-v0", "--policy", "tripod", "--rrd", "{bad}/r.rrd"], "--rrd"),
    (["train", "--out", "{bad}/run"], "--out"),
    (["rig", "plate", "--out", "{bad}/rig"], "--out"),
    (["bench", "--quick", "--out", "{bad}/bench"], "--out"),
    (["sweep", "--grid", "medium=poppy_lp", "--out", "{bad}/sweep"], "--out"),
    (["validate", "--out", "{bad}/val"], "--out"),
]


@pytest.mark.parametrize("argv,option", COMMANDS, ids=[" ".join(c[0][:2]) for c in COMMANDS])
def test_every_command_refuses_an_unwritable_output_before_working(argv, option, blocker, capsys):
    argv = [a.format(bad=blocker) for a in argv]
    t0 = time.perf_counter()
    with pytest.raises(SystemExit) as e:
        cli.main(argv)
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert f"{option} '{blocker}" in err and "cannot be written" in err, err
    assert time.perf_counter() - t0 < 20  # refused up front, not after the work


def test_printed_numbers_show_round_off_and_negative_zero_as_zero():
    from mjrft.tools.outputs import number

    assert number(2.582e-16, ".4g", scale=3.2) == "0"
    assert number(2.582e-16, ".4g") == "2.582e-16"  # no scale: a tiny value is not noise by itself
    assert number(-0.0001, ".3f") == "0.000" and number(-0.0, ".2f") == "0.00"
    assert number(-0.001, "8.2f") == "    0.00" and number(-0.02, ".3f") == "-0.020"
    assert number(12.3, "8.2f") == "   12.30" and number(-4e-4, ".2e") == "-4.00e-04"


def test_rig_prints_no_round_off(tmp_path, capsys):
    from mjrft.tools import cli

    assert cli.main(["rig", "plate", "--depth", "0.02", "--step", "0.002", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "drag 0 N" in out and "e-1" not in out, out



def test_a_clone_named_mjrft_found_first_says_what_happened(tmp_path):
    """A script run from the folder that holds a clone named ``mjrft`` finds the clone as an empty namespace
    package; importing its environments, models or training then says so instead of a confusing error."""
    import subprocess
    import sys

    repo = os.path.abspath(os.path.join(os.path.dirname(__file__), *[os.pardir] * 3))  # tests/mjrft/tools/ -> repo
    os.symlink(repo, tmp_path / "mjrft")
    for stmt in ("import mjrft.envs", "import mjrft.models", "import mjrft.train",
                 "import gymnasium; gymnasium.make('mjrft.envs:mjrft/HexapodSand-v0')"):
        run = subprocess.run([sys.executable, "-c", stmt], cwd=tmp_path, capture_output=True, text=True)
        assert run.returncode != 0 and "holds the mjrft repository, not from the installed package" in run.stderr, stmt
    ok = subprocess.run([sys.executable, "-c", "import mjrft.envs, mjrft.models, mjrft.train"], cwd=repo,
                        capture_output=True, text=True)
    assert ok.returncode == 0, ok.stderr

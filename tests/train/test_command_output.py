"""What the training commands print when something is off: one line naming the file, or a short note after the
output (the same notes as ``mjrft demo``), never a traceback or Python's warning lines with their source."""

from __future__ import annotations

import json
import pickle
import shutil
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest

pytest.importorskip("stable_baselines3")
pytest.importorskip("imageio")  # gymnasium.envs.mujoco needs it

from mjrft.tools.cli import main as cli  # noqa: E402
from mjrft.train.artefacts import ArtefactError, load_replay_buffer, load_vecnormalize  # noqa: E402
from mjrft.train.plot import load_run, plot_runs  # noqa: E402
from mjrft.train.train import train  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
ENV = "InvertedPendulum-v5"
HP = {"n_steps": 32, "batch_size": 32, "n_epochs": 1, "policy_kwargs": {"net_arch": [16]}}


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """A finished 64-step PPO run (model.zip, checkpoints at 32 and 64)."""
    out = tmp_path_factory.mktemp("run") / "run"
    train(ENV, "ppo", 64, out_dir=out, checkpoint_every=32, hyperparams=HP)
    return out


def write_run(folder: Path) -> Path:
    """A run folder's monitor.csv and training log, as mjrft train writes them (no model)."""
    folder.mkdir(parents=True)
    (folder / "monitor.csv").write_text('#{"t_start": 0}\nr,l,t,speed\n'
                                        + "".join(f"{k}.5,{10 + k},{k},0.1\n" for k in range(6)))
    log = folder / "logs" / "from_0000000000"
    log.mkdir(parents=True)
    (log / "progress.csv").write_text("time/total_timesteps,rollout/ep_rew_mean\n32,1.0\n64,2.0\n")
    return folder


def _error_line(argv, capsys) -> str:
    with pytest.raises(SystemExit) as e:
        cli(argv)
    err = capsys.readouterr().err
    assert e.value.code == 2 and len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    return err


# ---------------------------------------------------------------------------------------------- plot
@pytest.mark.parametrize("name", ["logs/from_0000000000/progress.csv", "monitor.csv"])
def test_plot_of_a_binary_file_names_it(tmp_path, capsys, name):
    folder = write_run(tmp_path / "run")
    (folder / name).write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR\xff\xfe")
    err = _error_line(["plot", str(folder), "--out", str(tmp_path / "c.png")], capsys)
    assert f"{folder / name}: " in err and "is not a text file" in err, err


def test_plot_says_which_rows_of_a_ragged_log_it_leaves_out(tmp_path):
    folder = write_run(tmp_path / "run")
    log = folder / "logs" / "from_0000000000" / "progress.csv"
    log.write_text(log.read_text() + "96,3.0,extra\n128\n")
    with pytest.warns(RuntimeWarning, match=f"{log}: 2 row.* left out; line 4 has 3 fields, the header 2"):
        run = load_run(folder)
    assert run.progress[0].tolist() == [32, 64]


def test_plot_skips_a_monitor_row_that_is_not_a_number_and_notes_it_once(tmp_path, capsys):
    folder = write_run(tmp_path / "run")
    monitor = folder / "monitor.csv"
    monitor.write_text(monitor.read_text() + "oops,12,7,0.1\n6.5,16,8,0.1\n")
    assert cli(["plot", str(folder), "--out", str(tmp_path / "c.png")]) == 0
    out, err = capsys.readouterr()
    assert "run: 7 episodes" in out  # six, the bad row left out, one after it
    notes = [line for line in out.splitlines() if line.startswith("note:")]
    assert notes == [f"note: 1 runtime warning(s), first: {monitor}: 1 line(s) that are not episode rows left out; "
                     "line 9 holds a value that is not a number: 'oops,12,7,0.1'"], out
    assert "Warning:" not in err and "warnings.warn" not in err  # no Python warning lines with their source
    assert (tmp_path / "c.png").is_file()


# ---------------------------------------------------------------------------------------------- rollout, eval
def test_rollout_notes_its_warnings_as_demo_does(tmp_path, capsys):
    # the 3 Hz tripod needs all of the hexapod's hip speed: the gait warns (mjrft.tools.gaits.GaitWarning)
    assert cli(["rollout", "--env", "mjrft/HexapodRigid-v0", "--policy", "tripod:f=3", "--seconds", "0.03",
                "--rrd", str(tmp_path / "r.rrd"), "--no-progress"]) == 0
    out, err = capsys.readouterr()
    notes = [line for line in out.splitlines() if line.strip().startswith("note:")]
    assert len(notes) == 1 and notes[0].startswith("  note: 1 gait warning(s), first: gait 'tripod' f=3 needs"), out
    assert out.index("return") < out.index("note:") < out.index("wrote")  # under the summary, as in mjrft demo
    assert "GaitWarning" not in err and "rollout.py" not in err


def test_a_damaged_config_json_is_said_once_and_the_model_still_runs(run, tmp_path, capsys):
    folder = tmp_path / "run"
    shutil.copytree(run, folder)
    (folder / "config.json").write_text("")
    from mjrft.train import evaluate as evaluate_module

    evaluate_module._REPORTED_CONFIGS.clear()  # said once per process: each command here is a new one
    assert cli(["eval", "--policy", str(folder), "--env", ENV, "--episodes", "1", "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert out.count("config.json") == 1 and "note: 1 skipped artefact warning(s), first: " in out, out
    assert "not valid JSON" in out and f"{folder / 'model.zip'} on {ENV}" in out
    # without --env: the note, then one error line saying what is missing
    evaluate_module._REPORTED_CONFIGS.clear()
    with pytest.raises(SystemExit) as e:
        cli(["eval", "--policy", str(folder), "--episodes", "1"])
    err = capsys.readouterr().err
    assert e.value.code == 2 and err.count("not valid JSON") == 1, err
    assert err.strip().splitlines()[-1].startswith("mjrft eval: error: give the env id for policy") and len(
        err.strip().splitlines()) == 2, err


def test_trust_with_a_pickle_of_something_else_is_one_line(run, tmp_path, capsys):
    folder = tmp_path / "run"
    shutil.copytree(run, folder)
    stats = folder / "model_vecnormalize.pkl"  # SB3's pickled VecNormalize statistics, here a dict
    stats.write_bytes(pickle.dumps({"obs_rms": 1}))
    err = _error_line(["eval", "--policy", str(folder), "--episodes", "1", "--trust"], capsys)
    assert f"{stats}: the pickle holds a dict, not stable-baselines3's VecNormalize statistics" in err
    with pytest.raises(ArtefactError, match="holds the class collections.OrderedDict, not"):
        stats.write_bytes(pickle.dumps(__import__("collections").OrderedDict))
        load_vecnormalize(stats, trust=True)
    buffer = folder / "step_replay_buffer.pkl"
    buffer.write_bytes(pickle.dumps([1, 2]))
    with pytest.raises(ArtefactError, match="holds a list, not a stable-baselines3 replay buffer"):
        load_replay_buffer(SimpleNamespace(replay_buffer=None), buffer, trust=True)  # refused before it is used


@pytest.mark.slow  # a new process importing JAX and Brax: 4 s of CPU, ~10 s on a busy 2-core machine
def test_eval_of_an_mjx_policy_prints_nothing_about_warp():
    """Importing MJX prints "Failed to import warp: ..." where NVIDIA Warp is not installed; mjrft runs MJX's JAX
    implementation, which does not use it. Run in a new process: MJX prints it once, on its first import."""
    pytest.importorskip("jax")
    pytest.importorskip("brax")
    folder = ROOT / "benchmarks" / "results" / "learning" / "mjx-cpu"
    code = f"from mjrft.train.evaluate import load_policy; print(load_policy({str(folder)!r}).kind)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.strip() == "brax-ppo" and "warp" not in out.stdout + out.stderr, out.stdout + out.stderr
    assert json.loads((folder / "policy.json").read_text())["env_id"] == "mjrft/HexapodSand-v0"

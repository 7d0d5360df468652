"""A resumed run keeps the configuration its run folder saved, and drops what a killed run recorded after the
checkpoint it resumes from; ``mjrft train`` takes only MuJoCo environments with continuous actions, so the
evaluation it prints works.

The runs train PPO on gymnasium's InvertedPendulum (MuJoCo, a few hundred steps) so that the suite stays fast.
"""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import textwrap
import warnings

import numpy as np
import pytest

pytest.importorskip("stable_baselines3")
pytest.importorskip("imageio")  # gymnasium.envs.mujoco needs it

from mjrft.tools.cli import main as cli  # noqa: E402
from mjrft.train.config import save_training_config  # noqa: E402
from mjrft.train.plot import load_run, read_monitor, read_progress  # noqa: E402
from mjrft.train.train import list_checkpoints, load_config, train  # noqa: E402

ENV = "InvertedPendulum-v5"
HP = {"n_steps": 32, "batch_size": 32, "n_epochs": 1, "policy_kwargs": {"net_arch": [16]}}


def _cli(*argv) -> int:
    return cli(["train", *map(str, argv), "--no-progress"])


# ---------------------------------------------------------------------------------------------- saved settings
def test_a_resume_keeps_the_saved_settings_and_records_a_deliberate_change(tmp_path, capsys):
    recipe = save_training_config({"env_id": ENV, "timesteps": 128, "n_envs": 2, "seed": 3, "checkpoint_every": 64,
                                   "vec_env": "dummy", "hyperparams": HP}, tmp_path / "recipe.yaml")
    out = tmp_path / "run"
    assert _cli("--config", recipe, "--out", out) == 0
    first = load_config(out / "config.json")

    # the documented resume, without the recipe: every setting is the saved run's
    assert _cli("--out", out, "--timesteps", 256) == 0
    cfg = load_config(out / "config.json")
    for key in ("seed", "n_envs", "checkpoint_every", "vec_env", "device", "torch_threads", "hyperparams",
                "hyperparams_given", "normalize", "config", "created"):
        assert cfg[key] == first[key], key
    assert [(r["from_step"], r["seed"], r["n_envs"], "changed" in r) for r in cfg["runs"]] == [
        (0, 3, 2, False), (128, 3, 2, False)]
    assert [s for s, _ in list_checkpoints(out)] == [64, 128, 192, 256]  # every 64 steps, as saved
    assert _cli("--out", out) == 0  # no --timesteps: the saved budget (256), already reached
    assert len(load_config(out / "config.json")["runs"]) == 2
    capsys.readouterr()

    # a setting that defines the run is refused in one line; config.json is left as it was
    saved = (out / "config.json").read_bytes()
    with pytest.raises(SystemExit) as e:
        _cli("--out", out, "--timesteps", 512, "--seed", 5)
    err = capsys.readouterr().err
    assert e.value.code == 2 and len(err.strip().splitlines()) == 1, err
    assert "seed 5 differs from the run being resumed (3 in" in err
    assert (out / "config.json").read_bytes() == saved

    # a setting of how it runs may change on purpose: said, recorded in the run's entry, in use from then on
    assert _cli("--out", out, "--timesteps", 320, "--n-envs", 1, "--checkpoint-every", 32) == 0
    assert "resuming with changed settings: n_envs 2 -> 1, checkpoint_every 64 -> 32" in capsys.readouterr().out
    cfg = load_config(out / "config.json")
    assert cfg["runs"][-1]["changed"] == {"n_envs": {"from": 2, "to": 1}, "checkpoint_every": {"from": 64, "to": 32}}
    assert (cfg["n_envs"], cfg["checkpoint_every"], cfg["seed"]) == (1, 32, 3)
    assert [s for s, _ in list_checkpoints(out)][-3:] == [256, 288, 320]


# ---------------------------------------------------------------------------------------------- a killed run
KILLED = textwrap.dedent("""
    import os, signal, sys
    from stable_baselines3.common.callbacks import BaseCallback
    from mjrft.train.train import train

    class Kill(BaseCallback):
        def _on_step(self):
            if self.num_timesteps >= 180:  # between the checkpoints at 96 and 192
                os.kill(os.getpid(), signal.SIGKILL)
            return True

    train("InvertedPendulum-v5", "ppo", 512, 1, 0, sys.argv[1], {}, checkpoint_every=96, callback=Kill(),
          hyperparams={"n_steps": 32, "batch_size": 32, "n_epochs": 1, "policy_kwargs": {"net_arch": [16]}})
""")


def test_a_resume_after_a_kill_drops_what_the_killed_run_lost(tmp_path):
    out = tmp_path / "run"
    proc = subprocess.run([sys.executable, "-c", KILLED, str(out)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == -signal.SIGKILL, proc.stderr
    assert [s for s, _ in list_checkpoints(out)] == [96]
    killed_monitor = (out / "monitor.csv").read_bytes()
    mark = json.loads((out / "checkpoints" / "step_0000000096_monitor.json").read_text())
    assert read_monitor(out / "monitor.csv").steps[-1] > 96  # episodes finished after the checkpoint
    assert read_progress(out)[0].max() == 160  # and rollouts logged after it

    said = []
    result = train(None, None, 256, out_dir=out, report=said.append)
    assert result.resumed_from.name == "step_0000000096.zip" and result.num_timesteps == 256
    run = load_config(out / "config.json")["runs"][-1]
    assert run["dropped"]["rows of logs/*/progress.csv"] == 2 and run["dropped"]["episodes of monitor.csv"] > 0
    assert any("dropped what the previous run recorded after step 96" in s for s in said), said

    # monitor.csv: the episodes up to the checkpoint, byte for byte, then the resumed run's
    monitor = (out / "monitor.csv").read_bytes()
    assert monitor[: mark["monitor_bytes"]] == killed_monitor[: mark["monitor_bytes"]]
    assert read_monitor(out / "monitor.csv").steps[-1] <= 256  # no more env steps than the model trained
    # the logs: each step once, in order (the killed run's rows at 128 and 160 are gone)
    assert read_progress(out)[0].tolist() == [32, 64, 96, 128, 160, 192, 224, 256]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        load_run(out)
    assert not [str(w.message) for w in caught if "left out" in str(w.message) or "killed" in str(w.message)]


def test_plot_marks_what_a_killed_run_lost_in_a_folder_resumed_without_the_drop(tmp_path):
    """A folder whose records still hold what a killed run lost (resumed by a version of mjrft that kept them):
    the overlapping log rows are left out and the monitor's excess is said."""
    (tmp_path / "monitor.csv").write_text('#{"t_start": 0}\nr,l,t\n' + "1.0,60,0.1\n" * 5)  # 300 steps
    for start, steps in ((0, (100, 200)), (100, (200, 250))):  # killed after 200, resumed from 100
        log = tmp_path / "logs" / f"from_{start:010d}"
        log.mkdir(parents=True)
        (log / "progress.csv").write_text("time/total_timesteps,rollout/ep_rew_mean\n"
                                          + "".join(f"{s},{s / 100}\n" for s in steps))
    (tmp_path / "config.json").write_text(json.dumps({"env_id": ENV, "num_timesteps": 250, "runs": [
        {"status": "crashed"}, {"status": "finished"}]}))
    with pytest.warns(RuntimeWarning) as caught:
        run = load_run(tmp_path)
    messages = [str(w.message) for w in caught]
    assert run.progress[0].tolist() == [100, 200, 250]  # 200 once: the resumed run's
    assert any("1 row(s) after step 100 left out" in m for m in messages), messages
    assert any("add up to 300 env steps, more than the 250 the run trained" in m for m in messages), messages


# ---------------------------------------------------------------------------------------------- which envs
def test_train_refuses_an_env_mjrft_cannot_evaluate_in_one_line(tmp_path, capsys):
    for env in ("CartPole-v1", "Pendulum-v1"):  # Discrete actions; no MuJoCo model
        with pytest.raises(SystemExit) as e:
            _cli("--env", env, "--timesteps", 64, "--out", tmp_path / env)
        err = capsys.readouterr().err
        assert e.value.code == 2 and len(err.strip().splitlines()) == 1, err
        assert f"{env}: it is not a MuJoCo environment" in err and "mjrft/HexapodSand-v0" in err
        assert not (tmp_path / env / "config.json").exists()
    assert "its actions are Discrete(2), not continuous (Box)" in str(
        pytest.raises(ValueError, train, "CartPole-v1", out_dir=tmp_path / "api").value)
    with pytest.raises(SystemExit):  # the gaits and the evaluation refuse it the same way
        cli(["eval", "--policy", "tripod", "--env", "CartPole-v1"])
    assert "CartPole-v1: it is not a MuJoCo environment" in capsys.readouterr().err


def test_the_eval_command_train_prints_works_for_a_gymnasium_mujoco_env(tmp_path, capsys):
    """gymnasium's own MuJoCo robots have no feet mjrft knows and no x_position in their info: the evaluation
    measures what they have (return, speed from the root joint, cost of transport) and reports 0 sinkage."""
    assert _cli("--env", ENV, "--timesteps", 64, "--out", tmp_path / "ip", "--hp", "n_steps=32",
                "--hp", "batch_size=32") == 0
    command = next(line for line in capsys.readouterr().out.splitlines() if line.startswith("evaluate: mjrft "))
    argv = command.removeprefix("evaluate: mjrft ").split()
    assert cli([*argv, "--no-progress"]) == 0
    table = capsys.readouterr().out
    assert "episode" in table and "mean" in table and "fall rate" in table
    rows = [line.split() for line in table.splitlines() if line.split() and line.split()[0].isdigit()]
    assert len(rows) == 10 and all(np.isfinite(float(r[1])) for r in rows)


def test_a_folder_without_a_checkpoint_names_the_command_that_restarts_its_run(tmp_path, capsys):
    out = tmp_path / "run"
    train(ENV, "ppo", 64, n_envs=1, seed=4, out_dir=out, checkpoint_every=32, hyperparams=HP)
    for ckpt in (out / "checkpoints").iterdir():  # as if killed before its first checkpoint
        ckpt.unlink()
    with pytest.raises(SystemExit):
        _cli("--out", out)
    err = capsys.readouterr().err
    command = err.strip().split("start its run again with its settings: ")[-1]
    assert command == f"mjrft train --config {out / 'config.json'} --out {out}", err
    assert _cli(*command.split()[2:]) == 0  # the command it names: the same settings, the config said replaced
    said = capsys.readouterr().out
    assert "holds no checkpoint to resume from: a new run starts there and replaces its config.json" in said
    cfg = load_config(out / "config.json")
    assert (cfg["seed"], cfg["hyperparams"]["n_steps"], cfg["num_timesteps"], len(cfg["runs"])) == (4, 32, 64, 1)


def test_sac_refuses_another_number_of_envs_on_resume(tmp_path):
    hp = {"learning_starts": 20, "batch_size": 16, "policy_kwargs": {"net_arch": [16]}}
    train(ENV, "sac", 40, out_dir=tmp_path, checkpoint_every=20, hyperparams=hp)
    with pytest.raises(ValueError, match=r"n_envs 2 differs from the SAC run being resumed \(1 in .*laid out per"):
        train(None, None, 80, n_envs=2, out_dir=tmp_path)

"""``mjrft demo`` and ``mjrft rollout``: exit 0, print the summary and write a readable rerun file."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

pytest.importorskip("rerun")
pytest.importorskip("datafusion")
gymnasium = pytest.importorskip("gymnasium")

from mjrft.tools.cli import main as cli  # noqa: E402
from mjrft.errors import TerrainStabilityWarning  # noqa: E402
from mjrft.tools.rerun_log import read_table  # noqa: E402
from mjrft.train.rollout import rollout  # noqa: E402


def test_demo_writes_a_readable_rerun_file(tmp_path, capsys):
    out = tmp_path / "demo.rrd"
    assert cli(["demo", "--seconds", "0.6", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert str(out) in text and f"rerun {out}" in text
    for word in ("distance", "mean speed", "mean sinkage"):
        assert word in text
    contacts = read_table(out, "/world/contacts")
    assert contacts.num_rows == 60 // 5 + 1  # frame 0 and every 5th of 60 env steps
    assert any(len(v or []) for v in contacts.column("/world/contacts:Points3D:positions").to_pylist())
    torso = read_table(out, "/world/robot/torso")
    times = [t.total_seconds() for t in torso.column("sim_time").to_pylist()]
    assert times[0] == pytest.approx(0.0) and times[-1] == pytest.approx(0.6)


def test_demo_default_path_in_the_current_folder(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert cli(["demo", "--seconds", "0.1"]) == 0
    assert (tmp_path / "mjrft-demo.rrd").is_file()
    assert str(tmp_path / "mjrft-demo.rrd") in capsys.readouterr().out


def test_rollout_summary_and_frames(tmp_path):
    path = tmp_path / "biped.rrd"
    s = rollout("mjrft/BipedSand-v0", "rect", steps=25, rrd_path=path, log_every=10, seed=1,
                env_kwargs={"pitch_free": False})
    assert s["steps"] == 25 and s["seconds"] == pytest.approx(0.25) and s["frames"] == 3
    assert s["mean_sinkage_mm"] > 0 and s["peak_sinkage_mm"] >= s["mean_sinkage_mm"]
    assert s["mean_speed"] == pytest.approx(s["distance"] / s["seconds"])
    assert not s["fell"]
    assert read_table(path, "/plots/sinkage").num_rows == 3
    # the same rollout without a file gives the same numbers (logging does not touch the simulation)
    s2 = rollout("mjrft/BipedSand-v0", "rect", steps=25, seed=1, env_kwargs={"pitch_free": False})
    assert s2["distance"] == s["distance"] and s2["frames"] == 0 and s2["rrd"] is None


def test_rollout_runs_a_saved_sb3_model(tmp_path, capsys):
    sb3 = pytest.importorskip("stable_baselines3")
    env = gymnasium.make("mjrft/HexapodRigid-v0")
    model = sb3.PPO("MlpPolicy", env, n_steps=64, batch_size=64, device="cpu", seed=0)
    model.save(tmp_path / "ppo_hex.zip")
    env.close()
    out = tmp_path / "ppo.rrd"
    assert cli(["rollout", "--env", "mjrft/HexapodRigid-v0", "--policy", str(tmp_path / "ppo_hex.zip"),
                "--seconds", "0.2", "--rrd", str(out), "--log-every", "4", "frame_skip=5"]) == 0
    text = capsys.readouterr().out
    assert "40 steps" in text and "11 frames" in text  # 0.2 s at 5 ms per env step; frame 0 + 10
    assert read_table(out, "/world/robot/torso").num_rows == 11


def test_rollout_on_an_env_object_with_seconds(tmp_path):
    env = gymnasium.make("mjrft/HexapodSand-v0", medium="poppy_lp", max_episode_steps=50)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TerrainStabilityWarning)
        s = rollout(env, "tripod:f=1.5", seconds=0.6, rrd_path=None)
    assert s["steps"] == 50  # the env's own time limit (0.5 s) ended it first
    assert not s["fell"]
    env.close()


@pytest.mark.parametrize("argv, match", [
    (["rollout", "--env", "mjrft/Nope-v0", "--policy", "tripod"], "valid choices"),
    (["rollout", "--env", "mjrft/HexapodSand-v0", "--policy", "tripod:f=-1"], "out of range"),
    (["rollout", "--env", "mjrft/HexapodSand-v0", "--policy", "missing.zip"], "neither a file nor a gait"),
    (["rollout", "--env", "mjrft/HexapodSand-v0", "--policy", "stand"], "gaits for this env: tripod"),
    (["rollout", "--env", "mjrft/HexapodSand-v0", "--policy", "tripod", "--seconds", "-2"], "seconds"),
    (["rollout", "--env", "mjrft/HexapodSand-v0", "--policy", "tripod", "--log-every", "0"], "log_every"),
    (["demo", "--gait", "rect"], "gaits for this env: tripod"),
    (["demo", "--medium", "quicksand"], "valid choices"),
])
def test_bad_input_is_one_error_line_and_status_2(argv, match, tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        cli(argv + (["--rrd", str(tmp_path / "x.rrd")] if argv[0] == "rollout" else ["--out", str(tmp_path / "x.rrd")]))
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert match in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "x.rrd").exists() or argv[0] == "demo"


def test_rollout_argument_checks():
    with pytest.raises(ValueError, match="exactly one"):
        rollout("mjrft/HexapodSand-v0", "tripod", seconds=1, steps=10)
    env = gymnasium.make("mjrft/HexapodRigid-v0")
    with pytest.raises(ValueError, match="env_kwargs"):
        rollout(env, "tripod", steps=2, env_kwargs={"medium": "poppy_lp"})
    assert np.isfinite(rollout(env, "tripod", steps=2)["distance"])
    env.close()


def test_log_every_has_one_default_for_demo_rollout_and_eval():
    from mjrft.tools import cli
    from mjrft.tools.rerun_log import LOG_EVERY

    argvs = (["demo"], ["rollout", "--env", "mjrft/HexapodSand-v0", "--policy", "tripod"], ["eval", "--policy", "tripod"])
    assert {cli.build_parser(a[0]).parse_args(a).log_every for a in argvs} == {LOG_EVERY}


def test_rollout_and_eval_show_progress_on_stderr(capsys, tmp_path):
    from mjrft.tools import cli

    assert cli.main(["rollout", "--env", "mjrft/HexapodRigid-v0", "--policy", "tripod", "--seconds", "0.3",
                     "--rrd", str(tmp_path / "r.rrd")]) == 0
    err = capsys.readouterr().err
    assert "rollout" in err and "30/30" in err, err
    assert cli.main(["eval", "--env", "mjrft/HexapodRigid-v0", "--policy", "tripod", "--episodes", "2",
                     "max_episode_steps=20"]) == 0
    err = capsys.readouterr().err
    assert "eval (2 episodes)" in err and "40/40" in err, err
    assert cli.main(["eval", "--env", "mjrft/HexapodRigid-v0", "--policy", "tripod", "--episodes", "1",
                     "--no-progress", "max_episode_steps=5"]) == 0
    assert "eval (" not in capsys.readouterr().err


def test_spawn_viewer_without_a_display_fails_fast(monkeypatch, tmp_path, capsys):
    import sys
    import time

    from mjrft.tools import cli

    if not sys.platform.startswith("linux"):
        pytest.skip("the display check applies to Linux/BSD")
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    for argv in (["demo", "--out", str(tmp_path / "d.rrd"), "--spawn-viewer"],
                 ["rollout", "--env", "mjrft/HexapodSand-v0", "--policy", "tripod", "--rrd", str(tmp_path / "r.rrd"),
                  "--spawn-viewer"]):
        t0 = time.perf_counter()
        with pytest.raises(SystemExit) as e:
            cli.main(argv)
        assert e.value.code == 2 and time.perf_counter() - t0 < 10
        assert "--spawn-viewer needs a display" in capsys.readouterr().err
        assert not list(tmp_path.iterdir())  # nothing written, no viewer process left behind

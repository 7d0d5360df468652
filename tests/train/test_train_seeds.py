"""``mjrft train --seeds``: one stable-baselines3 run per seed in ``OUT/seed-<S>/`` (the run of ``--seed S --out
OUT/seed-<S>``, resumed where it stopped and not trained again when complete), each final policy evaluated as
``mjrft eval`` does, and the mean and spread over the seeds in ``OUT/seeds.txt`` / ``OUT/seeds.json``
(:mod:`mjrft.train.seeds`).

The runs train PPO on gymnasium's InvertedPendulum (MuJoCo, 64 steps, 20-step episodes) so that the suite stays fast.
"""

from __future__ import annotations

import json
import math

import pytest

pytest.importorskip("stable_baselines3")
pytest.importorskip("imageio")  # gymnasium.envs.mujoco needs it

from mjrft.tools.cli import main as cli  # noqa: E402
from mjrft.train.config import save_training_config  # noqa: E402
from mjrft.train.evaluate import evaluate  # noqa: E402
from mjrft.train.seeds import spread  # noqa: E402
from mjrft.train.train import load_config  # noqa: E402

ENV = "InvertedPendulum-v5"
HP = {"n_steps": 32, "batch_size": 32, "n_epochs": 1, "policy_kwargs": {"net_arch": [16]}}


def _cli(*argv) -> int:
    return cli(["train", *map(str, argv), "--no-progress"])


def test_seeds_train_resume_evaluate_and_summarise(tmp_path, capsys):
    """``--seeds 2 1``: seed 1, stopped halfway by the one-seed command, resumes in its folder, seed 2 starts; each
    policy's row is ``mjrft eval``'s evaluation; the summary's spread is over both rows. The same command again
    trains and evaluates nothing, and a folder of other settings is refused before any seed trains."""
    recipe = save_training_config({"env_id": ENV, "timesteps": 64, "n_envs": 1, "checkpoint_every": 32,
                                   "vec_env": "dummy", "hyperparams": HP, "env_kwargs": {"max_episode_steps": 20}},
                                  tmp_path / "tiny.yaml")
    out = tmp_path / "runs"
    assert _cli("--config", recipe, "--seed", 1, "--out", out / "seed-1", "--timesteps", 32) == 0
    argv = ("--config", recipe, "--out", out, "--seeds", 2, 1, "--eval-episodes", 2)
    assert _cli(*argv) == 0
    assert sorted(p.name for p in out.iterdir()) == ["seed-1", "seed-2", "seeds.json", "seeds.txt"]
    for s, starts in ((1, [0, 32]), (2, [0])):
        cfg = load_config(out / f"seed-{s}" / "config.json")
        assert (cfg["seed"], cfg["num_timesteps"], cfg["hyperparams"]["n_steps"]) == (s, 64, 32)
        assert [r["from_step"] for r in cfg["runs"]] == starts and cfg["runs"][-1]["status"] == "finished"

    summary = json.loads((out / "seeds.json").read_text())
    assert (summary["env_id"], summary["seeds"], summary["finished"], summary["episodes"]) == (ENV, [2, 1], [2, 1], 2)
    rows = {r["seed"]: r for r in summary["rows"]}
    # seed 2's run and row are those of the one-seed command and of mjrft eval of its folder
    assert _cli("--config", recipe, "--seed", 2, "--out", tmp_path / "one") == 0
    one, two = (load_config(folder / "config.json") for folder in (tmp_path / "one", out / "seed-2"))
    assert all(one[k] == two[k] for k in ("env_id", "env_kwargs", "hyperparams", "seed", "n_envs", "config"))
    _, evaluated = evaluate(str(tmp_path / "one"), episodes=2)
    assert {k: rows[2][k] for k in ("return", "speed", "cot")} == {k: evaluated[k] for k in ("return", "speed", "cot")}
    assert rows[2]["fell"] == evaluated["fall_rate"] and rows[2]["num_timesteps"] == 64
    assert rows[1]["speed"] != rows[2]["speed"]  # two seeds, two policies
    assert all(r["warnings"] == 0 and r["unstable"] == 0 and r["train_s"] >= 0 for r in rows.values())
    returns = [rows[1]["return"], rows[2]["return"]]
    assert summary["spread"]["return"]["n"] == 2 and summary["spread"]["return"]["mean"] == pytest.approx(
        sum(returns) / 2) and summary["spread"]["return"]["sd"] == pytest.approx(abs(returns[0] - returns[1])
                                                                               / math.sqrt(2))
    text = (out / "seeds.txt").read_text()
    assert f"Recipe tiny over 2 seeds (2, 1; 2 finished) on {ENV} (max_episode_steps=20): PPO, 64 steps" in text
    assert f"$ mjrft train --config {recipe} --seed 1 --out {out / 'seed-1'}" in text
    assert f"$ mjrft eval --policy {out / 'seed-1'} --episodes 2" in text
    mean = next(line for line in text.splitlines() if line.startswith("mean"))
    assert mean.split()[1] == f"{sum(returns) / 2:.2f}"

    # the same command again: both runs are complete and evaluated; nothing is trained or evaluated again
    files = [out / f"seed-{s}" / f for s in (1, 2) for f in ("config.json", "model.zip", "evaluation.json")]
    before = [(f.read_bytes(), f.stat().st_mtime_ns) for f in files]
    capsys.readouterr()
    assert _cli(*argv) == 0
    assert capsys.readouterr().out.count("not trained again") == 2
    assert [(f.read_bytes(), f.stat().st_mtime_ns) for f in files] == before
    assert json.loads((out / "seeds.json").read_text())["rows"] == summary["rows"]

    # other settings in a seed's folder: one line, exit status 2, and no seed trained (seed 3's folder not made)
    with pytest.raises(SystemExit) as exit_:
        _cli("--config", recipe, "--out", out, "--seeds", 3, 1, "--hp", "n_steps=64")
    assert exit_.value.code == 2 and "hyper-parameter n_steps 64 differs" in capsys.readouterr().err
    assert not (out / "seed-3").exists()


@pytest.mark.parametrize("argv, message", [
    (["--env", ENV, "--seed", "1", "--seeds", "0"], "argument --seeds: not allowed with argument --seed"),
    (["--env", ENV, "--seeds", "0", "0"], "--seeds must name each seed once, got [0, 0]"),
    (["--env", ENV, "--seeds", "-1"], "--seeds must be integers >= 0, got [-1]"),
    (["--env", ENV, "--seeds", "1.5"], "argument --seeds: expected an integer, got '1.5'"),
    (["--env", ENV, "--seeds", "0", "--eval-episodes", "-1"], "--eval-episodes must be an integer >= 0, got -1"),
    (["--env", ENV, "--eval-episodes", "2"], "--eval-episodes applies to --seeds"),
    (["--seeds", "0"], "seed-0 holds no run to resume: give --config or --env to start seed 0")])
def test_bad_seeds_are_refused_before_anything_runs(tmp_path, capsys, argv, message):
    out = tmp_path / "runs"
    with pytest.raises(SystemExit) as exit_:
        _cli("--out", out, *argv)
    assert exit_.value.code == 2 and message in capsys.readouterr().err
    assert not out.exists()


def test_an_interrupted_seed_stops_the_run(tmp_path, monkeypatch, capsys):
    """Ctrl-C in a seed's training (its checkpoint saved by ``train``): the run stops there with status 130, no
    later seed trains, and the summary is not written; the same command resumes it."""
    from mjrft.train import train as train_module

    started = []

    def interrupted(cfg, out_dir, **options):
        started.append(cfg["seed"])
        return train_module.TrainResult(out_dir, out_dir / "model.zip", out_dir / "config.json", 16, interrupted=True)

    monkeypatch.setattr(train_module, "train_settings", interrupted)
    out = tmp_path / "runs"
    assert _cli("--env", ENV, "--out", out, "--seeds", 4, 5) == 130
    assert started == [4] and not (out / "seeds.txt").exists()
    assert "seed 4: interrupted at 16 steps; run the same command to resume" in capsys.readouterr().out


def test_a_measure_saved_as_null_is_left_out_of_the_spread():
    """A seed whose measure is NaN (every episode diverged) keeps it as null in evaluation.json; read back, it is
    left out of the spread like the NaN, not an error."""
    assert spread([0.3, None, 0.5]) == spread([0.3, math.nan, 0.5]) == {
        "n": 2, "mean": pytest.approx(0.4), "sd": pytest.approx(0.1 * math.sqrt(2)), "min": 0.3, "max": 0.5}

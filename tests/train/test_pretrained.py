"""The policy shipped with mjrft (``pretrained:HexapodSand-v0``) against the open-loop tripod.

The full comparison (10 episodes, every tripod frequency, every ground) is
``python benchmarks/learning_transfer.py`` (benchmarks/results/learning/); here one episode of each on the
env the policy was trained on checks its criteria: faster than the tripod at its best frequency,
cost of transport at most 1.5x the tripod's, no fall.
"""

import csv
from pathlib import Path

import pytest

pytest.importorskip("stable_baselines3")

from mjrft.tools.cli import main as cli  # noqa: E402
from mjrft.train.evaluate import evaluate, pretrained_names, trained_env  # noqa: E402

SWEEP = Path(__file__).resolve().parents[2] / "benchmarks" / "results" / "learning" / "tripod_sweep.csv"


def best_tripod_frequency(env_id: str) -> float:
    """The rule of benchmarks/learning_transfer.py: fastest frequency among those that never fell."""
    with open(SWEEP) as fh:
        rows = [r for r in csv.DictReader(fh) if r["ground"] == env_id]
    standing = [r for r in rows if float(r["fall_rate"]) == 0.0] or rows
    return float(max(standing, key=lambda r: float(r["speed"]))["f_hz"])


def test_the_hexapod_policy_is_shipped():
    assert "HexapodSand-v0" in pretrained_names()
    assert trained_env("pretrained:HexapodSand-v0")[0] == "mjrft/HexapodSand-v0"
    assert trained_env("pretrained:mjrft/HexapodSand-v0")[0] == "mjrft/HexapodSand-v0"


def test_pretrained_policy_beats_the_tripod_at_its_best_frequency():
    f = best_tripod_frequency("mjrft/HexapodSand-v0")
    _, learned = evaluate("pretrained:HexapodSand-v0", episodes=1)
    _, tripod = evaluate(f"tripod:f={f:g}", "mjrft/HexapodSand-v0", episodes=1)
    assert learned["fall_rate"] == 0.0
    assert learned["speed"] > tripod["speed"]
    assert learned["cot"] <= 1.5 * tripod["cot"]


def test_unknown_pretrained_name_lists_the_choices():
    with pytest.raises(ValueError, match="pretrained:HexapodSand-v0"):
        evaluate("pretrained:Nope-v0", episodes=1)


def test_rollout_cli_takes_the_env_of_a_pretrained_policy(tmp_path, capsys):
    rrd = tmp_path / "hex.rrd"
    assert cli(["rollout", "--policy", "pretrained:HexapodSand-v0", "--seconds", "0.5", "--rrd", str(rrd),
                "--no-progress"]) == 0
    assert rrd.is_file() and "HexapodSand-v0" in capsys.readouterr().out


def test_the_shipped_policy_loads_without_unpickling_anything(monkeypatch):
    import pickle

    import cloudpickle

    from mjrft.train.evaluate import PRETRAINED_DIR, load_policy

    folder = PRETRAINED_DIR / "HexapodSand-v0"
    assert sorted(p.name for p in folder.iterdir()) == ["config.json", "model.zip", "model_vecnormalize.npz"]

    def refuse(*a, **k):
        raise AssertionError("pickle was used")

    for module, name in ((pickle, "load"), (pickle, "loads"), (cloudpickle, "loads")):
        monkeypatch.setattr(module, name, refuse)
    loaded = load_policy("pretrained:HexapodSand-v0")
    assert loaded.vecnormalize.obs_rms.mean.shape == (35,) and loaded.model.num_timesteps == 1003520

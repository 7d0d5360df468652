"""Training configurations (mjrft.train.config) and ``mjrft train --config``."""

import json

import pytest

pytest.importorskip("stable_baselines3")
pytest.importorskip("yaml")

from mjrft.tools.cli import main as cli  # noqa: E402
from mjrft.train.config import (KEYS, check_training_config, load_training_config, named_configs,  # noqa: E402
                                save_training_config)


def test_named_recipe_is_shipped_and_complete():
    assert "hexapod-sand" in named_configs()
    cfg = load_training_config("hexapod-sand")
    assert list(cfg) == list(KEYS)
    assert cfg["env_id"] == "mjrft/HexapodSand-v0" and cfg["algo"] == "ppo"
    assert cfg["timesteps"] <= 3_000_000  # the recipe's budget: at most 3M steps
    assert cfg["description"]


@pytest.mark.parametrize("suffix", [".yaml", ".json"])
def test_config_file_round_trips(tmp_path, suffix):
    cfg = load_training_config("hexapod-sand")
    path = save_training_config(cfg, tmp_path / f"mine{suffix}")
    assert load_training_config(path) == cfg


def test_bad_configs_name_the_problem(tmp_path):
    with pytest.raises(ValueError, match="hexapod-sand"):
        load_training_config("hexapod-snad")
    with pytest.raises(ValueError, match="does not exist"):
        load_training_config(tmp_path / "missing.yaml")
    bad = tmp_path / "bad.yaml"
    bad.write_text("env_id: mjrft/HexapodSand-v0\nlearning_rate: 0.1\n")
    with pytest.raises(ValueError, match="unknown key.*'learning_rate'.*valid keys"):
        load_training_config(bad)
    with pytest.raises(ValueError, match="'env_id'.*required"):
        check_training_config({"algo": "ppo"})
    with pytest.raises(ValueError, match="'hyperparams' must be a mapping"):
        check_training_config({"env_id": "x", "hyperparams": [1, 2]})
    with pytest.raises(ValueError, match="'timesteps' must be an integer"):
        check_training_config({"env_id": "x", "timesteps": 1.5})


@pytest.mark.slow
def test_train_with_the_named_config_writes_the_run_and_round_trips(tmp_path, capsys):
    out = tmp_path / "run"
    # the named recipe, shortened on the command line (the overrides are part of the run's settings)
    rc = cli(["train", "--config", "hexapod-sand", "--out", str(out), "--timesteps", "2048", "--n-envs", "1",
              "--checkpoint-every", "512", "--vec-env", "dummy", "--hp", "n_steps=512", "--hp", "batch_size=128", "--no-progress",
              "resolution=0.02"])
    assert rc == 0
    for name in ("model.zip", "model_vecnormalize.npz", "config.json", "monitor.csv", "warnings.csv"):
        assert (out / name).is_file(), name
    assert list((out / "checkpoints").glob("step_*.zip"))
    run = json.loads((out / "config.json").read_text())
    assert run["config"] == "hexapod-sand" and run["num_timesteps"] >= 2048
    expected = load_training_config("hexapod-sand")
    expected.update(timesteps=2048, n_envs=1, checkpoint_every=512, vec_env="dummy", description="")
    expected["hyperparams"].update(n_steps=512, batch_size=128)
    expected["env_kwargs"] = {"resolution": 0.02}
    # the run's config.json is itself a training config holding exactly these settings
    assert load_training_config(out / "config.json") == expected
    # and repeating the run from it gives the same settings again
    again = tmp_path / "again"
    assert cli(["train", "--config", str(out / "config.json"), "--out", str(again), "--no-progress"]) == 0
    assert load_training_config(again / "config.json") == expected

"""The MJX recipes (``train/configs/mjx/``): every registered MJX environment has one that loads and names it, each
sand task's rigid twin trains at the same settings, and a recipe over several seeds (``mjrft train-mjx --seeds``)
writes one run per seed and the mean and spread over the seeds (:mod:`mjrft.train.seeds`)."""

from __future__ import annotations

import json
import math

import pytest

pytest.importorskip("jax", reason="the MJX recipes need the optional extra mjrft[mjx]")
pytest.importorskip("brax", reason="the MJX recipes need the optional extra mjrft[mjx]")
pytest.importorskip("ml_collections", reason="the MJX environments need ml_collections (mjrft[mjx])")

from mjrft.train import mjx_ppo  # noqa: E402
from mjrft.train import seeds  # noqa: E402
from mjrft.train.seeds import seeds_table, spread  # noqa: E402


def recipes() -> dict:
    return {name: mjx_ppo.load_recipe(name) for name in mjx_ppo.named_recipes()}


def test_every_registered_env_has_a_recipe_that_names_it():
    from mjrft.mjx import envs

    loaded = recipes()
    named = {cfg["env"] for cfg in loaded.values()}
    assert set(envs.names()) <= named, f"MJX envs without a recipe: {sorted(set(envs.names()) - named)}"
    assert named <= set(envs.names())
    for name, cfg in loaded.items():
        assert cfg["description"].strip(), f"recipe {name} has no description"
        assert cfg["ppo"]["normalize_observations"] is True
        if name != "hexapod-sand-cpu":  # the CPU-sized one names its own worlds in its description
            assert f"--config {name}" in cfg["description"], f"recipe {name}'s description lacks its command"
    # a recipe naming an environment outside the registry is refused (the check above could fail)
    with pytest.raises(ValueError, match="unknown env 'BipedSnad'"):
        mjx_ppo.check_recipe({**loaded["biped-sand"], "env": "BipedSnad"})


@pytest.mark.parametrize("robot", ["hexapod", "biped", "humanoid", "go2-joystick"])
def test_the_rigid_twin_trains_at_the_sand_recipes_settings(robot):
    loaded = recipes()
    sand, rigid = loaded[f"{robot}-sand"], loaded[f"{robot}-rigid"]
    assert sand["env"].endswith("Sand") and rigid["env"] == sand["env"][:-len("Sand")] + "Rigid"
    same = [k for k in mjx_ppo.RECIPE_KEYS if k not in ("env", "description")]
    assert {k: rigid[k] for k in same} == {k: sand[k] for k in same}


def test_spread_is_the_mean_and_sample_deviation_of_the_finite_values():
    s = spread([0.373, 0.358, 0.242])  # the SB3 recipe's three seeds (benchmarks/results/learning/recipe_seeds.txt)
    assert (s["n"], round(s["mean"], 3), round(s["sd"], 3), s["min"], s["max"]) == (3, 0.324, 0.072, 0.242, 0.373)
    assert round(spread([1.0, 3.0])["sd"], 6) == round(math.sqrt(2.0), 6)  # ddof=1: the population's would be 1
    one = spread([2.0, math.nan])
    assert one["n"] == 1 and one["mean"] == 2.0 and math.isnan(one["sd"])
    text = seeds_table([{"seed": 0, "v": 1.0}, {"seed": 1, "v": 3.0}, {"seed": 2}], [("v", "value", 2)])
    lines = text.splitlines()
    assert lines[3].split() == ["2", "-"] and lines[4].split() == ["mean", "2.00"]
    assert lines[5].split() == ["sd", "1.41"]


@pytest.mark.parametrize("bad, match", [([0, 0], "each seed once"), ([-1], "integers >= 0")])
def test_bad_seeds_are_refused(bad, match):
    with pytest.raises(ValueError, match=match):
        seeds.check_seeds(bad)


@pytest.mark.slow  # six CPU envs built and stepped: ~25 s on a busy 2-core machine
def test_a_policy_of_every_robot_runs_on_the_cpu_env_of_its_task(tmp_path):
    """The cross-check's other half for every MJX env with a gymnasium twin: a policy file in train-mjx's form
    (policy.json with the env's gymnasium id and sizes, policy.npz; fresh weights) runs on that CPU env through
    mjrft eval's evaluate, two steps of one episode each (the sizes are the rigid env's: both grounds share the
    task)."""
    import gymnasium

    import mjrft.envs  # noqa: F401  (registers the ids)
    from mjrft.envs.mjx.locomotion import Biped, Hexapod, Humanoid
    from mjrft.mjx import envs
    from mjrft.train.evaluate import evaluate

    for cls in (Hexapod, Biped, Humanoid):
        cpu = gymnasium.make(cls.gym_ids["rigid"])
        sizes = cpu.observation_space.shape[0], cpu.action_space.shape[0]
        cpu.close()
        for ground in ("sand", "rigid"):
            name, gym_id = cls.registry_name(ground), cls.gym_ids[ground]
            assert name in envs.names() and gym_id in gymnasium.registry
            meta = {"env": name, "env_config": {}, "env_id": gym_id, "env_kwargs": {}, "observation_size": sizes[0],
                    "action_size": sizes[1], "network": {"policy_hidden_layer_sizes": [4],
                                                         "value_hidden_layer_sizes": [4]}, "complete": True}
            run = tmp_path / name
            mjx_ppo.save_policy(run, mjx_ppo._template(meta)[1], meta)
            rows, summary = evaluate(str(run), episodes=1, env_kwargs={"max_episode_steps": 2})
            assert (summary["env_id"], summary["kind"], rows[0]["steps"]) == (gym_id, "brax-ppo", 2), name


def test_eval_says_that_the_go2_joystick_task_has_no_cpu_env(tmp_path, capsys):
    """A policy of an MJX env without a gymnasium twin (``env_id`` null in its policy.json): mjrft eval refuses it
    in one line that says so, on either backend, before building anything."""
    from mjrft.tools.cli import main as cli

    run = tmp_path / "go2"
    run.mkdir()
    (run / "policy.json").write_text(json.dumps({"format": mjx_ppo.FORMAT, "env": "Go2JoystickSand", "env_id": None,
                                                 "env_config": {}, "observation_size": 48, "action_size": 12}))
    (run / "policy.npz").write_bytes(b"")
    with pytest.raises(SystemExit) as exit_:
        cli(["eval", "--policy", str(run), "--episodes", "1"])
    assert exit_.value.code == 2 and "Go2JoystickSand, an MJX env with no gymnasium env" in capsys.readouterr().err


TINY = {"env": "Go2JoystickRigid", "num_timesteps": 320, "num_envs": 4, "episode_length": 20,
        "network": {"policy_hidden_layer_sizes": [8], "value_hidden_layer_sizes": [8]},
        "ppo": {"unroll_length": 5, "batch_size": 4, "num_minibatches": 2, "num_updates_per_batch": 1,
                "num_evals": 2, "normalize_observations": True}}


def test_seeds_write_a_run_per_seed_and_the_spread(tmp_path, monkeypatch, capsys):
    """``--seeds 3 1``: one run folder per seed, trained with its own seed, and the summary's mean and sample
    deviation of the seeds' returns; the same command again trains nothing, and a complete run of another recipe
    in a seed's folder is refused. The training is a stand-in that writes a complete run folder whose final return
    is 10 + seed (``mjrft train-mjx --seeds`` trains for real in tests/envs/test_mjx_env.py)."""
    import numpy as np

    from mjrft.tools.cli import main as cli

    trained = []

    def train(cfg, out, report=print):
        trained.append(cfg["seed"])
        meta = {"env": cfg["env"], "env_config": cfg["env_config"], "env_id": None, "recipe": cfg,
                "observation_size": 48, "action_size": 12, "complete": True, "wall_s": 2.0, "device": "cpu",
                "devices": 1, "final": {"eval/episode_reward": 10.0 + cfg["seed"]}}
        mjx_ppo.save_policy(out, {"w": np.zeros(2)}, meta)
        return meta

    monkeypatch.setattr(seeds, "train_recipe", train)
    recipe, out = tmp_path / "tiny.json", tmp_path / "runs"
    recipe.write_text(json.dumps(TINY))
    argv = ["train-mjx", "--config", str(recipe), "--out", str(out), "--seeds", "3", "1"]
    assert cli(argv) == 0
    assert trained == [3, 1]
    assert sorted(p.name for p in out.iterdir()) == ["seed-1", "seed-3", "seeds.json", "seeds.txt"]
    assert all(mjx_ppo.read_meta(out / f"seed-{s}")["recipe"]["seed"] == s for s in (1, 3))
    def no_constants(name):
        raise AssertionError(f"seeds.json holds {name}, which is not JSON")

    summary = json.loads((out / "seeds.json").read_text(), parse_constant=no_constants)
    assert [(r["seed"], r["return"]) for r in summary["rows"]] == [(3, 13.0), (1, 11.0)]
    assert summary["spread"]["cpu_speed"]["mean"] is None  # no CPU env for the Go2: no CPU measure, as null
    assert summary["spread"]["return"] == {"n": 2, "mean": 12.0, "sd": pytest.approx(math.sqrt(2.0)), "min": 11.0,
                                           "max": 13.0}
    text = (out / "seeds.txt").read_text()
    assert "Recipe tiny over 2 seeds (3, 1; 2 finished) on Go2JoystickRigid" in text
    assert "Go2JoystickRigid has no gymnasium env of the same task" in text
    assert f"$ mjrft train-mjx --config {recipe} --seed 1 --out {out / 'seed-1'}" in text
    assert [line.split()[:2] for line in text.splitlines() if line.startswith(("mean", "  sd"))] == [
        ["mean", "12.00"], ["sd", "1.41"]]
    capsys.readouterr()
    assert cli(argv) == 0  # both runs are complete: nothing is trained again, the summary is the same
    assert trained == [3, 1] and capsys.readouterr().out.count("not trained again") == 2
    assert json.loads((out / "seeds.json").read_text())["rows"] == summary["rows"]
    with pytest.raises(SystemExit) as exit_:  # a complete run of another recipe in the folder: one line, status 2
        cli(["train-mjx", "--config", str(recipe), "--out", str(out), "--seeds", "1", "--timesteps", "640"])
    assert exit_.value.code == 2 and "holds a complete run of another recipe" in capsys.readouterr().err
    assert trained == [3, 1]

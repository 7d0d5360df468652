"""Tests of ``mjrft train`` / ``mjrft eval`` (mjrft.train.train, mjrft.train.evaluate).

Kept small: the hexapod on poppy seeds with coarse elements (3 cm), 100-step episodes, tiny networks.
"""

from __future__ import annotations

import csv
import json
import warnings

import numpy as np
import pytest

pytest.importorskip("stable_baselines3")
pytest.importorskip("imageio")  # gymnasium.envs.mujoco needs it

import gymnasium  # noqa: E402
from stable_baselines3 import PPO, SAC  # noqa: E402
from stable_baselines3.common.callbacks import BaseCallback  # noqa: E402

from mjrft.tools.cli import main as cli  # noqa: E402
from mjrft.envs import ENV_IDS  # noqa: E402
from mjrft.errors import TerrainStabilityWarning  # noqa: E402
from mjrft.train.evaluate import COLUMNS, evaluate, format_table, load_policy  # noqa: E402
from mjrft.train.train import (atomic_write, list_checkpoints, load_config, parse_kwargs,  # noqa: E402
                               side_file, train)

HEX = "mjrft/HexapodSand-v0"
ENV_KW = {"resolution": 0.03, "max_episode_steps": 100}
PPO_HP = {"n_steps": 256, "batch_size": 64, "n_epochs": 2, "policy_kwargs": {"net_arch": [32, 32]}}


@pytest.fixture(autouse=True)
def _quiet():
    with warnings.catch_warnings():  # random early policies stomp; the coarse legs may warn (not under test)
        warnings.simplefilter("ignore", TerrainStabilityWarning)
        yield


@pytest.fixture(scope="module")
def ppo_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("ppo")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TerrainStabilityWarning)
        result = train(HEX, "ppo", 1024, 1, 3, out, ENV_KW, checkpoint_every=512, hyperparams=PPO_HP)
    return result


class StopAt(BaseCallback):
    """Simulates Ctrl-C: raises KeyboardInterrupt once num_timesteps reaches ``step``."""

    def __init__(self, step):
        super().__init__()
        self.step = step

    def _on_step(self) -> bool:
        if self.num_timesteps >= self.step:
            raise KeyboardInterrupt
        return True


# ---------------------------------------------------------------------------------------------- training
def test_smoke_run_saves_reloads_and_evaluates(ppo_run):
    out = ppo_run.out_dir
    assert not ppo_run.interrupted and ppo_run.num_timesteps == 1024
    assert ppo_run.model_path == out / "model.zip" and ppo_run.model_path.is_file()
    assert [s for s, _ in list_checkpoints(out)] == [512, 1024]
    cfg = load_config(out / "config.json")
    assert cfg["env_id"] == HEX and cfg["algo"] == "ppo" and cfg["seed"] == 3 and cfg["n_envs"] == 1
    assert cfg["env_kwargs"] == ENV_KW and cfg["num_timesteps"] == 1024
    hp = cfg["hyperparams"]  # SB3 defaults filled in, the given ones applied
    assert hp["n_steps"] == 256 and hp["gamma"] == 0.99 and hp["policy_kwargs"] == {"net_arch": [32, 32]}
    assert {"stable-baselines3", "torch", "mujoco", "gymnasium", "mjrft"} <= set(cfg["versions"])
    assert cfg["runs"][-1]["status"] == "finished"
    assert len(open(out / "monitor.csv").read().splitlines()) > 2  # header lines + finished episodes

    model = PPO.load(ppo_run.model_path, device="cpu")
    assert model.num_timesteps == 1024
    rows, summary = evaluate(ppo_run.model_path, episodes=2, seed=0, env_kwargs={"max_episode_steps": 40})
    assert summary["env_id"] == HEX and summary["kind"] == "ppo"
    assert summary["env_kwargs"] == {"resolution": 0.03, "max_episode_steps": 40}  # the run's, overridden
    assert [r["episode"] for r in rows] == [0, 1] and set(COLUMNS) <= set(rows[0])
    for r in rows:
        assert r["steps"] == 40 and not r["fell"]
        assert all(np.isfinite(r[k]) for k in COLUMNS[1:-1])
        assert r["sink_peak_mm"] >= r["sink_mean_mm"] > 0  # the hexapod stands in the sand
    # the reloaded policy gives the trained model's actions
    env = gymnasium.make(HEX, **ENV_KW)
    obs, _ = env.reset(seed=0)
    loaded = load_policy(out)  # a run folder means its model.zip
    np.testing.assert_array_equal(loaded.predict(obs)[0], model.predict(obs, deterministic=True)[0])
    env.close()


def test_evaluation_is_reproducible_bit_for_bit(ppo_run):
    kw = {"max_episode_steps": 30}
    a = evaluate(ppo_run.model_path, episodes=2, seed=5, env_kwargs=kw)
    b = evaluate(ppo_run.model_path, episodes=2, seed=5, env_kwargs=kw)
    assert a == b
    c = evaluate(ppo_run.model_path, episodes=2, seed=6, env_kwargs=kw)
    assert c[0][0]["return"] != a[0][0]["return"]  # another seed, other reset noise
    # stochastic evaluation is seeded too
    s1 = evaluate(ppo_run.model_path, episodes=1, seed=5, env_kwargs=kw, deterministic=False)
    s2 = evaluate(ppo_run.model_path, episodes=1, seed=5, env_kwargs=kw, deterministic=False)
    assert s1 == s2 and s1[0] != a[0][:1]


def test_resume_continues_the_step_count(ppo_run, tmp_path):
    out = tmp_path / "run"
    hp = {**PPO_HP, "n_steps": 128}
    first = train(HEX, "ppo", 2048, 1, 0, out, ENV_KW, checkpoint_every=128, hyperparams=hp, callback=StopAt(300))
    assert first.interrupted and first.num_timesteps == 300
    assert (out / "model.zip").is_file() and PPO.load(out / "model.zip").num_timesteps == 300
    assert [s for s, _ in list_checkpoints(out)] == [128, 256, 300]
    assert load_config(out / "config.json")["runs"][-1]["status"] == "interrupted"

    # resume with a smaller budget: continues from 300 and stops at the first rollout end >= 512
    second = train(None, None, 512, 1, 0, out, None, checkpoint_every=128)
    assert second.resumed_from == out / "checkpoints" / "step_0000000300.zip"
    assert not second.interrupted and second.num_timesteps == 300 + 2 * 128
    assert PPO.load(out / "model.zip").num_timesteps == second.num_timesteps
    assert [s for s, _ in list_checkpoints(out)] == [128, 256, 300, 384, 512, 556]
    cfg = load_config(out / "config.json")
    assert [(r["from_step"], r["to_step"]) for r in cfg["runs"]] == [(0, 300), (300, 556)]
    assert cfg["hyperparams"]["n_steps"] == 128  # the saved configuration was used
    assert (out / "logs" / "from_0000000300" / "progress.csv").is_file()

    # a finished budget is left alone; conflicting settings are refused
    again = train(HEX, "ppo", 512, 1, 0, out, checkpoint_every=128)
    assert again.num_timesteps == second.num_timesteps and len(load_config(out / "config.json")["runs"]) == 2
    with pytest.raises(ValueError, match="differs from the run being resumed"):
        train(HEX, "sac", 4096, 1, 0, out)
    with pytest.raises(ValueError, match="resolution"):
        train(HEX, "ppo", 4096, 1, 0, out, {"resolution": 0.01})

    # the PPO run of the fixture continues too (another budget, periodic checkpoints keep their grid)
    more = train(None, None, 1536, 1, 3, ppo_run.out_dir, None, checkpoint_every=512)
    assert more.resumed_from.name == "step_0000001024.zip" and more.num_timesteps == 1536
    assert [s for s, _ in list_checkpoints(ppo_run.out_dir)] == [512, 1024, 1536]


def test_subprocess_vec_env(tmp_path):
    hp = {**PPO_HP, "n_steps": 64}
    result = train(HEX, "ppo", 256, 2, 1, tmp_path, ENV_KW, checkpoint_every=128, hyperparams=hp, vec_env="subproc")
    assert result.num_timesteps == 256
    cfg = load_config(result.config_path)
    assert cfg["vec_env"] == "subproc" and cfg["n_envs"] == 2 and cfg["start_method"] in ("forkserver", "spawn")
    assert [s for s, _ in list_checkpoints(tmp_path)] == [128, 256]


def test_sac_smoke_with_replay_buffer(tmp_path):
    hp = {"learning_starts": 50, "batch_size": 32, "policy_kwargs": {"net_arch": [32, 32]}}
    result = train(HEX, "sac", 150, 1, 0, tmp_path, ENV_KW, checkpoint_every=100, hyperparams=hp)
    assert result.num_timesteps == 150
    cfg = load_config(result.config_path)
    assert cfg["hyperparams"]["buffer_size"] == 150  # capped at the budget
    ckpts = list_checkpoints(tmp_path)
    assert [s for s, _ in ckpts] == [100, 150]
    # only the newest checkpoint keeps its (large) replay buffer
    assert [side_file(p, "_replay_buffer.npz").exists() for _, p in ckpts] == [False, True]
    resumed = train(None, None, 200, 1, 0, tmp_path, None, checkpoint_every=100)
    assert resumed.num_timesteps == 200 and resumed.resumed_from.name == "step_0000000150.zip"
    assert SAC.load(tmp_path / "model.zip").num_timesteps == 200
    rows, summary = evaluate(tmp_path / "model.zip", episodes=1, env_kwargs={"max_episode_steps": 20})
    assert summary["kind"] == "sac" and rows[0]["steps"] == 20


def test_normalize_statistics_are_saved_and_used(tmp_path):
    hp = {**PPO_HP, "n_steps": 128}
    result = train(HEX, "ppo", 128, 1, 0, tmp_path, ENV_KW, checkpoint_every=128, hyperparams=hp, normalize=True)
    assert (tmp_path / "model_vecnormalize.npz").is_file()
    assert side_file(list_checkpoints(tmp_path)[-1][1], "_vecnormalize.npz").is_file()
    loaded = load_policy(result.model_path)
    assert loaded.vecnormalize is not None and not loaded.vecnormalize.training
    env = gymnasium.make(HEX, **ENV_KW)
    obs, _ = env.reset(seed=0)
    expected = loaded.model.predict(loaded.vecnormalize.normalize_obs(obs), deterministic=True)[0]
    np.testing.assert_array_equal(loaded.predict(obs)[0], expected)
    env.close()
    # resuming restores the statistics and keeps updating them
    train(None, None, 256, 1, 0, tmp_path, None, checkpoint_every=128)
    count = load_policy(tmp_path / "model.zip").vecnormalize.obs_rms.count
    assert count == pytest.approx(loaded.vecnormalize.obs_rms.count + 1 + 128)  # the reset, then 128 steps


def test_atomic_write_keeps_the_old_file_on_failure(tmp_path):
    target = tmp_path / "step_0000000001.zip"
    target.write_bytes(b"complete")

    def broken(path):
        open(path, "wb").write(b"half a fi")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        atomic_write(target, broken)
    assert target.read_bytes() == b"complete" and list(tmp_path.iterdir()) == [target]


# ---------------------------------------------------------------------------------------------- input errors
def test_bad_names_list_the_choices(tmp_path):
    with pytest.raises(ValueError, match="unknown algorithm 'a2c'; valid choices: ppo, sac"):
        train(HEX, "a2c", 100, 1, 0, tmp_path)
    with pytest.raises(ValueError, match="unknown env id 'Hexapod'.*mjrft/HexapodSand-v0"):
        train("Hexapod", "ppo", 100, 1, 0, tmp_path)
    with pytest.raises(ValueError, match="unknown PPO hyper-parameter 'n_step'.*n_steps"):
        train(HEX, "ppo", 100, 1, 0, tmp_path, hyperparams={"n_step": 64})
    with pytest.raises(ValueError, match="bad env kwarg.*valid keyword arguments:.*resolution"):
        train(HEX, "ppo", 100, 1, 0, tmp_path, {"resolutoin": 0.02})
    with pytest.raises(ValueError, match="timesteps must be an integer >= 1"):
        train(HEX, "ppo", 0, 1, 0, tmp_path)
    with pytest.raises(ValueError, match="env id is required"):
        train(None, "ppo", 100, 1, 0, tmp_path)
    with pytest.raises(ValueError, match="'trot:f=2' is neither a file nor a gait spec.*stand, tripod"):
        evaluate("trot:f=2", HEX, episodes=1)
    with pytest.raises(ValueError, match="gait 'tripod' has no parameter 'freq'; valid parameters: f, duty"):
        evaluate("tripod:freq=2", HEX, episodes=1)
    with pytest.raises(ValueError, match="neither a file nor a gait spec"):
        evaluate(tmp_path / "missing.zip", HEX, episodes=1)
    with pytest.raises(ValueError, match="give the env id"):
        evaluate("tripod", None, episodes=1)


def test_parse_kwargs():
    assert parse_kwargs(["resolution=0.02", "medium=poppy_lp", "terminate_when_unhealthy=false", "n=3",
                         "healthy_z_range=[-0.1, 0.5]", "law=None"]) == {
        "resolution": 0.02, "medium": "poppy_lp", "terminate_when_unhealthy": False, "n": 3,
        "healthy_z_range": [-0.1, 0.5], "law": None}
    with pytest.raises(ValueError, match="key=value"):
        parse_kwargs(["resolution"])


def test_cli_errors_exit_2(tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        cli(["train", "--env", HEX, "--algo", "dqn", "--out", str(tmp_path)])
    assert exc.value.code == 2 and "valid choices: ppo, sac" in capsys.readouterr().err
    with pytest.raises(SystemExit) as exc:
        cli(["eval", "--policy", "tripod:f=2", "--env", "mjrft/Nope-v0"])
    err = capsys.readouterr().err
    assert exc.value.code == 2 and all(i in err for i in ENV_IDS)


# ---------------------------------------------------------------------------------------------- evaluation
def test_metrics_match_a_manual_rollout():
    """The row's definitions, recomputed from a plain rollout of the same gait and seed."""
    from mjrft.tools.gaits import make_gait

    kw = {**ENV_KW, "max_episode_steps": 40}
    rows, _ = evaluate("tripod:f=2", HEX, episodes=1, seed=4, env_kwargs=kw)
    env = gymnasium.make(HEX, **kw)
    u = env.unwrapped
    gait = make_gait("tripod:f=2", env)
    obs, info = env.reset(seed=4)
    x0, energy, sinks, ret, num, den = info["x_position"], 0.0, [], 0.0, 0.0, 0.0
    feet = [u.model.body(n).id for n in u.foot_names]
    done = False
    while not done:
        obs, r, term, trunc, info = env.step(gait.predict(obs)[0])
        done = term or trunc
        ret += r
        energy += info["power"] * u.dt
        sinks.append(info["sinkage"])
        t = u.terrain
        buried = np.isin(t.elem_body, feet) & (t.depth > 0)
        num += np.sum(t.area[buried] * np.linalg.norm(t.vel[buried, :2], axis=1))
        den += np.sum(t.area[buried])
    env.close()
    sinks = np.array(sinks)
    row = rows[0]
    dx = info["x_position"] - x0
    assert row["return"] == pytest.approx(ret, rel=1e-12)
    assert row["speed"] == pytest.approx(dx / (40 * u.dt), rel=1e-12) and row["speed"] > 0.05
    mass = u.model.body_subtreemass[0]
    assert row["cot"] == pytest.approx(energy / (mass * 9.81 * abs(dx)), rel=1e-12)
    assert row["sink_mean_mm"] == pytest.approx(1e3 * sinks[sinks > 0].mean(), rel=1e-12)
    assert row["sink_peak_mm"] == pytest.approx(1e3 * sinks.max(), rel=1e-12)
    assert row["slip"] == pytest.approx(num / den, rel=1e-12) and row["slip"] > 0


def test_falls_and_rigid_ground():
    # a healthy range the robot is never in: terminated at the first step -> a fall
    rows, summary = evaluate("tripod", HEX, episodes=2, env_kwargs={**ENV_KW, "healthy_z_range": [0.4, 0.5]})
    assert [r["steps"] for r in rows] == [1, 1] and summary["fall_rate"] == 1.0
    assert "fall rate 100% (2 of 2" in format_table(rows, summary)
    rows, summary = evaluate("tripod", "mjrft/HexapodRigid-v0", episodes=1, env_kwargs={"max_episode_steps": 20})
    assert rows[0]["sink_peak_mm"] == 0.0 and rows[0]["slip"] > 0  # slip from the MuJoCo foot contacts
    assert summary["fall_rate"] == 0.0


def test_eval_cli_writes_csv_json_and_rrd(tmp_path, capsys):
    pytest.importorskip("rerun")
    csv_path, json_path, rrd = tmp_path / "e.csv", tmp_path / "e.json", tmp_path / "e.rrd"
    rc = cli(["eval", "--policy", "tripod:f=2", "--env", HEX, "--episodes", "2", "--csv", str(csv_path),
              "--json", str(json_path), "--rrd", str(rrd), "max_episode_steps=15", "resolution=0.03"])
    out = capsys.readouterr().out
    assert rc == 0 and "foot slip" in out and "fall rate 0%" in out
    with open(csv_path) as fh:
        table = list(csv.DictReader(fh))
    assert [r["episode"] for r in table] == ["0", "1", "mean", "std"] and table[0]["steps"] == "15"
    data = json.loads(json_path.read_text())
    assert len(data["episodes"]) == 2 and data["summary"]["fall_rate"] == 0.0
    assert data["summary"]["speed"] == pytest.approx(float(table[2]["speed"]))
    assert rrd.is_file() and rrd.stat().st_size > 0
    try:
        from mjrft.tools.rerun_log import read_table

        frames = read_table(rrd, "/world/contacts")
    except ImportError:  # the dataframe reader needs datafusion (rerun extra)
        return
    assert frames.num_rows == 4  # the reset state and every LOG_EVERY = 5th of the first episode's 15 steps


@pytest.mark.parametrize("hp,message", [
    ({"policy_kwargs": "{bad json"}, "policy_kwargs takes a JSON object"),
    ({"learning_rate": "abc"}, "learning_rate takes a number, got 'abc'"),
    ({"n_steps": 1.5}, "n_steps takes an integer, got 1.5"),
    ({"n_steps": True}, "n_steps takes an integer, got True"),
    ({"gamma": float("inf")}, "gamma takes a number"),
    ({"normalize_advantage": 1}, "normalize_advantage takes true or false"),
])
def test_hyperparameter_values_are_checked_before_any_env(hp, message):
    from mjrft.train.train import resolve_hyperparams

    with pytest.raises(ValueError, match=message):
        resolve_hyperparams("ppo", hp, 1000)


def test_hyperparameter_values_of_the_right_kind_pass():
    from mjrft.train.train import resolve_hyperparams

    given, _ = resolve_hyperparams("ppo", {"n_steps": 64.0, "learning_rate": 1, "target_kl": None,
                                           "policy_kwargs": {"net_arch": [8]}}, 100)
    assert given == {"n_steps": 64, "learning_rate": 1.0, "target_kl": None, "policy_kwargs": {"net_arch": [8]}}
    given, _ = resolve_hyperparams("sac", {"ent_coef": "auto_0.1", "train_freq": [1, "step"]}, 100)
    assert given["ent_coef"] == "auto_0.1" and given["train_freq"] == [1, "step"]


def test_train_command_reports_a_bad_hyperparameter_in_one_line(tmp_path, capsys):
    from mjrft.tools import cli

    with pytest.raises(SystemExit) as e:
        cli.main(["train", "--env", "mjrft/HexapodSand-v0", "--out", str(tmp_path / "run"), "--hp", "n_steps=1.5"])
    assert e.value.code == 2
    assert "PPO hyper-parameter n_steps takes an integer, got 1.5" in capsys.readouterr().err


def test_training_shows_each_kind_of_warning_once_and_logs_all(tmp_path, capsys):
    """An env that warns every step (numbers in the message vary): one line per kind, a count, a CSV of all."""
    import csv as _csv
    import warnings as _warnings

    import gymnasium as gym
    import numpy as _np

    from mjrft.errors import TerrainStabilityWarning
    from mjrft.train.run_warnings import WARNINGS_CSV, warning_kind
    from mjrft.train.train import train

    import mujoco

    class Warns(gym.Env):
        observation_space = gym.spaces.Box(-1, 1, (2,))
        action_space = gym.spaces.Box(-1, 1, (1,))
        model = mujoco.MjModel.from_xml_string("<mujoco/>")  # mjrft train takes MuJoCo envs only

        def reset(self, seed=None, options=None):
            super().reset(seed=seed)
            self.t = 0
            return _np.zeros(2, _np.float32), {}

        def step(self, action):
            self.t += 1
            _warnings.warn(TerrainStabilityWarning(f"mjrft: body 'leg' at t = {self.t * 0.01:.4g} s"))
            return _np.zeros(2, _np.float32), 0.0, False, self.t >= 8, {}

    gym.register("mjrft_test/Warns-v0", entry_point=Warns)
    try:
        train("mjrft_test/Warns-v0", "ppo", timesteps=32, n_envs=1, seed=0, out_dir=tmp_path, checkpoint_every=1000,
              hyperparams={"n_steps": 16, "batch_size": 16, "n_epochs": 1})
    finally:
        gym.registry.pop("mjrft_test/Warns-v0", None)
    out = capsys.readouterr()
    assert out.out.count("TerrainStabilityWarning (shown once") == 1
    assert "32 warning(s) of 1 kind(s)" in out.out and "32 x TerrainStabilityWarning: mjrft: body 'leg'" in out.out
    assert "TerrainStabilityWarning" not in out.err  # not printed per occurrence
    with open(tmp_path / WARNINGS_CSV) as f:
        rows = list(_csv.DictReader(f))
    assert len(rows) == 32 and rows[0]["category"] == "TerrainStabilityWarning" and "t = 0.01 s" in rows[0]["message"]
    assert warning_kind("W", "at t = 0.01 s, 3e-4 kg") == warning_kind("W", "at t = 2.5 s, 1 kg")

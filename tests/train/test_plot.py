"""Tests of ``mjrft plot`` (mjrft.train.plot) and the training vec envs (mjrft.train.vecenv).

The run folders are written here: a monitor.csv as SB3's VecMonitor writes it (with and without the
``speed`` column), two resumes' progress.csv and a config.json of a small hexapod env.
"""

from __future__ import annotations

import csv
import json
import warnings

import numpy as np
import pytest

pytest.importorskip("stable_baselines3")
pytest.importorskip("imageio")  # gymnasium.envs.mujoco needs it
pytest.importorskip("matplotlib")

from matplotlib.image import imread  # noqa: E402

from mjrft.tools.cli import main as cli  # noqa: E402
from mjrft.errors import TerrainStabilityWarning, ValidityRangeWarning  # noqa: E402
from mjrft.train.plot import load_run, plot_runs, read_monitor, rolling_mean  # noqa: E402
from mjrft.train.vecenv import KINDS, make_vec_env, resolve_kind  # noqa: E402

HEX = "mjrft/HexapodSand-v0"
ENV_KW = {"resolution": 0.03, "max_episode_steps": 8}
N_EPISODES = 30


@pytest.fixture(autouse=True)
def _quiet():
    with warnings.catch_warnings():  # random actions on coarse legs may warn (not under test)
        warnings.simplefilter("ignore", TerrainStabilityWarning)
        warnings.simplefilter("ignore", ValidityRangeWarning)
        yield


def write_run(folder, speed: bool = True, seed: int = 0):
    """A run folder as ``mjrft train`` leaves it; returns (returns, lengths, speeds) of its episodes."""
    rng = np.random.default_rng(seed)
    folder.mkdir(parents=True, exist_ok=True)
    returns = np.round(np.linspace(10, 40, N_EPISODES) + rng.normal(0, 3, N_EPISODES), 4)
    lengths = rng.integers(50, 101, N_EPISODES)
    speeds = np.round(np.linspace(0.01, 0.2, N_EPISODES), 5)
    with open(folder / "monitor.csv", "w") as fh:
        fh.write('#{"t_start": 1700000000.0, "env_id": "mjrft/HexapodSand-v0"}\n')
        fh.write("r,l,t" + (",speed" if speed else "") + "\n")
        for k in range(N_EPISODES):
            fh.write(f"{returns[k]},{lengths[k]},{k * 0.5}" + (f",{speeds[k]}" if speed else "") + "\n")
    for start, steps in ((0, (512, 1024)), (1024, (1536, 2048))):
        log = folder / "logs" / f"from_{start:010d}"
        log.mkdir(parents=True)
        with open(log / "progress.csv", "w") as fh:
            fh.write("time/fps,time/total_timesteps,rollout/ep_rew_mean,train/loss\n")
            for s in steps:
                fh.write(f"700,{s},{s / 100},0.5\n")
    with open(folder / "config.json", "w") as fh:
        json.dump({"env_id": HEX, "env_kwargs": ENV_KW, "algo": "ppo"}, fh)
    return returns, lengths, speeds


def read_series(path) -> dict:
    out = {}
    with open(path, newline="") as fh:
        for row in csv.DictReader(fh):
            out.setdefault((row["label"], row["series"]), []).append(
                (float(row["env_steps"]) if row["env_steps"] else None, float(row["value"])))
    return out


def test_rolling_mean_is_the_trailing_mean():
    x = np.array([1.0, 2.0, np.nan, 4.0, 8.0, 16.0])
    want = [1.0, 1.5, 1.5, 3.0, 6.0, 28 / 3]  # last 3 values, NaN left out
    assert np.allclose(rolling_mean(x, 3), want)
    assert np.allclose(rolling_mean(x[[0, 1, 3]], 1), x[[0, 1, 3]])


def test_plot_png_and_csv_series(tmp_path):
    returns, lengths, speeds = write_run(tmp_path / "a")
    write_run(tmp_path / "b", seed=1)
    out, table = tmp_path / "curves.png", tmp_path / "curves.csv"
    result = plot_runs([tmp_path / "a", tmp_path / "b"], out, baselines=["return=25,speed=0.15"], labels=["A", "B"],
                       window=5, csv_path=table)
    image = imread(out)
    assert image.shape[0] > 600 and image.shape[1] > 600  # two panels at 110 dpi
    assert image[..., :3].std() > 0.05  # lines drawn, not a blank canvas
    s = read_series(table)
    steps = np.cumsum(lengths)
    assert [v for _, v in s[("A", "return")]] == pytest.approx(returns)
    assert [x for x, _ in s[("A", "return")]] == pytest.approx(steps)
    assert [v for _, v in s[("A", "speed")]] == pytest.approx(speeds)
    smooth = [v for _, v in s[("A", "return_smoothed")]]
    assert smooth[-1] == pytest.approx(returns[-5:].mean())
    assert smooth[2] == pytest.approx(returns[:3].mean())
    assert np.allclose(s[("A", "ep_rew_mean")], [(512, 5.12), (1024, 10.24), (1536, 15.36), (2048, 20.48)])
    assert s[("baseline (return=25,speed=0.15)", "baseline_return")] == [(None, 25.0)]
    assert s[("baseline (return=25,speed=0.15)", "baseline_speed")] == [(None, 0.15)]
    assert ("B", "return") in s and [r.label for r in result.runs] == ["A", "B"]


def test_plot_without_speed_has_the_return_panel_only(tmp_path):
    write_run(tmp_path / "old", speed=False)
    out, table = tmp_path / "curves.png", tmp_path / "curves.csv"
    result = plot_runs([tmp_path / "old"], out, baselines=["return=25"], csv_path=table)
    assert result.runs[0].monitor.speed is None
    assert imread(out).shape[0] < 450  # one panel
    series = {k[1] for k in read_series(table)}
    assert series == {"return", "return_smoothed", "ep_rew_mean", "baseline_return"}


def test_gait_baseline_is_evaluated_on_the_run_env(tmp_path):
    write_run(tmp_path / "a")
    result = plot_runs([tmp_path / "a"], tmp_path / "c.png", baselines=["tripod:f=2.5"], episodes=1)
    (b,) = result.baselines
    assert b.env_id == HEX and np.isfinite(b.ret) and np.isfinite(b.speed)
    from mjrft.train.evaluate import evaluate

    _, summary = evaluate("tripod:f=2.5", HEX, episodes=1, env_kwargs=ENV_KW)
    assert b.ret == pytest.approx(summary["return"]) and b.speed == pytest.approx(summary["speed"])


def test_plot_input_errors(tmp_path, capsys):
    write_run(tmp_path / "a")
    (tmp_path / "empty").mkdir()
    out = tmp_path / "c.png"
    with pytest.raises(ValueError, match="does not exist"):
        plot_runs([tmp_path / "nope"], out)
    with pytest.raises(ValueError, match="has no monitor.csv"):
        plot_runs([tmp_path / "empty"], out)
    with pytest.raises(ValueError, match="neither a gait spec .* nor numbers"):
        plot_runs([tmp_path / "a"], out, baselines=["speed=fast"])
    with pytest.raises(ValueError, match="valid suffixes: .*png"):
        plot_runs([tmp_path / "a"], tmp_path / "c.xyz")
    with pytest.raises(ValueError, match="one label per run"):
        plot_runs([tmp_path / "a"], out, labels=["x", "y"])
    (tmp_path / "half").mkdir()
    (tmp_path / "half" / "monitor.csv").write_text('#{"t_start": 0}\nr,l,t\n')
    with pytest.raises(ValueError, match="no finished episode"):
        load_run(tmp_path / "half")
    assert not out.exists()
    with pytest.raises(SystemExit) as exc:
        cli(["plot", str(tmp_path / "nope"), "--out", str(out)])
    assert exc.value.code == 2 and "does not exist" in capsys.readouterr().err


def test_plot_cli(tmp_path, capsys):
    write_run(tmp_path / "a")
    assert cli(["plot", str(tmp_path / "a"), "--out", str(tmp_path / "c.png"), "--window", "5",
                "--baseline", "return=25,speed=0.15"]) == 0
    printed = capsys.readouterr().out
    assert f"{N_EPISODES} episodes" in printed and "wrote" in printed and (tmp_path / "c.png").stat().st_size > 0


# ---------------------------------------------------------------------------------------------- vec envs
def step_episodes(venv, n_steps: int, seed: int = 0) -> list[dict]:
    rng = np.random.default_rng(seed)
    venv.reset()
    infos_seen = []
    for _ in range(n_steps):
        actions = rng.uniform(-1, 1, size=(venv.num_envs, *venv.action_space.shape)).astype(np.float32)
        _, _, _, infos = venv.step(actions)
        infos_seen.append(infos)
    return infos_seen


@pytest.mark.parametrize("kind", ["dummy", "batched", "subproc"])
def test_vec_env_kinds_build_step_and_record_speed(tmp_path, kind):
    monitor = tmp_path / "monitor.csv"
    n = 2
    venv = make_vec_env(HEX, n, 3, ENV_KW, monitor, kind=kind)
    try:
        steps = step_episodes(venv, 2 * ENV_KW["max_episode_steps"])
    finally:
        venv.close()
    m = read_monitor(monitor)
    assert m.lengths.tolist() == [8] * 4 and m.speed is not None
    ends = [info["episode"] for infos in steps for info in infos if "episode" in info]
    assert np.allclose(m.speed, [e["speed"] for e in ends]) and np.all(np.isfinite(m.speed))
    if kind != "subproc":  # the per-step x_velocity of env 0's first episode, averaged
        vx = [infos[0]["x_velocity"] for infos in steps[:8]]
        assert steps[7][0]["episode"]["speed"] == pytest.approx(np.mean(vx))


def test_vec_env_kinds_give_the_same_episodes():
    rows = {}
    for kind in ("dummy", "batched"):
        venv = make_vec_env(HEX, 2, 5, ENV_KW, None, kind=kind)
        try:
            steps = step_episodes(venv, ENV_KW["max_episode_steps"])
        finally:
            venv.close()
        rows[kind] = [(e["r"], e["speed"]) for e in (info["episode"] for info in steps[-1])]
    assert np.allclose(rows["dummy"], rows["batched"], rtol=1e-5)


def append_one_episode(monitor, text: str):
    """A monitor file with ``text`` in it, one more episode appended by a dummy vec env, read back."""
    monitor.write_text(text)
    venv = make_vec_env(HEX, 1, 0, ENV_KW, monitor, kind="dummy")
    try:
        step_episodes(venv, ENV_KW["max_episode_steps"])
    finally:
        venv.close()
    return read_monitor(monitor)


def test_vec_env_appends_to_a_monitor_without_speed(tmp_path):
    m = append_one_episode(tmp_path / "monitor.csv", '#{"t_start": 0}\nr,l,t\n1.5,8,0.1\n')
    assert m.lengths.tolist() == [8, 8] and m.speed is None


def test_vec_env_bad_kind_and_auto():
    with pytest.raises(ValueError, match="unknown vec env kind 'threads'; valid choices: auto, batched, dummy, subproc"):
        make_vec_env(HEX, 2, 0, ENV_KW, kind="threads")
    with pytest.raises(ValueError, match="batched' steps only mjrft's own envs"):
        make_vec_env("mjrft/HopperSand-v5", 2, 0, kind="batched")
    assert set(KINDS) == {"auto", "subproc", "dummy", "batched"}
    assert resolve_kind("auto", HEX, 1) == "dummy"
    assert resolve_kind("auto", HEX, 4, cpu_count=2) == "batched"
    assert resolve_kind("auto", "mjrft/HopperSand-v5", 4, cpu_count=2) == "dummy"
    assert resolve_kind("auto", HEX, 4, cpu_count=8) == "subproc"
    assert resolve_kind("auto", HEX, 16, cpu_count=16) == "subproc"  # batched would step 16 envs on one core
    assert resolve_kind("auto", HEX, 8, cpu_count=3) == "batched"
    assert resolve_kind("subproc", HEX, 4) == "subproc"


def test_a_torn_last_line_and_damaged_files_of_a_run(tmp_path):
    returns, _, _ = write_run(tmp_path / "a")
    monitor = tmp_path / "a" / "monitor.csv"
    with open(monitor, "a") as fh:
        fh.write("12.5,10")  # the run was killed while writing this episode
    with pytest.warns(RuntimeWarning, match=f"line {N_EPISODES + 3} is incomplete"):
        run = load_run(tmp_path / "a")
    np.testing.assert_array_equal(run.monitor.returns, returns)
    # a torn line in the middle is left out with a warning naming the file and the line; the rest is read
    with open(monitor, "a") as fh:
        fh.write("\n1.0,8,0.1,0.02\n")
    with pytest.warns(RuntimeWarning, match=f"monitor.csv: 1 line.* left out; line {N_EPISODES + 3} has 2 fields"):
        run = load_run(tmp_path / "a")
    np.testing.assert_array_equal(run.monitor.returns, [*returns, 1.0])
    # a bad number in progress.csv: that row is left out, the file and line named; a corrupt config.json: an error
    write_run(tmp_path / "b")
    progress = tmp_path / "b" / "logs" / "from_0000000000" / "progress.csv"
    progress.write_text(progress.read_text().replace("512,5.12", "512,nan?"))
    with pytest.warns(RuntimeWarning, match=f"{progress}: 1 row.* left out; line 2 .*'nan\\?', not a number"):
        run = load_run(tmp_path / "b")
    assert 512 not in run.progress[0] and len(run.progress[0]) > 0
    write_run(tmp_path / "c")
    (tmp_path / "c" / "config.json").write_text('{"env_id": ')
    with pytest.raises(ValueError, match="config.json: run config is not valid JSON"):
        load_run(tmp_path / "c")


def test_vec_env_appends_after_a_torn_monitor_line(tmp_path):
    m = append_one_episode(tmp_path / "monitor.csv", '#{"t_start": 0}\nr,l,t\n1.5,8,0.1\n2.5,')
    assert m.lengths.tolist() == [8, 8] and m.returns[0] == 1.5

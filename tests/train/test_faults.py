"""Fault injection on the files of a run folder: truncated, corrupt, deleted and pickled files, and a
process killed while it writes a checkpoint. Every failure is one error naming the file; nothing is
unpickled without ``trust``; resuming and evaluating fall back to the newest file that loads and say
so; nothing is lost beyond the last complete checkpoint.

The runs train PPO / SAC on gymnasium's InvertedPendulum (MuJoCo; a few hundred steps) so that the suite stays fast.
"""

from __future__ import annotations

import base64
import json
import os
import pickle
import shutil
import signal
import subprocess
import sys
import textwrap
import zipfile
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("stable_baselines3")

from mjrft.train import artefacts  # noqa: E402
from mjrft.train.artefacts import ArtefactError, NeedsTrustError  # noqa: E402
from mjrft.train.evaluate import load_policy, resolve_model  # noqa: E402
from mjrft.train.train import list_checkpoints, load_config, side_file, train  # noqa: E402

ENV = "InvertedPendulum-v5"
PPO_HP = {"n_steps": 64, "batch_size": 32, "n_epochs": 1, "policy_kwargs": {"net_arch": [16]}}


def _ppo(out, timesteps=256, **kw):
    return train(ENV, "ppo", timesteps, 1, 0, out, {}, checkpoint_every=64, hyperparams=PPO_HP, **kw)


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """A finished normalised PPO run: checkpoints at 64, 128, 192, 256 and model.zip (256 steps)."""
    out = tmp_path_factory.mktemp("run")
    _ppo(out, normalize=True)
    return out


@pytest.fixture
def copy(run, tmp_path):
    dst = tmp_path / "run"
    shutil.copytree(run, dst)
    return dst


def _truncate(path: Path, keep: float = 0.5) -> None:
    data = path.read_bytes()
    path.write_bytes(data[: int(len(data) * keep)])


def _rezip(path: Path, member: str, transform) -> None:
    """Rewrite ``member`` of the zip at ``path`` with ``transform(bytes)`` (a valid zip with a damaged member)."""
    with zipfile.ZipFile(path) as zf:
        items = [(n, zf.read(n)) for n in zf.namelist()]
    with zipfile.ZipFile(path, "w") as zf:
        for name, data in items:
            zf.writestr(name, transform(data) if name == member else data)


class _Marker:
    """Unpickling this creates a file: proof that a pickle was (or was not) loaded."""

    def __init__(self, path):
        self.path = str(path)

    def __reduce__(self):
        return (Path.touch, (Path(self.path),))


def _one_line(exc, path) -> str:
    msg = str(exc)
    assert "\n" not in msg and str(path) in msg, msg
    return msg


# ---------------------------------------------------------------------------------------------- safe loading
def test_mjrft_files_load_without_unpickling_anything(run, monkeypatch):
    def refuse(*a, **k):
        raise AssertionError("pickle was used")

    import cloudpickle

    monkeypatch.setattr(pickle, "load", refuse)
    monkeypatch.setattr(pickle, "loads", refuse)
    monkeypatch.setattr(cloudpickle, "loads", refuse)
    loaded = load_policy(run)
    assert loaded.model.num_timesteps == 256 and loaded.vecnormalize is not None
    obs = np.array([0.05, 0.0, 0.5, -0.1], dtype=np.float32)
    assert loaded.predict(obs)[0].shape == (1,)
    assert sorted(p.suffix for p in run.iterdir() if p.name.startswith("model")) == [".npz", ".zip"]


def test_a_pickled_vecnormalize_file_needs_trust(copy, tmp_path):
    marker = tmp_path / "ran"
    side_file(copy / "model.zip", "_vecnormalize.npz").unlink()
    pkl = side_file(copy / "model.zip", "_vecnormalize.pkl")
    pkl.write_bytes(pickle.dumps(_Marker(marker)))
    with pytest.raises(NeedsTrustError, match="pickle.*--trust") as e:
        load_policy(copy / "model.zip")
    _one_line(e.value, pkl)
    assert not marker.exists()
    with pytest.raises(Exception):  # trusted: it is unpickled (and is no VecNormalize)
        load_policy(copy / "model.zip", trust=True)
    assert marker.exists()


def test_pickled_entries_of_a_zip_are_never_unpickled(copy, tmp_path):
    """A zip whose pickled policy class runs code loads safely (rebuilt from its description); an entry
    that only a pickle can give needs trust."""
    marker = tmp_path / "ran"
    payload = base64.b64encode(pickle.dumps(_Marker(marker))).decode()

    def poison(raw, extra=False):
        data = json.loads(raw)
        data["policy_class"][":serialized:"] = payload
        if extra:
            data["custom_thing"] = {":type:": "<class 'evil.Thing'>", ":serialized:": payload}
        return json.dumps(data).encode()

    path = copy / "model.zip"
    _rezip(path, "data", poison)
    assert load_policy(path).model.num_timesteps == 256 and not marker.exists()
    _rezip(path, "data", lambda raw: poison(raw, extra=True))
    with pytest.raises(NeedsTrustError, match="custom_thing") as e:
        load_policy(path)
    _one_line(e.value, path)
    assert not marker.exists()


# ---------------------------------------------------------------------------------------------- damaged files
DAMAGE = {
    "truncated": lambda p: _truncate(p),
    "empty": lambda p: p.write_bytes(b""),
    "garbage": lambda p: p.write_bytes(os.urandom(2000)),
    "cut policy.pth": lambda p: _rezip(p, "policy.pth", lambda b: b[: len(b) // 2]),
    "data not JSON": lambda p: _rezip(p, "data", lambda b: b[:100]),
    "no policy.pth": lambda p: _drop(p, "policy.pth"),
}


def _drop(path: Path, member: str) -> None:
    with zipfile.ZipFile(path) as zf:
        items = [(n, zf.read(n)) for n in zf.namelist() if n != member]
    with zipfile.ZipFile(path, "w") as zf:
        for name, data in items:
            zf.writestr(name, data)


@pytest.mark.parametrize("damage", DAMAGE, ids=list(DAMAGE))
def test_a_damaged_model_zip_is_one_error_naming_it(copy, damage):
    path = copy / "checkpoints" / "step_0000000256.zip"
    DAMAGE[damage](path)
    with pytest.raises(ArtefactError) as e:
        load_policy(path)
    _one_line(e.value, path)


@pytest.mark.parametrize("damage", ["truncated", "empty", "garbage", "deleted", "other format"])
def test_damaged_vecnormalize_statistics_are_one_error_naming_them(copy, damage):
    path = side_file(copy / "checkpoints" / "step_0000000256.zip", "_vecnormalize.npz")
    if damage == "deleted":
        path.unlink()
    elif damage == "other format":
        np.savez(path, format=np.array("something else"))
    else:
        DAMAGE[damage](path)
    with pytest.raises(ArtefactError) as e:
        load_policy(copy / "checkpoints" / "step_0000000256.zip")
    _one_line(e.value, path)


@pytest.mark.parametrize("text", ["", "{\"env_id\": ", "[1, 2]", "{\"seed\": 1}"])
def test_a_damaged_config_json_is_one_error_naming_it(copy, text):
    """Resuming needs the run's config: one error naming it. A good model stays usable without it: one warning
    naming the config (once, however many of the folder's models are checked), the algorithm read from the zip."""
    (copy / "config.json").write_text(text)
    with pytest.raises(ArtefactError) as e:
        train(None, None, 512, 1, 0, copy, None)
    _one_line(e.value, copy / "config.json")
    from mjrft.train import evaluate as evaluate_module

    evaluate_module._REPORTED_CONFIGS.clear()
    with pytest.warns(artefacts.SkippedArtefactWarning) as caught:
        policy = load_policy(copy)  # model.zip and four checkpoints are checked against the config
    mine = [str(w.message) for w in caught if issubclass(w.category, artefacts.SkippedArtefactWarning)]
    assert len(mine) == 1 and str(copy / "config.json") in mine[0], mine
    assert policy.kind == "ppo" and policy.source == str(copy / "model.zip") and policy.vecnormalize is not None


# ---------------------------------------------------------------------------------------------- newest complete model
def test_eval_of_a_run_folder_uses_the_newest_complete_model_and_says_which(copy):
    assert resolve_model(copy) == (copy / "model.zip", "")
    # killed after a checkpoint: model.zip is older than it
    shutil.copy(copy / "checkpoints" / "step_0000000128.zip", copy / "model.zip")
    path, note = resolve_model(copy)
    assert path == copy / "checkpoints" / "step_0000000256.zip"
    assert "(128 steps) is older" in note and "step_0000000256.zip (256 steps)" in note
    assert load_policy(copy).note == note
    # the newest checkpoint damaged too: the one before it, each problem named
    _truncate(copy / "checkpoints" / "step_0000000256.zip")
    path, note = resolve_model(copy)
    assert path.name == "step_0000000192.zip" and "step_0000000256.zip" in note and "truncated" in note
    # model.zip damaged or missing
    _truncate(copy / "model.zip")
    assert "model.zip: not a complete" in resolve_model(copy)[1]
    (copy / "model.zip").unlink()
    assert "model.zip is missing" in resolve_model(copy)[1]
    # nothing loads: one error that lists the problems
    for _, p in list_checkpoints(copy):
        p.write_bytes(b"")
    with pytest.raises(ArtefactError, match="no model in it loads") as e:
        resolve_model(copy)
    assert "step_0000000064.zip" in str(e.value)


# ---------------------------------------------------------------------------------------------- resume
def test_resume_falls_back_to_the_newest_checkpoint_that_loads(copy):
    before = (copy / "config.json").read_text()
    newest = copy / "checkpoints" / "step_0000000256.zip"
    _truncate(newest)
    (copy / "model.zip").unlink()
    said = []
    result = train(None, None, 320, 1, 0, copy, None, checkpoint_every=64, report=said.append)
    assert result.resumed_from.name == "step_0000000192.zip" and result.num_timesteps == 320
    assert any(str(newest) in s and "previous checkpoint" in s for s in said), said
    assert any("resuming" in s and "step_0000000192.zip at 192 steps" in s for s in said), said
    cfg = load_config(copy / "config.json")
    assert cfg["runs"][-1]["from_step"] == 192 and cfg["runs"][-1]["status"] == "finished"
    assert cfg["model"] == "model.zip" and before != (copy / "config.json").read_text()


def test_resume_with_no_loadable_checkpoint_changes_nothing(copy):
    before = {p: p.read_bytes() for p in copy.rglob("*") if p.is_file()}
    for _, p in list_checkpoints(copy):
        _truncate(p)
    before = {p: p.read_bytes() for p in copy.rglob("*") if p.is_file()}
    with pytest.raises(ValueError, match="none of the 4 checkpoint") as e:
        train(None, None, 512, 1, 0, copy, None, report=lambda s: None)
    assert "--no-resume" in str(e.value)
    assert {p: p.read_bytes() for p in copy.rglob("*") if p.is_file()} == before  # config.json untouched


def test_sac_resumes_with_an_empty_buffer_when_its_file_is_damaged(tmp_path):
    hp = {"learning_starts": 20, "batch_size": 16, "policy_kwargs": {"net_arch": [16]}}
    train(ENV, "sac", 60, 1, 0, tmp_path, {}, checkpoint_every=30, hyperparams=hp)
    buf = side_file(list_checkpoints(tmp_path)[-1][1], "_replay_buffer.npz")
    saved = np.load(buf)
    assert bool(saved["full"]) and saved["observations"].shape == (60, 1, 4)  # buffer_size = the budget
    _truncate(buf)
    said = []
    result = train(None, None, 90, 1, 0, tmp_path, None, checkpoint_every=30, report=said.append)
    assert result.num_timesteps == 90
    assert any(str(buf) in s and "empty replay buffer" in s for s in said), said


def test_a_replay_buffer_and_vecnormalize_statistics_round_trip(tmp_path):
    import gymnasium
    from stable_baselines3 import SAC
    from stable_baselines3.common.vec_env import DummyVecEnv, VecNormalize

    venv = VecNormalize(DummyVecEnv([lambda: gymnasium.make(ENV)]))
    a = SAC("MlpPolicy", venv, buffer_size=50, learning_starts=10, batch_size=8, seed=0,
            policy_kwargs={"net_arch": [8]})
    a.learn(30)
    artefacts.save_replay_buffer(a.replay_buffer, tmp_path / "buf.npz")
    artefacts.save_vecnormalize(venv, tmp_path / "vn.npz")
    b = SAC("MlpPolicy", gymnasium.make(ENV), buffer_size=50, policy_kwargs={"net_arch": [8]})
    artefacts.load_replay_buffer(b, tmp_path / "buf.npz")
    assert (b.replay_buffer.pos, b.replay_buffer.full) == (30, False)
    for name in ("observations", "next_observations", "actions", "rewards", "dones", "timeouts"):
        assert np.array_equal(getattr(b.replay_buffer, name), getattr(a.replay_buffer, name)), name
    stats = artefacts.load_vecnormalize(tmp_path / "vn.npz")
    obs = np.array([[0.3, -0.2, 4.0, 0.1]], dtype=np.float32)
    assert np.array_equal(stats.normalize_obs(obs), venv.normalize_obs(obs))
    assert stats.obs_rms.count == venv.obs_rms.count and stats.ret_rms.var == venv.ret_rms.var
    # another buffer layout: refused with the reason
    c = SAC("MlpPolicy", DummyVecEnv([lambda: gymnasium.make(ENV)] * 2), buffer_size=50, policy_kwargs={"net_arch": [8]})
    with pytest.raises(ValueError, match="n_envs=1"):
        artefacts.load_replay_buffer(c, tmp_path / "buf.npz")


# ---------------------------------------------------------------------------------------------- run status
def test_the_status_of_every_run_is_final(tmp_path):
    from stable_baselines3.common.callbacks import BaseCallback

    class Boom(BaseCallback):
        def _on_step(self):
            if self.num_timesteps >= 100:
                raise RuntimeError("boom")
            return True

    with pytest.raises(RuntimeError, match="boom"):
        _ppo(tmp_path, callback=Boom())
    run = load_config(tmp_path / "config.json")["runs"][-1]
    assert run["status"] == "crashed" and "boom" in run["error"] and run["to_step"] == 64


def test_an_interrupt_while_the_environments_are_built_is_recorded(tmp_path, monkeypatch):
    _ppo(tmp_path, timesteps=64)
    from mjrft.train import train as train_module

    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(train_module, "make_vec_env", interrupted)
    result = _ppo(tmp_path, timesteps=256)
    assert result.interrupted and not result.saved and result.num_timesteps == 64
    assert load_config(tmp_path / "config.json")["runs"][-1]["status"] == "interrupted"


KILL_SCRIPT = textwrap.dedent("""
    import os, signal, sys
    from mjrft.train import train as t

    real = t.atomic_write
    def killing_write(path, write):
        if path.name == "step_0000000192.zip":  # half of the zip is on disk, then the process dies
            def half(tmp):
                write(tmp)
                data = open(tmp, "rb").read()
                open(tmp, "wb").write(data[: len(data) // 2])
                os.kill(os.getpid(), signal.SIGKILL)
            return real(path, half)
        return real(path, write)
    t.atomic_write = killing_write
    t.train("InvertedPendulum-v5", "ppo", 256, 1, 0, sys.argv[1], {}, checkpoint_every=64, normalize=True,
            hyperparams={"n_steps": 64, "batch_size": 32, "n_epochs": 1, "policy_kwargs": {"net_arch": [16]}})
""")


def test_a_kill_during_a_checkpoint_write_loses_nothing_before_it(tmp_path):
    out = tmp_path / "run"
    proc = subprocess.run([sys.executable, "-c", KILL_SCRIPT, str(out)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == -signal.SIGKILL, proc.stderr
    ckpts = list_checkpoints(out)
    assert [s for s, _ in ckpts] == [64, 128]  # the half-written one is no checkpoint
    assert list((out / "checkpoints").glob(".*.tmp"))  # the stray temporary file
    assert load_config(out / "config.json")["runs"][-1]["status"] == "running"
    # eval of the folder: no model.zip yet, the newest complete checkpoint, said so
    path, note = resolve_model(out)
    assert path.name == "step_0000000128.zip" and "model.zip is missing" in note
    # resume: from 128, the killed run recorded as crashed, the stray file removed
    said = []
    result = train(None, None, 256, 1, 0, out, None, checkpoint_every=64, report=said.append)
    assert result.resumed_from.name == "step_0000000128.zip" and result.num_timesteps == 256
    runs = load_config(out / "config.json")["runs"]
    assert [r["status"] for r in runs] == ["crashed", "finished"] and "killed" in runs[0]["note"]
    assert not list((out / "checkpoints").glob(".*.tmp"))
    assert [s for s, _ in list_checkpoints(out)] == [64, 128, 192, 256]


def test_save_checkpoint_writes_only_data_files(tmp_path):
    _ppo(tmp_path, timesteps=64, normalize=True)
    model = load_policy(tmp_path).model
    assert model is not None
    names = sorted(p.name for p in (tmp_path / "checkpoints").iterdir())
    assert names == ["step_0000000064.zip", "step_0000000064_monitor.json", "step_0000000064_vecnormalize.npz"]
    with np.load(tmp_path / "checkpoints" / names[2], allow_pickle=False) as npz:
        assert str(npz["format"]) == artefacts.VECNORM_FORMAT and npz["obs_mean"].shape == (4,)
    mark = json.loads((tmp_path / "checkpoints" / names[1]).read_text())  # the monitor's length at the checkpoint
    assert mark == {"num_timesteps": 64, "monitor_bytes": (tmp_path / "monitor.csv").stat().st_size}


# ---------------------------------------------------------------------------------------------- validate
def test_an_interrupted_validate_writes_the_cases_that_finished(tmp_path, monkeypatch, capsys):
    from mjrft.tools import cli
    from mjrft.tools.validation import report
    from mjrft.tools.validation.case import CaseResult, check_close

    names = report.check_names([])[:3]

    def run_case(name, quick=False):
        if name == names[1]:
            raise KeyboardInterrupt
        return CaseResult(name, "t", "p", "s", "setup", [check_close("x", 1.0, 1.0, 0.1, source="src")], seconds=0.1)

    monkeypatch.setattr(report, "run_case", run_case)
    (tmp_path / "report.md").write_text("# an old report\n")
    argv = ["validate", "--out", str(tmp_path)] + [a for n in names for a in ("--case", n)]
    assert cli.main(argv) == 130
    md = (tmp_path / "report.md").read_text()
    assert "Interrupted after 1 of 3 cases" in md and f"[{names[0]}]" in md and f"[{names[2]}]" not in md
    assert "interrupted after 1 of 3" in capsys.readouterr().err
    assert not list(tmp_path.glob("*.tmp"))


def test_sweep_passes_trust_to_every_point_without_saving_it(copy, tmp_path, monkeypatch):
    """mjrft sweep --policy runs each point with --trust when given (load_policy refuses a pickled file otherwise,
    tested above); trust is not saved in sweep.json, so a resumed sweep may add or drop it."""
    import mjrft.train.evaluate as evaluate_module
    from mjrft.train.sweep import sweep

    seen = []

    def fake_evaluate(spec, env_id, episodes, seed, kwargs, trust=False):
        seen.append(trust)
        row = {"speed": 0.1, "seconds": 1.0}
        return [row], {"speed": 0.1, "cot": 1.0, "sink_mean_mm": 0.0, "sink_peak_mm": 0.0, "fall_rate": 0.0,
                       "return": 1.0}

    monkeypatch.setattr(evaluate_module, "evaluate", fake_evaluate)
    kw = dict(env="mjrft/HexapodSand-v0", gait=str(copy / "model.zip"), seconds=0.05, workers=1, progress=None)
    assert sweep({"medium": ["poppy_cp"]}, tmp_path / "s1", **kw)[0]["status"] == "ok"
    assert sweep({"medium": ["poppy_lp"]}, tmp_path / "s2", trust=True, **kw)[0]["status"] == "ok"
    assert seen == [False, True]
    assert "trust" not in json.loads((tmp_path / "s2" / "sweep.json").read_text())["settings"]

"""``mjrft train-mjx`` on more than one device: a tiny recipe on a small environment trains in a subprocess that sees
two CPU devices (``XLA_FLAGS=--xla_force_host_platform_device_count=2``) and joins ``jax.distributed`` as the only
host of a run: Brax's PPO splits the worlds over both devices and the run folder says so. The host flags are
checked before anything is compiled."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

pytest.importorskip("jax", reason="train-mjx needs the optional extra mjrft[mjx]")
pytest.importorskip("brax", reason="train-mjx needs the optional extra mjrft[mjx]")
pytest.importorskip("ml_collections", reason="the MJX environments need ml_collections (mjrft[mjx])")

from mjrft.tools.cli import main as cli  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
TINY = {"env": "Block", "env_config": {"floor": False}, "num_timesteps": 320, "num_envs": 4, "episode_length": 20,
        "network": {"policy_hidden_layer_sizes": [8], "value_hidden_layer_sizes": [8]},
        "ppo": {"unroll_length": 5, "batch_size": 4, "num_minibatches": 2, "num_updates_per_batch": 1,
                "num_evals": 2, "run_evals": False, "normalize_observations": True}}  # no evaluator: less to compile
SCRIPT = """
import sys
from mjx_helpers import BlockEnv, block_config
from mjrft.mjx import envs
from mjrft.tools.cli import main
envs.register("Block", BlockEnv, block_config)
sys.exit(main(sys.argv[1:]))
"""


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("localhost", 0))
        return s.getsockname()[1]


def test_train_mjx_uses_every_local_device_and_joins_a_distributed_run(tmp_path):
    recipe, out = tmp_path / "tiny.json", tmp_path / "run"
    recipe.write_text(json.dumps(TINY))
    env = {**os.environ, "XLA_FLAGS": "--xla_force_host_platform_device_count=2", "JAX_PLATFORMS": "cpu",
           "PYTHONPATH": os.pathsep.join([str(ROOT), str(ROOT / "tests")])}
    cmd = [sys.executable, "-c", textwrap.dedent(SCRIPT), "train-mjx", "--config", str(recipe), "--out", str(out),
           "--coordinator", f"localhost:{free_port()}", "--num-processes", "1", "--process-id", "0"]
    run = subprocess.run(cmd, env=env, cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    assert "on 2 device(s) (cpu, 1 host(s))" in run.stdout
    meta = json.loads((out / "policy.json").read_text())
    assert (meta["devices"], meta["processes"], meta["env"], meta["env_id"], meta["complete"]) == (2, 1, "Block", None,
                                                                                               True)
    rows = (out / "progress.csv").read_text().splitlines()
    assert len(rows) == 2 and rows[-1].startswith("320,")  # the header and the one update's row


@pytest.mark.parametrize("flags, match", [
    (["--coordinator", "localhost:1234"], "go together"),
    (["--coordinator", "localhost:1234", "--num-processes", "2", "--process-id", "2"], "from 0 to"),
])
def test_host_flags_are_checked_before_compiling(flags, match, capsys):
    with pytest.raises(SystemExit) as exit_:
        cli(["train-mjx", "--config", "hexapod-sand", *flags])
    assert exit_.value.code == 2 and match in capsys.readouterr().err


def test_worlds_must_split_over_the_devices(monkeypatch):
    import jax

    from mjrft.train import mjx_ppo

    monkeypatch.setattr(jax, "device_count", lambda: 2)
    cfg = mjx_ppo.load_recipe("hexapod-sand")
    cfg["num_envs"] = 4
    mjx_ppo.check_devices(cfg)
    cfg["num_envs"] = 5
    with pytest.raises(ValueError, match="num_envs = 5 must be a multiple of the 2 devices"):
        mjx_ppo.check_devices(cfg)


@pytest.mark.parametrize("name", ["go2-joystick-sand", "go2-joystick-rigid"])
def test_go2_recipes_name_registry_envs(name):
    from mjrft.mjx import envs
    from mjrft.train import mjx_ppo

    cfg = mjx_ppo.load_recipe(name)
    assert cfg["env"] in envs.names() and cfg["num_envs"] == 8192 and cfg["num_timesteps"] == 100_000_000
    assert cfg["ppo"]["batch_size"] * cfg["ppo"]["num_minibatches"] % cfg["num_envs"] == 0
    with pytest.raises(ValueError, match="unknown env 'Go2Joystick'"):
        mjx_ppo.check_recipe({**cfg, "env": "Go2Joystick"})


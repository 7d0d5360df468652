"""Every command and public constructor against bad values: one clear error naming the value and the choices.

A table per surface: the command line (exit status 2 and a single ``mjrft <command>: error: ...`` line, no
traceback, before any long work) and the public constructors (a ``ValueError``/``TypeError`` whose message
names the bad value). Module-specific edge cases live beside their modules; this suite keeps the whole
surface covered in one place.
"""

from __future__ import annotations

import importlib.util
import shlex
import subprocess
import sys
from pathlib import Path

import mujoco
import pytest

import mjrft
from mjrft.tools import cli

ENV = "mjrft/HexapodSand-v0"
CLI = [
    ("demo --gait nosuch", "policy 'nosuch' is neither a file nor a gait spec"),
    ("demo --seconds -1", "seconds must be finite and > 0, got -1"),
    ("demo --medium mud", "unknown medium 'mud'; valid choices: generic"),
    ("demo --log-every 0", "log_every must be an integer >= 1, got 0"),
    ("settle --medium mud", "unknown medium 'mud'; valid choices"),
    ("rig plate --beta abc", "argument --beta: invalid float value: 'abc'"),
    ("rig plate --depth -1", "depth must be finite and > 0, got -1"),
    ("rig plate --law nope", "unknown law 'nope'; valid choices: depth_only"),
    ("rig plate --speed 0", "speed must be finite and > 0, got 0"),
    ("rig leg --shape blob", "unknown leg shape 'blob'; valid choices: c, family, flat"),
    ("rig leg --omega 0", "omega must be non-zero"),
    ("rig leg --dtheta 0", "dtheta must be finite and > 0"),
    ("rig nosuchrig", "invalid choice: 'nosuchrig'"),
    ("train --env nosuch/Env-v0", "unknown env id 'nosuch/Env-v0'; valid choices: mjrft/"),
    (f"train --algo dqn --env {ENV}", "unknown algorithm 'dqn'; valid choices: ppo, sac"),
    (f"train --timesteps 0 --env {ENV}", "timesteps must be an integer >= 1, got 0"),
    (f"train --n-envs 0 --env {ENV}", "n_envs must be an integer >= 1, got 0"),
    (f"train --env {ENV} --hp learning_rate=abc", "hyper-parameter learning_rate takes a number, got 'abc'"),
    (f"train --env {ENV} bogus=1", "unexpected keyword argument(s): bogus"),
    (f"eval --policy nosuch.zip --env {ENV}", "policy 'nosuch.zip' is neither a file nor a gait spec"),
    (f"eval --policy tripod:f=abc --env {ENV}", "parameter f='abc' is not a number"),
    (f"eval --policy tripod --env {ENV} --episodes 0", "episodes must be an integer >= 1, got 0"),
    (f"eval --policy tripod --env {ENV} medium=mud", "unknown medium 'mud'"),
    (f"rollout --env {ENV} --policy tripod --seconds 0", "seconds must be finite and > 0, got 0"),
    ("rollout --env nope --policy tripod", "unknown env id 'nope'; valid choices"),
    ("bench --scenarios nosuch", "unknown scenario 'nosuch'; valid choices: cleg"),
    ("bench --repeats 0", "repeats must be finite and > 0, got 0"),
    ("sweep --grid f=", "grid axis must be NAME=V1,V2,..."),
    ("validate --case nosuch", "unknown validation case 'nosuch'; valid choices"),
]


@pytest.mark.parametrize("argv,message", CLI, ids=[c[0] for c in CLI])
def test_every_command_rejects_bad_input_with_one_line_and_status_2(argv, message, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)  # any output a command would write lands here (none should)
    with pytest.raises(SystemExit) as e:
        cli.main(shlex.split(argv))
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert message in err, err
    assert "Traceback" not in err and err.strip().splitlines()[-1].startswith("mjrft")


def _hexapod():
    from mjrft.models import hexapod_model

    return hexapod_model()


CONSTRUCTORS = [
    ("GranularTerrain medium", lambda: mjrft.GranularTerrain(_hexapod(), "mud"), "unknown medium 'mud'"),
    ("GranularTerrain law", lambda: mjrft.GranularTerrain(_hexapod(), law="nope"), "unknown law 'nope'"),
    ("GranularTerrain resolution", lambda: mjrft.GranularTerrain(_hexapod(), resolution=-1),
     "resolution must be finite and > 0, got -1"),
    ("GranularTerrain body", lambda: mjrft.GranularTerrain(_hexapod(), bodies=["nobody"]), "unknown body 'nobody'"),
    ("GranularTerrain empty bodies", lambda: mjrft.GranularTerrain(_hexapod(), bodies=[]), "bodies=[] selects nothing"),
    ("GranularTerrain world body", lambda: mjrft.GranularTerrain(_hexapod(), bodies=["world"]),
     "bodies names the world body, whose 2 geom"),
    ("GranularTerrain fine resolution", lambda: mjrft.GranularTerrain(_hexapod(), resolution=1e-5),
     "more than max_elements"),
    ("GranularTerrain model type", lambda: mjrft.GranularTerrain("hexapod.xml"), "model must be a mujoco.MjModel"),
    ("GranularTerrain inside-out mesh", lambda: mjrft.GranularTerrain(_inside_out_mesh(), bodies=["b"], floor="floor"),
     "mesh geom 1 'cube' (mesh 'cube') is inside out"),
    ("medium_3d", lambda: mjrft.medium_3d("x", -1.0, 0.5, 0.3), "must be finite and > 0"),
    ("calibrate", lambda: mjrft.calibrate([0.01, 0.02], [1.0]), "depth and stress must have the same length, got 2 and 1"),
    ("plate_intrusion", lambda: mjrft.tools.rigs.plate_intrusion(depth=0), "depth must be finite and > 0, got 0"),
    ("rotating_leg", lambda: mjrft.tools.rigs.rotating_leg("blob"), "unknown leg shape 'blob'"),
    ("env kwarg value", lambda: __import__("gymnasium").make(ENV, medium="mud"), "unknown medium 'mud'"),
    ("env kwarg name", lambda: __import__("gymnasium").make(ENV, bogus=1), "unexpected keyword argument(s): bogus"),
    ("gait spec", lambda: mjrft.tools.gaits.parse_gait_spec("tripod:f=-1"),
     "parameter f=-1.0 out of range; valid: (0, inf]"),
    ("published datum", lambda: mjrft.tools.validation.published("li2013", "nosuch"), "valid choices"),
    ("vector env reset option", lambda: _vector().reset(options={"reset_maks": None}),
     "unknown reset option 'reset_maks'; valid choices: reset_mask"),
]


def _inside_out_mesh() -> mujoco.MjModel:
    """A cube mesh whose faces wind clockwise seen from outside (MuJoCo compiles it)."""
    v = " ".join(f"{x} {y} {z}" for x in (-.05, .05) for y in (-.05, .05) for z in (-.05, .05))
    outward = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1), (2, 3, 7), (2, 7, 6),
               (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]
    f = " ".join(f"{a} {c} {b}" for a, b, c in outward)  # reversed
    return mujoco.MjModel.from_xml_string(f"""<mujoco><asset><mesh name="cube" vertex="{v}" face="{f}"/></asset>
  <worldbody><geom name="floor" type="plane" size="1 1 .1"/>
  <body name="b" pos="0 0 .1"><freejoint/><geom name="cube" type="mesh" mesh="cube"/></body></worldbody></mujoco>""")


def _vector():
    from mjrft.envs import make_vector

    return make_vector(ENV, num_envs=2, resolution=0.03)


@pytest.mark.parametrize("name,make,message", CONSTRUCTORS, ids=[c[0] for c in CONSTRUCTORS])
def test_public_constructors_name_the_bad_value(name, make, message):
    import mjrft.tools.gaits  # noqa: F401
    import mjrft.tools.rigs  # noqa: F401
    import mjrft.tools.validation  # noqa: F401

    with pytest.raises((ValueError, TypeError)) as e:
        make()
    assert message in str(e.value), str(e.value)


# the files a command reads: one line naming the file; nothing left behind
FILES = [
    ("eval --policy bad.zip --env " + ENV, {"bad.zip": b"PK\x03\x04 cut"}, "bad.zip: not a readable zip file"),
    ("eval --policy run --env " + ENV, {"run/model.zip": b""}, "run: no model in it loads"),
    ("train --config bad.json", {"bad.json": b'{"env_id": '}, "training config 'bad.json' cannot be read"),
    ("train --out run", {"run/config.json": b'{"env_id": ', "run/checkpoints/step_0000000064.zip": b""},
     "run/config.json: run config is not valid JSON"),
    ("train --config big.yaml --timesteps 0", {"big.yaml": b"env_id: mjrft/HexapodSand-v0\ntimesteps: 1e5\n"},
     "timesteps must be an integer >= 1, got 0"),
    ("plot run --out c.png", {"run/monitor.csv": b"r,l,t\n1,2,3\n", "run/logs/from_0000000000/progress.csv":
                              b"\x89PNG\r\n\x1a\n\x00\xff"}, "progress.csv: training log is not a text file"),
    ("train --env nosuch/Env-v0 --out new/run", {}, "unknown env id"),
    (f"sweep --env {ENV} --gait cut.zip --grid medium=poppy_lp --out sw", {"cut.zip": b"PK\x03\x04"},
     "cut.zip: not a readable zip file"),
]


@pytest.mark.parametrize("argv,files,message", FILES, ids=[f[0] for f in FILES])
def test_damaged_files_are_named_and_failed_commands_leave_no_folder(argv, files, message, tmp_path, capsys,
                                                                     monkeypatch):
    pytest.importorskip("stable_baselines3")
    monkeypatch.chdir(tmp_path)
    for name, data in files.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_bytes(data)
    before = sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*"))
    with pytest.raises(SystemExit) as e:
        cli.main(shlex.split(argv))
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert message in err, err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*")) == before  # no folder or file made


def test_config_files_take_integers_in_any_number_notation(tmp_path):
    pytest.importorskip("yaml")
    from mjrft.train.config import load_training_config

    path = tmp_path / "c.yaml"
    for text in ("1e5", "1.0e+5", "100_000", "100000"):
        path.write_text(f"env_id: {ENV}\ntimesteps: {text}\n")
        assert load_training_config(path)["timesteps"] == 100_000, text
    for text, shown in (("1.5e0", "'1.5e0'"), ("2.5", "2.5"), ("lots", "'lots'")):
        path.write_text(f"env_id: {ENV}\ntimesteps: {text}\n")
        with pytest.raises(ValueError, match=f"'timesteps' must be an integer >= 1, got {shown}"):
            load_training_config(path)


@pytest.mark.slow
def test_eval_exits_1_when_every_episode_diverged_and_leaves_no_mujoco_log(tmp_path, capsys, monkeypatch):
    pytest.importorskip("stable_baselines3")
    monkeypatch.chdir(tmp_path)
    rc = cli.main(shlex.split(f"eval --policy tripod --env {ENV} --episodes 2 --no-progress timestep=1.0 "
                              "resolution=0.03"))
    assert rc == 1
    assert "every episode (2) diverged" in capsys.readouterr().err
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()


def test_mjx_commands_without_the_optional_extra_say_which_extra(monkeypatch, capsys):
    """Where JAX / Brax / MJX are missing, train-mjx and an MJX policy give one line naming mjrft[mjx]."""
    from mjrft.tools import cli
    from mjrft.train import mjx_ppo

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name in ("jax", "brax") else real(name, *a))
    with pytest.raises(SystemExit) as exit_:
        cli.main(["train-mjx", "--config", "hexapod-sand"])
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert "optional extra mjrft[mjx] (jax, brax not installed)" in err and "Traceback" not in err
    monkeypatch.setattr(importlib.util, "find_spec", real)
    if real("jax") is not None and real("brax") is not None:  # control: with the extra it passes
        mjx_ppo.require_extra()


BENCH = [
    ("bench_third_party.py --resolution-scale 0", "--resolution-scale must be finite and > 0, got 0.0"),
    ("bench_third_party.py --resolution-scale nan", "--resolution-scale must be finite and > 0, got nan"),
    ("element_budget.py --scales 2 -1", "--scales must be finite and > 0, got -1.0"),
    ("element_budget.py --scales inf", "--scales must be finite and > 0, got inf"),
    ("env_timestep.py --budget 0", "--budget must be finite and > 0, got 0.0"),
    ("power_timestep.py --seconds nan", "--seconds must be finite and > 0, got nan"),
]
_NO_JAX = pytest.mark.skipif(importlib.util.find_spec("jax") is None, reason="needs the optional extra mjrft[mjx]")
BENCH += [pytest.param(argv, message, marks=_NO_JAX, id=argv) for argv, message in (
    ("bench_mjx_ground.py --worlds 4 0", "--worlds, --steps and --rounds must be >= 1, got [4, 0], 100, 3"),
    ("bench_mjx_ground.py --warm nan", "--warm must be a finite number of seconds >= 0, got nan"),
)]


@pytest.mark.parametrize("argv,message", BENCH, ids=[b[0] if isinstance(b, tuple) else b.id for b in BENCH])
def test_benchmark_options_reject_bad_values_before_running(argv, message):
    script, *args = shlex.split(argv)
    path = Path(__file__).resolve().parent.parent / "benchmarks" / script
    out = subprocess.run([sys.executable, str(path), *args], capture_output=True, text=True, timeout=120)
    assert out.returncode == 2 and message in out.stderr and "Traceback" not in out.stderr

"""The MJX envs stepped against their gymnasium envs (the hexapod, and the biped and the humanoid on sand), under
Brax's and MuJoCo Playground's training wrappers, and the Brax PPO recipe end to end on CPU JAX: ``mjrft train-mjx
--seeds 0`` trains a few hundred steps on the biped on sand, writes pickle-free policy files and the summary over the
seeds with the policy's episode on the CPU env, and ``mjrft eval`` runs the policy on the CPU env and on the MJX
env."""

from __future__ import annotations

import contextlib

import json
import math
import warnings

import numpy as np
import pytest

jax = pytest.importorskip("jax", reason="the MJX env needs the optional extra mjrft[mjx] (JAX)")
pytest.importorskip("brax", reason="the MJX env and recipe need Brax (mjrft[mjx])")
gymnasium = pytest.importorskip("gymnasium")

import jax.numpy as jnp  # noqa: E402

import mjrft  # noqa: E402
import mjrft.envs  # noqa: E402,F401  (registers the ids)
import mjrft.mjx.envs as envs  # noqa: E402
from mjrft.envs.mjx.locomotion import STEP_METRICS  # noqa: E402
from mjrft.tools.cli import main as cli  # noqa: E402
from mjrft.train import mjx_ppo  # noqa: E402

pytestmark = pytest.mark.slow  # every test compiles MJX programs (5-60 s each on 2 cores)

TRIPOD = np.full(6, 2 * np.pi * 2.0 / (6 * np.pi))  # 2 Hz on every hip: the legs start in the tripod's phases


@pytest.fixture(scope="module")
def mjx_env():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        env = envs.load("HexapodSand")
    return env, jax.jit(env.reset), jax.jit(env.step)


def test_env_matches_the_cpu_env_step_for_step(mjx_env):
    env, reset, step = mjx_env
    state = reset(jax.random.PRNGKey(3))
    reset_types = _types(state)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cpu = env.gym_env(state)
    assert env.observation_size == cpu.observation_space.shape[0] and env.action_size == cpu.action_space.shape[0]
    u = cpu.unwrapped
    np.testing.assert_allclose(np.asarray(state.obs), u.task.observation(np, u.data, u.target), atol=1e-6)
    for k in range(30):
        state = step(state, jnp.asarray(TRIPOD))
        obs, reward, terminated, truncated, info = cpu.step(TRIPOD)
        if k < 5:  # float32 MJX against float64 MuJoCo: equal to rounding while the legs enter the sand
            np.testing.assert_allclose(np.asarray(state.obs), obs, rtol=1e-3, atol=2e-3)
            assert float(state.reward) == pytest.approx(reward, rel=0.05, abs=5e-3)
    # after 0.3 s of gait the two simulations still walk the same way
    assert float(state.data.qpos[0]) == pytest.approx(info["x_position"], abs=3e-3)
    assert float(state.done) == 0.0 and not terminated
    np.testing.assert_allclose(np.asarray(state.info["sinkage"]), info["sinkage"], atol=3e-3)
    assert float(state.metrics["power"]) == pytest.approx(info["power"], rel=0.3)
    cpu.close()
    # step returns a State of reset's types (weak types included), so jit compiles step once for an episode
    assert _types(state) == reset_types


def _types(state):
    return jax.tree_util.tree_map(lambda x: (x.shape, x.dtype, x.aval.weak_type), state)


def test_env_follows_the_cpu_env_when_the_servos_clamp():
    """In float64, actions that drive the hip servos into their force clamp (each leg commanded at full speed,
    alternating in sign): the MJX env and the CPU env stay together to rounding, step for step. (MJX's own
    implicitfast keeps a clamped servo's kv in its derivative, MuJoCo does not: with it the two envs are 3 mrad
    apart after one step; mjrft.mjx integrates as MuJoCo, tests/mjrft/mjx/test_mjx.py.) The MJX env's power is the
    mean of the actuators' power over the step's physics steps, computed here from the CPU env's MjData after each;
    control: the last physics step's power (a sample at the end of the step) is not it."""
    with jax.enable_x64(True), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        env = envs.load("HexapodSand")
        step = jax.jit(env.step)
        state = jax.jit(env.reset)(jax.random.PRNGKey(3))
        cpu = env.gym_env(state)
        signs = np.array([1.0, -1.0, 1.0, -1.0, 1.0, -1.0])
        clamped, power = [], []  # per physics step of the CPU env: servo forces at their clamp, actuators' power

        def record(d):
            clamped.append(int(np.sum(np.abs(d.actuator_force) >= 0.3)))
            power.append(float(np.sum(np.abs(d.actuator_force * d.actuator_velocity))))

        cpu.unwrapped.each_physics_step(record)
        gaps = []
        for k in range(12):
            action = signs * (1.0 if k % 4 < 2 else -1.0)
            state = step(state, jnp.asarray(action))
            cpu.step(action)
            data = cpu.unwrapped.data
            np.testing.assert_allclose(np.asarray(state.data.qpos), data.qpos, rtol=0, atol=1e-9)
            np.testing.assert_allclose(np.asarray(state.data.qvel), data.qvel, rtol=0, atol=1e-7)
            mean = np.mean(power[-env.n_substeps:])
            assert float(state.metrics["power"]) == pytest.approx(mean, rel=1e-6)
            gaps.append(abs(power[-1] - mean) / mean)
        cpu.close()
    assert sum(clamped) > 0  # the servos did clamp: the case where MJX's own integrator departs from MuJoCo
    assert len(power) == 12 * env.n_substeps and max(gaps) > 0.1


def test_nonfinite_action_ends_the_episode_as_diverged(mjx_env):
    env, reset, step = mjx_env
    # the same action type as the other tests' (a Python scalar would make it weakly typed: another compile of step)
    state = step(reset(jax.random.PRNGKey(0)), jnp.full(6, jnp.nan, jnp.float32))
    assert float(state.done) == 1.0 and float(state.metrics["diverged"]) == 1.0 and float(state.reward) == 0.0
    assert np.all(np.isfinite(np.asarray(state.obs)))
    ok = step(reset(jax.random.PRNGKey(0)), jnp.zeros(6))  # control: a finite action does not
    assert float(ok.done) == 0.0 and float(ok.metrics["diverged"]) == 0.0


def test_the_sand_guards_reach_the_metrics_and_the_host_warnings(mjx_env):
    env, reset, step = mjx_env
    state = reset(jax.random.PRNGKey(0))
    for _ in range(10):
        state = step(state, jnp.asarray(TRIPOD))
    # the env's own 0.5 ms step: nothing fired, nothing to say
    assert float(state.metrics["unstable"]) == 0.0 and float(state.metrics["out_of_range"]) == 0.0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        env.warn(state)
    # control: the same robot at an 8x coarser physics step exceeds the granular stiffness's limit
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        coarse = envs.load("HexapodSand", config_overrides={"sim_dt": 0.004, "ctrl_dt": 0.02})
    state = jax.jit(coarse.reset)(jax.random.PRNGKey(0))
    cstep = jax.jit(coarse.step)
    for _ in range(30):
        state = cstep(state, jnp.ones(6))
    assert float(state.metrics["unstable"]) == 1.0
    with pytest.warns(mjrft.TerrainStabilityWarning, match="stability limit"):
        coarse.warn(state)


def test_terrain_randomization_draws_per_world_and_repeats_for_a_seed(mjx_env):
    media = ["poppy_cp", "poppy_lp", "glass03_cp"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        env = envs.load("HexapodSand", config_overrides={"randomization.media": media,
                                                         "randomization.stress_scale": [0.7, 1.3],
                                                         "randomization.surface_height": [-0.005, 0.005]})
    reset = jax.jit(jax.vmap(env.reset))
    keys = jax.random.split(jax.random.PRNGKey(0), 16)
    a, b = reset(keys), reset(keys)
    drawn = ("medium", "stress_scale", "surface_height")
    info = {k: np.asarray(a.info[k]) for k in drawn}
    assert env.media == tuple(media) and set(info["medium"]) == {0, 1, 2}  # 16 worlds draw every medium
    assert np.all((info["stress_scale"] >= 0.7) & (info["stress_scale"] <= 1.3))
    assert np.all(np.abs(info["surface_height"]) <= 0.005) and np.std(info["surface_height"]) > 1e-3
    for k in drawn:
        np.testing.assert_array_equal(np.asarray(a.info[k]), np.asarray(b.info[k]))
    sand = a.info["sand"]
    k = 3
    expected = env.sand.params_of(media[info["medium"][k]], stress_scale=float(info["stress_scale"][k]))
    np.testing.assert_allclose(np.asarray(sand.params[k]), expected, rtol=1e-6)
    np.testing.assert_allclose(np.asarray(sand.surface), info["surface_height"], atol=1e-7)
    plain = mjx_env[1](keys[0])  # control: no option, no draw
    assert not set(drawn) & set(plain.info) and float(plain.info["sand"].surface) == 0.0


def test_brax_and_playground_training_wrappers_take_the_env(mjx_env):
    """Brax's training wrappers (``brax.envs.wrappers.training.wrap``: vmap, episode length, auto-reset) and, where
    the ``playground`` package is installed, MuJoCo Playground's ``wrap_for_brax_training`` take the env as it is:
    their batched reset and step trace through it (``jax.eval_shape``: nothing compiled) to States of the env's
    shapes. (Brax's wrappers and PPO also train it in the recipe tests below.)"""
    from brax.envs.wrappers import training

    env = mjx_env[0]
    wrapped = {"brax": training.wrap(env, episode_length=5)}
    try:
        from mujoco_playground import wrapper
    except ImportError:
        pass
    else:
        wrapped["playground"] = wrapper.wrap_for_brax_training(env, episode_length=5)
    keys = jax.random.split(jax.random.PRNGKey(0), 3)
    for name, w in wrapped.items():
        state = jax.eval_shape(w.step, jax.eval_shape(w.reset, keys), jnp.zeros((3, env.action_size)))
        assert state.obs.shape == (3, env.observation_size) and state.data.qpos.shape == (3, env.mj_model.nq), name
        assert state.info["sand"].u.shape == (3, env.sand.n_elements, 3) and state.info["steps"].shape == (3,), name
        assert set(state.metrics) >= set(STEP_METRICS) and state.done.shape == (3,), name


def test_auto_reset_starts_each_episode_on_fresh_sand(mjx_env):
    """What the auto-resets of Brax and Playground do, restore the first ``data`` and ``obs`` and leave ``info`` (the
    sand's state) alone, starts an episode from the first state on sand without memory and without the ended
    episode's divergence record: its first step is the first episode's, bit for bit. Control: the same step with
    the world's time nudged off 0 (the rule's trigger) carries the ended episode's divergence on."""
    env, reset, step = mjx_env
    first = reset(jax.random.PRNGKey(5))
    action = jnp.full(6, 2 / 3, jnp.float32)  # strongly typed, as the other tests' actions: no new compile
    s1 = step(first, action)
    s2 = step(s1, action)
    assert float(jnp.max(jnp.abs(s2.info["sand"].u))) > 1e-5  # the episode's memory
    # as if the ended episode had diverged: its sand state records a body, sticky until a reset
    stale = s2.info["sand"]._replace(bad_body=jnp.array(3, jnp.int32), bad_time=jnp.array(0.015, jnp.float32))
    restarted = s2.replace(data=first.data, obs=first.obs, info={**s2.info, "sand": stale})
    s3 = step(restarted, action)
    np.testing.assert_array_equal(np.asarray(s3.obs), np.asarray(s1.obs))
    assert float(s3.metrics["diverged"]) == 0.0 and float(s3.done) == 0.0
    kept = step(restarted.replace(data=first.data.replace(time=jnp.float32(1e-7))), action)
    assert float(kept.metrics["diverged"]) == 1.0 and float(kept.done) == 1.0 and float(kept.reward) == 0.0


@pytest.mark.parametrize("name", ["BipedSand", "HumanoidSand"])
def test_biped_and_humanoid_on_sand_follow_their_gymnasium_envs(name):
    """The biped's and the humanoid's MJX envs (float32) against their gymnasium envs (float64) from the gymnasium
    env's reset state (put on the device; the same pytree as the MJX env's reset, traced, to compile only the step)
    with the same actions: equal to rounding over the first control steps, the same reward terms, the feet in the
    sand on both."""
    from mujoco import mjx

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        env = envs.load(name)
        cpu = env.gym_env()
        u = cpu.unwrapped
        n_feet = len(env.task.feet)
        zero = jnp.zeros(())
        state = envs.State(mjx.put_data(env.mj_model, u.data), jnp.asarray(u.task.observation(np, u.data, u.data.ctrl)),
                           zero, zero, {k: zero for k in STEP_METRICS},
                           {"sand": env.sand.init(), "sinkage": jnp.zeros(n_feet), "granular_force": jnp.zeros((n_feet, 3))})
        shapes = jax.eval_shape(env.reset, jax.random.PRNGKey(0))
        assert jax.tree_util.tree_structure(state) == jax.tree_util.tree_structure(shapes)
        assert all(a.shape == b.shape and a.dtype == b.dtype for a, b in
                   zip(jax.tree_util.tree_leaves(state), jax.tree_util.tree_leaves(shapes)))
        # every leaf committed to the device, as step's outputs are: jit compiles step once, not again for its own
        state = jax.device_put(state, jax.devices()[0])
        step = jax.jit(env.step)
        rng = np.random.default_rng(2)
        for _ in range(2):
            action = rng.uniform(-0.5, 0.5, env.action_size)
            state = step(state, jnp.asarray(action))
            obs, reward, terminated, _, info = cpu.step(action)
            np.testing.assert_allclose(np.asarray(state.obs), obs, rtol=2e-3, atol=2e-3)
            assert float(state.reward) == pytest.approx(reward, rel=0.02, abs=2e-3)
            assert float(state.metrics["reward_healthy"]) == info["reward_healthy"] and float(state.done) == terminated
            assert float(state.metrics["power"]) == pytest.approx(info["power"], rel=0.05)
        assert np.max(info["sinkage"]) > 1e-4  # the feet are in the sand
        np.testing.assert_allclose(np.asarray(state.info["sinkage"]), info["sinkage"], atol=2e-4)
    cpu.close()


TINY = {"env": "BipedSand", "num_timesteps": 400, "num_envs": 4, "episode_length": 50,
        "network": {"policy_hidden_layer_sizes": [16, 16], "value_hidden_layer_sizes": [16, 16]},
        "ppo": {"unroll_length": 5, "batch_size": 4, "num_minibatches": 2, "num_updates_per_batch": 1,
                "num_evals": 2, "num_eval_envs": 4, "normalize_observations": True, "learning_rate": 3e-4}}


@pytest.fixture(scope="module")
def trained(tmp_path_factory):
    """The tiny recipe on the biped on sand, as one seed of a several-seed run: the run folder ``seed-0``, its
    policy evaluated on the CPU env (one episode) and the summary over the seeds."""
    root = tmp_path_factory.mktemp("mjx")
    recipe = root / "tiny.json"
    recipe.write_text(json.dumps(TINY))
    out = root / "runs"
    assert cli(["train-mjx", "--config", str(recipe), "--out", str(out), "--seeds", "0", "--eval-episodes", "0",
                "--cpu-episodes", "1"]) == 0
    return out / "seed-0"


def test_recipe_trains_and_writes_pickle_free_files(trained):
    assert sorted(p.name for p in trained.iterdir()) == ["checkpoints", "evaluation.json", "policy.json", "policy.npz",
                                                         "progress.csv"]
    meta = json.loads((trained / "policy.json").read_text())
    assert meta["format"] == mjx_ppo.FORMAT and meta["env_id"] == "mjrft/BipedSand-v0"
    assert (meta["env"], meta["env_config"], meta["env_kwargs"]) == ("BipedSand", {}, {})
    assert meta["recipe"]["num_timesteps"] == 400 and meta["observation_size"] == 21 and meta["complete"] is True
    rows = (trained / "progress.csv").read_text().splitlines()
    assert rows[0].startswith("steps,") and len(rows) == 3 and rows[-1].startswith("400,")
    with np.load(trained / "policy.npz", allow_pickle=False) as z:
        assert all(z[k].dtype != object for k in z.files) and len(z.files) > 6
    policy = mjx_ppo.load_policy(trained)
    a = policy(np.zeros(21))
    assert a.shape == (8,) and np.all(np.abs(a) <= 1.0)


def test_the_seeds_summary_holds_the_cpu_cross_check(trained):
    """``--seeds 0 --cpu-episodes 1``: the policy ran one episode on the CPU env of the same task (mjrft eval), and
    the summary over the seeds reports it."""
    row = json.loads((trained / "evaluation.json").read_text())["row"]
    assert row["cpu_episodes"] == 1 and row["cpu_diverged"] == 0 and math.isfinite(row["cpu_speed"])
    assert row["eval_episodes"] == 0 and "mjx_speed" not in row
    summary = json.loads((trained.parent / "seeds.json").read_text())
    assert (summary["env"], summary["env_id"], summary["seeds"]) == ("BipedSand", "mjrft/BipedSand-v0", [0])
    assert summary["spread"]["cpu_speed"]["mean"] == row["cpu_speed"] and summary["spread"]["cpu_speed"]["n"] == 1
    text = (trained.parent / "seeds.txt").read_text()
    assert "CPU: 1 on the CPU env mjrft/BipedSand-v0" in text
    assert f"$ mjrft eval --policy {trained} --episodes 1" in text


def test_each_evaluation_keeps_its_policy_as_a_run_folder(trained):
    steps = [int(line.split(",")[0]) for line in (trained / "progress.csv").read_text().splitlines()[1:]]
    folders = sorted((trained / mjx_ppo.CHECKPOINTS).iterdir())
    assert [f.name for f in folders] == [f"{n:011d}" for n in steps] == ["00000000000", "00000000400"]
    first, last = (mjx_ppo.load_policy(f) for f in folders)
    assert first.meta["num_timesteps"] == 0 and first.meta["complete"] is False
    with np.load(folders[-1] / "policy.npz") as a, np.load(trained / "policy.npz") as b:  # the last one is final
        assert a.files == b.files and all(np.array_equal(a[k], b[k]) for k in a.files)
    obs = np.linspace(-1.0, 1.0, 21)
    assert not np.allclose(first(obs), last(obs))  # 400 steps of training changed the policy


def test_eval_runs_the_policy_on_both_backends(trained, capsys):
    assert cli(["eval", "--policy", str(trained), "--episodes", "1", "--no-progress", "max_episode_steps=20"]) == 0
    cpu_out = capsys.readouterr().out
    assert "mjrft/BipedSand-v0" in cpu_out and "1 episode(s)" in cpu_out
    assert cli(["eval", "--policy", str(trained), "--episodes", "2", "--backend", "mjx"]) == 0
    mjx_out = capsys.readouterr().out
    assert "on the MJX env BipedSand" in mjx_out and "diverged 0" in mjx_out


def test_damaged_or_foreign_policy_files_are_named(trained, tmp_path):
    bad = tmp_path / "bad"
    bad.mkdir()
    (bad / "policy.json").write_text((trained / "policy.json").read_text())
    (bad / "policy.npz").write_bytes((trained / "policy.npz").read_bytes()[:200])
    with pytest.raises(ValueError, match=r"policy\.npz cannot be read"):
        mjx_ppo.load_policy(bad)
    (bad / "policy.json").write_text("{not json")
    with pytest.raises(ValueError, match=r"policy\.json is not valid JSON"):
        mjx_ppo.load_policy(bad)
    with pytest.raises(ValueError, match="a run folder of 'mjrft train-mjx'"):
        from mjrft.train.evaluate import _main_mjx
        import argparse

        _main_mjx(argparse.Namespace(policy=str(tmp_path), csv=None, rrd=None, env_id=None, episodes=1, seed=0,
                                     json=None), {})


@pytest.mark.parametrize("change, match", [
    ({"nonsense": 1}, "unknown key"),
    ({"num_envs": 0}, "'num_envs' must be an integer >= 1"),
    ({"ppo": {"num_timesteps": 5}}, "set by mjrft"),
    ({"ppo": {"learning_rat": 1e-3}}, "unknown ppo key"),
    ({"network": {"policy_hidden_layer_sizes": [0]}}, "list of layer sizes"),
    ({"num_envs": 3}, "must divide one another"),
    ({"env": "HexapodSandy"}, "unknown env 'HexapodSandy'; valid choices: BipedRigid"),
    ({"env_kwargs": {}}, "replaced by 'env'"),
])
def test_bad_recipes_are_refused_before_compiling(change, match):
    cfg = {**TINY, **change}
    with pytest.raises(ValueError, match=match):
        mjx_ppo.check_recipe(cfg)


def test_named_recipe_is_valid():
    assert "hexapod-sand" in mjx_ppo.named_recipes()
    cfg = mjx_ppo.load_recipe("hexapod-sand")
    assert cfg["num_envs"] >= 1024 and cfg["ppo"]["normalize_observations"] is True
    with pytest.raises(ValueError, match="unknown MJX training recipe"):
        mjx_ppo.load_recipe("hexapod-sandy")


def test_replicated_put_stands_in_only_where_jax_lacks_it():
    """Brax 0.14.2's PPO calls jax.device_put_replicated, which jax 0.10 removed: train-mjx provides it for the
    call (the mjx extra pins jax 0.11 on Python 3.12+), and leaves a jax that has its own alone."""
    import types

    import jax

    lacking = types.SimpleNamespace()
    tree = {"w": np.arange(6.0, dtype=np.float32).reshape(2, 3), "b": np.float32(1.5)}
    with mjx_ppo._replicated_put(lacking):
        out = lacking.device_put_replicated(tree, jax.local_devices()[:1])
        assert out["w"].shape == (1, 2, 3) and out["b"].shape == (1,)
        np.testing.assert_array_equal(np.asarray(out["w"][0]), tree["w"])
        total = jax.pmap(lambda t: t["w"].sum() + t["b"])(out)  # what Brax does with the replicated state
        assert float(total[0]) == 16.5
    assert not hasattr(lacking, "device_put_replicated")
    own = types.SimpleNamespace(device_put_replicated="jax's own")
    with mjx_ppo._replicated_put(own):
        assert own.device_put_replicated == "jax's own"


def test_brax_evaluations_compile_their_unroll_once():
    """Brax's Evaluator calls one jitted unroll on a reset state and initial parameters (uncommitted, a weakly typed
    scalar), then on committed, strongly typed ones; train-mjx's wrapper gives every call the same compile key.
    Control: Brax's own Evaluator compiles again for each new form of its inputs. Brax's 'fast' env keeps it small."""
    import logging

    from brax import envs as brax_envs
    from brax.training import acting

    env = brax_envs.training.wrap(brax_envs.get_environment("fast"), episode_length=2)

    def policy_fn(params):
        return lambda obs, key: (jnp.zeros(obs.shape[:-1] + (env.action_size,)) * params["w"], {})

    def compiles(wrapped: bool) -> int:
        messages = []
        handler = logging.Handler()
        handler.emit = lambda record: messages.append(record.getMessage())
        logger = logging.getLogger("jax")
        logger.addHandler(handler)
        try:
            with jax.log_compiles(True):
                with mjx_ppo._evaluations_compile_once() if wrapped else contextlib.nullcontext():
                    ev = acting.Evaluator(env, policy_fn, num_eval_envs=2, episode_length=2, action_repeat=1,
                                          key=jax.random.PRNGKey(int(wrapped)))
                committed = jax.device_put(jnp.zeros((), jnp.float32), jax.local_devices()[0])
                for params in ({"w": jnp.asarray(0.0)}, {"w": committed}, {"w": committed}):
                    ev.run_evaluation(params, {})
        finally:
            logger.removeHandler(handler)
        return sum("Compiling jit(generate_eval_unroll)" in m for m in messages)

    assert compiles(wrapped=True) == 1
    assert compiles(wrapped=False) > 1

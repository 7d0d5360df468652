"""The batched vector environment (mjrft.envs.vector); the batched stepping it runs on (mjrft.batch) is tested in
tests/mjrft/test_batch.py."""

from __future__ import annotations

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")
pytest.importorskip("imageio")  # gymnasium.envs.mujoco needs it (gymnasium[mujoco])

from gymnasium.utils.env_checker import data_equivalence  # noqa: E402
from gymnasium.vector import AutoresetMode  # noqa: E402

from mjrft.envs import ENV_IDS, VECTOR_ENTRY_POINTS, make_vector  # noqa: E402
from mjrft.envs.hexapod import SAND_FRAME_SKIP  # noqa: E402
from mjrft.envs.vector import GranularVectorEnv, unbatch_infos  # noqa: E402

HEX = "mjrft/HexapodSand-v0"
# the torso sinks below 4.55 cm after 3-5 random steps: terminations at different steps in different envs
ENDING = {"healthy_z_range": (0.0455, 0.5)}


# ---------------------------------------------------------------------------------------------- vector env
@pytest.mark.parametrize("mode", ["NextStep", "SameStep", "Disabled"])
def test_vector_env_equals_sync_vector_env(mode, run_both):
    kw = dict(num_envs=3, max_episode_steps=6, vector_kwargs={"autoreset_mode": mode}, **ENDING)
    sync = gymnasium.make_vec(HEX, vectorization_mode="sync", **kw)
    kw.pop("vector_kwargs")
    ours = gymnasium.make_vec(HEX, vectorization_mode="vector_entry_point", autoreset_mode=mode, **kw)
    assert isinstance(ours, GranularVectorEnv) and ours.batch is not None
    assert ours.metadata["autoreset_mode"] == AutoresetMode(mode)
    if mode != "Disabled":
        assert run_both(ours, sync, 12) >= 3  # terminations and truncations both happened and were reset
    else:  # the caller resets ended environments with a reset_mask
        assert data_equivalence(ours.reset(seed=5), sync.reset(seed=5))
        rng = np.random.default_rng(1)
        ended = 0
        for _ in range(12):
            actions = rng.uniform(-1, 1, size=ours.action_space.shape).astype(np.float32)
            out_a, out_b = ours.step(actions), sync.step(actions)
            assert all(data_equivalence(x, y, exact=True) for x, y in zip(out_a, out_b))
            done = out_a[2] | out_a[3]
            if done.any():
                ended += int(done.sum())
                assert data_equivalence(ours.reset(options={"reset_mask": done}),
                                        sync.reset(options={"reset_mask": done}), exact=True)
        assert ended >= 3
        done = np.zeros(3, dtype=bool)
        while not done.any():
            _, _, term, trunc, _ = ours.step(np.zeros(ours.action_space.shape))
            done = term | trunc
        with pytest.raises(ValueError, match=r"Disabled and environments \d.* have ended; reset them"):
            ours.step(np.zeros(ours.action_space.shape))
    ours.close()
    sync.close()
    assert ours.closed


def test_rigid_vector_env_equals_sync(run_both):
    kw = dict(num_envs=2, max_episode_steps=4)
    ours = make_vector("mjrft/HexapodRigid-v0", **kw)
    sync = gymnasium.make_vec("mjrft/HexapodRigid-v0", vectorization_mode="sync", **kw)
    assert ours.batch is None
    run_both(ours, sync, 6)


def test_vector_api_contract_and_seeding(run_both):
    envs = make_vector(HEX, 4, parallel=False)
    single = envs.single_observation_space
    assert envs.num_envs == 4 and single.shape == (35,) and single.dtype == np.float64
    assert envs.observation_space.shape == (4, 35) and envs.action_space.shape == (4, 6)
    assert envs.action_space.dtype == np.float32
    with pytest.raises(gymnasium.error.ResetNeeded):
        envs.step(np.zeros((4, 6)))
    obs, infos = envs.reset(seed=11)
    assert envs.observation_space.contains(obs)
    assert infos["sinkage"].shape == (4, 6) and infos["_sinkage"].all()
    obs, rew, term, trunc, infos = envs.step(envs.action_space.sample())
    assert obs.dtype == np.float64 and obs.shape == (4, 35) and envs.observation_space.contains(obs)
    assert rew.dtype == np.float64 and rew.shape == (4,) and np.all(np.isfinite(rew))
    assert term.dtype == np.bool_ and trunc.dtype == np.bool_ and term.shape == trunc.shape == (4,)
    assert infos["granular_force"].shape == (4, 6, 3) and infos["x_velocity"].dtype == np.float64
    assert [e.np_random_seed for e in envs.envs] == [11, 12, 13, 14]
    assert envs.get_attr("frame_skip") == (SAND_FRAME_SKIP,) * 4 and envs.call("foot_sinkage")[3].shape == (6,)
    # seeding reproduces trajectories; another seed gives another start
    other = make_vector(HEX, 4)
    assert run_both(envs, other, 3, reset_seed=21) == 0
    o1, _ = envs.reset(seed=21)
    o2, _ = other.reset(seed=22)
    assert not np.array_equal(o1, o2)
    o3, _ = envs.reset(seed=[22, 23, 24, 25])
    assert np.array_equal(o2, o3)
    envs.close()
    other.close()


def test_vector_bad_input():
    envs = make_vector(HEX, 3)
    envs.reset(seed=0)
    bad = np.zeros((3, 6), dtype=np.float32)
    bad[2, 1] = np.nan
    t_before = envs.envs[0].data.time
    with pytest.raises(ValueError, match=r"actions of environment 2 contain NaN"):
        envs.step(bad)
    bad[0, 0] = np.inf
    with pytest.raises(ValueError, match=r"actions of environments 0, 2 contain NaN or infinite"):
        envs.step(bad)
    assert envs.envs[0].data.time == t_before  # nothing was stepped
    with pytest.raises(ValueError, match=r"actions must have shape \(3, 6\)"):
        envs.step(np.zeros((2, 6)))
    with pytest.raises(ValueError, match="reset_mask"):
        envs.reset(options={"reset_mask": np.zeros(3, dtype=bool)})
    with pytest.raises(ValueError, match="one per environment"):
        envs.reset(seed=[1, 2])
    envs.close()
    with pytest.raises(ValueError, match="unknown environment id 'mjrft/Nope-v0'; valid choices: .*HexapodSand-v0"):
        make_vector("mjrft/Nope-v0", 2)
    with pytest.raises(ValueError, match="unknown autoreset_mode 'later'; valid choices: .*NextStep"):
        make_vector(HEX, 2, autoreset_mode="later")
    with pytest.raises(ValueError, match="num_envs must be an integer >= 1, got 0"):
        make_vector(HEX, 0)
    with pytest.raises(ValueError, match="unknown medium 'mud'"):
        make_vector(HEX, 1, medium="mud")
    with pytest.raises(ValueError, match="not an mjrft GranularMujocoEnv"):
        GranularVectorEnv("CartPole-v1", 1)


def test_registered_vector_entry_points():
    for env_id in ENV_IDS:
        spec = gymnasium.spec(env_id)
        assert spec.vector_entry_point == VECTOR_ENTRY_POINTS[env_id]
        creator = gymnasium.envs.registration.load_env_creator(spec.vector_entry_point)
        assert callable(creator) and env_id in creator.__doc__
    envs = gymnasium.make_vec("mjrft/BipedSand-v0", num_envs=2)  # vector_entry_point is the default mode
    assert isinstance(envs, GranularVectorEnv) and envs.max_episode_steps == 1000
    obs, _ = envs.reset(seed=0)
    assert obs.shape == (2, 21)
    envs.close()


def test_unbatch_infos():
    infos = {"a": np.array([1.0, 2.0, 3.0]), "_a": np.array([True, False, True]),
             "final_info": {"b": np.array([0, 5, 0]), "_b": np.array([False, True, False])},
             "_final_info": np.array([False, True, False])}
    assert unbatch_infos(infos, 3) == [{"a": 1.0}, {"final_info": {"b": 5}}, {"a": 3.0}]


# ---------------------------------------------------------------------------------------------- stable-baselines3
def test_sb3_adapter_equals_dummy_vec_env():
    pytest.importorskip("stable_baselines3")
    from stable_baselines3.common.vec_env import DummyVecEnv

    from mjrft.envs.vector import SB3VecEnv

    kw = dict(max_episode_steps=3, healthy_z_range=(0.039, 0.5))  # both endings happen in 10 steps
    dummy = DummyVecEnv([lambda: gymnasium.make(HEX, **kw) for _ in range(3)])
    adapters = [SB3VecEnv(HEX, num_envs=3, **kw),
                SB3VecEnv(make_vector(HEX, 3, autoreset_mode="Disabled", **kw))]
    rng = np.random.default_rng(2)
    actions = rng.uniform(-1, 1, size=(10, 3, 6)).astype(np.float32)
    runs = []
    for venv in [dummy, *adapters]:
        venv.seed(9)
        obs = [venv.reset()]
        steps = []
        for a in actions:
            o, r, d, info = venv.step(a)
            steps.append((o, r, d, [(i.get("terminal_observation"), i["TimeLimit.truncated"]) for i in info]))
        runs.append((obs, steps))
        venv.close()
    limit = sum(t for s in runs[0][1] for _, t in s[3])
    assert limit >= 1 and sum(int(s[2].sum()) for s in runs[0][1]) > limit  # time limits and terminations
    for other in runs[1:]:
        assert data_equivalence(runs[0], other, exact=True)
    with pytest.raises(ValueError, match="SameStep or Disabled"):
        SB3VecEnv(make_vector(HEX, 1))


def test_sb3_ppo_learns_a_few_hundred_steps():
    pytest.importorskip("stable_baselines3")
    import torch
    from stable_baselines3 import PPO

    from mjrft.envs.vector import SB3VecEnv

    venv = SB3VecEnv(HEX, num_envs=4, max_episode_steps=50)
    model = PPO("MlpPolicy", venv, n_steps=32, batch_size=64, n_epochs=2, seed=0, device="cpu")
    before = [p.detach().clone() for p in model.policy.parameters()]
    model.learn(total_timesteps=256)
    assert model.num_timesteps >= 256
    assert any(not torch.equal(a, b) for a, b in zip(before, model.policy.parameters()))
    assert venv.get_attr("frame_skip") == [SAND_FRAME_SKIP] * 4 and venv.env_is_wrapped(gymnasium.Wrapper) == [False] * 4
    venv.close()

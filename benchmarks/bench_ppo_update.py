"""What PPO's gradient update costs per env step, and how batch size, epochs and torch threads change it.

With many envs the env steps run in parallel (worker processes, or thousands of MJX worlds), but
stable-baselines3's update runs in the trainer: ``n_epochs`` passes over the rollout of
``n_envs x n_steps`` samples in minibatches of ``batch_size``. Its cost per env step does not fall
with more envs, so past some number of envs it, not the physics, sets the training rate.

This script times ``PPO.train()`` alone on a rollout of the hexapod's shapes (35 observations,
6 actions, the recipe's MLP policy) filled by a stand-in env that returns random numbers, so no
physics is timed: for each setting, the update's seconds per 1,000 env steps and the env-step rate
the update alone would allow (``update-bound steps/s``; training cannot go faster than this however
fast the envs are). The settings alternate over repeats; medians are printed, with each setting's
cost over the recipe's (batch 256, 10 epochs, 1 thread) measured in the same run.

    python benchmarks/bench_ppo_update.py [--n-envs 16] [--n-steps 1024] [--repeats 3]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

#: (batch_size, n_epochs, torch threads); the first is the hexapod-sand recipe's
SETTINGS = ((256, 10, 1), (256, 10, 2), (1024, 10, 1), (1024, 10, 2), (4096, 10, 1), (4096, 10, 2),
            (1024, 5, 1), (4096, 5, 2))


def stand_in_env():
    """A gymnasium env with HexapodSand-v0's spaces that returns random observations at no cost."""
    import gymnasium
    from gymnasium import spaces

    class StandIn(gymnasium.Env):
        observation_space = spaces.Box(-np.inf, np.inf, (35,), np.float64)
        action_space = spaces.Box(-1.0, 1.0, (6,), np.float32)

        def reset(self, *, seed=None, options=None):
            super().reset(seed=seed)
            return self.np_random.normal(size=35), {}

        def step(self, action):
            return self.np_random.normal(size=35), float(self.np_random.normal()), False, False, {}

    return StandIn()


def time_update(n_envs: int, n_steps: int, batch_size: int, n_epochs: int, threads: int) -> float:
    """Seconds of one ``PPO.train()`` call on a freshly collected rollout of ``n_envs x n_steps``."""
    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import DummyVecEnv

    venv = DummyVecEnv([stand_in_env] * n_envs)
    model = PPO("MlpPolicy", venv, n_steps=n_steps, batch_size=batch_size, n_epochs=n_epochs, seed=0,
                learning_rate=3e-4, gae_lambda=0.95, policy_kwargs={"log_std_init": -0.5}, device="cpu")
    model.learn(n_envs * n_steps)  # one collected rollout (and one untimed update)
    before = torch.get_num_threads()
    torch.set_num_threads(threads)
    try:
        t0 = time.perf_counter()
        model.train()
        return time.perf_counter() - t0
    finally:
        torch.set_num_threads(before)
        venv.close()


def run(n_envs: int, n_steps: int, repeats: int) -> list[dict]:
    times = {s: [] for s in SETTINGS}
    for r in range(repeats):
        for s in (SETTINGS if r % 2 == 0 else SETTINGS[::-1]):
            times[s].append(time_update(n_envs, n_steps, *s))
    samples = n_envs * n_steps
    base = float(np.median(times[SETTINGS[0]]))
    rows = []
    for (batch, epochs, threads), t in times.items():
        sec = float(np.median(t))
        rows.append({"batch_size": batch, "n_epochs": epochs, "threads": threads, "seconds": sec,
                     "ms_per_1k": 1000.0 * sec / samples * 1000.0, "bound": samples / sec, "vs_recipe": sec / base})
    return rows


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n-envs", type=int, default=16)
    ap.add_argument("--n-steps", type=int, default=1024)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args(argv)
    for name, value in (("--n-envs", args.n_envs), ("--n-steps", args.n_steps), ("--repeats", args.repeats)):
        if value < 1:
            ap.error(f"{name} must be a positive integer, got {value}")
    load = os.getloadavg()
    rows = run(args.n_envs, args.n_steps, args.repeats)
    print(f"PPO.train() on a rollout of {args.n_envs} envs x {args.n_steps} steps ({args.n_envs * args.n_steps} "
          f"samples), hexapod shapes, MlpPolicy; median of {args.repeats} alternating repeats")
    print(f"{os.cpu_count()} cores, load average at start {load[0]:.1f} (1 min)")
    print(f"{'batch':>6} {'epochs':>6} {'threads':>7} | {'update s':>8} {'ms/1k steps':>11} "
          f"{'update-bound steps/s':>20} {'vs recipe':>9}")
    for r in rows:
        print(f"{r['batch_size']:>6} {r['n_epochs']:>6} {r['threads']:>7} | {r['seconds']:>8.2f} "
              f"{r['ms_per_1k']:>11.1f} {r['bound']:>20,.0f} {r['vs_recipe']:>9.2f}")
    print("update-bound steps/s: env steps per second of training if the envs cost nothing; "
          "vs recipe: update time over batch 256, 10 epochs, 1 thread")


if __name__ == "__main__":
    main()

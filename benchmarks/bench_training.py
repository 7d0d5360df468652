"""Env steps per second of PPO training on sand (HexapodSand-v0) against its rigid twin (HexapodRigid-v0).

For each number of envs and each vec env kind of :func:`mjrft.train.vecenv.make_vec_env` (``subproc``:
one worker process per env, ``dummy``: the envs one after the other in the trainer, ``batched``: the
physics of all envs in one compiled call), a short stable-baselines3 ``PPO.learn`` of ``--rollouts``
rollouts on each env, measured side by side in one run: the same hyper-parameters for every case (the
``hexapod-sand`` recipe's, with ``n_steps`` 256 instead of 1024 to keep the run short; the update work
per env step is the same), ``VecNormalize`` as the recipe, one torch thread, the envs as registered
(1000-step episodes, default resolution). Repeats alternate: every repeat runs every case once, in
reversed order on odd repeats; the medians are printed.

* ``train``: env steps / wall-clock seconds of the whole ``learn`` call (rollouts and gradient updates);
* ``collect``: env steps / wall-clock seconds spent collecting rollouts (policy forward passes and env steps);
* ``sand/rigid``: the sand env's rate over the rigid twin's, same kind;
* ``vs best``: the kind's rate over the fastest kind's for that env and number of envs.

Each vec env is built once per size (untimed, with 20 warm-up steps so every process has loaded the
compiled kernels), then reused by the repeats; every ``learn`` starts from a fresh PPO (seed 0) and a
fresh ``VecNormalize``. On a shared machine absolute rates mean little; the header prints the load.

    python benchmarks/bench_training.py [--n-envs 2 4 8] [--kinds subproc dummy batched] [--repeats 3]
                                        [--rollouts 3] [--n-steps 256]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

SAND, RIGID = "mjrft/HexapodSand-v0", "mjrft/HexapodRigid-v0"
#: the hexapod-sand recipe (train/configs/hexapod-sand.yaml) except n_steps
HYPERPARAMS = {"batch_size": 256, "learning_rate": 3e-4, "gae_lambda": 0.95, "n_epochs": 10,
               "policy_kwargs": {"log_std_init": -0.5}}
WARMUP_STEPS = 20


def rollout_timer():
    """An SB3 callback summing the wall-clock time spent in ``collect_rollouts`` (``.seconds``)."""
    from stable_baselines3.common.callbacks import BaseCallback

    class RolloutTimer(BaseCallback):
        def _init_callback(self) -> None:
            self.seconds = 0.0

        def _on_rollout_start(self) -> None:
            self._t0 = time.perf_counter()

        def _on_rollout_end(self) -> None:
            self.seconds += time.perf_counter() - self._t0

        def _on_step(self) -> bool:
            return True

    return RolloutTimer()


def build(env_id: str, kind: str, n_envs: int):
    """The training vec env of ``kind``, warmed up (every env stepped ``WARMUP_STEPS`` times)."""
    from mjrft.train.vecenv import make_vec_env

    venv = make_vec_env(env_id, n_envs, seed=0, kind=kind)
    venv.reset()
    rng = np.random.default_rng(0)
    low, high = venv.action_space.low, venv.action_space.high
    for _ in range(WARMUP_STEPS):
        venv.step(rng.uniform(low, high, size=(n_envs, *low.shape)).astype(np.float32))
    return venv


def learn_rate(venv, n_steps: int, rollouts: int) -> tuple[float, float]:
    """(train, collect) env steps/s of a fresh PPO learning ``rollouts`` rollouts of ``n_steps`` per env."""
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import VecNormalize

    env = VecNormalize(venv, gamma=0.99)
    model = PPO("MlpPolicy", env, n_steps=n_steps, seed=0, device="cpu", verbose=0, **HYPERPARAMS)
    timer = rollout_timer()
    total = rollouts * n_steps * venv.num_envs
    t0 = time.perf_counter()
    model.learn(total_timesteps=total, callback=timer)
    wall = time.perf_counter() - t0
    return model.num_timesteps / wall, model.num_timesteps / timer.seconds


def measure(n_envs: int, kinds, repeats: int, n_steps: int, rollouts: int) -> dict:
    cases = [(kind, env_id) for kind in kinds for env_id in (SAND, RIGID)]
    venvs = {case: build(case[1], case[0], n_envs) for case in cases}
    rates = {case: [] for case in cases}
    try:
        for r in range(repeats):
            for case in (cases if r % 2 == 0 else cases[::-1]):
                rates[case].append(learn_rate(venvs[case], n_steps, rollouts))
    finally:
        for venv in venvs.values():
            venv.close()
    return {case: np.median(np.array(v), axis=0) for case, v in rates.items()}


def table(n_envs: int, kinds, rates: dict) -> list[str]:
    best = {env: max(rates[(k, env)][0] for k in kinds) for env in (SAND, RIGID)}
    lines = []
    for kind in kinds:
        (ts, cs), (tr, cr) = rates[(kind, SAND)], rates[(kind, RIGID)]
        lines.append(f"{n_envs:5d} {kind:>8s} | {ts:7.0f} {tr:7.0f} {ts / tr:7.2f} | {cs:7.0f} {cr:7.0f} {cs / cr:7.2f} "
                     f"| {ts / best[SAND]:7.2f} {tr / best[RIGID]:7.2f}")
    return lines


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n-envs", type=int, nargs="+", default=[2, 4, 8])
    ap.add_argument("--kinds", nargs="+", default=["subproc", "dummy", "batched"])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--rollouts", type=int, default=3, help="PPO rollouts per measurement")
    ap.add_argument("--n-steps", type=int, default=256, help="PPO n_steps (per env and rollout)")
    args = ap.parse_args()
    from mjrft.train.vecenv import KINDS, check_kind

    for kind in args.kinds:
        if check_kind(kind) == "auto":
            raise SystemExit(f"--kinds takes concrete kinds, not auto: {', '.join(KINDS[1:])}")
    import numba
    import torch

    torch.set_num_threads(1)
    start = time.perf_counter()
    print(f"PPO training throughput, {SAND} against {RIGID}: {args.rollouts} rollouts of {args.n_steps} steps "
          f"per env, batch 256, 10 epochs, VecNormalize, 1 torch thread; median of {args.repeats} alternating "
          f"repeats")
    print(f"{os.cpu_count()} cores, numba threads {numba.get_num_threads()}, load average at start "
          f"{os.getloadavg()[0]:.1f} (1 min) {os.getloadavg()[1]:.1f} (5 min)")
    print(f"{'':14s} | {'train env steps/s':^23s} | {'collect env steps/s':^23s} | {'train vs best':^15s}")
    print(f"{'envs':>5s} {'kind':>8s} | {'sand':>7s} {'rigid':>7s} {'s/r':>7s} | {'sand':>7s} {'rigid':>7s} "
          f"{'s/r':>7s} | {'sand':>7s} {'rigid':>7s}", flush=True)
    for n in args.n_envs:
        for line in table(n, args.kinds, measure(n, args.kinds, args.repeats, args.n_steps, args.rollouts)):
            print(line, flush=True)
    print(f"s/r: sand rate / rigid rate (same kind); vs best: the kind's train rate / the fastest kind's (same env "
          f"and envs).\nload average at end {os.getloadavg()[0]:.1f} (1 min); wall time "
          f"{time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()

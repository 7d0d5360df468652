"""Env steps per second of the batched vector env against SyncVectorEnv (sand) and bare rigid-ground envs.

For 1, 8 and 64 hexapods (``mjrft/HexapodSand-v0``, 10 physics steps of 1 ms per env step, all hips
driven forward at half speed so the legs dig through the poppy seeds), measured side by side in one
run (interleaved repeats, median):

* ``batched``: :class:`mjrft.envs.vector.GranularVectorEnv`, all sub-environments' physics in one
  compiled call, on numba's threads (``threads``) and on one thread (``1 thread``);
* ``sync``: gymnasium's ``SyncVectorEnv`` over the SAME sub-environment objects, each wrapped as
  ``gymnasium.make`` wraps it (``TimeLimit``, ``OrderEnforcing``): one ``terrain.step`` per env;
* ``bare``: ``gymnasium.make_vec("mjrft/HexapodRigid-v0", vectorization_mode="sync")``, the same robot
  on a rigid floor (MuJoCo contacts, no granular terrain);
* ``physics``: the granular physics alone, ``BatchedTerrain.step`` against a loop of ``terrain.step``.

Prints env steps/s and the ratios, by wall clock and (for the single-threaded cases) by CPU time,
which a busy shared machine disturbs less; absolute numbers on a shared 2-core machine mean little.

    python benchmarks/bench_vector.py [--sizes 1 8 64] [--repeats 3] [--work 240] [--steps 10]
"""

from __future__ import annotations

import argparse
import math
import os
import time

import gymnasium
import numba
import numpy as np
from gymnasium.wrappers import OrderEnforcing, TimeLimit

import mjrft.envs
from mjrft.coupler import STABILITY_CHECK_EVERY
from mjrft.envs import make_vector

SAND, RIGID = "mjrft/HexapodSand-v0", "mjrft/HexapodRigid-v0"


def steps_per_second(envs, chunks: int, n_steps: int) -> tuple[float, float]:
    """``chunks`` x (reset, ``n_steps`` timed steps): every case times the same first steps of an episode.

    Returns env steps per second of wall-clock time and of this process's CPU time (all threads).
    """
    action = np.full(envs.action_space.shape, 0.5, dtype=np.float32)
    wall = cpu = 0.0
    for c in range(chunks):
        envs.reset(seed=c)
        t0, c0 = time.perf_counter(), time.process_time()
        for _ in range(n_steps):
            envs.step(action)
        wall += time.perf_counter() - t0
        cpu += time.process_time() - c0
    n = envs.num_envs * n_steps * chunks
    return n / wall, n / max(cpu, 1e-9)


class Physics:
    """The physics alone of a GranularVectorEnv's sub-environments (controls held at the reset pose):
    one ``BatchedTerrain.step`` (``batched=True``) or one ``terrain.step`` per environment."""

    def __init__(self, envs, batched: bool):
        self.envs, self.batched = envs, batched
        self.num_envs = envs.num_envs
        self.action_space = envs.action_space

    def reset(self, seed):
        self.envs.reset(seed=seed)

    def step(self, action):
        fs = self.envs.frame_skip
        if self.batched:
            self.envs.batch.step(fs)
        else:
            for env in self.envs.envs:
                env.terrain.step(env.data, fs)


def measure(n_envs: int, repeats: int, work: int, n_steps: int, frame_skip: int) -> dict:
    ours = make_vector(SAND, n_envs, frame_skip=frame_skip)
    sync = gymnasium.vector.SyncVectorEnv(
        [lambda e=e: OrderEnforcing(TimeLimit(e, mjrft.envs.MAX_EPISODE_STEPS)) for e in ours.envs])
    bare = gymnasium.make_vec(RIGID, num_envs=n_envs, vectorization_mode="sync", frame_skip=frame_skip)
    cases = {"sync": sync, "bare": bare, "1 thread": ours, "physics loop": Physics(ours, False),
             "physics batched": Physics(ours, True)}
    if n_envs > 1 and numba.get_num_threads() > 1:
        cases["threads"] = ours
    chunks = max(1, round(work / (n_envs * n_steps)))
    rates = {k: [] for k in cases}
    for r in range(repeats + 1):  # the first round warms up (compiled code, caches) and is dropped
        for label, envs in cases.items():
            if envs is ours:
                ours.batch.parallel = label == "threads"
            rate = steps_per_second(envs, chunks if r else 1, n_steps)
            if r:
                rates[label].append(rate)
    ours.close()
    sync.close()
    bare.close()
    return {k: np.median(np.array(v), axis=0) for k, v in rates.items()}  # (wall rate, cpu rate)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[1, 8, 64])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--work", type=int, default=240, help="env steps per measurement (at least one chunk)")
    ap.add_argument("--steps", type=int, default=10,
                    help="env steps after each reset (rounded up to whole stability-check periods)")
    ap.add_argument("--frame-skip", type=int, default=10, help="1 ms physics steps per env step")
    args = ap.parse_args()
    # every measurement runs a multiple of STABILITY_CHECK_EVERY physics steps per env, so each case pays the
    # terrain's periodic stability check equally often (the cases share the sub-environment objects)
    q = STABILITY_CHECK_EVERY // math.gcd(STABILITY_CHECK_EVERY, args.frame_skip)
    args.steps = -(-args.steps // q) * q
    print(f"HexapodSand-v0, frame_skip {args.frame_skip} (1 ms physics steps per env step), first {args.steps} "
          f"steps after reset, median of {args.repeats}; numba threads: {numba.get_num_threads()}, "
          f"load average at start: {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    print(f"{'':5s} {'env steps/s (wall clock)':^39s} | {'ratios (wall clock)':^29s} | {'CPU time ratios':^19s}")
    print(f"{'envs':>5s} {'batched':>9s} {'batched':>9s} {'sync':>9s} {'bare':>9s} | {'batched/':>9s} "
          f"{'batched/':>9s} {'threads/':>9s} | {'batched/':>9s} {'physics':>9s}")
    print(f"{'':5s} {'threads':>9s} {'1 thread':>9s} {'sand':>9s} {'rigid':>9s} | {'sync':>9s} {'bare':>9s} "
          f"{'1 thread':>9s} | {'sync':>9s} {'b./loop':>9s}")
    for n in args.sizes:
        r = measure(n, args.repeats, args.work, args.steps, args.frame_skip)
        one = r["1 thread"][0]
        best = max(one, r["threads"][0]) if "threads" in r else one
        thr = f"{r['threads'][0]:9.0f}" if "threads" in r else f"{'-':>9s}"
        gain = f"{r['threads'][0] / one:9.2f}" if "threads" in r else f"{'-':>9s}"
        print(f"{n:5d} {thr} {one:9.0f} {r['sync'][0]:9.0f} {r['bare'][0]:9.0f} | {best / r['sync'][0]:9.2f} "
              f"{best / r['bare'][0]:9.2f} {gain} | {r['1 thread'][1] / r['sync'][1]:9.2f} "
              f"{r['physics batched'][1] / r['physics loop'][1]:9.2f}", flush=True)
    print("batched/sync and batched/bare (wall clock) use the faster batched mode of the row. CPU-time ratios\n"
          "(this process's CPU time, robust on a busy machine): the one-thread batched env against SyncVectorEnv,\n"
          "and the physics alone: one BatchedTerrain.step against one terrain.step per env (controls held)")


if __name__ == "__main__":
    main()

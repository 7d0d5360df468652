"""One policy, closed loop, on the CPU env and on the MJX env from the same states: do the two backends simulate the
same physics?

A deterministic policy of an MJX run folder (``mjrft train-mjx``) walks ``--episodes`` episodes of ``--seconds`` on
``mjrft/HexapodSand-v0`` (MuJoCo's C library, the numba kernel) and on ``HexapodSand`` of ``mjrft.mjx.envs`` (MJX,
``mjrft.mjx.Sand``),
each episode from the same initial state (the MJX env's reset for seed k, put into the CPU env), in float64 and with
the policy network in float32 on both. Two MJX variants: ``mjrft`` (``mjrft.mjx.Sand.step``, whose integrator stage
follows MuJoCo's rule for clamped servos, ``mjrft.mjx.integrator``) and ``mjx own`` (the control: MJX's
``mjx.implicit`` as it is, which keeps a clamped servo's velocity gain in the implicitfast derivative). Per episode:
the torso's x travel, the speed and the cost of transport (``mjrft eval``'s definitions), and the largest
difference of qpos from the CPU env over the episode.

    python benchmarks/mjx_backends.py [--policy benchmarks/results/learning/mjx-cpu] [--episodes 3] [--seconds 10]
"""

from __future__ import annotations

import argparse
import os
import sys
import warnings
from pathlib import Path

import jax

jax.config.update("jax_enable_x64", True)

import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402
from mujoco import mjx  # noqa: E402

import mjrft.envs  # noqa: E402,F401  (registers the ids)
import mjrft.mjx.terrain as sand_terrain  # noqa: E402
import mjrft.mjx.envs as envs  # noqa: E402
from mjrft.train.mjx_ppo import load_policy  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"


def mjx_rollout(policy, integrate, seeds, steps):
    """(qpos per step (episodes, steps, nq), energy (episodes,)) of the policy on the MJX env with ``integrate`` as
    the integrator stage of ``Sand.step``."""
    saved = sand_terrain.integrate
    sand_terrain.integrate = integrate
    try:
        env = envs.load("HexapodSand")
        act = policy.jax_fn()
        key = jax.random.PRNGKey(0)

        def run(rng):
            def body(state, _):
                action, _ = act(state.obs.astype(jnp.float32), key)
                state = env.step(state, action.astype(state.obs.dtype))
                return state, (state.data.qpos, state.metrics["power"] * env.dt)

            _, (qpos, energy) = jax.lax.scan(body, env.reset(rng), None, length=steps)
            return qpos, energy.sum()

        qpos, energy = jax.jit(jax.vmap(run))(jnp.stack([jax.random.PRNGKey(s) for s in seeds]))
        return np.asarray(qpos), np.asarray(energy), env
    finally:
        sand_terrain.integrate = saved


def cpu_rollout(policy, env, seed, steps):
    """(initial torso x, qpos per step (steps, nq), energy) of the policy on the CPU env from the MJX env's reset
    for ``seed`` (fewer steps if the episode ends)."""
    cpu = env.gym_env(jax.jit(env.reset)(jax.random.PRNGKey(seed)))
    u = cpu.unwrapped
    obs = u.task.observation(np, u.data, u.target)
    x_start = float(u.data.qpos[0])
    qpos, energy = [], 0.0
    for _ in range(steps):
        obs, _, terminated, truncated, info = cpu.step(policy(obs))
        energy += info["power"] * u.dt
        qpos.append(u.data.qpos.copy())
        if terminated:
            break
    cpu.close()
    return x_start, np.array(qpos), energy


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--policy", default=str(RESULTS / "learning" / "mjx-cpu"), help="an MJX run folder")
    ap.add_argument("--episodes", type=int, default=3)
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--out", default=str(RESULTS / "mjx_backends.txt"))
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")  # validity-range warnings of the walk
    policy = load_policy(args.policy)
    seeds = list(range(args.episodes))
    lines = [f"python benchmarks/mjx_backends.py --episodes {args.episodes} --seconds {args.seconds:g}",
             f"policy {os.path.relpath(args.policy, RESULTS.parent.parent)}; float64 physics on both backends, the policy network in float32; per episode the "
             "same initial state (the MJX env's reset for seed k)", ""]
    variants = {"mjrft": sand_terrain.integrate, "mjx own": lambda m, d: mjx.implicit(m, d) if
                m.opt.integrator == mjx.IntegratorType.IMPLICITFAST else mjx.euler(m, d)}
    steps = int(round(args.seconds / 0.01))  # the env's 10 ms control step (checked below)
    runs = {}
    for name, integrate in variants.items():
        qpos, energy, env = mjx_rollout(policy, integrate, seeds, steps)
        runs[name] = (qpos, energy)
    if abs(env.dt - 0.01) > 1e-12:
        raise SystemExit(f"the env's control step is {env.dt} s, not 10 ms")
    weight = env.task.weight
    lines.append(f"{'episode':>7s} {'backend':>8s} {'x travel m':>10s} {'speed m/s':>9s} {'CoT':>6s} "
                 f"{'max |qpos - cpu|':>16s}")
    for k, seed in enumerate(seeds):
        x_start, q_cpu, e_cpu = cpu_rollout(policy, env, seed, steps)
        n = len(q_cpu)
        rows = [("cpu", q_cpu, e_cpu, 0.0)]
        for name, (qpos, energy) in runs.items():
            rows.append((name, qpos[k, :n], energy[k], float(np.abs(qpos[k, :n] - q_cpu).max())))
        t = n * env.dt
        for name, q, e, gap in rows:
            dx = float(q[-1, 0] - x_start)
            lines.append(f"{seed:7d} {name:>8s} {dx:10.4f} {dx / t:9.4f} {e / (weight * max(abs(dx), 1e-3 * t)):6.3f} "
                         f"{gap:16.2e}")
    text = "\n".join(lines) + "\n"
    print(text, end="")
    Path(args.out).write_text(text)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""The Go2 joystick task (``Go2JoystickRigid`` / ``Go2JoystickSand``, :mod:`mjrft.envs.mjx.go2_joystick`): its sand
step, and what the grains cost per step against rigid ground.

* ``step``: the choice of the sand task's physics step. The task's robot and terrain (``Go2JoystickSand``: every
  collision primitive in ``poppy_cp``, the floor's contacts removed) stepped with the terrain's own
  ``Sand.step`` on the task's device model, in float32, from the home keyframe with the servos holding the home pose
  (the task at a zero action) for 1.5 s, then (``trot``) 0.5 s of standing and 2.5 s of a trot around the home pose
  (the diagonal pairs in antiphase at 1.5 Hz, thighs +-0.3 rad, knees flexed by up to 0.8 rad in swing: the gait of
  ``benchmarks/bench_go2.py``). For the implicit granular step at the Go2 model's own 2 ms and at 4 ms (MuJoCo
  Playground's Go1 step), and the explicit step at 2 ms: the net vertical granular force over the weight at every
  physics step of the last 0.2 s of standing (mean, min, max) and the RMS of its change from one step to the next
  (chatter), the trunk's height, the trot's distance and force range, and whether a world was flagged.
* ``cost``: control steps of the two registered tasks (``mjrft.mjx.envs.load``), ``jax.vmap`` over ``--worlds``
  worlds, ``--steps`` control steps per call in a ``jax.lax.scan`` with random actions (uniform in [-1, 1]), on the
  host's JAX backend, float32: physics steps/s (worlds x control steps x physics steps per control step / wall
  time), the two tasks interleaved, median of ``--repeats`` after a warm-up call.

    OPENBLAS_NUM_THREADS=1 python benchmarks/go2_joystick.py [--worlds 1 16] [--steps 10] [--repeats 3]
        [--out benchmarks/results/go2_joystick.txt]

On CPU JAX run it with ``OPENBLAS_NUM_THREADS=1``: the implicit step's triangular solve (MJX's ``solve_m``, 6 columns
per body with elements, 78 for the Go2) runs in jaxlib's LAPACK kernels on scipy's OpenBLAS, which spreads a solve
with 64 or more columns over threads, which on a 2-core machine shared with other jobs wait milliseconds for their
turn (docs/gpu.md, "A quadruped on sand").
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

from mjrft.mjx import envs

RESULTS = Path(__file__).resolve().parent / "results"
STAND, SETTLE, TROT, LAST = 1.5, 0.5, 2.5, 0.2  # s
VARIANTS = {"implicit 2 ms": (0.002, True), "implicit 4 ms": (0.004, True), "explicit 2 ms": (0.002, False)}


def trot_targets(home, t):
    """Servo targets of the trot around the home pose at time ``t`` after its start (actuators FL, FR, RL, RR)."""
    phase = 2 * jnp.pi * 1.5 * t + jnp.array([0.0, jnp.pi, jnp.pi, 0.0])  # FL+RR and FR+RL in antiphase
    c = home.reshape(4, 3)
    c = c.at[:, 1].add(0.3 * jnp.cos(phase)).at[:, 2].add(-0.8 * jnp.maximum(jnp.sin(phase), 0.0))
    return c.ravel()


def run_step(sim_dt: float, implicit: bool, trot: bool) -> dict:
    env = envs.load("Go2JoystickSand", config_overrides={"sim_dt": sim_dt, "sand.implicit": implicit})
    sand, mx, m = env.sand, env.mjx_model, env.mj_model
    home = m.keyframe("home")
    q0, c0 = jnp.asarray(home.qpos), jnp.asarray(home.ctrl)
    stand_steps = int(round((SETTLE if trot else STAND) / sim_dt))
    n = stand_steps + (int(round(TROT / sim_dt)) if trot else 0)
    weight = float(m.body_subtreemass[0]) * 9.81
    from mujoco import mjx

    def body(carry, i):
        d, s = carry
        t = i * sim_dt
        d = d.replace(ctrl=jnp.where(i < stand_steps, c0, trot_targets(c0, t - stand_steps * sim_dt)))
        d, s = sand.step(mx, d, s)
        return (d, s), jnp.sum(s.wrench[:, 2]) / weight

    d = mjx.make_data(mx).replace(qpos=q0, ctrl=c0)
    run = jax.jit(lambda d, s: jax.lax.scan(body, (d, s), jnp.arange(n)))
    (d, s), load = run(d, sand.init())
    load = np.asarray(load)
    out = {"z": float(d.qpos[2]), "x": float(d.qpos[0]), "bad": int(s.bad_body),
           "finite": bool(np.all(np.isfinite(np.asarray(d.qpos))))}
    if trot:
        walk = load[stand_steps:]
        out.update(lo=float(walk.min()), hi=float(walk.max()))
    else:
        last = load[-int(round(LAST / sim_dt)):]
        out.update(mean=float(last.mean()), lo=float(last.min()), hi=float(last.max()),
                   chatter=float(np.sqrt(np.mean(np.diff(last) ** 2))))
    return out


def make_rollout(name: str, worlds: int, steps: int):
    env = envs.load(name)
    keys = jax.random.split(jax.random.PRNGKey(0), worlds)
    state = jax.jit(jax.vmap(env.reset))(keys)
    actions = jax.random.uniform(jax.random.PRNGKey(1), (steps, worlds, env.action_size), minval=-1.0, maxval=1.0)
    step = jax.vmap(env.step)
    run = jax.jit(lambda s: jax.lax.scan(lambda s, a: (step(s, a), None), s, actions)[0])
    return env, state, run


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--worlds", type=int, nargs="+", default=[1, 16])
    p.add_argument("--steps", type=int, default=10)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--out", type=Path, default=RESULTS / "go2_joystick.txt")
    args = p.parse_args()
    threads = os.environ.get("OPENBLAS_NUM_THREADS")
    lines = [("" if threads is None else f"# OPENBLAS_NUM_THREADS={threads}\n")
             + f"# python benchmarks/go2_joystick.py --worlds {' '.join(map(str, args.worlds))} --steps {args.steps} "
             f"--repeats {args.repeats}", f"# JAX {jax.__version__} on {jax.devices()[0]} (float32)", "",
             "step: Go2JoystickSand's robot and terrain (poppy_cp), home pose held 1.5 s; then 0.5 s + 2.5 s trot",
             f"{'variant':<15} {'Fz/W mean':>10} {'min':>8} {'max':>8} {'chatter':>9} {'trunk z mm':>10} "
             f"{'flag':>5} | {'trot x m':>8} {'Fz/W min':>8} {'max':>6} {'flag':>5}"]
    for label, (dt, implicit) in VARIANTS.items():
        st, tr = run_step(dt, implicit, False), run_step(dt, implicit, True)
        lines.append(f"{label:<15} {st['mean']:>10.5f} {st['lo']:>8.5f} {st['hi']:>8.5f} {st['chatter']:>9.2e} "
                     f"{1000 * st['z']:>10.1f} {st['bad']:>5d} | {tr['x']:>8.3f} {tr['lo']:>8.3f} {tr['hi']:>6.3f} "
                     f"{tr['bad']:>5d}")
        print(lines[-1], flush=True)
    lines += ["", f"cost: physics steps/s, random actions, {args.steps} control steps per call, median of "
                  f"{args.repeats} (interleaved)",
              f"{'worlds':>6} {'rigid':>10} {'sand':>10} {'sand/rigid':>10}"]
    for worlds in args.worlds:
        runs = {name: make_rollout(name, worlds, args.steps) for name in ("Go2JoystickRigid", "Go2JoystickSand")}
        times = {name: [] for name in runs}
        for name, (_, state, run) in runs.items():  # warm-up: compile
            jax.block_until_ready(run(state))
        for _ in range(args.repeats):
            for name, (_, state, run) in runs.items():
                t0 = time.perf_counter()
                jax.block_until_ready(run(state))
                times[name].append(time.perf_counter() - t0)
        rate = {name: worlds * args.steps * env.n_substeps / statistics.median(times[name])
                for name, (env, _, _) in runs.items()}
        lines.append(f"{worlds:>6d} {rate['Go2JoystickRigid']:>10,.0f} {rate['Go2JoystickSand']:>10,.0f} "
                     f"{rate['Go2JoystickSand'] / rate['Go2JoystickRigid']:>10.2f}")
        print(lines[-1], flush=True)
    args.out.write_text("\n".join(lines) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()

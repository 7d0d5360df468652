"""Environment steps per second on sand against the same robot on rigid ground, side by side in one run.

For each robot (hexapod, biped, humanoid) the ``...Sand-v0`` and ``...Rigid-v0`` environments are made
with their default settings (default element resolution, ``frame_skip``), driven by the same action
sequence, and timed in interleaved repeats (sand, rigid, sand, rigid, ...; median of the repeats).
Only ``env.step`` is timed (resets after a fall are not). Prints steps/s and the ratio sand/rigid;
the target is sand >= 0.5 x rigid for the hexapod. Then, for the hexapod, where one ``env.step``
spends its time (see :func:`breakdown`): MuJoCo's own physics, the granular kernel, the terrain's
stability check and the environment's Python work, on sand and on rigid ground.

    python benchmarks/bench_envs.py [--steps N] [--repeats R] [--robots hexapod biped humanoid]
                                    [--resolutions 0.01 0.02]
"""

from __future__ import annotations

import argparse
import time

import gymnasium
import mujoco
import numpy as np

import mjrft.envs  # noqa: F401  (registers the environments)

ROBOTS = {"hexapod": "Hexapod", "biped": "Biped", "humanoid": "Humanoid"}


def actions(env, n, seed=0):
    """A fixed action sequence: the hexapod's alternating tripod at 2 Hz, small random targets otherwise."""
    shape = env.action_space.shape
    rng = np.random.default_rng(seed)
    if shape == (6,) and "Hexapod" in env.spec.id:
        return np.full((n, 6), 2 * 2 * np.pi / (6 * np.pi), dtype=np.float32)  # 2 Hz on every hip
    return (0.3 * rng.uniform(-1, 1, size=(n, *shape))).astype(np.float32)


def timed_steps(env, acts) -> float:
    """Seconds spent in env.step over ``acts`` (resets after termination are not timed)."""
    env.reset(seed=0)
    total = 0.0
    for a in acts:
        t0 = time.perf_counter()
        _, _, term, trunc, _ = env.step(a)
        total += time.perf_counter() - t0
        if term or trunc:
            env.reset()
    return total


def breakdown(sand_env, rigid_env, acts) -> dict:
    """Where a sand env.step spends its time, measured inside real steps of the same action sequence.

    ``terrain.step`` and the terrain's stability check are wrapped with timers; before each
    ``terrain.step`` the state is copied to a scratch MjData and stepped with plain ``mj_step`` (same
    model, same state, no granular force) to time the bare physics. The rigid env is timed likewise
    (``_advance``, its ``mj_step`` call, inside its env.step).
    """
    env = sand_env.unwrapped
    terrain = env.terrain
    scratch = mujoco.MjData(env.model)
    acc = {"terrain_step": 0.0, "stability": 0.0, "bare": 0.0, "probe": 0.0}
    watch = terrain._stability  # the terrain's stability checks (mjrft.watch.StabilityWatch)
    step, check = terrain.step, watch.check_springs

    def timed_terrain_step(data, n=1):
        t_probe = time.perf_counter()
        mujoco.mj_copyData(scratch, env.model, data)
        t0 = time.perf_counter()
        mujoco.mj_step(env.model, scratch, nstep=n)
        acc["bare"] += time.perf_counter() - t0
        acc["probe"] += time.perf_counter() - t_probe
        t0 = time.perf_counter()
        step(data, n)
        acc["terrain_step"] += time.perf_counter() - t0

    def timed_check(*a, **k):
        t0 = time.perf_counter()
        check(*a, **k)
        acc["stability"] += time.perf_counter() - t0

    terrain.step, watch.check_springs = timed_terrain_step, timed_check
    try:
        whole = timed_steps(sand_env, acts)
        whole -= acc["probe"]  # the scratch copies and steps are not part of the env's work
    finally:
        del terrain.step, watch.check_springs
    env_r = rigid_env.unwrapped
    rigid_acc = [0.0]
    orig = env_r._advance

    def timed_advance(n):
        t0 = time.perf_counter()
        orig(n)
        rigid_acc[0] += time.perf_counter() - t0

    env_r._advance = timed_advance
    try:
        rigid_whole = timed_steps(rigid_env, acts)
    finally:
        del env_r._advance
    n = len(acts)
    return {"whole": whole / n, "terrain_step": acc["terrain_step"] / n, "stability": acc["stability"] / n,
            "bare": acc["bare"] / n, "rigid_whole": rigid_whole / n, "rigid_physics": rigid_acc[0] / n,
            "elements": terrain.n_elements, "frame_skip": env.frame_skip}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=400, help="env steps per timed run")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--robots", nargs="+", default=list(ROBOTS), choices=list(ROBOTS))
    ap.add_argument("--resolutions", nargs="*", type=float, default=[],
                    help="extra element sizes (m) for the hexapod on sand, timed in the same interleaving")
    args = ap.parse_args()

    envs = {}
    for r in args.robots:
        for kind in ("Sand", "Rigid"):
            envs[(r, kind)] = gymnasium.make(f"mjrft/{ROBOTS[r]}{kind}-v0", disable_env_checker=True)
    if "hexapod" in args.robots:
        for res in args.resolutions:
            envs[("hexapod", f"Sand {res * 1000:g} mm")] = gymnasium.make(
                "mjrft/HexapodSand-v0", disable_env_checker=True, resolution=res)
    acts = {r: actions(envs[(r, "Sand")], args.steps) for r in args.robots}
    for key, env in envs.items():  # warm-up: compiled kernels, caches
        timed_steps(env, acts[key[0]][:50])
    times = {key: [] for key in envs}
    for _ in range(args.repeats):
        for key, env in envs.items():
            times[key].append(timed_steps(env, acts[key[0]]))

    print(f"env steps/s, {args.steps} steps x {args.repeats} interleaved repeats (median), default settings")
    print(f"{'robot':10s} {'elements':>8s} {'sand':>10s} {'rigid':>10s} {'sand/rigid':>11s}")
    for r in args.robots:
        sand = args.steps / np.median(times[(r, "Sand")])
        rigid = args.steps / np.median(times[(r, "Rigid")])
        n_el = envs[(r, "Sand")].unwrapped.terrain.n_elements
        print(f"{r:10s} {n_el:8d} {sand:10.0f} {rigid:10.0f} {sand / rigid:11.2f}")
        for key in envs:
            if key[0] == r and key[1] not in ("Sand", "Rigid"):
                sand = args.steps / np.median(times[key])
                n_el = envs[key].unwrapped.terrain.n_elements
                print(f"{'  ' + key[1][5:]:10s} {n_el:8d} {sand:10.0f} {rigid:10.0f} {sand / rigid:11.2f}")

    if "hexapod" in args.robots:
        b = breakdown(envs[("hexapod", "Sand")], envs[("hexapod", "Rigid")], acts["hexapod"])
        w = b["whole"]
        kernel = b["terrain_step"] - b["stability"] - b["bare"]
        print(f"\nhexapod, time per env.step ({b['frame_skip']} physics steps; sand: {b['elements']} elements), ms:")
        print(f"{'':44s} {'sand':>7s} {'rigid':>7s}")
        print(f"{'whole env.step':44s} {w * 1e3:7.3f} {b['rigid_whole'] * 1e3:7.3f}")
        print(f"{'  MuJoCo physics (same model, no terrain)':44s} {b['bare'] * 1e3:7.3f} {b['rigid_physics'] * 1e3:7.3f}")
        print(f"{'  granular kernel (terrain.step - physics)':44s} {kernel * 1e3:7.3f} {'':>7s}")
        print(f"{'  terrain stability check':44s} {b['stability'] * 1e3:7.3f} {'':>7s}")
        print(f"{'  the rest: env Python, wrappers (residual)':44s} {(w - b['terrain_step']) * 1e3:7.3f} "
              f"{(b['rigid_whole'] - b['rigid_physics']) * 1e3:7.3f}")
    for env in envs.values():
        env.close()


if __name__ == "__main__":
    main()

"""Each mjrft environment under each speed/accuracy preset: its error and its cost; writes
benchmarks/results/env_presets.txt.

For every robot (hexapod, biped, humanoid) the sand env and its rigid twin run under ``preset="fast"``,
``"default"`` and ``"accurate"`` (:mod:`mjrft.tools.presets`: the element size, the law and the robot's own physics
step per preset) the controllers of ``benchmarks/env_timestep.py`` (the papers' open-loop gaits and the shipped
hexapod policy), ``--seconds`` of simulated time each from the same seeded reset.

* Error: the torso's mean forward speed and the feet's mean sinkage (:func:`mjrft.train.evaluate.evaluate`) against a
  reference fine in space and time: 1/4 of the model's element size (the trade study's reference scale), the explicit
  granular step at 0.05 ms (``--ref-dt``); on the rigid floor the same step. Each preset's worst over the controllers,
  and per controller. A speed under 1 cm/s is compared in absolute terms, as in env_timestep.
* Stability: :class:`mjrft.TerrainStabilityWarning` raised under the controllers and under ``--seconds`` of the
  initial PPO policy's random actions; falls the reference does not have.
* Cost: ``env.step`` time of the sand env under the preset against its rigid twin at its default settings, driven by
  the same action sequence (``benchmarks/bench_envs.py``'s: the hexapod's 2 Hz tripod, small random targets
  otherwise), in interleaved repeats (sand, rigid, sand, ...), the ratio of the medians, side by side in one run.

    python benchmarks/env_presets.py [--seconds 6] [--robots hexapod biped humanoid] [--steps 300] [--repeats 5]
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import os
import sys
import time
import warnings

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
PRESET_NAMES = ("fast", "default", "accurate")
#: the reference's element size as a multiple of the model's own (the trade study's finest scale)
REFERENCE_SCALE = 0.25


def _load(name: str):
    """A sibling benchmark script as a module (its runners and controllers are this study's too)."""
    spec = importlib.util.spec_from_file_location(name, os.path.join(HERE, f"{name}.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


STEP = _load("env_timestep")
BENCH = _load("bench_envs")


def episode(env_id: str, policy, seconds: float, kwargs: dict) -> dict:
    """One seeded episode of ``policy``: the evaluation's summary plus the stability warnings raised."""
    from mjrft import TerrainStabilityWarning
    from mjrft.train.evaluate import evaluate

    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always", TerrainStabilityWarning)
        if policy == "random":
            policy = STEP.RandomActions(STEP.action_size(env_id))
        rows, _ = evaluate(policy, env_id, episodes=1, seed=0, env_kwargs=dict(kwargs, episode_seconds=seconds))
    row = rows[0]
    return {"speed": row["speed"], "sink": row["sink_mean_mm"], "fell": bool(row["fell"]),
            "diverged": bool(row.get("diverged")),
            "unstable": sum(issubclass(w.category, TerrainStabilityWarning) for w in rec)}


def describe(env_id: str, kwargs: dict) -> str:
    """The physics step, coupling and element size an env takes with ``kwargs``."""
    import gymnasium

    env = gymnasium.make(env_id, **kwargs)
    try:
        u = env.unwrapped
        step = f"{u.model.opt.timestep * 1e3:g} ms x {u.frame_skip}"
        if u.terrain is None:
            return f"rigid {step}"
        return (f"{'implicit' if u.terrain.implicit else 'explicit'} {step}, elements "
                f"{u.terrain.resolution * 1e3:g} mm ({u.terrain.n_elements:,})")
    finally:
        env.close()


def own_resolution(env_id: str, extra: dict) -> float:
    import gymnasium

    env = gymnasium.make(env_id, **extra)
    try:
        return float(env.unwrapped.terrain.resolution)
    finally:
        env.close()


def accuracy(env_id: str, sand: bool, policies, seconds: float, ref_dt: float, slow: float, extra: dict, out) -> dict:
    """Each preset's errors against the fine reference; returns {preset: worst errors}."""
    ref_kw = dict(extra, timestep=ref_dt, frame_skip=int(round(STEP.CONTROL_PERIOD / ref_dt)))
    if sand:
        ref_kw.update(implicit=False, resolution=REFERENCE_SCALE * own_resolution(env_id, extra))
    refs = {p: episode(env_id, p, seconds, ref_kw) for p in policies}
    print(f"\n{env_id}{''.join(f' {k}={v}' for k, v in extra.items())}: {seconds:g} s of each controller; "
          f"reference: {describe(env_id, ref_kw)}", file=out)
    for p, r in refs.items():
        print(f"  reference {p:28s} speed {100 * r['speed']:7.2f} cm/s  sinkage {r['sink']:6.2f} mm  "
              f"fell {'yes' if r['fell'] else 'no'}", file=out)
    print(f"  {'preset':9s} {'speed err':>9s} {'sink err':>9s}  {'warn':>4s} {'fell':>4s}  step, coupling, elements; "
          f"speed / sinkage errors (%) per controller", file=out)
    worst_of = {}
    for name in PRESET_NAMES:
        kw = dict(extra, preset=name)
        rnd = episode(env_id, "random", seconds, kw)
        warn, diverged, fell = rnd["unstable"], rnd["diverged"], 0
        worst, each = {"speed": 0.0, "sink": 0.0}, []
        for p in policies:
            r, ref = episode(env_id, p, seconds, kw), refs[p]
            errs = {"speed": STEP.rel_error(r["speed"], ref["speed"], slow),
                    "sink": STEP.rel_error(r["sink"], ref["sink"], 1e-9) if sand else 0.0}
            each.append(f"{100 * errs['speed']:.1f}/{100 * errs['sink']:.1f}" if sand else f"{100 * errs['speed']:.1f}")
            worst = {k: max(worst[k], errs[k]) for k in worst}
            warn += r["unstable"]
            fell += int(r["fell"] and not ref["fell"])
            diverged |= r["diverged"]
        worst_of[name] = dict(worst, warn=warn, fell=fell, diverged=diverged)
        print(f"  {name:9s} {100 * worst['speed']:8.2f}% {100 * worst['sink']:8.2f}%  {warn:4d} {fell:4d}  "
              f"{'diverged; ' if diverged else ''}{describe(env_id, kw)}; {'  '.join(each)}", file=out, flush=True)
    return worst_of


def cost(sand_id: str, rigid_id: str, extra: dict, steps: int, repeats: int, out) -> dict:
    """env.step time of the sand env under each preset / its rigid twin at its defaults (ratio of the medians)."""
    import gymnasium

    envs = {name: gymnasium.make(sand_id, preset=name, **extra) for name in PRESET_NAMES}
    rigid = gymnasium.make(rigid_id, **extra)
    acts = BENCH.actions(rigid, steps)
    for env in (*envs.values(), rigid):  # warm up (numba's cache, first-call costs)
        BENCH.timed_steps(env, acts[:20])
    times = {name: [] for name in (*PRESET_NAMES, "rigid")}
    for _ in range(repeats):
        for name, env in envs.items():
            times[name].append(BENCH.timed_steps(env, acts))
            times["rigid"].append(BENCH.timed_steps(rigid, acts))
    for env in (*envs.values(), rigid):
        env.close()
    rigid_t = float(np.median(times["rigid"]))
    ratios = {name: float(np.median(times[name])) / rigid_t for name in PRESET_NAMES}
    print(f"  cost (env.step time / {rigid_id} at its defaults, {steps} steps x {repeats} interleaved repeats, "
          f"median): " + ", ".join(f"{n} {r:.2f}x" for n, r in ratios.items()), file=out, flush=True)
    return ratios


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robots", nargs="+", default=list(STEP.ROBOTS), choices=list(STEP.ROBOTS))
    ap.add_argument("--seconds", type=float, default=6.0, help="simulated seconds per run")
    ap.add_argument("--ref-dt", type=float, default=0.00005, help="reference physics step (s)")
    ap.add_argument("--slow", type=float, default=0.01, help="speeds below this (m/s) are compared in absolute terms")
    ap.add_argument("--steps", type=int, default=300, help="env steps per timed repeat")
    ap.add_argument("--repeats", type=int, default=5, help="interleaved timing repeats")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "env_presets.txt"))
    args = ap.parse_args()
    for name, val in (("seconds", args.seconds), ("ref-dt", args.ref_dt), ("slow", args.slow)):
        if not (math.isfinite(val) and val > 0):
            ap.error(f"--{name} must be finite and > 0, got {val!r}")
    for name, val in (("steps", args.steps), ("repeats", args.repeats)):
        if val < 1:
            ap.error(f"--{name} must be >= 1, got {val!r}")
    import mjrft.envs  # noqa: F401  (registers the envs)

    t0 = time.perf_counter()
    with open(args.out, "w") as f:
        out = STEP.Tee(sys.stdout, f)
        print(f"$ python benchmarks/env_presets.py {' '.join(sys.argv[1:])}".rstrip(), file=out)
        print("errors: each preset's worst over the controllers against the fine reference; warn: stability "
              "warnings under the controllers and random actions; fell: falls the reference does not have", file=out)
        summary = []
        for robot in args.robots:
            sand_id, rigid_id, policies = STEP.ROBOTS[robot]
            extra = STEP.ROBOT_KWARGS.get(robot, {})
            sand = accuracy(sand_id, True, policies, args.seconds, args.ref_dt, args.slow, extra, out)
            ratios = cost(sand_id, rigid_id, extra, args.steps, args.repeats, out)
            rigid = accuracy(rigid_id, False, tuple(p for p in policies if not p.startswith("pretrained:")),
                             args.seconds, args.ref_dt, args.slow, extra, out)
            summary.append((sand_id, sand, ratios, rigid_id, rigid))
        print("\nsummary: speed / sinkage worst error, cost x rigid twin (sand); speed worst error (rigid)", file=out)
        for sand_id, sand, ratios, rigid_id, rigid in summary:
            print(f"  {sand_id:24s} " + "   ".join(
                f"{n} {100 * sand[n]['speed']:.1f}/{100 * sand[n]['sink']:.1f} % {ratios[n]:.2f}x"
                f"{' WARN' if sand[n]['warn'] else ''}{' FELL' if sand[n]['fell'] else ''}" for n in PRESET_NAMES),
                file=out)
            print(f"  {rigid_id:24s} " + "   ".join(
                f"{n} {100 * rigid[n]['speed']:.1f} %{' FELL' if rigid[n]['fell'] else ''}" for n in PRESET_NAMES),
                file=out)
        print(f"study took {time.perf_counter() - t0:.0f} s", file=out)
        f.flush()
        os.fsync(f.fileno())


if __name__ == "__main__":
    main()

"""Each mjrft environment's physics step from a measured error budget; writes benchmarks/results/env_timestep.txt.

Every registered robot env (hexapod, biped, humanoid, on sand and on the rigid floor) runs the same controllers
(the papers' open-loop gaits of :mod:`mjrft.tools.gaits`, and the shipped hexapod policy) for ``--seconds`` of
simulated time from the same seeded reset at several physics steps, all with the env's 10 ms control period
(``frame_skip = 10 ms / dt``), with the explicit granular coupling and with the implicit one
(``implicit=True``, :mod:`mjrft.implicit_step`). The metrics are :func:`mjrft.train.evaluate.evaluate`'s: the
torso's mean forward speed, the mean sinkage of the feet in the sand and the cost of transport (the actuators'
mechanical power integrated over every physics step).

Reference: the explicit coupling at ``--ref-dt`` (default 0.05 ms); its own uncertainty is printed as the
difference between it and the explicit step at twice its size. Errors are relative to the reference; a speed under
1 cm/s (a standing robot) has no relative error and is compared in absolute terms (``--slow`` m/s).

Budget (the trade study's metrics): the gait speed and the sinkage within ``--budget`` (default 2 %) of the reference
on every controller of the env, no divergence, no fall the reference does not have, and no stability warning
(:class:`mjrft.TerrainStabilityWarning`), neither under the controllers nor under ``seconds`` of the initial PPO
policy's random actions (mean 0, s.d. 0.6, clipped: what training meets first). The
chosen step is the largest one within budget (the explicit coupling where both are, as it costs less per step);
the cost of transport's error is printed beside it but is not part of the budget (see the report's closing lines).

    python benchmarks/env_timestep.py [--seconds 6] [--robots hexapod biped humanoid] [--budget 0.02]
"""

from __future__ import annotations

import argparse
import functools
import math
import os
import sys
import time
import warnings

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))

#: robot -> (sand env id, rigid env id, controllers); a controller is a policy spec of ``mjrft eval``. The shipped
#: policy (``pretrained:``) was trained on sand and runs only there
ROBOTS = {
    "hexapod": ("mjrft/HexapodSand-v0", "mjrft/HexapodRigid-v0",
                ("tripod:f=1.0", "tripod:f=2.0", "tripod:f=3.0", "pretrained:HexapodSand-v0")),
    "biped": ("mjrft/BipedSand-v0", "mjrft/BipedRigid-v0", ("rect", "rect:angle=30")),
    "humanoid": ("mjrft/HumanoidSand-v0", "mjrft/HumanoidRigid-v0", ("shift", "stand")),
}
#: candidate steps (s), with the coupling: explicit and implicit; the control period stays 10 ms
EXPLICIT = (0.0001, 0.00025, 0.0005, 0.001, 0.002)
IMPLICIT = (0.00025, 0.0005, 0.001, 0.002)
CONTROL_PERIOD = 0.01
#: env keyword arguments of every run of a robot: the biped's gait study held the torso pitch (docs/environments.md)
ROBOT_KWARGS = {"biped": {"pitch_free": False}}
#: the stability check's random actions: the initial PPO policy's (mean 0, s.d. 0.6, clipped to [-1, 1])
RANDOM_SD = 0.6


class RandomActions:
    """Seeded random actions with stable-baselines3's ``predict``: the stability check's controller (the errors of a
    chaotic motion are not measured; only stability warnings, falls and divergence)."""

    def __init__(self, n: int, seed: int = 1):
        self.n, self.rng = n, np.random.default_rng(seed)

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        return np.clip(self.rng.normal(0.0, RANDOM_SD, self.n), -1.0, 1.0).astype(np.float32), state


@functools.lru_cache(maxsize=None)
def action_size(env_id: str) -> int:
    """The number of actions of ``env_id`` (one env made per id, not per run)."""
    import gymnasium

    env = gymnasium.make(env_id)
    try:
        return int(env.action_space.shape[0])
    finally:
        env.close()


def run(env_id: str, policy, dt: float, implicit: bool | None, seconds: float, extra: dict) -> dict:
    """One seeded episode of ``policy`` on ``env_id`` at physics step ``dt`` (``implicit`` None: a rigid env);
    the evaluation's summary plus the stability warnings raised and the wall time."""
    from mjrft import TerrainStabilityWarning
    from mjrft.train.evaluate import evaluate

    frame_skip = int(round(CONTROL_PERIOD / dt))
    kwargs = dict(extra, timestep=dt, frame_skip=frame_skip, episode_seconds=seconds)
    if implicit is not None:
        kwargs["implicit"] = implicit
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always", TerrainStabilityWarning)
        if policy == "random":
            policy = RandomActions(action_size(env_id))
        rows, summary = evaluate(policy, env_id, episodes=1, seed=0, env_kwargs=kwargs)
    row = rows[0]
    return {"speed": row["speed"], "sink": row["sink_mean_mm"], "cot": row["cot"], "seconds": row["seconds"],
            "fell": bool(row["fell"]), "diverged": bool(row.get("diverged")),
            "unstable": sum(issubclass(w.category, TerrainStabilityWarning) for w in rec),
            "wall": time.perf_counter() - t0}


def rel_error(value: float, ref: float, floor: float) -> float:
    """|value - ref| / |ref|, or |value - ref| / floor where |ref| < floor (then an absolute comparison)."""
    return abs(value - ref) / max(abs(ref), floor)


def configs(sand: bool) -> list[tuple[str, float, bool | None]]:
    if not sand:
        return [("rigid", dt, None) for dt in EXPLICIT]
    return [("explicit", dt, False) for dt in EXPLICIT] + [("implicit", dt, True) for dt in IMPLICIT]


def study(robot: str, seconds: float, ref_dt: float, budget: float, slow: float, out) -> dict:
    sand_id, rigid_id, policies = ROBOTS[robot]
    extra = ROBOT_KWARGS.get(robot, {})
    chosen = {}
    for env_id, sand in ((sand_id, True), (rigid_id, False)):
        policies = tuple(p for p in policies if sand or not p.startswith("pretrained:"))
        refs = {p: run(env_id, p, ref_dt, False if sand else None, seconds, extra) for p in policies}
        print(f"\n{env_id}{''.join(f' {k}={v}' for k, v in extra.items())}: {seconds:g} s of each controller; "
              f"reference: {'explicit ' if sand else ''}{ref_dt * 1e3:g} ms x {round(CONTROL_PERIOD / ref_dt)}", file=out)
        for p, r in refs.items():
            print(f"  reference {p:28s} speed {100 * r['speed']:7.2f} cm/s  sinkage {r['sink']:6.2f} mm  "
                  f"CoT {r['cot']:7.2f}  fell {'yes' if r['fell'] else 'no'}", file=out)
        print(f"  {'coupling':9s} {'dt ms':>6s} {'skip':>4s}  {'speed err':>9s} {'sink err':>9s} {'CoT err':>8s}"
              f"  {'warn':>4s} {'fell':>4s}  {'budget':8s}  speed / sinkage errors (%) per controller", file=out)
        passing = []
        for coupling, dt, implicit in configs(sand):
            worst = {"speed": 0.0, "sink": 0.0, "cot": 0.0}
            each, warn, fell, diverged = [], 0, 0, False
            rnd = run(env_id, "random", dt, implicit, seconds, extra)
            warn, diverged = rnd["unstable"], rnd["diverged"]
            for p in policies:
                r = run(env_id, p, dt, implicit, seconds, extra)
                ref = refs[p]
                errs = {"speed": rel_error(r["speed"], ref["speed"], slow),
                        "sink": rel_error(r["sink"], ref["sink"], 1e-9) if sand else 0.0,
                        "cot": rel_error(r["cot"], ref["cot"], 1e-9)}
                each.append(f"{100 * errs['speed']:.1f}/{100 * errs['sink']:.1f}" if sand else f"{100 * errs['speed']:.1f}")
                worst = {k: max(worst[k], errs[k]) for k in worst}
                warn += r["unstable"]
                fell += int(r["fell"] and not ref["fell"])
                diverged |= r["diverged"]
            ok = worst["speed"] <= budget and worst["sink"] <= budget and not (warn or fell or diverged)
            if ok:
                passing.append((dt, coupling))
            print(f"  {coupling:9s} {dt * 1e3:6.2f} {round(CONTROL_PERIOD / dt):4d}  {100 * worst['speed']:8.2f}% "
                  f"{100 * worst['sink']:8.2f}% {100 * worst['cot']:7.1f}%  {warn:4d} {fell:4d}  "
                  f"{'diverged' if diverged else ('within' if ok else 'over'):8s}  {'  '.join(each)}", file=out, flush=True)
        # the largest step within budget; the explicit coupling first on a tie (it costs less per step)
        best = max(passing, key=lambda c: (c[0], c[1] == "explicit" or c[1] == "rigid"), default=None)
        chosen[env_id] = best
        print(f"  chosen: {'none within budget' if best is None else f'{best[1]} {best[0] * 1e3:g} ms x ' + str(round(CONTROL_PERIOD / best[0]))}",
              file=out, flush=True)
    return chosen


class Tee:
    def __init__(self, *streams):
        self.streams = streams

    def write(self, s):
        for st in self.streams:
            st.write(s)

    def flush(self):
        for st in self.streams:
            st.flush()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robots", nargs="+", default=list(ROBOTS), choices=list(ROBOTS))
    ap.add_argument("--seconds", type=float, default=6.0, help="simulated seconds per run")
    ap.add_argument("--ref-dt", type=float, default=0.00005, help="reference physics step (s)")
    ap.add_argument("--budget", type=float, default=0.02, help="relative error budget of speed and sinkage")
    ap.add_argument("--slow", type=float, default=0.01, help="speeds below this (m/s) are compared in absolute terms")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "env_timestep.txt"))
    args = ap.parse_args()
    for name, val in (("seconds", args.seconds), ("ref-dt", args.ref_dt), ("budget", args.budget),
                      ("slow", args.slow)):
        if not (math.isfinite(val) and val > 0):
            ap.error(f"--{name} must be finite and > 0, got {val!r}")
    import mjrft.envs  # noqa: F401  (registers the envs)

    t0 = time.perf_counter()
    with open(args.out, "w") as f:
        out = Tee(sys.stdout, f)
        print(f"$ python benchmarks/env_timestep.py {' '.join(sys.argv[1:])}".rstrip(), file=out)
        print(f"budget: speed and sinkage within {100 * args.budget:g} % of the reference on every controller; "
              f"errors are each step's worst over the controllers", file=out)
        chosen = {}
        for robot in args.robots:
            chosen.update(study(robot, args.seconds, args.ref_dt, args.budget, args.slow, out))
        print("\nchosen steps (the largest within budget):", file=out)
        for env_id, best in chosen.items():
            print(f"  {env_id:24s} {'none' if best is None else f'{best[1]} {best[0] * 1e3:g} ms'}", file=out)
        print(f"study took {time.perf_counter() - t0:.0f} s", file=out)
        f.flush()
        os.fsync(f.fileno())


if __name__ == "__main__":
    main()

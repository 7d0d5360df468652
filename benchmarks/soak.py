"""Soak: a million steps of random actions in each sand environment without a non-finite value.

Every env step checks the observation, the reward, every number in ``info`` and the terrain's
outputs (per-element ``force`` and ``depth``, per-body ``wrench``, ``qpos``, ``qvel`` and
``xfrc_applied``) for NaN or inf; inside each env step the compiled loop itself checks every
physics step's state and force (it raises ``mjrft.NonFiniteError`` instead of writing a bad value
into MuJoCo; the env then ends the episode with ``info["diverged"]``, counted here as a divergence).
Episodes end by falls (``terminated``), divergences or the 1000-step time limit (``truncated``) and
are reset; all three are counted, as are stability warnings (once per body and env).

``--steps`` counts physics steps by default (each env's own: 0.5 ms x ``frame_skip`` 20 for the sand
hexapod, 1 ms x 10 for the others): 1,000,000 physics steps = 50,000-100,000 env steps. ``--unit env`` counts
env steps instead (1e6 env steps is 1-2e7 physics steps: about 20 minutes to an hour per environment on a
shared 2-core machine).

    python benchmarks/soak.py                         # 1e6 physics steps in each environment
    python benchmarks/soak.py --steps 100000          # a quicker 1e5
    python benchmarks/soak.py --unit env --steps 1000000 --json soak.json
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
import warnings

import numpy as np

ENV_IDS = ("mjrft/HexapodSand-v0", "mjrft/BipedSand-v0", "mjrft/HumanoidSand-v0")


def _finite(value) -> bool:
    if isinstance(value, (bool, np.bool_, str)) or value is None:
        return True
    if isinstance(value, dict):
        return all(_finite(v) for v in value.values())
    try:
        return bool(np.all(np.isfinite(np.asarray(value, dtype=float))))
    except (TypeError, ValueError):
        return True  # not numeric


def soak_env(env_id: str, steps: int, unit: str = "physics", seed: int = 0, progress=None) -> dict:
    """Random actions in ``env_id`` for ``steps`` physics (or env) steps; returns the counts."""
    import gymnasium

    import mjrft
    import mjrft.envs  # noqa: F401  (registers the ids)

    if unit not in ("physics", "env"):
        raise ValueError(f"unknown unit {unit!r}; valid choices: env, physics")
    env = gymnasium.make(env_id)
    u = env.unwrapped
    frame_skip = int(u.frame_skip)
    env_steps = steps if unit == "env" else math.ceil(steps / frame_skip)
    env.action_space.seed(seed)
    obs, info = env.reset(seed=seed)
    out = {"env": env_id, "env_steps": 0, "physics_steps": 0, "episodes": 1, "falls": 0, "time_limits": 0,
           "nonfinite": 0, "nonfinite_errors": 0, "diverged": 0, "stability_warnings": 0, "failures": [], "warnings": [],
           "max_sinkage_m": 0.0, "max_granular_force_N": 0.0, "elements": int(u.terrain.n_elements)}
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", mjrft.TerrainStabilityWarning)
        for k in range(env_steps):
            try:
                obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
            except mjrft.NonFiniteError as exc:
                out["nonfinite_errors"] += 1
                out["failures"].append(f"env step {k}: {exc}")
                terminated, truncated = True, False
            else:
                t = u.terrain
                checks = {"observation": obs, "reward": reward, "info": info, "force": t.force, "depth": t.depth,
                          "wrench": t.wrench, "qpos": u.data.qpos, "qvel": u.data.qvel,
                          "xfrc_applied": u.data.xfrc_applied}
                bad = [name for name, value in checks.items() if not _finite(value)]
                if bad:
                    out["nonfinite"] += 1
                    out["failures"].append(f"env step {k}: non-finite {', '.join(bad)}")
                out["max_sinkage_m"] = max(out["max_sinkage_m"], float(np.max(info["sinkage"])))
                out["max_granular_force_N"] = max(out["max_granular_force_N"],
                                                  float(np.max(np.linalg.norm(info["granular_force"], axis=1))))
            out["env_steps"] += 1
            out["physics_steps"] += frame_skip
            if info.get("diverged"):
                out["diverged"] += 1
                out["failures"].append(f"env step {k}: {info['diverged']}")
            elif terminated or truncated:
                out["falls" if terminated else "time_limits"] += 1
            if terminated or truncated:
                out["episodes"] += 1
                obs, info = env.reset()
            if progress is not None and (k + 1) % 20000 == 0:
                progress(f"  {env_id}: {k + 1}/{env_steps} env steps, {time.perf_counter() - t0:.0f} s")
        for w in caught:
            if issubclass(w.category, mjrft.TerrainStabilityWarning):
                out["stability_warnings"] += 1
                out["warnings"].append(str(w.message))
    out["wall_s"] = time.perf_counter() - t0
    out["failures"] = out["failures"][:20]
    env.close()
    return out


def table(results: list[dict]) -> str:
    head = ("| environment | elements | env steps | physics steps | episodes | falls | time limits | non-finite "
            "| NonFiniteError | diverged | stability warnings | max sinkage (mm) | max foot force (N) | wall (s) |")
    rows = [head, "|" + "---|" * 14]
    for r in results:
        rows.append(f"| {r['env']} | {r['elements']} | {r['env_steps']:,} | {r['physics_steps']:,} | {r['episodes']:,} "
                    f"| {r['falls']:,} | {r['time_limits']:,} | {r['nonfinite']} | {r['nonfinite_errors']} | {r['diverged']} "
                    f"| {r['stability_warnings']} | {1e3 * r['max_sinkage_m']:.1f} | {r['max_granular_force_N']:.1f} "
                    f"| {r['wall_s']:.0f} |")
    return "\n".join(rows)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=1_000_000, help="steps per environment (default 1e6)")
    ap.add_argument("--unit", choices=("physics", "env"), default="physics",
                    help="what --steps counts: physics steps (the env's own, default) or env steps (frame_skip physics steps)")
    ap.add_argument("--envs", nargs="+", default=list(ENV_IDS), help="environment ids")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--json", help="also write the results to this JSON file")
    args = ap.parse_args(argv)
    if args.steps < 1:
        ap.error(f"--steps must be >= 1, got {args.steps}")

    def progress(msg):
        print(msg, flush=True)

    results = []
    for env_id in args.envs:
        print(f"{env_id}: {args.steps:,} {args.unit} steps of random actions (seed {args.seed})", flush=True)
        r = soak_env(env_id, args.steps, args.unit, args.seed, progress)
        results.append(r)
        print(f"  done: {r['nonfinite']} non-finite, {r['nonfinite_errors']} NonFiniteError, {r['diverged']} diverged, "
              f"{r['stability_warnings']} stability warnings, {r['episodes']:,} episodes", flush=True)
        for line in r["failures"] + r["warnings"]:
            print(f"    {line}", flush=True)
        if args.json:
            with open(args.json, "w") as fh:
                json.dump(results, fh, indent=1)
    print(table(results), flush=True)
    ok = all(r["nonfinite"] == 0 and r["nonfinite_errors"] == 0 and r["diverged"] == 0 for r in results)
    print("PASS: no non-finite value, no divergence" if ok else "FAIL: non-finite values or divergences (see above)",
          flush=True)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())

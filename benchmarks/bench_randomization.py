"""Cost of terrain randomisation (``terrain_randomization``) on ``mjrft/HexapodSand-v0``, and the stability check
across stress scales.

1. ``env.step`` CPU time per option, the hexapod walking the alternating tripod at 2 Hz (``tripod:f=2``):
   interleaved repeats (each variant in turn, reset with the repeat's seed, ``--steps`` timed steps; median and
   fastest repeat). ``off`` is the env without the option; ``constant draw`` draws the same terrain as ``off``
   (``media=["poppy_cp"]``, ``stress_scale=1``: the same trajectory, bit for bit) and so measures the option's
   own overhead; the other rows change the terrain and with it the work (height-field lookups, several regions).
   Also the time of one ``reset()`` per variant.
2. Stress scales: the same gait for ``--seconds`` at each fixed ``stress_scale``; the smallest
   ``terrain.min_stable_timestep`` over the run and the number of ``TerrainStabilityWarning``s (at the env's
   own physics step, printed).

3. ``--plain N``: only the env without the option, N repeats, each repeat's CPU time per step (us) on one line:
   runs on any revision of mjrft (it uses no randomisation), to set the working tree against the code before
   the option existed, each imported from a copy laid out as the package (benchmarks/compare_revisions.py's
   layout), alternately.

    python benchmarks/bench_randomization.py [--steps 200] [--repeats 15] [--seconds 3]
    PYTHONPATH=<copy>/pkg python benchmarks/bench_randomization.py --plain 8
"""

from __future__ import annotations

import argparse
import time
import warnings

import gymnasium
import numpy as np

import mjrft
import mjrft.envs  # noqa: F401  (registers the environments)
from mjrft.tools.gaits import make_gait

HEX = "mjrft/HexapodSand-v0"
MEDIA = ["poppy_cp", "poppy_lp", "glass3_cp"]
VARIANTS = {
    "off": {},
    "constant draw": {"terrain_randomization": {"media": ["poppy_cp"], "stress_scale": 1.0}},
    "media + stress_scale": {"terrain_randomization": {"media": MEDIA, "stress_scale": [0.7, 1.3]}},
    "surface_height": {"terrain_randomization": {"surface_height": [-0.005, 0.01]}},
    "hfield, flat": {"surface_grid": 0.01},
    "roughness 3 mm": {"terrain_randomization": {"roughness": 0.003}},
    "strips 1-3": {"terrain_randomization": {"media": MEDIA, "strips": [1, 3]}},
    "all": {"terrain_randomization": {"media": MEDIA, "stress_scale": [0.7, 1.3], "surface_height": [-0.005, 0.01],
                                      "roughness": 0.003, "strips": [0, 3]}},
}


def make(kw):
    env = gymnasium.make(HEX, disable_env_checker=True, **kw)
    return env, make_gait("tripod:f=2", env)


def timed(env, gait, seed, steps) -> float:
    """CPU seconds per env.step over ``steps`` steps from ``reset(seed)`` (a reset after a fall is not timed)."""
    obs, _ = env.reset(seed=seed)
    total = 0.0
    for _ in range(steps):
        a, _ = gait.predict(obs)
        t0 = time.process_time()
        obs, _, term, trunc, _ = env.step(a)
        total += time.process_time() - t0
        if term or trunc:
            obs, _ = env.reset()
    return total / steps


def step_costs(steps, repeats) -> None:
    envs = {name: make(kw) for name, kw in VARIANTS.items()}
    for env, gait in envs.values():  # compile and warm up
        timed(env, gait, 0, 20)
    times = {name: [] for name in envs}
    names = list(envs)
    for r in range(repeats):
        for name in (names if r % 2 == 0 else names[::-1]):
            times[name].append(timed(*envs[name], r, steps))
    resets = {}
    for name, (env, _) in envs.items():
        t0 = time.process_time()
        for s in range(20):
            env.reset(seed=s)
        resets[name] = (time.process_time() - t0) / 20
    base = np.median(times["off"])
    print(f"env.step CPU time, tripod:f=2, {repeats} interleaved repeats x {steps} steps (median, fastest repeat)")
    print(f"{'variant':22s} {'median us':>10s} {'fastest us':>11s} {'vs off':>7s} {'reset ms':>9s}")
    for name, v in times.items():
        print(f"{name:22s} {1e6 * np.median(v):10.0f} {1e6 * min(v):11.0f} {np.median(v) / base:7.2f} "
              f"{1e3 * resets[name]:9.2f}")
    a, b = envs["off"][0], envs["constant draw"][0]
    oa, _ = a.reset(seed=7)
    ob, _ = b.reset(seed=7)
    same = np.array_equal(oa, ob)
    ga, gb = make_gait("tripod:f=2", a), make_gait("tripod:f=2", b)
    for _ in range(100):
        oa, ob = a.step(ga.predict(oa)[0])[0], b.step(gb.predict(ob)[0])[0]
        same &= np.array_equal(oa, ob)
    print(f"'off' and 'constant draw' give the same 100-step trajectory bit for bit: {same}")


def stability(seconds) -> None:
    step_ms = 1e3 * make({})[0].unwrapped.model.opt.timestep
    print(f"\nstress_scale vs the stability check, tripod:f=2 for {seconds:g} s on poppy_cp "
          f"(physics step {step_ms:g} ms)")
    print(f"{'stress_scale':>12s} {'min stable dt ms':>17s} {'5th pct ms':>11s} {'warnings':>9s}")
    for scale in (0.5, 1.0, 1.3, 1.5, 2.0, 3.0, 5.0):
        env, gait = make({"terrain_randomization": {"stress_scale": scale}})
        obs, _ = env.reset(seed=0)
        u = env.unwrapped
        dts = []
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            for _ in range(int(round(seconds / u.dt))):
                obs, *_ = env.step(gait.predict(obs)[0])
                dts.append(u.terrain.min_stable_timestep(u.data))
        n = sum(issubclass(c.category, mjrft.TerrainStabilityWarning) for c in caught)
        print(f"{scale:12g} {1e3 * min(dts):17.2f} {1e3 * np.percentile(dts, 5):11.2f} {n:9d}")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--steps", type=int, default=200)
    p.add_argument("--repeats", type=int, default=15)
    p.add_argument("--seconds", type=float, default=3.0)
    p.add_argument("--plain", type=int, default=0, metavar="N", help="only the plain env, N repeats")
    args = p.parse_args()
    if args.plain:
        env, gait = make({})
        timed(env, gait, 0, 50)
        print(" ".join(f"{1e6 * timed(env, gait, r, args.steps):.0f}" for r in range(args.plain)))
        return
    print(f"python benchmarks/bench_randomization.py --steps {args.steps} --repeats {args.repeats} "
          f"--seconds {args.seconds:g}\n")
    step_costs(args.steps, args.repeats)
    stability(args.seconds)


if __name__ == "__main__":
    main()

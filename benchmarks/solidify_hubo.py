"""The HUBO one-foot stance (validation case thesis_hubo_stance, thesis sec. 4.4.1, fig. 25) with the solidify option.

For each static yield factor (0 = off: the rest memory alone) the three trials (CoM 1 cm behind, on, 1 cm ahead of
the sole's centre) on the natural 15.2 cm foot, the 30.4 cm board and the cut-out board, as the case runs them;
then, on the 30.4 cm board with the CoM 1 cm behind, the speeds of the buried elements (both feet until the lift,
the stance foot after) and their memory ``|u| / delta`` every 0.5 s: the solidify option acts only on elements
slower than its stick speed (1 mm/s).

Usage: ``python benchmarks/solidify_hubo.py [--factors 0 1 2] [--out benchmarks/results/solidify_hubo.txt]``
"""

from __future__ import annotations

import argparse
import math
import sys
import time
import warnings

import numpy as np


def _patch(factor):
    from mjrft.coupler import GranularTerrain
    from mjrft.tools.validation.cases import thesis_hubo as th

    orig = th._env

    def env(w, cut, yd=None, sand=True):
        e = orig(w, cut, yd, sand)
        if factor > 0.0 and sand:
            t = e.terrain
            e.terrain = GranularTerrain(e.model, t.medium, t.law, resolution=t.resolution, solidify=factor)
        return e

    th._env = env
    return th, orig


def trials(factor):
    th, orig = _patch(factor)
    try:
        rows = {}
        for w, cut, name in ((0.152, False, "natural 15.2 cm"), (0.304, False, "board 30.4 cm"),
                             (0.304, True, "cut-out 30.4 cm")):
            rows[name] = [th.run_trial(f"stance:com_x={cx},lift=0.1", w, cut, th.HOLD_END)[3] for cx in th.PLACEMENTS]
        return rows
    finally:
        th._env = orig


def speeds(factor, com_x=-0.01, t_end=6.0):
    from mjrft.tools.gaits import make_gait

    th, orig = _patch(factor)
    out = []
    try:
        env = th._env(0.304, False)
        obs, _ = env.reset(seed=0)
        gait = make_gait(f"stance:com_x={com_x},lift=0.1", env)
        ter = env.terrain
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            while env.data.time < t_end - 1e-9:
                a, _ = gait.predict(obs)
                obs, *_ = env.step(a)
                t = env.data.time
                if abs(t * 2 - round(t * 2)) < 1e-6:
                    b = ter.depth > 0
                    sp = np.linalg.norm(ter.vel[b], axis=1)
                    mem = np.linalg.norm(ter.terrain_state.u[b], axis=1) / ter.yield_displacement
                    out.append((t, int(b.sum()), float(np.median(sp)), float(np.mean(sp < ter.stick_speed)),
                                float(np.median(mem)), float(mem.max()), env.torso_tilt()))
                if env.torso_tilt() > th.FALL_TILT:
                    break
        env.close()
    finally:
        th._env = orig
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--factors", type=float, nargs="+", default=[0.0, 1.0, 2.0])
    ap.add_argument("--out", default=None)
    args = ap.parse_args(argv)
    lines = [f"# python benchmarks/solidify_hubo.py {' '.join(argv if argv is not None else sys.argv[1:])}"]

    def say(s=""):
        print(s, flush=True)
        lines.append(s)

    t0 = time.perf_counter()
    say("Fall times (s; - = stood to 10 s) of the trials with the CoM -1, 0, +1 cm ahead of the sole's centre")
    for f in args.factors:
        rows = trials(f)
        say(f"  solidify={f:g}: " + "; ".join(
            f"{k}: " + ", ".join("-" if math.isnan(x) else f"{x:.2f}" for x in v) + f" ({sum(math.isnan(x) for x in v)}/3 stood)"
            for k, v in rows.items()))
    say()
    say("30.4 cm board, CoM 1 cm behind: time (s), buried elements, median speed (mm/s), fraction below 1 mm/s, "
        "median and largest |u|/delta, pelvis tilt (rad)")
    for f in args.factors:
        say(f"  solidify={f:g}:")
        for t, n, med, frac, mm, mx, tilt in speeds(f):
            say(f"    {t:4.1f}  {n:4d}  {med * 1000:6.2f}  {frac:4.2f}  {mm:4.2f}  {mx:4.2f}  {tilt:6.3f}")
    say()
    say(f"wall {time.perf_counter() - t0:.0f} s")
    if args.out:
        with open(args.out, "w") as fh:
            fh.write("\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())

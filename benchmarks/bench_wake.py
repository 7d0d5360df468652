"""The cost of the ground memory's wake (the hybrid law's undisturbed-grain rule) on a robot, side by side.

    python benchmarks/bench_wake.py [--steps N] [--rounds R] [--out FILE]

The hexapod (its bundled scene's medium, closely packed poppy seeds, under the ``hybrid`` law, 1 ms) walks its 2 Hz
tripod for 1 s on a terrain without a memory while a terrain with ``ground_memory=True`` is evaluated on the same
states (as ``benchmarks/bench_ground.py`` records); the next N physics steps are recorded as the kernel sees them.
Each timed round replays them in order through the compiled kernel from a compiled loop on the terrain with the
memory, its state restored to the recording's start, once with its wake and once with the wake emptied (the rule
off: the same ground, footprints and ridges, since the wake changes no update of the ground), alternately; the
fastest round of each is its cost. Then, on one more replay of each, step by step: the elements buried per step and
those the rule leaves without force (a force without the wake, none with it), and the largest difference of the
body wrenches between the two, relative to the largest wrench.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings

import numpy as np

from mjrft.types import MjViews

from bench_ground import record, replay, restore

LAW = "hybrid"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=1000, help="recorded physics steps (default 1000: 1 s)")
    ap.add_argument("--rounds", type=int, default=15, help="timed rounds per configuration (default 15)")
    ap.add_argument("--out", default=None, help="also write the report to this file")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    _, on, _, views, start, dt = record(args.steps, law=LAW)
    st = on.terrain_state
    wake = st.g_wake
    states = {"wake": st, "wake emptied": st._replace(g_wake=np.zeros((0, 0, 0), dtype=np.float32))}
    tables = on.terrain_model.tables
    best = {k: np.inf for k in states}
    for r in range(args.rounds + 1):  # round 0 compiles
        for name, s in states.items():
            restore(st, start)
            t0 = time.perf_counter_ns()
            bad = replay(tables, views, 9.81, dt, s)
            elapsed = (time.perf_counter_ns() - t0) / args.steps * 1e-3
            if bad:
                raise SystemExit(f"{name}: {bad} steps returned a bad status")
            if r > 0:
                best[name] = min(best[name], elapsed)
    # the same replay step by step: what the rule removes
    forces, wrenches, buried = {}, {}, 0
    for name, s in states.items():
        restore(st, start)
        f, w = [], []
        for k in range(args.steps):
            replay(tables, MjViews(*(v[k:k + 1] for v in views)), 9.81, dt, s)
            f.append(np.any(st.force != 0.0, axis=1))
            w.append(st.wrench.copy())
            if name == "wake":
                buried += np.count_nonzero(st.depth > 0.0)
        forces[name], wrenches[name] = np.array(f), np.array(w)
    removed = np.count_nonzero(forces["wake emptied"] & ~forces["wake"]) / args.steps
    dw = np.abs(wrenches["wake"] - wrenches["wake emptied"]).max() / np.abs(wrenches["wake emptied"]).max()
    w, e = best["wake"], best["wake emptied"]
    lines = [f"python benchmarks/bench_wake.py --steps {args.steps} --rounds {args.rounds}",
             f"hexapod ({on.medium.name}, law {on.law}, {on.n_elements} elements, dt {dt * 1e3:g} ms), 2 Hz tripod on "
             f"the terrain without a memory, a terrain with one evaluated on the same states; {args.steps} recorded "
             f"steps after 1 s; fastest of {args.rounds} rounds, kernel time per step (us), the same ground both ways:",
             f"  with the wake {w:.2f}, wake emptied {e:.2f}: the wake costs {100 * (w - e) / e:.1f} % of the kernel "
             f"with the memory",
             f"  wake: {wake.shape[0]} x {wake.shape[1]} cells x {wake.shape[2]} slabs, {wake.nbytes / 1e6:.1f} MB",
             f"  elements per step: {buried / args.steps:.0f} buried, {removed:.1f} left without force by the rule; "
             f"largest wrench difference {dw:.3f} of the largest wrench"]
    text = "\n".join(lines)
    print(text)
    if args.out:
        with open(args.out, "w") as fh:
            fh.write(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Per-step cost of a six-legged robot with granular terrain against the same model without it.

Measured side by side in one run (interleaved repeats; median and minimum), on the bundled RHex-class hexapod
walking an open-loop tripod on poppy seeds: coarse (~200 elements) and fine (~2,000 elements)
resolution. Times are this process's CPU time (on a shared machine wall time also counts the waits
for a core). Then the shoal scene (``hexapod_shoal``: dry poppy seeds, saturated sand, 2 cm of water
with buoyancy; mjrft.models.shoal) against the dry scene, same robot and the fine resolution, with
the robot walking in each strip and across all three. Prints ratios only; absolute times on a shared
2-core machine mean little.

    python benchmarks/bench_step.py [--steps N] [--repeats R]
"""

from __future__ import annotations

import argparse
import time
import tracemalloc

import mujoco
import numpy as np

import mjrft
from mjrft.models import hexapod_model, hexapod_shoal_model


def tripod_offsets(model) -> np.ndarray:
    """Phase offset of each actuator: 0 for tripod A (lf, rm, lr), pi for tripod B."""
    a = {"leg_lf", "leg_rm", "leg_lr"}
    off = np.zeros(model.nu)
    for i in range(model.nu):
        body = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, model.jnt_bodyid[model.actuator_trnid[i, 0]])
        off[i] = 0.0 if body in a else np.pi
    return off


def tripod_ctrl(model, data, t, freq=2.0, offsets=None):
    """Alternating tripod: every hip target advances at freq rev/s, tripod B half a cycle behind."""
    data.ctrl[:] = 2 * np.pi * freq * t + (tripod_offsets(model) if offsets is None else offsets)


def run(model, data, terrain, steps, chunk=10, buried=None, x0=0.0):
    """Seconds per physics step (the robot starting at x = x0); appends the number of buried elements
    after each chunk to ``buried`` (a count that the timed runs leave out: it is the benchmark's, not the
    terrain's work)."""
    mujoco.mj_resetData(model, data)
    data.qpos[0] = x0
    if terrain is not None:
        terrain.reset()
    off = tripod_offsets(model)
    t0 = time.process_time()
    for _ in range(steps // chunk):
        tripod_ctrl(model, data, data.time, offsets=off)
        if terrain is None:
            mujoco.mj_step(model, data, chunk)
        else:
            terrain.step(data, chunk)
            if buried is not None:
                buried.append(int(np.count_nonzero(terrain.depth > 0)))
    return (time.process_time() - t0) / steps


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=4000)
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()
    model = hexapod_model()
    data = mujoco.MjData(model)
    cases = {}
    for label, res in (("coarse", 0.03), ("fine", 0.0042)):
        cases[label] = mjrft.GranularTerrain(model, resolution=res)
    run(model, data, None, 200)
    for t in cases.values():  # compile / load the cache outside the timing
        run(model, data, t, 200)
    times = {k: [] for k in ["bare", *cases]}
    buried = {k: [] for k in cases}
    for _ in range(args.repeats):
        times["bare"].append(run(model, data, None, args.steps))
        for k, t in cases.items():
            times[k].append(run(model, data, t, args.steps))
    for k, t in cases.items():  # the same walk again, untimed, counting the buried elements
        run(model, data, t, args.steps, buried=buried[k])
    bare = np.median(times["bare"])
    bare_min = np.min(times["bare"])
    print(f"hexapod (RHex-class, 6 C-legs + torso), tripod gait at 2 Hz, {args.steps} steps x {args.repeats} repeats")
    print("ratio to the bare step: of the medians, and of the minima over the interleaved repeats (other")
    print("processes on a shared machine only ever add time, so the minima are the less disturbed estimate)")
    print(f"{'case':8s} {'elements':>8s} {'on legs':>8s} {'buried (mean)':>14s} {'median ratio':>13s} {'min ratio':>10s}")
    print(f"{'bare':8s} {0:8d} {0:8d} {0:14d} {1.0:13.2f} {1.0:10.2f}")
    for k, t in cases.items():
        legs = int(np.count_nonzero(t.elem_body != mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "torso")))
        print(f"{k:8s} {t.n_elements:8d} {legs:8d} {np.mean(buried[k]):14.0f} {np.median(times[k]) / bare:13.2f} "
              f"{np.min(times[k]) / bare_min:10.2f}")
    # memory does not grow with steps
    t = cases["fine"]
    tracemalloc.start()
    run(model, data, t, 1000)
    before = tracemalloc.get_traced_memory()[0]
    run(model, data, t, 5000)
    after = tracemalloc.get_traced_memory()[0]
    tracemalloc.stop()
    print(f"python heap growth over 5000 more steps: {after - before} bytes")
    shoal(args.steps, args.repeats)


def shoal(steps, repeats, res=0.0042):
    """The shoal scene against the dry one: same robot, same resolution, interleaved."""
    dry_m = hexapod_model()
    dry_d = mujoco.MjData(dry_m)
    sh_m = hexapod_shoal_model()
    sh_d = mujoco.MjData(sh_m)
    dry = mjrft.GranularTerrain(dry_m, resolution=res)
    wet = mjrft.GranularTerrain(sh_m, resolution=res)
    half = max(100, min(steps // 2, 1000))  # at most 1 s, ~23 cm of walking: stays inside one 50 cm strip
    cases = {  # label: (model, data, terrain, steps, start x)
        "dry scene": (dry_m, dry_d, dry, half, 0.0),
        "shoal, dry strip": (sh_m, sh_d, wet, half, 0.1),
        "shoal, saturated": (sh_m, sh_d, wet, half, 0.65),
        "shoal, water": (sh_m, sh_d, wet, half, 1.15),
        "shoal, crossing": (sh_m, sh_d, wet, 5000, 0.0),  # 0 -> ~1.1 m: all three strips
        "dry, same walk": (dry_m, dry_d, dry, 5000, 0.0),
    }
    run(dry_m, dry_d, None, 200)
    for m, d, t, _, x0 in cases.values():
        run(m, d, t, 200, x0=x0)
    times = {k: [] for k in ["bare", *cases]}
    buried = {k: [] for k in cases}
    for _ in range(repeats):
        times["bare"].append(run(dry_m, dry_d, None, half))
        for k, (m, d, t, n, x0) in cases.items():
            times[k].append(run(m, d, t, n, x0=x0))
    for k, (m, d, t, n, x0) in cases.items():
        run(m, d, t, n, buried=buried[k], x0=x0)
    bare = np.median(times["bare"])
    ref = {"dry scene": np.median(times["dry scene"]), "dry, same walk": np.median(times["dry, same walk"])}
    print(f"\nshoal scene vs dry scene (same hexapod, resolution {res} m, {wet.n_elements} elements), "
          f"{repeats} repeats")
    print(f"{'case':18s} {'buried (mean)':>14s} {'ratio to bare':>14s} {'ratio to dry':>13s}")
    for k in cases:
        r = np.median(times[k])
        dry_ref = ref["dry, same walk"] if cases[k][3] == 5000 else ref["dry scene"]
        print(f"{k:18s} {np.mean(buried[k]):14.0f} {r / bare:14.2f} {r / dry_ref:13.2f}")


if __name__ == "__main__":
    main()

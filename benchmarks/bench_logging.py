"""Cost of rerun logging: a rollout logged every N-th env step against the same rollout unlogged.

Runs the demo's set-up (RHex-class hexapod, tripod gait at 2 Hz, poppy seeds) for ``--seconds`` of
simulated time, alternating logged and unlogged repeats in one process (after a warm-up that
compiles the kernels and imports rerun), and prints the median wall-time ratio; the target is
below 2x at ``--log-every 10``. Also prints the file size per logged frame. Ratios only: absolute
times on a shared machine mean little.

    python benchmarks/bench_logging.py [--seconds 3] [--repeats 3] [--log-every 10] [--resolution R]
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
import warnings

import numpy as np

from mjrft.errors import TerrainStabilityWarning
from mjrft.train.rollout import rollout

ENV_ID = "mjrft/HexapodSand-v0"


def timed(rrd, seconds, log_every, kwargs):
    t0 = time.perf_counter()
    s = rollout(ENV_ID, "tripod:f=2", seconds=seconds, rrd_path=rrd, log_every=log_every, env_kwargs=kwargs)
    return time.perf_counter() - t0, s


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=3.0)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--log-every", type=int, default=10)
    ap.add_argument("--resolution", type=float, default=None, help="element size (m); default: the model's 5 mm")
    args = ap.parse_args()
    kwargs = {"medium": "poppy_cp"}
    if args.resolution is not None:
        kwargs["resolution"] = args.resolution
    warnings.simplefilter("ignore", TerrainStabilityWarning)
    with tempfile.TemporaryDirectory() as tmp:
        rrd = os.path.join(tmp, "bench.rrd")
        timed(rrd, 0.2, args.log_every, kwargs)  # warm-up: kernels, rerun, env construction paths
        timed(None, 0.2, args.log_every, kwargs)
        bare, logged, frames, size = [], [], 0, 0
        for _ in range(args.repeats):
            t, _ = timed(None, args.seconds, args.log_every, kwargs)
            bare.append(t)
            t, s = timed(rrd, args.seconds, args.log_every, kwargs)
            logged.append(t)
            frames, size = s["frames"], os.path.getsize(rrd)
        steps = s["steps"]
    ratio = np.median(logged) / np.median(bare)
    print(f"hexapod tripod 2 Hz on poppy_cp, {args.seconds:g} s simulated = {steps} env steps, "
          f"{args.repeats} repeats (each includes env construction and reset)")
    print(f"{'case':28s} {'ratio':>7s}")
    print(f"{'no logging':28s} {1.0:7.2f}")
    print(f"{f'logging every {args.log_every} env steps':28s} {ratio:7.2f}   (target < 2)")
    print(f"file: {frames} frames, {size / max(frames, 1) / 1024:.1f} KiB per frame")


if __name__ == "__main__":
    main()

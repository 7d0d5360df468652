"""Where the hexapod's period-2 bounce sets in, and what it does to a free body and to one held planar.

    python benchmarks/tripod_bounce.py [--media poppy_cp poppy_lp] [--frequencies 3 3.5 4 4.5 5]

Each run is ``mjrft.tools.validation.cases.li2013_robot.free_trial``: ``mjrft/HexapodSand-v0`` as a user makes it
(the env's start, reset noise of seed 0, 10 s), the open-loop tripod at f Hz, C-legs (+1/R') and reversed C-legs
(-1/R'), once free and once held in the sagittal plane (``planar=True``, as in Li 2013's simulation). Per run, over
the episode's second half: the torso's mean height on the two alternate half-cycles (one tripod's stance each),
whether that is a bounce (``li2013_robot.bounces``: the two more than 10 % of their mean apart), the heading rate
and the speed along x after the first second.
"""

from __future__ import annotations

import argparse
import math
import warnings

from mjrft.tools.validation.cases import li2013_robot


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--media", nargs="+", default=["poppy_cp", "poppy_lp"])
    ap.add_argument("--frequencies", type=float, nargs="+", default=[3.0, 3.5, 4.0, 4.5, 5.0])
    args = ap.parse_args(argv)
    print("tripod, 10 s per run, seed 0, law rft; second half: torso height on alternate half-cycles, heading rate; "
          "speed along x after 1 s")
    print("| medium | legs | f (Hz) | held | torso mm | bounce | heading deg/s | speed m/s |")
    print("|---|---|---|---|---|---|---|---|")
    for medium in args.media:
        for k, legs in ((1.0, "C"), (-1.0, "rev C")):
            for f in args.frequencies:
                for planar in (False, True):
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore")
                        r = li2013_robot.free_trial(k, f, medium, planar=planar)
                    z = r["height_halves"]
                    print(f"| {medium} | {legs} | {f:g} | {'planar' if planar else 'free'} | "
                          f"{1e3 * z[0]:.1f} / {1e3 * z[1]:.1f} | {'yes' if li2013_robot.bounces(r) else 'no'} | "
                          f"{math.degrees(r['yaw_rate']):+.1f} | {r['speed']:.3f} |", flush=True)


if __name__ == "__main__":
    main()

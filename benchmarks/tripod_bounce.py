"""Where the hexapod's period-2 bounce sets in, and what it does to a free body and to one held planar.

    python benchmarks/tripod_bounce.py [--media poppy_cp poppy_lp] [--frequencies 3 3.5 4 4.5 5]

Each run is ``mjrft.tools.validation.cases.li2013_robot.free_trial``: ``mjrft/HexapodSand-v0`` as a user makes it
(the env's start, reset noise of seed 0, 10 s), the open-loop tripod at f Hz, C-legs (+1/R') and reversed C-legs
(-1/R'), once free and once held in the sagittal plane (``planar=True``, as in Li 2013's simulation). Per run, over
the episode's second half: the torso's mean height on the two alternate half-cycles (one tripod's stance each),
whether that is a bounce (``li2013_robot.bounces``: the two more than 10 % of their mean apart), the heading rate
and the speed along x after the first second.

Then the drive: the same runs at 5 Hz on poppy CP with the hip servos' gains and torque limit (``kp``, ``kv``,
``torque_limit`` of :func:`mjrft.models.hexapod_xml`; the paper gives no drive model, only a DC motor through a
47:1 gear train at constant voltage) scaled by ``--servo-scales``, with each tripod's mean lag behind its command,
at a quarter of the env's timestep (:data:`DRIVE_TIMESTEP`, the same 10 ms control step): MuJoCo integrates a
position servo's stiffness explicitly, and 10x the gains at the env's 0.5 ms are not resolved (the C-legs at 3 Hz on
poppy LP, planar: 0.325 m/s there, 0.402 at 0.125 ms; 1x: 0.405 and 0.407); at 0.125 ms 10x is (at 5 Hz on poppy
CP, planar, C-legs 0.691 m/s, 0.692 at 0.0625 ms), 30x is not (0.402, 0.678 at 0.0625 ms, 0.693 at 0.03125 ms).
"""

from __future__ import annotations

import argparse
import math
import warnings

from mjrft.models.hexapod import VARIANTS
from mjrft.tools.validation.cases import li2013_robot


#: s: the drive runs' physics step, a quarter of the env's 0.5 ms (80 per 10 ms control step)
DRIVE_TIMESTEP = 0.000125


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--media", nargs="+", default=["poppy_cp", "poppy_lp"])
    ap.add_argument("--frequencies", type=float, nargs="+", default=[3.0, 3.5, 4.0, 4.5, 5.0])
    ap.add_argument("--servo-scales", type=float, nargs="+", default=[1.0, 10.0])
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
                    print(f"| {medium} | {legs} | {f:g} | {_row(r, planar)} |", flush=True)
    v = VARIANTS["rhex"]
    print()
    print(f"the drive: 5 Hz on poppy_cp, hip servos kp {v.kp:g} N m/rad, kv {v.kv:g} N m s/rad, torque limit "
          f"{v.torque_limit:g} N m, each times the scale; physics step {1e3 * DRIVE_TIMESTEP:g} ms")
    print("| legs | servo scale | held | torso mm | bounce | heading deg/s | speed m/s | tripod lag A / B deg |")
    print("|---|---|---|---|---|---|---|---|")
    for k, legs in ((1.0, "C"), (-1.0, "rev C")):
        for scale in args.servo_scales:
            for planar in (False, True):
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    r = li2013_robot.free_trial(k, 5.0, "poppy_cp", planar=planar, kp=v.kp * scale, kv=v.kv * scale,
                                                torque_limit=v.torque_limit * scale, timestep=DRIVE_TIMESTEP,
                                                frame_skip=round(0.01 / DRIVE_TIMESTEP))
                lag = r["tripod_lag"]
                print(f"| {legs} | {scale:g} | {_row(r, planar)} | "
                      f"{math.degrees(lag[0]):.1f} / {math.degrees(lag[1]):.1f} |", flush=True)


def _row(r: dict, planar: bool) -> str:
    """Held, torso heights, bounce, heading rate ("none" held planar: it cannot turn) and speed columns of a run."""
    z = r["height_halves"]
    heading = "none" if planar else f"{math.degrees(r['yaw_rate']):+.1f}"
    return (f"{'planar' if planar else 'free'} | {1e3 * z[0]:.1f} / {1e3 * z[1]:.1f} | "
            f"{'yes' if li2013_robot.bounces(r) else 'no'} | {heading} | {r['speed']:.3f}")


if __name__ == "__main__":
    main()

"""``mjrft demo``: the RHex-class hexapod walks an open-loop alternating tripod on poppy seeds.

Headless: the rollout is logged to a rerun file (default ``mjrft-demo.rrd`` in the current folder,
``--out`` to change it) and the command prints where the file is, how to open it and a short summary
(distance, mean speed, mean sinkage). ``--spawn-viewer`` also streams to a rerun viewer.

    mjrft demo [--seconds 4] [--out mjrft-demo.rrd] [--gait tripod:f=2] [--medium poppy_cp] [--ground-memory]
               [--spawn-viewer]

``--ground-memory`` gives the sand a memory (:mod:`mjrft.ground`): the recording then shows the footprints, ridges
and sheared grains the legs leave.

It is ``mjrft rollout --env mjrft/HexapodSand-v0 --policy tripod:f=2 --seconds 4 --rrd mjrft-demo.rrd``
with the demo's defaults (see :mod:`mjrft.train.rollout`). The settling demo of earlier versions is
``mjrft settle``.
"""

from __future__ import annotations

import argparse
import os

from mjrft.tools.rerun_log import LOG_EVERY

ENV_ID = "mjrft/HexapodSand-v0"
DEFAULT_OUT = "mjrft-demo.rrd"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--seconds", type=float, default=4.0, help="simulated seconds (default 4)")
    parser.add_argument("--out", default=DEFAULT_OUT, metavar="FILE", help=f"rerun file to write (default {DEFAULT_OUT})")
    parser.add_argument("--gait", default="tripod:f=2", metavar="SPEC",
                        help="hexapod gait spec (default tripod:f=2; see mjrft.tools.gaits)")
    parser.add_argument("--medium", default="poppy_cp", help="granular medium (default poppy_cp: closely packed poppy seeds)")
    parser.add_argument("--log-every", type=int, default=LOG_EVERY, metavar="N",
                        help=f"log every N-th env step (default {LOG_EVERY})")
    parser.add_argument("--seed", type=int, default=0, help="reset seed (default 0)")
    parser.add_argument("--ground-memory", action="store_true",
                        help="the sand remembers footprints, ridges and packing (recorded as world/ground_memory)")
    parser.add_argument("--spawn-viewer", action="store_true", help="also stream to a newly started rerun viewer")
    parser.add_argument("--viewer-bind", default="127.0.0.1", metavar="ADDRESS",
                        help="with --spawn-viewer: the address the viewer listens on (default 127.0.0.1, this "
                             "machine only; 0.0.0.0 opens it to the network)")


def main(args) -> int:
    from mjrft.train.rollout import format_summary, open_hint, rollout

    from mjrft.tools.outputs import WarningNotes, output_file

    out = os.path.abspath(output_file(args.out))
    if args.spawn_viewer:
        from mjrft.tools.rerun_log import check_viewer_display

        check_viewer_display()
    print(f"mjrft demo: RHex-class hexapod, gait {args.gait}, on {args.medium}, {args.seconds:g} s simulated "
          "(the first run compiles the terrain kernels first: a minute or two)", flush=True)
    with WarningNotes() as notes:  # the warnings become notes under the summary
        summary = rollout(ENV_ID, args.gait, seconds=args.seconds, rrd_path=out, log_every=args.log_every,
                          seed=args.seed, env_kwargs={"medium": args.medium,
                                                      **({"ground_memory": True} if args.ground_memory else {})},
                          spawn_viewer=args.spawn_viewer,
                          viewer_bind=args.viewer_bind)
    print(format_summary(summary))
    notes.print("  ")
    print(f"wrote {out} ({summary['frames']} frames: robot, sand, contact stresses, forces, per-leg lift/thrust/sinkage"
          + (", the ground's memory" if args.ground_memory else "") + ")")
    print(open_hint(out))
    return 0

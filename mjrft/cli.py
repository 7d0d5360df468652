"""The ``mjrft`` command line: ``mjrft demo`` (and ``mjrft --help``)."""

from __future__ import annotations

import argparse
import sys


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="mjrft", description="Granular terrain (RFT) for MuJoCo.")
    sub = parser.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="drop a box foot and a legged body onto poppy seeds; print the sinkage")
    demo.add_argument("--medium", default="poppy_cp", help="medium name (default poppy_cp)")
    demo.add_argument("--drop", type=float, default=0.01, help="drop height above the surface in m (default 0.01)")
    args = parser.parse_args(argv)
    if args.command == "demo":
        from .media import get_medium
        from .demo import run

        try:
            get_medium(args.medium)
        except ValueError as exc:
            parser.error(str(exc))
        if not args.drop >= 0:
            parser.error(f"--drop must be >= 0, got {args.drop}")
        run(args.medium, args.drop)
    return 0


if __name__ == "__main__":
    sys.exit(main())

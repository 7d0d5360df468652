"""The full speed/accuracy trade study; writes benchmarks/results/trade_study.{md,csv,png}.

Every configuration of every scenario (resolution, law, timestep, frame skip, presets; see
:mod:`mjrft.tools.tradeoff`) runs side by side with the bare MuJoCo model, interleaved, and is compared with
the converged reference. Prints the table and the preset choice. A few minutes on 2 cores.

    python benchmarks/trade_study.py [--scenarios hexapod,plate] [--repeats 3] [--out benchmarks/results]

The same study from the command line: ``mjrft bench`` (``--quick`` for a one-minute grid).
"""

from __future__ import annotations

import argparse
import os
import time

from mjrft.tools import tradeoff

HERE = os.path.dirname(os.path.abspath(__file__))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenarios", default="all", help=f"comma-separated: {', '.join(tradeoff.SCENARIOS)}")
    ap.add_argument("--repeats", type=int, default=3, help="timing repeats per configuration")
    ap.add_argument("--out", default=os.path.join(HERE, "results"), help="output folder")
    args = ap.parse_args()
    t0 = time.perf_counter()
    rows = tradeoff.run_study(tradeoff.parse_scenarios(args.scenarios), repeats=args.repeats)
    paths = tradeoff.write_outputs(rows, args.out)
    print()
    print(tradeoff.markdown_table(rows))
    print(tradeoff.recommendation_text(rows))
    print(f"study took {time.perf_counter() - t0:.0f} s; wrote {', '.join(paths.values())}")


if __name__ == "__main__":
    main()

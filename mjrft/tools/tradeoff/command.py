"""``mjrft bench``: the trade study from the command line (:func:`add_arguments`, :func:`main`)."""

from __future__ import annotations

import time

from mjrft.errors import check_positive

from ..outputs import output_dir
from .measure import run_study
from .report import markdown_table, recommendation_text, write_outputs
from .scenarios import SCENARIOS, get_scenario

def parse_scenarios(text) -> list[str]:
    """``"hexapod,plate"`` (or a list) -> validated scenario names; ``"all"`` -> every scenario."""
    if text is None:
        return list(SCENARIOS)
    items = text if isinstance(text, (list, tuple)) else [text]
    names = [n.strip() for item in items for n in str(item).split(",") if n.strip()]
    if not names:
        raise ValueError(f"no scenario given; valid choices: {', '.join(sorted(SCENARIOS))} (or 'all')")
    if names == ["all"]:
        return list(SCENARIOS)
    for n in names:
        get_scenario(n)
    return list(dict.fromkeys(names))


def add_arguments(parser) -> None:
    parser.add_argument("--scenarios", default="all",
                        help=f"comma-separated scenarios: {', '.join(SCENARIOS)} (default: all)")
    parser.add_argument("--quick", action="store_true",
                        help="small grid (default, 4x coarser, depth_only, 2 ms, a 1/2-resolution reference), half "
                             "the simulated time, 1 timing repeat: about a minute")
    parser.add_argument("--repeats", type=int, default=3, help="timing repeats per configuration (default 3)")
    parser.add_argument("--out", default="bench_results", help="output folder (default ./bench_results)")


def main(args) -> int:
    names = parse_scenarios(args.scenarios)
    repeats = int(check_positive("repeats", args.repeats))
    output_dir(args.out)
    t0 = time.perf_counter()
    rows = run_study(names, quick=args.quick, repeats=repeats)
    paths = write_outputs(rows, args.out)
    print()
    print(markdown_table(rows))
    print(recommendation_text(rows))
    print(f"study took {time.perf_counter() - t0:.0f} s; wrote {paths['markdown']}, {paths['csv']}, {paths['png']}")
    return 0

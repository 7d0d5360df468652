"""Every validation case with ``GranularTerrain(solidify=f)`` on, side by side with the option off.

Each case of ``mjrft validate`` runs twice in one process, once as it is and once with every terrain the case
builds made with ``solidify=f`` (the default of ``GranularTerrain``'s ``solidify`` argument is swapped for the
run), and the checks that pass are listed for both.

Usage: ``python benchmarks/solidify_validation.py [--factor 2] [--quick] [--case NAME ...] [--out FILE]``
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings


def _run(name: str, quick: bool, factor: float):
    from mjrft import coupler
    from mjrft.tools.validation import run_case

    init = coupler.GranularTerrain.__init__
    if factor > 0.0:
        def patched(self, *a, **kw):
            if kw.get("yield_displacement") != 0:  # the viscous mode has no memory to solidify
                kw.setdefault("solidify", factor)
            init(self, *a, **kw)
        coupler.GranularTerrain.__init__ = patched
    try:
        t0 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = run_case(name, quick)
        return res, time.perf_counter() - t0
    finally:
        coupler.GranularTerrain.__init__ = init


def main(argv=None) -> int:
    from mjrft.tools.validation import case_names

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--factor", type=float, default=2.0)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--case", action="append", default=None)
    ap.add_argument("--out", default=None)
    args = ap.parse_args(argv)
    names = args.case or case_names()
    lines = [f"# python benchmarks/solidify_validation.py {' '.join(argv if argv is not None else sys.argv[1:])}",
             f"# validation checks passed, option off vs solidify={args.factor:g}; checks whose result changes listed"]
    tot = [0, 0, 0]

    def say(s):
        print(s, flush=True)
        lines.append(s)
        if args.out:
            with open(args.out, "w") as fh:
                fh.write("\n".join(lines) + "\n")

    for name in names:
        off, t_off = _run(name, args.quick, 0.0)
        on, t_on = _run(name, args.quick, args.factor)
        p_off = sum(c.passed for c in off.checks)
        p_on = sum(c.passed for c in on.checks)
        tot[0] += p_off
        tot[1] += p_on
        tot[2] += len(off.checks)
        say(f"{name}: off {p_off}/{len(off.checks)} ({t_off:.0f} s), on {p_on}/{len(on.checks)} ({t_on:.0f} s)")
        by_name = {c.name: c for c in on.checks}
        for c in off.checks:
            d = by_name.get(c.name)
            if d is None:
                continue
            if d.passed != c.passed or d.simulated != c.simulated:
                mark = "" if d.passed == c.passed else (" NOW PASSES" if d.passed else " NOW FAILS")
                say(f"    {c.name}: off {'pass' if c.passed else 'FAIL'} [{c.simulated}] -> on "
                    f"{'pass' if d.passed else 'FAIL'} [{d.simulated}]{mark}")
    say(f"total checks passed: off {tot[0]}/{tot[2]}, solidify={args.factor:g} {tot[1]}/{tot[2]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

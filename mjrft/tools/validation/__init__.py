"""Validation against the source papers: ``mjrft validate`` reruns their experiments and writes a report.

>>> from mjrft.tools import validation
>>> validation.case_names()                       # every registered case
>>> r = validation.run_case("li2013_plate", quick=True)
>>> r.verdict, [(c.name, c.published, c.simulated, c.verdict) for c in r.checks]
>>> validation.write_report(validation.run_cases(), "benchmarks/results/validation")

Layout: :mod:`~mjrft.tools.validation.case` defines a case, its checks and figures and the published-data
files (``data/<paper>.json``); :mod:`~mjrft.tools.validation.cases` holds one module per paper, each
registering its cases; :mod:`~mjrft.tools.validation.report` runs them and writes the Markdown report, one
PNG per case and a CSV of every number (``mjrft validate``).
"""

from __future__ import annotations

import importlib
import pkgutil

from .case import CASES, Case, CaseResult, Check, Datum, Line, Panel, case, papers, published

__all__ = ["CASES", "Case", "CaseResult", "Check", "Datum", "Line", "Panel", "case", "case_names", "load_cases",
           "papers", "published", "run_case", "run_cases", "write_report"]


def load_cases() -> dict[str, Case]:
    """Import every module of :mod:`mjrft.tools.validation.cases` (each registers its cases); returns the registry."""
    from . import cases

    for info in pkgutil.iter_modules(cases.__path__):
        importlib.import_module(f"{cases.__name__}.{info.name}")
    return CASES


def case_names() -> list[str]:
    return list(load_cases())


def run_case(name: str, quick: bool = False, variant: str | None = None) -> CaseResult:
    """Run case ``name`` (``variant``: one of its wrong-physics variants, ``CASES[name].variants``)."""
    from .report import run_case as _run

    return _run(name, quick, variant)


def run_cases(names=None, quick: bool = False, progress: bool = True) -> list[CaseResult]:
    from .report import run_cases as _run

    return _run(names, quick, progress)


def write_report(results, out: str) -> dict:
    from .report import write_report as _write

    return _write(results, out)

"""What a validation case is: published data with its source, the checks that compare it with mjrft, and plots.

A case is a function ``run(quick: bool) -> CaseResult`` registered with :func:`case`. It reruns one
published experiment under the paper's setup (``quick`` selects coarse settings that finish in
seconds, for the tests) and returns:

* ``checks``: one :class:`Check` per published number or outcome: what is compared, the published
  value with its source, the simulated value, the agreement metric and the tolerance, and whether it
  passed. ``qualitative=True`` marks the published *outcome* (an ordering, a sign, a ratio band)
  that the case's fast test asserts. Each check is of one of two kinds (``kind``): a *validation* check
  compares mjrft with something it was not built from and could come out either way; a
  *consistency* check (``consistency="why"``) holds by construction (a law linear in speed by
  definition, R^2 = 1 of a line through it) or compares with the very number a coefficient was
  calibrated from. Reports count the two separately, and only validation checks count as agreement
  with the papers;
* ``panels``: the figure, simulation and paper on the same axes (a :class:`Line` with a ``source`` is
  paper data and is drawn as markers, labelled with its source);
* ``cause``: for a case that does not agree, the cause found by measurement.

A case registered with ``variants`` also runs as ``run(quick, variant=name)`` under a named wrong
physics (:data:`WRONG_PHYSICS`: stresses doubled or halved, the depth-only law, no speed dependence, ...),
building its rigs from :func:`wrong_physics`, so that its own checks can be shown to reject physics the
paper's claims rule out (the tests' controls).

Published numbers live as data in ``mjrft/validation/data/<paper>.json`` (:func:`published`), each
with its value, unit and source (paper, figure or table), never only inside a case or a test.
"""

from __future__ import annotations

import functools
import json
import math
from dataclasses import dataclass, field
from importlib import resources
from typing import Callable, Sequence

from mjrft.errors import unknown

__all__ = ["CASES", "CONSISTENCY", "Case", "CaseResult", "Check", "Datum", "Line", "MUCH_LESS", "Panel", "SIMILAR",
           "UPRIGHT_TILT", "VALIDATION", "WRONG_PHYSICS", "case", "check_band", "check_close", "check_outcome", "papers",
           "published", "similar", "stress_scaled", "wrong_physics"]

VALIDATION = "validation"
CONSISTENCY = "consistency"

# ------------------------------------------------------------------------------------------------
# readings of the papers' words, applied to every case (documented in docs/validation.md)
# ------------------------------------------------------------------------------------------------
#: "similar" (two forces or speeds): a ratio within [1/1.2, 1.2]. Li 2013's own usage: a force change of
#: "less than 20 %" over 1 cm/s to 1 m/s is called negligible ("insensitive to speed", suppl. Materials
#: and Methods, plate intrusion); a larger difference is not "similar".
SIMILAR = 0.20
#: "<<" (much less than): at least 10 times below the bound (an order of magnitude).
MUCH_LESS = 10.0
#: "upright": the torso's tilt from vertical below 60 deg (its up axis nearer vertical than horizontal by a
#: margin; a choice, no paper gives a number). "Upside down" is a tilt past 90 deg.
UPRIGHT_TILT = math.radians(60.0)


# ------------------------------------------------------------------------------------------------
# published data
# ------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Datum:
    """One published number (or list of numbers, or a stated outcome) with its unit and source."""

    paper: str
    key: str
    value: object  # float, list of floats, dict of lists, or a sentence for a qualitative outcome
    unit: str
    source: str  # paper, figure or table (and page/equation where useful)
    note: str = ""

    def cite(self) -> str:
        return f"{self.source}" + (f" ({self.note})" if self.note else "")


@functools.lru_cache(maxsize=None)
def _data(paper: str) -> dict:
    try:
        text = resources.files("mjrft.tools.validation").joinpath("data", f"{paper}.json").read_text()
    except FileNotFoundError:
        raise unknown("paper", paper, papers()) from None
    raw = json.loads(text)
    return {"_paper": raw.get("_paper", paper), **{k: v for k, v in raw.items() if not k.startswith("_")}}


def papers() -> list[str]:
    """The papers that have a published-data file."""
    folder = resources.files("mjrft.tools.validation").joinpath("data")
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".json"))


def published(paper: str, key: str) -> Datum:
    """The published datum ``key`` of ``paper`` (file ``data/<paper>.json``: ``{key: {value, unit, source, note}}``)."""
    entries = _data(paper)
    if key not in entries or key == "_paper":
        raise unknown(f"published datum of {paper!r}", key, [k for k in entries if k != "_paper"])
    e = entries[key]
    return Datum(paper=paper, key=key, value=e["value"], unit=e.get("unit", ""), source=e["source"],
                 note=e.get("note", ""))


# ------------------------------------------------------------------------------------------------
# results
# ------------------------------------------------------------------------------------------------
@dataclass
class Check:
    """One comparison of mjrft with a published number or outcome."""

    name: str  # what is compared
    published: str  # the published value or outcome, as printed in the report
    simulated: str  # mjrft's value, as printed
    metric: str  # the agreement metric and its value, e.g. "relative error 4.1 %"
    tolerance: str  # the verdict's tolerance, e.g. "<= 25 %"
    passed: bool
    source: str  # paper, figure or table
    qualitative: bool = False  # the published outcome that the case's fast test asserts
    value: float = math.nan  # the simulated number behind ``simulated`` (CSV)
    reference: float = math.nan  # the published number behind ``published`` (CSV)
    kind: str = VALIDATION  # or CONSISTENCY: holds by construction / compares with its own calibration number
    why: str = ""  # for a consistency check: the construction or calibration that makes it hold

    def __post_init__(self):
        if self.kind not in (VALIDATION, CONSISTENCY):
            raise ValueError(f"check kind {self.kind!r}; valid: {VALIDATION}, {CONSISTENCY}")
        if self.kind == CONSISTENCY and not self.why:
            raise ValueError(f"consistency check {self.name!r} needs the reason it holds by construction (why)")

    @property
    def is_validation(self) -> bool:
        return self.kind == VALIDATION

    @property
    def verdict(self) -> str:
        return "pass" if self.passed else "FAIL"


@dataclass
class Line:
    """One curve of a panel; a line with a ``source`` is published data (drawn as markers)."""

    x: Sequence[float]
    y: Sequence[float]
    label: str
    source: str | None = None

    @property
    def is_paper(self) -> bool:
        return self.source is not None


@dataclass
class Panel:
    title: str
    xlabel: str
    ylabel: str
    lines: list[Line] = field(default_factory=list)


@dataclass
class CaseResult:
    name: str
    title: str
    paper: str  # short citation of the paper
    source: str  # figure / table / section reproduced
    setup: str  # the published setup as simulated (dimensions, kinematics, medium, law)
    checks: list[Check]
    panels: list[Panel] = field(default_factory=list)
    cause: str = ""  # for a case that does not agree: the cause, from a measurement
    notes: str = ""  # choices where the paper is silent
    seconds: float = math.nan  # wall time of the run (set by the runner)
    warnings: list[str] = field(default_factory=list)  # distinct warnings the run raised (set by the runner)

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.checks)

    @property
    def outcomes(self) -> list[Check]:
        """The published outcomes (``qualitative`` checks): what the case's fast test asserts."""
        return [c for c in self.checks if c.qualitative]

    @property
    def failed_outcomes(self) -> list[tuple[str, str, str]]:
        """(name, published, simulated) of each published outcome that did not pass."""
        return [(c.name, c.published, c.simulated) for c in self.outcomes if not c.passed]

    @property
    def validation_checks(self) -> list[Check]:
        return [c for c in self.checks if c.is_validation]

    @property
    def consistency_checks(self) -> list[Check]:
        return [c for c in self.checks if not c.is_validation]

    @property
    def by_name(self) -> dict[str, Check]:
        return {c.name: c for c in self.checks}

    @property
    def verdict(self) -> str:
        n = sum(c.passed for c in self.checks)
        return "pass" if n == len(self.checks) else f"FAIL ({len(self.checks) - n} of {len(self.checks)} checks)"


# ------------------------------------------------------------------------------------------------
# registry
# ------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Case:
    name: str
    title: str
    paper: str
    run: Callable[[bool], CaseResult]
    variants: tuple = ()  # the WRONG_PHYSICS variants ``run(quick, variant=...)`` accepts


CASES: dict[str, Case] = {}


def case(name: str, title: str, paper: str, variants: Sequence[str] = ()):
    """Register ``run(quick: bool) -> CaseResult`` as the validation case ``name``; ``variants``: the names of
    :data:`WRONG_PHYSICS` that ``run(quick, variant=name)`` can rerun the case under (its controls)."""

    def register(run):
        if name in CASES:
            raise ValueError(f"validation case {name!r} is registered twice")
        for v in variants:
            if v not in WRONG_PHYSICS:
                raise unknown("wrong-physics variant", v, list(WRONG_PHYSICS))
        CASES[name] = Case(name, title, paper, run, tuple(variants))
        return run

    return register


# ------------------------------------------------------------------------------------------------
# wrong physics (the controls every validation check must reject)
# ------------------------------------------------------------------------------------------------
#: Named wrong physics a case can be rerun under (``run(quick, variant=name)``), so that its own check functions
#: judge readings that the paper's claims must rule out. A case builds its rigs from :func:`wrong_physics`.
WRONG_PHYSICS = {
    "x2": "every granular stress of the medium doubled (the parameter slots GranularTerrain's stress_scale "
          "multiplies: Li's coefficients and zeta, xi_n, the depth-only and hybrid constants)",
    "x0.5": "every granular stress of the medium halved",
    "depth_only": "Li's depth-only law (suppl. eqs. S3-S7) on the same medium in place of the case's law: the "
                  "stress of a plate pushed down, blind to the element's orientation and direction of motion",
    "rate_independent": "Li RFT (law rft) on the same medium in place of a speed-dependent law: the stress the "
                        "medium's coefficients give at their calibration speed, at every speed",
    "rate_dependent": "SGRFT's wet law (Li RFT x a linear speed factor) on its saturated sand in place of a "
                      "rate-independent law",
    "no_undisturbed_rule": "the hybrid whole-leg model counting every element, its undisturbed-grain (shadow) rule "
                           "off (hybrid paper, sec. 3.2)",
}
_STRESS_FACTOR = {"x2": 2.0, "x0.5": 0.5}


def stress_scaled(medium, k: float):
    """``medium`` with every granular stress times ``k``: ``params()[STRESS_SLOTS]`` scale by ``k``, the rest
    (friction, speed factors, the water's drag and buoyancy) keeps its value."""
    import dataclasses

    from mjrft.media import get_medium

    from mjrft.laws.hybrid import GAMMA_S

    m = get_medium(medium)
    extra = dict(m.extra)
    if "hybrid_unit_weight" in extra:
        extra["hybrid_unit_weight"] = extra["hybrid_unit_weight"] * k  # the wedge's force is linear in it
    elif m.rho_bulk is None:
        extra["hybrid_unit_weight"] = GAMMA_S * k  # the hybrid law's default (else 9.81 x rho_bulk, scaled below)
    return dataclasses.replace(
        m, name=f"{m.name}_x{k:g}".replace(".", "p"), coeffs=tuple(c * k for c in m.coeffs), zeta=m.zeta * k,
        alpha_z_measured=None if m.alpha_z_measured is None else m.alpha_z_measured * k,
        grain_density=None if m.grain_density is None else m.grain_density * k,  # xi_n and C rho_bulk
        extra=tuple(sorted(extra.items())))


def wrong_physics(variant: str | None, medium, law: str):
    """The (medium, law) a case builds a rig from under the wrong-physics ``variant`` (None: unchanged)."""
    if variant is None:
        return medium, law
    if variant in _STRESS_FACTOR:
        return stress_scaled(medium, _STRESS_FACTOR[variant]), law
    if variant == "depth_only":
        return medium, "depth_only"
    if variant == "rate_independent":
        return medium, "rft" if law == "wet" else law
    if variant == "rate_dependent":
        return "sea_sand_saturated", "wet"
    if variant in WRONG_PHYSICS:
        return medium, law  # a variant of a model the case builds itself (e.g. no_undisturbed_rule)
    raise unknown("wrong-physics variant", variant, list(WRONG_PHYSICS))


# ------------------------------------------------------------------------------------------------
# checks
# ------------------------------------------------------------------------------------------------
def _fmt(x: float, unit: str = "") -> str:
    return f"{x:.4g}" + (f" {unit}" if unit else "")


def _kind(consistency: str) -> dict:
    return {"kind": CONSISTENCY, "why": consistency} if consistency else {}


def _tol(text: str, basis: str) -> str:
    return f"{text} ({basis})" if basis else text


def check_close(name: str, reference: Datum | float, simulated: float, rel_tol: float, *, source: str | None = None,
                unit: str | None = None, qualitative: bool = False, basis: str = "", consistency: str = "") -> Check:
    """``|simulated - published| <= rel_tol |published|`` (relative error). ``basis``: where the tolerance comes
    from, printed with it (e.g. "the paper's own prediction error, fig. 6"); ``consistency``: why the check holds
    by construction (makes it a consistency check)."""
    ref, src, unit = _ref(reference, source, unit)
    err = abs(simulated - ref) / abs(ref) if ref != 0 else math.inf
    return Check(name=name, published=_fmt(ref, unit), simulated=_fmt(simulated, unit),
                 metric=f"relative error {100 * err:.1f} %", tolerance=_tol(f"<= {100 * rel_tol:g} %", basis),
                 passed=bool(err <= rel_tol), source=src, qualitative=qualitative, value=float(simulated),
                 reference=ref, **_kind(consistency))


def check_band(name: str, simulated: float, low: float, high: float, *, published: str, source: str,
               unit: str = "", qualitative: bool = True, reference: float = math.nan, basis: str = "",
               consistency: str = "") -> Check:
    """``low <= simulated <= high``: a published ratio, sign or range, stated in ``published``."""
    ok = bool(low <= simulated <= high)
    return Check(name=name, published=published, simulated=_fmt(simulated, unit), metric="in band",
                 tolerance=_tol(f"[{_fmt(low)}, {_fmt(high)}]", basis), passed=ok, source=source,
                 qualitative=qualitative, value=float(simulated), reference=reference, **_kind(consistency))


def check_outcome(name: str, passed: bool, *, published: str, simulated: str, source: str,
                  qualitative: bool = True, metric: str = "outcome", tolerance: str = "as published",
                  consistency: str = "") -> Check:
    """A published qualitative outcome (an ordering, a sign) and what mjrft gives."""
    return Check(name=name, published=published, simulated=simulated, metric=metric, tolerance=tolerance,
                 passed=bool(passed), source=source, qualitative=qualitative, **_kind(consistency))


def similar(ratio: float) -> bool:
    """Two positive numbers with this ratio are "similar" (:data:`SIMILAR`)."""
    return bool(ratio > 0 and abs(math.log(ratio)) <= math.log(1 + SIMILAR))


def _ref(reference, source, unit):
    if isinstance(reference, Datum):
        return float(reference.value), source or reference.cite(), reference.unit if unit is None else unit
    if source is None:
        raise ValueError("a published number given as a float needs its source")
    return float(reference), source, unit or ""

"""The speed, depth and grain-size ranges over which each law's source calibrated it (each law's entry in
:mod:`mjrft.laws.registry` holds its ranges; they are defined here with their sources).

:class:`mjrft.GranularTerrain` checks a scene against these: the static quantities (the medium's grain
size, and for ``rft3d`` its bulk density and internal friction) at construction, the dynamic ones
(the deepest buried element and the fastest buried element) at each of the terrain's checks (every
``STABILITY_CHECK_EVERY`` steps or ``STABILITY_CHECK_SPAN`` of simulated time), and warns once per terrain per (law, quantity) with :class:`mjrft.errors.ValidityRangeWarning`
naming the law, the quantity, the value and the range. Outside a range the law still runs: its
force there is an extrapolation of the source's fit.

Ranges and their sources (``None``: no bound published):

* ``rft``, ``depth_only`` (Li, Zhang & Goldman 2013, suppl.): speed up to 1 m/s (plates measured at
  ~1 cm/s; "at v = 1 m/s, force only increased by less than 20 %", sec. 2); depth up to 9.53 cm
  (alpha fitted with the plate at |z| = 2.54, 5.08 and 7.62 cm, sec. 2; the 3.81 cm plate at attack
  angles up to 90 degrees reaches half its length, 1.91 cm, deeper); grain diameter 0.1 to 3.2 mm (the
  scaling routine's "~0.1 to ~1 mm", sec. 3, and the measured media of table S1 up to the 3.2 mm
  glass spheres).
* ``wet`` (SGRFT, MDPI 2022): speed up to 50 mm/s and depth up to 70 mm (the paper's tests,
  10-50 mm/s and 0-60 mm, with the 20 mm plate reaching 10 mm below its stated depth: the paper's
  definition of depth is in its lost fig. 2b); grains up to 1 mm (sea sand, "particle diameter <= 1 mm").
* ``hybrid`` (hybrid curved-leg model): speed up to 1 m/s (bar drags at 1-100 cm/s); depth up to
  4 cm (bar drags at 2, 3 and 4 cm; the semicircle leg, a = b = 4.5 cm under a 5 cm axle, reaches
  4 cm). One sand was tested (0.41 mm mean grain), so no grain-size range is claimed.
* ``rft3d`` (Agarwal, Goldman & Kamrin, "Mechanistic framework for reduced-order models in soft materials",
  PNAS 2023): the published example inputs, bulk density 1310 to 1700 kg/m^3 and internal friction 0.21 to
  1.07. Choice: its generic response is a quasi-static fit like Li's, so the same 1 m/s bound
  applies to speed; no depth or grain-size range is published, so none is checked.

With the inertial regime on (:mod:`mjrft.laws.inertial`), the dry laws' speed range is
``INERTIAL_SPEED``: up to 1.5 m/s, the leg speeds of the DynaRoACH paper's DEM-validated runs (legs of
1 cm radius, 2 cm from hip to tip, driven at up to 12 Hz: 2 pi x 12 Hz x 2 cm = 1.5 m/s; vertical
penetration "nearly 1 m/s", fig. 4B), from which the regime's coefficient comes.

Choice for every law: only the upper bound of speed is checked. Each stroke of a leg passes through
zero speed at its turning points and a resting body sits still, so a lower bound (SGRFT's 10 mm/s)
would warn in every scene and say nothing about the scene.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

__all__ = ["HYBRID_RANGES", "LI_RANGES", "RFT3D_RANGES", "Range", "WET_RANGES", "buried_extremes", "check_static",
           "dynamic_ranges", "static_quantity"]


@dataclass(frozen=True)
class Range:
    """``low <= value <= high`` (either bound ``None``: open) for one quantity of one law."""

    quantity: str  # "speed", "depth", "grain_diameter", "rho_bulk", "mu_int"
    low: float | None
    high: float | None
    unit: str
    source: str
    scale: float = 1.0  # printed value = SI value x scale (e.g. 1e3 for mm)
    shown_unit: str = ""

    def contains(self, value: float) -> bool:
        return (self.low is None or value >= self.low) and (self.high is None or value <= self.high)

    def describe(self) -> str:
        u = self.shown_unit or self.unit
        lo = "" if self.low is None else f"{self.low * self.scale:g}"
        hi = "" if self.high is None else f"{self.high * self.scale:g}"
        if self.low is None:
            return f"<= {hi} {u}"
        if self.high is None:
            return f">= {lo} {u}"
        return f"{lo} to {hi} {u}"

    def message(self, law: str, value: float, where: str = "") -> str:
        u = self.shown_unit or self.unit
        return (f"mjrft: law '{law}': {LABELS.get(self.quantity, self.quantity)} {value * self.scale:.3g} {u}{where} is outside "
                f"the range its source calibrated, {self.describe()} ({self.source}); the force there is an "
                "extrapolation of the fit")


LABELS = {"speed": "speed", "depth": "depth", "grain_diameter": "grain diameter", "rho_bulk": "bulk density",
          "mu_int": "internal friction"}
_LI = "Li 2013 suppl."
_SG = "SGRFT (MDPI 2022)"
#: ``rft`` and ``depth_only``: Li's fit
LI_RANGES = (
    Range("speed", None, 1.0, "m/s", f"{_LI} sec. 2: force within 20 % from 1 cm/s to 1 m/s"),
    Range("depth", None, 0.0762 + 0.0381 / 2, "m", f"{_LI} sec. 2: alpha fitted with the plate at depths 2.54, 5.08 "
          "and 7.62 cm, its 3.81 cm length reaching 1.91 cm deeper", 100.0, "cm"),
    Range("grain_diameter", 0.1e-3, 3.2e-3, "m", f"{_LI} sec. 3 scaling routine ~0.1 to ~1 mm, table S1 media up to "
          "3.2 mm", 1e3, "mm"),
)
WET_RANGES = (Range("speed", None, 0.050, "m/s", f"{_SG}: tests at 10-50 mm/s", 1e3, "mm/s"),
              Range("depth", None, 0.070, "m", f"{_SG}: tests at 0-60 mm with a 20 mm plate", 1e3, "mm"),
              Range("grain_diameter", None, 1e-3, "m", f"{_SG}: sea sand, particle diameter <= 1 mm", 1e3, "mm"))
HYBRID_RANGES = (Range("speed", None, 1.0, "m/s", "hybrid model: bar drags at 1-100 cm/s"),
                 Range("depth", None, 0.04, "m", "hybrid model: bar drags at 2-4 cm, legs reaching 4 cm", 100.0, "cm"))
_AGARWAL = "Agarwal, Goldman & Kamrin, PNAS 2023: the 3D-RFT example inputs"
RFT3D_RANGES = (Range("speed", None, 1.0, "m/s", "quasi-static like Li's fit (mjrft's choice; Agarwal 2023 gives "
                      "none)"),
                Range("rho_bulk", 1310.0, 1700.0, "kg/m^3", _AGARWAL),
                Range("mu_int", 0.21, 1.07, "", _AGARWAL))
INERTIAL_SPEED = Range("speed", None, 2 * math.pi * 12.0 * 0.02, "m/s",
                       "inertial regime: DynaRoACH paper, legs 2 cm hip to tip at up to 12 Hz, penetration up to "
                       "~1 m/s (fig. 4B)")
STATIC = ("grain_diameter", "rho_bulk", "mu_int")
DYNAMIC = ("speed", "depth")


def static_quantity(medium, quantity: str) -> float | None:
    """The medium's value of a static quantity (SI), or None when it is unknown.

    Grain diameter: the medium's mean ``grain_diameter``, else its ``grain_diameter_max`` constant
    (a medium known only by an upper bound, e.g. SGRFT's sea sand, "<= 1 mm").
    """
    if quantity == "grain_diameter":
        d = medium.grain_diameter
        return d if d is not None else medium.get("grain_diameter_max")
    if quantity == "rho_bulk":
        return medium.rho_bulk
    if quantity == "mu_int":
        return medium.mu_int
    raise ValueError(f"unknown static quantity {quantity!r}; valid choices: {', '.join(STATIC)}")


def _law(name: str):
    """The law's entry in :mod:`mjrft.laws.registry` (imported here: the table imports the ranges above)."""
    from .registry import get_law

    return get_law(name)


def check_static(law: str, medium) -> list[tuple[Range, float]]:
    """The (range, value) pairs of ``law``'s static ranges that ``medium`` leaves."""
    out = []
    for r in _law(law).ranges:
        if r.quantity in STATIC:
            v = static_quantity(medium, r.quantity)
            if v is not None and math.isfinite(v) and not r.contains(v):
                out.append((r, float(v)))
    return out


#: a medium calibrated for the saturated-sand law carries this constant (its speed factor; mjrft.laws.wet)
SATURATED_CALIBRATION = "wet_eps_v"


def check_medium(law: str, medium) -> str | None:
    """The warning for a saturated law (``wet``) on a medium that carries no saturated-sand calibration (no
    :data:`SATURATED_CALIBRATION` among its constants: a dry medium, whose stresses would take SGRFT's sea-sand
    speed factor), or None."""
    if not _law(law).saturated or law == "water" or medium.get(SATURATED_CALIBRATION) is not None:
        return None
    return (f"mjrft: law '{law}' is SGRFT's saturated sand, and medium '{medium.name}' carries no saturated-sand "
            f"calibration (no {SATURATED_CALIBRATION} among its constants: a dry medium): its stresses get the sea "
            "sand's speed factor (SGRFT, MDPI 2022, table 3) and the water's constants; use a saturated medium "
            "('sea_sand_saturated', or one with the wet_* constants of mjrft.laws.wet) or a dry law ('rft')")


def dynamic_ranges(law: str, inertial: bool = False) -> tuple[Range, ...]:
    """The depth and speed ranges of ``law``; with ``inertial`` (a dry law with the inertial regime on) the
    speed range is :data:`INERTIAL_SPEED`."""
    entry = _law(law)
    out = tuple(r for r in entry.ranges if r.quantity in DYNAMIC)
    if inertial and entry.dry:
        out = tuple(INERTIAL_SPEED if r.quantity == "speed" else r for r in out)
    return out


@njit(cache=True, error_model="numpy")
def buried_extremes(depth, vel, region, in_group):
    """(deepest depth, largest speed) over the elements with ``depth > 0`` whose ``region`` has
    ``in_group[region]`` set; (0, 0) when there is none. One pass, no temporaries."""
    dmax = 0.0
    v2max = 0.0
    for i in range(depth.shape[0]):
        d = depth[i]
        if d > 0.0 and in_group[region[i]]:
            if d > dmax:
                dmax = d
            v2 = vel[i, 0] * vel[i, 0] + vel[i, 1] * vel[i, 1] + vel[i, 2] * vel[i, 2]
            if v2 > v2max:
                v2max = v2
    return dmax, math.sqrt(v2max)


def group_mask(n_regions: int, ids) -> np.ndarray:
    """Boolean mask over region ids for :func:`buried_extremes`."""
    m = np.zeros(n_regions, dtype=np.bool_)
    m[np.asarray(ids, dtype=np.int64)] = True
    return m

"""Errors and warnings raised by mjrft, with helpers that name the bad value and the valid choices."""

from __future__ import annotations

import math
from collections.abc import Iterable


class MjrftError(Exception):
    """Base class of mjrft's own errors."""


class UnknownNameError(MjrftError, ValueError, KeyError):
    """A medium, law, geom, body or model name that does not exist."""

    def __str__(self) -> str:  # KeyError would otherwise quote the message
        return str(self.args[0]) if self.args else ""


class NonFiniteError(MjrftError, FloatingPointError):
    """A force or state became NaN or infinite; raised instead of writing it into MuJoCo."""


class TerrainStabilityWarning(RuntimeWarning):
    """The timestep is beyond the explicit-integration stability limit of the granular stiffness."""


class SandContactWarning(UserWarning):
    """A set-up in which the robot may not meet the sand: a rigid collision floor it can still stand on, or
    selected geoms that never reach the sand surface."""


class ValidityRangeWarning(RuntimeWarning):
    """A scene leaves the speed, depth or grain-size range a law's source calibrated (:mod:`mjrft.laws.validity`)."""


def unknown(kind: str, value, choices: Iterable[str]) -> UnknownNameError:
    """Build the error for an unknown ``kind`` name, listing every valid choice."""
    choices = sorted(str(c) for c in choices)
    return UnknownNameError(f"unknown {kind} {value!r}; valid choices: {', '.join(choices)}")


def check_positive(name: str, value, *, allow_zero: bool = False) -> float:
    """Return ``value`` as float if it is finite and positive (or zero when allowed), else raise ValueError."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        bound = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"{name} must be finite and {bound}, got {value!r}")
    return v


def check_finite(name: str, value) -> float:
    """Return ``value`` as float if it is finite, else raise ValueError."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return v

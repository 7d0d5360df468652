"""The force laws, one :class:`Law` entry each in :data:`LAWS`: everything else about a law is derived from it.

An entry names the law, its integer id in the compiled kernels, its per-element stress function, the slots of a
medium's parameter vector it reads that hold grain stresses, the function that writes its own constants into
that vector, whether it is dry (takes the inertial regime) or saturated (water at least up to the sand surface),
and the ranges its source calibrated. From the table come :data:`LAW_IDS`, :data:`DRY_LAWS`, :data:`STRESS_SLOTS`,
the compiled dispatch (:func:`mjrft.laws.dispatch.element_stress`, generated from the entries and compiled by
numba), the parameter vector (:func:`parameter_vector`: the medium's constants and each law's, :func:`fill_params`),
the validity checks (:mod:`mjrft.laws.validity`) and the laws of the JAX path (:data:`mjrft.mjx.laws.LAWS` and
:data:`mjrft.mjx.laws.UNSUPPORTED`, from each entry's ``jax`` or ``no_jax``).

Adding a law: write its module (a compiled ``*_stress(depth, nx, ny, nz, mx, my, mz, speed, p)`` returning the
stress in Pa on one element, m the unit motion direction, speed in m/s, p the parameter vector; its constants
in slots from ``mjrft.params.P_FIRST_FREE`` on, named in :mod:`mjrft.params`) and append its entry here with the next id;
with a JAX twin (a function ``f(depth, n, m, p, speed=None)`` in :mod:`mjrft.mjx.laws`) the entry names it in
``jax``, without one it says in ``no_jax`` why mjrft.mjx refuses the law.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..errors import unknown
from ..params import (P_AX_DRAG, P_AZ_DOWN, P_AZ_UP, P_COEFF, P_HYB_E0, P_HYB_E1, P_HYB_E2, P_HYB_PAR_H, P_HYB_PERP_H,
                      P_INERTIA, P_SIZE, P_XI, P_ZETA)
from .depth_only import depth_only_stress
from .hybrid import hybrid_params, hybrid_stress
from .rft import rft_stress
from .rft3d import rft3d_stress
from .validity import HYBRID_RANGES, LI_RANGES, RFT3D_RANGES, WET_RANGES, Range
from .wet import water_stress, wet_params, wet_stress


@dataclass(frozen=True)
class Law:
    """One force law (module docstring). ``id``: its branch in the compiled kernels (stable: a new law takes the
    next one). ``stress_slots``: the slots of the parameter vector it reads that hold grain stresses, which
    ``stress_scale`` multiplies (:meth:`mjrft.GranularTerrain.set_medium`); friction coefficients, ratios, speed
    factors and the water's constants are not among them. ``params``: ``f(medium, p)`` writing the law's own
    constants into the parameter vector ``p`` (None: it reads only the medium's). ``dry``: the inertial regime
    (:mod:`mjrft.laws.inertial`) applies to it. ``saturated``: the water table is at least at the sand surface
    (buoyancy applies without a water layer). ``ranges``: what its source calibrated (:mod:`mjrft.laws.validity`).
    ``jax``: the name of its JAX twin in :mod:`mjrft.mjx.laws`; without one (None) ``no_jax`` says why the JAX path
    refuses the law."""

    name: str
    id: int
    stress: Callable
    stress_slots: tuple[int, ...] = ()
    params: Callable | None = None
    dry: bool = False
    saturated: bool = False
    ranges: tuple[Range, ...] = ()
    jax: str | None = None
    no_jax: str = ""


_LI_SLOTS = (*range(P_COEFF, P_COEFF + 9), P_ZETA)  # Li's nine Fourier coefficients and the scaling factor zeta

LAWS: tuple[Law, ...] = (
    Law("rft", 0, rft_stress, _LI_SLOTS, dry=True, ranges=LI_RANGES, jax="rft"),
    Law("rft3d", 1, rft3d_stress, (P_XI,), dry=True, ranges=RFT3D_RANGES, jax="rft3d"),
    Law("depth_only", 2, depth_only_stress, (P_AZ_DOWN, P_AZ_UP, P_AX_DRAG), dry=True, ranges=LI_RANGES,
        jax="depth_only"),
    Law("wet", 3, wet_stress, _LI_SLOTS, wet_params, saturated=True, ranges=WET_RANGES, jax="wet"),
    Law("water", 4, water_stress, (), wet_params, saturated=True, jax="water"),  # the free-water layer above the sand
    Law("hybrid", 5, hybrid_stress, (P_HYB_E0, P_HYB_E1, P_HYB_E2, P_HYB_PERP_H, P_HYB_PAR_H), hybrid_params,
        ranges=HYBRID_RANGES, jax="hybrid"),
)
_BY_NAME = {law.name: law for law in LAWS}
if sorted(law.id for law in LAWS) != list(range(len(LAWS))) or len(_BY_NAME) != len(LAWS):
    raise RuntimeError("mjrft.laws.registry.LAWS: law names must be unique and ids 0, 1, 2, ... without gaps")
if any((law.jax is None) == (not law.no_jax) for law in LAWS):
    raise RuntimeError("mjrft.laws.registry.LAWS: each law names its JAX twin (jax) or says why it has none (no_jax)")

#: law name -> kernel id
LAW_IDS: dict[str, int] = {law.name: law.id for law in LAWS}
#: the laws that take the inertial regime
DRY_LAWS: tuple[str, ...] = tuple(law.name for law in LAWS if law.dry)
#: every slot of a region's parameter vector that holds a granular stress: the laws' and the inertial regime's
#: ``C rho_bulk`` (kg/m^3); ``stress_scale`` multiplies these
STRESS_SLOTS = np.array(sorted({*(s for law in LAWS for s in law.stress_slots), P_INERTIA}), dtype=np.int64)
_PARAM_FUNCTIONS = tuple(dict.fromkeys(law.params for law in LAWS if law.params is not None))


def get_law(name) -> Law:
    """The :class:`Law` called ``name``; an unknown name raises an error listing the valid ones."""
    if isinstance(name, str) and name in _BY_NAME:
        return _BY_NAME[name]
    raise unknown("law", name, _BY_NAME)


def fill_params(medium, p: np.ndarray) -> None:
    """Write every law's own constants for ``medium`` into its parameter vector ``p`` (each law's ``params``)."""
    for fill in _PARAM_FUNCTIONS:
        fill(medium, p)


def parameter_vector(medium) -> np.ndarray:
    """The float64 parameter vector (layout :mod:`mjrft.params`) of a :class:`~mjrft.media.Medium`: its own constants
    (:meth:`~mjrft.media.Medium.own_params`), then each law's (:func:`fill_params`); the water layer and the
    inertial regime are the region's (:func:`mjrft.regions.build_regions`)."""
    p = medium.own_params(np.zeros(P_SIZE))
    fill_params(medium, p)
    return p


__all__ = ["DRY_LAWS", "LAWS", "LAW_IDS", "STRESS_SLOTS", "Law", "fill_params", "get_law", "parameter_vector"]

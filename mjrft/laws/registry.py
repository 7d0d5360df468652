"""Law names, their integer ids in the compiled kernels, and hooks that fill law constants into a medium's parameter vector."""

from __future__ import annotations

# name -> id used by mjrft.laws.dispatch.element_stress. Ids are stable; add new laws at the end.
LAW_IDS: dict[str, int] = {
    "rft": 0,
    "rft3d": 1,
    "depth_only": 2,
    "wet": 3,  # mjrft.laws.wet (params slots 15-21)
    "water": 4,  # mjrft.laws.wet (water layer, depth < 0)
    "hybrid": 5,  # mjrft.laws.hybrid (params slots 22-30)
}

# Functions f(medium, params) called by Medium.params() so that a law can store its own constants.
PARAM_HOOKS: list = []

"""The parameter vector's layout (mjrft.params): every named slot distinct and inside the vector, and the vector
that mjrft.laws.registry.parameter_vector builds for a medium holds the medium's constants in the named slots."""

from __future__ import annotations

import numpy as np

from mjrft import params
from mjrft.laws.registry import parameter_vector
from mjrft.media import MEDIA
from mjrft.params import P_AX_DRAG, P_AZ_DOWN, P_AZ_UP, P_COEFF, P_FIRST_FREE, P_MU_S, P_SIZE, P_XI, P_ZETA

#: every named slot (the nine Li coefficients from P_COEFF on)
SLOTS = {n: v for n, v in vars(params).items() if n.startswith("P_") and n not in ("P_SIZE", "P_FIRST_FREE")}


def test_the_named_slots_are_distinct_and_inside_the_vector():
    taken = [*range(P_COEFF, P_COEFF + 9), *(v for n, v in SLOTS.items() if n != "P_COEFF")]
    assert len(SLOTS) > 25 and all(isinstance(v, int) for v in SLOTS.values())
    assert len(taken) == len(set(taken)), "two names share a slot"
    assert 0 <= min(taken) and max(taken) < P_SIZE
    # the medium's own constants come first; the laws' own constants start at P_FIRST_FREE
    assert max(P_COEFF + 8, P_XI, P_MU_S, P_ZETA, P_AZ_DOWN, P_AZ_UP, P_AX_DRAG) == P_FIRST_FREE - 1


def test_parameter_vector_holds_the_medium_in_the_named_slots():
    poppy = MEDIA["poppy_cp"]
    p = parameter_vector(poppy)
    assert p.shape == (P_SIZE,) and p.dtype == np.float64
    assert np.array_equal(p[P_COEFF:P_COEFF + 9], poppy.coeffs)
    assert (p[P_XI], p[P_MU_S], p[P_ZETA]) == (poppy.xi_n, poppy.mu_surface, poppy.zeta)
    assert (p[P_AZ_DOWN], p[P_AZ_UP], p[P_AX_DRAG]) == tuple(poppy.depth_only_alphas)
    # control: another medium differs in its stress slots, not in its friction with the leg
    glass = MEDIA["glass3_cp"]
    q = parameter_vector(glass)
    assert not np.array_equal(q[P_COEFF:P_COEFF + 9], p[P_COEFF:P_COEFF + 9])
    assert q[P_MU_S] == glass.mu_surface

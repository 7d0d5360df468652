"""The table of laws (mjrft.laws.registry) and what is derived from it: ids, dry laws, stress slots, the compiled
dispatch, the parameter vector's law constants and the validity ranges."""

from __future__ import annotations

import re

import numpy as np
import pytest

from mjrft.errors import UnknownNameError
from mjrft.laws import DRY_LAWS, LAW_IDS, law_id
from mjrft.laws import registry as R
from mjrft.laws.dispatch import _dispatch_source, element_stress
from mjrft.laws.validity import INERTIAL_SPEED, dynamic_ranges
from mjrft.media import MEDIA
from mjrft.params import (P_AX_DRAG, P_AZ_DOWN, P_AZ_UP, P_HYB_E0, P_HYB_E1, P_HYB_E2, P_HYB_PAR_H, P_HYB_PERP_H,
                          P_INERTIA, P_SIZE, P_XI, P_ZETA)
from mjrft.laws.registry import parameter_vector


def test_ids_and_names_come_from_the_table():
    assert LAW_IDS == {"rft": 0, "rft3d": 1, "depth_only": 2, "wet": 3, "water": 4, "hybrid": 5}  # stable ids
    assert DRY_LAWS == ("rft", "rft3d", "depth_only")
    assert [law.name for law in R.LAWS if law.saturated] == ["wet", "water"]
    assert law_id("hybrid") == R.get_law("hybrid").id == 5
    with pytest.raises(UnknownNameError, match="unknown law 'mud'; valid choices: depth_only, hybrid, rft, rft3d"):
        R.get_law("mud")


def test_stress_slots_are_the_laws_and_the_inertial_regimes():
    expected = [*range(9), P_XI, P_ZETA, P_AZ_DOWN, P_AZ_UP, P_AX_DRAG, P_HYB_E0, P_HYB_E1, P_HYB_E2, P_HYB_PERP_H,
                P_HYB_PAR_H, P_INERTIA]
    assert R.STRESS_SLOTS.tolist() == sorted(expected) and R.STRESS_SLOTS.dtype == np.int64


def test_dispatch_has_one_branch_per_law_and_calls_its_stress_function():
    src = _dispatch_source()
    assert [line.strip() for line in src.splitlines() if line.strip().startswith("if law ==")] == [
        f"if law == {law.id}:" for law in R.LAWS]
    p = parameter_vector(MEDIA["poppy_cp"])
    args = (0.02, 0.3, 0.0, -0.95, 0.6, 0.0, -0.8, 0.01, p)
    for law in R.LAWS:
        # the dispatch may be compiled with its callee inlined (fastmath contraction): equal to rounding
        np.testing.assert_allclose(element_stress(law.id, *args), law.stress(*args), rtol=1e-12, atol=1e-12,
                                   err_msg=law.name)
    assert element_stress(len(R.LAWS), *args) == (0.0, 0.0, 0.0)  # no such law: nothing
    assert element_stress(0, *args) != element_stress(1, *args)  # control: the ids reach different laws


def test_params_hold_each_laws_own_constants():
    med = MEDIA["sea_sand_saturated"]
    p = parameter_vector(med)
    for law in R.LAWS:
        if law.params is not None:
            q = np.zeros(P_SIZE)
            law.params(med, q)
            own = q != 0
            assert own.any() and np.array_equal(p[own], q[own]), law.name
    q = np.zeros(P_SIZE)
    R.fill_params(med, q)
    assert np.array_equal(q[15:32], p[15:32])


def test_validity_lookups_follow_the_table():
    for law in R.LAWS:
        speed = [r for r in dynamic_ranges(law.name, inertial=True) if r.quantity == "speed"]
        assert (speed == [INERTIAL_SPEED]) == (law.dry and bool(law.ranges)), law.name
    assert dynamic_ranges("wet", inertial=True) == tuple(r for r in R.get_law("wet").ranges
                                                         if r.quantity in ("speed", "depth"))


def test_jax_laws_come_from_the_table():
    """mjrft.mjx's laws are the entries that name a JAX twin (every law now); another name is refused."""
    pytest.importorskip("jax", reason="mjrft.mjx needs the optional extra mjrft[mjx] (JAX)")
    from mjrft.mjx import laws as J

    assert list(J.LAWS) == ["rft", "rft3d", "depth_only", "wet", "water", "hybrid"]
    assert J.UNSUPPORTED == {law.name: law.no_jax for law in R.LAWS if law.jax is None} == {}
    for law in R.LAWS:
        assert J.law_function(law.name) is getattr(J, law.jax), law.name
    why = re.escape("law 'sand' has no JAX version (it is not a law of mjrft); mjrft.mjx supports rft, rft3d, "
                    "depth_only, wet, water, hybrid")
    with pytest.raises(NotImplementedError, match=why):
        J.law_function("sand")

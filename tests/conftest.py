"""Fixtures shared by the test modules. Shared plain helpers and constants (used in ``parametrize`` lists, which
fixtures cannot feed) are in tests/helpers.py; no test module imports another."""

from __future__ import annotations

import numpy as np
import pytest


@pytest.fixture
def run_both():
    """``run_both(a, b, steps, seed=0, reset_seed=5)``: the same seeds and random actions into two vector envs, every
    returned value asserted identical; returns how many sub-episodes ended (terminated or truncated)."""
    from gymnasium.utils.env_checker import data_equivalence

    def run(a, b, steps, seed=0, reset_seed=5):
        out_a, out_b = a.reset(seed=reset_seed), b.reset(seed=reset_seed)
        assert data_equivalence(out_a, out_b)
        rng = np.random.default_rng(seed)
        ended = 0
        for _ in range(steps):
            actions = rng.uniform(-1, 1, size=a.action_space.shape).astype(np.float32)
            out_a, out_b = a.step(actions), b.step(actions)
            for x, y in zip(out_a, out_b):
                assert data_equivalence(x, y, exact=True), (x, y)
            ended += int(np.sum(out_a[2] | out_a[3]))
        return ended

    return run


@pytest.fixture(scope="session")
def quick_run():
    """``quick_run(name)``: the quick-settings result of validation case ``name``, run once per session and shared by
    the test modules of tests/mjrft/tools/validation/."""
    from mjrft.tools import validation

    results = {}

    def run(name: str):
        if name not in results:
            results[name] = validation.run_case(name, quick=True)
        return results[name]

    return run

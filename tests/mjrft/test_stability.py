"""The stability checks (mjrft.stability) on given inputs. The chatter check on given force sequences
(:func:`mjrft.stability.track_chatter`, :func:`chattering`, docs/numerics.md, "Chatter"): a force alternating by more
than CHATTER_AMPLITUDE for CHATTER_STEPS steps is reported, a monotone or a slightly alternating one is not; the
robots are in tests/models/test_quadrupeds.py. The compiled largest rate of the stability limit against numpy; the
limit on stepped bodies is in tests/mjrft/test_extremes.py."""

from __future__ import annotations

import numpy as np
import pytest

from mjrft.stability import CHATTER_AMPLITUDE, CHATTER_STEPS, TRACK_SLOTS, chatter_warning, chattering, track_chatter


def run(forces) -> list:
    """Feed body 1's force sequence (n x 3) to track_chatter; what chattering reports after it."""
    wrench = np.zeros((2, 6))
    slots = np.zeros((2, TRACK_SLOTS, 10))
    bodies = np.array([1])
    for f in forces:
        wrench[1, :3] = f
        track_chatter(wrench, bodies, slots)
    return chattering(slots, bodies)


def alternating(n: int, amplitude: float, mean=(0.0, 0.0, 100.0)) -> np.ndarray:
    sign = np.where(np.arange(n) % 2 == 0, 1.0, -1.0)
    return np.asarray(mean) + amplitude * np.outer(sign, [0.0, 0.0, 100.0])


def test_alternating_force_is_reported_with_its_size():
    found = run(alternating(2 * CHATTER_STEPS, 0.5))  # 100 N +- 50 N: 150 and 50
    assert len(found) == 1
    body, steps, change, force = found[0]
    assert body == 1 and steps >= CHATTER_STEPS and change > 0.5 and force == 150.0
    text = str(chatter_warning("foot", 1.0, 0.005, steps, change, force, implicit=False))
    assert "'foot'" in text and "timestep 0.005 s" in text and "implicit=True" in text


def test_record_is_cleared_by_each_report():
    wrench = np.zeros((2, 6))
    slots = np.zeros((2, TRACK_SLOTS, 10))
    for f in alternating(2 * CHATTER_STEPS, 0.5):
        wrench[1, :3] = f
        track_chatter(wrench, np.array([1]), slots)
    assert chattering(slots, [1]) and not chattering(slots, [1])


def test_controls_a_short_a_small_and_a_smooth_change_are_not_reported():
    assert not run(alternating(CHATTER_STEPS, 0.5))  # too few reversals (the first change has no predecessor)
    assert not run(alternating(4 * CHATTER_STEPS, 0.5 * CHATTER_AMPLITUDE))  # below the amplitude
    t = np.linspace(0.0, 1.0, 200)[:, None]
    assert not run(100.0 + np.hstack([0 * t, 0 * t, 30.0 * np.sin(2 * np.pi * 3 * t)]))  # a gait's smooth load
    # a step change and a decaying ring-down over fewer than CHATTER_STEPS reversals
    ring = np.concatenate([np.full(10, 100.0), 100.0 + 40.0 * (-0.5) ** np.arange(12)])
    assert not run(np.hstack([np.zeros((len(ring), 2)), ring[:, None]]))


def test_compiled_rate_matches_numpy():
    """stability.largest_rate (compiled: Cholesky + Jacobi, no BLAS) is lambda_max(W6 K6) of explicit springs."""
    from mjrft import stability

    rng = np.random.default_rng(1)
    for _ in range(50):
        nv = int(rng.integers(1, 12))
        jac = rng.normal(size=(6, nv))
        a = rng.normal(size=(nv, nv))
        minv_jac = np.linalg.solve(a @ a.T + 0.1 * np.eye(nv), jac.T).T
        r, k = rng.normal(size=(20, 3)) * 0.05, rng.uniform(0, 1e4, 20)
        k6 = np.zeros((6, 6))
        for ki, ri in zip(k, r):
            x = np.array([[0, -ri[2], ri[1]], [ri[2], 0, -ri[0]], [-ri[1], ri[0], 0]])
            k6 += ki * np.block([[np.eye(3), -x], [x, -x @ x]])
        moments = np.array([k.sum(), *(k[:, None] * r).sum(0),
                            *[np.sum(k * r[:, i] * r[:, j]) for i, j in ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))]])
        expected = np.max(np.linalg.eigvals(jac @ minv_jac.T @ k6).real)
        assert stability.largest_rate(jac, minv_jac, moments) == pytest.approx(expected, rel=1e-8)

"""The physics-step study's outcomes (benchmarks/env_timestep.py, benchmarks/power_timestep.py), each with a control."""

import importlib.util
import warnings
from pathlib import Path

import gymnasium
import numpy as np
import pytest

import mjrft.envs  # noqa: F401
from mjrft import TerrainStabilityWarning
from mjrft.train.evaluate import evaluate

BENCH = Path(__file__).resolve().parents[2] / "benchmarks"


def _load(name):
    spec = importlib.util.spec_from_file_location(name, BENCH / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


POWER = _load("power_timestep")


@pytest.mark.parametrize("integrator", POWER.INTEGRATORS)
@pytest.mark.parametrize("ctrl,v", POWER.HINGE_CASES)
def test_the_applied_force_rule_is_mujocos_step(integrator, ctrl, v):
    stepped, applied, f = POWER.hinge_step(integrator, ctrl, v)
    assert stepped == pytest.approx(applied, rel=1e-6)
    # control: the start state's force is what the implicit integrators apply only where the force is clamped
    unclamped_implicit = integrator != "Euler" and ctrl < 1.0
    assert (stepped == pytest.approx(f, rel=1e-6)) is not unclamped_implicit


def _biped(dt, implicit, policy="rect", seconds=6.0):
    kw = dict(timestep=dt, frame_skip=round(0.01 / dt), implicit=implicit, pitch_free=False, episode_seconds=seconds)
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always", TerrainStabilityWarning)
        _, s = evaluate(policy, "mjrft/BipedSand-v0", episodes=1, env_kwargs=kw)
    return s, sum(issubclass(w.category, TerrainStabilityWarning) for w in rec)


def test_the_biped_keeps_its_gait_at_2_ms_with_the_implicit_step_and_the_explicit_step_warns():
    ref, _ = _biped(0.0001, False)  # within 0.01 % of the study's 0.05 ms reference
    implicit, warned = _biped(0.002, True)
    assert warned == 0
    assert implicit["speed"] == pytest.approx(ref["speed"], rel=0.02)
    assert implicit["sink_mean_mm"] == pytest.approx(ref["sink_mean_mm"], rel=0.02)
    # control: random actions take the explicit step at 2 ms past the feet's stability limit
    study = _load("env_timestep")
    _, warned = _biped(0.002, False, policy=study.RandomActions(8))
    assert warned > 0


def test_the_humanoid_keeps_the_explicit_step_that_holds_the_one_foot_stance():
    # benchmarks/stance_timestep.py: on the 30.4 cm board with the CoM over the sole's centre the explicit 1 ms
    # step (the env's default) stands the 10 s; the implicit step at 2 ms, within the gait budget, falls at ~7.6 s
    import math

    from mjrft.envs.humanoid import HumanoidSand
    from mjrft.tools.validation.cases.thesis_hubo import HOLD_END, run_trial

    assert not HumanoidSand.sand_implicit
    assert math.isnan(run_trial("stance:com_x=0.0,lift=0.1", 0.304, False, HOLD_END)[3])
    fall = run_trial("stance:com_x=0.0,lift=0.1", 0.304, False, HOLD_END,
                     env_kwargs=dict(timestep=0.002, frame_skip=5, implicit=True))[3]
    assert 5.0 < fall < HOLD_END

"""Validation cases thesis_hubo_stance and thesis_hubo_gait (the robophysics thesis' HUBO), with the humanoid's stance
and shift gaits they drive: each case's outcome test, known disagreements and wrong-physics controls, registered by
case name (:class:`helpers.CaseTests`; ``tests/mjrft/tools/validation/test_validation.py`` holds the framework's
tests and the controls that rerun cases under a wrong physics)."""

from __future__ import annotations

import math

import gymnasium
import numpy as np
import pytest

import mjrft.envs  # noqa: F401  (registers the envs)
from mjrft.tools.gaits import (GAITS, humanoid_com_sole, humanoid_static_targets, make_gait, parse_gait_spec,
                               shift_fraction, stance_pose)
from mjrft.tools.validation import published
from mjrft.tools.validation.cases import thesis_hubo

from helpers import CaseTests

case_tests = CaseTests()
outcome, disagreement, control = case_tests.outcome, case_tests.disagreement, case_tests.control


# ------------------------------------------------------------------------------------------- thesis HUBO
STANCE_CAUSE = ("RFT foot at its yield load resists a CoM offset only through depth hardening (alpha_z I, "
                "560 W N m/rad in pitch), below the robot's toppling stiffness m g h ~ 340 N m/rad; the cut-out "
                "board keeps 75 % of the second moment of area, so it stands like the full board")
GAIT_CAUSE = "every run falls in the first half step (the stance failure), so the shift timing is never reached"


@outcome("thesis_hubo_stance", slow=True)
def stance_width_outcomes(stance):
    by = stance.by_name
    # what mjrft reproduces: the natural foot falls, the 30.4 cm board stands (CoM on the sole centre)
    assert by["natural foot (15.2 cm): falls in every trial"].passed
    assert by["30.4 cm board: stands in every trial"].passed
    assert by["stable trials rise with foot width, from none to every trial"].passed
    assert "alpha_z I" in stance.cause and len(stance.panels) == 2


@disagreement("thesis_hubo_stance", slow=True, reason=STANCE_CAUSE)
def stance_cutout_falls(stance):
    assert not stance.failed_outcomes


@control("thesis_hubo_stance", "falls and width trend need a robot that stands and a real trend")
def hubo_stance_checks_need_a_robot_that_stands_and_a_real_trend():
    # a robot that never stands passes no "falls" check, and 0 0 0 0 0 1 is no rise from unstable to stable
    assert not thesis_hubo.falls_check("natural", 0, 3, 0, "natural_foot_stance").passed
    assert thesis_hubo.falls_check("natural", 0, 3, 1, "natural_foot_stance").passed
    widths = thesis_hubo.WIDTHS
    assert not thesis_hubo.width_trend_check(widths, [0, 0, 0, 0, 0, 1], 3).passed
    assert not thesis_hubo.width_trend_check(widths, [0] * 6, 3).passed
    assert not thesis_hubo.width_trend_check(widths, [3] * 6, 3).passed
    assert not thesis_hubo.width_trend_check(widths, [0, 1, 3, 2, 3, 3], 3).passed
    assert thesis_hubo.width_trend_check(widths, [0, 1, 3, 3, 3, 3], 3).passed


@control("thesis_hubo_stance", "stance checks reject a rigid floor", slow=True)
def hubo_stance_checks_reject_a_rigid_floor():
    rows = thesis_hubo._stance_counts((0.152, 0.304), (0.0,), sand=False)
    stable = {k: thesis_hubo._stable(v) for k, v in rows.items()}
    nat, wide = stable[(0.152, False)], stable[(0.304, False)]
    assert nat == 1 and wide == 1  # on a rigid floor the natural foot stands
    assert not thesis_hubo.falls_check("natural", nat, 1, wide, "natural_foot_stance").passed
    assert not thesis_hubo.width_trend_check((0.152, 0.304), [nat, wide], 1).passed


@outcome("thesis_hubo_gait")
def gait_case_reports_the_published_starts(gait):
    assert published("thesis_hubo", "shift_starts").value == [0.6, 0.65, 0.7, 0.8]
    assert "first half step" in gait.cause


@disagreement("thesis_hubo_gait", reason=GAIT_CAUSE)
def gait_shift_timing(gait):
    assert not gait.failed_outcomes


@control("thesis_hubo_gait", "fails within two steps rejects no step and walking on")
def hubo_hard_ground_check_needs_a_step_and_a_fall():
    # "fails within two steps": 0 steps (never stood) and walking on are both rejected
    assert not thesis_hubo.hard_ground_check(0.0, 2.0).passed
    assert not thesis_hubo.hard_ground_check(3.0, math.nan).passed
    assert not thesis_hubo.hard_ground_check(2.0, math.nan).passed
    assert thesis_hubo.hard_ground_check(1.0, 9.5).passed


@control("thesis_hubo_gait", "hard-ground check rejects a rigid floor", slow=True)
def hubo_hard_ground_check_rejects_a_rigid_floor():
    t_end = 0.5 * thesis_hubo.STEP_PERIOD + 3 * thesis_hubo.STEP_PERIOD
    _, _, _, fall, _ = thesis_hubo.run_trial("shift:amount=0,sway=0.17", 0.304, False, t_end, sand=False)
    steps = thesis_hubo._steps(fall, t_end)
    assert math.isnan(fall) and steps == 3  # the hard-ground gait walks on hard ground
    assert not thesis_hubo.hard_ground_check(steps, fall).passed


# the humanoid's shift and stance gaits the HUBO cases drive
def test_shift_spec_and_fraction():
    assert parse_gait_spec("shift:start=0.4") == ("shift", {"start": 0.4})
    p = GAITS["shift"].defaults()
    assert p["amount"] == published("thesis_hubo", "shift_amount").value and p["start"] == 0.65
    with pytest.raises(ValueError, match=r"amount=1.5 out of range; valid: \[0, 1\]"):
        parse_gait_spec("shift:amount=1.5")
    # amount of the way by the end of the partial shift, all of it after the double support, monotone
    s0 = 0.15 + 0.20 + 0.6 * 0.20
    assert shift_fraction(s0 - 1e-9, 0.6, 0.3) == 0.0
    assert shift_fraction(s0 + 0.05, 0.6, 0.3) == pytest.approx(0.3)
    assert shift_fraction(0.99, 0.6, 0.3) == pytest.approx(1.0)
    xs = np.linspace(0, 1, 401)
    f = [shift_fraction(s, 0.6, 0.3) for s in xs]
    assert np.all(np.diff(f) >= -1e-12)
    # amount 0: the hard-ground gait, nothing moves before the intrusion is over
    assert shift_fraction(0.15 + 0.20 + 0.20 - 1e-9, 0.0, 0.0) == 0.0
    # extremes: start 1 with amount 1 still ends over the new foot
    assert shift_fraction(0.99, 1.0, 1.0) == pytest.approx(1.0)


def test_stance_pose_puts_the_com_over_the_sole():
    env = gymnasium.make("mjrft/HumanoidRigid-v0", foot_width=0.304)
    u = env.unwrapped
    p = GAITS["stance"].defaults()
    for cx in (-0.02, 0.0, 0.03):
        p["com_x"] = cx
        ox, oy = stance_pose(u.model, p)
        assert oy < -0.15  # the pelvis moves well over the wide right board
        from mjrft.tools.gaits import _humanoid_dims, _leg_height, humanoid_leg_ik
        th, sh = _humanoid_dims()
        h = _leg_height(p["crouch"], th, sh)
        t = {}
        for side, dz in (("right", 0.0), ("left", p["lift"])):
            t.update({f"{side}_{j}": v for j, v in humanoid_leg_ik(-ox, -oy, -h + dz, th, sh).items()})
        assert humanoid_com_sole(u.model, t) == pytest.approx([cx, 0.0], abs=2e-4)
        # the feed-forward aims the loaded joints past the pose, finite, zero change for an unloaded arm
        held = humanoid_static_targets(u.model, t)
        assert all(math.isfinite(v) for v in held.values())
        assert abs(held["right_hip_roll"] - t["right_hip_roll"]) > 1e-3
    with pytest.raises(ValueError, match="com_x=0.5 out of range"):
        make_gait("stance:com_x=0.5", env)
    env.close()


def test_stance_stands_on_rigid_ground_and_holds_the_com():
    env = gymnasium.make("mjrft/HumanoidRigid-v0", foot_width=0.304, max_episode_steps=10_000)
    gait = make_gait("stance:lift=0.1", env)
    obs, _ = env.reset(seed=0)
    u = env.unwrapped
    while u.data.time < 5.5:
        obs, _, terminated, _, _ = env.step(gait.predict(obs)[0])
        assert not terminated
    com = u.data.subtree_com[1, :2]
    sole = u.data.site_xpos[u.model.site("right_sole").id, :2]
    assert np.linalg.norm(com - sole) < 0.01  # within 1 cm of the planned point (servo sag fed forward)
    left = u.data.site_xpos[u.model.site("left_sole").id, 2]
    assert left > 0.05  # the left foot is up (measured 6.7 cm of the 10 cm target: the free leg sags on its servos)
    env.close()


test_case, test_known_disagreement, test_control = case_tests.runners()

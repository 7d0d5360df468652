"""Every validation check can fail: each check below is run on a wrong-physics control (a rigid floor, the law
that distinguishes what the paper calls similar, a rate-independent law, a start that flips the robot) and must
reject it. The measurements use the cases' quick settings; the checks are the cases' own functions."""

from __future__ import annotations

import math

import pytest

from mjrft.laws.wet import dry_reference
from mjrft.tools.validation.case import CONSISTENCY, SIMILAR, UPRIGHT_TILT, Check, check_close, similar
from mjrft.tools.validation.cases import li2013, li2013_robot, sgrft, thesis_biped, thesis_hubo


# ------------------------------------------------------------------------------------------- readings
def test_readings_of_the_papers_words():
    assert similar(1.0) and similar(1.19) and similar(1 / 1.19)
    assert not similar(1.21) and not similar(1 / 1.21) and not similar(1.52) and not similar(0.0)
    assert SIMILAR == 0.2 and UPRIGHT_TILT == pytest.approx(math.radians(60))


def test_a_consistency_check_states_why_and_is_counted_apart():
    with pytest.raises(ValueError, match="needs the reason"):
        Check("x", "-", "-", "-", "-", True, "s", kind=CONSISTENCY)
    with pytest.raises(ValueError, match="check kind"):
        Check("x", "-", "-", "-", "-", True, "s", kind="other")
    c = check_close("k", 1.0, 1.0, 0.1, source="s", consistency="calibrated from it")
    assert c.kind == CONSISTENCY and not c.is_validation and c.why == "calibrated from it"
    assert check_close("k", 1.0, 1.0, 0.1, source="s", basis="the paper's error").tolerance == "<= 10 % (the paper's error)"


# ------------------------------------------------------------------------------------------- HUBO
def test_hubo_checks_need_a_robot_that_stands_and_a_real_trend():
    # a robot that never stands passes no "falls" check, and 0 0 0 0 0 1 is no rise from unstable to stable
    assert not thesis_hubo.falls_check("natural", 0, 3, 0, "natural_foot_stance").passed
    assert thesis_hubo.falls_check("natural", 0, 3, 1, "natural_foot_stance").passed
    widths = thesis_hubo.WIDTHS
    assert not thesis_hubo.width_trend_check(widths, [0, 0, 0, 0, 0, 1], 3).passed
    assert not thesis_hubo.width_trend_check(widths, [0] * 6, 3).passed
    assert not thesis_hubo.width_trend_check(widths, [3] * 6, 3).passed
    assert not thesis_hubo.width_trend_check(widths, [0, 1, 3, 2, 3, 3], 3).passed
    assert thesis_hubo.width_trend_check(widths, [0, 1, 3, 3, 3, 3], 3).passed
    # "fails within two steps": 0 steps (never stood) and walking on are both rejected
    assert not thesis_hubo.hard_ground_check(0.0, 2.0).passed
    assert not thesis_hubo.hard_ground_check(3.0, math.nan).passed
    assert not thesis_hubo.hard_ground_check(2.0, math.nan).passed
    assert thesis_hubo.hard_ground_check(1.0, 9.5).passed


@pytest.mark.slow
def test_hubo_stance_checks_reject_a_rigid_floor():
    rows = thesis_hubo._stance_counts((0.152, 0.304), (0.0,), sand=False)
    stable = {k: thesis_hubo._stable(v) for k, v in rows.items()}
    nat, wide = stable[(0.152, False)], stable[(0.304, False)]
    assert nat == 1 and wide == 1  # on a rigid floor the natural foot stands
    assert not thesis_hubo.falls_check("natural", nat, 1, wide, "natural_foot_stance").passed
    assert not thesis_hubo.width_trend_check((0.152, 0.304), [nat, wide], 1).passed


@pytest.mark.slow
def test_hubo_hard_ground_check_rejects_a_rigid_floor():
    t_end = 0.5 * thesis_hubo.STEP_PERIOD + 3 * thesis_hubo.STEP_PERIOD
    _, _, _, fall, _ = thesis_hubo.run_trial("shift:amount=0,sway=0.17", 0.304, False, t_end, sand=False)
    steps = thesis_hubo._steps(fall, t_end)
    assert math.isnan(fall) and steps == 3  # the hard-ground gait walks on hard ground
    assert not thesis_hubo.hard_ground_check(steps, fall).passed


# ------------------------------------------------------------------------------------------- Li 2013
def test_li2013_similar_peaks_rejects_the_fit():
    """Under the medium's fit (RFT), the C and reversed C legs' peaks differ: "similar" must reject them."""
    runs = li2013.leg_runs(True, ["poppy_lp"])
    fz = runs["poppy_lp", "c", "fit"].support.max() / runs["poppy_lp", "reversed_c", "fit"].support.max()
    assert fz > 1 + SIMILAR
    assert not li2013.similar_peaks_check("F_z", [fz]).passed
    fx = runs["poppy_lp", "c", "depth_only"].forward.max() / runs["poppy_lp", "reversed_c", "depth_only"].forward.max()
    assert li2013.similar_peaks_check("F_x", [fx]).passed  # depth-only thrust: the same within 1 %


def test_li2013_robot_similar_speeds_rejects_the_fit():
    f = 3.0
    v = {k: li2013_robot.trial(k, f, "fit", 2)["speed"] for k in (1.0, -1.0)}
    c = li2013_robot.similar_speeds_check("fit", [f], {f: v[1.0]}, {f: v[-1.0]}, {f: 0.0})
    assert v[1.0] / v[-1.0] > 1 + SIMILAR and not c.passed
    # and no f where the robot stayed upright is no pass either
    assert not li2013_robot.similar_speeds_check("x", [f], {f: 1.0}, {f: 1.0}, {f: math.pi}).passed


@pytest.mark.filterwarnings("ignore::mjrft.ValidityRangeWarning")
def test_li2013_robot_upright_rejects_the_depth_only_abrupt_start():
    """The depth-only robot started with every leg down (tripod B catching up at full speed) turns over at 4 Hz."""
    r = li2013_robot.trial(1.0, 4.0, "depth_only", 2, start="env")
    assert r["tilt"] > UPRIGHT_TILT
    assert not li2013_robot.upright_check("depth-only", r["tilt"]).passed


def test_li2013_robot_phase_spread_reads_much_less_as_ten_times_below():
    assert li2013_robot.phase_spread_check("x", {(1.0, 3.0): 0.0009}).passed
    assert not li2013_robot.phase_spread_check("x", {(1.0, 3.0): 0.002}).passed  # 0.2 cm/s: below 1, not << 1
    assert not li2013_robot.phase_spread_check("x", {(1.0, 3.0): 0.0011, (-1.0, 3.0): 0.0}).passed


# ------------------------------------------------------------------------------------------- SGRFT
def test_sgrft_speed_ratio_rejects_a_rate_independent_law():
    dry = dry_reference()
    f = [sgrft._plate_drag(v, 0.03, dry, "rft", True) for v in (0.010, 0.050)]
    c = sgrft.ratio_check(f[1] / f[0])
    assert f[1] / f[0] == pytest.approx(1.0, abs=0.01) and not c.passed
    assert "model error" in c.tolerance
    wet = [sgrft._plate_drag(v, 0.03, sgrft.SAND, "wet", True) for v in (0.010, 0.050)]
    assert sgrft.ratio_check(wet[1] / wet[0]).passed


# ------------------------------------------------------------------------------------------- biped
def test_biped_looser_bed_drop_rejects_swapped_and_equal_beds():
    angles = (-30.0, 0.0, 30.0, 55.0)
    cp, lp = [12.5, 13.7, 14.2, 13.7], [12.4, 13.6, 14.0, 12.6]
    assert thesis_biped.looser_bed_drop_check("cone", angles, cp, lp).passed
    # the looser bed stiffer than the denser (the beds swapped), a bed that does not matter (a rigid floor), and a
    # 55 deg drop no larger than the changes at other angles are all rejected
    assert not thesis_biped.looser_bed_drop_check("cone", angles, lp, cp).passed
    assert not thesis_biped.looser_bed_drop_check("cone", angles, cp, cp).passed
    assert not thesis_biped.looser_bed_drop_check("cone", angles, cp, [11.0, 13.6, 14.0, 12.6]).passed

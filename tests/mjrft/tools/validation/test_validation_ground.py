"""Validation cases dynaroach_memory, li2013_robot_memory, thesis_hubo_stance_memory and flipperbot_memory (the
ground memory): each
case's outcome test, its known disagreements and its controls, the same runs without the memory
(:class:`helpers.CaseTests`)."""

from __future__ import annotations

import math
import warnings

from mjrft.tools.validation.cases import ground, thesis_hubo

from helpers import CaseTests

case_tests = CaseTests()
outcome, disagreement, control = case_tests.outcome, case_tests.disagreement, case_tests.control

DYNAROACH_CAUSE = ("the legs' touchdowns land on disturbed ground at every frequency (hind legs in the fore legs' "
                   "tracks, DynaRoACH's own legs in their own), and disturbed ground only slows the robot: its "
                   "running needs inertial lift, which the regime gives the protraction as drag")
HUBO_CAUSE = ("the memory does not change which trials stand: a compacted or sheared bed scales the strength under "
              "every foot alike, so the cut-out board stands like the full one (thesis_hubo_stance's cause)")


@outcome("dynaroach_memory")
def dynaroach_memory_outcomes(r):
    by = r.by_name
    # DynaRoACH's own legs (stride near 2r) meet the ground they disturbed on most touchdowns at the top frequency
    assert by["own legs: legs land on previously disturbed ground at high frequency"].passed
    assert "touchdowns on previously disturbed ground" in r.cause and len(r.panels) == 3


@disagreement("dynaroach_memory", reason=DYNAROACH_CAUSE)
def dynaroach_memory_running(r):
    assert not [c for c in r.checks if not c.passed]


@control("dynaroach_memory", "the memory-off runs fail the checks the memory passes")
def dynaroach_without_memory():
    freqs = [3.0, 6.0, 8.0, 12.0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        on, off = ground.sweep(freqs, True, True), ground.sweep(freqs, True, False)
    passed_on = {c.name for robot in ground.ROBOTS for c in ground.robot_checks(robot, freqs, on[robot], True)
                 if c.passed}
    passed_off = {c.name for robot in ground.ROBOTS for c in ground.robot_checks(robot, freqs, off[robot], True)
                  if c.passed}
    assert "own legs: legs land on previously disturbed ground at high frequency" in passed_on - passed_off
    # the one check no memory-off run fails is dynaroach_robot's own 12 Hz speed (its controls are that case's)
    assert passed_on & passed_off <= {"one-hinge: speed at 12 Hz (experiment)"}


RHEX_CAUSE = ("with the memory the loose bed is compacted under the legs and the close one heaps the higher ridges, "
              "so the legs no longer sink deeper on poppy LP than on CP; the speed ordering CP >= LP fails with and "
              "without the memory (LP ahead at 5 Hz)")
SPEED = "speed on poppy CP >= on poppy LP at every tested f (lower phi, shorter effective stride)"
DEEPER = "legs sink deeper on poppy LP than on poppy CP at every tested f"


@outcome("li2013_robot_memory")
def rhex_memory_outcomes(r):
    by = r.by_name
    assert by["C-legs on poppy LP: the robot advances at every tested f"].passed  # fig. S13: it runs on LP
    assert "The checks the memory changes: " + DEEPER in r.cause and len(r.panels) == 2


@disagreement("li2013_robot_memory", reason=RHEX_CAUSE)
def rhex_memory_packing(r):
    assert r.by_name[DEEPER].passed or r.by_name[SPEED].passed


@control("li2013_robot_memory", "the memory-off runs pass the sinkage check the memory fails; both checks reject a "
         "bed whose packing does not matter")
def rhex_without_memory():
    freqs, seconds = ground.rhex_settings(True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        off = ground.rhex_sweep(freqs, seconds, False)
    by = {c.name: c.passed for c in ground.rhex_checks(freqs, off)}
    assert by[DEEPER]  # without the memory the prepared packing decides the legs' depth, as the thesis states
    same = {key: dict(off["poppy_cp", key[1]]) for key in off}  # both beds alike: the orderings must fail
    by = {c.name: c.passed for c in ground.rhex_checks(freqs, same)}
    assert not by[DEEPER] and by[SPEED]
    swapped = {(md, f): off["poppy_lp" if md == "poppy_cp" else "poppy_cp", f] for md, f in off}  # LP <-> CP
    assert not any(c.passed for c in ground.rhex_checks(freqs, swapped)[1:])
    stalled = {key: dict(r, speed=0.0) for key, r in off.items()}  # a robot that does not advance on LP
    assert not ground.rhex_checks(freqs, stalled)[0].passed


@outcome("thesis_hubo_stance_memory")
def hubo_memory_outcomes(r):
    by = r.by_name
    assert by["natural foot (15.2 cm): falls in every trial"].passed
    assert by["30.4 cm board: stands in every trial"].passed
    assert "nothing to compact" in r.cause


@disagreement("thesis_hubo_stance_memory", reason=HUBO_CAUSE)
def hubo_memory_cutout(r):
    assert not r.failed_outcomes


@control("thesis_hubo_stance_memory", "the stance checks reject a robot that never stands and one that always does")
def hubo_memory_checks_reject_wrong_readings():
    nan = math.nan
    fell = {(0.152, False): [(3.7, 0.09)], (0.304, False): [(4.0, 0.07)], (0.304, True): [(4.2, 0.1)]}
    rigid = {(0.152, False): [(nan, 0.0)], (0.304, False): [(nan, 0.0)], (0.304, True): [(nan, 0.0)]}
    for rows in (fell, rigid):  # neither passes the published pattern: natural falls, board stands, cut-out falls
        checks = {c.name: c.passed for c in ground.stance_checks(rows, 1)}
        assert not (checks["natural foot (15.2 cm): falls in every trial"] and checks["30.4 cm board: stands in every "
                                                                                    "trial"])
    paper = {(0.152, False): [(3.7, 0.09)], (0.304, False): [(nan, 0.03)], (0.304, True): [(4.2, 0.1)]}
    assert all(c.passed for c in ground.stance_checks(paper, 1))
    assert thesis_hubo.HOLD_END == 10.0


FAILS = "poppy CP: once its flippers re-enter material disturbed in a prior cycle, the robot fails to advance"
DROP = "poppy CP: the first cycle in disturbed material travels significantly less than the cycle before"
THRUST = "poppy CP, body held: the flippers' thrust per cycle falls once they re-enter their disturbed track"
CLEAR = "poppy CP: flippers that stay clear of their disturbed material keep the robot advancing every cycle"


@outcome("flipperbot_memory", slow=True)
def flipper_memory_outcomes(r):
    by = r.by_name
    assert [c.name for c in r.checks] == [FAILS, DROP, THRUST, CLEAR] and not r.failed_outcomes
    assert by[CLEAR].passed  # the light body's step clears its sweep: it keeps advancing with the memory
    # the heavy body's flippers re-enter their track and it stops; the light body's stay clear of it
    assert by[FAILS].simulated.startswith("2 kg:") and by[CLEAR].simulated.startswith("0.5 kg:")
    # the measured mechanism: the plates meet the surface their earlier cycles lowered, at a lower packing
    assert "Runs that re-enter in every cycle after the first: poppy CP 2 kg" in r.cause
    assert "control FAIL" in r.cause and len(r.panels) == 3


@control("flipperbot_memory", "the memory-off runs fail the checks the memory passes; the checks reject a robot that "
         "never re-enters and one that slows without re-entering")
def flipper_without_memory():
    s = dict(ground.flipper_settings(True), masses=(2.0,))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        off = ground.flipper_sweep(s, False)
    by = {c.name: c for c in ground.flipper_checks(s, off)}
    assert min(off["poppy_cp", 2.0]["reentry"][1:]) > ground.REENTER  # the same kinematics re-enter the track
    assert not by[FAILS].passed and not by[DROP].passed and not by[THRUST].passed
    clear = {("poppy_cp", 0.5): {"distance": [0.07] * 5, "reentry": [0.0] * 5}}
    assert not ground.fails_to_advance_check("x", clear).passed and not ground.hatchling_drop_check("x", clear).passed
    assert ground.keeps_advancing_check("x", clear).passed
    slowing = {("poppy_cp", 0.5): {"distance": [0.07, 0.05, 0.04, 0.03, 0.02], "reentry": [0.0] * 5}}
    assert not ground.keeps_advancing_check("x", slowing).passed


test_case, test_known_disagreement, test_control = case_tests.runners()

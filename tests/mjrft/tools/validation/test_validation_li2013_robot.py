"""Validation case li2013_robot (Li, Zhang & Goldman 2013 suppl.: the RHex-class robot), with the planar hexapod the
case runs on, its start on the gait and the tripod's phase: its outcome test, known disagreements and
wrong-physics controls, registered by case name (:class:`helpers.CaseTests`;
``tests/mjrft/tools/validation/test_validation.py`` holds the framework's tests and the controls that rerun cases
under a wrong physics)."""

from __future__ import annotations

import math

import gymnasium
import mujoco
import numpy as np
import pytest

import mjrft.envs  # noqa: F401  (registers the envs)
from mjrft.models.hexapod import hexapod_xml
from mjrft.tools.gaits import make_gait, tripod_angles
from mjrft.tools.validation.case import SIMILAR
from mjrft.tools.validation.cases import li2013_robot
from mjrft.tools.validation.cases.li2013_robot import UPSIDE_DOWN, _lowest_point, start_on_gait

from helpers import CaseTests

case_tests = CaseTests()
outcome, disagreement, control = case_tests.outcome, case_tests.disagreement, case_tests.control


# ------------------------------------------------------------------------------------------- Li 2013: robot
@outcome("li2013_robot", slow=True)
def li2013_robot_outcomes(robot):
    assert not robot.failed_outcomes
    by = {c.name.split(":")[0]: c for c in robot.checks}
    # the published outcomes the fast test asserts: C > reversed C (fit, generic), depth-only similar, no flip,
    # generic close to the fit, fig. S14's mechanism, three initial phases within 1 cm/s; the free robot: C faster
    # on poppy LP, upright
    assert sum(c.qualitative for c in robot.checks) == 11
    assert by["medium's fit (rft)"].passed
    assert by["free body, poppy LP"].passed and by["free body, medium's fit (rft), poppy LP and CP"].passed
    tilt = [c for c in robot.checks if c.name.startswith("medium's fit (rft): largest torso tilt")][0]
    assert 0.0 < tilt.value < UPSIDE_DOWN
    # a failing check carries its measured cause
    if not robot.passed:
        assert robot.cause
        for c in robot.checks:
            if not c.passed and "upside down" in c.name:
                assert "start-up transient" in robot.cause and "rad" in robot.cause
    # a free robot off the straight path: the bounce measured, the mirrored start turning it the other way
    track = [c for c in robot.checks if "path heading" in c.name]
    assert len(track) == 3
    if not all(c.passed for c in track):
        assert "period-2 bounce" in robot.cause and "Started with the tripods swapped" in robot.cause
        assert "Held in the sagittal plane" in robot.cause  # the same trial held planar: bounce, but no turn
    # speed vs f per law, speed vs curvature, the mechanism panel, the free robot's speed vs f per law and medium;
    # every speed finite and forward
    assert len(robot.panels) == 8
    for p in robot.panels[:4] + robot.panels[5:7]:
        for line in p.lines:
            assert all(math.isfinite(y) and y > 0 for y in line.y)


@disagreement("li2013_robot", slow=True, reason=(
    "measured: the free C-leg robot at 5 Hz (poppy LP and CP, fit and depth-only) and 4 Hz (poppy CP) settles into a "
    "period-2 bounce (on poppy CP at 5 Hz the torso rides at 30.3 / 20.7 mm and the legs carry 0.58 / 1.36 N on "
    "alternate half-cycles) and turns steadily (-45.5 deg/s; +45.5 deg/s with the tripods swapped; -46.8 and -45.6 "
    "deg/s at half the timestep and with 4x the elements): it leaves Li's track, and on poppy CP its speed along x falls below the "
    "reversed C-legs' (v_C / v_rev 0.13 at 5 Hz)"))
def li2013_robot_free_body_runs_straight(robot):
    free = [c for c in robot.checks if c.name.startswith("free body") and not c.qualitative]
    assert len(free) == 5
    assert all(c.passed for c in free)


@control("li2013_robot", "free-body order rejects the depth-only law")
def li2013_robot_free_body_order_rejects_the_depth_only_law():
    """The free robot's C-faster check, run on the depth-only law's speeds (blind to the legs' curvature), fails;
    on the fit's it passes."""
    f = 3.0
    v = {law: {(k, f, 0): li2013_robot.free_trial(k, f, "poppy_lp", law, seconds=4.0)["speed"] for k in (1.0, -1.0)}
         for law in ("rft", "depth_only")}
    assert not li2013_robot.free_order_check("poppy_lp", [f], [0], v["depth_only"], qualitative=True).passed
    assert li2013_robot.free_order_check("poppy_lp", [f], [0], v["rft"], qualitative=True).passed


@control("li2013_robot", "track check rejects a turning robot")
def li2013_robot_track_check_rejects_a_turning_robot():
    """The C-leg robot on poppy CP at 5 Hz turns (period-2 bounce): the track check rejects it; the reversed C-leg
    robot there runs straight and passes."""
    heading = {k: li2013_robot.free_trial(k, 5.0, "poppy_cp", seconds=6.0)["path_heading"] for k in (1.0, -1.0)}
    assert not li2013_robot.track_check("C", {(1.0, 5.0, 0): heading[1.0]}).passed
    assert li2013_robot.track_check("reversed C", {(-1.0, 5.0, 0): heading[-1.0]}).passed


@control("li2013_robot", "similar speeds reject the fit")
def li2013_robot_similar_speeds_rejects_the_fit():
    f = 3.0
    v = {k: li2013_robot.trial(k, f, "fit", 2)["speed"] for k in (1.0, -1.0)}
    c = li2013_robot.similar_speeds_check("fit", [f], {f: v[1.0]}, {f: v[-1.0]}, {f: 0.0})
    assert v[1.0] / v[-1.0] > 1 + SIMILAR and not c.passed
    # and no f where the robot stayed upright is no pass either
    assert not li2013_robot.similar_speeds_check("x", [f], {f: 1.0}, {f: 1.0}, {f: math.pi}).passed


@control("li2013_robot", "upright rejects a robot on its back",
         marks=(pytest.mark.filterwarnings("ignore::mjrft.ValidityRangeWarning"),))
def li2013_robot_upright_rejects_a_robot_on_its_back():
    """The planar robot started pitched half a turn (on its back) and driven by the tripod for 0.5 s: its tilt,
    read as the case reads it, fails the upright check; started upright it passes."""
    tilts = {}
    for pitch in (0.0, math.pi):
        env = gymnasium.make("mjrft/HexapodSand-v0", planar=True, medium="poppy_lp", terminate_when_unhealthy=False,
                             reset_noise_scale=0.0)
        u = env.unwrapped
        obs, _ = env.reset(seed=0)
        u.data.qpos[2] = pitch  # rooty
        u.data.qpos[1] += 0.03 if pitch else 0.0  # rootz: the legs, now up, clear the surface
        gait = make_gait("tripod:f=2", env)
        tilt = 0.0
        for _ in range(50):
            obs, *_ = env.step(gait.predict(obs)[0])
            tilt = max(tilt, u.torso_tilt())
        tilts[pitch] = tilt
    assert tilts[math.pi] > UPSIDE_DOWN and not li2013_robot.upright_check("on its back", tilts[math.pi]).passed
    assert li2013_robot.upright_check("upright", tilts[0.0]).passed


def test_li2013_robot_bounce_reads_two_heights_apart():
    """The period-2 bounce of the cause: torso heights on alternate half-cycles more than 10 % of their mean apart
    (the C-legs' 30.3 / 20.7 mm at 5 Hz on poppy CP); the reversed C-legs' equal 17.9 / 17.9 mm do not bounce."""
    assert li2013_robot.bounces({"height_halves": (0.0303, 0.0207)})
    assert not li2013_robot.bounces({"height_halves": (0.0179, 0.0179)})
    assert not li2013_robot.bounces({"height_halves": (0.0200, 0.0185)})  # 7.8 % apart


def test_li2013_robot_c_legs_bounce_held_planar_at_5_hz():
    """The bounce is in the sagittal motion (benchmarks/tripod_bounce.py): held planar, the C-leg robot at 5 Hz on
    poppy CP rides at two heights (measured 31.3 / 21.5 mm) and runs faster than the reversed C-legs (0.687 vs
    0.504 m/s over 3 s), which ride at one (17.9 / 17.9 mm)."""
    c, rev = (li2013_robot.free_trial(k, 5.0, "poppy_cp", planar=True, seconds=3.0) for k in (1.0, -1.0))
    assert li2013_robot.bounces(c) and not li2013_robot.bounces(rev)
    assert c["speed"] > rev["speed"] and c["heading"] == c["path_heading"] == 0.0  # held planar: no heading


@control("li2013_robot", "phase spread reads much less as ten times below")
def li2013_robot_phase_spread_reads_much_less_as_ten_times_below():
    assert li2013_robot.phase_spread_check("x", {(1.0, 3.0): 0.0009}).passed
    assert not li2013_robot.phase_spread_check("x", {(1.0, 3.0): 0.002}).passed  # 0.2 cm/s: below 1, not << 1
    assert not li2013_robot.phase_spread_check("x", {(1.0, 3.0): 0.0011, (-1.0, 3.0): 0.0}).passed


# the planar hexapod the case runs on, its start on the gait and the tripod's phase
def test_planar_model_joints_and_mass():
    m = mujoco.MjModel.from_xml_string(hexapod_xml(planar=True))
    free = mujoco.MjModel.from_xml_string(hexapod_xml())
    names = [m.joint(j).name for j in range(3)]
    assert names == ["rootx", "rootz", "rooty"]
    assert m.nq == free.nq - 4 and m.nv == free.nv - 3
    assert m.body_subtreemass[1] == pytest.approx(free.body_subtreemass[1])
    with pytest.raises(ValueError, match="planar must be True or False"):
        hexapod_xml(planar="yes")


def test_planar_env_layout_and_checkers():
    from gymnasium.utils.env_checker import check_env
    from stable_baselines3.common.env_checker import check_env as sb3_check_env

    env = gymnasium.make("mjrft/HexapodSand-v0", planar=True, medium="poppy_lp")
    u = env.unwrapped
    obs, _ = env.reset(seed=0)
    assert obs.shape == (35,) and env.observation_space.shape == (35,)
    gait = make_gait("tripod:f=2", env)
    for _ in range(30):
        obs, _, term, _, info = env.step(gait.predict(obs)[0])
    assert not term and "diverged" not in info
    d = u.data
    # the free-joint layout: height, a pure-pitch quaternion, (v_x, 0, v_z), (0, pitch rate, 0)
    mujoco.mj_kinematics(u.model, d)  # the body poses of the current qpos
    assert obs[0] == pytest.approx(d.xpos[u.task.torso, 2])
    assert np.allclose(obs[1:5], d.xquat[u.task.torso])
    assert obs[2] == 0.0 and obs[4] == 0.0
    assert obs[1] == pytest.approx(math.cos(d.qpos[2] / 2)) and obs[3] == pytest.approx(math.sin(d.qpos[2] / 2))
    assert obs[17] == d.qvel[0] and obs[18] == 0.0 and obs[19] == d.qvel[1]
    assert obs[20] == 0.0 and obs[21] == d.qvel[2] and obs[22] == 0.0
    assert d.xpos[u.task.torso, 1] == 0.0  # held in the sagittal plane
    assert info["x_position"] == pytest.approx(d.qpos[0]) and info["x_position"] > 0
    env.close()
    check_env(gymnasium.make("mjrft/HexapodSand-v0", planar=True).unwrapped, skip_render_check=True)
    sb3_check_env(gymnasium.make("mjrft/HexapodSand-v0", planar=True).unwrapped, warn=False)


def test_start_on_gait_keeps_the_clearance():
    env = gymnasium.make("mjrft/HexapodSand-v0", planar=True, medium="poppy_lp", reset_noise_scale=0.0)
    u = env.unwrapped
    env.reset(seed=0)
    z0 = _lowest_point(u.model, u.data)
    for phase in (0.0, 1 / 3, 2 / 3):
        env.reset(seed=0)
        start_on_gait(env, 2.0, phase)
        assert _lowest_point(u.model, u.data) == pytest.approx(z0, abs=1e-9)
        assert np.allclose(u.data.qpos[u.task.hip_qadr], tripod_angles(u, 0.0, 2.0, phase=phase))
        # the two tripods are half a cycle apart: a constant-speed rotation puts them pi apart
        a, b = u.data.qpos[u.task.hip_qadr[list(u.TRIPOD_A_IDX)]], u.data.qpos[u.task.hip_qadr[list(u.TRIPOD_B_IDX)]]
        assert np.allclose(np.mod(b - a, 2 * np.pi), np.pi)
    env.close()


def test_tripod_phase_parameter():
    env = gymnasium.make("mjrft/HexapodSand-v0", planar=True)
    u = env.unwrapped
    env.reset(seed=0)
    # phase shifts the gait in time: phase p at t is phase 0 at t + p / f
    assert np.allclose(tripod_angles(u, 0.1, 2.0, phase=0.25), tripod_angles(u, 0.225, 2.0))
    assert make_gait("tripod:f=2,phase=0.5", env).params["phase"] == 0.5
    with pytest.raises(ValueError, match=r"phase=1.0 out of range"):
        make_gait("tripod:phase=1", env)
    env.close()


test_case, test_known_disagreement, test_control = case_tests.runners()

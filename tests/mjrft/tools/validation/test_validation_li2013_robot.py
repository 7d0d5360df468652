"""Li 2013 robot validation case (quick settings) and the planar hexapod it runs on."""

from __future__ import annotations

import math

import gymnasium
import mujoco
import numpy as np
import pytest

import mjrft.envs  # noqa: F401
from mjrft.tools import validation
from mjrft.tools.gaits import make_gait, tripod_angles
from mjrft.models.hexapod import hexapod_xml
from mjrft.tools.validation.cases.li2013_robot import UPSIDE_DOWN, _lowest_point, start_on_gait


@pytest.fixture(scope="module")
def robot():
    return validation.run_case("li2013_robot", quick=True)


@pytest.mark.slow
def test_li2013_robot(robot):
    assert not robot.failed_outcomes
    by = {c.name.split(":")[0]: c for c in robot.checks}
    # the published outcomes the fast test asserts: C > reversed C (fit, generic), depth-only similar, no flip,
    # generic close to the fit, fig. S14's mechanism, three initial phases within 1 cm/s
    assert sum(c.qualitative for c in robot.checks) == 9
    assert by["medium's fit (rft)"].passed
    tilt = [c for c in robot.checks if c.name.startswith("medium's fit (rft): largest torso tilt")][0]
    assert 0.0 < tilt.value < UPSIDE_DOWN
    # a failing check carries its measured cause
    if not robot.passed:
        assert robot.cause
        for c in robot.checks:
            if not c.passed and "upside down" in c.name:
                assert "start-up transient" in robot.cause and "rad" in robot.cause
    # speed vs f per law, speed vs curvature, the mechanism panel; every speed finite and forward
    assert len(robot.panels) == 5
    for p in robot.panels[:4]:
        for line in p.lines:
            assert all(math.isfinite(y) and y > 0 for y in line.y)


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
    assert obs[0] == pytest.approx(d.xpos[u._torso_id, 2])
    assert np.allclose(obs[1:5], d.xquat[u._torso_id])
    assert obs[2] == 0.0 and obs[4] == 0.0
    assert obs[1] == pytest.approx(math.cos(d.qpos[2] / 2)) and obs[3] == pytest.approx(math.sin(d.qpos[2] / 2))
    assert obs[17] == d.qvel[0] and obs[18] == 0.0 and obs[19] == d.qvel[1]
    assert obs[20] == 0.0 and obs[21] == d.qvel[2] and obs[22] == 0.0
    assert d.xpos[u._torso_id, 1] == 0.0  # held in the sagittal plane
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
        assert np.allclose(u.data.qpos[u._hip_qadr], tripod_angles(u, 0.0, 2.0, phase=phase))
        # the two tripods are half a cycle apart: a constant-speed rotation puts them pi apart
        a, b = u.data.qpos[u._hip_qadr[list(u.TRIPOD_A_IDX)]], u.data.qpos[u._hip_qadr[list(u.TRIPOD_B_IDX)]]
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

"""Open-loop gaits (mjrft.tools.gaits): spec parsing, kinematics, and every gait running on its robot."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

import mjrft.envs  # noqa: E402,F401
from mjrft.errors import TerrainStabilityWarning  # noqa: E402
from mjrft.tools.gaits import (GAITS, GaitWarning, biped_leg_ik, buehler_angle, humanoid_leg_ik,  # noqa: E402
                         is_gait_spec, make_gait, parse_gait_spec, rect_path, shift_pose)
from mjrft.models import biped as bm  # noqa: E402
from mjrft.models import humanoid as hm  # noqa: E402


def run(env, gait, seconds):
    obs, _ = env.reset(seed=0)
    u = env.unwrapped
    terminated = False
    info = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TerrainStabilityWarning)
        for _ in range(int(round(seconds / u.dt))):
            action, state = gait.predict(obs)
            assert state is None
            assert env.action_space.contains(action)
            obs, reward, terminated, truncated, info = env.step(action)
            assert np.all(np.isfinite(obs)) and np.isfinite(reward)
            if terminated:
                break
    return u, terminated, info


# ------------------------------------------------------------------------------------------ parsing
def test_parse_specs():
    assert parse_gait_spec("tripod") == ("tripod", {})
    assert parse_gait_spec("tripod:f=2.5, duty=0.6") == ("tripod", {"f": 2.5, "duty": 0.6})
    assert parse_gait_spec(" shift:start=0.25 ") == ("shift", {"start": 0.25})
    assert parse_gait_spec("rect:angle=-30") == ("rect", {"angle": -30.0})
    assert set(GAITS) == {"tripod", "rect", "stand", "stance", "shift"}


@pytest.mark.parametrize("spec, match", [
    ("gallop", r"unknown gait 'gallop'; valid choices: rect, shift, stance, stand, tripod"),
    ("tripod:g=2", r"no parameter 'g'; valid parameters: f, duty, sweep, offset"),
    ("tripod:f=fast", r"f='fast' is not a number"),
    ("tripod:f", r"expected key=value.*valid parameters: f, duty"),
    ("tripod:f=0", r"f=0.0 out of range; valid: \(0, inf\]"),
    ("tripod:duty=1", r"duty=1.0 out of range; valid: \(0, 1\)"),
    ("tripod:f=nan", r"out of range"),
    ("tripod:f=1,f=2", r"given twice"),
    ("shift:start=1.5", r"start=1.5 out of range; valid: \[0, 1\]"),
    ("rect:angle=120", r"angle=120.0 out of range"),
    ("", r"valid gaits: rect, shift, stance, stand, tripod"),
])
def test_bad_specs_name_the_valid_choices(spec, match):
    with pytest.raises(ValueError, match=match):
        parse_gait_spec(spec)


def test_is_gait_spec():
    assert is_gait_spec("tripod") and is_gait_spec("tripod:f=2") and is_gait_spec("shift:start=0.5")
    assert is_gait_spec("tripod:f=oops")  # a gait spec (that will fail to parse), not a path
    assert not is_gait_spec("runs/hex/model.zip")
    assert not is_gait_spec("tripod.zip")
    assert not is_gait_spec(None)


def test_gait_for_the_wrong_robot():
    env = gymnasium.make("mjrft/BipedRigid-v0")
    with pytest.raises(ValueError, match=r"gait 'tripod' drives the hexapod.*gaits for this env: rect"):
        make_gait("tripod", env)
    env.close()


def test_tripod_too_fast_for_the_hips():
    env = gymnasium.make("mjrft/HexapodRigid-v0")
    with pytest.raises(ValueError, match="max_hip_speed"):
        make_gait("tripod:f=2,duty=0.8", env)  # swing 2 pi f (1 - sweep/2pi) / 0.2 = 31 rad/s > 6 pi
    env.close()


# ------------------------------------------------------------------------------------------ kinematics
def test_buehler_clock():
    duty, sweep = 0.6, 1.2
    assert buehler_angle(0.0, duty, sweep) == pytest.approx(0.0)  # mid-stance: leg straight down
    assert buehler_angle(duty / 2, duty, sweep) == pytest.approx(sweep / 2)  # end of stance
    assert buehler_angle(1.0, duty, sweep) == pytest.approx(2 * math.pi)  # one turn per cycle
    x = np.linspace(-1, 2, 3001)
    a = np.array([buehler_angle(v, duty, sweep) for v in x])
    assert np.all(np.diff(a) > 0)  # continuous, monotone
    speed = np.diff(a) / np.diff(x)
    stance = np.abs(((x[:-1] + duty / 2) % 1.0)) < duty - 1e-3
    np.testing.assert_allclose(speed[stance & (((x[:-1] + duty / 2) % 1.0) > 1e-3)], sweep / duty, rtol=1e-6)
    # default duty 0.5, sweep pi: constant rotation
    a = np.array([buehler_angle(v, 0.5, math.pi) for v in x])
    np.testing.assert_allclose(a, 2 * math.pi * x, atol=1e-9)


def test_biped_ik_reaches_the_rectangle():
    L1, L2, L3 = bm.THIGH, bm.KNEE_LINK, bm.SHANK
    for s in np.linspace(0, 1, 97, endpoint=False):
        x, z, pitch = rect_path(s, 0.16, 0.03, 5 / 8, math.radians(20), 0.14)
        hip, knee = biped_leg_ik(x, z, L1, L2, L3)
        a1, a2, a3 = hip, hip + knee / 2, hip + knee
        fx = -(L1 * math.sin(a1) + L2 * math.sin(a2) + L3 * math.sin(a3))
        fz = -(L1 * math.cos(a1) + L2 * math.cos(a2) + L3 * math.cos(a3))
        assert (fx, fz) == pytest.approx((x, z), abs=1e-12)
        assert -0.3 <= knee / 2 <= 1.6
    # the rectangle: 5/8 of the cycle on the bottom edge, front to back, at uniform speed
    xs = [rect_path(s, 0.16, 0.03, 5 / 8, 0.0, 0.14)[:2] for s in (0.0, 5 / 16, 0.62)]
    assert xs[0] == pytest.approx((0.08, -0.14)) and xs[1] == pytest.approx((0.0, -0.14))
    assert xs[2][0] == pytest.approx(0.08 - 0.16 * 0.62 / 0.625)
    # presentation angle (thesis sec. 2.3.3): level at the top of the lift, turning at constant rate to the full
    # angle as the foot is fully intruded, back to level at constant rate before the other foot lifts (s = 1/8)
    t_up = 0.03 * (3 / 8) / 0.22
    pitch = [rect_path(s, 0.16, 0.03, 5 / 8, 0.5, 0.14)[2] for s in (5 / 8 + t_up, 0.5 * (5 / 8 + t_up + 1), 1 - 1e-12,
                                                                     0.0, 1 / 16, 1 / 8, 0.3)]
    assert pitch == pytest.approx([0.0, 0.25, 0.5, 0.5, 0.25, 0.0, 0.0])


def test_humanoid_ik_and_shift_timing():
    th, sh = hm.THIGH, hm.SHANK
    j = humanoid_leg_ik(0.03, -0.05, -0.55, th, sh)
    r = j["hip_roll"]
    a1, a2 = j["hip_pitch"], j["hip_pitch"] + j["knee"]
    xs = -(th * math.sin(a1) + sh * math.sin(a2))
    zs = -(th * math.cos(a1) + sh * math.cos(a2))
    assert (xs, -zs * math.sin(r), zs * math.cos(r)) == pytest.approx((0.03, -0.05, -0.55), abs=1e-12)
    assert j["ankle_pitch"] == pytest.approx(-(a1 + j["knee"])) and j["ankle_roll"] == pytest.approx(-r)
    p = {k: v.default for k, v in GAITS["shift"].params.items()}
    T = p["period"]
    # pelvis over the right foot before the first step, moving left only after `shift` of the intrusion
    for shift in (0.0, 0.5, 1.0):
        p["start"] = shift
        start = T / 2 + T * (0.15 + 0.20 + shift * 0.20)
        assert shift_pose(start - 1e-6, p)[1] == pytest.approx(-p["sway"])
        assert shift_pose(start + 0.1, p)[1] > -p["sway"]
    feet, _ = shift_pose(T / 2 + 0.2 * T, p)
    assert feet["left"][2] > feet["right"][2] + 0.9 * p["lift"]  # the left foot is up, the right one down


# ------------------------------------------------------------------------------------------ on the robots
def test_tripod_walks_the_hexapod_forward_on_poppy_seeds():
    env = gymnasium.make("mjrft/HexapodSand-v0", medium="poppy_lp", max_episode_steps=10_000)
    gait = make_gait("tripod:f=2", env)
    u, terminated, info = run(env, gait, 2.0)
    assert not terminated
    assert u.data.qpos[0] > 0.1  # 10 cm in 2 s (measured 0.43 m)
    assert np.all(info["sinkage"] >= 0) and info["sinkage"].max() > 0
    # the tripods are half a cycle apart and on the Buehler clock
    hips = u.data.qpos[u.task.hip_qadr]
    a, b = hips[list(u.TRIPOD_A_IDX)], hips[list(u.TRIPOD_B_IDX)]
    assert np.ptp(u.target[list(u.TRIPOD_A_IDX)]) < 1e-6
    ref_a = buehler_angle(2.0 * u.data.time, 0.5, math.pi)
    assert u.target[u.TRIPOD_A_IDX[0]] == pytest.approx(ref_a, abs=0.05)
    assert np.mean(b - a) == pytest.approx(math.pi, abs=0.6)
    env.close()


def test_tripod_duty_factor_and_batch_predict():
    from stable_baselines3.common.vec_env import DummyVecEnv

    venv = DummyVecEnv([lambda: gymnasium.make("mjrft/HexapodRigid-v0") for _ in range(2)])
    gait = make_gait("tripod:f=1,duty=0.6,sweep=1.0", venv)
    obs = venv.reset()
    for _ in range(30):
        actions, _ = gait.predict(obs, episode_start=np.zeros(2, bool))
        assert actions.shape == (2, 6)
        obs, *_ = venv.step(actions)
    with pytest.raises(ValueError, match="batch of 3"):
        gait.predict(np.zeros((3, obs.shape[1])))
    venv.close()


def test_rect_walks_the_pitch_held_biped():
    env = gymnasium.make("mjrft/BipedSand-v0", pitch_free=False, max_episode_steps=10_000)
    gait = make_gait("rect:angle=20", env)
    u, terminated, info = run(env, gait, 3.0)
    assert not terminated
    assert u.data.qpos[0] > 0.05  # ~4 cm/s
    assert info["sinkage"].max() > 0
    env.close()
    env = gymnasium.make("mjrft/BipedRigid-v0")
    with pytest.warns(GaitWarning, match="pitch_free=False"):
        make_gait("rect", env)
    env.close()


def test_stand_holds_the_humanoid_on_sand():
    env = gymnasium.make("mjrft/HumanoidSand-v0", task="stand", max_episode_steps=10_000)
    gait = make_gait("stand:crouch=0.4", env)
    u, terminated, info = run(env, gait, 1.5)
    assert not terminated and u.torso_tilt() < 0.1
    knees = u.data.qpos[[u.model.jnt_qposadr[u.model.joint(n).id] for n in ("left_knee", "right_knee")]]
    np.testing.assert_allclose(knees, 0.4, atol=0.05)
    assert info["granular_force"][:, 2].sum() == pytest.approx(50 * 9.81, rel=0.2)
    env.close()


def test_shift_walk_runs_on_the_humanoid():
    env = gymnasium.make("mjrft/HumanoidRigid-v0", max_episode_steps=10_000)
    gait = make_gait("shift", env)
    u, terminated, _ = run(env, gait, 8.5)  # the first half step, a whole step and the CoM shift
    assert not terminated
    assert u.data.subtree_com[1, 1] > 0.03  # the CoM went over to the left (stepping) foot
    env.close()
    env = gymnasium.make("mjrft/HumanoidSand-v0", max_episode_steps=10_000)
    u, terminated, info = run(env, make_gait("shift:start=0.2", env), 1.0)
    assert info["sinkage"].min() > 0  # both feet in the sand, CoM moving over the right foot
    env.close()


def test_tripod_that_needs_all_the_hip_speed_warns_and_walks_in_step():
    """At 3 Hz the tripod's stance needs 6 pi rad/s, the env's default max_hip_speed: tripod B never catches up its
    half cycle from the env's start (measured: the tripods stay in step), so the gait warns; with speed to spare
    (2.5 Hz, or max_hip_speed = 12 pi) it does not, and the tripods are half a turn apart."""
    def tripod_gap(f, **kw):
        env = gymnasium.make("mjrft/HexapodSand-v0", **kw)
        u = env.unwrapped
        obs, _ = env.reset(seed=0)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            gait = make_gait(f"tripod:f={f:g}", env)
        for _ in range(100):
            action, _ = gait.predict(obs)
            obs, *_ = env.step(action)
        q = u.data.qpos[u.task.hip_qadr]
        gap = (q[list(u.TRIPOD_B_IDX)].mean() - q[list(u.TRIPOD_A_IDX)].mean()) / (2 * math.pi)
        env.close()
        return gap, [w for w in caught if issubclass(w.category, GaitWarning)]

    gap, warned = tripod_gap(3.0)
    assert abs(gap) < 0.01 and len(warned) == 1 and "max_hip_speed above 18.85" in str(warned[0].message)
    for f, kw in ((2.5, {}), (3.0, {"max_hip_speed": 12 * math.pi})):
        gap, warned = tripod_gap(f, **kw)
        assert abs(gap - 0.5) < 0.01 and not warned

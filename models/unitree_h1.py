"""The Unitree H1 humanoid (vendored under ``third_party/unitree_h1/``: Unitree's own MuJoCo model, whose feet
collide through a triangle mesh) and a simple controller for it on sand or on its rigid floor.

The model's 20 actuators are torque motors. :class:`Controller` is a joint PD holding the ``home`` keyframe pose
with two additions, both needed on poppy seeds (measured in ``tests/models/test_unitree_h1.py``):

* a lean: both ankles turned so that the centre of mass stands over the midpoint of the soles' centroids. In the
  keyframe it is 6 cm behind it, outside the soles' middle third (+-5 cm of a 30 cm sole), where a yielding bed
  cannot hold the moment: the heels sink and the robot tips backwards. :meth:`Controller.reset` puts the robot in
  the leaning pose with its soles level at the floor's height;
* an ankle balance term (the "ankle strategy"): both ankles add ``balance_kp x`` (centre of mass ahead of the
  soles' midpoint, m) ``+ balance_kd x`` (pelvis forward speed). The robot is an inverted pendulum of about
  M g h = 51.6 kg x 9.81 m/s^2 x 0.9 m = 460 N m/rad of toppling stiffness, more than the joint PD chain gives
  under the ankles' 40 N m limit: without the term it tips over within 2 s even on its rigid floor.

:meth:`Controller.step_targets` is an open-loop sway: the hip rolls move the pelvis from side to side and the
unloaded leg bends (knee, half of it at the hip pitch and ankle, keeping the foot level). The gains are documented
choices, not from a paper or from Unitree: stiff enough that the knee sags by under 0.05 rad under its ~42 N m
holding torque.

:meth:`Controller.walk` is a slow quasi-static walk (measured in the same test file). The ankles cannot roll, so
the weight goes sideways by rolling the legs, feet and all, in the grains; each step:

* shift (1.5 s): both hip rolls turn by up to ``walk_roll`` towards the stance foot while a pelvis-levelling term
  changes the two legs' lengths (``level`` m of length per rad of pelvis roll, at most ``level_max``) so that the
  legs tilt rather than the pelvis; a damping term on the hip rolls (``lateral_kd`` times the pelvis' sideways
  speed) slows the sway. The ankles' balance reference moves ``walk_shift`` of the way to the stance sole, and
  the stance ankle takes the whole proportional balance term;
* lift (0.15 s) the other foot by ``walk_lift`` towards the hip (its sole comes up to 3-4 cm deep, unloaded),
  swing it (0.2 s) two step lengths forward (on the first step one), lower it (0.15 s): quick, since little holds
  the robot sideways on one 3 cm wide sole; the levelling lengths are held meanwhile;
* shift back to the middle (1 s), both feet moving back by one step length under the pelvis.

Throughout, the ankles' targets follow their soles' pitch (``foot_level`` rad per rad), which keeps the soles level
in the grains, whose heels otherwise sink until it falls backwards. The walk's gains were chosen by a search over a
few hundred combinations on poppy seeds (controller choices, not terrain parameters); without the hip-roll shift, or
without the levelling, it falls sideways on the first step.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import mujoco
import numpy as np

from mjrft.geometry import discretize_geom

from .humanoid import humanoid_leg_ik

H1_DIR = os.path.join(os.path.dirname(__file__), "third_party", "unitree_h1")
SCENE = os.path.join(H1_DIR, "scene.xml")
FEET = ("left_ankle_link", "right_ankle_link")  # the bodies whose mesh geoms touch the ground

# joint PD gains by joint-name part (N m/rad, N m s/rad); the "not_use_joint" of Unitree's model gets none
KP = {"hip": 1000.0, "knee": 1500.0, "ankle": 300.0, "torso": 300.0, "shoulder": 100.0, "elbow": 100.0}
KD = {"hip": 20.0, "knee": 30.0, "ankle": 6.0, "torso": 6.0, "shoulder": 2.0, "elbow": 2.0}
THIGH = SHANK = 0.40  # m: the model's hip-pitch-to-knee and knee-to-ankle distances (0.3998 m)
# the walk's phases (s): shift to the stance foot, lift, swing, lower, shift back to the middle
WALK_PHASES = (1.5, 0.15, 0.2, 0.15, 1.0)


def load(keyframe: str = "home") -> tuple[mujoco.MjModel, mujoco.MjData]:
    """The H1 scene (robot above the plane ``floor``) and data reset to ``keyframe``."""
    m = mujoco.MjModel.from_xml_path(SCENE)
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key(keyframe).id)
    mujoco.mj_forward(m, d)
    return m, d


def pelvis_pitch(d: mujoco.MjData) -> float:
    """Pitch of the pelvis (rad, about the world y axis; positive: leaning forward)."""
    R = d.xmat[1].reshape(3, 3)
    return float(np.arctan2(R[0, 2], R[2, 2]))


def pelvis_roll(d: mujoco.MjData) -> float:
    """Roll of the pelvis (rad, about its x axis; positive: its left side up)."""
    R = d.xmat[1].reshape(3, 3)
    return float(np.arctan2(R[2, 1], R[2, 2]))


def leg_ik(x: float, h: float) -> tuple[float, float]:
    """Hip pitch and knee angles (rad, the model's signs) that put the ankle ``x`` ahead of and ``h`` below the
    hip pitch axis in the pelvis' sagittal plane (``leg_ik(0, h)`` with h of the keyframe gives -0.4, 0.8):
    :func:`mjrft.models.humanoid.humanoid_leg_ik` with no sideways offset."""
    joints = humanoid_leg_ik(x, 0.0, -h, THIGH, SHANK)
    return joints["hip_pitch"], joints["knee"]


def sole_centroid(m: mujoco.MjModel, body: int, resolution: float = 0.01) -> np.ndarray:
    """Area centroid (body frame) of the downward-facing surface of ``body``'s collision geoms in the
    ``home`` pose: where the sand's pressure on a level sole is centred."""
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key("home").id)
    mujoco.mj_kinematics(m, d)
    R = d.xmat[body].reshape(3, 3)
    pos, area = [], []
    for g in np.flatnonzero((m.geom_bodyid == body) & (m.geom_contype | m.geom_conaffinity).astype(bool)):
        el = discretize_geom(m, int(g), resolution)
        down = (el.normal @ R.T)[:, 2] < -0.5
        pos.append(el.pos[down])
        area.append(el.area[down])
    pos, area = np.concatenate(pos), np.concatenate(area)
    return (area[:, None] * pos).sum(0) / area.sum()


@dataclass
class Controller:
    """Joint PD around the keyframe pose plus the ankle balance term; ``__call__`` writes ``data.ctrl``."""

    model: mujoco.MjModel
    balance_kp: float = 600.0  # N m per m of centre-of-mass offset, per ankle
    balance_kd: float = 60.0  # N m s/m, per ankle, on the pelvis' forward speed
    # the walk (:meth:`walk`)
    walk_roll: float = 0.18  # rad: both hip rolls turned towards the stance foot before a foot lifts
    walk_shift: float = 0.6  # how far the balance reference moves from the soles' midpoint to the stance sole
    walk_lift: float = 0.16  # m the swing foot is raised (the soles stand 13 cm deep at rest in poppy seeds)
    level: float = 0.6  # m per rad of pelvis roll: one leg this much shorter, the other longer (double support)
    level_max: float = 0.03  # m: at most this much longer or shorter per leg
    lateral_kd: float = 100.0  # N m s/m on both hip rolls per m/s of the pelvis' sideways speed (double support)
    foot_level: float = 1.0  # rad of ankle target per rad of its sole's pitch
    kp: np.ndarray = field(init=False)
    kd: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        m = self.model
        joints = m.actuator_trnid[:, 0]
        names = [m.joint(j).name for j in joints]
        part = [next((k for k in KP if k in n), None) for n in names]
        self.kp = np.array([KP[p] if p else 0.0 for p in part])
        self.kd = np.array([KD[p] if p else 0.0 for p in part])
        self.qadr = m.jnt_qposadr[joints]
        self.dadr = m.jnt_dofadr[joints]
        self.home = m.key("home").qpos[self.qadr].copy()
        act = {n: a for a, n in enumerate(names)}
        self.ankles = np.array([act["left_ankle_joint"], act["right_ankle_joint"]])
        self.hip_roll = np.array([act["left_hip_roll_joint"], act["right_hip_roll_joint"]])
        self.hip_pitch = np.array([act["left_hip_pitch_joint"], act["right_hip_pitch_joint"]])
        self.knee = np.array([act["left_knee_joint"], act["right_knee_joint"]])
        self.feet = [m.body(f).id for f in FEET]
        self.sole = [sole_centroid(m, b) for b in self.feet]
        # lean the body over the soles: in the keyframe pose the centre of mass is 6 cm behind the soles'
        # centroid, outside their middle third (the kern: +-5 cm of a 30 cm sole), where a yielding bed cannot
        # hold the moment and the heels sink until the robot tips; turning both ankles by the angle that moves
        # the centre of mass over the centroid removes that moment
        d = mujoco.MjData(m)
        mujoco.mj_resetDataKeyframe(m, d, m.key("home").id)
        mujoco.mj_forward(m, d)
        height = d.subtree_com[1][2] - 0.5 * (d.xpos[self.feet[0]][2] + d.xpos[self.feet[1]][2])
        self.lean = -self.com_offset(d) / height  # rad, forward
        self.home[self.ankles] -= self.lean  # a smaller ankle angle tilts the shank forward over the foot
        self.lo, self.hi = m.actuator_ctrlrange[:, 0], m.actuator_ctrlrange[:, 1]
        self.leg_height = 2.0 * THIGH * np.cos(0.4)  # hip pitch axis to ankle in the keyframe (knee 0.8 rad)
        self.leg_offset = np.zeros(2)  # the levelling's leg lengths (left, right), held while a foot is up

    def reset(self, d: mujoco.MjData) -> None:
        """Reset ``d`` to the ``home`` keyframe leaning over the soles: the ankles at their targets, the whole
        robot turned forward by the lean about the y axis so that the soles stay level, lowered until the
        lowest point of its collision geoms is at z = 0 (the floor's height)."""
        m = self.model
        mujoco.mj_resetDataKeyframe(m, d, m.key("home").id)
        d.qpos[self.qadr[self.ankles]] = self.home[self.ankles]
        half = 0.5 * self.lean
        d.qpos[3:7] = [np.cos(half), 0.0, np.sin(half), 0.0]
        mujoco.mj_kinematics(m, d)
        lowest = np.inf
        for g in np.flatnonzero(np.isin(m.geom_bodyid, self.feet)):
            verts = m.mesh_vert[m.mesh_vertadr[m.geom_dataid[g]]:][:m.mesh_vertnum[m.geom_dataid[g]]]
            lowest = min(lowest, float((verts @ d.geom_xmat[g].reshape(3, 3).T + d.geom_xpos[g])[:, 2].min()))
        d.qpos[2] -= lowest
        mujoco.mj_forward(m, d)

    def step_targets(self, t: float, sway: float = 0.05, lift: float = 0.1, freq: float = 0.5) -> np.ndarray:
        """Joint targets of the open-loop sway at ``t`` (s): both hip rolls turn by ``sway`` rad at ``freq`` Hz,
        shifting the weight towards one foot, and the other leg's knee bends by up to ``lift`` rad (half of it at
        its hip pitch and ankle, keeping the foot level) while it carries the least weight. The defaults move
        nearly all the weight from foot to foot on poppy seeds without lifting a foot out of the grains; 0.08 rad,
        0.25 rad at 1 Hz tip the robot sideways (no lateral balance)."""
        q = self.home.copy()
        phase = 2.0 * np.pi * freq * t
        q[self.hip_roll] += sway * np.sin(phase)  # both hips roll together: the pelvis moves sideways
        bend = lift * np.maximum(np.array([-np.sin(phase), np.sin(phase)]), 0.0) ** 2  # lift the unloaded leg
        q[self.knee] += bend
        q[self.hip_pitch] -= 0.5 * bend
        q[self.ankles] -= 0.5 * bend
        return q

    def gait(self, t: float, steps: int, length: float) -> tuple[np.ndarray, np.ndarray, float, bool]:
        """The walk's plan at ``t`` (s): each foot's (left, right) ankle offset ahead of its keyframe position and
        height above it relative to the hip (m), the planned share of the left foot in the balance reference,
        and whether both feet are down. The left foot steps first; after ``steps`` steps it stands."""
        shift, lift, swing, lower, back = WALK_PHASES
        period = sum(WALK_PHASES)
        smooth = lambda u: 0.5 - 0.5 * np.cos(np.pi * np.clip(u, 0.0, 1.0))  # noqa: E731
        ahead, up = np.zeros(2), np.zeros(2)
        k = int(t // period)
        if k >= steps:  # the last swing foot ahead, the pelvis over the middle
            ahead[(steps - 1) % 2], ahead[steps % 2] = 0.5 * length, -0.5 * length
            return ahead, up, 0.5, True
        s = t - k * period
        sw = k % 2  # the swing foot: 0 left, 1 right
        st = 1 - sw
        stance_share = 0.5 + self.walk_shift * (0.5 if st == 0 else -0.5)
        start_st = 0.5 * length if k else 0.0  # where the feet are when the step begins
        start_sw = -0.5 * length if k else 0.0
        ahead[st], ahead[sw] = start_st, start_sw
        end = start_st + length  # where the swing foot lands
        if s <= shift:
            return ahead, up, 0.5 + (stance_share - 0.5) * smooth(s / shift), True
        s -= shift
        if s < lift + swing + lower:
            if s < lift:
                up[sw] = self.walk_lift * smooth(s / lift)
            elif s < lift + swing:
                up[sw] = self.walk_lift
                ahead[sw] = start_sw + (end - start_sw) * smooth((s - lift) / swing)
            else:
                up[sw] = self.walk_lift * (1.0 - smooth((s - lift - swing) / lower))
                ahead[sw] = end
            return ahead, up, stance_share, False
        u = smooth((s - lift - swing - lower) / back)  # back to the middle: both feet move back under the pelvis
        ahead[sw] = end - (end - 0.5 * length) * u
        ahead[st] = start_st - (start_st + 0.5 * length) * u
        return ahead, up, stance_share + (0.5 - stance_share) * u, True

    def walk(self, d: mujoco.MjData, t: float, steps: int = 2, length: float = 0.05) -> None:
        """Write ``data.ctrl`` for the walk's plan at ``t`` (s, from its start): ``steps`` steps of ``length`` m
        (the pelvis advances by about half of it on the first step and by it on each further one), then stand."""
        ahead, up, share, both_down = self.gait(t, steps, length)
        if both_down:  # level the pelvis with the legs' lengths (the left leg shorter when its side is up)
            self.leg_offset = np.clip(self.level * pelvis_roll(d) * np.array([-1.0, 1.0]), -self.level_max,
                                      self.level_max)
        q = self.home.copy()
        for i in range(2):
            hip, knee = leg_ik(ahead[i], self.leg_height - up[i] + self.leg_offset[i])
            q[self.hip_pitch[i]], q[self.knee[i]] = hip, knee
            q[self.ankles[i]] = -(hip + knee) - self.lean
        q[self.hip_roll] += self.walk_roll * (0.5 - share) / (0.5 * self.walk_shift)
        pitch = [np.arctan2(d.xmat[b].reshape(3, 3)[0, 2], d.xmat[b].reshape(3, 3)[2, 2]) for b in self.feet]
        q[self.ankles] += self.foot_level * np.array(pitch)
        u = self.kp * (q - d.qpos[self.qadr]) - self.kd * d.qvel[self.dadr]
        soles = [d.xpos[b] + d.xmat[b].reshape(3, 3) @ c for b, c in zip(self.feet, self.sole)]
        ref = share * soles[0] + (1.0 - share) * soles[1]
        stance = np.array([2.0 * share, 2.0 * (1.0 - share)])  # 1, 1 in the middle; 1.6, 0.4 on one foot
        u[self.ankles] += stance * self.balance_kp * (d.subtree_com[1][0] - ref[0]) + self.balance_kd * d.qvel[0]
        if both_down:
            u[self.hip_roll] += self.lateral_kd * d.qvel[1]
        d.ctrl[:] = np.clip(u, self.lo, self.hi)

    def __call__(self, d: mujoco.MjData, targets: np.ndarray | None = None) -> None:
        q = self.home if targets is None else targets
        u = self.kp * (q - d.qpos[self.qadr]) - self.kd * d.qvel[self.dadr]
        u[self.ankles] += self.balance_kp * self.com_offset(d) + self.balance_kd * d.qvel[0]
        d.ctrl[:] = np.clip(u, self.lo, self.hi)

    def com_offset(self, d: mujoco.MjData) -> float:
        """How far (m, along x) the centre of mass is ahead of the midpoint of the two soles' centroids."""
        soles = [d.xpos[b] + d.xmat[b].reshape(3, 3) @ c for b, c in zip(self.feet, self.sole)]
        return float(d.subtree_com[1][0] - 0.5 * (soles[0][0] + soles[1][0]))

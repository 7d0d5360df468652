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
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import mujoco
import numpy as np

from mjrft.geometry import discretize_geom

H1_DIR = os.path.join(os.path.dirname(__file__), "third_party", "unitree_h1")
SCENE = os.path.join(H1_DIR, "scene.xml")
FEET = ("left_ankle_link", "right_ankle_link")  # the bodies whose mesh geoms touch the ground

# joint PD gains by joint-name part (N m/rad, N m s/rad); the "not_use_joint" of Unitree's model gets none
KP = {"hip": 1000.0, "knee": 1500.0, "ankle": 300.0, "torso": 300.0, "shoulder": 100.0, "elbow": 100.0}
KD = {"hip": 20.0, "knee": 30.0, "ankle": 6.0, "torso": 6.0, "shoulder": 2.0, "elbow": 2.0}


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

    def __call__(self, d: mujoco.MjData, targets: np.ndarray | None = None) -> None:
        q = self.home if targets is None else targets
        u = self.kp * (q - d.qpos[self.qadr]) - self.kd * d.qvel[self.dadr]
        u[self.ankles] += self.balance_kp * self.com_offset(d) + self.balance_kd * d.qvel[0]
        d.ctrl[:] = np.clip(u, self.lo, self.hi)

    def com_offset(self, d: mujoco.MjData) -> float:
        """How far (m, along x) the centre of mass is ahead of the midpoint of the two soles' centroids."""
        soles = [d.xpos[b] + d.xmat[b].reshape(3, 3) @ c for b, c in zip(self.feet, self.sole)]
        return float(d.subtree_com[1][0] - 0.5 * (soles[0][0] + soles[1][0]))

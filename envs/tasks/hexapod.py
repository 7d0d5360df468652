"""The hexapod's task (``mjrft/HexapodSand-v0``, ``HexapodRigid-v0``, ``HexapodShoal-v0`` and the MJX
``HexapodSand`` / ``HexapodRigid``): hip-velocity commands integrated into the servo targets, the 35-number
observation; the tables are in :class:`mjrft.envs.hexapod.HexapodSand`."""

from __future__ import annotations

import mujoco

from .base import LocomotionTask


class HexapodTask(LocomotionTask):
    """The hexapod walking forward. ``dt``: the control step (s), over which a command ``a`` advances a hip's
    servo target by ``a * max_hip_speed * dt`` (rad), kept within ``max_lag`` (rad) of the hip's angle;
    ``planar``: the model's torso held in the sagittal plane (root joints ``rootx, rootz, rooty``), whose
    observation is written in the free body's layout. The other arguments: :class:`LocomotionTask`."""

    def __init__(self, model: mujoco.MjModel, *, dt: float, max_hip_speed: float, max_lag: float,
                 planar: bool = False, **kwargs):
        super().__init__(model, **kwargs)
        self.dt = float(dt)
        self.max_hip_speed = float(max_hip_speed)
        self.max_lag = float(max_lag)
        self.planar = bool(planar)
        joints = model.actuator_trnid[:, 0]
        self.hip_qadr = model.jnt_qposadr[joints].copy()
        self.hip_dadr = model.jnt_dofadr[joints].copy()
        #: the torso's height above its joints' origin (the planar model's ``rootz`` counts from it)
        self.torso_z0 = float(model.body_pos[self.torso, 2])
        self.observation_size = 35

    def reset_ctrl(self, xp, qpos):
        """The servo targets at reset: the hips where they are."""
        return qpos[self.hip_qadr]

    def action_to_ctrl(self, xp, qpos, ctrl, action):
        """The new servo targets: the current ones ``ctrl`` advanced by the hip-velocity command ``action``
        (clipped to [-1, 1]) over ``dt``, then kept within ``max_lag`` of the hip angles in ``qpos``."""
        a = xp.clip(action, -1.0, 1.0)
        q = qpos[self.hip_qadr]
        return xp.clip(ctrl + a * self.max_hip_speed * self.dt, q - self.max_lag, q + self.max_lag)

    def observation(self, xp, data, ctrl):
        """The 35 numbers of the observation table: torso height and orientation, sin and cos of the hips,
        the torso's twist, the hip rates and the servo targets ``ctrl`` minus the hip angles."""
        qpos, qvel = data.qpos, data.qvel
        hips = qpos[self.hip_qadr]
        if self.planar:  # rootx, rootz, rooty: the free-joint layout rebuilt from the joints
            half = 0.5 * qpos[2]
            zero = xp.zeros_like(half)
            pose = xp.stack([self.torso_z0 + qpos[1], xp.cos(half), zero, xp.sin(half), zero])
            twist = xp.stack([qvel[0], zero, qvel[1], zero, qvel[2], zero])
        else:
            pose, twist = qpos[2:7], qvel[:6]
        return xp.concatenate([pose, xp.sin(hips), xp.cos(hips), twist, qvel[self.hip_dadr], ctrl - hips])

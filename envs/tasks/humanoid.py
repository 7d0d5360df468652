"""The humanoid's task (``mjrft/HumanoidSand-v0``, ``HumanoidRigid-v0`` and the MJX ``HumanoidSand`` /
``HumanoidRigid``): walking forward or standing still; the tables are in :class:`mjrft.envs.humanoid.HumanoidSand`."""

from __future__ import annotations

import mujoco

from .base import JointTargets, LocomotionTask

MODES = ("walk", "stand")


class HumanoidTask(JointTargets, LocomotionTask):
    """The humanoid walking (``mode="walk"``: forward term ``scale * dx/dt``) or standing (``"stand"``: ``-scale``
    times the horizontal speed of its centre of mass); normalised joint-angle targets (:class:`JointTargets`),
    the observation ``qpos[2:]`` and ``qvel``. Arguments: :class:`LocomotionTask`'s, ``init_qpos`` and ``mode``."""

    def __init__(self, model: mujoco.MjModel, *, init_qpos, mode: str = "walk", **kwargs):
        if mode not in MODES:
            raise ValueError(f"unknown task {mode!r}; valid choices: {', '.join(MODES)}")
        LocomotionTask.__init__(self, model, **kwargs)
        JointTargets.__init__(self, model, init_qpos)
        self.mode = mode
        self.observation_size = model.nq - 2 + model.nv

    def forward(self, xp, scale, x_velocity, xy_velocity):
        if self.mode == "stand":
            return -scale * xp.linalg.norm(xy_velocity)
        return scale * x_velocity

    def observation(self, xp, data, ctrl):
        return xp.concatenate([data.qpos[2:], data.qvel])

"""The planar biped's task (``mjrft/BipedSand-v0``, ``BipedRigid-v0`` and the MJX ``BipedSand`` /
``BipedRigid``); the tables are in :class:`mjrft.envs.biped.BipedSand`."""

from __future__ import annotations

import mujoco

from .base import JointTargets, LocomotionTask


class BipedTask(JointTargets, LocomotionTask):
    """The biped walking forward: normalised joint-angle targets (:class:`JointTargets`), the observation
    ``qpos[1:]`` (all but ``rootx``) and ``qvel``. Arguments: :class:`LocomotionTask`'s and ``init_qpos``."""

    def __init__(self, model: mujoco.MjModel, *, init_qpos, **kwargs):
        LocomotionTask.__init__(self, model, **kwargs)
        JointTargets.__init__(self, model, init_qpos)
        self.observation_size = model.nq - 1 + model.nv

    def observation(self, xp, data, ctrl):
        return xp.concatenate([data.qpos[1:], data.qvel])

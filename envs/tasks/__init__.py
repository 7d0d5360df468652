"""The tasks of mjrft's robots, written once for the gymnasium envs (NumPy on ``mujoco.MjData``) and the MJX envs
(JAX on ``mjx.Data``): observation, action mapping, reward terms, termination and metrics
(:mod:`mjrft.envs.tasks.base`). Each backend only steps the physics.

==========================  ===============================================  =================================
task                        gymnasium ids                                    MJX envs (:mod:`mjrft.envs.mjx`)
==========================  ===============================================  =================================
:class:`HexapodTask`        ``mjrft/HexapodSand-v0``, ``HexapodRigid-v0``,   ``HexapodSand``, ``HexapodRigid``
                            ``HexapodShoal-v0``
:class:`BipedTask`          ``mjrft/BipedSand-v0``, ``BipedRigid-v0``        ``BipedSand``, ``BipedRigid``
:class:`HumanoidTask`       ``mjrft/HumanoidSand-v0``, ``HumanoidRigid-v0``  ``HumanoidSand``, ``HumanoidRigid``
==========================  ===============================================  =================================
"""

from .base import METRICS, REWARD_TERMS, JointTargets, LocomotionTask
from .biped import BipedTask
from .hexapod import HexapodTask
from .humanoid import HumanoidTask

__all__ = ["METRICS", "REWARD_TERMS", "BipedTask", "HexapodTask", "HumanoidTask", "JointTargets", "LocomotionTask"]

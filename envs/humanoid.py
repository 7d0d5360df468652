"""HUBO-class humanoid on granular media (``mjrft/HumanoidSand-v0``) or rigid ground (``mjrft/HumanoidRigid-v0``)."""

from __future__ import annotations

from mjrft.models.humanoid import FOOT_LENGTH, FOOT_WIDTH, humanoid_xml

from .base import GranularMujocoEnv, split_env_kwargs
from .tasks import HumanoidTask
from .tasks.humanoid import MODES as TASKS


class HumanoidSand(GranularMujocoEnv):
    """HUBO-class humanoid (1.2 m, 50 kg, 19 position servos) walking or standing on sand.

    Model: :func:`mjrft.models.humanoid_xml` (``foot_length``, ``foot_width``, ``foot_cutout``,
    ``sand``); granular bodies ``left_foot right_foot``. Physics step 1 ms, default ``frame_skip = 10``,
    under every preset too (within the 2 % gait budget of ``python benchmarks/env_timestep.py``).

    ## Action space

    ``Box(-1, 1, (19,), float32)`` in actuator order (``left_hip_yaw, left_hip_roll, left_hip_pitch,
    left_knee, left_ankle_pitch, left_ankle_roll``, the same ``right_``, ``waist_yaw``, then per arm
    ``shoulder_pitch, shoulder_roll, elbow``): normalised joint-angle targets mapped piecewise-linearly
    ``-1 -> ctrlrange low``, ``0 -> initial pose (all 0 rad, standing straight)``,
    ``+1 -> ctrlrange high``. ``a = 0`` therefore holds the initial posture.

    ## Observation space

    ``Box(-inf, inf, (49,), float64)``:

    | index  | observation                                         | unit      |
    |--------|-----------------------------------------------------|-----------|
    | 0      | pelvis height z (surface at 0; 0.78 m standing)     | m         |
    | 1-4    | pelvis orientation quaternion (w, x, y, z)          | -         |
    | 5-23   | joint angles (actuator order)                       | rad       |
    | 24-26  | pelvis linear velocity (world)                      | m/s       |
    | 27-29  | pelvis angular velocity (local)                     | rad/s     |
    | 30-48  | joint velocities                                    | rad/s     |

    ## Rewards

    | term     | ``task="walk"``                               | ``task="stand"``                            | default |
    |----------|-----------------------------------------------|---------------------------------------------|---------|
    | forward  | ``forward_reward_weight * dx/dt`` (m/s)        | ``-forward_reward_weight * |v_xy|`` (CoM)     | 1.0     |
    | healthy  | ``healthy_reward`` per step while healthy      | same                                        | 1.0     |
    | energy   | ``-energy_cost_weight * P / (m g)``            | same (``P``: ``info["power"]``)             | 0.05    |
    | ctrl     | ``-ctrl_cost_weight * sum(a**2)``              | same                                        | 0.0     |

    ## Termination and truncation

    Unhealthy (a fall): pelvis height outside ``healthy_z_range`` (default (0.5, 1.2) m) or pelvis tilt
    from vertical above ``max_tilt`` (default 0.8 rad). Truncation: ``max_episode_steps`` of the
    registration (1000 steps = 10 s) and ``episode_seconds``.

    ## Info

    See :mod:`mjrft.envs.base`; ``sinkage`` / ``granular_force`` rows: ``left_foot``, ``right_foot``.
    """

    base_model = "humanoid"
    foot_names = ("left_foot", "right_foot")
    torso_name = "pelvis"
    default_camera_config = {"trackbodyid": 1, "distance": 4.0, "elevation": -15.0}

    defaults = {"energy_cost_weight": 0.05, "healthy_reward": 1.0, "healthy_z_range": (0.5, 1.2), "max_tilt": 0.8}

    def __init__(self, sand: bool = True, *, task: str = "walk", foot_length: float = FOOT_LENGTH,
                 foot_width: float = FOOT_WIDTH, foot_cutout: bool = False, **kwargs):
        """Own arguments: ``task`` and ``foot_length``, ``foot_width``, ``foot_cutout``
        (:func:`mjrft.models.humanoid_xml`); the common ones are in :mod:`mjrft.envs.base` (defaults here:
        ``defaults``); any other keyword goes to :func:`~mjrft.models.humanoid_xml`."""
        pickle_kwargs = dict(sand=sand, task=task, foot_length=foot_length, foot_width=foot_width,
                             foot_cutout=foot_cutout, **kwargs)
        if task not in TASKS:
            raise ValueError(f"unknown task {task!r}; valid choices: {', '.join(TASKS)}")
        self._mode = task
        env_kw, model_kw = split_env_kwargs(kwargs)
        xml = humanoid_xml(foot_length=foot_length, foot_width=foot_width, foot_cutout=foot_cutout, sand=sand,
                           **model_kw)
        super().__init__(xml, sand=sand, pickle_kwargs=pickle_kwargs, **{**self.defaults, **env_kw})

    def _make_task(self, **common) -> HumanoidTask:
        return HumanoidTask(self.model, init_qpos=self.init_qpos, mode=self._mode, **common)


class HumanoidRigid(HumanoidSand):
    """:class:`HumanoidSand` on a rigid floor (``sand=False``; see that class for the tables)."""

    def __init__(self, **kwargs):
        kwargs.pop("sand", None)
        super().__init__(sand=False, **kwargs)

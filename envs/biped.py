"""Planar robophysics biped on granular media (``mjrft/BipedSand-v0``) or rigid ground (``mjrft/BipedRigid-v0``)."""

from __future__ import annotations

from mjrft.models.biped import biped_xml

from .base import GranularMujocoEnv, split_env_kwargs
from .tasks import BipedTask

#: the sand biped's physics step (s), steps per env step and granular coupling when neither ``timestep`` nor
#: ``frame_skip`` (nor ``implicit``) is given (under the ``default`` and ``accurate`` presets too: it is within the 2 %
#: budget): the implicit step at 2 ms x 5 = the 10 ms control period, the
#: largest step whose gait speed and sinkage stay within 2 % of a 0.05 ms reference and that stays stable under random
#: actions (``python benchmarks/env_timestep.py``; docs/numerics.md, "Each env's physics step"). The explicit step
#: passes the feet's stability limit there under random actions (``tests/envs/test_biped_timestep.py``).
SAND_TIMESTEP = 0.002
SAND_FRAME_SKIP = 5
#: the ``"fast"`` preset's step on sand: its 4x coarser elements (36 per foot) chatter at 2 ms under the 30 deg ``rect``
#: gait (one warning in 6 s) and not at 1 ms (``python benchmarks/env_presets.py``)
FAST_STEP = (0.001, 10)


class BipedSand(GranularMujocoEnv):
    """Planar 1.6 kg biped (x-z plane, 4 pitch servos per leg) walking forward (+x) on sand.

    Model: :func:`mjrft.models.biped_xml` (``foot``, ``foot_size``, ``foot_width``, ``sand``, ...);
    granular bodies ``left_foot right_foot``. On sand the implicit granular step at 2 ms, ``frame_skip = 5``
    (``dt = 0.01`` s; ``SAND_TIMESTEP``, ``SAND_FRAME_SKIP``) when neither ``timestep`` nor ``frame_skip`` is
    given, under the ``default`` and ``accurate`` presets too, 1 ms x 10 under ``fast`` (``FAST_STEP``)
    (``implicit=False``: the explicit step, which needs <= 0.5 ms);
    on the rigid floor 1 ms and ``frame_skip = 10``, under every preset too (both within the 2 % gait budget of
    ``python benchmarks/env_timestep.py``).
    Feet (``foot``): ``"cone"`` (default; the thesis robot's conical foot, circular sole 8.5 cm across),
    ``"wedge"`` (the thesis simulation's 8.5 x 8.5 x 7.5 cm wedge) or ``"roller"`` (a cylinder lying
    across); ``foot_size`` is the sole's diameter or length (m). The planarised robot of the thesis'
    gait study held the torso pitch: ``pitch_free=False``.

    ## Action space

    ``Box(-1, 1, (8,), float32)``, actuator order ``left_hip, left_knee_upper, left_knee_lower,
    left_ankle, right_hip, ...``: normalised joint-angle targets of the position servos, mapped
    piecewise-linearly ``-1 -> ctrlrange low``, ``0 -> initial pose (0 rad, legs straight)``,
    ``+1 -> ctrlrange high`` (hip [-2, 2], knee joints [-0.3, 1.6], ankle [-1.2, 1.2] rad;
    ``env.unwrapped.action_to_ctrl`` / ``ctrl_to_action`` convert).

    ## Observation space

    ``Box(-inf, inf, (21,), float64)`` (with the default ``pitch_free=True``):

    | index  | observation                                                | unit      |
    |--------|------------------------------------------------------------|-----------|
    | 0      | ``rootz``: torso height change from the initial height     | m         |
    | 1      | ``rooty``: torso pitch                                     | rad       |
    | 2-9    | joint angles (actuator order)                              | rad       |
    | 10     | torso x velocity                                           | m/s       |
    | 11     | torso z velocity                                           | m/s       |
    | 12     | torso pitch rate                                           | rad/s     |
    | 13-20  | joint velocities                                           | rad/s     |

    The x position (``rootx``) is excluded.

    ## Rewards

    | term     | value                                                          | default weight |
    |----------|----------------------------------------------------------------|----------------|
    | forward  | ``forward_reward_weight * dx/dt`` (m/s)                         | 1.0            |
    | healthy  | ``healthy_reward`` per step while healthy                       | 0.5            |
    | energy   | ``-energy_cost_weight * P / (m g)`` (m/s; ``P``: ``info["power"]``)    | 0.05           |
    | ctrl     | ``-ctrl_cost_weight * sum(a**2)``                               | 0.0            |

    ## Termination and truncation

    Unhealthy: torso (hip axis) height outside ``healthy_z_range`` (default (0.05, 0.6) m; standing
    straight-legged it is 0.2075 m above the surface, walking the ``rect`` gait 0.14 m minus the
    sinkage; below 0.05 m the legs have folded and the torso, whose bottom is 1.5 cm below the hip
    axis, is 3.5 cm from the sand) or torso pitch magnitude above ``max_tilt`` (default 1.0 rad).
    Truncation: ``max_episode_steps`` of the registration (1000 steps = 10 s), ``episode_seconds``.

    ## Info

    See :mod:`mjrft.envs.base`; ``sinkage`` / ``granular_force`` rows: ``left_foot``, ``right_foot``.
    """

    base_model = "biped"
    foot_names = ("left_foot", "right_foot")
    default_camera_config = {"trackbodyid": 1, "distance": 1.2, "elevation": -10.0}

    defaults = {"energy_cost_weight": 0.05, "healthy_reward": 0.5, "healthy_z_range": (0.05, 0.6), "max_tilt": 1.0}
    sand_step = (SAND_TIMESTEP, SAND_FRAME_SKIP)
    sand_implicit = True
    fast_step = FAST_STEP

    def __init__(self, sand: bool = True, *, foot: str = "cone", foot_size: float = 0.085,
                 pitch_free: bool = True, **kwargs):
        """Own arguments: ``foot``, ``foot_size``, ``pitch_free`` (:func:`mjrft.models.biped_xml`); the common
        ones are in :mod:`mjrft.envs.base` (defaults here: ``defaults``); any other keyword goes to
        :func:`~mjrft.models.biped_xml`."""
        pickle_kwargs = dict(sand=sand, foot=foot, foot_size=foot_size, pitch_free=pitch_free, **kwargs)
        env_kw, model_kw = split_env_kwargs(kwargs)
        xml = biped_xml(foot=foot, foot_size=foot_size, pitch_free=pitch_free, sand=sand, **model_kw)
        super().__init__(xml, sand=sand, pickle_kwargs=pickle_kwargs, **{**self.defaults, **env_kw})

    def _make_task(self, **common) -> BipedTask:
        return BipedTask(self.model, init_qpos=self.init_qpos, **common)


class BipedRigid(BipedSand):
    """:class:`BipedSand` on a rigid floor (``sand=False``; see that class for the tables)."""

    def __init__(self, **kwargs):
        kwargs.pop("sand", None)
        super().__init__(sand=False, **kwargs)

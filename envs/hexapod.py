"""RHex-class hexapod on granular media (``mjrft/HexapodSand-v0``), rigid ground (``mjrft/HexapodRigid-v0``) or
the shoal: dry sand, saturated sand, shallow water (``mjrft/HexapodShoal-v0``)."""

from __future__ import annotations

import numpy as np

from mjrft.errors import check_positive
from mjrft.models.hexapod import LEG_NAMES, TRIPOD_A, TRIPOD_B, hexapod_xml
from mjrft.models.shoal import SHOAL

from .base import GranularMujocoEnv, split_env_kwargs
from .randomization import DEFAULT_SURFACE_GRID, TerrainRandomization
from .tasks import HexapodTask


#: the sand envs' physics step (s) and steps per env step when neither ``timestep`` nor ``frame_skip`` is given
#: (without a preset, and under the ``fast`` and ``default`` presets): 0.5 ms x 20 = the 10 ms control period. The legs' explicit granular-stiffness
#: limit (:mod:`mjrft.stability`) falls to 0.93 ms under 40 s of the initial PPO policy's random actions on
#: poppy seeds, below the models' 1 ms step; at 0.5 ms no step passes it (``tests/envs/test_hexapod_timestep.py``).
SAND_TIMESTEP = 0.0005
SAND_FRAME_SKIP = 20
#: the ``"accurate"`` preset's steps (``python benchmarks/env_timestep.py``): on sand the explicit 0.25 ms step is the
#: largest within the 2 % gait budget (the own 0.5 ms is 2.6 % on sinkage); on the rigid floor no step is within it
#: (the C-legs' impacts: 3.7 % at 0.1 ms on the 3 Hz tripod), so it takes the finest step the study measures
ACCURATE_STEP = (0.00025, 40)
RIGID_ACCURATE_STEP = (0.0001, 100)


class HexapodSand(GranularMujocoEnv):
    """RHex-class hexapod (150 g, six continuously rotating C-legs) walking forward (+x) on sand.

    Model: :func:`mjrft.models.hexapod_xml` (``variant``, ``curvature``, ``sand``; ``curvature`` is the
    signed leg curvature 1/r in 1/m, default 1/R': positive = Li 2013's C-leg, convex side leading in
    stance, negative = reversed C-leg, convention in :mod:`mjrft.geometry.curved_leg`); granular bodies
    torso + six legs. Physics step 0.5 ms, ``frame_skip = 20`` (``dt = 0.01`` s; ``SAND_TIMESTEP``,
    ``SAND_FRAME_SKIP``: the legs' granular-stiffness limit falls below 1 ms in training) unless ``timestep`` or
    ``frame_skip`` is given; on the rigid floor 1 ms and ``frame_skip = 10``. The presets ``fast`` and ``default``
    keep these steps; ``accurate`` steps 0.25 ms x 40 on sand, 0.1 ms x 100 on the rigid floor (``ACCURATE_STEP``,
    ``RIGID_ACCURATE_STEP``). With
    ``variant="small"`` (25 g, DynaRoACH-sized) the sand scene turns on the dry laws' inertial regime
    (:mod:`mjrft.laws.inertial`; ``inertial=False`` turns it off), the RHex-class robot leaves it off.

    ## Action space

    ``Box(-1, 1, (6,), float32)``: hip angular-velocity commands, in the actuator order
    ``hip_lf, hip_lm, hip_lr, hip_rf, hip_rm, hip_rr``. Each step the position-servo target of hip
    ``i`` is advanced by ``a_i * max_hip_speed * dt`` (``max_hip_speed`` default ``6 pi`` rad/s =
    3 rev/s; positive = the forward-walking rotation), then kept within ``max_lag`` (default 1 rad)
    of the current hip angle so the target cannot wind up. ``a = 0`` holds the legs where they are.
    An alternating tripod at ``f`` Hz is ``a = 2 pi f / max_hip_speed`` on every leg with the two
    tripods (A = lf, rm, lr; B = rf, lm, rr: ``TRIPOD_A_IDX`` / ``TRIPOD_B_IDX``) half a turn apart.

    ## Observation space

    ``Box(-inf, inf, (35,), float64)``:

    | index  | observation                                              | unit          |
    |--------|----------------------------------------------------------|---------------|
    | 0      | torso height z                                           | m             |
    | 1-4    | torso orientation quaternion (w, x, y, z)                | -             |
    | 5-10   | sin(hip angle), legs lf lm lr rf rm rr                   | -             |
    | 11-16  | cos(hip angle), same order                               | -             |
    | 17-19  | torso linear velocity (world x, y, z)                    | m/s           |
    | 20-22  | torso angular velocity (local frame)                     | rad/s         |
    | 23-28  | hip angular velocities                                   | rad/s         |
    | 29-34  | servo target minus hip angle                             | rad           |

    The x, y position is excluded (as in gymnasium's locomotion tasks). With ``planar=True`` (the torso
    held in the sagittal x-z plane, :func:`mjrft.models.hexapod_xml`) the layout is the same: 0-4 are the
    torso's world height and orientation (a pure pitch), 17-19 its velocity ``(v_x, 0, v_z)`` and 20-22
    ``(0, pitch rate, 0)``.

    ## Rewards

    | term            | value                                                             | default weight |
    |-----------------|-------------------------------------------------------------------|----------------|
    | forward         | ``forward_reward_weight * dx/dt`` (torso x velocity, m/s)          | 1.0            |
    | healthy         | ``healthy_reward`` per step while healthy                          | 0.1            |
    | energy          | ``-energy_cost_weight * P / (m g)`` (m/s; ``P``: ``info["power"]``)       | 0.05           |
    | ctrl            | ``-ctrl_cost_weight * sum(a**2)``                                  | 0.0            |

    ## Termination and truncation

    Unhealthy (``terminated`` when ``terminate_when_unhealthy``): torso height outside
    ``healthy_z_range`` (default (-0.05, 0.5) m; z = 0 is the sand surface) or torso tilt (angle of its
    z axis from vertical) above ``max_tilt`` (default 1.2 rad, i.e. flipped over).
    Truncation: ``max_episode_steps`` of the registration (1000 steps = 10 s) and ``episode_seconds``.

    ## Info

    See :mod:`mjrft.envs.base`; ``sinkage`` and ``granular_force`` are per leg (6 rows, order above).

    ## Terrain randomisation

    ``terrain_randomization={...}`` draws a new terrain at each reset (:mod:`mjrft.envs.randomization`:
    ``media``, ``stress_scale``, ``surface_height``, ``roughness``, ``correlation_length``, ``strips``,
    ``strip_length``, ``strip_start``); ``info["terrain"]`` says what was drawn. With ``roughness`` the
    scene's sand surface becomes a height field of samples ``surface_grid`` apart (default
    ``DEFAULT_SURFACE_GRID`` = 1 cm over the 2 x 1 m bed; ``surface_grid=<m>`` chooses another, and
    gives a height-field surface without randomisation too). Drawn strips are not shown in the
    rendering, which shows one uniform bed (they replace a scene's own strips, e.g. the shoal's, whose
    boxes are then hidden); ``info["terrain"]["strips"]`` lists them.

    ## Roll and heading under the open-loop tripod

    The free body rocks about its roll axis and can turn. Measured with ``tripod`` at 1-5 Hz (10 s,
    ``seed=0``, ``max_hip_speed=12 pi``; ``python benchmarks/free_tripod.py``, output in
    ``benchmarks/results/free_tripod.txt``): the largest torso tilt is 27 deg and the heading stays within
    10 deg at 1-3 Hz on both media. With C-legs at 5 Hz (and 4 Hz on poppy_cp) the body settles into a
    period-2 bounce, one tripod carrying more than the other, and turns steadily; the side is set by the
    start (the model, coupler and gait are mirror-symmetric: ``tests/models/test_hexapod_symmetry.py``).
    The measured cause is in the ``li2013_robot`` validation case. Held in the sagittal plane
    (``planar=True``, as in Li 2013's simulation) the body walks straight.
    """

    base_model = "hexapod"
    foot_names = tuple(f"leg_{n}" for n in LEG_NAMES)
    TRIPOD_A_IDX = tuple(LEG_NAMES.index(n) for n in TRIPOD_A)
    TRIPOD_B_IDX = tuple(LEG_NAMES.index(n) for n in TRIPOD_B)
    default_camera_config = {"trackbodyid": 1, "distance": 0.6, "elevation": -20.0}

    defaults = {"energy_cost_weight": 0.05, "healthy_reward": 0.1, "healthy_z_range": (-0.05, 0.5), "max_tilt": 1.2}
    sand_step = (SAND_TIMESTEP, SAND_FRAME_SKIP)
    accurate_step = ACCURATE_STEP
    rigid_accurate_step = RIGID_ACCURATE_STEP

    def __init__(self, sand: bool = True, *, variant: str = "rhex", curvature: float | None = None,
                 max_hip_speed: float = 6 * np.pi, max_lag: float = 1.0, planar: bool = False, **kwargs):
        """Own arguments: ``variant``, ``curvature``, ``planar`` (:func:`mjrft.models.hexapod_xml`; ``planar``
        holds the torso in the sagittal plane as Li 2013's robot simulation did), ``max_hip_speed``,
        ``max_lag`` (the action space above); the common ones are in :mod:`mjrft.envs.base` (defaults
        here: ``defaults``); any other keyword goes to :func:`~mjrft.models.hexapod_xml`."""
        pickle_kwargs = dict(sand=sand, variant=variant, curvature=curvature, max_hip_speed=max_hip_speed,
                             max_lag=max_lag, planar=planar, **kwargs)
        self._action_options = dict(max_hip_speed=check_positive("max_hip_speed", max_hip_speed),
                                    max_lag=check_positive("max_lag", max_lag), planar=bool(planar))
        self.planar = bool(planar)
        env_kw, model_kw = split_env_kwargs(kwargs)
        randomization = TerrainRandomization.from_value(env_kw.get("terrain_randomization"))
        if sand and randomization is not None and randomization.roughness > 0:
            model_kw.setdefault("surface_grid", DEFAULT_SURFACE_GRID)  # a height-field surface to carry it
        xml = hexapod_xml(curvature, variant=variant, sand=sand, planar=planar, **model_kw)
        super().__init__(xml, sand=sand, pickle_kwargs=pickle_kwargs, **{**self.defaults, **env_kw})

    def _make_task(self, **common) -> HexapodTask:
        return HexapodTask(self.model, dt=self.dt, **self._action_options, **common)

    # ------------------------------------------------------------------ actions
    def _setup_action(self) -> None:
        super()._setup_action()
        #: the hip servos' targets (rad), advanced by each action (:meth:`action_to_ctrl`)
        self.target = self.data.qpos[self.task.hip_qadr].copy()

    def action_to_ctrl(self, action: np.ndarray) -> np.ndarray:
        """Integrate the hip-velocity command into the servo targets (changes the env's state)."""
        self.target = self.task.action_to_ctrl(np, self.data.qpos, self.target, action)
        return self.target.copy()

    def set_servo_targets(self, ctrl) -> None:
        self.target = np.array(ctrl, dtype=np.float64)
        self.data.ctrl[:] = self.target

    def _reset_extra(self) -> None:
        self.target = self.data.qpos[self.task.hip_qadr].copy()

    # ------------------------------------------------------------------ observation
    def _get_obs(self) -> np.ndarray:
        return self.task.observation(np, self.data, self.target).astype(np.float64)


class HexapodRigid(HexapodSand):
    """:class:`HexapodSand` on a rigid floor (``sand=False``; see that class for the tables)."""

    def __init__(self, **kwargs):
        kwargs.pop("sand", None)
        super().__init__(sand=False, **kwargs)


class HexapodShoal(HexapodSand):
    """:class:`HexapodSand` on the ``shoal`` scene (:mod:`mjrft.models.shoal`): dry poppy seeds for x < 0.5 m,
    saturated sea sand (law ``wet``) for 0.5 <= x < 1 m, then 2 cm of water over saturated sand, with
    buoyancy; regions blend over 1 cm. Same spaces, rewards and termination as :class:`HexapodSand`
    (the tables there); the scene's keyword arguments (``regions``, ``buoyancy``, ``bed_length``,
    ``medium``/``law`` of the dry strip, ...) can be overridden. The open-loop tripod at 2 Hz reaches
    the water after about 4.5 s."""

    base_model = "hexapod_shoal"

    def __init__(self, **kwargs):
        kwargs.pop("sand", None)
        for key, value in SHOAL.items():
            kwargs.setdefault(key, value)
        super().__init__(sand=True, **kwargs)

"""The trade study's scenarios (:data:`SCENARIOS`: each a model, a controller and what to measure) and its grid of
configurations (:func:`default_grid`, around the default; :func:`reference_config`). The package docstring,
:mod:`mjrft.tools.tradeoff`, describes both."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Callable

import mujoco
import numpy as np

from mjrft.errors import unknown

CONTROL_PERIOD = 0.01  # s; the default control period (1 ms x 10)
RESOLUTION_SCALES = (4.0, 2.0, 1.0, 0.5, 0.25)
RIG_RESOLUTION_SCALES = (4.0, 2.0, 1.0, 0.5)  # the rigs converge by 1/2 (x0.5 and x0.25 differ by < 0.05 %)
TIMESTEPS = (0.002, 0.001, 0.0005)
FRAME_SKIPS = (1, 5, 10, 20)
DRY_LAWS = ("depth_only", "rft_generic", "rft", "rft3d")
#: law variants of the study -> law name in the coupler (``rft_generic`` also swaps the medium, see law_and_medium)
LAW_VARIANTS = {
    "depth_only": "depth_only",
    "rft_generic": "rft",
    "rft": "rft",
    "rft3d": "rft3d",
    "wet": "wet",
    "hybrid": "hybrid",
    "rft_inertial": "rft",  # with the dry inertial regime on
    "rft_quasistatic": "rft",  # with the dry inertial regime off (a scene that turns it on)
}
#: the inertial regime each variant forces on (True) or off (False); others follow the scene's mjrft:inertial
INERTIAL_VARIANTS = {"rft_inertial": True, "rft_quasistatic": False}
#: variants that model a different physics; their errors are model differences, not accuracy
MODEL_DIFFERENCE_LAWS = ("wet", "hybrid", "rft_inertial", "rft_quasistatic")
REFERENCE_LAW = "rft"


@dataclass(frozen=True)
class Config:
    """One point of the grid. ``resolution_scale`` multiplies the model's own resolution (its ``<custom>``)."""

    label: str
    factor: str  # "default", "resolution", "law", "timestep", "frame_skip", "reference", "preset"
    resolution_scale: float = 1.0
    law: str = REFERENCE_LAW
    timestep: float = 0.001
    frame_skip: int = 10

    def key(self) -> tuple:
        return (round(self.resolution_scale, 9), self.law, round(self.timestep, 12), self.frame_skip)


@dataclass
class Scenario:
    """A standard scenario: a model builder, a controller factory and what to measure."""

    name: str
    description: str
    duration: float  # s of simulated time
    build: Callable[[], mujoco.MjModel]  # the model with terrain settings in <custom>, default timestep
    controller: Callable[[mujoco.MjModel, mujoco.MjData], Callable[[], None]]  # called every control period
    measure_bodies: tuple[str, ...]  # bodies whose granular force is measured
    track_body: str | None  # body whose final position is compared (None: kinematic rig)
    laws: tuple[str, ...] = DRY_LAWS
    kinematic: bool = False
    build_bare: Callable[[], mujoco.MjModel] | None = None  # plain-MuJoCo twin (None: ``build`` without terrain)
    resolution_scales: tuple[float, ...] = RESOLUTION_SCALES  # coarse to fine; the finest is the reference's
    hybrid_extra: Callable[[], dict] | None = None  # medium constants the hybrid law needs (leg width, depth)
    presets: bool = True  # takes part in choosing the presets (recommend_presets)


def _rigs():
    from mjrft.models import rigs  # the rig builders (imported lazily: mjrft.models imports nothing heavy)

    return rigs


# --- hexapod --------------------------------------------------------------------------------------
def _hexapod_model(sand: bool = True) -> mujoco.MjModel:
    """The hexapod held in the sagittal plane (``planar=True``, as in Li 2013's robot simulation). Choice: the
    free body's heading is set by its start transient and nothing restores it (:mod:`mjrft.envs.hexapod`), so
    a free walk's errors would measure how far two nearly equal runs turn apart, not the numerics."""
    from mjrft.models import hexapod_model

    return hexapod_model(sand=sand, planar=True)


def _hexapod_controller(model, data, freq: float = 2.0):
    """Open-loop alternating tripod at ``freq`` Hz: every hip target advances at 2 pi freq rad/s, tripod B + pi."""
    tripod_a = {"leg_lf", "leg_rm", "leg_lr"}
    offset = np.array([
        0.0 if mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, model.jnt_bodyid[model.actuator_trnid[i, 0]])
        in tripod_a else math.pi for i in range(model.nu)])
    omega = 2 * math.pi * freq

    def control():
        data.ctrl[:] = omega * data.time + offset

    return control


# --- the small (DynaRoACH-sized) hexapod -----------------------------------------------------------
SMALL_MEDIUM = "glass3_cp"  # the DynaRoACH paper's 3 mm glass
SMALL_FREQ = 10.0  # Hz, above the paper's ~6 Hz walk-to-run transition


def _small_hexapod_model(sand: bool = True) -> mujoco.MjModel:
    from mjrft.models import hexapod_model

    return hexapod_model(variant="small", sand=sand, medium=SMALL_MEDIUM)


def _small_hexapod_controller(model, data):
    return _hexapod_controller(model, data, SMALL_FREQ)


# --- humanoid on one foot -------------------------------------------------------------------------
BOARD_WIDTH = 0.304  # m, the widest board of the HUBO experiments (reference section 6)


def _humanoid_model(sand: bool = True) -> mujoco.MjModel:
    from mjrft.models import humanoid_model

    return humanoid_model(foot_width=BOARD_WIDTH, sand=sand)


def _smooth(x: float) -> float:
    x = min(1.0, max(0.0, x))
    return 0.5 - 0.5 * math.cos(math.pi * x)


def _humanoid_controller(model, data):
    """Stand on the right foot: lean over the right sole (PD on the centre of mass), fold the left leg up.

    Both legs lean as a parallelogram (hip roll = theta, ankle roll = -theta, torso upright) with
    ``theta = 0.15 s + 3 (y_com - y_d) + 0.5 vy_com`` rad (``s`` a 1 s cosine ramp, ``y_d = s y_sole``);
    the right ankle pitch (and the opposite hip pitch) hold the centre of mass over the sole
    fore-aft with the same gains; from 1.2 s to 1.8 s the left leg folds (hip pitch -0.6, knee 1.2,
    ankle pitch -0.6 rad), lifting its foot ~10 cm.
    """
    act = {mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_ACTUATOR, i): i for i in range(model.nu)}
    pelvis = model.body("pelvis").id
    sole = model.site("right_sole").id
    kp, kd = 3.0, 0.5
    i_roll = [(act[f"{s}_hip_roll"], act[f"{s}_ankle_roll"]) for s in ("left", "right")]
    i_lhp, i_lkn, i_lap = act["left_hip_pitch"], act["left_knee"], act["left_ankle_pitch"]
    i_rhp, i_rap = act["right_hip_pitch"], act["right_ankle_pitch"]

    def control():
        mujoco.mj_subtreeVel(model, data)
        t = data.time
        com, vel, foot = data.subtree_com[pelvis], data.subtree_linvel[pelvis], data.site_xpos[sole]
        s = _smooth(t / 1.0)
        theta = 0.15 * s + kp * (com[1] - s * foot[1]) + kd * vel[1]
        for hip, ankle in i_roll:
            data.ctrl[hip] = theta
            data.ctrl[ankle] = -theta
        lift = _smooth((t - 1.2) / 0.6)
        data.ctrl[i_lhp] = -0.6 * lift
        data.ctrl[i_lkn] = 1.2 * lift
        data.ctrl[i_lap] = -0.6 * lift
        lean = -kp * (com[0] - foot[0]) - kd * vel[0]  # shank pitch: positive leans forward
        data.ctrl[i_rap] = -lean
        data.ctrl[i_rhp] = lean

    return control


# --- kinematic rigs -------------------------------------------------------------------------------
RIG_ARMATURE = 1e6
PLATE_BETA = math.radians(30.0)
PLATE_GAMMA = math.radians(60.0)
PLATE_SPEED = 0.04  # m/s along gamma
PLATE_START = 0.01  # m, plate_z at t = 0 (centre 1 cm + half a thickness above the surface)
LEG_OMEGA = math.pi / 2  # rad/s
LEG_START = -math.pi / 2  # rad, leg angle at t = 0


def _heavy(xml: str) -> mujoco.MjModel:
    """Compile ``xml`` with every joint's armature set to RIG_ARMATURE (set in the spec: MuJoCo bakes the
    armature into the compiled model, a later ``model.dof_armature`` edit does not reach the mass matrix)."""
    spec = mujoco.MjSpec.from_string(xml)
    for joint in spec.joints:
        joint.armature = RIG_ARMATURE
    return spec.compile()


def _plate_model() -> mujoco.MjModel:
    return _heavy(_rigs().plate_rig_xml())


def _plate_controller(model, data):
    """Prescribe the plate's path: beta fixed, velocity PLATE_SPEED along gamma (down and forward)."""
    vx, vz = PLATE_SPEED * math.cos(PLATE_GAMMA), -PLATE_SPEED * math.sin(PLATE_GAMMA)

    def control():
        t = data.time
        data.qpos[:3] = (vx * t, PLATE_START + vz * t, PLATE_BETA)
        data.qvel[:3] = (vx, vz, 0.0)

    control()
    return control


def _leg_model() -> mujoco.MjModel:
    return _heavy(_rigs().leg_rig_xml("c"))


def _leg_hybrid_extra() -> dict:
    """The hybrid law's leg width and maximum penetration depth of the C-leg over the sweep (as
    ``mjrft.tools.rigs``)."""
    rigs = _rigs()
    geo = rigs.leg_geometry("c")
    v = np.asarray(geo["vertices"], float)
    theta = LEG_START + LEG_OMEGA * np.linspace(0.0, 2.0, 2001)
    z = rigs.default_axle_height("c") - np.outer(np.sin(theta), v[:, 0]) + np.outer(np.cos(theta), v[:, 2])
    return {"hybrid_width": geo["width"], "hybrid_max_depth": float(max(0.0, -z.min()))}


def _leg_controller(model, data):
    """Prescribe the leg angle: LEG_START + LEG_OMEGA t."""

    def control():
        data.qpos[0] = LEG_START + LEG_OMEGA * data.time
        data.qvel[0] = LEG_OMEGA

    control()
    return control


SCENARIOS: dict[str, Scenario] = {
    s.name: s for s in (
        Scenario("cleg", "rotating C-leg rig (Li 2013), pi/2 rad/s from -90 to +90 deg", 2.0,
                 _leg_model, _leg_controller, ("leg",), None, DRY_LAWS + ("wet", "hybrid"), kinematic=True,
                 resolution_scales=RIG_RESOLUTION_SCALES, hybrid_extra=_leg_hybrid_extra),
        Scenario("plate", "plate intrusion (Li 2013 plate), beta 30 deg, gamma 60 deg, 4 cm/s", 2.0,
                 _plate_model, _plate_controller, ("plate",), None, DRY_LAWS + ("wet",), kinematic=True,
                 resolution_scales=RIG_RESOLUTION_SCALES),
        Scenario("hexapod", "RHex-class hexapod (sagittal plane), open-loop tripod at 2 Hz", 2.0,
                 _hexapod_model, _hexapod_controller,
                 ("torso", "leg_lf", "leg_lm", "leg_lr", "leg_rf", "leg_rm", "leg_rr"), "torso",
                 DRY_LAWS + ("rft_inertial",), build_bare=lambda: _hexapod_model(sand=False)),
        Scenario("hexapod_small", "DynaRoACH-sized hexapod on 3 mm glass, inertial regime on, tripod at 10 Hz", 1.0,
                 _small_hexapod_model, _small_hexapod_controller,
                 ("torso", "leg_lf", "leg_lm", "leg_lr", "leg_rf", "leg_rm", "leg_rr"), "torso",
                 DRY_LAWS + ("rft_quasistatic",), build_bare=lambda: _small_hexapod_model(sand=False),
                 presets=False),
        Scenario("humanoid", "HUBO-class humanoid standing on its right foot (30.4 cm boards)", 2.5,
                 _humanoid_model, _humanoid_controller, ("left_foot", "right_foot"), "pelvis",
                 build_bare=lambda: _humanoid_model(sand=False)),
    )
}


def get_scenario(name: str) -> Scenario:
    if name in SCENARIOS:
        return SCENARIOS[name]
    raise unknown("scenario", name, SCENARIOS)


def reference_config(scenario: Scenario | None = None, scale: float | None = None) -> Config:
    """Finest resolution, smallest timestep, the medium's own Li fit, the default control period."""
    dt = min(TIMESTEPS)
    if scale is None:
        scale = min(scenario.resolution_scales if scenario is not None else RESOLUTION_SCALES)
    return Config("reference", "reference", scale, REFERENCE_LAW, dt, int(round(CONTROL_PERIOD / dt)))


def _preset_configs() -> list[Config]:
    from ..presets import PRESETS

    out = []
    for name, p in PRESETS.items():
        if name == "default":
            continue
        out.append(Config(f"preset {name}", "preset", p["resolution_scale"], p["law"], p["timestep"],
                          p["frame_skip"]))
    return out


def default_grid(scenario: Scenario, quick: bool = False) -> list[Config]:
    """The configurations of ``scenario`` (see the module docstring); ``quick``: a small grid."""
    base = Config("default", "default")
    if quick:
        return [base, Config("resolution x4", "resolution", 4.0), Config("law depth_only", "law", law="depth_only"),
                Config("dt 2 ms x 5", "timestep", timestep=0.002, frame_skip=5), reference_config(scale=0.5)]
    configs = [base]
    for s in scenario.resolution_scales:
        configs.append(Config(f"resolution x{s:g}", "resolution", s))
    for law in scenario.laws:
        configs.append(Config(f"law {law}", "law", law=law))
    for dt in TIMESTEPS:
        fs = int(round(CONTROL_PERIOD / dt))
        configs.append(Config(f"dt {dt * 1e3:g} ms x {fs}", "timestep", timestep=dt, frame_skip=fs))
    for fs in FRAME_SKIPS:
        configs.append(Config(f"frame skip {fs}", "frame_skip", frame_skip=fs))
    configs.append(reference_config(scenario))
    configs += _preset_configs()
    return dedupe(configs)


def dedupe(configs: list[Config]) -> list[Config]:
    """Drop configurations identical to an earlier one; the first keeps its place, a preset's name is
    added to its label (``"resolution x4 = preset fast"``)."""
    out: dict = {}
    for c in configs:
        k = c.key()
        if k not in out:
            out[k] = c
        elif c.factor == "preset":
            out[k] = replace(out[k], label=f"{out[k].label} = {c.label}")
    return list(out.values())

"""Open-loop gaits of the papers, as policies with the stable-baselines3 interface.

A gait is built from a spec string ``"name:key=value,key=value"`` and bound to the environment it
drives::

    import gymnasium, mjrft.envs
    from mjrft.gaits import make_gait
    env = gymnasium.make("mjrft/HexapodSand-v0")
    gait = make_gait("tripod:f=2.0,duty=0.5", env)
    obs, _ = env.reset(seed=0)
    action, _ = gait.predict(obs)          # same call as a trained PPO / SAC model

=========  ==========================  ============================================================
name       robot (environments)        what it does
=========  ==========================  ============================================================
tripod     hexapod (HexapodSand/Rigid) alternating tripod, Buehler clock: stride frequency ``f``,
                                       duty factor ``duty``, stance sweep ``sweep``, tripod phase
                                       offset ``offset`` (Li 2013, RHex)
rect       biped (BipedSand/Rigid)     each foot centre traces a rectangle (16 x 3 cm, 6 s, 5/8 on
                                       the bottom edge) with a toe presentation angle ``angle``
stand      humanoid (HumanoidSand/     hold a (crouched) standing posture
           Rigid)
shift      humanoid                    quasi-static walk that shifts the CoM toward the stepping
                                       foot once ``shift`` of its intrusion phase has passed
=========  ==========================  ============================================================

``mjrft.gaits.describe()`` lists every gait with its parameters, defaults and units.

Time
----
A gait is a function of simulation time. :func:`make_gait` binds it to an environment (a gymnasium
env, possibly wrapped, or a stable-baselines3 ``DummyVecEnv`` / ``VecNormalize`` around such envs)
and :meth:`GaitPolicy.predict` reads ``env.unwrapped.data.time`` of each bound env, so there is no
second clock to keep in step: ``episode_start`` and ``state`` are accepted and ignored (``state`` is
returned unchanged). The action returned at time ``t`` is held for one env step (``env.dt``) and is
chosen so that the joint targets reach the reference pose at ``t + dt``. The observation is used only
for its batch shape, so the gait also works behind observation normalisation.

Choices where the papers are silent
-----------------------------------
* **tripod.** Hexapod actions are hip-speed commands that the env integrates into servo targets.
  The gait reads the env's current targets and commands the speed that puts them on the Buehler-clock
  reference one step later (clipped to the action range), so the tripods never drift apart. The
  reference: stance (a fraction ``duty`` of the cycle) sweeps the leg at constant speed through
  ``sweep`` rad centred on straight down; the swing recirculates the remaining ``2 pi - sweep`` at
  constant speed. ``duty = 0.5, sweep = pi`` (default) is the constant-speed rotation of Li 2013's
  RHex experiments. The legs always turn the forward-walking way (positive hip angle, the buried part
  sweeping backward), the rotation for which a positive ``curvature`` is Li 2013's C-leg leading with
  its convex side and a negative one the reversed C-leg (:mod:`mjrft.geometry.curved_leg`). Tripod A
  (lf, rm, lr) has phase 0, tripod B phase ``offset`` (cycles, default 0.5); at ``t = 0`` tripod A is
  mid-stance (legs down) and B catches up to its phase at full speed.
  A spec whose stance or swing speed exceeds the env's ``max_hip_speed`` is rejected.
* **rect.** The foot centre (the ankle axis: the round foot's axis) moves relative to the hip on a
  rectangle ``length`` x ``height`` whose bottom edge is ``depth`` below the hip, centred under the
  hip. Order: bottom edge front to back (stance, fraction ``duty`` of ``period``, uniform speed), up
  the rear edge, forward along the top, down the front edge (intrusion); the swing (``1 - duty``) is
  shared among the three swing edges in proportion to their lengths (uniform speed along the swing
  path). Legs are half a period apart. Inverse kinematics: the two knee servos split the knee bend
  equally. Foot pitch: flat in stance; turns linearly to the presentation ``angle`` (degrees,
  positive toe-down) along the top edge, holds it during the intrusion and returns to flat over the
  first quarter of the stance. Torso pitch is not compensated (open loop).
* **stand / shift.** Joint targets come from leg inverse kinematics in the pelvis frame (feet flat,
  pelvis assumed upright). ``crouch`` is the knee bend (rad) of the posture; ``stand`` bends the knees
  from the straight initial pose over its first second (a sudden crouch throws the robot over).
  ``shift``: the first half step bends the knees and moves the pelvis over the right foot; then each
  step of ``period`` seconds lifts the swing foot by ``lift`` (15% of the step), carries it forward to
  ``+step/2`` (20%), intrudes it down to ``depth`` below the standing sole level (20%: the intrusion
  phase) while the stance foot slides back to ``-step/2``, and moves the pelvis sideways from over the
  stance foot to over the stepping foot (``sway`` m to either side of centre, in 30% of the step),
  starting at ``shift`` of the intrusion phase (0: as the intrusion starts; 1: once the foot is fully
  down, the hard-ground gait); the rest of the step holds. The left foot steps first. Defaults are
  slow (6 s steps) because the gait is quasi-static: measured in this session it walks 12 s on
  ``HumanoidRigid-v0``; on ``HumanoidSand-v0`` (15.2 cm feet, poppy seeds) the loaded stance foot
  yields and the robot tips over in its first single support, ~3 s in (no feedback balances it).
* **rect on a pitch-free torso.** The reference gait study held the biped's torso pitch (sagittal
  plane, fore-aft and vertical only; pitch was free only in the balance study), so ``rect`` is meant
  for ``BipedSand(pitch_free=False)``: there it walks ~4 cm/s. On the default pitch-free biped it still
  runs but tips over within ~2 s; :func:`make_gait` warns (``GaitWarning``) in that case.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from mjrft.errors import unknown


class GaitWarning(UserWarning):
    """A gait runs on an environment it was not designed for (see the message)."""

# ----------------------------------------------------------------------------- gait definitions


@dataclass(frozen=True)
class Param:
    default: float
    unit: str
    help: str
    low: float = -math.inf  # valid range (exclusive bounds where marked)
    high: float = math.inf
    low_open: bool = False
    high_open: bool = False

    def check(self, gait: str, name: str, value: float) -> float:
        ok_low = value > self.low if self.low_open else value >= self.low
        ok_high = value < self.high if self.high_open else value <= self.high
        if not (math.isfinite(value) and ok_low and ok_high):
            lo = ("(" if self.low_open else "[") + f"{self.low:g}"
            hi = f"{self.high:g}" + (")" if self.high_open else "]")
            raise ValueError(f"gait {gait!r}: parameter {name}={value!r} out of range; valid: {lo}, {hi}")
        return value


@dataclass(frozen=True)
class GaitDef:
    """One gait: its robot, parameters and the builder ``build(unwrapped_env, params) -> fn(t) -> action``."""

    name: str
    robot: str
    env_class: str  # "module:Class" that the env must be an instance of
    help: str
    params: dict[str, Param]
    build: Callable[[object, dict], Callable[[float], np.ndarray]] = field(repr=False)

    def defaults(self) -> dict[str, float]:
        return {k: p.default for k, p in self.params.items()}

    def __call__(self, env, **params) -> "GaitPolicy":
        """``GAITS[name](env, **params)``: the same as ``make_gait("name:k=v,...", env)``."""
        text = self.name + (":" + ",".join(f"{k}={v}" for k, v in params.items()) if params else "")
        return make_gait(text, env)


@dataclass
class GaitPolicy:
    """A gait bound to one or more environments; ``predict`` has stable-baselines3's signature."""

    spec: str
    name: str
    params: dict[str, float]
    envs: list  # unwrapped environments (one per batch row)
    _fns: list = field(repr=False)

    @property
    def observation_space(self):
        return self.envs[0].observation_space

    @property
    def action_space(self):
        return self.envs[0].action_space

    def action_at(self, t: float, index: int = 0) -> np.ndarray:
        """The action for env ``index`` at simulation time ``t`` (uses that env's current joint targets)."""
        return self._fns[index](float(t))

    def predict(self, observation, state=None, episode_start=None, deterministic: bool = True):
        """Actions for ``observation`` (one observation, or a batch with one row per bound env)."""
        obs = np.asarray(observation)
        single = obs.ndim <= len(self.observation_space.shape)
        n = 1 if single else obs.shape[0]
        if n != len(self.envs):
            raise ValueError(f"gait {self.spec!r} is bound to {len(self.envs)} env(s) but got a batch of {n} "
                             "observations")
        actions = np.stack([self._fns[i](float(self.envs[i].data.time)) for i in range(n)])
        return (actions[0] if single else actions), state


# ----------------------------------------------------------------------------- helpers


def _smooth(s: float) -> float:
    """Cosine ease from 0 to 1 over s in [0, 1] (zero slope at both ends), clipped outside."""
    s = min(max(s, 0.0), 1.0)
    return 0.5 - 0.5 * math.cos(math.pi * s)


def _actuator_index(env) -> dict[str, int]:
    import mujoco

    m = env.model
    return {mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_ACTUATOR, i): i for i in range(m.nu)}


def _joint_targets_to_action(env, index: dict[str, int], targets: dict[str, float]) -> np.ndarray:
    """Normalised action holding every actuator at its initial target except those in ``targets``."""
    ctrl = env.action_to_ctrl(np.zeros(env.model.nu))
    for name, value in targets.items():
        ctrl[index[name]] = value
    return env.ctrl_to_action(ctrl).astype(np.float32)


# ----------------------------------------------------------------------------- tripod (hexapod)


def buehler_angle(x: float, duty: float, sweep: float) -> float:
    """Unwrapped Buehler-clock leg angle (rad) at ``x`` cycles; 0 (leg down) at mid-stance x = 0."""
    y = x + duty / 2.0
    n = math.floor(y)
    p = y - n
    if p < duty:
        a = -sweep / 2.0 + sweep * p / duty
    else:
        a = sweep / 2.0 + (2.0 * math.pi - sweep) * (p - duty) / (1.0 - duty)
    return 2.0 * math.pi * n + a


def _build_tripod(env, p: dict) -> Callable[[float], np.ndarray]:
    f, duty, sweep, offset = p["f"], p["duty"], p["sweep"], p["offset"]
    ms, dt = float(env._max_hip_speed), float(env.dt)
    stance_speed = sweep * f / duty
    swing_speed = (2.0 * math.pi - sweep) * f / (1.0 - duty)
    need = max(stance_speed, swing_speed)
    if need > ms * (1.0 + 1e-9):
        raise ValueError(f"gait 'tripod' f={f:g}, duty={duty:g}, sweep={sweep:g} needs a hip speed of "
                         f"{need:.2f} rad/s (stance {stance_speed:.2f}, swing {swing_speed:.2f}), above the env's "
                         f"max_hip_speed {ms:.2f} rad/s; lower f, or move duty toward sweep / (2 pi)")
    phase = np.zeros(6)
    phase[list(env.TRIPOD_B_IDX)] = offset

    def act(t: float) -> np.ndarray:
        ref = np.array([buehler_angle(f * (t + dt) + ph, duty, sweep) for ph in phase])
        err = ref - env._target
        # whole turns do not matter: bring the error into [-pi/2, 3 pi/2) (catch up forward)
        err = np.mod(err + 0.5 * np.pi, 2.0 * np.pi) - 0.5 * np.pi
        return np.clip(err / (ms * dt), -1.0, 1.0).astype(np.float32)

    return act


# ----------------------------------------------------------------------------- rect (biped)


def biped_leg_ik(x: float, z: float, thigh: float, link: float, shank: float) -> tuple[float, float]:
    """Hip angle and total knee bend putting the ankle at (x, z) from the hip (x forward, z up).

    The two knee servos share the bend equally, so the chain thigh-link-shank is symmetric and the
    ankle lies at distance ``r = (thigh + shank) cos(k / 2) + link`` (for thigh = shank) along the
    knee link's direction. Positive hip angle swings the leg backward; positive knee flexes.
    """
    r = math.hypot(x, z)
    leg = 0.5 * (thigh + shank)
    c = (r - link) / (2.0 * leg)
    if not -1.0 <= c <= 1.0:
        raise ValueError(f"point ({x:.3f}, {z:.3f}) m is out of the biped leg's reach "
                         f"({link:.3f} to {link + 2 * leg:.3f} m from the hip)")
    k = 2.0 * math.acos(c)
    phi = math.atan2(-x, -z)
    return phi - k / 2.0, k


def rect_path(s: float, length: float, height: float, duty: float, presentation: float,
              depth: float, x0: float = 0.0) -> tuple[float, float, float]:
    """Foot centre (x, z) relative to the hip and foot pitch (rad) at cycle fraction ``s`` in [0, 1)."""
    x, z, pitch = _rect_path(s, length, height, duty, presentation, depth)
    return x + x0, z, pitch


def _rect_path(s, length, height, duty, presentation, depth):
    half = length / 2.0
    swing = 1.0 - duty
    per = swing / (2.0 * height + length)  # cycle fraction per metre of swing path
    t_up, t_top = height * per, length * per
    zb, zt = -depth, -depth + height
    if s < duty:  # stance: front to back along the bottom edge
        u = s / duty
        pitch = presentation * (1.0 - min(u / 0.25, 1.0))
        return half - length * u, zb, pitch
    s -= duty
    if s < t_up:  # lift along the rear edge
        return -half, zb + height * s / t_up, 0.0
    s -= t_up
    if s < t_top:  # forward along the top edge, turning the toe to the presentation angle
        u = s / t_top
        return -half + length * u, zt, presentation * u
    s -= t_top  # intrusion down the front edge
    u = min(s / t_up, 1.0)
    return half, zt - height * u, presentation


def _build_rect(env, p: dict) -> Callable[[float], np.ndarray]:
    from mjrft.models import biped as bm

    period, length, height, duty = p["period"], p["length"], p["height"], p["duty"]
    angle, depth, x0 = math.radians(p["angle"]), p["depth"], p["x0"]
    for x, z in ((x0 + length / 2, -depth), (x0 - length / 2, -depth), (x0, -depth + height),
                 (x0 + length / 2, -depth + height), (x0 - length / 2, -depth + height)):
        try:
            biped_leg_ik(x, z, bm.THIGH, bm.KNEE_LINK, bm.SHANK)
        except ValueError as exc:
            raise ValueError(f"gait 'rect' length={length:g}, height={height:g}, depth={depth:g}: {exc}; "
                             "use a shorter rectangle or a smaller depth") from None
    index = _actuator_index(env)
    lo, hi = bm.RANGES["knee_upper"]
    if "rooty" in {env.model.joint(j).name for j in range(env.model.njnt)}:
        warnings.warn("gait 'rect' drives a biped whose torso pitch is free; the reference gait study held "
                      "the pitch (make the env with pitch_free=False), open loop it tips over", GaitWarning,
                      stacklevel=4)

    def act(t: float) -> np.ndarray:
        targets = {}
        for side, ph in (("left", 0.0), ("right", 0.5)):
            s = ((t + env.dt) / period + ph) % 1.0
            x, z, pitch = rect_path(s, length, height, duty, angle, depth, x0)
            hip, knee = biped_leg_ik(x, z, bm.THIGH, bm.KNEE_LINK, bm.SHANK)
            k = min(max(knee / 2.0, lo), hi)
            targets[f"{side}_hip"] = hip
            targets[f"{side}_knee_upper"] = k
            targets[f"{side}_knee_lower"] = k
            targets[f"{side}_ankle"] = pitch - (hip + 2.0 * k)  # foot pitch in the (upright) torso frame
        return _joint_targets_to_action(env, index, targets)

    return act


# ----------------------------------------------------------------------------- stand / shift (humanoid)


def humanoid_leg_ik(x: float, y: float, z: float, thigh: float, shank: float) -> dict[str, float]:
    """Joint angles of one humanoid leg putting the ankle at (x, y, z) from the hip, foot flat.

    Chain: hip_roll (x) then hip_pitch, knee, ankle_pitch (y, in the rolled plane) then ankle_roll.
    Roll > 0 moves the foot toward +y; pitch > 0 swings the leg backward; knee > 0 flexes it.
    """
    roll = math.atan2(y, -z)
    zs = -math.hypot(y, z)
    r = math.hypot(x, zs)
    reach = (thigh + shank) * 0.9995
    if r > reach:  # fully stretched: keep the direction, stop at the reach
        x, zs, r = x * reach / r, zs * reach / r, reach
    # law of cosines for the knee
    c = (thigh ** 2 + shank ** 2 - r ** 2) / (2.0 * thigh * shank)
    knee = math.pi - math.acos(min(max(c, -1.0), 1.0))
    phi = math.atan2(-x, -zs)
    a = math.asin(min(max(shank * math.sin(knee) / max(r, 1e-9), -1.0), 1.0))
    hip = phi - a
    return {"hip_roll": roll, "hip_pitch": hip, "knee": knee, "ankle_pitch": -(hip + knee), "ankle_roll": -roll}


def _humanoid_dims():
    from mjrft.models import humanoid as hm

    return hm.THIGH, hm.SHANK


def _leg_height(crouch: float, thigh: float, shank: float) -> float:
    """Hip-to-ankle distance of a leg with knee bend ``crouch`` (rad)."""
    return math.sqrt(thigh ** 2 + shank ** 2 + 2 * thigh * shank * math.cos(crouch))


#: seconds over which ``stand`` bends the knees from the straight initial pose to ``crouch``
STAND_RAMP = 1.0


def _build_stand(env, p: dict) -> Callable[[float], np.ndarray]:
    thigh, shank = _humanoid_dims()
    index = _actuator_index(env)

    def act(t: float) -> np.ndarray:
        h = _leg_height(p["crouch"] * _smooth((t + env.dt) / STAND_RAMP), thigh, shank)
        targets = {}
        for side in ("left", "right"):
            for j, v in humanoid_leg_ik(0.0, 0.0, -h, thigh, shank).items():
                targets[f"{side}_{j}"] = v
        return _joint_targets_to_action(env, index, targets)

    return act


# fractions of a step (the shift gait): lift, swing forward, intrusion, CoM shift; the rest is a hold
LIFT, SWING, INTRUDE, SHIFT = 0.15, 0.20, 0.20, 0.30


def shift_pose(t: float, p: dict) -> tuple[dict[str, tuple[float, float, float]], float]:
    """Ankle targets relative to each hip (x, y, z) and the pelvis sideways offset at time ``t``.

    ``p`` holds every parameter of the ``shift`` gait. Returns ``({"left": (x, y, z), "right":
    (...)}, y_pelvis)``; see the module docstring.
    """
    thigh, shank = _humanoid_dims()
    T, step, lift, sway, depth = p["period"], p["step"], p["lift"], p["sway"], p["depth"]
    start = 0.5 * T  # first half step: bend the knees and move the pelvis over the right (stance) foot
    if t < start:
        u = _smooth(t / start)
        h = _leg_height(p["crouch"] * u, thigh, shank)
        y_p = -sway * u
        return {"left": (0.0, -y_p, -h), "right": (0.0, -y_p, -h)}, y_p
    h = _leg_height(p["crouch"], thigh, shank)
    k, s = divmod((t - start) / T, 1.0)
    k = int(k)
    swing_side, stance_side = ("left", "right") if k % 2 == 0 else ("right", "left")
    sign = 1.0 if swing_side == "left" else -1.0  # pelvis moves toward +y when the left foot steps
    x0_swing = -step / 2.0 if k > 0 else 0.0
    x0_stance = step / 2.0 if k > 0 else 0.0
    # swing foot
    if s < LIFT:
        xs, zs = x0_swing, -h + lift * _smooth(s / LIFT)
    elif s < LIFT + SWING:
        xs, zs = x0_swing + (step / 2.0 - x0_swing) * _smooth((s - LIFT) / SWING), -h + lift
    else:
        xs = step / 2.0
        zs = -h + lift - (lift + depth) * _smooth((s - LIFT - SWING) / INTRUDE)
    # stance foot slides back while the swing foot is in the air and intruding
    xt = x0_stance + (-step / 2.0 - x0_stance) * _smooth(s / (LIFT + SWING + INTRUDE))
    zt = -h
    # pelvis: over the stance foot, then toward the stepping foot from `shift` of the intrusion
    s0 = LIFT + SWING + p["shift"] * INTRUDE
    y_p = sign * sway * (2.0 * _smooth((s - s0) / SHIFT) - 1.0)
    feet = {swing_side: (xs, -y_p, zs), stance_side: (xt, -y_p, zt)}
    return feet, y_p


def _build_shift(env, p: dict) -> Callable[[float], np.ndarray]:
    thigh, shank = _humanoid_dims()
    h = _leg_height(p["crouch"], thigh, shank)
    reach = math.hypot(p["step"] / 2.0, math.hypot(h + p["depth"], p["sway"]))
    if reach > (thigh + shank) * 0.9995:
        raise ValueError(f"gait 'shift' step={p['step']:g}, depth={p['depth']:g}, sway={p['sway']:g} with "
                         f"crouch={p['crouch']:g} needs {reach:.3f} m of leg, more than {thigh + shank:.3f} m; "
                         "increase crouch or reduce step / depth / sway")
    index = _actuator_index(env)

    def act(t: float) -> np.ndarray:
        feet, _ = shift_pose(t + env.dt, p)
        targets = {}
        for side, (x, y, z) in feet.items():
            for j, v in humanoid_leg_ik(x, y, z, thigh, shank).items():
                targets[f"{side}_{j}"] = v
        return _joint_targets_to_action(env, index, targets)

    return act


# ----------------------------------------------------------------------------- registry

_HEX = "mjrft.envs.hexapod:HexapodSand"
_BIPED = "mjrft.envs.biped:BipedSand"
_HUMANOID = "mjrft.envs.humanoid:HumanoidSand"

GAITS: dict[str, GaitDef] = {
    "tripod": GaitDef(
        "tripod", "hexapod", _HEX, "alternating tripod (Buehler clock) for the RHex-class hexapod",
        {
            "f": Param(2.0, "Hz", "stride frequency", 0.0, math.inf, low_open=True),
            "duty": Param(0.5, "-", "duty factor: fraction of the cycle in stance", 0.0, 1.0, True, True),
            "sweep": Param(math.pi, "rad", "stance sweep angle, centred on straight down", 0.0, 2 * math.pi,
                           True, True),
            "offset": Param(0.5, "cycles", "phase offset of tripod B (rf, lm, rr) after tripod A", 0.0, 1.0,
                            high_open=True),
        },
        _build_tripod,
    ),
    "rect": GaitDef(
        "rect", "biped", _BIPED, "rectangular foot path with a toe presentation angle for the planar biped",
        {
            "period": Param(6.0, "s", "cycle period", 0.0, math.inf, low_open=True),
            "length": Param(0.16, "m", "rectangle length (stride)", 0.0, math.inf, low_open=True),
            "height": Param(0.03, "m", "rectangle height (foot lift)", 0.0, math.inf, low_open=True),
            "duty": Param(5 / 8, "-", "fraction of the period on the bottom edge", 0.0, 1.0, True, True),
            "angle": Param(0.0, "deg", "presentation angle on intrusion, positive toe-down", -90.0, 90.0),
            "depth": Param(0.14, "m", "bottom edge below the hip axis", 0.0, math.inf, low_open=True),
            "x0": Param(0.0, "m", "rectangle centre ahead of the hip axis", -0.2, 0.2),
        },
        _build_rect,
    ),
    "stand": GaitDef(
        "stand", "humanoid", _HUMANOID, "hold a standing posture (feet flat, pelvis above the ankles)",
        {"crouch": Param(0.0, "rad", "knee bend of the posture", 0.0, 2.0)},
        _build_stand,
    ),
    "shift": GaitDef(
        "shift", "humanoid", _HUMANOID, "centre-of-mass shifting walk for the humanoid",
        {
            "shift": Param(0.5, "-", "CoM shift start as a fraction of the stepping foot's intrusion phase",
                           0.0, 1.0),
            "period": Param(6.0, "s", "duration of one step", 0.0, math.inf, low_open=True),
            "step": Param(0.05, "m", "step length (foot travel relative to the pelvis)", 0.0, 0.5),
            "lift": Param(0.03, "m", "swing foot lift", 0.0, 0.3),
            "sway": Param(0.10, "m", "sideways pelvis shift to either side of centre", 0.0, 0.25),
            "depth": Param(0.01, "m", "intrusion target below the standing sole level", 0.0, 0.1),
            "crouch": Param(0.8, "rad", "knee bend of the stance posture", 0.0, 2.0),
        },
        _build_shift,
    ),
}


def describe() -> str:
    """Human-readable list of every gait, its robot and parameters (defaults and units)."""
    lines = []
    for g in GAITS.values():
        lines.append(f"{g.name} ({g.robot}): {g.help}")
        for k, prm in g.params.items():
            lines.append(f"    {k:8s} default {prm.default:<8.4g} {prm.unit:7s} {prm.help}")
    return "\n".join(lines)


# ----------------------------------------------------------------------------- public API


def is_gait_spec(text) -> bool:
    """True when ``text`` names a gait (``"tripod"``, ``"tripod:f=2"``); False for anything else (a path)."""
    if not isinstance(text, str):
        return False
    return text.split(":", 1)[0].strip() in GAITS


def parse_gait_spec(spec: str) -> tuple[str, dict[str, float]]:
    """``"name:key=value,..."`` -> ``(name, {key: float})`` with the given parameters only (checked).

    Raises ValueError naming the bad gait / parameter / value and listing the valid ones.
    """
    if not isinstance(spec, str) or not spec.strip():
        raise ValueError(f"empty gait spec {spec!r}; valid gaits: {', '.join(sorted(GAITS))}")
    name, _, rest = spec.strip().partition(":")
    name = name.strip()
    if name not in GAITS:
        raise unknown("gait", name, GAITS)
    gait = GAITS[name]
    params: dict[str, float] = {}
    for item in (s.strip() for s in rest.split(",")):
        if not item:
            continue
        key, eq, value = item.partition("=")
        key = key.strip()
        if not eq:
            raise ValueError(f"gait {name!r}: expected key=value, got {item!r}; valid parameters: "
                             f"{', '.join(gait.params)}")
        if key not in gait.params:
            raise ValueError(f"gait {name!r} has no parameter {key!r}; valid parameters: {', '.join(gait.params)}")
        if key in params:
            raise ValueError(f"gait {name!r}: parameter {key!r} given twice in {spec!r}")
        try:
            v = float(value)
        except ValueError:
            raise ValueError(f"gait {name!r}: parameter {key}={value.strip()!r} is not a number") from None
        params[key] = gait.params[key].check(name, key, v)
    return name, params


def _unwrap_envs(env) -> list:
    """Unwrapped gymnasium envs behind ``env`` (gymnasium wrappers, DummyVecEnv, VecEnvWrapper)."""
    while hasattr(env, "venv"):  # stable-baselines3 VecEnvWrapper (VecNormalize, VecMonitor, ...)
        env = env.venv
    if hasattr(env, "envs"):  # DummyVecEnv
        return [e.unwrapped for e in env.envs]
    if hasattr(env, "num_envs") and not hasattr(env, "unwrapped"):
        raise ValueError(f"cannot bind a gait to {type(env).__name__}: its simulations live in other processes; "
                         "use a DummyVecEnv or a plain gymnasium env")
    return [env.unwrapped]


def make_gait(spec: str, env) -> GaitPolicy:
    """Build the gait ``spec`` bound to ``env`` (see the module docstring for the time convention)."""
    import importlib

    name, given = parse_gait_spec(spec)
    gait = GAITS[name]
    params = {**gait.defaults(), **given}
    mod, cls = gait.env_class.split(":")
    env_cls = getattr(importlib.import_module(mod), cls)
    envs = _unwrap_envs(env)
    for u in envs:
        if not isinstance(u, env_cls):
            valid = sorted(g for g, d in GAITS.items() if isinstance(u, getattr(
                importlib.import_module(d.env_class.split(":")[0]), d.env_class.split(":")[1])))
            raise ValueError(f"gait {name!r} drives the {gait.robot} ({cls} and its rigid twin), not "
                             f"{type(u).__name__}; gaits for this env: {', '.join(valid) or 'none'}")
    fns = [gait.build(u, params) for u in envs]
    return GaitPolicy(spec=spec, name=name, params=params, envs=envs, _fns=fns)


__all__ = ["GAITS", "GaitDef", "GaitWarning", "GaitPolicy", "Param", "describe", "is_gait_spec", "make_gait", "parse_gait_spec",
           "buehler_angle", "biped_leg_ik", "humanoid_leg_ik", "rect_path", "shift_pose"]

"""Open-loop gaits of the papers, as policies with the stable-baselines3 interface.

A gait is built from a spec string ``"name:key=value,key=value"`` and bound to the environment it
drives::

    import gymnasium, mjrft.envs
    from mjrft.tools.gaits import make_gait
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
rect       biped (BipedSand/Rigid)     each sole centre traces a rectangle (16 x 3 cm, 6 s, 5/8 on
                                       the bottom edge) with a toe presentation angle ``angle``
stand      humanoid (HumanoidSand/     hold a (crouched) standing posture
           Rigid)
stance     humanoid                    one-foot stance: CoM over the right sole, left foot lifted
shift      humanoid                    quasi-static walk that shifts the CoM ``amount`` toward the
                                       stepping foot from ``start`` of its intrusion phase
=========  ==========================  ============================================================

``mjrft.tools.gaits.describe()`` lists every gait with its parameters, defaults and units.

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
  (lf, rm, lr) has phase ``phase`` at ``t = 0`` (cycles, default 0: mid-stance, legs down), tripod B
  ``phase + offset`` (``offset`` default 0.5). The env starts with every leg down, so B (and A when
  ``phase`` is not 0) catches up to its phase at full speed; :func:`tripod_angles` gives the gait's pose
  at any time, to start a robot on it instead (as Li 2013's simulation started its trials, each at a
  different phase).
  A spec whose stance or swing speed exceeds the env's ``max_hip_speed`` is rejected; one that needs all
  of it warns (``GaitWarning``): with no speed to spare the tripods never reach their phases from the
  env's start and walk in step.
* **rect** (robophysics thesis, section 2.3.3 and fig. 9). The foot centre moves relative to the hip
  on a rectangle ``length`` x ``height`` whose bottom edge is ``depth`` below the hip, centred under
  the hip. The foot centre is the centre of the sole (the model's ``<side>_sole`` site): the thesis
  measures the presentation angle as the angle of the toe tip about the foot centre, zero with the
  foot level, so the centre lies on the sole, and the foot turns about it. Order: bottom edge front to
  back (stance, fraction ``duty`` of ``period``, uniform speed), up the rear edge, forward along the
  top, down the front edge (intrusion); the swing (``1 - duty``) is shared among the three swing
  edges in proportion to their lengths (uniform speed along the swing path, as the thesis states).
  Legs are half a period apart. Foot pitch (positive toe-down): level from the end of stance until
  the foot is at its highest (the end of the lift), then turning at constant angular velocity to the
  presentation ``angle`` (degrees), reached as the foot is fully intruded (end of the front edge);
  in stance it returns to level at constant angular velocity while the other foot is still down
  (the double support, the first ``duty - 1/2`` of the cycle), so ``duty`` must exceed 1/2. The
  thesis leaves the foot's pitch during the lift unstated; we keep it level there. Inverse
  kinematics: the two knee servos split the knee bend equally; torso pitch is not compensated (open
  loop). ``depth`` defaults to 0.14 m, the deepest posture at which the model's legs reach every
  corner of the rectangle at presentation angles up to 57 deg (the thesis used up to 55 deg); the
  leg dimensions are the model's (the thesis gives only the robot's 30.3 cm height). Start: the joint
  targets blend from the env's initial (straight-legged) pose into the gait over ``start`` seconds
  (cosine ease; the thesis does not describe how its robot started).
* **stand / stance / shift.** Joint targets come from leg inverse kinematics in the pelvis frame (feet
  flat, pelvis assumed upright). ``crouch`` is the knee bend (rad) of the posture; ``stand`` bends the
  knees from the straight initial pose over its first second (a sudden crouch throws the robot over).
  ``stance`` (the thesis's one-foot stance test; HUBO was placed and left standing, open loop): bends
  the knees (1 s), moves the pelvis so that the whole-body CoM is ``(com_x, com_y)`` from the centre of
  the right sole (2 s; the pelvis offset is solved once from the model's kinematics,
  :func:`stance_pose`), lifts the left foot by ``lift`` (1 s) and holds. While the right foot takes the
  load, each servo is aimed past its angle by its static joint torque over ``kp``
  (:func:`humanoid_static_targets`): without it the hip servos sag ~0.03 rad and the CoM lands ~4 cm
  outside the planned point. ``shift``: the first half step bends the knees and moves the pelvis over
  the right foot; then each step of ``period`` seconds lifts the swing foot by ``lift`` (15% of the
  step), carries it from one ``step`` behind the stance foot (alongside on the first step) to one
  ``step`` ahead (20%), intrudes it down to ``depth`` below the standing sole level (20%: the intrusion
  phase). The pelvis moves from over the stance foot (``sway`` m to its side of centre, and over it
  along x) toward the new foothold in two parts (:func:`shift_fraction`, after the thesis's HUBO gait):
  ``amount`` of the way over 5% of the step from ``start`` of the intrusion phase, the rest over 25% once
  the intrusion and that partial shift are over (double support). ``amount = 0`` is the hard-ground
  gait (the CoM stays over the stance foot until both feet are down); the thesis's HUBO used
  ``amount = 0.3`` with starts 0.6-0.8. The loaded leg's static sag is fed forward as in ``stance``.
  The left foot steps first. Measured on ``HumanoidRigid-v0`` (15.2 cm feet, sway 0.1 m): the
  hard-ground and the default shifted gait walk 16 s, 10 cm (two 5 cm steps). On ``HumanoidSand-v0``
  the 30.4 cm boards fall in the first half step (``thesis_hubo_gait`` in ``mjrft validate``).
* **rect on a pitch-free torso.** The reference gait study held the biped's torso pitch (sagittal
  plane, fore-aft and vertical only; pitch was free only in the balance study), so ``rect`` is meant
  for ``BipedSand(pitch_free=False)``: there (cone feet, closely packed poppy seeds, ``angle=0``) it
  walks 4.6 cm/s (13.7 cm per 3 s step). On the default pitch-free biped it still runs but tips over
  within ~2 s; :func:`make_gait` warns (``GaitWarning``) in that case.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from mjrft.errors import unknown
from mjrft.models.biped import biped_leg_ik
from mjrft.models.humanoid import humanoid_leg_ik


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
    env_class: str  # "module:Class" that the env must be an instance of (:func:`_drives`)
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


def tripod_angles(env, t: float, f: float, duty: float = 0.5, sweep: float = math.pi, offset: float = 0.5,
                  phase: float = 0.0) -> np.ndarray:
    """Hip angles (rad, unwrapped, the hexapod env's actuator order) of the ``tripod`` gait at time ``t``:
    tripod A at ``phase + f t`` cycles, tripod B (``env.TRIPOD_B_IDX``) ``offset`` cycles later."""
    cycles = np.full(6, phase + f * t)
    cycles[list(env.TRIPOD_B_IDX)] += offset
    return np.array([buehler_angle(c, duty, sweep) for c in cycles])


def _build_tripod(env, p: dict) -> Callable[[float], np.ndarray]:
    f, duty, sweep, offset = p["f"], p["duty"], p["sweep"], p["offset"]
    ms, dt = float(env.task.max_hip_speed), float(env.dt)
    stance_speed = sweep * f / duty
    swing_speed = (2.0 * math.pi - sweep) * f / (1.0 - duty)
    need = max(stance_speed, swing_speed)
    if need > ms * (1.0 + 1e-9):
        raise ValueError(f"gait 'tripod' f={f:g}, duty={duty:g}, sweep={sweep:g} needs a hip speed of "
                         f"{need:.2f} rad/s (stance {stance_speed:.2f}, swing {swing_speed:.2f}), above the env's "
                         f"max_hip_speed {ms:.2f} rad/s; lower f, or move duty toward sweep / (2 pi)")
    if need >= ms * (1.0 - 1e-9) and (p["phase"] % 1.0 or offset % 1.0):
        warnings.warn(f"gait 'tripod' f={f:g} needs a hip speed of {need:.2f} rad/s, all of the env's max_hip_speed "
                      f"{ms:.2f} rad/s: from the env's start (every leg down) the tripods never catch up to their "
                      f"phases and stay in step with each other; make the env with max_hip_speed above {need:.2f} "
                      f"rad/s, or lower f", GaitWarning, stacklevel=4)

    def act(t: float) -> np.ndarray:
        ref = tripod_angles(env, t + dt, f, duty, sweep, offset, p["phase"])
        err = ref - env.target
        # whole turns do not matter: bring the error into [-pi/2, 3 pi/2) (catch up forward)
        err = np.mod(err + 0.5 * np.pi, 2.0 * np.pi) - 0.5 * np.pi
        return np.clip(err / (ms * dt), -1.0, 1.0).astype(np.float32)

    return act


# ----------------------------------------------------------------------------- rect (biped)


def rect_path(s: float, length: float, height: float, duty: float, presentation: float,
              depth: float, x0: float = 0.0) -> tuple[float, float, float]:
    """Sole centre (x, z) relative to the hip and foot pitch (rad, positive toe-down) at cycle fraction
    ``s`` in [0, 1) of the ``rect`` gait (see the module docstring; ``duty`` > 1/2)."""
    x, z, pitch = _rect_path(s, length, height, duty, presentation, depth)
    return x + x0, z, pitch


def _rect_path(s, length, height, duty, presentation, depth):
    half = length / 2.0
    swing = 1.0 - duty
    per = swing / (2.0 * height + length)  # cycle fraction per metre of swing path
    t_up, t_top = height * per, length * per
    zb, zt = -depth, -depth + height
    level = duty - 0.5  # the other foot lifts here (legs half a cycle apart): the foot is level again
    turn = t_top + t_up  # top edge + intrusion: the toe turns at constant rate from 0 to the presentation angle
    if s < duty:  # stance: front to back along the bottom edge
        return half - length * s / duty, zb, presentation * max(0.0, 1.0 - s / level)
    s -= duty
    if s < t_up:  # lift along the rear edge, foot level
        return -half, zb + height * s / t_up, 0.0
    s -= t_up
    pitch = presentation * min(s / turn, 1.0)
    if s < t_top:  # forward along the top edge
        return -half + length * s / t_top, zt, pitch
    s -= t_top  # intrusion down the front edge
    return half, zt - height * min(s / t_up, 1.0), pitch


def _build_rect(env, p: dict) -> Callable[[float], np.ndarray]:
    from mjrft.models import biped as bm

    period, length, height, duty = p["period"], p["length"], p["height"], p["duty"]
    angle, depth, x0, start = math.radians(p["angle"]), p["depth"], p["x0"], p["start"]
    m = env.model
    # the ankle axis above the sole centre, in the foot frame (the model's <side>_sole site)
    ankle = {side: -float(m.site_pos[m.site(f"{side}_sole").id][2]) for side in ("left", "right")}

    def leg(side: str, s: float) -> tuple[float, float, float]:
        x, z, pitch = rect_path(s, length, height, duty, angle, depth, x0)
        a = ankle[side]
        hip, knee = biped_leg_ik(x + a * math.sin(pitch), z + a * math.cos(pitch), bm.THIGH, bm.KNEE_LINK, bm.SHANK)
        return hip, knee, pitch

    for s in np.linspace(0.0, 1.0, 241):
        try:
            leg("left", s % 1.0)
        except ValueError as exc:
            raise ValueError(f"gait 'rect' length={length:g}, height={height:g}, depth={depth:g}, angle={p['angle']:g}: "
                             f"{exc}; use a shorter rectangle, a smaller depth or angle") from None
    index = _actuator_index(env)
    lo, hi = bm.RANGES["knee_upper"]
    q0 = env.action_to_ctrl(np.zeros(m.nu))  # the initial pose's joint targets
    if "rooty" in {m.joint(j).name for j in range(m.njnt)}:
        warnings.warn("gait 'rect' drives a biped whose torso pitch is free; the reference gait study held "
                      "the pitch (make the env with pitch_free=False), open loop it tips over", GaitWarning,
                      stacklevel=4)

    def act(t: float) -> np.ndarray:
        t = t + env.dt
        w = _smooth(t / start) if start > 0 else 1.0
        targets = {}
        for side, ph in (("left", 0.0), ("right", 0.5)):
            hip, knee, pitch = leg(side, (t / period + ph) % 1.0)
            k = min(max(knee / 2.0, lo), hi)
            joint = {"hip": hip, "knee_upper": k, "knee_lower": k,
                     "ankle": pitch - (hip + 2.0 * k)}  # foot pitch in the (upright) torso frame
            for j, v in joint.items():
                name = f"{side}_{j}"
                targets[name] = q0[index[name]] + w * (v - q0[index[name]])
        return _joint_targets_to_action(env, index, targets)

    return act


# ----------------------------------------------------------------------------- stand / shift (humanoid)


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


# fractions of a step (the shift gait): lift, swing forward, intrusion; the partial CoM shift that starts
# during the intrusion and the double-support shift that completes it; the rest is a hold
LIFT, SWING, INTRUDE, PARTIAL, DOUBLE = 0.15, 0.20, 0.20, 0.05, 0.25


def shift_fraction(s: float, start: float, amount: float) -> float:
    """How far (0..1) the pelvis has moved from over the stance foot toward the stepping foot at ``s``
    (fraction of the step): ``amount`` of the way over ``PARTIAL`` from ``start`` of the intrusion, the rest
    over ``DOUBLE`` once the intrusion and the partial shift are over (double support)."""
    s0 = LIFT + SWING + start * INTRUDE
    s1 = max(LIFT + SWING + INTRUDE, s0 + PARTIAL)
    return amount * _smooth((s - s0) / PARTIAL) + (1.0 - amount) * _smooth((s - s1) / DOUBLE)


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
    # world x along the walk: the stance foot at k * step, the swing foot from one step behind it (alongside
    # on the first step) to one step ahead; the pelvis from over the stance foot to over the new foothold
    x_stance = k * step
    x0_swing = x_stance - step if k > 0 else 0.0
    if s < LIFT:
        xs, zs = x0_swing, -h + lift * _smooth(s / LIFT)
    elif s < LIFT + SWING:
        xs, zs = x0_swing + (x_stance + step - x0_swing) * _smooth((s - LIFT) / SWING), -h + lift
    else:
        xs = x_stance + step
        zs = -h + lift - (lift + depth) * _smooth((s - LIFT - SWING) / INTRUDE)
    frac = shift_fraction(s, p["start"], p["amount"])
    x_p = x_stance + frac * step
    y_p = sign * sway * (2.0 * frac - 1.0)
    feet = {swing_side: (xs - x_p, -y_p, zs), stance_side: (x_stance - x_p, -y_p, -h)}
    return feet, y_p


def shift_load(t: float, p: dict) -> tuple[str, float]:
    """The stance foot of the ``shift`` gait at ``t`` and the weight (0..1) of its one-leg feed-forward:
    it grows with the pelvis moving over the right foot in the first half step and with the swing foot's
    lift, and falls as the pelvis moves over to the new foothold."""
    T = p["period"]
    if t < 0.5 * T:
        return "right", _smooth(t / (0.5 * T))
    k, s = divmod((t - 0.5 * T) / T, 1.0)
    stance = "right" if int(k) % 2 == 0 else "left"
    return stance, min(_smooth(s / LIFT) if k > 0 else 1.0, 1.0 - shift_fraction(s, p["start"], p["amount"]))


def _build_shift(env, p: dict) -> Callable[[float], np.ndarray]:
    thigh, shank = _humanoid_dims()
    h = _leg_height(p["crouch"], thigh, shank)
    reach = math.hypot(p["step"], math.hypot(h + p["depth"], p["sway"]))
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
        stance, w = shift_load(t + env.dt, p)
        if w > 0.0:  # the servos of the loaded leg aimed past the pose (humanoid_static_targets)
            held = humanoid_static_targets(env.model, targets, stance)
            targets = {k: targets.get(k, 0.0) + w * (v - targets.get(k, 0.0)) for k, v in held.items()}
        return _joint_targets_to_action(env, index, targets)

    return act


# ----------------------------------------------------------------------------- one-leg stance (humanoid)

#: seconds of the ``stance`` gait's phases: bend the knees, move the CoM over the right foot, lift the left
STANCE_CROUCH, STANCE_SHIFT, STANCE_LIFT = 1.0, 2.0, 1.0


def humanoid_com_sole(model, targets: dict[str, float], stance: str = "right") -> np.ndarray:
    """Whole-body CoM minus the centre of the ``stance`` sole (x, y; m) for joint angles ``targets``
    with the pelvis upright (the joints not named are at 0): :func:`mujoco.mj_kinematics` on a scratch
    ``MjData``, so it uses the model's real masses and foot plates."""
    import mujoco

    d = mujoco.MjData(model)
    for name, v in targets.items():
        d.qpos[model.jnt_qposadr[model.joint(name).id]] = v
    mujoco.mj_kinematics(model, d)
    mujoco.mj_comPos(model, d)
    root = model.body("pelvis").id
    return d.subtree_com[root, :2] - d.site_xpos[model.site(f"{stance}_sole").id, :2]


def humanoid_static_targets(model, targets: dict[str, float], stance: str = "right") -> dict[str, float]:
    """Servo targets that hold the joint angles ``targets`` at rest with the ``stance`` foot carrying the
    robot: each position servo (``kp``) is aimed past its angle by ``tau / kp``, ``tau`` the joint torque
    of the static pose (:func:`mujoco.mj_inverse` with zero velocity and acceleration; the free joint's
    force and torque are carried by a wrench on the stance foot, solved from the free joint's 6 rows).
    Without it the 1500 N m/rad hip servos give way by ~0.03 rad under the one-leg load and put the CoM
    ~4 cm outside the planned point (measured on ``HumanoidRigid-v0``)."""
    import mujoco

    d = mujoco.MjData(model)
    for name, v in targets.items():
        d.qpos[model.jnt_qposadr[model.joint(name).id]] = v
    mujoco.mj_forward(model, d)
    d.qacc[:] = 0.0
    mujoco.mj_inverse(model, d)
    foot = model.body(f"{stance}_foot").id
    jp, jr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    mujoco.mj_jacBody(model, d, jp, jr, foot)
    jac = np.vstack([jp, jr])  # (6, nv): the foot wrench's generalised force is jac.T @ wrench
    wrench = np.linalg.solve(jac[:, :6].T, d.qfrc_inverse[:6])
    tau = d.qfrc_inverse - jac.T @ wrench
    out = {}
    for i in range(model.nu):
        j = model.actuator_trnid[i, 0]
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, j)
        q = targets.get(name, 0.0)
        out[name] = q + tau[model.jnt_dofadr[j]] / model.actuator_gainprm[i, 0]
    return out


def stance_pose(model, p: dict) -> tuple[float, float]:
    """Pelvis offset ``(x, y)`` from the stance (right) foot's hip-aligned position that puts the CoM
    ``(com_x, com_y)`` from the centre of the right sole in the one-leg pose of ``p`` (left foot lifted
    by ``lift``; both feet keep their places on the ground, the pelvis moves). Solved by fixed-point
    iteration on :func:`humanoid_com_sole` to 0.1 mm."""
    thigh, shank = _humanoid_dims()
    h = _leg_height(p["crouch"], thigh, shank)
    off = np.zeros(2)
    want = np.array([p["com_x"], p["com_y"]])
    for _ in range(60):
        targets = {}
        for side, dz in (("right", 0.0), ("left", p["lift"])):
            for j, v in humanoid_leg_ik(-off[0], -off[1], -h + dz, thigh, shank).items():
                targets[f"{side}_{j}"] = v
        err = want - humanoid_com_sole(model, targets)
        off += err
        if np.all(np.abs(err) < 1e-4):
            return float(off[0]), float(off[1])
    raise ValueError(f"gait 'stance': no pelvis position puts the CoM at ({p['com_x']:g}, {p['com_y']:g}) m from "
                     f"the right sole with crouch={p['crouch']:g}, lift={p['lift']:g} (last error {err} m)")


def _build_stance(env, p: dict) -> Callable[[float], np.ndarray]:
    thigh, shank = _humanoid_dims()
    h = _leg_height(p["crouch"], thigh, shank)
    ox, oy = stance_pose(env.model, p)
    index = _actuator_index(env)

    def act(t: float) -> np.ndarray:
        t = t + env.dt
        hc = _leg_height(p["crouch"] * _smooth(t / STANCE_CROUCH), thigh, shank)
        u = _smooth((t - STANCE_CROUCH) / STANCE_SHIFT)
        lift = p["lift"] * _smooth((t - STANCE_CROUCH - STANCE_SHIFT) / STANCE_LIFT)
        targets = {}
        for side, dz in (("right", 0.0), ("left", lift)):
            for j, v in humanoid_leg_ik(-ox * u, -oy * u, -(hc if t < STANCE_CROUCH else h) + dz, thigh,
                                        shank).items():
                targets[f"{side}_{j}"] = v
        if u > 0.0:  # the right foot takes the load as the CoM moves over it: aim the servos past the pose
            held = humanoid_static_targets(env.model, targets)
            targets = {k: targets.get(k, 0.0) + u * (v - targets.get(k, 0.0)) for k, v in held.items()}
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
            "phase": Param(0.0, "cycles", "phase of tripod A at t = 0 (0: mid-stance)", 0.0, 1.0, high_open=True),
        },
        _build_tripod,
    ),
    "rect": GaitDef(
        "rect", "biped", _BIPED, "rectangular foot path with a toe presentation angle for the planar biped",
        {
            "period": Param(6.0, "s", "cycle period", 0.0, math.inf, low_open=True),
            "length": Param(0.16, "m", "rectangle length (stride)", 0.0, math.inf, low_open=True),
            "height": Param(0.03, "m", "rectangle height (foot lift)", 0.0, math.inf, low_open=True),
            "duty": Param(5 / 8, "-", "fraction of the period on the bottom edge (> 1/2: a double support)",
                          0.5, 1.0, True, True),
            "angle": Param(0.0, "deg", "presentation angle on intrusion, positive toe-down", -90.0, 90.0),
            "depth": Param(0.14, "m", "bottom edge (sole centre) below the hip axis", 0.0, math.inf,
                           low_open=True),
            "x0": Param(0.0, "m", "rectangle centre ahead of the hip axis", -0.2, 0.2),
            "start": Param(1.0, "s", "joint targets blend from the initial pose into the gait over this time",
                           0.0, math.inf),
        },
        _build_rect,
    ),
    "stand": GaitDef(
        "stand", "humanoid", _HUMANOID, "hold a standing posture (feet flat, pelvis above the ankles)",
        {"crouch": Param(0.0, "rad", "knee bend of the posture", 0.0, 2.0)},
        _build_stand,
    ),
    "stance": GaitDef(
        "stance", "humanoid", _HUMANOID, "one-leg stance: CoM over the right sole, left foot lifted (open loop)",
        {
            "crouch": Param(0.3, "rad", "knee bend of the posture", 0.0, 2.0),
            "lift": Param(0.05, "m", "height the left foot is lifted to", 0.0, 0.3),
            "com_x": Param(0.0, "m", "CoM target ahead of the right sole's centre", -0.2, 0.2),
            "com_y": Param(0.0, "m", "CoM target left of the right sole's centre", -0.2, 0.2),
        },
        _build_stance,
    ),
    "shift": GaitDef(
        "shift", "humanoid", _HUMANOID, "centre-of-mass shifting walk for the humanoid",
        {
            "start": Param(0.65, "-", "start of the partial CoM shift, as a fraction of the stepping foot's "
                           "intrusion phase", 0.0, 1.0),
            "amount": Param(0.3, "-", "partial CoM shift during the intrusion, as a fraction of the distance "
                            "between the stance foot and the stepping foot (0: the hard-ground gait)", 0.0, 1.0),
            "period": Param(6.0, "s", "duration of one step", 0.0, math.inf, low_open=True),
            "step": Param(0.05, "m", "step length (distance between consecutive footholds)", 0.0, 0.5),
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


def _drives(gait: GaitDef, env) -> bool:
    """Whether ``gait`` drives ``env``: an instance of its ``env_class`` or of a subclass, told by the names of the
    env's classes, so the gaits import no environment (:mod:`mjrft.envs` is built on the tools)."""
    return any(f"{c.__module__}:{c.__qualname__}" == gait.env_class for c in type(env).__mro__)


def make_gait(spec: str, env) -> GaitPolicy:
    """Build the gait ``spec`` bound to ``env`` (see the module docstring for the time convention)."""
    name, given = parse_gait_spec(spec)
    gait = GAITS[name]
    params = {**gait.defaults(), **given}
    cls = gait.env_class.split(":")[1]
    envs = _unwrap_envs(env)
    for u in envs:
        if not _drives(gait, u):
            valid = sorted(g for g, d in GAITS.items() if _drives(d, u))
            raise ValueError(f"gait {name!r} drives the {gait.robot} ({cls} and its rigid twin), not "
                             f"{type(u).__name__}; gaits for this env: {', '.join(valid) or 'none'}")
    fns = [gait.build(u, params) for u in envs]
    return GaitPolicy(spec=spec, name=name, params=params, envs=envs, _fns=fns)


__all__ = ["GAITS", "GaitDef", "GaitWarning", "GaitPolicy", "Param", "describe", "is_gait_spec", "make_gait", "parse_gait_spec",
           "buehler_angle", "biped_leg_ik", "humanoid_leg_ik", "rect_path", "shift_pose"]

"""What every locomotion task of mjrft shares: the torso's health, the reward terms and the metrics.

A task is written once for both backends: its functions take the array module ``xp`` (``numpy`` for the
gymnasium envs on ``mujoco.MjData``, ``jax.numpy`` for the MJX envs on ``mjx.Data``; the two share their field
names) and the data, and use only what both modules have. The constants (body ids, index arrays, reward
scales, thresholds) are read from the ``mujoco.MjModel`` once, in the constructor.

Reward: the sum, in the order of :data:`REWARD_TERMS`, of the named terms, each its scale times its quantity:

==========  ===========================================================================  ===============
term        scaled value                                                                 scale (CPU env)
==========  ===========================================================================  ===============
forward     ``scale * dx/dt`` (torso x velocity, m/s; the humanoid's ``stand``: its own)  ``forward_reward_weight``
healthy     ``scale`` while healthy (or always when not terminating on it), else 0         ``healthy_reward``
energy      ``scale * P / (m g)``: ``P`` the actuators' mean power (W), ``m g`` the weight   ``-energy_cost_weight``
ctrl        ``scale * sum(a**2)`` of the action as given                                  ``-ctrl_cost_weight``
==========  ===========================================================================  ===============

Costs have negative scales, as in MuJoCo Playground's reward configurations. ``P`` is the actuators' mechanical
power ``sum_a |actuator_force_a x actuator_velocity_a|`` averaged over every physics step of the control step
(:meth:`LocomotionTask.power` is its value at one state): the energy the actuators delivered over the step divided
by its duration, which a sample at the step's end does not give (the servo targets jump at the start of each control
step, so the power is highest in its first physics steps).
"""

from __future__ import annotations

import mujoco
import numpy as np

G = 9.81

#: the reward terms, in the order they are summed
REWARD_TERMS = ("forward", "healthy", "energy", "ctrl")
#: the per-step metrics of every task (the gymnasium env's ``info``, the MJX env's ``state.metrics``)
METRICS = ("x_velocity", "power", "cost_of_transport", "reward_forward", "reward_energy", "reward_ctrl",
           "reward_healthy")


class LocomotionTask:
    """A robot walking forward (+x): health from the torso's height and tilt, the reward terms of the module
    docstring, the metrics :data:`METRICS`. Subclasses add the observation and the action mapping.

    ``scales``: the reward scales by term name (:data:`REWARD_TERMS`); ``healthy_z_range`` (m) and ``max_tilt``
    (rad): the healthy torso; ``terminate_when_unhealthy``: an unhealthy step ends the episode (and earns no
    healthy reward); ``reset_noise_scale``: half width of the uniform noise on ``qpos`` / ``qvel`` at reset;
    ``torso``, ``feet``: body names (the torso whose motion is measured, the bodies of the per-foot info)."""

    def __init__(self, model: mujoco.MjModel, *, scales: dict, healthy_z_range, max_tilt: float,
                 terminate_when_unhealthy: bool, reset_noise_scale: float, torso: str = "torso",
                 feet: tuple[str, ...] = ()):
        bad = sorted(set(scales) ^ set(REWARD_TERMS))
        if bad:
            raise ValueError(f"reward scales must name exactly {', '.join(REWARD_TERMS)}; got {sorted(scales)}")
        self.scales = {name: float(scales[name]) for name in REWARD_TERMS}
        self.healthy_z_range = tuple(float(v) for v in healthy_z_range)
        self.max_tilt = float(max_tilt)
        self.terminate_when_unhealthy = bool(terminate_when_unhealthy)
        self.reset_noise_scale = float(reset_noise_scale)
        self.torso = int(model.body(torso).id)
        self.feet = np.array([model.body(n).id for n in feet], dtype=np.int64)
        self.mass = float(model.body_subtreemass[0])
        self.weight = self.mass * G
        self.action_size = int(model.nu)
        #: qpos addresses of the free joints' quaternions (normalised at reset)
        self.free_quats = tuple(int(model.jnt_qposadr[j]) + 3 for j in range(model.njnt)
                                if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE)

    # ------------------------------------------------------------------ start
    def normalise_quaternions(self, xp, qpos):
        """``qpos`` with each free joint's quaternion divided by its norm."""
        for adr in self.free_quats:
            q = qpos[adr:adr + 4]
            qpos = xp.concatenate([qpos[:adr], q / xp.linalg.norm(q), qpos[adr + 4:]])
        return qpos

    # ------------------------------------------------------------------ health
    def torso_height(self, xp, data):
        """Height (m) of the torso's frame; the sand surface (or the floor) is at 0."""
        return data.xpos[self.torso, 2]

    def torso_tilt(self, xp, data):
        """Angle (rad) between the torso's z axis and the world vertical."""
        return xp.arccos(xp.clip(data.xmat[self.torso].reshape(-1)[8], -1.0, 1.0))

    def is_healthy(self, xp, data):
        """Torso height inside ``healthy_z_range``, tilt below ``max_tilt`` and a finite ``qpos``."""
        lo, hi = self.healthy_z_range
        z = self.torso_height(xp, data)
        return (lo < z) & (z < hi) & (self.torso_tilt(xp, data) < self.max_tilt) & xp.all(xp.isfinite(data.qpos))

    def terminated(self, xp, healthy):
        """Whether an unhealthy step ends the episode."""
        return xp.logical_not(healthy) & self.terminate_when_unhealthy

    # ------------------------------------------------------------------ reward
    def power(self, xp, data):
        """The actuators' mechanical power ``sum_a |actuator_force_a x actuator_velocity_a|`` (W) at ``data``'s state
        (force times velocity in each actuator's own units is the power it delivers, whatever its gear). The
        reward and the metrics take its mean over the physics steps of the control step (each backend sums it
        after every physics step)."""
        return xp.sum(xp.abs(data.actuator_force * data.actuator_velocity))

    def forward(self, xp, scale, x_velocity, xy_velocity):
        """The forward term: ``scale`` times the torso's x velocity (m/s)."""
        return scale * x_velocity

    def rewards(self, xp, *, x_velocity, xy_velocity, power, action, healthy) -> dict:
        """The scaled reward terms (:data:`REWARD_TERMS`) of a step: ``x_velocity`` (m/s) and ``xy_velocity``
        ((2,), m/s, of the torso's subtree centre of mass) over the step, ``power`` (W), the ``action`` as given
        and whether the state after the step is ``healthy``."""
        s = self.scales
        return {"forward": self.forward(xp, s["forward"], x_velocity, xy_velocity),
                "healthy": xp.where(healthy | (not self.terminate_when_unhealthy), s["healthy"], 0.0),
                "energy": s["energy"] * power / self.weight,
                "ctrl": s["ctrl"] * xp.sum(xp.square(action))}

    @staticmethod
    def total(rewards: dict):
        """The reward: the terms summed in the order of :data:`REWARD_TERMS`."""
        out = rewards[REWARD_TERMS[0]]
        for name in REWARD_TERMS[1:]:
            out = out + rewards[name]
        return out

    def metrics(self, xp, *, x_velocity, power, rewards) -> dict:
        """The step's :data:`METRICS`: ``x_velocity`` (m/s), ``power`` (W), the cost of transport
        ``P / (m g max(|v_x|, 1e-3))`` and each reward term."""
        return {"x_velocity": x_velocity, "power": power,
                "cost_of_transport": power / (self.mass * G * xp.maximum(xp.abs(x_velocity), 1e-3)),
                "reward_forward": rewards["forward"], "reward_energy": rewards["energy"],
                "reward_ctrl": rewards["ctrl"], "reward_healthy": rewards["healthy"]}


class JointTargets:
    """Normalised joint-angle targets of position servos: ``a = 0`` is the initial pose, ``a = -1 / +1`` the
    ends of each actuator's ctrlrange, linear in between on each side."""

    def __init__(self, model: mujoco.MjModel, init_qpos):
        lo, hi = model.actuator_ctrlrange.T.copy()
        q0 = np.asarray(init_qpos)[model.jnt_qposadr[model.actuator_trnid[:, 0]]]
        self.ctrl_lo, self.ctrl_hi = lo, hi
        self.ctrl_mid = np.clip(q0, lo, hi)

    def action_to_ctrl(self, xp, qpos, ctrl, action):
        """Piecewise-linear map [-1, 0, 1] -> [ctrl_low, q_initial, ctrl_high] (per actuator); ``qpos`` and the
        current ``ctrl`` are not used (the targets depend on the action alone)."""
        a = xp.clip(action, -1.0, 1.0)
        mid = self.ctrl_mid
        return xp.where(a >= 0, mid + a * (self.ctrl_hi - mid), mid + a * (mid - self.ctrl_lo))

    def ctrl_to_action(self, xp, ctrl):
        """Inverse of :meth:`action_to_ctrl` (targets outside the ctrlrange are clipped)."""
        mid, lo, hi = self.ctrl_mid, self.ctrl_lo, self.ctrl_hi
        c = xp.clip(ctrl, lo, hi)
        up = xp.where(hi > mid, (c - mid) / xp.maximum(hi - mid, 1e-12), 0.0)
        down = xp.where(mid > lo, (c - mid) / xp.maximum(mid - lo, 1e-12), 0.0)
        return xp.where(c >= mid, up, down)

    def reset_ctrl(self, xp, qpos):
        """The servo targets at reset: the initial pose (``a = 0``)."""
        return xp.asarray(self.ctrl_mid)

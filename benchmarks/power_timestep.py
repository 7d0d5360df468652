"""The actuators' energy against the physics step: the env's power measure and the force the integrator applied.

``info["power"]`` (:meth:`mjrft.GranularTerrain.actuator_power`) sums ``|actuator_force x actuator_velocity|`` of the
state at the start of each physics step. MuJoCo's ``implicit`` and ``implicitfast`` integrators treat the actuators'
velocity terms (a position servo's ``kv``) implicitly: over a step of length ``h`` the force they apply is
``f + g (v' - v)`` (``g = d f / d v``, ``v'`` the actuator velocity at the step's end), except where the force is
clamped by ``forcerange`` (then ``f``); the position moves by ``h v'``. The work the actuators do over the step is
therefore ``h sum |(f + g (v' - v)) v'|``. This script measures both on mjrft's robots at physics steps from 0.05 ms
to 1 ms (the control period fixed at 10 ms) and prints the cost of transport each gives; it first checks the rule
against MuJoCo's own step on a single servo-driven hinge (the applied force times ``h / I`` equals the velocity
change), unclamped, clamped and with the Euler integrator (which applies ``f``).

    python benchmarks/power_timestep.py [--seconds 4]
"""

from __future__ import annotations

import argparse
import math
import sys
import warnings
from pathlib import Path

import mujoco
import numpy as np

RESULTS = Path(__file__).resolve().parent / "results"
RUNS = (("mjrft/HexapodSand-v0", "tripod:f=2.0", {}), ("mjrft/HexapodSand-v0", "pretrained:HexapodSand-v0", {}),
        ("mjrft/BipedSand-v0", "rect", {"pitch_free": False}), ("mjrft/HumanoidSand-v0", "shift", {}))
STEPS = (0.00005, 0.0001, 0.00025, 0.0005, 0.001)
CONTROL_PERIOD = 0.01
_AFFINE_GAIN, _AFFINE_BIAS = int(mujoco.mjtGain.mjGAIN_AFFINE), int(mujoco.mjtBias.mjBIAS_AFFINE)
_IMPLICIT = (int(mujoco.mjtIntegrator.mjINT_IMPLICIT), int(mujoco.mjtIntegrator.mjINT_IMPLICITFAST))


def velocity_gain(m: mujoco.MjModel, d: mujoco.MjData) -> np.ndarray:
    """``d f / d v`` of each actuator as the implicit integrators use it (affine gain and bias; zero where the force
    is clamped by ``forcerange`` and with the Euler integrator)."""
    if int(m.opt.integrator) not in _IMPLICIT:
        return np.zeros(m.nu)
    scale = d.ctrl.copy()
    has_act = m.actuator_dyntype != int(mujoco.mjtDyn.mjDYN_NONE)
    scale[has_act] = d.act[m.actuator_actadr[has_act] + m.actuator_actnum[has_act] - 1]
    g = (np.where(m.actuator_biastype == _AFFINE_BIAS, m.actuator_biasprm[:, 2], 0.0)
         + np.where(m.actuator_gaintype == _AFFINE_GAIN, m.actuator_gainprm[:, 2] * scale, 0.0))
    lo, hi = m.actuator_forcerange[:, 0], m.actuator_forcerange[:, 1]
    clamped = (m.actuator_forcelimited == 1) & ((d.actuator_force <= lo) | (d.actuator_force >= hi))
    return np.where(clamped, 0.0, g)


def end_velocity(m: mujoco.MjModel, d: mujoco.MjData) -> np.ndarray:
    """The actuators' velocity at the step's end: the step's (start-state) moment arms times the new ``qvel``."""
    v = np.zeros(m.nu)
    for a in range(m.nu):
        adr, n = d.moment_rowadr[a], d.moment_rownnz[a]
        v[a] = d.actuator_moment[adr:adr + n] @ d.qvel[d.moment_colind[adr:adr + n]]
    return v


def applied_power(m: mujoco.MjModel, d: mujoco.MjData) -> tuple[float, float]:
    """(the env's measure, the applied force's) power (W) of the physics step just taken (read after ``mj_step``)."""
    f, v0 = d.actuator_force, d.actuator_velocity
    v1 = end_velocity(m, d)
    applied = f + velocity_gain(m, d) * (v1 - v0)
    return float(np.sum(np.abs(f * v0))), float(np.sum(np.abs(applied * v1)))


#: one servo-driven hinge (kp 2, kv 0.02, forcerange +-0.3 N m, armature 1e-5 kg m^2, h = 1 ms), for the rule's check
HINGE = ('<mujoco><option timestep="0.001" integrator="{}" gravity="0 0 0"/><worldbody><body>'
         '<joint name="j" type="hinge" armature="1e-5"/><geom type="sphere" size="0.001" mass="1e-6"/>'
         '</body></worldbody><actuator><position joint="j" kp="2" kv="0.02" forcelimited="true" '
         'forcerange="-0.3 0.3"/></actuator></mujoco>')
INTEGRATORS = ("implicitfast", "implicit", "Euler")
#: (ctrl, initial velocity) of the check: the force unclamped at rest and moving, and clamped
HINGE_CASES = ((0.01, 0.0), (0.01, 3.0), (1.0, 0.0))


def hinge_step(integrator: str, ctrl: float, v: float) -> tuple[float, float, float]:
    """One MuJoCo step of :data:`HINGE` from rest at 0 with velocity ``v`` and target ``ctrl``: (the force the step
    applied, ``I dv / h``; the applied force by the rule, ``f + g (v' - v)``; the start state's force ``f``)."""
    m = mujoco.MjModel.from_xml_string(HINGE.format(integrator))
    d = mujoco.MjData(m)
    d.ctrl[0], d.qvel[0] = ctrl, v
    mujoco.mj_forward(m, d)
    inertia = np.zeros((1, 1))
    mujoco.mj_fullM(m, d, inertia)
    mujoco.mj_step(m, d)
    f, v0 = float(d.actuator_force[0]), float(d.actuator_velocity[0])
    applied = f + float(velocity_gain(m, d)[0]) * (float(end_velocity(m, d)[0]) - v0)
    return float(inertia[0, 0] * (d.qvel[0] - v) / m.opt.timestep), applied, f


def check_rule() -> list[str]:
    """The applied force against MuJoCo's step on :data:`HINGE` (:func:`hinge_step`)."""
    lines = ["rule check on one hinge (kp 2, kv 0.02, forcerange +-0.3, armature 1e-5, h = 1 ms): I dv / h against "
             "the applied force"]
    for integrator in INTEGRATORS:
        for ctrl, v in HINGE_CASES:
            stepped, applied, f = hinge_step(integrator, ctrl, v)
            lines.append(f"  {integrator:12s} ctrl {ctrl:4.2f} v {v:3.1f}: I dv/h {stepped:+.6f}"
                         f"  applied {applied:+.6f}  start force {f:+.6f}")
    return lines


def measure(env_id: str, spec: str, kwargs: dict, dt: float, seconds: float) -> tuple[float, float, float]:
    """(CoT by the env's measure, CoT by the applied force, info["power"]'s CoT) of one seeded run."""
    import gymnasium

    import mjrft.envs  # noqa: F401  (registers the ids)
    from mjrft.train.evaluate import load_policy

    env = gymnasium.make(env_id, timestep=dt, frame_skip=int(round(CONTROL_PERIOD / dt)), **kwargs)
    u = env.unwrapped
    obs, _ = env.reset(seed=0)
    policy = load_policy(spec, env=env).bind(env)
    work = np.zeros(2)

    def record(d):
        work[:] += np.array(applied_power(u.model, d)) * dt

    u.each_physics_step(record)
    x0, info_energy = float(u.data.qpos[0]), 0.0
    for _ in range(int(round(seconds / u.dt))):
        obs, _, terminated, _, info = env.step(policy.predict(obs)[0])
        info_energy += info["power"] * u.dt
        if terminated:
            break
    dx = abs(float(u.data.qpos[0]) - x0)
    weight = u.task.weight
    env.close()
    return work[0] / (weight * dx), work[1] / (weight * dx), info_energy / (weight * dx)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=4.0)
    ap.add_argument("--out", default=str(RESULTS / "power_timestep.txt"))
    args = ap.parse_args(argv)
    if not (math.isfinite(args.seconds) and args.seconds > 0):
        ap.error(f"--seconds must be finite and > 0, got {args.seconds!r}")
    warnings.simplefilter("ignore")  # the law's validity-range notes
    lines = [f"$ python benchmarks/power_timestep.py --seconds {args.seconds:g}", ""] + check_rule() + [""]
    lines.append(f"cost of transport over {args.seconds:g} s from reset(seed=0), 10 ms control period, explicit "
                 "granular coupling; 'start': sum |f v| of each step's start state (info['power']), 'applied': "
                 "sum |(f + g (v' - v)) v'|; error against the 0.05 ms run")
    print("\n".join(lines), flush=True)
    for env_id, spec, kwargs in RUNS:
        rows = [(dt, *measure(env_id, spec, kwargs, dt, args.seconds)) for dt in STEPS]
        ref_start, ref_applied = rows[0][1], rows[0][2]
        block = [f"{env_id} {spec}{''.join(f' {k}={v}' for k, v in kwargs.items())}",
                 f"  {'dt ms':>6s} {'start':>8s} {'err':>7s} {'applied':>8s} {'err':>7s}"]
        for dt, start, applied, from_info in rows:
            assert abs(from_info - start) <= 1e-9 * max(1.0, abs(start)), (from_info, start)
            block.append(f"  {dt * 1e3:6.2f} {start:8.3f} {100 * (start / ref_start - 1):+6.1f}% {applied:8.3f} "
                         f"{100 * (applied / ref_applied - 1):+6.1f}%")
        print("\n".join(block), flush=True)
        lines += block
    Path(args.out).write_text("\n".join(lines) + "\n")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

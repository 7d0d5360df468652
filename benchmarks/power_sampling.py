"""The actuators' energy over a control step: integrated over every physics step against a sample at its end.

A gait or policy walks ``--seconds`` on ``mjrft/HexapodSand-v0`` (poppy seeds) from ``reset(seed=0)``; after every
physics step (``each_physics_step``) the actuators' power ``sum_a |actuator_force_a x actuator_velocity_a|`` is
recorded. Printed per gait: the energy the actuators delivered (the sum of every physics step's power times its
timestep), what ``info["power"]`` integrates to (``sum info["power"] x dt``: the mean over each env step), what
one sample per env step integrates to (the power of the env step's last physics step, and the product of its
force with the joint velocity at the step's end), and the mean power at each
physics step of the env step (index 1 is the first after the servo targets moved), with the cost of transport of
each.

    python benchmarks/power_sampling.py [--gait tripod:f=2.5] [--gait pretrained:HexapodSand-v0] [--seconds 3]
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

RESULTS = Path(__file__).resolve().parent / "results"


def measure(spec: str, seconds: float) -> dict:
    import gymnasium

    import mjrft.envs  # noqa: F401  (registers the ids)
    from mjrft.train.evaluate import load_policy

    env = gymnasium.make("mjrft/HexapodSand-v0")
    u = env.unwrapped
    obs, info = env.reset(seed=0)
    policy = load_policy(spec, env=env).bind(env)
    per_step = []
    u.each_physics_step(lambda d: per_step.append(float(np.sum(np.abs(d.actuator_force * d.actuator_velocity)))))
    steps = int(round(seconds / u.dt))
    x0 = float(u.data.qpos[0])
    mean_info, sample, before = [], [], []
    dofs = u.model.jnt_dofadr[u.model.actuator_trnid[:, 0]]
    for _ in range(steps):
        action = policy.predict(obs)[0]
        obs, _, terminated, _, info = env.step(action)
        mean_info.append(info["power"])
        sample.append(per_step[-1])
        before.append(float(np.sum(np.abs(u.data.actuator_force * u.data.qvel[dofs]))))
        if terminated:
            break
    dx = float(u.data.qpos[0]) - x0
    n = u.frame_skip
    per = np.array(per_step[: len(mean_info) * n]).reshape(-1, n)
    h, dt = u.model.opt.timestep, u.dt
    weight = u.task.weight
    env.close()
    energy = float(per.sum() * h)
    return {"spec": spec, "seconds": len(mean_info) * dt, "dx": dx, "energy": energy,
            "energy_info": float(np.sum(mean_info) * dt), "energy_sample": float(np.sum(sample) * dt),
            "energy_before": float(np.sum(before) * dt),
            "profile": per.mean(axis=0), "cot": energy / (weight * abs(dx)),
            "cot_sample": float(np.sum(sample) * dt) / (weight * abs(dx))}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--gait", action="append", default=None, help="a gait or policy spec (repeatable)")
    ap.add_argument("--seconds", type=float, default=3.0)
    ap.add_argument("--out", default=str(RESULTS / "power_sampling.txt"))
    args = ap.parse_args(argv)
    specs = args.gait or ["tripod:f=2.5", "pretrained:HexapodSand-v0"]
    warnings.simplefilter("ignore")  # the law's validity-range notes
    lines = [f"python benchmarks/power_sampling.py --seconds {args.seconds:g}" +
             "".join(f" --gait {s}" for s in specs),
             "mjrft/HexapodSand-v0 (poppy_cp, 0.5 ms x 20 physics steps per 10 ms env step), reset(seed=0); power "
             "sum |actuator_force x actuator_velocity| after every physics step", ""]
    for spec in specs:
        r = measure(spec, args.seconds)
        lines += [f"{spec}: {r['seconds']:.2f} s, x travel {r['dx']:.4f} m",
                  f"  energy over every physics step      {r['energy']:8.3f} J   CoT {r['cot']:.2f}",
                  f"  sum of info['power'] x dt           {r['energy_info']:8.3f} J",
                  f"  one sample per env step (its last)  {r['energy_sample']:8.3f} J   CoT {r['cot_sample']:.2f}",
                  f"  one sample per env step: its last physics step's force x the joint velocity at its end "
                  f"{r['energy_before']:.3f} J",
                  "  mean power (W) at physics step 1..{} of the env step: ".format(len(r["profile"]))
                  + " ".join(f"{p:.2f}" for p in r["profile"]), ""]
    text = "\n".join(lines)
    print(text)
    Path(args.out).write_text(text)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""How large a step the implicit granular coupling can take on gymnasium's robots: accuracy against small steps.

For each robot (``GranularWrapper(gymnasium.make(id))``, defaults otherwise) the same seeded random actions are
run for ``--seconds`` of simulated time from the same reset, through:

* ``reference``: the explicit coupling at a fixed internal step of at most ``--ref-dt`` (default 0.1 ms), far below
  every robot's stability limit: the converged motion;
* ``explicit auto``: the explicit coupling with the wrapper's stability rule (half the stable timestep);
* ``implicit omega dt <= s``: the implicit coupling (:mod:`mjrft.implicit_step`) with the wrapper's accuracy rule at
  ``s`` = each of ``--spring-steps``;
* ``implicit k=1``: the implicit coupling at the env's own timestep.

Reported per run: sub-steps per model step (mean; the cost: each is one MuJoCo step and one kernel call; the
speed of the defaults is ``benchmarks/bench_third_party.py``'s), and the errors against the reference
over the run: RMS of the mean vertical granular force over each env step divided by the weight (the sand is the
only external force besides gravity once the floor is removed, so it is the change of the robot's vertical
momentum over the step, ``M dv_z / dt + M g``: an impulse, free of the sampling noise of one sub-step's force),
the root body's position at the end (mm) and the mean of the deepest sinkage (mm). Random actions make the
motion chaotic over seconds, so the horizon is short (default 1 s) and the errors are those of the integration
rather than of chaos (the explicit rule's own errors are listed for comparison).

    python benchmarks/implicit_accuracy.py [--seconds S] [--robots Ant-v5 ...] [--spring-steps 0.5 1 2]
"""

from __future__ import annotations

import argparse
import math
import warnings

import gymnasium
import mujoco
import numpy as np

from mjrft.envs.wrapper import GranularWrapper

ROBOTS = ("Ant-v5", "HalfCheetah-v5", "Hopper-v5", "Walker2d-v5", "Humanoid-v5")


def rollout(gym_id: str, implicit: bool, substeps, seconds: float, spring_step: float | None = None) -> dict:
    """One seeded random-action run; per env step the net vertical granular force, the root position, the sinkage."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        env = GranularWrapper(gymnasium.make(gym_id), substeps=substeps, implicit=implicit,
                              **({} if spring_step is None else {"spring_step": spring_step}))
    u = env.unwrapped
    n = int(round(seconds / u.dt))
    rng = np.random.default_rng(0)
    acts = rng.uniform(env.action_space.low, env.action_space.high, size=(n, *env.action_space.shape))
    env.reset(seed=0)
    m, d = u.model, u.data
    mass = float(m.body_subtreemass[0])
    scratch = mujoco.MjData(m)
    fz, root, sink, ks = [], [], [], []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for a in acts:
            vz0 = vertical_velocity(m, d, scratch)
            _, _, _, _, info = env.step(a.astype(env.action_space.dtype))
            if "diverged" in info:
                return {"diverged": info["diverged"]}
            fz.append(mass * ((vertical_velocity(m, d, scratch) - vz0) / u.dt - float(m.opt.gravity[2])))
            root.append(u.data.xpos[1].copy())
            sink.append(float(info["sinkage"].max()))
            ks.append(int(info["substeps"]))
    weight = mass * -float(m.opt.gravity[2])
    env.close()
    return {"fz": np.array(fz) / weight, "root": np.array(root), "sink": np.array(sink), "k": float(np.mean(ks))}


def vertical_velocity(m: mujoco.MjModel, d: mujoco.MjData, scratch: mujoco.MjData) -> float:
    """Vertical velocity of the whole robot's centre of mass in ``d``'s state (``subtree_linvel`` of the world,
    computed in ``scratch`` from ``qpos``/``qvel``: ``d``'s own kinematics are those of its last ``mj_step1``)."""
    scratch.qpos[:], scratch.qvel[:] = d.qpos, d.qvel
    mujoco.mj_kinematics(m, scratch)
    mujoco.mj_comPos(m, scratch)
    mujoco.mj_comVel(m, scratch)
    mujoco.mj_subtreeVel(m, scratch)
    return float(scratch.subtree_linvel[0, 2])


def model_timestep(gym_id: str) -> float:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        env = gymnasium.make(gym_id)
    h = float(env.unwrapped.model.opt.timestep)
    env.close()
    return h


def errors(run: dict, ref: dict) -> dict:
    if "diverged" in run:
        return {"force_rms": math.nan, "root_mm": math.nan, "sink_mm": math.nan}
    return {"force_rms": float(np.sqrt(np.mean((run["fz"] - ref["fz"]) ** 2))),
            "root_mm": 1e3 * float(np.linalg.norm(run["root"][-1] - ref["root"][-1])),
            "sink_mm": 1e3 * float(run["sink"].mean() - ref["sink"].mean())}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seconds", type=float, default=1.0, help="simulated seconds per run (default 1)")
    ap.add_argument("--ref-dt", type=float, default=1e-4, help="largest internal step of the reference (s)")
    ap.add_argument("--spring-steps", type=float, nargs="+", default=[0.5, 1.0, 2.0],
                    help="omega dt of the implicit accuracy rule to measure (default 0.5 1 2)")
    ap.add_argument("--robots", nargs="+", default=list(ROBOTS), help="gymnasium ids")
    args = ap.parse_args(argv)
    for s in args.spring_steps:
        if not s > 0:
            ap.error(f"--spring-steps must be > 0, got {s}")
    print(f"implicit vs explicit granular coupling on gymnasium's robots: {args.seconds:g} s of seeded random actions; "
          f"errors against the explicit coupling at <= {1e3 * args.ref_dt:g} ms")
    print()
    print(f"{'robot':<15} {'run':<24} {'k mean':>7} {'Fz err rms/weight':>17} "
          f"{'root err mm':>11} {'sinkage err mm':>14}")
    for gym_id in args.robots:
        k_ref = max(1, math.ceil(model_timestep(gym_id) / args.ref_dt - 1e-9))
        ref = rollout(gym_id, False, k_ref, args.seconds)
        runs = [("reference", ref), ("explicit auto", rollout(gym_id, False, "auto", args.seconds))]
        runs += [(f"implicit omega dt <= {s:g}", rollout(gym_id, True, "auto", args.seconds, s))
                 for s in args.spring_steps]
        runs.append(("implicit k=1", rollout(gym_id, True, 1, args.seconds)))
        for name, r in runs:
            if "diverged" in r:
                print(f"{gym_id:<15} {name:<24} DIVERGED: {r['diverged']}")
                continue
            e = errors(r, ref)
            print(f"{gym_id:<15} {name:<24} {r['k']:>7.2f} {e['force_rms']:>17.4f} "
                  f"{e['root_mm']:>11.2f} {e['sink_mm']:>+14.2f}")
        print(flush=True)


if __name__ == "__main__":
    main()

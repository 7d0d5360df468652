"""Accuracy and cost of ``resolution="auto"``'s element budget on gymnasium's five MuJoCo robots.

For each robot (``GranularWrapper(gymnasium.make(id))`` defaults, only the resolution changed) and each
element budget ``N`` (``mjrft.selection.auto_resolution(model, geoms, target=N)``), against a reference
at ``--reference`` elements (not coarser than 2 mm):

* replay: the reference run's random-action rollout (``--seconds``, seeded) is recorded at every physics
  step (state after ``mj_step1``, the step's timestep) and replayed through a terrain of ``N`` elements
  (``GranularTerrain.compute`` on the same states, memory advanced by the same steps): the relative RMS
  error of the net granular force (sum over bodies, world frame) ``|F_N - F_ref|_rms / |F_ref|_rms`` and of
  its vertical component, on the same trajectory (no chaotic divergence of two closed-loop runs);
* rest: zero action for ``--rest`` s from the env's reset state, then the vertical granular force / weight
  and the height of the whole model's centre of mass, compared with the reference's (mm);
* cost: env steps per second of the ``N``-element env over 400 other random actions (median of repeats;
  this process's CPU time, so the other processes of a shared machine do not count).

``--scales`` adds rows at ``resolution="auto"``'s own size (the 3,000-element budget) times each factor, as
``GranularWrapper(env, resolution_scale=s)`` builds them (budget column ``xS``).

    python benchmarks/element_budget.py [--budgets 250 500 ...] [--scales 1.5 2 ...] [--reference 32000]
                                        [--robots Ant-v5 ...]
"""

from __future__ import annotations

import argparse
import time
import warnings

import gymnasium
import mujoco
import numpy as np

from mjrft.selection import AUTO_ELEMENTS, auto_resolution, select_geoms
from mjrft.envs.wrapper import GranularWrapper
from mjrft.errors import check_positive

ROBOTS = ("Ant-v5", "HalfCheetah-v5", "Hopper-v5", "Walker2d-v5", "Humanoid-v5")
BUDGETS = (250, 500, 1000, 2000, 3000, 4000, 8000)
FINEST = 0.002  # m: no budget goes finer than this (the reference of the smallest robot)


def resolution(gym_id: str, budget: int, scale: float = 1.0) -> float:
    """The element size of a budget (``auto_resolution``, not finer than FINEST) times ``scale``."""
    env = gymnasium.make(gym_id)
    m = env.unwrapped.model
    res = auto_resolution(m, select_geoms(m, None, None), target=budget, finest=FINEST)
    env.close()
    return scale * res


def make(gym_id: str, res: float) -> GranularWrapper:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return GranularWrapper(gymnasium.make(gym_id), resolution=res)


def actions(env, n: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.uniform(env.action_space.low, env.action_space.high,
                       size=(n, *env.action_space.shape)).astype(env.action_space.dtype)


def record(env: GranularWrapper, acts) -> list:
    """Run ``acts`` (reset on termination), recording (qpos, qvel, act, time, timestep) before every physics step."""
    t = env.terrain
    states = []
    step = t.step

    def recording_step(data, nstep=1):
        m = t.model
        for _ in range(int(nstep)):
            states.append((data.qpos.copy(), data.qvel.copy(), data.act.copy(), data.time, m.opt.timestep))
            step(data, 1)

    t.step = recording_step
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        env.reset(seed=0)
        for a in acts:
            _, _, terminated, truncated, _ = env.step(a)
            if terminated or truncated:
                states.append(None)  # a reset: the terrain's memory starts again
                env.reset()
    del t.step
    return states


def replay(env: GranularWrapper, states) -> np.ndarray:
    """Net granular force (n, 3) of ``env``'s terrain along the recorded states (``None``: a reset)."""
    t, m = env.terrain, env.unwrapped.model
    d = mujoco.MjData(m)
    out = []
    h = m.opt.timestep
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for s in states:
            if s is None:
                t.reset()
                continue
            d.qpos[:], d.qvel[:], d.act[:], d.time = s[0], s[1], s[2], s[3]
            m.opt.timestep = s[4]
            mujoco.mj_step1(m, d)
            w = t.compute(d, s[4])
            out.append(w[t.body_ids, :3].sum(axis=0))
    m.opt.timestep = h
    return np.array(out)


def rest(env: GranularWrapper, seconds: float) -> tuple[float, float]:
    """(vertical granular force / weight, CoM height m) after ``seconds`` of zero action."""
    u = env.unwrapped
    zero = np.zeros(env.action_space.shape, dtype=env.action_space.dtype)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        env.reset(seed=0)
        for _ in range(int(round(seconds / u.dt))):
            env.step(zero)
    m, d = u.model, u.data
    weight = float(m.body_subtreemass[0]) * -float(m.opt.gravity[2])
    return float(env.terrain.wrench[env.body_ids, 2].sum()) / weight, float(d.subtree_com[0, 2])


def speed(env: GranularWrapper, acts, repeats: int) -> float:
    times = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for _ in range(repeats):
            env.reset(seed=0)
            spent = 0.0
            for a in acts:
                t0 = time.process_time()
                _, _, terminated, truncated, _ = env.step(a)
                spent += time.process_time() - t0
                if terminated or truncated:
                    env.reset()
            times.append(spent)
    return len(acts) / float(np.median(times))


def run(robots, budgets, reference: int, seconds: float, rest_s: float, steps: int, repeats: int,
        scales=()) -> list[dict]:
    rows = []
    for gym_id in robots:
        ref = make(gym_id, resolution(gym_id, reference))
        acts = actions(ref, max(1, int(round(seconds / ref.unwrapped.dt))))
        states = record(ref, acts)
        f_ref = replay(ref, states)
        ref_rest = rest(ref, rest_s)
        rms_ref = float(np.sqrt(np.mean(np.sum(f_ref**2, axis=1))))
        rms_ref_z = float(np.sqrt(np.mean(f_ref[:, 2] ** 2)))
        rows.append({"robot": gym_id, "budget": reference, "elements": ref.terrain.n_elements,
                     "res": ref.terrain.resolution, "err": 0.0, "err_z": 0.0, "balance": ref_rest[0],
                     "dz": 0.0, "rate": float("nan"), "reference": True, "rms": rms_ref})
        ref.close()
        speed_acts = actions(ref, steps, seed=1)
        cases = [(str(n), resolution(gym_id, n)) for n in budgets]
        cases += [(f"x{s:g}", resolution(gym_id, AUTO_ELEMENTS, s)) for s in scales]
        for label, res in cases:
            env = make(gym_id, res)
            f = replay(env, states)
            err = float(np.sqrt(np.mean(np.sum((f - f_ref) ** 2, axis=1)))) / rms_ref
            err_z = float(np.sqrt(np.mean((f[:, 2] - f_ref[:, 2]) ** 2))) / rms_ref_z
            bal, z = rest(env, rest_s)
            speed(env, speed_acts[:20], 1)  # warm up
            rows.append({"robot": gym_id, "budget": label, "elements": env.terrain.n_elements,
                         "res": env.terrain.resolution, "err": err, "err_z": err_z, "balance": bal,
                         "dz": z - ref_rest[1], "rate": speed(env, speed_acts, repeats), "reference": False,
                         "rms": rms_ref})
            env.close()
    return rows


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--robots", nargs="+", default=list(ROBOTS))
    ap.add_argument("--budgets", nargs="+", type=int, default=list(BUDGETS))
    ap.add_argument("--scales", nargs="*", type=float, default=[],
                    help="rows at the 3,000-element budget's size times these factors (GranularWrapper's "
                         "resolution_scale)")
    ap.add_argument("--reference", type=int, default=32000, help="element budget of the reference (default 32000)")
    ap.add_argument("--seconds", type=float, default=2.0, help="simulated seconds of the replayed rollout")
    ap.add_argument("--rest", type=float, default=3.0, help="seconds of zero action before the rest numbers")
    ap.add_argument("--steps", type=int, default=400, help="timed env steps per budget")
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args(argv)
    try:
        for s in args.scales:
            check_positive("--scales", s)
    except ValueError as exc:
        ap.error(str(exc))
    rows = run(args.robots, args.budgets, args.reference, args.seconds, args.rest, args.steps, args.repeats,
               args.scales)
    print(f"element budget of resolution='auto' (GranularWrapper defaults otherwise): {args.seconds:g} s random-action "
          f"rollout replayed; rest after {args.rest:g} s of zero action; reference budget {args.reference}")
    print()
    print(f"{'robot':<15} {'budget':>7} {'elements':>8} {'size mm':>7} {'|F| rms N':>9} {'F err %':>7} {'Fz err %':>8} "
          f"{'rest Fz/W':>9} {'rest CoM dz mm':>14} {'env st/s':>8}")
    for r in rows:
        tag = " (reference)" if r["reference"] else ""
        print(f"{r['robot']:<15} {r['budget']:>7} {r['elements']:>8d} {1e3 * r['res']:>7.1f} {r['rms']:>9.1f} "
              f"{100 * r['err']:>7.2f} {100 * r['err_z']:>8.2f} {r['balance']:>9.4f} {1e3 * r['dz']:>14.2f} "
              f"{r['rate']:>8.0f}{tag}")


if __name__ == "__main__":
    main()

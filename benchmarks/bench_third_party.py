"""Gymnasium's five MuJoCo robots on sand (``mjrft.envs.GranularWrapper``), side by side in one run.

For each robot (``Ant-v5``, ``HalfCheetah-v5``, ``Hopper-v5``, ``Walker2d-v5``, ``Humanoid-v5``) four
environments are driven by the same seeded random action sequence and timed (only ``env.step``, in this
process's CPU time, so the other processes of a shared machine do not count; resets after a termination are
not timed; median of repeats, the four environments interleaved):

* ``sand``: ``GranularWrapper(gymnasium.make(id))`` with its defaults (``floor="auto"``,
  ``resolution="auto"``, the implicit granular step, automatic sub-steps; RK4 run as semi-implicit Euler, see
  :mod:`mjrft.envs.wrapper`);
* ``explicit``: the same with ``implicit=False`` (the explicit step and its stability rule);
* ``rigid, same dt``: the same gymnasium env on its rigid floor with the same integrator and the SAME
  internal timestep in every env step (the sand run's sub-step counts replayed step by step): what the
  sand itself costs;
* ``stock``: the unchanged gymnasium env (its own integrator and timestep): what a user's env costs today.

Then, per robot, the sand's weight balance at rest: zero actions for ``--rest`` seconds (the robots without
a standing controller fall and lie on the sand), then the vertical granular force summed over the bodies
divided by the weight (target within 2 %), the largest body speed left, and the deepest sinkage.
Also listed: element count and size, sub-steps per model step (min / mean / max of the timed run; the
explicit step's mean), the stability warnings the terrain gave during the run, and per physics step the CPU
time of the rigid env (MuJoCo's step and the env's own work, per physics step) and what the sand adds to it
(``(sand - rigid) / physics steps``: the granular kernel and its bookkeeping), from the fastest repeat of each
env (a shared machine's other processes only add time, and meet runs of tens of milliseconds unevenly, so the
fastest repeats are the less disturbed estimate); ``sand / rigid >= 0.7`` needs the second to be at most 0.43x
the first.

Then the vendored robots of ``models/third_party`` (``--vendored``), each with its own controller at its own
timestep: the same controlled run (settle, then its motion pattern) on sand and on the unchanged model's rigid
floor, interleaved, CPU time of the physics steps (controller included in both); the element count and size,
the net vertical granular force / weight at rest (mean and largest deviation over the last 0.5 s of the settle)
and the sinkage. ``--robots`` with no id skips the gymnasium robots.

    python benchmarks/bench_third_party.py [--steps N] [--repeats R] [--rest SECONDS] [--robots Ant-v5 ...]
                                          [--vendored unitree_h1 anymal_c dm_quadruped ...]
"""

from __future__ import annotations

import argparse
import time
import warnings

import gymnasium
import mujoco
import numpy as np

import mjrft
from mjrft.envs.wrapper import GranularWrapper
from mjrft.errors import check_positive

ROBOTS = ("Ant-v5", "HalfCheetah-v5", "Hopper-v5", "Walker2d-v5", "Humanoid-v5")


def actions(env, n: int, seed: int = 0) -> np.ndarray:
    """``n`` uniform random actions in the env's action space (seeded)."""
    rng = np.random.default_rng(seed)
    low, high = env.action_space.low, env.action_space.high
    return rng.uniform(low, high, size=(n, *env.action_space.shape)).astype(env.action_space.dtype)


def timed(env, acts) -> tuple[float, list]:
    """(CPU seconds in ``env.step`` over ``acts``, the infos)."""
    env.reset(seed=0)
    spent, infos = 0.0, []
    for a in acts:
        t0 = time.process_time()
        _, _, terminated, truncated, info = env.step(a)
        spent += time.process_time() - t0
        infos.append(info)
        if terminated or truncated:
            env.reset()
    return spent, infos


def make_sand(gym_id: str, stability: list, **options) -> GranularWrapper:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        env = GranularWrapper(gymnasium.make(gym_id), **options)
    stability.extend(w for w in caught if issubclass(w.category, mjrft.TerrainStabilityWarning))
    return env


def make_rigid_replay(gym_id: str, substeps: list[int]):
    """The stock env on its rigid floor, Euler, stepping at ``h / k`` with ``k`` replayed from ``substeps``."""
    env = gymnasium.make(gym_id)
    u = env.unwrapped
    m, d = u.model, u.data
    if m.opt.integrator == mujoco.mjtIntegrator.mjINT_RK4:
        m.opt.integrator = mujoco.mjtIntegrator.mjINT_EULER
    h = float(m.opt.timestep)
    it = iter([])

    def physics(ctrl, n_frames):
        nonlocal it
        try:
            k = next(it)
        except StopIteration:
            it = iter(substeps)
            k = next(it)
        d.ctrl[:] = ctrl
        m.opt.timestep = h / k
        mujoco.mj_step(m, d, nstep=int(n_frames) * k)
        m.opt.timestep = h
        mujoco.mj_rnePostConstraint(m, d)

    u._step_mujoco_simulation = physics

    def restart():
        nonlocal it
        it = iter(substeps)

    return env, restart


def rest_balance(gym_id: str, seconds: float, resolution_scale: float = 1.0) -> dict:
    """Zero actions for ``seconds``; the vertical granular force / weight, the fastest body, the deepest sinkage."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        env = GranularWrapper(gymnasium.make(gym_id), resolution_scale=resolution_scale)
    u = env.unwrapped
    env.reset(seed=0)
    zero = np.zeros(env.action_space.shape, dtype=env.action_space.dtype)
    for _ in range(int(round(seconds / u.dt))):
        _, _, terminated, _, info = env.step(zero)
        if "diverged" in info:
            return {"balance": float("nan"), "speed": float("nan"), "sinkage": float("nan"), "note": info["diverged"]}
    m, d = u.model, u.data
    weight = float(m.body_subtreemass[0]) * -float(m.opt.gravity[2])
    fz = float(env.terrain.wrench[env.body_ids, 2].sum())
    speed = float(np.max(np.linalg.norm(d.cvel[1:, 3:], axis=1)))
    out = {"balance": fz / weight, "cfrc_balance": float(d.cfrc_ext[1:, 5].sum()) / weight, "speed": speed,
           "sinkage": float(env.sinkage().max()), "weight": weight, "healthy_end": not terminated}
    env.close()
    return out


def run(robots=ROBOTS, steps: int = 400, repeats: int = 3, rest: float = 3.0,
        resolution_scale: float = 1.0) -> list[dict]:
    rows = []
    for gym_id in robots:
        stability: list = []
        sand = make_sand(gym_id, stability, resolution_scale=resolution_scale)
        acts = actions(sand, steps)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            timed(sand, acts[:20])  # compile / warm up
            _, infos = timed(sand, acts)  # the sub-step counts the rigid env replays (a seeded run repeats them)
            ks = [int(i["substeps"]) for i in infos]
            diverged = sum("diverged" in i for i in infos)
            rigid, restart = make_rigid_replay(gym_id, ks)
            stock = gymnasium.make(gym_id)
            timed(stock, acts[:20])
            explicit = make_sand(gym_id, [], implicit=False, resolution_scale=resolution_scale)
            timed(explicit, acts[:20])
            sand_t, rigid_t, stock_t, explicit_t = [], [], [], []
            for _ in range(repeats):
                sand_t.append(timed(sand, acts)[0])
                restart()
                rigid_t.append(timed(rigid, acts)[0])
                stock_t.append(timed(stock, acts)[0])
                spent, explicit_infos = timed(explicit, acts)
                explicit_t.append(spent)
        stability.extend(w for w in caught if issubclass(w.category, mjrft.TerrainStabilityWarning))
        u = sand.unwrapped
        h = float(u.model.opt.timestep)
        sink = np.array([i["sinkage"].max() for i in infos])
        physics_steps = steps * u.frame_skip * float(np.mean(ks))
        row = {
            "robot": gym_id, "elements": sand.terrain.n_elements, "resolution": sand.terrain.resolution,
            "h": h, "frame_skip": u.frame_skip, "k_min": min(ks), "k_mean": float(np.mean(ks)), "k_max": max(ks),
            "sand": steps / float(np.median(sand_t)), "rigid": steps / float(np.median(rigid_t)),
            "stock": steps / float(np.median(stock_t)), "stability_warnings": len(stability), "diverged": diverged,
            "explicit": steps / float(np.median(explicit_t)),
            "k_explicit": float(np.mean([int(i["substeps"]) for i in explicit_infos])),
            # the split per physics step from the fastest repeat of each env: other processes of a shared machine
            # only ever add time, and its runs of tens of milliseconds meet them unevenly
            "rigid_us": 1e6 * min(rigid_t) / physics_steps,
            "sand_us": 1e6 * (min(sand_t) - min(rigid_t)) / physics_steps,
            "run_sinkage_mean": float(sink.mean()), "run_sinkage_max": float(sink.max()),
            **rest_balance(gym_id, rest, resolution_scale),
        }
        rows.append(row)
        for e in (sand, rigid, stock, explicit):
            e.close()
    return rows


def h1_setup(sand: bool, settle: float = 1.0):
    """Unitree H1 (mesh feet): model, data leaning over its soles, a step function running its controller (the
    open-loop sway, after ``settle`` s holding the pose), the terrain (poppy_cp, the feet, implicit) or None."""
    from mjrft.models import unitree_h1 as h1

    m, d = h1.load()
    ctl = h1.Controller(m)
    ctl.reset(d)
    terrain = mjrft.GranularTerrain(m, "poppy_cp", floor="auto", bodies=list(h1.FEET), implicit=True) if sand else None

    def step():
        t = d.time - settle
        ctl(d, ctl.step_targets(t, sway=0.05, lift=0.1, freq=0.5) if t > 0 else None)
        if terrain is None:
            mujoco.mj_step(m, d)
        else:
            terrain.step(d)

    return m, d, step, terrain


def quadruped_setup(name: str):
    """The setup of a quadruped of :mod:`mjrft.models.quadrupeds` (ANYmal C, dm_control's quadruped): its model's
    initial state, ``ctrl = 0`` for ``settle`` s, then its open-loop trot; the terrain (poppy_cp, every body,
    implicit) or None. Its "least foot" is the least share over every body (the trunk's is 0)."""
    def setup(sand: bool, settle: float = 1.0):
        from mjrft.models import quadrupeds as q

        m = q.MODELS[name]()
        d = mujoco.MjData(m)
        terrain = mjrft.GranularTerrain(m, "poppy_cp", floor="auto", implicit=True) if sand else None

        def step():
            t = d.time - settle
            d.ctrl[:] = q.trot_ctrl(name, m, t) if t > 0 else 0.0
            if terrain is None:
                mujoco.mj_step(m, d)
            else:
                terrain.step(d)

        return m, d, step, terrain

    return setup


VENDORED = {"unitree_h1": h1_setup, "anymal_c": quadruped_setup("anymal_c"),
            "dm_quadruped": quadruped_setup("dm_quadruped")}


def vendored_row(name: str, seconds: float = 3.0, repeats: int = 3) -> dict:
    """Sand against the rigid twin for a vendored robot (see the module docstring)."""
    setup = VENDORED[name]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sand_t, rigid_t = [], []
        for _ in range(repeats + 1):  # the first pair warms up (compiles)
            for sand, out in ((True, sand_t), (False, rigid_t)):
                m, d, step, terrain = setup(sand)
                n = int(round(seconds / m.opt.timestep))
                t0 = time.process_time()
                for _ in range(n):
                    step()
                out.append(time.process_time() - t0)
        m, d, step, terrain = setup(True, settle=2.0)  # at rest for 2 s, then its motion pattern for 3 s
        weight = float(m.body_subtreemass[1]) * -float(m.opt.gravity[2])
        loads, shares = [], []
        for i in range(int(round(5.0 / m.opt.timestep))):
            step()
            loads.append(float(terrain.wrench[:, 2].sum()) / weight)
            shares.append(terrain.wrench[terrain.body_ids, 2] / weight)
            if d.time <= 2.0 + 1e-9:
                sinkage = float(terrain.sinkage()[terrain.body_ids].max())
    h = float(m.opt.timestep)
    rest = np.array(loads[int(round(1.5 / h)):int(round(2.0 / h))])
    moving = np.array(loads[int(round(2.0 / h)):])
    return {"robot": name, "elements": terrain.n_elements, "resolution": terrain.resolution, "h": h,
            "sand": n / float(np.median(sand_t[1:])), "rigid": n / float(np.median(rigid_t[1:])),
            "balance": float(rest.mean()), "balance_dev": float(np.abs(rest - 1.0).max()), "sinkage": sinkage,
            "moving": float(moving.mean()), "share_min": float(np.array(shares)[int(round(2.0 / h)):].min()),
            "sinkage_end": float(terrain.sinkage()[terrain.body_ids].max()), "seconds": seconds}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--steps", type=int, default=400, help="timed env steps per robot and run (default 400)")
    ap.add_argument("--repeats", type=int, default=3, help="interleaved repeats, median reported (default 3)")
    ap.add_argument("--rest", type=float, default=3.0, help="seconds of zero action before the weight balance")
    ap.add_argument("--robots", nargs="*", default=list(ROBOTS), help="gymnasium ids (none: skip them)")
    ap.add_argument("--vendored", nargs="*", default=list(VENDORED), choices=list(VENDORED),
                    help="vendored robots of models/third_party (none: skip them)")
    ap.add_argument("--resolution-scale", type=float, default=1.0,
                    help="the gymnasium robots' element size x this (GranularWrapper's resolution_scale; default 1: "
                         "resolution='auto', about 3,000 elements; 2: about a quarter of them)")
    args = ap.parse_args(argv)
    try:
        check_positive("--resolution-scale", args.resolution_scale)
    except ValueError as exc:
        ap.error(str(exc))
    rows = run(args.robots, args.steps, args.repeats, args.rest, args.resolution_scale)
    if rows:
        scale = "" if args.resolution_scale == 1.0 else f", resolution_scale {args.resolution_scale:g}"
        print(f"gymnasium MuJoCo robots on sand (GranularWrapper defaults: medium {mjrft.settings.DEFAULTS['medium']}, "
              f"law {mjrft.settings.DEFAULTS['law']}{scale}); {args.steps} random-action env steps, median of "
              f"{args.repeats} (CPU time of env.step, the four envs interleaved)")
        print()
        print(f"{'robot':<15} {'elements':>8} {'size mm':>7} {'h ms':>5} {'k min/mean/max':>15} {'sand st/s':>9} "
              f"{'rigid same dt':>13} {'stock':>7} {'sand/rigid':>10} {'sand/stock':>10} {'stab.warn':>9} "
              f"{'diverged':>8}")
        for r in rows:
            print(f"{r['robot']:<15} {r['elements']:>8d} {1e3 * r['resolution']:>7.1f} {1e3 * r['h']:>5.3g} "
                  f"{r['k_min']:>4d}/{r['k_mean']:>5.2f}/{r['k_max']:<4d} {r['sand']:>9.0f} {r['rigid']:>13.0f} "
                  f"{r['stock']:>7.0f} {r['sand'] / r['rigid']:>10.2f} {r['sand'] / r['stock']:>10.2f} "
                  f"{r['stability_warnings']:>9d} {r['diverged']:>8d}")
        print()
        print("the implicit step against the explicit one (medians), and the cost per physics step (us of CPU time, "
              "fastest repeat)")
        print(f"{'robot':<15} {'explicit k mean':>15} {'explicit st/s':>13} {'sand/explicit':>13} {'rigid us':>8} "
              f"{'sand adds us':>12} {'adds/rigid':>10}")
        for r in rows:
            print(f"{r['robot']:<15} {r['k_explicit']:>15.2f} {r['explicit']:>13.0f} "
                  f"{r['sand'] / r['explicit']:>13.2f} "
                  f"{r['rigid_us']:>8.1f} {r['sand_us']:>12.1f} {r['sand_us'] / r['rigid_us']:>10.2f}")
        print()
        print(f"at rest after {args.rest:g} s of zero action (target: vertical granular force / weight within 2 %)")
        print(f"{'robot':<15} {'weight N':>9} {'Fz/weight':>9} {'cfrc_ext z/weight':>17} {'fastest body m/s':>16} "
              f"{'sinkage mm':>10} {'run sinkage mean/max mm':>23}")
        for r in rows:
            print(f"{r['robot']:<15} {r['weight']:>9.2f} {r['balance']:>9.4f} {r['cfrc_balance']:>17.4f} "
                  f"{r['speed']:>16.2g} {1e3 * r['sinkage']:>10.1f} "
                  f"{1e3 * r['run_sinkage_mean']:>11.1f}/{1e3 * r['run_sinkage_max']:<11.1f}")
    vendored = [vendored_row(name, repeats=args.repeats) for name in args.vendored]
    if vendored:
        print()
        print(f"vendored robots (models/third_party) with their controllers, {vendored[0]['seconds']:g} s timed: 1 s "
              f"holding the pose, then their motion pattern; median of {args.repeats} (CPU time of the physics steps, "
              "sand and rigid interleaved); then 2 s at rest (Fz/weight over its last 0.5 s) and 3 s of the pattern "
              "(Fz/weight mean, the least share of the weight on one foot, the sinkage at the end)")
        print(f"{'robot':<15} {'elements':>8} {'size mm':>7} {'h ms':>5} {'sand st/s':>9} {'rigid st/s':>10} "
              f"{'sand/rigid':>10} {'Fz/weight':>9} {'max dev':>8} {'sinkage mm':>10} {'moving Fz/W':>11} "
              f"{'least foot':>10} {'sinkage end':>11}")
        for r in vendored:
            print(f"{r['robot']:<15} {r['elements']:>8d} {1e3 * r['resolution']:>7.1f} {1e3 * r['h']:>5.3g} "
                  f"{r['sand']:>9.0f} {r['rigid']:>10.0f} {r['sand'] / r['rigid']:>10.3f} {r['balance']:>9.5f} "
                  f"{r['balance_dev']:>8.1e} {1e3 * r['sinkage']:>10.1f} {r['moving']:>11.4f} {r['share_min']:>10.3f} "
                  f"{1e3 * r['sinkage_end']:>11.1f}")


if __name__ == "__main__":
    main()

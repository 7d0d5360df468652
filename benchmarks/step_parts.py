"""Where a sand env's physics step spends its time: gymnasium robots under ``GranularWrapper`` (defaults: the implicit
step, automatic sub-steps), per physics step and per env step, on states of a seeded random-action run.

For each robot the wrapper env runs ``--steps`` env steps of seeded random actions; every 10th state is kept. On each
kept state, each part is timed on its own, repeatedly, and its fastest call counts (a call lasts microseconds, far
shorter than a scheduler slice, so on a loaded machine most calls run undisturbed; the parts are interleaved):

* ``mj_step``: MuJoCo's own step of the sand model (its floor's contacts removed) at the run's internal timestep;
* ``kernel``: ``mjrft.kernel.terrain_kernel`` alone (after ``mj_step1``), called from compiled code; split, on the same
  state, into ``cull`` (the kernel with the surface and its top lowered 5 m: every cull group is skipped, what is
  left is the per-group test and the per-body sums), ``+pass 1`` (the surface lowered 5 m, its top kept: the groups
  within reach compute their elements' positions and depths and find none buried) and the buried elements' work
  (``kernel`` less that: their velocity, rest memory, law, force and stiffness sums), given per buried element
  (``ns/buried``);
* ``implicit``: ``mjrft.implicit_step.implicit_wrench`` alone (0 when no body holds a spring below yield);
* ``terrain.step``: ``GranularTerrain.step(data, frame_skip x k)``, what the wrapper calls per env step, per physics
  step: MuJoCo's step, the kernel, the implicit solve, the stability bookkeeping and the Python call;
* per env step, the wrapper's own work after the physics: the next sub-step count's stable timesteps
  (``min_stable_timesteps``), the info arrays (``_sand_info``) and the sand's wrench in ``cfrc_ext``.

``rest`` is ``terrain.step`` less the three parts: MuJoCo's step split in ``mj_step1`` / ``mj_step2``, the stability
bookkeeping, the kernel reading the fresh state after ``mj_step1`` (the timed kernel runs on data it has just read),
and the Python call with its grouped arguments, once per env step and shared by its physics steps.

    python benchmarks/step_parts.py [--robots Hopper-v5 ...] [--steps N] [--reps R]
"""

from __future__ import annotations

import argparse
import time
import warnings

import gymnasium
import mujoco
import numpy as np
from numba import njit

from mjrft.envs.wrapper import GranularWrapper
from mjrft.implicit_step import implicit_wrench
from mjrft.kernel import terrain_kernel

ROBOTS = ("Hopper-v5", "Walker2d-v5", "HalfCheetah-v5")


@njit(cache=True)
def _kernel_loop(n, tables, mjd, gravity, dt, st):
    for _ in range(n):
        terrain_kernel(tables, mjd, gravity, dt, st)


@njit(cache=True)
def _implicit_loop(n, f, m_addr, d_addr, qacc, rows, wrench, imp, inert, use_inert, dt, jac, minv, blocks, a, rhs, r):
    saved = wrench.copy()
    for _ in range(n):
        wrench[:, :] = saved
        implicit_wrench(f[0], f[1], f[2], f[3], m_addr, d_addr, qacc, rows, wrench, imp, inert, use_inert, dt, jac,
                        minv, blocks, a, rhs, r)
    wrench[:, :] = saved


def fastest(fn, reps: int) -> float:
    best = np.inf
    for _ in range(reps):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def robot_parts(gym_id: str, steps: int, reps: int) -> dict:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        env = GranularWrapper(gymnasium.make(gym_id))
        u = env.unwrapped
        m, d, t = u.model, u.data, env.terrain
        h, fs = float(m.opt.timestep), int(u.frame_skip)
        rng = np.random.default_rng(0)
        acts = rng.uniform(env.action_space.low, env.action_space.high, size=(steps, *env.action_space.shape))
        env.reset(seed=0)
        parts = {k: [] for k in ("mj_step", "kernel", "cull", "pass1", "implicit", "terrain.step", "limits", "info",
                                 "cfrc")}
        buried, ks = [], []
        for i, a in enumerate(acts):
            _, _, terminated, truncated, info = env.step(a)
            if terminated or truncated:
                env.reset()
                continue
            if i % 10:
                continue
            k = int(info["substeps"])
            ks.append(k)
            st = t.terrain_state
            state = (d.qpos.copy(), d.qvel.copy(), d.act.copy(), d.time, st.u.copy(), st.group_active.copy(),
                     t._last_time)

            def restore():
                # the terrain's clock too: a call at a time before its last one would forget the memory (a reset)
                d.qpos[:], d.qvel[:], d.act[:], d.time = state[:4]
                st.u[:], st.group_active[:], t._last_time = state[4:]

            m.opt.timestep = h / k
            try:
                restore()
                mujoco.mj_step1(m, d)
                f_implicit, tables, mjd, views, gravity, dt, _ = t.step_arguments(d, m.opt.timestep)
                kargs = (tables, mjd, gravity, dt, st)
                _kernel_loop(1, *kargs)
                buried.append(int(np.count_nonzero(t.depth > 0)))
                # the same call with the surface 5 m lower, its top kept (pass 1 only) or lowered too (culling only);
                # the elements' state is the terrain's own, restored below
                sf = tables.surface
                no_buried = (tables._replace(surface=sf._replace(height=sf.height - 5.0)), *kargs[1:])
                culled = (tables._replace(surface=sf._replace(height=sf.height - 5.0, top=sf.top - 5.0)), *kargs[1:])
                iargs = (f_implicit, m._address, d._address, d.qacc_smooth, t.body_ids, st.wrench, st.imp, st.inert,
                         t.inertial, m.opt.timestep, st.imp_jac, st.imp_minv_jac, st.imp_blocks, st.imp_a, st.imp_rhs,
                         st.imp_rows)
                _implicit_loop(1, *iargs)

                def physics():
                    restore()
                    mujoco.mj_step(m, d, fs * k)

                def env_physics():
                    restore()
                    t.step(d, fs * k)

                for _ in range(3):  # interleaved rounds
                    restore()
                    parts["kernel"].append(fastest(lambda: _kernel_loop(5, *kargs), reps) / 5)
                    parts["pass1"].append(fastest(lambda: _kernel_loop(5, *no_buried), reps) / 5)
                    parts["cull"].append(fastest(lambda: _kernel_loop(5, *culled), reps) / 5)
                    restore()
                    parts["implicit"].append(fastest(lambda: _implicit_loop(5, *iargs), reps) / 5)
                    parts["mj_step"].append(fastest(physics, reps) / (fs * k))
                    parts["terrain.step"].append(fastest(env_physics, reps) / (fs * k))
                restore()
                t.step(d, fs * k)
                parts["limits"].append(fastest(lambda: t.min_stable_timesteps(d), reps))
                parts["info"].append(fastest(lambda: env._sand_info({}), reps))
                parts["cfrc"].append(fastest(lambda: env._add_cfrc_ext(d), reps))
            finally:
                m.opt.timestep = h
                restore()
                mujoco.mj_forward(m, d)
        out = {k: 1e6 * float(np.mean(v)) for k, v in parts.items()}
        out.update(robot=gym_id, elements=t.n_elements, buried=float(np.mean(buried)), k=float(np.mean(ks)),
                   frame_skip=fs, states=len(ks))
        env.close()
    return out


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robots", nargs="+", default=list(ROBOTS), help="gymnasium ids")
    ap.add_argument("--steps", type=int, default=150, help="env steps of the seeded run (every 10th state kept)")
    ap.add_argument("--reps", type=int, default=10, help="calls per part and state; the fastest counts")
    args = ap.parse_args(argv)
    rows = [robot_parts(r, args.steps, args.reps) for r in args.robots]
    print("per physics step (us; fastest of repeated calls, mean over the kept states)")
    print(f"{'robot':<15} {'elements':>8} {'buried':>7} {'k':>5} {'mj_step':>8} {'kernel':>7} {'implicit':>8} "
          f"{'terrain.step':>12} {'rest':>6}")
    for r in rows:
        rest = r["terrain.step"] - r["kernel"] - r["implicit"] - r["mj_step"]
        print(f"{r['robot']:<15} {r['elements']:>8d} {r['buried']:>7.0f} {r['k']:>5.2f} {r['mj_step']:>8.1f} "
              f"{r['kernel']:>7.1f} {r['implicit']:>8.1f} {r['terrain.step']:>12.1f} {rest:>6.1f}")
    print()
    print("the kernel (us): culling only, + pass 1 (positions and depths of the groups within reach), the buried "
          "elements' work")
    print(f"{'robot':<15} {'kernel':>7} {'cull':>6} {'+pass 1':>8} {'buried':>7} {'buried work':>11} {'ns/buried':>9}")
    for r in rows:
        work = r["kernel"] - r["pass1"]
        print(f"{r['robot']:<15} {r['kernel']:>7.1f} {r['cull']:>6.1f} {r['pass1'] - r['cull']:>8.1f} "
              f"{r['buried']:>7.0f} {work:>11.1f} {1e3 * work / max(r['buried'], 1.0):>9.0f}")
    print()
    print("per env step (us): the wrapper's stable timesteps, info arrays and cfrc_ext, after its physics steps")
    print(f"{'robot':<15} {'physics steps':>13} {'limits':>7} {'info':>6} {'cfrc':>6}")
    for r in rows:
        print(f"{r['robot']:<15} {r['frame_skip'] * r['k']:>13.2f} {r['limits']:>7.1f} {r['info']:>6.1f} "
              f"{r['cfrc']:>6.1f}")


if __name__ == "__main__":
    main()

"""terrain_kernel of an older revision against the working tree's, in one process, on the same states.

    python benchmarks/kernel_ab.py REV [--states N] [--reps R]

REV's ``mjrft/kernel.py`` (``git show``) is compiled in this process next to the installed one (uncached,
importing the installed laws and media, so only the kernel differs). On five scenes (the hexapod's dry poppy
seeds, the shoal's saturated strip, its water strip, the hexapod on 3D-RFT sand, which takes the general
per-element pass instead of the batched law, and the dry scene with the implicit step's spring moments), a
tripod walk records N states; on three gymnasium robots under ``GranularWrapper``'s defaults (Hopper, Walker2d,
HalfCheetah: most of their elements on a torso and thighs above the sand), seeded random actions do; for each
state both kernels run from a zeroed memory and their results are compared, then each is timed in R rounds,
alternately, of a compiled loop making 5 calls (zeroing the memory before each, as the stepping loop calls the kernel
from compiled code) and of the same loop making none; the state's time per call is the difference of the fastest
rounds over 5: a round lasts tens of microseconds, far shorter than a scheduler slice, so on a loaded machine most
rounds run undisturbed and the minimum is their cost. An older kernel that took each array on its own gets them in
that order (:func:`flat_args`), a newer one the grouped records. Prints the mean over states of those times and
their ratio, and whether the two kernels' forces, wrenches, stiffness moments (of the springs, the depth stiffness
and the implicit step) and damping are bit-identical on every state, or else their largest difference over the states
in units of each output's largest value.
"""

from __future__ import annotations

import argparse
import inspect
import os
import re
import subprocess
import sys
import time
import types
import warnings

import mujoco
import numpy as np
from numba import njit

import mjrft
from mjrft import kernel as current
from mjrft.models import hexapod_model, hexapod_shoal_model

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BATCH = 5  # kernel calls per timed round
FLAT_U = 32  # the position of the memory ``u`` among the flat arguments (flat_args)
RESOLUTION = 0.0042  # bench_step's fine resolution (2,610 elements on the hexapod)
SCENES = (  # label, model, start x (m), terrain keyword arguments
    ("dry poppy", hexapod_model, 0.0, {}),
    ("shoal saturated", hexapod_shoal_model, 0.65, {}),
    ("shoal water", hexapod_shoal_model, 1.15, {}),
    ("rft3d (general)", hexapod_model, 0.0, {"law": "rft3d"}),
    ("dry poppy implicit", hexapod_model, 0.0, {"implicit": True}),
)

GYM_SCENES = ("Hopper-v5", "Walker2d-v5", "HalfCheetah-v5")


def kernel_of(rev: str) -> types.ModuleType:
    """REV's mjrft/kernel.py as a module of the installed package (compiled uncached)."""
    out = subprocess.run(["git", "show", f"{rev}:mjrft/kernel.py"], cwd=REPO, capture_output=True, text=True)
    if out.returncode:
        raise SystemExit(f"cannot read mjrft/kernel.py at {rev!r}: {out.stderr.strip()}")
    name = "mjrft._kernel_ab_old"
    mod = types.ModuleType(name)
    mod.__package__ = "mjrft"
    mod.__file__ = f"<{rev}:mjrft/kernel.py>"
    sys.modules[name] = mod
    source = re.sub(r"from \.(media|laws\.wet) import (P_[A-Z_]+(, P_[A-Z_]+)*)(, )?", _params_import, out.stdout)
    mod.__dict__["__kernel_source__"] = source
    exec(compile(source.replace("cache=True", "cache=False"), mod.__file__, "exec"), mod.__dict__)
    return mod


def _params_import(m: re.Match) -> str:
    """An older kernel's import of parameter slots from the media or the wet law: they live in mjrft.params."""
    return f"from .params import {m.group(2)}\nfrom .{m.group(1)} import " if m.group(4) else \
        f"from .params import {m.group(2)}"


def record(make, x0: float, n: int, **kw):
    """(model, data, terrain, states): n states of a 2 Hz tripod walk, 10 steps apart."""
    model = make()
    data = mujoco.MjData(model)
    terrain = mjrft.GranularTerrain(model, resolution=RESOLUTION, **kw)
    data.qpos[0] = x0
    states = []
    for _ in range(n):
        data.ctrl[:] = 2 * np.pi * 2.0 * data.time + np.arange(model.nu) % 2 * np.pi
        terrain.step(data, 10)
        states.append((data.qpos.copy(), data.qvel.copy(), data.time))
    return model, data, terrain, states


def record_gym(gym_id: str, n: int):
    """(model, data, terrain, states): n states of a seeded random-action run of ``gym_id`` on sand, 5 env steps
    apart (the wrapper's internal timestep restored for the kernel's dt)."""
    import gymnasium

    from mjrft.envs.wrapper import GranularWrapper

    env = GranularWrapper(gymnasium.make(gym_id))
    env.reset(seed=0)
    env.action_space.seed(0)
    u = env.unwrapped
    states = []
    for _ in range(n):
        for _ in range(5):
            env.step(env.action_space.sample())
        states.append((u.data.qpos.copy(), u.data.qvel.copy(), u.data.time))
    u.model.opt.timestep = env.model_timestep / env.last_substeps
    return u.model, u.data, env.terrain, states


def n_params(kernel_function) -> int:
    """How many arguments a revision's ``terrain_kernel`` takes: 5 for the grouped form ``(tables, mjd, gravity, dt,
    state)``; otherwise its arguments are the flat list of :func:`flat_args` (arguments added later went at its end,
    so an older kernel takes the leading ones)."""
    return len(inspect.signature(kernel_function.py_func).parameters)


def flat_args(t, dt) -> tuple:
    """A terrain's kernel arguments in the flat order of the kernels that took each array on its own."""
    tm, st = t.terrain_model, t.terrain_state
    el, sf, rg, cs = tuple(tm.tables)[:4]
    v = t._views if hasattr(t, "_views") else None
    return (el.group_geom, el.group_body, el.group_start, el.group_aabb, st.group_active, el.lpos, el.lnrm, el.area,
            *v, el.body_root, sf.height, sf.top, rg.bounds, rg.law, rg.params, sf.hfield_z, sf.hfield_frame, rg.map,
            rg.map_frame, rg.rho, rg.transition, t.step_arguments(t._data, dt)[4], dt, cs.delta, cs.tau, cs.v_eps,
            st.u, st.pos, st.vel, st.normal, st.depth, st.force, st.region, st.wrench, st.stiff, st.damp, st.inert,
            st.scr_f, st.scr_i, st.imp, st.dstiff, cs.solid, cs.stick)


def n_groups(kernel_function) -> int:
    """How many groups of the model's tables a grouped ``terrain_kernel`` unpacks (``el, sf, rg, cs[, gr] = tables``:
    a kernel before the ground memory takes the first four)."""
    src = kernel_function.py_func.__globals__.get("__kernel_source__") or inspect.getsource(kernel_function.py_func)
    m = re.search(r"^\s*([\w, ]+)= tables\s*$", src, re.M)
    return len(m.group(1).split(",")) if m else 5


def kernel_args(kernel_function, t, dt) -> tuple:
    """The arguments ``kernel_function`` (a revision's ``terrain_kernel``) takes for terrain ``t``."""
    n = n_params(kernel_function)
    if n == 5:
        _, tables, mjd, _, gravity, dt, st = t.step_arguments(t._data, dt)
        if n_groups(kernel_function) < len(tables):
            tables = tuple(tables)[:n_groups(kernel_function)]
        return tables, mjd, gravity, dt, st
    return flat_args(t, dt)[:n]


def outputs(t) -> list[np.ndarray]:
    st = t.terrain_state
    return [st.force.copy(), st.wrench.copy(), st.stiff.copy(), st.damp.copy(), st.inert.copy(), st.depth.copy(),
            st.imp.copy(), st.dstiff.copy()]


def driver(kernel_function, n: int):
    """A compiled loop ``drive(reps, *args)`` that zeroes the elements' memory and calls ``kernel_function`` (with its
    ``n`` arguments) ``reps`` times: the calls come from compiled code, as in the stepping loop, so neither kernel's
    argument form costs anything per call."""
    names = ", ".join(f"a{i}" for i in range(n))
    u = "a4.u" if n == 5 else f"a{FLAT_U}"
    src = f"def drive(reps, {names}):\n    for _ in range(reps):\n        {u}[:] = 0.0\n        kernel({names})\n"
    scope = {"kernel": kernel_function}
    exec(src, scope)
    return njit(scope["drive"])


def scaled_difference(a: np.ndarray, b: np.ndarray) -> float:
    """max |a - b| over the largest |b| (0 where both are all zero): a difference relative to the output's scale."""
    scale = float(np.max(np.abs(b))) if b.size else 0.0
    diff = float(np.max(np.abs(a - b))) if b.size else 0.0
    return diff / scale if scale > 0.0 else diff


def compare(old, model, data, terrain, states, reps: int) -> tuple[float, float, bool, float]:
    """(mean old time, mean new time, bit-identical, largest scaled difference) over the states: per state, the
    results of one call of each kernel from the same memory (their difference in units of each output's largest
    value, :func:`scaled_difference`), and each kernel's time per call (the fastest of ``reps`` rounds of ``BATCH``
    calls in a compiled loop, less the fastest round of none)."""
    best = {"old": [], "new": []}
    same = True
    worst = 0.0
    terrain.bind(data)
    dt = model.opt.timestep
    kernels = {"old": old.terrain_kernel, "new": current.terrain_kernel}
    args = {name: kernel_args(k, terrain, dt) for name, k in kernels.items()}
    drives = {name: driver(k, len(args[name])) for name, k in kernels.items()}
    for qpos, qvel, t in states:
        data.qpos[:], data.qvel[:], data.time = qpos, qvel, t
        mujoco.mj_forward(model, data)
        res = {}
        for name in ("old", "new"):
            drives[name](1, *args[name])
            res[name] = outputs(terrain)
        same = same and all(np.array_equal(a, b) for a, b in zip(res["old"], res["new"]))
        worst = max([worst] + [scaled_difference(b, a) for a, b in zip(res["old"], res["new"])])
        low = {name: [np.inf, np.inf] for name in kernels}
        for _ in range(reps):
            for name in ("old", "new"):
                for slot, calls in enumerate((0, BATCH)):
                    t0 = time.perf_counter_ns()
                    drives[name](calls, *args[name])
                    low[name][slot] = min(low[name][slot], time.perf_counter_ns() - t0)
        for name in best:
            best[name].append((low[name][1] - low[name][0]) / BATCH)
    return float(np.mean(best["old"])) * 1e-3, float(np.mean(best["new"])) * 1e-3, same, worst


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("rev", help="the older revision (commit, tag or branch)")
    ap.add_argument("--states", type=int, default=30, help="recorded states per scene (default 30)")
    ap.add_argument("--reps", type=int, default=40, help="timed rounds per state and kernel (default 40)")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")  # validity-range warnings of the walks
    rev = subprocess.run(["git", "rev-parse", "--short", args.rev], cwd=REPO, capture_output=True, text=True)
    short = rev.stdout.strip() or args.rev
    old = kernel_of(args.rev)
    scenes = [(label, record(make, x0, args.states, **kw)) for label, make, x0, kw in SCENES]
    scenes += [(gym_id, record_gym(gym_id, args.states)) for gym_id in GYM_SCENES]
    for _, (m, d, t, states) in scenes:  # compile both outside the timing
        compare(old, m, d, t, states[:1], 1)
    print(f"terrain_kernel: {short} (old) vs the working tree (new), resolution {RESOLUTION} m (gymnasium robots: "
          "the wrapper's default), "
          f"{args.states} states x {args.reps} interleaved rounds of {BATCH} calls from compiled code; per state the "
          "fastest round less the fastest empty one, per call")
    print(f"{'scene':18s} {'elements':>8s} {'old (us)':>9s} {'new (us)':>9s} {'new/old':>8s}  outputs")
    for label, (m, d, t, states) in scenes:
        a, b, same, worst = compare(old, m, d, t, states, args.reps)
        print(f"{label:18s} {t.n_elements:8d} {a:9.2f} {b:9.2f} {b / a:8.3f}  "
              f"{'bit-identical' if same else f'differ by {worst:.1e} of their scale'}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

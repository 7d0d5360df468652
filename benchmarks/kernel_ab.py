"""terrain_kernel of an older revision against the working tree's, in one process, on the same states.

    python benchmarks/kernel_ab.py REV [--states N] [--reps R]

REV's ``mjrft/kernel.py`` (``git show``) is compiled in this process next to the installed one (uncached,
importing the installed laws and media, so only the kernel differs). On five scenes (the hexapod's dry poppy
seeds, the shoal's saturated strip, its water strip, the hexapod on 3D-RFT sand, which takes the general
per-element pass instead of the batched law, and the dry scene with the implicit step's spring moments), a
tripod walk records N states; on three gymnasium robots under ``GranularWrapper``'s defaults (Hopper, Walker2d,
HalfCheetah: most of their elements on a torso and thighs above the sand), seeded random actions do; for each
state both kernels run R times, alternately, each call timed on its own, and the state's time is the minimum of
its calls: a call lasts tens of microseconds, far shorter than a scheduler slice, so on a loaded machine most
calls run undisturbed and the minimum is their cost. Prints the mean over states of those minima and their ratio,
and whether the two kernels' forces, wrenches, stiffness moments (of the springs, the depth stiffness and the
implicit step) and damping are bit-identical on every state.
"""

from __future__ import annotations

import argparse
import inspect
import os
import subprocess
import sys
import time
import types
import warnings

import mujoco
import numpy as np

import mjrft
from mjrft import kernel as current
from mjrft.models import hexapod_model, hexapod_shoal_model

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
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
    exec(compile(out.stdout.replace("cache=True", "cache=False"), mod.__file__, "exec"), mod.__dict__)
    return mod


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
    """How many arguments a revision's ``terrain_kernel`` takes: arguments added later go at the end of
    ``_kernel_args`` (an explicit terrain's are empty arrays), so an older kernel takes the leading ones."""
    return len(inspect.signature(kernel_function.py_func).parameters)


def outputs(t) -> list[np.ndarray]:
    return [t.force.copy(), t.wrench.copy(), t._stiff.copy(), t._damp.copy(), t._inert.copy(), t.depth.copy(),
            t._imp.copy(), t._dstiff.copy()]


def compare(old, model, data, terrain, states, reps: int) -> tuple[float, float, bool]:
    """(mean old time, mean new time, bit-identical) over the states."""
    best = {"old": [], "new": []}
    same = True
    for qpos, qvel, t in states:
        data.qpos[:], data.qvel[:], data.time = qpos, qvel, t
        mujoco.mj_forward(model, data)
        args = terrain._kernel_args(model.opt.timestep)
        res, low = {}, {"old": np.inf, "new": np.inf}
        for _ in range(reps):
            for name, k in (("old", old), ("new", current)):
                terrain._u[:] = 0.0
                n = n_params(k.terrain_kernel)
                t0 = time.perf_counter_ns()
                k.terrain_kernel(*args[:n])
                low[name] = min(low[name], time.perf_counter_ns() - t0)
                res[name] = outputs(terrain)
        same = same and all(np.array_equal(a, b) for a, b in zip(res["old"], res["new"]))
        for name in best:
            best[name].append(low[name])
    return float(np.mean(best["old"])) * 1e-3, float(np.mean(best["new"])) * 1e-3, same


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("rev", help="the older revision (commit, tag or branch)")
    ap.add_argument("--states", type=int, default=30, help="recorded states per scene (default 30)")
    ap.add_argument("--reps", type=int, default=40, help="timed calls per state and kernel (default 40)")
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
          f"{args.states} states x {args.reps} interleaved calls each; per state the fastest call")
    print(f"{'scene':18s} {'elements':>8s} {'old (us)':>9s} {'new (us)':>9s} {'new/old':>8s}  outputs")
    for label, (m, d, t, states) in scenes:
        a, b, same = compare(old, m, d, t, states, args.reps)
        print(f"{label:18s} {t.n_elements:8d} {a:9.2f} {b:9.2f} {b / a:8.3f}  "
              f"{'bit-identical' if same else 'DIFFER'}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

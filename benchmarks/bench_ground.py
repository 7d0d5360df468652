"""The ground memory's cost: the kernel with and without it on the same recorded steps, side by side.

    python benchmarks/bench_ground.py [--steps N] [--rounds R] [--cells C ...] [--periods P ...]
                                      [--timesteps DT ...] [--out FILE]

The hexapod (its bundled scene: poppy seeds closely packed, Li RFT, 1,696 elements; its own 1 ms step, or each
``--timesteps`` one: mjrft/HexapodSand-v0 steps at 0.5 ms) walks its 2 Hz tripod for 1 s on the terrain without a
memory while a terrain with ``ground_memory=True`` is evaluated on the same states (its ground follows the legs; the
motion does not depend on the memory's implementation); the next N physics steps are recorded as the kernel sees
them (the ``mjData`` views after ``mj_step1``). Each timed round replays those N steps in order through the compiled
kernel from a compiled loop: on the terrain without a memory, on the one with it (its state restored to the
recording's start, so the ground evolves as it did while recording: the same footprints, ridges and avalanches), on
the one with it frozen (below) and on the one with it, its updates timed (below), alternately; a round's time per
step is its total over N. The fastest round of each is its cost (on a loaded machine most rounds run undisturbed).
Printed per physics step, grid cell and update period: the times per step, the memory's share of the kernel
``(with - without) / without``, and how that splits: the replay with the memory and its updates held off (the ground
frozen as it was at the recording's start, every element's memory advancing as in the others), ``(frozen - without)
/ without``, is what reading the ground costs (each element's surface and packing, each cull group's highest
surface around it, the elements that the ridges left by the first second bring within reach); the rest, ``(with -
frozen) / without``, is what the updates cost with what they cause. Of that, "update" is the updates' own time
(:func:`mjrft.ground.ground_step`, run on the kernel's schedule by the replay and timed around each call by the
monotonic clock, summed over the steps), and "caused" the remainder: the cull groups near a changed block reading
the ground afresh, and the ridges each leg heaps around itself as it digs (more of the legs' elements placed and
buried). Then, counted on one more replay of each, step by step: the elements placed per step (in the cull groups
within reach) and buried, the elements reading the ground afresh, and the torso's elements placed.
"""

from __future__ import annotations

import argparse
import ctypes
import ctypes.util
import sys
import time
import warnings

import mujoco
import numpy as np
from numba import njit

import mjrft
from mjrft import kernel
from mjrft.ground import GROUND_PERIOD, GroundOptions, ground_step
from mjrft.types import MjViews

# the C library's clock_gettime, which compiled code can call (the updates' own time, measured inside the replay)
_LIBC = ctypes.CDLL(ctypes.util.find_library("c"))
_clock_gettime = _LIBC.clock_gettime
_clock_gettime.argtypes = [ctypes.c_int, ctypes.c_void_p]
_clock_gettime.restype = ctypes.c_int


def record(steps: int, warm: float = 1.0, memory=True, law=None, timestep=None):
    """(model, terrain with memory, terrain without, stacked views, the first's state at the start, dt): the hexapod
    walks on the terrain without a memory (so the recorded motion does not depend on the memory), while the one with
    it (``memory``: its ``ground_memory`` argument) is evaluated on every step too, its ground following the legs;
    ``law``: both terrains' force law (None: the model's own); ``timestep``: the physics step (s; None: the model's
    own, 1 ms)."""
    model = mujoco.MjModel.from_xml_path(mjrft.models.model_path("hexapod"))
    if timestep is not None:
        model.opt.timestep = timestep
    data = mujoco.MjData(model)
    on = mjrft.GranularTerrain(model, law=law, ground_memory=memory)
    off = mjrft.GranularTerrain(model, law=law)
    dt = model.opt.timestep

    def one_step(keep=None):
        data.ctrl[:] = 2 * np.pi * 2.0 * data.time + np.arange(model.nu) % 2 * np.pi
        mujoco.mj_step1(model, data)
        if keep is not None:
            for k in keep:
                keep[k].append(getattr(data, k).copy())
        on.compute(data)
        off.compute(data)
        data.xfrc_applied[off.body_ids] = off.wrench[off.body_ids]
        mujoco.mj_step2(model, data)
        data.xfrc_applied[:] = 0.0

    while data.time < warm - 1e-9:
        one_step()
    start = copy_state(on.terrain_state)
    views = {k: [] for k in MjViews._fields}
    for _ in range(steps):
        one_step(views)
    stacked = MjViews(*(np.ascontiguousarray(np.array(views[k])) for k in MjViews._fields))
    return model, on, off, stacked, start, dt


@njit
def replay(tables, views, gravity, dt, st, frozen=False):
    """The kernel on each recorded step in order (``views``: each field stacked over the steps): the terrain's own
    (:func:`mjrft.kernel.terrain_kernel_ground` with a ground memory; ``frozen``: its updates held off, the time since
    the last one kept far below its period)."""
    gx, gm, xp, xm, xi, cv, sc = views
    bad = 0
    for s in range(gx.shape[0]):
        mjd = MjViews(gx[s], gm[s], xp[s], xm[s], xi[s], cv[s], sc[s])
        if frozen:
            st.g_since[0] = -1e300
        if tables.ground.on:
            status, _ = kernel.terrain_kernel_ground(tables, mjd, gravity, dt, st)
        else:
            status, _ = kernel.terrain_kernel(tables, mjd, gravity, dt, st)
        bad += status != kernel.OK
    return bad


@njit
def _now_ns(ts):
    """The monotonic clock (ns); ``ts``: two int64, scratch of ``clock_gettime``."""
    _clock_gettime(time.CLOCK_MONOTONIC, ts.ctypes.data)
    return ts[0] * 1_000_000_000 + ts[1]


@njit
def replay_timed(tables, views, gravity, dt, st, delta, v_eps):
    """:func:`replay` of a terrain with a ground memory, its kernel's updates held off and run here instead on the
    kernel's schedule (once per period of simulated time, :func:`mjrft.ground.ground_step`), each timed: returns
    (bad steps, the updates' total time in ns)."""
    gx, gm, xp, xm, xi, cv, sc = views
    gr = tables.ground
    ts = np.zeros(2, dtype=np.int64)
    bad = 0
    spent = 0
    since = st.g_since[0]
    for s in range(gx.shape[0]):
        mjd = MjViews(gx[s], gm[s], xp[s], xm[s], xi[s], cv[s], sc[s])
        st.g_since[0] = -1e300
        status, _ = kernel.terrain_kernel_ground(tables, mjd, gravity, dt, st)
        bad += status != kernel.OK
        since += dt
        if since >= gr.period * (1.0 - 1e-9):
            t0 = _now_ns(ts)
            ground_step(gr, tables.elements, st, delta, v_eps, since)
            spent += _now_ns(ts) - t0
            since = 0.0
    return bad, spent


def copy_state(st) -> list:
    """A copy of every array of the state ``st`` (the ground's blocks included)."""
    return [tuple(b.copy() for b in a) if isinstance(a, tuple) else a.copy() for a in st]


def restore(st, start) -> None:
    """Put the state ``st`` back to the recording's start (a terrain without a memory: every array but the ground's,
    so both replays start from the same elements' memory)."""
    for name, a, b in zip(st._fields, st, start):
        if isinstance(a, tuple):
            for x, y in zip(a, b):
                if x.shape == y.shape:
                    x[...] = y
        elif a.shape == b.shape:
            a[...] = b
        elif not (name.startswith("g_") or name == "scr_f"):
            raise ValueError(f"state array {name} has shape {a.shape}, the recording's {b.shape}")


def measure(steps: int, rounds: int, options: GroundOptions,
            timestep: float | None = None) -> tuple[dict, dict, mjrft.GranularTerrain, float]:
    """({"without", "with", "frozen", "update"}: the fastest round's time per step (us; "update": the updates' own
    time, :func:`replay_timed`), the first three: their :func:`counts`, the terrain with the memory, dt) of one
    recording (``frozen``: the terrain with the memory, its updates held off) at the physics step ``timestep`` (s;
    None: the model's own)."""
    model, on, off, views, start, dt = record(steps, memory=options, timestep=timestep)
    consts = on.terrain_model.constants
    best = {"without": np.inf, "with": np.inf, "frozen": np.inf, "update": np.inf}
    runs = {"without": (off, False), "with": (on, False), "frozen": (on, True)}
    for r in range(rounds + 1):  # round 0 compiles
        for name, (t, frozen) in runs.items():
            restore(t.terrain_state, start)
            t0 = time.perf_counter_ns()
            bad = replay(t.terrain_model.tables, views, 9.81, dt, t.terrain_state, frozen)
            elapsed = (time.perf_counter_ns() - t0) / steps * 1e-3
            if bad:
                raise SystemExit(f"{name}: {bad} steps returned a bad status")
            if r > 0:
                best[name] = min(best[name], elapsed)
        restore(on.terrain_state, start)
        bad, spent = replay_timed(on.terrain_model.tables, views, 9.81, dt, on.terrain_state, consts.delta,
                                  consts.v_eps)
        if bad:
            raise SystemExit(f"update: {bad} steps returned a bad status")
        if r > 0:
            best["update"] = min(best["update"], spent / steps * 1e-3)
    return best, {name: counts(t, views, start, dt, frozen) for name, (t, frozen) in runs.items()}, on, dt


def counts(t, views, start, dt: float, frozen: bool) -> tuple[float, float, float, float]:
    """(elements placed: in the cull groups within reach, elements buried, elements reading the ground afresh: in the
    groups whose reading changed, the torso's elements placed), per step, on the replay of the terrain ``t`` from
    ``start`` (step by step)."""
    st = t.terrain_state
    restore(st, start)
    el = t.terrain_model.tables.elements
    size = np.diff(el.group_start)
    torso = el.group_body == mujoco.mj_name2id(t.model, mujoco.mjtObj.mjOBJ_BODY, "torso")
    placed = buried = fresh = on_torso = 0
    n = views.geom_xpos.shape[0]
    for s in range(n):
        before = st.g_group.copy()
        replay(t.terrain_model.tables, MjViews(*(v[s:s + 1] for v in views)), 9.81, dt, st, frozen)
        placed += size[st.group_active].sum()
        on_torso += size[st.group_active & torso].sum()
        buried += np.count_nonzero(st.depth > 0.0)
        if before.shape[0]:
            fresh += size[np.any(st.g_group != before, axis=1)].sum()
    return placed / n, buried / n, fresh / n, on_torso / n


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=1000, help="recorded physics steps (default 1000: 1 s at 1 ms)")
    ap.add_argument("--rounds", type=int, default=15, help="timed rounds per configuration (default 15)")
    ap.add_argument("--cells", type=float, nargs="+", default=[None],
                    help="the grid's cells to measure (m; default GroundOptions': twice the elements' size)")
    ap.add_argument("--periods", type=float, nargs="+", default=[GROUND_PERIOD],
                    help=f"the ground's update periods to measure (s; default {GROUND_PERIOD})")
    ap.add_argument("--timesteps", type=float, nargs="+", default=[None],
                    help="the physics steps to measure (s; default the bundled model's own, 1 ms; "
                         "mjrft/HexapodSand-v0 steps at 0.5 ms), each recording STEPS steps")
    ap.add_argument("--out", default=None, help="also write the report to this file")
    args = ap.parse_args(argv)
    for dt in args.timesteps:
        if dt is not None and not (np.isfinite(dt) and dt > 0.0):
            ap.error(f"--timesteps must be positive seconds, got {dt!r}")
    warnings.simplefilter("ignore")
    lines = [f"python benchmarks/bench_ground.py --steps {args.steps} --rounds {args.rounds}"
             + ("" if args.cells == [None] else " --cells " + " ".join(f"{c:g}" for c in args.cells))
             + ("" if args.periods == [GROUND_PERIOD] else " --periods " + " ".join(f"{p:g}" for p in args.periods))
             + ("" if args.timesteps == [None] else " --timesteps " + " ".join(f"{t:g}" for t in args.timesteps))]
    header = False
    elements = ["elements per step: placed (in the cull groups within reach) / buried, without the memory, with it "
                "and with it frozen; reading the ground afresh, with it; of the placed, the torso's (without, with, "
                "frozen):",
                f"{'dt':>6s} {'cell':>6s} {'period':>7s} {'without':>9s} {'with':>9s} {'frozen':>9s} {'re-read':>8s} "
                f"{'torso':>14s}"]
    for timestep in args.timesteps:
        for cell in args.cells:
            for period in args.periods:
                best, count, on, dt = measure(args.steps, args.rounds, GroundOptions(cell=cell, period=period),
                                              timestep)
                gt = on.terrain_model.ground
                if not header:
                    lines += [f"hexapod (bundled scene: {on.medium.name}, {on.law}, {on.n_elements} elements), 2 Hz "
                              f"tripod on the terrain without a memory, a terrain with one evaluated on the same "
                              f"states; {args.steps} recorded steps after 1 s; fastest of {args.rounds} rounds, "
                              f"kernel time per step (us):",
                              f"{'dt':>6s} {'cell':>6s} {'period':>7s} {'without':>8s} {'with':>8s} {'frozen':>8s} "
                              f"{'memory / kernel':>16s} {'reading':>8s} {'updates':>8s} {'(update':>8s} "
                              f"{'caused)':>8s}"]
                    header = True
                w, g, k, u = best["without"], best["with"], best["frozen"], best["update"]
                row = f"{dt * 1e3:4.2g}ms {gt.frame[2] * 1e3:4.0f}mm {gt.period * 1e3:5.0f}ms"
                lines.append(f"{row} {w:8.2f} {g:8.2f} {k:8.2f} {100 * (g - w) / w:15.1f}% {100 * (k - w) / w:7.1f}% "
                             f"{100 * (g - k) / w:7.1f}% {100 * u / w:7.1f}% {100 * (g - k - u) / w:7.1f}%")
                print(lines[-1] if len(lines) > 3 else "\n".join(lines), flush=True)
                elements.append(f"{row} "
                                + " ".join(f"{'%.0f/%.0f' % count[name][:2]:>9s}"
                                           for name in ("without", "with", "frozen"))
                                + f" {count['with'][2]:8.0f} "
                                + f"{'/'.join('%.0f' % count[name][3] for name in ('without', 'with', 'frozen')):>14s}")
    text = "\n".join(lines + elements)
    print(text)
    if args.out:
        with open(args.out, "w") as fh:
            fh.write(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())

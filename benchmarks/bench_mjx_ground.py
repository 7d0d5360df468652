"""The ground memory's cost in MJX: ``mjrft.mjx.Sand.step`` of the hexapod with and without it, side by side.

    python benchmarks/bench_mjx_ground.py [--worlds 1 4 16] [--steps N] [--warm S] [--rounds R] [--bottom-contacts]
                                          [--out FILE]

The hexapod (its bundled scene: poppy seeds closely packed, Li RFT, 1,696 elements, 1 ms; the bed's rigid bottom
without contacts, as the MJX environment runs it, unless ``--bottom-contacts``) walks its 2 Hz tripod in
each of W worlds (``jax.vmap`` of ``Sand.step``, one jitted ``lax.scan``; the worlds' starting poses differ by a few
mm, so their grounds differ), first for ``--warm`` s untimed (the legs in the sand, footprints and ridges made), then
N timed steps from that state, on the terrain without a memory and on the one with ``ground_memory=True`` (default
options: 1 cm cells, updates every 4 ms), alternately; the fastest of R rounds is each one's cost (on a loaded machine
most rounds run undisturbed). Printed per world count: the world-steps per second of both, the memory's share of the
step ``(with - without) / without``, the compile times and the device memory of the timed call with the memory (XLA's
memory analysis: arguments + outputs + temporaries, per world). JAX's default device (CPU here; the GPU where JAX has
one). ``--bottom-contacts`` keeps the bed bottom's contacts (the bundled scene as the CPU path loads it): then MJX's
collision detection and constraint solver run for it in every step of both terrains.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings

import jax
import jax.numpy as jnp
import mujoco
import numpy as np
from mujoco import mjx

import mjrft
import mjrft.mjx as rmjx


def build(memory: bool, bottom_contacts: bool = False):
    model = mujoco.MjModel.from_xml_path(mjrft.models.model_path("hexapod"))
    if not bottom_contacts:  # the bed's rigid bottom without contacts, as the MJX environment
        bottom = model.geom("bed_bottom").id
        model.geom_contype[bottom] = model.geom_conaffinity[bottom] = 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sand = rmjx.Sand(model, ground_memory=memory)
    return model, sand, sand.put_model()


def runner(model, sand, mx, worlds: int, steps: int):
    """A jitted function (data, state) -> (data, state) of ``steps`` tripod steps of every world."""
    phase = jnp.asarray(np.arange(model.nu) % 2 * np.pi)

    def one(carry, _):
        d, s = carry
        d = d.replace(ctrl=2 * jnp.pi * 2.0 * d.time + phase)
        return sand.step(mx, d, s), None

    def world(d, s):
        return jax.lax.scan(one, (d, s), None, length=steps)[0]

    return jax.jit(jax.vmap(world))


def start(model, sand, mx, worlds: int):
    d0 = mjx.make_data(mx)
    qpos = np.tile(model.qpos0, (worlds, 1))
    qpos[:, 0] += 0.003 * np.arange(worlds)  # each world's own footprints
    d = jax.vmap(lambda q: d0.replace(qpos=q))(jnp.asarray(qpos))
    s = jax.vmap(lambda _: sand.init())(jnp.arange(worlds))
    return d, s


def device_mib(compiled) -> float:
    """XLA's memory analysis of a compiled call: arguments + outputs + temporaries (MiB); nan where not reported."""
    try:
        ma = compiled.memory_analysis()
        return (ma.argument_size_in_bytes + ma.output_size_in_bytes + ma.temp_size_in_bytes) / 2**20
    except Exception:  # not every backend reports it
        return float("nan")


def measure(worlds: int, steps: int, warm: float, rounds: int, bottom_contacts: bool = False) -> dict:
    out = {}
    cases = {}
    for memory in (False, True):
        model, sand, mx = build(memory, bottom_contacts)
        d, s = start(model, sand, mx, worlds)
        warm_steps = int(round(warm / model.opt.timestep))
        t0 = time.perf_counter()
        d, s = jax.block_until_ready(runner(model, sand, mx, worlds, warm_steps)(d, s))
        run = runner(model, sand, mx, worlds, steps).lower(d, s).compile()
        out[f"mib_{memory}"] = device_mib(run)
        jax.block_until_ready(run(d, s))
        out[f"compile_{memory}"] = time.perf_counter() - t0
        cases[memory] = (run, d, s)
    best = {False: np.inf, True: np.inf}
    for _ in range(rounds):
        for memory in (False, True):
            run, d, s = cases[memory]
            t0 = time.perf_counter()
            jax.block_until_ready(run(d, s))
            best[memory] = min(best[memory], time.perf_counter() - t0)
    for memory in (False, True):
        out[f"rate_{memory}"] = worlds * steps / best[memory]
    run, d, s = cases[True]
    d, s = run(d, s)
    out["updates"] = int(np.asarray(s.ground.clock[:, 0]).max())
    out["footprint_mm"] = float(-np.asarray(s.ground.cells[..., 1]).min() * 1e3)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--worlds", type=int, nargs="+", default=[1, 4, 16])
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--warm", type=float, default=0.3)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--bottom-contacts", action="store_true",
                    help="keep the bed bottom's contacts (MJX's collision and solver run for it in every step)")
    ap.add_argument("--out", default=None)
    a = ap.parse_args(argv)
    if min(a.worlds) < 1 or a.steps < 1 or a.rounds < 1:
        ap.error(f"--worlds, --steps and --rounds must be >= 1, got {a.worlds}, {a.steps}, {a.rounds}")
    if not (np.isfinite(a.warm) and a.warm >= 0):
        ap.error(f"--warm must be a finite number of seconds >= 0, got {a.warm}")
    flag = " --bottom-contacts" if a.bottom_contacts else ""
    lines = [f"mjrft.mjx.Sand.step, hexapod 2 Hz tripod, {a.steps} steps after {a.warm:g} s, fastest of {a.rounds} "
             f"rounds, bed bottom {'with' if a.bottom_contacts else 'without'} contacts, JAX {jax.__version__} on "
             f"{jax.devices()[0].platform} ({jax.devices()[0].device_kind})",
             f"command: python benchmarks/bench_mjx_ground.py{flag} --worlds {' '.join(map(str, a.worlds))} --steps "
             f"{a.steps} --warm {a.warm:g} --rounds {a.rounds}",
             f"{'worlds':>6} {'without (steps/s)':>18} {'with (steps/s)':>15} {'memory cost':>12} "
             f"{'compile without / with (s)':>27} {'deepest footprint (mm)':>23} {'MiB/world without / with':>25}"]
    print("\n".join(lines), flush=True)
    for w in a.worlds:
        r = measure(w, a.steps, a.warm, a.rounds, a.bottom_contacts)
        cost = r["rate_False"] / r["rate_True"] - 1.0
        line = (f"{w:>6} {r['rate_False']:>18.1f} {r['rate_True']:>15.1f} {100 * cost:>11.0f}% "
                f"{r['compile_False']:>13.1f} / {r['compile_True']:<11.1f} {r['footprint_mm']:>23.2f} "
                f"{r['mib_False'] / w:>12.3f} / {r['mib_True'] / w:<10.3f}")
        print(line, flush=True)
        lines.append(line)
    lines.append("memory cost = (time per step with - without) / without; world-steps per second = worlds x steps / "
                 "the round's time; compile: the warm-up's and the timed scan's first calls (seconds); MiB/world: XLA's "
                 "memory analysis of the timed call (arguments + outputs + temporaries) over the worlds")
    if a.out:
        with open(a.out, "w") as f:
            f.write("\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())

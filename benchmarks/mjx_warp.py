"""MuJoCo Warp (``impl="warp"``) against MJX's JAX implementation, with and without sand, on the host's device.

MJX runs a model through MuJoCo Warp when it is put with ``mjx.put_model(model, impl="warp")`` and its data made
with ``mjx.make_data(model, impl="warp")`` (from the ``mujoco.MjModel``); ``mujoco-mjx`` carries MuJoCo Warp itself
and needs only NVIDIA's ``warp-lang`` to run it (``pip install warp-lang``; on a machine without a CUDA driver
Warp runs its kernels on the CPU). :meth:`mjrft.mjx.Sand.step` with such a model computes the kinematics with
``mjx.forward``, the granular wrench in JAX, and the step with ``mjx.step`` (docs/gpu.md).

For the hexapod walking the 2 Hz tripod (``sand``: ``mjrft.mjx.Sand`` on the hexapod's bed, the rigid bottom without
contacts, at the sand env's 0.5 ms; ``rigid``: ``hexapod_rigid`` at its 1 ms, MJX's contacts and solver) and each
number of worlds, both implementations compile one call of ``--steps`` steps of every world (``jax.lax.scan`` of
``jax.vmap`` of the step, each world's data made inside ``jax.vmap`` as MuJoCo Warp needs) and time it (median of
``--repeats`` after a warm-up call), interleaved; reported: physics steps/s of each, warp / JAX, and the largest
difference of the worlds' ``qpos`` after the call (float32).

    python benchmarks/mjx_warp.py [--worlds 1 8] [--steps 100] [--repeats 3] [--out benchmarks/results/mjx_warp_cpu.txt]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

RESULTS = Path(__file__).resolve().parent / "results"
OFFSETS = (0.0, 3.141592653589793, 0.0, 3.141592653589793, 0.0, 3.141592653589793)


def compiled_call(scene: str, impl: str, worlds: int, steps: int):
    """(compiled call, its arguments, compile seconds) of ``steps`` steps of ``worlds`` worlds."""
    import jax
    import jax.numpy as jnp
    import mujoco
    from mujoco import mjx

    import mjrft
    import mjrft.mjx as rmjx

    if scene == "sand":
        model = mujoco.MjModel.from_xml_path(mjrft.models.model_path("hexapod"))
        bottom = model.geom("bed_bottom").id
        model.geom_contype[bottom] = model.geom_conaffinity[bottom] = 0
        model.opt.timestep = 0.0005
        sand = rmjx.Sand(model)
        mx = sand.put_model(impl=impl)
        step, s0 = sand.step, sand.init()
    else:
        model = mujoco.MjModel.from_xml_path(mjrft.models.model_path("hexapod_rigid"))
        mx = mjx.put_model(model, impl=impl)
        step, s0 = (lambda m, d, s: (rmjx.step(m, d), s)), jnp.zeros(())
    offsets = jnp.asarray(OFFSETS)
    qpos = jnp.tile(jnp.asarray(model.qpos0, jnp.float32), (worlds, 1)).at[:, 0].add(
        jnp.linspace(-0.01, 0.01, worlds))
    if impl == "warp":
        data = jax.vmap(lambda q: mjx.make_data(model, impl="warp").replace(qpos=q))(qpos)
    else:
        d0 = mjx.make_data(mx)
        data = jax.vmap(lambda q: d0.replace(qpos=q))(qpos)
    state = jax.tree_util.tree_map(lambda a: jnp.broadcast_to(a, (worlds,) + a.shape), s0)

    def one(d, s):
        return step(mx, d.replace(ctrl=2 * jnp.pi * 2.0 * d.time + offsets), s)

    def run(d, s):
        return jax.lax.scan(lambda c, _: (jax.vmap(one)(*c), None), (d, s), None, length=steps)[0]

    t0 = time.perf_counter()
    compiled = jax.jit(run).lower(data, state).compile()
    return compiled, (data, state), time.perf_counter() - t0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--worlds", type=int, nargs="+", default=[1, 8])
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--out", default=None)
    args = parser.parse_args(argv)
    import jax
    import mujoco
    import numpy as np

    dev = jax.devices()[0]
    out = Path(args.out) if args.out else RESULTS / f"mjx_warp_{dev.platform}.txt"
    shown = argv if argv is not None else sys.argv[1:]
    header = [f"python benchmarks/mjx_warp.py {' '.join(shown)}".rstrip()]
    try:
        import warp

        from mujoco.mjx import warp as mjx_warp

        if not mjx_warp.WARP_INSTALLED:
            raise ImportError("mujoco.mjx.warp reports WARP_INSTALLED = False")
        warp.init()
        header.append(f"device: {dev.device_kind} ({dev.platform}); host {os.cpu_count()} cores; jax {jax.__version__}, "
                      f"mujoco {mujoco.__version__}, warp-lang {warp.__version__} (Warp devices: "
                      f"{', '.join(str(d) for d in warp.get_devices())}); float32; {args.steps} steps per call, median "
                      f"of {args.repeats}")
    except Exception as exc:  # the measured reason it cannot run here
        header.append(f"impl='warp' cannot run here: {type(exc).__name__}: {exc}")
        out.write_text("\n".join(header) + "\n")
        print("\n".join(header))
        return 1
    print("\n".join(header), flush=True)
    lines = [f"{'scene':<6} {'worlds':>6} {'jax steps/s':>12} {'warp steps/s':>12} {'warp / jax':>10} "
             f"{'compile jax s':>13} {'compile warp s':>14} {'max |dqpos|':>11}"]
    print(lines[0], flush=True)
    for scene in ("sand", "rigid"):
        for n in args.worlds:
            calls = {impl: compiled_call(scene, impl, n, args.steps) for impl in ("jax", "warp")}
            outs = {impl: c(*a) for impl, (c, a, _) in calls.items()}  # warm-up
            jax.block_until_ready(outs)
            times = {impl: [] for impl in calls}
            for _ in range(args.repeats):
                for impl, (c, a, _) in calls.items():
                    t = time.perf_counter()
                    jax.block_until_ready(c(*a))
                    times[impl].append(time.perf_counter() - t)
            rate = {impl: n * args.steps / statistics.median(ts) for impl, ts in times.items()}
            diff = float(np.abs(np.asarray(outs["jax"][0].qpos) - np.asarray(outs["warp"][0].qpos)).max())
            line = (f"{scene:<6} {n:>6} {rate['jax']:>12,.0f} {rate['warp']:>12,.0f} {rate['warp'] / rate['jax']:>10.3f} "
                    f"{calls['jax'][2]:>13.1f} {calls['warp'][2]:>14.1f} {diff:>11.2e}")
            print(line, flush=True)
            lines.append(line)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(header + [""] + lines) + "\n")
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

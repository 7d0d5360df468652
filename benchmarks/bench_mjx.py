"""Physics steps per second of the hexapod on sand in MJX (mjrft.mjx) against its rigid twin, by number of worlds.

Every world walks the open-loop 2 Hz tripod (hip servo targets advancing with the simulation time, tripod B half a
turn behind) from the hexapod's initial pose, perturbed per world. For each number of worlds and each scene:

* ``compile_s``: ``jit(...).lower(...).compile()`` of one call that runs ``--steps`` physics steps of every
  world (``jax.lax.scan`` of ``jax.vmap`` of the step);
* ``steps/s``: worlds x steps / wall time of that call (median of ``--repeats`` after a warm-up call), the
  physics steps of all worlds together;
* ``memory``: XLA's memory analysis of the compiled call (arguments + outputs + temporaries, MiB); on a GPU also
  the device's peak bytes in use.

Scenes: ``sand``: ``mjrft.mjx.Sand`` on the hexapod's granular bed (every element of the default robot, Li RFT with the rest memory;
the bed's rigid bottom, 30 cm down, without contacts as in :class:`mjrft.envs.hexapod_mjx.HexapodSandMJX`);
``rigid``: the same robot on ``hexapod_rigid`` (MJX's collision and constraint solver on a rigid plane);
``sand-cull``: ``sand`` with ``Sand(cull=K)`` (``--cull``, default 704: above the most elements the tripod at 1 to 5
Hz buries, ``benchmarks/results/buried_elements.txt``).
``--cpu-path`` also measures mjrft's CPU path on this machine: the numba kernel through
``GranularTerrain.step``, one process per core (``os.cpu_count()``), each stepping its own hexapod with the same
gait; its steps/s is the sum over the processes.

    python benchmarks/bench_mjx.py                                  # CPU JAX: 1..64 worlds, writes results
    python benchmarks/bench_mjx.py --worlds 1024 2048 4096 8192 16384 --steps 1000 --cpu-path   # on a GPU
    python benchmarks/bench_mjx.py --worlds 1024 2048 4096 8192 16384 --rigid-worlds 1024 4096 16384 \
        --steps 200 --repeats 2 --cpu-path      # the run of results/bench_mjx_gpu.txt (docs/gpu.md)

Writes ``benchmarks/results/bench_mjx_<platform>.txt`` (and ``.json``) unless ``--out`` says otherwise. On a GPU the
script leaves XLA's memory preallocation at ``XLA_PYTHON_CLIENT_MEM_FRACTION`` = 0.6 unless it is set (see
docs/gpu.md: a kernel launch needs device memory outside XLA's pool).
"""

from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import os
import platform
import statistics
import sys
import time
from pathlib import Path

os.environ.setdefault("XLA_PYTHON_CLIENT_MEM_FRACTION", "0.6")

RESULTS = Path(__file__).resolve().parent / "results"
OFFSETS = (0.0, 3.141592653589793, 0.0, 3.141592653589793, 0.0, 3.141592653589793)  # lf lm lr rf rm rr


def scene(kind: str, cull=None):
    """(mjx model, step function (m, d, s) -> (d, s), initial per-world state, mujoco model) of a scene."""
    import jax.numpy as jnp
    import mujoco
    from mujoco import mjx

    import mjrft
    import mjrft.mjx as rmjx

    if kind in ("sand", "sand-cull"):
        model = mujoco.MjModel.from_xml_path(mjrft.models.model_path("hexapod"))
        bottom = model.geom("bed_bottom").id
        model.geom_contype[bottom] = model.geom_conaffinity[bottom] = 0
        sand = rmjx.Sand(model, cull=cull)
        return sand.put_model(), sand.step, sand.init(), model
    model = mujoco.MjModel.from_xml_path(mjrft.models.model_path("hexapod_rigid"))
    return mjx.put_model(model), (lambda m, d, s: (rmjx.step(m, d), s)), jnp.zeros(()), model


def batched_call(kind: str, worlds: int, steps: int, cull=None):
    """(compiled call, its arguments, mujoco model, compile seconds, memory MiB)."""
    import jax
    import jax.numpy as jnp
    import numpy as np
    from mujoco import mjx

    mx, step, s0, model = scene(kind, cull)
    offsets = jnp.asarray(OFFSETS)
    rng = np.random.default_rng(0)
    qpos = np.tile(model.qpos0, (worlds, 1))
    qpos[:, 0] += rng.uniform(-0.01, 0.01, worlds)
    d0 = mjx.make_data(mx)
    data = jax.vmap(lambda q: d0.replace(qpos=q))(jnp.asarray(qpos))
    state = jax.tree_util.tree_map(lambda a: jnp.broadcast_to(a, (worlds,) + a.shape), s0)

    def one(d, s):
        d = d.replace(ctrl=2 * jnp.pi * 2.0 * d.time + offsets)
        return step(mx, d, s)

    def run(data, state):
        def body(carry, _):
            return jax.vmap(one)(*carry), None

        return jax.lax.scan(body, (data, state), None, length=steps)[0]

    t0 = time.perf_counter()
    compiled = jax.jit(run).lower(data, state).compile()
    compile_s = time.perf_counter() - t0
    mem = None
    try:
        ma = compiled.memory_analysis()
        mem = (ma.argument_size_in_bytes + ma.output_size_in_bytes + ma.temp_size_in_bytes) / 2**20
    except Exception:  # not every backend reports it
        pass
    return compiled, (data, state), model, compile_s, mem


def measure(kind: str, worlds: int, steps: int, repeats: int, cull=None) -> dict:
    import jax

    compiled, args, model, compile_s, mem = batched_call(kind, worlds, steps, cull)
    out = compiled(*args)
    jax.block_until_ready(out)
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = compiled(*args)
        jax.block_until_ready(out)
        times.append(time.perf_counter() - t0)
    dev = jax.devices()[0]
    peak = None
    try:
        stats = dev.memory_stats()
        peak = stats.get("peak_bytes_in_use", None) / 2**20 if stats else None
    except Exception:
        pass
    d, s = out
    import numpy as np

    finite = bool(np.all(np.isfinite(np.asarray(d.qpos))))
    bad = int(np.sum(np.asarray(s.bad_body) != -1)) if kind != "rigid" else 0
    med = statistics.median(times)
    return {"scene": kind, "worlds": worlds, "steps": steps, "compile_s": round(compile_s, 2),
            "wall_s": round(med, 4), "steps_per_s": worlds * steps / med, "memory_mib": mem,
            "device_peak_mib": peak, "finite": finite, "bad_worlds": bad,
            "torso_z_mean": float(np.mean(np.asarray(d.qpos)[:, 2]))}


def _numba_hexapod():
    """(model, terrain, data, tripod phase offsets) of the hexapod on the numba path."""
    import mujoco
    import numpy as np

    import mjrft

    model = mujoco.MjModel.from_xml_path(mjrft.models.model_path("hexapod"))
    return model, mjrft.GranularTerrain(model), mujoco.MjData(model), np.array(OFFSETS)


def _cpu_warm_up() -> None:
    """Walk 1 s of simulated tripod on the numba path, compiling and caching every kernel the gait reaches."""
    import numpy as np

    model, terrain, data, off = _numba_hexapod()
    while data.time < 1.0:
        data.ctrl[:] = 2 * np.pi * 2.0 * data.time + off
        terrain.step(data, 10)


def _cpu_worker(seconds: float, queue) -> None:
    """Step the tripod on the numba path for ``seconds`` of wall time and put its steps/s on ``queue``."""
    import mujoco
    import numpy as np

    model, terrain, data, off = _numba_hexapod()
    n = 0
    terrain.step(data, 10)  # compiled kernels loaded
    t0 = time.perf_counter()
    while time.perf_counter() - t0 < seconds:
        data.ctrl[:] = 2 * np.pi * 2.0 * data.time + off
        terrain.step(data, 10)
        n += 10
        if data.time > 5.0:  # keep walking on fresh sand near the start
            mujoco.mj_resetData(model, data)
            terrain.reset()
    queue.put(n / (time.perf_counter() - t0))


def cpu_path(seconds: float = 10.0) -> dict:
    """Physics steps/s of the numba path with one process per core, all running at once."""
    cores = os.cpu_count() or 1
    ctx = mp.get_context("spawn")
    queue = ctx.Queue()
    # one process first fills numba's cache: a kernel compiled in the timed window would be counted as stepping
    warm = ctx.Process(target=_cpu_warm_up)
    warm.start()
    warm.join()
    if warm.exitcode != 0:
        raise RuntimeError(f"the numba path's warm-up process failed (exit code {warm.exitcode})")
    procs = [ctx.Process(target=_cpu_worker, args=(seconds, queue)) for _ in range(cores)]
    for p in procs:
        p.start()
    rates = [queue.get() for _ in procs]
    for p in procs:
        p.join()
    return {"processes": cores, "steps_per_s": sum(rates), "per_process": statistics.mean(rates)}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--worlds", type=int, nargs="+", default=None,
                        help="numbers of worlds (default: 1 4 16 64 on a CPU, 1024 ... 16384 on a GPU)")
    parser.add_argument("--steps", type=int, default=None, help="physics steps per timed call (CPU 100, GPU 1000)")
    parser.add_argument("--repeats", type=int, default=3, help="timed calls per point (median)")
    parser.add_argument("--scenes", nargs="+", default=["sand", "rigid", "sand-cull"],
                        choices=["sand", "rigid", "sand-cull"])
    parser.add_argument("--rigid-worlds", type=int, nargs="+", default=None,
                        help="numbers of worlds of the rigid scene (default: those of --worlds); its contact solver "
                             "makes it the slow scene at many worlds")
    parser.add_argument("--cull", type=int, default=704, help="K of the sand-cull scene: Sand(cull=K) evaluates at "
                                                               "most K buried elements per world (default 704)")
    parser.add_argument("--cpu-path", action="store_true", help="also the numba path, one process per core")
    parser.add_argument("--cpu-seconds", type=float, default=10.0, help="seconds of the CPU path per process")
    parser.add_argument("--out", default=None, help="results file (.txt; a .json is written beside it)")
    args = parser.parse_args(argv)
    for name in ("steps", "repeats", "cull"):
        v = getattr(args, name)
        if v is not None and v < 1:
            parser.error(f"--{name} must be >= 1, got {v}")
    for name in ("worlds", "rigid_worlds"):
        v = getattr(args, name)
        if v is not None and min(v) < 1:
            parser.error(f"--{name.replace('_', '-')} must be >= 1, got {v}")

    import jax

    dev = jax.devices()[0]
    gpu = dev.platform != "cpu"
    worlds = args.worlds or ([1024, 2048, 4096, 8192, 16384] if gpu else [1, 4, 16, 64])
    steps = args.steps or (1000 if gpu else 100)
    out = Path(args.out) if args.out else RESULTS / f"bench_mjx_{dev.platform}.txt"
    import mujoco

    header = [f"python benchmarks/bench_mjx.py {' '.join(argv if argv is not None else sys.argv[1:])}".rstrip(),
              f"device: {dev.device_kind} ({dev.platform}), {len(jax.devices())} device(s); host"
              f" {os.cpu_count()} cores; jax {jax.__version__}, mujoco {mujoco.__version__}, "
              f"float{'64' if jax.config.jax_enable_x64 else '32'}; {steps} physics steps per call, median of "
              f"{args.repeats}"]
    print("\n".join(header), flush=True)
    rows = []
    lines = [f"{'scene':<9} {'worlds':>7} {'steps/s':>12} {'compile s':>10} {'memory MiB':>11} {'peak MiB':>9} "
             f"{'finite':>6} {'bad':>4} {'torso z':>8}"]
    print(lines[0], flush=True)
    rigid_worlds = set(args.rigid_worlds or worlds) if "rigid" in args.scenes else set()
    for n in sorted(set(worlds) | rigid_worlds):
        for kind in args.scenes:
            if n not in (rigid_worlds if kind == "rigid" else worlds):
                continue
            try:
                r = measure(kind, n, steps, args.repeats, args.cull if kind == "sand-cull" else None)
            except Exception as exc:  # an out-of-memory or launch failure is a result too
                r = {"scene": kind, "worlds": n, "error": f"{type(exc).__name__}: {str(exc).splitlines()[0][:200]}"}
            rows.append(r)
            if "error" in r:
                line = f"{kind:<9} {n:>7} failed: {r['error']}"
            else:
                mem = f"{r['memory_mib']:.1f}" if r["memory_mib"] is not None else "n/a"
                peak = f"{r['device_peak_mib']:.0f}" if r["device_peak_mib"] is not None else "n/a"
                line = (f"{kind:<9} {n:>7} {r['steps_per_s']:>12,.0f} {r['compile_s']:>10.1f} {mem:>11} {peak:>9} "
                        f"{str(r['finite']):>6} {r['bad_worlds']:>4} {r['torso_z_mean']:>8.4f}")
            print(line, flush=True)
            lines.append(line)
    ratios = []
    for n in worlds:
        s = next((r for r in rows if r["scene"] == "sand" and r["worlds"] == n and "error" not in r), None)
        g = next((r for r in rows if r["scene"] == "rigid" and r["worlds"] == n and "error" not in r), None)
        c = next((r for r in rows if r["scene"] == "sand-cull" and r["worlds"] == n and "error" not in r), None)
        if s and g:
            ratios.append(f"sand / rigid at {n} worlds: {s['steps_per_s'] / g['steps_per_s']:.2f}")
        if s and c:
            ratios.append(f"sand-cull / sand at {n} worlds: {c['steps_per_s'] / s['steps_per_s']:.2f}")
    cpu = None
    if args.cpu_path:
        cpu = cpu_path(args.cpu_seconds)
        best = max((r for r in rows if r["scene"] == "sand" and "error" not in r), key=lambda r: r["steps_per_s"],
                   default=None)
        ratios.append(f"CPU path (numba, {cpu['processes']} processes): {cpu['steps_per_s']:,.0f} steps/s "
                      f"({cpu['per_process']:,.0f} per process)")
        if best:
            ratios.append(f"MJX sand at {best['worlds']} worlds / CPU path: {best['steps_per_s'] / cpu['steps_per_s']:.2f}")
    for line in ratios:
        print(line)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(header + [""] + lines + [""] + ratios) + "\n")
    out.with_suffix(".json").write_text(json.dumps({"header": header, "rows": rows, "cpu_path": cpu}, indent=2) + "\n")
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

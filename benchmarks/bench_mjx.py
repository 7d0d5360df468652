"""Sand in MJX (mjrft.mjx) against the rigid twin and against no floor at all, per scene at its own stable timestep.

For each scene (``hexapod``, ``go2``, ``humanoid``) and each row (a variant of the scene at its own timestep), one
process per row (so that each row's peak memory is its own) compiles one call that runs ``--window`` simulated
seconds of every world (``jax.lax.scan`` of ``jax.vmap`` of the step) and times it, median of ``--repeats`` after a
warm-up call, in two windows:

* ``landing``: from the initial pose (the robot dropped onto the ground, the legs entering the sand);
* ``steady``: from the state after ``--settle`` simulated seconds (walking: the hexapod's 2 Hz tripod, the Go2's
  1.5 Hz trot of ``benchmarks/bench_go2.py`` from 0.5 s on; the humanoid holds its standing pose).

Reported per row and window: physics steps per second at the row's timestep (all worlds together) and simulated
seconds per wall second (worlds x window / wall time); per row: the compile time, XLA's memory analysis of the
compiled call (arguments + outputs + temporaries), the row's peak memory (on a GPU the device's peak bytes in
use, on a CPU the process's peak resident memory, which includes the Python and JAX runtime), and what the
guards flagged (worlds with a stability flag, with a range flag, non-finite), so that "stable" is checked.

Rows (timesteps per scene in ``SCENES``):

* ``sand``: ``mjrft.mjx.Sand`` with the explicit granular step at the scene's stable timestep (``sand_dt``: the
  hexapod env's 0.5 ms, the Go2's 0.5 ms, the humanoid's 1 ms), guards on;
* ``sand-noguards``: the same with ``guards=False`` (the guards' cost);
* ``sand-implicit``: ``implicit=True`` at the model's own timestep (the implicit step's cost, per step and per
  simulated second);
* ``sand-auto``: ``Sand.auto_step`` at the model's own timestep (the automatic sub-steps' cost);
* ``rigid``: the robot on its rigid floor (MJX's collision and constraint solver) at the rigid env's timestep with
  MuJoCo's default solver settings (``iterations`` 100, ``ls_iterations`` 50);
* ``rigid-tuned``: the same with MuJoCo Playground's settings (``iterations`` 4, ``ls_iterations`` 8);
* ``rigid-own``: the Go2 with its MJX file's own settings (``iterations`` 1, ``ls_iterations`` 5);
* ``nofloor``: MJX's step of the sand scene's robot with no floor at all (it falls freely) at ``sand_dt``: the
  least an add-on can cost;
* ``sand-cull`` (``--cull K``, hexapod): ``Sand(cull=K)``.

The summary prints, per scene and window, per simulated second: sand / rigid-tuned, sand / rigid, sand-implicit /
rigid-tuned, sand-auto / rigid-tuned; per physics step: sand / nofloor (the add-on's overhead, the time of a step
over that of a step without floor), the guards' cost (sand-noguards steps/s over sand's, minus 1) and the implicit
step's cost per step (sand steps/s over sand-implicit's).
``--cpu-path`` also measures mjrft's CPU path (numba, ``GranularTerrain.step``) on the hexapod, one process per
core, at the sand env's 0.5 ms.

    python benchmarks/bench_mjx.py                      # CPU JAX: 8 worlds, every scene and row, writes results
    python benchmarks/bench_mjx.py --worlds 1024 4096 16384 --window 0.2 --settle 1.0   # on a GPU

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
import subprocess
import sys
import time
from pathlib import Path

os.environ.setdefault("XLA_PYTHON_CLIENT_MEM_FRACTION", "0.6")

RESULTS = Path(__file__).resolve().parent / "results"
OFFSETS = (0.0, 3.141592653589793, 0.0, 3.141592653589793, 0.0, 3.141592653589793)  # lf lm lr rf rm rr
#: per scene: the explicit sand step's stable timestep, the model's own, the rigid env's (s)
SCENES = {
    "hexapod": {"sand_dt": 0.0005, "own_dt": 0.001, "rigid_dt": 0.001},
    "go2": {"sand_dt": 0.0005, "own_dt": 0.002, "rigid_dt": 0.002},
    "humanoid": {"sand_dt": 0.001, "own_dt": 0.001, "rigid_dt": 0.001},
}
ROWS = ("sand", "sand-noguards", "sand-implicit", "sand-auto", "rigid", "rigid-tuned", "rigid-own", "nofloor",
        "sand-cull")
DEFAULT_SOLVER = (100, 50)  # MuJoCo's defaults: iterations, ls_iterations
TUNED_SOLVER = (4, 8)  # MuJoCo Playground's locomotion settings
GO2_TROT_START = 0.5  # s: the Go2 stands, then trots (benchmarks/bench_go2.py)


def row_dt(scene: str, row: str) -> float:
    s = SCENES[scene]
    if row in ("sand-implicit", "sand-auto"):
        return s["own_dt"]
    if row.startswith("rigid"):
        return s["rigid_dt"]
    return s["sand_dt"]


def _go2_path() -> str:
    import mjrft.models

    return os.path.join(os.path.dirname(mjrft.models.__file__), "third_party", "unitree_go2", "scene_mjx.xml")


def build(scene: str, row: str, cull: int):
    """(mujoco model, mjx model, step (m, d, s) -> (d, s), initial state, qpos0, controller (d) -> ctrl, info)."""
    import jax.numpy as jnp
    import mujoco
    from mujoco import mjx

    import mjrft
    import mjrft.mjx as rmjx

    rigid = row.startswith("rigid")
    if scene == "go2":
        model = mujoco.MjModel.from_xml_path(_go2_path())
        home = model.key("home")
        qpos, ctrl0 = home.qpos.copy(), home.ctrl.copy()
        kw = {"medium": "poppy_cp", "floor": "auto"}
    else:
        name = {"hexapod": "hexapod", "humanoid": "humanoid"}[scene] + ("_rigid" if rigid else "")
        model = mujoco.MjModel.from_xml_path(mjrft.models.model_path(name))
        if not rigid:  # the bed's rigid bottom without contacts, as the MJX env
            bottom = model.geom("bed_bottom").id
            model.geom_contype[bottom] = model.geom_conaffinity[bottom] = 0
        qpos, ctrl0 = model.qpos0.copy(), None
        kw = {}
    model.opt.timestep = row_dt(scene, row)
    info = {"solver": (int(model.opt.iterations), int(model.opt.ls_iterations))}
    if rigid:
        if row == "rigid":
            model.opt.iterations, model.opt.ls_iterations = DEFAULT_SOLVER
        elif row == "rigid-tuned":
            model.opt.iterations, model.opt.ls_iterations = TUNED_SOLVER
        info["solver"] = (int(model.opt.iterations), int(model.opt.ls_iterations))
        mx = mjx.put_model(model)
        step, state = (lambda m, d, s: (rmjx.step(m, d), s)), jnp.zeros(())
    else:
        sand = rmjx.Sand(model, implicit=row == "sand-implicit", guards=row != "sand-noguards",
                         cull=cull if row == "sand-cull" else None, **kw)
        info["elements"] = sand.n_elements
        mx = sand.put_model()
        state = sand.init()
        if row == "nofloor":
            step, state = (lambda m, d, s: (rmjx.step(m, d), s)), jnp.zeros(())
        elif row == "sand-auto":
            step = sand.auto_step
        else:
            step = sand.step
    if scene == "hexapod":
        offsets = jnp.asarray(OFFSETS)

        def controller(d):
            return 2 * jnp.pi * 2.0 * d.time + offsets
    elif scene == "go2":
        home_ctrl = jnp.asarray(ctrl0).reshape(4, 3)
        pairs = jnp.array([0.0, jnp.pi, jnp.pi, 0.0])

        def controller(d):  # bench_go2.trot_ctrl (stride 0.3 rad, lift 0.8 rad, 1.5 Hz) after standing 0.5 s
            phase = 2 * jnp.pi * 1.5 * d.time + pairs
            trot = home_ctrl.at[:, 1].add(0.3 * jnp.cos(phase)).at[:, 2].add(-0.8 * jnp.maximum(jnp.sin(phase), 0.0))
            return jnp.where(d.time < GO2_TROT_START, home_ctrl, trot).ravel()
    else:
        def controller(d):
            return jnp.zeros(model.nu, d.qpos.dtype)  # hold the initial (standing) pose
    return model, mx, step, state, qpos, controller, info


def run_row(scene: str, row: str, worlds: int, window: float, settle: float, repeats: int, cull: int,
            steps: int | None = None) -> dict:
    """Measure one row in this process (see the module docstring); ``steps``: physics steps per call instead of
    ``window`` simulated seconds (then ``settle`` is rounded to whole calls)."""
    import jax
    import jax.numpy as jnp
    import numpy as np
    from mujoco import mjx

    model, mx, step, s0, qpos0, controller, info = build(scene, row, cull)
    dt = float(model.opt.timestep)
    steps = int(steps) if steps else int(round(window / dt))
    window = steps * dt
    rng = np.random.default_rng(0)
    qpos = np.tile(qpos0, (worlds, 1))
    qpos[:, 0] += rng.uniform(-0.01, 0.01, worlds)
    d0 = mjx.make_data(mx)
    data = jax.vmap(lambda q: d0.replace(qpos=q))(jnp.asarray(qpos, d0.qpos.dtype))
    state = jax.tree_util.tree_map(lambda a: jnp.broadcast_to(a, (worlds,) + a.shape), s0)

    def one(d, s):
        return step(mx, d.replace(ctrl=controller(d)), s)

    def run(data, state):
        return jax.lax.scan(lambda c, _: (jax.vmap(one)(*c), None), (data, state), None, length=steps)[0]

    t0 = time.perf_counter()
    compiled = jax.jit(run).lower(data, state).compile()
    compile_s = time.perf_counter() - t0
    mem = None
    try:
        ma = compiled.memory_analysis()
        mem = (ma.argument_size_in_bytes + ma.output_size_in_bytes + ma.temp_size_in_bytes) / 2**20
    except Exception:  # not every backend reports it
        pass

    def timed(start):
        jax.block_until_ready(compiled(*start))  # warm-up
        times = []
        for _ in range(repeats):
            t = time.perf_counter()
            out = compiled(*start)
            jax.block_until_ready(out)
            times.append(time.perf_counter() - t)
        wall = statistics.median(times)
        return {"wall_s": wall, "steps_per_s": worlds * steps / wall, "sim_s_per_s": worlds * steps * dt / wall}, out

    landing, _ = timed((data, state))
    start = (data, state)
    for _ in range(int(round(settle / window))):
        start = compiled(*start)
    steady, out = timed(start)
    d, s = out
    flags = {"stability": 0, "range": 0, "nonfinite": 0}
    substeps = None
    if hasattr(s, "bad_body"):
        flags["nonfinite"] = int(np.sum(np.asarray(s.bad_body) != -1))
        if s.guard_count is not None:
            count = np.asarray(s.guard_count)
            flags["stability"] = int(np.sum(count[:, :3].sum(axis=1) > 0))
            flags["range"] = int(np.sum(count[:, 3:].sum(axis=1) > 0))
            if row == "sand-auto":
                substeps = float(np.mean(np.asarray(s.substeps)))
    dev = jax.devices()[0]
    peak, peak_kind = None, None
    try:
        stats = dev.memory_stats()
        if stats and stats.get("peak_bytes_in_use") is not None:
            peak, peak_kind = stats["peak_bytes_in_use"] / 2**20, "device"
    except Exception:
        pass
    if peak is None:
        import resource

        peak, peak_kind = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, "process RSS"
    return {"scene": scene, "row": row, "worlds": worlds, "dt": dt, "steps": steps, "compile_s": round(compile_s, 2),
            "landing": landing, "steady": steady, "memory_mib": mem, "peak_mib": peak, "peak_kind": peak_kind,
            "flags": flags, "substeps_last": substeps, "finite": bool(np.all(np.isfinite(np.asarray(d.qpos)))),
            "height": float(np.mean(np.asarray(d.qpos)[:, 2])), **info}


def _numba_hexapod():
    """(model, terrain, data, tripod phase offsets) of the hexapod on the numba path at the sand env's 0.5 ms."""
    import mujoco
    import numpy as np

    import mjrft

    model = mujoco.MjModel.from_xml_path(mjrft.models.model_path("hexapod"))
    model.opt.timestep = SCENES["hexapod"]["sand_dt"]
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
    return {"processes": cores, "steps_per_s": sum(rates), "per_process": statistics.mean(rates),
            "sim_s_per_s": sum(rates) * SCENES["hexapod"]["sand_dt"]}


def _in_process(args) -> dict:
    """Run one row in a fresh Python process (its own peak memory) and return its result."""
    cmd = [sys.executable, __file__, "--row", args.scene_row[0], args.scene_row[1]] + [
        "--worlds", str(args.worlds[0]), "--window", str(args.window), "--settle", str(args.settle),
        "--repeats", str(args.repeats), "--cull", str(args.cull)] + (["--steps", str(args.steps)] if args.steps else [])
    proc = subprocess.run(cmd, capture_output=True, text=True)
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("{")]
    if proc.returncode != 0 or not lines:
        err = (proc.stderr.strip().splitlines() or ["(no output)"])[-1]
        return {"scene": args.scene_row[0], "row": args.scene_row[1], "worlds": args.worlds[0],
                "error": f"exit {proc.returncode}: {err[:300]}"}
    return json.loads(lines[-1])


def _ratio(a, b):
    return a / b if a and b else None


def summary(rows: list[dict], scenes, worlds) -> list[str]:
    """The ratios of the module docstring, per scene, number of worlds and window."""
    out = []
    get = {(r["scene"], r["row"], r["worlds"]): r for r in rows if "error" not in r}
    for scene in scenes:
        for n in worlds:
            r = {row: get.get((scene, row, n)) for row in ROWS}
            for window in ("landing", "steady"):
                def sim(row):
                    return r[row][window]["sim_s_per_s"] if r.get(row) else None

                def sps(row):
                    return r[row][window]["steps_per_s"] if r.get(row) else None
                parts = []
                for num, den in (("sand", "rigid-tuned"), ("sand", "rigid"), ("sand", "rigid-own"),
                                 ("sand-implicit", "rigid-tuned"), ("sand-auto", "rigid-tuned")):
                    v = _ratio(sim(num), sim(den))
                    if v is not None:
                        parts.append(f"{num}/{den} {v:.2f}")
                line = f"{scene:<8} {n:>6} worlds {window:<7} per simulated second: " + ", ".join(parts)
                per_step = []
                v = _ratio(sps("nofloor"), sps("sand"))
                if v is not None:
                    per_step.append(f"sand step / nofloor step {v:.2f}")
                v = _ratio(sps("sand-noguards"), sps("sand"))
                if v is not None:
                    per_step.append(f"guards' cost {100 * (v - 1):+.1f} %")
                v = _ratio(sps("sand"), sps("sand-implicit"))
                if v is not None:
                    per_step.append(f"implicit step / explicit step {v:.2f}")
                v = _ratio(sps("sand-cull"), sps("sand"))
                if v is not None:
                    per_step.append(f"sand-cull / sand {v:.2f}")
                if parts:
                    out.append(line)
                if per_step:
                    out.append(f"{'':<8} {'':>6} {'':6} {'':<7} per physics step: " + ", ".join(per_step))
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--worlds", type=int, nargs="+", default=None,
                        help="numbers of worlds (default: 8 on a CPU, 1024 4096 16384 on a GPU)")
    parser.add_argument("--scenes", nargs="+", default=list(SCENES), choices=list(SCENES))
    parser.add_argument("--rows", nargs="+", default=None, choices=list(ROWS),
                        help="rows (default: every row that applies; sand-cull with the hexapod only)")
    parser.add_argument("--window", type=float, default=None,
                        help="simulated seconds per timed call (default: 0.1 on a CPU, 0.2 on a GPU)")
    parser.add_argument("--steps", type=int, default=None,
                        help="physics steps per timed call at each row's timestep, instead of --window")
    parser.add_argument("--settle", type=float, default=1.0, help="simulated seconds before the steady window")
    parser.add_argument("--repeats", type=int, default=3, help="timed calls per window (median)")
    parser.add_argument("--rigid-worlds", type=int, nargs="+", default=None,
                        help="numbers of worlds of the rigid rows (default: those of --worlds)")
    parser.add_argument("--cull", type=int, default=704, help="K of the sand-cull row: Sand(cull=K) (hexapod)")
    parser.add_argument("--cpu-path", action="store_true", help="also the numba path, one process per core")
    parser.add_argument("--cpu-seconds", type=float, default=10.0, help="seconds of the CPU path per process")
    parser.add_argument("--out", default=None, help="results file (.txt; a .json is written beside it)")
    parser.add_argument("--row", nargs=2, metavar=("SCENE", "ROW"), dest="scene_row", default=None,
                        help=argparse.SUPPRESS)  # one row in this process, its result as JSON on stdout
    args = parser.parse_args(argv)
    for name in ("repeats", "cull"):
        if getattr(args, name) < 1:
            parser.error(f"--{name} must be >= 1, got {getattr(args, name)}")
    for name in ("window", "settle"):
        v = getattr(args, name)
        if v is not None and not v > 0 and not (name == "settle" and v == 0):
            parser.error(f"--{name} must be > 0, got {v}")
    for name in ("worlds", "rigid_worlds"):
        v = getattr(args, name)
        if v is not None and min(v) < 1:
            parser.error(f"--{name.replace('_', '-')} must be >= 1, got {v}")
    if args.steps is not None and args.steps < 1:
        parser.error(f"--steps must be >= 1, got {args.steps}")

    import jax

    dev = jax.devices()[0]
    gpu = dev.platform != "cpu"
    worlds = args.worlds or ([1024, 4096, 16384] if gpu else [8])
    args.worlds = worlds
    args.window = args.window or (0.2 if gpu else 0.1)
    if args.scene_row is not None:
        scene, row = args.scene_row
        print(json.dumps(run_row(scene, row, worlds[0], args.window, args.settle, args.repeats, args.cull, args.steps)))
        return 0
    out = Path(args.out) if args.out else RESULTS / f"bench_mjx_{dev.platform}.txt"
    import mujoco

    shown = argv if argv is not None else sys.argv[1:]
    header = [f"python benchmarks/bench_mjx.py {' '.join(shown)}".rstrip(),
              f"device: {dev.device_kind} ({dev.platform}), {len(jax.devices())} device(s); host {os.cpu_count()} "
              f"cores ({platform.machine()}, load average {os.getloadavg()[0]:.1f} at the start); jax {jax.__version__}, "
              f"mujoco {mujoco.__version__}, "
              f"float{'64' if jax.config.jax_enable_x64 else '32'}; windows of "
              f"{f'{args.steps} physics steps' if args.steps else f'{args.window:g} simulated s'} "
              f"(landing: from the start; steady: after {args.settle:g} s), median of {args.repeats}; "
              "one process per row",
              "timesteps (s): " + "; ".join(f"{k} sand {v['sand_dt']:g}, own {v['own_dt']:g}, rigid {v['rigid_dt']:g}"
                                            for k, v in SCENES.items())]
    print("\n".join(header), flush=True)
    lines = [f"{'scene':<8} {'row':<13} {'worlds':>6} {'dt ms':>5} {'landing steps/s':>15} {'sim s/s':>8} "
             f"{'steady steps/s':>14} {'sim s/s':>8} {'compile s':>9} {'XLA MiB':>8} {'peak MiB':>9} "
             f"{'stab':>4} {'range':>5} {'nan':>3} {'k':>4} {'z m':>6}"]
    print(lines[0], flush=True)
    rows = []
    rigid_worlds = set(args.rigid_worlds or worlds)
    for n in sorted(set(worlds) | rigid_worlds):
        for scene in args.scenes:
            for row in args.rows or ROWS:
                if (row == "rigid-own" and scene != "go2") or (row == "sand-cull" and scene != "hexapod"):
                    continue
                if n not in (rigid_worlds if row.startswith("rigid") else worlds):
                    continue
                sub = argparse.Namespace(**vars(args))
                sub.scene_row, sub.worlds = (scene, row), [n]
                r = _in_process(sub)
                rows.append(r)
                if "error" in r:
                    line = f"{scene:<8} {row:<13} {n:>6} failed: {r['error']}"
                else:
                    la, st, f = r["landing"], r["steady"], r["flags"]
                    mem = f"{r['memory_mib']:.1f}" if r["memory_mib"] is not None else "n/a"
                    k = f"{r['substeps_last']:.1f}" if r.get("substeps_last") is not None else ""
                    line = (f"{scene:<8} {row:<13} {n:>6} {1e3 * r['dt']:>5.2g} {la['steps_per_s']:>15,.0f} "
                            f"{la['sim_s_per_s']:>8.3f} {st['steps_per_s']:>14,.0f} {st['sim_s_per_s']:>8.3f} "
                            f"{r['compile_s']:>9.1f} {mem:>8} {r['peak_mib']:>9.0f} {f['stability']:>4} "
                            f"{f['range']:>5} {f['nonfinite']:>3} {k:>4} {r['height']:>6.3f}")
                print(line, flush=True)
                lines.append(line)
    peak_kind = next((r["peak_kind"] for r in rows if "peak_kind" in r), "n/a")
    notes = [f"peak MiB: {peak_kind} peak of the row's own process; XLA MiB: the compiled call's arguments + outputs "
             "+ temporaries; stab / range / nan: worlds whose guards flagged a stability limit or chatter / a law's "
             "depth or speed range / a non-finite state, by the end of the steady window; k: sub-steps of "
             "sand-auto's last step (mean over worlds); z: mean base height at the end"]
    ratios = summary(rows, args.scenes, sorted(set(worlds) | rigid_worlds))
    cpu = None
    if args.cpu_path:
        cpu = cpu_path(args.cpu_seconds)
        ratios.append(f"CPU path (numba, hexapod at 0.5 ms, {cpu['processes']} processes): {cpu['steps_per_s']:,.0f} "
                      f"steps/s ({cpu['per_process']:,.0f} per process), {cpu['sim_s_per_s']:.2f} simulated s/s")
        best = max((r for r in rows if r.get("scene") == "hexapod" and r.get("row") == "sand" and "error" not in r),
                   key=lambda r: r["steady"]["sim_s_per_s"], default=None)
        if best:
            ratios.append(f"MJX hexapod sand at {best['worlds']} worlds (steady) / CPU path: "
                          f"{best['steady']['sim_s_per_s'] / cpu['sim_s_per_s']:.2f}")
    for line in notes + ratios:
        print(line)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(header + [""] + lines + [""] + notes + [""] + ratios) + "\n")
    out.with_suffix(".json").write_text(json.dumps({"header": header, "rows": rows, "cpu_path": cpu}, indent=2) + "\n")
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

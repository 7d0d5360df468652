"""The implicit granular step in MJX (``mjrft.mjx.Sand(..., implicit=True)``): agreement with the CPU path's implicit
step, the Go2 at its own 2 ms step, and the cost against the explicit step.

* ``agreement``: the hexapod walks the 2 Hz tripod for 0.6 s on the CPU path with the implicit step
  (``GranularTerrain(model, implicit=True)``, ``terrain.step(data, 1)``); every 50 steps the MjData before the
  step and the memory are taken, the step is replayed on a CPU implicit terrain and an explicit one, and one
  ``Sand.step`` (float64) runs from ``mjx.put_data`` of the same state with the same memory. Reported: the largest
  ``|MJX - CPU|`` of the applied wrench over the largest ``|CPU|`` (per state, the worst), of ``qvel`` after the
  step, and how far the implicit wrench is from the explicit one (the size of the correction being checked). For
  the rest memory (the hexapod's own settings) and the viscous mode (``yield_displacement=0``, ``v_eps=0.1``).
* ``go2``: MuJoCo Menagerie's Go2 (``scene_mjx.xml``, home keyframe, ``floor="auto"``, ``poppy_cp``) holding its
  home pose for 1.5 s at the model's 2 ms in MJX, float32, implicit and explicit: the net vertical granular force
  over the weight at every step of the last 0.2 s (mean, min, max), the trunk height, the feet's sinkage; and the
  CPU path's implicit step from the same state for its trunk height.
* ``cost``: the hexapod (bed bottom without contacts, as ``bench_mjx.py``) walking the tripod in 16 worlds on the
  host's JAX backend, float32: physics steps/s of ``jax.lax.scan`` over 100 steps of ``jax.vmap`` of
  ``Sand.step``, explicit and implicit, interleaved, median of ``--repeats`` after a warm-up call.

    python benchmarks/mjx_implicit.py [--repeats R] [--worlds N] [--out benchmarks/results/mjx_implicit.txt]
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
import warnings
from pathlib import Path

import mujoco
import numpy as np

import mjrft
import mjrft.models
from mjrft.mjx.compare import replay_steps, stand

RESULTS = Path(__file__).resolve().parent / "results"
GO2 = os.path.join(os.path.dirname(mjrft.models.__file__), "third_party", "unitree_go2", "scene_mjx.xml")
OFFSETS = np.array([0.0, np.pi, 0.0, np.pi, 0.0, np.pi])
MODES = {"rest memory": {}, "viscous (v_eps 0.1)": {"yield_displacement": 0.0, "v_eps": 0.1}}


def agreement(kw: dict, every: int = 50, count: int = 12) -> dict:
    """Largest relative differences of one MJX implicit step from the CPU's on replayed walking states."""
    import jax
    import jax.numpy as jnp
    from mujoco import mjx

    import mjrft.mjx as rmjx

    model = mujoco.MjModel.from_xml_path(mjrft.models.model_path("hexapod"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        states = replay_steps(model, kw, every * count, every, ctrl=lambda t: 2 * np.pi * 2 * t + OFFSETS)
        terrain = mjrft.GranularTerrain(model, implicit=True, **kw)
    ew = eq = corr = 0.0
    corrected = 0
    with jax.enable_x64(True):
        mx = mjx.put_model(model)
        sand = rmjx.Sand.from_terrain(terrain)
        step = jax.jit(sand.step)
        for before, u, fi, fe, qvel in states:
            d, s = step(mx, mjx.put_data(model, before), sand.init()._replace(u=jnp.asarray(u)))
            scale = np.abs(fi).max()
            ew = max(ew, float(np.abs(np.asarray(s.wrench) - fi).max() / scale))
            eq = max(eq, float(np.abs(np.asarray(d.qvel) - qvel).max() / np.abs(qvel).max()))
            c = float(np.abs(fe - fi).max() / scale)
            corr = max(corr, c)
            corrected += c > 1e-3
    return {"states": len(states), "wrench": ew, "qvel": eq, "correction": corr, "corrected": corrected}


def go2_stand(implicit: bool) -> dict:
    """The Go2 standing 1.5 s at 2 ms in MJX, float32."""
    import mjrft.mjx as rmjx

    m = mujoco.MjModel.from_xml_path(GO2)
    sand = rmjx.Sand(m, "poppy_cp", floor="auto", implicit=implicit)
    home = m.key("home")
    t0 = time.time()
    d, state, load = stand(sand, m, home.qpos, home.ctrl, 1.5)
    wall = time.time() - t0
    sand.check(state)
    rest = load[-int(round(0.2 / m.opt.timestep)):]
    calves = [m.body(f"{f}_calf").id for f in ("FL", "FR", "RL", "RR")]
    return {"dt": m.opt.timestep, "mean": rest.mean(), "min": rest.min(), "max": rest.max(),
            "z": float(d.qpos[2]), "feet": np.asarray(state.sinkage)[calves], "wall": wall}


def go2_cpu_height() -> float:
    """Trunk height (m) after the same 1.5 s on the CPU path's implicit step at 2 ms."""
    m = mujoco.MjModel.from_xml_path(GO2)
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key("home").id)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        terrain = mjrft.GranularTerrain(m, "poppy_cp", floor="auto", implicit=True)
        terrain.step(d, int(round(1.5 / m.opt.timestep)))
    return float(d.qpos[2])


def batched_call(implicit: bool, worlds: int, steps: int):
    """(compiled call of ``steps`` steps of ``worlds`` hexapods walking the tripod, its arguments, compile s)."""
    import jax
    import jax.numpy as jnp
    from mujoco import mjx

    import mjrft.mjx as rmjx

    model = mujoco.MjModel.from_xml_path(mjrft.models.model_path("hexapod"))
    bottom = model.geom("bed_bottom").id
    model.geom_contype[bottom] = model.geom_conaffinity[bottom] = 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sand = rmjx.Sand(model, implicit=implicit)
    mx = sand.put_model()
    offsets = jnp.asarray(OFFSETS)
    qpos = np.tile(model.qpos0, (worlds, 1))
    qpos[:, 0] += np.random.default_rng(0).uniform(-0.01, 0.01, worlds)
    d0 = mjx.make_data(mx)
    data = jax.vmap(lambda q: d0.replace(qpos=q))(jnp.asarray(qpos))
    states = jax.vmap(lambda _: sand.init())(jnp.arange(worlds))

    def one(d, s):
        return sand.step(mx, d.replace(ctrl=2 * jnp.pi * 2 * d.time + offsets), s)

    def run(data, states):
        return jax.lax.scan(lambda c, _: (jax.vmap(one)(*c), None), (data, states), None, length=steps)[0]

    t0 = time.time()
    call = jax.jit(run).lower(data, states).compile()
    return call, (data, states), time.time() - t0


def cost(worlds: int, steps: int, repeats: int) -> dict:
    """Steps/s of the explicit and the implicit step, interleaved."""
    import jax

    calls = {k: batched_call(k == "implicit", worlds, steps) for k in ("explicit", "implicit")}
    times = {k: [] for k in calls}
    for k, (call, args, _) in calls.items():
        jax.block_until_ready(call(*args))  # warm-up
    for _ in range(repeats):
        for k, (call, args, _) in calls.items():
            t0 = time.perf_counter()
            out = call(*args)
            jax.block_until_ready(out)
            times[k].append(time.perf_counter() - t0)
    finite = {k: bool(int(np.max(np.asarray(call(*args)[1].bad_body))) == -1) for k, (call, args, _) in calls.items()}
    return {k: {"steps_per_s": worlds * steps / statistics.median(times[k]), "compile": calls[k][2],
                "finite": finite[k]} for k in calls}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--worlds", type=int, default=16)
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--out", default=str(RESULTS / "mjx_implicit.txt"))
    args = ap.parse_args(argv)
    import jax

    lines = ["The implicit granular step in MJX (mjrft.mjx.Sand(..., implicit=True)); "
             f"JAX {jax.__version__} on {jax.default_backend()}, {os.cpu_count()} CPU cores", ""]
    lines.append("agreement with the CPU path's implicit step, hexapod walking the 2 Hz tripod, one step from each "
                 "replayed state, float64 (largest |MJX - CPU| / largest |CPU|)")
    for name, kw in MODES.items():
        r = agreement(kw)
        lines.append(f"  {name:<20} {r['states']} states: applied wrench {r['wrench']:.1e}  qvel after the step "
                     f"{r['qvel']:.1e}  (implicit vs explicit wrench up to {r['correction']:.1e}; "
                     f"{r['corrected']} states above 1e-3)")
    lines += ["", "Unitree Go2 standing 1.5 s from the home keyframe at the model's 2 ms, MJX float32 (net vertical "
              "granular force / weight at every step of the last 0.2 s; wall time includes compilation)"]
    for implicit in (True, False):
        r = go2_stand(implicit)
        feet = " ".join(f"{1e3 * x:.1f}" for x in r["feet"])
        lines.append(f"  {'implicit' if implicit else 'explicit':<9} mean {r['mean']:.5f}  min {r['min']:.5f}  "
                     f"max {r['max']:.5f}  trunk height {1e3 * r['z']:.1f} mm  feet sinkage {feet} mm  "
                     f"({r['wall']:.0f} s)")
    lines.append(f"  CPU path, implicit step at 2 ms: trunk height {1e3 * go2_cpu_height():.1f} mm")
    c = cost(args.worlds, args.steps, args.repeats)
    lines += ["", f"cost: hexapod, tripod gait, {args.worlds} worlds, {args.steps} steps per call, float32, median of "
              f"{args.repeats} interleaved calls"]
    for k, r in c.items():
        lines.append(f"  {k:<9} {r['steps_per_s']:>9,.0f} steps/s  (compile {r['compile']:.0f} s, finite "
                     f"{r['finite']})")
    lines.append(f"  implicit / explicit time per step: {c['explicit']['steps_per_s'] / c['implicit']['steps_per_s']:.2f}")
    text = "\n".join(lines) + "\n"
    print(text, end="")
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(text)


if __name__ == "__main__":
    main()

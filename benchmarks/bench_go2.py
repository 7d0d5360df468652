"""MuJoCo Menagerie's Unitree Go2 on sand: what the grains cost against its rigid floor, and how it stands and trots.

The robot is the MJX variant vendored under ``models/third_party/unitree_go2/`` (``scene_mjx.xml``: 23 collision
spheres, 12 position servos, a plane floor, 2 ms Euler steps), started from its ``home`` keyframe with the servos
holding the home pose. Three simulations at the model's own timestep are timed side by side (interleaved, CPU time
of this process so that other processes on a shared machine do not count, median of the repeats):

* ``sand``: ``GranularTerrain(model, "poppy_cp", floor="auto", implicit=True)`` stepped with ``terrain.step``
  (the floor's contacts removed, the implicit granular step: stable at 2 ms);
* ``sand explicit``: the same with ``implicit=False`` (past its stability limit at 2 ms: timed for the cost only);
* ``rigid``: the unchanged scene stepped with ``mujoco.mj_step`` (the robot on its rigid floor).

Two runs each: ``stand``, 1.5 s from the home keyframe holding the home pose (one call of ``n`` steps, no Python
per step); ``trot``, 0.5 s of standing then 2.5 s of a trot around the home pose (the diagonal pairs FL+RR and
FR+RL in antiphase at 1.5 Hz, thighs +-0.3 rad, knees flexed by up to 0.8 rad in swing, the targets set before
every step and only the step calls timed), the gait of ``tests/models/test_third_party_robots.py``.

Then the physics of the sand runs: the net vertical granular force over the weight at the end of the stand
(mean, min and max over the last 0.2 s), the feet's sinkage and the trunk's height, the distance the trot
covers, and with ``--mjx`` (needs ``mjrft[mjx]``) the same stand in MJX in float32 with the explicit granular
step at 2 ms and at 0.5 ms (``benchmarks/mjx_implicit.py`` runs MJX's implicit step at 2 ms).

    python benchmarks/bench_go2.py [--repeats R] [--mjx] [--out benchmarks/results/bench_go2.txt]
"""

from __future__ import annotations

import argparse
import os
import time
import warnings

import mujoco
import numpy as np

import mjrft
import mjrft.models

GO2 = os.path.join(os.path.dirname(mjrft.models.__file__), "third_party", "unitree_go2", "scene_mjx.xml")
MEDIUM = "poppy_cp"
STAND, SETTLE, TROT, REST = 1.5, 0.5, 2.5, 0.2  # s
FEET = ("FL", "FR", "RL", "RR")
VARIANTS = ("sand", "sand explicit", "rigid")


def trot_ctrl(m, t: float, stride: float = 0.3, lift: float = 0.8, freq: float = 1.5) -> np.ndarray:
    """Servo targets of the trot around the home pose (actuators FL, FR, RL, RR; hip, thigh, knee each)."""
    phase = 2 * np.pi * freq * t + np.array([0.0, np.pi, np.pi, 0.0])
    ctrl = m.key("home").ctrl.reshape(4, 3).copy()
    ctrl[:, 1] += stride * np.cos(phase)
    ctrl[:, 2] -= lift * np.maximum(np.sin(phase), 0.0)
    return ctrl.ravel()


def build(variant: str):
    """(model, data at the home keyframe, a step function ``step(n)``, the terrain or None)."""
    m = mujoco.MjModel.from_xml_path(GO2)
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key("home").id)
    if variant == "rigid":
        return m, d, (lambda n=1: mujoco.mj_step(m, d, n)), None
    terrain = mjrft.GranularTerrain(m, MEDIUM, floor="auto", implicit=variant == "sand")
    return m, d, (lambda n=1: terrain.step(d, n)), terrain


def weight(m) -> float:
    return float(m.body_subtreemass[0]) * -float(m.opt.gravity[2])


def stand(variant: str) -> tuple[float, int, dict]:
    """(CPU seconds, steps, the physics at the end) of the standing run."""
    m, d, step, terrain = build(variant)
    n = int(round(STAND / m.opt.timestep))
    t0 = time.process_time()
    step(n)
    spent = time.process_time() - t0
    return spent, n, {"z": float(d.qpos[2]), "finite": bool(np.all(np.isfinite(d.qpos)))}


def stand_load(variant: str) -> dict:
    """The standing run stepped one step at a time, recording the net vertical granular force over the weight."""
    m, d, step, terrain = build(variant)
    load = np.empty(int(round(STAND / m.opt.timestep)))
    for i in range(len(load)):
        step()
        load[i] = terrain.wrench[:, 2].sum() / weight(m)
    rest = load[-int(round(REST / m.opt.timestep)):]
    sink = terrain.sinkage()
    calves = [m.body(f"{f}_calf").id for f in FEET]
    return {"mean": rest.mean(), "min": rest.min(), "max": rest.max(), "peak": load.max(), "z": float(d.qpos[2]),
            "feet": sink[calves], "base": sink[m.body("base").id],
            "legs_share": terrain.wrench[calves, 2].sum() / weight(m), "elements": terrain.n_elements,
            "resolution": terrain.resolution}


def trot(variant: str, stride: float = 0.3) -> tuple[float, int, dict]:
    """(CPU seconds in the step calls, steps, the physics) of the settle-then-trot run."""
    m, d, step, terrain = build(variant)
    step(int(round(SETTLE / m.opt.timestep)))
    start, t0, spent = d.qpos[:3].copy(), d.time, 0.0
    n = int(round(TROT / m.opt.timestep))
    load = []
    for _ in range(n):
        d.ctrl[:] = trot_ctrl(m, d.time - t0, stride)
        c = time.process_time()
        step()
        spent += time.process_time() - c
        if terrain is not None:
            load.append(terrain.wrench[:, 2].sum() / weight(m))
    moved = d.qpos[:3] - start
    return spent, n, {"dx": moved[0], "dy": moved[1], "z": float(d.qpos[2]), "load": float(np.mean(load or [np.nan])),
                      "finite": bool(np.all(np.isfinite(d.qpos)))}


def mjx_stand(timestep: float) -> dict:
    """The standing run in MJX (float32) at ``timestep``: the load over the last 0.2 s, height and sinkage."""
    import mjrft.mjx as rmjx
    from mjrft.mjx.compare import stand

    m = mujoco.MjModel.from_xml_path(GO2)
    m.opt.timestep = timestep
    sand = rmjx.Sand(m, MEDIUM, floor="auto")
    home = m.key("home")
    t0 = time.time()
    d, state, load = stand(sand, m, home.qpos, home.ctrl, STAND)
    wall = time.time() - t0
    sand.check(state)
    rest = load[-int(round(REST / timestep)):]
    calves = [m.body(f"{f}_calf").id for f in FEET]
    return {"dt": timestep, "mean": rest.mean(), "min": rest.min(), "max": rest.max(), "z": float(d.qpos[2]),
            "feet": np.asarray(state.sinkage)[calves], "wall": wall}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=3, help="interleaved repeats, median reported (default 3)")
    ap.add_argument("--mjx", action="store_true", help="also the stand in MJX, float32, at 2 ms and 0.5 ms")
    ap.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "results",
                                                  "bench_go2.txt"), help="results file ('-': print only)")
    args = ap.parse_args(argv)

    warnings.simplefilter("ignore")  # the explicit variant's stability warnings, the depth range (reported below)
    for v in VARIANTS:  # compile the kernels before anything is timed
        build(v)[2](2)
    times = {(run, v): [] for run in ("stand", "trot") for v in VARIANTS}
    steps, phys = {}, {}
    for _ in range(args.repeats):
        for run, fn in (("stand", stand), ("trot", trot)):
            for v in VARIANTS:
                spent, n, p = fn(v)
                times[run, v].append(spent)
                steps[run], phys[run, v] = n, p
    load = stand_load("sand")
    load_explicit = stand_load("sand explicit")
    back = trot("sand", stride=-0.3)[2]

    m = mujoco.MjModel.from_xml_path(GO2)
    lines = [f"Unitree Go2 (MuJoCo Menagerie, MJX variant) on {MEDIUM}: CPU time per physics step at the model's "
             f"{m.opt.timestep * 1e3:g} ms, median of {args.repeats} interleaved repeats; {load['elements']} elements "
             f"of {load['resolution'] * 1e3:.1f} mm (resolution='auto'), weight {weight(m):.2f} N",
             "",
             f"{'run':<6} {'steps':>5} {'sand us':>8} {'explicit us':>11} {'rigid us':>8} {'sand/rigid':>10} "
             f"{'explicit/rigid':>14}"]
    for run in ("stand", "trot"):
        us = {v: 1e6 * float(np.median(times[run, v])) / steps[run] for v in VARIANTS}
        lines.append(f"{run:<6} {steps[run]:>5d} {us['sand']:>8.1f} {us['sand explicit']:>11.1f} {us['rigid']:>8.1f} "
                     f"{us['sand'] / us['rigid']:>10.2f} {us['sand explicit'] / us['rigid']:>14.2f}")
    lines += ["",
              "(sand: terrain.step with the implicit granular step; explicit: implicit=False; rigid: mj_step on the "
              "unchanged scene. sand/rigid > 1: the sand costs more than the rigid floor)",
              "",
              f"standing on sand for {STAND:g} s from the home keyframe (vertical granular force / weight over the "
              f"last {REST:g} s: mean, min, max; peak over the run)"]
    for name, r in (("implicit", load), ("explicit", load_explicit)):
        lines.append(f"  {name:<8} mean {r['mean']:.5f}  min {r['min']:.5f}  max {r['max']:.5f}  peak {r['peak']:.3f}"
                     f"  trunk height {r['z'] * 1e3:.1f} mm  feet sinkage {' '.join(f'{s * 1e3:.1f}' for s in r['feet'])}"
                     f" mm (FL FR RL RR)  trunk sinkage {r['base'] * 1e3:.1f} mm")
    lines.append(f"  the four calves carry {load['legs_share']:.4f} of the weight; on the rigid floor the trunk "
                 f"stands at {phys['stand', 'rigid']['z'] * 1e3:.1f} mm (home keyframe: 270 mm)")
    fwd, rig = phys["trot", "sand"], phys["trot", "rigid"]
    lines += ["",
              f"trot (1.5 Hz, thighs +-0.3 rad, knees up to 0.8 rad) for {TROT:g} s after {SETTLE:g} s of standing",
              f"  sand      dx {fwd['dx'] * 1e3:+.0f} mm  dy {fwd['dy'] * 1e3:+.0f} mm  ({fwd['dx'] / TROT:.3f} m/s)"
              f"  mean Fz/weight {fwd['load']:.4f}  finite {fwd['finite']}",
              f"  reversed  dx {back['dx'] * 1e3:+.0f} mm  dy {back['dy'] * 1e3:+.0f} mm  (thighs -0.3 rad: the gait "
              f"run backwards)  mean Fz/weight {back['load']:.4f}",
              f"  rigid     dx {rig['dx'] * 1e3:+.0f} mm  dy {rig['dy'] * 1e3:+.0f} mm  (the same gait on the rigid "
              "floor)"]
    if args.mjx:
        lines += ["", f"MJX, float32, standing for {STAND:g} s (Fz / weight over the last {REST:g} s; wall time "
                      "includes compilation)"]
        for dt in (m.opt.timestep, 0.0005):
            r = mjx_stand(dt)
            lines.append(f"  dt {dt * 1e3:g} ms: mean {r['mean']:.5f}  min {r['min']:.5f}  max {r['max']:.5f}  trunk "
                         f"height {r['z'] * 1e3:.1f} mm  feet sinkage {' '.join(f'{s * 1e3:.1f}' for s in r['feet'])} "
                         f"mm  ({r['wall']:.0f} s)")
    text = "\n".join(lines) + "\n"
    print(text, end="")
    if args.out != "-":
        with open(args.out, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()

"""The ground memory at its extremes: a robot standing for minutes, 12 Hz strides, a deep trench.

    python benchmarks/ground_extremes.py [--stand SECONDS] [--out FILE]

* **Standing.** The hexapod (bundled scene, poppy seeds closely packed) with ``ground_memory=True`` stands at its
  initial pose (hip targets 0) for ``--stand`` seconds of simulated time (default 180). Every 10 s: the torso's
  height, the deepest element, the grains' solid and bulk volume in the grid, the highest and lowest surface, and
  how many cells changed (their surface or packing by more than 1e-9) since the last record. A resting robot must settle and then leave the ground as it is:
  no creep of the torso, no cell changing, the grains' volume constant.
* **12 Hz strides.** The DynaRoACH-sized hexapod (``hexapod_xml(variant="small")``, 3 mm glass) turns its tripods
  at 12 Hz for 2 s with the memory: finite forces, conservation, the packing inside its two states, the surface
  within the legs' reach, against the same run without the memory.
* **Deep trench.** A 4 x 4 x 1 cm plate pushed 10 cm into closely packed poppy seeds (three times the packing's
  layer), dragged 20 cm at that depth and lifted out, then 2 s of the bed at rest: the trench's depth, the
  slopes against the angle of repose, conservation.

``tests/mjrft/test_ground.py`` runs a short version of each (its qualitative outcome) in seconds.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
import warnings

import mujoco
import numpy as np

import mjrft
from mjrft.ground import GroundOptions, ground_volumes


def stand(seconds: float, every: float = 10.0) -> list[str]:
    model = mujoco.MjModel.from_xml_path(mjrft.models.model_path("hexapod"))
    data = mujoco.MjData(model)
    t = mjrft.GranularTerrain(model, ground_memory=True)
    gt, st = t.terrain_model.ground, t.terrain_state
    data.ctrl[:] = 0.0
    rows = [f"standing: hexapod ({t.medium.name}, {t.n_elements} elements, dt {model.opt.timestep * 1e3:g} ms), hip "
            f"targets 0, ground memory {int(gt.shape[1])} x {int(gt.shape[0])} cells of {gt.frame[2] * 1e3:g} mm",
            f"{'t (s)':>6s} {'torso z (mm)':>12s} {'deepest (mm)':>12s} {'solid (cm^3)':>13s} {'bulk (cm^3)':>11s} "
            f"{'min h (mm)':>10s} {'max h (mm)':>10s} {'cells changed by > 1 nm':>23s}"]
    last = st.g_cells.copy()
    n = int(round(every / model.opt.timestep))
    t0 = time.time()
    while data.time < seconds - 1e-9:
        t.step(data, n)
        solid, bulk = ground_volumes(gt, st)
        changed = int(np.count_nonzero(np.any(np.abs(st.g_cells[:, :, :4] - last[:, :, :4]) > 1e-9, axis=2)))
        last = st.g_cells.copy()
        rows.append(f"{data.time:6.0f} {data.qpos[2] * 1e3:12.4f} {t.sinkage().max() * 1e3:12.4f} "
                    f"{solid * 1e6:13.6f} {bulk * 1e6:11.6f} {st.g_height.min() * 1e3:10.4f} "
                    f"{st.g_height.max() * 1e3:10.4f} {changed:23d}")
        print(rows[-1], flush=True)
    rows.append(f"({time.time() - t0:.0f} s wall)")
    return rows


def strides(freq: float = 12.0, seconds: float = 2.0) -> list[str]:
    from mjrft.models.hexapod import TRIPOD_A, hexapod_xml

    rows = [f"{freq:g} Hz strides: small hexapod on glass3_cp (rft, 5 mm elements, 1 ms), tripods half a turn apart, "
            f"{seconds:g} s"]
    for memory in (False, True):
        model = mujoco.MjModel.from_xml_string(hexapod_xml(variant="small", medium="glass3_cp", law="rft",
                                                           resolution=0.005))
        data = mujoco.MjData(model)
        t = mjrft.GranularTerrain(model, ground_memory=memory)
        off = np.array([0.0 if mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, model.jnt_bodyid[
            model.actuator_trnid[i, 0]]) in {f"leg_{k}" for k in TRIPOD_A} else math.pi for i in range(model.nu)])
        fmax = 0.0
        while data.time < seconds - 1e-9:
            data.ctrl[:] = 2 * math.pi * freq * data.time + off
            t.step(data, 1)
            fmax = max(fmax, float(np.abs(t.force).max()))
        line = (f"  memory {'on ' if memory else 'off'}: x {data.qpos[0] * 100:6.2f} cm, torso z {data.qpos[2] * 1e3:6.2f} mm, "
                f"deepest {t.sinkage().max() * 1e3:5.2f} mm, largest element force {fmax:.3g} N")
        if memory:
            gt, st = t.terrain_model.ground, t.terrain_state
            line += (f"; ground {st.g_height.min() * 1e3:.2f} to {st.g_height.max() * 1e3:.2f} mm, phi "
                     f"{st.g_phi.min():.4f}-{st.g_phi.max():.4f} (states {gt.pack[0]:g}-{gt.pack[1]:g}), solid volume "
                     f"{ground_volumes(gt, st)[0] * 1e6:.6f} cm^3 (start {np.prod(st.g_height.shape) * gt.frame[2] ** 2 * gt.pack[7] * gt.pack[3] * 1e6:.6f})")
        rows.append(line)
        print(line, flush=True)
    return rows


TRENCH = """<mujoco><option timestep="0.001"/><worldbody>
<body name="plate"><joint name="x" type="slide" axis="1 0 0"/><joint name="z" type="slide" axis="0 0 1"/>
<geom type="box" size="0.02 0.02 0.005" mass="0.1"/></body></worldbody></mujoco>"""


def trench(depth: float = 0.10, length: float = 0.20, rest: float = 2.0) -> list[str]:
    model = mujoco.MjModel.from_xml_string(TRENCH)
    data = mujoco.MjData(model)
    t = mjrft.GranularTerrain(model, "poppy_cp", "rft", resolution=0.005,
                              ground_memory=GroundOptions(cell=0.005, extent=(-0.1, 0.35, -0.12, 0.12)))
    gt, st = t.terrain_model.ground, t.terrain_state
    step, speed = 5e-4, 0.05
    path = ([(0.0, z) for z in np.arange(0.03, 0.005 - depth, -step)]
            + [(x, 0.005 - depth) for x in np.arange(0.0, length, step)]
            + [(length, z) for z in np.arange(0.005 - depth, 0.05, step)])
    solid0 = ground_volumes(gt, st)[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        prev = np.array(path[0])
        for x, z in path:
            v = (np.array([x, z]) - prev) / (step / speed)
            prev = np.array([x, z])
            data.qpos[:] = x, z
            data.qvel[:] = v
            mujoco.mj_fwdPosition(model, data)
            mujoco.mj_fwdVelocity(model, data)
            data.time += step / speed
            t.compute(data, step / speed)
        data.qvel[:] = 0.0
        for _ in range(int(rest / 0.004)):
            data.time += 0.004
            t.compute(data, 0.004)
    h = st.g_height
    c = gt.frame[2]
    steep = max(np.abs(np.diff(h, axis=0)).max(), np.abs(np.diff(h, axis=1)).max()) / c
    mid = t.ground_height(np.linspace(0.02, length - 0.02, 9), 0.0)
    return [f"deep trench: 4 x 4 x 1 cm plate pushed {depth * 100:g} cm into poppy_cp (layer {gt.pack[7] * 100:g} cm), "
            f"dragged {length * 100:g} cm at 5 cm/s and lifted, then {rest:g} s at rest (5 mm cells)",
            f"  trench floor along its middle {mid.min() * 1e3:.2f} to {mid.max() * 1e3:.2f} mm; ground {h.min() * 1e3:.2f}"
            f" to {h.max() * 1e3:.2f} mm; steepest slope {steep:.4f} (tan 47 deg = {math.tan(math.radians(47)):.4f}); "
            f"phi {st.g_phi.min():.4f}-{st.g_phi.max():.4f}; solid volume change "
            f"{(ground_volumes(gt, st)[0] - solid0) / solid0:.1e} (relative)"]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--stand", type=float, default=180.0, help="seconds of simulated standing (default 180)")
    ap.add_argument("--out", default=None, help="also write the report to this file")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    rows = [f"python benchmarks/ground_extremes.py --stand {args.stand:g}", ""]
    rows += trench() + [""]
    print("\n".join(rows), flush=True)
    rows += strides() + [""]
    rows += stand(args.stand)
    text = "\n".join(rows)
    if args.out:
        with open(args.out, "w") as fh:
            fh.write(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""The solidify option on plate rigs: what a resting plate holds with the rest memory alone and with
``GranularTerrain(solidify=f)`` (mjrft/laws/solidify.py), on poppy_cp under Li RFT at 1 ms steps.

1. Load-sinkage (Li's plate, 3.81 x 2.54 cm, horizontal, kinematic): pressed down at 1 cm/s to 3 cm, held
   0.2 s, pressed 4 mm further at 0.2 mm/s (below the stick speed: at rest), then at 1 cm/s for 1 cm.
2. Small tilt (Li's plate, kinematic): pressed to 3 cm at 1 cm/s, held, tilted about its centre at
   0.01 rad/s to 0.04 rad; the pitch moment against the angle and its slope over the first 2 mrad.
3. Foot pendulum (thesis fig. 22B): a plate 22.9 cm long (HUBO's feet: 15.2 cm, the 30.4 cm board and
   the cut-out 30.4 cm board) carrying 50 kg at 0.7 m on a massless rod, free to sink (slide z) and pitch
   (hinge y through the foot's centre). It is lowered onto the grains over 2 s (an upward force at the
   CoM ramps from its weight to 0), held 0.5 s, then its CoM moves 1 cm along the foot over 1 s (the CoM
   offset of the stance trials) and the pendulum runs to 8 s; fall = tilt > 0.5 rad. One that stands has
   the tilt stiffness ``m g x / tilt + m g h`` at constant load, to be set against ``m g h``.

Usage: ``python benchmarks/solidify_plate.py [--factors 0 1 1.5 2 3] [--out benchmarks/results/solidify_plate.txt]``
(factor 0 = the option off: the rest memory alone).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
import warnings

import mujoco
import numpy as np

from mjrft import GranularTerrain
from mjrft import TerrainStabilityWarning

DT = 1e-3
ALPHA_Z = 5.6e5  # poppy_cp alpha_z(0, pi/2), N/m^3 (Li 2013 table S3)
G = 9.81


def _plate_xml(length, width, thickness=0.0064, resolution=0.004):
    return f"""<mujoco><option timestep="{DT}" integrator="implicitfast"/>
<custom><text name="mjrft:medium" data="poppy_cp"/><text name="mjrft:law" data="rft"/>
<numeric name="mjrft:resolution" data="{resolution}"/></custom>
<worldbody><body name="plate" pos="0 0 {thickness / 2}">
<joint name="z" type="slide" axis="0 0 1"/><joint name="pitch" type="hinge" axis="0 1 0"/>
<geom type="box" size="{length / 2} {width / 2} {thickness / 2}" mass="0.02" contype="0" conaffinity="0"/>
</body></worldbody></mujoco>"""


def _terrain(model, factor):
    return GranularTerrain(model, bodies=[model.body(1).name], solidify=factor)


def _kinematic(model, terrain, program):
    """program: list of (duration, vz, omega); returns arrays of time, depth, pitch, Fz, My."""
    data = mujoco.MjData(model)
    out = []
    z, th, t = 0.0, 0.0, 0.0
    for dur, vz, om in program:
        for _ in range(int(round(dur / DT))):
            z += vz * DT
            th += om * DT
            t += DT
            data.qpos[:] = (z, th)
            data.qvel[:] = (vz, om)
            data.time = t
            mujoco.mj_fwdPosition(model, data)
            mujoco.mj_fwdVelocity(model, data)
            terrain.compute(data, DT)
            w = terrain.wrench[1]
            # moment about the plate centre (the wrench is about the CoM, which is the centre)
            out.append((t, -z, th, w[2], w[4]))
    return np.array(out)


def load_sinkage(factor):
    model = mujoco.MjModel.from_xml_string(_plate_xml(0.0381, 0.0254))
    terrain = _terrain(model, factor)
    a = _kinematic(model, terrain, [(3.0, -0.01, 0.0), (0.2, 0.0, 0.0), (20.0, -2e-4, 0.0), (1.0, -0.01, 0.0)])
    return a


def small_tilt(factor):
    model = mujoco.MjModel.from_xml_string(_plate_xml(0.0381, 0.0254))
    terrain = _terrain(model, factor)
    a = _kinematic(model, terrain, [(3.0, -0.01, 0.0), (0.2, 0.0, 0.0), (4.0, 0.0, 0.01)])
    return a


def _foot_boxes(length, width, cutout):
    if not cutout:
        return [((0.0, 0.0), (length / 2, width / 2))]
    s = 2 ** -0.5  # the humanoid's cut-out: hole = outline scaled by 1/sqrt(2), half the area
    hl, hw = length * s / 2, width * s / 2
    end, side = (length / 2 - hl) / 2, (width / 2 - hw) / 2
    return [((length / 2 - end, 0.0), (end, width / 2)), ((-(length / 2 - end), 0.0), (end, width / 2)),
            ((0.0, width / 2 - side), (hl, side)), ((0.0, -(width / 2 - side)), (hl, side))]


def _pendulum_xml(width, cutout, offset, mass=50.0, height=0.7, length=0.229, thickness=0.02, resolution=0.02):
    geoms = "\n".join(f'<geom type="box" pos="{cx} {cy} 0" size="{hx} {hy} {thickness / 2}" mass="0.1" '
                      f'contype="0" conaffinity="0"/>' for (cx, cy), (hx, hy) in _foot_boxes(length, width, cutout))
    return f"""<mujoco><option timestep="{DT}" integrator="implicitfast"/>
<custom><text name="mjrft:medium" data="poppy_cp"/><text name="mjrft:law" data="rft"/>
<numeric name="mjrft:resolution" data="{resolution}"/></custom>
<worldbody><body name="foot" pos="0 0 {thickness / 2}">
<joint name="z" type="slide" axis="0 0 1"/><joint name="pitch" type="hinge" axis="0 1 0"/>
{geoms}
<geom type="sphere" pos="{offset} 0 {height}" size="0.05" mass="{mass}" contype="0" conaffinity="0"/>
</body></worldbody></mujoco>"""


def pendulum(width, cutout, factor, offset=0.01, t_end=8.0, load_time=2.0, hold=0.5, shift_time=1.0, height=0.7,
             mass=50.0):
    """The foot pendulum (module docstring): (fall time or nan, tilt (rad) at ``t_end``, sinkage (m) after loading,
    effective tilt stiffness ``m g x / tilt + m g h`` (N m/rad) of a pendulum that stood)."""
    model = mujoco.MjModel.from_xml_string(_pendulum_xml(width, cutout, 0.0, mass=mass, height=height))
    terrain = _terrain(model, factor)
    data = mujoco.MjData(model)
    body = 1
    ipos0 = model.body_ipos[body].copy()
    weight = float(model.body_subtreemass[body]) * G
    fall, sink = math.nan, math.nan
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TerrainStabilityWarning)
        while data.time < t_end - 1e-9:
            t = data.time
            # lowered onto the grains: an upward force at the CoM ramping from the weight to 0
            data.xfrc_applied[body, 2] = weight * max(0.0, 1.0 - t / load_time)
            # then the CoM moves off the foot's centre along the foot at a uniform speed
            s = min(1.0, max(0.0, (t - load_time - hold) / shift_time))
            model.body_ipos[body, 0] = ipos0[0] + offset * s
            if math.isnan(sink) and t >= load_time + hold:
                sink = -float(data.qpos[0])
            terrain.step(data)
            if abs(data.qpos[1]) > 0.5:
                fall = data.time
                break
    tilt = float(data.qpos[1])
    k = weight * offset / abs(tilt) + weight * ipos0[2] if math.isnan(fall) and tilt != 0.0 else math.nan
    return fall, tilt, sink, k


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--factors", type=float, nargs="+", default=[0.0, 1.0, 1.5, 2.0, 3.0])
    ap.add_argument("--out", default=None)
    args = ap.parse_args(argv)
    lines = []

    def say(s=""):
        print(s, flush=True)
        lines.append(s)

    t0 = time.perf_counter()
    say("1. Li's plate, load-sinkage: Fz (N) at 3 cm after 1 cm/s; after 1, 2, 4 mm more at 0.2 mm/s; "
        "after 1 cm more at 1 cm/s (RFT there: alpha_z A z)")
    area = 0.0381 * 0.0254
    for f in args.factors:
        a = load_sinkage(f)
        d, fz = a[:, 1], a[:, 3]
        i3 = int(round(3.2 / DT)) - 1
        pts = [i3] + [i3 + int(round(x / 2e-4 / DT)) for x in (1e-3, 2e-3, 4e-3)] + [len(a) - 1]
        say(f"  solidify={f:g}: " + ", ".join(f"{fz[i]:.2f} N at {d[i] * 1000:.1f} mm (RFT {ALPHA_Z * area * d[i]:.2f})"
                                             for i in pts))
    say()
    say("2. Li's plate at rest 3 cm deep, tilted about its centre at 0.01 rad/s: pitch moment (N mm) at 1, 2, 5, 10, "
        "40 mrad; slope over the first 2 mrad (N m/rad); depth hardening alpha_z I (RFT at yield)")
    i_y = 0.0254 * 0.0381 ** 3 / 12
    for f in args.factors:
        a = small_tilt(f)
        th, my = a[:, 2], a[:, 4]
        start = int(round(3.2 / DT)) - 1
        m0 = my[start]
        pts = [start + int(round(x / 0.01 / DT)) for x in (1e-3, 2e-3, 5e-3, 1e-2, 4e-2 - 1e-4)]
        slope = -(my[pts[1]] - m0) / th[pts[1]]
        say(f"  solidify={f:g}: " + ", ".join(f"{-(my[i] - m0) * 1000:.2f}" for i in pts)
            + f"; slope {slope:.3f} N m/rad (alpha_z I = {ALPHA_Z * i_y:.4f})")
    say()
    say("3. Foot pendulum, 50 kg at 0.7 m (m g h = 343 N m/rad), foot 22.9 cm long, loaded centred over 2 s, held "
        "0.5 s, CoM moved 1 cm along the foot over 1 s: fall time (s, - = stood to 8 s) / tilt at the end (mrad) / "
        "sinkage after loading (mm) / tilt stiffness m g x / tilt + m g h (N m/rad) of one that stood")
    feet = [(0.152, False, "natural 15.2 cm"), (0.304, False, "board 30.4 cm"), (0.304, True, "cut-out 30.4 cm")]
    for f in args.factors:
        row = []
        for w, cut, name in feet:
            fall, tilt, sink, k = pendulum(w, cut, f)
            row.append(f"{name}: {'-' if math.isnan(fall) else f'{fall:.2f}'} / {tilt * 1000:.1f} / "
                       f"{sink * 1000:.1f} / {k:.0f}")
        say(f"  solidify={f:g}: " + "; ".join(row))
    say()
    say(f"wall {time.perf_counter() - t0:.0f} s")
    if args.out:
        with open(args.out, "w") as fh:
            fh.write(f"# python benchmarks/solidify_plate.py {' '.join(argv or sys.argv[1:])}\n")
            fh.write("\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())

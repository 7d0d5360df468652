"""Hexapod open-loop tripod against leg curvature: speed and mean vertical ground reaction force per tripod.

    .venv/bin/python benchmarks/leg_curvature.py                  # 2 Hz, 3 s, poppy_lp, the free robot
    .venv/bin/python benchmarks/leg_curvature.py --planar         # body held in the sagittal plane
    .venv/bin/python benchmarks/leg_curvature.py --f 1 --medium poppy_cp --curvature 1 0 -1

Curvature is given in units of 1/R' (R' = 2.05 cm; +1 = Li 2013's C-leg, -1 the reversed C-leg; the sign
convention is :mod:`mjrft.geometry.curved_leg`). The robot is ``mjrft/HexapodSand-v0`` driven by the gait
``tripod:f=F``. The granular wrench is averaged over every physics step (each 10-step env frame runs as ten
one-step terrain calls, the same physics): sampling it once per env step aliases the legs' step-to-step
force. ``--planar`` holds the torso to fore-aft, vertical and pitch motion, as Li 2013's MBDyn robot
simulation did (suppl., "Robot simulation"): the env's ``planar=True`` (joints ``rootx``, ``rootz``,
``rooty`` in place of the free joint). Each run starts as the env does (every leg down, tripod B
catching up half a turn); the validation case ``li2013_robot`` starts its trials on the gait's pose.
"""

from __future__ import annotations

import argparse

import gymnasium
import numpy as np

import mjrft.envs  # noqa: F401  (registers the environments)
from mjrft.tools.gaits import make_gait
from mjrft.models.hexapod import R_PRIME, TRIPOD_A, TRIPOD_B


def run(curvature_rp: float, f: float = 2.0, seconds: float = 3.0, medium: str = "poppy_lp",
        planar: bool = False) -> dict:
    """One run; returns speed (m/s), mean vertical force on tripod A, B and the belly (N), mean torso height (m)
    and the mean horizontal force on the legs and on the belly (N)."""
    env = gymnasium.make("mjrft/HexapodSand-v0", medium=medium, curvature=curvature_rp / R_PRIME["rhex"],
                         planar=planar)
    u = env.unwrapped
    m = u.model
    ids = {"A": [m.body(f"leg_{n}").id for n in TRIPOD_A], "B": [m.body(f"leg_{n}").id for n in TRIPOD_B]}
    rec = {k: [] for k in ("A", "B", "belly", "z", "legs_x", "belly_x")}

    def record(data):  # after every physics step
        w = u.terrain.wrench
        rec["A"].append(w[ids["A"], 2].sum())
        rec["B"].append(w[ids["B"], 2].sum())
        rec["belly"].append(w[u.task.torso, 2])
        rec["legs_x"].append(w[ids["A"] + ids["B"], 0].sum())
        rec["belly_x"].append(w[u.task.torso, 0])
        rec["z"].append(data.xpos[u.task.torso, 2])

    u.each_physics_step(record)
    gait = make_gait(f"tripod:f={f:g}", env)
    obs, _ = env.reset(seed=0)
    x0 = float(u.data.qpos[0])
    fell = False
    for _ in range(int(round(seconds / u.dt))):
        action, _ = gait.predict(obs)
        obs, _, fell, _, _ = env.step(action)
        if fell:
            break
    out = {k: float(np.mean(v)) for k, v in rec.items()}
    out.update(speed=(float(u.data.qpos[0]) - x0) / u.data.time, time=float(u.data.time), fell=bool(fell))
    env.close()
    return out


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--curvature", type=float, nargs="+", default=[1.0, 0.6, 0.0, -0.6, -1.0], help="in 1/R'")
    p.add_argument("--f", type=float, default=2.0, help="stride frequency, Hz (default 2)")
    p.add_argument("--seconds", type=float, default=3.0)
    p.add_argument("--medium", default="poppy_lp")
    p.add_argument("--planar", action="store_true", help="hold the body in the sagittal plane (Li's simulation)")
    a = p.parse_args(argv)
    print(f"tripod f = {a.f:g} Hz, {a.seconds:g} s, {a.medium}, {'planar body' if a.planar else 'free body'}")
    print("| curvature (1/R') | speed (m/s) | F_z tripod A (N) | F_z tripod B (N) | F_z belly (N) | "
          "F_x legs (N) | F_x belly (N) | torso z (mm) |")
    print("|---|---|---|---|---|---|---|---|")
    for k in a.curvature:
        r = run(k, a.f, a.seconds, a.medium, a.planar)
        print(f"| {k:+g} | {r['speed']:.3f} | {r['A']:.3f} | {r['B']:.3f} | {r['belly']:.3f} | {r['legs_x']:.3f} | "
              f"{r['belly_x']:.3f} | {r['z'] * 1000:.1f} |" + (" fell" if r["fell"] else ""), flush=True)


if __name__ == "__main__":
    main()

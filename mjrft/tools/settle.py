"""``mjrft settle``: a box foot and a small legged body dropped onto poppy seeds.

Prints, for each, the settled sinkage next to the analytic value. A plate loaded slowly settles at
``d0 = load / (alpha_z(0, pi/2) x area)``; dropped from a height h onto grains whose yield stress
grows linearly with depth it stops at ``d0 + sqrt(d0^2 + 2 d0 h)`` (energy balance, the grains do
not spring back) and stays there.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from mjrft.coupler import GranularTerrain

BOX_FOOT = """<mujoco model="box foot"><option timestep="0.002"/>
<worldbody><light pos="0 0 1"/>
<body name="foot" pos="0 0 {z}"><freejoint/><geom type="box" size="0.05 0.05 0.005" mass="{mass}"/></body>
</worldbody></mujoco>"""

LEGGED = """<mujoco model="four-legged body"><option timestep="0.001"/>
<default><geom type="box" size="0.01 0.01 0.0025"/></default>
<worldbody><light pos="0 0 1"/>
<body name="torso" pos="0 0 {z}"><freejoint/><geom type="box" size="0.06 0.04 0.01" mass="{mass}"/>
  <body name="foot_fl" pos=" 0.05  0.03 -0.03"><geom mass="0.01"/></body>
  <body name="foot_fr" pos=" 0.05 -0.03 -0.03"><geom mass="0.01"/></body>
  <body name="foot_rl" pos="-0.05  0.03 -0.03"><geom mass="0.01"/></body>
  <body name="foot_rr" pos="-0.05 -0.03 -0.03"><geom mass="0.01"/></body>
  <geom type="capsule" fromto=" 0.05  0.03 -0.01  0.05  0.03 -0.0275" size="0.002" mass="0.001"/>
  <geom type="capsule" fromto=" 0.05 -0.03 -0.01  0.05 -0.03 -0.0275" size="0.002" mass="0.001"/>
  <geom type="capsule" fromto="-0.05  0.03 -0.01 -0.05  0.03 -0.0275" size="0.002" mass="0.001"/>
  <geom type="capsule" fromto="-0.05 -0.03 -0.01 -0.05 -0.03 -0.0275" size="0.002" mass="0.001"/>
</body></worldbody></mujoco>"""


def _drop(xml: str, bodies, bottom_offset: float, drop: float, medium: str, seconds: float = 1.5):
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    terrain = GranularTerrain(model, medium, "rft", bodies=bodies, resolution=0.005)
    terrain.step(data, int(seconds / model.opt.timestep))
    speed = float(np.linalg.norm(data.qvel[:3]))
    return -(data.qpos[2] - bottom_offset), speed, terrain


def analytic(load: float, alpha: float, area: float, drop: float) -> tuple[float, float]:
    """(quasi-static depth d0, depth after a drop from ``drop`` metres above the surface)."""
    d0 = load / (alpha * area)
    return d0, d0 + math.sqrt(d0 * d0 + 2 * d0 * drop)


def run(medium: str = "poppy_cp", drop: float = 0.01) -> list[dict]:
    """Drop both bodies from ``drop`` above the surface; return and print the comparison."""
    rows = []
    mass = 1.0
    sink, speed, t = _drop(BOX_FOOT.format(z=0.005 + drop, mass=mass), ["foot"], 0.005, drop, medium)
    d0, dd = analytic(mass * 9.81, t.medium.alpha_z_down, 0.1 * 0.1, drop)
    rows.append({"body": "box foot 10x10 cm, 1 kg", "sinkage": sink, "quasi_static": d0, "dropped": dd,
                 "speed": speed, "elements": t.n_elements})
    mass = 0.3
    total = mass + 4 * 0.01 + 4 * 0.001
    feet = ["foot_fl", "foot_fr", "foot_rl", "foot_rr"]
    sink, speed, t = _drop(LEGGED.format(z=0.0325 + drop, mass=mass), feet, 0.0325, drop, medium)
    d0, dd = analytic(total * 9.81, t.medium.alpha_z_down, 4 * 0.02 * 0.02, drop)
    rows.append({"body": "legged body, four 2x2 cm feet", "sinkage": sink, "quasi_static": d0, "dropped": dd,
                 "speed": speed, "elements": t.n_elements})
    print(f"Dropped {drop * 100:.1f} cm onto {medium} (Li 2013 RFT, alpha_z(0, pi/2) = "
          f"{t.medium.alpha_z_down / 1e6:.3f} N/cm^3):")
    print(f"{'body':34s} {'elements':>8s} {'sinkage':>9s} {'analytic':>9s} {'(slow load)':>11s} {'speed':>10s}")
    for r in rows:
        print(f"{r['body']:34s} {r['elements']:8d} {r['sinkage'] * 1e3:7.2f}mm {r['dropped'] * 1e3:7.2f}mm "
              f"{r['quasi_static'] * 1e3:9.2f}mm {r['speed'] * 1e3:7.3f}mm/s")
    return rows


def add_arguments(parser) -> None:
    parser.add_argument("--medium", default="poppy_cp", help="medium name (mjrft.MEDIA; default poppy_cp)")
    parser.add_argument("--drop", type=float, default=0.01, help="drop height above the surface in m (default 0.01)")


def main(args) -> int:
    from mjrft.media import get_medium

    get_medium(args.medium)  # unknown name -> error listing the valid ones
    if not (math.isfinite(args.drop) and args.drop >= 0):
        raise ValueError(f"--drop must be a finite height >= 0 m, got {args.drop}")
    run(args.medium, args.drop)
    return 0


if __name__ == "__main__":
    run()

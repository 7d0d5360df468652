"""The free-body hexapod under the open-loop tripod: C-legs against reversed C-legs, speed, tilt, roll and heading.

    .venv/bin/python benchmarks/free_tripod.py                                   # poppy_lp and poppy_cp, seed 0
    .venv/bin/python benchmarks/free_tripod.py --media poppy_lp --seeds 0 1 2 --law depth_only

``mjrft/HexapodSand-v0`` as a user makes it (free joint, the env's start: every leg down, tripod B catching up
half a turn), ``curvature = +1/R'`` (Li 2013's C-leg) and ``-1/R'`` (reversed C-leg), gait ``tripod:f=F`` at
F = 1-5 Hz with ``max_hip_speed = 12 pi`` (the 5 Hz tripod needs 10 pi), 10 s per run. Per run: the speed along
x over the whole run, the largest torso tilt (angle of its z axis from vertical), the roll range and the heading
(yaw, unwrapped) at 1 s, at the end and its largest magnitude.
"""

from __future__ import annotations

import argparse
import math

import gymnasium
import numpy as np

import mjrft.envs  # noqa: F401  (registers the environments)
from mjrft.models.hexapod import R_PRIME
from mjrft.tools.gaits import make_gait


def _roll_yaw(q) -> tuple[float, float]:
    w, x, y, z = q
    return math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y)), math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))


def run(curvature_rp: float, f: float, medium: str = "poppy_lp", seed: int = 0, seconds: float = 10.0,
        law: str | None = None) -> dict:
    kw = {"law": law} if law else {}
    env = gymnasium.make("mjrft/HexapodSand-v0", medium=medium, curvature=curvature_rp / R_PRIME["rhex"],
                         max_hip_speed=12 * math.pi, terminate_when_unhealthy=False, **kw)
    u = env.unwrapped
    gait = make_gait(f"tripod:f={f:g}", env)
    obs, _ = env.reset(seed=seed)
    x0 = float(u.data.qpos[0])
    tilt, rolls, yaws = 0.0, [], []
    n = int(round(seconds / u.dt))
    for _ in range(n):
        action, _ = gait.predict(obs)
        obs, *_ = env.step(action)
        tilt = max(tilt, u.torso_tilt())
        r, y = _roll_yaw(u.data.qpos[3:7])
        rolls.append(r)
        yaws.append(y)
    yaws = np.degrees(np.unwrap(yaws))
    out = dict(speed=(float(u.data.qpos[0]) - x0) / float(u.data.time), tilt=math.degrees(tilt),
               roll=(math.degrees(min(rolls)), math.degrees(max(rolls))), yaw1=float(yaws[min(len(yaws), int(round(1.0 / u.dt))) - 1]),
               yaw_end=float(yaws[-1]), yaw_max=float(np.abs(yaws).max()))
    env.close()
    return out


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--media", nargs="+", default=["poppy_lp", "poppy_cp"])
    p.add_argument("--seeds", type=int, nargs="+", default=[0])
    p.add_argument("--freqs", type=float, nargs="+", default=[1, 2, 3, 4, 5])
    p.add_argument("--law", default=None, help="the medium's law (default: rft); e.g. depth_only")
    p.add_argument("--seconds", type=float, default=10.0)
    a = p.parse_args(argv)
    print(f"free body, tripod, {a.seconds:g} s per run, law {a.law or 'rft'}; C = +1/R', rev C = -1/R'")
    print("| medium | seed | f (Hz) | v_C (m/s) | v_revC (m/s) | v_C / v_revC | tilt C / rev C (deg) | roll C (deg) | "
          "heading C at 1 s / end / max (deg) | heading rev C at 1 s / end / max (deg) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for medium in a.media:
        for seed in a.seeds:
            for f in a.freqs:
                c, r = (run(k, f, medium, seed, a.seconds, a.law) for k in (1.0, -1.0))
                print(f"| {medium} | {seed} | {f:g} | {c['speed']:.3f} | {r['speed']:.3f} | {c['speed'] / r['speed']:.2f} | "
                      f"{c['tilt']:.0f} / {r['tilt']:.0f} | {c['roll'][0]:+.0f} to {c['roll'][1]:+.0f} | "
                      f"{c['yaw1']:+.0f} / {c['yaw_end']:+.0f} / {c['yaw_max']:.0f} | "
                      f"{r['yaw1']:+.0f} / {r['yaw_end']:+.0f} / {r['yaw_max']:.0f} |", flush=True)


if __name__ == "__main__":
    main()

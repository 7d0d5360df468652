"""Third-party quadrupeds resting on sand at their own timesteps: does the granular force carry the weight on every
step, or only on average?

For MuJoCo Menagerie's Unitree Go2 (2 ms, its ``home`` keyframe and servo targets), ANYmal C (2 ms, its initial
state, ``ctrl = 0``) and dm_control's quadruped (5 ms, its walk-task model, ``ctrl = 0``), each on poppy seeds
(``GranularTerrain(model, "poppy_cp", floor="auto")``), with the explicit and with the implicit granular step:
``--seconds`` of holding the pose, then over the last second the net vertical granular force over the weight at
every step (least, largest, largest deviation from 1), the largest joint speed left, the chatter and
stability-limit warnings the terrain gave (bodies, and the time before which the chatter was seen), the springs'
explicit stability limit and the step's limit (``terrain.min_stable_timestep(data, part)``) at the end, and
the wall time of the run. Then 3 s of the open-loop trot of :mod:`mjrft.models.quadrupeds` (the Go2's of
tests/models/test_third_party_robots.py) with the implicit step: distance, mean load, chatter warnings.

    python benchmarks/rest_balance.py [--seconds 3] [--robots go2 anymal_c dm_quadruped]
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
from mjrft.models import quadrupeds as q

GO2 = os.path.join(os.path.dirname(mjrft.models.__file__), "third_party", "unitree_go2", "scene_mjx.xml")


def go2_model():
    return mujoco.MjModel.from_xml_path(GO2)


def go2_trot(m, t: float, stride: float = 0.3, lift: float = 0.8, freq: float = 1.5) -> np.ndarray:
    """The Go2 test's trot (tests/models/test_third_party_robots.py)."""
    phase = 2 * np.pi * freq * t + np.array([0.0, np.pi, np.pi, 0.0])
    ctrl = m.key("home").ctrl.reshape(4, 3).copy()
    ctrl[:, 1] += stride * np.cos(phase)
    ctrl[:, 2] -= lift * np.maximum(np.sin(phase), 0.0)
    return ctrl.ravel()


MODELS = {"go2": go2_model, **q.MODELS}


def start(name: str):
    m = MODELS[name]()
    d = mujoco.MjData(m)
    if name == "go2":
        mujoco.mj_resetDataKeyframe(m, d, m.key("home").id)
    return m, d


def trot(name: str, m, t: float) -> np.ndarray:
    return go2_trot(m, t) if name == "go2" else q.trot_ctrl(name, m, t)


def summarise(caught) -> tuple[str, int]:
    """(the chattering bodies with the time before which each was seen, the number of stability-limit warnings)."""
    chatter, limit = [], 0
    for w in caught:
        if not issubclass(w.category, mjrft.TerrainStabilityWarning):
            continue
        text = str(w.message)
        if "chatters" in text:
            body = text.split("body '")[1].split("'")[0]
            chatter.append(f"{body}<{float(text.split('before t = ')[1].split(' s')[0]):.2g}s")
        else:
            limit += 1
    return (", ".join(chatter) or "-"), limit


def rest_row(name: str, implicit: bool, seconds: float) -> dict:
    m, d = start(name)
    weight = float(m.body_subtreemass[0]) * -float(m.opt.gravity[2])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        terrain = mjrft.GranularTerrain(m, "poppy_cp", floor="auto", implicit=implicit)
        load = np.empty(int(round(seconds / m.opt.timestep)))
        t0 = time.perf_counter()
        for i in range(len(load)):
            terrain.step(d)
            load[i] = terrain.wrench[:, 2].sum() / weight
        wall = time.perf_counter() - t0
    last = load[-int(round(1.0 / m.opt.timestep)):]
    chatter, limit = summarise(caught)
    return {"robot": name, "mode": "implicit" if implicit else "explicit", "h": m.opt.timestep,
            "min": last.min(), "max": last.max(), "dev": np.abs(last - 1.0).max(), "mean": last.mean(),
            "qvel": np.abs(d.qvel[6:]).max(), "chatter": chatter, "limit": limit,
            "springs": terrain.min_stable_timestep(d, "springs"), "step": terrain.min_stable_timestep(d),
            "wall": wall, "elements": terrain.n_elements}


def trot_row(name: str, seconds: float = 3.0) -> dict:
    m, d = start(name)
    weight = float(m.body_subtreemass[0]) * -float(m.opt.gravity[2])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        terrain = mjrft.GranularTerrain(m, "poppy_cp", floor="auto", implicit=True)
        terrain.step(d, int(round(1.0 / m.opt.timestep)))
        first, t0, load = d.qpos[:3].copy(), d.time, []
        for _ in range(int(round(seconds / m.opt.timestep))):
            d.ctrl[:] = trot(name, m, d.time - t0)
            terrain.step(d)
            load.append(terrain.wrench[:, 2].sum() / weight)
    chatter, limit = summarise(caught)
    moved = d.qpos[:3] - first
    return {"robot": name, "dx": moved[0], "dy": moved[1], "load": float(np.mean(load)),
            "upright": float(d.xmat[1][8]), "chatter": chatter, "limit": limit}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seconds", type=float, default=3.0, help="seconds holding the pose (default 3)")
    ap.add_argument("--robots", nargs="*", default=list(MODELS), choices=list(MODELS))
    args = ap.parse_args(argv)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        start("dm_quadruped")  # nothing to warm up but the imports; the first terrain compiles (not timed below)
        mjrft.GranularTerrain(q.dm_quadruped_model(), "poppy_cp", floor="auto", implicit=True).step(
            mujoco.MjData(q.dm_quadruped_model()), 2)
    rows = [rest_row(name, implicit, args.seconds) for name in args.robots for implicit in (False, True)]
    print(f"at rest on poppy_cp at the model's own timestep, {args.seconds:g} s; over the last second, the net "
          "vertical granular force / weight at every step")
    print(f"{'robot':<13} {'mode':<8} {'h ms':>4} {'elements':>8} {'Fz/W min':>9} {'Fz/W max':>9} {'max |dev|':>9} "
          f"{'mean':>7} {'joint speed':>11} {'springs dt ms':>13} {'step dt ms':>10} {'limit warn':>10} "
          f"{'wall s':>6}  chatter warnings (body<seen before)")
    for r in rows:
        print(f"{r['robot']:<13} {r['mode']:<8} {1e3 * r['h']:>4g} {r['elements']:>8d} {r['min']:>9.5f} "
              f"{r['max']:>9.5f} {r['dev']:>9.1e} {r['mean']:>7.4f} {r['qvel']:>11.2e} {1e3 * r['springs']:>13.3g} "
              f"{1e3 * r['step']:>10.3g} {r['limit']:>10d} {r['wall']:>6.1f}  {r['chatter']}")
    print()
    print("3 s of the open-loop trot after 1 s of rest, implicit step")
    print(f"{'robot':<13} {'dx m':>7} {'dy m':>7} {'Fz/W mean':>9} {'upright':>7} {'limit warn':>10}  chatter warnings")
    for name in args.robots:
        r = trot_row(name)
        print(f"{r['robot']:<13} {r['dx']:>7.3f} {r['dy']:>7.3f} {r['load']:>9.4f} {r['upright']:>7.3f} "
              f"{r['limit']:>10d}  {r['chatter']}")


if __name__ == "__main__":
    main()

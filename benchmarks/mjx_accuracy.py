"""How closely mjrft.mjx reproduces the CPU path: the wrench on recorded walking states, and a resting robot.

1. Wrench. The hexapod walks a 2 Hz tripod on the CPU path (``mj_step1``, ``GranularTerrain.compute``,
   ``mj_step2``); every 40 steps the state after ``mj_step1`` and the elements' memory are recorded, and
   :meth:`mjrft.mjx.Sand.wrench` evaluates the same state with the same memory, in float64 and in float32. Printed:
   the largest difference of any body's wrench component (and of the memory) relative to the largest value, per law.
2. Rest. The hexapod stands on poppy seeds for 1 s from its initial pose, on the CPU path and with
   ``Sand.step`` in MJX (float32 and float64): net vertical granular force over the weight, torso height and the
   difference of the torso heights.

    python benchmarks/mjx_accuracy.py        # writes benchmarks/results/mjx_accuracy.txt
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import jax
import jax.numpy as jnp
import mujoco
import numpy as np
from mujoco import mjx

import mjrft
import mjrft.mjx as rmjx
from mjrft.mjx.compare import record_states
from mjrft.mjx.compare import wrench_errors as errors

OUT = Path(__file__).resolve().parent / "results" / "mjx_accuracy.txt"
OFFSETS = np.array([0.0, np.pi, 0.0, np.pi, 0.0, np.pi])
LAWS = ("rft", "rft3d", "depth_only", "hybrid")


def wrench_errors(law: str) -> list[str]:
    model = mujoco.MjModel.from_xml_path(mjrft.models.model_path("hexapod"))
    terrain = mjrft.GranularTerrain(model, law=law)
    states = record_states(model, terrain, steps=400, every=40, ctrl=lambda t: 2 * np.pi * 2.0 * t + OFFSETS)
    sand = rmjx.Sand.from_terrain(terrain)
    lines = []
    for x64 in (True, False):
        ew, eu = errors(sand, model, states, x64)
        lines.append(f"{law:<11} {'float64' if x64 else 'float32':<8} {len(states):>6} {ew:>14.2e} {eu:>14.2e}")
    return lines


def rest(seconds: float = 1.0) -> list[str]:
    model = mujoco.MjModel.from_xml_path(mjrft.models.model_path("hexapod"))
    weight = float(model.body_subtreemass[0]) * -float(model.opt.gravity[2])
    n = int(round(seconds / model.opt.timestep))
    terrain = mjrft.GranularTerrain(model)
    data = mujoco.MjData(model)
    terrain.step(data, n)
    z_cpu = float(data.qpos[2])
    lines = [f"{'CPU (numba)':<14} {terrain.wrench[:, 2].sum() / weight:>10.5f} {1e3 * z_cpu:>12.3f} {'':>12}"]
    for x64 in (True, False):
        with jax.enable_x64(x64):
            m2 = mujoco.MjModel.from_xml_path(mjrft.models.model_path("hexapod"))
            sand = rmjx.Sand(m2)
            mx = sand.put_model()
            run = jax.jit(lambda d, s: jax.lax.fori_loop(0, n, lambda _, c: sand.step(mx, *c), (d, s)))
            d, s = run(mjx.make_data(mx), sand.init())
            z = float(d.qpos[2])
            lines.append(f"{'MJX ' + ('float64' if x64 else 'float32'):<14} {rmjx.resting_load(sand, s):>10.5f} "
                         f"{1e3 * z:>12.3f} {1e3 * (z - z_cpu):>+12.4f}")
    return lines


def main() -> int:
    warnings.simplefilter("ignore")
    lines = ["python benchmarks/mjx_accuracy.py", f"jax {jax.__version__} on {jax.devices()[0].platform}, "
             f"mujoco {mujoco.__version__}", "",
             "1. Wrench on recorded walking states (hexapod, 2 Hz tripod, every 40th of 400 steps), max |JAX - numba| "
             "over max |numba|:",
             f"{'law':<11} {'dtype':<8} {'states':>6} {'wrench':>14} {'memory u':>14}"]
    for law in LAWS:
        lines += wrench_errors(law)
        print("\n".join(lines[-2:]), flush=True)
    lines += ["", "2. Hexapod resting on poppy_cp for 1 s from its initial pose:",
              f"{'path':<14} {'Fz / weight':>10} {'torso z mm':>12} {'z - CPU mm':>12}"]
    lines += rest()
    text = "\n".join(lines) + "\n"
    print(text)
    OUT.write_text(text)
    print(f"wrote {OUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""The JAX twins of the kernel's per-element physics (mjrft.mjx.laws, .forces, .surface, .memory): how closely they
reproduce the numba originals, and what each part of a scene costs.

1. Accuracy. Random element states (depths across the sand surface and a 10 mm water layer, unit normals and
   motions with axis-aligned, face-on, trailing and edge-on ones mixed in, speeds from 0 to 5 m/s) evaluated by each
   law's twin, by the general pass (``region_force``) on six regions (every law, water layers, open water,
   buoyancy, the inertial regime) laid out as strips and as a map with transitions, and by ``surface_height`` on a
   yawed height field, in float64 and in float32, against the numba functions: the largest difference over the
   largest value. Also: the share of ``a * b + c * d`` that XLA rounds differently from numpy (it fuses
   multiply-adds), the reason a twin can differ from numba by more than an ulp where a formula amplifies one.
2. Cost on this machine's JAX backend: one call of ``region_force`` (with ``surface_height`` where the scene has a
   height field) on 4,096 elements per scene, and of each law's stress alone, float32, median of 30 calls, relative
   to one region of Li RFT.

    python benchmarks/mjx_forces.py        # writes benchmarks/results/mjx_forces.txt
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import mujoco
import numpy as np

from mjrft import forces as KF
from mjrft import surface as KS
from mjrft.laws.dispatch import element_stress
from mjrft.laws.registry import LAWS, parameter_vector
from mjrft.params import P_WATER_DEPTH
from mjrft.media import get_medium
from mjrft.mjx import forces as F
from mjrft.mjx import laws as J
from mjrft.mjx import surface as S
from mjrft.regions import RegionMap, build_regions
from mjrft.settings import resolve_settings

OUT = Path(__file__).resolve().parent / "results" / "mjx_forces.txt"
DELTA, V_EPS, GRAVITY = 0.002, 0.01, 9.81
REGIONS = [("sea_sand_saturated", "wet", 0.01), ("poppy_cp", "hybrid"), ("sea_sand_saturated", "water", 0.02),
           ("poppy_cp", "rft3d"), ("poppy_cp", "depth_only", 0.005)]


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def states(k: int, seed: int = 0) -> dict:
    rng = np.random.default_rng(seed)
    n = _unit(rng.normal(size=(k, 3)))
    n[: k // 20] = [0.0, 0.0, -1.0]
    mhat = _unit(rng.normal(size=(k, 3)))
    mhat[k // 20: k // 10] = n[k // 20: k // 10]  # face-on
    mhat[k // 10: k // 10 + k // 20] = _unit(mhat[k // 10: k // 10 + k // 20] * [1.0, 1.0, 0.0])  # horizontal
    ml = 10.0 ** rng.uniform(-4.5, -1.5, k)
    speed = 10.0 ** rng.uniform(-4.0, 0.7, k)
    speed[: k // 50] = 0.0
    vel = np.where(rng.random((k, 1)) < 0.5, mhat, _unit(rng.normal(size=(k, 3)))) * speed[:, None]
    depth = rng.uniform(-0.03, 0.08, k)
    ml = np.where(depth > 0.0, ml, 0.0)
    return dict(px=rng.uniform(-0.35, 0.35, k), py=rng.uniform(-0.3, 0.3, k), depth=depth, n=n, mhat=mhat,
                m=mhat * ml[:, None], ml=ml, mob=np.minimum(1.0, ml / DELTA), vel=vel,
                speed=np.linalg.norm(vel, axis=1), area=rng.uniform(1e-5, 1e-4, k))


def model():
    elev = " ".join(f"{v:.4f}" for v in np.random.default_rng(1).uniform(0.0, 1.0, 35))
    return mujoco.MjModel.from_xml_string(f"""<mujoco><asset>
        <hfield name="hf" nrow="5" ncol="7" size="0.3 0.2 0.05 0.01" elevation="{elev}"/></asset><worldbody>
        <geom name="ground" type="hfield" hfield="hf" pos="0.05 -0.02 -0.01" euler="0 0 30"/>
        <body name="box" pos="0 0 0.1"><freejoint/><geom type="box" size="0.02 0.02 0.02"/></body>
        </worldbody></mujoco>""")


def settings(m, **kw):
    kw = {"medium": "poppy_cp", "law": "rft", "buoyancy": True, "inertial": True, **kw}
    return resolve_settings(m, bodies=["box"], surface="ground", resolution=0.01, **kw)


def scenes(m) -> dict:
    """name -> (region tables, transition, height field or None)."""
    flat = build_regions(settings(m, inertial=False))[1]
    s = settings(m, inertial=False)
    return {
        "rft, one region": (flat, 0.0, None),
        "rft, one region, height field": (flat, 0.0, (s.hf_z, s.hf_frame)),
        "wet + water layer + buoyancy, one region": (
            build_regions(settings(m, medium="sea_sand_saturated", law="wet", water_depth=0.01, inertial=False))[1],
            0.0, None),
        "six laws, strips (2 slots)": (
            build_regions(settings(m, regions=[(x, *r) for x, r in zip((-0.2, -0.1, 0.0, 0.1, 0.2), REGIONS)],
                                   transition=0.02))[1], 0.02, None),
        "six laws, map (4 slots)": (
            build_regions(settings(m, regions=REGIONS, transition=0.04,
                                   region_map=RegionMap(np.array([[0, 1, 2, 3], [4, 5, 0, 2], [1, 1, 3, 5]]),
                                                        -0.2, -0.15, 0.1)))[1], 0.04, None),
    }


def pass_fn(features, tables, blend, hf):
    """``region_force`` on element states ``e`` with the region tables as arguments (not constants the compiler
    could fold: a world's own parameters arrive so)."""
    def run(e, law, params, rho, bounds, rmap, frame):
        depth = e["depth"]
        if hf is not None:  # below the height field at each element's (x, y), the element at height -depth
            depth = S.surface_height(e["px"], e["py"], 0.0, hf[0], hf[1]) + e["depth"]
        return F.region_force(features, e["px"], e["py"], depth, e["n"], e["m"], e["ml"], e["mob"], e["vel"],
                              e["speed"], e["area"], reg_law=law, reg_params=params, reg_rho=rho, reg_bounds=bounds,
                              reg_map=rmap, reg_map_frame=frame, blend=blend, gravity=GRAVITY, delta=DELTA,
                              v_eps=V_EPS)

    jitted = jax.jit(run)
    args = tuple(jnp.asarray(x) for x in (tables.law, tables.params, tables.rho, tables.bounds, tables.map,
                                          tables.map_frame))
    return lambda e: jitted(e, *args)


def numba_pass(e, tables, blend) -> np.ndarray:
    out = np.zeros((e["depth"].size, 7))
    for i in range(e["depth"].size):
        regs, wts = KS.region_weights(e["px"][i], e["py"][i], tables.bounds, tables.map, tables.map_frame, blend)
        out[i] = KF.blended_force(regs, wts, tables.law, tables.params, tables.rho, GRAVITY, e["area"][i],
                                  e["depth"][i], *e["n"][i], *e["m"][i], e["ml"][i], e["mob"][i], *e["vel"][i],
                                  e["speed"][i], DELTA, V_EPS)
    return out


def rel(a, b, rows=None) -> float:
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    if rows is not None:
        a, b = a[rows], b[rows]
    return float(np.abs(a - b).max() / np.abs(b).max())


def accuracy(m) -> list[str]:
    e = states(4000)
    lines = [f"{'twin':<44} {'float64':>10} {'float32':>10}"]
    for law in LAWS:
        p = parameter_vector(get_medium("sea_sand_saturated" if law.name in ("wet", "water") else "poppy_cp"))
        p[P_WATER_DEPTH] = 0.01
        ref = np.array([element_stress(law.id, d, *nn, *mm, s, p)
                        for d, nn, mm, s in zip(e["depth"], e["n"], e["mhat"], e["speed"])])
        cols = []
        for x64 in (True, False):
            with jax.enable_x64(x64):
                out = jax.jit(J.LAWS[law.name])(*(jnp.asarray(e[k]) for k in ("depth", "n", "mhat")), jnp.asarray(p),
                                                jnp.asarray(e["speed"]))
            cols.append(rel(out, ref))
        lines.append(f"{'law ' + law.name:<44} {cols[0]:>10.2e} {cols[1]:>10.2e}")
        if law.name == "rft3d":
            flat = e["mhat"][:, 2] != 0.0
            with jax.enable_x64(True):
                out = jax.jit(J.rft3d)(*(jnp.asarray(e[k]) for k in ("depth", "n", "mhat")), jnp.asarray(p))
            lines.append(f"{'  without exactly horizontal motion':<44} {rel(out, ref, flat):>10.2e}")
    for name, (tables, blend, _) in scenes(m).items():
        if "one region" in name:
            continue
        features = F.Features.of(tables.law, tables.params, tables.rho)
        ref = numba_pass(e, tables, blend)
        cols = []
        for x64 in (True, False):
            with jax.enable_x64(x64):
                out = pass_fn(features, tables, blend, None)({k: jnp.asarray(v) for k, v in e.items()})
            good = ref[:, 6] > 0.5
            cols.append(max(rel(out[0], ref[:, :3], good), rel(out[1], ref[:, 3], good)))
        lines.append(f"{'region_force, ' + name:<44} {cols[0]:>10.2e} {cols[1]:>10.2e}")
    s = settings(m)
    ref = np.array([KS.surface_height(x, y, 0.0, s.hf_z, s.hf_frame) for x, y in zip(e["px"], e["py"])])
    cols = []
    for x64 in (True, False):
        with jax.enable_x64(x64):
            out = jax.jit(lambda x, y: S.surface_height(x, y, 0.0, s.hf_z, s.hf_frame))(e["px"], e["py"])
        cols.append(rel(out, ref))
    lines.append(f"{'surface_height (height field)':<44} {cols[0]:>10.2e} {cols[1]:>10.2e}")
    return lines


def fma_share() -> float:
    a, b, c, d = np.random.default_rng(0).normal(size=(4, 100_000))
    with jax.enable_x64(True):
        out = np.asarray(jax.jit(lambda a, b, c, d: a * b + c * d)(a, b, c, d))
    return float(np.mean(out != a * b + c * d))


def cost(m, k: int = 4096, calls: int = 30) -> list[str]:
    e = {key: jnp.asarray(v, jnp.float32) for key, v in states(k, seed=1).items()}
    rows = []
    all_six = F.Features(tuple(range(len(LAWS))), inertia=True, water=True, buoyancy=True)
    cases = [(name, F.Features.of(t.law, t.params, t.rho), t, blend, hf) for name, (t, blend, hf) in scenes(m).items()]
    flat = cases[0][2]
    cases.insert(1, ("rft, one region, every law and part traced", all_six, flat, 0.0, None))
    for name, features, tables, blend, hf in cases:
        rows.append((name, _median(pass_fn(features, tables, blend, hf), (e,), calls)))
    p = jnp.asarray(parameter_vector(get_medium("poppy_cp")), jnp.float32)
    for law in LAWS:  # each law's stress alone (mjrft.mjx.laws), one parameter vector
        fn = jax.jit(lambda d, n, mh, p, s, fn=J.LAWS[law.name]: fn(d, n, mh, p, s))
        args = (e["depth"], e["n"], e["mhat"], p, e["speed"])
        rows.append((f"law {law.name} alone (its stress)", _median(fn, args, calls)))
    base = rows[0][1]
    return [f"{'scene':<46} {'us/call':>9} {'ns/element':>11} {'/ rft':>7}"] + [
        f"{name:<46} {1e6 * t:>9.1f} {1e9 * t / k:>11.1f} {t / base:>7.2f}" for name, t in rows]


def _median(fn, args, calls: int) -> float:
    jax.block_until_ready(fn(*args))
    times = []
    for _ in range(calls):
        t = time.perf_counter()
        jax.block_until_ready(fn(*args))
        times.append(time.perf_counter() - t)
    return float(np.median(times))


def main() -> None:
    m = model()
    lines = ["python benchmarks/mjx_forces.py",
             f"jax {jax.__version__} on {jax.default_backend()}, mujoco {mujoco.__version__}", "",
             "1. Largest |JAX - numba| over the largest |numba| on 4,000 random element states "
             "(force and stiffness for region_force):"]
    lines += accuracy(m)
    lines += ["", f"XLA ({jax.default_backend()}) rounds a * b + c * d differently from numpy in "
              f"{100 * fma_share():.1f} % of 100,000 random float64 cases (fused multiply-add).", "",
              "2. Cost of one call on 4,096 elements, float32, median of 30 calls:"]
    lines += cost(m)
    text = "\n".join(lines) + "\n"
    sys.stdout.write(text)
    OUT.write_text(text)


if __name__ == "__main__":
    main()

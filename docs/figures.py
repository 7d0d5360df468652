"""Make the figures of the README and the user guide (``docs/img/*.png``).

    python docs/figures.py              # every figure
    python docs/figures.py hero laws    # some of them (names: see FIGURES)

Every figure is computed here from mjrft itself; nothing is drawn by hand. The rendered frames use
MuJoCo's offscreen ``mujoco.Renderer`` through EGL (``MUJOCO_GL=egl``, set below unless the caller chose
a backend; Mesa's software EGL works without a GPU). Each figure also writes the numbers it shows to
``benchmarks/results/figures.txt`` (one block per figure, replaced when the figure is made again).
"""

from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")  # before mujoco is imported: the offscreen backend
os.environ.setdefault("PYOPENGL_PLATFORM", os.environ["MUJOCO_GL"])

import argparse  # noqa: E402
import math  # noqa: E402
import sys  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import mujoco  # noqa: E402
import numpy as np  # noqa: E402

import gymnasium  # noqa: E402
import mjrft  # noqa: E402
import mjrft.ground  # noqa: E402
from mjrft.tools import rigs  # noqa: E402
from mjrft.tools.gaits import make_gait  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
IMG = ROOT / "docs" / "img"
NUMBERS = ROOT / "benchmarks" / "results" / "figures.txt"
CMAP = "viridis"
DPI = 110
ELEMENT_OBJTYPE = int(mujoco.mjtObj.mjOBJ_UNKNOWN)  # the added element geoms, as the segmentation sees them


def _record(name: str, lines: list[str]) -> None:
    """Write the numbers behind figure ``name`` to ``benchmarks/results/figures.txt`` (replacing its block)."""
    blocks = {}
    if NUMBERS.exists():
        current = None
        for line in NUMBERS.read_text().splitlines():
            if line.startswith("== "):
                current = line[3:].split(" ", 1)[0]
                blocks[current] = [line]
            elif current is not None and line.strip():
                blocks[current].append(line)
    blocks[name] = [f"== {name} (python docs/figures.py {name})", *lines]
    NUMBERS.write_text("\n\n".join("\n".join(blocks[key]) for key in sorted(blocks)) + "\n")


def _walk(seconds: float, *, medium: str = "poppy_cp", gait: str = "tripod:f=2", **kwargs):
    """The hexapod env after ``seconds`` of ``gait`` from ``reset(seed=0)`` (warnings of the terrain muted)."""
    env = gymnasium.make("mjrft/HexapodSand-v0", medium=medium, **kwargs)
    policy = make_gait(gait, env)
    obs, _ = env.reset(seed=0)
    u = env.unwrapped
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        while u.data.time < seconds - 1e-9:
            obs, *_ = env.step(policy.predict(obs)[0])
    return env


def _buried(terrain):
    """Index, stress |F|/A (Pa) of the elements below the surface after the last step."""
    idx = np.flatnonzero(terrain.depth > 0.0)
    stress = np.linalg.norm(terrain.force[idx], axis=1) / terrain.area[idx]
    return idx, stress


def _add_element_geoms(scene, terrain, idx, stress, vmax: float) -> int:
    """Append one thin box per buried element to a ``mujoco.MjvScene``, oriented with the element's normal,
    coloured by stress; returns how many were added (the scene's ``maxgeom`` bounds it)."""
    cmap = matplotlib.colormaps[CMAP]
    added = 0
    for e, s in zip(idx, stress):
        if scene.ngeom >= scene.maxgeom:
            break
        n = terrain.normal[e]
        t = np.cross(n, [0.0, 0.0, 1.0] if abs(n[2]) < 0.9 else [1.0, 0.0, 0.0])
        t /= np.linalg.norm(t)
        mat = np.column_stack([t, np.cross(n, t), n])  # columns: the box's x, y, z axes (z = normal)
        half = 0.55 * math.sqrt(terrain.area[e])  # a little larger than the cell: no gaps between neighbours
        rgba = np.array(cmap(min(s / vmax, 1.0)), dtype=np.float32)
        mujoco.mjv_initGeom(scene.geoms[scene.ngeom], int(mujoco.mjtGeom.mjGEOM_BOX),
                            np.array([half, half, 0.0008]), terrain.pos[e] + 0.0005 * n, mat.ravel(), rgba)
        scene.geoms[scene.ngeom].emission = 0.4
        scene.geoms[scene.ngeom].objtype = ELEMENT_OBJTYPE  # found again in the segmentation image
        scene.geoms[scene.ngeom].objid = int(e)
        scene.geoms[scene.ngeom].segid = scene.ngeom
        scene.ngeom += 1
        added += 1
    return added


def hero(out: Path = IMG / "hexapod_sand.png") -> Path:
    """The hexapod on poppy seeds in its tripod gait, every buried surface element coloured by its stress."""
    t = 1.52
    env = _walk(t)
    u = env.unwrapped
    model, data, terrain = u.model, u.data, u.terrain
    model.mat_rgba[model.mat("sand").id] = (0.84, 0.72, 0.50, 0.35)  # translucent, so the buried elements show
    model.geom_rgba[model.geom("bed_bottom").id, 3] = 0.0  # the bed's bottom plane stays out of the picture
    model.mat_reflectance[:] = 0.0
    model.vis.global_.offwidth, model.vis.global_.offheight = 1280, 720
    idx, stress = _buried(terrain)
    vmax = float(np.percentile(stress, 98))
    cam = mujoco.MjvCamera()
    cam.type = mujoco.mjtCamera.mjCAMERA_FREE
    cam.lookat[:] = data.xpos[model.body("torso").id] + [0.0, 0.0, -0.035]
    cam.distance, cam.azimuth, cam.elevation = 0.26, 140.0, -16.0
    opt = mujoco.MjvOption()
    sand_rgba = model.mat_rgba[model.mat("sand").id].copy()
    with mujoco.Renderer(model, 720, 1280) as renderer:
        renderer.update_scene(data, cam, opt)
        shown = _add_element_geoms(renderer.scene, terrain, idx, stress, vmax)
        image = renderer.render().astype(np.float64)
        # the elements seen through the sand: the same view without the sand, its element pixels laid over
        model.mat_rgba[model.mat("sand").id, 3] = 0.0
        renderer.update_scene(data, cam, opt)
        _add_element_geoms(renderer.scene, terrain, idx, stress, vmax)
        clear = renderer.render().astype(np.float64)
        renderer.enable_segmentation_rendering()
        seg = renderer.render()[..., 1]
        renderer.disable_segmentation_rendering()
    model.mat_rgba[model.mat("sand").id] = sand_rgba
    mask = seg == ELEMENT_OBJTYPE
    image[mask] = 0.8 * clear[mask] + 0.2 * image[mask]
    image = image.round().astype(np.uint8)
    fig, ax = plt.subplots(figsize=(11.6, 6.9), dpi=DPI)
    ax.imshow(image)
    ax.set_axis_off()
    sm = plt.cm.ScalarMappable(cmap=CMAP, norm=plt.Normalize(0.0, vmax / 1e3))
    bar = fig.colorbar(sm, ax=ax, fraction=0.03, pad=0.01)
    bar.set_label("element stress |F| / area (kPa)")
    ax.set_title(f"HexapodSand-v0, tripod at 2 Hz on closely packed poppy seeds, t = {t:.2f} s: "
                 f"{len(idx)} of {terrain.n_elements} elements buried", fontsize=10)
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)
    force = terrain.wrench[terrain.body_ids, 2].sum()
    _record("hero", [f"t = {t} s, buried elements {len(idx)} of {terrain.n_elements} (drawn {shown})",
                     f"stress max {stress.max() / 1e3:.2f} kPa, colour scale 0..{vmax / 1e3:.2f} kPa (98th percentile)",
                     f"net vertical granular force {force:.3f} N; robot weight "
                     f"{mujoco.mj_getTotalmass(model) * 9.81:.3f} N"])
    env.close()
    return out


def _box_outline(model, data, g, e1) -> np.ndarray:
    """The outline (convex hull, closed) of box geom ``g`` in the vertical plane spanned by ``e1`` and z."""
    h = model.geom_size[g]
    corners = np.array([[sx * h[0], sy * h[1], sz * h[2]] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    world = data.geom_xpos[g] + corners @ data.geom_xmat[g].reshape(3, 3).T
    pts = np.column_stack([world @ e1, world[:, 2]])
    c = pts.mean(axis=0)
    order = np.argsort(np.arctan2(pts[:, 1] - c[1], pts[:, 0] - c[0]))
    hull = [pts[i] for i in order]
    return np.array(hull + hull[:1])


def _element_schematic(ax, medium: str = "poppy_cp", beta_deg: float = 30.0, gamma_deg: float = 45.0) -> list[str]:
    """One element of a plate at attack angle beta moving at intrusion angle gamma, with Li's stress."""
    med = mjrft.get_medium(medium)
    beta, gamma = math.radians(beta_deg), math.radians(gamma_deg)
    az, ax_ = (float(v) for v in med.alpha(beta, gamma))
    depth = 0.5
    c = np.array([0.0, -depth])
    t = np.array([math.cos(beta), math.sin(beta)])  # the plate's line in the (r, z) plane
    n = np.array([math.sin(beta), -math.cos(beta)])  # its leading face's outward normal
    m = np.array([math.cos(gamma), -math.sin(gamma)])  # direction of motion
    ax.axhspan(-1.1, 0.0, color="#e3cf9f", zorder=0)
    ax.axhline(0.0, color="#8a6d3b", lw=1.2)
    ax.text(-0.95, 0.04, "free surface", fontsize=8, color="#8a6d3b")
    ax.plot(*np.array([c - 0.28 * t, c + 0.28 * t]).T, color="#c45a1a", lw=6, solid_capstyle="butt")
    arrow = dict(width=0.012, head_width=0.05, length_includes_head=True)
    ax.arrow(*c, *(0.35 * n), color="k", **arrow)
    ax.text(*(c + 0.35 * n + [-0.1, -0.04]), "n", fontsize=11)
    ax.arrow(*c, *(0.45 * m), color="#1f5fa8", **arrow)
    ax.text(*(c + 0.5 * m + [0.03, 0.0]), "v", fontsize=11, color="#1f5fa8")
    f = np.array([-ax_, az])
    f = 0.45 * f / np.linalg.norm(f)
    ax.arrow(*c, *f, color="#b2182b", **arrow)
    ax.text(*(c + f + [-0.1, 0.02]), "F", fontsize=11, color="#b2182b")
    ax.annotate("", xy=(-0.55, 0.0), xytext=(-0.55, -depth), arrowprops=dict(arrowstyle="<->", lw=1))
    ax.text(-0.52, -depth / 2, "|z|", fontsize=10)
    ax.plot([c[0], c[0] + 0.3], [c[1], c[1]], color="0.4", lw=0.8, ls=":")
    ax.text(c[0] + 0.3, c[1] + 0.04, f"beta = {beta_deg:g} deg", fontsize=8)
    ax.text(c[0] + 0.36, c[1] - 0.2, f"gamma = {gamma_deg:g} deg", fontsize=8, color="#1f5fa8")
    ax.text(-0.98, -1.05, f"F = A |z| (-alpha_x r + alpha_z z)\n{medium}: alpha_z = {az / 1e6:.3f}, "
            f"alpha_x = {ax_ / 1e6:.3f} N/cm^3", fontsize=8, va="bottom")
    ax.set_xlim(-1.0, 1.0)
    ax.set_ylim(-1.1, 0.25)
    ax.set_aspect("equal")
    ax.set_axis_off()
    ax.set_title("one element: Li 2013 RFT in its vertical plane of motion", fontsize=10)
    return [f"schematic: {medium}, beta {beta_deg} deg, gamma {gamma_deg} deg: alpha_z {az / 1e6:.4f} N/cm^3, "
            f"alpha_x {ax_ / 1e6:.4f} N/cm^3"]


def element_model(out: Path = IMG / "element_model.png") -> Path:
    """A walking hexapod's most loaded leg cut into surface elements (side view), and one element's law."""
    t = 1.52
    env = _walk(t)
    u = env.unwrapped
    model, data, terrain = u.model, u.data, u.terrain
    legs = [model.body(f"leg_{n}").id for n in ("lf", "lm", "lr", "rf", "rm", "rr")]
    leg = max(legs, key=lambda b: abs(terrain.wrench[b, 2]))
    name = model.body(leg).name
    idx, stress = _buried(terrain)
    mine = terrain.elem_body[idx] == leg
    idx, stress = idx[mine], stress[mine]
    axis = data.xaxis[model.body_jntadr[leg]]  # the hip axis: the leg turns in the plane normal to it
    e1 = np.cross(axis, [0.0, 0.0, 1.0])
    e1 /= np.linalg.norm(e1)  # horizontal, in the leg's plane of rotation
    fig, (a, b) = plt.subplots(1, 2, figsize=(11.5, 4.8), dpi=DPI, gridspec_kw={"width_ratios": [1.1, 1]})
    top = -np.inf
    for g in np.flatnonzero(model.geom_bodyid == leg):
        if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX:
            hull = _box_outline(model, data, g, e1) * 100
            top = max(top, hull[:, 1].max())
            a.fill(hull[:, 0], hull[:, 1], color="#f2b35c", ec="#9c5a12", lw=0.6, alpha=0.7, zorder=2)
    pos = np.column_stack([terrain.pos[idx] @ e1, terrain.pos[idx, 2]]) * 100
    sc = a.scatter(pos[:, 0], pos[:, 1], c=stress / 1e3, cmap=CMAP, s=9, zorder=3, vmin=0.0)
    force = np.column_stack([terrain.force[idx] @ e1, terrain.force[idx, 2]])
    scale = 0.8 / np.linalg.norm(force, axis=1).max()  # the largest element force: an arrow 0.8 cm long
    a.quiver(pos[:, 0], pos[:, 1], force[:, 0] * scale, force[:, 1] * scale, angles="xy", scale_units="xy",
             scale=1.0, width=0.004, color="#b2182b", zorder=4)
    lo, hi = pos[:, 0].min() - 1.0, pos[:, 0].max() + 1.0
    bottom = pos[:, 1].min() - 0.8
    a.axhspan(bottom, 0.0, color="#e3cf9f", zorder=0)
    a.axhline(0.0, color="#8a6d3b", lw=1.0, zorder=1)
    a.set_xlim(lo, hi)
    a.set_ylim(bottom, max(top, 0.0) + 0.3)
    a.set_aspect("equal")
    a.set_xlabel("horizontal, in the leg's plane of rotation (cm)")
    a.set_ylabel("z (cm), sand surface at 0")
    net = terrain.wrench[leg, :3]
    a.set_title(f"{name} at t = {t} s: {len(idx)} buried elements\n(arrows: element forces; net "
                f"{np.linalg.norm(net[:2]):.2f} N horizontal, {net[2]:.2f} N up)", fontsize=10)
    fig.colorbar(sc, ax=a, fraction=0.04, pad=0.02).set_label("stress |F| / area (kPa)")
    lines = _element_schematic(b)
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)
    elems = int(np.count_nonzero(terrain.elem_body == leg))
    _record("element_model", [f"{name} at t = {t} s (tripod:f=2, poppy_cp, seed 0): {len(idx)} of {elems} elements "
                              f"buried; net force x {net[0]:.3f} N, z {net[2]:.3f} N; stress max {stress.max() / 1e3:.2f} kPa",
                              *lines])
    env.close()
    return out


LAW_CASES = (("rft", "poppy_cp"), ("rft3d", "poppy_cp"), ("depth_only", "poppy_cp"), ("wet", "sea_sand_saturated"))


def laws(out: Path = IMG / "laws.png") -> Path:
    """Li's fit alpha_z, alpha_x against attack angle, and Li's plate (3.81 x 2.54 x 0.64 cm) through every law."""
    med = mjrft.get_medium("poppy_cp")
    beta = np.linspace(-math.pi / 2, math.pi / 2, 181)
    fig, axes = plt.subplots(2, 2, figsize=(11, 7.6), dpi=DPI)
    lines = []
    for gamma_deg in (90, 45, 0, -45, -90):
        az, ax_ = med.alpha(beta, math.radians(gamma_deg))
        axes[0, 0].plot(np.degrees(beta), np.asarray(az) / 1e6, label=f"gamma {gamma_deg} deg")
        axes[0, 1].plot(np.degrees(beta), np.asarray(ax_) / 1e6, label=f"gamma {gamma_deg} deg")
    for a, what in ((axes[0, 0], "alpha_z"), (axes[0, 1], "alpha_x")):
        a.set_xlabel("attack angle beta (deg)")
        a.set_ylabel(f"{what} (N/cm^3)")
        a.set_title(f"{what}(beta, gamma): Li 2013 fit, poppy_cp", fontsize=10)
        a.axhline(0.0, color="0.6", lw=0.6)
        a.legend(fontsize=7)
    depths = np.linspace(0.01, 0.07, 7)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for law, medium in LAW_CASES:
            down = rigs.plate_intrusion(law=law, medium=medium, depth=0.076)
            axes[1, 0].plot(down.depth * 100, down.lift, label=f"{law} ({medium})")
            drag = [rigs.plate_intrusion(beta=math.pi / 2, gamma=0.0, depth=d, distance=0.02, speed=0.01,
                                         law=law, medium=medium).drag[-1] for d in depths]
            axes[1, 1].plot(depths * 100, drag, "o-", ms=3, label=f"{law} ({medium})")
            lines.append(f"{law} on {medium}: lift at 7.6 cm pushed down at 1 cm/s {down.lift[-1]:.2f} N; "
                         f"drag of the upright plate at 1 cm/s: " + ", ".join(f"{d * 100:.0f} cm {f:.2f} N"
                                                                           for d, f in zip(depths, drag)))
    axes[1, 0].set_xlabel("plate centre depth (cm)")
    axes[1, 0].set_ylabel("lift F_z (N)")
    axes[1, 0].set_title("horizontal plate pushed straight down, 1 cm/s", fontsize=10)
    axes[1, 1].set_xlabel("plate centre depth (cm)")
    axes[1, 1].set_ylabel("drag (N)")
    axes[1, 1].set_title("upright plate (beta 90 deg) dragged along x, 1 cm/s", fontsize=10)
    for a in axes[1]:
        a.legend(fontsize=7)
        a.set_xlim(left=0.0)
        a.set_ylim(bottom=0.0)
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)
    _record("laws", lines)
    return out


def media(out: Path = IMG / "media.png") -> Path:
    """The catalogue's plate stress (fit and measured) and Li's scaling routine on one simulated plate test."""
    names = [n for n, m in mjrft.MEDIA.items() if n != "generic"]
    fit = [mjrft.MEDIA[n].alpha_z_down / 1e6 for n in names]
    measured = [(mjrft.MEDIA[n].alpha_z_measured or np.nan) / 1e6 for n in names]
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2), dpi=DPI)
    x = np.arange(len(names))
    a.bar(x - 0.2, fit, 0.4, label="fit alpha_z(0, pi/2)")
    a.bar(x + 0.2, measured, 0.4, label="measured (Li 2013 table S3)")
    a.set_xticks(x, names, rotation=20, fontsize=8)
    a.set_ylabel("stress per depth (N/cm^3)")
    a.set_title("plate pushed straight down: mjrft.MEDIA", fontsize=10)
    a.legend(fontsize=8)
    thickness = 0.0064  # Li's plate: 3.81 x 2.54 x 0.64 cm; depth below is that of its bottom face (Li's |z|)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the depth-only law reproduces table S3's measured plate test
        p = rigs.plate_intrusion(law="depth_only", medium="poppy_lp", depth=0.0762 - thickness / 2)
    depth = p.depth + thickness / 2
    stress = p.lift / p.settings["area"]
    buried = depth > 0.0
    cal = mjrft.calibrate(depth[buried], stress[buried])
    b.plot(depth[buried] * 100, stress[buried] / 1e3, ".", ms=3, label="simulated plate test (depth_only, poppy_lp)")
    d = np.linspace(0.0, depth.max(), 2)
    b.plot(d * 100, cal.alpha_z_measured * d / 1e3, "-", label=f"zero-intercept fit: {cal.alpha_z_measured / 1e6:.3f} N/cm^3")
    b.set_xlabel("depth of the plate's bottom face (cm)")
    b.set_ylabel("lift / plate area (kPa)")
    zeta, ref = cal.zeta / 1e6, mjrft.MEDIA["poppy_lp"].zeta / 1e6
    b.set_title(f"mjrft.calibrate: zeta = slope / 1.26 = {zeta:.3f} N/cm^3 (table S2: {ref:.3f})", fontsize=10)
    b.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)
    _record("media", [f"{n}: fit {f:.3f} N/cm^3, measured " + ("none" if np.isnan(m) else f"{m:.3f} N/cm^3")
                      for n, f, m in zip(names, fit, measured)]
            + [f"calibrate on the simulated poppy_lp plate test (depth_only law = table S3's measured plate): slope {cal.alpha_z_measured / 1e6:.4f} N/cm^3, "
               f"zeta {zeta:.4f} N/cm^3 (catalogue {ref:.4f}, {100 * (zeta / ref - 1):+.1f} %)"])
    return out


def rest(out: Path = IMG / "rest.png") -> Path:
    """Rest regularisation: Li's plate, horizontal, placed at rest 2 cm deep (empty memory), pressed down,
    backed off 1.5 mm and pressed again (kinematic, 1 mm/s), against the same plate pushed in from the surface."""
    from mjrft.models.rigs import plate_rig_xml

    model = mujoco.MjModel.from_xml_string(plate_rig_xml())
    data = mujoco.MjData(model)
    terrain = mjrft.GranularTerrain(model, "poppy_cp", "rft", bodies=["plate"], resolution=0.005)
    body = model.body("plate").id
    z0 = model.body_pos[body, 2]
    legs = [(0.020, 0.026), (0.026, 0.0245), (0.0245, 0.030)]  # plate-centre depth, m: down, up 1.5 mm, down
    speed, dt = 1e-3, 1e-3
    depth, lift, ends = [], [], []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # kinematic: the stability check speaks of a free body
        for start, stop in legs:
            n = int(round(abs(stop - start) / (speed * dt)))
            sign = 1.0 if stop > start else -1.0
            for k in range(1, n + 1):
                d = start + sign * speed * dt * k
                data.qpos[:] = (0.0, -d - z0, 0.0)
                data.qvel[:] = (0.0, -sign * speed, 0.0)
                data.time += dt
                mujoco.mj_fwdPosition(model, data)
                mujoco.mj_fwdVelocity(model, data)
                terrain.compute(data, dt)
                depth.append(d)
                lift.append(terrain.wrench[body, 2])
            ends.append(len(depth) - 1)
        steady = rigs.plate_intrusion(depth=0.030, speed=speed, resolution=0.005, step=1e-4)
    depth, lift = np.array(depth), np.array(lift)
    fig, a = plt.subplots(figsize=(7.5, 4.2), dpi=DPI)
    keep = steady.depth >= 0.0
    a.plot(steady.depth[keep] * 1000, steady.lift[keep], "--", lw=1, color="0.4",
           label="pushed in from the surface (steady motion: the law)")
    a.plot(depth * 1000, lift, lw=1.5, label="placed at rest 20 mm deep, then moved")
    for i, (txt, dx, dy) in zip(ends, (("press 6 mm", -60, 8), ("back off 1.5 mm", -95, -10), ("press again", -60, 8))):
        a.annotate(txt, xy=(depth[i] * 1000, lift[i]), xytext=(dx, dy), textcoords="offset points", fontsize=8,
                   arrowprops=dict(arrowstyle="-", lw=0.5))
    a.set_xlabel("plate centre depth (mm)")
    a.set_ylabel("lift F_z (N)")
    a.set_xlim(14.0, 31.0)
    a.set_title("Li's plate, horizontal, on poppy_cp, 1 mm/s (yield_displacement delta = 1 mm)", fontsize=10)
    a.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)
    ref = lambda d: float(np.interp(d, steady.depth, steady.lift))  # noqa: E731
    first = int(np.argmax(depth >= 0.022))
    _record("rest", [f"placed at 20 mm, pressed: {lift[first]:.2f} N at 22 mm (steady {ref(0.022):.2f} N), "
                     f"{lift[ends[0]]:.2f} N at 26 mm (steady {ref(0.026):.2f} N)",
                     f"backed off 1.5 mm: {lift[ends[1]]:.2f} N at 24.5 mm; pressed again: {lift[ends[2]]:.2f} N at 30 mm "
                     f"(steady {ref(0.030):.2f} N)"])
    return out


def tradeoff(out: Path = IMG / "speed_accuracy.png") -> Path:
    """The two robots of the committed speed/accuracy study (``python benchmarks/trade_study.py`` ->
    ``benchmarks/results/trade_study.csv``; nothing is re-run here): cost against RMS force error."""
    import csv

    rows = list(csv.DictReader(open(ROOT / "benchmarks" / "results" / "trade_study.csv")))
    marks = {"resolution": ("o", "tab:blue"), "law": ("s", "tab:orange"), "timestep": ("^", "tab:green"),
             "frame_skip": ("v", "tab:purple")}
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.3), dpi=DPI)
    lines = []
    for ax, scenario, title in zip(axes, ("hexapod", "humanoid"),
                                   ("hexapod, tripod at 2 Hz, held planar", "humanoid on one foot, 30.4 cm boards")):
        mine = [r for r in rows if r["scenario"] == scenario and r["status"] == "ok" and r["config"] != "reference"]
        for factor, (m, c) in marks.items():
            pts = [r for r in mine if r["factor"] == factor]
            ax.scatter([float(r["cost_ratio"]) for r in pts], [100 * float(r["err_rms_force"]) for r in pts],
                       marker=m, color=c, label=factor.replace("_", " "), s=28)
        for r in mine:
            name = r["config"].replace("resolution", "res")
            cost, err = float(r["cost_ratio"]), 100 * float(r["err_rms_force"])
            if r["config"].startswith(("default", "preset", "resolution x4")):
                ax.scatter([cost], [err], marker="D", color="k", s=40, zorder=3)
                ax.annotate(name, (cost, err), xytext=(4, 4), textcoords="offset points", fontsize=8)
                lines.append(f"{scenario}: {r['config']}: cost {cost:.2f}x bare, RMS force error {err:.2f} %")
        ax.set_xscale("log")
        ax.set_yscale("log")
        costs = [float(r["cost_ratio"]) for r in mine]
        ax.set_xticks([t for t in (0.5, 1, 2, 5, 10, 20, 50, 100) if min(costs) / 1.5 <= t <= 1.5 * max(costs)])
        ax.xaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))  # 1, 2, 5, 10: labels that never overlap
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_xlabel("cost per simulated second (x the same robot on rigid ground)")
        ax.set_ylabel("RMS net granular force error (%)")
        ax.set_title(title, fontsize=10)
        ax.grid(True, which="both", lw=0.3)
        ax.legend(fontsize=7, title="varied", title_fontsize=7)
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)
    _record("tradeoff", ["read from benchmarks/results/trade_study.csv (python benchmarks/trade_study.py)", *lines])
    return out


def ground(out: Path = IMG / "ground_memory.png") -> Path:
    """The ground memory after the hexapod's tripod walk: the grains' surface (footprints, ridges) and packing."""
    seconds = 3.0
    env = _walk(seconds, ground_memory=True)
    u = env.unwrapped
    t = u.terrain
    gt, st = t.terrain_model.ground, t.terrain_state
    h, phi = st.g_height, st.g_phi
    changed = (np.abs(h) > 1e-6) | (np.abs(phi - gt.pack[3]) > 1e-6)
    rows, cols = np.nonzero(changed.any(axis=1))[0], np.nonzero(changed.any(axis=0))[0]
    j0, j1, i0, i1 = rows[0] - 3, rows[-1] + 4, cols[0] - 3, cols[-1] + 4
    c = gt.frame[2]
    ext = [gt.frame[0] + i0 * c, gt.frame[0] + i1 * c, gt.frame[1] + j0 * c, gt.frame[1] + j1 * c]
    fig, axes = plt.subplots(2, 1, figsize=(8.0, 5.4), constrained_layout=True)
    hv = h[j0:j1, i0:i1] * 1e3
    lim = float(np.abs(hv).max())
    im = axes[0].imshow(hv, origin="lower", extent=ext, cmap="BrBG", vmin=-lim, vmax=lim)
    fig.colorbar(im, ax=axes[0], label="surface (mm)")
    axes[0].set_title(f"grains' surface after {seconds:g} s of the 2 Hz tripod: footprints and ridges")
    im = axes[1].imshow(phi[j0:j1, i0:i1], origin="lower", extent=ext, cmap="copper", vmin=gt.pack[2], vmax=gt.pack[1])
    fig.colorbar(im, ax=axes[1], label="volume fraction")
    axes[1].set_title("packing: sheared grains at the critical state (0.60) in the closely packed bed (0.62)")
    torso = u.data.xpos[u.model.body("torso").id]
    for ax in axes:
        ax.plot([torso[0]], [torso[1]], "k+", ms=10)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
    fig.savefig(out, dpi=DPI)
    plt.close(fig)
    solid, bulk = mjrft.ground.ground_volumes(gt, st)
    _record("ground", [f"hexapod, poppy_cp, tripod:f=2, {seconds:g} s with ground_memory=True ({gt.frame[2] * 1e3:g} mm "
                       f"cells): torso x {torso[0]:.3f} m; surface {h.min() * 1e3:.2f} to {h.max() * 1e3:.2f} mm; "
                       f"packing {phi.min():.4f} to {phi.max():.4f}; {int(changed.sum())} cells changed; bulk volume "
                       f"above the undisturbed surface {bulk * 1e6:.3f} cm^3"])
    env.close()
    return out


FIGURES = {"hero": hero, "element_model": element_model, "laws": laws, "media": media, "rest": rest, "tradeoff": tradeoff,
           "ground": ground}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("names", nargs="*", help=f"figures to make (default all): {', '.join(FIGURES)}")
    args = parser.parse_args(argv)
    names = args.names or list(FIGURES)
    bad = [n for n in names if n not in FIGURES]
    if bad:
        parser.error(f"unknown figure {bad[0]!r}; valid choices: {', '.join(FIGURES)}")
    IMG.mkdir(parents=True, exist_ok=True)
    for name in names:
        print(f"{name}: wrote {FIGURES[name]().relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

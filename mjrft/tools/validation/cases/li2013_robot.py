"""Li, Zhang & Goldman 2013 (suppl. sec. 5, figs. S13-S14): the RHex-class robot, speed vs stride frequency and curvature.

One case, ``li2013_robot``, rerunning the paper's robot simulation (published numbers and stated
outcomes: ``mjrft/tools/validation/data/li2013_robot.json``). The measured curves of fig. S13 (and the main
paper's fig. 4, which S13 A-B reproduce) are not in the source texts, so no measured speed is
compared: the checks are the outcomes the text states.

Setup (the paper's): ``mjrft/HexapodSand-v0`` (13 cm, 150 g, pitch inertia 2.08e3 g cm^2, legs 4.1 x
1.0 x 0.3 cm of curvature 1/r in 1/R' (+1 = Li's C-leg, convex side leading; -1 the reversed C-leg),
alternating tripod of constant-speed leg rotation (gait ``tripod``, duty 0.5, sweep pi) on loosely
packed poppy seeds, the torso held in the sagittal plane (``planar=True``: fore-aft, vertical and
pitch, as Li's MBDyn simulation held it; the body's box takes resistive forces on its front, rear and
belly like Li's three body plates), under (a) the medium's Fourier fit (law ``rft``, medium
``poppy_lp``: Li's "measured stresses"), (b) the generic profile scaled by poppy LP's zeta (eq. S16)
and (c) the depth-only law (eqs. S3-S7). Each trial starts with the legs on the gait's pose at its
initial phase (tripod A at ``phase``, tripod B half a cycle later, the body lowered until its lowest
point is 0.5 mm above the surface), as Li started each trial at a phase; the paper ran three phases
2 pi/3 apart and found their speeds within << 1 cm/s, so one phase is run everywhere and the three
only where that statement is checked. Average forward speed = torso x travel over whole strides
after the first second (the start from rest).

Checks and tolerances:

* C-legs faster than reversed C-legs at every tested frequency, under the fit and under the scaled
  generic profile (sec. 5, text on figs. S13-S14: the depth-only models are "erroneous" in giving
  the two legs similar speeds). An ordering: no tolerance.
* depth-only: "similar speeds" for the two legs. The paper gives no number; "similar" is mjrft's
  documented reading (:data:`mjrft.tools.validation.case.SIMILAR`: a ratio within 20 %, Li's own
  "less than 20 %" for a negligible force change): v_C / v_rev within [1/1.2, 1.2] at every tested
  frequency where the depth-only robot stayed upright (the fit's 1.4-1.7 fails it).
* no flip under the fit: the robot stays upright, read as a torso tilt below 60 deg
  (:data:`~mjrft.tools.validation.case.UPRIGHT_TILT`, the same reading in every case) over every
  whole run; "upside down" (the depth-only flip below) is a tilt past pi/2.
* the scaled generic profile close to the fit ("only a small loss in accuracy"): the largest
  relative speed difference over every tested (f, 1/r) <= 2 s.d. of chi over its mean (2 x 0.14 /
  1.26 = 22 %), the accuracy the paper states for inferring the stresses from one plate test (eq.
  S13; the same tolerance as ``li2013_scaling``); and its RMS difference from the fit below the
  depth-only law's ("a larger loss in accuracy").
* fig. S14's mechanism, under the fit at every tested frequency: more vertical force on the C-legs
  than on the reversed C-legs, and less drag on the belly (forces averaged over every physics step
  of the measured strides).
* three initial phases 2 pi/3 apart change the speed by << 1 cm/s (the paper's words), read as at
  least 10x below: < 0.1 cm/s (:data:`~mjrft.tools.validation.case.MUCH_LESS`).
* the free robot (``mjrft/HexapodSand-v0`` as a user makes it: free joint, the env's start, 10 s episodes,
  seeds 0-2): C-legs faster than reversed C-legs at every tested f and seed on poppy LP (fig. S13's medium,
  asserted) and on poppy CP (the env's default; the texts give no robot speeds there); upright (tilt < 60 deg,
  asserted); on Li's 200 x 50 cm track: the path's heading within atan(25/200) = 7.1 deg in every trial; under the
  depth-only law on poppy LP, C and reversed C speeds similar (the same reading as the planar check). When a
  free robot leaves the straight path the case measures why: the two half-cycles' torso height and legs' load,
  the heading rate, the same trial with the tripods swapped, and (full run) at half the timestep and with 4x the
  elements.
* not asserted by the fast test: depth-only's largest speed difference from the fit against the
  published 150 % (which is against the measured speeds: tolerance 50 %, only the size can be
  compared, as in ``li2013_leg_rig``), and the depth-only robot turning upside down with C-legs at
  high f (fig. S13 caption), with its measured cause when it does not.
"""

from __future__ import annotations

import math

import gymnasium
import mujoco
import numpy as np

from ...gaits import make_gait, tripod_angles
from mjrft.envs.hexapod import SAND_FRAME_SKIP, SAND_TIMESTEP
from mjrft.media import MEDIA, generic
from ..case import (MUCH_LESS, SIMILAR, UPRIGHT_TILT, Check, CaseResult, Line, Panel, case, check_band, check_close,
                    check_outcome, published, similar)

PAPER = "li2013_robot"
CITE = "Li, Zhang & Goldman, Science 2013 (suppl.)"
LAWS = ("fit", "generic", "depth_only")
LAW_LABEL = {"fit": "medium's fit (rft)", "generic": "generic x zeta (rft)", "depth_only": "depth-only"}
#: hip speed bound of the env (rad/s): 6 rev/s, above the 5 rev/s the 5 Hz tripod needs (the env's default is 3)
MAX_HIP_SPEED = 12 * math.pi
SETTLE = 1.0  # s discarded at the start of each trial (the start from rest)
EPISODE = 10.0  # s: a free-body trial, the length of one episode of the env at its 10 ms control step
UPSIDE_DOWN = math.pi / 2  # torso tilt (rad) at which its up axis passes the horizontal
FREE_MEDIA = ("poppy_lp", "poppy_cp")  # fig. S13's medium and the env's default
MEDIUM_LABEL = {"poppy_lp": "poppy LP", "poppy_cp": "poppy CP"}
TURNING = math.radians(1.0)  # rad/s: a free robot whose heading changes faster over an episode's second half turns
BOUNCE = 0.1  # a torso whose mean heights on alternate half-cycles differ by more than this fraction bounces (period 2)


def _settings(quick: bool) -> dict:
    """Stride frequencies (Hz) of the speed-vs-f curves, their curvatures (1/R'), the frequencies of the
    speed-vs-curvature sweep, the strides averaged per trial, where the three initial phases are run, and the
    free-body trials' frequencies and seeds."""
    if quick:
        return {"freqs": [1.0, 3.0, 5.0], "curves": [1.0, -1.0], "sweep_freqs": [3.0], "sweep": [1.0, 0.0, -1.0],
                "strides": 2, "phase_freqs": [3.0], "abrupt_freqs": [4.0],
                "free_freqs": [1.0, 3.0, 5.0], "free_seeds": [0], "numerics": False}
    return {"freqs": [1.0, 2.0, 3.0, 4.0, 5.0], "curves": [1.0, 0.0, -1.0], "sweep_freqs": [2.0, 4.0],
            "sweep": list(published(PAPER, "leg_curvatures").value), "strides": 4,
            "phase_freqs": [1.0, 2.0, 3.0, 4.0, 5.0], "abrupt_freqs": [3.0, 4.0, 5.0],
            "free_freqs": [1.0, 2.0, 3.0, 4.0, 5.0], "free_seeds": [0, 1, 2], "numerics": True}


def _law_kwargs(law: str) -> dict:
    name = published(PAPER, "medium").value
    if law == "fit":
        return {"medium": name, "law": "rft"}
    if law == "generic":
        return {"medium": generic.scaled(MEDIA[name].zeta), "law": "rft"}
    if law == "depth_only":
        return {"medium": name, "law": "depth_only"}
    raise ValueError(f"unknown law {law!r}; valid: {', '.join(LAWS)}")


def _lowest_point(model: mujoco.MjModel, data: mujoco.MjData) -> float:
    """Lowest corner (m) of the robot's box geoms."""
    z = math.inf
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], float)
    for g in range(model.ngeom):
        if model.geom_bodyid[g] == 0:
            continue
        if model.geom_type[g] != mujoco.mjtGeom.mjGEOM_BOX:
            raise ValueError(f"geom {g} of the robot is not a box; the start pose handles box geoms only")
        pts = data.geom_xpos[g] + (corners * model.geom_size[g]) @ data.geom_xmat[g].reshape(3, 3).T
        z = min(z, float(pts[:, 2].min()))
    return z


def start_on_gait(env, f: float, phase: float) -> None:
    """Put the reset planar hexapod's legs on the tripod's pose at t = 0 (tripod A at ``phase`` cycles) and
    lower or raise the body so its lowest point keeps the model's start clearance above the surface."""
    u = env.unwrapped
    m, d = u.model, u.data
    mujoco.mj_forward(m, d)
    z_low = _lowest_point(m, d)
    q = tripod_angles(u, 0.0, f, phase=phase)
    d.qpos[u.task.hip_qadr] = q
    d.qvel[:] = 0.0
    u.target[:] = q
    d.ctrl[:] = q
    mujoco.mj_forward(m, d)
    d.qpos[1] += z_low - _lowest_point(m, d)  # rootz
    mujoco.mj_forward(m, d)


def trial(curvature: float, f: float, law: str, strides: int, phase: float = 0.0, start: str = "gait") -> dict:
    """One simulated trial of Li's robot: curvature in 1/R', stride frequency f (Hz), law ``fit``, ``generic`` or
    ``depth_only``; ``start="gait"`` (legs on the gait's pose) or ``"env"`` (the env's start: legs down, tripod B
    catching up half a cycle at the full hip speed). Returns the average forward speed (m/s) over ``strides`` whole
    strides after the first second, the realised stride frequency (Hz) there, the largest torso tilt (rad) over the
    whole run and over the measured strides, the mean torso height (m) and the mean vertical force on the legs,
    vertical force on the torso and horizontal force on the torso (N; every physics step of the measured strides)."""
    from mjrft.models.hexapod import LEG_NAMES, R_PRIME

    env = gymnasium.make("mjrft/HexapodSand-v0", planar=True, curvature=curvature / R_PRIME["rhex"],
                         max_hip_speed=MAX_HIP_SPEED, terminate_when_unhealthy=False, reset_noise_scale=0.0,
                         **_law_kwargs(law))
    u = env.unwrapped
    m, d = u.model, u.data
    obs, _ = env.reset(seed=0)
    if start == "gait":
        start_on_gait(env, f, phase)
    elif start != "env":
        raise ValueError(f"unknown start {start!r}; valid: gait, env")
    gait = make_gait(f"tripod:f={f:.10g},phase={phase:.10g}", env)
    legs = [m.body(f"leg_{n}").id for n in LEG_NAMES]
    torso = u.task.torso
    forces = []
    measuring = [False]

    def measure(data):  # after every physics step, so the forces are averaged over every step
        if measuring[0]:
            w = u.terrain.wrench
            forces.append((w[legs, 2].sum(), w[torso, 2], w[torso, 0]))

    u.each_physics_step(measure)
    n_settle = int(round(SETTLE / u.dt))
    n_total = n_settle + int(round(strides / f / u.dt))
    tilt_all = tilt_win = 0.0
    heights = []
    for i in range(n_total):
        if i == n_settle:
            x0, t0, hips0 = float(d.qpos[0]), float(d.time), d.qpos[u.task.hip_qadr].copy()
            measuring[0] = True
        action, _ = gait.predict(obs)
        obs, _, _, _, info = env.step(action)
        if "diverged" in info:
            raise RuntimeError(f"li2013_robot trial (1/r = {curvature:g}/R', f = {f:g} Hz, {law}) diverged: "
                               f"{info['diverged']}")
        tilt = u.torso_tilt()
        tilt_all = max(tilt_all, tilt)
        if measuring[0]:
            tilt_win = max(tilt_win, tilt)
            heights.append(u.torso_height())
    span = float(d.time) - t0
    out = {"speed": (float(d.qpos[0]) - x0) / span,
           "f_real": float(np.mean(d.qpos[u.task.hip_qadr] - hips0)) / (2 * math.pi * span),
           "tilt": tilt_all, "tilt_window": tilt_win, "height": float(np.mean(heights))}
    out.update(zip(("legs_fz", "belly_fz", "belly_fx"), np.mean(forces, axis=0).tolist()))
    env.close()
    return out


def _yaw(q) -> float:
    """Heading (rad) of a free body's quaternion (w, x, y, z): the yaw of its x axis about the world z."""
    w, x, y, z = q
    return math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))


def free_trial(curvature: float, f: float, medium: str, law: str = "rft", seed: int = 0, seconds: float = EPISODE,
               phase: float = 0.0, measure_ground: bool = False, **env_kw) -> dict:
    """One free-body trial: ``mjrft/HexapodSand-v0`` as a user makes it (free joint, the env's start and reset
    noise of ``seed``; ``env_kw`` passed on, e.g. ``timestep``), curvature in 1/R', the tripod at f (Hz) with tripod
    A at ``phase`` cycles, ``seconds`` long (held planar with ``planar=True``: heading and path heading 0).

    Returns the average speed along x after the first second (m/s), the largest torso tilt (rad), the path's
    largest heading (rad: the direction of the torso's displacement from its start, after the first second),
    the body's heading at the end (rad, unwrapped) and its mean rate over the second half (rad/s), and over the
    second half the two half-cycles' mean torso height (m) and mean vertical force on the six legs (N; the
    half-cycles of the gait's phase, ``floor(2 (phase + f t))`` even, then odd: one tripod's stance each), each
    tripod's mean hip lag behind its command (rad) and the largest fraction of steps a hip servo spent at its
    torque limit. With ``measure_ground``, also ``leg_sinkage``: the legs' deepest element depth below the surface
    they meet (m; with the ground memory, its local surface), averaged over every physics step of the second half;
    ``leg_packing``: the grains' volume fraction (:meth:`~mjrft.GranularTerrain.ground_packing`) under the legs'
    buried elements and ``leg_surface``: the grains' surface there above the undisturbed one (m,
    :meth:`~mjrft.GranularTerrain.ground_height`), both averaged over the second half's physics steps;
    ``track_relief``: the lowest and highest surface (m, above the undisturbed one) over the robot's track (10 cm
    around it) at the end."""
    from mjrft.models.hexapod import LEG_NAMES, R_PRIME

    env = gymnasium.make("mjrft/HexapodSand-v0", medium=medium, law=law, curvature=curvature / R_PRIME["rhex"],
                         max_hip_speed=MAX_HIP_SPEED, terminate_when_unhealthy=False, **env_kw)
    u = env.unwrapped
    m, d = u.model, u.data
    obs, _ = env.reset(seed=seed)
    gait = make_gait(f"tripod:f={f:.10g},phase={phase:.10g}", env)
    legs = [m.body(f"leg_{n}").id for n in LEG_NAMES]
    n_settle, n_total = int(round(SETTLE / u.dt)), int(round(seconds / u.dt))
    leg_elems = np.isin(u.terrain.elem_body, legs)
    ground_rows = ([], [], [])  # the legs' deepest depth; under their buried elements: packing, surface height
    half_rows = []  # (half-cycle parity, torso z, legs' Fz) at every physics step of the second half

    def measure(data):
        if data.time >= seconds / 2:
            w = u.terrain.wrench
            half = int(math.floor(2 * (phase + f * data.time))) % 2
            half_rows.append((half, data.xpos[u.task.torso, 2], w[legs, 2].sum()))
            if measure_ground:
                t = u.terrain
                buried = leg_elems & (t.depth > 0)
                ground_rows[0].append(float(t.depth[buried].max()) if buried.any() else 0.0)
                if buried.any():
                    bx, by = t.pos[buried, 0], t.pos[buried, 1]
                    ground_rows[1].append(float(t.ground_packing(bx, by).mean()))
                    ground_rows[2].append(float((t.ground_height(bx, by) - t.surface_height(bx, by)).mean()))

    u.each_physics_step(measure)
    planar = u.planar  # held in the x-z plane (qpos: x, z, pitch): no heading, no sideways path
    x0, y0 = float(d.qpos[0]), float(d.qpos[1])
    tilt, path, yaws, lags, saturated = 0.0, 0.0, [], [], []
    limit = m.actuator_forcerange[:, 1]
    for i in range(n_total):
        if i == n_settle:
            xs, ts = float(d.qpos[0]), float(d.time)
        action, _ = gait.predict(obs)
        obs, _, _, _, info = env.step(action)
        if "diverged" in info:
            raise RuntimeError(f"li2013_robot free trial (1/r = {curvature:g}/R', f = {f:g} Hz, {medium}, {law}) "
                               f"diverged: {info['diverged']}")
        tilt = max(tilt, u.torso_tilt())
        yaws.append(0.0 if planar else _yaw(d.qpos[3:7]))
        if i >= n_settle and not planar:
            path = max(path, abs(math.atan2(float(d.qpos[1]) - y0, float(d.qpos[0]) - x0)))
        if d.time >= seconds / 2:
            lag = u.target - d.qpos[u.task.hip_qadr]
            lags.append((lag[list(u.TRIPOD_A_IDX)].mean(), lag[list(u.TRIPOD_B_IDX)].mean()))
            saturated.append(np.abs(d.actuator_force) >= limit)
    yaws = np.unwrap(yaws)
    h = np.array(half_rows)
    halves = [h[h[:, 0] == k] for k in (0, 1)]
    out = {"speed": (float(d.qpos[0]) - xs) / (float(d.time) - ts), "tilt": tilt, "path_heading": path,
           "heading": float(yaws[-1]), "yaw_rate": float(yaws[-1] - yaws[len(yaws) // 2]) / (seconds / 2),
           "height_halves": tuple(float(x[:, 1].mean()) for x in halves),
           "legs_fz_halves": tuple(float(x[:, 2].mean()) for x in halves),
           "tripod_lag": tuple(float(x) for x in np.mean(lags, axis=0)),
           "saturated": float(np.mean(saturated, axis=0).max())}
    if measure_ground:
        out["leg_sinkage"], out["leg_packing"], out["leg_surface"] = (float(np.mean(x)) if x else math.nan
                                                                      for x in ground_rows)
        x1 = float(d.qpos[0])
        ys = (float(d.xpos[u.task.torso, 1]),) if planar else (y0, float(d.qpos[1]))  # planar qpos: x, z, pitch
        gx, gy = np.meshgrid(np.linspace(min(x0, x1) - 0.1, max(x0, x1) + 0.1, 200),
                             np.linspace(min(ys) - 0.1, max(ys) + 0.1, 41))
        relief = u.terrain.ground_height(gx, gy) - u.terrain.surface_height(gx, gy)
        out["track_relief"] = (float(relief.min()), float(relief.max()))
    env.close()
    return out


def upright_check(label: str, tilt: float, qualitative: bool = True) -> Check:
    """The robot stays upright (the paper: only the depth-only simulation turned it upside down): the largest
    torso tilt below :data:`~mjrft.tools.validation.case.UPRIGHT_TILT` (60 deg, mjrft's documented reading of
    "upright", the same in every case)."""
    return check_band(f"{label}: largest torso tilt over every trial (rad)", tilt, 0.0, UPRIGHT_TILT,
                      published="the robot stays upright (only the depth-only simulation turned it upside down)",
                      source=published(PAPER, "depth_only_flip").source, unit="rad", qualitative=qualitative,
                      reference=UPRIGHT_TILT,
                      basis=f"upright: tilt < {math.degrees(UPRIGHT_TILT):g} deg, mjrft's reading, every case")


def similar_speeds_check(label: str, freqs, v_c: dict, v_rev: dict, tilt: dict, fit: dict | None = None,
                         qualitative: bool = True) -> Check:
    """Sec. 5: the depth-only models "erroneously predicted that the robot moved at similar speeds using both
    c-legs and reversed c-legs". "Similar" is mjrft's documented reading (:data:`SIMILAR`: v_C / v_rev within
    [1/1.2, 1.2]), required at every tested f where the robot stayed upright (``tilt`` < 60 deg), and at least
    one such f."""
    upright = [f for f in freqs if tilt[f] < UPRIGHT_TILT]
    ratio = {f: v_c[f] / v_rev[f] if v_rev[f] > 0 else math.inf for f in freqs}
    ok = bool(upright) and all(similar(ratio[f]) for f in upright)
    return Check(
        name=f"{label}: C and reversed C speeds similar at every f where upright", passed=ok,
        published=published(PAPER, "depth_only_similar_speeds").value,
        source=published(PAPER, "depth_only_similar_speeds").source,
        simulated=(f"v_C / v_rev: {label} " + ", ".join(f"{ratio[f]:.2f}" for f in freqs)
                   + ("; fit " + ", ".join(f"{fit[f]:.2f}" for f in freqs) if fit else "")
                   + " (f = " + ", ".join(f"{f:g}" for f in freqs) + " Hz)"
                   + ("" if len(upright) == len(freqs) else "; not upright at "
                      + ", ".join(f"{f:g}" for f in freqs if f not in upright) + " Hz, not compared")),
        metric="ratio at every upright f", qualitative=qualitative,
        tolerance=(f"[{1 / (1 + SIMILAR):.3g}, {1 + SIMILAR:g}]: 'similar' read as within {100 * SIMILAR:g} % (Li's "
                   "own 'less than 20 %' for a negligible force change, suppl. Materials and Methods)"))


def phase_spread_check(label: str, spread: dict) -> Check:
    """Materials and Methods: three initial phases 2 pi/3 apart changed the average speed by "<< 1 cm/s". "<<" is
    mjrft's documented reading (:data:`MUCH_LESS`: at least 10x below), so the largest spread must be < 0.1 cm/s.
    ``spread``: {(curvature, f): max - min speed (m/s)}."""
    worst = max(spread, key=spread.get)
    bound = published(PAPER, "trial_variation").value / MUCH_LESS
    return check_band(
        f"{label}: speed spread over the three initial phases, largest ({worst[0]:+g}/R', {worst[1]:g} Hz)",
        100 * spread[worst], 0.0, bound, published="<< 1 cm/s", source=published(PAPER, "trial_variation").source,
        unit="cm/s", reference=bound, basis=f"'<<' read as at least {MUCH_LESS:g}x below, mjrft's reading")


def track_heading_bound() -> float:
    """The largest path heading (rad) that keeps a robot started on the centreline of Li's 200 x 50 cm track on it
    over the track's length: atan(25 / 200) = 7.1 deg."""
    length, width = published(PAPER, "robot_track").value
    return math.atan((width / 2) / length)


def track_check(label: str, headings: dict, qualitative: bool = False) -> Check:
    """The robot runs straight enough to stay on Li's track (the experiments measured v_x along a 200 x 50 cm
    track): the path's heading (direction of the displacement from the start) within
    :func:`track_heading_bound` in every trial. ``headings``: {(curvature, f, seed): path heading (rad)}."""
    bound = track_heading_bound()
    worst = max(headings, key=headings.get)
    off = sorted({(k, f) for (k, f, _), h in headings.items() if h > bound})
    return check_band(
        f"{label}: largest path heading over every trial ({worst[0]:+g}/R', {worst[1]:g} Hz, seed {worst[2]})",
        math.degrees(headings[worst]), 0.0, math.degrees(bound),
        published="the robot runs along the 200 x 50 cm track (v_x measured from the top view)",
        source=published(PAPER, "robot_track").source, unit="deg", qualitative=qualitative,
        reference=math.degrees(bound),
        basis="atan(25 cm / 200 cm): a straight path from the track's centreline stays on it over its length"
              + ("; off the track: " + ", ".join(f"{k:+g}/R' at {f:g} Hz" for k, f in off) if off else ""))


def free_order_check(medium: str, freqs, seeds, v: dict, qualitative: bool) -> Check:
    """C-legs faster than reversed C-legs at every tested f and seed on the free robot. ``v``:
    {(curvature, f, seed): speed along x (m/s)}."""
    ratios = {f: [v[1.0, f, sd] / v[-1.0, f, sd] for sd in seeds] for f in freqs}
    src = published(PAPER, "c_faster_than_reversed").source + "; " + published(PAPER, "robot_track").source
    if medium != published(PAPER, "medium").value:
        src += f" (fig. S13 is on poppy LP; on {MEDIUM_LABEL[medium]} the texts state no robot speeds)"
    return check_outcome(
        f"free body, {MEDIUM_LABEL[medium]}: C-legs faster than reversed C-legs at every tested f and seed",
        min(min(r) for r in ratios.values()) > 1.0, published=published(PAPER, "c_faster_than_reversed").value,
        source=src, qualitative=qualitative,
        simulated="v_C / v_reversed C = " + ", ".join(
            f"{'/'.join(f'{x:.2f}' for x in r)} ({f:g} Hz)" for f, r in ratios.items()) + f" (seeds {', '.join(map(str, seeds))})")


def _free_label(law: str) -> str:
    """The report's name of a free trial's law (``rft`` under the medium's fit, or ``depth_only``)."""
    return LAW_LABEL["fit" if law == "rft" else law]


def _halves(r: dict) -> str:
    """A free trial's second half: the two half-cycles' torso heights and legs' loads."""
    z, fz = r["height_halves"], r["legs_fz_halves"]
    return f"torso {1e3 * z[0]:.1f} / {1e3 * z[1]:.1f} mm and legs {fz[0]:.2f} / {fz[1]:.2f} N on alternate half-cycles"


def _bounce(r: dict) -> str:
    """:func:`_halves` and the heading rate."""
    return f"{_halves(r)}, heading {math.degrees(r['yaw_rate']):+.1f} deg/s"


def bounces(r: dict) -> bool:
    """Whether a trial's torso rides at two heights on alternate half-cycles: they differ by more than
    :data:`BOUNCE` of their mean."""
    z = r["height_halves"]
    return abs(z[0] - z[1]) > BOUNCE * 0.5 * abs(z[0] + z[1])


def free_body_cause(F: dict, seeds, numerics: bool) -> str:
    """The measured cause of free trials ``F`` ({(law, medium, curvature, f, seed): :func:`free_trial`}) that left
    the straight path ("" when none did): those that run straight at the angle their start gave them, and those
    that turn, with the worst one's bounce, drive, the same trial with the tripods swapped and (``numerics``) at
    half the timestep and with 4x the elements."""
    bound = track_heading_bound()
    turned = sorted({key[:4] for key, r in F.items() if r["path_heading"] > bound})
    rate = {key: max(abs(F[key + (sd,)]["yaw_rate"]) for sd in seeds) for key in turned}
    turning = [key for key in turned if rate[key] > TURNING]
    angled = [key for key in turned if rate[key] <= TURNING]

    def names(keys):
        return "; ".join(f"{_free_label(lw)} on {MEDIUM_LABEL[md]}, {kk:+g}/R' at {ff:g} Hz"
                         for lw, md, kk, ff in keys)

    cause = ""
    parts = []
    if angled:
        parts.append(
            f"Free body, straight but at an angle ({names(angled)}): heading rate below {math.degrees(TURNING):g} deg/s "
            "over the second half, end headings "
            + ", ".join(f"{math.degrees(F[key + (seeds[0],)]['heading']):+.0f} deg" for key in angled)
            + ": the env's start (every leg down, tripod B catching up half a turn at full speed) yaws the body in "
            "the first second and the gait keeps that heading. ")
    if turning:
        law, medium, k, f = max(turning, key=lambda key: rate[key])
        worst = F[law, medium, k, f, seeds[0]]
        mirror = free_trial(k, f, medium, law, seeds[0], phase=0.5)
        held = {kk: free_trial(kk, f, medium, law, seeds[0], planar=True) for kk in (k, -k)}
        bouncing = [key for key in turning if bounces(F[key + (seeds[0],)])]
        parts.append(
            f"Free body, turning ({names(turning)}): "
            + ("each of these trials" if len(bouncing) == len(turning)
               else f"{len(bouncing)} of these {len(turning)} trials")
            + f" (seed {seeds[0]}) settles into a period-2 bounce (torso heights on alternate half-cycles "
            f"more than {100 * BOUNCE:.0f} % of their mean apart): in the second half "
            "of the episode the torso rides higher after one tripod's stance than after the other's and the legs' "
            "load alternates between the two tripods, each of which has two legs on one side of the body; the "
            "unequal tripods turn the robot steadily. The worst, "
            f"{_free_label(law)} on {MEDIUM_LABEL[medium]} with {k:+g}/R' legs at {f:g} Hz: "
            f"{_bounce(worst)}; the reversed C-legs at the same f: {_bounce(F[law, medium, -k, f, seeds[0]])}. "
            f"Not the drive: the two tripods lag their commanded rotation by "
            f"{math.degrees(worst['tripod_lag'][0]):.1f} and {math.degrees(worst['tripod_lag'][1]):.1f} deg, and "
            f"the hip servos spend {100 * worst['saturated']:.0f} % of the steps at their torque limit. "
            f"Started with the tripods swapped (phase 0.5) the same robot turns at "
            f"{math.degrees(mirror['yaw_rate']):+.1f} deg/s: the side it turns to is set by the start, not by a bias "
            f"of the model. Held in the sagittal plane (the same env, start and gait with `planar=True`) it "
            f"{'bounces too' if bounces(held[k]) else 'does not bounce'} ({_halves(held[k])}) and runs straight, "
            f"{held[k]['speed']:.3f} m/s against the reversed C-legs' {held[-k]['speed']:.3f} m/s "
            f"({_halves(held[-k])})"
            + (": the bounce is in the sagittal motion, and the free body's roll and yaw turn its unequal tripods "
               "into a turn" if bounces(held[k]) else ""))
        split = [key for key in turning if len({np.sign(F[key + (sd,)]["heading"]) for sd in seeds}) > 1]
        if split:
            lw, md, kk, ff = split[0]
            parts.append(f"; the reset noise alone picks either side (headings at the end "
                         + ", ".join(f"{math.degrees(F[split[0] + (sd,)]['heading']):+.0f} deg (seed {sd})" for sd in seeds)
                         + f" for {kk:+g}/R' at {ff:g} Hz on {MEDIUM_LABEL[md]})")
        if numerics:
            half = free_trial(k, f, medium, law, seeds[0], timestep=SAND_TIMESTEP / 2, frame_skip=40)
            fine = free_trial(k, f, medium, law, seeds[0], preset="accurate", timestep=SAND_TIMESTEP,
                              frame_skip=SAND_FRAME_SKIP)  # the elements alone: the own step
            parts.append(f". Not numerical: at half the timestep it turns at {math.degrees(half['yaw_rate']):+.1f} "
                         f"deg/s and with the accurate preset's 4x elements at {math.degrees(fine['yaw_rate']):+.1f} "
                         f"deg/s (against {math.degrees(worst['yaw_rate']):+.1f})")
        parts.append(". ")
    if turned:
        parts.append("Li's simulation held the body planar (no roll or yaw; the planar trials above do not turn); "
                     "the real robot's heading on the track is not reported. Speed along x counts a turning robot's "
                     "path only in part.")
        cause = "".join(parts)
    return cause


def free_body(s: dict) -> tuple[list, str, list, dict]:
    """The free-body trials: ``mjrft/HexapodSand-v0`` as a user makes it, C and reversed C-legs, on poppy LP and CP
    under the medium's fit and on poppy LP under the depth-only law. Returns the checks, the measured cause of
    their failures, the figure's panels and the trials."""
    freqs, seeds = s["free_freqs"], s["free_seeds"]
    runs = [("rft", medium) for medium in FREE_MEDIA] + [("depth_only", published(PAPER, "medium").value)]
    F = {(law, medium, k, f, sd): free_trial(k, f, medium, law, sd)
         for law, medium in runs for k in (1.0, -1.0) for f in freqs for sd in seeds}
    checks = []
    for medium in FREE_MEDIA:
        v = {key[2:]: r["speed"] for key, r in F.items() if key[:2] == ("rft", medium)}
        checks.append(free_order_check(medium, freqs, seeds, v, qualitative=medium == published(PAPER, "medium").value))
    checks.append(upright_check("free body, medium's fit (rft), poppy LP and CP",
                                max(r["tilt"] for key, r in F.items() if key[0] == "rft")))
    for law, medium in runs:
        label = f"free body, {_free_label(law)}, {MEDIUM_LABEL[medium]}"
        checks.append(track_check(label, {key[2:]: r["path_heading"] for key, r in F.items() if key[:2] == (law, medium)}))
    lp = published(PAPER, "medium").value
    mean = {key: float(np.mean([F[key + (sd,)]["speed"] for sd in seeds])) for key in {k[:4] for k in F}}
    checks.append(similar_speeds_check(
        "free body, depth-only, poppy LP", freqs, {f: mean["depth_only", lp, 1.0, f] for f in freqs},
        {f: mean["depth_only", lp, -1.0, f] for f in freqs},
        {f: max(F["depth_only", lp, k, f, sd]["tilt"] for k in (1.0, -1.0) for sd in seeds) for f in freqs},
        fit={f: mean["rft", lp, 1.0, f] / mean["rft", lp, -1.0, f] for f in freqs}, qualitative=False))

    cause = free_body_cause(F, seeds, s["numerics"])

    style = {1.0: "C-leg (+1/R')", -1.0: "reversed C-leg (-1/R')"}
    panels = [Panel(f"free body, {_free_label(law)}, {MEDIUM_LABEL[medium]}: speed vs f "
                    f"(mean of {len(seeds)} seed{'s' if len(seeds) > 1 else ''})",
                    "stride frequency f (Hz)", "average forward speed v_x (cm/s)",
                    [Line(freqs, [100 * mean[law, medium, k, f] for f in freqs], style[k]) for k in (1.0, -1.0)])
              for law, medium in runs]
    return checks, cause, panels, F


@case("li2013_robot", "RHex-class robot on poppy seeds: speed vs stride frequency and leg curvature (fig. S13)", CITE)
def run_robot(quick: bool) -> CaseResult:
    s = _settings(quick)
    freqs, strides = s["freqs"], s["strides"]
    R: dict = {}
    for law in LAWS:
        for k in s["curves"]:
            for f in freqs:
                R[law, k, f] = trial(k, f, law, strides)
        for f in s["sweep_freqs"]:
            for k in s["sweep"]:
                if (law, k, f) not in R:
                    R[law, k, f] = trial(k, f, law, strides)
    v = {key: r["speed"] for key, r in R.items()}
    checks = []

    # C faster than reversed C at every frequency (fit, generic)
    src_order = published(PAPER, "c_faster_than_reversed").source
    for law in ("fit", "generic"):
        ratios = [v[law, 1.0, f] / v[law, -1.0, f] for f in freqs]
        checks.append(check_outcome(
            f"{LAW_LABEL[law]}: C-legs faster than reversed C-legs at every tested f", min(ratios) > 1.0,
            published=published(PAPER, "c_faster_than_reversed").value, source=src_order,
            simulated="v_C / v_reversed C = " + ", ".join(f"{r:.2f} ({f:g} Hz)" for r, f in zip(ratios, freqs))))

    # depth-only: similar speeds at every f where the robot stayed upright
    checks.append(similar_speeds_check("depth-only", freqs, {f: v["depth_only", 1.0, f] for f in freqs},
                                       {f: v["depth_only", -1.0, f] for f in freqs},
                                       {f: max(R["depth_only", k, f]["tilt"] for k in (1.0, -1.0)) for f in freqs},
                                       fit={f: v["fit", 1.0, f] / v["fit", -1.0, f] for f in freqs}))

    # no flip under the fit (and generic)
    for law, qual in (("fit", True), ("generic", False)):
        worst = max((key for key in R if key[0] == law), key=lambda key: R[key]["tilt"])
        checks.append(upright_check(LAW_LABEL[law], R[worst]["tilt"], qualitative=qual))

    # generic close to the fit; depth-only further
    chi, chi_sd = published("li2013", "chi").value, published("li2013", "chi_sd").value
    tol = 2 * chi_sd / chi
    rel = {law: {key[1:]: v[key] / v[("fit",) + key[1:]] - 1 for key in v if key[0] == law} for law in LAWS}
    worst_gen = max(rel["generic"], key=lambda key: abs(rel["generic"][key]))
    checks.append(check_band(
        f"generic x zeta vs fit: largest relative speed difference ({worst_gen[0]:+g}/R', {worst_gen[1]:g} Hz)",
        100 * abs(rel["generic"][worst_gen]), 0.0, 100 * tol, published=published(PAPER, "generic_small_loss").value,
        source=published(PAPER, "generic_small_loss").source + "; tolerance 2 s.d. of chi / chi (eq. S13)",
        unit="%", reference=100 * tol))
    rms = {law: float(np.sqrt(np.mean(np.square(list(rel[law].values()))))) for law in ("generic", "depth_only")}
    checks.append(check_outcome(
        "RMS relative speed difference from the fit: generic x zeta < depth-only", rms["generic"] < rms["depth_only"],
        published="generic x zeta: a small loss in accuracy; depth-only: a larger loss (up to 150 % error)",
        source=published(PAPER, "depth_only_error_max").source,
        simulated=f"generic {100 * rms['generic']:.1f} %, depth-only {100 * rms['depth_only']:.1f} % "
                  f"(over {len(rel['generic'])} trials)"))

    # fig. S14 mechanism under the fit
    src14 = published(PAPER, "c_more_lift_less_belly_drag").source
    lift = [(R["fit", 1.0, f]["legs_fz"], R["fit", -1.0, f]["legs_fz"]) for f in freqs]
    drag = [(-R["fit", 1.0, f]["belly_fx"], -R["fit", -1.0, f]["belly_fx"]) for f in freqs]
    checks.append(check_outcome(
        "fit: mean vertical force on the C-legs > on the reversed C-legs at every tested f",
        all(a > b for a, b in lift), published=published(PAPER, "c_more_lift_less_belly_drag").value, source=src14,
        simulated="C / reversed C (N): " + ", ".join(f"{a:.2f}/{b:.2f} ({f:g} Hz)" for (a, b), f in zip(lift, freqs))))
    checks.append(check_outcome(
        "fit: mean belly drag with C-legs < with reversed C-legs at every tested f",
        all(a < b for a, b in drag), published="higher lift above the medium reduces drag on the belly", source=src14,
        simulated="C / reversed C (N): " + ", ".join(f"{a:.3f}/{b:.3f} ({f:g} Hz)" for (a, b), f in zip(drag, freqs))))

    # three initial phases 2 pi/3 apart
    phases = published(PAPER, "initial_phases").value
    spread = {}
    for k in (1.0, -1.0):
        for f in s["phase_freqs"]:
            speeds = [v["fit", k, f]] + [trial(k, f, "fit", strides, phase=p)["speed"] for p in phases[1:]]
            spread[k, f] = max(speeds) - min(speeds)
    phase_check = phase_spread_check("fit", spread)
    checks.append(phase_check)

    # depth-only: the published error size and the flip
    worst_do = max(rel["depth_only"], key=lambda key: abs(rel["depth_only"][key]))
    checks.append(check_close(
        f"largest depth-only speed error, against the fit ({worst_do[0]:+g}/R', {worst_do[1]:g} Hz)",
        published(PAPER, "depth_only_error_max"), 100 * abs(rel["depth_only"][worst_do]), 0.5, unit="%"))
    near_c = [key for key in R if key[0] == "depth_only" and key[1] >= 0.92]
    flipped = sorted((key[2], key[1]) for key in near_c if R[key]["tilt"] >= UPSIDE_DOWN)
    worst_dt = max(near_c, key=lambda key: R[key]["tilt"])
    checks.append(check_outcome(
        "depth-only, R'/r >= 0.92: the robot turns upside down at some tested f", bool(flipped),
        published=published(PAPER, "depth_only_flip").value, source=published(PAPER, "depth_only_flip").source,
        simulated=(("upside down at " + ", ".join(f"{f:g} Hz ({k:+g}/R')" for f, k in flipped)) if flipped else
                   f"upright in every trial; largest tilt {R[worst_dt]['tilt']:.2f} rad ({worst_dt[1]:+g}/R', "
                   f"{worst_dt[2]:g} Hz)"), qualitative=False))

    # the cause, measured: the same C-leg trials started the env's way (tripod B catching up at full speed)
    abrupt = {(law, f): trial(1.0, f, law, strides, start="env") for law in ("fit", "depth_only")
              for f in s["abrupt_freqs"]}
    other_phases = {(f, p): trial(1.0, f, "depth_only", strides, phase=p)["tilt"]
                    for f in s["abrupt_freqs"] for p in published(PAPER, "initial_phases").value[1:]}
    causes = []
    if not phase_check.passed:
        causes.append(
            "Initial phases: the three phases 2 pi/3 apart change the fit's average speed by up to "
            + ", ".join(f"{100 * sp:.3f} cm/s ({k:+g}/R', {f:g} Hz)" for (k, f), sp in sorted(spread.items(), key=lambda x: -x[1])[:3])
            + f", below 1 cm/s but not the 10x below it that '<<' is read as; the speed is averaged over {strides} "
            f"strides after the first {SETTLE:g} s (Li's averaging window is not given).")
    if not checks[-1].passed:
        causes.append(
            "No depth-only flip: started on the gait's pose (Li's initial conditions), the depth-only C-leg robot "
            f"pitches at most {R[worst_dt]['tilt']:.2f} rad (fit: "
            f"{max(R[key]['tilt'] for key in R if key[0] == 'fit' and key[1] >= 0.92):.2f} rad), and at most "
            f"{max(other_phases.values()):.2f} rad from the other two initial phases (at "
            f"{', '.join(f'{f:g}' for f in s['abrupt_freqs'])} Hz). The pitch "
            "instability is in mjrft a start-up transient: started the env's way (every leg down, tripod B "
            "catching up half a turn at 6 rev/s), the C-leg robot's largest tilt is "
            + ", ".join(f"{abrupt['depth_only', f]['tilt']:.2f} rad depth-only vs {abrupt['fit', f]['tilt']:.2f} rad "
                        f"fit at {f:g} Hz" for f in s["abrupt_freqs"])
            + f" (upside down = {UPSIDE_DOWN:.2f} rad). Li's start of the MBDyn trials is not described.")
    if not checks[-2].passed:
        causes.append(
            f"Depth-only error {100 * abs(rel['depth_only'][worst_do]):.0f} % against 150 %: the published error is "
            "against the measured speeds of fig. S13 (not in the text); mjrft can compare only with the fit's speeds, "
            "which carry the fit's own error against the measurement.")

    # the free robot (the env as a user makes it)
    free_checks, free_cause, free_panels, free = free_body(s)
    checks += free_checks
    if free_cause:
        causes.append(free_cause)

    # figure
    style = {1.0: "C-leg (+1/R')", 0.0: "flat", -1.0: "reversed C-leg (-1/R')"}
    row = {"fit": "top", "generic": "middle", "depth_only": "bottom"}
    panels = [Panel(f"{LAW_LABEL[law]}: speed vs f (fig. S13 {row[law]})",
                    "stride frequency f (Hz)", "average forward speed (cm/s)",
                    [Line(freqs, [100 * v[law, k, f] for f in freqs], style.get(k, f"{k:+g}/R'")) for k in s["curves"]])
              for law in LAWS]
    for f in s["sweep_freqs"]:
        ks = sorted(k for (law, k, ff) in R if law == "fit" and ff == f)
        panels.append(Panel(f"speed vs curvature at {f:g} Hz (fig. S13 right)", "R'/r", "average forward speed (cm/s)",
                            [Line(ks, [100 * v[law, k, f] for k in ks], LAW_LABEL[law]) for law in LAWS]))
    panels.append(Panel("fit: fig. S14 mechanism", "stride frequency f (Hz)", "mean force (N)", [
        Line(freqs, [R["fit", k, f]["legs_fz"] for f in freqs], f"F_z legs, {style[k]}") for k in (1.0, -1.0)] + [
        Line(freqs, [-R["fit", k, f]["belly_fx"] for f in freqs], f"belly drag, {style[k]}") for k in (1.0, -1.0)]))
    panels += free_panels

    f_dev = max(abs(r["f_real"] / key[2] - 1) for key, r in R.items())
    return CaseResult(
        name="li2013_robot", title="RHex-class robot: speed vs stride frequency and leg curvature", paper=CITE,
        source="Materials and Methods (robot experiments, robot simulation); section 5, figs. S13-S14",
        setup=(f"mjrft/HexapodSand-v0 with planar=True (torso in the sagittal plane: x, z and pitch, as Li's MBDyn "
               f"simulation), 13 x 4.9 x 3.7 cm torso with the hips at its mid-height, 150 g, pitch inertia 2.08e3 g cm^2, "
               f"six legs 4.1 x 1.0 x 0.3 cm of "
               f"curvature 1/r in 1/R' (R' = 2.05 cm), alternating tripod of constant-speed leg rotation (gait "
               f"tripod: duty 0.5, sweep pi) at f = {', '.join(f'{f:g}' for f in freqs)} Hz; speed vs curvature at "
               f"{', '.join(f'{f:g}' for f in s['sweep_freqs'])} Hz over 1/r = "
               f"{', '.join(f'{k:g}' for k in s['sweep'])} /R'. Loosely packed poppy seeds: the medium's fit (rft), "
               f"the generic profile x zeta = 0.248 N/cm^3 (rft), the depth-only law. Each trial starts on the "
               f"gait's pose (tripod A mid-stance), discards the first {SETTLE:g} s and averages the torso's speed over "
               f"{strides} strides; physics step {SAND_TIMESTEP * 1e3:g} ms (the sand env's), elements 5 mm (the "
               f"model's). Free body: the same env as a user makes it (free joint, the env's start: every leg down, "
               f"tripod B catching up half a turn; reset noise of seeds {', '.join(map(str, s['free_seeds']))}), C and "
               f"reversed C-legs at f = {', '.join(f'{f:g}' for f in s['free_freqs'])} Hz for {EPISODE:g} s (one "
               f"episode), on poppy LP (fig. S13's medium) and poppy CP (the env's default) under the medium's fit "
               f"and on poppy LP under the depth-only law; speed along x after the first {SETTLE:g} s."),
        checks=checks, panels=panels, cause=" ".join(causes),
        notes=(f"Choices where the paper is silent: the servo-driven legs (kp 2 N m/rad, torque limit 0.3 N m, the "
               f"model's) follow the commanded rotation: realised stride frequency within {100 * f_dev:.1f} % of f in "
               f"every trial. Li's legs rotate at constant speed (one motor, a gear train), hence duty 0.5 and sweep "
               f"pi. The env's hip speed bound is {MAX_HIP_SPEED / (2 * math.pi):g} rev/s (the gait needs f). The "
               f"torso's width, height and hip height are RHex's scaled to the 13 cm body (mjrft.models.hexapod; Li "
               f"gives the 13 x 2 cm belly), the legs' 2 mm clearance from its sides is the model's choice. The measured speeds of fig. S13 / the main paper's fig. 4 are not in the "
               f"source texts: no simulated speed is compared with a measured one; the medium's fit stands in for "
               f"the measurement where the text compares with it. Li checked that the legs' speed averaged over a "
               f"stance stays below 1 m/s at 5 Hz; the leg tips pass it (2 pi f x 4.1 cm = 1.29 m/s at 5 Hz), hence "
               f"the validity warnings of the fit's calibrated speed range below. Between |R'/r| = 0.92 and 1 the "
               f"speed changes steeply because the legs' arc angle 2 asin(R'/r) does (134 deg at 0.92, 180 deg at "
               f"1: the tip turns 23 deg). Free body: Li's robot ran free on a 200 x 50 cm track; a trial stays on it "
               f"when its path heading (the direction of the torso's displacement from the start) is within "
               f"atan(25/200) = {math.degrees(track_heading_bound()):.1f} deg, mjrft's reading of a measurable run. "
               f"Largest torso tilt of the free robot {math.degrees(max(r['tilt'] for r in free.values())):.0f} deg."),
    )

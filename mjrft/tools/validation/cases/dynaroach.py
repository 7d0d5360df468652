"""Zhang et al., "Ground fluidization promotes rapid running of a lightweight robot" (DynaRoACH): the dry inertial regime.

Published numbers and outcomes: ``mjrft/tools/validation/data/dynaroach.json``. Three cases: the intrusion rig, the
one-hinge small hexapod (``dynaroach_robot``) and the robot with its own swing-and-lift legs (``dynaroach_legs``,
:mod:`mjrft.models.dynaroach`). The regime itself, its
coefficient and why it is taken from the paper's 12 Hz numbers rather than fig. 5's printed alpha:
:mod:`mjrft.laws.inertial`.

``dynaroach_intrusion``
    A horizontal plate with the projected area of a DynaRoACH tripod (3 x 1.4 cm^2, a 2.05 cm square,
    0.2 cm thick: the paper's "~1.4 cm^2" per leg) on the paper's 3 mm glass (catalogue ``glass3_cp``,
    law ``rft``), pushed straight down through the real coupler (:class:`mjrft.GranularTerrain`, kinematic
    sweep as :mod:`mjrft.tools.rigs` does) and read where its quasi-static lift equals the robot's weight
    (the fit's "+1": the legs sink until the grains carry the body), at intrusion speeds 0 to 1.2 m/s,
    with the inertial regime off and on. Compared with fig. 5's quadratic ``F_z / mg = alpha v^2 + 1``,
    v_c = 25 cm/s and the text's 12 Hz peak (6-7 mg at ~1 m/s, fig. 2J and 4B). Also the regime's
    explicit stability limit on the 25 g plate at 1 m/s against the 1 ms timestep of the bundled envs.

    Tolerances. The 12 Hz peak: the paper's own band, 6-7 mg (it is the point the coefficient was derived
    from, with the paper's 2.47 g/cm^3 glass; the catalogue medium is Li's 2.6 g/cm^3, so mjrft is 5 %
    higher by construction: the check tests the implementation, not the physics, and is reported as a
    consistency check, as are the onset, which is the paper's own v_c = sqrt(2 g d) built into the
    regime, the monotonic rise, and the stability limit). Onset: the sampling
    step of the speed sweep (2.5 cm/s). Fig. 5's alpha: the fit's coefficient against the regime's
    quadratic coefficient (C rho_bulk A / mg) within 25 %, the spread a one-parameter fit to robot data
    of the size of fig. 5's error bars can be expected to carry; it fails by a factor of ~10 for the
    cause given in the result.

``dynaroach_robot``
    The small hexapod (:func:`mjrft.models.hexapod_xml` ``variant="small"``: 10 cm, 25 g, six C-legs of
    radius 1 cm and width 0.7 cm) on ``glass3_cp`` under ``rft``, alternating tripod at stride
    frequencies 2-12 Hz, regime off and on: average forward speed, stride length (speed / f), maximum
    leg penetration depth (in grain diameters, 3 mm), maximum vertical penetration speed of a buried
    leg element, peak vertical force on a tripod, duty factor and mean body height.

    Choices where the paper is silent or lost. The robot's legs are driven by one motor through a
    linkage that retracts each leg, lifts it sideways and protracts it (fig. 1B, E; the swing and lift
    angles are in the lost figures, not the text). The bundled small hexapod has one hip hinge per leg,
    so its tripod turns the legs continuously (RHex's clock: hip target ``2 pi f t``, tripod B half a
    turn behind), which is the "rotary walking" kinematics of the paper's model (Li et al. 2009) but
    not DynaRoACH's swing. The first 0.5 s (full; 0.3 s quick) are a transient from rest and are not
    averaged. The published experiment's speed at 12 Hz (50 cm/s) is compared within 50 %: the leg
    kinematics differ, so only the scale is comparable. The transition frequency is found as the paper's
    fig. 7 does: the intersection of straight lines fitted to speed over 2-6 Hz and 7-12 Hz (band
    5-7 Hz, "around 6 Hz").

``dynaroach_legs``
    DynaRoACH with the paper's own leg motion (:mod:`mjrft.models.dynaroach`: per leg a lift hinge and a
    swing hinge as the paper's multibody model, one crank, tripods half a period apart; its choices are in
    that module), regime off and on, at the same frequencies, plus measurements of the cause: the same
    gait with no granular forces on the torso (the legs alone), and the depth at which a still tripod of
    these legs pushed straight down carries the weight. Checks: speed rising with frequency, the stride
    near 2r at 3 Hz (consistency: the swing amplitude is derived from it), stance beginning during
    protraction (sec. 3.1.1), the fig. 7 transition, the 12 Hz speed within 50 % and the body rising with
    frequency by at least half the paper's 0.58 cm (3 to 11 Hz).
"""

from __future__ import annotations

import math
import warnings

import mujoco
import numpy as np

from mjrft import GranularTerrain
from mjrft.laws.inertial import INERTIAL_DRAG
from mjrft.media import MEDIA
from ..case import (SIMILAR, CaseResult, Check, Line, Panel, case, check_band, check_close, check_outcome,
                    published)

PAPER = "dynaroach"
CITE = "Zhang et al., IJRR 2013 (DynaRoACH)"
MEDIUM = "glass3_cp"
G = 9.81


def _d(key):
    return published(PAPER, key)


def _mg() -> float:
    return _d("robot_mass").value * 1e-3 * G


# ------------------------------------------------------------------------------------------------
# the intrusion rig
# ------------------------------------------------------------------------------------------------
PLATE_XML = """<mujoco><option timestep="0.001" gravity="0 0 -9.81"/>
<worldbody><body name="plate" pos="0 0 0"><joint name="z" type="slide" axis="0 0 1"/>
<geom type="box" size="{h:.6g} {h:.6g} 0.001" mass="{m:.6g}"/></body></worldbody></mujoco>"""


def _plate_force(terrain, model, data, depth, speed, travel=0.003, step=2.5e-4):
    """Vertical force (N) on the plate pushed down at ``speed`` until its bottom face is ``depth`` deep
    (a kinematic sweep over the last ``travel`` of the path: the rest memory loads up over 1 mm)."""
    terrain.reset()
    n = int(round(travel / step)) + 1
    zs = np.linspace(-(depth - travel), -depth, n) + 0.001  # centre of the 2 mm plate
    v = max(speed, 1e-4)  # a plate at rest has no direction: a slow push stands for the quasi-static limit
    fz = 0.0
    for k, z in enumerate(zs):
        data.qpos[0] = z
        data.qvel[0] = -v
        mujoco.mj_fwdPosition(model, data)
        mujoco.mj_fwdVelocity(model, data)
        data.time = k * step / v
        fz = terrain.compute(data, 0.0 if k == 0 else step / v)[1, 2]
    return float(fz)


@case("dynaroach_intrusion", "DynaRoACH tripod-area plate: lift vs intrusion speed, inertial regime off and on",
      PAPER)
def intrusion(quick: bool) -> CaseResult:
    mg = _mg()
    area = 3 * _d("leg_area").value * 1e-4
    half = 0.5 * math.sqrt(area)
    model = mujoco.MjModel.from_xml_string(PLATE_XML.format(h=half, m=_d("robot_mass").value * 1e-3))
    data = mujoco.MjData(model)
    res = 0.005 if quick else 0.0025
    terrains = {on: GranularTerrain(model, MEDIUM, "rft", bodies=["plate"], resolution=res, inertial=on)
                for on in (False, True)}
    # the depth where the quasi-static lift carries the weight (lift is linear in depth under rft)
    ref_depth = 0.01
    d0 = ref_depth * mg / _plate_force(terrains[False], model, data, ref_depth, 0.01)
    dv = 0.05 if quick else 0.025
    speeds = np.round(np.arange(0.0, 1.2 + 1e-9, dv), 6)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the off law leaves its 1 m/s range at the top speeds: that is the point
        lift = {on: np.array([_plate_force(t, model, data, d0, v) for v in speeds]) / mg for on, t in terrains.items()}
    vc = _d("v_c").value * 1e-2
    alpha = _d("alpha_fig5").value * 1e4  # cm^-2 s^2 -> m^-2 s^2
    v12 = _d("penetration_speed_12hz").value * 1e-2
    peak = _d("peak_lift_12hz")
    at = {on: float(np.interp(v12, speeds, lift[on])) for on in lift}
    extra = lift[True] - lift[False]
    # onset: where the added lift, a straight line in v^2 above the first sampled speed that has any, is zero
    rising = extra > 1e-9
    onset = math.nan
    if rising.sum() >= 2:
        k, c0 = np.polyfit(speeds[rising] ** 2, extra[rising], 1)
        onset = math.sqrt(max(-c0 / k, 0.0)) if k > 0 else math.nan
    # the regime's quadratic coefficient, fitted like fig. 5 (F/mg - 1 = a v^2) over the speeds above v_c
    fast = speeds > vc
    a_sim = float(np.sum(speeds[fast] ** 2 * (lift[True][fast] - 1.0)) / np.sum(speeds[fast] ** 4))
    # stability: the 25 g plate at the 12 Hz speed, 1 ms step
    t = terrains[True]
    data.qpos[0], data.qvel[0] = -d0 + 0.001, -v12
    mujoco.mj_fwdPosition(model, data)
    mujoco.mj_fwdVelocity(model, data)
    t.compute(data, 0.0)
    dt_lim = float(t.stable_timestep(data, "springs")[1])
    buried = t.depth > 0
    c_theory = 2 * INERTIAL_DRAG * MEDIA[MEDIUM].rho_bulk * float(
        np.sum(t.area[buried & (t.normal[:, 2] < -0.99)])) * v12 * min(1.0, d0 / 1e-3)

    checks = [
        check_outcome("regime off: lift independent of intrusion speed (rate-independent RFT)",
                      bool(np.ptp(lift[False][speeds > 0]) < 1e-6),
                      published="fig. 5: lift rises about quadratically with penetration speed",
                      simulated=f"F_z/mg {lift[False][1]:.3f} at {speeds[1]:g} m/s and {lift[False][-1]:.3f} at "
                                f"{speeds[-1]:g} m/s", source=_d("alpha_fig5").cite(), qualitative=False),
        check_close("regime on: onset of the speed-dependent lift", _d("v_c"), onset * 100, dv / vc,
                    unit="cm/s", qualitative=True, basis="the speed sweep's step",
                    consistency="the regime starts at the medium's v_c = sqrt(2 g d), the paper's own formula"),
        check_band("regime on: tripod-area lift at the 12 Hz penetration speed", at[True], peak.value[0],
                   peak.value[1], published=f"{peak.value[0]:g}-{peak.value[1]:g} mg at ~{v12 * 100:g} cm/s",
                   source=f"{peak.cite()}; {_d('penetration_speed_12hz').source}", unit="mg", qualitative=True,
                   consistency="the regime's coefficient C is calibrated from this 6-7 mg at ~1 m/s "
                               "(mjrft.laws.inertial)"),
        check_outcome("regime on: lift rises monotonically above v_c",
                      bool(np.all(np.diff(lift[True][fast]) > 0)),
                      published="hydrodynamic-like force increasing approximately quadratically with speed",
                      simulated=f"F_z/mg {lift[True][fast][0]:.3f} -> {lift[True][-1]:.3f}",
                      source=_d("alpha_fig5").source, qualitative=True,
                      consistency="the regime's force C rho_bulk (u^2 - v_c^2) rises with u by definition"),
        check_close("quadratic coefficient vs fig. 5's fit", _d("alpha_fig5"), a_sim * 1e-4, 0.25,
                    unit="cm^-2 s^2"),
        check_band("explicit stability limit of the regime (25 g plate, 12 Hz speed) above the 1 ms step",
                   dt_lim * 1e3, 1.0, math.inf, published="dt < 2 m / c, c = 2 C rho_bulk A u (mjrft.laws.inertial)",
                   source="mjrft.laws.inertial (stability)", unit="ms", qualitative=True,
                   consistency="a property of mjrft's integration, not a published number"),
    ]
    vv = np.linspace(0, 1.2, 61)
    panels = [
        Panel("Tripod-area plate at the weight-carrying depth", "intrusion speed (m/s)", "F_z / mg", [
            Line(speeds, lift[False], "mjrft rft, inertial off"),
            Line(speeds, lift[True], "mjrft rft, inertial on"),
            Line(vv, 1 + alpha * vv ** 2, "paper: fig. 5 fit as printed", source=_d("alpha_fig5").source),
            Line([v12, v12], list(peak.value), "paper: 12 Hz peak (fig. 2J, 4B text)", source=peak.source),
            Line([vc, vc], [0, 8], "paper: v_c = 25 cm/s", source=_d("v_c").source),
        ]),
        Panel("Same, below 10 mg", "intrusion speed (m/s)", "F_z / mg", [
            Line(speeds, lift[False], "mjrft rft, inertial off"),
            Line(speeds, lift[True], "mjrft rft, inertial on"),
            Line(vv[vv <= 0.35], 1 + alpha * vv[vv <= 0.35] ** 2, "paper: fig. 5 fit as printed",
                 source=_d("alpha_fig5").source),
            Line([v12, v12], list(peak.value), "paper: 12 Hz peak", source=peak.source),
        ]),
    ]
    return CaseResult(
        name="dynaroach_intrusion", title="DynaRoACH tripod-area plate: lift vs intrusion speed", paper=CITE,
        source="sec. 3.2, figs. 2J, 4B, 5",
        setup=(f"plate {2 * half * 100:.3g} x {2 * half * 100:.3g} x 0.2 cm (3 x {_d('leg_area').value:g} cm^2, a tripod's "
               f"projected legs), 25 g, medium {MEDIUM} (3.2 mm glass, rho_bulk {MEDIA[MEDIUM].rho_bulk:.0f} kg/m^3, "
               f"v_c = sqrt(2 g d) = {MEDIA[MEDIUM].critical_speed * 100:.1f} cm/s), law rft, resolution {res * 1e3:g} mm, "
               f"pushed straight down, read with its bottom face at {d0 * 1e3:.2f} mm (quasi-static lift = mg), "
               f"speeds 0-1.2 m/s every {dv * 100:g} cm/s; inertial regime C = {INERTIAL_DRAG:.3f}"),
        checks=checks, panels=panels,
        cause=(f"Fig. 5's caption alpha = 5.7e-3 cm^-2 s^2 is not consistent with the paper's own text: at the 12 Hz "
               f"penetration speed (~1 m/s, fig. 4B) it gives F_z/mg = {1 + alpha * v12 ** 2:.0f}, against the stated "
               f"peak of 6-7 mg at 12 Hz (fig. 2J); the text's numbers need alpha ~ 5.5e-4 cm^-2 s^2. mjrft's regime "
               f"is derived from the consistent text numbers (mjrft.laws.inertial), so its quadratic coefficient, "
               f"{a_sim * 1e-4:.3g} cm^-2 s^2 (fitted like fig. 5 above v_c), is ~{alpha * 1e-4 / (a_sim * 1e-4):.0f} "
               "times below the printed one; with alpha as printed C would be 21.4. The regime-off check fails by "
               "construction: quasi-static RFT has no speed dependence, which is what the regime adds."),
        notes=(f"Measured: F_z/mg at {v12 * 100:g} cm/s: {at[False]:.3f} off, {at[True]:.3f} on; onset "
               f"{onset * 100:.1f} cm/s; stable timestep of the plate at {v12 * 100:g} cm/s with the regime on "
               f"{dt_lim * 1e3:.2f} ms (the damper alone: 2 m / c = {2 * 0.025 / c_theory * 1e3:.2f} ms). The plate, not a "
               "C-leg, because fig. 5's force is a tripod's and the paper gives its legs' projected area; the weight-"
               "carrying depth stands for the fit's '+1' (the legs sink until the grains carry the body)."),
    )


# ------------------------------------------------------------------------------------------------
# the robot
# ------------------------------------------------------------------------------------------------
def _tripod_offsets(model, tripod_a) -> np.ndarray:
    off = np.zeros(model.nu)
    for i in range(model.nu):
        body = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, model.jnt_bodyid[model.actuator_trnid[i, 0]])
        off[i] = 0.0 if body in tripod_a else math.pi
    return off


def _tripod_walk(data, terrain, ctrl, n, nw, legs, tri_a, freq, out):
    """Run a gait for ``n`` terrain steps (``ctrl(t)``: the actuator targets at time t) and, after each step from
    step ``nw`` on, record in ``out`` the deepest element of the ``legs`` (``depth``, m), the fastest downward
    buried one (``vpen``, m/s) and the peak vertical force on tripod A's elements ``tri_a`` (``lift``, N), then
    yield that step's force on tripod A (N) for the caller's own measures. At the end ``out`` gets the mean
    forward ``speed`` (m/s) over the recorded steps and the ``stride`` (m) at ``freq`` Hz."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the speed-range warning of the regime-off law is expected here
        for s in range(n):
            data.ctrl[:] = ctrl(data.time)
            terrain.step(data, 1)
            if s == nw:
                x0, t0 = data.qpos[0], data.time
            if s >= nw:
                bur = legs & (terrain.depth > 0)
                if bur.any():
                    out["depth"] = max(out["depth"], float(terrain.depth[bur].max()))
                    out["vpen"] = max(out["vpen"], float((-terrain.vel[bur, 2]).max()))
                fa = float(terrain.force[tri_a, 2].sum())
                out["lift"] = max(out["lift"], fa)
                yield fa
    out["speed"] = (data.qpos[0] - x0) / (data.time - t0)
    out["stride"] = out["speed"] / freq


def robot_run(freq: float, inertial: bool, seconds: float, warm: float, resolution: float = 0.005,
              ground_memory=False, observe=None) -> dict:
    """The small hexapod's tripod at ``freq`` Hz for ``seconds`` (the first ``warm`` s not averaged); returns
    speed (m/s), stride (m), deepest leg element (m), fastest downward buried leg element (m/s), peak tripod
    A lift (N), mean torso height (m), duty factor (fraction of the time tripod A carries more than 2 % of
    the weight). ``ground_memory``: the terrain's (:mod:`mjrft.ground`); ``observe(terrain, data)``: called after
    every averaged step."""
    from mjrft.models.hexapod import LEG_NAMES, TRIPOD_A, hexapod_xml

    xml = hexapod_xml(variant="small", medium=MEDIUM, law="rft", resolution=resolution)
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    off = _tripod_offsets(model, {f"leg_{n}" for n in TRIPOD_A})
    n = int(round(seconds / model.opt.timestep))
    nw = int(round(warm / model.opt.timestep))
    out = {"depth": 0.0, "vpen": 0.0, "lift": 0.0, "height": 0.0}
    terrain = GranularTerrain(model, inertial=inertial, ground_memory=ground_memory)
    legs = np.isin(terrain.elem_body, [model.body(f"leg_{k}").id for k in LEG_NAMES])
    tri_a = np.isin(terrain.elem_body, [model.body(f"leg_{k}").id for k in TRIPOD_A])
    heights = []
    stance = 0
    mg = float(model.body_subtreemass[model.body("torso").id]) * G
    for fa in _tripod_walk(data, terrain, lambda t: 2 * math.pi * freq * t + off, n, nw, legs, tri_a, freq, out):
        stance += fa > 0.02 * mg
        heights.append(data.qpos[2])
        if observe is not None:
            observe(terrain, data)
    out["height"] = float(np.mean(heights))
    out["duty"] = stance / max(1, n - nw)
    return out


def _transition(freqs, speeds) -> float:
    """Fig. 7's transition: intersection of lines fitted to speed over 2-6 Hz and 7-12 Hz."""
    f = np.asarray(freqs)
    v = np.asarray(speeds)
    lo, hi = (f >= 2) & (f <= 6), (f >= 7) & (f <= 12)
    if lo.sum() < 2 or hi.sum() < 2:
        return math.nan
    a1, b1 = np.polyfit(f[lo], v[lo], 1)
    a2, b2 = np.polyfit(f[hi], v[hi], 1)
    return (b2 - b1) / (a1 - a2) if a1 != a2 else math.nan


@case("dynaroach_robot", "DynaRoACH-sized hexapod on 3 mm glass: speed, stride and sinkage vs stride frequency",
      PAPER)
def robot(quick: bool) -> CaseResult:
    freqs = [3.0, 6.0, 8.0, 12.0] if quick else [2.0, 3.0, 4.0, 6.0, 8.0, 10.0, 12.0]
    seconds, warm = (0.8, 0.3) if quick else (1.5, 0.5)
    mg = _mg()
    d_grain = _d("grain_diameter").value * 1e-3
    runs = {on: [robot_run(f, on, seconds, warm) for f in freqs] for on in (False, True)}

    def col(on, key, k=1.0):
        return np.array([r[key] * k for r in runs[on]])

    speed = {on: col(on, "speed", 100) for on in runs}  # cm/s
    stride = {on: col(on, "stride", 100) for on in runs}  # cm
    depth = {on: col(on, "depth") / d_grain for on in runs}  # grain diameters
    height = {on: col(on, "height", 100) for on in runs}  # cm
    lift = {on: col(on, "lift") / mg for on in runs}
    vpen = {on: col(on, "vpen", 100) for on in runs}
    duty = {on: col(on, "duty") for on in runs}
    fa = np.array(freqs)
    trans = {on: _transition(freqs, speed[on]) for on in runs}
    hi = fa >= 7
    mid = (fa >= 4) & (fa <= 6)
    i3 = int(np.argmin(abs(fa - 3.0)))
    checks = []
    for on in (False, True):
        tag = "on" if on else "off"
        checks += [
            check_outcome(f"regime {tag}: speed rises with stride frequency", bool(np.all(np.diff(speed[on]) > 0)),
                          published=_d("speed_outcome").value, simulated=" -> ".join(f"{v:.1f}" for v in speed[on])
                          + " cm/s", source=_d("speed_outcome").source, qualitative=True),
            check_outcome(f"regime {tag}: stride length rises again at 7-12 Hz (speed super-linear)",
                          bool(stride[on][hi][-1] > stride[on][mid].min()),
                          published=_d("stride_outcome").value,
                          simulated=", ".join(f"{f:g} Hz {s:.2f} cm" for f, s in zip(freqs, stride[on])),
                          source=_d("stride_outcome").source, qualitative=False),
            check_outcome(f"regime {tag}: penetration depth falls above ~3 Hz",
                          bool(depth[on][-1] < depth[on].max() and freqs[int(np.argmax(depth[on]))] <= 4.0),
                          published=_d("depth_outcome").value,
                          simulated=", ".join(f"{f:g} Hz {d:.2f}" for f, d in zip(freqs, depth[on])) + " grain diameters",
                          source=_d("depth_outcome").source, qualitative=False),
        ]
        if not quick:
            checks.append(check_band(f"regime {tag}: walk-to-run transition (fig. 7 line fits)", trans[on], 5.0, 7.0,
                                     published="around 6 Hz", source=_d("transition_frequency").source, unit="Hz",
                                     qualitative=False, reference=_d("transition_frequency").value))
        checks.append(check_outcome(f"regime {tag}: duty factor falls below 0.5 near 6 Hz",
                                    bool(np.any(duty[on][fa <= 7] < 0.5)), published=_d("duty_outcome").value,
                                    simulated=", ".join(f"{f:g} Hz {d:.2f}" for f, d in zip(freqs, duty[on])),
                                    source=_d("duty_outcome").source, qualitative=False))
        checks.append(check_close(f"regime {tag}: speed at 12 Hz (experiment)", _d("speed_12hz"), speed[on][-1], 0.5,
                                  qualitative=False))
        checks.append(check_band(f"regime {tag}: peak tripod lift at 12 Hz", lift[on][-1],
                                 _d("peak_lift_12hz").value[0], _d("peak_lift_12hz").value[1],
                                 published="~6-7 mg", source=_d("peak_lift_12hz").source, unit="mg", qualitative=False))
    checks += [
        check_outcome("regime on lifts the body at high frequency, off does not",
                      bool(height[True][-1] > height[True][i3] and height[True][-1] > height[False][-1]),
                      published=f"body {_d('body_height').value[1]:g} cm above the surface at 11 Hz vs "
                                f"{_d('body_height').value[0]:g} cm at 3 Hz: the legs' hydrodynamic-like lift keeps "
                                "the body well above the surface",
                      simulated=(f"{freqs[i3]:g} Hz: {height[True][i3]:.2f} cm on / {height[False][i3]:.2f} off; "
                                 f"{freqs[-1]:g} Hz: {height[True][-1]:.2f} on / {height[False][-1]:.2f} off"),
                      source=_d("body_height").source, qualitative=True),
        check_outcome("regime on keeps the legs shallower at the top frequency than off",
                      bool(depth[True][-1] < depth[False][-1]),
                      published="at high frequencies the inertial lift balances the body before the legs sink deep",
                      simulated=f"{freqs[-1]:g} Hz: {depth[True][-1]:.2f} on, {depth[False][-1]:.2f} off grain diameters",
                      source="Zhang et al., sec. 3.2", qualitative=True),
    ]
    panels = [
        Panel("Average forward speed", "stride frequency (Hz)", "speed (cm/s)", [
            Line(freqs, speed[False], "mjrft, inertial off"), Line(freqs, speed[True], "mjrft, inertial on"),
            Line([12.0], [_d("speed_12hz").value], "paper: experiment at 12 Hz", source=_d("speed_12hz").source)]),
        Panel("Stride length", "stride frequency (Hz)", "stride (cm)", [
            Line(freqs, stride[False], "mjrft, inertial off"), Line(freqs, stride[True], "mjrft, inertial on"),
            Line([2.0, 3.0], [_d("stride_2r").value] * 2, "paper: ~2r at low frequency", source=_d("stride_2r").source)]),
        Panel("Maximum leg penetration depth", "stride frequency (Hz)", "depth (grain diameters)", [
            Line(freqs, depth[False], "mjrft, inertial off"), Line(freqs, depth[True], "mjrft, inertial on")]),
        Panel("Peak tripod lift", "stride frequency (Hz)", "F_z / mg", [
            Line(freqs, lift[False], "mjrft, inertial off"), Line(freqs, lift[True], "mjrft, inertial on"),
            Line([3.0, 12.0], [_d("peak_lift_3hz").value, float(np.mean(_d("peak_lift_12hz").value))],
                 "paper: ~1 mg at 3 Hz, ~6-7 mg at 12 Hz", source=_d("peak_lift_12hz").source)]),
    ]
    return CaseResult(
        name="dynaroach_robot", title="DynaRoACH-sized hexapod: speed, stride and sinkage vs stride frequency",
        paper=CITE, source="secs. 3.1-3.2, figs. 3, 4, 7",
        setup=(f"mjrft.models.hexapod_xml(variant='small'): 10 x 4.5 x 1.5 cm torso, 25 g, C-legs radius 1 cm, width "
               f"0.7 cm; medium {MEDIUM}, law rft, resolution 5 mm, timestep 1 ms; tripod hips driven at 2 pi f t "
               f"(tripod B half a turn behind) at f = {', '.join(f'{f:g}' for f in freqs)} Hz for {seconds:g} s, "
               f"averaged after {warm:g} s; inertial regime off and on (C = {INERTIAL_DRAG:.3f})"),
        checks=checks, panels=panels,
        cause=(f"Measured: the small hexapod's legs turn continuously about one hip hinge (rotary walking at every "
               f"frequency), where DynaRoACH's linkage retracts each leg through a limited angle, lifts it sideways "
               f"and protracts it (fig. 1B, E; the angles are in the lost figures). Its stride is "
               f"{stride[False].min():.1f}-{stride[False].max():.1f} cm (off) and {stride[True].min():.1f}-"
               f"{stride[True].max():.1f} cm (on), 3-4 times the paper's ~2r = 2 cm at low frequency, so the speed "
               f"is about stride x f and near-linear in f; the 12 Hz speed is {speed[False][-1]:.0f} (off) and "
               f"{speed[True][-1]:.0f} cm/s (on) against 50 cm/s. Its buried leg elements go down at up to "
               f"{vpen[True][-1]:.0f} cm/s at 12 Hz (a 2 cm leg turning at 12 Hz: 2 pi x 12 x 2 cm = 151 cm/s; "
               f"paper ~100 cm/s). The duty factor does fall below 0.5 from ~6 Hz as published "
               f"({', '.join(f'{d:.2f}' for d in duty[True])}, on), but the peak tripod lift at 12 Hz is "
               f"{lift[True][-1]:.1f} mg (on; paper 6-7 mg): a tripod's lift averaged over its stance is mg / (2 "
               f"duty) = {1 / (2 * duty[True][-1]):.1f} mg, so the turning legs spread it over the stance where the "
               "paper's tripods peak at 4-5 times their mean (not isolated further here). With the regime on, the inertial lift raises the body "
               f"with frequency ({height[True][0]:.2f} -> {height[True][-1]:.2f} cm) and shortens the legs' reach "
               f"below it, so the stride falls at high frequency instead of rising, and the deepest penetration "
               f"comes at {freqs[int(np.argmax(depth[True]))]:g} Hz, not 3 Hz. Without the regime the stride falls "
               f"then rises ({stride[False][0]:.2f} -> {stride[False].min():.2f} -> {stride[False][-1]:.2f} cm) "
               f"but the body does not rise and the legs sink deepest at {freqs[int(np.argmax(depth[False]))]:g} Hz. "
               "DynaRoACH's own swing-and-lift leg kinematics are the case dynaroach_legs, where the robot does "
               "not run either: its legs sweep through the grains and the belly carries the weight (measured there)."),
        notes=(f"Measured max vertical penetration speed of a buried leg element: "
               + ", ".join(f"{f:g} Hz {v:.0f}" for f, v in zip(freqs, vpen[True])) + " cm/s (on; paper: ~100 cm/s at "
               f"12 Hz, fig. 4B); transition frequency from the fig. 7 line fits: off {trans[False]:.2f} Hz, on "
               f"{trans[True]:.2f} Hz; mean torso height off " + ", ".join(f"{h:.2f}" for h in height[False])
               + " cm, on " + ", ".join(f"{h:.2f}" for h in height[True]) + " cm."),
    )


# ------------------------------------------------------------------------------------------------
# DynaRoACH's own leg kinematics (mjrft.models.dynaroach): swing and lift hinges on one crank
# ------------------------------------------------------------------------------------------------
def legs_run(freq: float, inertial: bool, seconds: float, warm: float, resolution: float = 0.005,
             torso_granular: bool = True, inertial_drag: float | None = None, ground_memory=False, observe=None,
             **gait) -> dict:
    """:func:`mjrft.models.dynaroach.dynaroach_xml` on the case's medium at ``freq`` Hz, driven by
    :func:`~mjrft.models.dynaroach.dynaroach_ctrl` (``gait``: its ``swing``, ``lift``, ``lift_phase``); the first
    ``warm`` s not averaged; ``inertial_drag``: the regime's coefficient C (None: mjrft's); ``ground_memory``: the
    terrain's (:mod:`mjrft.ground`); ``observe(terrain, data)``: called after every averaged step. ``torso_granular=False``
    leaves the torso out of the granular bodies (the legs alone carry the robot: a measurement of what the belly
    does, not a setup of the paper). Returns speed (m/s), stride (m), deepest leg element (m), fastest downward
    buried leg element (m/s), mean CoM height and
    its 5-95 % range (m), mean vertical granular force on the torso over mg, peak tripod-A lift (N), duty factor of
    tripod A, the fraction of leg lf's touchdowns that fall in its protraction (its swing hinge turning the tip
    forward), the mean fore-aft granular force on the legs while protracting and while retracting and their mean
    vertical force (all over mg)."""
    from mjrft.models.dynaroach import dynaroach_ctrl, dynaroach_xml, tripod_phase
    from mjrft.models.hexapod import LEG_NAMES, TRIPOD_A

    bodies = (["torso"] if torso_granular else []) + [f"leg_{n}" for n in LEG_NAMES]
    model = mujoco.MjModel.from_xml_string(dynaroach_xml(medium=MEDIUM, law="rft", resolution=resolution,
                                                         granular_bodies=bodies))
    data = mujoco.MjData(model)
    off = tripod_phase(model)
    terrain = GranularTerrain(model, inertial=inertial, inertial_drag=inertial_drag, ground_memory=ground_memory)
    legs = np.isin(terrain.elem_body, [model.body(f"leg_{k}").id for k in LEG_NAMES])
    tri_a = np.isin(terrain.elem_body, [model.body(f"leg_{k}").id for k in TRIPOD_A])
    lf = terrain.elem_body == model.body("leg_lf").id
    swing_lf = model.jnt_dofadr[model.joint("swing_lf").id]
    leg_of = {k: terrain.elem_body == model.body(f"leg_{k}").id for k in LEG_NAMES}
    swing_dof = {k: model.jnt_dofadr[model.joint(f"swing_{k}").id] for k in LEG_NAMES}
    fx_pro = fx_ret = fz_legs = 0.0
    torso = terrain.elem_body == model.body("torso").id
    mg = float(model.body_subtreemass[model.body("torso").id]) * G
    n, nw = int(round(seconds / model.opt.timestep)), int(round(warm / model.opt.timestep))
    out = {"depth": 0.0, "lift": 0.0, "vpen": 0.0}
    heights, belly, stance, down, touch, in_pro = [], [], 0, False, 0, 0
    for fa in _tripod_walk(data, terrain, lambda t: dynaroach_ctrl(model, t, freq, off, **gait), n, nw, legs, tri_a,
                           freq, out):
        stance += fa > 0.02 * mg
        heights.append(data.qpos[2])
        if observe is not None:
            observe(terrain, data)
        belly.append(float(terrain.force[torso, 2].sum()) / mg)
        fz_legs += float(terrain.force[legs, 2].sum())
        for k, el in leg_of.items():
            fx = float(terrain.force[el, 0].sum())
            if data.qvel[swing_dof[k]] < 0:  # the tip moving forward: protraction
                fx_pro += fx
            else:
                fx_ret += fx
        on = float(terrain.force[lf, 2].sum()) > 0.02 * mg / 3
        if on and not down:
            touch += 1
            in_pro += data.qvel[swing_lf] < 0  # positive swing turns the tip backward
        down = on
    out["height"] = float(np.mean(heights))
    out["bounce"] = float(np.percentile(heights, 95) - np.percentile(heights, 5))
    out["belly"] = float(np.mean(belly))
    out["duty"] = stance / max(1, n - nw)
    out["protraction"] = in_pro / touch if touch else math.nan
    steps = max(1, n - nw)
    out["fx_protraction"], out["fx_retraction"] = fx_pro / steps / mg, fx_ret / steps / mg
    out["legs_lift"] = fz_legs / steps / mg
    return out


def still_tripod_depth(resolution: float = 0.005) -> float:
    """Depth (m) of the tips at which DynaRoACH's legs, hanging straight down (swing 0, lift 0) and pushed slowly
    straight down into the case's medium, carry the robot's weight on one tripod (half the six legs' lift; the
    regime off): the depth the paper's "legs penetrate until vertical force balance" reaches."""
    from mjrft.models.dynaroach import HIP_Z, LEG_RADIUS, _lowest_tip, dynaroach_xml
    from mjrft.models.hexapod import LEG_NAMES

    model = mujoco.MjModel.from_xml_string(dynaroach_xml(medium=MEDIUM, law="rft", resolution=resolution,
                                                         granular_bodies=[f"leg_{n}" for n in LEG_NAMES]))
    data = mujoco.MjData(model)
    terrain = GranularTerrain(model, inertial=False)
    tip = HIP_Z + _lowest_tip(1.0 / LEG_RADIUS, 8)  # the lowest leg point below the torso's centre (< 0)
    mg, v, step = _mg(), 0.01, 2.5e-4
    depths = np.arange(0.0005, 0.02 + 1e-9, 0.0005)
    lift = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for dep in depths:
            terrain.reset()
            for k, dz in enumerate(np.linspace(dep - 0.003, dep, 13)):  # the rest memory loads over the last 3 mm
                data.qpos[2] = -max(dz, 0.0) - tip
                data.qvel[:] = 0.0
                data.qvel[2] = -v
                mujoco.mj_fwdPosition(model, data)
                mujoco.mj_fwdVelocity(model, data)
                terrain.compute(data, 0.0 if k == 0 else step / v)
            lift.append(float(terrain.force[:, 2].sum()) / 2 / mg)
    lift = np.array(lift)
    return float(np.interp(1.0, lift, depths)) if lift[-1] >= 1.0 else math.inf


def standing_height(sand: bool = True, seconds: float = 1.0) -> tuple[float, float]:
    """(CoM height (m), the torso's share of the weight) of DynaRoACH standing still, its legs at mid-retraction
    (swing 0, lift 0), after ``seconds`` on the case's bed (regime off) or, ``sand=False``, on a rigid floor."""
    from mjrft.models.dynaroach import dynaroach_xml

    model = mujoco.MjModel.from_xml_string(dynaroach_xml(sand=sand, medium=MEDIUM, law="rft", inertial=False))
    data = mujoco.MjData(model)
    terrain = GranularTerrain(model, inertial=False) if sand else None
    mg = _mg()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for _ in range(int(round(seconds / model.opt.timestep))):
            data.ctrl[:] = 0.0
            if terrain is not None:
                terrain.step(data, 1)
            else:
                mujoco.mj_step(model, data)
    share = 0.0 if terrain is None else float(terrain.force[terrain.elem_body == model.body("torso").id, 2].sum()) / mg
    return float(data.qpos[2]), share


def standing_check(height_cm: float) -> Check:
    """Sec. 3.1.1's standing body height, 1.2 cm above the grains, within 20 % ('similar', as in every case)."""
    return check_close("standing CoM height on the bed", _d("standing_height"), height_cm, 0.2, qualitative=True,
                       basis="'similar': within 20 %, as in every case")


def _first(freqs, mask) -> str:
    """The first frequency where ``mask`` holds (as text), or 'no frequency run'."""
    hits = [f for f, m in zip(freqs, mask) if m]
    return f"{hits[0]:g}" if hits else "none of the frequencies run"


def speed_rises_check(tag: str, speeds_cm) -> Check:
    """Fig. 3A: the average speed rises with stride frequency at every step of the sweep."""
    return check_outcome(f"regime {tag}: speed rises with stride frequency", bool(np.all(np.diff(speeds_cm) > 0)),
                         published=_d("speed_outcome").value, simulated=" -> ".join(f"{v:.1f}" for v in speeds_cm)
                         + " cm/s", source=_d("speed_outcome").source, qualitative=True)


def stride_check(tag: str, freq: float, stride_cm: float) -> Check:
    """Sec. 4.2: at low frequency the stride is near 2r (within 20 %); the swing amplitude is derived from it."""
    return check_close(f"regime {tag}: stride at {freq:g} Hz near 2r", _d("stride_2r"), stride_cm, 0.2,
                       qualitative=False, basis="'near': within 20 %, as 'similar' in every case",
                       consistency="the swing amplitude A = 30 deg is derived from this 2r (mjrft.models.dynaroach)")


def protraction_check(tag: str, freqs, fractions) -> Check:
    """Sec. 3.1.1's "stance phases that begin during protraction": more than half of a leg's touchdowns fall while it
    protracts, at every frequency."""
    fr = np.asarray(fractions, float)
    return check_outcome(f"regime {tag}: stance begins during protraction", bool(np.all(fr > 0.5)),
                         published="stance phases that begin during protraction phases of the legs",
                         simulated=", ".join(f"{f:g} Hz {p:.2f}" for f, p in zip(freqs, fr))
                         + " of leg lf's touchdowns in protraction", source="Zhang et al., sec. 3.1.1",
                         qualitative=True)


def _line_fits(freqs, speeds) -> tuple[float, float, float]:
    """(crossing frequency, slope over 2-6 Hz, slope over 7-12 Hz) of fig. 7's two straight-line fits."""
    f, v = np.asarray(freqs, float), np.asarray(speeds, float)
    lo, hi = (f >= 2) & (f <= 6), (f >= 7) & (f <= 12)
    if lo.sum() < 2 or hi.sum() < 2:
        return math.nan, math.nan, math.nan
    (a1, b1), (a2, b2) = np.polyfit(f[lo], v[lo], 1), np.polyfit(f[hi], v[hi], 1)
    return ((b2 - b1) / (a1 - a2) if a1 != a2 else math.nan), float(a1), float(a2)


def transition_check(tag: str, freqs, speeds) -> Check:
    """Fig. 7's walk-to-run transition: the speed's line fit over 7-12 Hz is steeper than over 2-6 Hz (speed rising
    super-linearly; slopes that are 'similar', within 20 %, are one line, no transition) and the two cross in 5-7 Hz
    ("around 6 Hz")."""
    trans, a_lo, a_hi = _line_fits(freqs, speeds)
    steeper = bool(a_lo > 0 and a_hi > (1 + SIMILAR) * a_lo)
    value = trans if (steeper and math.isfinite(trans)) else math.inf
    return check_band(f"regime {tag}: walk-to-run transition (fig. 7 line fits)", value, 5.0, 7.0,
                      published="around 6 Hz, the speed steeper above it", source=_d("transition_frequency").source,
                      unit="Hz", qualitative=False, reference=_d("transition_frequency").value,
                      basis=f"the 7-12 Hz slope > {1 + SIMILAR:g} x the 2-6 Hz slope (measured {a_hi:.2f} vs "
                            f"{a_lo:.2f} cm/s per Hz), crossing in the band")


def body_lift_check(f_lo: float, h_lo: float, f_hi: float, h_hi: float) -> Check:
    """Secs. 3.1.1-3.1.2: the body runs 0.58 cm higher at 11 Hz than at 3 Hz (1.86 vs 1.28 cm); read as a rise of at
    least half that between the lowest and highest frequencies run."""
    lo, hi = _d("body_height").value
    return check_outcome(
        "regime on lifts the body at high frequency", bool(h_hi - h_lo >= 0.5 * (hi - lo)),
        published=f"body {hi:g} cm above the surface at 11 Hz vs {lo:g} cm at 3 Hz (a rise of {hi - lo:.2f} cm)",
        simulated=f"CoM {h_lo:.2f} cm at {f_lo:g} Hz, {h_hi:.2f} cm at {f_hi:g} Hz", source=_d("body_height").source,
        qualitative=True, tolerance=f"a rise >= half the paper's ({0.5 * (hi - lo):.2f} cm)")


@case("dynaroach_legs", "DynaRoACH with its swing-and-lift legs on 3 mm glass: speed, stride and sinkage vs stride "
      "frequency", PAPER)
def legs(quick: bool) -> CaseResult:
    from mjrft.models import dynaroach as dr

    freqs = [3.0, 6.0, 8.0, 12.0] if quick else [2.0, 3.0, 4.0, 6.0, 8.0, 10.0, 12.0]
    seconds, warm = (0.8, 0.3) if quick else (1.5, 0.5)
    d_grain = _d("grain_diameter").value * 1e-3
    runs = {on: [legs_run(f, on, seconds, warm) for f in freqs] for on in (False, True)}
    bare = [legs_run(f, False, seconds, warm, torso_granular=False) for f in freqs]  # the legs alone
    bare_on = legs_run(freqs[-1], True, seconds, warm, torso_granular=False)
    still = still_tripod_depth()
    stand, stand_belly = standing_height()
    # the regime's coefficient from fig. 5's printed alpha instead of the text's 12 Hz numbers (mjrft.laws.inertial)
    from mjrft.laws.inertial import PAPER_RHO_BULK, ROBOT_MASS, TRIPOD_AREA
    c_fig5 = _d("alpha_fig5").value * 1e4 * ROBOT_MASS * G / (PAPER_RHO_BULK * TRIPOD_AREA)
    fig5 = legs_run(freqs[-1], True, seconds, warm, inertial_drag=c_fig5)

    def col(rs, key, k=1.0):
        return np.array([r[key] * k for r in rs])

    speed = {on: col(runs[on], "speed", 100) for on in runs}
    stride = {on: col(runs[on], "stride", 100) for on in runs}
    depth = {on: col(runs[on], "depth") / d_grain for on in runs}
    height = {on: col(runs[on], "height", 100) for on in runs}
    belly = {on: col(runs[on], "belly") for on in runs}
    pro = {on: col(runs[on], "protraction") for on in runs}
    trans = {on: _transition(freqs, speed[on]) for on in runs}
    fits = {on: _line_fits(freqs, speed[on]) for on in runs}
    fa = np.array(freqs)
    i3 = int(np.argmin(abs(fa - 3.0)))
    checks = [standing_check(stand * 100)]
    for on in (False, True):
        tag = "on" if on else "off"
        checks += [
            speed_rises_check(tag, speed[on]),
            stride_check(tag, freqs[i3], stride[on][i3]),
            protraction_check(tag, freqs, pro[on]),
        ]
        if not quick:
            checks.append(transition_check(tag, freqs, speed[on]))
        checks.append(check_close(f"regime {tag}: speed at 12 Hz (experiment)", _d("speed_12hz"), speed[on][-1], 0.5,
                                  qualitative=False))
    checks.append(body_lift_check(freqs[i3], height[True][i3], freqs[-1], height[True][-1]))
    panels = [
        Panel("Average forward speed", "stride frequency (Hz)", "speed (cm/s)", [
            Line(freqs, speed[False], "mjrft, inertial off"), Line(freqs, speed[True], "mjrft, inertial on"),
            Line(freqs, col(bare, "speed", 100), "mjrft, off, torso without granular forces"),
            Line([12.0], [_d("speed_12hz").value], "paper: experiment at 12 Hz", source=_d("speed_12hz").source)]),
        Panel("Stride length", "stride frequency (Hz)", "stride (cm)", [
            Line(freqs, stride[False], "mjrft, inertial off"), Line(freqs, stride[True], "mjrft, inertial on"),
            Line(freqs, col(bare, "stride", 100), "mjrft, off, torso without granular forces"),
            Line([2.0, 3.0], [_d("stride_2r").value] * 2, "paper: ~2r at low frequency", source=_d("stride_2r").source)]),
        Panel("CoM height", "stride frequency (Hz)", "height (cm)", [
            Line(freqs, height[False], "mjrft, inertial off"), Line(freqs, height[True], "mjrft, inertial on"),
            Line(freqs, col(bare, "height", 100), "mjrft, off, torso without granular forces"),
            Line([3.0, 11.0], list(_d("body_height").value), "paper: 1.28 cm at 3 Hz, 1.86 cm at 11 Hz",
                 source=_d("body_height").source)]),
        Panel("Maximum leg penetration depth", "stride frequency (Hz)", "depth (grain diameters)", [
            Line(freqs, depth[False], "mjrft, inertial off"), Line(freqs, depth[True], "mjrft, inertial on"),
            Line(freqs, col(bare, "depth") / d_grain, "mjrft, off, torso without granular forces")]),
    ]
    bs = col(bare, "speed", 100)
    return CaseResult(
        name="dynaroach_legs", title="DynaRoACH with its swing-and-lift legs: speed, stride and sinkage vs stride frequency",
        paper=CITE, source="secs. 2.1.4, 2.2.2, 3.1-3.2, 4.2, figs. 1B, 3, 7",
        setup=(f"mjrft.models.dynaroach_xml: 10 x 4.5 x 1.5 cm torso, 25 g, C-legs radius 1 cm, width 0.7 cm, each on a "
               f"lift hinge (torso-plate) and a swing hinge (plate-leg) as the paper's multibody model; one crank: swing "
               f"-{math.degrees(dr.SWING_AMPLITUDE):g} cos(phi) deg, lift {math.degrees(dr.LIFT_RANGE):g} (1 - sin phi) / 2 "
               f"deg, tripod B half a period behind; lift hinges at the CoM's height; "
               f"medium {MEDIUM}, law rft, resolution 5 mm, timestep 1 ms; f = {', '.join(f'{f:g}' for f in freqs)} Hz "
               f"for {seconds:g} s, averaged after {warm:g} s; inertial regime off and on (C = {INERTIAL_DRAG:.3f})"),
        checks=checks, panels=panels,
        cause=(f"Measured: DynaRoACH stands on the bed at {stand * 100:.2f} cm (paper 1.2 cm; its legs sunk "
               f"{(2 * dr.LEG_RADIUS - stand) * 100:.2f} cm, where a still tripod pushed straight down carries the "
               f"weight at {still * 100:.2f} cm) and strides {stride[False][i3]:.2f} cm at {freqs[i3]:g} Hz (paper "
               f"~2r = 2 cm), but walking its legs sink {depth[False].min():.1f}-{depth[False].max():.1f} grain "
               f"diameters ({depth[False].min() * d_grain * 100:.1f}-{depth[False].max() * d_grain * 100:.1f} cm), deeper "
               f"than the sideways lift raises their tips (1 cm), so from {_first(freqs, col(runs[False], 'duty') > 0.99)} "
               f"Hz a tripod never leaves the grains (duty " + ", ".join(f"{d:.2f}" for d in col(runs[False], "duty"))
               + f", off) and the stance no longer begins in protraction; the CoM runs at {height[False].min():.2f}-"
               f"{height[False].max():.2f} cm with the belly carrying {belly[False].min():.2f}-{belly[False].max():.2f} "
               "of the weight. The stride stays near 2 cm at every frequency, quasi-static rotary walking, so the speed "
               f"rises about linearly, to {speed[False][-1]:.1f} cm/s at 12 Hz (paper 50), with no walk-to-run "
               f"transition: fig. 7's line fits have slopes {fits[False][1]:.2f} (2-6 Hz) and {fits[False][2]:.2f} "
               f"cm/s per Hz (7-12 Hz). With the inertial regime the robot "
               f"is slower above ~6 Hz ({speed[True][-1]:.1f} cm/s at 12 Hz): the legs' protraction through the "
               f"grains drags at {runs[True][-1]['fx_protraction']:+.2f} mg (off {runs[False][-1]['fx_protraction']:+.2f}) "
               f"while the CoM rises only to {height[True][-1]:.2f} cm (paper 1.86 cm at 11 Hz) and the peak tripod "
               f"lift is {runs[True][-1]['lift'] / _mg():.2f} mg (paper 6-7 mg). Without granular forces on the torso "
               f"the speeds barely change ({bs[-1]:.1f} cm/s at 12 Hz off, {bare_on['speed'] * 100:.1f} on): the "
               "belly is not what holds the robot back. Nor is the regime's coefficient alone: with C from fig. 5's printed "
               f"alpha ({c_fig5:.1f} instead of {INERTIAL_DRAG:.2f}) the 12 Hz CoM rises to {fig5['height'] * 100:.2f} cm, "
               f"the duty falls to {fig5['duty']:.2f} and the peak tripod lift to {fig5['lift'] / _mg():.2f} mg, but the speed "
               f"is {fig5['speed'] * 100:.1f} cm/s. The legs' fastest buried element goes down at "
               f"{runs[True][-1]['vpen'] * 100:.0f} cm/s at 12 Hz (paper nearly 100, fig. 4B), so the speeds the regime "
               "needs are there; the body does not bounce onto the legs (CoM 5-95 % range "
               f"{runs[True][-1]['bounce'] * 100:.2f} cm at 12 Hz, {runs[False][i3]['bounce'] * 100:.2f} cm at "
               f"{freqs[i3]:g} Hz; paper: a 0.46 cm rise at 3 Hz, 0.19 cm dips at 11 Hz). What the paper's DEM legs do and mjrft's quasi-static RFT "
               "does not: stop penetrating once they carry the body and rotate atop solidified grains (sec. 2.2.4), "
               "and, above ~6 Hz, get lifted by the grains' inertia enough to leave the grains between steps "
               "(aerial phases, duty factor below 0.5, sec. 3.1)."),
        notes=(f"Transition frequency from the fig. 7 line fits: off {trans[False]:.2f} Hz, on {trans[True]:.2f} Hz. "
               "Torso without granular forces (off): speed " + ", ".join(f"{f:g} Hz {v:.1f}" for f, v in zip(freqs, bs))
               + " cm/s. CoM height off " + ", ".join(f"{h:.2f}" for h in height[False]) + " cm, on "
               + ", ".join(f"{h:.2f}" for h in height[True]) + " cm. Mean fore-aft force on the legs (off, with the "
               "torso): " + ", ".join(f"{f:g} Hz {r['fx_retraction']:+.2f} retracting / {r['fx_protraction']:+.2f} "
                                     f"protracting" for f, r in zip(freqs, runs[False])) + " mg. The swing amplitude, "
               "lift range, hip height and crank sinusoids are choices (mjrft.models.dynaroach); the one-hinge small "
               "hexapod stays in dynaroach_robot."),
    )

"""SGRFT (saturated wet sand, Machines 2022): plate drags and presses, and the R/V/T legs at 2, 30 and 40 rpm.

Every case runs the paper's setup through mjrft's own rigs (:mod:`mjrft.tools.rigs`: kinematic plate and
rotating leg through :class:`mjrft.GranularTerrain`) with the catalogue medium ``sea_sand_saturated``
and the law ``wet`` (:mod:`mjrft.laws.wet`: Li RFT x the paper's linear velocity coefficient); the
dry comparisons use :func:`mjrft.laws.wet.dry_reference` with the law ``rft``. Published numbers come
from ``data/sgrft.json``.

Tolerances. The paper's own statement of its model error is fig. 6 / sec. 3.1: of 14 SGRFT predictions
of the horizontal plate force, 10 err by less than 6 % and only 2 by more than 16 %. A published
number that SGRFT itself predicts (plate force ratio, alpha^v) is therefore compared with a 16 %
relative tolerance (``prediction_error_bound``). "No significant difference" and "not sensitive"
use the paper's own thresholds: 5 % (sec. 2.4, the dry media's largest change over 10-50 mm/s) and
10 % (conclusion (1)). The 30 -> 40 rpm thrust change is compared with the paper's prediction within
2 % and with its measurements within the paper's own prediction error (see :func:`rpm`).
"""

from __future__ import annotations

import math

import numpy as np

from ... import rigs
from mjrft.laws.wet import dry_reference
from mjrft.media import get_medium
from ..case import Check, CaseResult, Line, Panel, case, check_band, check_close, check_outcome, published, wrong_physics

PAPER = "sgrft"
CITE = "SGRFT, Machines 2022"
SAND = "sea_sand_saturated"
N_CM3 = 1e6  # N/m^3 per N/cm^3


def _d(key):
    return published(PAPER, key)


def _v(key):
    return _d(key).value


def _fmt_list(xs, scale=1.0, unit=""):
    return ", ".join(f"{x * scale:g}" for x in xs) + (f" {unit}" if unit else "")


def _r2(x, y):
    x, y = np.asarray(x, float), np.asarray(y, float)
    slope, icpt = np.polyfit(x, y, 1)
    ss = float(np.sum((y - y.mean()) ** 2))
    return 1.0 - float(np.sum((y - (slope * x + icpt)) ** 2)) / ss if ss > 0 else 1.0, float(slope), float(icpt)


# ------------------------------------------------------------------------------------------------
# plate
# ------------------------------------------------------------------------------------------------
PAPER_ERROR = "SGRFT's own prediction error, fig. 6: the tolerance equals the paper's model error"


def ratio_check(ratio: float) -> Check:
    """Sec. 2.4: the measured wet drag at 50 mm/s is 178.6 % of that at 10 mm/s (30 mm depth), compared within
    16 %, the paper's own prediction error (fig. 6: of 14 SGRFT predictions only 2 err by more)."""
    return check_close("wet F(50 mm/s) / F(10 mm/s) at 30 mm depth", _d("wet_force_ratio_50_10"), ratio,
                       _v("prediction_error_bound"), basis=PAPER_ERROR)


def _plate_settings(quick):
    return {"resolution": 0.005 if quick else 0.00125, "step": 0.002 if quick else 0.0005}


def _plate_drag(speed, depth, medium, law, quick, variant=None):
    """Steady horizontal drag (N) on the paper's plate face-on at centre ``depth``: mean over the second
    half of a 3-plate-length drag (the first ~1 mm of travel is the grains loading up); ``variant``: a
    wrong-physics variant (:func:`mjrft.tools.validation.case.wrong_physics`)."""
    length, width, thick = _v("plate_size")
    medium, law = wrong_physics(variant, medium, law)
    p = rigs.plate_intrusion(beta=math.pi / 2, gamma=0.0, speed=speed, depth=depth, length=length, width=width,
                             thickness=thick, medium=medium, law=law, **_plate_settings(quick))
    return float(np.mean(p.drag[len(p.drag) // 2:]))


@case("sgrft_plate_speed", "plate drag vs speed, wet vs dry", CITE)
def plate_speed(quick: bool) -> CaseResult:
    """Horizontal force on the 20 x 20 x 2 mm plate at 30 mm depth, 10-50 mm/s (sec. 2.4, fig. 3a).

    Checks: F(50)/F(10) = 1.786 within 16 % (the paper's prediction-error bound, fig. 6); force grows
    with speed; roughly linear (R^2 of a line >= the paper's 0.952); wet below dry at 10-20 mm/s and
    above at >= 30 mm/s; dry force changes by <= 5 % over the range (sec. 2.4).
    """
    speeds = np.asarray(_v("plate_speeds"), float)
    depths = [d for d in _v("plate_speed_depths") if d > 0]  # 0 mm: a plate centred on the surface (below)
    d30 = _v("base_depth")
    dry = dry_reference()
    wet = {d: np.array([_plate_drag(v, d, SAND, "wet", quick) for v in speeds]) for d in depths}
    dry_f = {d: np.array([_plate_drag(v, d, dry, "rft", quick) for v in speeds]) for d in depths}
    w30, dr30 = wet[d30], dry_f[d30]
    ratio = w30[-1] / w30[0]
    r2, _, _ = _r2(speeds, w30)
    dry_change = float(np.max(np.abs(dr30 - dr30[0])) / dr30[0])
    below = [float(v) for v in _v("wet_below_dry_speeds")]
    above = [float(v) for v in _v("wet_above_dry_speeds")]
    wd = {float(v): float(w / d) for v, w, d in zip(speeds, w30, dr30)}
    ok_cross = all(wd[v] < 1 for v in below) and all(wd[v] > 1 for v in above)
    checks = [
        ratio_check(ratio),
        check_outcome("wet force grows with speed", bool(np.all(np.diff(w30) > 0)),
                      published="force in SWGM increases significantly with speed",
                      simulated=" < ".join(f"{f:.3g}" for f in w30) + " N", source="sec. 2.4, fig. 3a",
                      consistency="the wet law's speed factor 1 + eps_v (v - 30 mm/s) / 10 mm/s rises with speed by "
                                  "definition (mjrft.laws.wet)"),
        check_band("wet force roughly linear in speed (R^2 of a line)", r2, _v("eps_v_r2"), 1.0,
                   published=f"linear fit, R^2 {_v('eps_v_r2')}", source=_d("eps_v_r2").cite(),
                   consistency="the wet law is linear in speed by construction (R^2 = 1 up to the rig's sampling)"),
        check_outcome("wet < dry at 10-20 mm/s, wet > dry at >= 30 mm/s", ok_cross,
                      published="wet lower than dry at 10-20 mm/s, higher above 30 mm/s",
                      simulated="wet/dry " + ", ".join(f"{wd[float(v)]:.3f} at {v * 1000:g}" for v in speeds) + " mm/s",
                      source=_d("wet_below_dry_speeds").source,
                      consistency="the dry reference is the wet law's stress at 25 mm/s (mjrft.laws.wet.dry_reference)"),
        check_band("dry force change over 10-50 mm/s", dry_change, 0.0, _v("dry_force_change_max"),
                   published=f"<= {_v('dry_force_change_max') * 100:g} %", source=_d("dry_force_change_max").cite(),
                   consistency="Li RFT (law rft) has no speed dependence"),
    ]
    mm = speeds * 1000
    panels = [
        Panel("horizontal force at 30 mm depth", "speed (mm/s)", "drag (N)",
              [Line(mm, w30, "mjrft wet (law wet)"), Line(mm, dr30, "mjrft dry reference (law rft)")]
              + [Line(mm, wet[d], f"mjrft wet, {d * 1000:g} mm") for d in depths if d != d30]),
        Panel("wet force relative to 10 mm/s (30 mm depth)", "speed (mm/s)", "F(v) / F(10 mm/s)",
              [Line(mm, w30 / w30[0], "mjrft"),
               Line([mm[0], mm[-1]], [1.0, _v("wet_force_ratio_50_10")], "paper", source="sec. 2.4")]),
    ]
    length, width, thick = _v("plate_size")
    setup = (f"Plate {length * 1000:g} x {width * 1000:g} x {thick * 1000:g} mm dragged horizontally face-on "
             f"(beta 90 deg, gamma 0) with its centre at {_fmt_list(depths, 1000, 'mm')}, speeds "
             f"{_fmt_list(speeds, 1000, 'mm/s')}; medium {SAND}, law wet; dry: {dry.name} "
             f"(zeta {dry.zeta / N_CM3:.3f} N/cm^3), law rft. Steady drag = mean over the second half of a "
             f"{3 * length * 1000:g} mm drag; elements {_plate_settings(quick)['resolution'] * 1000:g} mm.")
    notes = ("The paper's 0 mm depth series is not run: a plate centred on the surface is half in the water, and "
             "its fig. 3a values are lost with the figure. The dry medium is mjrft's documented dry reference "
             "(the same sea sand with the rate-independent stress the wet law reaches at 25 mm/s, mjrft.laws.wet): "
             "the paper does not tabulate its dry sand, so the crossover check holds by that construction and the "
             "dry <= 5 % check by Li RFT's rate independence; they show the construction stays consistent. "
             f"The linear law itself gives F(50)/F(10) = 1.32/0.68 = {1.32 / 0.68:.3f}.")
    return CaseResult(name="sgrft_plate_speed", title="plate drag vs speed, wet vs dry", paper=CITE,
                      source="sec. 2.4, fig. 3a", setup=setup, checks=checks, panels=panels, notes=notes)


def _press_alpha(speed, quick, variant=None):
    """Vertical press of the horizontal plate to 60 mm at ``speed``: depth (m), vertical stress F_z / area (Pa),
    the slope (N/cm^3) of a line fitted to them beyond the top 10 mm, and that fit's R^2."""
    length, width, thick = _v("plate_size")
    medium, law = wrong_physics(variant, SAND, "wet")
    p = rigs.plate_intrusion(beta=0.0, gamma=math.pi / 2, speed=speed, depth=_v("vertical_max_depth"),
                             length=length, width=width, thickness=thick, medium=medium, law=law,
                             **_plate_settings(quick))
    stress = p.lift / (length * width)  # Pa
    sel = p.depth >= _v("linear_depth_min")
    r2, slope, _ = _r2(p.depth[sel], stress[sel])
    return p.depth, stress, slope / N_CM3, r2


@case("sgrft_plate_depth", "plate force vs depth; table 3's alpha^10, alpha^20, alpha^30", CITE,
      variants=("rate_independent", "x2", "x0.5"))
def plate_depth(quick: bool, variant: str | None = None) -> CaseResult:
    """Stress per depth of the plate pressed down at 10, 20, 30 mm/s (sec. 2.5, fig. 4b, table 3), and the
    horizontal force vs depth at 30 mm/s, wet vs dry (sec. 2.4, fig. 3b).

    Checks: alpha^v within 16 % of table 3 (the paper's prediction-error bound, fig. 6); alpha grows with
    speed; force linear in depth beyond 10 mm (R^2 >= table 3's lowest, 0.933); wet and dry horizontal
    forces at 30 mm/s within the paper's 10 % "not significant" (conclusion (1)).
    """
    speeds = np.asarray(_v("alpha_speeds"), float)
    alpha_pub = np.asarray(_v("alpha_v"), float)
    runs = [_press_alpha(v, quick, variant) for v in speeds]
    alpha = np.array([r[2] for r in runs])
    r2min = min(r[3] for r in runs)
    tol = _v("prediction_error_bound")
    src = _d("alpha_v").source
    base = _v("base_speed")
    checks = [check_close(f"alpha^{v * 1000:g} (stress per depth, press at {v * 1000:g} mm/s)", a_pub, a, tol,
                          source=src, unit="N/cm^3", basis=PAPER_ERROR,
                          consistency=("alpha^30 = 0.47 N/cm^3 is the medium's zeta: the law is calibrated from it"
                                       if abs(v - base) < 1e-9 else ""))
              for v, a_pub, a in zip(speeds, alpha_pub, alpha)]
    checks.append(check_outcome("alpha^v grows with speed", bool(np.all(np.diff(alpha) > 0)),
                                published=" < ".join(f"{a:g}" for a in alpha_pub),
                                simulated=" < ".join(f"{a:.3g}" for a in alpha), source=src,
                                consistency="the wet law's speed factor rises with speed by definition"))
    checks.append(check_band("press force linear in depth beyond 10 mm (lowest R^2)", r2min, _v("alpha_r2_min"), 1.0,
                             published=f"R^2 {_v('alpha_r2_min')}-0.977", source=_d("alpha_r2_min").cite(),
                             consistency="RFT stress is linear in depth by construction"))
    # horizontal force vs depth at 30 mm/s, wet vs dry (fig. 3b)
    vb = _v("base_speed")
    depths = np.asarray([d for d in _v("depth_series") if d >= _v("linear_depth_min")], float)
    dry = dry_reference()
    hw = np.array([_plate_drag(vb, d, SAND, "wet", quick, variant) for d in depths])
    hd = np.array([_plate_drag(vb, d, dry, "rft", quick, variant) for d in depths])
    ratio = float(np.mean(hw / hd))
    lim = _v("insensitive_change_max")
    checks.append(check_band("wet / dry horizontal force at 30 mm/s (mean over depth)", ratio, 1 / (1 + lim), 1 + lim,
                             published="no significant difference (fig. 3b); the paper's 'not significant' is "
                                       f"<= {lim * 100:g} % (conclusion (1))", source="sec. 2.4, fig. 3b",
                             consistency="the dry reference is the wet law's stress at 25 mm/s, so at 30 mm/s the "
                                         "ratio is 1 + eps_v / 2 = 1.08 by construction"))
    checks.append(check_band("horizontal force linear in depth (R^2)", _r2(depths, hw)[0], _v("alpha_r2_min"), 1.0,
                             published="approximately linear", source="sec. 2.4, fig. 3b",
                             consistency="RFT stress is linear in depth by construction"))
    lines = [Line(r[0] * 1000, r[1] * 1e-4, f"mjrft press {v * 1000:g} mm/s") for v, r in zip(speeds, runs)]
    dz = np.linspace(0, _v("vertical_max_depth"), 7)
    lines += [Line(dz * 1000, a * dz * 100, f"table 3 alpha^{v * 1000:g} x depth", source="table 3")
              for v, a in zip(speeds, alpha_pub)]
    panels = [
        Panel("plate pressed down: stress vs depth", "plate depth (mm)", "vertical stress (N/cm^2)", lines),
        Panel("alpha^v vs press speed", "speed (mm/s)", "stress per depth (N/cm^3)",
              [Line(speeds * 1000, alpha, "mjrft"), Line(speeds * 1000, alpha_pub, "paper", source="table 3")]),
        Panel("horizontal force at 30 mm/s vs depth", "plate centre depth (mm)", "drag (N)",
              [Line(depths * 1000, hw, "mjrft wet"), Line(depths * 1000, hd, "mjrft dry reference")]),
    ]
    length, width, thick = _v("plate_size")
    setup = (f"Plate {length * 1000:g} x {width * 1000:g} x {thick * 1000:g} mm, horizontal (beta 0), pressed "
             f"straight down from the surface to {_v('vertical_max_depth') * 1000:g} mm at "
             f"{_fmt_list(speeds, 1000, 'mm/s')}; alpha = slope of a line through (depth, F_z / plate area) "
             f"beyond {_v('linear_depth_min') * 1000:g} mm, as the paper fits (sec. 3.1). Horizontal: the plate "
             f"face-on dragged at {vb * 1000:g} mm/s with its centre at {_fmt_list(depths, 1000, 'mm')}; medium "
             f"{SAND}, law wet; dry reference with law rft. Elements {_plate_settings(quick)['resolution'] * 1000:g} mm.")
    notes = ("Table 3 gives alpha^v without a unit; mjrft reads them as N/cm^3 and alpha^30 = 0.47 as the medium's "
             "zeta (mjrft.laws.wet), so the alpha^30 check holds by that calibration. The wet law's stress per "
             "depth at speed v is alpha^30 x (1 + 0.16 (v - 30 mm/s) / 10 mm/s): 0.320 and 0.395 N/cm^3 at 10 and "
             "20 mm/s. The 0 mm drag (plate centred on the surface) is left out, as the paper finds the top 10 mm "
             "fluctuating (sec. 3.1).")
    cause = ""
    failing = [c for c in checks if not c.passed]
    if failing:
        a10 = alpha_pub[0]
        cause = (f"alpha^10: mjrft {alpha[0]:.3f} vs table 3's {a10:g} N/cm^3. The law is table 3's own line: "
                 f"alpha^30 x (1 - 2 eps_v) = {alpha_pub[-1]:g} x {1 - 2 * _v('eps_v'):.2f} = "
                 f"{alpha_pub[-1] * (1 - 2 * _v('eps_v')):.3f} N/cm^3 (measured here {alpha[0]:.3f}). Table 3 is not "
                 f"one line: alpha^30 / alpha^10 = {alpha_pub[-1] / a10:.2f}, where its eps_v = {_v('eps_v')} per "
                 f"10 mm/s gives 1 / {1 - 2 * _v('eps_v'):.2f} = {1 / (1 - 2 * _v('eps_v')):.2f}, and it exceeds even the "
                 f"{_v('wet_force_ratio_50_10')} the paper measured over the 5x wider 10-50 mm/s range (sec. 2.4). "
                 "The vertical presses behind alpha^v fall off faster towards 10 mm/s than the horizontal drags behind "
                 "eps_v; one speed factor for all directions (eqs. 6-8) can not meet both, and mjrft keeps eps_v, "
                 "which the paper uses for its leg predictions. The paper itself places its worst prediction errors "
                 "at the lowest speed (sec. 3.1).")
    return CaseResult(name="sgrft_plate_depth", title="plate force vs depth; table 3's alpha^10, alpha^20, alpha^30",
                      paper=CITE, source="sec. 2.4-2.5, figs. 3b and 4b, table 3", setup=setup, checks=checks,
                      panels=panels, cause=cause, notes=notes)


# ------------------------------------------------------------------------------------------------
# legs
# ------------------------------------------------------------------------------------------------
LEGS = (("R", "flat"), ("V", "v_section"), ("T", "triangle_section"))


def _leg_settings(quick):
    return {"resolution": 0.005 if quick else 0.0025, "dtheta": math.radians(1.0 if quick else 0.25)}


def _leg(shape, rpm, sinkage, quick, water=True, variant=None):
    """One rotation of the leg through the sand: axle ``length - sinkage`` above the surface (the tip is
    ``sinkage`` deep when the leg hangs straight down), water 50 mm above the sand (sec. 2.2)."""
    width, length = _v("leg_projection")
    med = get_medium(SAND).with_extra(water_depth=_v("water_above_sand_box") if water else 0.0)
    med, law = wrong_physics(variant, med, "wet")
    span = math.acos((length - sinkage) / length) + math.radians(10.0)  # in the sand, plus 10 deg either side
    omega = rpm * 2 * math.pi / 60
    return rigs.rotating_leg(shape, omega=omega, start=-span, stop=span, axle_height=length - sinkage, chord=length,
                             width=width, thickness=_v("plate_size")[2], medium=med, law=law, **_leg_settings(quick))


def _peak(p):
    """The paper's peak: mean forward force within +-3 deg of the angle of the largest forward force."""
    i = int(np.argmax(p.forward))
    win = np.abs(p.angle - p.angle[i]) <= math.radians(_v("peak_window")) + 1e-12
    return float(np.mean(p.forward[win])), float(math.degrees(p.angle[i]))


def _asymmetry(p):
    """|impulse before - impulse after straight down| / total, of the forward force against angle."""
    a, f = p.angle, np.clip(p.forward, 0.0, None)
    da = np.gradient(a)
    down, up = float(np.sum((f * da)[a < 0])), float(np.sum((f * da)[a > 0]))
    return abs(down - up) / (down + up), down, up


def _slow_setup(quick):
    width, length = _v("leg_projection")
    return (f"Straight legs {width * 1000:g} mm wide (projection {width * 1000:g} x {length * 1000:g} mm), "
            f"{_v('plate_size')[2] * 1000:g} mm plates, hip on the axle; R = flat plate, V = V cross-section "
            "(90 deg, open side leading), T = solid equilateral-triangle cross-section (apex leading); "
            f"medium {SAND}, law wet, water {_v('water_above_sand_box') * 1000:g} mm above the sand (law water on "
            f"the same elements); elements {_leg_settings(quick)['resolution'] * 1000:g} mm, "
            f"{math.degrees(_leg_settings(quick)['dtheta']):g} deg per sample.")


LEG_NOTES = ("The paper draws its legs only in lost figures: the hip on the axle, a 2 mm plate (the thickness of its "
             "plate intruder), the V's 90 deg opening and the T's equilateral section are mjrft's choices, each "
             "keeping the published 25 x 110 mm projection. Sinkage = depth of the tip when the leg hangs "
             "straight down (axle 110 mm - sinkage above the sand).")


@case("sgrft_legs", "R/V/T legs at 2 rpm, 50 mm sinkage: force and torque profiles", CITE,
      variants=("depth_only",))
def legs(quick: bool, variant: str | None = None) -> CaseResult:
    """R, V and T legs at 2 rpm with 50 mm sinkage (sec. 3.2, fig. 8b).

    The paper's curves are lost with fig. 8; what the text states is checked: the force profile is
    asymmetric between the descending and the ascending half (an asymmetry above the 5 % the paper
    counts as no significant change, sec. 2.4), and the 2D SGRFT simulation fits both R and V (mjrft's
    Li RFT uses each element's projection, so R and V must agree within the same 5 %).
    """
    slow = _v("leg_slow")
    profs = {name: _leg(shape, slow["rpm"], slow["sinkage"], quick, variant=variant) for name, shape in LEGS}
    peaks = {n: _peak(p) for n, p in profs.items()}
    asym = {n: _asymmetry(p) for n, p in profs.items()}
    lim = _v("dry_force_change_max")
    rv = peaks["V"][0] / peaks["R"][0]
    checks = [
        check_band(f"{n}-leg forward-force asymmetry, descending vs ascending half", asym[n][0], lim, 1.0,
                   published=f"{_v('slow_asymmetry')} (significant: > {lim * 100:g} %, sec. 2.4)",
                   source=_d("slow_asymmetry").source) for n in ("R", "V")
    ]
    checks.append(check_band("V / R peak thrust (2D SGRFT fits both)", rv, 1 - lim, 1 + lim,
                             published="the SGRFT simulation follows both the R- and the V-leg test; both project "
                                       "to 25 x 110 mm", source="sec. 3.2, fig. 8b",
                             consistency="mjrft's Li RFT acts on each element's projection onto the plane of motion, "
                                         "and both legs project to 25 x 110 mm: no law of that form tells them apart"))
    deg = {n: np.degrees(p.angle) for n, p in profs.items()}
    panels = [
        Panel("forward force (thrust), 2 rpm, 50 mm", "leg angle from straight down (deg)", "F_x (N)",
              [Line(deg[n], p.forward, f"{n}-leg") for n, p in profs.items()]),
        Panel("vertical force", "leg angle from straight down (deg)", "F_z (N)",
              [Line(deg[n], p.support, f"{n}-leg") for n, p in profs.items()]),
        Panel("drive torque", "leg angle from straight down (deg)", "torque (N m)",
              [Line(deg[n], p.torque, f"{n}-leg") for n, p in profs.items()]),
    ]
    width, length = _v("leg_projection")
    omega = slow["rpm"] * 2 * math.pi / 60
    setup = (f"Legs turned at {slow['rpm']:g} rpm ({omega:.4f} rad/s) with {slow['sinkage'] * 1000:g} mm sinkage: the "
             f"buried part moves at {omega * (length - slow['sinkage']) * 1000:.1f}-{omega * length * 1000:.1f} mm/s, "
             "inside the plate tests' 10-50 mm/s. " + _slow_setup(quick))
    summary = "; ".join(f"{n}: peak thrust {peaks[n][0]:.3f} N at {peaks[n][1]:+.1f} deg, max torque "
                        f"{profs[n].torque.max():.4f} N m, asymmetry {asym[n][0] * 100:.1f} %" for n in profs)
    notes = (LEG_NOTES + " Measured: " + summary + f". T / R peak thrust {peaks['T'][0] / peaks['R'][0]:.3f}: the "
             "paper's T-leg test deviates from its 2D simulation through 3D forces that neither SGRFT nor mjrft's "
             "per-element law models (sec. 3.2); the T value here is the 2D law's.")
    return CaseResult(name="sgrft_legs", title="R/V/T legs at 2 rpm, 50 mm sinkage: force and torque profiles",
                      paper=CITE, source="sec. 3.2, fig. 8b", setup=setup, checks=checks, panels=panels, notes=notes)


@case("sgrft_rpm", "R/V/T legs at 30 and 40 rpm, 30 mm sinkage: thrust change", CITE,
      variants=("rate_independent",))
def rpm(quick: bool, variant: str | None = None) -> CaseResult:
    """Peak horizontal thrust of the R, V and T legs at 30 and 40 rpm, 30 mm sinkage (sec. 3.2, fig. 8c).

    The paper predicts +30.33 % with table 3's coefficients and measures +28.27 % (R) and +26.65 % (V).
    mjrft runs the same linear velocity coefficient, so its R- and V-leg changes are compared with the
    prediction within 2 %: the paper does not say how it evaluated its prediction, and evaluating the line
    by hand at one effective radius of the buried part between 95 mm (its middle) and 110 mm (the tip)
    gives +30.05 to +30.46 %, within 1 % of 30.33 % (in the rig, legs 2 to 10 mm thick give +30.29 to
    +30.21 %, and the run without the water layer +30.19 %). The measurements are compared within the paper's own prediction error for each leg,
    |30.33 - measured| / measured (7.3 % for R, 13.8 % for V): mjrft may miss a measurement by as much as
    the paper's model does.
    """
    fast = _v("leg_fast")
    r30, r40 = fast["rpm"]
    sink = fast["sinkage"]
    profs = {(n, r): _leg(shape, r, sink, quick, variant=variant) for n, shape in LEGS for r in (r30, r40)}
    peaks = {k: _peak(p) for k, p in profs.items()}
    change = {n: peaks[(n, r40)][0] / peaks[(n, r30)][0] - 1 for n, _ in LEGS}
    pred = _d("thrust_change_predicted")
    grow = _v("dry_force_change_max")  # "higher": a significant change, more than the paper's 5 % (sec. 2.4)
    checks = [check_outcome("thrust grows from 30 to 40 rpm (R, V, T)", all(c > grow for c in change.values()),
                            published="higher thrust at 40 rpm", source=pred.source,
                            simulated=", ".join(f"{n} {c * 100:+.2f} %" for n, c in change.items()),
                            tolerance=f"each > {grow * 100:g} % (significant, sec. 2.4)"),
              check_close("R-leg thrust change vs SGRFT's prediction", pred, change["R"], 0.02, unit="",
                          qualitative=True),
              check_close("V-leg thrust change vs SGRFT's prediction", pred, change["V"], 0.02, unit="")]
    for n, key in (("R", "thrust_change_measured_r"), ("V", "thrust_change_measured_v")):
        meas = _d(key)
        tol = abs(pred.value - meas.value) / meas.value
        checks.append(check_close(f"{n}-leg thrust change vs measured", meas, change[n], tol + 1e-9, unit="",
                                  basis="SGRFT's own error on this measurement, |30.33 - measured| / measured: the "
                                        "tolerance equals the paper's model error"))
    # the same rig without the water layer: how much of the thrust is the water drag
    if not quick:
        dry_top = {r: _peak(_leg("flat", r, sink, quick, water=False))[0] for r in (r30, r40)}
        water_share = {r: peaks[("R", r)][0] / dry_top[r] - 1 for r in (r30, r40)}
    else:
        water_share = {}
    x = np.arange(3)
    panels = [
        Panel(f"forward force, {n}-leg, {sink * 1000:g} mm", "leg angle from straight down (deg)", "F_x (N)",
              [Line(np.degrees(profs[(n, r)].angle), profs[(n, r)].forward, f"{r:g} rpm") for r in (r30, r40)])
        for n, _ in LEGS
    ]
    panels.append(Panel("thrust change 30 -> 40 rpm (0 = R, 1 = V, 2 = T)", "leg", "change (%)",
                        [Line(x, [change[n] * 100 for n, _ in LEGS], "mjrft"),
                         Line(x, [pred.value * 100] * 3, "SGRFT prediction", source="sec. 3.2"),
                         Line(x[:2], [_v("thrust_change_measured_r") * 100, _v("thrust_change_measured_v") * 100],
                              "measured", source="sec. 3.2")]))
    width, length = _v("leg_projection")
    w30, w40 = (r * 2 * math.pi / 60 for r in (r30, r40))
    setup = (f"Legs turned at {r30:g} and {r40:g} rpm with {sink * 1000:g} mm sinkage; the buried part moves at "
             f"{w30 * (length - sink):.3f}-{w30 * length:.3f} m/s ({r30:g} rpm) and {w40 * (length - sink):.3f}-"
             f"{w40 * length:.3f} m/s ({r40:g} rpm), 5-9x the plate tests' top speed. Peak = mean forward force within "
             f"{_v('peak_window'):g} deg of the largest (sec. 3.2). " + _slow_setup(quick))
    summary = "; ".join(f"{n}: {peaks[(n, r30)][0]:.3f} -> {peaks[(n, r40)][0]:.3f} N ({change[n] * 100:+.2f} %)"
                        for n, _ in LEGS)
    notes = (LEG_NOTES + " Measured peaks: " + summary + ". The law's speed factor follows the paper's line at these "
             "speeds (mjrft.laws.wet); a factor held at its 50 mm/s value would leave the sand's force unchanged "
             "here (+0 %), every buried element being faster than 50 mm/s at both speeds.")
    if water_share:
        notes += (" Water drag on the leg's part between the sand and the water surface adds "
                  + ", ".join(f"{water_share[r] * 100:.2f} % at {r:g} rpm" for r in (r30, r40))
                  + " to the R-leg's peak (same run without the water layer).")
    return CaseResult(name="sgrft_rpm", title="R/V/T legs at 30 and 40 rpm, 30 mm sinkage: thrust change", paper=CITE,
                      source="sec. 3.2, fig. 8c", setup=setup, checks=checks, panels=panels, notes=notes)

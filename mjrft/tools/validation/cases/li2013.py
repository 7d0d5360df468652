"""Li, Zhang & Goldman 2013 (Science, supplementary materials): plate intrusion, the scaling routine and the leg rig.

Three cases, each rerunning a published experiment under the paper's setup (published numbers:
``mjrft/tools/validation/data/li2013.json``):

``li2013_plate``
    Li's plate (3.81 x 2.54 x 0.64 cm) pushed straight down at 1 cm/s until its bottom face is 7.62 cm
    deep, in each of the five media, under the medium's Fourier fit (law ``rft``) and under the
    depth-only law; the stress per depth is the slope of a zero-intercept line through vertical stress (lift / plate area) against
    the depth of the plate's bottom face over the whole (linear) intrusion, as the paper does (fig.
    S11). Compared with table S3: the fit's alpha_z^fit(0, pi/2), the measured alpha_z(0, pi/2)
    (the depth-only law is built from it, eqs. S3-S7) and the ratio chi between them (eq. S13).
    Then fig. S1's statement on loosely packed poppy seeds: the plate at attack angles beta and
    downward intrusion angles gamma, depth-only against the fit.

    Tolerances. Fit vs table S3: the printed precision, half a unit of the table's last digit
    (0.005 N/cm^3) plus the rounding of the five coefficients that add up at (0, pi/2) (5 x 0.0005),
    relative to each value (2-4 %). Depth-only vs measured: 1 %, the rig's numerical error (the law
    is exact by construction; the first yield displacement of travel and the sampling are all that
    differ). chi: the paper's mean +- 2 s.d. (1.26 +- 0.28). The fit and chi checks run the plate through the
    MuJoCo-coupled rig and are rejected when the medium's stresses are doubled or halved; "over-predicts"
    (fig. S1) is read as strictly above, which the fit's orientation dependence gives and an
    orientation-blind law (the depth-only law in place of the fit) does not.

``li2013_scaling``
    The scaling routine (fig. S9): a plate test in each medium that reproduces the measured plate
    stress of table S3 (the rig under the depth-only law, whose plate-pushed-down stress is that
    measurement) is given to :func:`mjrft.calibrate` (zero-intercept slope / chi, chi = 1.26) and
    the recovered zeta is compared with table S2. Tolerance: 2 s.d. of chi relative to its mean
    (2 x 0.14 / 1.26 = 22 %), the accuracy the paper states for inferring the fit from one plate
    measurement (eq. S13-S14). Then the scaled generic profile zeta alpha^generic (eq. S16) against
    each medium's own fit over the whole (beta, gamma) plane (a thin plate through
    :func:`mjrft.laws.rft`): the RMS difference of alpha_z and alpha_x relative to the fit's
    alpha_z(0, pi/2), with the same tolerance (the paper quotes no other accuracy for eq. S11; it
    calls the approximation good, "a small loss in accuracy").
    Both are consistency checks: each compares two of the paper's own tables through arithmetic that
    cannot come out otherwise (the plate test is the depth-only law built from table S3).

``li2013_leg_rig``
    Li's leg rotation rig (legs 7.62 x 2.54 x 0.64 cm, axle 2 cm above the surface, 0.2 rad/s over
    -3pi/4 .. 3pi/4; :func:`mjrft.tools.rigs.rotating_leg`, shapes ``"c"`` (convex side leading, Li's
    C-leg), ``"flat"``, ``"reversed_c"``) in each medium under (a) the medium's fit, (b) the scaled
    generic profile and (c) the depth-only law. The measured curves of figs. S2, S5 and S8 are not in
    the text, so the medium's fit (a) stands in for the measurement (the paper: RFT "predicted" the
    measured forces, fig. S5). Checked: depth-only over-predicts peak lift everywhere and by how much
    at most (text: "up to 1400 %", tolerance 50 %: only the size can be compared when the reference
    is the fit, not the measured curve); depth-only gives C and reversed C "similar" peaks (read as
    a ratio within 20 %, :data:`mjrft.tools.validation.case.SIMILAR`); the C-leg has more lift than the reversed C-leg; the generic profile x zeta
    reproduces the C and flat legs and is worst on the reversed C-leg (fig. S8, eq. S12).
"""

from __future__ import annotations

import math

import numpy as np

from mjrft import laws
from ... import rigs
from mjrft.media import CHI, MEDIA, N_CM3, calibrate, generic
from ..case import (SIMILAR, Check, CaseResult, Line, Panel, case, check_band, check_close, check_outcome, published,
                    similar, wrong_physics)

PAPER = "li2013"
CITE = "Li, Zhang & Goldman, Science 2013 (suppl.)"
SHAPES = ("c", "flat", "reversed_c")
SHAPE_LABEL = {"c": "C-leg", "flat": "flat leg", "reversed_c": "reversed C-leg"}
LEG_LAWS = ("fit", "generic", "depth_only")
LAW_LABEL = {"fit": "medium's fit (rft)", "generic": "generic x zeta (rft)", "depth_only": "depth-only"}


def _media() -> list[str]:
    return list(published(PAPER, "media").value)


def _row(key: str) -> dict[str, float]:
    """A per-medium row of the published data, by catalogue name."""
    return dict(zip(_media(), published(PAPER, key).value))


def _settings(quick: bool) -> dict:
    """Element size (m), plate travel per sample (m) and leg angle per sample (rad)."""
    if quick:
        return {"resolution": 0.005, "step": 2e-3, "dtheta": 0.02}
    return {"resolution": 0.0025, "step": 5e-4, "dtheta": 0.005}


# ------------------------------------------------------------------------------------------------
# plate
# ------------------------------------------------------------------------------------------------
def plate_test(medium, law: str, quick: bool, beta: float = 0.0, gamma: float = math.pi / 2, thickness_scale=1.0,
               variant: str | None = None):
    """Li's plate at (beta, gamma) into ``medium`` at 1 cm/s until its lowest point is 7.62 cm deep (Li's deepest
    depth): (depth of the lowest point m, stress Pa, slope N/m^3).

    ``thickness_scale`` scales the 0.64 cm thickness (a diagnostic of the side faces' share); ``variant``: a
    wrong-physics variant of the medium and law (:func:`mjrft.tools.validation.case.wrong_physics`).

    Depth is that of the plate's lowest point (for the horizontal plate its bottom face: Li's |z| = 0
    when the plate touches the surface); stress = lift / (3.81 x 2.54 cm^2); the slope is the
    zero-intercept least-squares fit over the samples below the surface (the whole path is linear).
    """
    s = _settings(quick)
    medium, law = wrong_physics(variant, medium, law)
    size = published(PAPER, "plate_size").value
    depth_max = published(PAPER, "plate_depths").value[-1] / 100  # deepest point of the plate
    length, thickness = size[0] / 100, size[2] / 100 * thickness_scale
    half_z = 0.5 * (length * abs(math.sin(beta)) + thickness * abs(math.cos(beta)))
    p = rigs.plate_intrusion(beta=beta, gamma=gamma, speed=published(PAPER, "plate_speed").value / 100,
                             depth=depth_max - half_z, length=length, width=size[1] / 100, thickness=thickness,
                             medium=medium, law=law, resolution=s["resolution"], step=s["step"])
    d = p.depth + half_z
    stress = p.lift / p.settings["area"]
    k = d > 0
    slope = float(np.dot(d[k], stress[k]) / np.dot(d[k], d[k]))
    return d[k], stress[k], slope


def _precision(value: float) -> float:
    """Relative printed precision of a table S3 fit value (N/cm^3): 0.005 + 5 x 0.0005 over the value."""
    return (0.005 + 5 * 0.0005) / value


@case("li2013_plate", "Plate intrusion: stress per depth of a horizontal plate pushed down (table S3, fig. S1)", CITE,
      variants=("x2", "x0.5", "depth_only"))
def run_plate(quick: bool, variant: str | None = None) -> CaseResult:
    media = _media()
    fit_pub, meas_pub = _row("alpha_z_fit"), _row("alpha_z_measured")
    chi, chi_sd = published(PAPER, "chi").value, published(PAPER, "chi_sd").value
    src3 = published(PAPER, "alpha_z_fit").source
    srcm = published(PAPER, "alpha_z_measured").source
    checks, curves, slopes, thin = [], [], {}, {}
    for name in media:
        d_fit, s_fit, k_fit = plate_test(name, "rft", quick, variant=variant)
        d_do, s_do, k_do = plate_test(name, "depth_only", quick, variant=variant)
        slopes[name] = (k_fit, k_do)
        checks.append(check_close(f"{name}: alpha_z^fit(0, pi/2), rig under the fit", fit_pub[name], k_fit / N_CM3,
                                  _precision(fit_pub[name]), source=src3, unit="N/cm^3"))
        checks.append(check_band(f"{name}: measured / fit alpha_z(0, pi/2) = chi", meas_pub[name] * N_CM3 / k_fit,
                                 chi - 2 * chi_sd, chi + 2 * chi_sd, published=f"chi = {chi} +- {chi_sd} (s.d.)",
                                 source=published(PAPER, "chi").source + " and table S3", reference=chi,
                                 basis="mean +- 2 s.d. of the paper's chi over its media"))
        checks.append(check_close(f"{name}: alpha_z(0, pi/2), rig under the depth-only law", meas_pub[name],
                                  k_do / N_CM3, 0.01, source=srcm, unit="N/cm^3", qualitative=True,
                                  basis="the rig's numerical error",
                                  consistency="the depth-only law is built from this measured value (eqs. S3-S7)"))
        curves.append((name, d_fit, s_fit, d_do, s_do))
        thin[name] = plate_test(name, "rft", quick, thickness_scale=0.1, variant=variant)[2]

    # fig. S1: depth-only vs the fit on loosely packed poppy seeds, plates at beta moving down at gamma
    betas = [-math.pi / 3, 0.0, math.pi / 3] if quick else [-math.pi / 3, -math.pi / 6, 0.0, math.pi / 6, math.pi / 3]
    gammas = [math.pi / 4, math.pi / 2] if quick else [math.pi / 6, math.pi / 3, math.pi / 2, 2 * math.pi / 3]
    over, grid = [], []
    for g in gammas:
        for b in betas:
            k_fit = plate_test("poppy_lp", "rft", quick, b, g, variant=variant)[2]
            k_do = plate_test("poppy_lp", "depth_only", quick, b, g, variant=variant)[2]
            over.append(k_do - k_fit)
            grid.append((b, g, k_fit, k_do))
    worst = min(range(len(over)), key=lambda i: over[i])
    b, g, kf, kd = grid[worst]
    checks.append(check_outcome(
        "poppy_lp: depth-only alpha_z > fit at every tested downward (beta, gamma)", min(over) > 0.0,
        published=published(PAPER, "depth_only_plate_overprediction").value,
        simulated=(f"{len(over)} plates (beta {', '.join(f'{math.degrees(x):g}' for x in betas)} deg; gamma "
                   f"{', '.join(f'{math.degrees(x):g}' for x in gammas)} deg): smallest excess {min(over) / N_CM3:.3f} "
                   f"N/cm^3 at ({math.degrees(b):g}, {math.degrees(g):g}) deg ({kd / N_CM3:.3f} vs {kf / N_CM3:.3f})"),
        source=published(PAPER, "depth_only_plate_overprediction").source))

    failed = [c.name.split(":")[0] for c in checks if not c.passed and "rig under the fit" in c.name]
    cause = ""
    if failed:
        size = published(PAPER, "plate_size").value
        share = 0.5 * 2 * (size[0] + size[1]) * size[2] / (size[0] * size[1])  # half-weighted sides / face area
        parts = []
        for n in failed:
            side = float(MEDIA[n].alpha(math.pi / 2, math.pi / 2)[0])
            parts.append(f"{n}: {slopes[n][0] / N_CM3:.4f} with the 0.64 cm plate, {thin[n] / N_CM3:.4f} with a "
                         f"0.064 cm one (fit {MEDIA[n].alpha_z_down / N_CM3:.4f}, table {fit_pub[n]}); predicted side "
                         f"share alpha_z(pi/2, pi/2) x {share:.2f} = {side * share / N_CM3:.4f}")
        cause = ("The plate's four 0.64 cm side faces. A face moving along its own plane counts half (mjrft's "
                 "leading-surface rule) and the fit gives it alpha_z(pi/2, pi/2) (an edge-on plate pushed down), "
                 "so the simulated plate adds that stress on half its side area (0.84 x the face area) to the "
                 "face's: large for the glass media, whose fit has alpha_z(pi/2, pi/2) = 0.040-0.049 N/cm^3 "
                 "(poppy LP 0.014). Li's alpha is force / face area of the real plate, sides included, so the "
                 "thick plate double-counts them. Measured (N/cm^3): " + "; ".join(parts)
                 + ". " + ("A 10x thinner plate agrees with the table within its printed precision: the law is right, "
                           "the sides are the difference." if all(abs(thin[n] / N_CM3 - fit_pub[n]) <= _precision(fit_pub[n])
                                                                   * fit_pub[n] for n in failed)
                           else "A 10x thinner plate still differs from the table; the sides are not all of it."))

    x = np.arange(len(media), dtype=float)
    panels = [
        Panel("poppy LP: sigma_z vs depth, plate pushed down", "depth of bottom face (cm)",
              "sigma_z (N/cm^2)", [
                  Line(curves[0][1] * 100, curves[0][2] / 1e4, "mjrft, medium's fit"),
                  Line(curves[0][3] * 100, curves[0][4] / 1e4, "mjrft, depth-only"),
                  Line([0.0, 7.62], [0.0, 7.62 * meas_pub["poppy_lp"]], "paper: measured slope", source="table S3"),
                  Line([0.0, 7.62], [0.0, 7.62 * fit_pub["poppy_lp"]], "paper: fit slope", source="table S3")]),
        Panel("alpha_z(0, pi/2) per medium",
              "medium (0 poppy LP, 1 poppy CP, 2/3 0.3 mm glass LP/CP, 4 3 mm glass)", "alpha_z (N/cm^3)", [
                  Line(x, [slopes[n][0] / N_CM3 for n in media], "mjrft, medium's fit"),
                  Line(x, [slopes[n][1] / N_CM3 for n in media], "mjrft, depth-only"),
                  Line(x, [fit_pub[n] for n in media], "paper: fit", source="table S3"),
                  Line(x, [meas_pub[n] for n in media], "paper: measured", source="table S3")]),
        Panel("poppy LP, plates moving down (fig. S1)", "beta (deg)",
              "alpha_z (N/cm^3)", [
                  Line([math.degrees(bb) for bb, gg, _, _ in grid if gg == gm],
                       [kk / N_CM3 for bb, gg, kk, _ in grid if gg == gm], f"fit, gamma {math.degrees(gm):g} deg")
                  for gm in gammas] + [
                  Line([math.degrees(bb) for bb, gg, _, _ in grid if gg == gm],
                       [kk / N_CM3 for bb, gg, _, kk in grid if gg == gm], f"depth-only, gamma {math.degrees(gm):g} deg")
                  for gm in gammas]),
    ]
    s = _settings(quick)
    return CaseResult(
        name="li2013_plate", title="Plate intrusion: stress per depth of a horizontal plate pushed down", paper=CITE,
        source="table S3; section 1 and fig. S1; Materials and Methods (plate intrusion)",
        setup=(f"Plate 3.81 x 2.54 x 0.64 cm (3.81 cm in the plane of motion), beta = 0, pushed straight down "
               f"(gamma = pi/2) at 1 cm/s until its bottom face is 7.62 cm deep (Li's deepest depth), in poppy "
               f"seeds LP/CP, 0.3 mm glass LP/CP and 3 mm glass CP; laws rft (medium's Fourier fit, table S2) and depth_only (eqs. S3-S7 "
               f"with the measured alpha_z(0, pi/2) of table S3); elements {s['resolution'] * 1000:g} mm, one "
               f"sample per {s['step'] * 1000:g} mm of travel. Fig. S1 check: poppy LP, the same plate at the "
               f"listed (beta, gamma) until its lowest point is 7.62 cm deep."),
        checks=checks, panels=panels, cause=cause,
        notes=("Depth is that of the plate's lowest point (Li's |z| = 0 when the plate touches the surface). The "
               "fit rig value includes the plate's four 0.64 cm side faces, which move along their own plane "
               "and count half (the leading-surface rule) with the fit's alpha_z(pi/2, pi/2): +2 % on poppy LP; "
               "the depth-only law gives them no vertical force. Fig. S1 is compared with the medium's fit as "
               "the stand-in for the measured alpha_z (Fig. 2 C-D and data table S5 are not in the text), and "
               "only for downward motion: for horizontal motion eq. S7's sgn(z') is 0."),
    )


# ------------------------------------------------------------------------------------------------
# scaling routine
# ------------------------------------------------------------------------------------------------
def _plane(medium, n_beta: int, n_gamma: int):
    """(alpha_z, alpha_x) in N/m^3 of a thin plate (two faces) over beta x gamma, through mjrft.laws.rft."""
    betas = np.linspace(-math.pi / 2, math.pi / 2, n_beta)
    gammas = np.linspace(-math.pi, math.pi, n_gamma)
    B, G = np.meshgrid(betas, gammas, indexing="ij")
    b, g = B.ravel(), G.ravel()
    n = np.column_stack([np.sin(b), np.zeros_like(b), -np.cos(b)])
    v = np.column_stack([np.cos(g), np.zeros_like(g), -np.sin(g)])
    f = laws.rft(np.ones(2 * b.size), np.concatenate([n, -n]), np.concatenate([v, v]), np.ones(2 * b.size), medium)
    f = f[: b.size] + f[b.size:]
    return B, G, f[:, 2].reshape(B.shape), -f[:, 0].reshape(B.shape)


@case("li2013_scaling", "Scaling routine: one plate test -> zeta -> generic profile (eqs. S13-S16, fig. S9)", CITE)
def run_scaling(quick: bool) -> CaseResult:
    media = _media()
    zeta_pub = _row("zeta")
    chi, chi_sd = published(PAPER, "chi").value, published(PAPER, "chi_sd").value
    tol = 2 * chi_sd / chi
    checks, zcal, rms_z, rms_x = [], {}, {}, {}
    nb, ng = (13, 25) if quick else (37, 73)
    for name in media:
        d, stress, _ = plate_test(name, "depth_only", quick)  # reproduces the measured plate test (table S3)
        cal = calibrate(d, stress, name=f"{name}_calibrated", chi=chi)
        zcal[name] = cal.zeta
        checks.append(check_close(f"{name}: zeta from one simulated plate test (calibrate)", zeta_pub[name],
                                  cal.zeta / N_CM3, tol, source=published(PAPER, "zeta").source, unit="N/cm^3",
                                  qualitative=True, basis="2 s.d. of chi: the paper's stated accuracy of the routine",
                                  consistency="the simulated plate test is the depth-only law built from table S3's "
                                              "measured value, so the recovered zeta is table S3 / 1.26: two "
                                              "published tables compared through calibrate's arithmetic"))
        med = MEDIA[name]
        _, _, az_fit, ax_fit = _plane(med, nb, ng)
        _, _, az_gen, ax_gen = _plane(generic.scaled(zeta_pub[name] * N_CM3), nb, ng)
        ref = med.alpha_z_down
        rms_z[name] = float(np.sqrt(np.mean((az_gen - az_fit) ** 2)) / ref)
        rms_x[name] = float(np.sqrt(np.mean((ax_gen - ax_fit) ** 2)) / ref)
        for comp, val in (("alpha_z", rms_z[name]), ("alpha_x", rms_x[name])):
            checks.append(check_band(f"{name}: RMS(zeta alpha_{comp[-1]}^generic - {comp}^fit) / alpha_z^fit(0, pi/2)",
                                     val, 0.0, tol, published=f"alpha ~ zeta alpha^generic (eq. S11); accuracy of the "
                                     f"routine chi s.d. {chi_sd}/{chi}", source="Li 2013 suppl., eqs. S11, S13",
                                     qualitative=False, basis="2 s.d. of chi: the paper's stated accuracy of its "
                                                              "scaling routine, i.e. its own model error",
                                     consistency="both profiles are table S2's (the medium's fit, and M0 x the "
                                                 "medium's zeta) evaluated through eq. S8: the RMS is a property of "
                                                 "the paper's numbers, which mjrft's media are built from"))

    x = np.arange(len(media), dtype=float)
    B, G, az_fit, ax_fit = _plane(MEDIA["poppy_lp"], nb, ng)
    _, _, az_gen, ax_gen = _plane(generic.scaled(zeta_pub["poppy_lp"] * N_CM3), nb, ng)
    jg = int(np.argmin(np.abs(G[0] - math.pi / 2)))
    jh = int(np.argmin(np.abs(G[0])))
    deg = np.degrees(B[:, 0])
    panels = [
        Panel("zeta per medium", "medium (0 poppy LP, 1 poppy CP, 2/3 0.3 mm glass LP/CP, 4 3 mm glass)",
              "zeta (N/cm^3)", [Line(x, [zcal[n] / N_CM3 for n in media], "mjrft: calibrate(plate test)"),
                                Line(x, [zeta_pub[n] for n in media], "paper", source="table S2")]),
        Panel("poppy LP: alpha_z, gamma = pi/2", "beta (deg)", "alpha_z (N/cm^3)",
              [Line(deg, az_fit[:, jg] / N_CM3, "medium's fit"), Line(deg, az_gen[:, jg] / N_CM3, "generic x zeta")]),
        Panel("poppy LP: alpha_x, gamma = 0", "beta (deg)", "alpha_x (N/cm^3)",
              [Line(deg, ax_fit[:, jh] / N_CM3, "medium's fit"), Line(deg, ax_gen[:, jh] / N_CM3, "generic x zeta")]),
        Panel("generic x zeta vs fit: RMS over (beta, gamma)", "medium (order of table S2)", "RMS / alpha_z^fit(0, pi/2)",
              [Line(x, [rms_z[n] for n in media], "alpha_z"), Line(x, [rms_x[n] for n in media], "alpha_x")]),
    ]
    return CaseResult(
        name="li2013_scaling", title="Scaling routine: one plate test -> zeta -> generic profile", paper=CITE,
        source="section 3: eqs. S10-S16, tables S2-S3, fig. S9",
        setup=(f"Per medium, the plate test of li2013_plate under the depth-only law (its plate pushed down feels "
               f"the measured alpha_z(0, pi/2) of table S3, i.e. the test the routine asks for) is fitted by "
               f"mjrft.calibrate (zero-intercept slope / chi, chi = {CHI}). Stress profiles: a thin plate through "
               f"mjrft.laws.rft on a {nb} x {ng} grid of beta in [-pi/2, pi/2], gamma in [-pi, pi], generic x zeta "
               f"(table S2 zeta) vs the medium's own fit."),
        checks=checks, panels=panels,
        notes=("The recovered zeta differs from table S2 by the medium's own chi_i / 1.26 - 1 (table S3: -17 % to "
               "+9 %) times zeta_i / alpha_z^fit_i: the routine's error is the spread of chi, which the tolerance "
               "(2 s.d.) covers. The RMS is over the whole plane with equal weight per grid point."),
    )


# ------------------------------------------------------------------------------------------------
# leg rig
# ------------------------------------------------------------------------------------------------
def leg_runs(quick: bool, media=None) -> dict:
    """{(medium, shape, law): LegProfile} for Li's rig; law in LEG_LAWS."""
    s = _settings(quick)
    size = published(PAPER, "leg_size").value
    sweep = published(PAPER, "leg_sweep").value
    kw = dict(omega=published(PAPER, "leg_omega").value, start=sweep[0], stop=sweep[1], dtheta=s["dtheta"],
              axle_height=published(PAPER, "leg_hip_height").value / 100, resolution=s["resolution"],
              chord=size[0] / 100, width=size[1] / 100, thickness=size[2] / 100)
    out = {}
    for name in media or _media():
        gen = generic.scaled(MEDIA[name].zeta, name=f"generic*{name}")
        for shape in SHAPES:
            out[name, shape, "fit"] = rigs.rotating_leg(shape, medium=name, law="rft", **kw)
            out[name, shape, "generic"] = rigs.rotating_leg(shape, medium=gen, law="rft", **kw)
            out[name, shape, "depth_only"] = rigs.rotating_leg(shape, medium=name, law="depth_only", **kw)
    return out


def similar_peaks_check(comp: str, ratios, fit_ratios=()) -> Check:
    """Fig. S2: the depth-only models "erroneously predicted similar peak F_z,x for the c-leg and reversed c-leg".
    "Similar" is read as mjrft's documented band (:data:`~mjrft.tools.validation.case.SIMILAR`: a ratio within
    [1/1.2, 1.2], Li's own "less than 20 %" for a negligible change): every medium's depth-only C / reversed-C
    peak ratio must lie in it. ``fit_ratios`` (the fit's ratios) are printed for comparison."""
    lo, hi = min(ratios), max(ratios)
    worst = max(ratios, key=lambda r: abs(math.log(r)))
    fit = f"; fit {min(fit_ratios):.2f}-{max(fit_ratios):.2f}" if len(fit_ratios) else ""
    return Check(
        name=f"peak {comp} C / reversed C under the depth-only law: similar (every medium)",
        published=published(PAPER, "depth_only_c_vs_reversed").value,
        simulated=f"depth-only {lo:.2f}-{hi:.2f}{fit}", metric=f"ratio furthest from 1: {worst:.3g}",
        tolerance=(f"[{1 / (1 + SIMILAR):.3g}, {1 + SIMILAR:g}]: 'similar' read as within {100 * SIMILAR:g} % (Li's "
                   "own 'less than 20 %' for a negligible force change, suppl. Materials and Methods)"),
        passed=similar(worst), source=published(PAPER, "depth_only_c_vs_reversed").source, qualitative=True,
        value=float(worst), reference=1.0)


def _rms_rel(a, b) -> float:
    """RMS difference of the (F_z, F_x) curves of profile a from b, relative to b's peak |F|."""
    da = np.concatenate([a.support - b.support, a.forward - b.forward])
    peak = max(np.max(np.abs(b.support)), np.max(np.abs(b.forward)))
    return float(np.sqrt(np.mean(da ** 2)) / peak)


@case("li2013_leg_rig", "Leg rotation rig: fit, generic x zeta and depth-only on C, flat and reversed C legs "
      "(figs. S2, S5, S8)", CITE)
def run_leg(quick: bool) -> CaseResult:
    media = _media()
    R = leg_runs(quick, media)
    checks = []
    peak = {k: (float(p.support.max()), float(p.forward.max())) for k, p in R.items()}

    # fig. S2: depth-only over-predicts peak lift (up to 1400 %)
    over = {(n, s): 100 * (peak[n, s, "depth_only"][0] / peak[n, s, "fit"][0] - 1) for n in media for s in SHAPES}
    lo_key = min(over, key=over.get)
    hi_key = max(over, key=over.get)
    src2 = published(PAPER, "depth_only_overprediction_max").source
    checks.append(check_outcome(
        "depth-only over-predicts peak F_z on every leg in every medium", over[lo_key] > 0,
        published="depth-only models significantly over-predict peak F_z", source=src2,
        simulated=f"over-prediction {over[lo_key]:.0f} % ({lo_key[0]}, {SHAPE_LABEL[lo_key[1]]}) to "
                  f"{over[hi_key]:.0f} % ({hi_key[0]}, {SHAPE_LABEL[hi_key[1]]})"))
    checks.append(check_close(f"largest depth-only over-prediction of peak F_z ({hi_key[0]}, {SHAPE_LABEL[hi_key[1]]})",
                              published(PAPER, "depth_only_overprediction_max"), over[hi_key], 0.5))

    # fig. S2: depth-only gives C and reversed C similar peaks (RFT different ones: the C-leg check below)
    for comp, i in (("F_z", 0), ("F_x", 1)):
        r_do = [peak[n, "c", "depth_only"][i] / peak[n, "reversed_c", "depth_only"][i] for n in media]
        r_fit = [peak[n, "c", "fit"][i] / peak[n, "reversed_c", "fit"][i] for n in media]
        checks.append(similar_peaks_check(comp, r_do, r_fit))
    lift_c = [peak[n, "c", "fit"][0] / peak[n, "reversed_c", "fit"][0] for n in media]
    checks.append(check_outcome(
        "C-leg peak F_z > reversed C-leg peak F_z (medium's fit, every medium)", min(lift_c) > 1.0,
        published=published(PAPER, "c_leg_more_lift").value, source=published(PAPER, "c_leg_more_lift").source,
        simulated=f"ratio {min(lift_c):.2f}-{max(lift_c):.2f}"))

    # fig. S8 / eq. S12: generic x zeta captures C and flat; worse for reversed C
    src8 = published(PAPER, "generic_leg_forces").source
    err = {(n, s): _rms_rel(R[n, s, "generic"], R[n, s, "fit"]) for n in media for s in SHAPES}
    mean_err = {s: float(np.mean([err[n, s] for n in media])) for s in SHAPES}
    worst_rev = mean_err["reversed_c"] > max(mean_err["c"], mean_err["flat"])
    checks.append(check_outcome(
        "generic x zeta: mean RMS error largest on the reversed C-leg", worst_rev,
        published=published(PAPER, "generic_leg_forces").value, source=src8,
        simulated=", ".join(f"{SHAPE_LABEL[s]} {100 * mean_err[s]:.1f} %" for s in SHAPES)
        + " (RMS of F_z and F_x vs the medium's fit, / its peak |F|, mean over media)"))
    over_rev = [100 * (peak[n, "reversed_c", "generic"][1] / peak[n, "reversed_c", "fit"][1] - 1) for n in media]
    checks.append(check_outcome(
        "generic x zeta over-estimates the reversed C-leg's peak thrust (every medium)", min(over_rev) > 0,
        published="stresses significantly over-estimated for the reversed C-leg's deep elements", source=src8,
        simulated=", ".join(f"{n} {v:+.0f} %" for n, v in zip(media, over_rev)), qualitative=False))

    causes = []
    if not checks[1].passed:
        n, sh = hi_key
        need = peak[n, sh, "depth_only"][0] / (1 + published(PAPER, "depth_only_overprediction_max").value / 100)
        causes.append(
            f"Largest depth-only over-prediction {over[hi_key]:.0f} % against 1400 %: the published percentage is "
            f"against the measured curves of fig. S2 (not in the text); mjrft can only compare with the medium's "
            f"fit. In {n} the depth-only peak lift of the {SHAPE_LABEL[sh]} is {peak[n, sh, 'depth_only'][0]:.2f} N and "
            f"the fit's {peak[n, sh, 'fit'][0]:.2f} N; 1400 % would need a measured peak of {need:.2f} N, "
            f"{100 * need / peak[n, sh, 'fit'][0]:.0f} % of the fit's. The paper states the fit-shaped generic "
            f"profile over-estimates the reversed C-leg's deep elements (fig. S8), so the measured peak lies below "
            f"the fit's, but by how much is only in the lost figure. Over-prediction against the fit, per leg "
            f"(mean over media): " + ", ".join(
                f"{SHAPE_LABEL[s]} {np.mean([over[m, s] for m in media]):.0f} %" for s in SHAPES) + ".")
    sim_fz = checks[2]
    if not sim_fz.passed:
        r_do = {n: peak[n, "c", "depth_only"][0] / peak[n, "reversed_c", "depth_only"][0] for n in media}
        causes.append(
            "Depth-only C vs reversed C: mjrft's depth-only peak lift of the C-leg is "
            + ", ".join(f"{n} {r:.2f}" for n, r in r_do.items()) + " x the reversed C-leg's (peak thrust the same "
            "within 1 %), outside the 20 % read as 'similar'. Eq. S7's vertical stress alpha_z(0, sgn(z') pi/2) "
            "|cos beta| depends on whether an element moves down or up, which differs between the two mirrored arcs; "
            "which of that, mjrft's leading-surface rule or the leg mesh's faces makes the 1.5x was not isolated, and "
            "fig. S2's depth-only curves, which Li calls similar, are lost with the figure.")
    if not checks[-1].passed:
        ratio = {n: generic.scaled(MEDIA[n].zeta).alpha(math.pi / 2, 0.0)[1] / MEDIA[n].alpha(math.pi / 2, 0.0)[1]
                 for n in media}
        causes.append(
            "Generic x zeta vs the reversed C-leg's peak thrust: mjrft compares with the medium's fit, not the "
            "measurement, and the error follows the generic profile's horizontal drag relative to the fit's, "
            "alpha_x(pi/2, 0) generic x zeta / fit = " + ", ".join(f"{n} {ratio[n]:.2f}" for n in media)
            + " (thrust error " + ", ".join(f"{v:+.0f} %" for v in over_rev) + "): where the fit drags harder "
            "than generic x zeta (0.3 mm glass LP, 3 mm glass) the generic profile under-estimates. The paper's "
            "over-estimate is against measured stresses of deep elements, which the two smooth fits share.")

    panels = []
    for s in SHAPES:
        lines = []
        for law in LEG_LAWS:
            p = R["poppy_lp", s, law]
            lines.append(Line(np.degrees(p.angle), p.support, f"F_z {LAW_LABEL[law]}"))
            lines.append(Line(np.degrees(p.angle), p.forward, f"F_x {LAW_LABEL[law]}"))
        panels.append(Panel(f"{SHAPE_LABEL[s]}, loosely packed poppy seeds", "leg angle theta (deg)", "force (N)", lines))
    x = np.arange(len(media), dtype=float)
    panels.append(Panel("depth-only peak F_z over-prediction vs the fit", "medium (order of table S3)",
                        "over-prediction (%)",
                        [Line(x, [over[n, s] for n in media], SHAPE_LABEL[s]) for s in SHAPES]))
    rev = R["poppy_lp", "reversed_c", "fit"]
    s = _settings(quick)
    return CaseResult(
        name="li2013_leg_rig", title="Leg rotation rig: fit, generic x zeta and depth-only", paper=CITE,
        source="section 1 (fig. S2), section 2 (fig. S5), section 3 (fig. S8, eq. S12), section 5 (fig. S14)",
        setup=(f"Legs 7.62 cm hip to tip, 2.54 cm wide, 0.64 cm thick (flat bar; C and reversed C semicircular "
               f"arcs, one closed mesh), axle 2 cm above the surface, turning at 0.2 rad/s from -3pi/4 to 3pi/4, "
               f"in the five media, each under the medium's Fourier fit (rft), the generic profile x the medium's "
               f"zeta (rft), and the depth-only law; elements {s['resolution'] * 1000:g} mm, one sample per "
               f"{s['dtheta']:g} rad. F_z = lift, F_x = thrust; peak = maximum over the sweep."),
        checks=checks, panels=panels, cause=" ".join(causes),
        notes=(f"The measured curves (figs. S2, S5, S8) are not in the text; the medium's fit stands in for the "
               f"measurement. Leg: {rev.settings['elements']} elements on the curved legs. The depth-only peak lift "
               f"of the C-leg is {min(peak[n, 'c', 'depth_only'][0] / peak[n, 'reversed_c', 'depth_only'][0] for n in media):.2f}"
               f"-{max(peak[n, 'c', 'depth_only'][0] / peak[n, 'reversed_c', 'depth_only'][0] for n in media):.2f} x the "
               f"reversed C-leg's (its peak thrust the same within 1 %); 'similar' is read as within 20 % "
               f"(mjrft.tools.validation.case.SIMILAR, from Li's own 'less than 20 %' for a negligible change)."),
    )

"""The papers' experiments whose outcome the sources tie to disturbed or compacted ground, rerun with the ground
memory (:mod:`mjrft.ground`, ``ground_memory=True``); their control is the same run without it (the cases
``dynaroach_robot``, ``dynaroach_legs`` and ``thesis_hubo_stance``).

``dynaroach_memory``
    Zhang et al. (DynaRoACH) sec. 2.2.4 predict from the rotary walking model that at high stride frequency "stride
    length should become small enough that the legs will encounter previously disturbed material during each
    step", which triggers the change of locomotor mode near 6 Hz (figs. 3, 7). Both robots of
    :mod:`~mjrft.tools.validation.cases.dynaroach` (the one-hinge small hexapod of ``dynaroach_robot``, and
    DynaRoACH with its own swing-and-lift legs, ``dynaroach_legs``), with the inertial regime on, sweep the stride
    frequency with the ground memory on 3 mm glass (``glass3_cp``: its loose state at phi 0.61, the paper's
    achievable range). Measured per run besides the published quantities: the share of the legs' touchdowns that
    land on ground changed before them (a cell whose surface moved by more than 0.2 mm or whose packing by more
    than 0.001). Checks, each also evaluated on the memory-off runs by the tests (the control): the touchdowns on
    disturbed ground rise with frequency (the mechanism), the fig. 7 transition near 6 Hz (full runs), the 12 Hz
    speed within 50 % of the experiment's 50 cm/s (the scale; as ``dynaroach_robot``), stride falling then rising.

``li2013_robot_memory``
    The RHex-class robot of ``li2013_robot`` (C-legs, held in the sagittal plane as Li's simulation) at 1-5 Hz on
    closely (phi 0.62) and loosely (0.58) packed poppy seeds (Li, Zhang & Goldman 2013 suppl. table S1), with the
    ground memory and, as the control, without it. Checks, each evaluated on both: the robot advances on LP at every
    f (fig. S13 / main fig. 4C: the measured curves, whose values are not in the source texts), the speed on CP at
    least the speed on LP and the legs sinking deeper on LP at every f (the thesis's sec. 1.4.1 on SandBot: "as the
    yield stress of the material decreased with lower phi, the leg sank deeper ... decreasing its effective stride
    length"). The report lists the checks the memory changes and measures the packing and the relief under the legs.

``thesis_hubo_stance_memory``
    The thesis (sec. 4.4.1, fig. 25) ties HUBO's one-foot stance on the 30.4 cm board, and its fall on the natural
    foot and on the cut-out board, to the stress under the foot against the bed's yield stress ("grains solidify
    under a static foot" is how docs/terrain.md reads it: a load compacts loose grains). ``thesis_hubo_stance``'s
    trials (natural foot, 30.4 cm board, the cut-out board; CoM -1, 0, +1 cm; quick: 0) with the ground memory, on
    the case's ``poppy_cp`` and, as a measurement of the compaction (not a check), on ``poppy_lp`` (the thesis's
    bed was raked level; its packing is not given). Checks as in ``thesis_hubo_stance``.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from mjrft.ground import C_H, C_PHI

from ..case import CaseResult, Check, Line, Panel, case, check_band, check_close, check_outcome, published
from . import dynaroach

LI2013 = "Li, Zhang & Goldman, Science 2013 (suppl.)"  # li2013_robot.CITE, as HUBO below
HUBO = "Robophysics PhD thesis, ch. IV (HUBO)"  # thesis_hubo.CITE (that module is imported when a HUBO run needs it,
# so that the registry keeps the cases in the order of their modules)

#: a touchdown lands on disturbed ground when the cell under the leg's lowest element moved by more than this (m: a
#: footprint or a ridge, not the dilation of a sheared layer) ...
DISTURBED_HEIGHT = 1e-3
#: ... or its volume fraction by more than this (a tenth of 3 mm glass's range between its two states)
DISTURBED_PACKING = 2e-3


class Touchdowns:
    """Counts the legs' touchdowns and those on ground changed before them (``observe(terrain, data)`` after each step
    of a run of :func:`~mjrft.tools.validation.cases.dynaroach.robot_run` or ``legs_run``)."""

    def __init__(self):
        self.legs = None
        self.down = {}
        self.total = 0
        self.disturbed = 0

    def __call__(self, terrain, data):
        if self.legs is None:
            m = terrain.model
            self.legs = {b: terrain.elem_body == b for b in np.unique(terrain.elem_body)
                         if (m.body(int(b)).name or "").startswith("leg_")}
            self.down = {b: False for b in self.legs}
            self.mg = float(m.body_subtreemass[1]) * 9.81
        st, gt = terrain.terrain_state, terrain.terrain_model.ground
        for b, el in self.legs.items():
            on = float(terrain.force[el, 2].sum()) > 0.02 * self.mg / 3
            if on and not self.down[b]:
                self.total += 1
                buried = el & (terrain.depth > 0)
                if buried.any():
                    k = np.flatnonzero(buried)[np.argmin(terrain.pos[buried, 2])]
                    i = int((terrain.pos[k, 0] - gt.frame[0]) * gt.frame[3])
                    j = int((terrain.pos[k, 1] - gt.frame[1]) * gt.frame[3])
                    if 0 <= i < st.g_cells.shape[1] and 0 <= j < st.g_cells.shape[0]:
                        cell = st.g_cells[j, i]
                        self.disturbed += (abs(cell[C_H]) > DISTURBED_HEIGHT
                                           or abs(cell[C_PHI] - gt.pack[3]) > DISTURBED_PACKING)
            self.down[b] = on

    @property
    def share(self) -> float:
        return self.disturbed / self.total if self.total else math.nan


ROBOTS = {"one-hinge": dynaroach.robot_run, "own legs": dynaroach.legs_run}


def sweep(freqs, quick: bool, memory: bool = True) -> dict:
    """{robot: list of run dicts (with ``disturbed``: the share of touchdowns on disturbed ground)} of both robots at
    ``freqs`` with the inertial regime on, ``memory`` the terrain's ground memory."""
    seconds, warm = (0.8, 0.3) if quick else (1.5, 0.5)
    out = {}
    for name, run in ROBOTS.items():
        rows = []
        for f in freqs:
            td = Touchdowns() if memory else None
            r = run(f, True, seconds, warm, ground_memory=memory, observe=td)
            r["disturbed"] = td.share if memory else 0.0
            rows.append(r)
        out[name] = rows
    return out


def _d(key):
    return published("dynaroach", key)


def disturbed_check(robot: str, freqs, shares) -> Check:
    """Sec. 2.2.4: at high frequency the legs meet disturbed ground: the share of touchdowns on it is higher at the
    top frequency than at the lowest, and more than half of them there."""
    return check_outcome(f"{robot}: legs land on previously disturbed ground at high frequency",
                         bool(shares[-1] > shares[0] and shares[-1] > 0.5), published=_d("disturbed_outcome").value,
                         simulated=", ".join(f"{f:g} Hz {100 * s:.0f} %" for f, s in zip(freqs, shares))
                         + " of touchdowns", source=_d("disturbed_outcome").source,
                         tolerance="higher at the top frequency than at the lowest, and > 50 % there")


def robot_checks(robot: str, freqs, runs, quick: bool) -> list[Check]:
    """The published outcomes for one robot's sweep ``runs`` (the memory's runs, or the control's)."""
    speed = np.array([r["speed"] for r in runs]) * 100
    stride = np.array([r["stride"] for r in runs]) * 100
    fa = np.array(freqs)
    hi, mid = fa >= 7, (fa >= 4) & (fa <= 6)
    checks = [disturbed_check(robot, freqs, [r["disturbed"] for r in runs]),
              check_close(f"{robot}: speed at 12 Hz (experiment)", _d("speed_12hz"), speed[-1], 0.5),
              check_outcome(f"{robot}: stride length falls, then rises at 7-12 Hz",
                            bool(stride[hi][-1] > stride[mid].min() and stride[mid].min() < stride[0]),
                            published=_d("stride_outcome").value,
                            simulated=", ".join(f"{f:g} Hz {s:.2f} cm" for f, s in zip(freqs, stride)),
                            source=_d("stride_outcome").source)]
    if not quick:
        checks.append(check_band(f"{robot}: walk-to-run transition (fig. 7 line fits)",
                                 dynaroach._transition(freqs, speed), 5.0, 7.0, published="around 6 Hz",
                                 source=_d("transition_frequency").source, unit="Hz", qualitative=False,
                                 reference=_d("transition_frequency").value))
    return checks


@case("dynaroach_memory", "DynaRoACH's frequency sweep with the ground memory: legs on disturbed ground", "dynaroach")
def run_dynaroach(quick: bool) -> CaseResult:
    freqs = [3.0, 6.0, 8.0, 12.0] if quick else [2.0, 3.0, 4.0, 6.0, 8.0, 10.0, 12.0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        on, off = sweep(freqs, quick, True), sweep(freqs, quick, False)
    checks = []
    for robot in ROBOTS:
        checks += robot_checks(robot, freqs, on[robot], quick)

    def col(runs, key, k=1.0):
        return [r[key] * k for r in runs]

    panels = [Panel(f"{robot}: average forward speed", "stride frequency (Hz)", "speed (cm/s)", [
        Line(freqs, col(on[robot], "speed", 100), "mjrft, ground memory"),
        Line(freqs, col(off[robot], "speed", 100), "mjrft, no memory (control)"),
        Line([12.0], [_d("speed_12hz").value], "paper: experiment at 12 Hz", source=_d("speed_12hz").source)])
        for robot in ROBOTS]
    panels.append(Panel("Touchdowns on previously disturbed ground", "stride frequency (Hz)", "share", [
        Line(freqs, col(on[robot], "disturbed"), robot) for robot in ROBOTS]))
    table = "; ".join(
        f"{robot}: speed " + ", ".join(f"{f:g} Hz {a * 100:.1f}/{b * 100:.1f}" for f, a, b in
                                       zip(freqs, col(on[robot], "speed"), col(off[robot], "speed")))
        + " cm/s (memory/none), stride " + ", ".join(f"{a * 100:.2f}/{b * 100:.2f}" for a, b in
                                                     zip(col(on[robot], "stride"), col(off[robot], "stride"))) + " cm"
        for robot in ROBOTS)
    h = on["one-hinge"]
    legs = on["own legs"]
    return CaseResult(
        name="dynaroach_memory", title="DynaRoACH's frequency sweep with the ground memory", paper=dynaroach.CITE,
        source="secs. 1, 2.2.4, 3.1; figs. 3, 7",
        setup=(f"the robots of dynaroach_robot (one hip hinge per leg, hips at 2 pi f t) and dynaroach_legs "
               f"(DynaRoACH's swing and lift hinges on one crank) on {dynaroach.MEDIUM}, law rft, inertial regime on, "
               f"ground memory on (GroundOptions defaults: 1 cm cells, 3 cm layer, loose state phi 0.61), at "
               f"f = {', '.join(f'{f:g}' for f in freqs)} Hz for {0.8 if quick else 1.5:g} s (averaged after "
               f"{0.3 if quick else 0.5:g} s); the same runs without the memory are the control. {table}"),
        checks=checks, panels=panels,
        cause=(f"Measured: the share of the legs' touchdowns on previously disturbed ground (which the rotary walking "
               f"model predicts to rise with frequency): "
               + "; ".join(f"{robot} " + ", ".join(f"{100 * r['disturbed']:.0f}" for r in on[robot]) + " %"
                           for robot in ROBOTS)
               + f" at {', '.join(f'{f:g}' for f in freqs)} Hz: a hexapod's hind legs land in its fore legs' "
               f"tracks at any frequency, and DynaRoACH's own legs (stride near 2r) in their own. On the "
               f"one-hinge robot the memory changes the speed by at most "
               f"{max(abs(a - b) / b for a, b in zip(col(h, 'speed'), col(off['one-hinge'], 'speed'))) * 100:.0f} % "
               f"at any frequency (its stride {min(col(h, 'stride', 100)):.1f}-{max(col(h, 'stride', 100)):.1f} cm, "
               f"3-4 times the paper's 2r, as without it). With DynaRoACH's own legs the memory makes the stride fall "
               f"with frequency ({legs[0]['stride'] * 100:.2f} -> {legs[-1]['stride'] * 100:.2f} cm; without it "
               f"{off['own legs'][0]['stride'] * 100:.2f} -> {off['own legs'][-1]['stride'] * 100:.2f} cm): the legs "
               f"sink into the loosened, lowered ground they left and the robot slows to "
               f"{legs[-1]['speed'] * 100:.1f} cm/s at {freqs[-1]:g} Hz. That is SandBot's failure on disturbed "
               "ground (Li et al. 2009, the paper's sec. 1), not DynaRoACH's running: the paper's robot runs on the "
               "grains' inertial response, which in mjrft adds drag to the protraction instead of lift (measured in "
               "dynaroach_legs), so disturbed ground can only slow it."),
        notes=("A touchdown is a leg's vertical granular force rising past 2 % of a third of the weight; its ground "
               f"is the cell under the leg's lowest buried element at that step, disturbed when its surface moved by "
               f"more than {DISTURBED_HEIGHT * 1e3:g} mm or its volume fraction by more than {DISTURBED_PACKING:g}."),
    )


# ------------------------------------------------------------------------------------------------
# HUBO's one-foot stance
# ------------------------------------------------------------------------------------------------
def stance_rows(placements, memory=True, medium=None) -> dict:
    """{(width, cut-out): [(fall time or nan, deepest sinkage m) per placement]} of the natural foot, the 30.4 cm
    board and the cut-out board, with the ground memory ``memory`` on ``medium`` (None: the case's)."""
    from . import thesis_hubo

    rows = {}
    for w, cut in ((0.152, False), (0.304, False), (0.304, True)):
        out = []
        for cx in placements:
            _, _, sink, fall, _ = thesis_hubo.run_trial(f"stance:com_x={cx},lift=0.1", w, cut, thesis_hubo.HOLD_END,
                                                        ground_memory=memory, medium=medium)
            out.append((fall, float(sink.max())))
        rows[(w, cut)] = out
    return rows


def stance_checks(rows, n: int) -> list[Check]:
    """``thesis_hubo_stance``'s checks on the trials ``rows``."""
    from . import thesis_hubo

    stable = {k: sum(math.isnan(f) for f, _ in v) for k, v in rows.items()}
    nat, wide, cut = stable[(0.152, False)], stable[(0.304, False)], stable[(0.304, True)]
    src = published("thesis_hubo", "cutout_stance").source
    return [thesis_hubo.falls_check("natural foot (15.2 cm): falls in every trial", nat, n, wide, "natural_foot_stance"),
            check_outcome("30.4 cm board: stands in every trial", wide == n,
                          published="stable stance (" + published("thesis_hubo", "stable_width").note + ")",
                          simulated=f"{wide} of {n} trials stable", source=published("thesis_hubo", "stable_width").source),
            thesis_hubo.falls_check("cut-out 30.4 cm board (half the area): falls", cut, n, wide, "cutout_stance"),
            check_outcome("full 30.4 cm board more stable than the cut-out board", wide > cut,
                          published="area, not the polygon of support, decides (sec. 4.4.1)",
                          simulated=f"{wide} vs {cut} of {n} trials stable", source=src)]


@case("thesis_hubo_stance_memory", "HUBO one-foot stance with the ground memory (fig. 25)", HUBO)
def run_hubo(quick: bool) -> CaseResult:
    from . import thesis_hubo

    placements = (0.0,) if quick else thesis_hubo.PLACEMENTS
    n = len(placements)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rows = stance_rows(placements)
        off = stance_rows(placements, memory=False)
        loose = {} if quick else {m: stance_rows(placements, memory=m, medium="poppy_lp") for m in (False, True)}
    checks = stance_checks(rows, n)
    labels = {(0.152, False): "natural 15.2 cm", (0.304, False): "30.4 cm board", (0.304, True): "30.4 cm cut-out"}

    def fmt(r):
        return "; ".join(f"{labels[k]}: " + ", ".join(("stood" if math.isnan(f) else f"fell {f:.2f} s")
                                                     + f" ({s * 1e3:.0f} mm)" for f, s in v) for k, v in r.items())

    def stable(r):
        return [sum(math.isnan(f) for f, _ in r[k]) / n for k in labels]

    panels = [Panel("One-foot stance with and without the ground memory", "foot (0: 15.2 cm, 1: 30.4 cm, 2: cut-out)",
                    "fraction of trials stable", [Line([0, 1, 2], stable(rows), "mjrft, ground memory"),
                                                  Line([0, 1, 2], stable(off), "mjrft, no memory (control)"),
                                                  Line([0, 1, 2], [0.0, 1.0, 0.0], "paper", source="fig. 25")])]
    sink_on = {k: min(s for _, s in v) for k, v in rows.items()}
    extra = ""
    if loose:
        lp_off = {k: min(s for _, s in v) for k, v in loose[False].items()}
        lp_on = {k: min(s for _, s in v) for k, v in loose[True].items()}
        extra = (f" On loosely packed poppy seeds the load compacts the grains under the foot: the centred trial's "
                 f"sinkage {lp_off[(0.304, False)] * 1e3:.0f} -> {lp_on[(0.304, False)] * 1e3:.0f} mm on the 30.4 cm "
                 f"board and {lp_off[(0.304, True)] * 1e3:.0f} -> {lp_on[(0.304, True)] * 1e3:.0f} mm on the cut-out "
                 f"(natural foot {lp_off[(0.152, False)] * 1e3:.0f} -> {lp_on[(0.152, False)] * 1e3:.0f} mm) without "
                 f"and with the memory, and the trials fall as without it ({fmt(loose[True])}).")
    return CaseResult(
        name="thesis_hubo_stance_memory", title="HUBO one-foot stance with the ground memory", paper=HUBO,
        source="sec. 4.4.1, fig. 25",
        setup=(f"thesis_hubo_stance's trials (gait 'stance', CoM {', '.join(f'{c * 100:+.0f}' for c in placements)} cm "
               f"ahead of the sole centre, held to {thesis_hubo.HOLD_END:g} s) on the natural foot, the 30.4 cm board "
               f"and its cut-out, poppy_cp, ground memory on (GroundOptions defaults: 4 cm cells). With the memory: "
               f"{fmt(rows)}. Without (the control): {fmt(off)}."),
        checks=checks, panels=panels,
        cause=("Measured: the memory does not change which trials stand. A closely packed bed has nothing to compact; "
               f"the feet still end their load transfer at the law's yield (sinkage of the centred trials "
               f"{sink_on[(0.304, False)] * 1e3:.0f} mm on the board, {sink_on[(0.304, True)] * 1e3:.0f} mm on the "
               "cut-out) and an offset CoM tilts them through the same depth hardening as without it (the cause in "
               "thesis_hubo_stance). A compacted bed is stronger under every foot by the same factor, so it cannot "
               "tell the full board from the cut-out either: the thesis's criterion, the foot's mean stress against "
               "a yield stress of the bed, needs a law whose strength does not scale with the footing." + extra),
        notes="The loose bed is a measurement of what compaction does, not a check (the thesis gives no packing).",
    )


# ------------------------------------------------------------------------------------------------
# the RHex-class robot on closely and loosely packed poppy seeds
# ------------------------------------------------------------------------------------------------
RHEX_MEDIA = ("poppy_cp", "poppy_lp")


def rhex_settings(quick: bool) -> tuple[list, float]:
    """The stride frequencies (Hz) and the trial length (s) of ``li2013_robot_memory``."""
    from . import li2013_robot

    return ([1.0, 3.0, 5.0], 4.0) if quick else ([1.0, 2.0, 3.0, 4.0, 5.0], li2013_robot.EPISODE)


def rhex_sweep(freqs, seconds: float, memory: bool) -> dict:
    """{(medium, f): :func:`~mjrft.tools.validation.cases.li2013_robot.free_trial`} of the C-leg robot held in the
    sagittal plane on poppy CP and LP (law rft), ``memory`` the terrain's ground memory."""
    from . import li2013_robot

    return {(md, f): li2013_robot.free_trial(1.0, f, md, "rft", 0, seconds, planar=True, measure_ground=True,
                                             ground_memory=memory)
            for md in RHEX_MEDIA for f in freqs}


def _l(key):
    return published("li2013_robot", key)


def rhex_checks(freqs, runs) -> list[Check]:
    """The published outcomes on the sweep ``runs`` (:func:`rhex_sweep`: the memory's, or the control's)."""
    v = {k: 100 * r["speed"] for k, r in runs.items()}
    sink = {k: 1e3 * r["leg_sinkage"] for k, r in runs.items()}

    def pairs(x, unit):
        return ", ".join(f"{x['poppy_cp', f]:.1f}/{x['poppy_lp', f]:.1f}" for f in freqs) + \
            f" {unit} (CP/LP at {', '.join(f'{f:g}' for f in freqs)} Hz)"

    return [
        check_outcome("C-legs on poppy LP: the robot advances at every tested f",
                      all(v["poppy_lp", f] > 0 for f in freqs), published=_l("runs_on_lp").value,
                      simulated=", ".join(f"{v['poppy_lp', f]:.1f}" for f in freqs) + " cm/s", tolerance="v_x > 0",
                      source=_l("runs_on_lp").source),
        check_outcome("speed on poppy CP >= on poppy LP at every tested f (lower phi, shorter effective stride)",
                      all(v["poppy_cp", f] >= v["poppy_lp", f] for f in freqs),
                      published=_l("lower_phi_shorter_stride").value, simulated=pairs(v, "cm/s"),
                      source=_l("lower_phi_shorter_stride").source + "; phi " + _l("volume_fractions").note
                      + " (" + _l("volume_fractions").source + ")"),
        check_outcome("legs sink deeper on poppy LP than on poppy CP at every tested f",
                      all(sink["poppy_lp", f] > sink["poppy_cp", f] for f in freqs),
                      published=_l("lower_phi_deeper").value, simulated=pairs(sink, "mm mean deepest leg depth"),
                      source=_l("lower_phi_deeper").source),
    ]


@case("li2013_robot_memory", "RHex-class robot at 1-5 Hz on closely and loosely packed poppy seeds with the ground "
      "memory", LI2013)
def run_rhex(quick: bool) -> CaseResult:
    from . import li2013_robot

    freqs, seconds = rhex_settings(quick)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        on, off = rhex_sweep(freqs, seconds, True), rhex_sweep(freqs, seconds, False)
    checks, control = rhex_checks(freqs, on), rhex_checks(freqs, off)
    changed = [a.name for a, b in zip(checks, control) if a.passed != b.passed]
    label = {"poppy_cp": "poppy CP", "poppy_lp": "poppy LP"}

    def line(runs, md, key, k, what):
        return Line(freqs, [k * runs[md, f][key] for f in freqs], f"{label[md]}, {what}")

    panels = [Panel(title, "stride frequency f (Hz)", ylabel, [
        line(runs, md, key, k, what) for runs, what in ((on, "ground memory"), (off, "no memory (control)"))
        for md in RHEX_MEDIA]) for title, ylabel, key, k in (
        ("C-legs, planar: average forward speed", "v_x (cm/s)", "speed", 100.0),
        ("C-legs, planar: mean deepest leg depth below the local surface", "depth (mm)", "leg_sinkage", 1e3))]

    def row(runs):
        return "; ".join(f"{label[md]} " + ", ".join(f"{f:g} Hz {100 * runs[md, f]['speed']:.1f} cm/s "
                                                    f"{1e3 * runs[md, f]['leg_sinkage']:.1f} mm" for f in freqs)
                         for md in RHEX_MEDIA)

    gap = {m: [1e3 * (r["poppy_lp", f]["leg_sinkage"] - r["poppy_cp", f]["leg_sinkage"]) for f in freqs]
           for m, r in (("on", on), ("off", off))}
    verdicts = "; ".join(f"{a.name}: memory {a.verdict}, control {b.verdict}" for a, b in zip(checks, control))
    return CaseResult(
        name="li2013_robot_memory",
        title="RHex-class robot at 1-5 Hz on closely and loosely packed poppy seeds with the ground memory",
        paper=LI2013 + "; " + HUBO.split(",")[0] + ", sec. 1.4.1",
        source="Li 2013 suppl. table S1, fig. S13 (main fig. 4C); thesis secs. 1.4.1, 2.5.2",
        setup=(f"li2013_robot's free-trial robot (mjrft/HexapodSand-v0, C-legs +1/R', alternating tripod at f = "
               f"{', '.join(f'{f:g}' for f in freqs)} Hz, the env's start, reset noise of seed 0) held in the sagittal "
               f"plane (planar=True, as Li's simulation), law rft, {seconds:g} s per trial (speed after the first "
               f"{li2013_robot.SETTLE:g} s; depth averaged over the second half), on poppy_cp (phi 0.62) and poppy_lp "
               f"(phi 0.58), ground memory on (GroundOptions defaults: 1 cm cells, 3 cm layer, Li's LP/CP pair, "
               f"critical state 0.60); the same trials without the memory are the control. With the memory: "
               f"{row(on)}. Without: {row(off)}."),
        checks=checks, panels=panels,
        cause=(f"Measured: the checks on the control (memory off): {verdicts}. The checks the memory changes: "
               + (", ".join(changed) if changed else "none")
               + ". The legs' depth on LP minus on CP (mm) at " + ", ".join(f"{f:g}" for f in freqs) + " Hz: "
               + ", ".join(f"{x:+.1f}" for x in gap["on"]) + " with the memory, "
               + ", ".join(f"{x:+.1f}" for x in gap["off"]) + " without. Under the legs' buried elements (mean "
               "over the second half) the memory holds phi "
               + "; ".join(f"{label[md]} " + ", ".join(f"{on[md, f]['leg_packing']:.3f}" for f in freqs)
                           for md in RHEX_MEDIA)
               + " (prepared 0.62 and 0.58): the loose bed is compacted toward the critical state (0.60) and past it "
               "by the legs' load, the close one barely dilates. The track's relief at the end (lowest / highest "
               "surface above the undisturbed one, mm): "
               + "; ".join(f"{label[md]} " + ", ".join(f"{1e3 * on[md, f]['track_relief'][0]:.1f}/"
                                                       f"{1e3 * on[md, f]['track_relief'][1]:+.1f}" for f in freqs)
                           for md in RHEX_MEDIA)
               + ": the volume a footprint displaces compacts loose grains first and heaps up the rest, so the "
               "closely packed bed, which cannot compact, raises the higher ridges. The legs on CP reach deeper with "
               "the memory (" + ", ".join(f"{1e3 * off['poppy_cp', f]['leg_sinkage']:.1f} -> "
                                          f"{1e3 * on['poppy_cp', f]['leg_sinkage']:.1f}" for f in freqs)
               + " mm) although the packing under them stays near 0.62, so not through a weaker bed: a leg's depth is "
               "read from the level its cell had before the leg entered it (docs/terrain.md), and the legs enter "
               "the ridges of the earlier strides. The speed ordering without the memory: LP ahead of CP at "
               + (", ".join(f"{f:g}" for f in freqs if off["poppy_lp", f]["speed"] > off["poppy_cp", f]["speed"])
                  or "no") + " Hz tested, the two beds' speeds at most "
               f"{100 * max(abs(off['poppy_lp', f]['speed'] / off['poppy_cp', f]['speed'] - 1) for f in freqs):.0f} % "
               "apart: Li's LP and CP coefficients (table S2) change the legs' depth more than the robot's stride."),
        notes=("The robot is held in the sagittal plane: the free robot turns at 4-5 Hz (li2013_robot's measured "
               "period-2 bounce), which mixes the turn into v_x. Fig. S13's measured speeds are not in the source "
               "texts, so no simulated speed is compared with a measured one (as li2013_robot). The thesis's "
               "SandBot (a different RHex-class robot and gait, Li et al. 2009) failed to advance at phi = 0.58; "
               "Li 2013's robot ran on loosely packed poppy seeds (fig. S13), so the advance on LP is the check. "
               "Depth: each step the deepest element of the six legs below the surface it meets (with the memory, "
               "the local surface)."),
    )

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

``flipperbot_memory``
    The thesis (sec. 1.4.2, on Mazouchova, Umbanhowar & Goldman 2013): sea-turtle hatchlings travel significantly
    less in a cycle whose flipper meets material disturbed in a prior cycle, and FlipperBot, whose flippers began
    interacting with previously disturbed material after a few cycles, no longer generated enough thrust against its
    body drag and failed to advance; a flexible wrist shrank the disturbed region and kept it advancing. A flipper
    robot built here (:func:`flipper_xml`: a 19 cm box body dragging on the grains, two plates inserted, swept back,
    lifted and returned in a symmetric gait) of 0.5, 1 and 2 kg on closely and loosely packed poppy seeds, and its
    flippers on the body held fixed (the thrust rig), with the ground memory and, as the control, without it.
    Measured per cycle: the body's advance, the plates' thrust impulse, the share of their buried element-steps in
    cells they were buried in during an earlier cycle (kinematics only, the same with and without the memory).
    Checks: a robot whose flippers re-enter fails to advance (the last half of the cycles << the first), its first
    re-entering cycle travels significantly less than the one before, the held flippers' thrust falls once they
    re-enter, and robots whose flippers stay clear keep advancing (the flexible wrist's statement; the wrist itself
    is not modelled).
"""

from __future__ import annotations

import math
import warnings

import mujoco
import numpy as np

from mjrft import GranularTerrain
from mjrft.ground import C_H, C_PHI

from ..case import (MUCH_LESS, SIMILAR, CaseResult, Check, Line, Panel, case, check_band, check_close, check_outcome,
                    published, similar)
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
    stable_width = published("thesis_hubo", "stable_width")
    return [thesis_hubo.falls_check("natural foot (15.2 cm): falls in every trial", nat, n, wide,
                                    "natural_foot_stance"),
            check_outcome("30.4 cm board: stands in every trial", wide == n,
                          published="stable stance (" + stable_width.note + ")",
                          simulated=f"{wide} of {n} trials stable", source=stable_width.source),
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


# ------------------------------------------------------------------------------------------------
# FlipperBot: flippers re-entering the grains they disturbed in a prior cycle
# ------------------------------------------------------------------------------------------------
FLIPPER = "flipperbot"
FLIPPER_CITE = "Robophysics PhD thesis, sec. 1.4.2 (FlipperBot: Mazouchova, Umbanhowar & Goldman 2013)"
FLIPPER_MEDIA = ("poppy_cp", "poppy_lp")
#: the rig's choices (m; the thesis and the sources found give the gait's form only, and the body's 19 cm length):
#: the body box (length, width, height); the shoulders' position ahead of its centre and at its sides; the arm from
#: the shoulder to the flipper plate (above the grains); the plate (radial length, height, thickness)
BODY = (0.19, 0.10, 0.03)
SHOULDER = (0.05, 0.05)
ARM = 0.04
PADDLE = (0.04, 0.03, 0.003)
#: the gait: one cycle per PERIOD (s); the plates are inserted (cycle fraction 0 to 0.2) at SWEEP ahead of the
#: lateral, swept back at depth to SWEEP behind it (0.2 to 0.6), lifted (0.6 to 0.7) and returned in the air (0.7 to 1);
#: the insertion stroke STROKE (m) from LIFT above the plate's rest position to STROKE below it (the plate's bottom,
#: 5 mm below the belly's at rest, then reaches about 3.5 cm below the surface)
PERIOD = 1.0
SWEEP = math.radians(45.0)
STROKE = 0.03
LIFT = 0.02
FLIPPER_PHASES = (0.2, 0.6, 0.7)
FLIPPER_SETTLE = 0.5  # s the robot rests on the grains, plates up, before the first cycle
#: body masses (kg): the flippers' thrust against the body's drag decides the step, and FlipperBot's mass was not found
FLIPPER_MASSES = (0.5, 1.0, 2.0)
#: a cycle re-enters disturbed material when more than this share of its plates' buried element-steps lie in cells
#: (REENTRY_CELL, the memory's cell) that the plates were buried in during an earlier cycle: a record of the
#: kinematics, the same with and without the memory
REENTER = 0.5
REENTRY_CELL = 0.01


def flipper_xml(mass: float, held: bool = False) -> str:
    """The flipper robot: a box body (``mass`` kg) free to slide along x and z on the grains (``held``: fixed, the
    rig that measures the flippers' thrust), two arms with a vertical insertion slide and a vertical-axis sweep hinge
    at the shoulders (position servos), each carrying a flat plate whose broad face is normal to its sweep."""
    bx, by, bz = (v / 2 for v in BODY)
    joints = "" if held else ('<joint name="x" type="slide" axis="1 0 0"/>'
                              '<joint name="z" type="slide" axis="0 0 1"/>')
    arms, servos = [], []
    for side, s in (("l", 1), ("r", -1)):
        arms.append(
            f'<body name="shoulder_{side}" pos="{SHOULDER[0]} {s * SHOULDER[1]} 0">'
            f'<joint name="lift_{side}" type="slide" axis="0 0 1" range="-0.1 0.1" armature="0.2"/>'
            f'<joint name="sweep_{side}" type="hinge" axis="0 0 1" armature="0.001"/>'
            f'<geom name="arm_{side}" type="box" pos="0 {s * ARM / 2} 0.02" size="0.004 {ARM / 2} 0.004" mass="0.01" '
            f'contype="0" conaffinity="0"/>'
            f'<body name="flipper_{side}" pos="0 {s * ARM} 0">'
            f'<geom name="paddle_{side}" type="box" pos="0 {s * PADDLE[0] / 2} {0.01 - PADDLE[1] / 2}" '
            f'size="{PADDLE[2] / 2} {PADDLE[0] / 2} {PADDLE[1] / 2}" mass="0.01"/></body></body>')
        servos.append(f'<position joint="lift_{side}" kp="2000" kv="60"/>'
                      f'<position joint="sweep_{side}" kp="20" kv="0.5"/>')
    return (f'<mujoco model="flipper"><option timestep="0.0005"/><worldbody>'
            f'<body name="body" pos="0 0 {bz}">{joints}'
            f'<geom name="belly" type="box" size="{bx} {by} {bz}" mass="{mass}"/>{"".join(arms)}</body>'
            f'</worldbody><actuator>{"".join(servos)}</actuator></mujoco>')


def flipper_pose(t: float) -> tuple[float, float]:
    """The plates' insertion (m, + up) and sweep angle (rad ahead of the lateral) at time ``t`` of the gait."""
    p = (t / PERIOD) % 1.0
    ins, swe, lif = FLIPPER_PHASES
    if p < ins:
        return LIFT - (LIFT + STROKE) * p / ins, SWEEP
    if p < swe:
        return -STROKE, SWEEP * (1 - 2 * (p - ins) / (swe - ins))
    if p < lif:
        return -STROKE + (LIFT + STROKE) * (p - swe) / (lif - swe), -SWEEP
    return LIFT, -SWEEP * (1 - 2 * (p - lif) / (1 - lif))


def flipper_run(mass: float, medium: str, memory: bool, cycles: int, held: bool = False) -> dict:
    """``cycles`` gait cycles of the flipper robot (``held``: the body fixed) on ``medium`` (law rft), ``memory`` the
    ground memory, after :data:`FLIPPER_SETTLE` s at rest. Per cycle: ``distance`` (m, the body's x), ``impulse``
    (N s, the grains' x force on the two plates over the cycle: their thrust), ``reentry`` (the share of the plates'
    buried element-steps in cells they were buried in during an earlier cycle), ``depth`` (m, the mean depth of the
    plates' buried elements below the surface they meet), ``immersion`` (m s, that depth summed over the buried
    elements and integrated over the cycle), ``height`` (m, the body's centre above the undisturbed surface at the
    cycle's end) and, with the memory, ``met_height`` (m) and ``met_packing``: the mean surface and volume fraction
    the earlier cycles left in the cells under the plates' buried elements (the ground at the cycle's start)."""
    from mjrft.ground import GroundOptions

    m = mujoco.MjModel.from_xml_string(flipper_xml(mass, held))
    d = mujoco.MjData(m)
    terrain = GranularTerrain(m, medium, "rft", ground_memory=GroundOptions() if memory else False)
    plates = [m.body("flipper_l").id, m.body("flipper_r").id]
    on_plate = np.isin(terrain.elem_body, plates)
    dt = m.opt.timestep
    d.ctrl[:] = [LIFT, -SWEEP, LIFT, SWEEP]
    terrain.step(d, int(round(FLIPPER_SETTLE / dt)))
    t0 = d.time
    visited: set = set()
    out = {k: [] for k in ("distance", "impulse", "reentry", "depth", "immersion", "height", "met_height",
                           "met_packing")}
    gt = terrain.terrain_model.ground
    for _ in range(cycles):
        x0 = float(d.qpos[0]) if not held else 0.0
        ground = terrain.terrain_state.g_cells.copy() if memory else None
        now: set = set()
        impulse = depth = 0.0
        buried = again = 0
        met = np.zeros(2)
        for _ in range(int(round(PERIOD / dt))):
            ins, ang = flipper_pose(d.time - t0)
            d.ctrl[:] = [ins, -ang, ins, ang]
            terrain.step(d)
            impulse += float(terrain.wrench[plates, 0].sum()) * dt
            b = on_plate & (terrain.depth > 0)
            if not b.any():
                continue
            depth += float(terrain.depth[b].sum())
            pos = terrain.pos[b]
            keys = (np.floor(pos[:, 0] / REENTRY_CELL).astype(np.int64) * 1_000_003
                    + np.floor(pos[:, 1] / REENTRY_CELL).astype(np.int64)).tolist()
            buried += len(keys)
            again += sum(k in visited for k in keys)
            now.update(keys)
            if memory:
                i = ((pos[:, 0] - gt.frame[0]) * gt.frame[3]).astype(np.int64)
                j = ((pos[:, 1] - gt.frame[1]) * gt.frame[3]).astype(np.int64)
                cells = ground[np.clip(j, 0, ground.shape[0] - 1), np.clip(i, 0, ground.shape[1] - 1)]
                met += (cells[:, C_H].sum(), cells[:, C_PHI].sum())
        visited |= now
        out["distance"].append((float(d.qpos[0]) if not held else 0.0) - x0)
        out["impulse"].append(impulse)
        out["reentry"].append(again / buried if buried else 0.0)
        out["depth"].append(depth / buried if buried else 0.0)
        out["immersion"].append(depth * dt)
        out["height"].append(float(d.xpos[1, 2]))
        out["met_height"].append(met[0] / buried if memory and buried else math.nan)
        out["met_packing"].append(met[1] / buried if memory and buried else math.nan)
    return out


def flipper_settings(quick: bool) -> dict:
    """The media, body masses and cycles of ``flipperbot_memory``."""
    if quick:
        return {"media": ("poppy_cp",), "masses": (FLIPPER_MASSES[0], FLIPPER_MASSES[-1]), "cycles": 4}
    return {"media": FLIPPER_MEDIA, "masses": FLIPPER_MASSES, "cycles": 8}


def flipper_sweep(s: dict, memory: bool) -> dict:
    """{(medium, mass): :func:`flipper_run`} of the free robot and {(medium, "held")}: the held rig (body fixed)."""
    runs = {}
    for md in s["media"]:
        for mass in s["masses"]:
            runs[md, mass] = flipper_run(mass, md, memory, s["cycles"])
        runs[md, "held"] = flipper_run(FLIPPER_MASSES[0], md, memory, s["cycles"], held=True)
    return runs


def _f(key):
    return published(FLIPPER, key)


def _mm(values) -> str:
    return ", ".join(f"{1e3 * v:.1f}" for v in values)


def _reentering(runs) -> dict:
    """The free-robot runs (key: (medium, mass)) whose plates re-enter disturbed material in every cycle after the
    first."""
    return {k: r for k, r in runs.items() if k[1] != "held" and min(r["reentry"][1:]) > REENTER}


def fails_to_advance_check(label: str, runs) -> Check:
    """FlipperBot (thesis sec. 1.4.2): once the flippers interact with previously disturbed material, the robot
    "failed to advance with each cycle": in every run whose plates re-enter disturbed material in every cycle after
    the first, the mean distance per cycle over the last half of the cycles is << (:data:`MUCH_LESS`, 10x below) the
    first cycle's; and some run re-enters."""
    re = _reentering(runs)
    ratio = {k: float(np.mean(r["distance"][len(r["distance"]) // 2:]) / r["distance"][0]) for k, r in re.items()}
    return check_outcome(
        f"{label}: once its flippers re-enter material disturbed in a prior cycle, the robot fails to advance",
        bool(re) and all(x <= 1 / MUCH_LESS for x in ratio.values()), published=_f("fails_to_advance").value,
        simulated=("; ".join(f"{k[1]:g} kg: " + _mm(r["distance"]) + " mm per cycle, re-entry "
                             + ", ".join(f"{100 * x:.0f}" for x in r["reentry"]) + " %" for k, r in re.items())
                   if re else "no run's flippers re-enter disturbed material"),
        source=_f("fails_to_advance").source, metric="last half of the cycles / first cycle: "
        + (", ".join(f"{ratio[k]:.3f} ({k[1]:g} kg)" for k in re) or "none"),
        tolerance=f"<= 1/{MUCH_LESS:g} ('failed to advance' read as '<<' the first cycle) in every re-entering run")


def hatchling_drop_check(label: str, runs) -> Check:
    """The hatchlings (thesis sec. 1.4.2): a cycle that meets material disturbed in a prior cycle travels a distance
    that "dropped significantly": the first re-entering cycle's distance below the cycle's before it by more than
    the "similar" band (:data:`~mjrft.tools.validation.case.SIMILAR`), in every re-entering run."""
    re = _reentering(runs)
    pairs = {k: (r["distance"][0], r["distance"][1]) for k, r in re.items()}
    return check_outcome(
        f"{label}: the first cycle in disturbed material travels significantly less than the cycle before",
        bool(re) and all(b < a / (1 + SIMILAR) for a, b in pairs.values()), published=_f("hatchling_drop").value,
        simulated=("; ".join(f"{k[1]:g} kg: {1e3 * a:.1f} -> {1e3 * b:.1f} mm" for k, (a, b) in pairs.items())
                   or "no run's flippers re-enter disturbed material"),
        source=_f("hatchling_drop").source,
        tolerance=f"below the cycle before by more than the 'similar' band (ratio < 1/{1 + SIMILAR:g})")


def thrust_drop_check(label: str, held: dict) -> Check:
    """FlipperBot: the flippers in previously disturbed material "no longer generated enough thrust": on the held rig
    (every cycle after the first re-enters the first's track) the last cycle's thrust impulse is below the first's by
    more than the "similar" band."""
    imp = held["impulse"]
    return check_outcome(
        f"{label}, body held: the flippers' thrust per cycle falls once they re-enter their disturbed track",
        bool(min(held["reentry"][1:]) > REENTER and imp[-1] < imp[0] / (1 + SIMILAR)),
        published=_f("fails_to_advance").value, source=_f("fails_to_advance").source,
        simulated="thrust impulse " + ", ".join(f"{x:.3f}" for x in imp) + " N s per cycle, re-entry "
        + ", ".join(f"{100 * x:.0f}" for x in held["reentry"]) + " %",
        tolerance=f"last cycle below the first by more than the 'similar' band (ratio < 1/{1 + SIMILAR:g})")


def keeps_advancing_check(label: str, runs) -> Check:
    """The flexible-wrist FlipperBot (thesis sec. 1.4.2): with a smaller disturbed region the robot kept advancing for
    multiple cycles. Read on the runs whose plates stay clear of their disturbed material (re-entry below
    :data:`REENTER` in every cycle): every cycle's distance similar to the first's; and some run stays clear."""
    clear = {k: r for k, r in runs.items() if k[1] != "held" and max(r["reentry"]) <= REENTER}
    return check_outcome(
        f"{label}: flippers that stay clear of their disturbed material keep the robot advancing every cycle",
        bool(clear) and all(similar(x / r["distance"][0]) for r in clear.values() for x in r["distance"]),
        published=_f("flexible_wrist").value, qualitative=False,
        source=_f("flexible_wrist").source + " (the wrist itself is not modelled: the statement's cause, a disturbed "
        "region the next cycle does not reach)",
        simulated=("; ".join(f"{k[1]:g} kg: " + _mm(r["distance"]) + " mm per cycle" for k, r in clear.items())
                   or "no run stays clear of its disturbed material"),
        tolerance="every cycle within the 'similar' band of the first")


def flipper_checks(s: dict, runs) -> list[Check]:
    """The checks of ``flipperbot_memory`` on ``runs`` (:func:`flipper_sweep`: the memory's, or the control's)."""
    checks = []
    for md in s["media"]:
        label = "poppy CP" if md == "poppy_cp" else "poppy LP"
        free = {k: r for k, r in runs.items() if k[0] == md}
        checks += [fails_to_advance_check(label, free), hatchling_drop_check(label, free),
                   thrust_drop_check(label, runs[md, "held"]), keeps_advancing_check(label, free)]
    return checks


@case("flipperbot_memory", "FlipperBot's flippers re-entering the grains they disturbed, with the ground memory",
      FLIPPER_CITE)
def run_flipper(quick: bool) -> CaseResult:
    s = flipper_settings(quick)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        on, off = flipper_sweep(s, True), flipper_sweep(s, False)
    checks, control = flipper_checks(s, on), flipper_checks(s, off)
    verdicts = "; ".join(f"{a.name}: memory {a.verdict}, control {b.verdict}" for a, b in zip(checks, control))
    label = {"poppy_cp": "poppy CP", "poppy_lp": "poppy LP"}
    cyc = list(range(1, s["cycles"] + 1))
    panels = [Panel(f"{label[md]}: distance per cycle", "cycle", "body's advance (mm)", [
        Line(cyc, [1e3 * x for x in runs[md, mass]["distance"]], f"{mass:g} kg, {what}")
        for mass in s["masses"] for runs, what in ((on, "ground memory"), (off, "no memory (control)"))])
        for md in s["media"]]
    panels.append(Panel("Body held: the flippers' thrust per cycle", "cycle", "thrust impulse (N s)", [
        Line(cyc, runs[md, "held"]["impulse"], f"{label[md]}, {what}") for md in s["media"]
        for runs, what in ((on, "ground memory"), (off, "no memory (control)"))]))
    panels.append(Panel("Plates in material disturbed in a prior cycle (ground memory)", "cycle",
                        "share of buried element-steps", [
                            Line(cyc, on[md, key]["reentry"], f"{label[md]}, " + (f"{key:g} kg" if key != "held"
                                                                                     else "body held"))
                            for md in s["media"] for key in (*s["masses"], "held")]))

    def row(runs):
        return "; ".join(f"{label[md]} {mass:g} kg " + _mm(runs[md, mass]["distance"]) + " mm"
                         for md in s["media"] for mass in s["masses"])

    re = sorted(_reentering(on))
    clear = sorted(k for k, r in on.items() if k[1] != "held" and max(r["reentry"]) <= REENTER)
    def per_immersion(k):  # thrust per unit immersion, each cycle, over the control's first cycle
        ref = off[k]["impulse"][0] / off[k]["immersion"][0]
        return [i / m / ref for i, m in zip(on[k]["impulse"], on[k]["immersion"])]

    met = "; ".join(
        f"{label[k[0]]} " + (f"{k[1]:g} kg" if k[1] != "held" else "body held") + ": surface "
        + ", ".join(f"{1e3 * h:+.1f}" for h in on[k]["met_height"][1:]) + " mm, phi "
        + ", ".join(f"{p:.3f}" for p in on[k]["met_packing"][1:]) + "; immersion "
        + ", ".join(f"{100 * x / on[k]['immersion'][0]:.0f}" for x in on[k]["immersion"]) + " % of the first cycle's "
        + "(without the memory " + ", ".join(f"{100 * x / off[k]['immersion'][0]:.0f}" for x in off[k]["immersion"])
        + " %), thrust impulse " + ", ".join(f"{x:.2f}" for x in on[k]["impulse"]) + " N s (without the memory "
        + ", ".join(f"{x:.2f}" for x in off[k]["impulse"]) + "), thrust per unit immersion "
        + ", ".join(f"{x:.2f}" for x in per_immersion(k)) + " x the control's first cycle"
        for k in re + [(md, "held") for md in s["media"]])
    sinking = "; ".join(
        f"{label[k[0]]} {k[1]:g} kg: " + _mm(off[k]["distance"][:3]) + " mm in the first cycles, the body's centre "
        + _mm([off[k]["height"][0], off[k]["height"][-1]]).replace(", ", " -> ") + " mm above the surface"
        for k in sorted(_reentering(off)))
    prepared = ", ".join(f"{label[md]} {on[md, s['masses'][0]]['met_packing'][0]:.2f}" for md in s["media"])
    return CaseResult(
        name="flipperbot_memory",
        title="FlipperBot's flippers re-entering the grains they disturbed, with the ground memory",
        paper=FLIPPER_CITE, source="thesis sec. 1.4.2 (sea turtle hatchlings and FlipperBot, ref. [34])",
        setup=(f"a flipper robot built by the case: a {BODY[0] * 100:g} x {BODY[1] * 100:g} x {BODY[2] * 100:g} cm "
               f"box body of {', '.join(f'{m:g}' for m in s['masses'])} kg dragging on the grains (free along x and "
               f"z), two flippers at its sides {SHOULDER[0] * 100:g} cm ahead of its centre, each a "
               f"{PADDLE[0] * 100:g} x {PADDLE[1] * 100:g} cm plate {ARM * 100:g} cm out from a vertical sweep hinge "
               f"and an insertion slide (position servos), in the symmetric gait: inserted {STROKE * 100:g} cm, "
               f"swept back from {math.degrees(SWEEP):g} deg ahead of the lateral to {math.degrees(SWEEP):g} deg "
               f"behind it, lifted and returned in the air, one cycle per {PERIOD:g} s, {s['cycles']} cycles after "
               f"{FLIPPER_SETTLE:g} s at rest; and the same flippers on the body held fixed (the thrust rig: every "
               f"cycle re-enters the first cycle's track). Poppy seeds ({', '.join(s['media'])}), law rft, physics "
               f"step 0.5 ms, ground memory on (GroundOptions defaults: 1 cm cells, 3 cm layer); the same runs "
               f"without the memory are the control. "
               f"Distance per cycle with the memory: {row(on)}. Without: {row(off)}."),
        checks=checks, panels=panels,
        cause=(f"Measured: the checks on the control (memory off): {verdicts}. Whether the flippers re-enter "
               "disturbed material is decided by the step against the sweep: the plates slip back through the grains "
               "while the body advances, and the next insertion lands ahead of that track only when the step is "
               "long enough. Runs that re-enter in every cycle after the first: "
               + (", ".join(f"{label[k[0]]} {k[1]:g} kg" for k in re) or "none")
               + "; runs that stay clear: " + (", ".join(f"{label[k[0]]} {k[1]:g} kg" for k in clear) or "none")
               + f". Under the re-entering plates (cycles 2 on; prepared phi {prepared}) the earlier cycles left: "
               + met + ". The immersion is the plates' depth below the local surface summed over their buried "
               "element-steps (at a fixed strength a plate's force is about proportional to it). The plates meet the "
               "surface their earlier cycles lowered (the holes stay open), so they are less immersed and push less; "
               "the packing they meet (grains sheared toward the critical state 0.60: closely packed ones dilate, "
               "loosely packed ones compact) sets the thrust per unit immersion, which stays near its first cycle's "
               "while the immersion falls. On the free robot the thrust falls below what the dragging body needs "
               "and the step collapses. Without the memory every cycle meets the prepared bed: the step dips in "
               "the second cycle as the dragging body sinks, then grows as the plates reach deeper (" + sinking
               + ")."),
        notes=("Sources: the thesis states the outcome (sec. 1.4.2) and cites Mazouchova, Umbanhowar & Goldman, "
               "Bioinspiration & Biomimetics 2013 for it; that paper's text is not among the sources, and its "
               "flipper size, insertion depth, sweep, body mass, distance per cycle and cycles to failure were not "
               "found. The body's 19 cm length is the press coverage's ('the 19 cm robot', The Engineer, April "
               "2013), the poppy seed bed the Georgia Tech news release's (April 2013); the bed's packing was not "
               "found, so the full case runs closely (0.62) and loosely (0.58) packed seeds. Every other "
               "dimension, the servo gains, the gait's timing and the body masses are choices; the masses span "
               "bodies whose step clears the previous sweep and bodies whose step does not, since FlipperBot's "
               "mass, which decides that, was not found. The flexible wrist is not modelled (its joint, range and "
               "stiffness are not in the sources); the check of its statement reads the runs whose flippers stay "
               "clear of their disturbed material. A cycle re-enters when more than half of its plates' buried "
               "element-steps lie in 1 cm cells the plates were buried in during an earlier cycle (kinematics "
               "only: the same with and without the memory). Thrust: the grains' x force on both plates integrated "
               "over the cycle."),
    )

"""The trade study's outputs: the CSV and Markdown tables, the presets' choice (:func:`recommend_presets`) and the
Pareto plot of cost against force error (:func:`write_outputs` writes all three)."""

from __future__ import annotations

import csv
import math
import os

import numpy as np

from .measure import Row
from .scenarios import CONTROL_PERIOD, MODEL_DIFFERENCE_LAWS, REFERENCE_LAW, SCENARIOS

CSV_FIELDS = ("scenario", "config", "factor", "law", "resolution_scale", "resolution_mm", "elements", "timestep_ms",
              "frame_skip", "cost_ratio", "err_peak_force", "err_rms_force", "err_final_position_mm",
              "err_sinkage_mm", "peak_force_N", "rms_force_N", "final_x_m", "final_y_m", "final_z_m",
              "sinkage_mm", "stability_warnings", "status")


def _num(v, fmt="{:.6g}"):
    return "" if v is None or (isinstance(v, float) and not math.isfinite(v)) else fmt.format(v)


def write_csv(rows: list[Row], path) -> str:
    """One line per scenario and configuration; empty cells where a value does not apply."""
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(CSV_FIELDS)
        for r in rows:
            c = r.config
            w.writerow([r.scenario, c.label, c.factor, c.law, _num(c.resolution_scale), _num(r.resolution * 1e3),
                        r.elements, _num(c.timestep * 1e3), c.frame_skip, _num(r.cost_ratio), _num(r.err_peak),
                        _num(r.err_rms), _num(r.err_position * 1e3), _num(r.err_sinkage * 1e3), _num(r.peak_force),
                        _num(r.rms_force), *(_num(v) for v in r.final_position), _num(r.sinkage * 1e3), r.warnings,
                        r.status])
        fh.flush()
    return str(path)


def _pct(v):
    return "–" if not math.isfinite(v) else f"{100 * v:.2f} %"


def _mm(v):
    return "–" if not math.isfinite(v) else f"{1e3 * v:.2f}"


def markdown_table(rows: list[Row]) -> str:
    """The result table, one section per scenario."""
    out = []
    for name in dict.fromkeys(r.scenario for r in rows):
        sc = SCENARIOS.get(name)
        out.append(f"#### {name}: {sc.description if sc else ''}\n")
        out.append("| configuration | law | resolution | elements | dt x skip | cost (x bare) | peak F err | "
                   "RMS F err | final pos err (mm) | sinkage err (mm) | notes |")
        out.append("|---|---|---|---:|---|---:|---:|---:|---:|---:|---|")
        for r in (r for r in rows if r.scenario == name):
            c = r.config
            notes = []
            if r.status != "ok":
                notes.append("failed (non-finite)")
            if r.warnings:
                notes.append(f"{r.warnings} stability warning(s)")
            if c.law in MODEL_DIFFERENCE_LAWS:
                notes.append("other physics: error = model difference")
            if abs(c.timestep * c.frame_skip - CONTROL_PERIOD) > 1e-12 and not (sc and sc.kinematic):
                notes.append(f"control period {c.timestep * c.frame_skip * 1e3:g} ms: error includes the "
                             "different control signal")
            cost = "–" if not math.isfinite(r.cost_ratio) else f"{r.cost_ratio:.2f}"
            out.append(f"| {c.label} | {c.law} | {r.resolution * 1e3:g} mm | {r.elements} | "
                       f"{c.timestep * 1e3:g} ms x {c.frame_skip} | {cost} | {_pct(r.err_peak)} | {_pct(r.err_rms)} | "
                       f"{_mm(r.err_position)} | {_mm(r.err_sinkage)} | {'; '.join(notes)} |")
        conv = next((r.convergence for r in rows if r.scenario == name and r.config.factor == "reference"
                     and r.convergence), None)
        if conv:
            out.append(f"\nResolution convergence at 1 ms, {conv['coarser']} against {conv['finer']}: peak F "
                       f"{_pct(conv['err_peak'])}, RMS F {_pct(conv['err_rms'])}, final position "
                       f"{_mm(conv['err_position'])} mm, sinkage {_mm(conv['err_sinkage'])} mm (the reference is "
                       "no more certain than this).")
        out.append("")
    return "\n".join(out)


#: preset criteria: worst case over the scenarios of the study (see :func:`recommend_presets`)
FAST_MAX_RMS, FAST_MAX_PEAK = 0.20, 0.10
ACCURATE_MAX_RMS, ACCURATE_MAX_PEAK, ACCURATE_MAX_POSITION = 0.01, 0.01, 0.001
ACCURATE_GAIN = 4.0  # the accurate preset's force errors are at most 1/4 of the default configuration's


def recommend_presets(rows: list[Row]) -> dict:
    """Pick the "fast" and "accurate" configurations from a study's rows.

    Candidates: configurations with the ``rft`` law (the medium's own fit) and the default 10 ms control
    period that ran in every scenario of ``rows`` without failure and with no more stability warnings
    than the scenario's default configuration (a preset must not be less stable than the default).
    Cost is the geometric mean of the cost ratios over the scenarios; errors are the worst case.

    * fast: the cheapest candidate with RMS force error <= 20 % and peak force error <= 10 %;
    * accurate: the cheapest candidate that is not the reference of every scenario, with RMS and peak
      force errors <= 1 % and at most 1/4 of the default configuration's (a clear gain over the default,
      not only a threshold the default may already meet) and final position error <= 1 mm, in every
      scenario whose reference is converged:
      a scenario whose two finest resolutions (at 1 ms) already differ by more than these limits
      (``Row.convergence`` of its reference row) can not tell such errors apart and is left out of
      this criterion (its name is listed under ``"unconverged"``).

    Scenarios registered with ``presets=False`` are reported but take no part: the small hexapod at 10 Hz,
    whose 1 ms default is already 22 % (RMS force) from its 0.5 ms reference, says that fast gaits need a
    finer timestep, which its own env can set, not what the other robots' presets should be.

    Returns ``{name: {"config": Config, "cost": geometric-mean ratio, "err_rms": worst, "err_peak": worst,
    "err_position": worst (m, nan without robots)}}`` (a name is missing when no candidate qualifies).
    """
    rows = [r for r in rows if r.scenario not in SCENARIOS or SCENARIOS[r.scenario].presets]
    scenarios = list(dict.fromkeys(r.scenario for r in rows))
    unconverged = []
    for r in rows:
        conv = r.convergence
        if r.config.factor == "reference" and conv is not None and (
                conv["err_rms"] > ACCURATE_MAX_RMS or conv["err_peak"] > ACCURATE_MAX_PEAK
                or conv["err_position"] > ACCURATE_MAX_POSITION):
            unconverged.append(r.scenario)
    allowed = {sc: 0 for sc in scenarios}
    for r in rows:
        if r.config.factor == "default":
            allowed[r.scenario] = r.warnings
    by_key: dict = {}
    for r in rows:
        by_key.setdefault(r.config.key(), []).append(r)
    cands = []
    for key, rs in by_key.items():
        c = rs[0].config
        if (c.law != REFERENCE_LAW or abs(c.timestep * c.frame_skip - CONTROL_PERIOD) > 1e-12
                or len({r.scenario for r in rs}) != len(scenarios)
                or any(r.status != "ok" or r.warnings > allowed[r.scenario] or not math.isfinite(r.cost_ratio)
                       for r in rs)):
            continue
        conv = [r for r in rs if r.scenario not in unconverged]

        def worst(rs_, attr):
            vals = [getattr(r, attr) for r in rs_ if math.isfinite(getattr(r, attr))]
            return max(vals) if vals else math.nan

        cands.append({"config": c, "cost": float(np.exp(np.mean(np.log([r.cost_ratio for r in rs])))),
                      "err_rms": worst(rs, "err_rms"), "err_peak": worst(rs, "err_peak"),
                      "err_position": worst(rs, "err_position"),
                      "conv": {k: worst(conv, k) for k in ("err_rms", "err_peak", "err_position")},
                      "reference": all(r.config.factor == "reference" for r in rs)})
    cands.sort(key=lambda d: d["cost"])
    defaults = [r for r in rows if r.config.factor == "default" and r.scenario not in unconverged]
    gain = {k: max((getattr(r, k) for r in defaults), default=math.inf) / ACCURATE_GAIN
            for k in ("err_rms", "err_peak")}
    out = {}
    for d in cands:
        public = {k: v for k, v in d.items() if k not in ("conv", "reference")}
        if "fast" not in out and d["err_rms"] <= FAST_MAX_RMS and d["err_peak"] <= FAST_MAX_PEAK:
            out["fast"] = public
        e = d["conv"]
        if ("accurate" not in out and not d["reference"] and e["err_rms"] <= min(ACCURATE_MAX_RMS, gain["err_rms"])
                and e["err_peak"] <= min(ACCURATE_MAX_PEAK, gain["err_peak"])
                and not e["err_position"] > ACCURATE_MAX_POSITION):
            out["accurate"] = public
    out["unconverged"] = unconverged
    return out


def recommendation_text(rows: list[Row]) -> str:
    rec = recommend_presets(rows)
    left_out = [s for s in dict.fromkeys(r.scenario for r in rows) if s in SCENARIOS and not SCENARIOS[s].presets]
    note = f", {', '.join(left_out)} reported but not used" if left_out else ""
    lines = [f"#### Preset choice (worst case over the scenarios above{note}, cost = geometric mean)\n",
             "| preset | criterion | chosen configuration | resolution x | dt x skip | cost (x bare) | worst RMS F err | "
             "worst peak F err | worst final pos err (mm) |", "|---|---|---|---:|---|---:|---:|---:|---:|"]
    crit = {"fast": f"RMS F <= {FAST_MAX_RMS:.0%}, peak F <= {FAST_MAX_PEAK:.0%}",
            "accurate": f"RMS and peak F <= {ACCURATE_MAX_RMS:.0%} and <= 1/{ACCURATE_GAIN:g} of the default's, "
                        f"position <= {ACCURATE_MAX_POSITION * 1e3:g} mm"}
    if rec["unconverged"]:
        crit["accurate"] += f" (not judged on {', '.join(rec['unconverged'])}: reference not converged)"
    for name in ("fast", "accurate"):
        d = rec.get(name)
        if d is None:
            lines.append(f"| {name} | {crit[name]} | none qualifies | | | | | | |")
            continue
        c = d["config"]
        lines.append(f"| {name} | {crit[name]} | {c.label} | {c.resolution_scale:g} | {c.timestep * 1e3:g} ms x "
                     f"{c.frame_skip} | {d['cost']:.2f} | {_pct(d['err_rms'])} | {_pct(d['err_peak'])} | "
                     f"{_mm(d['err_position'])} |")
    return "\n".join(lines) + "\n"


def write_markdown(rows: list[Row], path, title: str = "Speed/accuracy trade study") -> str:
    text = (f"# {title}\n\nCost: wall time per simulated second relative to the bare MuJoCo model (robots: the "
            "rigid-ground twin with the same controller; rigs: the rig without terrain; 1 ms x 10), measured "
            "interleaved in one run. Errors against the reference (finest resolution, 0.5 ms, the medium's own Li "
            "fit): peak and RMS of the net granular force (relative), final position and late-run sinkage (robots "
            "only). See `mjrft.tools.tradeoff`.\n\n" + markdown_table(rows) + "\n" + recommendation_text(rows))
    with open(path, "w") as fh:
        fh.write(text)
        fh.flush()
    return str(path)


def pareto_front(points: list[tuple[float, float]]) -> list[int]:
    """Indices of the points not dominated in (cost, error), both smaller-is-better, sorted by cost."""
    idx = [i for i, (c, e) in enumerate(points) if math.isfinite(c) and math.isfinite(e)]
    idx.sort(key=lambda i: (points[i][0], points[i][1]))
    front, best = [], math.inf
    for i in idx:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


FACTOR_STYLE = {"default": ("k", "o"), "resolution": ("tab:blue", "o"), "law": ("tab:orange", "s"),
                "timestep": ("tab:green", "^"), "frame_skip": ("tab:purple", "v"), "reference": ("tab:red", "*"),
                "preset": ("tab:brown", "D")}
ERROR_FLOOR = 1e-4  # plotted in place of a zero error (the reference) on the log axis


def plot_pareto(rows: list[Row], path) -> str:
    """Cost ratio (x, log) against RMS force error (y, log), one panel per scenario, Pareto front drawn."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.ticker import FuncFormatter, NullFormatter

    names = list(dict.fromkeys(r.scenario for r in rows))
    ncol = 2 if len(names) > 1 else 1
    nrow = math.ceil(len(names) / ncol)
    fig = Figure(figsize=(6.0 * ncol, 4.6 * nrow), constrained_layout=True)
    FigureCanvasAgg(fig)
    for k, name in enumerate(names):
        ax = fig.add_subplot(nrow, ncol, k + 1)
        rs = [r for r in rows if r.scenario == name and r.status == "ok" and math.isfinite(r.cost_ratio)]
        pts = [(r.cost_ratio, max(r.err_rms, ERROR_FLOOR)) for r in rs]
        for factor, (color, marker) in FACTOR_STYLE.items():
            sel = [i for i, r in enumerate(rs) if r.config.factor == factor]
            if sel:
                ax.scatter([pts[i][0] for i in sel], [100 * pts[i][1] for i in sel], c=color, marker=marker,
                           s=60 if factor in ("reference", "preset") else 36, label=factor, zorder=3)
        for i, r in enumerate(rs):
            ax.annotate(r.config.label.replace("resolution ", "res ").replace("law ", ""), (pts[i][0], 100 * pts[i][1]),
                        fontsize=6.5, xytext=(3, 3), textcoords="offset points")
        dry = [i for i, r in enumerate(rs) if r.config.law not in MODEL_DIFFERENCE_LAWS]
        front = [dry[j] for j in pareto_front([pts[i] for i in dry])]
        ax.plot([pts[i][0] for i in front], [100 * pts[i][1] for i in front], "-", color="0.5", lw=1, zorder=2,
                label="Pareto front")
        ax.set_xscale("log")
        ax.set_yscale("log")
        for axis in (ax.xaxis, ax.yaxis):
            axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
            axis.set_minor_formatter(NullFormatter())
        ax.set_xlabel("cost per simulated second (x bare MuJoCo)")
        ax.set_ylabel("RMS force error (%)")
        ax.set_title(f"{name}", fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="best")
    fig.suptitle(f"mjrft speed/accuracy trade (reference plotted at {100 * ERROR_FLOOR:g} %)", fontsize=11)
    fig.savefig(path, dpi=120)
    return str(path)


def write_outputs(rows: list[Row], out_dir, stem: str = "trade_study") -> dict:
    """Write the Markdown table, CSV and Pareto PNG into ``out_dir``; returns their paths."""
    os.makedirs(out_dir, exist_ok=True)
    return {
        "markdown": write_markdown(rows, os.path.join(out_dir, f"{stem}.md")),
        "csv": write_csv(rows, os.path.join(out_dir, f"{stem}.csv")),
        "png": plot_pareto(rows, os.path.join(out_dir, f"{stem}.png")),
    }

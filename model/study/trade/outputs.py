# SPDX-License-Identifier: Apache-2.0
"""What a trade run writes: the CSV of every point, the markdown tables and the Pareto plots.

Owns ``write_outputs`` (``results.csv``, ``results.md``, ``pareto_cycles.png``,
``pareto_bits.png`` and the README's ``trade_pareto.png``), the tables (``CSV_FIELDS``,
``table_row``, ``sweep_rows``, ``knob_summary``, ``format_markdown``) and the plots
(``plot_pareto``, ``plot_figure``, ``place_labels``).  Every table row names its family (the
patent's cos^k or a BRDF form), results.md lists each front's points with their families
(``front_lines``) and the plots mark the family (``family_marker``; a BRDF point's label starts
with its form).  May import numpy, matplotlib, ``model.study.metrics`` and ``model.study.trade``
``points``, ``analysis`` and ``hardware``.

Size: about 540 lines: the three outputs read the same aggregated rows and share their labels
(``point_label``, the families' markers), so a change to one is a change to all.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from model.study import metrics
from model.study.trade.analysis import (
    NEAR,
    aggregate,
    default_position,
    default_row,
    front_families,
    throughput_axis,
)
from model.study.trade.hardware import HW_FIELDS
from model.study.trade.labels import (
    marker_boxes,
    overlap,
    place_labels,
    polyline_boxes,
)
from model.study.trade.points import (
    DEFAULT_POINT,
    FAMILIES,
    KNOBS,
    PATENT,
    SMALL_SWEEPS,
    Sweep,
    family,
    row_knobs,
)

# ================================================================================ outputs
CSV_FIELDS = (
    "scene",
    "size",
    *KNOBS,
    "label",
    "nmse",
    "psnr",
    "max_abs_error",
    "share_off_by_more_than_1",
    "highlight_max_abs_error",
    "epicentre_rel_error",
    "epicentre_worst_n",
    "epicentre_out_lsb",
    "unit_error_lsb",
    "line_drift_levels",
    "angle_drift_steps",
    "pixels_shaded",
    "divider_cycles",
    "gouraud_cycles",
    "specular_cycles",
    "specular_pixels",
    "diffuse_cycles",
    "diffuse_pixels",
    "cycles",
    "frame_clocks",
    "px_per_clock",
    "px_per_clock_parallel",
    "core_clocks",
    "px_per_clock_core",
    "table_bits",
    "adders",
    "multipliers",
    "mult_bits",
    *HW_FIELDS,
    "shade_seconds",
    "sw_pixels_per_second",
    "key",
    "config_key",
)


def write_csv(results: list[dict], path: Path) -> Path:
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=CSV_FIELDS, extrasaction="ignore")
        w.writeheader()
        w.writerows(results)
    return path


def _num(x: float) -> str:
    return "-" if not np.isfinite(x) else f"{x:.3f}"


def _pct(x: float) -> str:
    return "-" if not np.isfinite(x) else f"{100 * x:.2f} %"


TABLE_HEAD = (
    "| config | family | NMSE (mean) | PSNR dB (min) | max err | epicentre err (n) "
    "| unit err (LSB) | line drift "
    "| angle drift | cycles/frame | frame clocks | px/clk | px/clk par. | core clocks "
    "| px/clk core | table bits | adders "
    "| mult (bits) | LUT | FF | BRAM | DSP | Fmax MHz | hw Mpx/s | sw Mpx/s | front |\n"
    "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    "---|---|---|"
)


def _int(x: float) -> str:
    return "-" if not np.isfinite(float(x)) else f"{round(float(x)):,}"


def _num4(x: float) -> str:
    return "-" if not np.isfinite(float(x)) else f"{float(x):.4f}"


def _hw(r: dict) -> str:
    """The synthesised columns: LUT, FF, BRAM, DSP, Fmax, the hardware's Mpx/s."""
    cells = [_int(r[k]) for k in ("lut", "ff", "bram", "dsp")]
    fmax, mpx = float(r["fmax_mhz"]), float(r["hw_mpx_per_s"])
    cells += ["-" if not np.isfinite(fmax) else f"{fmax:.1f}", _num(mpx)]
    return " | ".join(cells)


FRONT_MARKS = {
    "C": "pareto_cycles",
    "B": "pareto_bits",
    "L": "pareto_lut",
    "T": "pareto_throughput",
}
"""The marks of the "front" column: the fronts a configuration is on (``analysis.aggregate``)."""


def table_row(r: dict) -> str:
    marks = "".join(m for m, k in FRONT_MARKS.items() if r[k])
    epi = (
        f"{_pct(r['epicentre_rel_error'])} ({r['epicentre_worst_n']})"
        if np.isfinite(r["epicentre_rel_error"])
        else "-"
    )
    name = "**default**" if r["label"] == "default" else r["label"]
    mults = _int(r["multipliers"])
    if np.isfinite(float(r["mult_bits"])):
        mults += f" ({int(r['mult_bits'])})"
    return (
        f"| {name} | {r['family']} | {r['nmse']:.6f} | {r['psnr']:.1f} "
        f"| {r['max_abs_error']:.0f} | {epi} "
        f"| {_num(r['unit_error_lsb'])} "
        f"| {r['line_drift_levels']:.3f} | {_num(r['angle_drift_steps'])} "
        f"| {r['cycles']:,.0f} | {r['frame_clocks']:,.0f} "
        f"| {r['px_per_clock']:.3f} | {r['px_per_clock_parallel']:.3f} "
        f"| {_int(r['core_clocks'])} | {_num4(r['px_per_clock_core'])} | {r['table_bits']:,} "
        f"| {_int(r['adders'])} | {mults} | {_hw(r)} "
        f"| {r['sw_pixels_per_second'] / 1e6:.2f} | {marks or '-'} |"
    )


def sweep_rows(sweep: Sweep, rows: list[dict]) -> list[dict]:
    """The aggregated rows of the sweep's configurations, in the sweep's order."""
    by_knobs = {tuple(r[k] for k in KNOBS): r for r in rows if not r.get("config_name")}
    out = []
    for c in sweep.configs():
        knobs = {**DEFAULT_POINT.knobs, **c}
        r = by_knobs.get(tuple(knobs[k] for k in KNOBS))
        if r is not None:
            out.append(r)
    return out


def _ratio(a: float, b: float) -> str:
    return f"{a / b:.2f}x" if b else "-"


def knob_summary(sweep: Sweep, rows: list[dict]) -> str:
    """What the knob buys, from its one-knob sweep: accuracy and cost at each end."""
    rs = sweep_rows(sweep, rows)
    if len(rs) < 2:
        return f"* {sweep.title}: not measured"
    base = {**DEFAULT_POINT.knobs, **dict(sweep.base)}
    ref = next((r for r in rs if r[sweep.knob] == base[sweep.knob]), rs[0])
    parts = []
    for r in rs:
        if r is ref:
            continue
        parts.append(
            f"{r[sweep.knob]}: NMSE {_ratio(r['nmse'], ref['nmse'])}, epicentre "
            f"{_pct(r['epicentre_rel_error'])}, cycles {_ratio(r['cycles'], ref['cycles'])}, "
            f"frame clocks {_ratio(r['frame_clocks'], ref['frame_clocks'])}, table bits "
            f"{_ratio(r['table_bits'], ref['table_bits'])}"
        )
    return (
        f"* **{sweep.title}** (`{sweep.knob}`, against {ref[sweep.knob]}: NMSE "
        f"{ref['nmse']:.6f}, epicentre {_pct(ref['epicentre_rel_error'])}): " + "; ".join(parts)
    )


def front_lines(rows: list[dict]) -> list[str]:
    """results.md's "fronts across families": per front, its points from the most accurate on,
    each with its family, and the run's families with no point on it."""
    run = [f for f in FAMILIES if any(r["family"] == f for r in rows)]
    run += sorted({r["family"] for r in rows} - set(run))
    lines = ["## The fronts across families", ""]
    lines.append(
        f"One front per cost over every configuration of the run, whatever its family "
        f"({', '.join(run)}); from the most accurate point on, each with its family."
    )
    lines.append("")
    for name, members in front_families(rows).items():
        if not members:
            continue
        listed = "; ".join(f"{label} ({fam})" for label, fam in members)
        absent = [f for f in run if f not in {fam for _, fam in members}]
        why = ""
        unmeasured = [
            f
            for f in absent
            if name.endswith("throughput")
            and all(math.isnan(r["hw_mpx_per_s"]) for r in rows if r["family"] == f)
        ]
        # no throughput: no core clocks (no shading core built with the family), or clocks but
        # no Fmax (its units do not fit the part, or were not synthesised)
        no_core = [
            f
            for f in unmeasured
            if all(math.isnan(r["px_per_clock_core"]) for r in rows if r["family"] == f)
        ]
        no_fmax = [f for f in unmeasured if f not in no_core]
        reasons = []
        if no_core:
            reasons.append(f"{', '.join(no_core)}: no shading core built with it")
        if no_fmax:
            reasons.append(f"{', '.join(no_fmax)}: no Fmax, its units not placed on the part")
        if reasons:
            why = f" ({'; '.join(reasons)}: no throughput)"
        off = f"; no point of {', '.join(absent)}{why}" if absent else ""
        lines.append(f"* {name}: {listed}{off}")
    return [*lines, ""]


def format_markdown(
    rows: list[dict], sweeps: Sequence[Sweep] = SMALL_SWEEPS, refused: Sequence[str] = ()
) -> str:
    lines = ["# Speed/accuracy trade", ""]
    if rows:
        lines.append(
            f"Scenes: {rows[0]['scenes']} at {rows[0]['size']} x {rows[0]['size']}; accuracy "
            "against exact Blinn (a): NMSE mean, PSNR and max error worst over the scenes; "
            "cost per frame: mean over the scenes.  front: C = on the NMSE-vs-cycles Pareto "
            "front, B = on the NMSE-vs-table-bits front, L = on the NMSE-vs-LUTs front, T = on "
            f"the NMSE-vs-{throughput_axis(rows)} front (over every configuration of the run).  "
            f"LUT, FF, BRAM, DSP: the units' own cells on {rows[0]['part']} (sums over the "
            "units the configuration uses), Fmax: the slowest unit's; frame clocks, px/clk par.: "
            "the units in parallel with ideal buffering (an estimate); core clocks: the shading "
            "core's with the configuration's highlight path (core.core_cycles = core.latency + "
            "pixels per frame: 18 with the patent's unit, 20 to 28 with a BRDF form's pipe; its "
            "RTL matches them clock for clock), px/clk core = pixels / core clocks; hw Mpx/s: "
            "px/clk core x Fmax (the units' Fmax, not the core's own); sw Mpx/s: the software "
            "model.  family: the highlight's unit, cos^k = the patent's specular unit, else the "
            "BRDF family unit of that form (`brdf` knob); every front spans every family.  A "
            "BRDF unit's epicentre error is its word F against cos^n over n = 2..1000 "
            "(brdf.fixed_accuracy) and it has no unit error in output LSBs."
        )
        lines.append("")
        lines += front_lines(rows)
    shown: set[str] = set()
    for sw in sweeps:
        rs = sweep_rows(sw, rows)
        if not rs:
            continue
        lines += [f"## {sw.title} (`{sw.knob}`)", "", TABLE_HEAD]
        lines += [table_row(r) for r in rs]
        lines.append("")
        shown.update(r["config_key"] for r in rs)
    rest = [r for r in rows if r["config_key"] not in shown and not r.get("config_name")]
    if rest:
        lines += ["## other configurations", "", TABLE_HEAD, *map(table_row, rest), ""]
    files = [r for r in rows if r.get("config_name")]
    if files or refused:
        lines += ["## configuration files (`--config`)", ""]
        lines += [f"* {r['config_name']}: scenes {r['scenes']}" for r in files]
        lines += [f"* refused: {why}" for why in refused]
        if files:
            lines += ["", TABLE_HEAD, *map(table_row, files)]
        lines.append("")
    lines += ["## What each knob buys", ""]
    lines += [knob_summary(sw, rows) for sw in sweeps]
    lines += ["", "## Where the default lies", ""]
    for name, labels in default_position(rows).items():
        verdict = "on or near the front" if not labels else "eps-dominated by " + "; ".join(labels)
        lines.append(f"* NMSE vs {name}: {verdict}")
    lines.append(
        f"\n(eps-dominated: another configuration is more than {100 * NEAR:.0f} % better in one "
        f"figure and at most {100 * NEAR:.0f} % worse in every other; all figures: NMSE, the "
        "worst epicentre error, line drift and angle drift, cycles, table bits, adders and "
        "multiplier bits.)"
    )
    return "\n".join(lines) + "\n"


THRESHOLD_LABEL = "visually identical: NMSE ≤ {:g} (thesis)"
"""The label of the thesis's "visually identical" line (``metrics.NMSE_VISUALLY_IDENTICAL``)."""


def point_label(r: dict) -> str:
    """A row's label on the plots: "default", a named combination, the changed knob of its
    sweep (``p=4``, ``highlight_levels=16``), else every changed knob, one per line; a BRDF
    family point's label starts with its form (``quadratic``, ``quadratic:\nrecip_bits=14``),
    so the family of every labelled point is on the plot."""
    if r.get("config_name"):
        return r["config_name"]
    knobs = row_knobs(r)
    if knobs["brdf"] != PATENT:
        rest = {k: v for k, v in knobs.items() if k != "brdf"}
        changed = DEFAULT_POINT.with_knobs(**rest).changed_knobs()
        text = "\n".join(
            f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}" for k, v in changed.items()
        )
        return f"{knobs['brdf']}:\n{text}" if text else knobs["brdf"]
    group = DEFAULT_POINT.with_knobs(**knobs).group
    if group in KNOBS:
        v = r[group]
        return f"{group}={v:g}" if isinstance(v, float) else f"{group}={v}"
    return r["label"].replace(", ", "\n")


def _threshold_line(ax, markers: list, fontsize: float):
    """The "visually identical" line with its label just above or below it, at its right or
    left end, wherever it keeps clear of the markers (padded by 2 pixels), else where it covers
    least; returns the label's display box."""
    from matplotlib.transforms import blended_transform_factory

    y = metrics.NMSE_VISUALLY_IDENTICAL
    ax.axhline(y, color="0.35", lw=0.9, ls=":", zorder=1)
    trans = blended_transform_factory(ax.transAxes, ax.transData)
    renderer = ax.figure.canvas.get_renderer()
    best = None
    for va in ("bottom", "top"):
        for x, ha in ((0.99, "right"), (0.01, "left")):
            text = ax.text(
                x,
                y,
                THRESHOLD_LABEL.format(y),
                transform=trans,
                ha=ha,
                va=va,
                fontsize=fontsize,
                color="0.3",
                zorder=4,
            )
            box = text.get_window_extent(renderer)
            cost = sum(overlap(box.padded(2), m) for m in markers)
            if best is None or cost < best[0]:
                if best is not None:
                    best[1].remove()
                best = (cost, text, box)
            else:
                text.remove()
            if best[0] == 0:
                return best[2]
    return best[2]


X_AXES: dict[str, tuple[str, str, bool]] = {
    "cycles": ("pareto_cycles", "unit cycles per frame (mean over scenes)", False),
    "table_bits": ("pareto_bits", "ROM bits", True),
    "lut": ("pareto_lut", "LUTs (synthesised, the units' own)", False),
    "hw_mpx_per_s": ("pareto_throughput", "Mpx/s (the core's px/clk x the units' Fmax)", False),
    "px_per_clock_core": ("pareto_throughput", "pixels per clock (the shading core)", False),
}
"""The x axes of ``plot_pareto``: (front field, axis label, log scale)."""


FAMILY_MARKERS = ("o", "s", "^", "v", "P", "X", "h")


def family_marker(fam: str) -> str:
    """The plots' marker of a family: a circle for the patent's cos^k, then one per form."""
    i = FAMILIES.index(fam) if fam in FAMILIES else len(FAMILY_MARKERS) - 1
    return FAMILY_MARKERS[min(i, len(FAMILY_MARKERS) - 1)]


def _group(r: dict) -> str:
    return "fitted" if r.get("config_name") else DEFAULT_POINT.with_knobs(**row_knobs(r)).group


def plot_pareto(
    rows: list[dict], x: str, path: Path | None = None, ax=None, legend: bool = True
) -> Path | None:
    """NMSE (log) against ``x`` (``X_AXES``: cycles, table bits, LUTs, throughput): every
    configuration coloured by its sweep, the Pareto front dashed, the default starred, the
    configuration files' points (``--config``) as black diamonds, the thesis's "visually
    identical" threshold as a labelled line, and the front points, the default and the files'
    points labelled without collisions (``place_labels``).  Rows without a value of ``x`` (no
    synthesis) are left out.  With ``ax``, draws into it (its figure's layout must be final) and
    returns None; otherwise writes ``path``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    front_key, xlabel, log_x = X_AXES[x]
    if x == "lut" and rows:
        xlabel = xlabel.replace("synthesised", f"synthesised on {rows[0]['part']}")
    rows = [r for r in rows if np.isfinite(float(r[x]))]
    own = ax is None
    if own:
        fig, ax = plt.subplots(figsize=(8.4, 4.8), dpi=100)
        fig.subplots_adjust(left=0.1, right=0.74, bottom=0.11, top=0.97)
    fontsize = 6.5 if own else 6.0
    xs = np.array([r[x] for r in rows], dtype=float)
    ys = np.array([r["nmse"] for r in rows], dtype=float)
    front = np.array([bool(r[front_key]) for r in rows], dtype=bool)
    knob = [_group(r) for r in rows]
    fams = [r.get("family") or family(r) for r in rows]
    kinds = sorted(set(knob) - {"default", "fitted"})
    cmap = plt.get_cmap("tab10")
    for i, kname in enumerate(kinds):
        for fam in sorted(set(fams)):
            sel = np.array([k == kname and f == fam for k, f in zip(knob, fams, strict=True)])
            if sel.any():
                ax.scatter(
                    xs[sel], ys[sel], s=18, color=cmap(i % 10), marker=family_marker(fam),
                    alpha=0.8,
                )  # fmt: skip
        ax.scatter([], [], s=18, color=cmap(i % 10), marker="o", label=kname, alpha=0.8)
    if len(set(fams)) > 1:  # the families' markers in the legend, grey
        for fam in sorted(set(fams), key=lambda f: FAMILIES.index(f) if f in FAMILIES else 99):
            ax.scatter([], [], s=18, color="0.5", marker=family_marker(fam), label=f"family {fam}")
    order = np.argsort(xs[front])
    ax.plot(xs[front][order], ys[front][order], "k--", lw=1, label="Pareto front")
    ax.scatter(xs[front], ys[front], s=60, facecolors="none", edgecolors="k")
    d = default_row(rows)
    if d is not None:
        ax.scatter([xs[d]], [ys[d]], s=140, marker="*", color="red", zorder=5, label="default")
    fitted = [i for i, k in enumerate(knob) if k == "fitted"]
    if fitted:
        ax.scatter(
            xs[fitted], ys[fitted], s=70, marker="D", color="k", zorder=5, label="fitted (--config)"
        )
    ax.axhline(metrics.NMSE_VISUALLY_IDENTICAL, lw=0)  # in the y limits before they freeze
    ax.set_yscale("log")
    if log_x:
        ax.set_xscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("NMSE vs exact Blinn (mean over scenes)")
    ax.grid(True, which="both", alpha=0.3)
    if legend:
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
    ax.set_xlim(ax.get_xlim())  # freeze the limits: the labels are placed in them
    ax.set_ylim(ax.get_ylim())
    markers = marker_boxes(ax, xs, ys, 60) + polyline_boxes(ax, xs[front][order], ys[front][order])
    if d is not None:
        markers += marker_boxes(ax, xs[d : d + 1], ys[d : d + 1], 140)
    avoid = [_threshold_line(ax, markers, fontsize)]
    labelled = sorted(set(np.flatnonzero(front)) | ({d} if d is not None else set()) | set(fitted))
    place_labels(
        ax,
        np.c_[xs[labelled], ys[labelled]],
        [point_label(rows[i]) for i in labelled],
        markers=markers,
        avoid=avoid,
        others=np.delete(np.c_[xs, ys], labelled, axis=0),
        fontsize=fontsize,
    )
    if own:
        fig.savefig(path)
        plt.close(fig)
        return path
    return None


PANELS = {
    "cycles": "NMSE against unit cycles per frame",
    "table_bits": "NMSE against ROM bits",
    "lut": "NMSE against LUTs",
    "hw_mpx_per_s": "NMSE against the hardware's Mpx/s",
    "px_per_clock_core": "NMSE against the core's pixels per clock",
}


def plot_axes(rows: list[dict]) -> list[str]:
    """The x axes a run plots: cycles, table bits, LUTs (when synthesised) and throughput."""
    has_lut = any(np.isfinite(float(r["lut"])) for r in rows)
    return ["cycles", "table_bits", *(["lut"] if has_lut else []), throughput_axis(rows)]


def plot_figure(rows: list[dict], path: Path) -> Path:
    """Every front (``plot_axes``) in a grid of two columns, small, one legend below them (the
    README's committed figure)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    xs = plot_axes(rows)
    n_rows = (len(xs) + 1) // 2
    fig, axes = plt.subplots(n_rows, 2, figsize=(10, 0.6 + 3.8 * n_rows), dpi=80, squeeze=False)
    bottom = 0.6 / (0.6 + 3.8 * n_rows) + 0.1 / n_rows
    fig.subplots_adjust(left=0.07, right=0.99, bottom=bottom, top=1 - 0.08 / n_rows, hspace=0.3)
    fig.subplots_adjust(wspace=0.18)
    flat = list(axes.flat)
    for x, ax in zip(xs, flat, strict=False):
        ax.set_title(PANELS[x], fontsize=10)
        plot_pareto(rows, x, ax=ax, legend=False)
    for ax in flat[len(xs) :]:
        ax.set_visible(False)
    handles, labels = {}, {}
    for ax in flat[: len(xs)]:
        for h, lab in zip(*ax.get_legend_handles_labels(), strict=True):
            handles.setdefault(lab, h)
            labels[lab] = lab
    fig.legend(list(handles.values()), list(labels), loc="lower center", ncol=7, fontsize=7)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    plt.close(fig)
    return path


PLOT_FILES = {
    "cycles": "pareto_cycles.png",
    "table_bits": "pareto_bits.png",
    "lut": "pareto_lut.png",
    "hw_mpx_per_s": "pareto_throughput.png",
    "px_per_clock_core": "pareto_throughput.png",
}


def write_outputs(
    results: list[dict],
    out_dir: Path,
    figure_dir: Path | None = None,
    refused: Sequence[str] = (),
) -> tuple[list[dict], list[Path]]:
    """results.csv, results.md, pareto_cycles.png, pareto_bits.png, pareto_lut.png (when
    synthesised), pareto_throughput.png (+ figure_dir's trade_pareto.png); ``refused``: the
    scenes the configuration files refused, for results.md."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    results = [{"part": "none", **dict.fromkeys(HW_FIELDS[1:], np.nan), **r} for r in results]
    rows = aggregate(results)
    written = [write_csv(results, out_dir / "results.csv")]
    md = out_dir / "results.md"
    md.write_text(format_markdown(rows, refused=refused))
    written.append(md)
    if rows:
        for x in plot_axes(rows):
            written.append(plot_pareto(rows, x, out_dir / PLOT_FILES[x]))
        if figure_dir is not None:
            written.append(plot_figure(rows, Path(figure_dir) / "trade_pareto.png"))
    return rows, written

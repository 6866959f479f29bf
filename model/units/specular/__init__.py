# SPDX-License-Identifier: Apache-2.0
"""Specular unit of patent UA 71489 (docs/specular.md): ``I = C * cos^k(a * zeta)`` per pixel.

Blinn's highlight ``cos^n(delta)`` along a scan line becomes, after the float set-up of the
"external device" (``setup_line``), ``C * cos^n(zeta)`` with an angle ``zeta`` that grows by a
constant ``dz`` per pixel.  The unit approximates ``cos^n(x) ~ cos^k(a * x)`` with one of a few
tables of ``cos^k`` (k chosen by a decoder from n) and a per-n scale ``a`` (ROM 9), so it needs
no power function: per pixel an add, a multiply, a table read and a multiply (fig. 1).

Formats (``SpecularConfig``, every value an integer in units of 2**-f):
* angles ``dz``, ``z0`` and the accumulator (register 8) in units of pi/2, two's complement,
  ``z_frac_bits`` fraction bits; ``dz``/``z0`` are ``z_int_bits + z_frac_bits`` wide, the
  accumulator ``len_width`` bits wider, so ``z0 + l*dz`` cannot wrap for any register values;
* ``a`` (ROM 9, one word per kept n = ``n_first..n_last``, by default 1..1000, at address
  n - n_first): unsigned Q``a_int_bits``.``a_frac_bits``; every other n gives n_err;
* the scaled angle ``|zeta| * a`` (multiplier 11) is rounded to ``rom_addr_bits`` fraction bits:
  that is the ROM-12 address inside the table of the decoded k; a value that rounds to 1 (pi/2)
  or more gives cos^k = 0 (overflow detected, never wrapped);
* ROM 12 words: ``round(cos^k(i/2**A * pi/2) * 2**D)``, saturated to ``2**D - 1`` (i = 0 would
  be exactly 2**D); D = ``rom_data_bits``;
* ``C``: unsigned Q``c_int_bits``.``c_frac_bits`` in output LSBs; the output is
  ``saturate(round(C * rom12 / 2**(c_frac_bits + D)), 0, 2**out_width - 1)``.

Named steps, in the order the RTL takes them: accumulate (exact), magnitude and saturation of
``|zeta|`` to ``mag_int_bits`` integer bits (invisible: every clamped value already gives 0),
multiply by a (exact), round to the address (add half, slice), overflow -> 0, table read,
multiply by C (exact), round (add half, slice), saturate.

Timing (``cycles``): a line of l intervals keeps ``busy`` high for ``FILL_LATENCY + l`` cycles;
the l + 1 results come one per clock at offsets ``FILL_LATENCY .. FILL_LATENCY + l`` after the
start edge, the last one together with busy = 0.

Modules, each importing only those above it: ``config`` (formats, constants, a(n), named
configurations), ``approx`` (the float approximation and its exact errors), ``roms`` (decoder,
ROM 9, ROM 12), ``datapath`` (the bit-exact unit, per line and batched), ``setup`` (the float
set-up of the external device), ``accuracy`` (exhaustive accuracy and the README's tables).
This file only re-exports: code outside the package imports ``model.units.specular``.
"""

from model.units.specular.accuracy import (
    N_RANGES,
    REL_FLOOR,
    SINGLE_TABLES,
    Accuracy,
    Worst,
    angle_drift_example,
    angle_drift_steps,
    approx_lsb_bound,
    fixed_point_accuracy,
    float_errors,
    format_accuracy_table,
    format_brdf_table,
    format_config_table,
    rom_rel_errors,
    single_table_worst,
)
from model.units.specular.approx import (
    ABS_ERROR_TOL,
    brdf_approx,
    brdf_max_abs_error,
    brdf_max_rel_error,
    cos_power_max_slope,
)
from model.units.specular.config import (
    ALPHA_MODES,
    DEFAULT,
    FILL_LATENCY,
    INFLECTION,
    KEPT,
    KEPT_CONFIGS,
    MAX_TABLES,
    N_MAX,
    N_WIDTH,
    NARROW,
    PATENT_K_RANGES,
    PROTOTYPE,
    PROTOTYPE_K_RANGES,
    ROM_CONFIGS,
    UP5K,
    SpecularConfig,
    alpha_value,
    epicentre,
    mag_int_bits_for,
    rom_path,
)
from model.units.specular.datapath import (
    cycles,
    line_angles,
    pixel_value,
    rom12_path_kernel,
    shade_line,
    shade_lines,
    unit_line,
    valid_offsets,
)
from model.units.specular.roms import (
    Tables,
    cos_table,
    decode_k,
    decode_k_patent9,
    n_valid,
    read_rom,
    rom9_image,
    rom9_words,
    rom12_words,
    rom_layout,
    rom_text,
    tables,
    write_roms,
)
from model.units.specular.setup import (
    MIN_NORM,
    LineSetup,
    LineSetups,
    blinn_line,
    half_vector_path,
    rotation_onto,
    setup_line,
    setup_lines,
    setup_row,
)

__all__ = [
    "ABS_ERROR_TOL",
    "ALPHA_MODES",
    "DEFAULT",
    "FILL_LATENCY",
    "INFLECTION",
    "KEPT",
    "KEPT_CONFIGS",
    "MAX_TABLES",
    "MIN_NORM",
    "NARROW",
    "N_MAX",
    "N_RANGES",
    "N_WIDTH",
    "PATENT_K_RANGES",
    "PROTOTYPE",
    "PROTOTYPE_K_RANGES",
    "REL_FLOOR",
    "ROM_CONFIGS",
    "SINGLE_TABLES",
    "UP5K",
    "Accuracy",
    "LineSetup",
    "LineSetups",
    "SpecularConfig",
    "Tables",
    "Worst",
    "alpha_value",
    "angle_drift_example",
    "angle_drift_steps",
    "approx_lsb_bound",
    "blinn_line",
    "brdf_approx",
    "brdf_max_abs_error",
    "brdf_max_rel_error",
    "cos_power_max_slope",
    "cos_table",
    "cycles",
    "decode_k",
    "decode_k_patent9",
    "epicentre",
    "fixed_point_accuracy",
    "float_errors",
    "format_accuracy_table",
    "format_brdf_table",
    "format_config_table",
    "half_vector_path",
    "line_angles",
    "mag_int_bits_for",
    "n_valid",
    "pixel_value",
    "read_rom",
    "rom9_image",
    "rom9_words",
    "rom12_path_kernel",
    "rom12_words",
    "rom_layout",
    "rom_path",
    "rom_rel_errors",
    "rom_text",
    "rotation_onto",
    "setup_line",
    "setup_lines",
    "setup_row",
    "shade_line",
    "shade_lines",
    "single_table_worst",
    "tables",
    "unit_line",
    "valid_offsets",
    "write_roms",
]

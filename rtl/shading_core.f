// SPDX-License-Identifier: Apache-2.0
// rtl/shading_core.f: the sources of shading_core for tools that read a file list (docs/core.md).
// Verilator: -F rtl/shading_core.f (paths relative to this file); Icarus: iverilog -c shading_core.f in rtl/.
// ROM images: $readmemh of `SHADING_ROM_DIR/<file>.hex, default "rom" (relative to the
// tool's working folder); see rtl/specular_unit.f for another folder.
divider_shift.v
specular_unit.v
brdf_unit.v
brdf_front.v
brdf_cosine_quadratic.v
brdf_quadratic.v
brdf_cubic.v
brdf_log2.v
brdf_piecewise.v
brdf_div.v
brdf_delay.v
brdf_mul.v
brdf_round.v
shading_rom.v
shading_increment.v
shading_specular_pipe.v
shading_brdf_word.v
shading_brdf_pipe.v
shading_axis_fifo.v
shading_core.v

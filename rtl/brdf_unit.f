// SPDX-License-Identifier: Apache-2.0
// rtl/brdf_unit.f: the sources of brdf_unit for tools that read a file list (docs/brdf_unit.md).
// Verilator: -F rtl/brdf_unit.f (paths relative to this file); Icarus: iverilog -c brdf_unit.f in rtl/.
// ROM images: $readmemh of `SHADING_ROM_DIR/<file>.hex, default "rom" (relative to the
// tool's working folder). For another folder add a define (the two tools quote differently):
//   Verilator: +define+SHADING_ROM_DIR=\"/abs/path/rtl/rom\"
//   Icarus:    +define+SHADING_ROM_DIR="/abs/path/rtl/rom"
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

// SPDX-License-Identifier: Apache-2.0
// rtl/specular_unit.f: the sources of specular_unit for tools that read a file list (docs/fpga.md).
// Verilator: -F rtl/specular_unit.f (paths relative to this file); Icarus: iverilog -c specular_unit.f in rtl/.
// ROM images: $readmemh of `SHADING_ROM_DIR/<file>.hex, default "rom" (relative to the
// tool's working folder). For another folder add a define (the two tools quote differently):
//   Verilator: +define+SHADING_ROM_DIR=\"/abs/path/rtl/rom\"
//   Icarus:    +define+SHADING_ROM_DIR="/abs/path/rtl/rom"
specular_unit.v
shading_rom.v

// SPDX-License-Identifier: Apache-2.0
// rtl/divider_shift.f: the sources of divider_shift for tools that read a file list (docs/fpga.md).
// Verilator: -F rtl/divider_shift.f (paths relative to this file); Icarus: iverilog -c divider_shift.f in rtl/.
// ROM images: $readmemh of `SHADING_ROM_DIR/<file>.hex, default "rom" (relative to the
// tool's working folder). For another folder add a define (the two tools quote differently):
//   Verilator: +define+SHADING_ROM_DIR=\"/abs/path/rtl/rom\"
//   Icarus:    +define+SHADING_ROM_DIR="/abs/path/rtl/rom"
divider_shift.v
shading_rom.v

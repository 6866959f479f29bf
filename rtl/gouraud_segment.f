// SPDX-License-Identifier: Apache-2.0
// rtl/gouraud_segment.f: the sources of gouraud_segment for tools that read a file list (docs/fpga.md).
// Verilator: -F rtl/gouraud_segment.f (paths relative to this file); Icarus: iverilog -c gouraud_segment.f in rtl/.
gouraud_segment.v

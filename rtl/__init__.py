# SPDX-License-Identifier: Apache-2.0
"""Package-data marker: rtl/ is installed as ``model.rtl`` (the Verilog and rom/*.hex), so the
model and the benches find it from any folder.  Not Verilog; FPGA users can ignore this file."""

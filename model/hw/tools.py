# SPDX-License-Identifier: Apache-2.0
"""Where the tools of the Python environment are: the one lookup ``make synth``, ``make formal``
and ``make gate`` share (the venv's own ``bin`` folder first, then ``PATH``)."""

from __future__ import annotations

import shutil
import sys
from pathlib import Path


def find_tool(name: str) -> str | None:
    """The path of the program ``name`` next to this Python (the venv's yowasp tools, z3), else
    on PATH; None if neither has it."""
    local = Path(sys.executable).parent / name
    return str(local) if local.exists() else shutil.which(name)

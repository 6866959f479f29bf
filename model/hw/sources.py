# SPDX-License-Identifier: Apache-2.0
"""The Verilog sources of a top, read from its ``.f`` source list (``rtl/<top>.f``): the one
list that simulation, synthesis, formal and the vector benches read, so that a top may span
files (verilog-axis' file lists).  A list names one file a line, relative to its own folder;
``//`` starts a comment."""

from __future__ import annotations

from pathlib import Path

from model.units import rom

RTL_DIR = rom.ROM_DIR.parent  # rtl/, installed as the package data model.rtl


def source_list(top: str, rtl_dir: Path = RTL_DIR) -> list[Path]:
    """The files ``rtl/<top>.f`` lists, in order, as absolute paths; a missing list or a listed
    file that does not exist raises, naming it."""
    listing = rtl_dir / f"{top}.f"
    if not listing.is_file():
        raise ValueError(f"top = {top!r} has no source list: {listing} does not exist")
    out = []
    for number, line in enumerate(listing.read_text().splitlines(), 1):
        text = line.split("//", 1)[0].strip()
        if not text:
            continue
        path = (listing.parent / text).resolve()
        if not path.is_file():
            raise ValueError(f"{listing}:{number}: {text} does not exist")
        out.append(path)
    if not out:
        raise ValueError(f"{listing} lists no source file")
    return out

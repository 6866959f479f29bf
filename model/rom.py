"""ROM images as ``$readmemh`` files: the one way tables travel from the model to the RTL."""

from __future__ import annotations

from pathlib import Path

import numpy as np

ROM_DIR = Path(__file__).resolve().parent.parent / "rtl" / "rom"


def hex_digits(width: int) -> int:
    return (width + 3) // 4


def format_hex(words: np.ndarray, width: int, header: str) -> str:
    """One word a line, zero-padded to the word width, after a ``//`` comment header.

    Negative words are written as their ``width``-bit two's-complement pattern.
    """
    mask = (1 << width) - 1
    lines = [f"// {line}" for line in header.splitlines()]
    digits = hex_digits(width)
    lines += [f"{int(w) & mask:0{digits}x}" for w in np.asarray(words).ravel()]
    return "\n".join(lines) + "\n"


def write_hex(path: Path, words: np.ndarray, width: int, header: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(format_hex(words, width, header))
    return path


def read_hex(path: Path) -> list[int]:
    """The words of a ``$readmemh`` file (comments and blank lines skipped)."""
    words = []
    for line in Path(path).read_text().splitlines():
        text = line.split("//", 1)[0].strip()
        if text:
            words.append(int(text, 16))
    return words

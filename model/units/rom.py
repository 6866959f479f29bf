# SPDX-License-Identifier: Apache-2.0
"""ROM images as ``$readmemh`` files: the one way tables travel from the model to the RTL.

An image (``format_image``) is a ``//`` comment header, the ``depth`` data words of the ROM (one
a line, ``width`` bits as exactly ``hex_digits(width)`` hex digits, address 0 first), then the
check words: 32-bit fields, each in ``chunks(width)`` words of ``width`` bits, low bits first, each
after a ``// name = value`` comment:

* ``magic``: the kind of ROM (``MAGIC``: ``"DIVR"``, ``"SR09"``, ``"SR12"``, ``"BRDA"``,
  ``"BRDC"``, ``"BRD3"``, ``"BRDP"``, ``"BRDL"`` in ASCII);
* ``depth``, ``width``: of the data words;
* the configuration the contents were built for, one field per RTL parameter
  (``KIND_FIELDS``; ``ALPHA`` as its index in ``ALPHA_NAMES``, a K of an unused table as 0);
* ``checksum``: FNV-1a (32 bits) over the data words, each split into 32-bit pieces, low first;
* ``end mark``: ``END_MARK`` (``"END!"``), so a truncated file never passes.

The RTL reads the whole image in simulation and compares every field with its own parameters at
time 0 (``rtl/*.v``, "ROM image check"); synthesis loads the data words only.  ``read_hex`` is
the model's strict loader: it names the file, the line, what it expected and what it found.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from importlib.resources import files
from pathlib import Path

import numpy as np

# rtl/ is installed as the package data ``model.rtl`` (the checkout's rtl/ under the editable
# install ``make setup`` makes, so ``make roms`` writes into the repository).
ROM_DIR = Path(str(files("model.rtl"))) / "rom"


def hex_digits(width: int) -> int:
    return (width + 3) // 4


def format_hex(words: np.ndarray, width: int, header: str) -> str:
    """One word a line, zero-padded to the word width, after a ``//`` comment header.

    Negative words are written as their ``width``-bit two's-complement pattern.  A ROM image
    for the RTL also needs its check words: use ``format_image``.
    """
    mask = (1 << width) - 1
    lines = [f"// {line}" for line in header.splitlines()]
    digits = hex_digits(width)
    lines += [f"{int(w) & mask:0{digits}x}" for w in np.asarray(words).ravel()]
    return "\n".join(lines) + "\n"


def _tag(text: str) -> int:
    """Four ASCII characters as a 32-bit word (Verilog's ``"DIVR"``)."""
    return int.from_bytes(text.encode("ascii"), "big")


MAGIC: dict[str, int] = {
    "divider_recip": _tag("DIVR"),
    "specular_a": _tag("SR09"),
    "specular_cos": _tag("SR12"),
    "brdf_angle": _tag("BRDA"),
    "brdf_coef": _tag("BRDC"),
    "brdf_cubic_coef": _tag("BRD3"),
    "brdf_piecewise_coef": _tag("BRDP"),
    "brdf_log2": _tag("BRDL"),
}
"""The first check field of each kind of image."""
END_MARK = _tag("END!")
KIND_FIELDS: dict[str, tuple[str, ...]] = {
    "divider_recip": ("K_WIDTH", "RECIP_BITS"),
    "specular_a": (
        *("A_INT_BITS", "A_FRAC_BITS", "ALPHA", "NUM_TABLES"),
        *("N_HI0", "N_HI1", "N_HI2", "N_HI3", "K0", "K1", "K2", "K3"),
    ),
    "specular_cos": ("ROM_ADDR_BITS", "ROM_DATA_BITS", "NUM_TABLES", "K0", "K1", "K2", "K3"),
    "brdf_angle": ("COS_ADDR_BITS", "COS_DATA_BITS", "TABLE"),
    "brdf_coef": ("FORM", "COEF_BITS", "COEF_FRAC_BITS"),
    "brdf_cubic_coef": (
        *("FORM", "COEF_BITS", "R_FRAC_BITS", "P0_FRAC_BITS", "B1_FRAC_BITS", "B2_FRAC_BITS"),
    ),
    "brdf_piecewise_coef": (
        *("FORM", "COEF_BITS", "R_FRAC_BITS", "P0_FRAC_BITS", "B1_FRAC_BITS", "B2_FRAC_BITS"),
        *("S2_FRAC_BITS", "BETA_FRAC_BITS"),
    ),
    "brdf_log2": ("LOG_ADDR_BITS", "LOG_DATA_BITS"),
}
"""The configuration fields of each kind, in image order: the RTL parameters they must equal."""
KIND_TITLES = {
    "divider_recip": "divider_shift reciprocal ROM",
    "specular_a": "specular_unit ROM 9 (a)",
    "specular_cos": "specular_unit ROM 12 (cos^k)",
    "brdf_angle": "brdf_unit angle table",
    "brdf_coef": "brdf_unit coefficient table",
    "brdf_cubic_coef": "brdf_unit cubic coefficient table",
    "brdf_piecewise_coef": "brdf_unit piecewise coefficient table",
    "brdf_log2": "brdf_unit log2 table",
}
ALPHA_NAMES = ("taylor", "inflection")
"""``ALPHA`` field values: the index of the mode (the RTL's ``ALPHA`` string parameter)."""
FORM_NAMES = ("quadratic", "cubic", "piecewise", "log2", "cosine_quadratic")
"""``FORM`` field values (the BRDF unit's coefficient table): the index of the form, in
``model.units.brdf.FORMS``' order (the RTL's ``FORM`` string parameter)."""
TABLE_NAMES = ("w", "log2cos")
"""``TABLE`` field values (the BRDF unit's angle table): 0 holds w = 1 - cos, 1 -log2 cos."""
FNV_OFFSET = 0x811C9DC5
FNV_PRIME = 0x01000193
_HEX = re.compile(r"[0-9a-fA-F]+")


class RomFileError(ValueError):
    """A ROM image that is missing, malformed or built for another configuration."""


def chunks(width: int) -> int:
    """Words of ``width`` bits that hold one 32-bit check field."""
    return -(-32 // width)


def checksum(words, width: int) -> int:
    """FNV-1a over the data words, each split into 32-bit pieces (low piece first)."""
    mask = (1 << width) - 1
    pieces = -(-width // 32)
    h = FNV_OFFSET
    for w in np.asarray(words).ravel().tolist():
        w &= mask
        for p in range(pieces):
            h = ((h ^ ((w >> (32 * p)) & 0xFFFFFFFF)) * FNV_PRIME) & 0xFFFFFFFF
    return h


@dataclass(frozen=True)
class RomLayout:
    """What an image must be: its kind, its data words and the configuration they were built for.

    ``config`` is ``((name, value), ...)`` in ``KIND_FIELDS[kind]`` order.
    """

    kind: str
    depth: int
    width: int
    config: tuple[tuple[str, int], ...]

    def __post_init__(self) -> None:
        if self.kind not in MAGIC:
            raise ValueError(f"kind = {self.kind!r} is out of range: legal are {tuple(MAGIC)}")
        names = tuple(name for name, _ in self.config)
        if names != KIND_FIELDS[self.kind]:
            raise ValueError(f"config fields {names} must be {KIND_FIELDS[self.kind]}")
        for name, value in (("depth", self.depth), ("width", self.width), *self.config):
            if not 0 <= value < 1 << 32:
                raise ValueError(f"{name} = {value} is out of range: legal is 0..2**32 - 1")
        if self.width < 1:
            raise ValueError(f"width = {self.width} is out of range: legal is 1 or more")

    @property
    def chunks(self) -> int:
        return chunks(self.width)

    @property
    def field_names(self) -> tuple[str, ...]:
        return ("magic", "depth", "width", *KIND_FIELDS[self.kind], "checksum", "end mark")

    @property
    def check_words(self) -> int:
        return len(self.field_names) * self.chunks

    @property
    def words(self) -> int:
        """Words in the file: data and check words."""
        return self.depth + self.check_words

    def fields(self, data_checksum: int) -> list[int]:
        values = [value for _, value in self.config]
        return [MAGIC[self.kind], self.depth, self.width, *values, data_checksum, END_MARK]

    def describe(self) -> str:
        config = ", ".join(f"{name} = {_field_text(name, v)}" for name, v in self.config)
        return (
            f"the {KIND_TITLES[self.kind]} image for {config}: {self.depth} data words + "
            f"{self.check_words} check words of {self.width} bits "
            f"({hex_digits(self.width)} hex digits each)"
        )


def _field_text(name: str, value: int) -> str:
    names = {"ALPHA": ALPHA_NAMES, "FORM": FORM_NAMES, "TABLE": TABLE_NAMES}.get(name, ())
    if 0 <= value < len(names):
        return f"{value} ({names[value]})"
    if name in ("magic", "end mark") and 0 <= value < 1 << 32:
        text = value.to_bytes(4, "big").decode("latin-1")
        return f"0x{value:08x} ({text!r})" if text.isprintable() else f"0x{value:08x}"
    if name == "checksum":
        return f"0x{value:08x}"
    return str(value)


def check_words(data, layout: RomLayout) -> list[int]:
    """The check words that follow ``data`` in the image of ``layout``."""
    out = []
    mask = (1 << layout.width) - 1
    for value in layout.fields(checksum(data, layout.width)):
        out += [(value >> (layout.width * c)) & mask for c in range(layout.chunks)]
    return out


def format_image(words, layout: RomLayout, header: str) -> str:
    """The ``$readmemh`` image of ``words``: the data words, then the check words."""
    data = np.asarray(words).ravel()
    if data.size != layout.depth:
        raise ValueError(f"{data.size} data words do not fit a depth of {layout.depth}")
    if data.size and (int(data.min()) < 0 or int(data.max()) >> layout.width):
        raise ValueError(f"a data word does not fit in {layout.width} bits (unsigned)")
    digits = hex_digits(layout.width)
    lines = [format_hex(data, layout.width, header).rstrip("\n")]
    lines.append(
        f"// check words (model.rom): {len(layout.field_names)} fields of 32 bits, "
        f"{layout.chunks} word(s) each, low bits first"
    )
    check = check_words(data, layout)
    values = layout.fields(checksum(data, layout.width))
    for f, (name, value) in enumerate(zip(layout.field_names, values, strict=True)):
        lines.append(f"// {name} = {_field_text(name, value)}")
        lines += [f"{w:0{digits}x}" for w in check[f * layout.chunks : (f + 1) * layout.chunks]]
    return "\n".join(lines) + "\n"


def _field_values(values: list[int], width: int, n_fields: int) -> list[int]:
    """The 32-bit (or wider, if malformed) fields of the check words ``values``."""
    c = chunks(width)
    return [
        sum(v << (width * i) for i, v in enumerate(values[f * c : (f + 1) * c]))
        for f in range(n_fields)
    ]


def _identify(values: list[int], digits: int) -> RomLayout | None:
    """The layout the image's own check words describe, if they are well formed."""
    for width in range(max(1, 4 * digits - 3), 4 * digits + 1):
        for kind, names in KIND_FIELDS.items():
            n_fields = len(names) + 5
            n_check = n_fields * chunks(width)
            if len(values) < n_check:
                continue
            fields = _field_values(values[-n_check:], width, n_fields)
            if (
                fields[0] == MAGIC[kind]
                and fields[-1] == END_MARK
                and fields[1] == len(values) - n_check
                and fields[2] == width
                and all(v < 1 << 32 for v in fields)
            ):
                return RomLayout(
                    kind, fields[1], width, tuple(zip(names, fields[3:-2], strict=True))
                )
    return None


def read_hex(path: Path, layout: RomLayout) -> list[int]:
    """The data words of the image at ``path``, checked against ``layout``.

    Raises ``RomFileError`` naming the file, the line, what was expected and what was found for
    a missing, empty, non-hex, over-wide, truncated or too long file, a bad checksum, and an
    image built for another configuration.  Comments (``//``) and blank lines are skipped.
    """
    path = Path(path)
    digits = hex_digits(layout.width)
    mask = (1 << layout.width) - 1
    want = f"this configuration needs {layout.describe()}"
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as err:
        why = getattr(err, "strerror", None) or str(err)
        raise RomFileError(
            f"{path}: cannot read the ROM image ({why}); {want}; `make roms` writes it"
        ) from None
    tokens = [
        (number, token)
        for number, line in enumerate(text.splitlines(), 1)
        for token in line.split("//", 1)[0].split()
    ]
    if not tokens:
        raise RomFileError(f"{path}: empty, no words found; {want}")
    for i, (number, token) in enumerate(tokens):
        if not _HEX.fullmatch(token):
            bad = next(ch for ch in token if ch not in "0123456789abcdefABCDEF")
            raise RomFileError(
                f"{path}:{number}: word {i} is {token!r}, not hex ({bad!r}): expected {digits} "
                f"hex digits (a {layout.width}-bit word); {want}"
            )
    values = [int(token, 16) for _, token in tokens]
    found = _identify(values, len(tokens[-1][1]))
    if found is not None and found != layout:
        names = ("kind", "depth", "width", *(n for n, _ in found.config))
        ours = (layout.kind, layout.depth, layout.width, *(v for _, v in layout.config))
        theirs = (found.kind, found.depth, found.width, *(v for _, v in found.config))
        name, a, b = next((n, a, b) for n, a, b in zip(names, theirs, ours, strict=True) if a != b)
        number = tokens[found.depth][0]
        raise RomFileError(
            f"{path}:{number}: built for another configuration ({name} = {a}, expected {b}): "
            f"found {found.describe()}; {want}"
        )
    for i, (number, token) in enumerate(tokens):
        if len(token) != digits or values[i] > mask:
            why = (
                f"only {len(token)} hex digit{'s' if len(token) > 1 else ''}"
                if len(token) < digits and values[i] <= mask
                else f"wider than {layout.width} bits"
            )
            raise RomFileError(
                f"{path}:{number}: word {i} is {token!r}, {why}: expected {digits} hex digits, "
                f"at most {mask:0{digits}x} (a {layout.width}-bit word); {want}"
            )
    if len(tokens) < layout.words:
        hint = ""
        if len(tokens) == layout.depth:
            hint = " (the data words without check words: an image older than the checks)"
        raise RomFileError(
            f"{path}:{tokens[-1][0]}: truncated: the file ends after {len(tokens)} words{hint}; "
            f"{want} = {layout.words} words"
        )
    if len(tokens) > layout.words:
        raise RomFileError(
            f"{path}:{tokens[layout.words][0]}: too long: word {layout.words} is past the end "
            f"of the image ({len(tokens)} words found); {want} = {layout.words} words"
        )
    data = values[: layout.depth]
    fields = _field_values(values[layout.depth :], layout.width, len(layout.field_names))
    expected = layout.fields(checksum(data, layout.width))
    for f, (name, expect) in enumerate(zip(layout.field_names, expected, strict=True)):
        if fields[f] != expect:
            number = tokens[layout.depth + f * layout.chunks][0]
            why = (
                "a data word was changed after the image was written"
                if name == "checksum"
                else "not an image of this configuration"
            )
            raise RomFileError(
                f"{path}:{number}: check field {name} is {_field_text(name, fields[f])}, "
                f"expected {_field_text(name, expect)} ({why}); {want}"
            )
    return data

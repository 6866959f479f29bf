# SPDX-License-Identifier: Apache-2.0
"""Specular unit: the decoder (block 10), ROM 9 (a per n) and ROM 12 (the cos^k tables).

Owns what the decoder answers (``decode_k``, ``decode_k_patent9``, ``n_valid``), the ROM
contents (``rom9_words``, ``rom9_image``, ``cos_table``, ``rom12_words``), their ``$readmemh``
images (``rom_layout``, ``rom_text``, ``read_rom``, ``write_roms``) and ``tables``: one
configuration's ROMs and datapath constants, computed once, that the datapath kernels and the
accuracy walk read.  May import numpy, ``model.units.fixed``, ``rom`` and ``config``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from model.units import fixed, rom
from model.units.specular.config import (
    DEFAULT,
    KEPT_CONFIGS,
    MAX_TABLES,
    N_MAX,
    N_WIDTH,
    ROM_CONFIGS,
    SpecularConfig,
    a_words,
    rom_path,
)


# ==================================================================== decoder and ROMs
def _table_index(n: np.ndarray, cfg: SpecularConfig) -> np.ndarray:
    """Index of the k range holding each n (0 for n outside 1..1000, flagged by n_err)."""
    idx = np.zeros(np.shape(n), dtype=np.int64)
    for j, (lo, hi, _) in enumerate(cfg.k_ranges):
        idx = np.where((n >= lo) & (n <= hi), j, idx)
    return idx


def decode_k(n, cfg: SpecularConfig = DEFAULT):
    """The decoder (block 10): k of the cos^k table used for n = 1..1000 (10-bit n).

    The patent's decoder has 9 inputs n1..n9 "because n = 1..1000", but 1000 needs 10 bits: a
    9-bit decoder sees n mod 512 and aliases every n >= 512 (see ``decode_k_patent9``).  This
    unit decodes all 10 bits.
    """
    n_arr = fixed.check_operand("n", n, 1, N_MAX)
    k = np.asarray(cfg.ks, dtype=np.int64)[_table_index(n_arr, cfg)]
    return int(k) if k.ndim == 0 else k


def decode_k_patent9(n, cfg: SpecularConfig = DEFAULT):
    """What the patent's 9-input decoder would give for a 10-bit n: k of (n mod 512), 0 = none.

    For n >= 512 it answers for n - 512: n = 513 gets the cos table (k = 1) instead of cos^16,
    and n = 512 gets no table at all.
    """
    n_arr = fixed.check_operand("n", n, 0, (1 << N_WIDTH) - 1) & 511
    k = np.where(n_arr >= 1, np.asarray(cfg.ks, dtype=np.int64)[_table_index(n_arr, cfg)], 0)
    return int(k) if k.ndim == 0 else k


def n_valid(n: int, cfg: SpecularConfig = DEFAULT) -> bool:
    """Whether the unit accepts n (the kept range n_first..n_last, by default 1..1000);
    otherwise it outputs 0 with n_err = 1."""
    return cfg.n_first <= n <= cfg.n_last


def rom9_words(cfg: SpecularConfig = DEFAULT) -> np.ndarray:
    """a = round(alpha_value(n, k) * 2**a_frac_bits) indexed by the 10-bit n (1024 words), 0 for
    every n the unit refuses; ROM 9 holds words n_first..n_last of it (``rom9_image``)."""
    return a_words(cfg)


def rom9_image(cfg: SpecularConfig = DEFAULT) -> np.ndarray:
    """ROM 9's contents: the a word of n = n_first..n_last at address n - n_first."""
    return a_words(cfg)[cfg.n_first : cfg.n_last + 1]


def cos_table(k: int, addr_bits: int, data_bits: int) -> np.ndarray:
    """One ROM-12 table: round(cos^k(i/2**A * pi/2) * 2**D) saturated to 2**D - 1, i < 2**A."""
    x = np.arange(1 << addr_bits, dtype=np.float64) * (np.pi / 2) / 2**addr_bits
    words = np.floor(np.cos(x) ** k * 2.0**data_bits + 0.5).astype(np.int64)
    return np.minimum(words, (1 << data_bits) - 1)


def rom12_words(cfg: SpecularConfig = DEFAULT) -> np.ndarray:
    """ROM 12: the tables of cfg.ks one after the other (address = {table, angle}), 0-padded
    to 2**tsel_bits tables."""
    size = 1 << cfg.rom_addr_bits
    words = np.zeros(size << cfg.tsel_bits, dtype=np.int64)
    for j, k in enumerate(cfg.ks):
        words[j * size : (j + 1) * size] = cos_table(k, cfg.rom_addr_bits, cfg.rom_data_bits)
    return words


def rom_layout(cfg: SpecularConfig = DEFAULT, which: str = "a") -> rom.RomLayout:
    """The image of ROM 9 (``which="a"``) or ROM 12 (``"cos"``) and the RTL parameters its
    contents depend on (``rom.KIND_FIELDS``)."""
    ks = tuple(zip(("K0", "K1", "K2", "K3"), cfg.rom_ks, strict=True))
    if which == "a":
        hi = (*cfg.n_hi, *(N_MAX,) * (MAX_TABLES - cfg.num_tables))
        config = (
            ("A_INT_BITS", cfg.a_int_bits),
            ("A_FRAC_BITS", cfg.a_frac_bits),
            ("ALPHA", rom.ALPHA_NAMES.index(cfg.alpha)),
            ("NUM_TABLES", cfg.num_tables),
            *zip(("N_HI0", "N_HI1", "N_HI2", "N_HI3"), hi, strict=True),
            *ks,
        )
        return rom.RomLayout("specular_a", cfg.rom9_depth, cfg.a_width, config)
    if which == "cos":
        config = (
            ("ROM_ADDR_BITS", cfg.rom_addr_bits),
            ("ROM_DATA_BITS", cfg.rom_data_bits),
            ("NUM_TABLES", cfg.num_tables),
            *ks,
        )
        depth = 1 << (cfg.tsel_bits + cfg.rom_addr_bits)
        return rom.RomLayout("specular_cos", depth, cfg.rom_data_bits, config)
    raise ValueError(f"which = {which!r} is out of range: legal are 'a', 'cos'")


def read_rom(cfg: SpecularConfig = DEFAULT, which: str = "a", path=None) -> list[int]:
    """The data words of the image at ``path`` (default ``rom_path(cfg, which)``), checked
    against ``cfg`` (``rom.read_hex``: a bad or foreign image raises ``rom.RomFileError``).
    The header has no field for ROM 9's kept range (its depth only), so, as the RTL does, the
    first and last words must be a of n_first and n_last."""
    path = rom_path(cfg, which) if path is None else path
    words = rom.read_hex(path, rom_layout(cfg, which))
    if which == "a":
        want = rom9_image(cfg)
        for i, n in ((0, cfg.n_first), (-1, cfg.n_last)):
            if words[i] != want[i]:
                raise rom.RomFileError(
                    f"{path}: data word {i % len(words)} is {words[i]}, expected {want[i]} (a of "
                    f"n = {n}): not the ROM 9 image of n_first = {cfg.n_first}, n_last = "
                    f"{cfg.n_last}; `make roms` writes it"
                )
    return words


def rom_text(cfg: SpecularConfig = DEFAULT, which: str = "a") -> str:
    """The ``$readmemh`` image of ROM 9 (``which="a"``) or ROM 12 (``which="cos"``)."""
    ranges = ", ".join(f"{lo}..{hi} -> k = {k}" for lo, hi, k in cfg.k_ranges)
    if which == "a":
        header = (
            f"specular_unit ROM 9: a(n) for n = {cfg.n_first}..{cfg.n_last} at address "
            f"n - {cfg.n_first} ({cfg.alpha}), unsigned Q{cfg.a_int_bits}.{cfg.a_frac_bits}\n"
            f"k ranges: {ranges}; every other n has no word (n_err). Generated by model.specular."
        )
        return rom.format_image(rom9_image(cfg), rom_layout(cfg, "a"), header)
    if which == "cos":
        header = (
            f"specular_unit ROM 12: cos^k(i/2^{cfg.rom_addr_bits} * pi/2) * 2^{cfg.rom_data_bits}"
            f" (saturated), tables k = {', '.join(map(str, cfg.ks))}\n"
            f"address = {{table ({cfg.tsel_bits} bits), i ({cfg.rom_addr_bits} bits)}}; "
            "unused tables hold 0. Generated by model.specular."
        )
        return rom.format_image(rom12_words(cfg), rom_layout(cfg, "cos"), header)
    raise ValueError(f"which = {which!r} is out of range: legal are 'a', 'cos'")


def write_roms() -> list[Path]:
    """Write ROM 9 and ROM 12 of every configuration in ``ROM_CONFIGS`` and ``KEPT_CONFIGS`` to
    rtl/rom/."""
    paths = []
    for cfg in (*ROM_CONFIGS.values(), *KEPT_CONFIGS.values()):
        for which in ("a", "cos"):
            path = rom_path(cfg, which)
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(rom_text(cfg, which))
            paths.append(path)
    return list(dict.fromkeys(paths))


# ==================================================================== one configuration's tables
class Tables:
    """ROM contents and derived constants of one configuration, computed once.

    ``rom9`` (0 for every n outside n_first..n_last) and ``tsel`` (the decoded table of each
    10-bit n, 0 for invalid n) are indexed by n; ``pixel_args`` are the arguments
    ``datapath.pixels_kernel`` takes after (acc, c, a_word, tsel), the first four of them also
    those of ``rom12_path_kernel``.
    """

    def __init__(self, cfg: SpecularConfig) -> None:
        self.rom9 = rom9_words(cfg)
        self.rom12 = rom12_words(cfg)
        self.mag_max = (1 << cfg.mag_width) - 1
        self.tsel = np.zeros(1 << N_WIDTH, dtype=np.int64)
        self.tsel[1 : N_MAX + 1] = _table_index(np.arange(1, N_MAX + 1), cfg)
        # What ``pixels_kernel`` needs after (acc, c, a_word, tsel): ROM 12 and the shifts.
        self.pixel_args = (
            self.rom12,
            self.mag_max,
            cfg.addr_shift,
            cfg.rom_addr_bits,
            cfg.c_frac_bits + cfg.rom_data_bits,
            cfg.out_max,
        )


_TABLES: dict[SpecularConfig, Tables] = {}


def tables(cfg: SpecularConfig) -> Tables:
    """The ``Tables`` of ``cfg`` (built on first use, then shared)."""
    if cfg not in _TABLES:
        _TABLES[cfg] = Tables(cfg)
    return _TABLES[cfg]

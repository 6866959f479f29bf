# SPDX-License-Identifier: Apache-2.0
"""Contract sentences of the specular unit (docs/specular.md) that no other test checked.

Each test names the sentence it holds the model (or the benches' expectation) to; the table in
docs/specular.md points every sentence of the contract at its test.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from model.units import rom, specular
from model.units.specular import DEFAULT, N_MAX, SpecularConfig
from sim import soak, units
from tests.contract_protocol import Drive, column, ones

CONFIGS = list(specular.ROM_CONFIGS.items()) + list(specular.KEPT_CONFIGS.items())
IDS = [name for name, _ in CONFIGS]
BENCH_CONFIGS = [("default", specular.DEFAULT), ("narrow", specular.NARROW)]
PATENT_K = {1: 1, 2: 2, **dict.fromkeys(range(3, 7), 4), **dict.fromkeys(range(7, 1001), 16)}


# ------------------------------------------------------------------------ formats
def test_default_formats_are_the_documented_ones() -> None:
    """Formats table, defaults: C unsigned Q8.8; dz, z0 signed Q3.26 ([-4, 4) x pi/2); the
    accumulator LEN_WIDTH bits wider than dz (40 bits); n 10 bits; l = 0..2047 (lines up to
    2048 pixels); a unsigned Q3.14; ROM 12 4096 words of 16 bits per table; intensity 8 bits;
    abs(zeta) saturated to 1 integer bit, so multiplier 11 is 27 x 17 bits; a frozen dataclass."""
    cfg = DEFAULT
    assert cfg.c_format.describe() == "unsigned Q8.8"
    assert cfg.z_format.describe() == "signed Q3.26"
    one = 1 << cfg.z_frac_bits  # pi/2
    assert (cfg.z_format.lo, cfg.z_format.hi) == (-4 * one, 4 * one - 1)
    assert cfg.acc_width == cfg.z_width + cfg.len_width == 40
    assert specular.N_WIDTH == 10 and units.spec(cfg).operand("n").width == 10
    assert cfg.len_max == 2047 and specular.shade_line(0, 0, 0, 5, cfg.len_max).size == 2048
    assert (cfg.a_int_bits, cfg.a_frac_bits, cfg.a_width) == (3, 14, 17)
    assert (1 << cfg.rom_addr_bits, cfg.rom_data_bits, cfg.out_width) == (4096, 16, 8)
    assert (cfg.mag_int_bits, cfg.mag_width) == (1, 27)
    assert dataclasses.is_dataclass(SpecularConfig)
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.out_width = 6  # type: ignore[misc]


@pytest.mark.parametrize(("name", "cfg"), BENCH_CONFIGS, ids=[n for n, _ in BENCH_CONFIGS])
def test_ports_are_the_documented_ones(name: str, cfg: SpecularConfig) -> None:
    """Ports table: c_in C_INT_BITS+C_FRAC_BITS, dz_in and z0_in Z_INT_BITS+Z_FRAC_BITS (signed),
    n_in 10, len_in LEN_WIDTH, intensity OUT_WIDTH (held), n_err 1 (a held flag): the widths
    the benches check the RTL's ports against; every operand register resets to 0."""
    spec = units.spec(cfg)
    z = cfg.z_int_bits + cfg.z_frac_bits
    ops = {p.name: (p.width, p.signed, p.reset) for p in spec.operands}
    assert ops == {
        "c": (cfg.c_int_bits + cfg.c_frac_bits, False, 0),
        "dz": (z, True, 0),
        "z0": (z, True, 0),
        "n": (10, False, 0),
        "len": (cfg.len_width, False, 0),
    }
    outs = {p.name: (p.width, p.kind) for p in spec.outputs}
    assert outs == {"intensity": (cfg.out_width, "data"), "n_err": (1, "flag")}


@pytest.mark.parametrize(("name", "cfg"), CONFIGS, ids=IDS)
def test_parameters_are_the_documented_ones(name: str, cfg: SpecularConfig) -> None:
    """Contract: "Parameters: C_INT_BITS ... OUT_WIDTH (the config fields), NUM_TABLES (1..4) and
    N_HI0..N_HI3 (the decoder), MAG_INT_BITS (derived by the model), N_FIRST and N_LAST (the kept
    range), A_ROM_FILE and COS_ROM_FILE (named ...). cfg.hdl_parameters() gives them all for a
    configuration." (It also gives K0..K3
    and ALPHA, which the RTL header documents: checks only.)"""
    params = cfg.hdl_parameters()
    fields = [
        "c_int_bits",
        "c_frac_bits",
        "z_int_bits",
        "z_frac_bits",
        "len_width",
        "a_int_bits",
        "a_frac_bits",
        "rom_addr_bits",
        "rom_data_bits",
        "out_width",
        "n_first",
        "n_last",
    ]
    for f in fields:
        assert params[f.upper()] == getattr(cfg, f), f
    assert 1 <= params["NUM_TABLES"] == len(cfg.k_ranges) <= 4
    hi = [params[f"N_HI{j}"] for j in range(4)]
    assert hi[: cfg.num_tables] == [r[1] for r in cfg.k_ranges]
    assert params["MAG_INT_BITS"] == cfg.mag_int_bits
    kept = "" if (cfg.n_first, cfg.n_last) == (1, N_MAX) else f"_keep{cfg.n_first}-{cfg.n_last}"
    a_rom = f"specular_a_{cfg.alpha}_{cfg.rom_tag}_q{cfg.a_int_bits}.{cfg.a_frac_bits}{kept}.hex"
    ks = "-".join(str(k) for k in cfg.ks)
    cos_rom = f"specular_cos_k{ks}_a{cfg.rom_addr_bits}_d{cfg.rom_data_bits}.hex"
    for key, file in (("A_ROM_FILE", a_rom), ("COS_ROM_FILE", cos_rom)):
        path = rom.ROM_DIR / file
        assert params[key] == str(path) and path.exists(), key
        assert path.parent.name == "rom" and path.parent.parent.name == "rtl"
    documented = {f.upper() for f in fields} | {"NUM_TABLES", "MAG_INT_BITS"}
    documented |= {f"N_HI{j}" for j in range(4)} | {"A_ROM_FILE", "COS_ROM_FILE"}
    assert set(params) - documented == {"K0", "K1", "K2", "K3", "ALPHA"}
    five = (*((n, n, 1) for n in range(1, 5)), (5, 1000, 16))
    for ranges in ((), five):
        with pytest.raises(ValueError, match=r"k_ranges has \d entries: out of range"):
            SpecularConfig(k_ranges=ranges)


# ------------------------------------------------------------------------ the ROMs
@pytest.mark.parametrize(("name", "cfg"), CONFIGS, ids=IDS)
def test_rom9_holds_round_a_for_every_n(name: str, cfg: SpecularConfig) -> None:
    """Contract: "a (ROM 9, one word per kept n = N_FIRST..N_LAST at address n - N_FIRST: 1000
    words by default): unsigned Q A_INT_BITS.A_FRAC_BITS, round(a 2^14) [a = sqrt(n/k) for the
    patent's taylor a]; no word for n = 0, n > 1000 or a dropped n": every word of the committed
    image."""
    words = specular.read_rom(cfg, "a")
    assert len(words) == cfg.n_last - cfg.n_first + 1 == (N_MAX if name != "kept" else 24)
    for n in range(cfg.n_first, cfg.n_last + 1):
        k = specular.decode_k(n, cfg)
        a = math.sqrt(n / k) if cfg.alpha == "taylor" else specular.alpha_value(n, k, cfg.alpha)
        assert words[n - cfg.n_first] == math.floor(a * 2**cfg.a_frac_bits + 0.5), n
        assert words[n - cfg.n_first] < 1 << cfg.a_width


@pytest.mark.parametrize(("name", "cfg"), CONFIGS, ids=IDS)
def test_rom12_holds_every_cos_k_word(name: str, cfg: SpecularConfig) -> None:
    """Contract: "ROM 12: 2^ROM_ADDR_BITS words per table, ROM_DATA_BITS bits: round(cos^k(i 2^-A
    pi/2) 2^D), the 1.0 of i = 0 saturated to 2^D - 1": every word of every table of the
    committed image, computed here with math.cos; the unused tables hold 0. Not only i = 0 rounds
    to 2^D: the first few words of each table do too (i = 0..10 for k = 1 by default), and are
    saturated the same way."""
    words = specular.read_rom(cfg, "cos")
    size, full = 1 << cfg.rom_addr_bits, (1 << cfg.rom_data_bits) - 1
    for j, k in enumerate(cfg.ks):
        table = words[j * size : (j + 1) * size]
        assert table[0] == full, k
        saturated = 0
        for i in range(size):
            exact = math.floor(math.cos(i * math.pi / 2 / size) ** k * 2**cfg.rom_data_bits + 0.5)
            assert table[i] == min(exact, full), (k, i)
            saturated += exact > full
        assert saturated >= 1
    assert not any(words[len(cfg.ks) * size :])


@pytest.mark.parametrize(("name", "cfg"), CONFIGS, ids=IDS)
def test_mag_int_bits_is_the_smallest_width_that_reaches_pi_over_2(
    name: str, cfg: SpecularConfig
) -> None:
    """Contract: "abs(zeta) saturated to MAG_INT_BITS integer bits (the smallest width at which
    every clamped value times the smallest a of any kept n already reaches pi/2, so the clamp
    never changes a result)"."""
    a_min = int(specular.rom9_words(cfg)[cfg.n_first : cfg.n_last + 1].min())
    one = 1 << (cfg.z_frac_bits + cfg.a_frac_bits)  # pi/2 in the product's units

    def reaches(m: int) -> bool:
        return a_min * ((1 << (m + cfg.z_frac_bits)) - 1) >= one

    m = cfg.mag_int_bits
    assert reaches(m) and (m == 0 or not reaches(m - 1))
    # ... and a clamped value does give 0 for every n: the address rounds to pi/2 or beyond.
    mag_max = (1 << cfg.mag_width) - 1
    for n in (1, 2, 3, 7, 17, 40, N_MAX):
        if specular.n_valid(n, cfg):
            assert not specular.shade_line(cfg.c_format.hi, 0, mag_max, n, 0, cfg).any()


# ------------------------------------------------------------------------ timing (bench model)
@pytest.mark.parametrize(("name", "cfg"), BENCH_CONFIGS, ids=[n for n, _ in BENCH_CONFIGS])
def test_bench_expects_the_documented_timing(name: str, cfg: SpecularConfig) -> None:
    """Contract: "After the edge that accepts start, busy is high for cycles(l) = 8 + l cycles
    and valid is high in cycles 8 .. 8 + l: l + 1 results, one per clock, ..., the last together
    with busy = 0"; an n outside 1..1000 runs "with the same timing, every pixel 0 with n_err =
    1"."""
    c = cfg.c_format.hi
    for length in sorted({0, 1, 3, 17, cfg.len_max}):
        for n in (40, 0, 1001, 1023):
            d = Drive(cfg)
            d.reset()
            after = d.job(c=c, dz=3 << 10, z0=-(1 << 14), n=n, len=length)
            busy = 8 + length
            assert specular.FILL_LATENCY == 8 and specular.cycles(length, cfg) == busy
            assert column(after, "busy") == [1] * busy + [0] * (len(after) - busy)
            assert ones(column(after, "valid")) == list(range(8, 8 + length + 1))
            got = [after[i]["intensity"] for i in range(8, 9 + length)]
            flags = {after[i]["n_err"] for i in range(8, 9 + length)}
            if n == 40:
                values = specular.shade_line(c, 3 << 10, -(1 << 14), 40, length, cfg)
                assert got == values.tolist() and flags == {0}
            else:
                assert got == [0] * (length + 1) and flags == {1}


def test_kept_range_drops_every_other_n_like_an_invalid_n() -> None:
    """Contract: "n_first and n_last (N_FIRST, N_LAST): ROM 9 holds a for n_first..n_last only;
    every other n runs with the same timing, every pixel 0 with n_err = 1; 1 <= n_first <=
    n_last <= 1000, else ValueError naming the field, its value and the legal range;
    mag_int_bits (and the largest a's check) take the kept range only"."""
    cfg, c = specular.KEPT, specular.KEPT.c_format.hi
    for n in (0, 1, 16, 17, 40, 41, 1000, 1023):
        kept = cfg.n_first <= n <= cfg.n_last
        assert specular.n_valid(n, cfg) == kept and specular.n_valid(n) == (1 <= n <= N_MAX)
        d = Drive(cfg)
        d.reset()
        after = d.job(c=c, dz=3 << 6, z0=-(1 << 9), n=n, len=5)
        assert column(after, "busy") == [1] * 13 + [0] * (len(after) - 13)
        got = [after[i]["intensity"] for i in range(8, 14)]
        assert {after[i]["n_err"] for i in range(8, 14)} == {int(not kept)}, n
        want, n_err = specular.unit_line(c, 3 << 6, -(1 << 9), n, 5, cfg)
        assert got == want.tolist() and n_err == int(not kept), n
        assert any(got) == kept, n  # a kept n lights the peak; a dropped one gives zeros
        if not kept and 1 <= n <= N_MAX:
            with pytest.raises(ValueError, match=rf"n = {n} is out of range: legal .*17\.\.40"):
                specular.shade_line(c, 0, 0, n, 0, cfg)
    for fields, message in (
        ({"n_first": 0}, "n_first = 0 is out of range: legal is 1..1000"),
        ({"n_first": 1001}, "n_first = 1001 is out of range: legal is 1..1000"),
        ({"n_last": 1001}, r"n_last = 1001 is out of range: legal is 1..1000"),
        ({"n_first": 9, "n_last": 8}, r"n_last = 8 is out of range: legal is 9..1000"),
    ):
        with pytest.raises(ValueError, match=message):
            SpecularConfig(**fields)
    # a grows with n: without n < 17 the smallest a is sqrt(17/16) > 1, and |zeta| needs no
    # integer bit; without n > 40 the largest a is sqrt(40/16) = 1.58, which Q2.x holds
    assert (DEFAULT.mag_int_bits, SpecularConfig(n_first=17).mag_int_bits) == (1, 0)
    with pytest.raises(ValueError, match="a_int_bits = 2 is out of range"):
        SpecularConfig(a_int_bits=2)
    assert SpecularConfig(a_int_bits=2, n_last=40).rom9_bits == 40 * 16


def test_back_to_back_line_clocks() -> None:
    """Contract: "back-to-back lines take l + 9 clocks each: 2056 clocks for a 2048-pixel line,
    12 for the four pixels of fig. 11 (l = 3)": start held high, results every l + 9 edges."""
    assert specular.cycles(2047) + 1 == 2056 and specular.cycles(3) + 1 == 12
    for length in (0, 3, 10):
        d = Drive(DEFAULT)
        d.reset()
        d.edge(c=255 << 8, dz=1 << 12, z0=0, n=9, len=length)
        first = len(d.outputs)
        period = length + 9
        for _ in range(4 * period):
            d.edge(start=1)
        valids = ones(column(d.outputs[first:], "valid"))
        assert valids == [period * j + 8 + i for j in range(4) for i in range(length + 1)]
        assert d.model.stats.back_to_back == 3


def test_bench_expects_reset_to_clear_and_outputs_held() -> None:
    """Reset aborts the line (busy, valid and n_err 0) and clears the operand registers: a start
    right after it is one pixel with n = 0 (0 with n_err = 1); between results intensity and
    n_err hold the last result."""
    d = Drive(DEFAULT)
    d.reset()
    d.edge(c=255 << 8, dz=0, z0=0, n=5, len=30)
    d.edge(start=1)
    d.idle(7)
    out = d.edge(rst_n=0)
    assert (out["busy"], out["valid"], out["n_err"], out["intensity"]) == (0, 0, 0, None)
    after = d.job(tail=8)
    assert d.model.last_job.operands == {"c": 0, "dz": 0, "z0": 0, "n": 0, "len": 0}
    assert ones(column(after, "valid")) == [8]
    assert all((o["intensity"], o["n_err"]) == (0, 1) for o in after[8:])
    line = d.job(tail=8, c=255 << 8, dz=0, z0=0, n=5, len=2)
    assert all((o["intensity"], o["n_err"]) == (0, 1) for o in line[:8])  # the last result
    assert all((o["intensity"], o["n_err"]) == (255, 0) for o in line[8:])


# ------------------------------------------------------------------------ set-up
def random_unit(rng) -> np.ndarray:
    v = rng.normal(size=3)
    return v / np.linalg.norm(v)


def test_c_is_light_times_full_scale_times_a_to_the_n() -> None:
    """Contract: "c (register 1) ... in output LSBs: C = I_l k_s A^n (2^OUT_WIDTH - 1)"; "C
    beyond the register saturates"; dz = gamma / l and z0 = -lambda in units of pi/2."""
    rng = np.random.default_rng(21)
    for cfg in (DEFAULT, specular.NARROW):
        for _ in range(300):
            vecs = [random_unit(rng) for _ in range(4)]
            n = int(rng.integers(1, 60))
            light = float(rng.uniform(0, 3))
            length = int(rng.integers(1, cfg.len_max + 1))
            s = specular.setup_line(*vecs, n, light, length, cfg)
            assert s.c == pytest.approx(light * cfg.out_max * s.amp**n, rel=1e-12, abs=1e-12)
            c_raw = math.floor(s.c * 2**cfg.c_frac_bits + 0.5)
            assert s.c_reg == min(c_raw, cfg.c_format.hi)
            assert s.dz == pytest.approx(s.gamma / length / (math.pi / 2), abs=1e-15)
            assert s.z0 == pytest.approx(-s.lam / (math.pi / 2), abs=1e-15)


def test_setup_lambda_a_and_the_range_of_the_angles() -> None:
    """Contract: "lambda = atan2(N1.W, cos theta1) and A = hypot(cos theta1, N1.W)"; "lambda is
    moved by 2 pi so that the middle of the line's angles lies in (-pi, pi]: all of them are
    within 3pi/2 of 0" -- measured: the middle lies in [-pi, pi] (it is -pi for lambda = pi,
    gamma = 0: H facing away all along), and every angle within 3pi/2."""
    rng = np.random.default_rng(22)
    for i in range(2000):
        vecs = [random_unit(rng) for _ in range(4)]
        if i % 5 == 0:
            vecs[3] = -vecs[2]
        s = specular.setup_line(*vecs, 10, 1.0, 16)
        n1u, h1u, w, gamma = specular.half_vector_path(*vecs)
        cos1, nw = float(n1u @ h1u), float(n1u @ w)
        assert s.amp == pytest.approx(min(1.0, math.hypot(cos1, nw)), abs=1e-12)
        lam = math.atan2(nw, cos1)
        assert s.lam == pytest.approx(lam, abs=1e-12) or s.lam == pytest.approx(
            lam + 2 * math.pi, abs=1e-12
        )
        middle = gamma / 2 - s.lam
        assert -math.pi - 1e-12 <= middle <= math.pi + 1e-12
        assert abs(middle) + gamma / 2 <= 1.5 * math.pi + 1e-12


def test_h2_is_rotated_by_the_rotation_taking_n2_onto_n1() -> None:
    """Contract: "H2 is rotated by the rotation taking N2 onto N1 (Rodrigues)": a proper rotation
    about N2 x N1 that takes N2 onto N1; gamma is the angle between H1 and the rotated H2."""
    rng = np.random.default_rng(23)
    for _ in range(300):
        n1, n2, h1, h2 = (random_unit(rng) for _ in range(4))
        r = specular.rotation_onto(n2, n1)
        np.testing.assert_allclose(r @ n2, n1, atol=1e-12)
        np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-12)
        assert np.linalg.det(r) == pytest.approx(1.0)
        axis = np.cross(n2, n1)
        np.testing.assert_allclose(r @ axis, axis, atol=1e-12)  # the axis is N2 x N1
        gamma = specular.half_vector_path(n1, n2, h1, h2)[3]
        h2r = r @ h2
        assert gamma == pytest.approx(math.acos(np.clip(h1 @ h2r, -1, 1)), abs=1e-6)


def test_antiparallel_normals_use_the_documented_half_turn() -> None:
    """Contract: "N1 = -N2 (rotation axis undefined) uses the half turn about a fixed
    perpendicular (N1 x the coordinate axis least aligned with N1)"."""
    rng = np.random.default_rng(24)
    for n1 in [np.array([0.0, 0.0, 1.0]), np.array([0.6, 0.8, 0.0])] + [
        random_unit(rng) for _ in range(50)
    ]:
        e = np.zeros(3)
        e[int(np.argmin(np.abs(n1)))] = 1.0
        u = np.cross(n1, e)
        u /= np.linalg.norm(u)
        half_turn = 2.0 * np.outer(u, u) - np.eye(3)
        np.testing.assert_allclose(specular.rotation_onto(-n1, n1), half_turn, atol=1e-12)


# ------------------------------------------------------------------------ the soak
def test_soak_stimulus_replays_from_its_seed_and_reaches_the_extremes() -> None:
    """Contract: "The seed is printed in the run's summary; SOAK_SEED=N make sim replays it": the
    stimulus is a function of its seed; it writes the extreme angles, values across 0, the
    invalid n and each decoder range's edges."""
    cfg = DEFAULT
    stim = soak.stimulus(cfg, 20_000, seed=5)
    assert stim == soak.stimulus(cfg, 20_000, seed=5)
    assert stim != soak.stimulus(cfg, 20_000, seed=6)
    z = {cfg.z_format.lo, -1, 0, 1, cfg.z_format.hi}
    assert z <= {s["dz_in"] for s in stim if s["dz_we"]}
    assert z <= {s["z0_in"] for s in stim if s["z0_we"]}
    ns = {s["n_in"] for s in stim if s["n_we"]}
    assert {0, 1, 2, 3, 6, 7, 1000, 1001, 1023} <= ns

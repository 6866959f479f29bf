# SPDX-License-Identifier: Apache-2.0
"""ROM images are validated loudly: by the model's loader and by the RTL at time 0.

The model (``model.rom.read_hex``) names the file, the line, what it expected (depth, width, hex
digits, the configuration) and what it found for a missing, empty, non-hex, over-wide, short,
truncated, too long, edited or foreign image.  The RTL reads the whole image in simulation,
checks every word is defined and every check field is its own, and a bad image ends the run with
a message and a non-zero exit status: under a plain ``iverilog``/``vvp`` run and under cocotb.
"""

from __future__ import annotations

import dataclasses
import re
import subprocess
from pathlib import Path

import numpy as np
import pytest

from model.hw.sources import source_list
from model.units import divider, rom, specular
from model.units.rom import RomFileError

ROOT = Path(__file__).resolve().parent.parent
RTL = ROOT / "rtl"
ARTICLE = divider.ARTICLE  # 32 data words + 28 check words of 9 bits (3 hex digits)


def _lines(text: str) -> list[str]:
    return text.splitlines(keepends=True)


def _word_lines(text: str) -> list[int]:
    """Indices (0-based) of the lines that hold a word, in order."""
    return [i for i, line in enumerate(_lines(text)) if line.strip() and not line.startswith("//")]


def _replace_word(text: str, word: int, new: str) -> str:
    lines = _lines(text)
    lines[_word_lines(text)[word]] = new + "\n"
    return "".join(lines)


def _drop_words(text: str, first: int) -> str:
    """The image cut after ``first`` words (comment lines after them dropped as well)."""
    lines = _lines(text)
    return "".join(lines[: _word_lines(text)[first]])


# ==================================================================== the model's loader
def _article_image() -> str:
    return divider.rom_text(ARTICLE)


def _line_of_word(text: str, word: int) -> int:
    return _word_lines(text)[word] + 1


TEXT = _article_image()
BROKEN = [
    # (name, text (None: no file), what the message must contain)
    ("missing", None, ["cannot read the ROM image"]),
    ("empty", "", ["empty, no words found"]),
    ("comments only", "// nothing here\n\n", ["empty, no words found"]),
    (
        "non-hex word",
        _replace_word(TEXT, 5, "0g1"),
        [f":{_line_of_word(TEXT, 5)}: word 5 is '0g1', not hex ('g')", "expected 3 hex digits"],
    ),
    (
        "over-wide word (digits)",
        _replace_word(TEXT, 7, "0001"),
        [f":{_line_of_word(TEXT, 7)}: word 7 is '0001', wider than 9 bits", "at most 1ff"],
    ),
    (
        "over-wide word (value)",
        _replace_word(TEXT, 7, "3ff"),
        [f":{_line_of_word(TEXT, 7)}: word 7 is '3ff', wider than 9 bits"],
    ),
    (
        "short word",
        _replace_word(TEXT, 2, "80"),
        [f":{_line_of_word(TEXT, 2)}: word 2 is '80', only 2 hex digits", "expected 3 hex digits"],
    ),
    (
        "truncated",
        _drop_words(TEXT, 59),
        [
            f":{_line_of_word(TEXT, 58)}: truncated: the file ends after 59 words",
            "32 data words + 28 check words of 9 bits (3 hex digits each) = 60 words",
        ],
    ),
    (
        "data words only (an image older than the checks)",
        _drop_words(TEXT, 32),
        ["truncated: the file ends after 32 words (the data words without check words"],
    ),
    (
        "too long",
        TEXT + "000\n",
        [f":{len(_lines(TEXT)) + 1}: too long: word 60 is past the end of the image (61 words"],
    ),
    (
        "edited data word",
        _replace_word(TEXT, 3, "0aa"),
        ["check field checksum is 0x", "a data word was changed after the image was written"],
    ),
    (
        "broken magic",
        _replace_word(TEXT, 32, "000"),
        ["check field magic is 0x", "expected 0x44495652 ('DIVR')"],
    ),
    (
        "another configuration (n4)",
        divider.rom_text(divider.ROM_CONFIGS["n4"]),
        ["built for another configuration (width = 5, expected 9)", "RECIP_BITS = 4"],
    ),
    (
        "another configuration (default)",
        divider.rom_text(divider.DEFAULT),
        ["built for another configuration (depth = 2048, expected 32)", "K_WIDTH = 11"],
    ),
    (
        "another kind (specular ROM 9)",
        specular.rom_text(specular.NARROW, "a"),
        ["built for another configuration (kind = specular_a, expected divider_recip)"],
    ),
]


@pytest.mark.parametrize(("name", "text", "needles"), BROKEN, ids=[b[0] for b in BROKEN])
def test_loader_names_file_line_expected_and_found(
    tmp_path: Path, name: str, text: str | None, needles: list[str]
) -> None:
    path = tmp_path / "article.hex"
    if text is not None:
        path.write_text(text)
    with pytest.raises(RomFileError) as info:
        divider.read_rom(ARTICLE, path)
    message = str(info.value)
    assert message.startswith(str(path)), message
    # What was expected is always said: the configuration, the depth and the width
    assert "K_WIDTH = 5, RECIP_BITS = 8: 32 data words + 28 check words of 9 bits" in message
    for needle in needles:
        assert needle in message, f"{name}: {needle!r} not in {message!r}"


def test_loader_accepts_every_committed_image() -> None:
    for cfg in divider.ROM_CONFIGS.values():
        assert divider.read_rom(cfg) == divider.rom_words(cfg).tolist()
    for cfg in (*specular.ROM_CONFIGS.values(), *specular.KEPT_CONFIGS.values()):
        assert specular.read_rom(cfg, "a") == specular.rom9_image(cfg).tolist()
        assert specular.read_rom(cfg, "cos") == specular.rom12_words(cfg).tolist()


def test_loader_refuses_the_image_of_another_alpha() -> None:
    """Same depth, width, ranges: only the ALPHA field tells the two ROM 9 images apart."""
    path = specular.rom_path(specular.INFLECTION, "a")
    with pytest.raises(RomFileError, match=r"\(ALPHA = 1, expected 0\)"):
        specular.read_rom(specular.DEFAULT, "a", path)


def test_loader_refuses_the_image_of_another_kept_range(tmp_path: Path) -> None:
    """Same fields and depth (24 words), n = 18..41 instead of 17..40: the header cannot tell
    them apart, the first data word can (a of n_first)."""
    path = tmp_path / "a.hex"
    path.write_text(specular.rom_text(dataclasses.replace(specular.KEPT, n_first=18, n_last=41)))
    with pytest.raises(RomFileError, match=r"data word 0 is 1086, expected 1056 \(a of n = 17\)"):
        specular.read_rom(specular.KEPT, "a", path)


def test_check_words_layout() -> None:
    """Check fields: 32 bits in ceil(32/width) words, low bits first; the end mark last."""
    layout = divider.rom_layout(ARTICLE)
    assert (layout.chunks, layout.check_words, layout.words) == (4, 28, 60)
    words = [int(line, 16) for line in TEXT.splitlines() if line and not line.startswith("//")]
    end = sum(w << (9 * i) for i, w in enumerate(words[-4:]))
    assert end == rom.END_MARK == int.from_bytes(b"END!", "big")
    assert rom.ALPHA_NAMES == specular.ALPHA_MODES
    assert "// RECIP_BITS = 8" in TEXT and "// end mark = 0x454e4421 ('END!')" in TEXT


def test_format_image_refuses_words_that_do_not_fit() -> None:
    layout = divider.rom_layout(ARTICLE)
    with pytest.raises(ValueError, match="does not fit in 9 bits"):
        rom.format_image(np.full(32, 512), layout, "too wide")
    with pytest.raises(ValueError, match="do not fit a depth of 32"):
        rom.format_image(np.zeros(31, dtype=np.int64), layout, "too short")


# ==================================================================== the RTL, at time 0


def _simulate(unit: str, params: dict[str, object], work: Path) -> tuple[int, str]:
    """Build the unit (rtl/<unit>.f: its file and the ROM module) with ``params`` (iverilog
    -g2005) and run it (vvp): the ROM check is all that happens.  Returns vvp's exit status
    and output."""
    flags = [
        f'-P{unit}.{k}="{v}"' if isinstance(v, str | Path) else f"-P{unit}.{k}={int(v)}"
        for k, v in params.items()
    ]
    build = subprocess.run(
        ["iverilog", "-g2005", "-o", "unit.vvp", "-s", unit, *flags, *map(str, source_list(unit))],
        cwd=work,
        capture_output=True,
        text=True,
    )
    assert build.returncode == 0, build.stdout + build.stderr
    run = subprocess.run(["vvp", "-n", "unit.vvp"], cwd=work, capture_output=True, text=True)
    return run.returncode, run.stdout + run.stderr


def _divider_params(cfg: divider.DividerConfig, path: Path | str) -> dict[str, object]:
    return {"A_WIDTH": cfg.a_width, "K_WIDTH": cfg.k_width, "RECIP_BITS": cfg.recip_bits,
            "ROM_FILE": str(path)}  # fmt: skip


DIVIDER_IMAGES = [
    # (name, instance, image text (None: no file), what the message must contain)
    ("missing", ARTICLE, None, "word 0 is undefined: the file is missing or unreadable"),
    ("truncated", ARTICLE, _drop_words(TEXT, 58), "word 58 is undefined"),
    ("data words only", ARTICLE, _drop_words(TEXT, 32), "word 32 is undefined"),
    # Icarus reads the "0" of "0g1" as word 5, then stops at the "g"
    ("non-hex word", ARTICLE, _replace_word(TEXT, 5, "0g1"), "word 6 is undefined"),
    ("edited data word", ARTICLE, _replace_word(TEXT, 3, "0aa"), "check field checksum is"),
    ("n4 image", ARTICLE, divider.rom_text(divider.ROM_CONFIGS["n4"]), "check field magic is"),
    (
        "n16 image in the default unit (255/3 -> 4.98)",
        divider.DEFAULT,
        divider.rom_text(divider.ROM_CONFIGS["n16"]),
        # 17-bit words read as 21-bit ones: the check words no longer spell the magic
        "check field magic is",
    ),
]


def test_rtl_runs_with_its_own_image(tmp_path: Path) -> None:
    for cfg in (ARTICLE, divider.DEFAULT):
        status, output = _simulate(
            "divider_shift", _divider_params(cfg, divider.rom_path(cfg)), tmp_path
        )
        assert status == 0 and "ROM" not in output, output
    for cfg in (specular.NARROW, specular.PROTOTYPE, specular.KEPT):
        status, output = _simulate("specular_unit", cfg.hdl_parameters(), tmp_path)
        assert status == 0 and "ROM" not in output, output


@pytest.mark.parametrize(
    ("name", "cfg", "text", "needle"), DIVIDER_IMAGES, ids=[d[0] for d in DIVIDER_IMAGES]
)
def test_rtl_stops_on_a_bad_divider_image(
    tmp_path: Path, name: str, cfg: divider.DividerConfig, text: str | None, needle: str
) -> None:
    path = tmp_path / "recip.hex"
    if text is not None:
        path.write_text(text)
    status, output = _simulate("divider_shift", _divider_params(cfg, path), tmp_path)
    assert status != 0, f"{name}: the run went on with a bad ROM:\n{output}"
    assert f'ROM_FILE "{path}": {needle}' in output, output
    assert "regenerate it with make roms" in output


SPECULAR_IMAGES = [
    # (name, instance, parameters changed, what the message must contain)
    (
        "ROM 9 of the inflection a in the taylor unit",
        specular.DEFAULT,
        {"A_ROM_FILE": specular.rom_path(specular.INFLECTION, "a")},
        'A_ROM_FILE "{A_ROM_FILE}": check field ALPHA is 1 (0x1), this instance needs 0 (0x0)',
    ),
    (
        "ROM 12 of the default unit in the narrow one",
        specular.NARROW,
        {"COS_ROM_FILE": specular.rom_path(specular.DEFAULT, "cos")},
        'COS_ROM_FILE "{COS_ROM_FILE}": check field magic is',
    ),
    (
        "ROM_ADDR_BITS = 8 with the 12-bit ROM 12",
        specular.DEFAULT,
        {"ROM_ADDR_BITS": 8},
        'COS_ROM_FILE "{COS_ROM_FILE}": check field magic is',
    ),
    (
        "ROM 9 of every n in the unit that keeps n = 17..40",
        specular.KEPT,
        {"A_ROM_FILE": specular.rom_path(specular.NARROW, "a")},
        'A_ROM_FILE "{A_ROM_FILE}": check field magic is',  # 1000 data words read as 24
    ),
    (
        "ROM 9 of n = 17..40 in the unit that keeps n = 18..41",
        dataclasses.replace(specular.KEPT, n_first=18, n_last=41),
        {"A_ROM_FILE": specular.rom_path(specular.KEPT, "a")},
        'A_ROM_FILE "{A_ROM_FILE}": data word 0 is 1056, this instance needs a of n = 18 (1086)',
    ),
    (
        "missing ROM 12",
        specular.NARROW,
        {"COS_ROM_FILE": "no/such/rom.hex"},
        'COS_ROM_FILE "no/such/rom.hex": word 0 is undefined',
    ),
]


@pytest.mark.parametrize(
    ("name", "cfg", "change", "needle"), SPECULAR_IMAGES, ids=[s[0] for s in SPECULAR_IMAGES]
)
def test_rtl_stops_on_a_bad_specular_image(
    tmp_path: Path, name: str, cfg: specular.SpecularConfig, change: dict, needle: str
) -> None:
    params = {**cfg.hdl_parameters(), **change}
    status, output = _simulate("specular_unit", params, tmp_path)
    assert status != 0, f"{name}: the run went on with a bad ROM:\n{output}"
    assert needle.format(**{k: v for k, v in params.items() if isinstance(v, str | Path)}) in output
    assert re.search(r"FATAL: .*bad ROM image", output), output


@pytest.mark.sim
def test_cocotb_run_stops_on_a_bad_image(capfd) -> None:
    """Under cocotb the time-0 check ends vvp with status 1: the runner raises, every test
    fails, and the message is in the log."""
    from sim.runner import hdl_parameters, run_bench

    wrong = divider.rom_path(divider.ROM_CONFIGS["n4"])
    params = hdl_parameters(ARTICLE, ROM_FILE=wrong)
    with pytest.raises(Exception):  # noqa: B017 (the runner's own error, whatever its type)
        run_bench("divider_shift", "sim.tb_divider", "rom_check_article", params, ARTICLE)
    out, err = capfd.readouterr()
    assert f'ROM_FILE "{wrong}": check field magic is' in out + err


def _simulate_defaults(
    unit: str, define: str | None, work: Path, run_in: Path | None = None
) -> tuple[int, str]:
    """Build the unit's sources (rtl/<unit>.f) into ``work`` with its default parameters (no
    ROM path passed) and, if given, ``-DSHADING_ROM_DIR="<define>"``; run it in ``run_in``
    (default ``work``).  Returns vvp's exit status and output."""
    flags = [] if define is None else [f'-DSHADING_ROM_DIR="{define}"']
    vvp = work / "defaults.vvp"
    build = subprocess.run(
        ["iverilog", "-g2005", "-o", str(vvp), "-s", unit, *flags, *map(str, source_list(unit))],
        cwd=work,
        capture_output=True,
        text=True,
    )
    assert build.returncode == 0, build.stdout + build.stderr
    run = subprocess.run(
        ["vvp", "-n", str(vvp)], cwd=run_in or work, capture_output=True, text=True
    )
    return run.returncode, run.stdout + run.stderr


def test_specular_rom_dir_define_names_the_image_folder(tmp_path: Path) -> None:
    """Compiled without Python, the default ROM files are `SHADING_ROM_DIR "/specular_...hex"`:
    the folder given on the command line, else "rom" relative to the folder the tool runs in;
    a folder without the images stops the run with the path it tried."""
    status, output = _simulate_defaults("specular_unit", str(rom.ROM_DIR), tmp_path)
    assert status == 0 and "ROM" not in output, output
    status, output = _simulate_defaults("specular_unit", None, tmp_path, RTL)  # rtl/rom, from rtl
    assert status == 0 and "ROM" not in output, output
    status, output = _simulate_defaults("specular_unit", None, tmp_path)  # no rom/ there
    assert status != 0 and f'A_ROM_FILE "rom/{specular.DEFAULT.a_rom_name}"' in output, output
    wrong = tmp_path / "nothing"
    status, output = _simulate_defaults("specular_unit", str(wrong), tmp_path)
    assert status != 0, output
    assert f'"{wrong}/{specular.DEFAULT.a_rom_name}": word 0 is undefined' in output, output
    assert re.search(r"FATAL: .*bad ROM image", output), output

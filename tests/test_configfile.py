# SPDX-License-Identifier: Apache-2.0
"""Pipeline configuration files: every method's configuration survives a round trip, fields left
out take the defaults, and every bad file is refused in one message naming file, field, value
and what is allowed; ``shading demo --config`` reads one."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from model.cli import main
from model.render import configfile, pipeline
from model.units import gouraud, specular


@pytest.mark.parametrize("method", sorted(pipeline.METHODS))
def test_every_method_round_trips(tmp_path: Path, method: str) -> None:
    cfg = pipeline.METHODS[method]
    path = configfile.write_config(cfg, tmp_path / "c.toml")
    assert configfile.read_config(path) == cfg


def test_narrow_units_round_trip(tmp_path: Path) -> None:
    cfg = pipeline.PipelineConfig(
        gouraud=gouraud.GouraudConfig(p=2, i_frac=5, len_width=7),
        specular=dataclasses.replace(specular.NARROW, k_ranges=((1, 9, 4), (10, 1000, 16))),
        specular_mode="adaptive",
        highlight_levels=2.5,
    )
    cfg = dataclasses.replace(
        cfg, divider=dataclasses.replace(cfg.divider, a_width=14, k_width=7, recip_bits=9)
    )
    path = configfile.write_config(cfg, tmp_path / "c.toml")
    assert configfile.read_config(path) == cfg
    assert path.read_text().startswith(configfile.HEADER)


def test_fields_left_out_take_the_defaults(tmp_path: Path) -> None:
    path = tmp_path / "short.toml"
    path.write_text('[pipeline]\nspecular_mode = "vertex"\n[gouraud]\np = 4\n')
    cfg = configfile.read_config(path)
    assert cfg == pipeline.PipelineConfig(
        gouraud=gouraud.GouraudConfig(p=4), specular_mode="vertex"
    )
    (tmp_path / "empty.toml").write_text("")
    assert configfile.read_config(tmp_path / "empty.toml") == pipeline.PipelineConfig()


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("[shader]\n", "shader is not a table here: legal tables are pipeline, divider"),
        ("[gouraud]\nlanes = 4\n", "gouraud.lanes is not a field here: legal fields are i_int"),
        ('[gouraud]\np = "4"\n', "gouraud.p = '4' is not legal: legal is an integer"),
        ("[gouraud]\np = true\n", "gouraud.p = True is not legal: legal is an integer"),
        ("[gouraud]\np = 3\n", "[gouraud] p = 3 is out of range"),
        ("[specular]\nk_ranges = 16\n", "specular.k_ranges = 16 is not legal: legal is a list"),
        ("[specular]\nk_ranges = [[1, 500, 16]]\n", "[specular] k_ranges end at n = 500"),
        ('[pipeline]\nspecular_mode = "fast"\n', "[pipeline] specular_mode = 'fast' is out of"),
        ("[pipeline]\nhighlight_levels = -1\n", "[pipeline] highlight_levels = -1.0 is out of"),
        ("gouraud = 3\n", "gouraud = 3 is not legal: legal is a table"),
        ("[divider]\na_width = 10\n", "[pipeline] divider a_width = 10 is out of range"),
        ("[divider]\nrecip_bits = 4\n", "[divider] k_width = 11 is out of range"),
        ("[gouraud\n", "not valid TOML"),
    ],
)
def test_bad_files_are_refused(tmp_path: Path, text: str, message: str) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(ValueError) as info:
        configfile.read_config(path)
    assert str(info.value).startswith(f"{path}: ")
    assert message in str(info.value)


def test_a_missing_file_is_refused(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=r"does not exist: legal value is an existing \.toml"):
        configfile.read_config(tmp_path / "nope.toml")


def test_demo_refuses_a_bad_config_in_one_line(tmp_path: Path, capsys) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text("[gouraud]\np = 3\n")
    status = main(["demo", "--size", "16", "--out", str(tmp_path / "o"), "--config", str(bad)])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1
    assert "argument --config:" in err[0] and "p = 3 is out of range" in err[0]


def test_demo_shades_with_a_config_file(tmp_path: Path, capsys) -> None:
    path = configfile.write_config(
        pipeline.PipelineConfig(gouraud=gouraud.GouraudConfig(p=2)), tmp_path / "c.toml"
    )
    status = main(
        ["demo", "--scene", "sphere", "--size", "24", "--out", str(tmp_path / "o"),
         "--config", str(path)]
    )  # fmt: skip
    out = capsys.readouterr().out
    assert status == 0
    # the configured units are one more row; P = 2 changes no pixel, so it equals (c)
    rows = {line.split("|")[1].strip(): line for line in out.splitlines() if line.startswith("|")}
    assert "config" in rows
    nmse = {k: row.split("|")[2].strip() for k, row in rows.items()}
    assert nmse["config"] == nmse["(c) units: patent k-set, a = sqrt(n/k)"]

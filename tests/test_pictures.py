# SPDX-License-Identifier: Apache-2.0
"""The pictures README.md and docs/ show exist and are current (`make pictures` remakes them).

docs/pictures.json, written by `make pictures`, records per picture the command that makes it
and a SHA-256 of the numbers it plots (``images.data_digest``), not of its PNG bytes, which change
with the Pillow, matplotlib and zlib versions.  The demo sheet's numbers are recomputed here
in-process at the recorded scene and size (about a second): any change to what it shows (a
shading method, the renderer, the scene, a label, the error scale, its ticks or colours) fails
the test until `make pictures` is rerun.
The trade figure's numbers are recomputed by a fresh in-process sweep of its recorded scenes and
size (half a minute).  Nothing untracked is read: not out/trade/ (a local sweep may be stale or of
another grid), only docs/pictures.json and the tracked sources.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np

from model.study import images, report

ROOT = Path(__file__).resolve().parents[1]
RECORD = ROOT / report.PICTURES_JSON
IMAGE_REF = re.compile(r"!\[[^\]]*\]\(\s*<?([^)\s>]+)|<img\b[^>]*\bsrc=[\"']([^\"']+)")
RERUN = "run `make pictures`"


def recorded() -> dict:
    assert RECORD.is_file(), f"{report.PICTURES_JSON} is missing: {RERUN}"
    return json.loads(RECORD.read_text())["pictures"]


def tracked() -> set[str]:
    """The files git tracks, from the repository root: the only files these tests read."""
    out = subprocess.run(
        ["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout
    return set(out.splitlines())


def shown_pictures() -> list[tuple[str, str]]:
    """(markdown file, picture) of every local picture the tracked README.md and docs/**/*.md
    show, the picture's path from the repository root."""
    found = []
    files = tracked()
    pages = ["README.md", *sorted(f for f in files if f.startswith("docs/") and f.endswith(".md"))]
    for md in (ROOT / page for page in pages):
        for m in IMAGE_REF.finditer(md.read_text()):
            target = (m.group(1) or m.group(2)).split("#")[0]
            if "://" in target or target.startswith("data:"):
                continue
            picture = (md.parent / target).resolve().relative_to(ROOT).as_posix()
            found.append((md.relative_to(ROOT).as_posix(), picture))
    return found


def make_pictures_recipe() -> list[str]:
    """The commands of the Makefile's `pictures` target, with $(PY) written as python."""
    lines = (ROOT / "Makefile").read_text().splitlines()
    start = next((i for i, s in enumerate(lines) if s.startswith("pictures:")), None)
    assert start is not None, "the Makefile has no `pictures` target"
    recipe = []
    for line in lines[start + 1 :]:
        if not line.startswith("\t"):
            break
        recipe.append(re.sub(r"^\$\(PY\)", "python", line.strip().lstrip("@")))
    return recipe


def test_every_picture_the_docs_show_exists_and_is_recorded() -> None:
    shown = shown_pictures()
    assert ("README.md", report.DEMO_SHEET) in shown  # the pattern finds the README's pictures
    pictures = recorded()
    files = tracked()
    assert Path(report.PICTURES_JSON).as_posix() in files, (
        f"{report.PICTURES_JSON} is not committed"
    )
    for md, picture in shown:
        assert (ROOT / picture).is_file(), f"{md} shows {picture}, which does not exist: {RERUN}"
        assert picture in files, f"{md} shows {picture}, which git does not track: commit it"
        assert picture in pictures, (
            f"{md} shows {picture}, which {report.PICTURES_JSON} does not list: make it in "
            "`make pictures` (model.study.report.record_pictures)"
        )
    recipe = make_pictures_recipe()
    for picture, entry in pictures.items():
        assert (ROOT / picture).is_file(), f"{picture} is listed but missing: {RERUN}"
        assert picture in files, f"{picture} is listed but git does not track it: commit it"
        assert entry["command"] in recipe, f"{picture}: `{entry['command']}` is not in {recipe}"
        assert re.fullmatch(r"[0-9a-f]{64}", entry["data_sha256"])
    assert "python -m model.study.report pictures" in recipe  # writes the record


def test_demo_sheet_shows_what_the_demo_draws_now(teapot_file) -> None:
    entry = recorded()[report.DEMO_SHEET]
    assert entry["command"] == report.DEMO_COMMAND
    made = (entry["scene"], entry["size"], entry["log_error"])
    assert made == (report.DEFAULT_SCENE, report.DEFAULT_SIZE, False), (
        f"{report.DEMO_SHEET} is of {made}, not the demo's default: {RERUN}"
    )
    run = report.run_methods(entry["scene"], entry["size"])
    now = report.sheet_record(run, entry["log_error"])["data_sha256"]
    assert now == entry["data_sha256"], (
        f"{report.DEMO_SHEET} is stale: `{report.DEMO_COMMAND}` now draws other numbers than "
        f"the ones {report.PICTURES_JSON} records (data {now[:12]}, recorded "
        f"{entry['data_sha256'][:12]}): {RERUN}"
    )


def test_the_sheet_digest_sees_one_level_in_one_pixel() -> None:
    """The probe of the check above: any change to what the sheet plots changes its digest."""
    rng = np.random.default_rng(12)
    ref = rng.integers(0, 256, (16, 16, 3)).astype(np.uint8)
    img = ref.copy()
    img[4:6, 4:6] //= 2
    args = {"panels": [("(b) m", img)], "title": "t", "error_reference": ref}
    base = images.sheet_digest(**args)
    assert images.sheet_digest(**args) == base
    one_level = img.copy()
    one_level[9, 3, 1] ^= 1
    off_ref = ref.copy()
    off_ref[0, 0, 2] ^= 1
    for change in (
        {"panels": [("(b) m", one_level)]},
        {"error_reference": off_ref},
        {"panels": [("(b) n", img)]},
        {"title": "u"},
        {"log_error": True},
        {"reference_label": "(z)"},
    ):
        assert images.sheet_digest(**{**args, **change}) != base, change
    # Numbers are hashed, not their representation: key order and float noise do not count.
    assert images.data_digest({"a": 1, "b": 0.1 + 0.2}) == images.data_digest({"b": 0.3, "a": 1})
    assert images.data_digest([np.uint8(7)]) == images.data_digest([7])
    assert images.data_digest([0.3]) != images.data_digest([0.30001])


def test_trade_figure_is_drawn_from_the_current_sweep(teapot_file, tmp_path: Path) -> None:
    """The trade figure's numbers are the ones the sweep gives now: a fresh in-process sweep of
    the figure's recorded scenes and size into a temporary folder (the small grid, its own
    cache; half a minute on one core), never a local out/trade/ sweep."""
    from model.study import trade

    entry = recorded()[report.TRADE_FIGURE]
    assert entry["command"] == report.TRADE_COMMAND
    assert len(entry["sizes"]) == 1, entry
    status = trade.main(
        scenes=entry["scenes"],
        size=entry["sizes"][0],
        out_dir=tmp_path,
        workers=0,
        repeats=1,
        part="none",  # the synthesised columns are not in the digest
    )
    assert status == 0
    results = tmp_path / "results.csv"
    now = report.trade_results_record(results)
    assert {k: now[k] for k in ("scenes", "sizes")} == {k: entry[k] for k in ("scenes", "sizes")}
    assert now["data_sha256"] == entry["data_sha256"], (
        f"{report.TRADE_FIGURE} was drawn from other results ({entry['rows']} rows) than the "
        f"sweep gives now ({now['rows']} rows): the sweep changed, {RERUN}"
    )


def test_the_pictures_colours_and_ticks_are_matplotlibs() -> None:
    """The pictures are drawn with Pillow (``canvas``), their colours and colour-bar ticks as
    matplotlib draws them: the stored colour tables equal matplotlib's (``python -m
    model.study.palette`` rewrites them), every level's colour on every scale (tops 1..255,
    linear and symmetric-log) is ``cmap(norm(level))``, and the linear ticks are
    ``MaxNLocator(nbins=5, integer=True)``'s."""
    from matplotlib import colormaps, colors, ticker

    from model.study import canvas, palette

    assert np.array_equal(palette.INFERNO, palette.from_matplotlib("inferno"))
    assert palette.tab10_from_matplotlib() == palette.TAB10
    cmap = colormaps[images.ERROR_CMAP]
    levels = np.arange(256.0)
    for top in range(1, 256):
        for log in (False, True):
            if log:
                norm = colors.SymLogNorm(linthresh=1.0, linscale=1.0, vmin=0.0, vmax=top, base=10)
            else:
                norm = colors.Normalize(vmin=0.0, vmax=top)
            want = (cmap(norm(levels))[:, :3] * 255).astype(np.uint8)
            assert np.array_equal(canvas.error_colours(levels, top, log), want), (top, log)
        ticks = ticker.MaxNLocator(nbins=5, integer=True).tick_values(0, top)
        assert canvas.tick_values(top, False) == [t for t in ticks if 0 <= t <= top], top
    assert canvas.tick_values(170, True) == [0, 1, 2, 5, 10, 20, 50, 100, 170]
    assert canvas.tick_values(22, True) == [0, 1, 2, 5, 10, 20]


def test_the_demo_pictures_are_drawn_without_matplotlib(tmp_path: Path) -> None:
    """`make demo` draws its heat-maps and sheet without importing matplotlib (it took most
    of the demo's time): a fresh process writes them and has not imported it."""
    script = (
        "import sys, numpy as np\n"
        "from model.study import images\n"
        "ref = np.zeros((16, 16, 3), np.uint8); img = ref.copy(); img[3:5, 3:5] = 40\n"
        f"out = {str(tmp_path)!r}\n"
        "images.save_error_heatmaps([(out + '/e.png', img, '(b) m')], ref)\n"
        "images.save_sheet(out + '/s.png', [('(b) m', img), ('(c) n', ref)], title='t',\n"
        "                  error_reference=ref)\n"
        "print('matplotlib' in sys.modules)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, cwd=ROOT, timeout=300
    )
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.split() == ["False"]
    for name in ("e.png", "s.png"):
        assert images.load_png(tmp_path / name).shape[0] > 16

# SPDX-License-Identifier: Apache-2.0
"""Image output: PNG files, error heat-maps and a labelled side-by-side sheet, all drawn with
Pillow (``model.study.canvas``: no matplotlib on the demo's path; the colours, scales and ticks
are matplotlib's), and the digest of what a picture plots.

Every error heat-map has its own scale (0 to its own largest error, at least 1 level) and its own
colour bar in 8-bit levels; ``log=True`` draws it on a symmetric-log scale (linear from 0 to 1
level, then decades), so that the many pixels off by a level or two show next to the few large
ones.  ``sheet_data`` is everything a sheet plots (the images, the error maps, their scales and
colour-bar ticks, the colour map, the titles, the error distribution), ``data_digest`` a hash
of it that does not depend on the drawing or PNG library versions: ``tests/test_pictures.py``
compares it with the one ``make pictures`` recorded.
"""

from __future__ import annotations

import hashlib
import re
import textwrap
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from model.study import canvas, palette

ERROR_CMAP = "inferno"
ERROR_UNIT = "|error| (8-bit levels)"


def _rgb(image) -> np.ndarray:
    arr = np.asarray(image)
    if arr.dtype != np.uint8 or arr.ndim != 3 or arr.shape[2] != 3:
        raise ValueError(
            f"image shape = {arr.shape} (dtype {arr.dtype}) is not legal: legal is (H, W, 3) uint8"
        )
    return arr


def save_png(path: str | Path, image) -> Path:
    """Write an (H, W, 3) uint8 image as PNG (parent folders created)."""
    from PIL import Image

    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray(_rgb(image), mode="RGB").save(p, compress_level=3)
    return p


def load_png(path: str | Path) -> np.ndarray:
    from PIL import Image

    with Image.open(path) as im:
        return np.asarray(im.convert("RGB"), dtype=np.uint8)


def error_map(image, reference) -> np.ndarray:
    """(H, W) float: the largest absolute channel error per pixel, in 8-bit levels."""
    a = _rgb(image).astype(np.int16)
    b = _rgb(reference).astype(np.int16)
    if a.shape != b.shape:
        raise ValueError(
            f"image shape = {a.shape} is not legal: must equal the reference {b.shape}"
        )
    return np.abs(a - b).max(axis=2).astype(np.float64)


def error_top(err: np.ndarray, vmax: float | None = None) -> float:
    """The top of an error map's own scale: ``vmax`` if given, else its largest error (>= 1)."""
    return float(vmax) if vmax is not None else max(1.0, float(np.max(err)))


def save_error_heatmaps(
    items: Sequence[tuple[str | Path, np.ndarray, str]],
    reference,
    log: bool = False,
    vmax: float | None = None,
    cmap: str = ERROR_CMAP,
    reference_label: str = "the reference",
    errors: Sequence[np.ndarray] | None = None,
) -> list[Path]:
    """One heat-map PNG per ``(path, image, title)`` of ``error_map(image, reference)``
    (``errors``: those maps, already made, one per item: e.g. ``sheet_data``'s),
    titled ``title`` and "error against ``reference_label``: max N levels", each on its own scale
    (``error_top``; ``vmax`` fixes it for all) with its own colour bar in 8-bit levels, linear
    or (``log``) symmetric-log.  The same size and layout for every map (a 256 x 256 map at one
    pixel per pixel)."""
    ref = _rgb(reference)
    h, w = ref.shape[:2]
    pw, ph = round(256 * w / max(h, w)), round(256 * h / max(h, w))
    lines = max((wrap_title(t, 44).count("\n") + 2 if t else 1) for _, _, t in items)
    left, gap, bar_w, bar_txt, bottom = 10, 8, 12, 62, 8
    top_txt = 12 + 16 * lines  # the title band: 9-point lines
    fw, fh = left + pw + gap + bar_w + bar_txt, bottom + ph + top_txt
    unit = ERROR_UNIT + (", log scale" if log else "")
    written = []
    for i, (path, image, title) in enumerate(items):
        err = error_map(image, ref) if errors is None else errors[i]
        top = error_top(err, vmax)
        pic = canvas.Canvas(fw, fh)
        pic.paste(left, top_txt, _fit(canvas.error_colours(err, top, log, cmap), pw, ph))
        pic.colorbar(left + pw + gap, top_txt, bar_w, ph, top, log, cmap, label=unit)
        line = f"error against {reference_label}: max {int(err.max())} levels"
        pic.text(fw / 2, 6, (wrap_title(title, 44) + "\n" if title else "") + line, 9, va="top")
        written.append(pic.save(path))
    return written


def save_error_heatmap(
    path: str | Path,
    image,
    reference,
    title: str = "",
    vmax: float | None = None,
    cmap: str = ERROR_CMAP,
    log: bool = False,
) -> Path:
    """A heat-map PNG of ``error_map(image, reference)`` with a colour bar in 8-bit levels, on
    its own scale (``vmax`` fixes the top; default its largest error, at least 1)."""
    return save_error_heatmaps([(path, image, title)], reference, log=log, vmax=vmax, cmap=cmap)[0]


# ======================================================================== what a picture plots
def data_digest(data, digits: int = 6) -> str:
    """SHA-256 of the numbers (and text) a picture plots: nested dicts (keys sorted), lists,
    strings, booleans, integers and integer arrays exactly, floats rounded to ``digits``
    significant digits.  Independent of the plotting and PNG libraries."""
    h = hashlib.sha256()
    _feed(h, data, digits)
    return h.hexdigest()


def _float_text(x: float, digits: int) -> bytes:
    return (f"{float(x):.{digits}g}" if np.isfinite(x) else repr(float(x))).encode()


def _feed(h, x, digits: int) -> None:
    if isinstance(x, dict):
        h.update(b"{%d;" % len(x))
        for key in sorted(x, key=str):
            _feed(h, str(key), digits)
            _feed(h, x[key], digits)
    elif isinstance(x, list | tuple):
        h.update(b"[%d;" % len(x))
        for v in x:
            _feed(h, v, digits)
    elif isinstance(x, str):
        b = x.encode()
        h.update(b"s%d;" % len(b) + b)
    elif x is None:
        h.update(b"n;")
    elif isinstance(x, bool | np.bool_):
        h.update(b"b1;" if x else b"b0;")
    elif isinstance(x, int | np.integer):
        h.update(b"i%d;" % int(x))
    elif isinstance(x, float | np.floating):
        h.update(b"f" + _float_text(x, digits) + b";")
    elif isinstance(x, np.ndarray):
        h.update(b"a" + ",".join(map(str, x.shape)).encode() + b";")
        if x.dtype.kind in "biu":
            h.update(np.ascontiguousarray(x, dtype="<i8").tobytes())
        elif x.dtype.kind == "f":
            for v in x.ravel():
                h.update(_float_text(v, digits) + b",")
        else:
            raise TypeError(f"array dtype = {x.dtype} is not legal: legal are integers and floats")
    else:
        raise TypeError(f"type = {type(x).__name__} is not legal in a picture's data")


def wrap_title(label: str, width: int = 34) -> str:
    """A panel title in at most two lines, broken after ", " or ": " where it can be."""
    if len(label) <= width:
        return label
    for sep in (", ", ": "):
        cut = label.rfind(sep, 0, width + 1)
        if cut > 0 and len(label) - cut - len(sep) <= width:
            return label[: cut + len(sep)].rstrip() + "\n" + label[cut + len(sep) :]
    return textwrap.fill(label, width)


def _key(label: str) -> str:
    """The short key of a method label: "(c)" of "(c) units: ...", else the label."""
    m = re.match(r"\(\w+\)", label)
    return m.group(0) if m else label


def sheet_data(
    panels: Sequence[tuple[str, np.ndarray]],
    title: str = "",
    error_reference: np.ndarray | None = None,
    reference_label: str = "reference",
    log_error: bool = False,
) -> dict:
    """Everything ``save_sheet`` plots, as numbers and text (``data_digest`` hashes it)."""
    if not panels:
        raise ValueError("panels = [] is not legal: the sheet needs at least one image")
    data: dict = {
        "title": str(title),
        "panels": [{"label": str(label), "image": _rgb(img)} for label, img in panels],
    }
    if error_reference is not None:
        ref = _rgb(error_reference)
        data["reference"] = {"label": str(reference_label), "image": ref}
        data["log_error"] = bool(log_error)
        data["error_colours"] = palette.table(ERROR_CMAP)  # the colour bars' 256 colours
        for panel in data["panels"]:
            err = error_map(panel["image"], ref).astype(np.uint8)
            panel["error"] = err
            panel["error_top"] = error_top(err)
            panel["error_ticks"] = canvas.tick_values(panel["error_top"], bool(log_error))
            # Pixels with an error of at least L levels, L = 1..255 (the distribution chart).
            counts = np.bincount(err.ravel(), minlength=256)
            panel["at_least"] = counts[::-1].cumsum()[::-1][1:]
    return data


def sheet_digest(*args, **kwargs) -> str:
    """``data_digest(sheet_data(...))``: the sheet's numbers, without drawing it."""
    return data_digest(sheet_data(*args, **kwargs))


def save_sheet(
    path: str | Path,
    panels: Sequence[tuple[str, np.ndarray]],
    columns: int = 3,
    title: str = "",
    error_reference: np.ndarray | None = None,
    reference_label: str = "reference",
    log_error: bool = False,
) -> Path:
    """A side-by-side sheet: one labelled panel per ``(label, image)``, ``columns`` a row.

    With ``error_reference`` every panel has its error heat-map against it underneath, each on
    its own scale with its own colour bar (symmetric-log with ``log_error``), and a column on the
    left holds the reference image and a chart of how many pixels of each panel are off by at
    least L levels.  The layout is fixed (no blank bands): each panel is drawn at 256 x 256
    pixels (a 256 x 256 image at one pixel per pixel).
    """
    return draw_sheet(
        path,
        sheet_data(panels, title, error_reference, reference_label, log_error),
        columns,
    )


def draw_sheet(path: str | Path, data: dict, columns: int = 3) -> Path:
    """Draw ``sheet_data``'s ``data`` (the layout of ``save_sheet``)."""
    panels = data["panels"]
    with_err = "reference" in data
    log = bool(data.get("log_error", False))
    cols = max(1, min(int(columns), len(panels)))
    rows = -(-len(panels) // cols)
    # Layout in pixels: a PW x PH panel (the first image's aspect, 256 on its long side), title
    # bands T1 (two lines) above an image and T2 above an error map; a cell is a panel, its
    # colour bar and tick labels and a gap; the left column (reference, chart, note) is at
    # least LW wide.
    h0, w0 = panels[0]["image"].shape[:2]
    PW, PH = round(256 * w0 / max(h0, w0)), round(256 * h0 / max(h0, w0))
    T1, T2, M, GAP = 34, 18, 8, 14
    BAR_GAP, BAR_W, BAR_TXT = 5, 10, 30
    cell_w = PW + (BAR_GAP + BAR_W + BAR_TXT if with_err else 0) + GAP
    cell_h = T1 + PH + ((T2 + PH) if with_err else 0) + 6
    left_w = max(cell_w, 300) if with_err else 0
    sup = 30 if data["title"] else 0
    width = M + left_w + cols * cell_w - GAP + M
    height = sup + rows * cell_h + M
    pic = canvas.Canvas(width, height)

    def show(x: float, y_top: float, rgb: np.ndarray) -> None:
        """Pixels at one pixel per pixel, centred in a PW x PH box."""
        img = _fit(rgb, PW, PH)
        h, w = img.shape[:2]
        pic.paste(x + (PW - w) // 2, y_top + (PH - h) // 2, img)

    x0 = M + left_w
    for k, panel in enumerate(panels):
        r, c = divmod(k, cols)
        x, y = x0 + c * cell_w, sup + r * cell_h
        pic.text(x + PW / 2, y + T1 - 3, wrap_title(panel["label"]), 9)
        show(x, y + T1, panel["image"])
        if not with_err:
            continue
        top = panel["error_top"]
        ye = y + T1 + PH + T2
        pic.text(x + PW / 2, ye - 2, f"error: max {int(np.max(panel['error']))} levels", 8)
        show(x, ye, canvas.error_colours(panel["error"], top, log, ERROR_CMAP))
        pic.colorbar(x + PW + BAR_GAP, ye, BAR_W, PH, top, log, ERROR_CMAP)
    if with_err:
        ref = data["reference"]
        pic.text(M + PW / 2, sup + T1 - 3, wrap_title(ref["label"]), 9)
        show(M, sup + T1, ref["image"])
        # The chart: under the reference, down to the end of the next row's image band.
        chart_h = (PH + T2 + T1 + PH) if rows >= 2 else PH
        box = (M + 44, sup + T1 + PH + T2 + 4, left_w - GAP - 44 - 8, chart_h - 40)
        _distribution_chart(pic, box, panels)
        if rows >= 2:
            scale = "symmetric-log (linear to 1 level, then decades)" if log else "linear"
            note = (
                "Under each image: its error against the reference, |method \u2212 reference| "
                "per pixel (the largest of the three channels) in 8-bit levels, on its own "
                f"{scale} scale with its own colour bar; black = no error. The chart above "
                "compares the methods on one scale."
            )
            pic.text(
                M + 4,
                sup + cell_h + T1 + PH + T2 + PH / 2,
                textwrap.fill(note, max(20, (left_w - GAP) // 7)),
                9,
                ha="left",
                va="center",
                spacing=1.35,
            )
    if data["title"]:
        pic.text(width / 2, 8, data["title"], 11, va="top")
    return pic.save(path)


def _fit(rgb: np.ndarray, width: int, height: int) -> np.ndarray:
    """``rgb`` resized (nearest pixel) to fit a width x height box, aspect kept."""
    h, w = rgb.shape[:2]
    scale = min(width / w, height / h)
    if scale == 1:
        return rgb
    rows = (np.arange(max(1, round(h * scale))) / scale).astype(int)
    cols = (np.arange(max(1, round(w * scale))) / scale).astype(int)
    return rgb[np.minimum(rows, h - 1)][:, np.minimum(cols, w - 1)]


def _distribution_chart(pic: canvas.Canvas, box: tuple, panels) -> None:
    """Pixels off by at least L levels against L, every panel (log-log)."""
    levels = np.arange(1, 256)
    curves = []
    for i, panel in enumerate(panels):
        n = panel["at_least"]
        if n[0] == 0:
            continue
        last = int(np.flatnonzero(n)[-1]) + 1
        width = 1.0 + 1.2 * (len(panels) - 1 - i) / max(1, len(panels) - 1)  # equal curves show
        curves.append((_key(panel["label"]), levels[:last], n[:last], width, palette.TAB10[i % 10]))
    canvas.step_chart(
        pic,
        box,
        curves,
        "how many pixels are off by L or more",
        "L (8-bit levels)",
        "pixels with error \u2265 L",
        (1, 256),
    )

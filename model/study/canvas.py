# SPDX-License-Identifier: Apache-2.0
"""A small Pillow canvas for the demo's pictures: text, images, colour bars and a log-log chart,
laid out in pixels at 100 dpi (a font size in points is ``points * 100 / 72`` pixels), with no
matplotlib on the way (importing and drawing with it took most of ``make demo``'s time).

The error colours follow matplotlib's conventions exactly: ``norm`` is ``colors.Normalize``
(0..top) or ``colors.SymLogNorm(linthresh=1, linscale=1, base=10)`` (linear to 1 level, then
decades), ``colour_index`` is the row a ``Colormap`` of 256 colours picks for a normalised
value, and the tables come from ``palette`` (matplotlib's, stored).  ``tick_values`` gives a
colour bar's ticks: at most 6 round integers (a whole step of 1, 1.5, 2, 2.5, 3, 4, 5, 6 or 8
times a power of ten, at least 1: ``ticker.MaxNLocator(nbins=5, integer=True)``'s choice),
or on the log scale 0, 1, 2, 5, 10, ... up to the top (and the top itself when it is well
above the last).  Text is DejaVu Sans (the font
matplotlib draws with: its file from matplotlib's package folder, found without importing
matplotlib, else the system's, else Pillow's own).  May import numpy, Pillow and
``model.study.palette``.
"""

from __future__ import annotations

import importlib.util
import math
from functools import lru_cache
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from model.study import palette

DPI = 100
LOG_TICKS = (0, 1, 2, 5, 10, 20, 50, 100, 200)
SUPERSCRIPT = str.maketrans(
    "-0123456789", "\u207b\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079"
)
GRID = (230, 230, 230)
FRAME = (0, 0, 0)


@lru_cache(maxsize=1)
def font_file() -> str | None:
    """DejaVu Sans: matplotlib's copy (located, not imported), else the system's, else None."""
    spec = importlib.util.find_spec("matplotlib")
    places = []
    if spec is not None and spec.origin:
        places.append(Path(spec.origin).parent / "mpl-data" / "fonts" / "ttf" / "DejaVuSans.ttf")
    places.append(Path("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"))
    return next((str(p) for p in places if p.is_file()), None)


@lru_cache(maxsize=32)
def font(points: float, scale: int = 1) -> ImageFont.FreeTypeFont | ImageFont.ImageFont:
    """The text font at ``points`` (x ``scale`` for a supersampled drawing)."""
    size = max(1, round(points * DPI / 72 * scale))
    path = font_file()
    return ImageFont.truetype(path, size) if path else ImageFont.load_default(size)


def px(points: float) -> float:
    """Points to pixels at ``DPI``."""
    return points * DPI / 72


# ======================================================================= colours and scales
def norm(values, top: float, log: bool = False) -> np.ndarray:
    """0..``top`` to 0..1: linear, or symmetric-log (linear to 1 level, then decades), with
    matplotlib's arithmetic (``Normalize`` / ``SymLogNorm(1, 1, base=10)``, vmin 0)."""
    v = np.asarray(values, dtype=np.float64)
    if not log:
        return (v - 0.0) / (top - 0.0)
    linscale_adj = 1.0 / (1.0 - 10.0**-1)

    def transform(a: np.ndarray) -> np.ndarray:
        abs_a = np.abs(a)
        with np.errstate(divide="ignore", invalid="ignore"):
            out = np.sign(a) * 1.0 * (linscale_adj + np.log(abs_a / 1.0) / np.log(10.0))
            inside = abs_a <= 1.0
        out[inside] = a[inside] * linscale_adj
        return out

    lo, hi = transform(np.array([0.0, float(top)]))
    return (transform(v.reshape(-1)).reshape(v.shape) - lo) / (hi - lo)


def colour_index(fraction) -> np.ndarray:
    """The row of a 256-colour map for normalised values (``Colormap.__call__``): x 256,
    1.0 -> 255, clipped to 0..255, truncated."""
    x = np.asarray(fraction, dtype=np.float64) * 256
    x[x == 256] = 255
    return np.clip(x, -1, 256).astype(int).clip(0, 255)


def error_colours(err: np.ndarray, top: float, log: bool, cmap: str = "inferno") -> np.ndarray:
    """(H, W, 3) uint8 of an error map in whole levels 0..255 (``top`` the scale's top)."""
    lut = palette.table(cmap)[colour_index(norm(np.arange(256.0), top, log))]
    levels = np.clip(np.asarray(err), 0, 255).astype(np.intp)
    return lut[levels]


def tick_values(top: float, log: bool) -> list[float]:
    """A colour bar's ticks from 0 to ``top`` (see the module doc)."""
    if log:
        ticks = [float(t) for t in LOG_TICKS if t <= top]
        if top >= 1.5 * ticks[-1]:
            ticks.append(float(top))
        return ticks
    raw = top / 5  # MaxNLocator(nbins=5, integer=True): its steps x a power of ten, whole
    scale = 10.0 ** math.floor(math.log10(raw))
    steps = [s * scale for s in (1, 1.5, 2, 2.5, 3, 4, 5, 6, 8, 10)]
    step = next(s for s in steps if s >= raw and (s < 1 or abs(s - round(s)) < 0.001))
    step = max(1.0, step) if top >= 1 else step
    return [i * step for i in range(int(top // step) + 1)]


# ================================================================================= the canvas
class Canvas:
    """A white RGB picture of ``width`` x ``height`` pixels to draw on (pixels from the top)."""

    def __init__(self, width: float, height: float) -> None:
        self.image = Image.new("RGB", (round(width), round(height)), "white")
        self.draw = ImageDraw.Draw(self.image)

    def text(
        self, x: float, y: float, label: str, points: float, ha: str = "center",
        va: str = "bottom", spacing: float = 1.1, rotate: bool = False,
    ) -> None:  # fmt: skip
        """Text anchored at (x, y): ``ha`` left / center / right, ``va`` top / center /
        bottom of its box; ``spacing`` the line distance in font sizes; ``rotate`` turns it
        90 degrees counter-clockwise (a vertical label, read from below)."""
        f = font(points)
        gap = max(0, round(px(points) * (spacing - 1.0) + 2))
        box = self.draw.multiline_textbbox((0, 0), label, font=f, spacing=gap, align=ha)
        w, h = math.ceil(box[2] - box[0]), math.ceil(box[3] - box[1])
        tile = Image.new("L", (w + 2, h + 2), 0)
        ImageDraw.Draw(tile).multiline_text(
            (1 - box[0], 1 - box[1]), label, font=f, fill=255, spacing=gap, align=ha
        )
        if rotate:
            tile = tile.rotate(90, expand=True)
        tw, th = tile.size
        left = {"left": x, "center": x - tw / 2, "right": x - tw}[ha]
        top = {"top": y, "center": y - th / 2, "bottom": y - th}[va]
        self.image.paste((0, 0, 0), (round(left), round(top)), tile)

    def paste(self, x: float, y: float, rgb: np.ndarray) -> None:
        """An (H, W, 3) uint8 image with its top-left corner at (x, y)."""
        self.image.paste(Image.fromarray(np.ascontiguousarray(rgb), "RGB"), (round(x), round(y)))

    def colorbar(
        self, x: float, y: float, w: float, h: float, top: float, log: bool,
        cmap: str = "inferno", points: float = 7, label: str = "",
    ) -> None:  # fmt: skip
        """A vertical colour bar for 0..``top`` at (x, y), w x h pixels: the 256 colours bottom
        to top, a frame, ticks and their labels on the right (``tick_values``) and ``label``
        beside them (read from below)."""
        x, y, w, h = round(x), round(y), round(w), round(h)
        rows = (np.arange(h)[::-1] + 0.5) / h
        strip = palette.table(cmap)[colour_index(rows)]
        self.paste(x, y, np.repeat(strip[:, None, :], w, axis=1))
        self.draw.rectangle((x, y, x + w - 1, y + h - 1), outline=FRAME)
        widest = 0
        for t in tick_values(top, log):
            ty = y + (h - 1) * (1 - float(norm(np.array([t]), top, log)[0]))
            self.draw.line((x + w, round(ty), x + w + 2, round(ty)), fill=FRAME)
            text = f"{int(t)}"
            self.text(x + w + 4, ty, text, points, ha="left", va="center")
            widest = max(widest, self.draw.textlength(text, font=font(points)))
        if label:
            self.text(x + w + 8 + widest, y + h / 2, label, 8, ha="left", va="center",
                      rotate=True)  # fmt: skip

    def save(self, path: str | Path) -> Path:
        p = Path(path)
        p.parent.mkdir(parents=True, exist_ok=True)
        self.image.save(p, compress_level=3)  # 6 (the default) takes twice as long
        return p


# ================================================================================= the chart
def log_range(lo: float, hi: float) -> tuple[float, float]:
    """log10 limits of data from ``lo`` to ``hi`` (> 0), 5 % to spare on each side."""
    a, b = math.log10(lo), math.log10(hi)
    pad = 0.05 * (b - a) if b > a else 0.5
    return a - pad, b + pad


def step_chart(
    canvas: Canvas,
    box: tuple[float, float, float, float],
    curves: list[tuple[str, np.ndarray, np.ndarray, float, tuple[int, int, int]]],
    title: str,
    xlabel: str,
    ylabel: str,
    x_limits: tuple[float, float],
) -> None:
    """A log-log chart in ``box`` (x, y, w, h: the plotting area, pixels): each curve
    (label, x, y, line width in points, colour) as steps after each point, a grid at the
    decades, tick labels 10^k, the axis labels, ``title`` above and a legend (two columns) in
    the upper right corner.  Drawn at 3x and reduced, so that the lines are smooth."""
    k = 3
    x0, y0, w, h = (round(v) for v in box)
    ys = [c[2] for c in curves if len(c[2])]
    ylo, yhi = (
        log_range(min(float(np.min(v)) for v in ys), max(float(np.max(v)) for v in ys))
        if ys
        else (0.0, 1.0)
    )
    xlo, xhi = math.log10(x_limits[0]), math.log10(x_limits[1])
    tile = Image.new("RGB", (w * k, h * k), "white")
    d = ImageDraw.Draw(tile)

    def to_px(xv: np.ndarray, yv: np.ndarray) -> list[tuple[float, float]]:
        u = (np.log10(xv) - xlo) / (xhi - xlo) * (w * k - 1)
        v = (1 - (np.log10(yv) - ylo) / (yhi - ylo)) * (h * k - 1)
        return list(zip(u.tolist(), v.tolist(), strict=True))

    xdec = range(math.ceil(xlo), math.floor(xhi) + 1)
    ydec = range(math.ceil(ylo), math.floor(yhi) + 1)
    for e in xdec:
        u = to_px(np.array([10.0**e]), np.array([10.0**ylo]))[0][0]
        d.line((u, 0, u, h * k), fill=GRID, width=k)
    for e in ydec:
        v = to_px(np.array([10.0**xlo]), np.array([10.0**e]))[0][1]
        d.line((0, v, w * k, v), fill=GRID, width=k)
    for _, xv, yv, lw, colour in curves:
        if not len(xv):
            continue
        xs = np.repeat(np.asarray(xv, dtype=np.float64), 2)[1:]
        ys_ = np.repeat(np.asarray(yv, dtype=np.float64), 2)[:-1]
        d.line(to_px(xs, ys_), fill=colour, width=max(1, round(px(lw) * k)), joint="curve")
    tile = tile.resize((w, h), Image.Resampling.BOX)
    canvas.image.paste(tile, (x0, y0))
    draw = canvas.draw
    draw.rectangle((x0, y0, x0 + w - 1, y0 + h - 1), outline=FRAME)
    for e in xdec:  # ticks and labels
        u = x0 + to_px(np.array([10.0**e]), np.array([10.0**ylo]))[0][0] / k
        draw.line((round(u), y0 + h, round(u), y0 + h + 2), fill=FRAME)
        canvas.text(u, y0 + h + 4, f"10{str(e).translate(SUPERSCRIPT)}", 7, va="top")
    widest = 0.0
    for e in ydec:
        v = y0 + to_px(np.array([10.0**xlo]), np.array([10.0**e]))[0][1] / k
        draw.line((x0 - 3, round(v), x0 - 1, round(v)), fill=FRAME)
        label = f"10{str(e).translate(SUPERSCRIPT)}"
        canvas.text(x0 - 4, v, label, 7, ha="right", va="center")
        widest = max(widest, draw.textlength(label, font=font(7)))
    canvas.text(x0 + w / 2, y0 + h + 16, xlabel, 8, va="top")
    canvas.text(x0 - 8 - widest, y0 + h / 2, ylabel, 8, ha="right", va="center", rotate=True)
    canvas.text(x0 + w / 2, y0 - 2, title, 9)
    _legend(canvas, x0 + w - 4, y0 + 4, [(c[0], c[3], c[4]) for c in curves if len(c[1])])


def _legend(canvas: Canvas, right: float, top: float, entries) -> None:
    """Two columns of (label, line width, colour), filled column by column, in a framed box
    whose top-right corner is at (right, top)."""
    if not entries:
        return
    f = font(7)
    rows = -(-len(entries) // 2)
    line_h = round(px(7) * 1.35)
    handle = round(px(7) * 1.2)
    label_w = max(canvas.draw.textlength(e[0], font=f) for e in entries)
    col_w = handle + 4 + label_w + 8
    cols = 1 if len(entries) == 1 else 2
    bw, bh = cols * col_w + 4, rows * line_h + 6
    bx, by = right - bw, top
    canvas.draw.rectangle((bx, by, bx + bw, by + bh), fill="white", outline=(204, 204, 204))
    for i, (label, lw, colour) in enumerate(entries):
        c, r = divmod(i, rows)
        x = bx + 5 + c * col_w
        y = by + 3 + r * line_h + line_h / 2
        canvas.draw.line(
            (x, round(y), x + handle, round(y)), fill=colour, width=max(1, round(px(lw)))
        )
        canvas.text(x + handle + 4, y, label, 7, ha="left", va="center")

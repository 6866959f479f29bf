"""Image output: PNG files (Pillow), error heat-maps and a labelled side-by-side sheet
(matplotlib, Agg backend: no display needed)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np


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
    Image.fromarray(_rgb(image), mode="RGB").save(p)
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


def _pyplot():
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


def save_error_heatmap(
    path: str | Path,
    image,
    reference,
    title: str = "",
    vmax: float | None = None,
    cmap: str = "inferno",
) -> Path:
    """A heat-map PNG of ``error_map(image, reference)`` with a colour bar in 8-bit levels.
    ``vmax`` fixes the top of the scale (default: the largest error, at least 1)."""
    plt = _pyplot()
    err = error_map(image, reference)
    top = float(vmax) if vmax is not None else max(1.0, float(err.max()))
    h, w = err.shape
    fig, ax = plt.subplots(figsize=(w / 80 + 1.4, h / 80 + 0.6), dpi=100)
    im = ax.imshow(err, cmap=cmap, vmin=0.0, vmax=top, interpolation="nearest")
    ax.set_axis_off()
    if title:
        ax.set_title(title, fontsize=9)
    bar = fig.colorbar(im, ax=ax, fraction=0.046, pad=0.04)
    bar.set_label("|error| (8-bit levels)", fontsize=8)
    bar.ax.tick_params(labelsize=7)
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(p, bbox_inches="tight")
    plt.close(fig)
    return p


def save_sheet(
    path: str | Path,
    panels: Sequence[tuple[str, np.ndarray]],
    columns: int = 4,
    title: str = "",
    error_reference: np.ndarray | None = None,
    error_vmax: float | None = None,
) -> Path:
    """A side-by-side sheet: one labelled panel per ``(label, image)``.

    With ``error_reference`` a second row of panels per row shows each image's error heat-map
    against it (shared scale ``error_vmax``, default the largest error), with one colour bar.
    """
    plt = _pyplot()
    if not panels:
        raise ValueError("panels = [] is not legal: the sheet needs at least one image")
    imgs = [(str(label), _rgb(img)) for label, img in panels]
    cols = max(1, min(int(columns), len(imgs)))
    rows = -(-len(imgs) // cols)
    errs = None
    if error_reference is not None:
        errs = [error_map(img, error_reference) for _, img in imgs]
        top = error_vmax if error_vmax is not None else max(1.0, max(float(e.max()) for e in errs))
    h, w = imgs[0][1].shape[:2]
    panel_rows = rows * (2 if errs is not None else 1)
    scale = 2.4 / max(h, w)
    fig, axes = plt.subplots(
        panel_rows,
        cols,
        figsize=(cols * w * scale + 0.8, panel_rows * (h * scale + 0.35) + 0.4),
        dpi=110,
        squeeze=False,
    )
    im_err = None
    for k in range(rows * cols):
        r, c = divmod(k, cols)
        ax = axes[r * (2 if errs is not None else 1), c]
        ax.set_axis_off()
        if errs is not None:
            axes[r * 2 + 1, c].set_axis_off()
        if k >= len(imgs):
            continue
        label, img = imgs[k]
        ax.imshow(img, interpolation="nearest")
        ax.set_title(label, fontsize=8)
        if errs is not None:
            eax = axes[r * 2 + 1, c]
            im_err = eax.imshow(errs[k], cmap="inferno", vmin=0, vmax=top, interpolation="nearest")
            eax.set_title(f"error, max {errs[k].max():.0f}", fontsize=7)
    if im_err is not None:
        bar = fig.colorbar(im_err, ax=axes.ravel().tolist(), fraction=0.02, pad=0.01)
        bar.set_label("|error| (8-bit levels)", fontsize=8)
    if title:
        fig.suptitle(title, fontsize=10)
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(p, bbox_inches="tight")
    plt.close(fig)
    return p

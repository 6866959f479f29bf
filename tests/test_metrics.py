# SPDX-License-Identifier: Apache-2.0
"""Metrics on known inputs, and the image helpers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from model.study import images, metrics


def ref_image(h: int = 8, w: int = 10, value: int = 100) -> np.ndarray:
    return np.full((h, w, 3), value, dtype=np.uint8)


def test_identical_images() -> None:
    ref = np.random.default_rng(1).integers(0, 256, (12, 9, 3)).astype(np.uint8)
    assert metrics.nmse(ref, ref) == 0.0
    assert metrics.psnr(ref, ref) == math.inf
    assert metrics.max_abs_error(ref, ref) == 0.0
    assert metrics.share_off_by_more_than(ref, ref) == 0.0
    c = metrics.compare(ref, ref)
    assert c.visually_identical and c.nmse == 0.0


def test_known_perturbation() -> None:
    h, w = 8, 10
    ref = ref_image(h, w, 100)
    img = ref.copy()
    img[2, 3, 1] = 103  # one channel of one pixel off by 3
    img[5, 5, :] = 98  # every channel of another pixel off by 2
    sq = 3**2 + 3 * 2**2  # 21
    assert metrics.nmse(img, ref) == pytest.approx(sq / (100.0**2 * h * w * 3))
    mse = sq / (h * w * 3)
    assert metrics.psnr(img, ref) == pytest.approx(10 * math.log10(255**2 / mse))
    assert metrics.max_abs_error(img, ref) == 3.0
    assert metrics.share_off_by_more_than(img, ref, 1) == pytest.approx(2 / (h * w))
    assert metrics.share_off_by_more_than(img, ref, 2) == pytest.approx(1 / (h * w))
    assert metrics.share_off_by_more_than(img, ref, 3) == 0.0
    # restricted to a mask holding only the first pixel and one exact pixel
    mask = np.zeros((h, w), dtype=bool)
    mask[2, 3] = mask[0, 0] = True
    assert metrics.nmse(img, ref, mask) == pytest.approx(9 / (100.0**2 * 6))
    assert metrics.max_abs_error(img, ref, mask) == 3.0


def test_visually_identical_threshold() -> None:
    assert metrics.NMSE_VISUALLY_IDENTICAL == 0.00025
    ref = ref_image(10, 10, 200)
    img = ref.copy()
    # NMSE = k * d^2 / (200^2 * 300): d = 3 on 333 channels... use whole pixels: 3 channels each
    img[:1, :4] = 203  # 12 channels off by 3: 108 / 12e6 = 9e-6
    c = metrics.compare(img, ref)
    assert c.visually_identical and c.nmse == pytest.approx(108 / (200.0**2 * 300))
    img[:] = 206  # every channel off by 6: 36/40000 = 9e-4
    c = metrics.compare(img, ref)
    assert not c.visually_identical and c.nmse == pytest.approx(36 / 200.0**2)
    assert c.share_off_by_more_than_1 == 1.0


def test_highlight_mask_and_restricted_figures() -> None:
    ref = ref_image(6, 6, 50)
    spec = np.zeros((6, 6))
    spec[1:3, 1:3] = 40.0
    spec[4, 4] = 5.0
    mask = metrics.highlight_mask(spec, threshold=8.0)
    assert mask.sum() == 4 and not mask[4, 4]
    img = ref.copy()
    img[1, 1] = 60  # inside the highlight: off by 10
    img[5, 5] = 51  # outside: off by 1
    c = metrics.compare(img, ref, highlight=mask)
    assert c.highlight_pixels == 4
    assert c.highlight_max_abs_error == 10.0
    assert c.highlight_mean_abs_error == pytest.approx(30 / 12)
    assert c.highlight_nmse == pytest.approx(300 / (50.0**2 * 12))
    assert c.max_abs_error == 10.0
    none = metrics.compare(img, ref, highlight=np.zeros((6, 6), dtype=bool))
    assert none.highlight_pixels == 0 and math.isnan(none.highlight_nmse)
    assert set(c.as_dict()) >= {"nmse", "psnr", "highlight_nmse"}


def test_zero_reference() -> None:
    z = np.zeros((2, 2, 3), dtype=np.uint8)
    assert metrics.nmse(z, z) == 0.0
    assert metrics.nmse(z + 1, z) == math.inf


def test_bad_input() -> None:
    with pytest.raises(ValueError, match=r"image shape = .* must equal the reference"):
        metrics.nmse(ref_image(4, 4), ref_image(4, 5))
    with pytest.raises(ValueError, match="mask shape"):
        metrics.nmse(ref_image(4, 4), ref_image(4, 4), np.ones((3, 3), dtype=bool))
    with pytest.raises(ValueError, match="specular = None"):
        metrics.highlight_mask(None)
    with pytest.raises(ValueError, match=r"legal is \(H, W, 3\) uint8"):
        images.save_png("/tmp/never.png", np.zeros((4, 4)))


def test_png_round_trip_heatmap_and_sheet(tmp_path) -> None:
    rng = np.random.default_rng(7)
    ref = rng.integers(0, 256, (20, 30, 3)).astype(np.uint8)
    img = ref.copy()
    img[5:8, 5:9] = 0
    p = images.save_png(tmp_path / "a" / "ref.png", ref)
    assert np.array_equal(images.load_png(p), ref)
    err = images.error_map(img, ref)
    assert err.shape == (20, 30) and err.max() == ref[5:8, 5:9].max()
    heat = images.save_error_heatmap(tmp_path / "heat.png", img, ref, title="err")
    sheet = images.save_sheet(
        tmp_path / "sheet.png",
        [("reference", ref), ("method", img), ("again", img)],
        columns=2,
        title="sheet",
        error_reference=ref,
    )
    plain = images.save_sheet(tmp_path / "plain.png", [("one", ref)])
    for path in (heat, sheet, plain):
        out = images.load_png(path)
        assert out.ndim == 3 and out.shape[0] > 20 and out.shape[1] > 20
    with pytest.raises(ValueError, match="at least one image"):
        images.save_sheet(tmp_path / "x.png", [])

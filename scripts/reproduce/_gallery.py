"""Shared plumbing of the gallery reproduction scripts (not part of the warpoptics package).

Panels of rendered images with titles composed into one small PNG, a JSON readout written next to
it, the jobs of a sweep preset as scenes, and a wall-clock timer.  Every number these helpers
return comes from warpoptics (``wo.render``, ``warpoptics.metrics``); nothing here re-derives
physics.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
GALLERY = ROOT / "docs" / "gallery"
# the sampling the three-wavelength and wavelength-sampling figures were made with
# (scenes/diamond.toml's until it moved to adaptive sampling and splits down to 5 %): every pixel
# the same samples, splits down to 0.2 %
FIGURE_SAMPLING = {"render.adaptive": False, "render.split_threshold": 0.002}


class Timer:
    """``with Timer() as t: ...``; ``t.seconds`` is the wall time of the block."""

    def __enter__(self):
        self.t0 = time.perf_counter()
        self.seconds = float("nan")
        return self

    def __exit__(self, *exc):
        self.seconds = time.perf_counter() - self.t0
        return False


def sweep_scenes(path: str | Path, *, overrides: dict | None = None):
    """[(job, Scene)] of a sweep preset (``scenes/sweeps/*.toml``): its axes and expressions
    resolved exactly as ``warpoptics sweep`` resolves them, plus ``overrides`` (dotted paths)."""
    from warpoptics.sweep import Sweep
    from warpoptics.sweep.spec import scene_for

    sw = Sweep.load(path)
    data, scene_path, _ = sw.scene_source()
    out = []
    for job in sw.jobs():
        ov = {**job.overrides, **(overrides or {})}
        out.append((job, scene_for(data, scene_path, ov, sw.base_dir)))
    return out


def compose(
    path: str | Path,
    rows: list[list[np.ndarray]],
    titles: list[list[str]],
    *,
    suptitle: str = "",
    footer: str = "",
    panel_inches: float = 2.0,
    colorbar: dict | None = None,
    dpi: int = 100,
) -> Path:
    """Write a grid of display images ``rows[r][c]`` (H, W, 3) in [0, 1] with ``titles`` as a PNG.
    ``colorbar``: {"row": r, "scale": s, "label": str, "cmap": name} adds a colour bar (default
    inferno, the ΔE maps' of ``warpoptics.metrics.difference_image``) beside row r."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from warpoptics.film.image import save_figure

    nr = len(rows)
    nc = max(len(r) for r in rows)
    extra = 0.5 if colorbar else 0.0
    fig, axes = plt.subplots(
        nr,
        nc,
        figsize=(panel_inches * nc + extra, panel_inches * nr + 0.35 * nr + 0.6 + (0.3 if footer else 0.0)),
        squeeze=False,
    )
    for r in range(nr):
        for c in range(nc):
            a = axes[r][c]
            a.set_xticks([])
            a.set_yticks([])
            if c < len(rows[r]):
                a.imshow(np.clip(rows[r][c], 0.0, 1.0), interpolation="nearest")
                a.set_title(titles[r][c], fontsize=7)
            else:
                a.axis("off")
    if suptitle:
        fig.suptitle(suptitle, fontsize=9)
    if footer:
        fig.text(0.5, 0.01, footer, ha="center", va="bottom", fontsize=7)
    fig.tight_layout(rect=(0, 0.04 if footer else 0.0, 1, 1))
    if colorbar:
        from matplotlib import cm, colors

        r = colorbar["row"]
        sm = cm.ScalarMappable(
            norm=colors.Normalize(0.0, colorbar["scale"]), cmap=colorbar.get("cmap", "inferno")
        )
        cb = fig.colorbar(sm, ax=list(axes[r]), fraction=0.02, pad=0.01)
        cb.set_label(colorbar.get("label", "ΔE00"), fontsize=7)
        cb.ax.tick_params(labelsize=6)
    save_figure(fig, path, dpi=dpi, bbox_inches="tight")  # atomic: temp file + rename
    plt.close(fig)
    return Path(path)


def stone_box(*alphas: np.ndarray, margin: float = 0.06) -> tuple[slice, slice]:
    """(rows, cols) slices of the square around every pixel that any ``alphas`` (H, W) covers,
    grown by ``margin`` of the image size: panels cropped to the stone, for display only."""
    a = np.max(np.stack([np.asarray(x) for x in alphas]), axis=0) > 0.0
    h, w = a.shape
    if not a.any():
        return slice(0, h), slice(0, w)
    ys, xs = np.nonzero(a)
    cy, cx = 0.5 * (ys.min() + ys.max()), 0.5 * (xs.min() + xs.max())
    half = 0.5 * max(ys.max() - ys.min(), xs.max() - xs.min()) + margin * max(h, w)
    y0, y1 = max(0, int(cy - half)), min(h, int(np.ceil(cy + half)) + 1)
    x0, x1 = max(0, int(cx - half)), min(w, int(np.ceil(cx + half)) + 1)
    return slice(y0, y1), slice(x0, x1)


def write_json(path: str | Path, data: dict) -> Path:
    """Write ``data`` as indented JSON atomically (temp file + rename)."""
    from warpoptics.film.image import atomic_path

    path = Path(path)
    with atomic_path(path) as tmp:
        Path(tmp).write_text(json.dumps(data, indent=2, default=float) + "\n", encoding="utf-8")
    return path


def display_rmse(a: np.ndarray, b: np.ndarray, mask: np.ndarray | None = None) -> float:
    """Root-mean-square difference of two display-encoded sRGB images (values in [0, 1]), over
    all channels of the pixels in ``mask`` (all pixels by default)."""
    d = np.asarray(a, dtype=np.float64) - np.asarray(b, dtype=np.float64)
    if mask is not None:
        d = d[np.asarray(mask, dtype=bool)]
    return float(np.sqrt(np.mean(d * d)))

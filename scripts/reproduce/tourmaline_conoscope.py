"""The gem polariscope with a conoscope sphere over a faceted stone.

Renders scenes/tourmaline_conoscope.toml (a BK7 sphere over the table of a 5 mm tourmaline
brilliant, optic axis along the view, crossed polarizers) in the coherent mode and in the
incoherent ``exact`` mode and writes them side by side.  Prints, for both, the mean crossed
image along the polarizer directions through the centre over the mean along the diagonals (the
isogyre cross: much below 1) and the pixels where the two modes differ (the first isochromes,
near the axis, where the o and e waves leave the pavilion in one direction).

Usage:
    python scripts/reproduce/tourmaline_conoscope.py [-o docs/gallery/tourmaline_conoscope.png]
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import _guy_soler_panels as sp
import numpy as np

import warpoptics as wo

SCENE = Path(__file__).resolve().parents[2] / "scenes" / "tourmaline_conoscope.toml"


def cross_ratio(y: np.ndarray) -> float:
    """Mean of ``y`` within 10 degrees of the polarizer directions over the mean within 10 degrees
    of the diagonals, 0.15-0.7 of the half-image from the centre."""
    n = y.shape[0]
    yy, xx = np.mgrid[:n, :n]
    c = (n - 1) / 2
    r = np.hypot(xx - c, yy - c) / (n / 2)
    psi = np.degrees(np.arctan2(yy - c, xx - c)) % 90.0
    ring = (r >= 0.15) & (r < 0.7)
    lines = ring & (np.minimum(psi, 90.0 - psi) < 10.0)
    diag = ring & (np.abs(psi - 45.0) < 10.0)
    return float(y[lines].mean() / y[diag].mean())


def main(argv: list[str] | None = None) -> int:
    args = sp.parser(__doc__, "docs/gallery/tourmaline_conoscope.png").parse_args(argv)
    size, wl = sp.sizes(args, 192, 16)
    base = wo.Scene.load(SCENE).with_overrides(width=size, height=size, wavelengths=wl)
    views, ys = {}, {}
    for mode in ("coherent", "exact"):
        t0 = time.perf_counter()
        img = wo.render(base.with_overrides({"render.birefringence": mode}), device=args.device)
        v = img.view("polariscope")
        views[mode], ys[mode] = v, v.xyz[..., 1].astype(np.float64)
        print(
            f"{mode}: {size} px, {wl} wavelengths, {time.perf_counter() - t0:.1f} s; "
            f"polarizer lines / diagonals {cross_ratio(ys[mode]):.3f}"
        )
    d = np.abs(ys["coherent"] - ys["exact"])
    print(
        f"coherent vs exact: {int((d > 0.05 * ys['exact'].max()).sum())} pixels differ by > 5 % of the peak"
    )
    panels = [
        ("coherent", views["coherent"].display()),
        ("exact (o + e powers)", views["exact"].display()),
    ]
    sp.montage(args.output, panels, title="tourmaline, axis along the view, BK7 sphere")
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Reproduce fig. 3 of Guy & Soler 2004 (seed 002): pleochroism of a green tourmaline.

A long step-cut tourmaline (14 x 7 mm, §6.1 absorbance spectra, eq. 7 for the e-wave, exact o/e
transport), seen from above on a white dome (diffuse light from the whole upper hemisphere),
with its optic axis toward the eye, left-right (as in the paper's photo) and up-down, side by
side.  With the axis toward the eye both waves are ordinary (K^o); across the view half of the
light is extraordinary and sees K^e.  Top row: the §6.1 absorbances as tabulated (base-e per
mm): a pale stone.  Bottom row: the same spectra x 4 (``absorption_scale``), a darker stone in
which the two colours are easier to see.  Prints the mean colour of the stone in each panel and
the CIEDE2000 difference (brightness removed) against the axis-toward-the-eye panel of its row.

Usage:
    python scripts/reproduce/seed002_fig3_pleochroism.py [-o docs/gallery/seed002_fig3_pleochroism.png]
"""

from __future__ import annotations

import sys
import time

import _seed002_panels as sp

CAMERA = {"position": [0.0, -8.0, 40.0], "look_at": [0.0, 0.0, -0.5], "fov": 24.0}
STONE = {"length": 14.0, "width": 7.0}


def main(argv: list[str] | None = None) -> int:
    args = sp.parser(__doc__, "docs/gallery/seed002_fig3_pleochroism.png").parse_args(argv)
    size, wl = sp.sizes(args, 112, 12)
    t0 = time.perf_counter()
    rows = []
    print(f"tourmaline (Guy & Soler §6.1 spectra), step cut 14 x 7 mm, {size} px, {wl} wavelengths, dome light")
    for scale in (1.0, 4.0):
        panels = sp.axis_panels("tourmaline", ["toward the eye", "left-right", "up-down"], size=size,
                                wavelengths=wl, device=args.device, obj={**STONE, "absorption_scale": scale},
                                camera=CAMERA, render={"exposure": 0.0},
                                light={"type": "environment", "map": "dome"})
        ref = panels[0]
        for p in panels:
            print(f"  absorbance x{scale:g}  axis {p.label:15s} {p.describe()}  dE00 vs toward-the-eye "
                  f"{sp.delta_e(p, ref):5.2f}  ({p.seconds:.1f} s)")
        rows.append([(f"x{scale:g}: axis {p.label}", p.image.display()) for p in panels])
    sp.montage(args.output, rows, title="tourmaline pleochroism, optic axis toward the eye | left-right | up-down")
    print(f"wrote {args.output}  total {time.perf_counter() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())

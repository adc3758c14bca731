"""Reproduce fig. 3 of Guy & Soler 2004: pleochroism of a green tourmaline.

A long step-cut tourmaline (14 x 7 mm, §6.1 absorbance spectra, eq. 7 for the e-wave, exact o/e
transport), seen from above on a white dome (diffuse light from the whole upper hemisphere),
with its optic axis toward the eye, left-right (as in the paper's photo) and up-down, side by
side.  With the axis toward the eye both waves are ordinary (K^o); across the view half of the
light is extraordinary and sees K^e.  Top row: the §6.1 absorbances as tabulated (base-e per
mm): a pale stone.  Bottom row: the same spectra x 4 (``absorption_scale``), a darker stone in
which the two colours are easier to see.  Prints the mean colour of the stone in each panel and
the CIEDE2000 difference (brightness removed) against the axis-toward-the-eye panel of its row.

Usage:
    python scripts/reproduce/guy_soler_fig3_pleochroism.py [-o docs/gallery/guy_soler_fig3_pleochroism.png]
"""

from __future__ import annotations

import sys
import time

import _guy_soler_panels as sp


def main(argv: list[str] | None = None) -> int:
    args = sp.parser(__doc__, "docs/gallery/guy_soler_fig3_pleochroism.png").parse_args(argv)
    size, wl = sp.sizes(args, 112, 12)
    t0 = time.perf_counter()
    print(
        f"tourmaline (Guy & Soler §6.1 spectra), step cut 14 x 7 mm, {size} px, {wl} wavelengths, dome light"
    )
    rows = sp.pleochroism_rows(
        "tourmaline",
        ["toward the eye", "left-right", "up-down"],
        (1.0, 4.0),
        size=size,
        wavelengths=wl,
        device=args.device,
    )
    sp.montage(
        args.output, rows, title="tourmaline pleochroism, optic axis toward the eye | left-right | up-down"
    )
    print(f"wrote {args.output}  total {time.perf_counter() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())

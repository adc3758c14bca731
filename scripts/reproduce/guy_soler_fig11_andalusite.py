"""Reproduce the andalusite of Guy & Soler 2004 fig. 11 (e)-(g).

A long step-cut andalusite (14 x 7 mm; §6.1: biaxial treated as uniaxial, n_o 1.635, n_e 1.644
± .005, K^o = (0.0056, 0.006, 0.0183), K^e = (0.170, 0.175, 0.257) per mm as eq. 9 spectra) seen
from above on the white dome, with its optic axis (e) toward the eye, (f) up-down and (g)
left-right in the image.  The library's ``andalusite`` is biaxial; the paper's uniaxial
approximation is the entry ``andalusite_uniaxial``, used here (the biaxial stone beside it:
``scripts/reproduce/biaxial_gallery.py``).  Top row: absorbances as tabulated; bottom row: x 5.
Prints the mean colour of the stone per panel and the CIEDE2000 difference (brightness removed) against the
axis-toward-the-eye panel of its row.

Usage:
    python scripts/reproduce/guy_soler_fig11_andalusite.py [-o docs/gallery/guy_soler_fig11_andalusite.png]
"""

from __future__ import annotations

import sys
import time

import _guy_soler_panels as sp


def main(argv: list[str] | None = None) -> int:
    args = sp.parser(__doc__, "docs/gallery/guy_soler_fig11_andalusite.png").parse_args(argv)
    size, wl = sp.sizes(args, 112, 12)
    t0 = time.perf_counter()
    print(
        f"andalusite_uniaxial (Guy & Soler §6.1, the uniaxial approximation), step cut 14 x 7 mm, "
        f"{size} px, {wl} wavelengths, dome light"
    )
    rows = sp.pleochroism_rows(
        "andalusite_uniaxial",
        ["toward the eye", "up-down", "left-right"],
        (1.0, 5.0),
        size=size,
        wavelengths=wl,
        device=args.device,
    )
    sp.montage(
        args.output, rows, title="andalusite: optic axis toward the eye | up-down | left-right (fig. 11 e-g)"
    )
    print(f"wrote {args.output}  total {time.perf_counter() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())

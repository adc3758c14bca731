"""Reproduce the andalusite of Guy & Soler 2004 (seed 002) fig. 11 (e)-(g).

The step-cut andalusite (§6.1: biaxial treated as uniaxial, n_o 1.635, n_e 1.644 ± .005,
K^o = (0.0056, 0.006, 0.0183), K^e = (0.170, 0.175, 0.257) per mm as eq. 9 spectra) with its optic
axis (e) toward the eye, (f) up-down and (g) left-right in the image, same studio light.  Prints
the mean colour of the stone per panel and the CIEDE2000 differences (brightness removed).

Usage:
    python scripts/reproduce/seed002_fig11_andalusite.py [-o docs/gallery/seed002_fig11_andalusite.png]
"""

from __future__ import annotations

import sys
import time

import _seed002_panels as sp


def main(argv: list[str] | None = None) -> int:
    args = sp.parser(__doc__, "docs/gallery/seed002_fig11_andalusite.png").parse_args(argv)
    size, wl = sp.sizes(args, 128, 8)
    t0 = time.perf_counter()
    panels = sp.axis_panels("andalusite", ["toward the eye", "up-down", "left-right"], size=size, wavelengths=wl,
                            device=args.device)
    print(f"andalusite (Guy & Soler §6.1), step cut 8 x 6 mm, {size} px, {wl} wavelengths, studio light")
    for p in panels:
        print(f"  axis {p.label:15s} {p.describe()}  ({p.seconds:.1f} s)")
    for i in range(3):
        for j in range(i + 1, 3):
            a, b = panels[i], panels[j]
            print(f"  dE00 (brightness removed) {a.label} vs {b.label}: {sp.delta_e(a, b):.2f}")
    sp.montage(args.output, [(p.label, p.image.display()) for p in panels],
               title="andalusite: optic axis toward the eye | up-down | left-right (fig. 11 e-g)")
    print(f"wrote {args.output}  total {time.perf_counter() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())

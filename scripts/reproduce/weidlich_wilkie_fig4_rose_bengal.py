"""Reproduce Weidlich & Wilkie 2009, fig. 4: n(λ) and k(λ) of three rose bengal solutions beside water.

The solutions (10 %, 3.3 %, 1 %) are water (refractiveindex.info Daimon 20 °C) plus the
Kramers–Kronig index of the dye's absorption bands (warpoptics.materials.kramers_kronig).  The
source's curves come from van der Plaats (1915) data; ours from documented Gaussian bands, so
the shapes match (n dips on the short side and rises on the long side of the 549 nm band; the
swing grows with concentration) but the exact values do not.

    python scripts/reproduce/weidlich_wilkie_fig4_rose_bengal.py -o out/weidlich_wilkie_fig4.png
"""

from __future__ import annotations

import argparse
import sys

import numpy as np


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", required=True, help="PNG file to write")
    ap.add_argument("--step", type=float, default=1.0, help="wavelength step of the plot (nm)")
    args = ap.parse_args(argv)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    import warpoptics as wo

    lam = np.arange(400.0, 700.0 + 1e-9, args.step)
    water = wo.materials.get("water")
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
    colours = {"10": "#8b0045", "3.3": "#d6417f", "1": "#f4a3c4"}
    for pct, col in colours.items():
        mat = wo.materials.get(f"rose_bengal_{pct}")
        n, k = mat.n(lam), mat.k(lam)
        a1.plot(lam, n, color=col, label=f"rose bengal {pct} %")
        a2.plot(lam, k, color=col, label=f"rose bengal {pct} %")
        i_lo, i_hi = int(np.argmin(n)), int(np.argmax(n))
        print(
            f"rose bengal {pct:>3s} %: k max {k.max():.4f} at {lam[np.argmax(k)]:.0f} nm; "
            f"n min {n[i_lo]:.4f} at {lam[i_lo]:.0f} nm, n max {n[i_hi]:.4f} at {lam[i_hi]:.0f} nm"
        )
    a1.plot(lam, water.n(lam), "k:", label="water")
    a1.set_title("(a) refractive index n")
    a2.set_title("(b) extinction coefficient k")
    for a in (a1, a2):
        a.set_xlabel("wavelength (nm)")
        a.grid(alpha=0.3)
        a.legend()
    fig.suptitle("Weidlich & Wilkie 2009 fig. 4: rose bengal in water (Kramers–Kronig, Maclaurin)")
    fig.tight_layout()
    from warpoptics.film.image import save_figure

    save_figure(fig, args.output, dpi=100)  # atomic: temp file + rename
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

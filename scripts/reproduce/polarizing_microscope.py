"""The polarizing microscope: the Michel-Lévy chart and conoscopic figures.

Writes into the output directory (default docs/gallery):

- ``michel_levy.png``: interference colours against retardation 0-2000 nm with thickness and
  birefringence lines (``warpoptics chart michel-levy``);
- ``conoscope_calcite.png``: a calcite plate 0.25 mm thick cut across its optic axis, NA 0.5,
  crossed polarizers: 589 nm | white light (the uniaxial cross and isochromes) | white light
  with a first-order red plate (slow NE-SW): yellow NE/SW, blue NW/SE, the optic sign (-);
- ``conoscope_tanzanite.png``: a tanzanite (biaxial, 2V = 60 deg) plate 1 mm thick cut across its
  acute bisectrix Z, NA 0.9, white light: optic axial plane along the polarizer (cross) | at 45
  degrees (isogyres through the two melatopes).

Prints the isochrome radii of the calcite figure against the analytic Delta(theta) = k lambda.
Optical activity (the quartz "bull's eye") and strained glass: scripts/reproduce/quartz_and_strained_glass.py.

Usage:
    python scripts/reproduce/polarizing_microscope.py [-o docs/gallery] [--quick]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

import warpoptics as wo
from warpoptics.commands.chart import draw_conoscope, draw_michel_levy
from warpoptics.pipelines import microscope as ms


def _side_by_side(parts: list[Path], out: Path) -> None:
    from PIL import Image

    ims = [Image.open(p).convert("RGB") for p in parts]
    w = Image.new("RGB", (sum(i.width for i in ims), max(i.height for i in ims)), "white")
    x = 0
    for im in ims:
        w.paste(im, (x, 0))
        x += im.width
    with wo.atomic.atomic_path(out) as tmp:
        w.save(tmp, format="png")
    for p in parts:
        p.unlink()


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("-o", "--output", default="docs/gallery", help="output directory (default docs/gallery)")
    p.add_argument("--quick", action="store_true", help="small figures (a smoke test)")
    p.add_argument("--device", default=None)
    args = p.parse_args(argv)
    out = Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    size = 48 if args.quick else 241
    columns = 101 if args.quick else 801

    chart = ms.michel_levy_chart(columns=columns, device=args.device)
    draw_michel_levy(chart, out / "michel_levy.png")
    print(f"wrote {out / 'michel_levy.png'}")

    calcite = wo.materials.get("calcite")
    d, na, lam = 0.25, 0.5, 589.3
    mono = ms.conoscopic_figure(
        calcite, d, size=size, numerical_aperture=na, wavelength_nm=lam, device=args.device
    )
    white = ms.conoscopic_figure(
        calcite, d, size=size, numerical_aperture=na, wavelength_nm=None, device=args.device
    )
    gypsum = ms.conoscopic_figure(
        calcite,
        d,
        size=size,
        numerical_aperture=na,
        wavelength_nm=None,
        accessory_nm=550.0,
        device=args.device,
    )
    draw_conoscope(
        mono, out / "_a.png", title=f"calcite cut across c, {d} mm, NA {na}, {lam} nm, crossed polarizers"
    )
    draw_conoscope(white, out / "_b.png", title="the same in white light (D65)")
    draw_conoscope(gypsum, out / "_c.png", title="with a first-order red plate, slow NE-SW: negative sign")
    _side_by_side([out / "_a.png", out / "_b.png", out / "_c.png"], out / "conoscope_calcite.png")
    print(f"wrote {out / 'conoscope_calcite.png'}")
    no, ne = calcite.n(lam)
    r = np.linspace(0.0, 1.0, 2001)
    prof = ms.conoscope_profile(calcite, d, r, wavelength_nm=lam, numerical_aperture=na, device=args.device)
    s = na * r
    delta = d * 1e6 * (np.sqrt(no**2 - s**2) - no / ne * np.sqrt(ne**2 - s**2))
    for k in range(1, 6):
        j = int(np.argmin(np.abs(delta - k * lam)))
        lo, hi = max(j - 40, 1), min(j + 40, r.size - 1)
        m = lo + int(np.argmin(prof[lo:hi]))
        print(f"  ring {k}: analytic r = {r[j]:.4f}, figure minimum r = {r[m]:.4f} (of the aperture)")

    tz = wo.materials.get("tanzanite")
    c = np.sqrt(0.5)
    turn = np.array([[c, c, 0.0], [-c, c, 0.0], [0.0, 0.0, 1.0]])
    axes0 = np.asarray(tz.crystal_axes)  # Z (the acute bisectrix, optic sign +) along the axis
    figs = []
    for axes in (axes0, axes0 @ turn):
        figs.append(
            ms.conoscopic_figure(
                tz,
                1.0,
                size=size,
                numerical_aperture=0.9,
                wavelength_nm=None,
                crystal_axes=axes,
                device=args.device,
            )
        )
    draw_conoscope(
        figs[0],
        out / "_a.png",
        title="tanzanite cut across Z (acute bisectrix), 1 mm, NA 0.9: axial plane E-W",
    )
    draw_conoscope(figs[1], out / "_b.png", title="the same at 45°: isogyres through the melatopes")
    _side_by_side([out / "_a.png", out / "_b.png"], out / "conoscope_tanzanite.png")
    two_v = float(tz.two_v(589.3))
    print(f"wrote {out / 'conoscope_tanzanite.png'} (2V = {two_v:.1f} deg, sign {tz.optic_sign})")
    return 0


if __name__ == "__main__":
    sys.exit(main())

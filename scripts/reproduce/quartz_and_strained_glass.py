"""Optical activity and strained glass between polarizers.

Writes into the output directory (default docs/gallery):

- ``quartz_bullseye.png``: conoscopic figures, NA 0.5, crossed polarizers (E-W, N-S), white
  light (D65): calcite 0.25 mm cut across c (the uniaxial cross reaches the centre) | a
  right-handed quartz plate 3 mm thick cut across c without optical activity (the same cross)
  | the same plate with its optical activity: the "bull's eye", a coloured centre with no
  isogyres there (rho d = 65 deg at 589 nm, dispersed) and the cross back in the outer rings |
  the same at 589.3 nm;
- ``strained_glass.png``: a BK7 disc 20 mm across, 5 mm thick, under diametral compression of
  4 kN (the Brazilian disc, fringe order 2.4 at the centre), plane (top) and circular (bottom)
  polariscope: strain-free glass (black) | strained, white light | strained, 589.3 nm; below,
  a 6 mm BK7 plate seen edge-on through 20 mm of glass in the plane polariscope at 45 degrees:
  annealed (black) | quenched (parabolic residual stress, 30 MPa surface compression), white
  light | 589.3 nm.

Prints the fringe order at the disc centre and the centre transmission of the quartz plate
against the closed forms.

Usage:
    python scripts/reproduce/quartz_and_strained_glass.py [-o docs/gallery] [--quick]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

import warpoptics as wo
from warpoptics.commands.chart import draw_conoscope
from warpoptics.materials.stress import STRESS_OPTIC_TPA, brazilian_disc
from warpoptics.optics.photoelastic import principal_stresses, stress_retardations
from warpoptics.pipelines import microscope as ms
from warpoptics.pipelines import photoelastic as pe


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


def _disc_grid(images, titles, out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from warpoptics.film.image import save_figure

    rows, cols = len(images), len(images[0])
    ratios = [row[0].mask.shape[0] / row[0].mask.shape[1] for row in images]
    fig, axes = plt.subplots(
        rows,
        cols,
        figsize=(3.0 * cols, sum(3.0 * r + 0.25 for r in ratios)),
        gridspec_kw={"height_ratios": [3.0 * r + 0.25 for r in ratios]},
        squeeze=False,
    )
    for r in range(rows):
        for c in range(cols):
            ax = axes[r][c]
            im = images[r][c]
            ax.imshow(im.srgb, interpolation="bilinear")
            n, m = im.mask.shape
            if n == m:  # the disc's rim, so that black glass shows against the field
                ax.add_patch(plt.Circle(((n - 1) / 2, (n - 1) / 2), n / 2, fill=False, color="0.45", lw=0.6))
            else:  # the plate's faces
                ax.add_patch(plt.Rectangle((-0.5, -0.5), m, n, fill=False, color="0.45", lw=0.6))
            ax.set_xticks([])
            ax.set_yticks([])
            ax.set_title(titles[r][c], fontsize=7)
    fig.tight_layout()
    save_figure(fig, out, dpi=120)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("-o", "--output", default="docs/gallery", help="output directory (default docs/gallery)")
    p.add_argument("--quick", action="store_true", help="small figures (a smoke test)")
    p.add_argument("--device", default=None)
    args = p.parse_args(argv)
    out = Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    size = 40 if args.quick else 201
    dev = args.device

    # --- quartz: the bull's eye next to calcite's cross
    calcite = wo.materials.get("calcite")
    quartz = wo.materials.get("quartz")
    na, d, lam = 0.5, 3.0, 589.3
    cone = dict(size=size, numerical_aperture=na, device=dev)
    figs = [
        (ms.conoscopic_figure(calcite, 0.25, wavelength_nm=None, **cone), "calcite ⊥c, 0.25 mm, white light"),
        (
            ms.conoscopic_figure(quartz, d, wavelength_nm=None, **cone),
            f"quartz ⊥c, {d} mm, no optical activity",
        ),
        (
            ms.conoscopic_figure(quartz, d, wavelength_nm=None, optical_activity="right", **cone),
            f"quartz ⊥c, {d} mm, right-handed: bull's eye",
        ),
        (
            ms.conoscopic_figure(
                quartz, d, wavelength_nm=lam, optical_activity="right", exposure=1.0, **cone
            ),
            f"the same at {lam} nm",
        ),
    ]
    for i, (fig, title) in enumerate(figs):
        draw_conoscope(fig, out / f"_q{i}.png", title=title)
    _side_by_side([out / f"_q{i}.png" for i in range(len(figs))], out / "quartz_bullseye.png")
    rho = abs(float(wo.materials.optical_activity("quartz").rho_rad_mm(lam)))
    no = float(quartz.n([lam])[0, 0])
    centre = ms.conoscope_profile(quartz, d, [0.0], wavelength_nm=lam, optical_activity="right", device=dev)[
        0
    ]
    fresnel = (4 * no / (1 + no) ** 2) ** 2
    print(
        f"wrote {out / 'quartz_bullseye.png'}: centre transmission {centre:.5f}, "
        f"closed form T^2 sin^2(rho d) = {fresnel * np.sin(rho * d) ** 2:.5f} "
        f"(rho d = {np.degrees(rho * d):.1f} deg)"
    )

    # --- strained glass: the Brazilian disc
    disc = dict(diameter_mm=20.0, thickness_mm=5.0, glass="bk7", size=size if args.quick else 241, device=dev)
    images, titles = [], []
    for pol in ("plane", "circular"):
        row = [
            pe.brazilian_disc_image(load_n=0.0, polariscope=pol, wavelength_nm=None, **disc),
            pe.brazilian_disc_image(load_n=4000.0, polariscope=pol, wavelength_nm=None, **disc),
            pe.brazilian_disc_image(load_n=4000.0, polariscope=pol, wavelength_nm=lam, **disc),
        ]
        images.append(row)
        titles.append(
            [
                f"{pol} polariscope: strain-free BK7",
                "4 kN diametral load, white light",
                f"4 kN, {lam} nm",
            ]
        )
    plate = dict(thickness_mm=6.0, path_mm=20.0, glass="bk7", device=dev)
    plate.update(dict(width=40, height=12) if args.quick else dict(width=240, height=72))
    images.append(
        [
            pe.quenched_plate_image(surface_mpa=0.0, wavelength_nm=None, **plate),
            pe.quenched_plate_image(surface_mpa=30.0, wavelength_nm=None, **plate),
            pe.quenched_plate_image(surface_mpa=30.0, wavelength_nm=lam, **plate),
        ]
    )
    titles.append(
        [
            "6 mm plate edge-on, 20 mm path, 45°: annealed",
            "quenched: 30 MPa surface compression, white light",
            f"quenched, {lam} nm",
        ]
    )
    _disc_grid(images, titles, out / "strained_glass.png")
    c = STRESS_OPTIC_TPA["bk7"]
    s1, s2, _ = principal_stresses(
        *brazilian_disc(0.0, 0.0, diameter_mm=20.0, thickness_mm=5.0, load_n=4000.0),
        device=dev,
    )
    n_code = float(stress_retardations(c, 5.0, s1, s2, device=dev)) / lam
    n_closed = c * 5.0 * 8 * 4000.0 / (np.pi * 20.0 * 5.0) / lam
    print(
        f"wrote {out / 'strained_glass.png'}: centre fringe order {n_code:.4f} (closed form {n_closed:.4f})"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())

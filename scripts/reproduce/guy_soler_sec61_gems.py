"""Reproduce the six gems of Guy & Soler 2004 §6.1 from that section's table.

Garnet, tourmaline (dravite), peridot, diamond, sapphire and andalusite, each a round brilliant
(6.5 mm) in the same studio light, with the library materials built from the §6.1 table: the
indices (green value ± half the dispersion, Cauchy fits) and the absorbances (eq. 9 inverted to
K^o(λ), K^e(λ) spectra; base-e per mm, see warpoptics.materials.absorption), optic axis along the
table normal for the uniaxial (and treated-as-uniaxial biaxial) stones, exact o/e transport.
Peridot and andalusite are biaxial in the library; the paper's uniaxial approximation of them is
named explicitly here: the library entries ``peridot_uniaxial`` and ``andalusite_uniaxial``.
Top row: the absorbances as tabulated.  Bottom row: each coloured stone's absorbances scaled
(``absorption_scale``) so that its largest tabulated K is 0.3 /mm (x 1.7 garnet, x 3.7 tourmaline,
x 5.9 peridot, x 1.2 andalusite; sapphire, already above, and the white diamond stay x 1): the
pale tourmaline and peridot then show their body colours.  Prints each stone's mean colour (over
the pixels of the stone, reflections included) beside the colour names of the paper's table.

Usage:
    python scripts/reproduce/guy_soler_sec61_gems.py [-o docs/gallery/guy_soler_sec61_gems.png]
"""

from __future__ import annotations

import sys
import time

import _guy_soler_panels as sp

# name, the paper's colour names (o, e as printed in the table)
GEMS = [
    ("garnet", "orange-red"),
    ("tourmaline", "yellow green (o) / blue green (e)"),
    ("peridot", "green (o) / yellow green (e)"),
    ("diamond", "white"),
    ("sapphire", "light blue (e) / violetish blue (o)"),
    ("andalusite", "greenish red (o) / yellowish green (e)"),
]


#: the library entry of each table row: the Guy & Soler uniaxial approximation of the biaxial stones
LIBRARY = {"peridot": "peridot_uniaxial", "andalusite": "andalusite_uniaxial"}


def _scale(name: str) -> float:
    """absorption_scale that makes the largest tabulated K of a coloured stone 0.3 /mm (never < 1)."""
    from warpoptics.materials import GUY_SOLER_2004_GEMS

    row = GUY_SOLER_2004_GEMS[name]
    k = max(max(row["K_o"]), max(row["K_e"] or row["K_o"]))
    return 1.0 if name == "diamond" else max(1.0, 0.3 / k)


CAMERA = {"position": [0.0, -22.0, 30.0], "look_at": [0.0, 0.0, -0.3], "fov": 17.0}


def main(argv: list[str] | None = None) -> int:
    args = sp.parser(__doc__, "docs/gallery/guy_soler_sec61_gems.png").parse_args(argv)
    size, wl = sp.sizes(args, 112, 8)
    t0 = time.perf_counter()
    rows = []
    print(f"Guy & Soler 2004 §6.1 gems, round brilliant 6.5 mm, {size} px, {wl} wavelengths, studio light")
    for row in ("as tabulated", "scaled"):
        panels = []
        for name, _ in GEMS:
            scale = 1.0 if row == "as tabulated" else _scale(name)
            obj = {
                "shape": "round_brilliant",
                "diameter": 6.5,
                "material": LIBRARY.get(name, name),
                "absorption_scale": scale,
            }
            sc = sp.gem_scene(obj, size=size, wavelengths=wl, camera=CAMERA, render={"exposure": 0.0})
            panels.append(sp.render_panel(name, sc, args.device))
        for p, (name, paper) in zip(panels, GEMS, strict=True):
            sc = 1.0 if row == "as tabulated" else _scale(name)
            print(f"  x{sc:.1f} {name:10s} {p.describe()}  paper: {paper}  ({p.seconds:.1f} s)")
        rows.append(
            [
                (f"x{(1.0 if row == 'as tabulated' else _scale(p.label)):.1f} {p.label}", p.image.display())
                for p in panels
            ]
        )
    sp.montage(
        args.output,
        rows,
        title="Guy & Soler sec. 6.1: absorbance as tabulated (top), largest K scaled to 0.3/mm (bottom)",
    )
    print(f"wrote {args.output}  total {time.perf_counter() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())

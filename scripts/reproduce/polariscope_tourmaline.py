"""The tourmaline of scenes/tourmaline_polariscope.toml in a polariscope and a dichroscope.

Renders the scene once with polarized light (the sheet polarizer at 45 deg to the optic axis) and
writes, from that one Stokes image, parallel polarizers | crossed polarizers | the dichroscope
(analyzer along the optic axis | across it).  A second render with unpolarized light checks that
the dichroscope of the polarized render shows the same two colours.  Prints the extinction of the
empty field, the stone's crossed/parallel ratio, the two dichroscope colours and their CIEDE2000
difference.

Usage:
    python scripts/reproduce/polariscope_tourmaline.py [-o docs/gallery/tourmaline_polariscope.png]
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import _guy_soler_panels as sp

import warpoptics as wo

SCENE = Path(__file__).resolve().parents[2] / "scenes" / "tourmaline_polariscope.toml"


def main(argv: list[str] | None = None) -> int:
    args = sp.parser(__doc__, "docs/gallery/tourmaline_polariscope.png").parse_args(argv)
    size, wl = sp.sizes(args, 160, 12)
    t0 = time.perf_counter()
    scene = wo.Scene.load(SCENE).with_overrides(width=size, height=size, wavelengths=wl)
    pol = wo.render(scene, device=args.device)
    t_pol = time.perf_counter() - t0
    unpol = wo.render(scene.with_overrides({"light.0.polarizer": "none"}), device=args.device)
    crossed = pol.view("polariscope")
    parallel = pol.view("polariscope:parallel")
    stone = pol.alpha > 0.99
    field = pol.alpha == 0.0
    ext = crossed.xyz[..., 1][field].mean() / parallel.xyz[..., 1][field].mean()
    ratio = crossed.xyz[..., 1][stone].mean() / parallel.xyz[..., 1][stone].mean()
    print(f"scenes/tourmaline_polariscope.toml at {size} px, {wl} wavelengths: {t_pol:.1f} s per render")
    print(f"  empty field crossed/parallel (extinction): {ext:.2e}")
    print(f"  stone crossed/parallel: {ratio:.3f}")
    de = wo.color.delta_e2000
    cols = {}
    for name, img in (("polarized 45", pol), ("unpolarized", unpol)):
        a0 = img.view("analyzer:0").xyz[stone].mean(axis=0)
        a90 = img.view("analyzer:90").xyz[stone].mean(axis=0)
        cols[name] = (a0, a90)
        print(
            f"  dichroscope ({name} light): along the axis xy {a0[0] / a0.sum():.4f} {a0[1] / a0.sum():.4f}, "
            f"across xy {a90[0] / a90.sum():.4f} {a90[1] / a90.sum():.4f}, "
            f"dE00 (brightness removed) {float(de(a0 / a0[1], a90 / a90[1])):.2f}"
        )
    (p0, p90), (u0, u90) = cols["polarized 45"], cols["unpolarized"]
    print(
        f"  polarized vs unpolarized light, dE00 of the windows (brightness removed): "
        f"along {float(de(p0 / p0[1], u0 / u0[1])):.2f}, across {float(de(p90 / p90[1], u90 / u90[1])):.2f}; "
        f"brightness ratio {p0[1] / u0[1]:.3f}, {p90[1] / u90[1]:.3f}"
    )
    dich = unpol.view("dichroscope")
    h = size
    panels = [
        ("parallel polarizers", parallel.display()),
        ("crossed polarizers", crossed.display()),
        ("dichroscope: along | across the axis", dich.display()[:h]),
    ]
    sp.montage(args.output, panels, title="tourmaline, optic axis horizontal, polarizer at 45 deg")
    print(f"wrote {args.output}  total {time.perf_counter() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())

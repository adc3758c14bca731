"""Smits & Meyer 1990, fig. 7: the iridescent blue of a Morpho wing (§4.3).

Twelve mullions (n = 1.53, d2 = 50 nm) separated by d1 = 150 nm of air; the colour is looked up
by angle in a table (eq. 9 with the effective thickness of eq. 14, or the exact stack).  A wavy
surface seen from above, lit from the viewer's direction, shows the colours over a range of
angles.  Left: the paper's model; right: the exact twelve-layer stack; bottom strips: both
tables from 0 to 89 degrees.

    python scripts/reproduce/smits_meyer_morpho.py -o morpho.png [--size 192]
"""

from __future__ import annotations

import argparse

import numpy as np

import warpoptics as wo
from warpoptics.color import encode_srgb
from warpoptics.film.image import write_png


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", required=True, help="PNG path")
    ap.add_argument("--size", type=int, default=192, help="height of each panel in pixels")
    ap.add_argument("--amplitude", type=float, default=0.35, help="slope amplitude of the waves")
    ap.add_argument("--tilt", type=float, default=25.0, help="view tilt from the mean normal (deg)")
    ap.add_argument("--exposure", type=float, default=None, help="table exposure (default: peak Y 0.5)")
    ap.add_argument("--device", default=None)
    args = ap.parse_args(argv)

    n = args.size
    y, x = np.mgrid[0.0 : 1.0 : n * 1j, 0.0 : 1.0 : n * 1j]
    k = 2.0 * np.pi * 2.5
    a = args.amplitude / k
    # wavy wing: z = a sin(k x + 0.6 sin(3 y)) cos(0.7 k y); slopes analytically
    ph = k * x + 0.6 * np.sin(3.0 * y)
    dzdx = a * k * np.cos(ph) * np.cos(0.7 * k * y)
    dzdy = a * (
        np.cos(ph) * 1.8 * np.cos(3.0 * y) * np.cos(0.7 * k * y) - 0.7 * k * np.sin(ph) * np.sin(0.7 * k * y)
    )
    normal = np.stack([-dzdx, -dzdy, np.ones_like(x)], axis=-1)
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    tilt = np.radians(args.tilt)
    view = np.array([0.0, -np.sin(tilt), np.cos(tilt)])
    angle = np.degrees(np.arccos(np.clip(normal @ view, 0.0, 1.0)))
    panels = []
    strips = []
    for model in ("smits-meyer", "exact"):
        table = wo.thinfilm.multilayer_color_table(model=model, exposure=args.exposure, device=args.device)
        panels.append(table.lookup(angle, device=args.device))
        strip = table.lookup(
            np.linspace(0.0, 89.0, n)[None, :].repeat(max(n // 8, 4), axis=0), device=args.device
        )
        strips.append(strip)
        print(
            f"{model:12s} table exposure {table.exposure:.3g}; angles {angle.min():.1f}-{angle.max():.1f} deg"
        )
    gap = np.zeros((n, 4, 3))
    top = np.concatenate([panels[0], gap, panels[1]], axis=1)
    bottom = np.concatenate([strips[0], gap[: strips[0].shape[0]], strips[1]], axis=1)
    img = np.concatenate([top, np.zeros((4, top.shape[1], 3)), bottom], axis=0)
    write_png(args.output, encode_srgb(np.clip(img, 0.0, 1.0)))
    print(
        f"wrote {args.output} ({img.shape[1]}x{img.shape[0]}): left Smits-Meyer eq. 9+14, right exact stack"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

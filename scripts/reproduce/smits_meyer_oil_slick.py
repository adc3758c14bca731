"""Smits & Meyer 1990, fig. 5: an oil drop on wet asphalt (§4.1, eq. 12–13).

The oil thickness is t = t_max exp(-k1 (x^2 + y^2 + k2 turb(x, y))) (eq. 13, Perlin turbulence);
the viewer looks at the ground at an angle that grows toward the top of the picture, the
optical thickness is t' = t n cos(theta) (eq. 11, n = 1.5 for oil) and the colour comes from the
table with the phase change (oil on water: the reflection at the top, air -> oil, inverts).
The asphalt is two noise calls for the scale and roughness of the texture plus fine bumps.

    python scripts/reproduce/smits_meyer_oil_slick.py -o oil.png [--size 256] [--model exact]
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
    ap.add_argument("--size", type=int, default=256, help="image size in pixels (square)")
    ap.add_argument("--model", choices=["smits-meyer", "exact"], default="smits-meyer")
    ap.add_argument("--k1", type=float, default=4.0, help="eq. 12: how fast the oil thins out")
    ap.add_argument("--k2", type=float, default=0.25, help="eq. 13: irregularity of the spreading")
    ap.add_argument("--max-thickness", type=float, default=900.0, help="oil thickness at the centre (nm)")
    ap.add_argument("--n-oil", type=float, default=1.5)
    ap.add_argument("--view-angle", type=float, default=45.0, help="viewing angle at the centre (deg)")
    ap.add_argument(
        "--refraction-angle",
        action="store_true",
        help="phase from the refraction angle, t (n^2 - sin^2)^(1/2) (eq. 10), instead of eq. 11",
    )
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--device", default=None)
    args = ap.parse_args(argv)

    n = args.size
    y, x = np.mgrid[1.0 : -1.0 : n * 1j, -1.0 : 1.0 : n * 1j]
    t = wo.fields.oil_slick_thickness(
        x, y, k1=args.k1, k2=args.k2, max_thickness_nm=args.max_thickness, seed=args.seed, device=args.device
    )
    angle = np.clip(args.view_angle + 15.0 * y, 0.0, 89.0)  # grazing toward the horizon (top)
    if args.refraction_angle:
        tp = wo.thinfilm.smits_meyer_effective_thickness(t, args.n_oil, angle, device=args.device)
    else:  # as the paper does: t' = t n cos(theta) with the viewing angle (eq. 11)
        tp = wo.thinfilm.smits_meyer_optical_thickness(t, args.n_oil, angle, device=args.device)
    table = wo.thinfilm.film_color_table(
        phase_change=True, model=args.model, n_film=args.n_oil, n_substrate=1.0, device=args.device
    )
    film = table.lookup(tp, device=args.device)
    # wet asphalt: two noise calls (scale, roughness) and fine bumps
    base = wo.fields.turbulence_field(x, y, seed=args.seed + 1, octaves=4, scale=6.0, device=args.device)
    rough = wo.fields.turbulence_field(x, y, seed=args.seed + 2, octaves=3, scale=40.0, device=args.device)
    fine = wo.fields.turbulence_field(x, y, seed=args.seed + 3, octaves=2, scale=180.0, device=args.device)
    albedo = 0.015 + 0.05 * base * (0.4 + rough) + 0.03 * fine
    rgb = albedo[..., None] * np.array([1.0, 0.98, 0.95]) + 0.45 * film
    write_png(args.output, encode_srgb(np.clip(rgb, 0.0, 1.0)))
    print(
        f"oil slick {n}x{n}, {table.model} table: thickness {t.min():.0f}-{t.max():.0f} nm, "
        f"t' {tp.min():.0f}-{tp.max():.0f} nm; wrote {args.output}"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

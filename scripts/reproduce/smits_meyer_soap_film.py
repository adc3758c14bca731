"""Smits & Meyer 1990, fig. 6: a soap film thinning under gravity (§4.2).

The film hangs in a round wire frame; its thickness is proportional to the normalised height
(0 at the top, where the film is black, 1 at the bottom; offset so that a band of black
film shows at the top) plus turbulence for air currents;
seen at normal incidence, t' = t n (n = 1.33), colours from the table with the phase change.

    python scripts/reproduce/smits_meyer_soap_film.py -o soap.png [--size 256] [--model exact]
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
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--model", choices=["smits-meyer", "exact"], default="smits-meyer")
    ap.add_argument("--max-thickness", type=float, default=700.0, help="thickness at the bottom (nm)")
    ap.add_argument(
        "--k2", type=float, default=0.12, help="turbulence amplitude (fraction of the height range)"
    )
    ap.add_argument("--n-film", type=float, default=1.33)
    ap.add_argument("--black", type=float, default=0.3, help="height offset giving the black film at the top")
    ap.add_argument("--seed", type=int, default=3)
    ap.add_argument("--device", default=None)
    args = ap.parse_args(argv)

    n = args.size
    h, x = np.mgrid[0.0 : 1.0 : n * 1j, 0.0 : 1.0 : n * 1j]
    # the normalised height starts below zero so that the top of the film is black (t = 0)
    height = -args.black + (1.0 + args.black) * h
    t = wo.fields.soap_film_thickness(
        x, height, k2=args.k2, max_thickness_nm=args.max_thickness, seed=args.seed, device=args.device
    )
    table = wo.thinfilm.film_color_table(
        phase_change=True, model=args.model, n_film=args.n_film, device=args.device
    )
    tp = wo.thinfilm.smits_meyer_optical_thickness(t, args.n_film, 0.0, device=args.device)
    rgb = table.lookup(tp, device=args.device) * 0.8
    r = np.hypot(x - 0.5, h - 0.5)
    rgb[r > 0.48] = 0.02
    rgb[(r > 0.48) & (r < 0.5)] = 0.25  # the wire frame
    write_png(args.output, encode_srgb(np.clip(rgb, 0.0, 1.0)))
    print(f"soap film {n}x{n}, {table.model} table: t' {tp.min():.0f}-{tp.max():.0f} nm; wrote {args.output}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

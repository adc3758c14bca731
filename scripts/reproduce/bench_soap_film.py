"""Optical bench: the coloured reflection of a soap film (Smits & Meyer 1990).

A white D65 beam meets a free-standing 500 nm water film at 45 degrees; the front-surface spot
on the screen (light that met one interface) takes the film's interference colour.  Readout: the
spot's XYZ (normalised so that a perfect mirror would give Y = luminous fraction of the beam)
against the colour of the exact thin-film reflectance R(lambda) of ``warpoptics.thinfilm`` under
the beam's spectrum at the same wavelength samples (the "thin-film table"), as chromaticity xy,
Y and CIEDE2000; plus a sweep of film thicknesses.

    python scripts/reproduce/bench_soap_film.py -o out/bench_soap_film.png
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "scenes" / "bench" / "soap_film.toml"


def spot_and_table(result, thickness_nm: float, angle_deg: float = 45.0):
    """(XYZ of the front spot, XYZ predicted from the thin-film reflectance)."""
    import warpoptics as wo
    from warpoptics.spectra import cmf

    dp = result.deposits
    front = (dp["screen"] == 0) & (dp["depth"] == 1)
    xyz = dp["xyz"][front].sum(axis=0)
    wl = result.wavelengths
    n_water = wo.materials.get("water").n(wl)
    R = np.array(
        [
            wo.thinfilm.reflectance(w, [n], [thickness_nm], 1.0, 1.0, angle=angle_deg)
            for w, n in zip(wl, n_water, strict=True)
        ]
    ).ravel()
    cm = cmf(wl)
    table = (result.weights * R)[:, None] * cm / float((result.weights * cm[:, 1]).sum())
    return xyz, table.sum(axis=0)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", required=True, help="PNG image of the screen to write")
    ap.add_argument("--rays", type=int, default=None, help="beam positions (default: the scene's)")
    ap.add_argument("--thicknesses", default="200,300,400,500,600,800", help="film thicknesses (nm) to sweep")
    ap.add_argument("--device", default=None)
    args = ap.parse_args(argv)

    from warpoptics.color import delta_e2000
    from warpoptics.pipelines.bench import bench
    from warpoptics.scene.bench import BenchScene

    scene = BenchScene.load(SCENE)
    base = {"source.rays": args.rays} if args.rays else {}
    last = None
    print(
        f"{'film nm':>8s} {'spot x':>8s} {'spot y':>8s} {'spot Y':>8s} {'table x':>8s} {'table y':>8s} "
        f"{'table Y':>8s} {'dE2000':>7s}"
    )
    for t in (float(v) for v in args.thicknesses.split(",")):
        r = bench(scene, device=args.device, overrides={**base, "object.0.coating.0.thickness_nm": t})
        xyz, ref = spot_and_table(r, t)
        # colour difference of the spot scaled to Y = 0.5 (both by the same factor)
        k = 0.5 / ref[1]
        de = float(delta_e2000(xyz * k, ref * k))
        print(
            f"{t:8.0f} {xyz[0] / xyz.sum():8.4f} {xyz[1] / xyz.sum():8.4f} {xyz[1]:8.5f} "
            f"{ref[0] / ref.sum():8.4f} {ref[1] / ref.sum():8.4f} {ref[1]:8.5f} {de:7.4f}"
        )
        if last is None or t == 500.0:
            last = r  # the picture: the scene's 500 nm film (or the first of the sweep)
    print("ledger (W): " + ", ".join(f"{k} {v:.6f}" for k, v in last.ledger.items()))
    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    last.save(args.output)
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Optical bench: the fire a round brilliant throws when a white beam enters through its table.

A 6.5 mm Tolkowsky round brilliant (diamond) is lit straight down through its table by a 3 mm
D65 beam; a screen 20 mm above catches what the crown returns - the fire pattern, with the
8-fold symmetry of the pavilion mains - and a screen below catches what leaks through the
pavilion.  Readout: the fraction of the beam's power returned upward, split into the specular
reflection of the table (one interface) and light that entered the stone and came back out
through the crown, the leakage below, the energy ledger, and the spread of colours on the upper
screen (power-weighted mean CIE 1976 u'v' distance from the D65 white point of the return).

    python scripts/reproduce/bench_diamond_fire.py -o out/bench_diamond_fire.png
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "scenes" / "bench" / "diamond_fire.toml"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", required=True, help="PNG image of the upper screen to write")
    ap.add_argument("--rays", type=int, default=None, help="beam positions (default: the scene's)")
    ap.add_argument("--wavelengths", type=int, default=None, help="spectral samples (default: the scene's)")
    ap.add_argument("--crop", type=float, default=80.0, help="size (mm) of the central crop in the PNG")
    ap.add_argument("--device", default=None)
    args = ap.parse_args(argv)

    from warpoptics.pipelines.bench import bench
    from warpoptics.pipelines.render import Image
    from warpoptics.scene.bench import BenchScene

    over = {}
    if args.rays:
        over["source.rays"] = args.rays
    if args.wavelengths:
        over["render.wavelengths"] = args.wavelengths
    scene = BenchScene.load(SCENE)
    r = bench(scene, device=args.device, overrides=over)
    dp = r.deposits
    lg = r.ledger
    up = dp["screen"] == 0
    specular = float(dp["power"][up & (dp["depth"] == 1)].sum())
    crown = float(dp["power"][up & (dp["depth"] >= 2)].sum())
    below = float(dp["power"][dp["screen"] == 1].sum())
    e = lg["emitted"]
    print(
        f"beam: {r.stats['beam_rays'] // r.wavelengths.size} positions x {r.wavelengths.size} wavelengths, "
        f"{r.stats['seconds']:.2f} s"
    )
    print(f"returned upward (screen above)        : {(specular + crown) / e:.4f}")
    print(f"  specular reflection of the table    : {specular / e:.4f}")
    print(f"  returned through the crown          : {crown / e:.4f}")
    print(f"leaked through the pavilion (below)   : {below / e:.4f}")
    print("ledger (W): " + ", ".join(f"{k} {v:.6f}" for k, v in lg.items()))
    print(f"closure (screen + absorbed + escaped) / emitted - 1 = {r.balance():+.2e}")
    # colour spread of the crown return: u'v' of each pixel vs the white point
    img = r.screens[0]
    xyz = img.xyz.reshape(-1, 3)
    s = xyz.sum(axis=1)
    lit = s > 0
    d = xyz[:, 0] + 15 * xyz[:, 1] + 3 * xyz[:, 2]
    uv = np.stack([4 * xyz[lit, 0] / d[lit], 9 * xyz[lit, 1] / d[lit]], axis=-1)
    white = np.array([0.1978, 0.4683])  # D65 u'v'
    spread = float((np.linalg.norm(uv - white, axis=1) * xyz[lit, 1]).sum() / xyz[lit, 1].sum())
    print(f"fire: luminance-weighted mean u'v' distance from D65 on the upper screen = {spread:.4f}")
    # central crop of the light returned through the crown (the table's specular spot left out)
    img = r.screen_image(0, select=dp["depth"] >= 2)
    sc = img.screen
    nx, ny = sc.resolution
    cx = int(round(nx * min(1.0, args.crop / sc.size[0]) / 2))
    cy = int(round(ny * min(1.0, args.crop / sc.size[1]) / 2))
    sl = (slice(ny // 2 - cy, ny // 2 + cy), slice(nx // 2 - cx, nx // 2 + cx))
    crop = Image(xyz=img.xyz[sl], stokes=img.stokes[sl], alpha=(img.stokes[sl][..., 0] > 0).astype(float))
    y = crop.xyz[..., 1]
    ref = float(np.percentile(y[y > 0], 90.0)) if (y > 0).any() else 1.0
    crop.exposure = -np.log2(ref)
    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    crop.save(args.output)
    exr = os.path.splitext(args.output)[0] + ".exr"
    r.screens[0].save(exr)
    print(
        f"wrote {args.output} (central {args.crop:g} mm, crown return only) and {exr} "
        "(whole screen, all light)"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Pixel beams in blocks against one beam per pixel: the blocks' bias at a given pixel angle.

Renders a scene (default ``scenes/diamond_fire.toml``) with ``render.beam_block = B`` and with
1, two seeds each, and reports each one's noise of one pass (rms of the seeds' difference /
sqrt 2) and the bias of the blocks: the rms difference of the two means with both noises taken
out in quadrature, all relative to the image mean (linear sRGB).  A pinhole block's pixels take
its parts' centre-ray Fresnel factors, so the bias grows with the block's angle
(``stages/pixel_beam.py``).

    python scripts/bench/beam_block_bias.py --res 32 --block 4           # 1.9-degree blocks
    python scripts/bench/beam_block_bias.py --res 64 --fov 1.875 --block 4  # 512x512's pixel angle
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

import warpoptics as wo

ROOT = Path(__file__).resolve().parents[2]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scene", default=str(ROOT / "scenes" / "diamond_fire.toml"))
    ap.add_argument("--res", type=int, default=32)
    ap.add_argument("--fov", type=float, default=None, help="camera.fov (degrees; default the scene's)")
    ap.add_argument("--block", type=int, default=4)
    ap.add_argument("--wavelengths", type=int, default=64)
    ap.add_argument("--json", default=None)
    a = ap.parse_args()
    sc = wo.Scene.load(a.scene)
    over = {"camera.width": a.res, "camera.height": a.res, "render.wavelengths": a.wavelengths}
    if a.fov is not None:
        over["camera.fov"] = a.fov
    sc = sc.with_overrides(over)
    imgs = {}
    for b in (1, a.block):
        for seed in (1, 2):
            s = sc.with_overrides({"render.beam_block": b, "render.seed": seed})
            imgs[b, seed] = wo.render(s).rgb.astype(np.float64)
    mean = imgs[1, 1].mean()

    def rms(x: np.ndarray) -> float:
        return float(np.sqrt((x**2).mean()) / mean)

    n1 = rms(imgs[1, 1] - imgs[1, 2]) / np.sqrt(2.0)
    nb = rms(imgs[a.block, 1] - imgs[a.block, 2]) / np.sqrt(2.0)
    d = rms(0.5 * (imgs[a.block, 1] + imgs[a.block, 2]) - 0.5 * (imgs[1, 1] + imgs[1, 2]))
    bias = float(np.sqrt(max(d**2 - (n1**2 + nb**2) / 2.0, 0.0)))
    pixel = (a.fov if a.fov is not None else sc.camera.fov) / a.res
    print(
        f"{a.res}x{a.res}, blocks of {a.block} ({a.block * pixel:.3f} deg), {a.wavelengths} wavelengths:"
        f" noise of one pass {100 * n1:.2f} % (pixels) / {100 * nb:.2f} % (blocks),"
        f" means differ {100 * d:.2f} %, bias {100 * bias:.2f} %",
        flush=True,
    )
    if a.json:
        from warpoptics.film.image import atomic_path

        out = {"res": a.res, "fov": a.fov, "block": a.block, "wavelengths": a.wavelengths,
               "noise_pixels": n1, "noise_blocks": nb, "difference": d, "bias": bias}  # fmt: skip
        with atomic_path(a.json) as tmp, open(tmp, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()

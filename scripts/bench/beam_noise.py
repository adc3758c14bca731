"""Pixel beams' noise of one pass against the settings that set it (stages/pixel_beam.py).

For each setting (wavelengths per pass, split threshold), renders the fire benchmark scene
(scenes/bench_fire.toml: dispersive, clear, polarized diamond under the lat-long studio map)
with ``render.estimator = "beam"`` twice with independent seeds, one beam per pixel, and reports the
relative RMSE of one pass in linear sRGB over the whole image (rms of the difference / sqrt 2,
over the mean) and the wall seconds of each render.  This is how the beams' sampling was chosen:
where a beam's noise comes from (spectral, environment lookups, roulette) shows as which
setting moves it.

    python scripts/bench/beam_noise.py --res 64 --settings 16,0.001 24,0.001 32,0.001 48,0.001 \\
        64,0.001 32,0.01 --json scripts/bench/results/beam_noise_64.json
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from warpoptics.color import xyz_to_srgb_linear
from warpoptics.pipelines.render import Renderer
from warpoptics.scene import Scene

ROOT = Path(__file__).resolve().parents[2]


def one_pass(
    base: Scene, res: int, wavelengths: int, split: float, seed: int, block: int = 1
) -> tuple[np.ndarray, float]:
    over = {
        "camera.width": res,
        "camera.height": res,
        "render.estimator": "beam",
        "render.wavelengths": wavelengths,
        "render.bundle_lanes": 16,
        "render.spp": 1,
        "render.adaptive": False,
        "render.split_threshold": split,
        "render.seed": seed,
        "render.beam_block": block,
    }
    r = Renderer(base.with_overrides(over))
    r.load_kernels()
    t = time.perf_counter()
    im = r.run()
    return xyz_to_srgb_linear(im.xyz), time.perf_counter() - t


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scene", default=str(ROOT / "scenes" / "bench_fire.toml"))
    ap.add_argument("--res", type=int, default=64)
    ap.add_argument(
        "--settings",
        nargs="+",
        default=["16,0.001", "32,0.001", "64,0.001"],
        help="WAVELENGTHS,SPLIT_THRESHOLD pairs",
    )
    ap.add_argument("--block", type=int, default=1, help="render.beam_block (pixels per beam side)")
    ap.add_argument("--json", default=None)
    a = ap.parse_args()
    base = Scene.load(a.scene)
    rows = []
    for item in a.settings:
        wl_s, split_s = item.split(",")
        wl, split = int(wl_s), float(split_s)
        (im1, t1), (im2, t2) = (one_pass(base, a.res, wl, split, seed, a.block) for seed in (1, 2))
        noise = float(np.sqrt(((im1 - im2) ** 2).mean() / 2.0) / (0.5 * (im1 + im2)).mean())
        rows.append({"wavelengths": wl, "split_threshold": split, "noise": noise, "seconds": [t1, t2]})
        print(
            f"{wl:4d} wavelengths, split {split:g}: one pass {100 * noise:.2f} % rel. RMSE,"
            f" {t1:.1f} / {t2:.1f} s wall",
            flush=True,
        )
    if a.json:
        from warpoptics.film.image import atomic_path

        command = (
            f"python scripts/bench/beam_noise.py --res {a.res} --block {a.block} --settings "
            + " ".join(a.settings)
        )
        out = {"scene": a.scene, "res": a.res, "block": a.block, "rows": rows, "command": command}
        with atomic_path(a.json) as tmp, open(tmp, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()

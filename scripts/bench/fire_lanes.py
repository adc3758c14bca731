"""Spectral bundles: how many wavelengths per bundle, and how many bundles per sample.

The bundle estimator (``stages/bundle.py``) traces one path tree for ``lanes`` wavelengths at one
pixel position.  Its noise has two parts: where the positions fall in the pixel (facet edges,
falling like N^-0.75 over the R2 sequence) and how well ``lanes`` wavelengths integrate the
spectrum at one position; its cost grows with the lanes (each lane has its own rays, Fresnel
amplitudes and Jones matrices).  This script renders the fire benchmark stone
(``fire_convergence.scene_for``: ``scenes/bench_diamond.toml`` with the library's dispersive
``diamond``, polarized, uniform sampling) with several (wavelengths per sample, lanes) settings
at about equal cost, twice with independent seeds, and reports per setting: single-threaded CPU
seconds (``time.process_time``), rays, the relative RMSE of linear sRGB of one render (from the
two renders' difference: all estimators are unbiased, so RMSE = noise = rms(a - b) / sqrt 2 /
mean), and the CPU seconds to 1 % extrapolated with the R2 slope 0.75.  The clear twin (the same
stone without dispersion, one tree for the whole spectrum) is the issue's 3x yardstick.

    python scripts/bench/fire_lanes.py [--res 64] [--json scripts/bench/results/fire_lanes_64.json]
    python scripts/bench/fire_lanes.py --quick      # 16x16, seconds
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from fire_convergence import scene_for  # noqa: E402

from warpoptics.pipelines.render import Renderer  # noqa: E402

# (estimator, wavelengths per sample, lanes per bundle, spp): about equal cost per setting
SETTINGS = (
    ("bundle", 8, 8, 64),
    ("bundle", 4, 4, 128),
    ("bundle", 2, 2, 256),
    ("bundle", 16, 16, 32),
    ("bundle", 16, 8, 32),
    ("clear", 8, 8, 64),
)


def measure(estimator: str, res: int, wavelengths: int, lanes: int, spp: int) -> dict:
    runs = []
    for seed in (11, 12):
        sc = scene_for(estimator, res, wavelengths, lanes).with_overrides(
            {"render.spp": spp, "render.seed": seed}
        )
        r = Renderer(sc)
        r.load_kernels()
        t0 = time.process_time()
        img = r.run(threads=1)
        runs.append((time.process_time() - t0, int(img.stats["rays"]), img.rgb.astype(np.float64)))
    a, b = runs[0][2], runs[1][2]
    noise = float(np.sqrt(np.mean((a - b) ** 2) / 2.0) / np.mean(0.5 * (a + b)))
    cpu = 0.5 * (runs[0][0] + runs[1][0])
    positions = spp * (wavelengths // lanes if estimator == "bundle" else wavelengths)
    return {
        "estimator": estimator,
        "wavelengths": wavelengths,
        "lanes": lanes,
        "spp": spp,
        "positions_per_pixel": positions,
        "cpu_seconds": cpu,
        "rays": runs[0][1],
        "rel_rmse": noise,
        "cpu_seconds_to_1pct": cpu * (noise / 0.01) ** (1.0 / 0.75),
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--res", type=int, default=64)
    ap.add_argument("--json", type=Path)
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args(argv)
    res = 16 if args.quick else args.res
    rows = []
    print(f"fire_lanes: {res}x{res}, load average {os.getloadavg()[0]:.2f}", flush=True)
    for est, w, lanes, spp in SETTINGS:
        row = measure(est, res, w, lanes, max(1, spp // 8) if args.quick else spp)
        rows.append(row)
        print(
            f"{est:6s} wavelengths {w:2d} lanes {lanes:2d} spp {row['spp']:3d}"
            f" positions {row['positions_per_pixel']:3d}: {row['cpu_seconds']:.2f} CPU-s,"
            f" {row['rays'] / 1e6:.2f} M rays, noise {100 * row['rel_rmse']:.2f} %"
            f" -> {row['cpu_seconds_to_1pct']:.1f} CPU-s to 1 %",
            flush=True,
        )
    print(f"load average after {os.getloadavg()[0]:.2f}")
    if args.json:
        from warpoptics.atomic import atomic_path

        with atomic_path(args.json) as tmp, open(tmp, "w") as f:
            json.dump({"res": res, "rows": rows}, f, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

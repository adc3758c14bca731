"""Two sampling settings of ``scenes/diamond.toml`` at 512x512, alternated: error at about equal time.

``diamond512.py`` times one setting's ladder; run one after another, two settings meet machines
whose speed drifted (10-15 % between runs here).  This script alternates them -- A, B, A, B -- in
one process, each render against one reference (the mean of the ``--reference`` files that
``diamond512.py --reference FILE`` writes: sampling settings do not change the expected image,
so references of any setting may be averaged), and prints render seconds and relative RMSE of
linear sRGB (the reference's own noise subtracted in quadrature, as ``diamond512.py`` does).

    python scripts/bench/diamond512.py --ref-spp 72 --reference ref.npz --ladder 4
    python scripts/bench/diamond512_ab.py --reference ref.npz \\
        --a render.wavelengths=45 --a render.split_threshold=0.002 --a-spp 4 --b-spp 12 --rounds 3
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

sys.path.insert(0, str(Path(__file__).resolve().parent))
from diamond512 import error_vs_reference, reference_noise, render  # noqa: E402

import warpoptics as wo  # noqa: E402
from warpoptics.scene.load import parse_set_options  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--reference", type=Path, action="append", required=True)
    ap.add_argument("--a", action="append", default=[], metavar="KEY=VALUE", help="setting A (TOML value)")
    ap.add_argument("--b", action="append", default=[], metavar="KEY=VALUE", help="setting B (TOML value)")
    ap.add_argument("--a-spp", type=int, required=True)
    ap.add_argument("--b-spp", type=int, required=True)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--adaptive", type=int, default=1, help="1: render.adaptive = true in both")
    ap.add_argument("--scene", type=Path, default=ROOT / "scenes" / "diamond.toml", help="another scene")
    args = ap.parse_args(argv)
    files = [np.load(f) for f in args.reference]
    ref = np.mean([h for z in files for h in (z["h1"], z["h2"])], axis=0)
    mean = float(ref.mean())
    # the mean of k files: 1/k of the quadrature sum of each file's own noise
    noises = [reference_noise(z["h1"], z["h2"], mean) for z in files]
    ref_noise = float(np.sqrt(np.sum(np.square(noises)))) / len(files)
    print(f"diamond512_ab: load average {os.getloadavg()[0]:.2f}, {os.cpu_count()} CPUs", flush=True)
    print(f"reference: {2 * len(files)} halves, its noise {100 * ref_noise:.3f} %", flush=True)
    sc = wo.Scene.load(args.scene)
    runs = (("A", parse_set_options(args.a), args.a_spp), ("B", parse_set_options(args.b), args.b_spp))
    for name, ov, spp in runs:
        print(f"{name}: {ov or 'the scene'}, {spp} spp", flush=True)
    for rnd in range(args.rounds):
        for name, ov, spp in runs:
            img, sec, _cpu, _rays = render(sc, spp, 5000 + rnd, adaptive=bool(args.adaptive), settings=ov)
            err, _raw = error_vs_reference(img, ref, mean, ref_noise)
            print(f"round {rnd} {name}: {sec:6.2f} s render, {100 * err:.2f} %", flush=True)
    print(f"load average after {os.getloadavg()[0]:.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

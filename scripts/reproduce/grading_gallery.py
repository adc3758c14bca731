"""ASET, Ideal Scope and Hearts & Arrows of three round brilliant diamonds (warpoptics.grading).

The stones (6.5 mm, diamond): a Tolkowsky (table 53 %, crown 34.5°, pavilion 40.75°), GIA's
reference proportions (table 57 %, crown 34.0°, pavilion 40.7°) and a deliberately poor,
deep stone (table 55 %, crown 34.5°, pavilion 43°).  Per stone: ASET (AGS zones: blue = the
observer's obstruction, red = 45-90° above the girdle plane, green = 0-45°, white = leakage),
Ideal Scope (red reflector; leakage white), the H&A viewer face-up (arrows) and face-down
(hearts) with the counted dark lobes.  Writes ``grading_scopes.png`` and ``grading_scopes.json``
(zone fractions, lobe counts) into the output folder, atomically.

    python scripts/reproduce/grading_gallery.py -o docs/gallery            # 128 px panels
    python scripts/reproduce/grading_gallery.py --quick -o /tmp/gallery    # seconds
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from warpoptics.atomic import atomic_path
from warpoptics.color import encode_srgb
from warpoptics.grading.scopes import aset, count_dark_lobes, hearts_and_arrows, ideal_scope, ring_profile
from warpoptics.sweep.results import write_text_atomic

STONES = {
    "Tolkowsky 53/34.5/40.75": {"table": 0.53, "crown_angle": 34.5, "pavilion_angle": 40.75},
    "GIA reference 57/34.0/40.7": {"table": 0.57, "crown_angle": 34.0, "pavilion_angle": 40.7},
    "deep pavilion 55/34.5/43": {"table": 0.55, "crown_angle": 34.5, "pavilion_angle": 43.0},
}


def _lobes(img, size, face_down):
    half = size / 2 / 1.08  # the girdle radius in pixels (face_up_scene frames it with 8 % margin)
    radii = np.linspace(0.12, 0.3, 7) if face_down else np.linspace(0.15, 0.45, 9)
    counts = [count_dark_lobes(ring_profile(img, r * half)) for r in radii]
    vals, n = np.unique(counts, return_counts=True)
    return int(vals[np.argmax(n)])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", default="docs/gallery", help="output folder")
    ap.add_argument("--size", type=int, default=128)
    ap.add_argument("--quick", action="store_true", help="24 px panels")
    args = ap.parse_args(argv)
    size = 24 if args.quick else args.size
    out = Path(args.output)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axs = plt.subplots(len(STONES), 4, figsize=(9.2, 2.5 * len(STONES)))
    readout = {}
    for row, (label, kw) in zip(axs, STONES.items(), strict=True):
        stone = {"shape": "round_brilliant", "diameter": 6.5, "material": "diamond", **kw}
        a_img, zones, _ = aset(stone, size=size)
        i_img, ifr, _ = ideal_scope(stone, size=size)
        arrows, _ = hearts_and_arrows(stone, size=size)
        hearts, _ = hearts_and_arrows(stone, size=size, face_down=True)
        n_arrows, n_hearts = _lobes(arrows, size, False), _lobes(hearts, size, True)
        readout[label] = {
            "stone": stone,
            "aset": zones,
            "ideal_scope": ifr,
            "arrows": n_arrows,
            "hearts": n_hearts,
        }
        panels = [
            (encode_srgb(a_img), f"ASET: leak {zones['leak']:.2f}, red {zones['red']:.2f}"),
            (encode_srgb(i_img), f"Ideal Scope: leak {ifr['leak']:.2f}"),
            (arrows, f"arrows: {n_arrows}"),
            (hearts, f"hearts: {n_hearts}"),
        ]
        for ax, (img, title) in zip(row, panels, strict=True):
            ax.imshow(img, cmap="gray" if img.ndim == 2 else None, vmin=0, vmax=1, interpolation="nearest")
            ax.set_title(title, fontsize=8)
            ax.set_xticks([])
            ax.set_yticks([])
        row[0].set_ylabel(label, fontsize=8)
        print(f"{label}: ASET {zones}, Ideal Scope {ifr}, arrows {n_arrows}, hearts {n_hearts}", flush=True)
    fig.tight_layout()
    with atomic_path(out / "grading_scopes.png") as tmp:
        fig.savefig(tmp, dpi=100)
    write_text_atomic(out / "grading_scopes.json", json.dumps(readout, indent=1) + "\n")
    print(f"wrote {out / 'grading_scopes.png'} and .json")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

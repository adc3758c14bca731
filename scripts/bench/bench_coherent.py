"""Cost of the coherent birefringence mode against the exact (incoherent) one (target <= 1.3x).

``scenes/tourmaline_polariscope.toml`` (the step-cut tourmaline between crossed polarizers) is
rendered with ``render.birefringence = "exact"`` and ``"coherent"`` (the optical phase on every
segment, the per-primary leaf buffer summed by ``stages/coherence.py``), alternating runs after a
warm-up of each, on one CPU thread (``WARPOPTICS_THREADS=1``), timing CPU seconds
(``time.process_time``) so that other processes on the machine change the result less.  Both
modes trace the same trees up to rounding (the unit phase factor changes |M|^2 in float32, which can
flip a split or roulette decision: rays agree to a few in a million).

    python scripts/bench/bench_coherent.py [--size 64] [--repeat 5] [--width-mm 0.001] [--json out.json]
    python scripts/bench/bench_coherent.py --quick      # a seconds-long smoke run
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

os.environ.setdefault("WARPOPTICS_THREADS", "1")

import numpy as np  # noqa: E402

import warpoptics as wo  # noqa: E402

SCENE = Path(__file__).resolve().parents[2] / "scenes" / "tourmaline_polariscope.toml"


def _run(sc) -> tuple[float, float, int]:
    """(CPU seconds, wall seconds, rays) of one render."""
    t, w = time.process_time(), time.perf_counter()
    img = wo.render(sc)
    return time.process_time() - t, time.perf_counter() - w, int(img.stats["rays"])


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=64)
    ap.add_argument("--wavelengths", type=int, default=16)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument(
        "--width-mm", type=float, default=None, help="render.coherence_width_mm (default: the scene's)"
    )
    ap.add_argument("--json", default=None)
    ap.add_argument("--quick", action="store_true", help="16x16, 4 wavelengths, 1 repeat")
    args = ap.parse_args(argv)
    if args.quick:
        args.size, args.wavelengths, args.repeat = 16, 4, 1
    base = wo.Scene.load(SCENE).with_overrides(
        {"camera.width": args.size, "camera.height": args.size, "render.wavelengths": args.wavelengths}
    )
    over = {} if args.width_mm is None else {"render.coherence_width_mm": args.width_mm}
    sc = {m: base.with_overrides({"render.birefringence": m, **over}) for m in ("exact", "coherent")}
    _run(sc["exact"]), _run(sc["coherent"])  # warm-up: kernel cache, material tables
    t: dict[str, list] = {"exact": [], "coherent": []}
    wall: dict[str, list] = {"exact": [], "coherent": []}
    rays: dict[str, list] = {"exact": [], "coherent": []}
    load_before = os.getloadavg()[0]
    for _ in range(args.repeat):
        for m in ("exact", "coherent"):
            a, w, r = _run(sc[m])
            t[m].append(a)
            wall[m].append(w)
            rays[m].append(r)
    out = {
        "scene": SCENE.name,
        "size": args.size,
        "wavelengths": args.wavelengths,
        "threads": os.environ["WARPOPTICS_THREADS"],
        "coherence_width_mm": sc["coherent"].render.coherence_width_mm,
        "cpu_s_exact_median": float(np.median(t["exact"])),
        "cpu_s_coherent_median": float(np.median(t["coherent"])),
        "rays_exact": int(np.median(rays["exact"])),
        "rays_coherent": int(np.median(rays["coherent"])),
        "ratio_cpu": float(np.median(t["coherent"]) / np.median(t["exact"])),
        "wall_s_exact_median": float(np.median(wall["exact"])),
        "wall_s_coherent_median": float(np.median(wall["coherent"])),
        "ratio_wall": float(np.median(wall["coherent"]) / np.median(wall["exact"])),
        "cpu_s_exact": [round(x, 3) for x in t["exact"]],
        "cpu_s_coherent": [round(x, 3) for x in t["coherent"]],
        "target": 1.3,
        # the machine's 1-minute load average around the passes (this benchmark itself adds 1)
        "load_average": [round(load_before, 2), round(os.getloadavg()[0], 2)],
    }
    for k, v in out.items():
        print(f"{k:24s} {v}")
    if args.json:
        from warpoptics.atomic import atomic_path

        with atomic_path(args.json) as tmp, open(tmp, "w") as f:
            json.dump(out, f, indent=2)
    return out


if __name__ == "__main__":
    main()

"""Cost of a biaxial stone against the same stone in the uniaxial approximation (target <= 1.5x).

The same tanzanite brilliant is rendered as the library ``Biaxial`` (fast/slow waves from the
quartic of ``optics/biaxial.py`` at every interface) and as its ``uniaxial_approximation()``
(today's o/e path), alternating runs after a warm-up of each, on one CPU thread
(``WARPOPTICS_THREADS=1``), timing CPU seconds (``time.process_time``) so that other processes on
the machine change the result less; also reports rays traced (the two trees have the same shape,
so rays should agree within a few per cent) and the CPU time per ray.

    python scripts/bench/bench_biaxial.py [--size 96] [--repeat 7] [--material tanzanite] [--json out.json]
    python scripts/bench/bench_biaxial.py --quick      # a seconds-long smoke run (tests)
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import time

os.environ.setdefault("WARPOPTICS_THREADS", "1")

import numpy as np  # noqa: E402

import warpoptics as wo  # noqa: E402
from warpoptics.materials.dispersion import Biaxial  # noqa: E402


def _scene(material: str, size: int, wavelengths: int):
    data = {
        "camera": {
            "position": [0.0, -30.0, 20.0],
            "look_at": [0.0, 0.0, 0.0],
            "fov": 14.0,
            "width": size,
            "height": size,
        },
        "render": {
            "spectral": "stratified",
            "wavelengths": wavelengths,
            "max_depth": 12,
            "birefringence": "exact",
        },
        "light": [{"type": "environment", "map": "studio", "intensity": 1.0}],
        "object": [
            {
                "shape": "round_brilliant",
                "diameter": 6.5,
                "material": material,
                "crystal_axes": [[0.6, 0.8, 0.0], [-0.8, 0.6, 0.0], [0.0, 0.0, 1.0]],
                "rotation": [17.0, 29.0, 3.0],
            }
        ],
    }
    sc = wo.Scene.from_dict(data)
    bi = wo.materials.get(material)
    if not isinstance(bi, Biaxial):
        raise SystemExit(f"{material} is not a biaxial library stone")
    # the uniaxial approximation in the same orientation (its axis is in the crystal frame)
    uni = Biaxial.uniaxial_approximation(bi.with_crystal_axes(np.asarray(sc.objects[0].crystal_axes)))
    ob = dataclasses.replace(sc.objects[0], material=uni, crystal_axes=None, optic_axis=uni.optic_axis)
    return sc, dataclasses.replace(sc, objects=(ob,))


def _run(sc) -> tuple[float, int]:
    t = time.process_time()
    img = wo.render(sc)
    return time.process_time() - t, int(img.stats["rays"])


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=96)
    ap.add_argument("--wavelengths", type=int, default=8)
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--material", default="tanzanite")
    ap.add_argument("--json", default=None)
    ap.add_argument("--quick", action="store_true", help="16x16, 2 wavelengths, 1 repeat")
    args = ap.parse_args(argv)
    if args.quick:
        args.size, args.wavelengths, args.repeat = 16, 2, 1
    sc_bi, sc_uni = _scene(args.material, args.size, args.wavelengths)
    _run(sc_bi), _run(sc_uni)  # warm-up: kernel cache, material tables
    t_bi, t_uni, r_bi, r_uni = [], [], [], []
    for _ in range(args.repeat):
        a, ra = _run(sc_bi)
        b, rb = _run(sc_uni)
        t_bi.append(a)
        t_uni.append(b)
        r_bi.append(ra)
        r_uni.append(rb)
    out = {
        "material": args.material,
        "size": args.size,
        "wavelengths": args.wavelengths,
        "threads": os.environ["WARPOPTICS_THREADS"],
        "cpu_s_biaxial_median": float(np.median(t_bi)),
        "cpu_s_uniaxial_median": float(np.median(t_uni)),
        "rays_biaxial": int(np.median(r_bi)),
        "rays_uniaxial": int(np.median(r_uni)),
        "ratio_cpu": float(np.median(t_bi) / np.median(t_uni)),
        "ratio_cpu_per_ray": float(
            (np.median(t_bi) / np.median(r_bi)) / (np.median(t_uni) / np.median(r_uni))
        ),
        "target": 1.5,
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

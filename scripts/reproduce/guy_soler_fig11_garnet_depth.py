"""Reproduce the garnet depth series of Guy & Soler 2004 fig. 11 (a)-(d).

A garnet (§6.1: isotropic, n 1.730 ± .014, K = (0.136, 0.153, 0.175)) round brilliant rendered with
0, 1, 2 and 3 internal reflections: ``max_depth`` counts interfaces per path, and a path through
the stone with k internal reflections crosses k + 2 interfaces (in, k reflections, out), so
max_depth = k + 2; the external reflection is in every panel.  A fifth panel is the converged
render (max_depth 12).  Prints the stone's mean luminance per panel as a fraction of the converged
one and what each extra reflection adds — the paper: "after 2 reflections, very little is added".

Usage:
    python scripts/reproduce/guy_soler_fig11_garnet_depth.py \
        [-o docs/gallery/guy_soler_fig11_garnet_depth.png]
"""

from __future__ import annotations

import sys
import time

import _guy_soler_panels as sp


def main(argv: list[str] | None = None) -> int:
    args = sp.parser(__doc__, "docs/gallery/guy_soler_fig11_garnet_depth.png").parse_args(argv)
    size, wl = sp.sizes(args, 160, 16)
    t0 = time.perf_counter()
    panels = []
    for k, depth in ((0, 2), (1, 3), (2, 4), (3, 5), (None, 12)):
        label = f"{k} internal refl." if k is not None else "converged (depth 12)"
        sc = sp.gem_scene(
            {"shape": "round_brilliant", "diameter": 6.5, "material": "garnet"},
            size=size,
            wavelengths=wl,
            render={"max_depth": depth},
            camera={"position": [0.0, -22.0, 30.0], "look_at": [0.0, 0.0, -0.3], "fov": 17.0},
        )
        panels.append(sp.render_panel(label, sc, args.device))
    full = panels[-1]
    y_full = full.mean_xyz()[1]
    print(f"garnet (Guy & Soler §6.1), round brilliant 6.5 mm, {size} px, {wl} wavelengths, studio light")
    print(f"{'panel':22s} {'max_depth':>9s} {'Y stone':>8s} {'/ converged':>11s} {'added':>7s} {'time':>7s}")
    prev = 0.0
    for p, depth in zip(panels, (2, 3, 4, 5, 12), strict=True):
        y = p.mean_xyz()[1]
        added = (y - prev) / y_full
        print(f"{p.label:22s} {depth:9d} {y:8.4f} {y / y_full:11.3f} {added:+7.3f} {p.seconds:6.1f}s")
        prev = y
    sp.montage(
        args.output,
        [(p.label, p.image.display()) for p in panels],
        title="garnet: 0, 1, 2, 3 internal reflections and converged (Guy & Soler fig. 11 a-d)",
    )
    print(f"wrote {args.output}  total {time.perf_counter() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())

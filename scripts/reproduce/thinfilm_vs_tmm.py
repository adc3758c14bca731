"""Exact thin-film stacks (wo.thinfilm.reflectance, float64 Warp kernels) against the tmm package.

Prints the worst |R - R_tmm| per stack over wavelengths 380-780 nm, angles 0-89.9 degrees and s,
p and unpolarized light.

    python scripts/reproduce/thinfilm_vs_tmm.py [--quick]
"""

from __future__ import annotations

import argparse

import numpy as np
import tmm

import warpoptics as wo


def _tmm_r(pol, n_list, d_list, angle, wl):
    th = np.radians(angle)
    if pol == "unpolarized":
        return tmm.unpolarized_RT(n_list, d_list, th, wl)["R"]
    return tmm.coh_tmm(pol, n_list, d_list, th, wl)["R"]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="11 wavelengths instead of 81")
    ap.add_argument("--device", default=None)
    args = ap.parse_args(argv)
    rng = np.random.default_rng(5)
    cases = {
        "soap film": (1.0, [1.33], [420.0], 1.0),
        "film on glass": (1.0, [1.38], [99.6], 1.52),
        "twelve layers": (1.0, [1.46, 2.3] * 6, list(rng.uniform(40.0, 200.0, 12)), 1.52),
        "absorbing": (1.0, [1.5, 0.18 + 3.4j, 2.0 + 0.3j], [120.0, 15.0, 60.0], 1.7 + 0.02j),
    }
    wl = np.linspace(380.0, 780.0, 11 if args.quick else 81)
    angles = np.array([0.0, 30.0, 60.0, 85.0, 89.9])
    for name, (n0, nl, d, ns) in cases.items():
        n_list = [n0, *nl, ns]
        d_list = [np.inf, *d, np.inf]
        worst = 0.0
        for pol in ("s", "p", "unpolarized"):
            R = wo.thinfilm.reflectance(wl[:, None], nl, d, n0, ns, angles[None, :], pol, device=args.device)
            for j, a in enumerate(angles):
                ref = np.array([_tmm_r(pol, n_list, d_list, a, w) for w in wl])
                worst = max(worst, float(np.abs(R[:, j] - ref).max()))
        print(
            f"{name:15s} worst |R - R_tmm| over {wl.size} wavelengths x {angles.size} angles "
            f"x s/p/unpolarized: {worst:.2e}"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

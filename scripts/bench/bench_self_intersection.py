"""CPU seconds of the self-intersection check (``geometry.self_intersection``) against mesh size.

Icospheres of 4**s * 20 triangles (accepted: the check visits every edge), and the same sphere
merged with a shifted copy (refused: a witness is found).  Process CPU time of the warm kernel
(compile excluded), best of ``--repeat``: CPU time, unlike wall time, is not inflated much by
other processes on a shared machine.

    python scripts/bench/bench_self_intersection.py [--subdivisions 4 5 6 7] [--repeat 3]
"""

from __future__ import annotations

import argparse
import time

import trimesh

from warpoptics.geometry.self_intersection import self_intersection


def cpu_seconds(mesh: trimesh.Trimesh, repeat: int) -> tuple[float, bool]:
    best, found = float("inf"), False
    for _ in range(repeat):
        m = mesh.copy()  # no cached edges: the edge table is part of the cost
        t0 = time.process_time()
        found = self_intersection(m) is not None
        best = min(best, time.process_time() - t0)
    return best, found


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--subdivisions", type=int, nargs="+", default=[4, 5, 6, 7])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    self_intersection(trimesh.creation.icosphere(subdivisions=1))  # compile / load the kernel
    print(f"{'triangles':>10} {'accepted CPU s':>15} {'two spheres':>12} {'refused CPU s':>14}")
    for s in args.subdivisions:
        sphere = trimesh.creation.icosphere(subdivisions=s)
        other = sphere.copy()
        other.apply_translation([0.3, 0.2, 0.1])
        one, bad = cpu_seconds(sphere, args.repeat)
        two, found = cpu_seconds(trimesh.util.concatenate([sphere, other]), args.repeat)
        assert not bad and found
        print(f"{len(sphere.faces):>10} {one:>15.3f} {2 * len(sphere.faces):>12} {two:>14.3f}")


if __name__ == "__main__":
    main()

"""Write the lat-long environment maps of the light-performance sweeps (scenes/sweeps/*.exr).

- ``spots.exr``: the fire lighting.  24 small bright discs (angular radius 0.75 deg, radiance
  100 x white) spread evenly (a Fibonacci lattice) over 10-70 deg from the zenith, above a dim
  uniform upper hemisphere (2 % of white, so the stone's outline shows) and a black ground.
  GIA's fire metric (DCLR, Reinitz et al. 2001) uses directed, point-like light; several
  sources stand in for its average over light and observer positions, so that fire does not
  hinge on where one spot's image happens to fall in one view.
- ``dome_head.exr``: the uniform white dome (Y = 1) with a black cap of 20 deg radius at the
  zenith: an observer's head (or a camera) blocking the light from straight above a face-up
  stone, which GIA's brightness work discusses as observer obstruction.

The layout is warpoptics.stages.environment's default lat-long convention, Blender's (u = 0.5 -
atan2(y, x) / 2 pi, v = acos(z) / pi, row 0 at the zenith); values are linear sRGB (white = D65
in the renderer).

    python scripts/make_sweep_maps.py [--width 1024] [--folder scenes/sweeps]
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

from warpoptics.film.image import write_exr
from warpoptics.stages.environment import latlong_directions


def directions(width: int) -> np.ndarray:
    return latlong_directions(width, width // 2)


def spots_map(
    width: int = 1024,
    count: int = 24,
    radius_deg: float = 0.75,
    radiance: float = 100.0,
    ambient: float = 0.02,
    zenith_range_deg=(10.0, 70.0),
) -> np.ndarray:
    d = directions(width)
    img = np.where(d[..., 2:3] > 0, ambient, 0.0) * np.ones(3)
    c0, c1 = (math.cos(math.radians(a)) for a in zenith_range_deg)
    golden = math.pi * (3 - math.sqrt(5))
    cos_r = math.cos(math.radians(radius_deg))
    for i in range(count):
        z = c0 + (c1 - c0) * (i + 0.5) / count  # even in solid angle between the two zenith angles
        r = math.sqrt(1 - z * z)
        c = np.array([r * math.cos(i * golden), r * math.sin(i * golden), z])
        img[d @ c >= cos_r] = radiance
    return img.astype(np.float32)


def dome_head_map(width: int = 1024, head_radius_deg: float = 20.0) -> np.ndarray:
    d = directions(width)
    lit = (d[..., 2] > 0) & (d[..., 2] < math.cos(math.radians(head_radius_deg)))
    return (lit[..., None] * np.ones(3)).astype(np.float32)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--width", type=int, default=1024)
    ap.add_argument("--folder", default="scenes/sweeps")
    a = ap.parse_args()
    for name, img in (("spots.exr", spots_map(a.width)), ("dome_head.exr", dome_head_map(a.width))):
        p = write_exr(Path(a.folder) / name, img)
        p.chmod(0o644)
        print(p)


if __name__ == "__main__":
    main()

"""The ``Screen`` sink of the optical bench: a plane rectangular detector.

A screen absorbs every forward ray that meets it (from either side) and records the ray's power
per wavelength sample with its Stokes vector.  The forward kernel (``stages.forward``) writes
one *deposit* per ray that reaches a screen (screen, position on it, wavelength sample, power
and Stokes vector, number of interfaces crossed) into that ray's own slots; :meth:`Screen.image`
bins the deposits into pixels in a fixed order (``np.bincount``), so the images do not depend
on the thread count or tiling.

Frames: a screen has a centre, a unit ``normal`` pointing toward the light it receives (the lit
side) and an ``up`` vector.  Its image is the picture seen *looking toward the light* (from
behind a translucent screen, like a camera sensor): ``right = normal x up``, ``up``; (right, up,
d) is right-handed for light arriving against the normal, the camera convention of
``docs/conventions.md``.  Pixel (row 0 = top).  Stokes vectors are given in the frame (x, y) with x the
screen's ``right`` projected perpendicular to the ray and ``y = d x x``.

Units: power in W (the beam's ``power``), positions in mm; XYZ images are normalised so that the
whole beam collected in one pixel would have Y = 1 (Y = luminous fraction of the beam).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import warp as wp

from ..device import get_device
from ..errors import InputError
from .image import Image

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = ["ScreenSet", "Screen", "ScreenImage", "screen_hit", "screen_set"]


@wp.struct
class ScreenSet:
    """All screens of a bench, for kernels: per screen its centre, unit normal, right and up
    vectors and half sizes (mm)."""

    count: int
    center: wp.array(dtype=wp.vec3f)
    normal: wp.array(dtype=wp.vec3f)
    right: wp.array(dtype=wp.vec3f)
    up: wp.array(dtype=wp.vec3f)
    half_size: wp.array(dtype=wp.vec2f)


@wp.func
def screen_hit(s: ScreenSet, origin: wp.vec3f, direction: wp.vec3f, t_max: float):
    """Nearest screen along the ray within (0, t_max): (t, screen index or -1, u, v) with (u, v)
    the hit point in the screen's (right, up) coordinates, mm from its centre."""
    best_t = t_max
    best = int(-1)
    bu = float(0.0)
    bv = float(0.0)
    for k in range(s.count):
        n = s.normal[k]
        dn = wp.dot(direction, n)
        if dn != 0.0:
            t = wp.dot(s.center[k] - origin, n) / dn
            if t > 0.0 and t < best_t:
                p = origin + direction * t - s.center[k]
                u = wp.dot(p, s.right[k])
                v = wp.dot(p, s.up[k])
                h = s.half_size[k]
                if wp.abs(u) <= h[0] and wp.abs(v) <= h[1]:
                    best_t = t
                    best = k
                    bu = u
                    bv = v
    return best_t, best, bu, bv


def _unit(v, field: str) -> np.ndarray:
    a = np.asarray(v, dtype=np.float64)
    n = float(np.linalg.norm(a)) if a.shape == (3,) else 0.0
    if a.shape != (3,) or not np.isfinite(a).all() or n == 0.0:
        raise InputError("must be a non-zero vector [x, y, z]", field=field, value=v)
    return a / n


@dataclass(frozen=True)
class Screen:
    """A plane detector: ``center`` (mm), ``normal`` toward the lit side, ``up``, ``size``
    (width, height, mm), ``resolution`` (width, height, pixels)."""

    center: tuple[float, float, float] = (0.0, 0.0, 100.0)
    normal: tuple[float, float, float] = (0.0, 0.0, -1.0)
    up: tuple[float, float, float] = (0.0, 1.0, 0.0)
    size: tuple[float, float] = (50.0, 50.0)
    resolution: tuple[int, int] = (256, 256)
    name: str = "screen"

    def __post_init__(self) -> None:
        f = f"sensor.{self.name}."
        n = _unit(self.normal, f + "normal")
        u = _unit(self.up, f + "up")
        if abs(float(n @ u)) > 1.0 - 1e-9:
            raise InputError("up must not be parallel to the normal", field=f + "up", value=list(self.up))
        if len(self.size) != 2 or not all(math.isfinite(s) and s > 0 for s in self.size):
            raise InputError(
                "must be two sizes > 0 [width, height] in mm", field=f + "size", value=list(self.size)
            )
        if len(self.resolution) != 2 or not all(int(r) == r and 1 <= r <= 16384 for r in self.resolution):
            raise InputError(
                "must be two pixel counts 1..16384 [width, height]",
                field=f + "resolution",
                value=list(self.resolution),
            )

    def frame(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(normal, right, up) orthonormal, right = normal x up (up re-orthogonalised)."""
        n = _unit(self.normal, "normal")
        u = _unit(self.up, "up")
        u = u - n * (n @ u)
        u /= np.linalg.norm(u)
        return n, np.cross(n, u), u

    def pixel_index(self, u: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Flat pixel index (row 0 = top) of screen coordinates (mm from the centre)."""
        w, h = self.size
        nx, ny = (int(r) for r in self.resolution)
        col = np.clip(np.floor((np.asarray(u) / w + 0.5) * nx), 0, nx - 1).astype(np.int64)
        row = np.clip(np.floor((0.5 - np.asarray(v) / h) * ny), 0, ny - 1).astype(np.int64)
        return row * nx + col

    def pixel_centers(self) -> tuple[np.ndarray, np.ndarray]:
        """(u, v) coordinates (mm) of the pixel centres, each (height, width)."""
        w, h = self.size
        nx, ny = (int(r) for r in self.resolution)
        u = (np.arange(nx) + 0.5) / nx * w - w / 2
        v = h / 2 - (np.arange(ny) + 0.5) / ny * h
        return np.meshgrid(u, v)


def screen_set(screens: list[Screen], device=None) -> ScreenSet:
    """Upload screens for kernels."""
    dev = get_device(device)
    s = ScreenSet()
    s.count = len(screens)
    rows = [sc.frame() for sc in screens] or [(np.zeros(3), np.zeros(3), np.zeros(3))]
    centers = [sc.center for sc in screens] or [(0.0, 0.0, 0.0)]
    halves = [(sc.size[0] / 2, sc.size[1] / 2) for sc in screens] or [(0.0, 0.0)]
    s.center = wp.array(np.asarray(centers, dtype=np.float32), dtype=wp.vec3f, device=dev)
    s.normal = wp.array(np.asarray([r[0] for r in rows], dtype=np.float32), dtype=wp.vec3f, device=dev)
    s.right = wp.array(np.asarray([r[1] for r in rows], dtype=np.float32), dtype=wp.vec3f, device=dev)
    s.up = wp.array(np.asarray([r[2] for r in rows], dtype=np.float32), dtype=wp.vec3f, device=dev)
    s.half_size = wp.array(np.asarray(halves, dtype=np.float32), dtype=wp.vec2f, device=dev)
    return s


@dataclass
class ScreenImage:
    """What one screen recorded.  ``xyz`` (H, W, 3) float64 (Y = luminous fraction of the
    beam); ``stokes`` (H, W, 4) float64, power-weighted Stokes vectors in W (S0 = power);
    ``power`` total W on the screen; ``screen`` the :class:`Screen`."""

    screen: Screen
    xyz: np.ndarray
    stokes: np.ndarray
    power: float
    exposure: float = 0.0
    tone: str = "filmic"

    def as_image(self):
        """A :class:`warpoptics.film.image.Image` (for ``rgb``, ``display()``, ``save()``); its exposure
        puts the 99.9th percentile of the lit pixels' Y at 1 (plus ``exposure`` stops)."""
        y = self.xyz[..., 1]
        lit = y[y > 0]
        ref = float(np.percentile(lit, 99.9)) if lit.size else 1.0
        auto = -math.log2(ref) if ref > 0 else 0.0
        alpha = (self.stokes[..., 0] > 0).astype(np.float64)
        return Image(
            xyz=self.xyz, stokes=self.stokes, alpha=alpha, exposure=auto + self.exposure, tone=self.tone
        )

    def save(self, path):
        """EXR (R, G, B, A, S0..S3, X, Y, Z; unscaled) or PNG (auto-exposed, tone mapped)."""
        return self.as_image().save(path)

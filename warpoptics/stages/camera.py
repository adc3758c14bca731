"""The camera: primary rays for an image, with their polarization basis.

Raster coordinates: x to the right, y down, pixel (i, j) covers [i, i+1) x [j, j+1).  The
polarization basis of a primary ray is the image-right axis made perpendicular to the ray; with
the light travelling toward the camera (k = -direction) the frame (x = right, y = k x right ~ up,
k) is right-handed, so output Stokes vectors are in the camera frame x = image right, y = image
up (docs/conventions.md, "Frames").
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import warp as wp

from ..errors import InputError

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = ["CameraParams", "CameraConfig", "Camera", "camera_basis", "camera_ray", "CAMERA_KINDS"]

CAMERA_KINDS = {"perspective": 0, "orthographic": 1, "thin_lens": 2}
_ORTHO = wp.constant(1)
_THIN_LENS = wp.constant(2)


@wp.struct
class CameraParams:
    kind: int
    position: wp.vec3f
    forward: wp.vec3f
    right: wp.vec3f
    up: wp.vec3f
    tan_half_x: float  # perspective: tan of half the horizontal field of view
    tan_half_y: float
    half_width: float  # orthographic: half the view size in mm
    half_height: float
    width: int
    height: int
    aperture_radius: float  # thin lens, mm
    focus_distance: float  # thin lens, mm along forward


@wp.func
def camera_ray(cam: CameraParams, px: float, py: float, lens_u: float, lens_v: float):
    """Primary ray through raster point (px, py): returns (origin, unit direction, unit
    polarization basis x perpendicular to the direction).  ``lens_u, lens_v`` in [0, 1) sample
    the thin-lens aperture (ignored otherwise)."""
    sx = 2.0 * px / float(cam.width) - 1.0
    sy = 1.0 - 2.0 * py / float(cam.height)
    origin = cam.position
    direction = cam.forward
    if cam.kind == _ORTHO:
        origin = cam.position + cam.right * (sx * cam.half_width) + cam.up * (sy * cam.half_height)
    else:
        direction = wp.normalize(
            cam.forward + cam.right * (sx * cam.tan_half_x) + cam.up * (sy * cam.tan_half_y)
        )
        if cam.kind == _THIN_LENS:
            # point on the plane of focus, then a ray to it from a point on the aperture disc
            focus = cam.position + direction * (cam.focus_distance / wp.dot(direction, cam.forward))
            r = cam.aperture_radius * wp.sqrt(lens_u)
            phi = 2.0 * wp.pi * lens_v
            origin = cam.position + cam.right * (r * wp.cos(phi)) + cam.up * (r * wp.sin(phi))
            direction = wp.normalize(focus - origin)
    bx = cam.right - direction * wp.dot(cam.right, direction)
    return origin, direction, wp.normalize(bx)


@dataclass(frozen=True)
class CameraConfig:
    """Camera settings (scene ``[camera]``), lengths in mm, angles in degrees."""

    type: str = "perspective"
    position: tuple[float, float, float] = (0.0, -30.0, 25.0)
    look_at: tuple[float, float, float] = (0.0, 0.0, 0.0)
    up: tuple[float, float, float] = (0.0, 0.0, 1.0)
    fov: float = 20.0  # vertical field of view (perspective, thin lens)
    view_height: float = 10.0  # orthographic: height of the view in mm
    width: int = 512
    height: int = 512
    aperture: float = 0.0  # thin lens: aperture diameter, mm
    focus_distance: float | None = None  # thin lens: default the distance to look_at
    source: str | None = field(default=None, compare=False)

    def _err(self, name, value, message, allowed=None):
        return InputError(message, file=self.source, field=f"camera.{name}", value=value, allowed=allowed)

    def __post_init__(self):
        if not isinstance(self.type, str) or self.type not in CAMERA_KINDS:
            raise self._err("type", self.type, "unknown camera type", ", ".join(CAMERA_KINDS))
        for name in ("width", "height"):
            v = getattr(self, name)
            if not isinstance(v, int) or isinstance(v, bool) or not 1 <= v <= 16384:
                raise self._err(name, v, "must be an integer pixel count", "1 to 16384")
        if not (0.01 <= self.fov <= 170.0):
            raise self._err("fov", self.fov, "field of view out of range", "0.01 to 170 degrees")
        if not (self.view_height > 0 and math.isfinite(self.view_height)):
            raise self._err("view_height", self.view_height, "must be > 0 mm")
        if not (self.aperture >= 0 and math.isfinite(self.aperture)):
            raise self._err("aperture", self.aperture, "must be >= 0 mm")
        for name in ("position", "look_at", "up"):
            v = getattr(self, name)
            if len(v) != 3 or not all(isinstance(c, (int, float)) and math.isfinite(c) for c in v):
                raise self._err(name, v, "must be three finite numbers [x, y, z] in mm")
        fwd = np.subtract(self.look_at, self.position)
        if np.linalg.norm(fwd) == 0:
            raise self._err("look_at", self.look_at, "equals camera.position; the camera has no direction")
        if np.linalg.norm(np.cross(fwd, self.up)) < 1e-9 * np.linalg.norm(fwd) * max(
            np.linalg.norm(self.up), 1e-30
        ):
            raise self._err("up", self.up, "is zero or parallel to the viewing direction")
        if self.focus_distance is not None and not (
            self.focus_distance > 0 and math.isfinite(self.focus_distance)
        ):
            raise self._err("focus_distance", self.focus_distance, "must be > 0 mm")


def camera_basis(config: CameraConfig) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(forward, right, up): the camera's unit world axes (image right = forward x up, image up
    = right x forward), as the camera stage traces them."""
    pos = np.asarray(config.position, dtype=np.float64)
    fwd = np.asarray(config.look_at, dtype=np.float64) - pos
    fwd /= np.linalg.norm(fwd)
    right = np.cross(fwd, np.asarray(config.up, dtype=np.float64))
    right /= np.linalg.norm(right)
    return fwd, right, np.cross(right, fwd)


class Camera:
    """Source stage for images: holds the :class:`CameraParams` struct of a configuration."""

    def __init__(self, config: CameraConfig):
        self.config = config
        c = config
        pos = np.asarray(c.position, dtype=np.float64)
        dist = float(np.linalg.norm(np.asarray(c.look_at, dtype=np.float64) - pos))
        fwd, right, up = camera_basis(c)
        p = CameraParams()
        p.kind = CAMERA_KINDS[c.type]
        p.position = wp.vec3f(*pos)
        p.forward = wp.vec3f(*fwd)
        p.right = wp.vec3f(*right)
        p.up = wp.vec3f(*up)
        aspect = c.width / c.height
        p.tan_half_y = math.tan(math.radians(c.fov) / 2)
        p.tan_half_x = p.tan_half_y * aspect
        p.half_height = c.view_height / 2
        p.half_width = p.half_height * aspect
        p.width = c.width
        p.height = c.height
        p.aperture_radius = c.aperture / 2
        p.focus_distance = float(c.focus_distance if c.focus_distance is not None else dist)
        self.params = p

    @property
    def width(self) -> int:
        return self.config.width

    @property
    def height(self) -> int:
        return self.config.height

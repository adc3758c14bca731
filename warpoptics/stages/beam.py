"""The ``Beam`` source of the optical bench: a collimated beam or a spot light, traced forward.

A beam emits ``power`` watts (1 by default) spread over ``rays`` deterministic positions (or
directions) and ``wavelengths`` spectral samples: each forward ray is one (position, wavelength)
pair and carries ``power * w_lambda / rays`` where ``w_lambda`` is the fraction of the power in
its wavelength sample (from the beam's spectrum: an illuminant, an sRGB colour, or lines).

- ``collimated``: parallel rays along ``direction`` from points of a disc of diameter ``width``
  centred on ``position`` (uniform irradiance over the disc).  Positions follow Vogel's sunflower
  spiral, r_k = R sqrt((k + 1/2) / N), phi_k = k * golden angle: equal areas per ray, no
  grid aliasing, deterministic.
- ``spot``: a point light at ``position`` emitting into a cone of full angle ``divergence`` (deg)
  about ``direction``, uniform in solid angle (the same spiral on the spherical cap).

Polarization: the beam's field is described in the frame ``(x, y = d x x)`` with
``x = perpendicular(d)`` (``optics.jones``) unless ``polarization_x`` names another x; the source
coherency matrix (trace 1) is ``I / 2`` (unpolarized), ``e e^dagger`` for linear light at
``polarization_angle`` degrees from x toward y, or circular light (``right``: S3 = +1 in the
convention of ``optics.jones.stokes_from_coherency``).

References: H. Vogel, "A better way to construct the sunflower head", Math. Biosci. 44 (1979).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import warp as wp

from ..errors import InputError
from ..optics.jones import Jones, perpendicular

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = ["BeamParams", "Beam", "beam_ray", "BEAM_COLLIMATED", "BEAM_SPOT", "BEAM_TYPES", "POLARIZATIONS"]

BEAM_COLLIMATED = 0
BEAM_SPOT = 1
BEAM_TYPES = {"collimated": BEAM_COLLIMATED, "spot": BEAM_SPOT}
POLARIZATIONS = ("unpolarized", "linear", "right", "left")
_GOLDEN_ANGLE = math.pi * (3.0 - math.sqrt(5.0))


@wp.struct
class BeamParams:
    """A beam for kernels.  Lengths in mm, angles in radians."""

    kind: int  # BEAM_COLLIMATED | BEAM_SPOT
    position: wp.vec3f  # disc centre (collimated) or the point light (spot), mm
    direction: wp.vec3f  # unit beam axis
    basis_x: wp.vec3f  # unit x of the source polarization frame, perpendicular to direction
    radius: float  # disc radius, mm (collimated)
    cos_half_angle: float  # cosine of the cone's half angle (spot)
    count: int  # number of positions / directions
    source_coherency: Jones  # coherency matrix of the emitted light in (x, d x x), trace 1


@wp.func
def beam_ray(b: BeamParams, k: int):
    """Origin, unit direction and polarization basis x of ray ``k`` of ``b.count`` (Vogel spiral)."""
    f = (float(k) + 0.5) / float(b.count)
    phi = float(k) * 2.399963229728653  # golden angle, rad
    bx = b.basis_x
    by = wp.cross(b.direction, bx)
    if b.kind == BEAM_COLLIMATED:
        r = b.radius * wp.sqrt(f)
        o = b.position + bx * (r * wp.cos(phi)) + by * (r * wp.sin(phi))
        return o, b.direction, bx
    # spot: uniform in solid angle on the cap cos(theta) in [cos_half_angle, 1]
    c = 1.0 - (1.0 - b.cos_half_angle) * f
    s = wp.sqrt(wp.max(1.0 - c * c, 0.0))
    d = wp.normalize(b.direction * c + bx * (s * wp.cos(phi)) + by * (s * wp.sin(phi)))
    # carry the source frame onto the ray: x' = x - d (d . x), renormalised (parallel transport
    # about the small tilt; exact for the axis ray)
    x = bx - d * wp.dot(d, bx)
    if wp.dot(x, x) < 1.0e-12:
        x = perpendicular(d)
    return b.position, d, wp.normalize(x)


def _unit(v, field: str) -> np.ndarray:
    a = np.asarray(v, dtype=np.float64)
    n = float(np.linalg.norm(a))
    if a.shape != (3,) or not np.isfinite(a).all() or n == 0.0:
        raise InputError(
            "must be a non-zero vector [x, y, z]", field=field, value=[float(x) for x in np.ravel(a)]
        )
    return a / n


@dataclass(frozen=True)
class Beam:
    """A beam source (see the module docstring).  Lengths in mm, angles in degrees.

    ``spectrum``: an illuminant name (``"E"``, ``"D65"``, ``"A"``) or a linear-sRGB triple;
    ``lines``: emit only these wavelengths (nm), equal power each, instead of ``spectrum``.
    """

    type: str = "collimated"
    position: tuple[float, float, float] = (0.0, 0.0, 10.0)
    direction: tuple[float, float, float] = (0.0, 0.0, -1.0)
    width: float = 1.0
    divergence: float = 10.0
    spectrum: str | tuple[float, float, float] = "E"
    lines: tuple[float, ...] | None = None
    polarization: str = "unpolarized"
    polarization_angle: float = 0.0
    polarization_x: tuple[float, float, float] | None = None
    power: float = 1.0
    rays: int = 256

    def __post_init__(self) -> None:
        if self.type not in BEAM_TYPES:
            raise InputError(
                "unknown beam type", field="source.type", value=self.type, allowed=", ".join(BEAM_TYPES)
            )
        _unit(self.direction, "source.direction")
        if not (math.isfinite(self.width) and self.width >= 0.0):
            raise InputError("must be >= 0", field="source.width", value=self.width)
        if not (0.0 < self.divergence < 360.0):
            raise InputError(
                "out of range", field="source.divergence", value=self.divergence, allowed="> 0 and < 360"
            )
        if self.polarization not in POLARIZATIONS:
            raise InputError(
                "unknown polarization",
                field="source.polarization",
                value=self.polarization,
                allowed=", ".join(POLARIZATIONS),
            )
        if not (self.power > 0.0 and math.isfinite(self.power)):
            raise InputError("must be > 0", field="source.power", value=self.power)
        if int(self.rays) != self.rays or not 1 <= self.rays <= 1 << 24:
            raise InputError("out of range", field="source.rays", value=self.rays, allowed="1 .. 16777216")
        if self.lines is not None:
            lines = np.asarray(self.lines, dtype=np.float64)
            if lines.ndim != 1 or lines.size == 0 or not np.all((lines >= 360.0) & (lines <= 830.0)):
                raise InputError(
                    "wavelengths must lie in 360 .. 830 nm", field="source.lines", value=list(self.lines)
                )
        if isinstance(self.spectrum, str):
            from ..spectra import ILLUMINANTS

            if self.spectrum not in ILLUMINANTS:
                raise InputError(
                    "unknown illuminant",
                    field="source.spectrum",
                    value=self.spectrum,
                    allowed=", ".join(ILLUMINANTS) + " or an sRGB triple [r, g, b]",
                )
        else:
            rgb = np.asarray(self.spectrum, dtype=np.float64)
            if rgb.shape != (3,) or not np.isfinite(rgb).all() or rgb.min() < 0 or rgb.max() <= 0:
                raise InputError(
                    "must be an illuminant name or a non-negative sRGB triple [r, g, b]",
                    field="source.spectrum",
                    value=self.spectrum,
                )

    def basis(self) -> tuple[np.ndarray, np.ndarray]:
        """(direction, x) unit vectors of the source frame (x = ``polarization_x`` projected
        perpendicular to the direction, else ``perpendicular(direction)`` of ``optics.jones``)."""
        d = _unit(self.direction, "source.direction")
        if self.polarization_x is not None:
            x = np.asarray(self.polarization_x, dtype=np.float64)
            x = x - d * (d @ x)
            if np.linalg.norm(x) < 1e-9:
                raise InputError(
                    "must not be parallel to the direction",
                    field="source.polarization_x",
                    value=list(self.polarization_x),
                )
            return d, x / np.linalg.norm(x)
        # perpendicular() of optics.jones, written out (host-side choice of a frame, not physics)
        a = np.abs(d)
        e = np.array([1.0, 0.0, 0.0])
        if a[1] <= a[0] and a[1] <= a[2]:
            e = np.array([0.0, 1.0, 0.0])
        elif a[2] < a[0] and a[2] < a[1]:
            e = np.array([0.0, 0.0, 1.0])
        x = np.cross(e, d)
        return d, x / np.linalg.norm(x)

    def coherency(self) -> np.ndarray:
        """2x2 complex source coherency matrix (trace 1) in the frame (x, d x x)."""
        if self.polarization == "unpolarized":
            return np.eye(2, dtype=complex) / 2.0
        if self.polarization == "linear":
            a = math.radians(self.polarization_angle)
            e = np.array([math.cos(a), math.sin(a)], dtype=complex)
        elif self.polarization == "right":
            # S3 = 2 Im J_xy = +1: J_xy = i/2 -> e = (1, -i)/sqrt 2 (J = e e^dagger)
            e = np.array([1.0, -1.0j]) / math.sqrt(2.0)
        else:
            e = np.array([1.0, 1.0j]) / math.sqrt(2.0)
        return np.outer(e, e.conj())

    def spectral_samples(self, count: int) -> tuple[np.ndarray, np.ndarray]:
        """(wavelength_nm, power fraction) of the beam's spectral samples (fractions sum to 1).

        ``lines``: those wavelengths, equal power.  Otherwise ``count`` strata of 360-830 nm,
        each sampled at its midpoint, weighted by the spectrum's power in it."""
        from ..spectra import LAMBDA_MAX, LAMBDA_MIN, illuminant, rgb_to_spectrum

        if self.lines is not None:
            wl = np.asarray(self.lines, dtype=np.float64)
            return wl, np.full(wl.size, 1.0 / wl.size)
        count = int(count)
        if count < 1:
            raise InputError("at least one wavelength", field="render.wavelengths", value=count)
        step = (LAMBDA_MAX - LAMBDA_MIN) / count
        wl = LAMBDA_MIN + step * (np.arange(count) + 0.5)
        if isinstance(self.spectrum, str):
            s = illuminant(self.spectrum, wl)
        else:
            s = rgb_to_spectrum(np.asarray(self.spectrum, dtype=np.float64), wl)
        s = np.clip(np.asarray(s, dtype=np.float64), 0.0, None)
        if s.sum() <= 0:
            raise InputError(
                "the spectrum has no power in 360-830 nm", field="source.spectrum", value=self.spectrum
            )
        return wl, s / s.sum()

    def params(self) -> BeamParams:
        """The kernel struct of this beam."""
        d, x = self.basis()
        c = self.coherency()
        p = BeamParams()
        p.kind = BEAM_TYPES[self.type]
        p.position = wp.vec3f(*[float(v) for v in self.position])
        p.direction = wp.vec3f(*[float(v) for v in d])
        p.basis_x = wp.vec3f(*[float(v) for v in x])
        p.radius = float(self.width) / 2.0
        p.cos_half_angle = math.cos(math.radians(self.divergence) / 2.0)
        p.count = int(self.rays)
        j = Jones()
        j.re = wp.mat22(*[float(v) for v in c.real.ravel()])
        j.im = wp.mat22(*[float(v) for v in c.imag.ravel()])
        p.source_coherency = j
        return p

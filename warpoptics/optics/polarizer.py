"""Ideal linear polarizers: the Mueller matrix (analyzers on Stokes images) and the polarized
light behind a polarizer sheet (polarized illumination for a polariscope).

Conventions (docs/conventions.md, :mod:`warpoptics.optics.jones`): Stokes vectors S0..S3 in a frame
(x, y, k) with k the direction the light travels; ``S1 = Jxx - Jyy``, ``S2 = 2 Re Jxy``.  An
angle ``theta`` (radians in the ``@wp.func``s, degrees in the NumPy wrappers and scenes) is the
transmission axis measured from x toward y — in the camera frame from image right toward image
up, i.e. counter-clockwise on the image.

- :func:`mueller_linear_polarizer`: the Mueller matrix of an ideal linear polarizer with its
  transmission axis at ``theta`` (Goldstein 2003 eq. 5-15; Born & Wolf §10.8):
  ``M = 1/2 [[1, c, s, 0], [c, c^2, cs, 0], [s, cs, s^2, 0], [0, 0, 0, 0]]``, c = cos 2 theta,
  s = sin 2 theta.  On fully polarized linear light of azimuth psi it gives Malus's law
  ``I cos^2(theta - psi)``; on unpolarized light ``I/2``.
- :func:`sheet_polarizer_coherency`: the coherency matrix, in a ray's own frame, of unpolarized
  light of intensity ``I`` that has passed an ideal dichroic sheet polarizer whose *absorbing*
  axis is the unit world vector ``a``.  The sheet removes the field component along ``a``
  (projected on the plane transverse to the ray) and passes the rest: light travelling along
  ``k`` leaves linearly polarized along ``k x a`` with intensity ``I/2`` (the Mueller matrix
  above applied to ``(I, 0, 0, 0)`` at that azimuth).  For light travelling along the sheet
  normal this is a polarizer whose transmission axis is ``a`` turned by -90 deg about ``k``;
  light travelling along ``a`` itself (grazing the sheet) is left unpolarized.

- :func:`lens_polarizer_field`: a polarizer (or analyzer) in the collimated beam of a
  polarizing microscope seen through its aplanatic condenser (objective) in one direction of
  the cone (conoscopic light).

References:
    B. Richards, E. Wolf, *Electromagnetic diffraction in optical systems II*, Proc. R. Soc. A
    253 (1959) (aplanatic lens: the field turned with the ray in its meridional plane).
    D. Goldstein, *Polarized Light*, 2nd ed. (2003), §5.3, eq. 5-15 (Mueller matrix of a linear
    polarizer).  M. Born, E. Wolf, *Principles of Optics*, 7th ed. (1999), §1.4.2 (Malus), §10.8
    (Stokes parameters).  E. Wolf (1959) (coherency matrices).
"""

from __future__ import annotations

import math

import numpy as np
import warp as wp

from ..device import device_function, elementwise
from ..errors import InputError
from .jones import Jones, coherency_from_stokes_vec, coherency_unpolarized

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "mueller_linear_polarizer",
    "polarizer_stokes",
    "sheet_polarizer_coherency",
    "sheet_absorbing_axis",
    "lens_polarizer_field",
    # NumPy wrappers
    "mueller_polarizer",
    "analyze",
    "sheet_polarizer_stokes",
]


@wp.func
def mueller_linear_polarizer(theta: float):
    """Mueller matrix (4x4) of an ideal linear polarizer, transmission axis at ``theta``
    (radians, from x toward y of the Stokes frame) (Goldstein 2003 eq. 5-15)."""
    c = wp.cos(2.0 * theta)
    s = wp.sin(2.0 * theta)
    return wp.mat44(
        0.5, 0.5 * c, 0.5 * s, 0.0,
        0.5 * c, 0.5 * c * c, 0.5 * c * s, 0.0,
        0.5 * s, 0.5 * c * s, 0.5 * s * s, 0.0,
        0.0, 0.0, 0.0, 0.0,
    )  # fmt: skip


@wp.func
def polarizer_stokes(s: wp.vec4, theta: float):
    """Stokes vector after an ideal linear polarizer at ``theta`` (radians): M(theta) s."""
    return mueller_linear_polarizer(theta) * s


@wp.func
def sheet_polarizer_coherency(
    absorb_axis: wp.vec3f, k: wp.vec3f, basis_x: wp.vec3f, intensity: float
) -> Jones:
    """Coherency matrix, in the frame (basis_x, k x basis_x), of unpolarized light of
    ``intensity`` after an ideal dichroic sheet with unit absorbing axis ``absorb_axis`` (world);
    ``k``: unit direction the light travels.  A zero axis means no polarizer (unpolarized light
    of the full intensity).  Polarized light leaves along ``k x a`` with intensity I/2."""
    e = wp.cross(k, absorb_axis)
    if wp.dot(e, e) < 1.0e-12:
        # no polarizer, or light along the absorbing axis (grazing the sheet): nothing removed
        return coherency_unpolarized(intensity)
    y = wp.cross(k, basis_x)
    psi = wp.atan2(wp.dot(e, y), wp.dot(e, basis_x))
    return coherency_from_stokes_vec(polarizer_stokes(wp.vec4(intensity, 0.0, 0.0, 0.0), psi))


@wp.func
def lens_polarizer_field(t_axis: wp.vec3f, beam: wp.vec3f, x: wp.vec3f):
    """Field components, in the frame (x, k x x) of a direction k of a lens's cone, of the unit
    field an ideal linear polarizer (unit transmission axis ``t_axis`` across the collimated
    ``beam``) gives after an aplanatic lens turns the beam into k; ``x`` is the unit vector
    across the meridional plane of k (the s-direction of a face normal to ``beam``).

    An aplanatic lens (sine condition) keeps the component across the meridional plane and
    turns the meridional one with the ray (Richards & Wolf 1959): the components are
    ``(t . x, t . (beam x x))``.  The same holds backward for the objective in front of an
    analyzer, so a crossed pair extinguishes every direction of an isotropic specimen (the dark
    field of a conoscope; Fresnel s/p differences at the specimen lift it off the polarizers'
    directions, the isogyres of a uniaxial figure)."""
    return wp.vec2f(wp.dot(t_axis, x), wp.dot(t_axis, wp.cross(beam, x)))


# ----------------------------------------------------------------------------------------------
# private element-wise kernels (offset first, see warpoptics.device)


@wp.kernel
def _analyze_kernel(
    offset: int,
    s: wp.array(dtype=wp.vec4d),
    theta: wp.array(dtype=wp.float32),
    out: wp.array(dtype=wp.vec4d),
):
    # images are float64 (the film); the polarizer acts in float32 (relative error ~1e-7)
    i = wp.tid() + offset
    v = s[i]
    r = polarizer_stokes(wp.vec4(float(v[0]), float(v[1]), float(v[2]), float(v[3])), theta[i])
    out[i] = wp.vec4d(wp.float64(r[0]), wp.float64(r[1]), wp.float64(r[2]), wp.float64(r[3]))


@wp.kernel
def _mueller_kernel(offset: int, theta: wp.array(dtype=wp.float32), out: wp.array(dtype=wp.mat44)):
    i = wp.tid() + offset
    out[i] = mueller_linear_polarizer(theta[i])


@wp.kernel
def _sheet_kernel(
    offset: int,
    axis: wp.array(dtype=wp.vec3f),
    k: wp.array(dtype=wp.vec3f),
    bx: wp.array(dtype=wp.vec3f),
    out: wp.array(dtype=wp.vec4),
):
    i = wp.tid() + offset
    j = sheet_polarizer_coherency(axis[i], k[i], bx[i], 1.0)
    out[i] = wp.vec4(j.re[0, 0] + j.re[1, 1], j.re[0, 0] - j.re[1, 1], 2.0 * j.re[0, 1], 2.0 * j.im[0, 1])


# ----------------------------------------------------------------------------------------------
# NumPy wrappers (angles in degrees)


def _finite(value, name: str) -> np.ndarray:
    """``value`` as an array, or an InputError naming the argument and its first NaN/Inf."""
    a = np.asarray(value)
    bad = ~np.isfinite(a)
    if np.any(bad):
        raise InputError("must be finite", field=name, value=a[bad].flat[0], allowed="finite numbers")
    return a


@device_function(mueller_linear_polarizer)
def mueller_polarizer(angle_deg, *, device=None) -> np.ndarray:
    """Mueller matrices (..., 4, 4) of ideal linear polarizers at ``angle_deg`` (degrees)."""
    theta = np.radians(_finite(angle_deg, "angle_deg").astype(np.float64))
    (m,) = elementwise(_mueller_kernel, [(theta, wp.float32)], [wp.mat44], device=device)
    return np.asarray(m, dtype=np.float64).reshape(*theta.shape, 4, 4)


@device_function(polarizer_stokes)
def analyze(stokes, angle_deg, *, device=None) -> np.ndarray:
    """Stokes vectors (..., 4) after an ideal linear analyzer with its transmission axis at
    ``angle_deg`` (degrees from x toward y; broadcasts against ``stokes[..., 0]``).  Float64 in
    and out, the polarizer computed in float32 (``mueller_linear_polarizer``)."""
    theta = np.radians(_finite(angle_deg, "angle_deg").astype(np.float64))
    (out,) = elementwise(
        _analyze_kernel,
        [(_finite(stokes, "stokes"), wp.vec4d), (theta, wp.float32)],
        [wp.vec4d],
        device=device,
    )
    return out


@device_function(sheet_polarizer_coherency)
def sheet_polarizer_stokes(absorb_axis, k, basis_x, *, device=None) -> np.ndarray:
    """Stokes vectors (..., 4) in the frame (basis_x, k x basis_x) of unit-intensity unpolarized
    light after an ideal sheet with absorbing axis ``absorb_axis`` (see
    :func:`sheet_polarizer_coherency`)."""
    (s,) = elementwise(
        _sheet_kernel,
        [
            (_finite(absorb_axis, "absorb_axis"), wp.vec3f),
            (_finite(k, "k"), wp.vec3f),
            (_finite(basis_x, "basis_x"), wp.vec3f),
        ],
        [wp.vec4],
        device=device,
    )
    return s.astype(np.float64)


def sheet_absorbing_axis(right, up, angle_deg: float) -> np.ndarray:
    """World absorbing axis of a sheet polarizer facing the camera whose *transmission* axis is at
    ``angle_deg`` on the image (from image right toward image up): ``a = -sin(t) right + cos(t) up``.
    Light travelling toward the camera (k = right x up) then leaves polarized along
    ``k x a = -(cos t right + sin t up)``, i.e. at ``angle_deg`` (a line, so the sign is immaterial)."""
    t = math.radians(float(angle_deg))
    a = -math.sin(t) * np.asarray(right, dtype=np.float64) + math.cos(t) * np.asarray(up, dtype=np.float64)
    return a / np.linalg.norm(a)

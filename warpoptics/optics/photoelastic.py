"""Photoelasticity: the stress-optic law of a glass (or polymer) plate under plane stress.

A transparent isotropic plate under a plane stress state (sigma_xx, sigma_yy, tau_xy in its
plane, light along its normal) becomes a linear retarder at each point (Brewster 1816; the
stress-optic law, Frocht 1941, Photoelasticity vol. 1; Timoshenko & Goodier §9 for the
principal stresses):

- :func:`principal_stresses_2d`: the principal stresses sigma_1 >= sigma_2 and the direction
  of sigma_1 (Mohr's circle);
- :func:`stress_optic_retardation`: Delta = C d (sigma_1 - sigma_2), the retardation of the
  two waves vibrating along the principal directions, the slow one along sigma_1 for C > 0
  (C the stress-optic coefficient; 1 TPa^-1 = 1e-12 Pa^-1 = 1 brewster);
- :func:`photoelastic_jones`: the plate at a point as the ideal retarder of
  ``plate.wave_plate_jones`` with that retardation and slow direction (no Fresnel loss, which
  is the same for both waves of a nearly isotropic plate).

Units: stresses in MPa (N/mm^2), thickness in mm, C in TPa^-1, so that C d (sigma_1 - sigma_2)
is in nm.  Angles in radians from x toward y.  C is taken as independent of wavelength (the
data sheets give it at 589.3 nm; its dispersion is a few per cent over the visible).
"""

from __future__ import annotations

import numpy as np
import warp as wp

from ..device import device_function, elementwise
from ..errors import InputError
from .plate import wave_plate_jones

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "principal_stresses_2d",
    "stress_optic_retardation",
    "photoelastic_jones",
    # NumPy wrappers
    "principal_stresses",
    "stress_retardations",
    "photoelastic_plates",
]


@wp.func
def principal_stresses_2d(sxx: float, syy: float, txy: float):
    """(sigma_1, sigma_2, theta_1) of a plane stress state: sigma_1,2 = (sxx + syy) / 2 +-
    sqrt(((sxx - syy) / 2)^2 + txy^2), sigma_1 >= sigma_2, along the direction
    theta_1 = atan2(2 txy, sxx - syy) / 2 (radians from x toward y; 0 for an isotropic state)."""
    mean = 0.5 * (sxx + syy)
    half = 0.5 * (sxx - syy)
    r = wp.sqrt(half * half + txy * txy)
    theta = 0.0
    if r > 0.0:
        theta = 0.5 * wp.atan2(txy, half)
    return mean + r, mean - r, theta


@wp.func
def stress_optic_retardation(c_tpa: float, thickness_mm: float, sigma_1: float, sigma_2: float):
    """Delta = C d (sigma_1 - sigma_2) in nm (C in TPa^-1, d in mm, stresses in MPa): the
    stress-optic law (Brewster; Frocht, Photoelasticity vol. 1), slow wave along sigma_1 for C > 0."""
    return c_tpa * thickness_mm * (sigma_1 - sigma_2)


@wp.func
def photoelastic_jones(
    sxx: float, syy: float, txy: float, c_tpa: float, thickness_mm: float, wavelength: float
):
    """Jones matrix (frame x, y of the beam) of a stressed plate at one point: the ideal
    retarder (``plate.wave_plate_jones``) of retardation C d (sigma_1 - sigma_2), its slow
    direction along sigma_1 (along sigma_2 when C < 0: the retardation is then negative)."""
    s1, s2, theta = principal_stresses_2d(sxx, syy, txy)
    return wave_plate_jones(theta, stress_optic_retardation(c_tpa, thickness_mm, s1, s2), wavelength)


# ----------------------------------------------------------------------------------------------
# private element-wise kernels (offset first, see warpoptics.device)


@wp.kernel
def _principal_kernel(
    offset: int,
    sxx: wp.array(dtype=float),
    syy: wp.array(dtype=float),
    txy: wp.array(dtype=float),
    out_1: wp.array(dtype=float),
    out_2: wp.array(dtype=float),
    out_t: wp.array(dtype=float),
):
    i = wp.tid() + offset
    s1, s2, t = principal_stresses_2d(sxx[i], syy[i], txy[i])
    out_1[i] = s1
    out_2[i] = s2
    out_t[i] = t


@wp.kernel
def _retardation_kernel(
    offset: int,
    c: wp.array(dtype=float),
    d: wp.array(dtype=float),
    s1: wp.array(dtype=float),
    s2: wp.array(dtype=float),
    out: wp.array(dtype=float),
):
    i = wp.tid() + offset
    out[i] = stress_optic_retardation(c[i], d[i], s1[i], s2[i])


@wp.kernel
def _photoelastic_kernel(
    offset: int,
    sxx: wp.array(dtype=float),
    syy: wp.array(dtype=float),
    txy: wp.array(dtype=float),
    c: wp.array(dtype=float),
    d: wp.array(dtype=float),
    wavelength: wp.array(dtype=float),
    out_re: wp.array(dtype=wp.vec4f),
    out_im: wp.array(dtype=wp.vec4f),
):
    i = wp.tid() + offset
    j = photoelastic_jones(sxx[i], syy[i], txy[i], c[i], d[i], wavelength[i])
    out_re[i] = wp.vec4f(j.re[0, 0], j.re[0, 1], j.re[1, 0], j.re[1, 1])
    out_im[i] = wp.vec4f(j.im[0, 0], j.im[0, 1], j.im[1, 0], j.im[1, 1])


# ----------------------------------------------------------------------------------------------
# NumPy wrappers


def _finite(value, name: str) -> np.ndarray:
    a = np.asarray(value, dtype=np.float64)
    bad = ~np.isfinite(a)
    if np.any(bad):
        raise InputError("must be finite", field=name, value=a[bad].flat[0], allowed="finite numbers")
    return a


@device_function(principal_stresses_2d)
def principal_stresses(sxx_mpa, syy_mpa, txy_mpa, *, device=None):
    """(sigma_1, sigma_2, theta_1 in degrees) of :func:`principal_stresses_2d`."""
    s1, s2, t = elementwise(
        _principal_kernel,
        [
            (_finite(sxx_mpa, "sxx_mpa"), wp.float32),
            (_finite(syy_mpa, "syy_mpa"), wp.float32),
            (_finite(txy_mpa, "txy_mpa"), wp.float32),
        ],
        [wp.float32, wp.float32, wp.float32],
        device=device,
    )
    return s1.astype(np.float64), s2.astype(np.float64), np.degrees(t.astype(np.float64))


@device_function(stress_optic_retardation)
def stress_retardations(c_tpa, thickness_mm, sigma_1_mpa, sigma_2_mpa, *, device=None) -> np.ndarray:
    """Retardation C d (sigma_1 - sigma_2) in nm of :func:`stress_optic_retardation`."""
    (out,) = elementwise(
        _retardation_kernel,
        [
            (_finite(c_tpa, "c_tpa"), wp.float32),
            (_finite(thickness_mm, "thickness_mm"), wp.float32),
            (_finite(sigma_1_mpa, "sigma_1_mpa"), wp.float32),
            (_finite(sigma_2_mpa, "sigma_2_mpa"), wp.float32),
        ],
        [wp.float32],
        device=device,
    )
    return out.astype(np.float64)


@device_function(photoelastic_jones)
def photoelastic_plates(sxx_mpa, syy_mpa, txy_mpa, c_tpa, thickness_mm, wavelength_nm, *, device=None):
    """Jones matrices (..., 2, 2) complex of :func:`photoelastic_jones` (frame x, y)."""
    lam = _finite(wavelength_nm, "wavelength_nm")
    if np.any(lam <= 0):
        raise InputError("must be > 0", field="wavelength_nm", value=float(lam.min()), allowed="> 0")
    re, im = elementwise(
        _photoelastic_kernel,
        [
            (_finite(sxx_mpa, "sxx_mpa"), wp.float32),
            (_finite(syy_mpa, "syy_mpa"), wp.float32),
            (_finite(txy_mpa, "txy_mpa"), wp.float32),
            (_finite(c_tpa, "c_tpa"), wp.float32),
            (_finite(thickness_mm, "thickness_mm"), wp.float32),
            (lam, wp.float32),
        ],
        [wp.vec4f, wp.vec4f],
        device=device,
    )
    j = re.astype(np.float64) + 1j * im.astype(np.float64)
    return j.reshape(*j.shape[:-1], 2, 2)

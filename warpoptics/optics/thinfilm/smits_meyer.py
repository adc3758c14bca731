"""The Smits & Meyer 1990 thin-film model: two-beam interference of a single film with
and without the phase change (eq. 7, 8), the optical-thickness rules (eq. 10, 11, 14) and the
Anderson–Richards multilayer iridescence (eq. 9), as ``@wp.func``s with NumPy wrappers.

References
----------
* B. E. Smits and G. W. Meyer, "Newton's colors: simulating interference phenomena in
  realistic image synthesis", Eurographics Workshop on Photosimulation, Realism and Physics
  in Computer Graphics, 1990, eq. 5–14.
* T. F. Anderson and A. G. Richards, J. Appl. Phys. 13, 748 (1942) (eq. 9, 10, 14 of Smits & Meyer).
"""

from __future__ import annotations

import numpy as np
import warp as wp

from ...device import device_function, elementwise
from ...errors import InputError
from ...validate import finite_array
from .inputs import cos_angle, positive

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "smits_meyer_film_reflectance",
    "smits_meyer_optical_thickness_wp",
    "smits_meyer_effective_thickness_wp",
    "smits_meyer_morpho_thickness_wp",
    "smits_meyer_multilayer_intensity",
    "smits_meyer_film",
    "smits_meyer_optical_thickness",
    "smits_meyer_effective_thickness",
    "smits_meyer_morpho_thickness",
    "smits_meyer_multilayer",
]


@wp.func
def smits_meyer_film_reflectance(
    wavelength_nm: float, optical_thickness_nm: float, phase_change: float, K: float
):
    """Two-beam reflectance of a single film, Smits & Meyer 1990 eq. 7 (phase change) and 8.

    rho = [K cos(2 pi t' / lambda + phase_change * pi / 2)]^2 with t' = t n (cos theta) the
    optical thickness of eq. 11, in nm; ``phase_change`` is 1 for a film between two media of
    lower index (soap film, eq. 7; rho -> 0 as t' -> 0) and 0 for a film with the higher index
    behind it (eq. 8).  K is the constant "that measures how much light is reflected at each
    boundary": two equal beams of amplitude r give K = 2 |r|.
    """
    a = K * wp.cos(2.0 * wp.pi * optical_thickness_nm / wavelength_nm + phase_change * (0.5 * wp.pi))
    return a * a


@wp.func
def smits_meyer_optical_thickness_wp(thickness_nm: float, n: float, cos_theta: float):
    """Optical thickness t' = t n cos(theta), Smits & Meyer 1990 eq. 11 (nm)."""
    return thickness_nm * n * cos_theta


@wp.func
def smits_meyer_effective_thickness_wp(thickness_nm: float, n: float, sin_theta: float):
    """Effective thickness t_theta = t (n^2 - sin^2 theta)^(1/2), Smits & Meyer 1990 eq. 10 (nm)."""
    return thickness_nm * wp.sqrt(wp.max(n * n - sin_theta * sin_theta, 0.0))


@wp.func
def smits_meyer_morpho_thickness_wp(d1_nm: float, d2_nm: float, n: float, cos_theta: float):
    """Morpho period t_theta = d1 cos(theta) + d2 (n^2 - sin^2 theta)^(1/2), eq. 14 (nm).

    d1 is the air spacing between the mullions, d2 their thickness, n their index.
    """
    s2 = wp.max(1.0 - cos_theta * cos_theta, 0.0)
    return d1_nm * cos_theta + d2_nm * wp.sqrt(wp.max(n * n - s2, 0.0))


@wp.func
def smits_meyer_multilayer_intensity(
    wavelength_nm: float, effective_thickness_nm: float, layers: int, A0: float
):
    """Multilayer iridescence, Smits & Meyer 1990 eq. 9 (after Anderson & Richards 1942).

    I = 1/2 A0 [sin(2 pi (l + 1) t / lambda) / sin(2 pi t / lambda)]^2 with l the number of
    layers and t the effective thickness of eq. 10 or 14.  At sin(2 pi t / lambda) = 0 the
    ratio takes its limit (l + 1) cos((l + 1) x) / cos(x).  Peaks of height A0 (l + 1)^2 / 2
    sit at lambda = 2 t / m.
    """
    x = 2.0 * wp.pi * effective_thickness_nm / wavelength_nm
    m = float(layers + 1)
    s = wp.sin(x)
    ratio = wp.float32(0.0)
    if wp.abs(s) < 1.0e-4:
        ratio = m * wp.cos(m * x) / wp.cos(x)
    else:
        ratio = wp.sin(m * x) / s
    return 0.5 * A0 * ratio * ratio


# ---------------------------------------------------------------------------------------------
# Kernels (element-wise, launched through device.elementwise)
# ---------------------------------------------------------------------------------------------


@wp.kernel
def _sm_film_kernel(
    offset: int,
    wavelength_nm: wp.array(dtype=float),
    optical_thickness_nm: wp.array(dtype=float),
    phase_change: wp.array(dtype=float),
    K: wp.array(dtype=float),
    out: wp.array(dtype=float),
):
    i = wp.tid() + offset
    out[i] = smits_meyer_film_reflectance(wavelength_nm[i], optical_thickness_nm[i], phase_change[i], K[i])


@wp.kernel
def _sm_thickness_kernel(
    offset: int,
    d1_nm: wp.array(dtype=float),
    d2_nm: wp.array(dtype=float),
    n: wp.array(dtype=float),
    cos_theta: wp.array(dtype=float),
    rule: int,
    out: wp.array(dtype=float),
):
    i = wp.tid() + offset
    c = cos_theta[i]
    if rule == 11:
        out[i] = smits_meyer_optical_thickness_wp(d1_nm[i], n[i], c)
    elif rule == 10:
        out[i] = smits_meyer_effective_thickness_wp(d1_nm[i], n[i], wp.sqrt(wp.max(1.0 - c * c, 0.0)))
    else:
        out[i] = smits_meyer_morpho_thickness_wp(d1_nm[i], d2_nm[i], n[i], c)


@wp.kernel
def _sm_multilayer_kernel(
    offset: int,
    wavelength_nm: wp.array(dtype=float),
    effective_thickness_nm: wp.array(dtype=float),
    layers: wp.array(dtype=wp.int32),
    A0: wp.array(dtype=float),
    out: wp.array(dtype=float),
):
    i = wp.tid() + offset
    out[i] = smits_meyer_multilayer_intensity(wavelength_nm[i], effective_thickness_nm[i], layers[i], A0[i])


# ---------------------------------------------------------------------------------------------
# Python wrappers
# ---------------------------------------------------------------------------------------------


@device_function(smits_meyer_film_reflectance)
def smits_meyer_film(
    wavelength_nm, optical_thickness_nm, phase_change: bool = True, K=1.0, *, device=None
) -> np.ndarray:
    """Single-film two-beam reflectance, Smits & Meyer 1990 eq. 7 (``phase_change``) or eq. 8.

    ``optical_thickness_nm`` is t' = t n cos(theta) (eq. 11, :func:`smits_meyer_optical_thickness`).
    """
    wl = positive(wavelength_nm, "wavelength_nm")
    t = positive(optical_thickness_nm, "optical_thickness_nm", allow_zero=True)
    (out,) = elementwise(
        _sm_film_kernel,
        [
            (wl, wp.float32),
            (t, wp.float32),
            (np.asarray(phase_change, dtype=np.float32), wp.float32),
            (finite_array(K, field="K"), wp.float32),
        ],
        [wp.float32],
        device=device,
    )
    return out


def _thickness_rule(rule: int, d1, d2, n, angle, device, d1_name: str = "thickness_nm") -> np.ndarray:
    c = cos_angle(angle)
    (out,) = elementwise(
        _sm_thickness_kernel,
        [
            (positive(d1, d1_name, allow_zero=True), wp.float32),
            (positive(d2, "d2_nm", allow_zero=True), wp.float32),
            (positive(n, "n"), wp.float32),
            (c, wp.float32),
        ],
        [wp.float32],
        extra=(rule,),
        device=device,
    )
    return out


@device_function(smits_meyer_optical_thickness_wp)
def smits_meyer_optical_thickness(thickness_nm, n=1.0, angle=0.0, *, device=None) -> np.ndarray:
    """Optical thickness t' = t n cos(theta), Smits & Meyer 1990 eq. 11 (nm); ``angle`` in degrees.

    The paper applies it with the viewing angle; the exact two-beam phase uses the refraction
    angle in the film, t n cos(theta_t) = t (n^2 - sin^2 theta)^(1/2) (eq. 10).
    """
    return _thickness_rule(11, thickness_nm, 0.0, n, angle, device)


@device_function(smits_meyer_effective_thickness_wp)
def smits_meyer_effective_thickness(thickness_nm, n, angle=0.0, *, device=None) -> np.ndarray:
    """Effective thickness t (n^2 - sin^2 theta)^(1/2), Smits & Meyer 1990 eq. 10 (nm)."""
    return _thickness_rule(10, thickness_nm, 0.0, n, angle, device)


@device_function(smits_meyer_morpho_thickness_wp)
def smits_meyer_morpho_thickness(d1_nm, d2_nm, n, angle=0.0, *, device=None) -> np.ndarray:
    """Morpho period d1 cos(theta) + d2 (n^2 - sin^2 theta)^(1/2), Smits & Meyer 1990 eq. 14 (nm)."""
    return _thickness_rule(14, d1_nm, d2_nm, n, angle, device, "d1_nm")


@device_function(smits_meyer_multilayer_intensity)
def smits_meyer_multilayer(
    wavelength_nm, effective_thickness_nm, layers, A0=1.0, *, device=None
) -> np.ndarray:
    """Multilayer iridescence I(lambda), Smits & Meyer 1990 eq. 9 (Anderson & Richards 1942)."""
    wl = positive(wavelength_nm, "wavelength_nm")
    t = positive(effective_thickness_nm, "effective_thickness_nm", allow_zero=True)
    lay = np.asarray(layers)
    if not np.issubdtype(lay.dtype, np.integer) or np.any(lay < 1):
        raise InputError("layers must be a positive integer", field="layers", value=layers, allowed=">= 1")
    (out,) = elementwise(
        _sm_multilayer_kernel,
        [(wl, wp.float32), (t, wp.float32), (lay, wp.int32), (finite_array(A0, field="A0"), wp.float32)],
        [wp.float32],
        device=device,
    )
    return out

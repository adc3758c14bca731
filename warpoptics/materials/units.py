"""Absorption units: the extinction coefficient k, the absorption coefficient alpha and decadic
absorbance, as ``@wp.func``s with NumPy wrappers (a law of its own, below every material module).

- alpha (1/mm, base e) = 4 pi k / λ_mm (Weidlich & Wilkie 2009, eq. 3);
- decadic absorbance per cm A_10 (the chemist's absorbance of a 1 cm cell):
  alpha [1/mm] = ln(10) · A_10 / 10.

References
----------
- A. Weidlich, A. Wilkie, "Anomalous dispersion in predictive rendering", CGF 28(4), 2009, eq. 3–4.
"""

from __future__ import annotations

import numpy as np
import warp as wp

from .. import device as _device
from ..device import device_function
from ..errors import InputError

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "alpha_from_k_wp",
    "k_from_alpha_wp",
    "alpha_from_absorbance_per_cm_wp",
    "absorbance_per_cm_from_alpha_wp",
    "alpha_from_k",
    "k_from_alpha",
    "alpha_from_absorbance_per_cm",
    "absorbance_per_cm_from_alpha",
    "finite_array",
    "nonnegative_array",
    "wavelength_array",
]


@wp.func
def alpha_from_k_wp(k: float, wavelength_nm: float):
    """alpha (1/mm, base e) = 4 pi k / λ, λ in mm (Weidlich & Wilkie 2009, eq. 3)."""
    return 4.0 * wp.pi * k / (wavelength_nm * 1.0e-6)


@wp.func
def k_from_alpha_wp(alpha_per_mm: float, wavelength_nm: float):
    """k = alpha λ / (4 pi), alpha in 1/mm, λ in nm (Weidlich & Wilkie 2009, eq. 3)."""
    return alpha_per_mm * (wavelength_nm * 1.0e-6) / (4.0 * wp.pi)


@wp.func
def alpha_from_absorbance_per_cm_wp(absorbance_per_cm: float):
    """alpha (1/mm, base e) = ln(10) A / 10 from a decadic absorbance A per cm."""
    return absorbance_per_cm * wp.log(10.0) / 10.0


@wp.func
def absorbance_per_cm_from_alpha_wp(alpha_per_mm: float):
    """Decadic absorbance per cm = 10 alpha / ln(10) from alpha (1/mm, base e)."""
    return alpha_per_mm * 10.0 / wp.log(10.0)


@wp.kernel
def _unit_kernel(
    offset: int,
    value: wp.array(dtype=wp.float32),
    wavelength_nm: wp.array(dtype=wp.float32),
    mode: int,
    out: wp.array(dtype=wp.float32),
):
    i = wp.tid() + offset
    v = value[i]
    if mode == 0:
        out[i] = alpha_from_k_wp(v, wavelength_nm[i])
    elif mode == 1:
        out[i] = k_from_alpha_wp(v, wavelength_nm[i])
    elif mode == 2:
        out[i] = alpha_from_absorbance_per_cm_wp(v)
    else:
        out[i] = absorbance_per_cm_from_alpha_wp(v)


def finite_array(name: str, value) -> np.ndarray:
    """``value`` as float64, or an InputError naming ``name`` if any element is not finite."""
    a = np.asarray(value, dtype=np.float64)
    if not np.all(np.isfinite(a)):
        # the first offending element, not the array: one line at any size
        raise InputError("must be finite", field=name, value=a[~np.isfinite(a)].flat[0].item())
    return a


def nonnegative_array(name: str, value) -> np.ndarray:
    """``value`` as float64, finite and >= 0 (an absorption), else an InputError naming ``name``."""
    a = finite_array(name, value)
    if np.any(a < 0):
        raise InputError(
            "must be >= 0 (negative absorption would amplify light)", field=name, value=float(a.min())
        )
    return a


def wavelength_array(value) -> np.ndarray:
    """``value`` as float64 wavelengths (nm), finite and > 0, else an InputError."""
    a = finite_array("wavelength_nm", value)
    if np.any(a <= 0):
        raise InputError("wavelength must be > 0 nm", field="wavelength_nm", value=float(a.min()))
    return a


def _convert(value, wavelength_nm, mode: int, device=None) -> np.ndarray:
    (out,) = _device.elementwise(
        _unit_kernel,
        [(value, wp.float32), (wavelength_nm, wp.float32)],
        [wp.float32],
        extra=(mode,),
        device=device,
    )
    return out


@device_function(alpha_from_k_wp)
def alpha_from_k(k, wavelength_nm, *, device=None) -> np.ndarray:
    """alpha (1/mm, base e) from the extinction coefficient k at λ (nm): 4 pi k / λ."""
    return _convert(nonnegative_array("k", k), wavelength_array(wavelength_nm), 0, device)


@device_function(k_from_alpha_wp)
def k_from_alpha(alpha_per_mm, wavelength_nm, *, device=None) -> np.ndarray:
    """Extinction coefficient k from alpha (1/mm, base e) at λ (nm): alpha λ / 4 pi."""
    return _convert(
        nonnegative_array("alpha_per_mm", alpha_per_mm), wavelength_array(wavelength_nm), 1, device
    )


@device_function(alpha_from_absorbance_per_cm_wp)
def alpha_from_absorbance_per_cm(absorbance_per_cm, *, device=None) -> np.ndarray:
    """alpha (1/mm, base e) from decadic absorbance per cm: ln(10) A / 10."""
    a = nonnegative_array("absorbance_per_cm", absorbance_per_cm)
    return _convert(a, np.ones_like(a), 2, device)


@device_function(absorbance_per_cm_from_alpha_wp)
def absorbance_per_cm_from_alpha(alpha_per_mm, *, device=None) -> np.ndarray:
    """Decadic absorbance per cm from alpha (1/mm, base e): 10 alpha / ln(10)."""
    a = nonnegative_array("alpha_per_mm", alpha_per_mm)
    return _convert(a, np.ones_like(a), 3, device)

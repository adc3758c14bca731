"""Procedural noise and thickness fields: Perlin turbulence (2-D and 3-D) and the thin-film
thickness profiles of Smits & Meyer 1990 (an oil drop on a rough surface, eq. 12–13; a soap
film thinning under gravity, §4.2), as ``@wp.func``s with NumPy wrappers.

References
----------
* K. Perlin, "An image synthesizer", SIGGRAPH 1985 (turbulence).
* B. E. Smits and G. W. Meyer, "Newton's colors: simulating interference phenomena in
  realistic image synthesis", 1990, eq. 12–13 and §4.2.
"""

from __future__ import annotations

import numpy as np
import warp as wp

from .device import device_function, elementwise
from .errors import InputError
from .validate import finite_array, number

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "turbulence",
    "turbulence_3d",
    "oil_slick_thickness_wp",
    "soap_film_thickness_wp",
    "oil_slick_thickness",
    "soap_film_thickness",
    "turbulence_field",
]


@wp.func
def turbulence(seed: int, x: float, y: float, octaves: int):
    """Perlin's turbulence, sum over octaves o of |noise(2^o p)| / 2^o (Perlin 1985).

    Self-similar, non-negative (about 0..1.5 for 6 octaves); one feature per unit of (x, y) at
    the lowest octave.  Used by Smits & Meyer 1990 eq. 13 and §4.2.
    """
    state = wp.rand_init(seed)
    total = wp.float32(0.0)  # a mutable loop variable, not a constant
    scale = wp.float32(1.0)  # a mutable loop variable, not a constant
    for _octave in range(octaves):
        total += wp.abs(wp.noise(state, wp.vec2f(x * scale, y * scale))) / scale
        scale *= 2.0
    return total


@wp.func
def turbulence_3d(seed: int, p: wp.vec3f, octaves: int):
    """Perlin's turbulence in 3-D, sum over octaves o of |noise(2^o p)| / 2^o (Perlin 1985);
    the 3-D form of :func:`turbulence` for closed surfaces (a bubble)."""
    state = wp.rand_init(seed)
    total = wp.float32(0.0)  # a mutable loop variable
    scale = wp.float32(1.0)  # a mutable loop variable
    for _octave in range(octaves):
        total += wp.abs(wp.noise(state, p * scale)) / scale
        scale *= 2.0
    return total


@wp.func
def oil_slick_thickness_wp(x: float, y: float, k1: float, k2: float, turb: float, max_thickness_nm: float):
    """Oil drop on a rough surface, Smits & Meyer 1990 eq. 13 (eq. 12 for k2 = 0), in nm.

    t = t_max exp(-k1 (x^2 + y^2 + k2 turb(x, y))); ``turb`` is :func:`turbulence` at (x, y).
    """
    return max_thickness_nm * wp.exp(-k1 * (x * x + y * y + k2 * turb))


@wp.func
def soap_film_thickness_wp(height: float, k2: float, turb: float, max_thickness_nm: float):
    """Soap film thinning under gravity, Smits & Meyer 1990 §4.2, in nm.

    ``height`` runs 0 (top) to 1 (bottom); the thickness is proportional to height plus
    turbulence: t = t_max (height + k2 turb), clamped at 0 (the black film at the top).
    """
    return max_thickness_nm * wp.max(height + k2 * turb, 0.0)


# ---------------------------------------------------------------------------------------------
# Kernels (element-wise, launched through device.elementwise)
# ---------------------------------------------------------------------------------------------


@wp.kernel
def _thickness_field_kernel(
    offset: int,
    x: wp.array(dtype=float),
    y: wp.array(dtype=float),
    which: int,
    k1: float,
    k2: float,
    max_thickness_nm: float,
    seed: int,
    octaves: int,
    turb_scale: float,
    out: wp.array(dtype=float),
):
    i = wp.tid() + offset
    turb = turbulence(seed, x[i] * turb_scale, y[i] * turb_scale, octaves)
    if which == 0:
        out[i] = oil_slick_thickness_wp(x[i], y[i], k1, k2, turb, max_thickness_nm)
    elif which == 1:
        out[i] = soap_film_thickness_wp(y[i], k2, turb, max_thickness_nm)
    else:
        out[i] = turb


# ---------------------------------------------------------------------------------------------
# Python wrappers
# ---------------------------------------------------------------------------------------------


def _real(v, name: str) -> float:
    # a finite real keyword argument (NumPy scalars accepted), else an InputError naming it
    try:
        f = float(v)
    except (TypeError, ValueError):
        raise InputError("must be a number", field=name, value=v) from None
    return float(number(f, field=name))


def _int(v, name: str, lo: int) -> int:
    if isinstance(v, bool) or not isinstance(v, int | np.integer) or v < lo:
        raise InputError(f"must be an integer >= {lo}", field=name, value=v)
    return int(v)


def _field(which: int, x, y, k1, k2, max_thickness_nm, seed, octaves, turb_scale, device, names):
    # ``names``: the wrapper's own names of (x, y, the noise frequency) for the error messages
    x_name, y_name, scale_name = names
    (out,) = elementwise(
        _thickness_field_kernel,
        [(finite_array(x, field=x_name), wp.float32), (finite_array(y, field=y_name), wp.float32)],
        [wp.float32],
        extra=(
            which,
            _real(k1, "k1"),
            _real(k2, "k2"),
            _real(max_thickness_nm, "max_thickness_nm"),
            _int(seed, "seed", -(2**31)),
            _int(octaves, "octaves", 0),
            _real(turb_scale, scale_name),
        ),
        device=device,
    )
    return out


@device_function(oil_slick_thickness_wp)
def oil_slick_thickness(
    x,
    y,
    *,
    k1: float = 3.0,
    k2: float = 0.3,
    max_thickness_nm: float = 1000.0,
    seed: int = 0,
    octaves: int = 6,
    turb_scale: float = 4.0,
    device=None,
) -> np.ndarray:
    """Oil drop thickness (nm) at (x, y), Smits & Meyer 1990 eq. 13 (k2 = 0: eq. 12).

    t = t_max exp(-k1 (x^2 + y^2 + k2 turb(s x, s y))) with Perlin turbulence of ``octaves``
    octaves at spatial frequency ``turb_scale`` = s.
    """
    return _field(
        0, x, y, k1, k2, max_thickness_nm, seed, octaves, turb_scale, device, ("x", "y", "turb_scale")
    )


@device_function(soap_film_thickness_wp)
def soap_film_thickness(
    x,
    height,
    *,
    k2: float = 0.15,
    max_thickness_nm: float = 1000.0,
    seed: int = 0,
    octaves: int = 5,
    turb_scale: float = 3.0,
    device=None,
) -> np.ndarray:
    """Soap film thickness (nm), Smits & Meyer 1990 §4.2: proportional to the normalised height
    (0 at the top, 1 at the bottom) plus ``k2`` times turbulence at (x, height)."""
    return _field(
        1,
        x,
        height,
        0.0,
        k2,
        max_thickness_nm,
        seed,
        octaves,
        turb_scale,
        device,
        ("x", "height", "turb_scale"),
    )


@device_function(turbulence)
def turbulence_field(x, y, *, seed: int = 0, octaves: int = 6, scale: float = 1.0, device=None) -> np.ndarray:
    """Perlin turbulence (:func:`turbulence`) at (scale x, scale y)."""
    return _field(2, x, y, 0.0, 0.0, 0.0, seed, octaves, scale, device, ("x", "y", "scale"))

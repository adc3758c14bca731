"""Spherical angles of a direction: the one place where a lat-long layout turns a direction into
(polar angle, azimuth), for the environment map lookup and its sampling table.

Why not ``wp.acos`` and ``wp.atan2``: on the CPU device they are libm's ``acosf`` and ``atan2f``,
~6 % of a dispersive render's samples in a ``perf`` profile (every lane of a spectral bundle
looks the map up at every leaf).  :func:`fast_atan2` is the Cephes ``atanf`` polynomial
(Moshier 1989, ``atanf.c``: relative error 1.9e-7 on |t| <= tan(pi/8)) after the usual octant
reduction, with the two divisions of that reduction merged into one.  The polar angle is
``atan2(sqrt(x^2 + y^2), z)`` rather than ``acos(z)``: accurate near the poles, where acos loses
half the digits of z, and independent of the length of ``d``.  Both agree with NumPy's float64
``arctan2``/``arccos`` to 3e-7 rad over the sphere (``tests/test_directions.py``), 2e-4 of a
texel of a 4k map.

References:
    Moshier, S. L. 1989. Methods and Programs for Mathematical Functions (Cephes), atanf.c.
"""

from __future__ import annotations

import numpy as np
import warp as wp

from ..device import device_function, elementwise

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = ["fast_atan2", "polar_azimuth", "polar_azimuths"]

_TAN_PI_8 = wp.constant(0.41421356237309503)
_PI_4 = wp.constant(0.7853981633974483)
_PI_2 = wp.constant(1.5707963267948966)
_PI = wp.constant(3.141592653589793)


@wp.func
def fast_atan2(y: float, x: float):
    """atan2(y, x) in (-pi, pi] (0 for (0, 0)), within ~2 ulp of float32 (module docstring)."""
    ax = wp.abs(x)
    ay = wp.abs(y)
    mx = wp.max(ax, ay)
    mn = wp.min(ax, ay)
    if mx == 0.0:
        return 0.0
    # atan(mn / mx) in [0, pi/4]; above tan(pi/8) as pi/4 + atan((mn - mx) / (mn + mx))
    t = float(0.0)
    base = float(0.0)
    if mn > _TAN_PI_8 * mx:
        t = (mn - mx) / (mn + mx)
        base = _PI_4
    else:
        t = mn / mx
    z = t * t
    poly = ((8.05374449538e-2 * z - 1.38776856032e-1) * z + 1.99777106478e-1) * z - 3.33329491539e-1
    r = base + poly * z * t + t
    if ay > ax:
        r = _PI_2 - r
    if x < 0.0:
        r = _PI - r
    if y < 0.0:
        r = -r
    return r


@wp.func
def polar_azimuth(d: wp.vec3f):
    """(theta, phi) of direction ``d`` (any length, z up): theta = acos(z / |d|) in [0, pi] from
    +z, phi = atan2(y, x) in (-pi, pi] from +x toward +y."""
    rho = wp.sqrt(d[0] * d[0] + d[1] * d[1])
    return fast_atan2(rho, d[2]), fast_atan2(d[1], d[0])


@wp.kernel
def _polar_azimuth_kernel(
    offset: int,
    d: wp.array(dtype=wp.vec3f),
    theta: wp.array(dtype=float),
    phi: wp.array(dtype=float),
):
    i = wp.tid() + offset
    t, p = polar_azimuth(d[i])
    theta[i] = t
    phi[i] = p


@device_function(polar_azimuth)
def polar_azimuths(directions, *, device=None) -> tuple[np.ndarray, np.ndarray]:
    """(theta, phi) arrays (radians, float64 of the float32 results) of :func:`polar_azimuth`
    for directions ``(..., 3)``."""
    theta, phi = elementwise(
        _polar_azimuth_kernel, [(directions, wp.vec3f)], [wp.float32, wp.float32], device=device
    )
    return theta.astype(np.float64), phi.astype(np.float64)

"""The GGX (Trowbridge–Reitz) microfacet distribution: D, Smith G1 and sampling of normals.

One place for the microfacet laws used by the glossy tables (``stages/surfaces.py``) and the rough
film surfaces (``stages/coated.py``).  ``alpha`` is the GGX width (Walter et al.'s alpha_g);
``cos`` arguments are cosines with the macro-surface normal.

References:
    Walter, B., Marschner, S., Li, H., Torrance, K. 2007. Microfacet models for refraction
        through rough surfaces. EGSR. eq. 33 (D), 34 (Smith G1), 35-36 (sampling D |m.n|).
    Duff, T. et al. 2017. Building an orthonormal basis, revisited. JCGT 6(1).
"""

from __future__ import annotations

import warp as wp

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = ["orthonormal_basis", "ggx_d", "ggx_g1", "ggx_sample_normal"]


@wp.func
def orthonormal_basis(n: wp.vec3f):
    """Two unit vectors completing unit ``n`` to an orthonormal frame (Duff et al. 2017,
    branchless)."""
    sign = float(1.0)
    if n[2] < 0.0:
        sign = -1.0
    a = -1.0 / (sign + n[2])
    b = n[0] * n[1] * a
    t = wp.vec3f(1.0 + sign * n[0] * n[0] * a, sign * b, -sign * n[0])
    bb = wp.vec3f(b, sign + n[1] * n[1] * a, -n[1])
    return t, bb


@wp.func
def ggx_d(cos_h: float, alpha: float):
    """GGX normal distribution D(h) (Walter et al. 2007 eq. 33), 1/sr; ``cos_h`` = n.h."""
    if cos_h <= 0.0:
        return 0.0
    a2 = alpha * alpha
    c2 = cos_h * cos_h
    den = c2 * (a2 - 1.0) + 1.0
    return a2 / (wp.pi * den * den)


@wp.func
def ggx_g1(cos_v: float, alpha: float):
    """Smith masking G1 of GGX (Walter et al. 2007 eq. 34) for a direction with n.v = cos_v:
    2 / (1 + sqrt(1 + alpha^2 tan^2)), written as 2 cos / (cos + sqrt(alpha^2 + (1 - alpha^2) cos^2))
    (no division by cos); 0 below the surface."""
    if cos_v <= 0.0:
        return 0.0
    a2 = alpha * alpha
    c2 = cos_v * cos_v
    return 2.0 * cos_v / (cos_v + wp.sqrt(a2 + (1.0 - a2) * c2))


@wp.func
def ggx_sample_normal(n: wp.vec3f, alpha: float, u1: float, u2: float):
    """A microfacet normal m drawn with density D(m) |m.n| about unit ``n`` (Walter et al. 2007
    eq. 35-36: tan^2 theta_m = alpha^2 u1 / (1 - u1), phi = 2 pi u2)."""
    tan2 = alpha * alpha * u1 / wp.max(1.0 - u1, 1.0e-7)
    cos_t = 1.0 / wp.sqrt(1.0 + tan2)
    sin_t = wp.sqrt(wp.max(1.0 - cos_t * cos_t, 0.0))
    phi = 2.0 * wp.pi * u2
    t, b = orthonormal_basis(n)
    return wp.normalize(t * (sin_t * wp.cos(phi)) + b * (sin_t * wp.sin(phi)) + n * cos_t)

"""Complex arithmetic for Warp kernels.

Warp has no complex type, so a complex number is a ``wp.vec2f`` (real, imaginary).  Addition,
subtraction and scaling by a real are the vector operations; everything else has an explicit
name here (operator overloads on custom types are looked up per module in Warp).

Conventions used throughout warpoptics:
- time dependence exp(-i omega t); a plane wave is exp(i (k.r - omega t));
- a complex refractive index is ``n + i k`` with k >= 0 for an absorbing medium, so the field
  decays as exp(-2 pi k z / lambda) and the intensity absorption coefficient is
  alpha = 4 pi k / lambda (Weidlich & Wilkie 2009, eq. 1);
- the normal component of a wave vector in a medium, ``N cos(theta)``, is taken on the branch
  with a non-negative imaginary part (a decaying or evanescent wave), and a non-negative real
  part when it is real (a wave travelling away from the interface).
"""

from __future__ import annotations

import warp as wp

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

complex_t = wp.vec2f

__all__ = [
    "complex_t",
    "cplx",
    "c_real",
    "c_mul",
    "c_div",
    "c_conj",
    "c_abs2",
    "c_abs",
    "c_sqrt",
    "c_exp",
    "c_exp_i",
    "c_inv",
    "c_normal_component",
]


@wp.func
def cplx(re: float, im: float):
    return wp.vec2f(re, im)


@wp.func
def c_real(re: float):
    return wp.vec2f(re, 0.0)


@wp.func
def c_mul(a: wp.vec2f, b: wp.vec2f):
    return wp.vec2f(a[0] * b[0] - a[1] * b[1], a[0] * b[1] + a[1] * b[0])


@wp.func
def c_conj(a: wp.vec2f):
    return wp.vec2f(a[0], -a[1])


@wp.func
def c_abs2(a: wp.vec2f):
    return a[0] * a[0] + a[1] * a[1]


@wp.func
def c_abs(a: wp.vec2f):
    # hypot-style evaluation avoids overflow/underflow of the squares
    x = wp.abs(a[0])
    y = wp.abs(a[1])
    m = wp.max(x, y)
    if m == 0.0:
        return 0.0
    xs = x / m
    ys = y / m
    return m * wp.sqrt(xs * xs + ys * ys)


@wp.func
def c_div(a: wp.vec2f, b: wp.vec2f):
    # Smith's algorithm: robust against overflow for large |b|
    if wp.abs(b[0]) >= wp.abs(b[1]):
        if b[0] == 0.0:
            return wp.vec2f(0.0, 0.0)
        r = b[1] / b[0]
        d = b[0] + b[1] * r
        return wp.vec2f((a[0] + a[1] * r) / d, (a[1] - a[0] * r) / d)
    r = b[0] / b[1]
    d = b[0] * r + b[1]
    return wp.vec2f((a[0] * r + a[1]) / d, (a[1] * r - a[0]) / d)


@wp.func
def c_inv(a: wp.vec2f):
    return c_div(wp.vec2f(1.0, 0.0), a)


@wp.func
def c_sqrt(a: wp.vec2f):
    """Principal square root (real part >= 0), branch cut on the negative real axis."""
    m = c_abs(a)
    re = wp.sqrt(wp.max(0.5 * (m + a[0]), 0.0))
    im = wp.sqrt(wp.max(0.5 * (m - a[0]), 0.0))
    if a[1] < 0.0:
        im = -im
    return wp.vec2f(re, im)


@wp.func
def c_exp(a: wp.vec2f):
    e = wp.exp(a[0])
    return wp.vec2f(e * wp.cos(a[1]), e * wp.sin(a[1]))


@wp.func
def c_exp_i(phase: float):
    """exp(i * phase) for a real phase."""
    return wp.vec2f(wp.cos(phase), wp.sin(phase))


@wp.func
def c_normal_component(n1: wp.vec2f, n2: wp.vec2f, cos_i: float):
    """N2 cos(theta_t) from Snell's law N1 sin(theta_i) = N2 sin(theta_t).

    Returns the product ``N2 * cos(theta_t)`` (the normal component of the transmitted wave
    vector in units of k0), on the physical branch: imaginary part >= 0 (decaying or
    evanescent), real part >= 0 when real.  ``cos_i`` is the real cosine of the incidence angle
    in medium 1 (clamped to [0, 1]).  If medium 1 absorbs, the propagating root (Re > 0) is kept
    wherever the wave mostly propagates (see the branch rule in the code).
    """
    c = wp.clamp(cos_i, 0.0, 1.0)
    s2 = wp.max(1.0 - c * c, 0.0)
    # (N2 cos t)^2 = N2^2 - N1^2 sin^2 i
    n1sq = c_mul(n1, n1)
    n2sq = c_mul(n2, n2)
    q = c_sqrt(n2sq - n1sq * s2)
    # Branch: a wave that mostly propagates (|Re q| > |Im q|) travels away from the interface,
    # Re q > 0; a mostly evanescent one decays, Im q >= 0.  For a lossless medium 1 both rules
    # agree (q^2 has Im >= 0).  With an absorbing medium 1 the incident wave is inhomogeneous and
    # q^2 can have a small negative imaginary part: "Im >= 0" alone would then pick the backward
    # wave and |r| >> 1; the propagating rule keeps the forward one.
    if wp.abs(q[0]) > wp.abs(q[1]):
        if q[0] < 0.0:
            q = -q
    elif q[1] < 0.0 or (q[1] == 0.0 and q[0] < 0.0):
        q = -q
    return q


# ---------------------------------------------------------------------------------------------
# Double-precision overloads (``wp.vec2d``).  Warp resolves an overloaded ``@wp.func`` by the
# argument types, so kernels call the same names on ``wp.vec2f`` or ``wp.vec2d``.  The thin-film
# stacks (``optics/thinfilm.py``) run in float64: products of many layer matrices and phases of
# thick films lose too many float32 digits for the 1e-6 agreement with ``tmm``.
# ---------------------------------------------------------------------------------------------


@wp.func
def cplx(re: wp.float64, im: wp.float64):  # noqa: F811 (overload)
    return wp.vec2d(re, im)


@wp.func
def c_real(re: wp.float64):  # noqa: F811 (overload)
    return wp.vec2d(re, wp.float64(0.0))


@wp.func
def c_mul(a: wp.vec2d, b: wp.vec2d):  # noqa: F811 (overload)
    return wp.vec2d(a[0] * b[0] - a[1] * b[1], a[0] * b[1] + a[1] * b[0])


@wp.func
def c_conj(a: wp.vec2d):  # noqa: F811 (overload)
    return wp.vec2d(a[0], -a[1])


@wp.func
def c_abs2(a: wp.vec2d):  # noqa: F811 (overload)
    return a[0] * a[0] + a[1] * a[1]


@wp.func
def c_abs(a: wp.vec2d):  # noqa: F811 (overload)
    x = wp.abs(a[0])
    y = wp.abs(a[1])
    m = wp.max(x, y)
    if m == wp.float64(0.0):
        return wp.float64(0.0)
    xs = x / m
    ys = y / m
    return m * wp.sqrt(xs * xs + ys * ys)


@wp.func
def c_div(a: wp.vec2d, b: wp.vec2d):  # noqa: F811 (overload)
    zero = wp.float64(0.0)
    if wp.abs(b[0]) >= wp.abs(b[1]):
        if b[0] == zero:
            return wp.vec2d(zero, zero)
        r = b[1] / b[0]
        d = b[0] + b[1] * r
        return wp.vec2d((a[0] + a[1] * r) / d, (a[1] - a[0] * r) / d)
    r = b[0] / b[1]
    d = b[0] * r + b[1]
    return wp.vec2d((a[0] * r + a[1]) / d, (a[1] * r - a[0]) / d)


@wp.func
def c_inv(a: wp.vec2d):  # noqa: F811 (overload)
    return c_div(wp.vec2d(wp.float64(1.0), wp.float64(0.0)), a)


@wp.func
def c_sqrt(a: wp.vec2d):  # noqa: F811 (overload)
    """Principal square root (real part >= 0), branch cut on the negative real axis."""
    zero = wp.float64(0.0)
    half = wp.float64(0.5)
    m = c_abs(a)
    re = wp.sqrt(wp.max(half * (m + a[0]), zero))
    im = wp.sqrt(wp.max(half * (m - a[0]), zero))
    if a[1] < zero:
        im = -im
    return wp.vec2d(re, im)


@wp.func
def c_exp(a: wp.vec2d):  # noqa: F811 (overload)
    e = wp.exp(a[0])
    return wp.vec2d(e * wp.cos(a[1]), e * wp.sin(a[1]))


@wp.func
def c_exp_i(phase: wp.float64):  # noqa: F811 (overload)
    """exp(i * phase) for a real phase."""
    return wp.vec2d(wp.cos(phase), wp.sin(phase))


@wp.func
def c_normal_component(n1: wp.vec2d, n2: wp.vec2d, cos_i: wp.float64):  # noqa: F811 (overload)
    """N2 cos(theta_t) in double precision; same branch rules as the float32 version."""
    zero = wp.float64(0.0)
    one = wp.float64(1.0)
    c = wp.clamp(cos_i, zero, one)
    s2 = wp.max(one - c * c, zero)
    n1sq = c_mul(n1, n1)
    n2sq = c_mul(n2, n2)
    q = c_sqrt(n2sq - n1sq * s2)
    if wp.abs(q[0]) > wp.abs(q[1]):
        if q[0] < zero:
            q = -q
    elif q[1] < zero or (q[1] == zero and q[0] < zero):
        q = -q
    return q

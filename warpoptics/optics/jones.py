"""Jones and coherency matrices, polarization frames and Stokes vectors for Warp kernels.

A polarized ray carries a 2x2 complex matrix relative to an explicit basis: a unit vector ``x``
perpendicular to the ray direction ``d`` and ``y = d x x`` (so that ``(x, y, d)`` is
right-handed).  A field ``E = Ex x + Ey y`` is the column ``(Ex, Ey)``; a *Jones* (modifier)
matrix maps such columns, and a *coherency* matrix ``J = <E E^dagger>`` (Wolf 1959) is Hermitian
positive semi-definite with ``Jxx + Jyy`` the intensity.  Both are stored as :class:`Jones`, a
struct of two ``wp.mat22`` (real and imaginary parts); the operations have explicit names
(``jones_mul``...) because Warp looks operator overloads up per module.

Conventions (docs/conventions.md, "Polarization and Stokes vectors"):

- time dependence ``exp(-i omega t)``;
- Stokes vector ``S0 = Jxx + Jyy``, ``S1 = Jxx - Jyy``, ``S2 = 2 Re Jxy``, ``S3 = 2 Im Jxy``
  with ``Jxy = <Ex Ey*>``.  With ``exp(-i omega t)`` the field ``(1, -i)/sqrt(2)`` has
  ``S3 = +1``: its real field ``(cos wt, -sin wt)`` turns *clockwise* in the (x, y) plane seen
  by an observer facing the oncoming wave, i.e. ``S3 > 0`` is right-handed circular
  polarization in the optics (Born & Wolf) naming, ``S3 < 0`` left-handed (tested in
  ``tests/test_jones.py``);
- the frame rotation of Guy & Soler 2004 §4.2, ``R_theta = [[cos, sin], [-sin, cos]]``, gives the
  components of a field in a frame whose x axis is the old one turned by ``+theta`` about the ray
  direction (counter-clockwise seen from the tip of ``d``).

References:
    Guy, S., Soler, C. 2004. Graphics Gems Revisited. ACM TOG 23(3), §4.2, eq. 12.
    Wolf, E. 1959. Coherence properties of partially polarized electromagnetic radiation.
    Born, M., Wolf, E. 1999. Principles of Optics, 7th ed., §1.4.2 (handedness), §10.8.
"""

from __future__ import annotations

import numpy as np
import warp as wp

from ..device import device_function, elementwise
from ..errors import InputError

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "Jones",
    "jones",
    "jones_real",
    "jones_diag",
    "jones_identity",
    "jones_zero",
    "jones_entry",
    "jones_add",
    "jones_scale",
    "jones_mul",
    "jones_adjoint",
    "jones_trace",
    "coherency_transform",
    "coherency_unpolarized",
    "rotation_matrix",
    "perpendicular",
    "frame_y",
    "s_vector",
    "frame_change",
    "transport_basis",
    "stokes_from_coherency",
    "coherency_from_stokes_vec",
    "degree_of_polarization",
    # NumPy wrappers
    "jones_product",
    "coherency_apply",
    "stokes",
    "coherency_from_stokes",
    "dop",
    "frame_change_matrix",
    "s_vectors",
    "transport_bases",
]


@wp.struct
class Jones:
    """A 2x2 complex matrix: ``re + i im``.  Used for Jones (modifier) and coherency matrices."""

    re: wp.mat22
    im: wp.mat22


# ----------------------------------------------------------------------------------------------
# construction and algebra


@wp.func
def jones(m00: wp.vec2f, m01: wp.vec2f, m10: wp.vec2f, m11: wp.vec2f):
    """The matrix [[m00, m01], [m10, m11]] from four complex entries (wp.vec2f = re, im)."""
    j = Jones()
    j.re = wp.mat22(m00[0], m01[0], m10[0], m11[0])
    j.im = wp.mat22(m00[1], m01[1], m10[1], m11[1])
    return j


@wp.func
def jones_real(m: wp.mat22):
    """A real 2x2 matrix as a Jones matrix (rotations, frame changes)."""
    j = Jones()
    j.re = m
    j.im = wp.mat22(0.0)
    return j


@wp.func
def jones_diag(a: wp.vec2f, b: wp.vec2f):
    """diag(a, b) for complex a, b (Fresnel matrices in their s/p or o/e frames)."""
    j = Jones()
    j.re = wp.mat22(a[0], 0.0, 0.0, b[0])
    j.im = wp.mat22(a[1], 0.0, 0.0, b[1])
    return j


@wp.func
def jones_identity():
    return jones_real(wp.identity(n=2, dtype=float))


@wp.func
def jones_zero():
    j = Jones()
    j.re = wp.mat22(0.0)
    j.im = wp.mat22(0.0)
    return j


@wp.func
def jones_entry(a: Jones, i: int, k: int):
    """Entry (i, k) as a complex number (wp.vec2f)."""
    return wp.vec2f(a.re[i, k], a.im[i, k])


@wp.func
def jones_add(a: Jones, b: Jones):
    j = Jones()
    j.re = a.re + b.re
    j.im = a.im + b.im
    return j


@wp.func
def jones_scale(a: Jones, s: float):
    """Multiply by a real scalar."""
    j = Jones()
    j.re = a.re * s
    j.im = a.im * s
    return j


@wp.func
def jones_mul(a: Jones, b: Jones):
    """Complex matrix product a @ b."""
    j = Jones()
    j.re = a.re * b.re - a.im * b.im
    j.im = a.re * b.im + a.im * b.re
    return j


@wp.func
def jones_adjoint(a: Jones):
    """Conjugate transpose a^dagger."""
    j = Jones()
    j.re = wp.transpose(a.re)
    j.im = -wp.transpose(a.im)
    return j


@wp.func
def jones_trace(a: Jones):
    return wp.vec2f(a.re[0, 0] + a.re[1, 1], a.im[0, 0] + a.im[1, 1])


@wp.func
def coherency_transform(m: Jones, j: Jones):
    """J' = M J M^dagger (Guy & Soler 2004, §4.2 and eq. 12).

    Keeps J Hermitian; the result is symmetrised so that float32 rounding cannot break the
    Hermitian property (re symmetric, im antisymmetric, real diagonal).
    """
    r = jones_mul(jones_mul(m, j), jones_adjoint(m))
    out = Jones()
    out.re = 0.5 * (r.re + wp.transpose(r.re))
    out.im = 0.5 * (r.im - wp.transpose(r.im))
    return out


@wp.func
def coherency_unpolarized(intensity: float):
    """Coherency matrix of unpolarized light, I/2 * identity (Guy & Soler 2004, §4.2)."""
    return jones_real(wp.mat22(0.5 * intensity, 0.0, 0.0, 0.5 * intensity))


@wp.func
def rotation_matrix(theta: float):
    """R_theta = [[cos, sin], [-sin, cos]] (Guy & Soler 2004, §4.2), theta in radians."""
    c = wp.cos(theta)
    s = wp.sin(theta)
    return jones_real(wp.mat22(c, s, -s, c))


# ----------------------------------------------------------------------------------------------
# polarization frames


@wp.func
def perpendicular(d: wp.vec3):
    """A deterministic unit vector perpendicular to unit ``d`` (cross product with the
    coordinate axis least aligned with ``d``).  It depends on ``d`` only through ``|d_k|`` and
    the sign of ``d``: perpendicular(-d) = -perpendicular(d)."""
    ax = wp.abs(d[0])
    ay = wp.abs(d[1])
    az = wp.abs(d[2])
    e = wp.vec3(1.0, 0.0, 0.0)
    if ay <= ax and ay <= az:
        e = wp.vec3(0.0, 1.0, 0.0)
    elif az < ax and az < ay:
        e = wp.vec3(0.0, 0.0, 1.0)
    return wp.normalize(wp.cross(e, d))


@wp.func
def frame_y(d: wp.vec3, x: wp.vec3):
    """The second basis vector y = d x x of the right-handed frame (x, y, d)."""
    return wp.cross(d, x)


@wp.func
def s_vector(d: wp.vec3, normal: wp.vec3):
    """Unit s-direction (perpendicular to the plane of incidence) for a ray ``d`` hitting a
    surface of unit ``normal``: normalize(normal x d).  The same vector serves the incident,
    reflected and transmitted waves.  At normal incidence (plane of incidence undefined) it
    falls back to ``perpendicular(normal)``, which does not depend on the sign of ``d``."""
    s = wp.cross(normal, d)
    l2 = wp.dot(s, s)
    if l2 < 1.0e-12:
        return perpendicular(normal)
    return s / wp.sqrt(l2)


@wp.func
def frame_change(d: wp.vec3, x_from: wp.vec3, x_to: wp.vec3):
    """Real 2x2 matrix B giving a field's components in the frame (x_to, d x x_to) from its
    components in the frame (x_from, d x x_from), both perpendicular to the same direction d:
    B[i, k] = to_i . from_k.  A pure rotation R_theta (det = +1) when both x are unit vectors
    perpendicular to d."""
    yf = wp.cross(d, x_from)
    yt = wp.cross(d, x_to)
    return wp.mat22(
        wp.dot(x_to, x_from), wp.dot(x_to, yf),
        wp.dot(yt, x_from), wp.dot(yt, yf),
    )  # fmt: skip


@wp.func
def transport_basis(x: wp.vec3, d_old: wp.vec3, d_new: wp.vec3):
    """Carry the basis vector ``x`` (perpendicular to ``d_old``) to a ray turned to ``d_new``
    by the smallest rotation that takes d_old to d_new (Rodrigues).  The Jones matrix of the
    ray is unchanged by this transport.  For opposite directions every half-turn about an axis
    perpendicular to d_old is minimal; we turn about ``x`` itself, so x is kept (and y = d x x
    flips with d)."""
    c = wp.dot(d_old, d_new)
    axis = wp.cross(d_old, d_new)
    s2 = wp.dot(axis, axis)
    if s2 < 1.0e-14:
        # parallel: nothing to do; antiparallel: half-turn about x, which keeps x
        return x
    # Rodrigues with k = axis/|axis|, sin = |axis|, cos = c
    k = axis / wp.sqrt(s2)
    sn = wp.sqrt(s2)
    r = x * c + wp.cross(k, x) * sn + k * (wp.dot(k, x) * (1.0 - c))
    # remove rounding drift: re-orthogonalise against d_new
    r = r - d_new * wp.dot(r, d_new)
    return wp.normalize(r)


# ----------------------------------------------------------------------------------------------
# Stokes vectors


@wp.func
def stokes_from_coherency(j: Jones):
    """Stokes vector (S0, S1, S2, S3) of a coherency matrix:
    S0 = Jxx + Jyy, S1 = Jxx - Jyy, S2 = 2 Re Jxy, S3 = 2 Im Jxy (S3 > 0: right-handed
    circular in Born & Wolf's naming, with exp(-i omega t) and a right-handed (x, y, d) frame)."""
    return wp.vec4(
        j.re[0, 0] + j.re[1, 1],
        j.re[0, 0] - j.re[1, 1],
        2.0 * j.re[0, 1],
        2.0 * j.im[0, 1],
    )


@wp.func
def coherency_from_stokes_vec(s: wp.vec4):
    """Inverse of stokes_from_coherency: Jxx = (S0+S1)/2, Jyy = (S0-S1)/2, Jxy = (S2 + i S3)/2."""
    j = Jones()
    j.re = wp.mat22(0.5 * (s[0] + s[1]), 0.5 * s[2], 0.5 * s[2], 0.5 * (s[0] - s[1]))
    j.im = wp.mat22(0.0, 0.5 * s[3], -0.5 * s[3], 0.0)
    return j


@wp.func
def degree_of_polarization(j: Jones):
    """sqrt(S1^2 + S2^2 + S3^2) / S0, clamped to [0, 1]; 0 for zero intensity."""
    s = stokes_from_coherency(j)
    if s[0] <= 0.0:
        return 0.0
    p = wp.sqrt(s[1] * s[1] + s[2] * s[2] + s[3] * s[3]) / s[0]
    return wp.min(p, 1.0)


# ----------------------------------------------------------------------------------------------
# private element-wise kernels (offset first, see warpoptics.device)


@wp.func
def _load(re: wp.vec4, im: wp.vec4):
    j = Jones()
    j.re = wp.mat22(re[0], re[1], re[2], re[3])
    j.im = wp.mat22(im[0], im[1], im[2], im[3])
    return j


@wp.func
def _store_re(j: Jones):
    return wp.vec4(j.re[0, 0], j.re[0, 1], j.re[1, 0], j.re[1, 1])


@wp.func
def _store_im(j: Jones):
    return wp.vec4(j.im[0, 0], j.im[0, 1], j.im[1, 0], j.im[1, 1])


@wp.kernel
def _jones_mul_kernel(
    offset: int,
    a_re: wp.array(dtype=wp.vec4),
    a_im: wp.array(dtype=wp.vec4),
    b_re: wp.array(dtype=wp.vec4),
    b_im: wp.array(dtype=wp.vec4),
    out_re: wp.array(dtype=wp.vec4),
    out_im: wp.array(dtype=wp.vec4),
):
    i = wp.tid() + offset
    r = jones_mul(_load(a_re[i], a_im[i]), _load(b_re[i], b_im[i]))
    out_re[i] = _store_re(r)
    out_im[i] = _store_im(r)


@wp.kernel
def _coherency_transform_kernel(
    offset: int,
    m_re: wp.array(dtype=wp.vec4),
    m_im: wp.array(dtype=wp.vec4),
    j_re: wp.array(dtype=wp.vec4),
    j_im: wp.array(dtype=wp.vec4),
    out_re: wp.array(dtype=wp.vec4),
    out_im: wp.array(dtype=wp.vec4),
):
    i = wp.tid() + offset
    r = coherency_transform(_load(m_re[i], m_im[i]), _load(j_re[i], j_im[i]))
    out_re[i] = _store_re(r)
    out_im[i] = _store_im(r)


@wp.kernel
def _stokes_kernel(
    offset: int,
    j_re: wp.array(dtype=wp.vec4),
    j_im: wp.array(dtype=wp.vec4),
    out_s: wp.array(dtype=wp.vec4),
    out_dop: wp.array(dtype=float),
):
    i = wp.tid() + offset
    j = _load(j_re[i], j_im[i])
    out_s[i] = stokes_from_coherency(j)
    out_dop[i] = degree_of_polarization(j)


@wp.kernel
def _from_stokes_kernel(
    offset: int,
    s: wp.array(dtype=wp.vec4),
    out_re: wp.array(dtype=wp.vec4),
    out_im: wp.array(dtype=wp.vec4),
):
    i = wp.tid() + offset
    j = coherency_from_stokes_vec(s[i])
    out_re[i] = _store_re(j)
    out_im[i] = _store_im(j)


@wp.kernel
def _frame_kernel(
    offset: int,
    d: wp.array(dtype=wp.vec3),
    a: wp.array(dtype=wp.vec3),
    b: wp.array(dtype=wp.vec3),
    out_change: wp.array(dtype=wp.vec4),
    out_s: wp.array(dtype=wp.vec3),
    out_transport: wp.array(dtype=wp.vec3),
):
    # one kernel for the three frame helpers: frame_change(d, a, b), s_vector(d, a) and
    # transport_basis(a, d, b); each wrapper reads the output it needs
    i = wp.tid() + offset
    m = frame_change(d[i], a[i], b[i])
    out_change[i] = wp.vec4(m[0, 0], m[0, 1], m[1, 0], m[1, 1])
    out_s[i] = s_vector(d[i], a[i])
    out_transport[i] = transport_basis(a[i], d[i], b[i])


# ----------------------------------------------------------------------------------------------
# NumPy wrappers


def _split(m, name: str) -> tuple[np.ndarray, np.ndarray]:
    m = _finite(m, name)
    if m.shape[-2:] != (2, 2):
        raise ValueError(f"expected (..., 2, 2) matrices, got shape {m.shape}")
    flat = m.reshape(*m.shape[:-2], 4)
    return np.real(flat), np.imag(flat)


def _finite(value, name: str) -> np.ndarray:
    """``value`` as an array, or an InputError naming the argument and its first NaN/Inf."""
    a = np.asarray(value)
    bad = ~np.isfinite(a)
    if np.any(bad):
        raise InputError("must be finite", field=name, value=a[bad].flat[0], allowed="finite numbers")
    return a


def _join(re: np.ndarray, im: np.ndarray) -> np.ndarray:
    out = re.astype(np.float64) + 1j * im.astype(np.float64)
    return out.reshape(*out.shape[:-1], 2, 2)


@device_function(jones_mul)
def jones_product(a, b, *, device=None) -> np.ndarray:
    """a @ b for (..., 2, 2) complex arrays, through ``jones_mul`` (float32)."""
    ar, ai = _split(a, "a")
    br, bi = _split(b, "b")
    re, im = elementwise(
        _jones_mul_kernel,
        [(ar, wp.vec4), (ai, wp.vec4), (br, wp.vec4), (bi, wp.vec4)],
        [wp.vec4, wp.vec4],
        device=device,
    )
    return _join(re, im)


@device_function(coherency_transform)
def coherency_apply(m, j, *, device=None) -> np.ndarray:
    """J' = M J M^dagger for (..., 2, 2) complex arrays, through ``coherency_transform``."""
    mr, mi = _split(m, "m")
    jr, ji = _split(j, "j")
    re, im = elementwise(
        _coherency_transform_kernel,
        [(mr, wp.vec4), (mi, wp.vec4), (jr, wp.vec4), (ji, wp.vec4)],
        [wp.vec4, wp.vec4],
        device=device,
    )
    return _join(re, im)


@device_function(stokes_from_coherency)
def stokes(j, *, device=None) -> np.ndarray:
    """Stokes vectors (..., 4) of coherency matrices (..., 2, 2): S0 = Jxx+Jyy, S1 = Jxx-Jyy,
    S2 = 2 Re Jxy, S3 = 2 Im Jxy (S3 > 0 right-circular, Born & Wolf naming)."""
    jr, ji = _split(j, "j")
    s, _ = elementwise(_stokes_kernel, [(jr, wp.vec4), (ji, wp.vec4)], [wp.vec4, wp.float32], device=device)
    return s.astype(np.float64)


@device_function(degree_of_polarization)
def dop(j, *, device=None) -> np.ndarray:
    """Degree of polarization of coherency matrices (..., 2, 2), in [0, 1]."""
    jr, ji = _split(j, "j")
    _, p = elementwise(_stokes_kernel, [(jr, wp.vec4), (ji, wp.vec4)], [wp.vec4, wp.float32], device=device)
    return p.astype(np.float64)


@device_function(coherency_from_stokes_vec)
def coherency_from_stokes(s, *, device=None) -> np.ndarray:
    """Coherency matrices (..., 2, 2) from Stokes vectors (..., 4)."""
    re, im = elementwise(_from_stokes_kernel, [(_finite(s, "s"), wp.vec4)], [wp.vec4, wp.vec4], device=device)
    return _join(re, im)


def _frames(d, a, b, device):
    return elementwise(
        _frame_kernel,
        [(d, wp.vec3), (a, wp.vec3), (b, wp.vec3)],
        [wp.vec4, wp.vec3, wp.vec3],
        device=device,
    )


@device_function(frame_change)
def frame_change_matrix(direction, x_from, x_to, *, device=None) -> np.ndarray:
    """(..., 2, 2) real matrices B with B[i, k] = to_i . from_k (see ``frame_change``)."""
    m, _, _ = _frames(
        _finite(direction, "direction"), _finite(x_from, "x_from"), _finite(x_to, "x_to"), device
    )
    return m.astype(np.float64).reshape(*m.shape[:-1], 2, 2)


@device_function(s_vector)
def s_vectors(direction, normal, *, device=None) -> np.ndarray:
    """Unit s-directions normalize(normal x direction) (see ``s_vector``)."""
    nrm = _finite(normal, "normal")
    _, s, _ = _frames(_finite(direction, "direction"), nrm, nrm, device)
    return s.astype(np.float64)


@device_function(transport_basis)
def transport_bases(x, d_old, d_new, *, device=None) -> np.ndarray:
    """Basis vectors ``x`` carried from ray direction d_old to d_new (see ``transport_basis``)."""
    _, _, t = _frames(_finite(d_old, "d_old"), _finite(x, "x"), _finite(d_new, "d_new"), device)
    return t.astype(np.float64)

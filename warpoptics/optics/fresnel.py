"""Fresnel amplitude coefficients at a plane interface between isotropic media.

``fresnel_amplitudes(cos_i, n1, n2)`` is the one place where the Fresnel laws of a bare
interface live: the interface event (``optics/interface.py``, every tracer), the glossy coat of
``stages/surfaces.py`` and the uniaxial approximation (eq. 10 of Guy & Soler) call it per ray.
The thin-film stack computes its amplitudes by the characteristic-matrix method in float64
(a bare interface is its zero-layer case, tested against this function) and takes only the
flux laws from here (``flux_transmittance``, ``p_normal_flux``).

Conventions
-----------
- Complex indices ``n + i k`` as ``wp.vec2f`` (k >= 0 absorbing), time dependence
  ``exp(-i omega t)`` (see ``warpoptics.optics.complex``).
- ``cos_i`` is the cosine of the incidence angle in medium 1, in [0, 1] (clamped).
- Amplitudes are ratios of electric-field amplitudes, each wave in its own right-handed frame
  ``(s, p, k)``: ``s = normalize(normal x d)`` is shared by the incident, reflected and
  transmitted waves and ``p = k x s`` for each wave.  This is the Born & Wolf / Hecht (and
  Mitsuba 3) sign convention::

      rs = (n1 cos i - n2 cos t) / (n1 cos i + n2 cos t)
      rp = (n2 cos i - n1 cos t) / (n2 cos i + n1 cos t)
      ts = 2 n1 cos i / (n1 cos i + n2 cos t)
      tp = 2 n1 cos i / (n2 cos i + n1 cos t)

  so that at normal incidence ``rp = -rs``: every frame stays right-handed, which Jones
  matrices, Stokes S3 and the frame rotations of eq. 12 need.  These are Guy & Soler 2004's
  fig. 2 formulas and what the generalized 4x4 solution of ``birefringence.py`` reduces to
  (tested).
- ``N2 cos t`` is taken on the physical branch (Im >= 0, decaying / evanescent) by
  ``c_normal_component``.  Beyond the critical angle ``N2 cos t = i |.|`` and ``|rs| = |rp| = 1``
  with the total-internal-reflection phase; exactly at the critical angle ``rs = rp = 1``; at
  grazing incidence ``rs = rp = -1`` (``r = 0, t = 1`` when also ``n1 = n2``).  No NaN/Inf.
- Power coefficients (``fresnel_power``): ``R = |r|^2``, ``Ts = Re(N2 cos t) |ts|^2 /
  Re(n1 cos i)`` and ``Tp = Re(conj(N2) cos t) |tp|^2 / Re(n1 cos i)`` are the normal energy
  fluxes just past the interface (valid for a non-absorbing medium 1); ``R + T = 1``.

References: Born & Wolf, Principles of Optics, 7th ed., §1.5.2 eq. 20-21, §13.2 (absorbing);
Hecht, Optics, 5th ed. (2017), §4.6.2 eq. 4.42-4.45; Guy & Soler 2004, fig. 2.
"""

from __future__ import annotations

import numpy as np
import warp as wp

from ..device import device_function, elementwise
from ..errors import InputError
from .complex import c_abs2, c_conj, c_mul, c_normal_component

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "FresnelAmplitudes",
    "fresnel_amplitudes",
    "fresnel_reverse",
    "fresnel_power_coefficients",
    "reflect_direction",
    "refract_direction",
    "refract_with_cos",
    "refracted_cos",
    "refract_from_fresnel",
    "flux_ratio",
    "p_normal_flux",
    "flux_transmittance",
    "transmitted_flux_ratio",
    "unpolarized_power",
    "fresnel",
    "fresnel_power",
    "refract",
    "reflect",
]


@wp.struct
class FresnelAmplitudes:
    """Complex amplitude coefficients (wp.vec2f) and the normal wave-vector components."""

    rs: wp.vec2f
    rp: wp.vec2f
    ts: wp.vec2f
    tp: wp.vec2f
    n1_cos_i: wp.vec2f  # N1 cos(theta_i)
    n2_cos_t: wp.vec2f  # N2 cos(theta_t), Im >= 0 (imaginary beyond the critical angle)


@wp.func
def fresnel_amplitudes(cos_i: float, n1: wp.vec2f, n2: wp.vec2f):
    """Fresnel amplitudes rs, rp, ts, tp for complex indices n1 -> n2 (Born & Wolf convention,
    rp = -rs at normal incidence; see the module docstring).  ``cos_i`` in [0, 1]."""
    c = wp.clamp(cos_i, 0.0, 1.0)
    a = n1 * c  # N1 cos i
    b = c_normal_component(n1, n2, c)  # N2 cos t
    n1sq = c_mul(n1, n1)
    n2sq = c_mul(n2, n2)
    # s: (a - b) / (a + b), 2a / (a + b)
    ds = a + b
    # p, multiplied through by N2 (avoids dividing by N2): (N2^2 cos i - N1 N2 cos t) / (...)
    pa = n2sq * c
    pb = c_mul(n1, b)
    dp = pa + pb
    f = FresnelAmplitudes()
    f.n1_cos_i = a
    f.n2_cos_t = b
    if c_abs2(ds) == 0.0 or c_abs2(dp) == 0.0:
        # grazing incidence into an identical medium (the only way both normal components
        # vanish): no interface
        f.rs = wp.vec2f(0.0, 0.0)
        f.rp = wp.vec2f(0.0, 0.0)
        f.ts = wp.vec2f(1.0, 0.0)
        f.tp = wp.vec2f(1.0, 0.0)
        return f
    # one reciprocal per denominator (conj / |.|^2: one real division) serves r and t; four
    # Smith divisions cost 12 (~3 ns of the ~30 ns solve; scripts/bench/bench_lane_cost.py).
    # |ds|^2 and |dp|^2 are >= the squared normal components, far from overflow for any index
    inv_s = c_conj(ds) * (1.0 / c_abs2(ds))
    inv_p = c_conj(dp) * (1.0 / c_abs2(dp))
    f.rs = c_mul(a - b, inv_s)
    f.ts = c_mul(2.0 * a, inv_s)
    f.rp = c_mul(pa - pb, inv_p)
    # tp = 2 N1 cos i / (N2 cos i + N1 cos t) = 2 N1 N2 cos i / (N2^2 cos i + N1 N2 cos t)
    f.tp = c_mul(c_mul(n1, n2) * (2.0 * c), inv_p)
    if n1sq[0] == n2sq[0] and n1sq[1] == n2sq[1]:
        # identical media: exactly no reflection and cos t = cos i, whatever the rounding of
        # N2 cos t (at grazing incidence its float32 sqrt is off by ~5e-4 relative, and the
        # transmitted flux ratio N2 cos t / N1 cos i with it)
        f.rs = wp.vec2f(0.0, 0.0)
        f.rp = wp.vec2f(0.0, 0.0)
        f.ts = wp.vec2f(1.0, 0.0)
        f.tp = wp.vec2f(1.0, 0.0)
        f.n2_cos_t = a
    return f


@wp.func
def fresnel_reverse(f: FresnelAmplitudes, cos_t: float, n1: wp.vec2f, n2: wp.vec2f):
    """``fresnel_amplitudes(cos_t, n2, n1)`` -- the same interface crossed back, from medium 2 at
    the refracted angle (``cos_t = refracted_cos(f, n2)``) -- given the forward solution
    ``f = fresnel_amplitudes(cos_i, n1, n2)`` below the critical angle.  Between lossless media
    (real indices) the reverse crossing swaps a = n1 cos i and b = n2 cos t: rs' = -rs, rp' = -rp
    (Stokes relations, Born & Wolf §1.5.2), ts' = 2 b / (a + b), tp' = 2 n1 n2 b / (n2^2 a +
    n1^2 b) -- two real divisions instead of a complex square root and four complex ones, and
    exact where the re-solve loses digits near grazing (every backward isotropic event needs
    both crossings).  With an absorbing side it is the direct solve."""
    if n1[1] != 0.0 or n2[1] != 0.0:
        return fresnel_amplitudes(cos_t, n2, n1)
    a = f.n1_cos_i[0]
    b = f.n2_cos_t[0]
    r = FresnelAmplitudes()
    r.n1_cos_i = f.n2_cos_t
    r.n2_cos_t = f.n1_cos_i
    r.rs = -f.rs
    r.rp = -f.rp
    r.ts = wp.vec2f(1.0, 0.0)
    r.tp = wp.vec2f(1.0, 0.0)
    ds = a + b
    if ds > 0.0:  # else grazing into an identical medium: no interface (as fresnel_amplitudes)
        m1 = n1[0]
        m2 = n2[0]
        r.ts = wp.vec2f(2.0 * b / ds, 0.0)
        r.tp = wp.vec2f(2.0 * m1 * m2 * b / (m2 * m2 * a + m1 * m1 * b), 0.0)
    return r


@wp.func
def flux_ratio(in_flux: float, out_flux: float):
    """Normal energy flux of an outgoing wave per unit incident flux, for unit amplitudes:
    out / in, 0 where either vanishes (grazing incidence, an evanescent wave).  Power-normalised
    amplitudes (``|t|^2`` = transmitted power) multiply the field amplitude by its square root;
    the uniaxial waves of ``birefringence.generalized_fresnel`` carry their own ``flux``."""
    if in_flux <= 0.0 or out_flux <= 0.0:
        return 0.0
    return out_flux / in_flux


@wp.func
def flux_transmittance(t_abs2: float, in_flux: float, out_flux: float):
    """Transmitted power per unit incident power of a wave with |t|^2 = ``t_abs2``:
    |t|^2 out / in (the product first: at grazing incidence ``in`` underflows while |t|^2 -> 0),
    0 where either flux vanishes."""
    if in_flux <= 0.0 or out_flux <= 0.0:
        return 0.0
    return t_abs2 * out_flux / in_flux


@wp.func
def flux_transmittance(t_abs2: wp.float64, in_flux: wp.float64, out_flux: wp.float64):  # noqa: F811
    """:func:`flux_transmittance` in double precision (the thin-film stacks)."""
    zero = wp.float64(0.0)
    if in_flux <= zero or out_flux <= zero:
        return zero
    return t_abs2 * out_flux / in_flux


@wp.func
def p_normal_flux(q: wp.vec2f, n: wp.vec2f):
    """Re(conj(N) cos theta) = Re(q conj(N)^2) / |N|^2 with q = N cos theta: the normal Poynting flux
    of a p wave per unit |E|^2 (Byrnes 2016, "Multilayer optical calculations", eq. 22); an s wave's
    is Re(q).  The p and s fluxes differ only in an absorbing medium."""
    nc = wp.vec2f(n[0], -n[1])
    return c_mul(q, c_mul(nc, nc))[0] / c_abs2(n)


@wp.func
def p_normal_flux(q: wp.vec2d, n: wp.vec2d):  # noqa: F811 (float64 overload)
    """:func:`p_normal_flux` in double precision (the thin-film stacks)."""
    nc = wp.vec2d(n[0], -n[1])
    return c_mul(q, c_mul(nc, nc))[0] / c_abs2(n)


@wp.func
def transmitted_flux_ratio(f: FresnelAmplitudes):
    """Re(N2 cos t) / Re(N1 cos i): the transmitted normal flux per unit incident flux and unit
    |t|^2 (Born & Wolf §1.5.3), zero under total internal reflection (N2 cos t imaginary).  Exact
    for s; for p also when N2 is real (the renderer's interfaces; ``fresnel_power_coefficients``
    has the absorbing-medium p form)."""
    return flux_ratio(f.n1_cos_i[0], f.n2_cos_t[0])


@wp.func
def unpolarized_power(a_s: wp.vec2f, a_p: wp.vec2f):
    """(|a_s|^2 + |a_p|^2) / 2: the power coefficient of unpolarized light (an average over s
    and p) of a pair of amplitude coefficients."""
    return 0.5 * (c_abs2(a_s) + c_abs2(a_p))


@wp.func
def fresnel_power_coefficients(f: FresnelAmplitudes, n1: wp.vec2f, n2: wp.vec2f):
    """(Rs, Rp, Ts, Tp): reflectances |r|^2 and the transmitted normal energy fluxes per unit
    incident flux, Ts = |ts|^2 Re(N2 cos t) / Re(N1 cos i) and Tp = |tp|^2 Re(conj(N2) cos t) /
    Re(conj(N1) cos i) (Byrnes 2016 eq. 21-22; the thin-film stacks use the same two laws,
    :func:`flux_transmittance` and :func:`p_normal_flux`).  Zero transmittance beyond the critical angle."""
    ts = flux_transmittance(c_abs2(f.ts), f.n1_cos_i[0], f.n2_cos_t[0])
    tp = flux_transmittance(c_abs2(f.tp), p_normal_flux(f.n1_cos_i, n1), p_normal_flux(f.n2_cos_t, n2))
    return wp.vec4(c_abs2(f.rs), c_abs2(f.rp), ts, tp)


@wp.func
def reflect_direction(d: wp.vec3, normal: wp.vec3):
    """Mirror direction d - 2 (d . n) n (either orientation of the unit normal)."""
    return d - normal * (2.0 * wp.dot(d, normal))


@wp.func
def refract_with_cos(d: wp.vec3, normal: wp.vec3, eta: float, cos_i: float, cos_t: float):
    """The refracted unit direction eta d + (eta cos i - cos t) n for eta = n1 / n2 and the two
    cosines of Snell's law (``normal`` to the incident side): the tangential wave vector is
    conserved.  Mitsuba 3's ``refract(wi, n, cos_theta_t, eta_ti)`` the same way reuses the cosine
    its ``fresnel()`` computed."""
    return wp.normalize(d * eta + normal * (eta * cos_i - cos_t))


@wp.func
def refracted_cos(f: FresnelAmplitudes, n2: wp.vec2f):
    """cos(theta_t) of the refracted wave from the Fresnel solution: Re(N2 cos t) / Re(N2) (Snell's
    law N1 sin i = N2 sin t as ``c_normal_component`` solved it); 0 under total internal
    reflection, where N2 cos t is imaginary."""
    return wp.max(f.n2_cos_t[0], 0.0) / n2[0]


@wp.func
def refract_from_fresnel(d: wp.vec3, normal: wp.vec3, f: FresnelAmplitudes, n1: wp.vec2f, n2: wp.vec2f):
    """Refracted unit direction of ``d`` (``normal`` to the incident side) from the Fresnel
    solution ``f = fresnel_amplitudes(cos_i, n1, n2)``; the zero vector under total internal
    reflection."""
    ct = refracted_cos(f, n2)
    if ct <= 0.0:
        return wp.vec3(0.0, 0.0, 0.0)
    return refract_with_cos(d, normal, n1[0] / n2[0], f.n1_cos_i[0] / n1[0], ct)


@wp.func
def refract_direction(d: wp.vec3, normal: wp.vec3, n1: float, n2: float):
    """Snell refraction of unit ``d`` through a surface whose unit ``normal`` points to the
    incident side (d . normal <= 0), real indices.  Returns the zero vector under total
    internal reflection.  Also the o-ray of a uniaxial crystal (n2 = n_o), and the exact wave
    normal leaving a crystal into an isotropic medium when ``d`` is the incident wave normal and
    ``n1`` its effective index (n_o, or n_e(theta) of an e-wave): the tangential wave vector
    n1 (d - (d.n) n) is conserved.  Snell's law itself is ``c_normal_component``'s."""
    c = wp.clamp(-wp.dot(d, normal), 0.0, 1.0)
    q = c_normal_component(wp.vec2f(n1, 0.0), wp.vec2f(n2, 0.0), c)
    if q[0] <= 0.0:
        return wp.vec3(0.0, 0.0, 0.0)
    return refract_with_cos(d, normal, n1 / n2, c, q[0] / n2)


_vec8 = wp.types.vector(length=8, dtype=wp.float32)


@wp.kernel
def _fresnel_kernel(
    offset: int,
    cos_i: wp.array(dtype=float),
    n1: wp.array(dtype=wp.vec2f),
    n2: wp.array(dtype=wp.vec2f),
    out_amp: wp.array(dtype=_vec8),
    out_pow: wp.array(dtype=wp.vec4),
):
    i = wp.tid() + offset
    f = fresnel_amplitudes(cos_i[i], n1[i], n2[i])
    v = _vec8()
    v[0] = f.rs[0]
    v[1] = f.rs[1]
    v[2] = f.rp[0]
    v[3] = f.rp[1]
    v[4] = f.ts[0]
    v[5] = f.ts[1]
    v[6] = f.tp[0]
    v[7] = f.tp[1]
    out_amp[i] = v
    out_pow[i] = fresnel_power_coefficients(f, n1[i], n2[i])


@wp.kernel
def _directions_kernel(
    offset: int,
    d: wp.array(dtype=wp.vec3),
    normal: wp.array(dtype=wp.vec3),
    n1: wp.array(dtype=float),
    n2: wp.array(dtype=float),
    out_reflect: wp.array(dtype=wp.vec3),
    out_refract: wp.array(dtype=wp.vec3),
):
    i = wp.tid() + offset
    out_reflect[i] = reflect_direction(d[i], normal[i])
    out_refract[i] = refract_direction(d[i], normal[i], n1[i], n2[i])


def _complex_pairs(n, name: str) -> np.ndarray:
    a = np.asarray(n)
    if not np.iscomplexobj(a):
        a = a.astype(np.float64)
    # each message shows the first offending element, not the array (one line at any size)
    if not np.all(np.isfinite(a)):
        raise InputError(
            "refractive index must be finite", field=name, value=a[~np.isfinite(a)].flat[0].item()
        )
    if np.any(np.imag(a) < 0):
        raise InputError(
            "refractive index must have a non-negative imaginary part (n + ik, k >= 0 absorbing)",
            field=name,
            value=a[np.imag(a) < 0].flat[0].item(),
            allowed="Im(n) >= 0",
        )
    if np.any(np.real(a) <= 0):
        raise InputError(
            "refractive index must have a positive real part",
            field=name,
            value=a[np.real(a) <= 0].flat[0].item(),
            allowed="Re(n) > 0",
        )
    return np.stack([np.real(a), np.imag(a)], axis=-1)


def _cosines(cos_i) -> np.ndarray:
    c = np.asarray(cos_i, dtype=np.float64)
    bad = ~np.isfinite(c) | (c < -1e-6) | (c > 1.0 + 1e-6)
    if np.any(bad):
        raise InputError(
            "cosine of the incidence angle must lie in [0, 1]",
            field="cos_i",
            value=c[bad].flat[0].item(),
            allowed="[0, 1]",
        )
    return np.clip(c, 0.0, 1.0)


def _run(cos_i, n1, n2, device):
    return elementwise(
        _fresnel_kernel,
        [
            (_cosines(cos_i), wp.float32),
            (_complex_pairs(n1, "n1"), wp.vec2f),
            (_complex_pairs(n2, "n2"), wp.vec2f),
        ],
        [_vec8, wp.vec4],
        device=device,
    )


@device_function(fresnel_amplitudes)
def fresnel(cos_i, n1, n2, *, device=None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Fresnel amplitude coefficients (rs, rp, ts, tp) as complex NumPy arrays.

    Parameters
    ----------
    cos_i : array_like
        Cosine of the incidence angle in medium 1, in [0, 1].
    n1, n2 : array_like, real or complex
        Refractive indices ``n + ik`` (k >= 0) of the incident and transmitting media.
        All three broadcast together.

    Born & Wolf sign convention (``rp = -rs`` at normal incidence), evaluated in float32 by
    ``fresnel_amplitudes``; see the module docstring.
    """
    amp, _ = _run(cos_i, n1, n2, device)
    amp = amp.astype(np.float64)
    return tuple(amp[..., 2 * k] + 1j * amp[..., 2 * k + 1] for k in range(4))  # type: ignore[return-value]


@device_function(fresnel_power_coefficients)
def fresnel_power(cos_i, n1, n2, *, device=None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Power coefficients (Rs, Rp, Ts, Tp): reflectances and transmitted normal energy fluxes
    (valid for a non-absorbing incident medium); Rs + Ts = Rp + Tp = 1."""
    _, pw = _run(cos_i, n1, n2, device)
    pw = pw.astype(np.float64)
    return pw[..., 0], pw[..., 1], pw[..., 2], pw[..., 3]


def _unit3(v, name: str) -> np.ndarray:
    a = np.asarray(v, dtype=np.float64)
    if a.ndim == 0 or a.shape[-1] != 3 or not np.all(np.isfinite(a)):
        raise InputError("expected finite 3-vectors (last axis of length 3)", field=name)
    n = np.linalg.norm(a, axis=-1, keepdims=True)
    if np.any(n == 0):
        raise InputError("expected non-zero vectors", field=name)
    return a / n


@device_function(refract_direction)
def refract(direction, normal, n1, n2, *, device=None) -> np.ndarray:
    """Snell refraction directions (..., 3) through a surface whose ``normal`` points to the
    incident side; zero vectors under total internal reflection (see ``refract_direction``)."""
    n1a = np.asarray(n1, dtype=np.float64)
    n2a = np.asarray(n2, dtype=np.float64)
    if np.any(~np.isfinite(n1a) | (n1a <= 0)) or np.any(~np.isfinite(n2a) | (n2a <= 0)):
        raise InputError("refractive indices must be finite and positive", field="n1/n2", allowed="> 0")
    _, t = elementwise(
        _directions_kernel,
        [
            (_unit3(direction, "direction"), wp.vec3),
            (_unit3(normal, "normal"), wp.vec3),
            (n1a, wp.float32),
            (n2a, wp.float32),
        ],
        [wp.vec3, wp.vec3],
        device=device,
    )
    return t.astype(np.float64)


@device_function(reflect_direction)
def reflect(direction, normal, *, device=None) -> np.ndarray:
    """Mirror directions (..., 3) (see ``reflect_direction``)."""
    r, _ = elementwise(
        _directions_kernel,
        [
            (_unit3(direction, "direction"), wp.vec3),
            (_unit3(normal, "normal"), wp.vec3),
            (1.0, wp.float32),
            (1.0, wp.float32),
        ],
        [wp.vec3, wp.vec3],
        device=device,
    )
    return r.astype(np.float64)

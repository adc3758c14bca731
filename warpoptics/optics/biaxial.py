"""Biaxial crystals: the two plane waves of a given tangential wave vector, eigenpolarizations,
Poynting rays, normal fluxes, the generalized Fresnel solve with a biaxial medium on either side,
trichroic absorption per wave and the optic-axial angle 2V.

Conventions (those of ``birefringence.py``; wave vectors in units of k0; in full, with the
documented choices: docs/design/biaxial_crystals.md):
- A biaxial medium is the tracers' ``UniaxialMedium`` with ``nb`` > 0 (:func:`biaxial_medium`):
  n_alpha <= n_beta <= n_gamma (``no``, ``nb``, ``ne``) along the principal axes X, Y, Z (rows
  of ``frame``, world space).  The optic axes lie in the XZ plane at V_z from Z,
  sin^2 V_z = (n_a^-2 - n_b^-2) / (n_a^-2 - n_g^-2) (Born & Wolf §15.3.3, eq. 29); the crystal is
  optically positive when V_z < 45°.
- The waves k = kt + q m solve Fresnel's equation of wave normals written for k (Born & Wolf
  §15.2, eq. 22), a quartic in q solved in float64 (Ferrari, Newton-polished); the two roots
  leaving into the medium are the real ones whose Poynting vector points along +m and the complex
  ones with Im q > 0 (evanescent).
- Eigenpolarizations: D along the principal axes of the index ellipsoid's section perpendicular
  to s (closed-form 2x2), E = eps^-1 D; waves 0 (fast) and 1 (slow) are the ``mode`` a ray
  carries in a biaxial stone.  Along an optic axis the pair is the limit approached within the
  XZ plane (D_fast along Y's projection); the ring of internal conical refraction is not sampled.
- :func:`crystal_fresnel` solves the boundary system (Guy & Soler 2004 eq. 5; McClain et al.
  1993) with each side's waves from its own solver (s/p, o/e, fast/slow).
- Trichroic absorption: each wave is attenuated by what its own D sees
  (``optics.absorption.trichroic_kappa``; Guy & Soler eq. 7 when two indices coincide).

References: Born & Wolf, Principles of Optics, 7th ed., §15.2-15.3, §15.6; Yariv & Yeh, Optical
Waves in Crystals (1984), ch. 4; Guy & Soler 2004, eq. 5, 7; McClain, Hillman & Chipman 1993,
JOSA A 10(11).
"""

from __future__ import annotations

import numpy as np
import warp as wp

from ..device import elementwise
from ..errors import InputError
from .absorption import trichroic_kappa
from .birefringence import (
    SOLUTION_OUTPUTS,
    InterfaceSolution,
    PlaneWave,
    UniaxialMedium,
    boundary_amplitudes,
    extraordinary_wave,
    generalized_fresnel,
    incident_wave,
    interface_solution,
    n_e_theta,
    ordinary_wave,
    solution_result,
    store_solution,
    uniaxial_medium,
    wave_normal_of_ray,
)

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "is_biaxial",
    "biaxial_medium",
    "biaxial_wave_pair",
    "biaxial_incident_wave",
    "biaxial_wave_d",
    "medium_waves",
    "medium_incident_wave",
    "medium_wave_normal",
    "wave_index",
    "crystal_fresnel",
    "crystal_fresnel_both",
    "fresnel_from_waves",
    "EventWaves",
    "event_waves",
    "event_fresnel",
    "biaxial_kappa",
    # NumPy
    "optic_axial_angle",
    "biaxial_waves",
    "biaxial_fresnel_coefficients",
    "biaxial_absorption",
    "principal_d",
]


# ----------------------------------------------------------------------------------------------
# the medium


@wp.func
def is_biaxial(med: UniaxialMedium):
    """A biaxial crystal (``nb`` > 0)."""
    return med.nb > 0.0


@wp.func
def biaxial_medium(n_alpha: float, n_beta: float, n_gamma: float, frame: wp.mat33, alpha_y: float):
    """The medium struct of a biaxial crystal: principal indices along the rows X, Y, Z of
    ``frame`` (world), ``alpha_y`` its absorption for D along Y (1/mm)."""
    m = uniaxial_medium(n_alpha, n_gamma, wp.vec3(frame[2, 0], frame[2, 1], frame[2, 2]))
    m.nb = n_beta
    m.frame = frame
    m.alpha_y = alpha_y
    return m


# ----------------------------------------------------------------------------------------------
# float64 helpers (the quartic loses precision near double roots in float32)


@wp.func
def _d3(v: wp.vec3):
    return wp.vec3d(wp.float64(v[0]), wp.float64(v[1]), wp.float64(v[2]))


@wp.func
def _world(frame: wp.mat33, v: wp.vec3d):
    # principal coordinates -> world vector (rows of frame are X, Y, Z)
    p = wp.vec3(wp.float32(v[0]), wp.float32(v[1]), wp.float32(v[2]))
    return wp.transpose(frame) * p


@wp.func
def _principal(frame: wp.mat33, v: wp.vec3):
    # world -> principal coordinates, in float64
    f = wp.mat33d()
    for i in range(3):
        for j in range(3):
            f[i, j] = wp.float64(frame[i, j])
    return f * _d3(v)


@wp.func
def _inv_eps(med: UniaxialMedium):
    a = wp.float64(med.no)
    b = wp.float64(med.nb)
    c = wp.float64(med.ne)
    return wp.vec3d(wp.float64(1.0) / (a * a), wp.float64(1.0) / (b * b), wp.float64(1.0) / (c * c))


@wp.func
def _eps(med: UniaxialMedium):
    a = wp.float64(med.no)
    b = wp.float64(med.nb)
    c = wp.float64(med.ne)
    return wp.vec3d(a * a, b * b, c * c)


@wp.func
def _cmul(ar: wp.float64, ai: wp.float64, br: wp.float64, bi: wp.float64):
    return ar * br - ai * bi, ar * bi + ai * br


@wp.func
def _cdiv(ar: wp.float64, ai: wp.float64, br: wp.float64, bi: wp.float64):
    d = br * br + bi * bi
    return (ar * br + ai * bi) / d, (ai * br - ar * bi) / d


@wp.func
def _csqrt(zr: wp.float64, zi: wp.float64):
    r = wp.sqrt(zr * zr + zi * zi)
    re = wp.sqrt(wp.max((r + zr) * wp.float64(0.5), wp.float64(0.0)))
    im = wp.sqrt(wp.max((r - zr) * wp.float64(0.5), wp.float64(0.0)))
    if zi < wp.float64(0.0):
        im = -im
    return re, im


# ----------------------------------------------------------------------------------------------
# eigenpolarizations of a wave normal


@wp.func
def _eigen_pair(s: wp.vec3d, ie: wp.vec3d):
    """(n_fast, D_fast, n_slow, D_slow) for the unit wave normal ``s`` (principal coordinates),
    ``ie`` = (1/n_alpha^2, 1/n_beta^2, 1/n_gamma^2): the principal axes of the section of the
    index ellipsoid perpendicular to s.  Degenerate (s along an optic axis): D_fast is the
    projection of Y (see the module docstring)."""
    one = wp.float64(1.0)
    zero = wp.float64(0.0)
    u = wp.vec3d(-s[1] * s[0], one - s[1] * s[1], -s[1] * s[2])  # Y - s (s.Y)
    if wp.dot(u, u) < wp.float64(1.0e-20):
        u = wp.vec3d(one - s[0] * s[0], -s[0] * s[1], -s[0] * s[2])  # s along Y: use X
    u = wp.normalize(u)
    v = wp.cross(s, u)
    a = ie[0] * u[0] * u[0] + ie[1] * u[1] * u[1] + ie[2] * u[2] * u[2]
    b = ie[0] * u[0] * v[0] + ie[1] * u[1] * v[1] + ie[2] * u[2] * v[2]
    c = ie[0] * v[0] * v[0] + ie[1] * v[1] * v[1] + ie[2] * v[2] * v[2]
    h = (a - c) * wp.float64(0.5)
    mean = (a + c) * wp.float64(0.5)
    r = wp.sqrt(h * h + b * b)
    e0 = b
    e1 = r - h
    if h >= zero:
        e0 = h + r
        e1 = b
    l2 = e0 * e0 + e1 * e1
    if l2 < wp.float64(1.0e-40):
        e0 = one
        e1 = zero
    else:
        inv = one / wp.sqrt(l2)
        e0 = e0 * inv
        e1 = e1 * inv
    d_f = u * e0 + v * e1
    d_s = wp.cross(s, d_f)
    n_f = one / wp.sqrt(mean + r)
    n_s = one / wp.sqrt(wp.max(mean - r, wp.float64(1.0e-30)))
    return n_f, d_f, n_s, d_s


@wp.func
def _e_of_d(d: wp.vec3d, ie: wp.vec3d):
    return wp.normalize(wp.vec3d(d[0] * ie[0], d[1] * ie[1], d[2] * ie[2]))


@wp.func
def _poynting(k: wp.vec3d, e: wp.vec3d):
    # Re(E x conj(k x E)) for real k, E: |E|^2 k - (E.k) E
    return k * wp.dot(e, e) - e * wp.dot(e, k)


# ----------------------------------------------------------------------------------------------
# the quartic in q


@wp.func
def _cubic_max_root(a: wp.float64, b: wp.float64, c: wp.float64):
    """The largest real root of x^3 + a x^2 + b x + c (Cardano / Viete), two Newton steps."""
    third = wp.float64(1.0) / wp.float64(3.0)
    qv = (a * a - wp.float64(3.0) * b) / wp.float64(9.0)
    rv = (wp.float64(2.0) * a * a * a - wp.float64(9.0) * a * b + wp.float64(27.0) * c) / wp.float64(54.0)
    q3 = qv * qv * qv
    x = wp.float64(0.0)
    if rv * rv < q3:
        th = wp.acos(wp.clamp(rv / wp.sqrt(q3), wp.float64(-1.0), wp.float64(1.0)))
        x = (
            wp.float64(-2.0) * wp.sqrt(qv) * wp.cos((th + wp.float64(2.0 * 3.141592653589793)) * third)
            - a * third
        )
    else:
        big = wp.pow(wp.abs(rv) + wp.sqrt(rv * rv - q3), third)
        if rv > wp.float64(0.0):
            big = -big
        small = wp.float64(0.0)
        if big != wp.float64(0.0):
            small = qv / big
        x = big + small - a * third
    for _it in range(2):
        f = ((x + a) * x + b) * x + c
        fp = (wp.float64(3.0) * x + wp.float64(2.0) * a) * x + b
        if fp != wp.float64(0.0):
            x = x - f / fp
    return x


@wp.func
def _quadratic_roots(b: wp.float64, c: wp.float64):
    """Roots of y^2 + b y + c (real b, c) as (r0, i0, r1, i1), the real ones without cancellation."""
    disc = b * b - wp.float64(4.0) * c
    zero = wp.float64(0.0)
    if disc >= zero:
        sq = wp.sqrt(disc)
        t = -wp.float64(0.5) * (b + sq)
        if b < zero:
            t = -wp.float64(0.5) * (b - sq)
        if t == zero:
            return zero, zero, zero, zero
        return t, zero, c / t, zero
    im = wp.float64(0.5) * wp.sqrt(-disc)
    return -wp.float64(0.5) * b, im, -wp.float64(0.5) * b, -im


@wp.func
def _polish(xr: wp.float64, xi: wp.float64, a3: wp.float64, a2: wp.float64, a1: wp.float64, a0: wp.float64):
    # Newton steps on the monic quartic (complex x), each kept only if it lowers |f|
    for _it in range(2):
        fr, fi = _cmul(xr + a3, xi, xr, xi)
        fr, fi = _cmul(fr + a2, fi, xr, xi)
        fr, fi = _cmul(fr + a1, fi, xr, xi)
        fr = fr + a0
        gr, gi = _cmul(wp.float64(4.0) * xr + wp.float64(3.0) * a3, wp.float64(4.0) * xi, xr, xi)
        gr, gi = _cmul(gr + wp.float64(2.0) * a2, gi, xr, xi)
        gr, gi = _cmul(gr, gi, xr, xi)
        gr = gr + a1
        if gr * gr + gi * gi > wp.float64(1.0e-60):
            dr, di = _cdiv(fr, fi, gr, gi)
            nr = xr - dr
            ni = xi - di
            hr, hi = _cmul(nr + a3, ni, nr, ni)
            hr, hi = _cmul(hr + a2, hi, nr, ni)
            hr, hi = _cmul(hr + a1, hi, nr, ni)
            hr = hr + a0
            if hr * hr + hi * hi < fr * fr + fi * fi:
                xr = nr
                xi = ni
    return xr, xi


@wp.func
def _quartic_roots(c4: wp.float64, c3: wp.float64, c2: wp.float64, c1: wp.float64, c0: wp.float64):
    """The four complex roots (re, im as vec4d) of c4 q^4 + ... + c0 (c4 > 0) by Ferrari's method:
    the depressed quartic y^4 + p y^2 + r1 y + r0 = (y^2 - s y + u)(y^2 + s y + w) with s^2 = 2 m,
    m the largest root of the resolvent cubic m^3 + p m^2 + (p^2/4 - r0) m - r1^2/8."""
    a3 = c3 / c4
    a2 = c2 / c4
    a1 = c1 / c4
    a0 = c0 / c4
    sh = a3 * wp.float64(0.25)
    p = a2 - wp.float64(0.375) * a3 * a3
    r1 = a1 - wp.float64(0.5) * a3 * a2 + wp.float64(0.125) * a3 * a3 * a3
    r0 = a0 - wp.float64(0.25) * a3 * a1 + a3 * a3 * a2 / wp.float64(16.0)
    r0 = r0 - wp.float64(3.0) * a3 * a3 * a3 * a3 / wp.float64(256.0)
    re = wp.vec4d()
    im = wp.vec4d()
    scale = wp.float64(1.0) + wp.abs(p) + wp.sqrt(wp.abs(r0))
    m = wp.float64(0.0)
    if wp.abs(r1) > wp.float64(1.0e-13) * scale * wp.sqrt(scale):
        m = _cubic_max_root(p, wp.float64(0.25) * p * p - r0, -wp.float64(0.125) * r1 * r1)
    if m > wp.float64(1.0e-14) * scale:
        s = wp.sqrt(wp.float64(2.0) * m)
        t = r1 / (wp.float64(2.0) * s)
        y0r, y0i, y1r, y1i = _quadratic_roots(-s, wp.float64(0.5) * p + m + t)
        y2r, y2i, y3r, y3i = _quadratic_roots(s, wp.float64(0.5) * p + m - t)
        re = wp.vec4d(y0r, y1r, y2r, y3r)
        im = wp.vec4d(y0i, y1i, y2i, y3i)
    else:
        # biquadratic (r1 = 0): y^2 = z, z^2 + p z + r0 = 0
        z0r, z0i, z1r, z1i = _quadratic_roots(p, r0)
        ar, ai = _csqrt(z0r, z0i)
        br, bi = _csqrt(z1r, z1i)
        re = wp.vec4d(ar, -ar, br, -br)
        im = wp.vec4d(ai, -ai, bi, -bi)
    for j in range(4):
        xr, xi = _polish(re[j] - sh, im[j], a3, a2, a1, a0)
        re[j] = xr
        im[j] = xi
    return re, im


@wp.func
def _quartic_roots_known(
    c4: wp.float64, c3: wp.float64, c2: wp.float64, c1: wp.float64, c0: wp.float64, r: wp.float64
):
    """The four roots of the quartic when one, ``r``, is known (the incident wave's, for the
    reflected waves): ``r`` itself, then the largest real root of the deflated cubic and the two
    roots of the deflated quadratic, each polished on the full quartic.  Near an optic axis the
    incident root is double; deflating by it keeps its twin a real (incident-side) root instead
    of a complex pair that could pass for an evanescent reflected wave."""
    a3 = c3 / c4
    a2 = c2 / c4
    a1 = c1 / c4
    a0 = c0 / c4
    b2 = a3 + r
    b1 = a2 + r * b2
    b0 = a1 + r * b1
    x1 = _cubic_max_root(b2, b1, b0)
    q1 = b2 + x1
    q0 = b1 + x1 * q1
    y0r, y0i, y1r, y1i = _quadratic_roots(q1, q0)
    re = wp.vec4d(r, x1, y0r, y1r)
    im = wp.vec4d(wp.float64(0.0), wp.float64(0.0), y0i, y1i)
    for j in range(1, 4):
        xr, xi = _polish(re[j], im[j], a3, a2, a1, a0)
        re[j] = xr
        im[j] = xi
    return re, im


@wp.func
def _quartic(kt: wp.vec3d, m: wp.vec3d, eps: wp.vec3d):
    """Coefficients (c4..c0) of F(kt + q m) = A |k|^2 - B + eps1 eps2 eps3 (principal frame,
    kt . m = 0, |m| = 1): A = sum eps_i k_i^2, B = sum eps_i (S - eps_i) k_i^2, S = sum eps_i."""
    ssum = eps[0] + eps[1] + eps[2]
    a0 = wp.float64(0.0)
    a1 = wp.float64(0.0)
    a2 = wp.float64(0.0)
    b0 = wp.float64(0.0)
    b1 = wp.float64(0.0)
    b2 = wp.float64(0.0)
    for i in range(3):
        e = eps[i]
        be = e * (ssum - e)
        a0 += e * kt[i] * kt[i]
        a1 += wp.float64(2.0) * e * kt[i] * m[i]
        a2 += e * m[i] * m[i]
        b0 += be * kt[i] * kt[i]
        b1 += wp.float64(2.0) * be * kt[i] * m[i]
        b2 += be * m[i] * m[i]
    t = wp.dot(kt, kt)
    c4 = a2
    c3 = a1
    c2 = a0 + a2 * t - b2
    c1 = a1 * t - b1
    c0 = a0 * t - b0 + eps[0] * eps[1] * eps[2]
    return c4, c3, c2, c1, c0


# ----------------------------------------------------------------------------------------------
# the waves of one side


@wp.func
def _evanescent_e(kr: wp.vec3d, ki: wp.vec3d, eps: wp.vec3d):
    """Unit complex E (re, im) in the null space of eps - (k.k) I + k k^T for complex k."""
    kkr = wp.dot(kr, kr) - wp.dot(ki, ki)
    kki = wp.float64(2.0) * wp.dot(kr, ki)
    best = wp.float64(-1.0)
    er = wp.vec3d()
    ei = wp.vec3d()
    for pair in range(3):
        i = 0
        j = 1
        if pair == 1:
            j = 2
        if pair == 2:
            i = 1
            j = 2
        # rows i, j: (eps_i - kk) e_i + k_i k
        ar = kr * kr[i] - ki * ki[i]
        ai = kr * ki[i] + ki * kr[i]
        ar[i] = ar[i] + eps[i] - kkr
        ai[i] = ai[i] - kki
        br = kr * kr[j] - ki * ki[j]
        bi = kr * ki[j] + ki * kr[j]
        br[j] = br[j] + eps[j] - kkr
        bi[j] = bi[j] - kki
        cr = wp.cross(ar, br) - wp.cross(ai, bi)
        ci = wp.cross(ar, bi) + wp.cross(ai, br)
        n2 = wp.dot(cr, cr) + wp.dot(ci, ci)
        if n2 > best:
            best = n2
            er = cr
            ei = ci
    if best <= wp.float64(1.0e-40):
        return wp.vec3d(wp.float64(0.0), wp.float64(1.0), wp.float64(0.0)), wp.vec3d()
    inv = wp.float64(1.0) / wp.sqrt(best)
    return er * inv, ei * inv


@wp.func
def _propagating(med: UniaxialMedium, k: wp.vec3d, e: wp.vec3d, m_world: wp.vec3):
    w = PlaneWave()
    n = wp.length(k)
    w.k_re = _world(med.frame, k)
    w.k_im = wp.vec3(0.0)
    w.wave_normal = wp.normalize(w.k_re)
    w.ray = wp.normalize(_world(med.frame, _poynting(k, e)))
    w.n = wp.float32(n)
    w.e_re = wp.normalize(_world(med.frame, e))
    w.e_im = wp.vec3(0.0)
    w.propagating = 1
    # the normal flux in float64 from the principal-frame k, E (exact bookkeeping near grazing)
    w.flux = wp.float32(wp.dot(_poynting(k, e), _principal(med.frame, m_world)))
    return w


@wp.func
def _frame64(frame: wp.mat33):
    f = wp.mat33d()
    for i in range(3):
        for j in range(3):
            f[i, j] = wp.float64(frame[i, j])
    return f


@wp.func
def biaxial_wave_pair(kt: wp.vec3, m: wp.vec3, med: UniaxialMedium):
    """The two waves with tangential wave vector ``kt`` leaving the interface into the biaxial
    ``med`` on the side of unit normal ``m`` (energy along +m, or decaying along +m):
    (fast wave, slow wave) as ``PlaneWave``\\ s (labels 0 and 1).  When only one propagates it is
    the slow one (a fast wave is totally reflected first)."""
    return _wave_pair64(_d3(kt), m, med, 0, wp.vec3d())


@wp.func
def _pair_labels(la: int, lb: int):
    # sheet labels of a pair of roots: a propagating wave keeps its sheet; an evanescent one
    # (label -1) takes the other label; two waves on one sheet (a double root on an optic axis)
    # are split as documented in the module docstring
    if la < 0 and lb < 0:
        return 0, 1
    if la < 0:
        return 1 - lb, lb
    if lb < 0:
        return la, 1 - la
    if la == lb:
        return la, 1 - la
    return la, lb


@wp.func
def _root_wave(
    med: UniaxialMedium,
    ktp: wp.vec3d,
    mp: wp.vec3d,
    qr: wp.float64,
    qi: wp.float64,
    root_label: int,
    lab: int,
    e: wp.vec3d,
    m_flux: wp.vec3,
):
    # the PlaneWave of root q = qr + i qi on sheet ``lab`` (its flux taken along ``m_flux``);
    # ``root_label`` < 0 marks an evanescent root, a label other than the root's own the second
    # copy of a double root (the other eigenpolarization)
    eps = _eps(med)
    ie = _inv_eps(med)
    w = PlaneWave()
    if root_label >= 0:
        k = ktp + mp * qr
        if root_label != lab:
            n_f, d_f, n_s, d_s = _eigen_pair(wp.normalize(k), ie)
            d = d_f
            if lab == 1:
                d = d_s
            e = _e_of_d(d, ie)
        w = _propagating(med, k, e, m_flux)
    else:
        kr = ktp + mp * qr
        ki = mp * qi
        er, ei = _evanescent_e(kr, ki, eps)
        w.k_re = _world(med.frame, kr)
        w.k_im = _world(med.frame, ki)
        w.wave_normal = wp.normalize(w.k_re)
        w.ray = wp.vec3(0.0)
        w.n = 0.0
        w.e_re = _world(med.frame, er)
        w.e_im = _world(med.frame, ei)
        w.flux = 0.0
        w.propagating = 0
    return w


@wp.func
def _side_waves64(kt_world: wp.vec3d, m: wp.vec3, med: UniaxialMedium, known: int, k_known: wp.vec3d):
    """All four waves of the biaxial ``med`` with one tangential wave vector, from one quartic:
    (out0, out1, in0, in1).  ``out`` leave the interface into the medium on the side of unit
    normal ``m`` (energy along +m, or decaying along +m; flux taken along +m), ``in`` arrive at it
    (energy along -m, or decaying along -m; flux taken along -m, as an incident wave's);
    0 fast, 1 slow.  ``kt_world`` is the tangential wave vector (world, float64); with ``known``
    = 1 it is that of ``k_known`` (principal coordinates), a propagating wave of this medium,
    whose root is then exact and deflated (``_quartic_roots_known``): near an optic axis its
    root is double, and deflating keeps its twin a real root instead of a complex pair that
    could pass for an evanescent wave.  Phase matching makes these four waves every crystal wave
    of an interface event: the incident and reflected waves on this side, the transmitted ones
    of a solve from the other side (the backward event solves its quartics once)."""
    eps = _eps(med)
    ie = _inv_eps(med)
    f64 = _frame64(med.frame)
    mp = wp.normalize(f64 * _d3(m))
    ktp = f64 * kt_world
    if known != 0:
        ktp = k_known
    # kt . m = 0 exactly in the quartic (float32 input may carry a rounding component)
    q_known = wp.dot(ktp, mp)
    ktp = ktp - mp * q_known
    c4, c3, c2, c1, c0 = _quartic(ktp, mp, eps)
    qr = wp.vec4d()
    qi = wp.vec4d()
    if known != 0:
        qr, qi = _quartic_roots_known(c4, c3, c2, c1, c0, q_known)
    else:
        qr, qi = _quartic_roots(c4, c3, c2, c1, c0)
    score = wp.vec4d()
    label = wp.vec4i()
    efield = wp.mat33d()  # rows: E of the first three roots (the fourth in e3)
    e3 = wp.vec3d()
    tol = wp.float64(1.0e-7)
    for j in range(4):
        if wp.abs(qi[j]) <= tol * (wp.float64(1.0) + wp.abs(qr[j])):
            k = ktp + mp * qr[j]
            n = wp.length(k)
            s = k / n
            n_f, d_f, n_s, d_s = _eigen_pair(s, ie)
            d = d_f
            lab = 0
            if wp.abs(n - n_s) < wp.abs(n - n_f):
                d = d_s
                lab = 1
            e = _e_of_d(d, ie)
            st = _poynting(k, e)
            score[j] = wp.dot(st, mp) / wp.length(st)
            label[j] = lab
            if j < 3:
                efield[j] = e
            else:
                e3 = e
        else:
            score[j] = wp.float64(2.0)
            if qi[j] < wp.float64(0.0):
                score[j] = wp.float64(-2.0)
            label[j] = -1
    # the two highest scores leave into the medium, the other two arrive
    i0 = int(0)
    for j in range(1, 4):
        if score[j] > score[i0]:
            i0 = j
    i1 = int(-1)
    for j in range(4):
        if j != i0:
            if i1 < 0:
                i1 = j
            elif score[j] > score[i1]:
                i1 = j
    j0 = int(-1)
    j1 = int(-1)
    for j in range(4):
        if j != i0 and j != i1:
            if j0 < 0:
                j0 = j
            else:
                j1 = j
    l0, l1 = _pair_labels(label[i0], label[i1])
    a0, a1 = _pair_labels(label[j0], label[j1])
    out0 = PlaneWave()
    out1 = PlaneWave()
    in0 = PlaneWave()
    in1 = PlaneWave()
    m_in = -m
    for pick in range(4):
        j = i0
        lab = l0
        if pick == 1:
            j = i1
            lab = l1
        elif pick == 2:
            j = j0
            lab = a0
        elif pick == 3:
            j = j1
            lab = a1
        e = e3
        if j < 3:
            e = efield[j]
        if pick < 2:
            w = _root_wave(med, ktp, mp, qr[j], qi[j], label[j], lab, e, m)
            if lab == 0:
                out0 = w
            else:
                out1 = w
        else:
            w = _root_wave(med, ktp, mp, qr[j], qi[j], label[j], lab, e, m_in)
            if lab == 0:
                in0 = w
            else:
                in1 = w
    return out0, out1, in0, in1


@wp.func
def _wave_pair64(kt_world: wp.vec3d, m: wp.vec3, med: UniaxialMedium, known: int, k_known: wp.vec3d):
    # the two waves leaving into ``med`` along m (``_side_waves64``)
    out0, out1, in0, in1 = _side_waves64(kt_world, m, med, known, k_known)
    return out0, out1


@wp.func
def biaxial_incident_wave(d: wp.vec3, mode: int, med: UniaxialMedium, normal: wp.vec3):
    """The propagating wave of unit wave normal ``d`` on sheet ``mode`` (0 fast, 1 slow) of the
    biaxial ``med``, its flux taken along ``-normal`` (an incident wave)."""
    ie = _inv_eps(med)
    s = wp.normalize(_principal(med.frame, d))
    n_f, d_f, n_s, d_s = _eigen_pair(s, ie)
    n = n_f
    dd = d_f
    if mode == 1:
        n = n_s
        dd = d_s
    return _propagating(med, s * n, _e_of_d(dd, ie), -normal)


@wp.func
def biaxial_wave_d(s: wp.vec3, mode: int, med: UniaxialMedium):
    """(index, unit D in principal coordinates as a float32 vec3) of sheet ``mode`` (0 fast,
    1 slow) for the unit wave normal ``s`` (world) in the biaxial ``med``."""
    ie = _inv_eps(med)
    n_f, d_f, n_s, d_s = _eigen_pair(wp.normalize(_principal(med.frame, s)), ie)
    n = n_f
    dd = d_f
    if mode == 1:
        n = n_s
        dd = d_s
    return wp.float32(n), wp.vec3(wp.float32(dd[0]), wp.float32(dd[1]), wp.float32(dd[2]))


@wp.func
def biaxial_kappa(mode: int, wave_normal: wp.vec3, med: UniaxialMedium, a_x: float, a_y: float, a_z: float):
    """Intensity absorption coefficient of the wave on sheet ``mode`` with unit ``wave_normal``
    in the biaxial ``med``: ``trichroic_kappa`` of its own D (principal alphas a_x, a_y, a_z)."""
    n, d = biaxial_wave_d(wave_normal, mode, med)
    return trichroic_kappa(d, wp.vec3(med.no, med.nb, med.ne), wp.vec3(a_x, a_y, a_z))


# ----------------------------------------------------------------------------------------------
# any medium: dispatch by kind


@wp.func
def medium_waves(kt: wp.vec3, m: wp.vec3, med: UniaxialMedium, normal: wp.vec3):
    """The two waves of tangential wave vector ``kt`` leaving into ``med`` along ``m``: s/p of an
    isotropic medium, o/e of a uniaxial one (``birefringence.py``), fast/slow of a biaxial one."""
    if is_biaxial(med):
        return biaxial_wave_pair(kt, m, med)
    return ordinary_wave(kt, m, med, normal), extraordinary_wave(kt, m, med, normal)


@wp.func
def medium_incident_wave(d: wp.vec3, mode: int, med: UniaxialMedium, normal: wp.vec3):
    """The incident wave of wave normal ``d`` and mode ``mode`` in any medium."""
    if is_biaxial(med):
        return biaxial_incident_wave(d, mode, med, normal)
    return incident_wave(d, mode, med, normal)


@wp.func
def medium_wave_normal(ray: wp.vec3, mode: int, med: UniaxialMedium):
    """The unit wave normal of the wave of mode ``mode`` whose unit ray (Poynting direction) is
    ``ray`` in any medium: itself in an isotropic medium and for an o-wave,
    ``birefringence.wave_normal_of_ray`` for an e-wave; in a biaxial crystal the fixed point
    k = k + ray - ray(k) (``biaxial_incident_wave``), which contracts by the walk-off's
    derivative (~ the birefringence): 6 steps return the wave normal within 1e-5 away from the
    optic axes (tests/test_wave_normal_of_ray.py), where the ray map is singular."""
    if mode < 0:
        return ray
    if not is_biaxial(med):
        return wave_normal_of_ray(ray, mode, med)
    k = ray
    for _i in range(6):
        w = biaxial_incident_wave(k, mode, med, ray)
        k = wp.normalize(k + ray - w.ray)
    return k


@wp.func
def wave_index(med: UniaxialMedium, mode: int, s: wp.vec3):
    """Effective index of the wave of mode ``mode`` (-1 isotropic, o/e, fast/slow) with unit wave
    normal ``s`` in ``med``."""
    if is_biaxial(med):
        n, d = biaxial_wave_d(s, mode, med)
        return n
    if mode == 1:
        return n_e_theta(wp.dot(s, med.axis), med.no, med.ne)
    return med.no


@wp.func
def fresnel_from_waves(
    inc: PlaneWave, ro: PlaneWave, re: PlaneWave, to: PlaneWave, te: PlaneWave, normal: wp.vec3, d: wp.vec3
):
    """The generalized Fresnel solution (eq. 5, ``birefringence.boundary_amplitudes``) of given
    waves: the incident ``inc`` (wave normal ``d``), reflected ``ro``/``re`` and transmitted
    ``to``/``te``, ``normal`` towards the incident side; refused (``solved`` = 0, zero
    amplitudes) where an outgoing wave would carry energy into the interface."""
    xr, xi, ok = boundary_amplitudes(inc, ro, re, to, te, normal, d)
    # a propagating outgoing wave must carry its energy away from the interface; where the root
    # classification cannot tell (a wave normal on an optic axis at grazing incidence, where the
    # sheets touch and every normal flux is ~0) the solve is refused rather than let an
    # interface return more power than arrives
    # (float32 rounding leaves grazing waves' fluxes at ~ -1e-7: the bound is 1e-4)
    if (ro.propagating == 1 and ro.flux < -1.0e-4) or (re.propagating == 1 and re.flux < -1.0e-4):
        ok = 0
    if (to.propagating == 1 and to.flux < -1.0e-4) or (te.propagating == 1 and te.flux < -1.0e-4):
        ok = 0
    if ok == 0:
        xr = wp.vec4(0.0)
        xi = wp.vec4(0.0)
    return interface_solution(inc, ro, re, to, te, xr, xi, ok)


@wp.struct
class EventWaves:
    """The crystal waves of one interface event with a biaxial side, solved once (phase matching:
    every wave of the event shares the tangential wave vector ``kt``).  A side's ``*_out`` leave
    the interface into it, ``*_in`` arrive from it (index 0 fast, 1 slow); unset for a side that
    is not biaxial (its closed-form waves are cheap and built per solve)."""

    kt: wp.vec3  # tangential wave vector / k0 (world)
    a_out0: PlaneWave
    a_out1: PlaneWave
    a_in0: PlaneWave
    a_in1: PlaneWave
    b_out0: PlaneWave
    b_out1: PlaneWave
    b_in0: PlaneWave
    b_in1: PlaneWave


@wp.func
def event_waves(w_a: wp.vec3, mode_a: int, nrm: wp.vec3, med_a: UniaxialMedium, med_b: UniaxialMedium):
    """The waves of a backward event whose parent leaves the interface into A (unit wave normal
    ``w_a``, mode ``mode_a``; ``nrm`` the unit normal on A's side): one quartic per biaxial side
    (``_side_waves64``; A's deflated by the parent's own exact root)."""
    ev = EventWaves()
    kp = wp.vec3d()
    k64 = wp.vec3d()
    known = int(0)
    if is_biaxial(med_a):
        fa = _frame64(med_a.frame)
        sp = wp.normalize(fa * _d3(w_a))
        n_f, d_f, n_s, d_s = _eigen_pair(sp, _inv_eps(med_a))
        n_p = n_f
        if mode_a == 1:
            n_p = n_s
        kp = sp * n_p
        k64 = wp.transpose(fa) * kp
        known = 1
    else:
        n_eff = med_a.no
        if mode_a == 1:
            n_eff = n_e_theta(wp.dot(w_a, med_a.axis), med_a.no, med_a.ne)
        k64 = _d3(w_a) * wp.float64(n_eff)
    nv = _d3(nrm)
    kt64 = k64 - nv * wp.dot(k64, nv)
    ev.kt = wp.vec3(wp.float32(kt64[0]), wp.float32(kt64[1]), wp.float32(kt64[2]))
    if is_biaxial(med_a):
        o0, o1, i0, i1 = _side_waves64(kt64, nrm, med_a, known, kp)
        ev.a_out0 = o0
        ev.a_out1 = o1
        ev.a_in0 = i0
        ev.a_in1 = i1
    if is_biaxial(med_b):
        o0, o1, i0, i1 = _side_waves64(kt64, -nrm, med_b, 0, wp.vec3d())
        ev.b_out0 = o0
        ev.b_out1 = o1
        ev.b_in0 = i0
        ev.b_in1 = i1
    return ev


@wp.func
def event_fresnel(
    ev: EventWaves, side: int, mode_in: int, nrm: wp.vec3, med_a: UniaxialMedium, med_b: UniaxialMedium
):
    """The generalized Fresnel solution (:func:`fresnel_from_waves`) of the incident wave of mode
    ``mode_in`` arriving from A (``side`` 0) or B (1) with the event's tangential wave vector,
    from the waves of :func:`event_waves` (closed forms for a side that is not biaxial).
    ``solved`` = 0 when that incident wave does not propagate."""
    n_into = nrm
    med_x = med_a
    med_y = med_b
    x_in0 = ev.a_in0
    x_in1 = ev.a_in1
    x_out0 = ev.a_out0
    x_out1 = ev.a_out1
    y_out0 = ev.b_out0
    y_out1 = ev.b_out1
    if side == 1:
        n_into = -nrm
        med_x = med_b
        med_y = med_a
        x_in0 = ev.b_in0
        x_in1 = ev.b_in1
        x_out0 = ev.b_out0
        x_out1 = ev.b_out1
        y_out0 = ev.a_out0
        y_out1 = ev.a_out1
    kt = ev.kt
    inc = PlaneWave()
    if is_biaxial(med_x):
        inc = x_in0
        if mode_in == 1:
            inc = x_in1
    else:
        # the time reverse of the wave leaving into X with tangential -kt
        wv = ordinary_wave(-kt, n_into, med_x, n_into)
        if mode_in == 1 and wp.dot(med_x.axis, med_x.axis) > 0.0:
            wv = extraordinary_wave(-kt, n_into, med_x, n_into)
        if wv.propagating == 1:
            inc = incident_wave(-wv.wave_normal, mode_in, med_x, n_into)
    if inc.propagating == 0:
        sol = InterfaceSolution()
        sol.solved = 0
        return sol
    if not is_biaxial(med_x):
        x_out0, x_out1 = medium_waves(kt, n_into, med_x, n_into)
    if not is_biaxial(med_y):
        y_out0, y_out1 = medium_waves(kt, -n_into, med_y, n_into)
    return fresnel_from_waves(inc, x_out0, x_out1, y_out0, y_out1, n_into, inc.wave_normal)


@wp.func
def crystal_fresnel(d: wp.vec3, mode: int, normal: wp.vec3, m1: UniaxialMedium, m2: UniaxialMedium):
    """Generalized Fresnel amplitudes (eq. 5) for any pair of media; the waves of each side from
    its own solver.  Without a biaxial side this is ``birefringence.generalized_fresnel``
    (unchanged numbers).  Solution fields ``*_o``/``*_e`` are waves 0/1 of each side (s/p, o/e
    or fast/slow)."""
    if not is_biaxial(m1) and not is_biaxial(m2):
        return generalized_fresnel(d, mode, normal, m1, m2)
    inc = medium_incident_wave(d, mode, m1, normal)
    kt = inc.k_re - normal * wp.dot(inc.k_re, normal)
    # the tangential wave vector in float64 (from the incident wave normal itself when it is in
    # a biaxial medium): the reflected roots then keep the energy balance near grazing incidence
    k64 = _d3(inc.k_re)
    kp = wp.vec3d()  # the incident wave vector in m1's principal frame
    near_axis = int(0)  # incident wave normal within ~1e-5 of an optic axis (a double root)
    if is_biaxial(m1):
        f1 = _frame64(m1.frame)
        sp = wp.normalize(f1 * _d3(d))
        n_f, d_f, n_s, d_s = _eigen_pair(sp, _inv_eps(m1))
        n1 = n_f
        if mode == 1:
            n1 = n_s
        kp = sp * n1
        k64 = wp.transpose(f1) * kp
        if n_s - n_f < wp.float64(1.0e-5):
            near_axis = 1
    nv = _d3(normal)
    kt64 = k64 - nv * wp.dot(k64, nv)
    ro = PlaneWave()
    re = PlaneWave()
    to = PlaneWave()
    te = PlaneWave()
    if is_biaxial(m1):
        # near an optic axis the incident root is double: deflate by it (_quartic_roots_known)
        ro, re = _wave_pair64(kt64, normal, m1, near_axis, kp)
    else:
        ro, re = medium_waves(kt, normal, m1, normal)
    if is_biaxial(m2):
        to, te = _wave_pair64(kt64, -normal, m2, 0, wp.vec3d())
    else:
        to, te = medium_waves(kt, -normal, m2, normal)
    return fresnel_from_waves(inc, ro, re, to, te, normal, d)


@wp.func
def crystal_fresnel_both(d: wp.vec3, normal: wp.vec3, m1: UniaxialMedium, m2: UniaxialMedium):
    """:func:`crystal_fresnel` for both polarizations (modes 0 and 1) of an incident wave of unit
    wave normal ``d`` in the non-biaxial ``m1``: (sol_0, sol_1), the outgoing waves solved once
    (one quartic for a biaxial ``m2`` instead of two)."""
    if not is_biaxial(m2):
        return generalized_fresnel(d, 0, normal, m1, m2), generalized_fresnel(d, 1, normal, m1, m2)
    inc0 = medium_incident_wave(d, 0, m1, normal)
    inc1 = medium_incident_wave(d, 1, m1, normal)
    kt = inc0.k_re - normal * wp.dot(inc0.k_re, normal)
    ro, re = medium_waves(kt, normal, m1, normal)
    k64 = _d3(inc0.k_re)
    nv = _d3(normal)
    kt64 = k64 - nv * wp.dot(k64, nv)
    to, te = _wave_pair64(kt64, -normal, m2, 0, wp.vec3d())
    return fresnel_from_waves(inc0, ro, re, to, te, normal, d), fresnel_from_waves(
        inc1, ro, re, to, te, normal, d
    )


# ----------------------------------------------------------------------------------------------
# private element-wise kernels

_vec5 = wp.types.vector(length=5, dtype=wp.float32)
_vec8 = wp.types.vector(length=8, dtype=wp.float32)
_vec15 = wp.types.vector(length=15, dtype=wp.float32)


@wp.func
def _frame_of(x: wp.vec3, y: wp.vec3, z: wp.vec3):
    return wp.mat33(x[0], x[1], x[2], y[0], y[1], y[2], z[0], z[1], z[2])


@wp.func
def _medium_of(n3: wp.vec3, axis: wp.vec3, x: wp.vec3, y: wp.vec3, z: wp.vec3):
    # n3 = (no, nb, ne): nb > 0 a biaxial crystal with frame rows x, y, z; else uniaxial/isotropic
    if n3[1] > 0.0:
        return biaxial_medium(n3[0], n3[1], n3[2], _frame_of(x, y, z), 0.0)
    return uniaxial_medium(n3[0], n3[2], axis)


@wp.kernel
def _waves_kernel(
    offset: int,
    d: wp.array(dtype=wp.vec3),
    normal: wp.array(dtype=wp.vec3),
    x: wp.array(dtype=wp.vec3),
    y: wp.array(dtype=wp.vec3),
    z: wp.array(dtype=wp.vec3),
    n1: wp.array(dtype=float),
    n3: wp.array(dtype=wp.vec3),
    out_k0: wp.array(dtype=wp.vec3),
    out_k1: wp.array(dtype=wp.vec3),
    out_r0: wp.array(dtype=wp.vec3),
    out_r1: wp.array(dtype=wp.vec3),
    out_n: wp.array(dtype=wp.vec2f),
):
    i = wp.tid() + offset
    nrm = normal[i]
    kin = d[i] * n1[i]
    kt = kin - nrm * wp.dot(kin, nrm)
    med = biaxial_medium(n3[i][0], n3[i][1], n3[i][2], _frame_of(x[i], y[i], z[i]), 0.0)
    w0, w1 = biaxial_wave_pair(kt, -nrm, med)
    zero = wp.vec3(0.0)
    out_k0[i] = zero
    out_r0[i] = zero
    out_k1[i] = zero
    out_r1[i] = zero
    nn = wp.vec2f(0.0, 0.0)
    if w0.propagating == 1:
        out_k0[i] = w0.wave_normal
        out_r0[i] = w0.ray
        nn[0] = w0.n
    if w1.propagating == 1:
        out_k1[i] = w1.wave_normal
        out_r1[i] = w1.ray
        nn[1] = w1.n
    out_n[i] = nn


@wp.kernel
def _fresnel_kernel(
    offset: int,
    d: wp.array(dtype=wp.vec3),
    normal: wp.array(dtype=wp.vec3),
    mode: wp.array(dtype=wp.int32),
    n31: wp.array(dtype=wp.vec3),
    ax1: wp.array(dtype=wp.vec3),
    x1: wp.array(dtype=wp.vec3),
    y1: wp.array(dtype=wp.vec3),
    z1: wp.array(dtype=wp.vec3),
    n32: wp.array(dtype=wp.vec3),
    ax2: wp.array(dtype=wp.vec3),
    x2: wp.array(dtype=wp.vec3),
    y2: wp.array(dtype=wp.vec3),
    z2: wp.array(dtype=wp.vec3),
    out_coef: wp.array(dtype=_vec8),
    out_k_re: wp.array(dtype=_vec15),
    out_k_im: wp.array(dtype=_vec15),
    out_e_re: wp.array(dtype=_vec15),
    out_e_im: wp.array(dtype=_vec15),
    out_ray: wp.array(dtype=_vec15),
    out_flux: wp.array(dtype=_vec5),
):
    i = wp.tid() + offset
    m1 = _medium_of(n31[i], ax1[i], x1[i], y1[i], z1[i])
    m2 = _medium_of(n32[i], ax2[i], x2[i], y2[i], z2[i])
    sol = crystal_fresnel(d[i], mode[i], normal[i], m1, m2)
    store_solution(sol, i, out_coef, out_k_re, out_k_im, out_e_re, out_e_im, out_ray, out_flux)


@wp.kernel
def _absorption_kernel(
    offset: int,
    s: wp.array(dtype=wp.vec3),
    mode: wp.array(dtype=wp.int32),
    x: wp.array(dtype=wp.vec3),
    y: wp.array(dtype=wp.vec3),
    z: wp.array(dtype=wp.vec3),
    n3: wp.array(dtype=wp.vec3),
    a3: wp.array(dtype=wp.vec3),
    out_kappa: wp.array(dtype=float),
    out_n: wp.array(dtype=float),
    out_d: wp.array(dtype=wp.vec3),
):
    i = wp.tid() + offset
    med = biaxial_medium(n3[i][0], n3[i][1], n3[i][2], _frame_of(x[i], y[i], z[i]), 0.0)
    out_kappa[i] = biaxial_kappa(mode[i], s[i], med, a3[i][0], a3[i][1], a3[i][2])
    n, d = biaxial_wave_d(s[i], mode[i], med)
    out_n[i] = n
    out_d[i] = d


# ----------------------------------------------------------------------------------------------
# NumPy wrappers


def optic_axial_angle(n_alpha, n_beta, n_gamma):
    """(2V in degrees, optic sign "+"/"-" per element as a bool array ``positive``) from the
    principal indices: sin^2 V_z = (n_a^-2 - n_b^-2) / (n_a^-2 - n_g^-2) (Born & Wolf §15.3.3);
    2V = 2 V_z when Z is the acute bisectrix (V_z <= 45°, optically positive), else 180° - 2 V_z."""
    a = np.asarray(n_alpha, dtype=np.float64)
    b = np.asarray(n_beta, dtype=np.float64)
    g = np.asarray(n_gamma, dtype=np.float64)
    if np.any(~np.isfinite(a + b + g)) or np.any(a <= 0) or np.any(a > b) or np.any(b > g) or np.any(a >= g):
        raise InputError(
            "principal indices must satisfy 0 < n_alpha <= n_beta <= n_gamma with n_alpha < n_gamma",
            field="n_alpha, n_beta, n_gamma",
            value=(float(np.min(a)), float(np.min(b)), float(np.min(g))),
        )
    s2 = (a**-2 - b**-2) / (a**-2 - g**-2)
    vz = np.degrees(np.arcsin(np.sqrt(np.clip(s2, 0.0, 1.0))))
    positive = vz <= 45.0
    return np.where(positive, 2.0 * vz, 180.0 - 2.0 * vz), positive


def _frames(crystal_axes, name: str = "crystal_axes") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    a = np.asarray(crystal_axes, dtype=np.float64)
    if a.ndim < 2 or a.shape[-2:] != (3, 3) or not np.all(np.isfinite(a)):
        raise InputError("crystal axes must be finite (..., 3, 3) arrays (rows X, Y, Z)", field=name)
    n = np.linalg.norm(a, axis=-1, keepdims=True)
    if np.any(n < 1e-12):
        raise InputError("crystal axes must be non-zero vectors", field=name)
    a = a / n
    g = np.einsum("...ij,...kj->...ik", a, a)
    if np.max(np.abs(g - np.eye(3))) > 1e-4 or np.any(np.linalg.det(a) < 0):
        raise InputError("crystal axes must be orthonormal and right-handed (Z = X x Y)", field=name)
    return a[..., 0, :], a[..., 1, :], a[..., 2, :]


def _unit(v, name: str) -> np.ndarray:
    a = np.asarray(v, dtype=np.float64)
    if a.ndim == 0 or a.shape[-1] != 3 or not np.all(np.isfinite(a)):
        raise InputError("expected finite 3-vectors", field=name)
    n = np.linalg.norm(a, axis=-1, keepdims=True)
    if np.any(n == 0):
        raise InputError("expected non-zero vectors", field=name)
    return a / n


def _principal_indices(n_alpha, n_beta, n_gamma) -> np.ndarray:
    optic_axial_angle(n_alpha, n_beta, n_gamma)  # validates the order
    return np.stack(np.broadcast_arrays(n_alpha, n_beta, n_gamma), axis=-1).astype(np.float64)


def biaxial_waves(direction, normal, crystal_axes, n1, n_alpha, n_beta, n_gamma, *, device=None):
    """Refraction from an isotropic medium of index ``n1`` into a biaxial crystal.

    ``crystal_axes`` (..., 3, 3): rows = principal axes X, Y, Z carrying n_alpha, n_beta, n_gamma;
    ``normal`` points to the incident side.  Returns ``(wave_normals (..., 2, 3),
    ray_directions (..., 2, 3), indices (..., 2))``: the two transmitted waves, fast first
    (sheet labels, see the module docstring); zero vectors and index 0 where a wave is
    evanescent."""
    x, y, z = _frames(crystal_axes)
    n1a = np.asarray(n1, dtype=np.float64)
    if np.any(~np.isfinite(n1a)) or np.any(n1a <= 0):
        raise InputError("incident index must be finite and positive", field="n1", value=n1)
    k0, k1, r0, r1, n = elementwise(
        _waves_kernel,
        [
            (_unit(direction, "direction"), wp.vec3),
            (_unit(normal, "normal"), wp.vec3),
            (x, wp.vec3),
            (y, wp.vec3),
            (z, wp.vec3),
            (n1a, wp.float32),
            (_principal_indices(n_alpha, n_beta, n_gamma), wp.vec3),
        ],
        [wp.vec3, wp.vec3, wp.vec3, wp.vec3, wp.vec2f],
        device=device,
    )
    k = np.stack([k0, k1], axis=-2).astype(np.float64)
    r = np.stack([r0, r1], axis=-2).astype(np.float64)
    return k, r, n.astype(np.float64)


def _medium_arrays(m, name: str):
    """(n3, axis, X, Y, Z) arrays of a medium: an index (isotropic), ``(no, ne, axis)`` (uniaxial)
    or ``(n_alpha, n_beta, n_gamma, crystal_axes)`` (biaxial)."""
    eye = np.eye(3)
    if isinstance(m, tuple) and len(m) == 4:
        na, nb, ng, axes = m
        x, y, z = _frames(axes, name + ".crystal_axes")
        return _principal_indices(na, nb, ng), np.zeros(3), x, y, z
    if isinstance(m, tuple) and len(m) == 3:
        no, ne, axis = m
        n3 = np.stack(np.broadcast_arrays(no, np.zeros_like(np.asarray(no, dtype=float)), ne), axis=-1)
        if np.any(n3[..., ::2] <= 0):
            raise InputError("indices must be positive", field=name)
        return n3, _unit(axis, name + ".axis"), eye[0], eye[1], eye[2]
    n = np.asarray(m, dtype=np.float64)
    if np.any(~np.isfinite(n)) or np.any(n <= 0):
        raise InputError("refractive index must be finite and positive", field=name, value=m)
    n3 = np.stack([n, np.zeros_like(n), n], axis=-1)
    return n3, np.zeros(3), eye[0], eye[1], eye[2]


def biaxial_fresnel_coefficients(direction, normal, medium1, medium2, *, mode=0, device=None):
    """Generalized Fresnel coefficients (eq. 5) with any media on either side
    (:func:`crystal_fresnel`): ``medium`` = an index, ``(no, ne, axis)`` or
    ``(n_alpha, n_beta, n_gamma, crystal_axes)``; ``mode`` the incident wave's (0/1: s/p, o/e or
    fast/slow).  Returns a ``birefringence.GeneralizedFresnelResult`` (waves: incident, r0, r1,
    t0, t1)."""
    a1 = _medium_arrays(medium1, "medium1")
    a2 = _medium_arrays(medium2, "medium2")
    mode_arr = np.asarray(mode, dtype=np.int32)
    if np.any((mode_arr != 0) & (mode_arr != 1)):
        raise InputError("incident mode must be 0 or 1", field="mode", allowed="0, 1")
    ins = [(_unit(direction, "direction"), wp.vec3), (_unit(normal, "normal"), wp.vec3), (mode_arr, wp.int32)]
    for a in (a1, a2):
        ins += [(v, wp.vec3) for v in a]
    return solution_result(*elementwise(_fresnel_kernel, ins, SOLUTION_OUTPUTS, device=device))


def biaxial_absorption(wave_normal, mode, crystal_axes, n_alpha, n_beta, n_gamma, alphas, *, device=None):
    """Intensity absorption coefficient of the wave on sheet ``mode`` (0 fast, 1 slow) with unit
    ``wave_normal`` (:func:`biaxial_kappa`; ``alphas`` (..., 3) the principal alpha_X, alpha_Y,
    alpha_Z, same units as the result)."""
    x, y, z = _frames(crystal_axes)
    kappa, _, _ = elementwise(
        _absorption_kernel,
        [
            (_unit(wave_normal, "wave_normal"), wp.vec3),
            (np.asarray(mode, dtype=np.int32), wp.int32),
            (x, wp.vec3),
            (y, wp.vec3),
            (z, wp.vec3),
            (_principal_indices(n_alpha, n_beta, n_gamma), wp.vec3),
            (np.asarray(alphas, dtype=np.float64), wp.vec3),
        ],
        [wp.float32, wp.float32, wp.vec3],
        device=device,
    )
    return kappa.astype(np.float64)


def principal_d(wave_normal, mode, crystal_axes, n_alpha, n_beta, n_gamma, *, device=None):
    """(index, unit D in principal coordinates) of sheet ``mode`` for unit wave normals."""
    x, y, z = _frames(crystal_axes)
    _, n, d = elementwise(
        _absorption_kernel,
        [
            (_unit(wave_normal, "wave_normal"), wp.vec3),
            (np.asarray(mode, dtype=np.int32), wp.int32),
            (x, wp.vec3),
            (y, wp.vec3),
            (z, wp.vec3),
            (_principal_indices(n_alpha, n_beta, n_gamma), wp.vec3),
            (np.zeros(3), wp.vec3),
        ],
        [wp.float32, wp.float32, wp.vec3],
        device=device,
    )
    return n.astype(np.float64), d.astype(np.float64)

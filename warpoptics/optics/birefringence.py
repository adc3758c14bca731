"""Uniaxial crystals: o/e waves, extraordinary refraction and reflection, generalized Fresnel
coefficients, pleochroic absorption.

All physics are ``@wp.func``s that the renderer's trace kernel calls per ray; each has a NumPy
wrapper (bottom of the file) that launches it through ``warpoptics.device.elementwise``.

Conventions (in full, with the derivations: docs/design/uniaxial_crystals.md):
- Wave vectors ``k`` are in units of k0 (``k = n s``, ``s`` the unit wave normal); evanescent
  waves have a complex ``k`` whose imaginary part points away from the interface.
- ``normal`` points to the *incident* side (``d . normal < 0``); reflected waves travel along
  ``+normal``, transmitted ones along ``-normal``.
- ``UniaxialMedium(no, ne, axis)``: real indices (absorption is applied by eq. 7 and 11) and a
  unit optic axis ``a``; ``axis = 0`` marks an isotropic medium, whose o/e frames are the s/p
  frames of the interface.
- o/e frames (Guy & Soler 2004 eq. 2): ``X_a = a x s / |a x s|``, ``Y_a = s x X_a``; the o-wave
  has D and E along X_a, the e-wave D along Y_a and ``E = eps^-1 D``.  Along the optic axis X_a
  falls back to the s-direction of ``fresnel.py``.
- ``1/n_e(theta)^2 = cos^2(theta)/no^2 + sin^2(theta)/ne^2``, ``cos(theta) = s . a``.
- Extraordinary wave vectors solve ``k^T M k = 1``, ``M = I/ne^2 + (1/no^2 - 1/ne^2) a a^T``,
  with the tangential ``k`` conserved; the root whose ray direction ``t = M k / |M k|`` (the
  Poynting direction) enters the new medium is taken (eq. 3-4, after Beyerle & McDermid 1998).
- Generalized Fresnel (eq. 5, McClain et al. 1993): continuity of tangential E and
  ``H ~ k x E`` (not the printed ``n h``, which breaks energy conservation for e-waves), with
  evanescent waves kept in the 4x4 system, so total reflection has its phase and ``|r| = 1``.
  Each wave's ``flux = Re(E x conj(H)) . m``, and ``sum |coef|^2 flux_out = flux_in``.
- Eq. 10 (the ``approx`` mode): isotropic Fresnel amplitudes between o/e frame rotations.
- Pleochroism (eq. 7): ``kappa_o = K_o``, ``kappa_e = K_o cos^2 + K_e (no/ne)^2 sin^2`` for the
  intensity (base e, 1/length); the field attenuation of eq. 11 is taken with ``kappa l / 2``
  so that the intensity decays by ``exp(-kappa l)`` (eq. 11 as printed squares it).

References: Guy & Soler 2004, "Graphics Gems Revisited", ACM TOG 23(3), §3.1 eq. 2-5, §3.2 eq.
6-7, §4.2 eq. 10-12; Beyerle & McDermid 1998, Appl. Opt. 37(34); McClain, Hillman & Chipman
1993, JOSA A 10(11); Born & Wolf, Principles of Optics, 7th ed., §15.3.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import warp as wp

from ..device import device_function, elementwise
from ..errors import InputError
from .absorption import attenuation_oe, pleochroic_kappa
from .fresnel import fresnel_amplitudes, reflect_direction, refract_direction
from .jones import Jones, frame_change, jones, jones_diag, jones_mul, jones_real, perpendicular

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "UniaxialMedium",
    "PlaneWave",
    "InterfaceSolution",
    "InterfaceJones",
    "uniaxial_medium",
    "n_e_theta",
    "oe_frame_x",
    "mode_field",
    "ordinary_wave",
    "extraordinary_wave",
    "generalized_fresnel",
    "interface_solution",
    "incident_wave",
    "wave_normal_of_ray",
    "boundary_amplitudes",
    "interface_jones",
    "interface_jones_approx",
    # NumPy wrappers
    "extraordinary_index",
    "refract_extraordinary",
    "reflect_extraordinary",
    "oe_polarizations",
    "GeneralizedFresnelResult",
    "store_solution",
    "solution_result",
    "SOLUTION_OUTPUTS",
    "generalized_fresnel_coefficients",
    "fresnel_matrices",
    "kappa_e",
    "attenuation",
]


@wp.struct
class UniaxialMedium:
    """The medium struct of every tracer: real ordinary/extraordinary indices and unit optic axis
    (zero vector: isotropic).  A biaxial crystal (``optics/biaxial.py``) sets ``nb`` > 0: then
    ``no``, ``nb``, ``ne`` are n_alpha, n_beta, n_gamma, ``frame`` holds the principal axes X, Y,
    Z (rows, world space), ``axis`` = Z (non-zero: a crystal) and ``alpha_y`` the absorption
    coefficient (1/mm) for D along Y at the medium's wavelength."""

    no: float
    ne: float
    axis: wp.vec3
    nb: float  # n_beta of a biaxial crystal; 0 for isotropic and uniaxial media
    frame: wp.mat33  # biaxial: rows = principal axes X, Y, Z (world)
    alpha_y: float  # biaxial: alpha for D along Y (1/mm, base e)


@wp.struct
class PlaneWave:
    """One plane wave at an interface (see the module docstring for the conventions)."""

    k_re: wp.vec3  # wave vector / k0 (n * wave normal when propagating)
    k_im: wp.vec3  # imaginary part, nonzero only for evanescent waves
    wave_normal: wp.vec3  # unit direction of k_re
    ray: wp.vec3  # unit Poynting (energy) direction; zero for evanescent waves
    n: float  # effective index |k| of a propagating wave (0 when evanescent)
    e_re: wp.vec3  # unit electric-field vibration direction (complex for evanescent waves)
    e_im: wp.vec3
    flux: float  # normal Poynting flux per unit |amplitude|^2 (0 when evanescent)
    propagating: int


@wp.struct
class InterfaceSolution:
    """Solution of eq. 5 for one incident wave: amplitudes and the five waves."""

    r_o: wp.vec2f
    r_e: wp.vec2f
    t_o: wp.vec2f
    t_e: wp.vec2f
    incident: PlaneWave
    ro: PlaneWave
    re: PlaneWave
    to: PlaneWave
    te: PlaneWave
    solved: int  # 0 if the system was singular (then all amplitudes are zero)


@wp.struct
class InterfaceJones:
    """Reflection and transmission Jones matrices between o/e (or s/p) frames.

    Rows: outgoing (o, e); columns: incident (o, e).  Frames: ``x = X_a`` of each wave's medium at
    its wave normal, ``y = wave_normal x x``.  Columns of waves that do not propagate are zero."""

    mr: Jones
    mt: Jones
    d_r: wp.vec3  # reflected wave normal (Snell / mirror; o-wave for the exact solution)
    d_t: wp.vec3  # transmitted wave normal (zero under total internal reflection)


# ----------------------------------------------------------------------------------------------
# media, indices and frames


@wp.func
def uniaxial_medium(no: float, ne: float, axis: wp.vec3):
    m = UniaxialMedium()
    m.no = no
    m.ne = ne
    m.axis = axis
    return m


@wp.func
def n_e_theta(cos_theta: float, no: float, ne: float):
    """n_e(theta): 1/n^2 = cos^2/no^2 + sin^2/ne^2, theta between wave normal and optic axis."""
    c2 = wp.min(cos_theta * cos_theta, 1.0)
    return no * ne / wp.sqrt(ne * ne * c2 + no * no * (1.0 - c2))


@wp.func
def _frame_axis(med: UniaxialMedium, normal: wp.vec3):
    # isotropic media use the interface normal as 'optic axis': o/e frames become s/p frames
    if wp.dot(med.axis, med.axis) == 0.0:
        return normal
    return med.axis


@wp.func
def oe_frame_x(s: wp.vec3, axis: wp.vec3, normal: wp.vec3):
    """X_a(s) = a x s / |a x s| (eq. 2), falling back to the s-direction ``normal x s`` along the
    optic axis and to ``perpendicular(normal)`` when s is also along the normal."""
    x = wp.cross(axis, s)
    l2 = wp.dot(x, x)
    if l2 > 1.0e-12:
        return x / wp.sqrt(l2)
    x = wp.cross(normal, s)
    l2 = wp.dot(x, x)
    if l2 > 1.0e-12:
        return x / wp.sqrt(l2)
    return perpendicular(normal)


@wp.func
def _eps_inv(v: wp.vec3, a: wp.vec3, no: float, ne: float):
    # eps^-1 v for eps = no^2 I + (ne^2 - no^2) a a^T
    return v / (no * no) + a * ((1.0 / (ne * ne) - 1.0 / (no * no)) * wp.dot(a, v))


@wp.func
def _index_metric(v: wp.vec3, a: wp.vec3, no: float, ne: float):
    # M v, M = I/ne^2 + (1/no^2 - 1/ne^2) a a^T (index ellipsoid k^T M k = 1 of e-waves)
    return v / (ne * ne) + a * ((1.0 / (no * no) - 1.0 / (ne * ne)) * wp.dot(a, v))


@wp.func
def _normalize_c(re: wp.vec3, im: wp.vec3):
    l2 = wp.dot(re, re) + wp.dot(im, im)
    if l2 <= 0.0:
        return re, im
    inv = 1.0 / wp.sqrt(l2)
    return re * inv, im * inv


@wp.func
def mode_field(wave: PlaneWave, extraordinary: int, med: UniaxialMedium, normal: wp.vec3):
    """Unit electric-field vibration direction (e_re, e_im) of the o (0) or e (1) mode of
    ``wave`` in ``med`` (eq. 2: D along X_a for o, along Y_a for e, E = eps^-1 D)."""
    a = _frame_axis(med, normal)
    if wave.propagating == 1:
        s = wave.wave_normal
        x = oe_frame_x(s, a, normal)
        if extraordinary == 0:
            return x, wp.vec3(0.0)
        y = wp.cross(s, x)
        if wp.dot(med.axis, med.axis) == 0.0:
            return y, wp.vec3(0.0)
        return wp.normalize(_eps_inv(y, a, med.no, med.ne)), wp.vec3(0.0)
    # evanescent wave, complex k: o: E ~ a x k ; e: E ~ no^2 a - (k.a) k (both solve
    # k x (k x E) + eps E = 0 for complex k)
    kr = wave.k_re
    ki = wave.k_im
    if extraordinary == 0:
        er = wp.cross(a, kr)
        ei = wp.cross(a, ki)
        if wp.dot(er, er) + wp.dot(ei, ei) < 1.0e-20:
            er = wp.normalize(wp.cross(normal, kr))
            ei = wp.vec3(0.0)
        return _normalize_c(er, ei)
    ka_r = wp.dot(kr, a)
    ka_i = wp.dot(ki, a)
    er = a * (med.no * med.no) - (kr * ka_r - ki * ka_i)
    ei = -(ki * ka_r + kr * ka_i)
    return _normalize_c(er, ei)


@wp.func
def _flux(kr: wp.vec3, ki: wp.vec3, er: wp.vec3, ei: wp.vec3, m: wp.vec3):
    # Re(E x conj(H)) . m with H = k x E (complex)
    hr = wp.cross(kr, er) - wp.cross(ki, ei)
    hi = wp.cross(kr, ei) + wp.cross(ki, er)
    return wp.dot(wp.cross(er, hr) + wp.cross(ei, hi), m)


@wp.func
def _finish(wave: PlaneWave, extraordinary: int, med: UniaxialMedium, normal: wp.vec3, m: wp.vec3):
    e_re, e_im = mode_field(wave, extraordinary, med, normal)
    wave.e_re = e_re
    wave.e_im = e_im
    if wave.propagating == 1:
        wave.flux = _flux(wave.k_re, wave.k_im, e_re, e_im, m)
    else:
        wave.flux = 0.0
    return wave


@wp.func
def ordinary_wave(kt: wp.vec3, m: wp.vec3, med: UniaxialMedium, normal: wp.vec3):
    """The o-wave (or the wave of an isotropic medium, index ``no``) with tangential wave vector
    ``kt`` travelling (or decaying) along the unit normal ``m`` into its medium.  Snell's law."""
    w = PlaneWave()
    q2 = med.no * med.no - wp.dot(kt, kt)
    if q2 >= 0.0:
        w.k_re = kt + m * wp.sqrt(q2)
        w.k_im = wp.vec3(0.0)
        w.wave_normal = wp.normalize(w.k_re)
        w.ray = w.wave_normal
        w.n = med.no
        w.propagating = 1
    else:
        w.k_re = kt
        w.k_im = m * wp.sqrt(-q2)
        w.wave_normal = wp.normalize(kt)
        w.ray = wp.vec3(0.0)
        w.n = 0.0
        w.propagating = 0
    return _finish(w, 0, med, normal, m)


@wp.func
def _e_wave_root(kt: wp.vec3, m: wp.vec3, q: float, med: UniaxialMedium, normal: wp.vec3):
    # the propagating e-wave k = kt + q m for a known root q of the index-ellipsoid quadratic
    a = _frame_axis(med, normal)
    w = PlaneWave()
    w.k_re = kt + m * q
    w.k_im = wp.vec3(0.0)
    w.wave_normal = wp.normalize(w.k_re)
    w.ray = wp.normalize(_index_metric(w.k_re, a, med.no, med.ne))
    w.n = wp.length(w.k_re)
    w.propagating = 1
    return _finish(w, 1, med, normal, m)


@wp.func
def _reflected_same_mode(inc: PlaneWave, extraordinary: int, med: UniaxialMedium, normal: wp.vec3):
    # The reflected wave of the incident wave's own mode, from the incident root by Vieta's
    # formula (q_r = -2b/A - q_in; q_r = -q_in for o-waves) instead of a square root: exact
    # energy bookkeeping at grazing incidence in float32, where sqrt(n^2 - kt^2) cancels.
    q_in = wp.dot(inc.k_re, normal)
    kt = inc.k_re - normal * q_in
    if extraordinary == 0:
        w = PlaneWave()
        w.k_re = kt - normal * q_in
        w.k_im = wp.vec3(0.0)
        w.wave_normal = wp.normalize(w.k_re)
        w.ray = w.wave_normal
        w.n = med.no
        w.propagating = 1
        return _finish(w, 0, med, normal, normal)
    a = _frame_axis(med, normal)
    mm = _index_metric(normal, a, med.no, med.ne)
    q = -2.0 * wp.dot(kt, mm) / wp.dot(normal, mm) - q_in
    return _e_wave_root(kt, normal, q, med, normal)


@wp.func
def extraordinary_wave(kt: wp.vec3, m: wp.vec3, med: UniaxialMedium, normal: wp.vec3):
    """The e-wave with tangential wave vector ``kt`` into the medium on the side of unit normal
    ``m``: k = kt + q m on the index ellipsoid k^T M k = 1, the root whose ray direction M k
    points along +m (eq. 3 for refraction with m = -normal, eq. 4 for internal reflection with
    m = +normal; Beyerle & McDermid 1998).  Evanescent (complex q, Im q > 0) when no real root."""
    a = _frame_axis(med, normal)
    mm = _index_metric(m, a, med.no, med.ne)
    qa = wp.dot(m, mm)
    qb = wp.dot(kt, mm)
    qc = wp.dot(kt, _index_metric(kt, a, med.no, med.ne)) - 1.0
    disc = qb * qb - qa * qc
    w = PlaneWave()
    if disc >= 0.0:
        return _e_wave_root(kt, m, (wp.sqrt(disc) - qb) / qa, med, normal)
    else:
        w.k_re = kt - m * (qb / qa)
        w.k_im = m * (wp.sqrt(-disc) / qa)
        w.wave_normal = wp.normalize(w.k_re)
        w.ray = wp.vec3(0.0)
        w.n = 0.0
        w.propagating = 0
    return _finish(w, 1, med, normal, m)


@wp.func
def _incident_wave(d: wp.vec3, extraordinary: int, med: UniaxialMedium, normal: wp.vec3):
    # propagating incident wave of wave normal d in mode o/e of med
    a = _frame_axis(med, normal)
    w = PlaneWave()
    n = med.no
    if extraordinary == 1:
        n = n_e_theta(wp.dot(d, a), med.no, med.ne)
    w.k_re = d * n
    w.k_im = wp.vec3(0.0)
    w.wave_normal = d
    w.n = n
    w.propagating = 1
    if extraordinary == 1:
        w.ray = wp.normalize(_index_metric(w.k_re, a, med.no, med.ne))
    else:
        w.ray = d
    return _finish(w, extraordinary, med, normal, -normal)


@wp.func
def incident_wave(d: wp.vec3, extraordinary: int, med: UniaxialMedium, normal: wp.vec3):
    """The propagating incident wave of unit wave normal ``d`` in mode o (0) / e (1) of a uniaxial
    or isotropic ``med`` (its flux taken along ``-normal``)."""
    return _incident_wave(d, extraordinary, med, normal)


@wp.func
def wave_normal_of_ray(s: wp.vec3, extraordinary: int, med: UniaxialMedium):
    """The unit wave normal of the o (0) or e (1) wave whose ray (Poynting direction) is the unit
    ``s`` in the uniaxial or isotropic ``med``: ``s`` itself for an o-wave; for an e-wave the
    inverse of the ray map ``s = M k / |M k|`` (M the index metric, so k is along M^-1 s:
    tan theta_k = (ne/no)^2 tan theta_s from the optic axis; Born & Wolf §15.3).  Pixel beams
    carry ray directions at their vertices and need each vertex's wave for its interfaces."""
    if extraordinary != 1 or wp.dot(med.axis, med.axis) == 0.0:
        return s
    a = med.axis
    return wp.normalize(s * (med.ne * med.ne) + a * ((med.no * med.no - med.ne * med.ne) * wp.dot(a, s)))


# ----------------------------------------------------------------------------------------------
# generalized Fresnel coefficients (eq. 5)


@wp.func
def _h(w: PlaneWave):
    # H = k x E (complex)
    hr = wp.cross(w.k_re, w.e_re) - wp.cross(w.k_im, w.e_im)
    hi = wp.cross(w.k_re, w.e_im) + wp.cross(w.k_im, w.e_re)
    return hr, hi


@wp.func
def _solve4(ar: wp.mat44, ai: wp.mat44, br: wp.vec4, bi: wp.vec4):
    """Complex 4x4 linear solve by Gaussian elimination with partial pivoting.
    Returns (x_re, x_im, ok)."""
    mr = ar
    mi = ai
    vr = br
    vi = bi
    ok = 1
    for col in range(4):
        piv = col
        best = mr[col, col] * mr[col, col] + mi[col, col] * mi[col, col]
        for r in range(col + 1, 4):
            v = mr[r, col] * mr[r, col] + mi[r, col] * mi[r, col]
            if v > best:
                best = v
                piv = r
        if best <= 0.0:
            ok = 0
        else:
            if piv != col:
                for c in range(4):
                    t = mr[col, c]
                    mr[col, c] = mr[piv, c]
                    mr[piv, c] = t
                    t = mi[col, c]
                    mi[col, c] = mi[piv, c]
                    mi[piv, c] = t
                t = vr[col]
                vr[col] = vr[piv]
                vr[piv] = t
                t = vi[col]
                vi[col] = vi[piv]
                vi[piv] = t
            pr = mr[col, col]
            pi = mi[col, col]
            for r in range(col + 1, 4):
                # f = m[r, col] / pivot
                nr = mr[r, col]
                ni = mi[r, col]
                fr = (nr * pr + ni * pi) / best
                fi = (ni * pr - nr * pi) / best
                for c in range(col, 4):
                    xr = mr[col, c]
                    xi = mi[col, c]
                    mr[r, c] = mr[r, c] - (fr * xr - fi * xi)
                    mi[r, c] = mi[r, c] - (fr * xi + fi * xr)
                xr = vr[col]
                xi = vi[col]
                vr[r] = vr[r] - (fr * xr - fi * xi)
                vi[r] = vi[r] - (fr * xi + fi * xr)
    xr_out = wp.vec4(0.0)
    xi_out = wp.vec4(0.0)
    if ok == 1:
        for kk in range(4):
            row = 3 - kk
            sr = vr[row]
            si = vi[row]
            for c in range(row + 1, 4):
                sr = sr - (mr[row, c] * xr_out[c] - mi[row, c] * xi_out[c])
                si = si - (mr[row, c] * xi_out[c] + mi[row, c] * xr_out[c])
            dr = mr[row, row]
            di = mi[row, row]
            d2 = dr * dr + di * di
            xr_out[row] = (sr * dr + si * di) / d2
            xi_out[row] = (si * dr - sr * di) / d2
    return xr_out, xi_out, ok


@wp.func
def boundary_amplitudes(
    inc: PlaneWave, ro: PlaneWave, re: PlaneWave, to: PlaneWave, te: PlaneWave, normal: wp.vec3, d: wp.vec3
):
    """The 4x4 boundary system of eq. 5 for any media: continuity of tangential E and H = k x E
    for the incident wave ``inc`` and the four outgoing waves (two reflected ``ro``, ``re``, two
    transmitted ``to``, ``te``; unit-|E| fields), dotted with two tangential vectors built from
    ``normal`` and the incident wave normal ``d``.  Returns (x_re, x_im, ok): the amplitudes of
    (ro, re, to, te).  The uniaxial (``generalized_fresnel``) and biaxial (``optics/biaxial.py``)
    solvers share it."""
    # two independent tangential vectors
    v1 = wp.cross(normal, d)
    if wp.dot(v1, v1) < 1.0e-12:
        v1 = perpendicular(normal)
    v1 = wp.normalize(v1)
    v2 = wp.cross(normal, v1)
    hro_r, hro_i = _h(ro)
    hre_r, hre_i = _h(re)
    hto_r, hto_i = _h(to)
    hte_r, hte_i = _h(te)
    hin_r, hin_i = _h(inc)
    ar = wp.mat44(0.0)
    ai = wp.mat44(0.0)
    br = wp.vec4(0.0)
    bi = wp.vec4(0.0)
    for row in range(2):
        v = v1
        if row == 1:
            v = v2
        # tangential E
        ar[row, 0] = -wp.dot(v, ro.e_re)
        ai[row, 0] = -wp.dot(v, ro.e_im)
        ar[row, 1] = -wp.dot(v, re.e_re)
        ai[row, 1] = -wp.dot(v, re.e_im)
        ar[row, 2] = wp.dot(v, to.e_re)
        ai[row, 2] = wp.dot(v, to.e_im)
        ar[row, 3] = wp.dot(v, te.e_re)
        ai[row, 3] = wp.dot(v, te.e_im)
        br[row] = wp.dot(v, inc.e_re)
        bi[row] = wp.dot(v, inc.e_im)
        # tangential H = k x E
        ar[row + 2, 0] = -wp.dot(v, hro_r)
        ai[row + 2, 0] = -wp.dot(v, hro_i)
        ar[row + 2, 1] = -wp.dot(v, hre_r)
        ai[row + 2, 1] = -wp.dot(v, hre_i)
        ar[row + 2, 2] = wp.dot(v, hto_r)
        ai[row + 2, 2] = wp.dot(v, hto_i)
        ar[row + 2, 3] = wp.dot(v, hte_r)
        ai[row + 2, 3] = wp.dot(v, hte_i)
        br[row + 2] = wp.dot(v, hin_r)
        bi[row + 2] = wp.dot(v, hin_i)
    return _solve4(ar, ai, br, bi)


@wp.func
def interface_solution(
    inc: PlaneWave,
    ro: PlaneWave,
    re: PlaneWave,
    to: PlaneWave,
    te: PlaneWave,
    xr: wp.vec4,
    xi: wp.vec4,
    ok: int,
):
    """The :class:`InterfaceSolution` of the five waves and the amplitudes (r_o, r_e, t_o, t_e) =
    xr + i xi of :func:`boundary_amplitudes` (``ok`` = 0: not solved)."""
    sol = InterfaceSolution()
    sol.r_o = wp.vec2f(xr[0], xi[0])
    sol.r_e = wp.vec2f(xr[1], xi[1])
    sol.t_o = wp.vec2f(xr[2], xi[2])
    sol.t_e = wp.vec2f(xr[3], xi[3])
    sol.incident = inc
    sol.ro = ro
    sol.re = re
    sol.to = to
    sol.te = te
    sol.solved = ok
    return sol


@wp.func
def generalized_fresnel(
    d: wp.vec3, extraordinary: int, normal: wp.vec3, m1: UniaxialMedium, m2: UniaxialMedium
):
    """Generalized Fresnel amplitudes (eq. 5) for an incident wave of unit wave normal ``d`` in
    mode o (0) or e (1) of medium ``m1`` hitting the interface to ``m2`` (``normal`` towards m1).

    Covers isotropic->uniaxial, uniaxial->isotropic, uniaxial->uniaxial and isotropic->isotropic
    (``axis = 0``: o/e = s/p).  Amplitudes relate unit-|E| fields: outgoing field =
    coefficient * incident amplitude * e_out."""
    inc = _incident_wave(d, extraordinary, m1, normal)
    kt = inc.k_re - normal * wp.dot(inc.k_re, normal)
    ro = PlaneWave()
    re = PlaneWave()
    if extraordinary == 0:
        ro = _reflected_same_mode(inc, 0, m1, normal)
        re = extraordinary_wave(kt, normal, m1, normal)
    else:
        ro = ordinary_wave(kt, normal, m1, normal)
        re = _reflected_same_mode(inc, 1, m1, normal)
    to = ordinary_wave(kt, -normal, m2, normal)
    te = extraordinary_wave(kt, -normal, m2, normal)
    xr, xi, ok = boundary_amplitudes(inc, ro, re, to, te, normal, d)
    return interface_solution(inc, ro, re, to, te, xr, xi, ok)


@wp.func
def _prop(c: wp.vec2f, w: PlaneWave):
    if w.propagating == 1:
        return c
    return wp.vec2f(0.0, 0.0)


@wp.func
def interface_jones(d: wp.vec3, normal: wp.vec3, m1: UniaxialMedium, m2: UniaxialMedium):
    """Reflection/transmission Jones matrices for a wave normal ``d`` incident from an
    *isotropic* ``m1`` (o/e = s/p; incident o and e share d) by two solutions of eq. 5.
    Entries to waves that do not propagate are zero (the 2x2 reduction under total
    reflection).  For a uniaxial m1 the incident o- and e-waves have different wave normals:
    call ``generalized_fresnel`` per incident mode instead."""
    so = generalized_fresnel(d, 0, normal, m1, m2)
    se = generalized_fresnel(d, 1, normal, m1, m2)
    out = InterfaceJones()
    out.mr = jones(_prop(so.r_o, so.ro), _prop(se.r_o, se.ro), _prop(so.r_e, so.re), _prop(se.r_e, se.re))
    out.mt = jones(_prop(so.t_o, so.to), _prop(se.t_o, se.to), _prop(so.t_e, so.te), _prop(se.t_e, se.te))
    out.d_r = so.ro.wave_normal
    out.d_t = wp.vec3(0.0)
    if so.to.propagating == 1:
        out.d_t = so.to.wave_normal
    return out


@wp.func
def interface_jones_approx(
    d: wp.vec3,
    normal: wp.vec3,
    m1: UniaxialMedium,
    m2: UniaxialMedium,
    n1: wp.vec2f,
    n2: wp.vec2f,
):
    """Eq. 10: isotropic Fresnel amplitudes for the single indices ``n1``, ``n2`` (complex
    allowed) rotated between the o/e frames of the media and the s/p frame of the interface:
    ``M^r = R_r diag(rs, rp) R_i``, ``M^t = R_t diag(ts, tp) R_i``.  Reflected and transmitted
    waves share one direction each (mirror and Snell with Re n1, Re n2); the o/e frames are taken
    on those directions (D directions X_a, Y_a of eq. 2).  Exact when no = ne."""
    a1 = _frame_axis(m1, normal)
    a2 = _frame_axis(m2, normal)
    cos_i = -wp.dot(d, normal)
    f = fresnel_amplitudes(cos_i, n1, n2)
    s = wp.cross(normal, d)
    if wp.dot(s, s) < 1.0e-12:
        s = perpendicular(normal)
    s = wp.normalize(s)
    d_r = reflect_direction(d, normal)
    d_t = refract_direction(d, normal, n1[0], n2[0])
    r_in = jones_real(frame_change(d, oe_frame_x(d, a1, normal), s))
    r_r = jones_real(frame_change(d_r, s, oe_frame_x(d_r, a1, normal)))
    out = InterfaceJones()
    out.mr = jones_mul(r_r, jones_mul(jones_diag(f.rs, f.rp), r_in))
    out.d_r = d_r
    out.d_t = d_t
    if wp.dot(d_t, d_t) > 0.0:
        r_t = jones_real(frame_change(d_t, s, oe_frame_x(d_t, a2, normal)))
        out.mt = jones_mul(r_t, jones_mul(jones_diag(f.ts, f.tp), r_in))
    else:
        out.mt = jones_real(wp.mat22(0.0))
    return out


# ----------------------------------------------------------------------------------------------
# pleochroic absorption (eq. 7 and 11)


# ----------------------------------------------------------------------------------------------
# private element-wise kernels

_vec5 = wp.types.vector(length=5, dtype=wp.float32)
_vec8 = wp.types.vector(length=8, dtype=wp.float32)
_vec15 = wp.types.vector(length=15, dtype=wp.float32)


@wp.kernel
def _n_e_kernel(
    offset: int,
    cos_theta: wp.array(dtype=float),
    no: wp.array(dtype=float),
    ne: wp.array(dtype=float),
    k_o: wp.array(dtype=float),
    k_e: wp.array(dtype=float),
    length: wp.array(dtype=float),
    out_n: wp.array(dtype=float),
    out_kappa: wp.array(dtype=float),
    out_att: wp.array(dtype=wp.vec2f),
):
    i = wp.tid() + offset
    out_n[i] = n_e_theta(cos_theta[i], no[i], ne[i])
    ke = pleochroic_kappa(cos_theta[i], k_o[i], k_e[i], no[i], ne[i])
    out_kappa[i] = ke
    a = attenuation_oe(k_o[i], ke, length[i])
    out_att[i] = wp.vec2f(a.re[0, 0], a.re[1, 1])


@wp.kernel
def _e_direction_kernel(
    offset: int,
    d: wp.array(dtype=wp.vec3),
    normal: wp.array(dtype=wp.vec3),
    axis: wp.array(dtype=wp.vec3),
    n_in: wp.array(dtype=float),
    no: wp.array(dtype=float),
    ne: wp.array(dtype=float),
    side: wp.array(dtype=float),
    out_k: wp.array(dtype=wp.vec3),
    out_ray: wp.array(dtype=wp.vec3),
    out_n: wp.array(dtype=float),
):
    # side = -1: refraction (new wave along -normal); +1: internal reflection (along +normal)
    i = wp.tid() + offset
    nrm = normal[i]
    kin = d[i] * n_in[i]
    kt = kin - nrm * wp.dot(kin, nrm)
    med = uniaxial_medium(no[i], ne[i], axis[i])
    w = extraordinary_wave(kt, nrm * side[i], med, nrm)
    if w.propagating == 1:
        out_k[i] = w.wave_normal
        out_ray[i] = w.ray
        out_n[i] = w.n
    else:
        out_k[i] = wp.vec3(0.0)
        out_ray[i] = wp.vec3(0.0)
        out_n[i] = 0.0


@wp.kernel
def _oe_frame_kernel(
    offset: int,
    s: wp.array(dtype=wp.vec3),
    axis: wp.array(dtype=wp.vec3),
    normal: wp.array(dtype=wp.vec3),
    no: wp.array(dtype=float),
    ne: wp.array(dtype=float),
    out_x: wp.array(dtype=wp.vec3),
    out_y: wp.array(dtype=wp.vec3),
    out_ee: wp.array(dtype=wp.vec3),
):
    i = wp.tid() + offset
    med = uniaxial_medium(no[i], ne[i], axis[i])
    w = _incident_wave(s[i], 1, med, normal[i])
    a = _frame_axis(med, normal[i])
    x = oe_frame_x(s[i], a, normal[i])
    out_x[i] = x
    out_y[i] = wp.cross(s[i], x)
    out_ee[i] = w.e_re


@wp.func
def _pack_wave(w: PlaneWave, j: int, kv: _vec15, kiv: _vec15, erv: _vec15, eiv: _vec15, rayv: _vec15):
    for c in range(3):
        kv[3 * j + c] = w.k_re[c]
        kiv[3 * j + c] = w.k_im[c]
        erv[3 * j + c] = w.e_re[c]
        eiv[3 * j + c] = w.e_im[c]
        rayv[3 * j + c] = w.ray[c]
    return kv, kiv, erv, eiv, rayv


@wp.func
def store_solution(
    sol: InterfaceSolution,
    i: int,
    out_coef: wp.array(dtype=_vec8),
    out_k_re: wp.array(dtype=_vec15),
    out_k_im: wp.array(dtype=_vec15),
    out_e_re: wp.array(dtype=_vec15),
    out_e_im: wp.array(dtype=_vec15),
    out_ray: wp.array(dtype=_vec15),
    out_flux: wp.array(dtype=_vec5),
):
    """Row ``i`` of the NumPy wrappers' outputs of one interface solution (amplitudes r_o, r_e,
    t_o, t_e; the five waves' k, E, ray and flux): the uniaxial and the biaxial wrapper share it."""
    out_coef[i] = _vec8(
        sol.r_o[0], sol.r_o[1], sol.r_e[0], sol.r_e[1], sol.t_o[0], sol.t_o[1], sol.t_e[0], sol.t_e[1]
    )
    kv = _vec15()
    kiv = _vec15()
    erv = _vec15()
    eiv = _vec15()
    rayv = _vec15()
    kv, kiv, erv, eiv, rayv = _pack_wave(sol.incident, 0, kv, kiv, erv, eiv, rayv)
    kv, kiv, erv, eiv, rayv = _pack_wave(sol.ro, 1, kv, kiv, erv, eiv, rayv)
    kv, kiv, erv, eiv, rayv = _pack_wave(sol.re, 2, kv, kiv, erv, eiv, rayv)
    kv, kiv, erv, eiv, rayv = _pack_wave(sol.to, 3, kv, kiv, erv, eiv, rayv)
    kv, kiv, erv, eiv, rayv = _pack_wave(sol.te, 4, kv, kiv, erv, eiv, rayv)
    out_k_re[i] = kv
    out_k_im[i] = kiv
    out_e_re[i] = erv
    out_e_im[i] = eiv
    out_ray[i] = rayv
    out_flux[i] = _vec5(sol.incident.flux, sol.ro.flux, sol.re.flux, sol.to.flux, sol.te.flux)


#: the output dtypes of :func:`store_solution`, for ``device.elementwise``
SOLUTION_OUTPUTS = [_vec8, _vec15, _vec15, _vec15, _vec15, _vec15, _vec5]


@wp.kernel
def _generalized_fresnel_kernel(
    offset: int,
    d: wp.array(dtype=wp.vec3),
    normal: wp.array(dtype=wp.vec3),
    mode: wp.array(dtype=wp.int32),
    no1: wp.array(dtype=float),
    ne1: wp.array(dtype=float),
    axis1: wp.array(dtype=wp.vec3),
    no2: wp.array(dtype=float),
    ne2: wp.array(dtype=float),
    axis2: wp.array(dtype=wp.vec3),
    out_coef: wp.array(dtype=_vec8),
    out_k_re: wp.array(dtype=_vec15),
    out_k_im: wp.array(dtype=_vec15),
    out_e_re: wp.array(dtype=_vec15),
    out_e_im: wp.array(dtype=_vec15),
    out_ray: wp.array(dtype=_vec15),
    out_flux: wp.array(dtype=_vec5),
):
    i = wp.tid() + offset
    m1 = uniaxial_medium(no1[i], ne1[i], axis1[i])
    m2 = uniaxial_medium(no2[i], ne2[i], axis2[i])
    sol = generalized_fresnel(d[i], mode[i], normal[i], m1, m2)
    store_solution(sol, i, out_coef, out_k_re, out_k_im, out_e_re, out_e_im, out_ray, out_flux)


@wp.kernel
def _interface_jones_kernel(
    offset: int,
    d: wp.array(dtype=wp.vec3),
    normal: wp.array(dtype=wp.vec3),
    no1: wp.array(dtype=float),
    ne1: wp.array(dtype=float),
    axis1: wp.array(dtype=wp.vec3),
    no2: wp.array(dtype=float),
    ne2: wp.array(dtype=float),
    axis2: wp.array(dtype=wp.vec3),
    n1_iso: wp.array(dtype=wp.vec2f),
    n2_iso: wp.array(dtype=wp.vec2f),
    approx: int,
    out_mr: wp.array(dtype=_vec8),
    out_mt: wp.array(dtype=_vec8),
):
    i = wp.tid() + offset
    m1 = uniaxial_medium(no1[i], ne1[i], axis1[i])
    m2 = uniaxial_medium(no2[i], ne2[i], axis2[i])
    r = InterfaceJones()
    if approx == 1:
        r = interface_jones_approx(d[i], normal[i], m1, m2, n1_iso[i], n2_iso[i])
    else:
        r = interface_jones(d[i], normal[i], m1, m2)
    a = _vec8()
    b = _vec8()
    for p in range(2):
        for q in range(2):
            a[4 * p + 2 * q] = r.mr.re[p, q]
            a[4 * p + 2 * q + 1] = r.mr.im[p, q]
            b[4 * p + 2 * q] = r.mt.re[p, q]
            b[4 * p + 2 * q + 1] = r.mt.im[p, q]
    out_mr[i] = a
    out_mt[i] = b


# ----------------------------------------------------------------------------------------------
# NumPy wrappers


def _unit(v, name: str) -> np.ndarray:
    a = np.asarray(v, dtype=np.float64)
    if a.ndim == 0 or a.shape[-1] != 3:
        raise InputError("expected 3-vectors (last axis of length 3)", field=name, value=np.shape(v))
    n = np.linalg.norm(a, axis=-1, keepdims=True)
    if not np.all(np.isfinite(a)) or np.any(n == 0):
        raise InputError("expected finite non-zero vectors", field=name)
    return a / n


def _axis(v, name: str = "axis") -> np.ndarray:
    # zero vector allowed: isotropic medium
    a = np.asarray(v, dtype=np.float64)
    if a.ndim == 0 or a.shape[-1] != 3 or not np.all(np.isfinite(a)):
        raise InputError("optic axis must be finite 3-vectors (zero for an isotropic medium)", field=name)
    n = np.linalg.norm(a, axis=-1, keepdims=True)
    return np.where(n > 0, a / np.where(n > 0, n, 1.0), 0.0)


def _index(v, name: str) -> np.ndarray:
    a = np.asarray(v, dtype=np.float64)
    bad = ~np.isfinite(a) | (a <= 0)
    if np.any(bad):
        raise InputError(
            "refractive index must be finite and positive",
            field=name,
            value=a[bad].flat[0].item(),
            allowed="> 0",
        )
    return a


def _finite(value, name: str) -> np.ndarray:
    """``value`` as an array, or an InputError naming the argument and its first NaN/Inf."""
    a = np.asarray(value)
    bad = ~np.isfinite(a)
    if np.any(bad):
        raise InputError("must be finite", field=name, value=a[bad].flat[0], allowed="finite numbers")
    return a


def _medium(m, name: str):
    """(no, ne, axis) from a scalar (isotropic) or a tuple (no, ne, axis)."""
    if isinstance(m, tuple):
        if len(m) != 3:
            raise InputError("a uniaxial medium is (no, ne, axis)", field=name, value=m)
        no, ne, axis = m
        return _index(no, name + ".no"), _index(ne, name + ".ne"), _axis(axis, name + ".axis")
    n = _index(m, name)
    return n, n, np.zeros(3)


@device_function(n_e_theta)
def extraordinary_index(cos_theta, no, ne, *, device=None) -> np.ndarray:
    """n_e(theta) for cos(theta) = wave normal . optic axis (see ``n_e_theta``)."""
    n, _, _ = _pleo(cos_theta, no, ne, 0.0, 0.0, 0.0, device)
    return n


def _pleo(cos_theta, no, ne, k_o, k_e, length, device):
    outs = elementwise(
        _n_e_kernel,
        [
            (np.clip(_finite(cos_theta, "cos_theta").astype(np.float64), -1.0, 1.0), wp.float32),
            (_index(no, "no"), wp.float32),
            (_index(ne, "ne"), wp.float32),
            (_finite(k_o, "k_o"), wp.float32),
            (_finite(k_e, "k_e"), wp.float32),
            (_finite(length, "length"), wp.float32),
        ],
        [wp.float32, wp.float32, wp.vec2f],
        device=device,
    )
    return [o.astype(np.float64) for o in outs]


@device_function(pleochroic_kappa)
def kappa_e(cos_theta, k_o, k_e, no, ne, *, device=None) -> np.ndarray:
    """Pleochroic absorbance of the e-ray, eq. 7: K_o cos^2 + K_e (no/ne)^2 sin^2 (cos theta =
    e wave normal . optic axis).  Same units as K_o, K_e (base e, 1/length)."""
    _, k, _ = _pleo(cos_theta, no, ne, k_o, k_e, 0.0, device)
    return k


@device_function(attenuation_oe)
def attenuation(cos_theta, k_o, k_e, no, ne, length, *, device=None) -> np.ndarray:
    """Diagonal of the o/e field attenuation matrix A(s) of eq. 11 (..., 2): exp(-kappa l/2),
    so that the intensities decay as exp(-kappa l) (eq. 6); kappa^e from eq. 7."""
    _, _, a = _pleo(cos_theta, no, ne, k_o, k_e, length, device)
    return a


def _e_dir(direction, normal, axis, n_in, no, ne, side, device, n_in_name="n1"):
    ax = _axis(axis)
    if np.any(np.linalg.norm(ax, axis=-1) == 0):
        raise InputError("optic axis must be non-zero for a uniaxial crystal", field="axis")
    k, ray, n = elementwise(
        _e_direction_kernel,
        [
            (_unit(direction, "direction"), wp.vec3),
            (_unit(normal, "normal"), wp.vec3),
            (ax, wp.vec3),
            (_index(n_in, n_in_name), wp.float32),
            (_index(no, "no"), wp.float32),
            (_index(ne, "ne"), wp.float32),
            (side, wp.float32),
        ],
        [wp.vec3, wp.vec3, wp.float32],
        device=device,
    )
    return k.astype(np.float64), ray.astype(np.float64), n.astype(np.float64)


@device_function(extraordinary_wave)
def refract_extraordinary(direction, normal, axis, n1, no, ne, *, return_index: bool = False, device=None):
    """Extraordinary refraction into a uniaxial crystal (Guy & Soler eq. 3; Beyerle & McDermid 1998).

    Parameters
    ----------
    direction : (..., 3) incident wave normal (unit; normalised here).
    normal : (..., 3) interface normal pointing to the incident side.
    axis : (..., 3) optic axis of the crystal.
    n1 : incident index: the isotropic medium's index, or the effective index of the incident
        wave when it comes from another crystal (``n_o``, or ``n_e(theta)`` of an e-wave).
    no, ne : ordinary and extraordinary indices of the crystal.

    Returns ``(wave_normal, ray_direction)`` as (..., 3) arrays: the unit e wave normal and the
    unit energy (Poynting) direction; zero vectors where the e-wave cannot propagate (total
    reflection).  With ``return_index=True`` also the effective index n_e(theta) (0 there).
    """
    k, ray, n = _e_dir(direction, normal, axis, n1, no, ne, -1.0, device)
    return (k, ray, n) if return_index else (k, ray)


@device_function(extraordinary_wave)
def reflect_extraordinary(direction, normal, axis, n_in, no, ne, *, return_index: bool = False, device=None):
    """Extraordinary internal reflection inside a uniaxial crystal (eq. 4; Beyerle & McDermid).

    ``direction`` is the incident wave normal inside the crystal, ``n_in`` its index (``no`` for
    an o-wave, ``n_e(theta)`` for an e-wave), ``normal`` points back into the crystal (the incident
    side).  Returns the reflected e ``(wave_normal, ray_direction)`` (zero when evanescent)."""
    k, ray, n = _e_dir(direction, normal, axis, n_in, no, ne, 1.0, device, "n_in")
    return (k, ray, n) if return_index else (k, ray)


@device_function(oe_frame_x)
def oe_polarizations(wave_normal, axis, no, ne, *, normal=(0.0, 0.0, 1.0), device=None):
    """Eq. 2 frames and eigenpolarizations for wave normals ``s`` in a uniaxial crystal.

    Returns ``(x_o, y_e, e_e)``: X_a(s) (o-wave D and E), Y_a(s) (e-wave D) and the unit e-wave
    electric field eps^-1 Y_a / |.|.  ``normal`` only picks the frame along the optic axis."""
    x, y, ee = elementwise(
        _oe_frame_kernel,
        [
            (_unit(wave_normal, "wave_normal"), wp.vec3),
            (_axis(axis), wp.vec3),
            (_unit(normal, "normal"), wp.vec3),
            (_index(no, "no"), wp.float32),
            (_index(ne, "ne"), wp.float32),
        ],
        [wp.vec3, wp.vec3, wp.vec3],
        device=device,
    )
    return x.astype(np.float64), y.astype(np.float64), ee.astype(np.float64)


@dataclass(frozen=True)
class GeneralizedFresnelResult:
    """Solution of eq. 5 per incident wave.  Wave order: incident, ro, re, to, te.

    coefficients : (..., 4) complex  r_o, r_e, t_o, t_e (unit-|E| fields)
    k : (..., 5, 3) complex          wave vectors / k0 (complex for evanescent waves)
    e : (..., 5, 3) complex          unit electric-field vibration directions
    ray : (..., 5, 3)                Poynting directions (zero for evanescent waves)
    flux : (..., 5)                  normal Poynting flux per unit |amplitude|^2
    propagating : (..., 4) bool      for ro, re, to, te
    """

    coefficients: np.ndarray
    k: np.ndarray
    e: np.ndarray
    ray: np.ndarray
    flux: np.ndarray
    propagating: np.ndarray

    def energy(self) -> np.ndarray:
        """(..., 4) fractions of the incident normal energy flux going to ro, re, to, te
        (zero where the incident wave carries no flux towards the surface, e.g. grazing)."""
        f_in = self.flux[..., :1]
        safe = np.where(f_in > 0, f_in, 1.0)
        return np.where(f_in > 0, np.abs(self.coefficients) ** 2 * self.flux[..., 1:] / safe, 0.0)


@device_function(generalized_fresnel)
def generalized_fresnel_coefficients(
    direction, normal, medium1, medium2, *, mode="o", device=None
) -> GeneralizedFresnelResult:
    """Generalized Fresnel coefficients of eq. 5 (Guy & Soler 2004; McClain et al. 1993).

    ``medium1``/``medium2`` are an index (isotropic) or ``(no, ne, axis)``; ``direction`` is the
    incident wave normal in medium 1 and ``mode`` ("o"/"e", or 0/1, array allowed) its mode (for
    an isotropic medium 1: "o" = s-polarized, "e" = p-polarized).  ``normal`` points to medium 1.
    """
    no1, ne1, ax1 = _medium(medium1, "medium1")
    no2, ne2, ax2 = _medium(medium2, "medium2")
    if isinstance(mode, str):
        if mode not in ("o", "e"):
            raise InputError("incident mode must be 'o' or 'e'", field="mode", value=mode, allowed="o, e")
        mode_arr = np.int32(mode == "e")
    else:
        mode_arr = np.asarray(mode, dtype=np.int32)
        if np.any((mode_arr != 0) & (mode_arr != 1)):
            raise InputError("incident mode must be 0 (o) or 1 (e)", field="mode", allowed="0, 1")
    coef, kr, ki, er, ei, ray, flux = elementwise(
        _generalized_fresnel_kernel,
        [
            (_unit(direction, "direction"), wp.vec3),
            (_unit(normal, "normal"), wp.vec3),
            (mode_arr, wp.int32),
            (no1, wp.float32),
            (ne1, wp.float32),
            (ax1, wp.vec3),
            (no2, wp.float32),
            (ne2, wp.float32),
            (ax2, wp.vec3),
        ],
        SOLUTION_OUTPUTS,
        device=device,
    )
    return solution_result(coef, kr, ki, er, ei, ray, flux)


def solution_result(coef, kr, ki, er, ei, ray, flux) -> GeneralizedFresnelResult:
    """The :class:`GeneralizedFresnelResult` of the arrays :func:`store_solution` wrote."""
    shape = coef.shape[:-1]
    c = coef.astype(np.float64)
    coefficients = c[..., 0::2] + 1j * c[..., 1::2]
    k = (kr.astype(np.float64) + 1j * ki.astype(np.float64)).reshape(*shape, 5, 3)
    e = (er.astype(np.float64) + 1j * ei.astype(np.float64)).reshape(*shape, 5, 3)
    ray3 = ray.astype(np.float64).reshape(*shape, 5, 3)
    propagating = np.linalg.norm(ray3[..., 1:, :], axis=-1) > 0
    return GeneralizedFresnelResult(coefficients, k, e, ray3, flux.astype(np.float64), propagating)


@device_function(interface_jones)
def fresnel_matrices(
    direction, normal, medium1, medium2, *, approx: bool = False, n1=None, n2=None, device=None
) -> tuple[np.ndarray, np.ndarray]:
    """Reflection and transmission Jones matrices (..., 2, 2) complex for incidence from an
    isotropic (or, with ``approx``, any) medium 1: rows outgoing (o, e), columns incident (s, p)
    = (o, e).  ``approx=False``: two solutions of eq. 5 (``interface_jones``); ``approx=True``:
    eq. 10 (``interface_jones_approx``) with single indices ``n1``, ``n2`` (default: the mean
    (no + ne)/2 of each medium)."""
    no1, ne1, ax1 = _medium(medium1, "medium1")
    no2, ne2, ax2 = _medium(medium2, "medium2")
    if not approx and np.any(np.linalg.norm(ax1, axis=-1) > 0) and np.any(no1 != ne1):
        raise InputError(
            "exact Jones matrices need an isotropic incident medium (use "
            "generalized_fresnel_coefficients per incident mode)",
            field="medium1",
        )
    n1v = 0.5 * (no1 + ne1) if n1 is None else n1
    n2v = 0.5 * (no2 + ne2) if n2 is None else n2
    n1c = np.asarray(n1v, dtype=np.complex128)
    n2c = np.asarray(n2v, dtype=np.complex128)
    mr, mt = elementwise(
        _interface_jones_kernel,
        [
            (_unit(direction, "direction"), wp.vec3),
            (_unit(normal, "normal"), wp.vec3),
            (no1, wp.float32),
            (ne1, wp.float32),
            (ax1, wp.vec3),
            (no2, wp.float32),
            (ne2, wp.float32),
            (ax2, wp.vec3),
            (np.stack([n1c.real, n1c.imag], axis=-1), wp.vec2f),
            (np.stack([n2c.real, n2c.imag], axis=-1), wp.vec2f),
        ],
        [_vec8, _vec8],
        extra=(int(bool(approx)),),
        device=device,
    )

    def cm(v):
        v = v.astype(np.float64)
        z = v[..., 0::2] + 1j * v[..., 1::2]
        return z.reshape(*z.shape[:-1], 2, 2)

    return cm(mr), cm(mt)

"""A plane wave through a plane-parallel plate: the two waves of a crystal added as amplitudes.

A plate of thickness ``d`` between two half-spaces of the same isotropic medium splits an
incident plane wave into the crystal's two waves (o and e, fast and slow, or s and p), each with
the incident tangential wave vector.  Both leave along the incident direction again, overlap
everywhere behind the plate and interfere: their complex amplitudes are added before any
intensity is formed.  This makes the interference colours of a thin section and the isochromes
of a conoscopic figure; adding their powers instead (:func:`plate_mode_jones` returns the two
waves apart) is the incoherent model of thick stones.

The laws composed: the faces' generalized Fresnel amplitudes (``biaxial.crystal_fresnel``, Guy
& Soler 2004 eq. 5), power-normalised by the waves' normal fluxes; the optical phase across the
plate, :func:`slab_phase`, ``2 pi (q - q_amb) d / lambda`` for ``k = k_t + q m`` (relative to the
ambient medium, so no plate is the identity); Bouguer–Lambert absorption along each wave's ray
with its own kappa (eq. 7; ``biaxial.biaxial_kappa``).  Only the directly transmitted light is
kept (multiple reflections between the faces, 0.2 % of the power for quartz in air, would add
Fabry–Perot fringes of that size).

Optical activity (quartz): :func:`plate_active_jones` couples the two linear waves by the
gyration (:func:`active_retarder_jones`, with :func:`gyration_rotatory_power`): along the optic
axis the plate turns the plane of vibration by rho d (the "bull's eye" between crossed
polarizers); without activity it is :func:`plate_mode_jones`'s coherent sum.

Frames: every Jones matrix maps components in the frame ``(x, k x x)`` of the incident direction
``k``, ``x = jones.s_vector(k, normal)``, to the same components behind the plate; ``normal``
is the plate normal on the side the light comes from (``k . normal < 0``).  ``|J e|^2`` is the
transmitted power fraction of a unit-power field ``e``.

References: Born & Wolf, Principles of Optics, 7th ed., §15.4; Guy & Soler 2004, eq. 5, 7;
Jones 1948, JOSA 38(8) 671-685 (linear and circular birefringence); Nye, Physical Properties
of Crystals (1985), ch. XIV; Yariv & Yeh, Optical Waves in Crystals (1984), §5.1.
"""

from __future__ import annotations

import math

import numpy as np
import warp as wp

from ..device import device_function, elementwise
from ..errors import InputError
from .absorption import bouguer_lambert, wave_kappa
from .biaxial import biaxial_kappa, biaxial_medium, crystal_fresnel, crystal_fresnel_both, is_biaxial
from .birefringence import InterfaceSolution, PlaneWave, UniaxialMedium, uniaxial_medium
from .complex import c_mul
from .fresnel import flux_ratio
from .jones import Jones, jones, jones_add, jones_mul, jones_real, jones_zero, s_vector

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "slab_phase",
    "wave_plate_jones",
    "plate_medium",
    "plate_mode_jones",
    "gyration_rotatory_power",
    "active_retarder_jones",
    "plate_active_jones",
    # NumPy wrappers
    "active_plate_jones",
    "active_retarders",
    "rotatory_powers",
    "plate_jones",
    "slab_phases",
    "wave_plates",
]

_TWO_PI = wp.constant(wp.float64(2.0 * math.pi))


@wp.func
def slab_phase(q: float, q_ref: float, thickness: float, wavelength: float):
    """exp(i 2 pi (q - q_ref) d / lambda) as a complex number: the phase a plane wave of normal
    wave-vector component ``q`` (units of k0) gains across a slab of ``thickness`` mm relative to
    one of component ``q_ref`` (``wavelength`` in nm, vacuum).  The product is formed and reduced
    in float64: at d = 1 mm the phase is ~1e4 rad."""
    ph = (
        _TWO_PI
        * (wp.float64(q) - wp.float64(q_ref))
        * wp.float64(thickness)
        * wp.float64(1.0e6)
        / wp.float64(wavelength)
    )
    ph = ph - _TWO_PI * wp.floor(ph / _TWO_PI)
    return wp.vec2f(float(wp.cos(ph)), float(wp.sin(ph)))


@wp.func
def wave_plate_jones(slow_angle: float, retardation_nm: float, wavelength: float):
    """Jones matrix, in the frame (x, y) of a collimated beam, of an ideal retarder (an accessory
    plate: no Fresnel loss, no dispersion of its retardation ``retardation_nm``) whose slow
    vibration direction is at ``slow_angle`` (radians, from x toward y): R(-t) diag(1,
    exp(i 2 pi Gamma / lambda)) R(t) with the fast direction first (Yariv & Yeh §5.1; the slow
    wave gains the larger phase, as in :func:`slab_phase`).  Gamma = 0 is the identity."""
    c = wp.cos(slow_angle)
    s = wp.sin(slow_angle)
    e = slab_phase(1.0, 0.0, retardation_nm * 1.0e-6, wavelength)
    # fast along (-s, c), slow along (c, s): J = f f^T + e * u u^T
    j = Jones()
    j.re = wp.mat22(s * s + e[0] * c * c, -s * c + e[0] * c * s, -s * c + e[0] * c * s, c * c + e[0] * s * s)
    j.im = wp.mat22(e[1] * c * c, e[1] * c * s, e[1] * c * s, e[1] * s * s)
    return j


@wp.func
def plate_medium(n3: wp.vec3, frame: wp.mat33):
    """The medium struct of a plate: ``n3`` = (n_alpha, n_beta, n_gamma) of a biaxial crystal
    (``n3[1] > 0``; ``frame`` rows = principal axes X, Y, Z in the world), else (n_o, 0, n_e) of a
    uniaxial crystal with its optic axis the row Z of ``frame`` (isotropic when n_o = n_e)."""
    if n3[1] > 0.0:
        return biaxial_medium(n3[0], n3[1], n3[2], frame, 0.0)
    axis = wp.vec3(frame[2, 0], frame[2, 1], frame[2, 2])
    if n3[0] == n3[2]:
        axis = wp.vec3(0.0, 0.0, 0.0)
    return uniaxial_medium(n3[0], n3[2], axis)


@wp.func
def _wave_kappa(wave: PlaneWave, mode: int, med: UniaxialMedium, alpha3: wp.vec3):
    # intensity absorption coefficient (1/mm) of a plate wave: the uniaxial/isotropic eq. 7 or
    # the biaxial kappa of its D; alpha3 = (alpha_o, -, alpha_e) or (alpha_X, alpha_Y, alpha_Z)
    if is_biaxial(med):
        return biaxial_kappa(mode, wave.wave_normal, med, alpha3[0], alpha3[1], alpha3[2])
    m = mode
    if wp.dot(med.axis, med.axis) == 0.0:
        m = -1
    return wave_kappa(m, wp.dot(wave.wave_normal, med.axis), alpha3[0], alpha3[2], med.no, med.ne)


@wp.func
def _scale_c(c: wp.vec2f, s: float):
    return wp.vec2f(c[0] * s, c[1] * s)


@wp.func
def _incident_basis(sol0: InterfaceSolution, sol1: InterfaceSolution, s: wp.vec3, y: wp.vec3):
    # field components along the two incident polarizations of the solutions, from (s, y)
    x0 = sol0.incident.e_re
    x1 = sol1.incident.e_re
    return jones_real(wp.mat22(wp.dot(x0, s), wp.dot(x0, y), wp.dot(x1, s), wp.dot(x1, y)))


@wp.func
def _plate_wave(
    mode: int,
    sol0: InterfaceSolution,
    sol1: InterfaceSolution,
    normal: wp.vec3,
    ambient: UniaxialMedium,
    plate: UniaxialMedium,
    thickness: float,
    alpha3: wp.vec3,
    s: wp.vec3,
    y: wp.vec3,
):
    """The parts of the plate's wave ``mode`` (0: o / fast / s, 1: e / slow / p):
    (ok, a0, a1, ux, uy, q, att, sign): ``ok`` 0 when it does not propagate; its entrance
    amplitudes (power-normalised) from the two incident polarizations of the solutions; the
    outgoing field components (along s and k x s) of a unit amplitude of it at the exit face,
    before ``sign``; its normal wave-vector component ``q`` (units of k0); the field
    attenuation ``att`` along its ray; ``sign`` = e_exit . e_wave, the sign of its field at the
    exit face relative to its own (the exit solution recomputes it)."""
    m = -normal
    wave = sol0.to
    c0 = sol0.t_o
    c1 = sol1.t_o
    if mode == 1:
        wave = sol0.te
        c0 = sol0.t_e
        c1 = sol1.t_e
    zero = wp.vec2f(0.0, 0.0)
    if wave.propagating == 0 or sol0.solved == 0 or sol1.solved == 0:
        return 0, zero, zero, zero, zero, 0.0, 0.0, 0.0
    # entrance: power amplitudes of this wave from the two incident polarizations
    a0 = _scale_c(c0, wp.sqrt(flux_ratio(sol0.incident.flux, wave.flux)))
    a1 = _scale_c(c1, wp.sqrt(flux_ratio(sol1.incident.flux, wave.flux)))
    # across the plate: absorption along the wave's ray
    cos_ray = wp.max(wp.dot(wave.ray, m), 1.0e-6)
    kappa = _wave_kappa(wave, mode, plate, alpha3)
    att = wp.sqrt(bouguer_lambert(kappa, thickness / cos_ray))
    # exit: the same wave incident on the exit face from inside (its field recomputed there
    # with the same sign convention; the dot product guards the sign)
    ex = crystal_fresnel(wave.wave_normal, mode, normal, plate, ambient)
    sign = wp.dot(ex.incident.e_re, wave.e_re)
    bo = _scale_c(ex.t_o, wp.sqrt(flux_ratio(ex.incident.flux, ex.to.flux)))
    be = _scale_c(ex.t_e, wp.sqrt(flux_ratio(ex.incident.flux, ex.te.flux)))
    ux = _scale_c(bo, wp.dot(ex.to.e_re, s)) + _scale_c(be, wp.dot(ex.te.e_re, s))
    uy = _scale_c(bo, wp.dot(ex.to.e_re, y)) + _scale_c(be, wp.dot(ex.te.e_re, y))
    return 1, a0, a1, ux, uy, wp.dot(wave.k_re, m), att, sign


@wp.func
def plate_mode_jones(
    k: wp.vec3,
    normal: wp.vec3,
    ambient: UniaxialMedium,
    plate: UniaxialMedium,
    thickness: float,
    wavelength: float,
    alpha3: wp.vec3,
):
    """(J_0, J_1): the Jones matrices, frame (s, k x s) in and out (module docstring), of the
    light a plane wave of unit direction ``k`` in the isotropic ``ambient`` medium sends through
    the plate on each of its two waves (0: o / fast / s, 1: e / slow / p).  The coherent plate is
    J_0 + J_1; an incoherent (thick-plate) model sums the coherency matrices of the two.

    ``thickness`` in mm, ``wavelength`` in nm, ``alpha3`` the plate's intensity absorption
    coefficients in 1/mm (see :func:`_wave_kappa`).  A wave that cannot propagate in the plate
    (total reflection at the entrance) gives a zero matrix."""
    m = -normal  # into the plate, toward the exit face
    s = s_vector(k, normal)
    y = wp.cross(k, s)
    sol0, sol1 = crystal_fresnel_both(k, normal, ambient, plate)
    b_in = _incident_basis(sol0, sol1, s, y)
    q_amb = wp.dot(sol0.incident.k_re, m)
    out0 = jones_zero()
    out1 = jones_zero()
    for mode in range(2):
        ok, a0, a1, ux, uy, q, att, sign = _plate_wave(
            mode, sol0, sol1, normal, ambient, plate, thickness, alpha3, s, y
        )
        if ok == 0:
            continue
        ph = slab_phase(q, q_amb, thickness, wavelength)
        f = _scale_c(ph, att * sign)
        ux = c_mul(ux, f)
        uy = c_mul(uy, f)
        # outer product (ux, uy)^T (a0, a1) in the solutions' incident frame, then from (s, y)
        jm = jones_mul(jones(c_mul(ux, a0), c_mul(ux, a1), c_mul(uy, a0), c_mul(uy, a1)), b_in)
        if mode == 0:
            out0 = jm
        else:
            out1 = jm
    return out0, out1


@wp.func
def gyration_rotatory_power(cos_axis: float, rho_axis: float, perpendicular_ratio: float):
    """Rotatory power (rad/mm, the sign of ``rho_axis``) of a uniaxial optically active crystal
    for a wave normal at angle theta to the optic axis (``cos_axis`` = cos theta):
    rho(theta) = rho_axis (cos^2 theta + r sin^2 theta), r = G11 / G33.  The rotation per unit
    path is pi G / (lambda n) with the gyration scalar G = G33 cos^2 theta + G11 sin^2 theta of
    a crystal of class 32 (Nye 1985, Physical Properties of Crystals, ch. XIV;
    Born & Wolf ch. XV), so that its direction dependence is that of G (the small difference of
    the two waves' indices in pi / (lambda n) is neglected)."""
    c2 = cos_axis * cos_axis
    return rho_axis * (c2 + perpendicular_ratio * (1.0 - c2))


@wp.func
def active_retarder_jones(retardation: wp.float64, rotation: wp.float64):
    """Jones matrix, in the basis of the two linear waves (0, 1) of a birefringent plate
    (right-handed about the propagation direction), of the plate with optical activity, relative
    to the mean phase of the two waves: the solution of the coupled-wave equations
    dE/dz = [i (beta / 2) diag(-1, 1) + rho [[0, -1], [1, 0]]] E over the plate, with the
    linear ``retardation`` delta = beta d = phi_1 - phi_0 (rad; wave 1 gains the larger phase
    when delta > 0, as in :func:`slab_phase`) and the ``rotation`` tau = rho d (rad, positive
    from wave 0 toward wave 1).  The generator is traceless with square -Omega^2 I, so that
    exp(A d) = cos(Omega) I + sin(Omega) / Omega A d, Omega = sqrt(delta^2 / 4 + tau^2): the
    elliptic retarder (Jones 1948, "A new calculus for the treatment of optical systems VII",
    JOSA 38, 671, the N-matrix of a medium with both linear and circular birefringence).
    tau = 0: diag(exp(-i delta / 2), exp(i delta / 2)); delta = 0: a rotation by tau.
    Computed in float64: delta reaches 1e4 rad in a millimetre plate."""
    half = retardation * wp.float64(0.5)
    omega = wp.sqrt(half * half + rotation * rotation)
    c = wp.cos(omega)
    sinc = wp.float64(1.0)
    if omega > wp.float64(1.0e-12):
        sinc = wp.sin(omega) / omega
    j = Jones()
    j.re = wp.mat22(float(c), float(-sinc * rotation), float(sinc * rotation), float(c))
    j.im = wp.mat22(float(-sinc * half), 0.0, 0.0, float(sinc * half))
    return j


@wp.func
def plate_active_jones(
    k: wp.vec3,
    normal: wp.vec3,
    ambient: UniaxialMedium,
    plate: UniaxialMedium,
    thickness: float,
    wavelength: float,
    alpha3: wp.vec3,
    rho_axis: float,
    perpendicular_ratio: float,
):
    """The coherent Jones matrix (frames of :func:`plate_mode_jones`) of a uniaxial plate with
    optical activity: the plate's two linear waves, entering and leaving as in
    :func:`plate_mode_jones`, coupled inside by the gyration (:func:`active_retarder_jones`)
    instead of crossing independently.  ``rho_axis``: rotatory power along the optic axis,
    rad/mm, positive for a rotation counter-clockwise about the propagation direction (from x
    toward y for light along +z; seen by an observer facing the light source this is to the
    left: laevorotatory); ``perpendicular_ratio`` = G11 / G33 (:func:`gyration_rotatory_power`).

    Approximations (the coupled-wave model of a weakly active crystal): the
    two waves' small difference in direction (walk-off, refraction) is kept in their own
    Fresnel factors and phases but not in the coupling, which uses their mean normal
    wave-vector component; absorption is split symmetrically around the coupling
    (diag(sqrt a) K diag(sqrt a)), exact for equal absorption of the two waves or no activity.
    ``rho_axis = 0`` gives the sum of :func:`plate_mode_jones`'s two matrices (to rounding)."""
    m = -normal
    s = s_vector(k, normal)
    y = wp.cross(k, s)
    sol0, sol1 = crystal_fresnel_both(k, normal, ambient, plate)
    b_in = _incident_basis(sol0, sol1, s, y)
    q_amb = wp.dot(sol0.incident.k_re, m)
    ok0, p0, p1, ux0, uy0, q0, att0, sg0 = _plate_wave(
        0, sol0, sol1, normal, ambient, plate, thickness, alpha3, s, y
    )
    ok1, r0, r1, ux1, uy1, q1, att1, sg1 = _plate_wave(
        1, sol0, sol1, normal, ambient, plate, thickness, alpha3, s, y
    )
    if ok0 == 0 or ok1 == 0:
        # one wave totally reflected at the entrance: nothing to couple to
        j0, j1 = plate_mode_jones(k, normal, ambient, plate, thickness, wavelength, alpha3)
        return jones_add(j0, j1)
    # the internal basis (wave 0, wave 1) and its handedness about the mean wave normal
    w0 = sol0.to.e_re
    w1 = sol0.te.e_re
    kn = wp.normalize(sol0.to.wave_normal + sol0.te.wave_normal)
    hand = 1.0
    if wp.dot(wp.cross(w0, w1), kn) < 0.0:
        hand = -1.0
    q_mean = 0.5 * (q0 + q1)
    rho = gyration_rotatory_power(wp.dot(kn, plate.axis), rho_axis, perpendicular_ratio)
    # path along the mean wave normal, d / cos(theta_n) = d |k| / q
    path = thickness * (0.5 * (sol0.to.n + sol0.te.n)) / wp.max(q_mean, 1.0e-6)
    delta = (
        _TWO_PI
        * (wp.float64(q1) - wp.float64(q0))
        * wp.float64(thickness)
        * wp.float64(1.0e6)
        / wp.float64(wavelength)
    )
    kc = active_retarder_jones(delta, wp.float64(hand * rho * path))
    # the mean phase exp(i (phi_0 + phi_1) / 2) as the product of each wave's phase over half
    # the thickness (each reduced in float64 by slab_phase; q_mean in float32 would not do)
    ph = c_mul(
        slab_phase(q0, q_amb, 0.5 * thickness, wavelength), slab_phase(q1, q_amb, 0.5 * thickness, wavelength)
    )
    g0 = wp.sqrt(att0)
    g1 = wp.sqrt(att1)
    # U (columns: the waves' exit fields, their exit signs included) . M . A (rows: entrance)
    u = jones(
        _scale_c(ux0, sg0 * g0), _scale_c(ux1, sg1 * g1), _scale_c(uy0, sg0 * g0), _scale_c(uy1, sg1 * g1)
    )
    a = jones(
        _scale_c(c_mul(p0, ph), g0),
        _scale_c(c_mul(p1, ph), g0),
        _scale_c(c_mul(r0, ph), g1),
        _scale_c(c_mul(r1, ph), g1),
    )
    return jones_mul(jones_mul(u, jones_mul(kc, a)), b_in)


# ----------------------------------------------------------------------------------------------
# private element-wise kernels (offset first, see warpoptics.device)


@wp.kernel
def _plate_jones_kernel(
    offset: int,
    k: wp.array(dtype=wp.vec3),
    wavelength: wp.array(dtype=float),
    n3: wp.array(dtype=wp.vec3),
    alpha3: wp.array(dtype=wp.vec3),
    thickness: wp.array(dtype=float),
    n_ambient: wp.array(dtype=float),
    normal: wp.vec3,
    frame: wp.mat33,
    out_s: wp.array(dtype=wp.vec3),
    out_j0: wp.array(dtype=wp.vec4f),  # re00, re01, re10, re11
    out_j0i: wp.array(dtype=wp.vec4f),
    out_j1: wp.array(dtype=wp.vec4f),
    out_j1i: wp.array(dtype=wp.vec4f),
):
    i = wp.tid() + offset
    amb = uniaxial_medium(n_ambient[i], n_ambient[i], wp.vec3(0.0, 0.0, 0.0))
    med = plate_medium(n3[i], frame)
    d = wp.normalize(k[i])
    j0, j1 = plate_mode_jones(d, normal, amb, med, thickness[i], wavelength[i], alpha3[i])
    out_s[i] = s_vector(d, normal)
    out_j0[i] = wp.vec4f(j0.re[0, 0], j0.re[0, 1], j0.re[1, 0], j0.re[1, 1])
    out_j0i[i] = wp.vec4f(j0.im[0, 0], j0.im[0, 1], j0.im[1, 0], j0.im[1, 1])
    out_j1[i] = wp.vec4f(j1.re[0, 0], j1.re[0, 1], j1.re[1, 0], j1.re[1, 1])
    out_j1i[i] = wp.vec4f(j1.im[0, 0], j1.im[0, 1], j1.im[1, 0], j1.im[1, 1])


@wp.kernel
def _slab_phase_kernel(
    offset: int,
    q: wp.array(dtype=float),
    q_ref: wp.array(dtype=float),
    thickness: wp.array(dtype=float),
    wavelength: wp.array(dtype=float),
    out: wp.array(dtype=wp.vec2f),
):
    i = wp.tid() + offset
    out[i] = slab_phase(q[i], q_ref[i], thickness[i], wavelength[i])


@wp.kernel
def _wave_plate_kernel(
    offset: int,
    angle: wp.array(dtype=float),
    retardation: wp.array(dtype=float),
    wavelength: wp.array(dtype=float),
    out_re: wp.array(dtype=wp.vec4f),
    out_im: wp.array(dtype=wp.vec4f),
):
    i = wp.tid() + offset
    j = wave_plate_jones(angle[i], retardation[i], wavelength[i])
    out_re[i] = wp.vec4f(j.re[0, 0], j.re[0, 1], j.re[1, 0], j.re[1, 1])
    out_im[i] = wp.vec4f(j.im[0, 0], j.im[0, 1], j.im[1, 0], j.im[1, 1])


@wp.kernel
def _plate_active_kernel(
    offset: int,
    k: wp.array(dtype=wp.vec3),
    wavelength: wp.array(dtype=float),
    n3: wp.array(dtype=wp.vec3),
    alpha3: wp.array(dtype=wp.vec3),
    thickness: wp.array(dtype=float),
    n_ambient: wp.array(dtype=float),
    rho_axis: wp.array(dtype=float),
    perpendicular_ratio: wp.array(dtype=float),
    normal: wp.vec3,
    frame: wp.mat33,
    out_s: wp.array(dtype=wp.vec3),
    out_re: wp.array(dtype=wp.vec4f),
    out_im: wp.array(dtype=wp.vec4f),
):
    i = wp.tid() + offset
    amb = uniaxial_medium(n_ambient[i], n_ambient[i], wp.vec3(0.0, 0.0, 0.0))
    med = plate_medium(n3[i], frame)
    d = wp.normalize(k[i])
    j = plate_active_jones(
        d, normal, amb, med, thickness[i], wavelength[i], alpha3[i], rho_axis[i], perpendicular_ratio[i]
    )
    out_s[i] = s_vector(d, normal)
    out_re[i] = wp.vec4f(j.re[0, 0], j.re[0, 1], j.re[1, 0], j.re[1, 1])
    out_im[i] = wp.vec4f(j.im[0, 0], j.im[0, 1], j.im[1, 0], j.im[1, 1])


@wp.kernel
def _active_retarder_kernel(
    offset: int,
    retardation: wp.array(dtype=wp.float64),
    rotation: wp.array(dtype=wp.float64),
    out_re: wp.array(dtype=wp.vec4f),
    out_im: wp.array(dtype=wp.vec4f),
):
    i = wp.tid() + offset
    j = active_retarder_jones(retardation[i], rotation[i])
    out_re[i] = wp.vec4f(j.re[0, 0], j.re[0, 1], j.re[1, 0], j.re[1, 1])
    out_im[i] = wp.vec4f(j.im[0, 0], j.im[0, 1], j.im[1, 0], j.im[1, 1])


@wp.kernel
def _gyration_kernel(
    offset: int,
    cos_axis: wp.array(dtype=float),
    rho_axis: wp.array(dtype=float),
    ratio: wp.array(dtype=float),
    out: wp.array(dtype=float),
):
    i = wp.tid() + offset
    out[i] = gyration_rotatory_power(cos_axis[i], rho_axis[i], ratio[i])


# ----------------------------------------------------------------------------------------------
# NumPy wrappers


def _finite(value, name: str) -> np.ndarray:
    a = np.asarray(value, dtype=np.float64)
    bad = ~np.isfinite(a)
    if np.any(bad):
        raise InputError("must be finite", field=name, value=a[bad].flat[0], allowed="finite numbers")
    return a


def _positive(value, name: str) -> np.ndarray:
    a = _finite(value, name)
    if np.any(a <= 0):
        raise InputError("must be > 0", field=name, value=a[a <= 0].flat[0], allowed="> 0")
    return a


@device_function(slab_phase)
def slab_phases(q, q_ref, thickness_mm, wavelength_nm, *, device=None) -> np.ndarray:
    """exp(i 2 pi (q - q_ref) d / lambda) (complex array) of :func:`slab_phase`."""
    (out,) = elementwise(
        _slab_phase_kernel,
        [
            (_finite(q, "q"), wp.float32),
            (_finite(q_ref, "q_ref"), wp.float32),
            (_finite(thickness_mm, "thickness_mm"), wp.float32),
            (_positive(wavelength_nm, "wavelength_nm"), wp.float32),
        ],
        [wp.vec2f],
        device=device,
    )
    return out[..., 0].astype(np.float64) + 1j * out[..., 1].astype(np.float64)


def _crystal_frame(crystal_axes) -> np.ndarray:
    f = _finite(crystal_axes, "crystal_axes")
    if f.shape == (3,):  # an optic axis alone: it is the row Z
        n = np.linalg.norm(f)
        if n == 0:
            raise InputError("optic axis must be non-zero", field="optic_axis", value=tuple(f))
        z = f / n
        x = np.cross(z, [1.0, 0.0, 0.0] if abs(z[0]) < 0.9 else [0.0, 1.0, 0.0])
        x /= np.linalg.norm(x)
        return np.stack([x, np.cross(z, x), z])
    if f.shape != (3, 3):
        raise InputError(
            "crystal axes must be a 3-vector or a 3x3 matrix", field="crystal_axes", value=f.shape
        )
    return f


@device_function(plate_mode_jones)
def plate_jones(
    direction,
    wavelength_nm,
    indices,
    thickness_mm,
    *,
    crystal_axes=(0.0, 0.0, 1.0),
    alpha=(0.0, 0.0, 0.0),
    n_ambient=1.0,
    normal=(0.0, 0.0, -1.0),
    coherent: bool = True,
    device=None,
):
    """Jones matrices of a plane-parallel plate (:func:`plate_mode_jones`).

    ``direction`` (..., 3) the incident direction (normalised here), ``wavelength_nm`` (...),
    ``indices`` (..., 3) = (n_o, 0, n_e) of a uniaxial plate, (n_alpha, n_beta, n_gamma) of a
    biaxial one, (n, 0, n) of an isotropic one; ``thickness_mm`` (...); ``crystal_axes``: the
    optic axis (3,) of a uniaxial plate or the principal axes (3, 3) (rows X, Y, Z, world) of a
    biaxial one; ``alpha`` (..., 3) intensity absorption coefficients (1/mm: alpha_o, -, alpha_e
    or alpha_X, alpha_Y, alpha_Z); ``n_ambient`` the isotropic medium on both sides; ``normal``
    the unit plate normal on the incident side.

    Returns ``(J, s)``: ``J`` (..., 2, 2) complex, the coherent sum of the two waves
    (``coherent=True``) or the pair ``(J_0, J_1)`` stacked on a leading axis of length 2; ``s``
    (..., 3) the frame's x vector (the field components are along s and k x s)."""
    nrm = _finite(normal, "normal")
    nrm = nrm / np.linalg.norm(nrm)
    k = _finite(direction, "direction")
    frame = _crystal_frame(crystal_axes)
    outs = elementwise(
        _plate_jones_kernel,
        [
            (k, wp.vec3),
            (_positive(wavelength_nm, "wavelength_nm"), wp.float32),
            (_finite(indices, "indices"), wp.vec3),
            (_finite(alpha, "alpha"), wp.vec3),
            (_finite(thickness_mm, "thickness_mm"), wp.float32),
            (_positive(n_ambient, "n_ambient"), wp.float32),
        ],
        [wp.vec3, wp.vec4f, wp.vec4f, wp.vec4f, wp.vec4f],
        extra=(wp.vec3(*nrm.tolist()), wp.mat33(*frame.ravel().tolist())),
        device=device,
    )
    s, j0r, j0i, j1r, j1i = (np.asarray(o, dtype=np.float64) for o in outs)
    j0 = (j0r + 1j * j0i).reshape(*j0r.shape[:-1], 2, 2)
    j1 = (j1r + 1j * j1i).reshape(*j1r.shape[:-1], 2, 2)
    if coherent:
        return j0 + j1, s
    return np.stack([j0, j1]), s


@device_function(wave_plate_jones)
def wave_plates(slow_angle_deg, retardation_nm, wavelength_nm, *, device=None) -> np.ndarray:
    """Jones matrices (..., 2, 2) complex of ideal retarders (:func:`wave_plate_jones`); the
    slow direction at ``slow_angle_deg`` degrees from x toward y."""
    re, im = elementwise(
        _wave_plate_kernel,
        [
            (np.radians(_finite(slow_angle_deg, "slow_angle_deg")), wp.float32),
            (_finite(retardation_nm, "retardation_nm"), wp.float32),
            (_positive(wavelength_nm, "wavelength_nm"), wp.float32),
        ],
        [wp.vec4f, wp.vec4f],
        device=device,
    )
    j = re.astype(np.float64) + 1j * im.astype(np.float64)
    return j.reshape(*j.shape[:-1], 2, 2)


@device_function(gyration_rotatory_power)
def rotatory_powers(cos_axis, rho_axis, perpendicular_ratio=0.0, *, device=None) -> np.ndarray:
    """rho(theta) = rho_axis (cos^2 theta + r sin^2 theta) of :func:`gyration_rotatory_power`
    (the unit of ``rho_axis``)."""
    (out,) = elementwise(
        _gyration_kernel,
        [
            (_finite(cos_axis, "cos_axis"), wp.float32),
            (_finite(rho_axis, "rho_axis"), wp.float32),
            (_finite(perpendicular_ratio, "perpendicular_ratio"), wp.float32),
        ],
        [wp.float32],
        device=device,
    )
    return out.astype(np.float64)


@device_function(active_retarder_jones)
def active_retarders(retardation_rad, rotation_rad, *, device=None) -> np.ndarray:
    """Jones matrices (..., 2, 2) complex of :func:`active_retarder_jones`: linear retardation
    delta and rotation tau (radians), in the basis of the two linear waves, relative to their
    mean phase."""
    re, im = elementwise(
        _active_retarder_kernel,
        [
            (_finite(retardation_rad, "retardation_rad"), wp.float64),
            (_finite(rotation_rad, "rotation_rad"), wp.float64),
        ],
        [wp.vec4f, wp.vec4f],
        device=device,
    )
    j = re.astype(np.float64) + 1j * im.astype(np.float64)
    return j.reshape(*j.shape[:-1], 2, 2)


@device_function(plate_active_jones)
def active_plate_jones(
    direction,
    wavelength_nm,
    indices,
    thickness_mm,
    rho_axis_rad_mm,
    *,
    perpendicular_ratio=0.0,
    optic_axis=(0.0, 0.0, 1.0),
    alpha=(0.0, 0.0, 0.0),
    n_ambient=1.0,
    normal=(0.0, 0.0, -1.0),
    device=None,
):
    """Coherent Jones matrices of a uniaxial plate with optical activity
    (:func:`plate_active_jones`); the arguments of :func:`plate_jones` (uniaxial or isotropic
    ``indices`` (n_o, 0, n_e) only) and ``rho_axis_rad_mm`` (...), the rotatory power along the
    optic axis in rad/mm, positive counter-clockwise about the propagation direction
    (``materials.optical_activity(...).rho_rad_mm``).  Returns ``(J, s)`` as
    :func:`plate_jones` with ``coherent=True``."""
    nrm = _finite(normal, "normal")
    nrm = nrm / np.linalg.norm(nrm)
    n3 = _finite(indices, "indices")
    if np.any(n3[..., 1] != 0):
        raise InputError(
            "optical activity is modelled for uniaxial (or isotropic) plates only",
            field="indices",
            allowed="(n_o, 0, n_e)",
        )
    outs = elementwise(
        _plate_active_kernel,
        [
            (_finite(direction, "direction"), wp.vec3),
            (_positive(wavelength_nm, "wavelength_nm"), wp.float32),
            (n3, wp.vec3),
            (_finite(alpha, "alpha"), wp.vec3),
            (_finite(thickness_mm, "thickness_mm"), wp.float32),
            (_positive(n_ambient, "n_ambient"), wp.float32),
            (_finite(rho_axis_rad_mm, "rho_axis_rad_mm"), wp.float32),
            (_finite(perpendicular_ratio, "perpendicular_ratio"), wp.float32),
        ],
        [wp.vec3, wp.vec4f, wp.vec4f],
        extra=(wp.vec3(*nrm.tolist()), wp.mat33(*_crystal_frame(optic_axis).ravel().tolist())),
        device=device,
    )
    s, jr, ji = (np.asarray(o, dtype=np.float64) for o in outs)
    return (jr + 1j * ji).reshape(*jr.shape[:-1], 2, 2), s

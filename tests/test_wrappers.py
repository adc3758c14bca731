"""Every public element-wise NumPy wrapper of a ``@wp.func``, colour-science's trio per function:

- a reference value from an independent closed form (written here in NumPy, float64/complex128);
- shapes: item-shaped in -> item-shaped out, 1-D, n-D broadcasting of two arguments (each element
  equal to the closed form at its own inputs), empty arrays;
- edge cases: NaN and +-Inf in any argument (and in the scalar keywords listed per wrapper)
  raise ``InputError`` naming that argument, on one line even for a large array.

References: closed forms (vector Snell, Hecht's Fresnel equations, the index surface of a
uniaxial crystal, Airy sums, the Smits & Meyer 1990 equations, Walter et al. 2007's GGX), ``tmm``
for stacks, colour-science for CMFs and the Mallett–Yuksel basis, scipy's rotations.  The Perlin
turbulence fields have no closed form: their shape tests compare every element with the wrapper's
own item-shaped call, and they are checked for determinism and seeding.

Public import paths only (``wo.optics.fresnel``...): what a user imports is what is tested.
Tolerances: the kernels run in float32 (docs/conventions.md, "Precision"), so 2e-6 relative plus
an absolute floor for values near zero covers rounding; compiled with FMA, hence not bit-exact.  Wrappers with
float64 kernels (the thin-film stacks) are held to 1e-9; looser ones say why beside them.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import pytest

import warpoptics as wo
from warpoptics.errors import InputError


@dataclass
class W:
    name: str
    fn: Callable
    # (argument name, sample values): each value has the argument's item shape, the first is the
    # default; the others give the 1-D and n-D tests different inputs per element
    args: list[tuple[str, list]]
    # the closed form: item-shaped inputs -> list of item-shaped outputs; None for noise (the shape
    # tests then compare each element with the wrapper's own item-shaped call)
    ref: Callable | None
    rtol: float = 2e-6
    atol: float = 2e-6
    kwargs: dict = field(default_factory=dict)
    # keyword arguments (scalars) that must refuse NaN / +-Inf too, with an InputError naming them
    nan_kwargs: tuple[str, ...] = ()


def _zoned_depth_ref(o, d, t):
    """Optical depth and zone lengths of the segment o + d s, s in [0, t], through the planes
    u . x = -0.3 and 0.4 (u = (0, 0.6, 0.8)) with kappa 0.5, 2.0, 1.2 below, between, above:
    the crossing parameters sorted and each piece's zone found at its midpoint (float64)."""
    u, b, kap = np.array([0.0, 0.6, 0.8]), np.array([-0.3, 0.4]), np.array([0.5, 2.0, 1.2])
    s0, ds, t = float(np.dot(o, u)), float(np.dot(d, u)), float(t)
    cuts = sorted({0.0, t, *[min(max((bj - s0) / ds, 0.0), t) for bj in b if ds != 0.0]})
    lengths = np.zeros(3)
    for a, c in zip(cuts[:-1], cuts[1:], strict=True):
        lengths[np.searchsorted(b, s0 + ds * 0.5 * (a + c), side="right")] += c - a
    return [float(kap @ lengths), lengths]


def _c(x):
    return np.asarray(x, dtype=complex)


def _fresnel_ref(cos_i, n1, n2):
    # Hecht, Optics (5th ed.) eq. 4.42-4.45, with the transmitted cosine from Snell's law
    cos_t = np.sqrt(_c(1 - (n1 / n2) ** 2 * (1 - cos_i**2)))
    rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t)
    ts = 2 * n1 * cos_i / (n1 * cos_i + n2 * cos_t)
    rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t)
    tp = 2 * n1 * cos_i / (n2 * cos_i + n1 * cos_t)
    return [rs, rp, ts, tp], cos_t


def _fresnel_power_ref(cos_i, n1, n2):
    (rs, rp, ts, tp), cos_t = _fresnel_ref(cos_i, n1, n2)
    flux = (n2 * cos_t).real / (n1 * cos_i)  # ratio of normal energy fluxes (Hecht eq. 4.60-4.61)
    return [abs(rs) ** 2, abs(rp) ** 2, flux * abs(ts) ** 2, flux * abs(tp) ** 2]


def _unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def _refract_ref(d, n, n1, n2):
    # vector Snell's law (Glassner 1989; PBRT 4th ed. eq. 9.4), normal on the incident side
    eta = n1 / n2
    c = -np.dot(d, n)
    k = 1 - eta**2 * (1 - c**2)
    return [eta * d + (eta * c - np.sqrt(k)) * n if k >= 0 else np.zeros(3)]


def _stokes_ref(j):
    return [
        np.array([(j[0, 0] + j[1, 1]).real, (j[0, 0] - j[1, 1]).real, 2 * j[0, 1].real, 2 * j[0, 1].imag])
    ]


def _mueller_ref(angle):
    # Goldstein, Polarized Light (3rd ed.) eq. 5-12: ideal linear polarizer at angle theta
    c, s = np.cos(2 * np.radians(angle)), np.sin(2 * np.radians(angle))
    return np.array([[1, c, s, 0], [c, c * c, c * s, 0], [s, c * s, s * s, 0], [0, 0, 0, 0]]) / 2


def _n_e(cos_t, no, ne):
    # index ellipsoid of a uniaxial crystal (Born & Wolf §15.3): 1/n^2 = cos^2/no^2 + sin^2/ne^2
    return 1 / np.sqrt(cos_t**2 / no**2 + (1 - cos_t**2) / ne**2)


def _kappa_e(cos_t, k_o, k_e, no, ne):
    # Guy & Soler 2004 eq. 7, as documented by kappa_e
    return k_o * cos_t**2 + k_e * (no / ne) ** 2 * (1 - cos_t**2)


def _airy(wl, angle, n0, n_f, d, n2, kind):
    """Single film (index n_f, thickness d nm) between n0 and n2: the Airy sum of the two
    interfaces (Born & Wolf §7.6.1, Hecht eq. 9.88).  Returns (R, T) for polarization ``kind``."""
    s = n0 * np.sin(np.radians(angle))
    cos = [np.sqrt(_c(1 - (s / n) ** 2)) for n in (n0, n_f, n2)]
    idx = (n0, n_f, n2)

    def r_t(a, b):
        na, nb, ca, cb = idx[a], idx[b], cos[a], cos[b]
        if kind == "s":
            return (na * ca - nb * cb) / (na * ca + nb * cb), 2 * na * ca / (na * ca + nb * cb)
        return (nb * ca - na * cb) / (nb * ca + na * cb), 2 * na * ca / (nb * ca + na * cb)

    (r01, t01), (r12, t12) = r_t(0, 1), r_t(1, 2)
    ph = np.exp(2j * np.pi * n_f * cos[1] * d / wl)  # one pass through the film
    r = (r01 + r12 * ph**2) / (1 + r01 * r12 * ph**2)
    t = t01 * t12 * ph / (1 + r01 * r12 * ph**2)
    flux = (n2 * cos[2]).real / (n0 * cos[0]).real
    return abs(r) ** 2, flux * abs(t) ** 2


def _film_ref(pol):
    """n_film = 1.38, d = 120 nm (a MgF2 anti-reflection layer on glass), unpolarized."""

    def ref(wl, angle, n0, n2):
        rs, ts = _airy(wl, angle, n0, 1.38, 120.0, n2, "s")
        rp, tp = _airy(wl, angle, n0, 1.38, 120.0, n2, "p")
        return [(rs + rp) / 2] if pol == "R" else [(ts + tp) / 2]

    return ref


def _srgb_from_xyz(xyz):
    # IEC 61966-2-1:1999 matrix (D65)
    m = np.array([[3.2406, -1.5372, -0.4986], [-0.9689, 1.8758, 0.0415], [0.0557, -0.2040, 1.0570]])
    return [m @ xyz]


_RNG = np.random.default_rng(7)


def _cmat(k):
    return [_RNG.normal(size=(2, 2)) + 1j * _RNG.normal(size=(2, 2)) for _ in range(k)]


def _coherency(k):
    out = []
    for _ in range(k):
        e = _RNG.normal(size=(2, 2)) + 1j * _RNG.normal(size=(2, 2))
        out.append(e @ e.conj().T / 4)  # Hermitian positive semi-definite
    return out


_DIRS = [_unit([0.3, 0.1, -1.0]), _unit([-0.5, 0.2, -0.8]), _unit([0.0, 0.0, -1.0])]
_NORMALS = [np.array([0.0, 0.0, 1.0]), _unit([0.1, 0.0, 1.0]), _unit([0.0, -0.2, 1.0])]
_FILM = {"n_layers": [1.38], "thickness_nm": [120.0]}

WRAPPERS = [
    W(
        "optics.fresnel",
        lambda cos_i, n1, n2, **k: wo.optics.fresnel(cos_i, n1, n2, **k),
        [("cos_i", [0.7, 0.3, 1.0]), ("n1", [1.0, 1.33, 1.5]), ("n2", [1.5, 2.417, 1.76])],
        lambda c, a, b: _fresnel_ref(c, a, b)[0],
    ),
    W(
        "optics.fresnel_power",
        lambda cos_i, n1, n2, **k: wo.optics.fresnel_power(cos_i, n1, n2, **k),
        [("cos_i", [0.7, 0.3, 1.0]), ("n1", [1.0, 1.33, 1.5]), ("n2", [1.5, 2.417, 1.76])],
        _fresnel_power_ref,
        atol=1e-5,  # R + T = 1 in float32 to 1e-5 near normal incidence
    ),
    W(
        "optics.refract",
        lambda direction, normal, n1, n2, **k: wo.optics.refract(direction, normal, n1, n2, **k),
        [("direction", _DIRS), ("normal", _NORMALS), ("n1", [1.0, 1.33, 1.5]), ("n2", [1.5, 2.417, 1.0])],
        _refract_ref,
        atol=1e-6,
    ),
    W(
        "optics.reflect",
        lambda direction, normal, **k: wo.optics.reflect(direction, normal, **k),
        [("direction", _DIRS), ("normal", _NORMALS)],
        lambda d, n: [d - 2 * np.dot(d, n) * n],
        atol=1e-6,
    ),
    W(
        "optics.jones_product",
        lambda a, b, **k: wo.optics.jones_product(a, b, **k),
        [("a", _cmat(3)), ("b", _cmat(3))],
        lambda a, b: [a @ b],
        atol=1e-5,
    ),
    W(
        "optics.coherency_apply",
        lambda m, j, **k: wo.optics.coherency_apply(m, j, **k),
        [("m", _cmat(3)), ("j", _coherency(3))],
        lambda m, j: [m @ j @ m.conj().T],
        atol=1e-5,
    ),
    W(
        "optics.stokes",
        lambda j, **k: wo.optics.stokes(j, **k),
        [("j", _coherency(3))],
        _stokes_ref,
        atol=1e-6,
    ),
    W(
        "optics.dop",
        lambda j, **k: wo.optics.dop(j, **k),
        [("j", _coherency(3))],
        lambda j: [np.linalg.norm(_stokes_ref(j)[0][1:]) / _stokes_ref(j)[0][0]],
        atol=1e-5,
    ),
    W(
        "optics.coherency_from_stokes",
        lambda s, **k: wo.optics.coherency_from_stokes(s, **k),
        [
            (
                "s",
                [
                    np.array([1.0, 0.2, -0.3, 0.4]),
                    np.array([2.0, 1.0, 0.5, -1.0]),
                    np.array([1.0, 0.0, 0.0, 0.0]),
                ],
            )
        ],
        lambda s: [np.array([[s[0] + s[1], s[2] + 1j * s[3]], [s[2] - 1j * s[3], s[0] - s[1]]]) / 2],
        atol=1e-6,
    ),
    W(
        "optics.mueller_polarizer",
        lambda angle_deg, **k: wo.optics.mueller_polarizer(angle_deg, **k),
        [("angle_deg", [30.0, 0.0, 135.0])],
        lambda a: [_mueller_ref(a)],
        atol=1e-6,
    ),
    W(
        "optics.analyze",
        lambda stokes, angle_deg, **k: wo.optics.analyze(stokes, angle_deg, **k),
        [
            (
                "stokes",
                [np.array([1.0, 0.2, -0.3, 0.4]), np.array([2.0, 1.0, 0.5, -1.0]), np.array([1, 0, 0, 0.0])],
            ),
            ("angle_deg", [30.0, 0.0, 135.0]),
        ],
        lambda s, a: [_mueller_ref(a) @ s],
        atol=1e-6,
    ),
    W(
        "optics.extraordinary_index",
        lambda cos_theta, no, ne, **k: wo.optics.extraordinary_index(cos_theta, no, ne, **k),
        [("cos_theta", [0.5, 0.0, 1.0]), ("no", [1.658, 1.768, 1.544]), ("ne", [1.486, 1.760, 1.553])],
        lambda c, o, e: [_n_e(c, o, e)],
    ),
    W(
        "optics.kappa_e",
        lambda cos_theta, k_o, k_e, no, ne, **k: wo.optics.kappa_e(cos_theta, k_o, k_e, no, ne, **k),
        [
            ("cos_theta", [0.5, 0.0, 1.0]),
            ("k_o", [0.2, 1.0, 0.0]),
            ("k_e", [0.7, 0.1, 2.0]),
            ("no", [1.658, 1.768, 1.544]),
            ("ne", [1.486, 1.760, 1.553]),
        ],
        lambda c, ko, ke, o, e: [_kappa_e(c, ko, ke, o, e)],
    ),
    W(
        "optics.attenuation",
        lambda cos_theta, k_o, k_e, no, ne, length, **k: wo.optics.attenuation(
            cos_theta, k_o, k_e, no, ne, length, **k
        ),
        [
            ("cos_theta", [0.5, 0.0, 1.0]),
            ("k_o", [0.2, 1.0, 0.0]),
            ("k_e", [0.7, 0.1, 2.0]),
            ("no", [1.658, 1.768, 1.544]),
            ("ne", [1.486, 1.760, 1.553]),
            ("length", [3.0, 0.5, 10.0]),
        ],
        lambda c, ko, ke, o, e, s: [np.exp(-np.array([ko, _kappa_e(c, ko, ke, o, e)]) * s / 2)],
    ),
    W(
        "optics.segment_optical_depth",
        lambda origin, direction, length, **k: wo.optics.segment_optical_depth(
            origin, direction, length, **k
        ),
        [
            ("origin", [[0.3, -1.0, -2.0], [0.0, 0.0, 0.1], [1.0, 2.0, 3.0]]),
            ("direction", [[0.0, 0.6, 0.8], [1.0, 0.0, 0.0], [0.0, -0.6, -0.8]]),
            ("length", [4.0, 2.0, 5.0]),
        ],
        lambda o, d, t: _zoned_depth_ref(o, d, t),
        kwargs=dict(kind="planes", axis=[0.0, 0.6, 0.8], bounds=[-0.3, 0.4], kappa=[0.5, 2.0, 1.2]),
        nan_kwargs=("axis", "bounds", "kappa", "centre"),
    ),
    W(
        "materials.pleochroic_alpha",
        lambda alpha_o, alpha_e, n_o, n_e, cos_theta, **k: wo.materials.pleochroic_alpha(
            alpha_o, alpha_e, n_o, n_e, cos_theta, **k
        ),
        [
            ("alpha_o", [0.2, 1.0, 0.0]),
            ("alpha_e", [0.7, 0.1, 2.0]),
            ("n_o", [1.658, 1.768, 1.544]),
            ("n_e", [1.486, 1.760, 1.553]),
            ("cos_theta", [0.5, 0.0, 1.0]),
        ],
        lambda ao, ae, o, e, c: [_kappa_e(c, ao, ae, o, e)],
    ),
    W(
        "materials.alpha_from_k",
        lambda k, wavelength_nm, **kw: wo.materials.alpha_from_k(k, wavelength_nm, **kw),
        [("k", [1e-4, 0.0, 2.5]), ("wavelength_nm", [550.0, 400.0, 780.0])],
        lambda k, wl: [4 * np.pi * k / (wl * 1e-6)],  # alpha = 4 pi k / lambda, lambda in mm
    ),
    W(
        "materials.k_from_alpha",
        lambda alpha_per_mm, wavelength_nm, **kw: wo.materials.k_from_alpha(
            alpha_per_mm, wavelength_nm, **kw
        ),
        [("alpha_per_mm", [2.3, 0.0, 1e3]), ("wavelength_nm", [550.0, 400.0, 780.0])],
        lambda a, wl: [a * wl * 1e-6 / (4 * np.pi)],
    ),
    W(
        "materials.alpha_from_absorbance_per_cm",
        lambda absorbance_per_cm, **kw: wo.materials.alpha_from_absorbance_per_cm(absorbance_per_cm, **kw),
        [("absorbance_per_cm", [1.0, 0.0, 30.0])],
        lambda a: [np.log(10) * a / 10],  # decadic per cm -> natural per mm
    ),
    W(
        "materials.absorbance_per_cm_from_alpha",
        lambda alpha_per_mm, **kw: wo.materials.absorbance_per_cm_from_alpha(alpha_per_mm, **kw),
        [("alpha_per_mm", [0.23, 0.0, 7.0])],
        lambda a: [10 * a / np.log(10)],
    ),
    W(
        "thinfilm.smits_meyer_optical_thickness",
        lambda thickness_nm, n, angle, **kw: wo.thinfilm.smits_meyer_optical_thickness(
            thickness_nm, n, angle, **kw
        ),
        [("thickness_nm", [300.0, 0.0, 1200.0]), ("n", [1.33, 1.0, 1.5]), ("angle", [30.0, 0.0, 60.0])],
        lambda t, n, a: [t * n * np.cos(np.radians(a))],  # Smits & Meyer 1990 eq. 11
        atol=1e-4,
    ),
    W(
        "thinfilm.reflectance",
        lambda wavelength_nm, angle, n_incident, n_substrate, **kw: wo.thinfilm.reflectance(
            wavelength_nm, _FILM["n_layers"], _FILM["thickness_nm"], n_incident, n_substrate, angle, **kw
        ),
        [
            ("wavelength_nm", [550.0, 400.0, 700.0]),
            ("angle", [30.0, 0.0, 70.0]),
            ("n_incident", [1.0, 1.33, 1.0]),
            ("n_substrate", [1.52, 1.76, 2.417]),
        ],
        _film_ref("R"),
        atol=1e-6,
    ),
    W(
        "thinfilm.transmittance",
        lambda wavelength_nm, angle, n_incident, n_substrate, **kw: wo.thinfilm.transmittance(
            wavelength_nm, _FILM["n_layers"], _FILM["thickness_nm"], n_incident, n_substrate, angle, **kw
        ),
        [
            ("wavelength_nm", [550.0, 400.0, 700.0]),
            ("angle", [30.0, 0.0, 70.0]),
            ("n_incident", [1.0, 1.33, 1.0]),
            ("n_substrate", [1.52, 1.76, 2.417]),
        ],
        _film_ref("T"),
        atol=1e-6,
    ),
    W(
        "color.gamut_clip",
        lambda xyz, **kw: wo.color.gamut_clip(xyz, **kw),
        # in-gamut colours (linear sRGB 0.05..0.9): the clip is the plain XYZ -> sRGB matrix
        [("xyz", [np.array([0.3, 0.35, 0.25]), np.array([0.2, 0.15, 0.4]), np.array([0.5, 0.6, 0.55])])],
        _srgb_from_xyz,
        rtol=2e-4,  # the IEC matrix is given to 4 decimals
        atol=1e-4,
    ),
]
# ----------------------------------------------------------------------------------------------
# Uniaxial crystals: e-waves, o/e frames, generalized Fresnel coefficients (Guy & Soler 2004)

_AXES = [_unit([0.3, 0.2, 0.9]), np.array([1.0, 0.0, 0.0]), _unit([0.5, -0.5, 0.7])]
_NO = [1.658, 1.768, 1.544]  # calcite, sapphire, quartz (o)
_NE = [1.486, 1.760, 1.553]


def _e_wave_ref(side):
    """The e-wave leaving a plane interface, solved on the index surface (Born & Wolf §15.3):
    wave vector K = T + side q N with the tangential part T = n_in (d - (d.N) N) conserved and
    (K.a)^2 / no^2 + (|K|^2 - (K.a)^2) / ne^2 = 1, a quadratic in q.  Its larger root is the wave
    whose ray (the surface's gradient, the Poynting direction) leaves along side * N (into the
    crystal for refraction, side = -1; back into it for internal reflection, side = +1).  No real
    root: evanescent, zero vectors and index."""

    def ref(d, nrm, axis, n_in, no, ne):
        d, nrm, a = _unit(d), _unit(nrm), _unit(axis)
        t = n_in * (d - np.dot(d, nrm) * nrm)
        delta = 1 / no**2 - 1 / ne**2
        u, v = np.dot(t, a), np.dot(nrm, a)
        qa = v * v * delta + 1 / ne**2
        qb = 2 * side * u * v * delta
        qc = u * u * delta + np.dot(t, t) / ne**2 - 1
        disc = qb * qb - 4 * qa * qc
        if disc < 0:
            return [np.zeros(3), np.zeros(3), 0.0]
        k = t + side * (-qb + np.sqrt(disc)) / (2 * qa) * nrm
        ka = np.dot(k, a)
        ray = ka * a / no**2 + (k - ka * a) / ne**2
        return [k / np.linalg.norm(k), ray / np.linalg.norm(ray), np.linalg.norm(k)]

    return ref


def _oe_ref(s, axis, no, ne):
    # Guy & Soler 2004 eq. 2: X = a x s / |a x s| (o-wave D and E), Y = s x X (e-wave D), and the
    # e-wave E along eps^-1 Y, eps = no^2 I + (ne^2 - no^2) a a^T (Born & Wolf §15.2)
    s, a = _unit(s), _unit(axis)
    x = _unit(np.cross(a, s))
    y = np.cross(s, x)
    eps_inv = np.eye(3) / no**2 + (1 / ne**2 - 1 / no**2) * np.outer(a, a)
    return [x, y, _unit(eps_inv @ y)]


_Z = np.array([0.0, 0.0, 1.0])


def _axis_normal_ref(d, n1, no, ne):
    """Isotropic n1 onto a uniaxial crystal whose optic axis is the surface normal z: s and p
    decouple into the o- and e-waves.  o: Hecht's rs, ts with n2 = no.  e (TM): the H-field ratio
    r = (no ne cos - n1 sqrt(ne^2 - T^2)) / (no ne cos + n1 sqrt(ne^2 - T^2)), T = n1 sin
    (Lekner, J. Phys.: Condens. Matter 3, 6121 (1991), optic axis normal to the surface), the
    transmitted H = 1 + r, and |E| = |H| sqrt(kz^2 / no^4 + T^2 / ne^4) in the crystal
    (E = eps^-1 D, D = -K x H) against |E| = |H| / n1 in the incident medium."""
    c = -np.dot(d, _Z)
    t = n1 * np.sqrt(1 - c * c)
    (rs, _, ts, _), cos_o = _fresnel_ref(c, n1, no)
    sq = np.sqrt(ne**2 - t**2)
    kz_e = no / ne * sq
    r_e = (no * ne * c - n1 * sq) / (no * ne * c + n1 * sq)
    t_e = (1 + r_e) * n1 * np.sqrt(kz_e**2 / no**4 + t**2 / ne**4)
    tang = n1 * (d - np.dot(d, _Z) * _Z)
    mirror = n1 * (d - 2 * np.dot(d, _Z) * _Z)
    # wave vectors / k0 of (incident, ro, re, to, te): the tangential part is conserved
    k = np.array([n1 * d, mirror, mirror, tang - no * cos_o.real * _Z, tang - kz_e * _Z], dtype=complex)
    return rs, ts, r_e, t_e, k


def _gfc_ref(mode):
    def ref(d, n1, no, ne):
        rs, _, r_e, _, k = _axis_normal_ref(_unit(d), n1, no, ne)
        r_e, rs = abs(r_e) ** 2, abs(rs) ** 2
        # energy fractions to (ro, re, to, te): lossless, so T = 1 - R
        energy = np.array([rs, 0.0, 1 - rs, 0.0]) if mode == "o" else np.array([0.0, r_e, 0.0, 1 - r_e])
        return [energy, k]

    return ref


def _gfc_fn(mode):
    def fn(direction, medium1, no, ne, **kw):
        res = wo.optics.generalized_fresnel_coefficients(
            direction, _Z, medium1, (no, ne, _Z), mode=mode, **kw
        )
        return res.energy(), res.k

    return fn


def _jones_axis_normal_ref(d, n1, no, ne):
    rs, ts, r_e, t_e, _ = _axis_normal_ref(_unit(d), n1, no, ne)
    return [np.diag([rs, r_e]), np.diag([ts, t_e])]


def _jones_approx_ref(d, n1, no, ne):
    # Guy & Soler eq. 10 with the optic axis on the normal: o = s, e = p, Fresnel at (no + ne) / 2
    rs, rp, ts, tp = _fresnel_ref(-np.dot(_unit(d), _Z), n1, (no + ne) / 2)[0]
    return [np.diag([rs, rp]), np.diag([ts, tp])]


def _rotate_ref(x, d_old, d_new):
    # the smallest rotation taking d_old to d_new (about d_old x d_new by their angle), from scipy,
    # then the projection onto the plane perpendicular to d_new, normalised
    from scipy.spatial.transform import Rotation

    d_old, d_new = _unit(d_old), _unit(d_new)
    axis = np.cross(d_old, d_new)
    angle = np.arctan2(np.linalg.norm(axis), np.dot(d_old, d_new))
    r = Rotation.from_rotvec(_unit(axis) * angle).apply(np.asarray(x, float))
    return [_unit(r - d_new * np.dot(r, d_new))]


def _sheet_ref(a, k, bx):
    # unpolarized unit intensity through an ideal dichroic sheet: half of it leaves linearly
    # polarized along k x a (Hecht §8.2, Malus); its Jones vector in the frame (bx, k x bx)
    e = np.cross(k, a)
    if np.dot(e, e) < 1e-12:
        return [np.array([1.0, 0.0, 0.0, 0.0])]  # no sheet: unpolarized light passes
    u = np.array([np.dot(e, bx), np.dot(e, np.cross(k, bx))])
    u = u / np.linalg.norm(u)
    return [0.5 * np.array([1.0, u[0] ** 2 - u[1] ** 2, 2 * u[0] * u[1], 0.0])]


# ----------------------------------------------------------------------------------------------
# Thin films: stacks (against tmm), the Smits & Meyer 1990 model, thickness fields


def _tmm_stack(pol, wl, n_layers, d, n0, n2, angle, from_back=False):
    import tmm

    n_list = [n0, *np.atleast_1d(n_layers), n2]
    d_list = [np.inf, *np.atleast_1d(d), np.inf]
    if from_back:
        n_list, d_list = n_list[::-1], d_list[::-1]
    return tmm.coh_tmm(pol, n_list, d_list, np.radians(angle), wl)


def _stack_ref(what):
    def ref(wl, n_layers, d, n0, n2, angle):
        s, p = (_tmm_stack(pol, wl, n_layers, d, n0, n2, angle) for pol in ("s", "p"))
        if what == "amplitudes":
            return [s["r"], p["r"], s["t"], p["t"]]
        if what == "R":
            return [(s["R"] + p["R"]) / 2]
        return [p["T"]]

    return ref


_STACK_ARGS = [
    ("wavelength_nm", [550.0, 400.0, 700.0]),
    ("n_layers", [np.array([2.3, 1.46]), np.array([1.38, 2.0 + 0.1j]), np.array([1.6, 1.33])]),
    ("thickness_nm", [np.array([120.0, 90.0]), np.array([100.0, 50.0]), np.array([0.0, 300.0])]),
    ("n_incident", [1.0, 1.33, 1.0]),
    ("n_substrate", [1.52, 1.76 + 0.02j, 2.417]),
    ("angle", [30.0, 0.0, 70.0]),
]
_COATING = [(2.3, 120.0), (1.46, 90.0)]
_STACKS: dict = {}


def _coating_stack(device):
    # coatings 0 (bare) and 1 (_COATING), uploaded once per device
    key = str(device)
    if key not in _STACKS:
        _STACKS[key] = wo.thinfilm.make_coating_stack([[], _COATING], device=device)
    return _STACKS[key]


def _evaluate_coating_ref(from_back):
    def ref(wl, angle, n_front, n_back):
        out = [
            _tmm_stack(pol, wl, [2.3, 1.46], [120.0, 90.0], n_front, n_back, angle, from_back) for pol in "sp"
        ]
        return [out[0]["r"], out[1]["r"], out[0]["t"], out[1]["t"]]

    return ref


def _multilayer_ref(wl, t, a0, layers=5):
    # Smits & Meyer 1990 eq. 9 (Anderson & Richards 1942); at sin x = 0 the ratio's limit
    # (l + 1) cos((l + 1) x) / cos x (l'Hopital)
    x, m = 2 * np.pi * t / wl, layers + 1
    ratio = m * np.cos(m * x) / np.cos(x) if abs(np.sin(x)) < 1e-9 else np.sin(m * x) / np.sin(x)
    return [0.5 * a0 * ratio**2]


# ----------------------------------------------------------------------------------------------
# Spectra, surfaces, materials, colour (references from colour-science, Walter et al. 2007)

_CMFS = None


def _cmf_ref(wl):
    # CIE 1931 2° (colour-science, 1 nm, 360-830 nm) normalised by sum(ybar) * 1 nm: per nm
    global _CMFS
    if _CMFS is None:
        import colour

        _CMFS = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    k = 1.0 / _CMFS.values[:, 1].sum()
    return np.array([np.interp(wl, _CMFS.wavelengths, _CMFS.values[:, c]) * k for c in range(3)])


def _sample_ref(strategy, count):
    lo, width = 360.0, 470.0

    def ref(u, index):
        if strategy == "uniform":
            wl = lo + u * width
        else:  # stratified: stratum ``index`` of ``count`` equal ones, jittered by u
            wl = lo + (index + u) * width / count
        # the estimator weight cmf(l) / (count p(l)) with p = 1 / width (wavelength importance sampling)
        return [wl, _cmf_ref(wl) * width / count]

    return ref


def _rgb3_ref(u, index):
    # rgb3: fixed wavelengths (the three-wavelength paper) whose weights k_c cmf(l_c) make a constant
    # spectrum exact
    lam = np.array([700.0, 546.1, 435.8])
    m = np.stack([_cmf_ref(x) for x in lam])
    white = _CMFS.values.sum(axis=0) / _CMFS.values[:, 1].sum()  # XYZ of E (Y = 1)
    k = np.linalg.solve(m.T, white)
    return [lam[index], k[index] * m[index]]


def _ggx_d(cos_m, alpha):
    # Walter et al. 2007 eq. 33
    tan2 = (1 - cos_m**2) / cos_m**2
    return alpha**2 / (np.pi * cos_m**4 * (alpha**2 + tan2) ** 2)


def _ggx_g1(cos_v, alpha):
    # Walter et al. 2007 eq. 34 (Smith)
    tan2 = (1 - cos_v**2) / cos_v**2
    return 2 / (1 + np.sqrt(1 + alpha**2 * tan2))


def _bsdf_ref(kind):
    def ref(albedo, roughness, ior, n, w_o, w_i):
        n, w_o, w_i = _unit(n), _unit(w_o), _unit(w_i)
        ci, co = np.dot(n, w_i), np.dot(n, w_o)
        if ci <= 0 or co <= 0:
            return [0.0, 0.0]
        if kind == "diffuse":  # Lambert
            return [albedo / np.pi, ci / np.pi]
        alpha = max(roughness**2, 1e-4)
        h = _unit(w_i + w_o)
        ch = np.dot(n, h)

        def fresnel_r(c):
            rs, rp, _, _ = _fresnel_power_ref(c, 1.0, ior)
            return (rs + rp) / 2

        d = _ggx_d(ch, alpha)
        spec = fresnel_r(np.dot(w_i, h)) * d * _ggx_g1(ci, alpha) * _ggx_g1(co, alpha) / (4 * ci * co)
        diff = (1 - fresnel_r(ci)) * (1 - fresnel_r(co)) * albedo / np.pi
        # half the samples from D(m) |m.n| reflected (Jacobian 1 / (4 |o.m|), eq. 14), half cosine
        pdf = 0.5 * d * ch / (4 * abs(np.dot(w_o, h))) + 0.5 * ci / np.pi
        return [spec + diff, pdf]

    return ref


def _reflectance_ref(rgb, wl):
    # Mallett & Yuksel 2019 sRGB basis (colour-science): reflectance = sum_c rgb_c B_c(l)
    import colour

    b = colour.recovery.MSDS_BASIS_FUNCTIONS_sRGB_MALLETT2019
    return [sum(rgb[c] * np.interp(wl, b.wavelengths, b.values[:, c]) for c in range(3))]


# Schott N-BK7 Sellmeier coefficients (Schott data sheet; lambda in um): nd = 1.5168 at 587.56 nm
_BK7_B = (1.03961212, 0.231792344, 1.01046945)
_BK7_C = (0.00600069867, 0.0200179144, 103.560653)
_MATS: dict = {}


def _sellmeier(wl_nm, b, c):
    l2 = (wl_nm * 1e-3) ** 2
    return np.sqrt(1 + sum(bi * l2 / (l2 - ci) for bi, ci in zip(b, c, strict=True)))


def _material(name):
    if name not in _MATS:
        m = wo.materials
        if name == "bk7":
            _MATS[name] = m.Sellmeier(_BK7_B, _BK7_C)
        elif name == "table":
            _MATS[name] = m.Tabulated(_TAB_WL, _TAB_N, _TAB_K)
        else:  # a uniaxial crystal of two Cauchy channels
            _MATS[name] = m.Uniaxial(m.Cauchy(1.65, 0.01), m.Cauchy(1.48, 0.004))
    return _MATS[name]


_TAB_WL = np.array([380.0, 500.0, 600.0, 780.0])
_TAB_N = np.array([1.60, 1.55, 1.52, 1.50])
_TAB_K = np.array([1e-4, 5e-4, 2e-4, 0.0])


def _gamut_clip_ref(xyz, max_value):
    """Smits & Meyer 1990 §3.2, solved by bisection: the colour moves along the line of constant
    Y toward the grey (Y, Y, Y) until it first lies in [0, max]^3 (that set of t is an interval
    ending at the grey, so bisection finds its start); Y <= 0 is black, Y >= max white."""
    m = np.array([[3.2406, -1.5372, -0.4986], [-0.9689, 1.8758, 0.0415], [0.0557, -0.2040, 1.0570]])
    rgb, y = m @ xyz, xyz[1]
    if y <= 0:
        return [np.zeros(3)]
    if y >= max_value:
        return [np.full(3, max_value)]

    def inside(t):
        c = rgb + t * (y - rgb)
        return np.all(c >= -1e-12) and np.all(c <= max_value + 1e-12)

    lo, hi = 0.0, 1.0
    if inside(0.0):
        return [rgb]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if inside(mid) else (mid, hi)
    return [rgb + hi * (y - rgb)]


_DIRS_OBLIQUE = [_DIRS[0], _DIRS[1], _unit([0.1, -0.4, -0.9])]
_UP = [_unit([0.2, 0.1, 1.0]), _unit([-0.3, 0.2, 0.9]), _unit([0.0, 0.5, 0.8])]
_GRAVITY = {"top_nm": 10.0, "bottom_nm": 910.0, "noise": 0.0, "noise_scale": 2.0, "seed": 0, "octaves": 3}
_OIL = {"max_nm": 1200.0, "k1": 2.5, "k2": 0.0, "noise_scale": 3.0, "seed": 0, "octaves": 2}
_SHELL = {"surface": "shell", "layers": ((complex(1.33, 0.0), 420.0),)}


def _film_event_fn(direction, normal, wavelength_nm, **kw):
    ev = wo.stages.coated.film_event(
        wo.stages.coated.FilmConfig(**_SHELL), direction, normal, wavelength_nm, **kw
    )
    return ev["count"], ev["energy"], ev["direction"]


def _film_event_ref(d, n, wl):
    # a soap-film shell (air | 1.33, 420 nm | air): children (transmitted straight on, reflected)
    # with the Airy sum's unpolarized T and R, the mirror direction for the reflection
    d, n = _unit(d), _unit(n)
    angle = np.degrees(np.arccos(abs(np.dot(d, n))))
    (rs, ts), (rp, tp) = (_airy(wl, angle, 1.0, 1.33, 420.0, 1.0, k) for k in "sp")
    return [2, np.array([(ts + tp) / 2, (rs + rp) / 2]), np.stack([d, d - 2 * np.dot(d, n) * n])]


def _film_thickness_fn(profile, params, frame):
    def fn(position, **kw):
        cfg = wo.stages.coated.FilmConfig(
            surface="film", layers=((complex(1.47, 0.0), 500.0),), profile=profile, profile_params=params
        )
        return wo.stages.coated.film_thickness(cfg, position, frame=frame, **kw)

    return fn


_TABLES: dict = {}


def _table(device):
    # a small Smits-Meyer table (eq. 7), 31 entries 0-1500 nm of optical thickness, once per device
    key = str(device)
    if key not in _TABLES:
        _TABLES[key] = wo.thinfilm.film_color_table(count=31, step_nm=10.0, device=device)
    return _TABLES[key]


def _lookup_ref(x):
    # the renderer's lookup is linear interpolation in its table, clamped at both ends: np.interp
    # (the wrapper has run before the reference is asked for, so the table exists)
    t = next(iter(_TABLES.values()))
    return [np.array([np.interp(x, t.axis, t.rgb[:, c]) for c in range(3)])]


WRAPPERS += [
    W(
        "optics.refract_extraordinary",
        lambda direction, normal, axis, n1, no, ne, **k: wo.optics.refract_extraordinary(
            direction, normal, axis, n1, no, ne, return_index=True, **k
        ),
        [
            ("direction", _DIRS),
            ("normal", _NORMALS),
            ("axis", _AXES),
            ("n1", [1.0, 1.33, 1.0]),
            ("no", _NO),
            ("ne", _NE),
        ],
        _e_wave_ref(-1.0),
        rtol=1e-5,  # float32 root of a quadratic with a cancelling discriminant
        atol=2e-6,
    ),
    W(
        "optics.reflect_extraordinary",
        lambda direction, normal, axis, n_in, no, ne, **k: wo.optics.reflect_extraordinary(
            direction, normal, axis, n_in, no, ne, return_index=True, **k
        ),
        [
            # the third incident wave (n_in = 3, 38 degrees) has an evanescent reflected e-wave
            ("direction", [_DIRS[0], _DIRS[1], _unit([0.6, 0.0, -0.8])]),
            ("normal", _NORMALS),
            ("axis", _AXES),
            ("n_in", [1.658, 1.768, 3.0]),
            ("no", _NO),
            ("ne", _NE),
        ],
        _e_wave_ref(1.0),
        rtol=1e-5,
        atol=2e-6,
    ),
    W(
        "optics.oe_polarizations",
        lambda wave_normal, axis, no, ne, **k: wo.optics.oe_polarizations(wave_normal, axis, no, ne, **k),
        [("wave_normal", _DIRS), ("axis", _AXES), ("no", _NO), ("ne", _NE)],
        _oe_ref,
        atol=1e-6,
    ),
    *[
        W(
            f"optics.generalized_fresnel_coefficients[{mode}]",
            _gfc_fn(mode),
            [("direction", _DIRS), ("medium1", [1.0, 1.33, 1.2]), ("medium2.no", _NO), ("medium2.ne", _NE)],
            _gfc_ref(mode),
            atol=1e-5,  # R + T = 1 in float32, as fresnel_power
        )
        for mode in ("o", "e")
    ],
    W(
        "optics.fresnel_matrices",
        lambda direction, medium1, no, ne, **k: wo.optics.fresnel_matrices(
            direction, _Z, medium1, (no, ne, _Z), **k
        ),
        [("direction", _DIRS), ("medium1", [1.0, 1.33, 1.2]), ("medium2.no", _NO), ("medium2.ne", _NE)],
        _jones_axis_normal_ref,
        atol=1e-6,
    ),
    W(
        "optics.fresnel_matrices[approx]",
        lambda direction, medium1, no, ne, **k: wo.optics.fresnel_matrices(
            direction, _Z, medium1, (no, ne, _Z), approx=True, **k
        ),
        [("direction", _DIRS), ("medium1", [1.0, 1.33, 1.2]), ("medium2.no", _NO), ("medium2.ne", _NE)],
        _jones_approx_ref,
        atol=1e-6,
    ),
    W(
        "optics.frame_change_matrix",
        lambda direction, x_from, x_to, **k: wo.optics.frame_change_matrix(direction, x_from, x_to, **k),
        [
            ("direction", _DIRS),
            ("x_from", [_unit([1.0, 0.0, 0.3]), _unit([0.2, 1.0, 0.1]), np.array([1.0, 0.0, 0.0])]),
            ("x_to", [_unit([0.0, 1.0, 0.1]), _unit([-1.0, 0.4, -0.2]), _unit([1.0, 1.0, 0.0])]),
        ],
        # frame_change's definition B[i, k] = to_i . from_k with y = d x x (Jones basis, docs/conventions.md)
        lambda d, xf, xt: [
            np.array(
                [
                    [np.dot(xt, xf), np.dot(xt, np.cross(d, xf))],
                    [np.dot(np.cross(d, xt), xf), np.dot(np.cross(d, xt), np.cross(d, xf))],
                ]
            )
        ],
        atol=1e-6,
    ),
    W(
        "optics.s_vectors",
        lambda direction, normal, **k: wo.optics.s_vectors(direction, normal, **k),
        [("direction", _DIRS_OBLIQUE), ("normal", _NORMALS)],
        lambda d, n: [_unit(np.cross(n, d))],  # perpendicular to the plane of incidence (Hecht §4.6)
        atol=1e-6,
    ),
    W(
        "optics.transport_bases",
        lambda x, d_old, d_new, **k: wo.optics.transport_bases(x, d_old, d_new, **k),
        [
            ("x", [_unit([1.0, 0.0, 0.3]), _unit([0.2, 1.0, 0.1]), _unit([1.0, 1.0, 0.5])]),
            ("d_old", _DIRS),
            ("d_new", [_unit([0.3, 0.1, 1.0]), _unit([0.5, 0.6, -0.2]), _unit([-0.2, 0.1, 0.9])]),
        ],
        _rotate_ref,
        atol=2e-6,
    ),
    W(
        "optics.sheet_polarizer_stokes",
        lambda absorb_axis, k, basis_x, **kw: wo.optics.sheet_polarizer_stokes(absorb_axis, k, basis_x, **kw),
        [
            ("absorb_axis", [np.array([0.0, 1.0, 0.0]), _unit([1.0, 1.0, 0.2]), np.zeros(3)]),
            ("k", [_Z, _unit([0.3, 0.0, 1.0]), _unit([-0.5, 0.0, 1.0])]),
            ("basis_x", [np.array([1.0, 0.0, 0.0]), _unit([1.0, 1.0, 0.0]), np.array([0.0, 1.0, 0.0])]),
        ],
        _sheet_ref,
        atol=1e-6,
    ),
    W(
        "thinfilm.amplitudes",
        lambda wavelength_nm, n_layers, thickness_nm, n_incident, n_substrate, angle, **k: (
            wo.thinfilm.amplitudes(wavelength_nm, n_layers, thickness_nm, n_incident, n_substrate, angle, **k)
        ),
        _STACK_ARGS,
        _stack_ref("amplitudes"),
        rtol=1e-9,  # float64 inside the kernels, as tmm (module docstring: < 1e-12)
        atol=1e-10,
    ),
    W(
        "thinfilm.reflectance[stack]",
        lambda wavelength_nm, n_layers, thickness_nm, n_incident, n_substrate, angle, **k: (
            wo.thinfilm.reflectance(
                wavelength_nm, n_layers, thickness_nm, n_incident, n_substrate, angle, **k
            )
        ),
        _STACK_ARGS,
        _stack_ref("R"),
        rtol=1e-9,
        atol=1e-10,
    ),
    W(
        "thinfilm.transmittance[stack,p]",
        lambda wavelength_nm, n_layers, thickness_nm, n_incident, n_substrate, angle, **k: (
            wo.thinfilm.transmittance(
                wavelength_nm, n_layers, thickness_nm, n_incident, n_substrate, angle, "p", **k
            )
        ),
        _STACK_ARGS,
        _stack_ref("Tp"),
        rtol=1e-9,
        atol=1e-10,
    ),
    *[
        W(
            f"thinfilm.evaluate_coating[{'back' if back else 'front'}]",
            lambda wavelength_nm, angle, n_front, n_back, back=back, **k: wo.thinfilm.evaluate_coating(
                _coating_stack(k["device"]), 1, wavelength_nm, angle, n_front, n_back, from_back=back, **k
            ),
            [
                ("wavelength_nm", [550.0, 400.0, 700.0]),
                ("angle", [30.0, 0.0, 20.0]),
                ("n_front", [1.0, 1.33, 1.0]),
                ("n_back", [1.52, 1.76, 2.417]),
            ],
            _evaluate_coating_ref(back),
            rtol=1e-5,  # float32 in and out (the renderer's path), float64 inside
            atol=2e-6,
        )
        for back in (False, True)
    ],
    *[
        W(
            f"thinfilm.smits_meyer_film[{'eq7' if phase else 'eq8'}]",
            lambda wavelength_nm, optical_thickness_nm, K, phase=phase, **k: wo.thinfilm.smits_meyer_film(
                wavelength_nm, optical_thickness_nm, phase, K, **k
            ),
            [
                ("wavelength_nm", [550.0, 400.0, 700.0]),
                ("optical_thickness_nm", [300.0, 0.0, 1200.0]),
                ("K", [1.0, 0.4, -0.3]),
            ],
            # Smits & Meyer 1990 eq. 7 (with the pi/2 of the phase change) and eq. 8
            lambda wl, t, K, phase=phase: [(K * np.cos(2 * np.pi * t / wl + phase * np.pi / 2)) ** 2],
            atol=1e-5,  # float32 phase of up to 19 rad: 2e-6 rad
        )
        for phase in (True, False)
    ],
    W(
        "thinfilm.smits_meyer_multilayer",
        lambda wavelength_nm, effective_thickness_nm, A0, **k: wo.thinfilm.smits_meyer_multilayer(
            wavelength_nm, effective_thickness_nm, 5, A0, **k
        ),
        # (600 nm, 300 nm) and (400 nm, 200 nm) are peaks lambda = 2 t: the sin x = 0 limit
        [
            ("wavelength_nm", [500.0, 400.0, 600.0]),
            ("effective_thickness_nm", [200.0, 150.0, 300.0]),
            ("A0", [1.0, 2.0, 0.5]),
        ],
        _multilayer_ref,
        rtol=1e-4,  # float32 phase 2 pi t / lambda, amplified (l + 1)-fold in sin((l + 1) x)
        atol=1e-4,
    ),
    W(
        "thinfilm.smits_meyer_effective_thickness",
        lambda thickness_nm, n, angle, **k: wo.thinfilm.smits_meyer_effective_thickness(
            thickness_nm, n, angle, **k
        ),
        [("thickness_nm", [300.0, 0.0, 1200.0]), ("n", [1.33, 1.0, 1.5]), ("angle", [30.0, 0.0, 60.0])],
        lambda t, n, a: [t * np.sqrt(n**2 - np.sin(np.radians(a)) ** 2)],  # Smits & Meyer 1990 eq. 10
        atol=1e-4,
    ),
    W(
        "thinfilm.smits_meyer_morpho_thickness",
        lambda d1_nm, d2_nm, n, angle, **k: wo.thinfilm.smits_meyer_morpho_thickness(
            d1_nm, d2_nm, n, angle, **k
        ),
        [
            ("d1_nm", [100.0, 0.0, 250.0]),
            ("d2_nm", [80.0, 120.0, 0.0]),
            ("n", [1.56, 1.0, 1.33]),
            ("angle", [30.0, 0.0, 60.0]),
        ],
        # Smits & Meyer 1990 eq. 14
        lambda d1, d2, n, a: [d1 * np.cos(np.radians(a)) + d2 * np.sqrt(n**2 - np.sin(np.radians(a)) ** 2)],
        atol=1e-4,
    ),
    W(
        "fields.oil_slick_thickness[eq12]",
        lambda x, y, **k: wo.fields.oil_slick_thickness(x, y, **k),
        [("x", [0.1, 0.0, -0.5]), ("y", [0.2, 0.7, 0.3])],
        lambda x, y: [800.0 * np.exp(-3.0 * (x * x + y * y))],  # Smits & Meyer 1990 eq. 12 (k2 = 0)
        rtol=2e-6,
        atol=1e-4,
        kwargs={"k1": 3.0, "k2": 0.0, "max_thickness_nm": 800.0},
        nan_kwargs=("k1", "k2", "max_thickness_nm", "turb_scale"),
    ),
    W(
        "fields.oil_slick_thickness[eq13]",
        lambda x, y, **k: wo.fields.oil_slick_thickness(x, y, **k),
        [("x", [0.1, 0.0, -0.5]), ("y", [0.2, 0.7, 0.3])],
        None,  # Perlin turbulence: shapes, NaN and determinism only
        kwargs={"k1": 3.0, "k2": 0.3, "max_thickness_nm": 800.0, "seed": 4},
    ),
    W(
        "fields.soap_film_thickness[no noise]",
        lambda x, height, **k: wo.fields.soap_film_thickness(x, height, **k),
        [("x", [0.1, 0.0, -0.5]), ("height", [0.3, 0.0, 1.0])],
        lambda x, h: [500.0 * max(h, 0.0)],  # Smits & Meyer 1990 §4.2: proportional to the height
        atol=1e-4,
        kwargs={"k2": 0.0, "max_thickness_nm": 500.0},
        nan_kwargs=("k2", "max_thickness_nm", "turb_scale"),
    ),
    W(
        "fields.soap_film_thickness[turbulent]",
        lambda x, height, **k: wo.fields.soap_film_thickness(x, height, **k),
        [("x", [0.1, 0.0, -0.5]), ("height", [0.3, 0.0, 1.0])],
        None,
        kwargs={"k2": 0.15, "seed": 2},
    ),
    W(
        "fields.turbulence_field",
        lambda x, y, **k: wo.fields.turbulence_field(x, y, **k),
        [("x", [0.1, 0.0, -0.5]), ("y", [0.2, 0.7, 0.3])],
        None,
        kwargs={"seed": 3, "octaves": 4, "scale": 5.0},
        nan_kwargs=("scale",),
    ),
    *[
        W(
            f"spectra.sample_wavelengths[{strategy}]",
            lambda u, index, strategy=strategy, **k: wo.spectra.sample_wavelengths(
                strategy, u, index, 5, **k
            ),
            [("u", [0.5, 0.0, 0.9]), ("index", [0, 2, 4])],
            None if strategy == "importance" else _sample_ref(strategy, 5),
            rtol=1e-5,  # float32 wavelength (1e-7 relative) moves the CMF by up to 5e-6 relative
            atol=2e-6,
        )
        for strategy in ("uniform", "stratified", "importance")
    ],
    W(
        "spectra.sample_wavelengths[rgb3]",
        lambda u, index, **k: wo.spectra.sample_wavelengths("rgb3", u, index, 3, **k),
        [("u", [0.5, 0.0, 0.9]), ("index", [0, 1, 2])],
        _rgb3_ref,
        rtol=1e-5,
        atol=2e-6,
    ),
    W(
        "spectra.cmf_device",
        lambda wavelength_nm, **k: wo.spectra.cmf_device(wavelength_nm, **k),
        [("wavelength_nm", [555.0, 380.5, 700.25])],
        lambda wl: [_cmf_ref(wl)],
        atol=2e-6,
    ),
    *[
        W(
            f"stages.surfaces.bsdf_values[{kind}]",
            lambda albedo, roughness, ior, normal, w_o, w_i, kind=kind, **k: wo.stages.surfaces.bsdf_values(
                kind, albedo, roughness, ior, normal, w_o, w_i, **k
            ),
            [
                ("albedo", [0.6, 0.2, 1.0]),
                ("roughness", [0.3, 0.5, 0.8]),
                ("ior", [1.5, 1.33, 1.7]),
                ("normal", _NORMALS),
                ("wo", _UP),
                # the third light direction lies below the surface: f = pdf = 0
                ("wi", [_unit([-0.4, 0.0, 1.0]), _unit([0.5, 0.3, 0.7]), _unit([0.1, -0.6, -0.2])]),
            ],
            _bsdf_ref(kind),
            rtol=1e-5,  # float32 GGX terms
            atol=1e-6,
        )
        for kind in ("diffuse", "glossy")
    ],
    W(
        "stages.surfaces.reflectance_spectrum",
        lambda rgb, wavelength_nm, **k: wo.stages.surfaces.reflectance_spectrum(rgb, wavelength_nm, **k),
        [
            ("rgb", [np.array([0.8, 0.3, 0.1]), np.array([0.1, 0.5, 0.9]), np.ones(3)]),
            ("wavelength_nm", [550.0, 450.0, 650.0]),
        ],
        _reflectance_ref,
        atol=2e-6,
    ),
    W(
        "stages.coated.film_event[shell]",
        _film_event_fn,
        [("direction", _DIRS), ("normal", _NORMALS), ("wavelength_nm", [550.0, 400.0, 700.0])],
        _film_event_ref,
        atol=2e-6,  # float32 event, as test_coated
    ),
    W(
        "stages.coated.film_thickness[gravity]",
        _film_thickness_fn("gravity", _GRAVITY, (-2.0, 2.0, 2.0)),
        [("position", [np.array([0.0, 0.0, 1.0]), np.array([0.5, -0.3, -2.0]), np.array([1.0, 1.0, 2.0])])],
        # §4.2 without turbulence: linear in the depth below the top of the frame (z 2 .. -2)
        lambda p: [10.0 + 900.0 * (2.0 - p[2]) / 4.0],
        rtol=1e-5,
        atol=1e-4,
    ),
    W(
        "stages.coated.film_thickness[oil_drop]",
        _film_thickness_fn("oil_drop", _OIL, (0.0, 0.0, 10.0)),
        [("position", [np.array([2.0, 1.0, 0.0]), np.array([0.0, 0.0, 3.0]), np.array([-6.0, 4.0, 1.0])])],
        # eq. 12 in units of the half size 10 mm: t_max exp(-k1 (u^2 + v^2))
        lambda p: [1200.0 * np.exp(-2.5 * ((p[0] / 10) ** 2 + (p[1] / 10) ** 2))],
        rtol=1e-5,
        atol=1e-4,
    ),
    W(
        "thinfilm.ColorTable.lookup",
        lambda x, **k: _table(k["device"]).lookup(x, **k),
        # between entries, on the first one, and beyond the last (clamped)
        [("x", [123.4, 0.0, 2000.0])],
        _lookup_ref,
        atol=1e-6,  # float32 table and weights
    ),
    W(
        "materials.Isotropic.n[sellmeier]",
        lambda wavelength_nm, **k: _material("bk7").n(wavelength_nm, **k),
        [("wavelength_nm", [587.56, 400.0, 700.0])],
        lambda wl: [_sellmeier(wl, _BK7_B, _BK7_C)],
    ),
    W(
        "materials.Isotropic.k[table]",
        lambda wavelength_nm, **k: _material("table").k(wavelength_nm, **k),
        [("wavelength_nm", [550.0, 400.0, 780.0])],
        lambda wl: [np.interp(wl, _TAB_WL, _TAB_K)],
        atol=1e-9,  # k ~ 1e-4, float32
    ),
    W(
        "materials.Isotropic.alpha[table]",
        lambda wavelength_nm, **k: _material("table").alpha(wavelength_nm, **k),
        [("wavelength_nm", [550.0, 400.0, 780.0])],
        lambda wl: [
            4 * np.pi * np.interp(wl, _TAB_WL, _TAB_K) / (wl * 1e-6)
        ],  # alpha = 4 pi k / lambda, 1/mm
        rtol=1e-5,
        atol=1e-6,
    ),
    W(
        "materials.Uniaxial.n[cauchy]",
        lambda wavelength_nm, **k: _material("uniaxial").n(wavelength_nm, **k),
        [("wavelength_nm", [589.3, 400.0, 700.0])],
        # Cauchy n = A + B / lambda^2, lambda in um, per channel (o, e)
        lambda wl: [np.array([1.65 + 0.01 / (wl * 1e-3) ** 2, 1.48 + 0.004 / (wl * 1e-3) ** 2])],
    ),
    W(
        "color.gamut_clip[max_value]",
        lambda xyz, max_value, **kw: wo.color.gamut_clip(xyz, max_value, **kw),
        # in gamut at max 1, a saturated green (negative red and blue), a bright magenta
        [
            ("xyz", [np.array([0.3, 0.35, 0.25]), np.array([0.2, 0.5, 0.05]), np.array([0.6, 0.3, 0.9])]),
            ("max_value", [1.0, 0.8, 2.0]),
        ],
        _gamut_clip_ref,
        rtol=2e-4,  # the IEC matrix is given to 4 decimals
        atol=2e-4,
    ),
]


def _slab_phase_ref(q, q_ref, d, lam):
    return [np.exp(2j * np.pi * (q - q_ref) * d * 1e6 / lam)]


def _wave_plate_ref(angle, gamma, lam):
    # Yariv & Yeh §5.1: R(-t) diag(exp(i 2 pi Gamma / lambda), 1) R(t), the slow axis first
    t = np.radians(angle)
    r = np.array([[np.cos(t), np.sin(t)], [-np.sin(t), np.cos(t)]])
    return [r.T @ np.diag([np.exp(2j * np.pi * gamma / lam), 1.0]) @ r]


def _active_retarder_ref(delta, tau):
    # exp of the coupled-wave generator [[-i d/2, -t], [t, i d/2]] (Jones 1948), by scipy
    from scipy.linalg import expm

    return [expm(np.array([[-0.5j * delta, -tau], [tau, 0.5j * delta]]))]


def _principal_ref(sxx, syy, txy):
    # Mohr's circle by an eigen-decomposition of the stress tensor
    w, v = np.linalg.eigh(np.array([[sxx, txy], [txy, syy]]))
    t = np.degrees(np.arctan2(v[1, 1], v[0, 1]))
    t = (t + 90.0) % 180.0 - 90.0  # the direction modulo 180, in (-90, 90]
    return [w[1], w[0], t if sxx != syy or txy != 0 else 0.0]


def _photoelastic_ref(sxx, syy, txy, c, d, lam):
    # a retarder of C d (s1 - s2) with its slow axis along sigma_1 (Brewster's law), as
    # _wave_plate_ref: R(-t) diag(exp(i 2 pi Delta / lambda), 1) R(t)
    w, v = np.linalg.eigh(np.array([[sxx, txy], [txy, syy]]))
    t = np.arctan2(v[1, 1], v[0, 1])
    r = np.array([[np.cos(t), np.sin(t)], [-np.sin(t), np.cos(t)]])
    return [r.T @ np.diag([np.exp(2j * np.pi * c * d * (w[1] - w[0]) / lam), 1.0]) @ r]


WRAPPERS += [
    W(
        "optics.plate.slab_phases",
        lambda q, q_ref, d, lam, **k: wo.optics.plate.slab_phases(q, q_ref, d, lam, **k),
        [
            ("q", [1.5, 1.66, 1.0]),
            ("q_ref", [1.0, 1.0, 1.33]),
            ("thickness_mm", [0.01, 0.002, 0.05]),
            ("wavelength_nm", [589.0, 400.0, 700.0]),
        ],
        _slab_phase_ref,
        rtol=0.0,
        atol=5e-5,  # phases up to 150 rad: the float32 rounding of the inputs (1.33) moves them 1e-5
    ),
    W(
        "optics.plate.wave_plates",
        lambda a, g, lam, **k: wo.optics.plate.wave_plates(a, g, lam, **k),
        [
            ("slow_angle_deg", [45.0, 10.0, 120.0]),
            ("retardation_nm", [550.0, 147.0, 0.0]),
            ("wavelength_nm", [589.0, 450.0, 700.0]),
        ],
        _wave_plate_ref,
        atol=2e-6,
    ),
    W(
        "optics.plate_jones",
        lambda k, lam, n3, d, **kw: wo.optics.plate_jones(k, lam, n3, d, crystal_axes=(1.0, 1.0, 0.2), **kw),
        [
            ("direction", [_unit([0.1, 0.2, 1.0]), _unit([0.0, 0.0, 1.0]), _unit([-0.4, 0.1, 0.9])]),
            ("wavelength_nm", [589.0, 450.0, 700.0]),
            (
                "indices",
                [np.array([1.658, 0.0, 1.486]), np.array([1.544, 0.0, 1.553]), np.array([1.69, 1.694, 1.70])],
            ),
            ("thickness_mm", [0.01, 0.03, 0.002]),
        ],
        None,  # tests/test_plate.py holds the closed forms and the Berreman reference
    ),
    W(
        "optics.plate.active_retarders",
        lambda d, t, **k: wo.optics.plate.active_retarders(d, t, **k),
        [("retardation_rad", [2.5, 0.0, -7.0]), ("rotation_rad", [0.6, 0.7, 0.0])],
        _active_retarder_ref,
        atol=2e-6,
    ),
    W(
        "optics.plate.rotatory_powers",
        lambda c, r, g, **k: wo.optics.plate.rotatory_powers(c, r, g, **k),
        [
            ("cos_axis", [1.0, 0.5, 0.0]),
            ("rho_axis", [0.379, -0.2, 0.1]),
            ("perpendicular_ratio", [-0.5, 0.0, 0.3]),
        ],
        lambda c, r, g: [r * (c**2 + g * (1 - c**2))],
    ),
    W(
        "optics.plate.active_plate_jones",
        lambda k, lam, n3, d, rho, **kw: wo.optics.plate.active_plate_jones(
            k, lam, n3, d, rho, optic_axis=(1.0, 1.0, 0.2), **kw
        ),
        [
            ("direction", [_unit([0.1, 0.2, 1.0]), _unit([0.0, 0.0, 1.0]), _unit([-0.4, 0.1, 0.9])]),
            ("wavelength_nm", [589.0, 450.0, 700.0]),
            (
                "indices",
                [np.array([1.544, 0.0, 1.553]), np.array([1.658, 0.0, 1.486]), np.array([1.5, 0.0, 1.5])],
            ),
            ("thickness_mm", [0.01, 0.03, 0.002]),
            ("rho_axis_rad_mm", [0.379, -0.379, 0.0]),
        ],
        None,  # tests/test_activity.py holds the N-slice and closed-form references
    ),
    W(
        "optics.photoelastic.principal_stresses",
        lambda a, b, c, **k: wo.optics.photoelastic.principal_stresses(a, b, c, **k),
        [("sxx_mpa", [10.0, -3.0, 5.0]), ("syy_mpa", [-5.0, 4.0, 5.0]), ("txy_mpa", [3.0, -2.0, 0.0])],
        _principal_ref,
        rtol=2e-6,
        atol=2e-5,  # stresses ~10 MPa in float32
    ),
    W(
        "optics.photoelastic.stress_retardations",
        lambda c, d, s1, s2, **k: wo.optics.photoelastic.stress_retardations(c, d, s1, s2, **k),
        [
            ("c_tpa", [2.77, 3.5, -1.0]),
            ("thickness_mm", [5.0, 1.0, 2.0]),
            ("sigma_1_mpa", [20.0, 3.0, 0.0]),
            ("sigma_2_mpa", [-5.0, 3.0, -4.0]),
        ],
        lambda c, d, s1, s2: [c * d * (s1 - s2)],
        atol=2e-5,
    ),
    W(
        "optics.photoelastic.photoelastic_plates",
        lambda a, b, c, k, d, lam, **kw: wo.optics.photoelastic.photoelastic_plates(a, b, c, k, d, lam, **kw),
        [
            ("sxx_mpa", [10.0, -3.0, 5.0]),
            ("syy_mpa", [-5.0, 4.0, 5.0]),
            ("txy_mpa", [3.0, -2.0, 0.0]),
            ("c_tpa", [2.77, 3.5, 2.77]),
            ("thickness_mm", [5.0, 1.0, 2.0]),
            ("wavelength_nm", [589.0, 450.0, 700.0]),
        ],
        _photoelastic_ref,
        atol=1e-5,  # phases of a few rad from float32 inputs
    ),
]

IDS = [w.name for w in WRAPPERS]


def _outputs(result) -> list[np.ndarray]:
    if isinstance(result, tuple | list):
        return [np.asarray(r) for r in result]
    return [np.asarray(result)]


def _call(w: W, values, device, **extra):
    return _outputs(w.fn(*values, **{**w.kwargs, **extra}, device=device))


def _defaults(w: W):
    return [np.asarray(v[0]) for _, v in w.args]


def _expected(w: W, point, device):
    """The closed form at item-shaped inputs, or (noise, no closed form) the wrapper's own
    item-shaped call: the shape tests then check that broadcasting changes nothing."""
    if w.ref is not None:
        return w.ref(*point)
    return _call(w, point, device)


def _assert_close(got, want, w: W):
    assert len(got) == len(want)
    for g, r in zip(got, want, strict=True):
        r = np.asarray(r)
        assert g.shape == r.shape, (g.shape, r.shape)
        np.testing.assert_allclose(g, r, rtol=w.rtol, atol=w.atol)


WITH_REF = [w for w in WRAPPERS if w.ref is not None]


@pytest.mark.parametrize("w", WITH_REF, ids=[w.name for w in WITH_REF])
def test_reference_value(device, w):
    for k in range(3):
        values = [np.asarray(v[k]) for _, v in w.args]
        _assert_close(_call(w, values, device), w.ref(*values), w)


@pytest.mark.parametrize("w", WRAPPERS, ids=IDS)
def test_one_dimensional(device, w):
    """The first argument as a (3, ...) array, the others item-shaped: (3, ...) out, row by row."""
    name, vals = w.args[0]
    values = [np.stack([np.asarray(v) for v in vals])] + _defaults(w)[1:]
    got = _call(w, values, device)
    for k in range(3):
        row = [np.asarray(vals[k])] + _defaults(w)[1:]
        _assert_close([g[k] for g in got], _expected(w, row, device), w)


@pytest.mark.parametrize("w", WRAPPERS, ids=IDS)
def test_n_dimensional_broadcasting(device, w):
    """The first argument (3, 1, ...), the last (1, 2, ...), the rest item-shaped: (3, 2, ...)."""
    d = _defaults(w)
    first = np.stack([np.asarray(v) for v in w.args[0][1]])[:, None]
    last = np.stack([np.asarray(v) for v in w.args[-1][1][:2]])[None, :]
    values = [first, *d[1:-1], last] if len(d) > 1 else [np.stack([first] * 2, axis=1)[:, :, 0]]
    got = _call(w, values, device)
    for i in range(3):
        for j in range(2):
            if len(d) > 1:
                point = [np.asarray(w.args[0][1][i]), *d[1:-1], np.asarray(w.args[-1][1][j])]
            else:
                point = [np.asarray(w.args[0][1][i])]
            _assert_close([g[i, j] for g in got], _expected(w, point, device), w)


@pytest.mark.parametrize("w", WRAPPERS, ids=IDS)
def test_empty(device, w):
    d = _defaults(w)
    values = [np.zeros((0, *d[0].shape)), *d[1:]]
    got = _call(w, values, device)
    want = _expected(w, d, device)
    for g, r in zip(got, want, strict=True):
        assert g.shape == (0, *np.shape(r))


NAN_CASES = [
    pytest.param(w, i, bad, id=f"{w.name}-{name}-{bad}")
    for w in WRAPPERS
    for i, (name, _) in enumerate(w.args)
    for bad in (np.nan, np.inf, -np.inf)
]


@pytest.mark.parametrize(("w", "index", "bad"), NAN_CASES)
def test_non_finite_input_is_an_input_error(device, w, index, bad):
    values = [v.astype(complex if np.iscomplexobj(v) else float) for v in _defaults(w)]
    values[index].flat[-1] = bad  # the last component: a vector's z, a matrix's yy
    with pytest.raises(InputError) as info:
        _call(w, values, device)
    msg = str(info.value)
    assert w.args[index][0] in msg and "\n" not in msg, msg


@pytest.mark.parametrize(
    ("w", "index"),
    [pytest.param(w, i, id=f"{w.name}-{n}") for w in WRAPPERS for i, (n, _) in enumerate(w.args)],
)
def test_non_finite_in_a_large_array_is_one_line(device, w, index):
    """A NaN deep inside a (4, 50, ...) argument: still one line naming the argument (the message
    must not print the array, whose repr spans lines)."""
    values = [v.astype(complex if np.iscomplexobj(v) else float) for v in _defaults(w)]
    big = np.broadcast_to(values[index], (4, 50, *values[index].shape)).copy()
    big.reshape(4, 50, -1)[2, 17, -1] = np.nan  # a view: item (2, 17), its last component
    values[index] = big
    with pytest.raises(InputError) as info:
        _call(w, values, device)
    msg = str(info.value)
    assert w.args[index][0] in msg and "\n" not in msg, msg


KW_NAN_CASES = [
    pytest.param(w, name, bad, id=f"{w.name}-{name}-{bad}")
    for w in WRAPPERS
    for name in w.nan_kwargs
    for bad in (np.nan, np.inf, -np.inf)
]


@pytest.mark.parametrize(("w", "name", "bad"), KW_NAN_CASES)
def test_non_finite_keyword_is_an_input_error(device, w, name, bad):
    with pytest.raises(InputError) as info:
        _call(w, _defaults(w), device, **{name: bad})
    msg = str(info.value)
    assert name in msg and "\n" not in msg, msg


NOISE = [w for w in WRAPPERS if "seed" in w.kwargs]  # the Perlin-turbulence fields


@pytest.mark.parametrize("w", NOISE, ids=[w.name for w in NOISE])
def test_noise_is_deterministic_and_seeded(device, w):
    """The same inputs and seed give the same values bit for bit; another seed other values;
    turbulence (Perlin 1985: a sum of |noise|) and film thicknesses are >= 0."""
    x = np.linspace(-0.9, 0.9, 37)
    values = [x, np.abs(x[::-1])]
    a = _call(w, values, device)
    b = _call(w, values, device)
    for ga, gb in zip(a, b, strict=True):
        np.testing.assert_array_equal(ga, gb)
    c = _call(w, values, device, seed=w.kwargs["seed"] + 1)
    assert not np.allclose(c[0], a[0])
    assert np.all(a[0] >= 0) and np.all(np.isfinite(a[0]))


# ---------------------------------------------------------------------------------------------
# The naming rule (docs/architecture.md, "Naming"): every element-wise wrapper ``f`` names the
# ``@wp.func`` it launches as ``f.wp``; a device function that would share its wrapper's name
# carries the suffix ``_wp`` (no other suffixes: ``_func``, ``_f``).  Methods of material and
# colour-table objects evaluate through the device-side material table / table lookup instead.
# ---------------------------------------------------------------------------------------------


def _public(name: str):
    obj = wo
    for part in name.split("[")[0].split("."):
        obj = getattr(obj, part)
    return obj


_FUNCTION_WRAPPERS = sorted(
    {w.name.split("[")[0] for w in WRAPPERS if not any(c.isupper() for c in w.name.split("[")[0])}
)


@pytest.mark.parametrize("name", _FUNCTION_WRAPPERS)
def test_wrapper_names_its_device_function(name):
    import ast
    import inspect

    fn = _public(name)
    func = getattr(fn, "wp", None)
    assert type(func).__name__ == "Function" and type(func).__module__.startswith("warp"), (
        f"{name} has no .wp device function"
    )
    key = func.key
    assert key != fn.__name__
    assert not key.endswith(("_func", "_f")), key
    # the wrapper's module launches a kernel that calls the device function it names
    tree = ast.parse(inspect.getsource(inspect.getmodule(fn)))
    called = {
        ast.unparse(node.func).split(".")[-1]
        for k in tree.body
        if isinstance(k, ast.FunctionDef) and any("kernel" in ast.unparse(d) for d in k.decorator_list)
        for node in ast.walk(k)
        if isinstance(node, ast.Call)
    }
    assert key in called, f"no kernel of {fn.__module__} calls {key}"


def test_no_device_function_has_an_old_suffix():
    import ast
    from pathlib import Path

    bad = []
    for path in Path(wo.__file__).parent.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.FunctionDef) and any(
                "wp.func" in ast.unparse(d) for d in node.decorator_list
            ):
                if not node.name.startswith("_") and node.name.endswith(("_func", "_f")):
                    bad.append(f"{path.name}:{node.name}")
    assert not bad

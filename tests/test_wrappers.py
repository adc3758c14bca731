"""Every public element-wise NumPy wrapper of a ``@wp.func``, colour-science's trio per function:

- a reference value from an independent closed form (written here in NumPy, float64/complex128);
- shapes: item-shaped in -> item-shaped out, 1-D, n-D broadcasting of two arguments (each element
  equal to the closed form at its own inputs), empty arrays;
- edge cases: NaN and +-Inf in any argument raise ``InputError`` naming that argument.

Public import paths only (``wo.optics.fresnel``...): the modules are being reorganized.
Tolerances: the kernels run in float32 (DESIGN.md, "Precision"), so 2e-6 relative plus an absolute
floor for values near zero covers rounding; compiled with FMA, hence not bit-exact.
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
    ref: Callable  # the closed form: item-shaped inputs -> list of item-shaped outputs
    rtol: float = 2e-6
    atol: float = 2e-6
    kwargs: dict = field(default_factory=dict)


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


def _film_ref(pol):
    """Single film on a substrate: the Airy sum of the two interfaces (Born & Wolf §7.6.1,
    Hecht eq. 9.88), n_film = 1.38, d = 120 nm (a MgF2 anti-reflection layer on glass)."""
    n_f, d = 1.38, 120.0

    def one(wl, angle, n0, n2, kind):
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

    def ref(wl, angle, n0, n2):
        rs, ts = one(wl, angle, n0, n2, "s")
        rp, tp = one(wl, angle, n0, n2, "p")
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
IDS = [w.name for w in WRAPPERS]


def _outputs(result) -> list[np.ndarray]:
    if isinstance(result, tuple | list):
        return [np.asarray(r) for r in result]
    return [np.asarray(result)]


def _call(w: W, values, device):
    return _outputs(w.fn(*values, **w.kwargs, device=device))


def _defaults(w: W):
    return [np.asarray(v[0]) for _, v in w.args]


def _assert_close(got, want, w: W):
    assert len(got) == len(want)
    for g, r in zip(got, want, strict=True):
        r = np.asarray(r)
        assert g.shape == r.shape, (g.shape, r.shape)
        np.testing.assert_allclose(g, r, rtol=w.rtol, atol=w.atol)


@pytest.mark.parametrize("w", WRAPPERS, ids=IDS)
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
        _assert_close([g[k] for g in got], w.ref(*row), w)


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
            _assert_close([g[i, j] for g in got], w.ref(*point), w)


@pytest.mark.parametrize("w", WRAPPERS, ids=IDS)
def test_empty(device, w):
    d = _defaults(w)
    values = [np.zeros((0, *d[0].shape)), *d[1:]]
    got = _call(w, values, device)
    want = w.ref(*d)
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

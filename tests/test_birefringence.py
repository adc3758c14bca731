"""Uniaxial crystals (warpoptics.optics.birefringence) against a direct numerical solution of the
plane-wave problem written here, the isotropic Fresnel formulas and Maxwell's boundary conditions.

Reference (float64, independent of the code under test): for a medium of dielectric tensor
eps = no^2 I + (ne^2 - no^2) a a^T a plane wave exp(i k.r) (k in units of k0) exists iff the
wave-equation matrix W(k) = k k^T - (k.k) I + eps is singular (k x (k x E) + eps E = 0).  With the
tangential wave vector kt conserved, det W(kt + q m) is a quartic in q, fitted from samples and
solved with numpy; E is the null vector of W, D = eps E, H = k x E and the Poynting vector is
S = Re(E x conj(H)).

Tolerances: the kernels run in float32.  Unit vectors built from O(1) products carry errors of a
few 1e-7; the e-wave normal component q comes from a square root of a discriminant, whose
relative error grows as 1/q near grazing transmission, so direction tests use configurations
whose ray leaves the surface at more than ~3 degrees (a few 1e-6 expected); near-critical ones
are only checked for finiteness.
"""

import numpy as np
import pytest

import warpoptics as wo
from warpoptics.errors import InputError

opt = wo.optics


# ----------------------------------------------------------------------------------------------
# independent reference


def eps_tensor(no, ne, a):
    a = np.asarray(a, float)
    return no**2 * np.eye(3) + (ne**2 - no**2) * np.outer(a, a)


def wave_matrix(k, eps):
    k = np.asarray(k)
    return np.outer(k, k) - (k @ k) * np.eye(3) + eps  # bilinear (no conjugation): complex k ok


def det_roots(kt, m, eps):
    """All four q with det W(kt + q m) = 0 (det is a quartic in q)."""
    qs = np.linspace(-4.0, 4.0, 9)
    dets = [np.linalg.det(wave_matrix(kt + q * m, eps)) for q in qs]
    coef = np.polynomial.polynomial.polyfit(qs, dets, 4)
    return np.polynomial.polynomial.polyroots(coef)


def null_vector(w):
    _, _, vh = np.linalg.svd(w)
    return vh[-1].conj()


def poynting(k, e):
    h = np.cross(k, e)
    return np.real(np.cross(e, np.conj(h)))


def numeric_e_wave(kt, m, no, ne, a):
    """The propagating extraordinary wave (k, ray) with energy flowing along +m, or None."""
    eps = eps_tensor(no, ne, a)
    roots = det_roots(kt, m, eps)
    q_o = np.sqrt(max(no**2 - kt @ kt, 0.0)) if no**2 - kt @ kt > 0 else None
    cands = []
    for q in roots:
        if abs(q.imag) > 1e-7 * max(1, abs(q)):
            continue
        q = q.real
        if q_o is not None and min(abs(q - q_o), abs(q + q_o)) < 1e-6:
            continue  # an o-wave root
        k = kt + q * m
        e = null_vector(wave_matrix(k, eps)).real
        s = poynting(k, e)
        if s @ m > 0:
            cands.append((k, s / np.linalg.norm(s), e))
    if len(cands) != 1:
        return None
    return cands[0]


def numeric_e_index(s, no, ne, a):
    """n of the e-wave along unit wave normal s: det(eps - n^2 (I - s s^T)) = 0, quadratic in n^2."""
    eps = eps_tensor(no, ne, a)
    xs = np.array([0.5, 1.5, 2.5, 4.0, 6.0])
    dets = [np.linalg.det(eps - x * (np.eye(3) - np.outer(s, s))) for x in xs]
    roots = np.polynomial.polynomial.polyroots(np.polynomial.polynomial.polyfit(xs, dets, 2)).real
    # the e root is the one that is not no^2 (both equal along the axis)
    x = roots[np.argmax(np.abs(roots - no**2))]
    return np.sqrt(x)


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _angle(u, v):
    return np.arctan2(np.linalg.norm(np.cross(u, v), axis=-1), np.sum(u * v, axis=-1))


def _f32(x):
    # the kernels see float32 inputs: give the float64 reference exactly the same ones
    return np.asarray(x, np.float32).astype(np.float64)


def _random_setup(rng, n):
    normal = _f32(_unit(rng.normal(size=(n, 3))))
    d = _unit(rng.normal(size=(n, 3)))
    d = _f32(np.where(np.sum(d * normal, -1, keepdims=True) > 0, -d, d))  # towards the surface
    axis = _f32(_unit(rng.normal(size=(n, 3))))
    no = _f32(rng.uniform(1.4, 2.5, n))
    dn = rng.uniform(0.01, 0.25, n) * rng.choice([-1, 1], n)
    return d, normal, axis, no, _f32(no + dn)


# ----------------------------------------------------------------------------------------------
# indices, frames, eigenpolarizations


def test_extraordinary_index(device):
    rng = np.random.default_rng(0)
    s = _unit(rng.normal(size=(200, 3)))
    a = _unit(rng.normal(size=(200, 3)))
    no = rng.uniform(1.4, 2.5, 200)
    ne = no + rng.uniform(-0.2, 0.2, 200)
    got = opt.extraordinary_index(np.sum(s * a, -1), no, ne, device=device)
    want = np.array([numeric_e_index(s[i], no[i], ne[i], a[i]) for i in range(200)])
    np.testing.assert_allclose(got, want, rtol=1e-6)
    assert opt.extraordinary_index(1.0, 1.544, 1.553, device=device) == pytest.approx(1.544, rel=1e-7)
    assert opt.extraordinary_index(0.0, 1.544, 1.553, device=device) == pytest.approx(1.553, rel=1e-7)


def test_oe_eigenpolarizations(device):
    rng = np.random.default_rng(1)
    n = 300
    s = _unit(rng.normal(size=(n, 3)))
    a = _unit(rng.normal(size=(n, 3)))
    no = rng.uniform(1.4, 2.5, n)
    ne = no + rng.uniform(-0.2, 0.2, n)
    x, y, ee = opt.oe_polarizations(s, a, no, ne, device=device)
    # eq. 2: X_a = a x s / |a x s|, Y_a = s x X_a
    np.testing.assert_allclose(x, _unit(np.cross(a, s)), atol=2e-6)
    np.testing.assert_allclose(y, np.cross(s, x), atol=2e-6)
    for i in range(n):
        eps = eps_tensor(no[i], ne[i], a[i])
        d_field = eps @ ee[i]
        # D = eps E of the e-wave vibrates along Y_a (eq. 2), E is a mode of the wave equation
        assert np.linalg.norm(np.cross(d_field, y[i])) < 2e-6 * np.linalg.norm(d_field)
        k = numeric_e_index(s[i], no[i], ne[i], a[i]) * s[i]
        assert np.linalg.norm(wave_matrix(k, eps) @ ee[i]) < 2e-5
        # the o-wave field X_a is a mode with n = no
        assert np.linalg.norm(wave_matrix(no[i] * s[i], eps) @ x[i]) < 2e-5
    # along the optic axis: finite orthonormal frame
    x, y, ee = opt.oe_polarizations([0, 0, 1.0], [0, 0, 1.0], 1.5, 1.6, device=device)
    assert np.all(np.isfinite(np.concatenate([x, y, ee])))
    assert abs(x @ y) < 1e-7 and abs(np.linalg.norm(x) - 1) < 1e-6 and abs(x[2]) < 1e-7


# ----------------------------------------------------------------------------------------------
# extraordinary directions


def _direction_errors(device, internal: bool, n_cases: int, seed: int):
    rng = np.random.default_rng(seed)
    d, normal, axis, no, ne = _random_setup(rng, n_cases)
    if internal:
        # an o- or e-wave inside the crystal hitting the surface (normal points into the crystal)
        is_e = rng.random(n_cases) < 0.5
        n_in = _f32(
            np.where(is_e, [numeric_e_index(d[i], no[i], ne[i], axis[i]) for i in range(n_cases)], no)
        )
        wave, ray, n_eff = opt.reflect_extraordinary(
            d, normal, axis, n_in, no, ne, return_index=True, device=device
        )
        side = 1.0
    else:
        n_in = _f32(rng.uniform(1.0, 2.5, n_cases))
        wave, ray, n_eff = opt.refract_extraordinary(
            d, normal, axis, n_in, no, ne, return_index=True, device=device
        )
        side = -1.0
    assert np.all(np.isfinite(wave)) and np.all(np.isfinite(ray))
    errs = {"wave": [], "ray": [], "tangential": [], "ellipsoid": [], "d_perp_k": []}
    checked = evanescent = 0
    for i in range(n_cases):
        m = side * normal[i]
        kt = n_in[i] * (d[i] - (d[i] @ normal[i]) * normal[i])
        ref = numeric_e_wave(kt, m, no[i], ne[i], axis[i])
        if ref is None:
            # no propagating e-wave (total reflection): the wrapper returns zeros
            if np.linalg.norm(wave[i]) == 0:
                evanescent += 1
            continue
        k_ref, ray_ref, e_ref = ref
        if ray_ref @ m < 0.05:
            # near-grazing energy flow (double root of the quartic: the normal component of k
            # is a square root of a vanishing discriminant): only finiteness is checked
            continue
        checked += 1
        k = n_eff[i] * wave[i]
        errs["wave"].append(_angle(wave[i], k_ref))
        errs["ray"].append(_angle(ray[i], ray_ref))
        errs["tangential"].append(np.linalg.norm((k - (k @ normal[i]) * normal[i]) - kt))
        # index ellipsoid: (k.a)^2/no^2 + (|k|^2 - (k.a)^2)/ne^2 = 1
        ka = k @ axis[i]
        errs["ellipsoid"].append(abs(ka**2 / no[i] ** 2 + (k @ k - ka**2) / ne[i] ** 2 - 1))
        # D = eps E is transverse to k
        eps = eps_tensor(no[i], ne[i], axis[i])
        dd = eps @ e_ref
        errs["d_perp_k"].append(abs(dd @ wave[i]) / np.linalg.norm(dd))
    return {k: max(v) for k, v in errs.items()}, checked, evanescent


@pytest.mark.parametrize("internal", [False, True], ids=["refraction_eq3", "internal_reflection_eq4"])
def test_extraordinary_directions_vs_numerical_solution(device, internal):
    worst, checked, evanescent = _direction_errors(device, internal, 1500, seed=2 + internal)
    print(f"{'internal reflection' if internal else 'refraction'}: {checked} checked, worst", worst)
    assert checked > 800
    assert worst["wave"] < 1e-5, worst
    assert worst["ray"] < 1e-5, worst
    assert worst["tangential"] < 1e-5, worst
    assert worst["ellipsoid"] < 1e-5, worst
    assert worst["d_perp_k"] < 1e-5, worst
    if internal:
        assert evanescent > 0  # internal reflection o -> e can be evanescent (ne < no crystals)


def test_incidence_along_the_optic_axis(device):
    z = np.array([0.0, 0.0, 1.0])
    # normal incidence on a c-cut crystal: e-wave along the axis, index no, no walk-off
    wave, ray, n = opt.refract_extraordinary(-z, z, z, 1.0, 1.768, 1.760, return_index=True, device=device)
    np.testing.assert_allclose(wave, -z, atol=1e-7)
    np.testing.assert_allclose(ray, -z, atol=1e-7)
    assert n == pytest.approx(1.768, rel=1e-6)
    # oblique incidence with the axis along the refracted o direction: e = o there
    th = np.radians(40.0)
    d = np.array([np.sin(th), 0.0, -np.cos(th)])
    sin_t = np.sin(th) / 1.768
    a = np.array([sin_t, 0.0, -np.sqrt(1 - sin_t**2)])
    wave, ray, n = opt.refract_extraordinary(d, z, a, 1.0, 1.768, 1.760, return_index=True, device=device)
    assert _angle(wave, a) < 2e-6 and _angle(ray, a) < 2e-6 and n == pytest.approx(1.768, rel=1e-6)
    for axis in (z, a):
        for dd in (-z, d):
            for mode in "oe":
                res = opt.generalized_fresnel_coefficients(
                    dd, z, 1.0, (1.768, 1.760, axis), mode=mode, device=device
                )
                assert np.all(np.isfinite(res.coefficients))
                assert res.energy().sum() == pytest.approx(1.0, abs=2e-5)


# ----------------------------------------------------------------------------------------------
# generalized Fresnel coefficients (eq. 5)


def _angle_forms(theta_i, n1, n2):
    theta_t = np.arcsin(n1 * np.sin(theta_i) / n2)
    s, d = theta_i + theta_t, theta_i - theta_t
    return (
        -np.sin(d) / np.sin(s),
        np.tan(d) / np.tan(s),
        2 * np.sin(theta_t) * np.cos(theta_i) / np.sin(s),
        2 * np.sin(theta_t) * np.cos(theta_i) / (np.sin(s) * np.cos(d)),
    )


def test_eq5_reduces_to_isotropic_fresnel(device):
    """Fig. 2: both media isotropic ('optical axis' = normal) gives the Fresnel formulas."""
    theta = np.radians(np.linspace(0.5, 89.5, 179))
    z = np.array([0.0, 0.0, 1.0])
    for n1, n2 in [(1.0, 1.5), (1.0, 2.417), (2.417, 1.0), (1.33, 1.0)]:
        phi = 0.7  # plane of incidence at an arbitrary azimuth
        d = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), -np.cos(theta)], -1)
        so = opt.generalized_fresnel_coefficients(d, z, n1, n2, mode="o", device=device).coefficients
        se = opt.generalized_fresnel_coefficients(d, z, n1, n2, mode="e", device=device).coefficients
        rs, rp, ts, tp = opt.fresnel(np.cos(theta), n1, n2, device=device)
        print(
            f"{n1} -> {n2}: worst |eq5 - Fresnel| r_s {np.abs(so[:, 0] - rs).max():.1e}, "
            f"r_p {np.abs(se[:, 1] - rp).max():.1e}"
        )
        # same values as the isotropic Fresnel amplitudes, incl. the TIR phase ...
        np.testing.assert_allclose(so[:, 0], rs, atol=1e-5)
        np.testing.assert_allclose(se[:, 1], rp, atol=1e-5)
        np.testing.assert_allclose(so[:, 1], 0, atol=1e-5)
        np.testing.assert_allclose(se[:, 0], 0, atol=1e-5)
        prop = n1 * np.sin(theta) < n2 - 1e-3
        np.testing.assert_allclose(so[prop, 2], ts[prop], atol=1e-5)
        np.testing.assert_allclose(se[prop, 3], tp[prop], atol=1e-5)
        # ... and as the closed (angle) forms of fig. 2 where the wave is transmitted
        want = _angle_forms(theta[prop], n1, n2)
        np.testing.assert_allclose(so[prop, 0], want[0], atol=1e-5)
        np.testing.assert_allclose(se[prop, 1], want[1], atol=1e-5)
        np.testing.assert_allclose(so[prop, 2], want[2], atol=1e-5)
        np.testing.assert_allclose(se[prop, 3], want[3], atol=1e-5)
        # total reflection: |r| = 1
        np.testing.assert_allclose(np.abs(so[~prop, 0]), 1, atol=1e-5)
        np.testing.assert_allclose(np.abs(se[~prop, 1]), 1, atol=1e-5)


def test_eq10_exact_when_no_equals_ne(device):
    """With no = ne and an arbitrary optic axis, eq. 5 in o/e frames equals eq. 10 (rotated
    isotropic Fresnel amplitudes): 'Equality holds when no = ne'."""
    rng = np.random.default_rng(7)
    n = 400
    d, normal, axis, no, _ = _random_setup(rng, n)
    n1 = rng.uniform(1.0, 1.6, n)
    med2 = (no, no, axis)
    mr, mt = opt.fresnel_matrices(d, normal, n1, med2, device=device)
    ar, at = opt.fresnel_matrices(d, normal, n1, med2, approx=True, n1=n1, n2=no, device=device)
    # float32: near grazing incidence r changes fast with cos_i (dr/dcos_i ~ 2/(n2 cos_t)), so
    # the rounding of two different computations differs more there
    steep = -np.sum(d * normal, -1) < 0.1
    print(
        f"eq. 5 vs eq. 10 with no = ne: worst |diff| r {np.abs(mr - ar).max():.2e}, "
        f"t {np.abs(mt - at).max():.2e}"
    )
    for exact, approx in ((mr, ar), (mt, at)):
        np.testing.assert_allclose(exact[~steep], approx[~steep], atol=2e-5)
        np.testing.assert_allclose(exact[steep], approx[steep], atol=2e-4)


def _maxwell_check(res, med1, med2, normal):
    """Residuals of Maxwell's equations for the eq. 5 solution (NumPy, float64)."""
    out = {"mode": 0.0, "bc_e": 0.0, "bc_h": 0.0, "energy": 0.0, "tangential": 0.0, "flux": 0.0}
    n = res.coefficients.shape[0]
    for i in range(n):
        k = res.k[i]
        e = res.e[i]
        c = res.coefficients[i]
        nrm = normal[i]
        eps1 = eps_tensor(med1[0][i], med1[1][i], med1[2][i])
        eps2 = eps_tensor(med2[0][i], med2[1][i], med2[2][i])
        for j, eps in enumerate([eps1, eps1, eps1, eps2, eps2]):
            out["mode"] = max(out["mode"], np.linalg.norm(wave_matrix(k[j], eps) @ e[j]))
            kt = k[j] - (k[j] @ nrm) * nrm
            out["tangential"] = max(out["tangential"], np.linalg.norm(kt - (k[0] - (k[0] @ nrm) * nrm)))
        h = np.cross(k, e)
        amp = np.array([1.0, c[0], c[1], c[2], c[3]])
        e1 = amp[0] * e[0] + amp[1] * e[1] + amp[2] * e[2]
        e2 = amp[3] * e[3] + amp[4] * e[4]
        h1 = amp[0] * h[0] + amp[1] * h[1] + amp[2] * h[2]
        h2 = amp[3] * h[3] + amp[4] * h[4]
        de, dh = e1 - e2, h1 - h2
        out["bc_e"] = max(out["bc_e"], np.linalg.norm(de - (de @ nrm) * nrm))
        out["bc_h"] = max(out["bc_h"], np.linalg.norm(dh - (dh @ nrm) * nrm))
        # energy with Poynting fluxes computed here (cross terms between different waves carry
        # no net normal flux in lossless media, so fluxes add)
        f = np.array([poynting(k[j], e[j]) @ (nrm if j in (1, 2) else -nrm) for j in range(5)])
        f[1:] = np.where(np.abs(k[1:].imag).sum(-1) > 0, 0.0, f[1:])
        total = np.sum(np.abs(amp[1:]) ** 2 * f[1:]) / f[0]
        out["energy"] = max(out["energy"], abs(total - 1))
        out["flux"] = max(out["flux"], np.abs(f - res.flux[i]).max())
    return out


@pytest.mark.parametrize("kind", ["iso_to_uni", "uni_to_iso", "uni_to_uni"])
def test_eq5_maxwell_and_energy_balance(device, kind):
    rng = np.random.default_rng({"iso_to_uni": 11, "uni_to_iso": 12, "uni_to_uni": 13}[kind])
    n = 1500
    d, normal, axis1, no1, ne1 = _random_setup(rng, n)
    _, _, axis2, no2, ne2 = _random_setup(rng, n)
    iso = rng.uniform(1.0, 2.0, n)
    zero = np.zeros((n, 3))
    if kind == "iso_to_uni":
        med1, med2 = (iso, iso, zero), (no2, ne2, axis2)
    elif kind == "uni_to_iso":
        med1, med2 = (no1, ne1, axis1), (iso, iso, zero)
    else:
        med1, med2 = (no1, ne1, axis1), (no2, ne2, axis2)
    mode = rng.integers(0, 2, n)
    res = opt.generalized_fresnel_coefficients(d, normal, med1, med2, mode=mode, device=device)
    assert np.all(np.isfinite(res.coefficients))
    # incident e-waves whose energy does not flow towards the surface are not incident waves
    ok = res.flux[:, 0] > 1e-2
    sub = type(res)(*(getattr(res, f)[ok] for f in ("coefficients", "k", "e", "ray", "flux", "propagating")))
    pick = lambda med: tuple(np.asarray(m)[ok] for m in med)  # noqa: E731
    worst = _maxwell_check(sub, pick(med1), pick(med2), normal[ok])
    print(f"{kind}: {ok.sum()} configs, worst", {k: f"{v:.2e}" for k, v in worst.items()})
    assert worst["mode"] < 5e-5, worst
    assert worst["tangential"] < 5e-6, worst
    assert worst["bc_e"] < 5e-5, worst
    assert worst["bc_h"] < 1e-4, worst
    assert worst["energy"] < 5e-5, worst
    assert worst["flux"] < 1e-4, worst
    # the kernel's own energy bookkeeping agrees
    np.testing.assert_allclose(sub.energy().sum(-1), 1.0, atol=1e-4)
    # total reflection happens in the sample (uniaxial -> iso / uni) and is exact there
    if kind != "iso_to_uni":
        tir = ~sub.propagating[:, 2] & ~sub.propagating[:, 3]
        assert tir.sum() > 20
        np.testing.assert_allclose(sub.energy()[tir, :2].sum(-1), 1.0, atol=1e-4)


def test_eq10_approximation_close_for_weak_birefringence(device):
    """Eq. 10 vs eq. 5 for sapphire (no - ne = 0.008): differences of order the birefringence."""
    rng = np.random.default_rng(21)
    n = 500
    theta = rng.uniform(0, np.radians(85), n)
    phi = rng.uniform(0, 2 * np.pi, n)
    d = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), -np.cos(theta)], -1)
    z = np.array([0.0, 0.0, 1.0])
    axis = _unit(rng.normal(size=(n, 3)))
    med = (1.768, 1.760, axis)
    mr, mt = opt.fresnel_matrices(d, z, 1.0, med, device=device)
    ar, at = opt.fresnel_matrices(d, z, 1.0, med, approx=True, device=device)
    assert np.abs(mr - ar).max() < 0.005
    # near the optic axis the o/e frames (eq. 2) turn fast with the wave normal, and eq. 10 takes
    # them on the mean-index Snell direction instead of the o and e wave normals: compare away
    # from the axis
    sin_t = np.sin(theta) / 1.764
    s_t = np.stack([sin_t * np.cos(phi), sin_t * np.sin(phi), -np.sqrt(1 - sin_t**2)], -1)
    off_axis = np.abs(np.sum(s_t * axis, -1)) < np.cos(np.radians(5.0))
    assert np.abs(mt - at)[off_axis].max() < 0.01


# ----------------------------------------------------------------------------------------------
# pleochroism (eq. 7) and attenuation (eq. 11)


def test_pleochroic_absorbance_and_attenuation(device):
    no, ne = 1.642, 1.619
    k_o, k_e = 0.034, 0.076  # tourmaline, green channel (Guy & Soler §6.1), 1/cm
    theta = np.linspace(0, np.pi / 2, 7)
    got = opt.kappa_e(np.cos(theta), k_o, k_e, no, ne, device=device)
    np.testing.assert_allclose(
        got, k_o * np.cos(theta) ** 2 + k_e * (no / ne) ** 2 * np.sin(theta) ** 2, rtol=1e-6
    )
    assert got[0] == pytest.approx(k_o, rel=1e-6)
    # attenuation: unpolarized light's intensity follows Bouguer-Lambert (eq. 6) per o/e component
    length = 2.5
    a = opt.attenuation(np.cos(theta), k_o, k_e, no, ne, length, device=device)
    amat = np.zeros((7, 2, 2), complex)
    amat[:, 0, 0], amat[:, 1, 1] = a[:, 0], a[:, 1]
    j = opt.coherency_apply(amat, np.broadcast_to(0.5 * np.eye(2), (7, 2, 2)), device=device)
    want = 0.5 * (np.exp(-k_o * length) + np.exp(-got * length))
    np.testing.assert_allclose(np.trace(j, axis1=-2, axis2=-1).real, want, rtol=2e-6)


def test_bad_input(device):
    with pytest.raises(InputError):
        opt.refract_extraordinary([0, 0, -1.0], [0, 0, 1.0], [0, 0, 0.0], 1.0, 1.5, 1.6, device=device)
    with pytest.raises(InputError):
        opt.refract_extraordinary([0, 0, -1.0], [0, 0, 1.0], [0, 0, 1.0], 1.0, -1.5, 1.6, device=device)
    with pytest.raises(InputError):
        opt.generalized_fresnel_coefficients([0, 0, -1.0], [0, 0, 1.0], 1.0, 1.5, mode="x", device=device)
    with pytest.raises(InputError):
        opt.fresnel_matrices([0, 0, -1.0], [0, 0, 1.0], (1.5, 1.6, [1.0, 0, 0]), 1.0, device=device)

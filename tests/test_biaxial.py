"""Biaxial crystals (optics/biaxial.py): waves, eigenpolarizations, Fresnel, absorption, 2V.

The reference is an independent numerical solution of the plane-wave eigenproblem written here:
for k = kt + q m the determinant det(k k^T - |k|^2 I + eps) (eps = R^T diag(n^2) R in world
coordinates) is sampled at nine values of q and fitted exactly by a quartic (numpy.polyfit), its
roots taken by numpy.roots (companion-matrix eigenvalues), E as the null vector of the matrix by
SVD and the ray as the Poynting vector Re(E x conj(k x E)).  Nothing of the code under test (the
analytic quartic coefficients, Ferrari's method, the 2x2 eigen-section) is used.
"""

from __future__ import annotations

import numpy as np
import pytest

from warpoptics.errors import InputError
from warpoptics.optics import biaxial as bx
from warpoptics.optics.birefringence import generalized_fresnel_coefficients


def _rotations(rng, n):
    q, r = np.linalg.qr(rng.normal(size=(n, 3, 3)))
    q = q * np.sign(np.diagonal(r, axis1=1, axis2=2))[:, None, :]
    q[np.linalg.det(q) < 0, 2] *= -1.0  # rows X, Y, Z right-handed
    return q


def _eps(axes, n3):
    return np.einsum("ki,k,kj->ij", axes, n3**2, axes)


def _reference_waves(kt, m, eps):
    """The two waves leaving along +m: (k, unit E, unit ray) per root, sorted by |k|."""

    def det(q):
        k = kt + q * m
        return np.linalg.det(np.outer(k, k) - (k @ k) * np.eye(3) + eps)

    qs = np.linspace(-3.0, 3.0, 9)
    coef = np.polyfit(qs, [det(q) for q in qs], 4)
    out = []
    for q in np.roots(coef):
        if abs(q.imag) > 1e-6:
            continue
        k = kt + q.real * m
        mat = np.outer(k, k) - (k @ k) * np.eye(3) + eps
        e = np.linalg.svd(mat)[2][-1]
        s = k * (e @ e) - e * (e @ k)
        if s @ m > 0:
            out.append((k, e, s / np.linalg.norm(s)))
    out.sort(key=lambda w: np.linalg.norm(w[0]))
    return out


def _angle(a, b):
    a = a / np.linalg.norm(a)
    b = b / np.linalg.norm(b)
    return float(np.arctan2(np.linalg.norm(np.cross(a, b)), abs(a @ b)))


def _random_cases(rng, n):
    axes = _rotations(rng, n)
    na = rng.uniform(1.45, 1.85, n)
    nb = na + rng.uniform(0.002, 0.08, n)
    ng = nb + rng.uniform(0.002, 0.08, n)
    normal = rng.normal(size=(n, 3))
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    # incidence angle uniform in cos over 0..85 degrees
    t = rng.normal(size=(n, 3))
    t -= normal * np.sum(t * normal, axis=1, keepdims=True)
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    cos_i = rng.uniform(np.cos(np.radians(85.0)), 1.0, n)
    d = -normal * cos_i[:, None] + t * np.sqrt(1 - cos_i**2)[:, None]
    return axes, na, nb, ng, normal, d


def test_refraction_matches_numerical_eigenproblem():
    rng = np.random.default_rng(20)
    n = 300
    axes, na, nb, ng, normal, d = _random_cases(rng, n)
    k, ray, idx = bx.biaxial_waves(d, normal, axes, 1.0, na, nb, ng)
    worst_k = worst_r = 0.0
    for i in range(n):
        kt = d[i] - normal[i] * (d[i] @ normal[i])
        ref = _reference_waves(kt, -normal[i], _eps(axes[i], np.array([na[i], nb[i], ng[i]])))
        assert len(ref) == 2  # from air every wave propagates
        for j in range(2):
            assert idx[i, j] == pytest.approx(np.linalg.norm(ref[j][0]), abs=2e-6)
            worst_k = max(worst_k, _angle(k[i, j], ref[j][0]))
            worst_r = max(worst_r, _angle(ray[i, j], ref[j][2]))
    # float32 outputs: ~1e-7 rad; the brief's bound is 1e-5 rad
    assert worst_k < 1e-5 and worst_r < 1e-5, (worst_k, worst_r)


@pytest.mark.parametrize("inside", [False, True])
def test_fresnel_waves_eigenpolarizations_and_energy(inside):
    """Every wave of the generalized Fresnel solve (refraction in, and reflection inside with
    total reflection) against the reference; R + T = 1 over the two reflected and two
    transmitted waves."""
    rng = np.random.default_rng(7 + inside)
    n = 200
    axes, na, nb, ng, normal, d = _random_cases(rng, n)
    crystal = (na, nb, ng, axes)
    if inside:
        # a wave inside the crystal (wave normal d, fast or slow) meeting the surface to air
        mode = rng.integers(0, 2, n)
        res = bx.biaxial_fresnel_coefficients(d, normal, crystal, 1.0, mode=mode)
    else:
        mode = rng.integers(0, 2, n)
        res = bx.biaxial_fresnel_coefficients(d, normal, 1.0, crystal, mode=mode)
    e = res.energy()
    ok = res.flux[:, 0] > 1e-3  # skip the few grazing incident waves with no normal flux
    # float32 solve of the 4x4 system: |R + T - 1| ~ 1e-6; the brief's bound is 1e-5
    assert np.max(np.abs(e[ok].sum(axis=1) - 1.0)) < 1e-5
    worst_e = 0.0
    for i in np.flatnonzero(ok)[:120]:
        eps = _eps(axes[i], np.array([na[i], nb[i], ng[i]]))
        kt = np.real(res.k[i, 0]) - normal[i] * (np.real(res.k[i, 0]) @ normal[i])
        side = (1, 2) if inside else (3, 4)
        m = normal[i] if inside else -normal[i]
        ref = _reference_waves(kt, m, eps)
        got = [j for j in side if res.propagating[i, j - 1]]
        assert len(got) == len(ref)
        ref_by_n = {round(float(np.linalg.norm(r[0])), 4): r for r in ref}
        for j in got:
            kk = np.real(res.k[i, j])
            r = min(ref, key=lambda w: np.linalg.norm(w[0] - kk))
            assert np.linalg.norm(r[0] - kk) < 2e-5, ref_by_n
            worst_e = max(worst_e, _angle(np.real(res.e[i, j]), r[1]), _angle(res.ray[i, j], r[2]))
    assert worst_e < 1e-5, worst_e


def test_uniaxial_limit_reproduces_birefringence_module():
    """n_alpha = n_beta (positive) or n_beta = n_gamma (negative) through the biaxial solver gives
    the numbers of optics/birefringence.py (modes: fast = o for positive, fast = e for negative)."""
    rng = np.random.default_rng(3)
    n = 400
    axes, _, _, _, normal, d = _random_cases(rng, n)
    no, ne = 1.544, 1.553  # quartz-like, positive
    for positive in (True, False):
        if positive:
            crystal = (no, no, ne, axes)
            axis = axes[:, 2]
            uni = (no, ne, axis)
        else:
            crystal = (1.486, 1.658, 1.658, axes)  # calcite: n_alpha = n_e, optic axis X
            axis = axes[:, 0]
            uni = (1.658, 1.486, axis)
        for mode in (0, 1):
            b = bx.biaxial_fresnel_coefficients(d, normal, 1.0, crystal, mode=mode)
            u = generalized_fresnel_coefficients(d, normal, 1.0, uni, mode=mode)
            order = [0, 1, 2, 3] if positive else [0, 1, 3, 2]  # (r_s, r_p, t_fast, t_slow)
            # the outgoing fields coefficient * E (an eigenvector's sign is a convention)
            fb = b.coefficients[..., None] * b.e[:, 1:]
            fu = (u.coefficients[..., None] * u.e[:, 1:])[:, order]
            # same physics, different arithmetic in float32: 2e-5 of unit amplitudes
            assert np.max(np.abs(fb - fu)) < 2e-5
            kb = np.real(b.k[:, 3:5])
            ku = np.real(u.k[:, [3, 4] if positive else [4, 3]])
            assert np.max(np.linalg.norm(kb - ku, axis=-1)) < 2e-6
            rb, ru = b.ray[:, 3:5], u.ray[:, [3, 4] if positive else [4, 3]]
            assert np.max(np.linalg.norm(rb - ru, axis=-1)) < 2e-5
            np.testing.assert_allclose(b.energy(), u.energy()[:, order], atol=2e-5)


def test_optic_axis_conical_refraction_choice():
    """Normal incidence along an optic axis: a double root, no NaN; both waves have index n_beta,
    the fast ray along the axis (D along Y) and the slow ray on the cone of internal conical
    refraction, tan chi = n_b^2 sqrt((n_a^-2 - n_b^-2)(n_b^-2 - n_g^-2)) (Born & Wolf §15.3.4)."""
    na, nb, ng = 1.70, 1.72, 1.75
    two_v, pos = bx.optic_axial_angle(na, nb, ng)
    vz = np.radians(two_v / 2 if pos else 90 - two_v / 2)
    axes = np.eye(3)
    for sign in (1.0, -1.0):
        s = np.array([sign * np.sin(vz), 0.0, np.cos(vz)])
        k, ray, idx = bx.biaxial_waves(s, -s, axes, 1.0, na, nb, ng)
        assert np.all(np.isfinite(k)) and np.all(np.isfinite(ray))
        np.testing.assert_allclose(idx, [nb, nb], atol=2e-6)
        chi = np.arctan(nb**2 * np.sqrt((na**-2 - nb**-2) * (nb**-2 - ng**-2)))
        assert _angle(ray[0], s) < 1e-5
        assert _angle(ray[1], s) == pytest.approx(chi, abs=2e-4)
        # near the axis (1e-6 .. 1e-2 rad off): finite, indices bracket n_beta
        for off in (1e-6, 1e-4, 1e-2):
            dn = s + off * np.array([0.3, 0.9, 0.1])
            k2, r2, i2 = bx.biaxial_waves(dn, -s, axes, 1.0, na, nb, ng)
            assert np.all(np.isfinite(k2)) and np.all(np.isfinite(r2))
            assert i2[0] <= nb + 1e-6 <= i2[1] + 2e-6


def test_total_reflection_inside_and_evanescent_waves():
    """Beyond the critical angles both transmitted waves are evanescent: r0 + r1 carry all the
    energy (|r|^2 flux ratios sum to 1) and the transmitted columns carry none."""
    na, nb, ng = 1.60, 1.63, 1.64
    axes = _rotations(np.random.default_rng(1), 50)
    th = np.radians(70.0)
    d = np.array([np.sin(th), 0.0, -np.cos(th)])
    res = bx.biaxial_fresnel_coefficients(d, [0.0, 0.0, 1.0], (na, nb, ng, axes), 1.0, mode=1)
    assert not np.any(res.propagating[:, 2:])
    np.testing.assert_allclose(res.energy()[:, :2].sum(axis=1), 1.0, atol=1e-5)
    assert np.all(np.isfinite(res.coefficients))


def test_two_v_closed_form():
    # forsterite-like and a positive crystal; 2V from cos^2 V_z = (n_b^-2 - n_g^-2)/(n_a^-2 - n_g^-2)
    for na, nb, ng in ((1.635, 1.651, 1.670), (1.619, 1.620, 1.627)):
        two_v, pos = bx.optic_axial_angle(na, nb, ng)
        vz = np.degrees(np.arccos(np.sqrt((nb**-2 - ng**-2) / (na**-2 - ng**-2))))
        assert two_v == pytest.approx(2 * vz if vz <= 45 else 180 - 2 * vz, abs=1e-9)
        assert bool(pos) == (vz <= 45)
    with pytest.raises(InputError):
        bx.optic_axial_angle(1.7, 1.6, 1.8)


def test_trichroic_absorption_reduces_to_eq7():
    """n_alpha = n_beta: the o-wave (fast, positive crystal) absorbs K_o, the e-wave (slow)
    K_o cos^2 + K_e (n_o/n_e)^2 sin^2 (Guy & Soler eq. 7, written out here)."""
    rng = np.random.default_rng(5)
    s = rng.normal(size=(500, 3))
    s /= np.linalg.norm(s, axis=1, keepdims=True)
    axes = _rotations(rng, 500)
    no, ne, k_o, k_e = 1.62, 1.64, 0.3, 1.1
    ko = bx.biaxial_absorption(s, 0, axes, no, no, ne, [k_o, k_o, k_e])
    ke = bx.biaxial_absorption(s, 1, axes, no, no, ne, [k_o, k_o, k_e])
    c2 = np.sum(s * axes[:, 2], axis=1) ** 2
    np.testing.assert_allclose(ko, k_o, rtol=1e-5)
    np.testing.assert_allclose(ke, k_o * c2 + k_e * (no / ne) ** 2 * (1 - c2), rtol=1e-5)
    # negative uniaxial (n_beta = n_gamma = n_o, optic axis X): the slow wave is the o-wave
    ko2 = bx.biaxial_absorption(s, 1, axes, ne - 0.05, ne, ne, [k_e, k_o, k_o])
    np.testing.assert_allclose(ko2, k_o, rtol=1e-5)


def test_trichroic_absorption_along_principal_axes():
    # a wave along Z: D along X (fast) and Y (slow) see alpha_X (n_b/n_a)^2 and alpha_Y
    na, nb, ng = 1.69, 1.70, 1.71
    a3 = np.array([0.2, 0.5, 0.9])
    k = bx.biaxial_absorption(
        [[0, 0, 1], [0, 0, 1], [1, 0, 0], [1, 0, 0]], [0, 1, 0, 1], np.eye(3), na, nb, ng, a3
    )
    np.testing.assert_allclose(k, [0.2 * (nb / na) ** 2, 0.5, 0.5, 0.9 * (nb / ng) ** 2], rtol=1e-6)


def test_bad_inputs_are_input_errors():
    with pytest.raises(InputError):
        bx.biaxial_waves([0, 0, -1], [0, 0, 1], np.ones((3, 3)), 1.0, 1.5, 1.6, 1.7)
    with pytest.raises(InputError):
        bx.biaxial_waves([0, 0, -1], [0, 0, 1], np.eye(3), 1.0, 1.6, 1.5, 1.7)
    with pytest.raises(InputError):
        bx.biaxial_waves([0, 0, np.nan], [0, 0, 1], np.eye(3), 1.0, 1.5, 1.6, 1.7)


def test_random_nan_scan_including_optic_axes():
    """Waves inside a crystal meeting random surfaces, with wave normals random and exactly along
    the optic axes (both sheets): every coefficient, wave vector and ray finite; no wave gains
    energy."""
    rng = np.random.default_rng(11)
    n = 400
    axes, na, nb, ng, normal, _ = _random_cases(rng, n)
    two_v, pos = bx.optic_axial_angle(na, nb, ng)
    vz = np.radians(np.where(pos, two_v / 2, 90 - two_v / 2))
    local = np.stack([np.sin(vz) * rng.choice([-1, 1], n), np.zeros(n), np.cos(vz)], axis=1)
    d_axis = np.einsum("ni,nij->nj", local, axes)  # along an optic axis (world)
    d_rand = rng.normal(size=(n, 3))
    for d in (d_axis, d_rand):
        d = d * -np.sign(np.sum(d * normal, axis=1, keepdims=True))  # towards the surface
        for mode in (0, 1):
            for other in (1.0, 1.33, (1.544, 1.553, axes[:, 1])):
                res = bx.biaxial_fresnel_coefficients(d, normal, (na, nb, ng, axes), other, mode=mode)
                for arr in (res.coefficients, res.k, res.e, res.ray, res.flux):
                    assert np.all(np.isfinite(arr))
                ok = res.flux[:, 0] > 1e-3
                total = res.energy()[ok].sum(axis=1)
                # energy not gained beyond float32 rounding at grazing (5e-4, below); the few
                # refused solves (on an optic axis at grazing incidence, see crystal_fresnel)
                # return nothing
                fin = res.flux[ok, 0]
                assert np.all(total[fin > 0.05] < 1 + 1e-4) and np.all(total < 1 + 5e-4)
                assert np.all(total >= 0)
                if d is d_rand:
                    # R + T = 1 to 1e-4 away from grazing (all directions, up to ~88 deg incidence,
                    # measured 4.3e-5; 1e-5 holds to 85 deg, test above); within 5e-4 at grazing (cos ~ 0.01:
                    # float32 wave vectors of the reflected waves, measured 2.1e-4)
                    np.testing.assert_allclose(total[fin > 0.05], 1.0, atol=1e-4)
                    np.testing.assert_allclose(total, 1.0, atol=5e-4)

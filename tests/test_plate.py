"""A crystal plate between polarizers (optics/plate.py): the o and e waves added as amplitudes.

References, both independent of the code under test:

- normal incidence: the closed form of a wave plate between crossed polarizers with the Fresnel
  transmissions of its two faces, I = 1/4 sin^2(2 phi) |T_e exp(i delta) - T_o|^2 with
  T = 4 n / (1 + n)^2 per wave (amplitude through both faces, power-normalised) and
  delta = 2 pi d (n_e - n_o) / lambda.  Expanding, I = sin^2(2 phi) [T_o T_e sin^2(delta / 2)
  + (T_e - T_o)^2 / 4], so that (I / sin^2 2phi - (T_e - T_o)^2 / 4) / (T_o T_e) is exactly the
  issue's sin^2(pi Delta / lambda): that correction removes the Fresnel losses without
  approximation, and the test asserts the issue's formula itself after it.
- oblique incidence: a Berreman-style plane-wave solution written here in NumPy: the four
  waves of the crystal for the tangential wave vector of the incident wave from the roots of
  det(k k^T - |k|^2 I + eps) = 0 (a quartic in the normal component q, fitted from samples),
  fields as null vectors (SVD), H = k x E, and the 4x4 continuity of tangential E and H solved
  at each face; the light goes entrance -> phase exp(i k0 q d) -> exit (one pass, the backward
  waves at the exit dropped, as the code under test does).  Nothing of the package's wave
  solvers or Fresnel system is used.
"""

from __future__ import annotations

import numpy as np
import pytest

import warpoptics as wo
from warpoptics.errors import InputError
from warpoptics.optics.plate import plate_jones, slab_phases

LAM = np.linspace(380.0, 780.0, 81)
NORMAL = np.array([0.0, 0.0, -1.0])  # light travels along +z; the normal faces the light


def _indices(mat, lam):
    n = mat.n(lam)
    return np.stack([n[..., 0], np.zeros_like(lam), n[..., 1]], axis=-1)


def _crossed(j, s, k, pol, ana):
    """|a . J p|^2 for polarizer/analyzer world vectors projected on the frame (s, k x s)."""
    y = np.cross(k, s)
    p = np.stack([s @ pol, y @ pol], axis=-1)
    a = np.stack([s @ ana, y @ ana], axis=-1)
    e = np.einsum("...ij,...j->...i", j, p)
    return np.abs(np.einsum("...i,...i->...", a, e)) ** 2


@pytest.mark.parametrize("phi_deg", [0.0, 10.0, 22.5, 45.0, 67.0, 90.0, 130.0])
def test_normal_incidence_crossed_polarizers_closed_form(device, phi_deg):
    quartz = wo.materials.get("quartz")
    n = quartz.n(LAM)
    no, ne = n[:, 0], n[:, 1]
    d = 0.060  # mm: Delta = 0.54 um (first-order colours), dispersion of both indices included
    phi = np.radians(phi_deg)
    axis = np.array([np.cos(phi), np.sin(phi), 0.0])
    j, s = plate_jones([0.0, 0.0, 1.0], LAM, _indices(quartz, LAM), d, crystal_axes=axis, device=device)
    i_cross = _crossed(j, s, np.array([0.0, 0.0, 1.0]), np.array([1.0, 0, 0]), np.array([0.0, 1, 0]))
    t_o = 4 * no / (1 + no) ** 2
    t_e = 4 * ne / (1 + ne) ** 2
    delta = 2 * np.pi * d * 1e6 * (ne - no) / LAM
    s2 = np.sin(2 * phi) ** 2
    ref = 0.25 * s2 * np.abs(t_e * np.exp(1j * delta) - t_o) ** 2
    assert np.max(np.abs(i_cross - ref)) < 1e-4
    # the formula after removing the Fresnel transmissions exactly (module docstring)
    if s2 > 1e-6:
        corrected = (i_cross / s2 - 0.25 * (t_e - t_o) ** 2) / (t_o * t_e)
        assert np.max(np.abs(corrected - np.sin(np.pi * d * 1e6 * np.abs(ne - no) / LAM) ** 2)) < 1e-4
    else:
        assert np.max(i_cross) < 1e-6


def test_index_matched_plate_is_the_bare_formula(device):
    # in a mounting medium of index n_o the o wave crosses unreflected and the e wave loses
    # ((ne - no) / (ne + no))^2 ~ 1e-5 per face: the transmission is sin^2(2 phi) sin^2(pi D / l)
    calcite = wo.materials.get("calcite")
    n = calcite.n(LAM)
    d = 0.004
    phi = np.radians(45.0)
    axis = np.array([np.cos(phi), np.sin(phi), 0.0])
    quartz_like = np.stack([np.full_like(LAM, 1.55), np.zeros_like(LAM), np.full_like(LAM, 1.56)], -1)
    j, s = plate_jones([0, 0, 1.0], LAM, quartz_like, d, crystal_axes=axis, n_ambient=1.55, device=device)
    i = _crossed(j, s, np.array([0.0, 0, 1]), np.array([1.0, 0, 0]), np.array([0.0, 1, 0]))
    assert np.max(np.abs(i - np.sin(np.pi * d * 1e6 * 0.01 / LAM) ** 2)) < 1e-4
    assert n.shape == (LAM.size, 2)


# ---------------------------------------------------------------------------------------------
# independent oblique-incidence reference


def _waves(kt, m, eps):
    """The four plane waves of tangential wave vector kt in a medium of dielectric tensor eps:
    (q, E, H) with k = kt + q m, the two forward (energy along +m) first, then the backward."""

    def mat(q):
        k = kt + q * m
        return np.outer(k, k) - (k @ k) * np.eye(3) + eps

    qs = np.linspace(-3.0, 3.0, 9)
    coef = np.polyfit(qs, [np.linalg.det(mat(q)) for q in qs], 4)
    roots = np.roots(coef)
    waves = []
    for q in roots:
        q = q.real if abs(q.imag) < 1e-9 else q
        _, _, vh = np.linalg.svd(mat(q))
        e = vh[-1].conj()
        k = kt + q * m
        h = np.cross(k, e)
        flux = np.real(np.cross(e, h.conj())) @ m
        waves.append((q, e, h, flux))
    fwd = sorted([w for w in waves if w[3] > 0], key=lambda w: w[0].real)
    bwd = [w for w in waves if w[3] <= 0]
    assert len(fwd) == 2 and len(bwd) == 2
    return fwd, bwd


def _tangential(v, t1, t2):
    return np.array([v @ t1, v @ t2])


def _reference_plate(k_hat, lam, eps, d, n_amb):
    """Jones matrix (frame (s, k x s) in and out) of one pass through the plate."""
    m = np.array([0.0, 0.0, 1.0])  # into the plate
    s = np.cross(NORMAL, k_hat)
    s = s / np.linalg.norm(s) if np.linalg.norm(s) > 1e-9 else np.array([1.0, 0, 0])
    y = np.cross(k_hat, s)
    t1, t2 = s, np.cross(m, s)
    k_in = n_amb * k_hat
    kt = k_in - (k_in @ m) * m
    q_amb = k_in @ m
    fwd, bwd = _waves(kt, m, n_amb**2 * np.eye(3) * 0 + eps)
    k_r = kt - q_amb * m
    r_hat = k_r / np.linalg.norm(k_r)
    air_r = [(s, np.cross(k_r, s)), (np.cross(r_hat, s), np.cross(k_r, np.cross(r_hat, s)))]
    air_t = [(s, np.cross(k_in, s)), (y, np.cross(k_in, y))]
    k0d = 2 * np.pi * d * 1e6 / lam
    jm = np.zeros((2, 2), dtype=complex)
    for col, e_in in enumerate((s, y)):
        h_in = np.cross(k_in, e_in)
        a = np.zeros((4, 4), dtype=complex)
        for c, (e, h) in enumerate(air_r):
            a[:, c] = -np.concatenate([_tangential(e, t1, t2), _tangential(h, t1, t2)])
        for c, w in enumerate(fwd):
            a[:, 2 + c] = np.concatenate([_tangential(w[1], t1, t2), _tangential(w[2], t1, t2)])
        b = np.concatenate([_tangential(e_in, t1, t2), _tangential(h_in, t1, t2)])
        amp = np.linalg.solve(a, b)[2:]
        for j, w in enumerate(fwd):
            c_exit = np.zeros((4, 4), dtype=complex)
            for c, wb in enumerate(bwd):
                c_exit[:, c] = -np.concatenate([_tangential(wb[1], t1, t2), _tangential(wb[2], t1, t2)])
            for c, (e, h) in enumerate(air_t):
                c_exit[:, 2 + c] = np.concatenate([_tangential(e, t1, t2), _tangential(h, t1, t2)])
            rhs = np.concatenate([_tangential(w[1], t1, t2), _tangential(w[2], t1, t2)])
            tau = np.linalg.solve(c_exit, rhs)[2:]
            jm[:, col] += amp[j] * np.exp(1j * k0d * (w[0] - q_amb)) * tau
    return jm, s


def _uniaxial_eps(no, ne, a):
    return no**2 * np.eye(3) + (ne**2 - no**2) * np.outer(a, a)


@pytest.mark.parametrize(
    "theta_deg, psi_deg, axis",
    [
        (20.0, 30.0, (1.0, 0.3, 0.2)),
        (35.0, 100.0, (0.2, 0.5, 1.0)),
        (50.0, 250.0, (0.0, 1.0, 0.0)),
        (10.0, 0.0, (0.0, 0.0, 1.0)),
    ],
)
def test_oblique_incidence_against_berreman_reference(device, theta_deg, psi_deg, axis):
    calcite = wo.materials.get("calcite")
    lam = np.linspace(380.0, 780.0, 9)
    n = calcite.n(lam)
    a = np.asarray(axis) / np.linalg.norm(axis)
    th, ps = np.radians(theta_deg), np.radians(psi_deg)
    k = np.array([np.sin(th) * np.cos(ps), np.sin(th) * np.sin(ps), np.cos(th)])
    d = 0.003  # mm: a few um of retardation at 0.17 birefringence
    j, s = plate_jones(k, lam, _indices(calcite, lam), d, crystal_axes=a, device=device)
    for i, lm in enumerate(lam):
        ref, s_ref = _reference_plate(k, lm, _uniaxial_eps(n[i, 0], n[i, 1], a), d, 1.0)
        np.testing.assert_allclose(s[i], s_ref, atol=1e-6)
        assert np.max(np.abs(j[i] - ref)) < 1e-4, (lm, j[i], ref)
        for pol_deg in (0.0, 30.0, 45.0):
            p = np.array([np.cos(np.radians(pol_deg)), np.sin(np.radians(pol_deg)), 0.0])
            an = np.cross([0.0, 0.0, 1.0], p)
            i_code = _crossed(j[i], s[i], k, p, an)
            i_ref = _crossed(ref, s_ref, k, p, an)
            assert abs(i_code - i_ref) < 1e-4


def test_oblique_biaxial_plate_against_berreman_reference(device):
    tanzanite = wo.materials.get("tanzanite")
    lam = np.array([450.0, 589.0, 700.0])
    n3 = tanzanite.n(lam)
    rng = np.random.default_rng(3)
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))[None, :]
    if np.linalg.det(q) < 0:
        q[2] *= -1
    k = np.array([np.sin(0.4) * np.cos(1.1), np.sin(0.4) * np.sin(1.1), np.cos(0.4)])
    d = 0.01
    j, s = plate_jones(k, lam, n3, d, crystal_axes=q, device=device)
    for i, lm in enumerate(lam):
        eps = np.einsum("ki,k,kj->ij", q, n3[i] ** 2, q)
        ref, _ = _reference_plate(k, lm, eps, d, 1.0)
        assert np.max(np.abs(j[i] - ref)) < 1e-4, (lm, j[i], ref)


def test_coherent_is_sum_of_modes_and_energy(device):
    lam = np.linspace(400, 700, 7)
    idx = np.stack([np.full(7, 1.6), np.zeros(7), np.full(7, 1.7)], -1)
    k = np.array([0.3, 0.1, 0.9])
    k = k / np.linalg.norm(k)
    pair, s = plate_jones(k, lam, idx, 0.02, crystal_axes=(1.0, 1.0, 0.5), coherent=False, device=device)
    coh, _ = plate_jones(k, lam, idx, 0.02, crystal_axes=(1.0, 1.0, 0.5), device=device)
    np.testing.assert_allclose(coh, pair[0] + pair[1], atol=1e-7)
    # a lossless plate transmits at most the incident power, and nearly all of it
    for jj in coh:
        sv = np.linalg.svd(jj, compute_uv=False)
        assert sv.max() <= 1.0 + 1e-5 and sv.min() > 0.8


def test_isotropic_plate_keeps_crossed_polarizers_dark(device):
    lam = np.linspace(400, 700, 5)
    idx = np.stack([np.full(5, 1.5), np.zeros(5), np.full(5, 1.5)], -1)
    j, s = plate_jones([0, 0, 1.0], lam, idx, 1.0, device=device)
    i = _crossed(j, s, np.array([0, 0, 1.0]), np.array([1.0, 0, 0]), np.array([0, 1.0, 0]))
    assert np.max(i) < 1e-10
    # and the transmission is (4n/(1+n)^2)^2 with a zero phase relative to the ambient medium
    # crossing (n - 1) d of extra optical path: exp(i 2 pi (n - 1) d / lambda)
    expect = (4 * 1.5 / 2.5**2) * np.exp(2j * np.pi * 0.5 * 1e6 / lam)
    np.testing.assert_allclose(j[:, 0, 0], expect, atol=3e-4)


def test_slab_phase_closed_form(device):
    q = np.array([1.5, 1.6, 1.0])
    out = slab_phases(q, 1.0, 0.5, 589.0, device=device)
    np.testing.assert_allclose(out, np.exp(2j * np.pi * (q - 1.0) * 0.5e6 / 589.0), atol=2e-4)


def test_bad_inputs_name_the_field(device):
    with pytest.raises(InputError, match="wavelength_nm"):
        plate_jones([0, 0, 1.0], -5.0, (1.5, 0, 1.6), 0.01, device=device)
    with pytest.raises(InputError, match="indices"):
        plate_jones([0, 0, 1.0], 500.0, (np.nan, 0, 1.6), 0.01, device=device)
    with pytest.raises(InputError, match="crystal_axes"):
        plate_jones([0, 0, 1.0], 500.0, (1.5, 0, 1.6), 0.01, crystal_axes=(1.0, 2.0), device=device)


def test_pleochroic_plate_absorbs_each_wave_by_its_own_kappa(device):
    # axis along x at normal incidence: light polarized along x is the e wave (Guy & Soler eq. 7
    # with the wave normal across the axis: kappa^e = K^e (n_o / n_e)^2), along y the o wave
    # (K^o): |J_xx|^2 = T_e^2 exp(-kappa^e d), |J_yy|^2 = T_o^2 exp(-K^o d), T = 4n/(1+n)^2
    lam = np.array([450.0, 550.0, 650.0])
    no, ne = 1.64, 1.62
    idx = np.stack([np.full(3, no), np.zeros(3), np.full(3, ne)], -1)
    k_o, k_e, d = np.array([2.0, 0.5, 1.0]), np.array([0.1, 1.5, 0.3]), 0.8
    alpha = np.stack([k_o, np.zeros(3), k_e], -1)
    j, s = plate_jones([0, 0, 1.0], lam, idx, d, crystal_axes=(1.0, 0.0, 0.0), alpha=alpha, device=device)
    y = np.cross([0, 0, 1.0], s)
    x_hat, y_hat = np.array([1.0, 0, 0]), np.array([0.0, 1, 0])
    p_x = np.stack([s @ x_hat, y @ x_hat], -1)
    p_y = np.stack([s @ y_hat, y @ y_hat], -1)
    t_x = np.abs(np.einsum("...i,...ij,...j->...", p_x, j, p_x)) ** 2
    t_y = np.abs(np.einsum("...i,...ij,...j->...", p_y, j, p_y)) ** 2
    np.testing.assert_allclose(
        t_x, (4 * ne / (1 + ne) ** 2) ** 2 * np.exp(-k_e * (no / ne) ** 2 * d), rtol=2e-5
    )
    np.testing.assert_allclose(t_y, (4 * no / (1 + no) ** 2) ** 2 * np.exp(-k_o * d), rtol=2e-5)


def test_biaxial_vibration_directions_follow_biot_fresnel(device):
    # Biot-Fresnel rule (Born & Wolf §15.3.3): the two waves of wave normal s in a biaxial
    # crystal vibrate along the bisectors of the planes (s, A1) and (s, A2), A1, A2 the optic
    # axes, i.e. along n1 +- n2 with n_i = s x A_i.  The input polarization that excites one
    # wave alone (the row of its rank-one Jones matrix) must have that azimuth in the frame
    # (x, s x x); the entrance face's s/p transmission ratio turns it by < 1 degree for
    # n sin(theta) <= 0.5.  Optic axes from the indices: A = (+-sin V, 0, cos V),
    # tan V = (n_g / n_a) sqrt((n_b^2 - n_a^2) / (n_g^2 - n_b^2)) (optic sign +).
    tz = wo.materials.get("tanzanite")
    lam = 589.3
    na, nb, ng = tz.n([lam])[0]
    v = np.arctan(ng / na * np.sqrt((nb**2 - na**2) / (ng**2 - nb**2)))
    c = np.sqrt(0.5)
    axes = np.array([[c, c, 0.0], [-c, c, 0.0], [0.0, 0.0, 1.0]])  # X, Y, Z rows (world)
    optic = [np.array([s * np.sin(v), 0.0, np.cos(v)]) @ axes for s in (1.0, -1.0)]
    rng = np.random.default_rng(7)
    for _ in range(12):
        p = rng.uniform(-0.5, 0.5, 2)
        if p @ p > 0.25 or p @ p < 1e-3:
            continue
        k = np.array([p[0], p[1], np.sqrt(1 - p @ p)])
        pair, s = plate_jones(k, lam, [na, nb, ng], 0.001, crystal_axes=axes, coherent=False, device=device)
        got = []
        for jm in pair:
            r = jm[0] if np.abs(jm[0]).sum() > np.abs(jm[1]).sum() else jm[1]
            r = r / r[np.argmax(np.abs(r))]
            got.append(np.degrees(np.arctan2(r[1].real, r[0].real)) % 180)
        s_in = np.array([p[0], p[1], np.sqrt(nb**2 - p @ p)])
        s_in /= np.linalg.norm(s_in)
        y = np.cross(s_in, s)
        n1, n2 = (np.cross(s_in, a) / np.linalg.norm(np.cross(s_in, a)) for a in optic)
        want = [np.degrees(np.arctan2(d @ y, d @ s)) % 180 for d in (n1 + n2, n1 - n2)]
        for g in got:
            err = min(abs((g - w + 90) % 180 - 90) for w in want)
            assert err < 1.0, (p, got, want)

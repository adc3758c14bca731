"""Fresnel amplitudes (warpoptics.optics.fresnel) against closed forms, tmm and energy balance.

Tolerances: the kernels run in float32 (machine epsilon 6e-8); an amplitude is a ratio of sums
of a few products, so its error is a few ulp of O(1) values: 2e-6 absolute.  Near the critical
angle N2 cos(t) = sqrt(n2^2 - n1^2 sin^2 i) loses half its digits to cancellation
(d sqrt(x) = dx / (2 sqrt(x))), hence the looser tolerances there.
"""

import numpy as np
import pytest
import tmm

import warpoptics as wo
from warpoptics.errors import InputError

fresnel = wo.optics.fresnel
fresnel_power = wo.optics.fresnel_power

ATOL = 2e-6


def _angle_forms(theta_i, n1, n2):
    """Hecht eq. 4.42-4.45 in the angle forms of Guy & Soler fig. 2 (real indices, no TIR)."""
    theta_t = np.arcsin(n1 * np.sin(theta_i) / n2)
    s, d = theta_i + theta_t, theta_i - theta_t
    rs = -np.sin(d) / np.sin(s)
    rp = np.tan(d) / np.tan(s)
    ts = 2 * np.sin(theta_t) * np.cos(theta_i) / np.sin(s)
    tp = 2 * np.sin(theta_t) * np.cos(theta_i) / (np.sin(s) * np.cos(d))
    return rs, rp, ts, tp


def test_normal_incidence_values(device):
    # Hecht §4.6.2: air -> glass n = 1.5 at normal incidence: r = -0.2 (s), +0.2 (p, B&W), t = 0.8
    rs, rp, ts, tp = fresnel(1.0, 1.0, 1.5, device=device)
    assert rs == pytest.approx(-0.2, abs=ATOL)
    assert rp == pytest.approx(0.2, abs=ATOL)  # rp = -rs: Born & Wolf convention
    assert ts == pytest.approx(0.8, abs=ATOL)
    assert tp == pytest.approx(0.8, abs=ATOL)
    Rs, Rp, Ts, Tp = fresnel_power(1.0, 1.0, 1.5, device=device)
    assert Rs == pytest.approx(0.04, abs=ATOL) and Rp == pytest.approx(0.04, abs=ATOL)
    assert Ts == pytest.approx(0.96, abs=ATOL) and Tp == pytest.approx(0.96, abs=ATOL)


def test_hecht_angle_forms(device):
    theta = np.radians(np.linspace(1.0, 89.0, 89))
    for n1, n2 in [(1.0, 1.5), (1.0, 2.417), (1.33, 1.0), (1.5, 1.33)]:
        crit = np.arcsin(min(1.0, n2 / n1))
        th = theta[theta < crit - np.radians(0.5)]
        got = fresnel(np.cos(th), n1, n2, device=device)
        want = _angle_forms(th, n1, n2)
        for g, w in zip(got, want, strict=True):
            np.testing.assert_allclose(g, w, atol=5 * ATOL, rtol=0)
    # Hecht fig. 4.49 style spot value: 1 -> 1.5 at 30 deg
    rs, rp, _, _ = fresnel(np.cos(np.radians(30.0)), 1.0, 1.5, device=device)
    assert rs.real == pytest.approx(-0.2404, abs=1e-4)
    assert rp.real == pytest.approx(0.1589, abs=1e-4)


@pytest.mark.parametrize("n1,n2", [(1.0, 1.5), (1.0, 2.417), (1.5, 1.0), (1.33, 1.76)])
def test_brewster(device, n1, n2):
    theta_b = np.arctan(n2 / n1)
    rs, rp, _, _ = fresnel(np.cos(theta_b), n1, n2, device=device)
    assert abs(rp) < 5e-6
    assert abs(rs) > 0.05


def test_energy_balance_random_dielectrics(device):
    rng = np.random.default_rng(1)
    n = 20000
    # inputs representable in float32, so that the float64 reference sees the kernel's inputs
    n1 = rng.uniform(1.0, 3.0, n).astype(np.float32).astype(np.float64)
    n2 = rng.uniform(1.0, 3.0, n).astype(np.float32).astype(np.float64)
    cos_i = rng.uniform(0.0, 1.0, n).astype(np.float32).astype(np.float64)
    rs, rp, ts, tp = fresnel(cos_i, n1, n2, device=device)
    Rs, Rp, Ts, Tp = fresnel_power(cos_i, n1, n2, device=device)
    # independent transmittances: T = (n2 cos t)/(n1 cos i) |t|^2, cos t from Snell in float64
    sin_t2 = (n1 / n2) ** 2 * (1 - cos_i**2)
    prop = sin_t2 < 1
    factor = np.where(prop, n2 * np.sqrt(np.clip(1 - sin_t2, 0, None)) / np.maximum(n1 * cos_i, 1e-300), 0.0)
    ok = prop & (cos_i > 1e-3)
    for r, t, R, T in [(rs, ts, Rs, Ts), (rp, tp, Rp, Tp)]:
        total = np.abs(r) ** 2 + factor * np.abs(t) ** 2
        err = np.abs(total - 1)[ok & (1 - sin_t2 > 1e-4)]
        print(f"worst |R + T - 1| (T from n cos factors), 20000 dielectric configs: {err.max():.2e}")
        assert err.max() < 2e-5, err.max()
        assert np.abs(R + T - 1).max() < 2e-5
        assert np.abs(R - np.abs(r) ** 2).max() < 1e-6
    assert np.all(np.isfinite(np.stack([rs, rp, ts, tp])))


def test_total_internal_reflection(device):
    n1, n2 = 1.5, 1.0
    crit = np.arcsin(n2 / n1)
    theta = np.linspace(crit + 1e-3, np.pi / 2, 500)
    rs, rp, ts, tp = fresnel(np.cos(theta), n1, n2, device=device)
    print(
        f"worst ||r| - 1| under TIR: s {np.abs(np.abs(rs) - 1).max():.2e}, "
        f"p {np.abs(np.abs(rp) - 1).max():.2e}"
    )
    np.testing.assert_allclose(np.abs(rs), 1.0, atol=2e-6)
    np.testing.assert_allclose(np.abs(rp), 1.0, atol=2e-6)
    # phase of TIR vs Born & Wolf §1.5.4 with exp(-i w t): rs = exp(-i d_s), tan(d_s/2) =
    # sqrt(sin^2 - n^2)/cos, tan(d_p/2) = sqrt(sin^2 - n^2)/(n^2 cos), rp = -exp(-i d_p)... see below
    n = n2 / n1
    root = np.sqrt(np.sin(theta) ** 2 - n**2)
    d_s = 2 * np.arctan2(root, np.cos(theta))
    d_p = 2 * np.arctan2(root, n**2 * np.cos(theta))
    np.testing.assert_allclose(rs, np.exp(-1j * d_s), atol=2e-5)
    np.testing.assert_allclose(rp, np.exp(-1j * d_p), atol=2e-5)
    _, _, Ts, Tp = fresnel_power(np.cos(theta), n1, n2, device=device)
    assert np.all(Ts == 0) and np.all(Tp == 0)


def test_critical_and_grazing_angles_are_finite(device):
    n1, n2 = 2.417, 1.0
    cos_c = np.sqrt(1 - (n2 / n1) ** 2)
    cos_i = np.array(
        [
            cos_c,
            np.float32(cos_c),
            np.nextafter(np.float32(cos_c), 1),
            np.nextafter(np.float32(cos_c), 0),
            0.0,
            1e-30,
        ]
    )
    out = fresnel(cos_i, n1, n2, device=device)
    for a in out:
        assert np.all(np.isfinite(a))
    rs, rp, _, _ = out
    # at the critical angle both amplitudes are +1 (continuous with the TIR side, where |r| = 1)
    assert np.all(np.abs(rs[:4] - 1) < 2e-2) and np.all(np.abs(rp[:4] - 1) < 2e-2)
    # |r| = 1 at and beyond the critical angle (index 2 is one ulp on the propagating side,
    # where |r| < 1 is correct)
    tir = [0, 1, 3, 4, 5]
    assert np.all(np.abs(np.abs(rs[tir]) - 1) < 1e-6) and np.all(np.abs(np.abs(rp[tir]) - 1) < 1e-6)
    # grazing incidence: r = -1
    np.testing.assert_allclose(rs[4:], -1.0, atol=1e-6)
    np.testing.assert_allclose(rp[4:], -1.0, atol=1e-6)
    # grazing into the same medium: no interface
    rs, rp, ts, tp = fresnel(0.0, 1.5, 1.5, device=device)
    assert rs == 0 and rp == 0 and ts == 1 and tp == 1
    rs, rp, ts, tp = fresnel(0.0, 1.0, 1.5, device=device)
    assert rs == pytest.approx(-1) and rp == pytest.approx(-1) and np.isfinite(ts) and np.isfinite(tp)


def _tmm_reference(cos_i, n1, n2):
    th1 = np.arccos(cos_i)
    th2 = tmm.snell(n1, n2, th1)
    out = [tmm.interface_r(p, n1, n2, th1, th2) for p in "sp"]
    out += [tmm.interface_t(p, n1, n2, th1, th2) for p in "sp"]
    return out


@pytest.mark.parametrize(
    "n2",
    [
        0.18 + 3.43j,  # gold near 600 nm
        1.5 + 0.5j,
        4.0 + 0.04j,  # silicon-like
        1.76 + 1e-6j,  # weakly absorbing sapphire
        0.05 + 5.0j,  # silver-like
    ],
)
def test_absorbing_media_vs_tmm(device, n2):
    n1 = 1.0 + 0j
    cos_i = np.linspace(0.02, 1.0, 50)
    got = fresnel(cos_i, n1, n2, device=device)
    want = np.array([_tmm_reference(c, n1, complex(n2)) for c in cos_i]).T
    print(
        f"n2 = {n2}: worst |amplitude - tmm| "
        f"{max(np.abs(g - w).max() for g, w in zip(got, want, strict=True)):.2e}"
    )
    for g, w in zip(got, want, strict=True):
        np.testing.assert_allclose(g, w, atol=5e-6, rtol=0)
    # energy at the interface: flux into the absorber + reflected = incident
    Rs, Rp, Ts, Tp = fresnel_power(cos_i, n1, n2, device=device)
    np.testing.assert_allclose(Rs + Ts, 1.0, atol=2e-5)
    np.testing.assert_allclose(Rp + Tp, 1.0, atol=2e-5)
    tmm_T = np.array(
        [
            [
                tmm.interface_T(p, 1.0, complex(n2), np.arccos(c), tmm.snell(1.0, complex(n2), np.arccos(c)))
                for p in "sp"
            ]
            for c in cos_i
        ]
    )
    np.testing.assert_allclose(Ts, tmm_T[:, 0], atol=2e-5)
    np.testing.assert_allclose(Tp, tmm_T[:, 1], atol=2e-5)


def test_dense_to_rare_vs_tmm_including_tir(device):
    n1, n2 = 1.76 + 0j, 1.0 + 0j
    cos_i = np.linspace(0.0, 1.0, 101)[1:]
    got = fresnel(cos_i, n1, n2, device=device)
    crit_cos = np.sqrt(1 - (1 / 1.76) ** 2)
    far = np.abs(cos_i - crit_cos) > 5e-3
    want = np.array([_tmm_reference(c, n1, n2) for c in cos_i]).T
    for g, w in zip(got, want, strict=True):
        np.testing.assert_allclose(g[far], w[far], atol=2e-5, rtol=0)


def test_broadcasting_and_shapes(device):
    cos_i = np.linspace(0, 1, 6).reshape(2, 3)
    n2 = np.array([1.5, 2.0, 2.4])
    rs, rp, ts, tp = fresnel(cos_i, 1.0, n2, device=device)
    assert rs.shape == (2, 3) and rs.dtype == np.complex128
    single = fresnel(cos_i[1, 2], 1.0, n2[2], device=device)[0]
    assert single == pytest.approx(rs[1, 2])


def test_bad_input(device):
    with pytest.raises(InputError):
        fresnel(1.5, 1.0, 1.5, device=device)
    with pytest.raises(InputError):
        fresnel(0.5, 1.0, 1.5 - 0.1j, device=device)
    with pytest.raises(InputError):
        fresnel(0.5, np.nan, 1.5, device=device)


def test_snell_directions(device):
    rng = np.random.default_rng(9)
    n = 2000
    normal = rng.normal(size=(n, 3))
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    d = np.where(np.sum(d * normal, -1, keepdims=True) > 0, -d, d)
    n1 = rng.uniform(1.0, 2.5, n)
    n2 = rng.uniform(1.0, 2.5, n)
    t = wo.optics.refract(d, normal, n1, n2, device=device)
    r = wo.optics.reflect(d, normal, device=device)
    sin_i = np.linalg.norm(np.cross(d, normal), axis=-1)
    tir = n1 * sin_i > n2
    ok = ~tir & (n1 * sin_i < n2 * (1 - 1e-4))
    # Snell: n1 sin i = n2 sin t, t in the plane of incidence, on the far side
    sin_t = np.linalg.norm(np.cross(t, normal), axis=-1)
    assert np.abs(n1 * sin_i - n2 * sin_t)[ok].max() < 2e-6
    assert np.abs(np.sum(np.cross(d, normal) * t, -1))[ok].max() < 2e-6
    assert np.all(np.sum(t * normal, -1)[ok] < 0)
    assert np.all(t[tir] == 0)
    # mirror: angle of reflection = angle of incidence, tangential part kept
    np.testing.assert_allclose(np.sum(r * normal, -1), -np.sum(d * normal, -1), atol=1e-6)
    np.testing.assert_allclose(np.cross(r, normal), np.cross(d, normal), atol=1e-6)


def test_absorbing_incident_medium_keeps_the_forward_wave(device):
    # light leaving a weakly absorbing dye (n = 1.33 + 0.00075i) into air at 25 deg: the
    # reflection must stay that of the lossless interface (|rs| = 0.1861), not the backward root
    # (|rs| = 5.4) that "Im(N cos t) >= 0" alone picks when medium 1 absorbs
    c = np.cos(np.radians(25.0))
    lossy = wo.optics.fresnel(c, 1.33 + 0.00075j, 1.0, device=device)
    clear = wo.optics.fresnel(c, 1.33, 1.0, device=device)
    for a, b in zip(lossy, clear, strict=True):
        assert abs(abs(a) - abs(b)) < 1e-4


def test_reverse_crossing_is_the_swapped_solution(device):
    """fresnel_reverse (the B -> A amplitudes every backward event needs, from the A -> B solve)
    against the closed angle forms of the crossing from medium 2 at the refracted angle, below
    the critical angle, for rare-to-dense and dense-to-rare pairs; and R + T = 1 for it."""
    import warp as wp

    from warpoptics.optics.fresnel import (
        fresnel_amplitudes,
        fresnel_reverse,
        refracted_cos,
        transmitted_flux_ratio,
    )

    @wp.kernel
    def k(cos_i: wp.array(dtype=float), n1: float, n2: float, out: wp.array2d(dtype=float)):
        i = wp.tid()
        f = fresnel_amplitudes(cos_i[i], wp.vec2f(n1, 0.0), wp.vec2f(n2, 0.0))
        r = fresnel_reverse(f, refracted_cos(f, wp.vec2f(n2, 0.0)), wp.vec2f(n1, 0.0), wp.vec2f(n2, 0.0))
        out[i, 0] = r.rs[0]
        out[i, 1] = r.rp[0]
        out[i, 2] = r.ts[0]
        out[i, 3] = r.tp[0]
        out[i, 4] = r.rs[1] + r.rp[1] + r.ts[1] + r.tp[1]
        out[i, 5] = transmitted_flux_ratio(r)

    for n1, n2 in ((1.0, 2.4173), (2.4173, 1.0), (1.5, 1.76), (1.33, 1.0)):
        crit = np.sqrt(max(0.0, 1.0 - (n2 / n1) ** 2)) if n1 > n2 else 0.0
        cos_i = np.linspace(crit, 1.0, 400)[1:-1]  # propagating, away from the critical angle
        if crit == 0.0:
            # down to grazing incidence from the rare side, where re-solving from cos t lost 1e-2
            cos_i = np.concatenate([np.logspace(-7, -2, 60), cos_i])
        cos_i = cos_i[np.abs(cos_i - crit) > 2e-3]
        out = wp.zeros((len(cos_i), 6), dtype=float, device=device)
        wp.launch(
            k,
            dim=len(cos_i),
            inputs=[wp.array(cos_i, dtype=float, device=device), n1, n2, out],
            device=device,
        )
        got = out.numpy().astype(np.float64)
        theta_t = np.arcsin(n1 * np.sin(np.arccos(cos_i)) / n2)
        want = np.array(_angle_forms(theta_t, n2, n1))  # from medium 2 at theta_t into medium 1
        np.testing.assert_allclose(got[:, :4], want.T, atol=2e-5, rtol=0)
        assert np.all(got[:, 4] == 0.0)
        # energy: |r'|^2 + |t'|^2 Re(b') / Re(a') = 1 for s and for p
        for r_col, t_col in ((0, 2), (1, 3)):
            np.testing.assert_allclose(got[:, r_col] ** 2 + got[:, t_col] ** 2 * got[:, 5], 1.0, atol=2e-5)


def test_reverse_crossing_with_an_absorbing_side_is_the_direct_solve(device):
    """An absorbing medium has no Stokes swap: fresnel_reverse is then fresnel_amplitudes at the
    refracted angle, bit for bit (the swap between real indices is tested above)."""
    import warp as wp

    from warpoptics.optics.fresnel import fresnel_amplitudes, fresnel_reverse, refracted_cos

    @wp.kernel
    def k(cos_i: wp.array(dtype=float), out: wp.array2d(dtype=float)):
        i = wp.tid()
        n1 = wp.vec2f(1.0, 0.0)
        n2 = wp.vec2f(1.76, 0.02)
        f = fresnel_amplitudes(cos_i[i], n1, n2)
        c = refracted_cos(f, n2)
        r = fresnel_reverse(f, c, n1, n2)
        d = fresnel_amplitudes(c, n2, n1)
        out[i, 0] = wp.length(r.rs - d.rs) + wp.length(r.rp - d.rp)
        out[i, 1] = wp.length(r.ts - d.ts) + wp.length(r.tp - d.tp)
        out[i, 2] = wp.length(r.rs + f.rs)  # what a (wrong) swap would give: -rs

    cos_i = np.linspace(0.05, 1.0, 64)
    out = wp.zeros((64, 3), dtype=float, device=device)
    wp.launch(k, dim=64, inputs=[wp.array(cos_i, dtype=float, device=device), out], device=device)
    got = out.numpy()
    assert np.all(got[:, :2] == 0.0)
    assert got[:, 2].max() > 1e-3  # the absorbing case really differs from the swap

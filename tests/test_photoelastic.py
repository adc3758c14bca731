"""Strained glass: the stress-optic law (optics/photoelastic.py), the Brazilian disc
(materials/stress.py) and its polariscope images (pipelines/photoelastic.py).

References, independent of the code under test:

- the disc's stress field checked as a solution of plane elasticity, numerically here:
  equilibrium (div sigma = 0 by central differences), a traction-free rim, and the load it
  carries (the integral of sigma_yy t across the horizontal diameter is -P);
- the closed forms of Frocht (Photoelasticity vol. 2): sigma_1 - sigma_2 = 8P / (pi D t)
  at the centre and 8 P D / (pi t (D^2 - 4 y^2)) along the loaded diameter, so that the dark
  fringes of the circular polariscope lie at y_k = sqrt(D^2 - 8 C P D / (pi lambda k)) / 2;
- the polariscope laws I = sin^2(2 (theta - p)) sin^2(pi Delta / lambda) (plane) and
  sin^2(pi Delta / lambda) (circular), with Delta and theta written here from the stress
  components (Mohr's circle);
- symmetry: on both diameters of the disc tau_xy = 0, so the principal directions are x and y
  and the plane polariscope at 0 / 90 degrees is dark there (the isoclinic of 0 degrees).
"""

from __future__ import annotations

import numpy as np
import pytest

from warpoptics.errors import InputError
from warpoptics.materials.stress import STRESS_OPTIC_TPA, brazilian_disc, quenched_plate
from warpoptics.optics.photoelastic import photoelastic_plates, principal_stresses, stress_retardations
from warpoptics.pipelines import photoelastic as pe

D, T, P = 20.0, 5.0, 4000.0  # mm, mm, N: fringe order 2.39 at the centre at 589.3 nm in BK7
C = STRESS_OPTIC_TPA["bk7"]
LAM = 589.3


def _disc(x, y, load=P):
    return brazilian_disc(x, y, diameter_mm=D, thickness_mm=T, load_n=load)


def test_disc_is_a_plane_elasticity_solution():
    h = 1e-4
    rng = np.random.default_rng(0)
    for x, y in rng.uniform(-6, 6, size=(6, 2)):
        dsxx = (_disc(x + h, y)[0] - _disc(x - h, y)[0]) / (2 * h)
        dtxy_y = (_disc(x, y + h)[2] - _disc(x, y - h)[2]) / (2 * h)
        dtxy_x = (_disc(x + h, y)[2] - _disc(x - h, y)[2]) / (2 * h)
        dsyy = (_disc(x, y + h)[1] - _disc(x, y - h)[1]) / (2 * h)
        assert abs(dsxx + dtxy_y) < 1e-5 and abs(dtxy_x + dsyy) < 1e-5  # stresses ~ 10-100 MPa
    for a in np.radians([10.0, 45.0, 80.0, 100.0, 200.0, 300.0]):
        n = np.array([np.cos(a), np.sin(a)])
        sxx, syy, txy = _disc(*(0.5 * D * (1 - 1e-9) * n))
        assert abs(sxx * n[0] + txy * n[1]) < 1e-5 and abs(txy * n[0] + syy * n[1]) < 1e-5
    x = np.linspace(-0.5 * D, 0.5 * D, 200001)
    assert abs(np.trapezoid(_disc(x, 0 * x)[1], x) * T + P) < 1e-3 * P
    assert np.isnan(_disc(0.0, 0.6 * D)[0]) and np.isnan(_disc(0.0, 0.5 * D)[0])


def test_centre_fringe_order_closed_form(device):
    s1, s2, theta = principal_stresses(*_disc(0.0, 0.0), device=device)
    dsig = 8 * P / (np.pi * D * T)
    assert abs((s1 - s2) / dsig - 1) < 1e-6
    assert abs(theta) < 1e-6  # sigma_1 (tension) along x at the centre
    n = stress_retardations(C, T, s1, s2, device=device) / LAM
    assert abs(n / (C * T * dsig / LAM) - 1) < 1e-2
    assert 2.3 < n < 2.5


def test_principal_stresses_against_mohr(device):
    rng = np.random.default_rng(1)
    sxx, syy, txy = rng.normal(0, 30, size=(3, 50))
    s1, s2, th = principal_stresses(sxx, syy, txy, device=device)
    for i in range(50):
        w, v = np.linalg.eigh([[sxx[i], txy[i]], [txy[i], syy[i]]])
        assert abs(s1[i] - w[1]) < 1e-4 and abs(s2[i] - w[0]) < 1e-4
        e = np.array([np.cos(np.radians(th[i])), np.sin(np.radians(th[i]))])
        assert abs(abs(e @ v[:, 1]) - 1) < 1e-6  # theta_1 is the eigenvector of sigma_1


@pytest.mark.parametrize("polariscope", ["plane", "circular"])
def test_polariscope_laws(device, polariscope):
    rng = np.random.default_rng(2)
    sxx, syy, txy = rng.normal(0, 20, size=(3, 40))
    lam = np.array([450.0, 589.3, 700.0])
    for p in (0.0, 30.0):
        got = pe.polariscope_transmission(
            sxx,
            syy,
            txy,
            lam,
            c_tpa=C,
            thickness_mm=T,
            polariscope=polariscope,
            polarizer_deg=p,
            device=device,
        )
        delta = C * T * np.sqrt((sxx - syy) ** 2 + 4 * txy**2)
        theta = 0.5 * np.arctan2(2 * txy, sxx - syy)
        ref = np.sin(np.pi * delta[:, None] / lam) ** 2
        if polariscope == "plane":
            ref = ref * np.sin(2 * (theta - np.radians(p)))[:, None] ** 2
        assert np.max(np.abs(got - ref)) < 1e-5


def test_strain_free_glass_is_black(device):
    for pol in ("plane", "circular"):
        for lam in (589.3, None):
            im = pe.brazilian_disc_image(
                load_n=0.0, polariscope=pol, wavelength_nm=lam, size=16, device=device
            )
            if lam is None:
                assert np.max(np.abs(im.xyz)) < 1e-7
            else:
                assert np.max(im.intensity) < 1e-7
            assert im.mask.sum() > 150


def test_dark_fringes_along_the_loaded_diameter(device):
    # circular polariscope, monochromatic: I = sin^2(pi N(y)); minima at integer N
    y = np.linspace(0.0, 0.49 * D, 4001)
    sxx, syy, txy = _disc(0 * y, y)
    i = pe.polariscope_transmission(
        sxx, syy, txy, [LAM], c_tpa=C, thickness_mm=T, polariscope="circular", device=device
    )[:, 0]
    k_min = int(np.ceil(8 * C * P / (np.pi * LAM * D)))
    want = [0.5 * np.sqrt(D**2 - 8 * C * P * D / (np.pi * LAM * k)) for k in range(k_min, k_min + 5)]
    # local minima of the sampled profile, refined by a parabola through three samples
    idx = [j for j in range(1, y.size - 1) if i[j] < i[j - 1] and i[j] <= i[j + 1] and i[j] < 0.05]
    found = []
    for j in idx:
        a, b, c = i[j - 1], i[j], i[j + 1]
        found.append(y[j] + 0.5 * (a - c) / (a - 2 * b + c) * (y[1] - y[0]))
    assert len(found) >= 5
    # 1 % asked; the positions agree to 4e-7 (float32 stresses, parabola on a 2.5 µm grid)
    np.testing.assert_allclose(found[:5], want, rtol=1e-4)


def test_isoclinics_of_the_plane_polariscope(device):
    # on both diameters tau_xy = 0 (symmetry): dark at polarizer 0 and 90, bright at 45 where
    # the retardation is not a whole number of wavelengths
    u = np.linspace(-0.45 * D, 0.45 * D, 19)
    u = u[np.abs(u) > 0.5]
    pts = [np.concatenate([0 * u, u]), np.concatenate([u, 0 * u])]
    sxx, syy, txy = _disc(*pts)
    for p in (0.0, 90.0):
        dark = pe.polariscope_transmission(
            sxx, syy, txy, [LAM], c_tpa=C, thickness_mm=T, polarizer_deg=p, device=device
        )
        assert np.max(dark) < 1e-7
    bright = pe.polariscope_transmission(
        sxx, syy, txy, [LAM], c_tpa=C, thickness_mm=T, polarizer_deg=45.0, device=device
    )
    circ = pe.polariscope_transmission(
        sxx, syy, txy, [LAM], c_tpa=C, thickness_mm=T, polariscope="circular", device=device
    )
    np.testing.assert_allclose(bright, circ, atol=1e-5)  # sin^2(2 * 45) = 1 there
    # off the diameters the plane image is not dark at 0 degrees: the isoclinic is a curve
    off = pe.polariscope_transmission(
        *_disc(np.array([4.0]), np.array([4.0])), [LAM], c_tpa=C, thickness_mm=T
    )
    assert off[0, 0] > 1e-3


def test_jones_of_a_stressed_point_is_a_retarder(device):
    j = photoelastic_plates(10.0, -5.0, 3.0, C, T, LAM, device=device)
    np.testing.assert_allclose(j @ j.conj().T, np.eye(2), atol=1e-6)  # lossless
    assert abs(np.linalg.det(j)) == pytest.approx(1.0, abs=1e-6)


def test_quenched_plate_profile():
    z = np.linspace(-2.0, 2.0, 20001)
    s = quenched_plate(z, thickness_mm=4.0, surface_mpa=100.0)
    assert s[0] == pytest.approx(-100.0) and s[10000] == pytest.approx(50.0)
    assert abs(np.trapezoid(s, z)) < 1e-6  # no net force
    assert np.all(quenched_plate(z, thickness_mm=4.0, surface_mpa=0.0) == 0.0)


def test_quenched_plate_edge_on(device):
    # circular polariscope: dark where sigma(z) = 0, z = +-h / (2 sqrt 3), and where
    # C L sigma(z) = k lambda; annealed glass is black in both polariscopes
    h, length, s0 = 6.0, 20.0, 100.0
    z0 = h / (2 * np.sqrt(3))
    i = pe.polariscope_transmission(
        quenched_plate(np.array([z0, -z0, 0.0]), thickness_mm=h, surface_mpa=s0),
        0.0,
        0.0,
        [LAM],
        c_tpa=C,
        thickness_mm=length,
        polariscope="circular",
        device=device,
    )[:, 0]
    assert np.max(i[:2]) < 1e-7
    assert abs(i[2] - np.sin(np.pi * C * length * 0.5 * s0 / LAM) ** 2) < 1e-5
    for pol in ("plane", "circular"):
        im = pe.quenched_plate_image(surface_mpa=0.0, polariscope=pol, width=16, height=16, device=device)
        assert np.max(im.intensity) < 1e-7
    # the plane polariscope with the polarizer along the plate sees nothing: the isoclinic
    im = pe.quenched_plate_image(polarizer_deg=0.0, width=16, height=16, device=device)
    assert np.max(im.intensity) < 1e-7


def test_bad_inputs():
    with pytest.raises(InputError, match="polariscope"):
        pe.polariscope_transmission(1.0, 0.0, 0.0, [LAM], c_tpa=C, thickness_mm=T, polariscope="round")
    with pytest.raises(InputError, match="glass"):
        pe.brazilian_disc_image(glass="unobtainium", size=16)
    with pytest.raises(InputError, match="diameter_mm"):
        brazilian_disc(0.0, 0.0, diameter_mm=-1.0, thickness_mm=T, load_n=P)

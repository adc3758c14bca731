"""Optical activity of quartz in the plate model (optics/plate.py, materials/activity.py).

References, independent of the code under test:

- the N-slice Jones product: a plate cut into N thin slices, each a linear retarder of
  retardation delta / N followed by a rotation by tau / N, written here in NumPy; as N grows it
  converges to the exact elliptic retarder (Lie-Trotter: the error is below
  |[A, B]| / (2 N) = |delta tau| / (2 N) in the operator norm), so N = 2^20 slices bound it by
  1e-5 for the retardations used;
- along the optic axis the plate is a pure rotation by rho d: between crossed polarizers it
  transmits sin^2(rho d) times the Fresnel transmission (4 n / (1 + n)^2)^2 of its two faces
  (both waves have index n_o there);
- the rotatory power itself against the measurements of Soret & Sarasin (1882) as tabulated in
  Winkelmann's Handbuch der Physik (quartz, 1 mm, cut across the axis): C 17.31, D 21.72,
  F 32.72 degrees;
- the conoscopic figure: the closed form of an elliptic retarder between crossed polarizers,
  I = sin^2(Omega) / Omega^2 ((delta / 2)^2 sin^2(2 alpha) + tau^2) with
  Omega^2 = (delta / 2)^2 + tau^2 (the N-slice limit, worked out here for crossed polarizers), delta(theta)
  from the closed-form normal wave-vector components of a plate cut across its axis,
  q_o = sqrt(n_o^2 - s^2), q_e = (n_o / n_e) sqrt(n_e^2 - s^2), s = NA r.
"""

from __future__ import annotations

import numpy as np
import pytest

import warpoptics as wo
from warpoptics.errors import InputError
from warpoptics.materials.activity import optical_activity
from warpoptics.optics.plate import active_plate_jones, active_retarders, plate_jones, rotatory_powers
from warpoptics.pipelines import microscope as ms

LAM = np.linspace(380.0, 780.0, 41)


def _n_slice(delta, tau, n_slices=2**20):
    """prod_N [R(tau / N) diag(exp(-i delta / 2N), exp(i delta / 2N))], by repeated squaring."""
    h = delta / (2 * n_slices)
    lin = np.diag([np.exp(-1j * h), np.exp(1j * h)])
    t = tau / n_slices
    rot = np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]])
    return np.linalg.matrix_power(rot @ lin, n_slices)


@pytest.mark.parametrize("delta, tau", [(0.0, 0.7), (3.0, 0.0), (2.5, 0.6), (-7.0, 0.4), (30.0, -1.2)])
def test_active_retarder_is_the_n_slice_limit(device, delta, tau):
    got = active_retarders(delta, tau, device=device)
    ref = _n_slice(delta, tau)
    # float32 output (1e-7) + the slicing error |delta tau| / 2N <= 2e-5
    assert np.max(np.abs(got - ref)) < 2e-5 + 2e-7
    # the slicing converges to it: N = 2^10 is much farther off when delta tau != 0
    if delta * tau != 0:
        assert np.max(np.abs(got - _n_slice(delta, tau, 2**10))) > 10 * np.max(np.abs(got - ref))


def test_rotatory_power_data_against_measurements():
    q = optical_activity("quartz")
    lam = np.array([656.3, 589.3, 486.1])  # Fraunhofer C, D, F
    measured = np.array([17.31, 21.72, 32.72])  # deg/mm, Soret & Sarasin
    assert np.max(np.abs(q.rotatory_power_deg_mm(lam) / measured - 1)) < 2e-3
    assert (
        optical_activity("quartz", "right").rho_rad_mm(589.3)
        < 0
        < optical_activity("quartz", "left").rho_rad_mm(589.3)
    )
    with pytest.raises(InputError, match="handedness"):
        optical_activity("quartz", "up")
    with pytest.raises(InputError, match="optical-activity"):
        optical_activity("calcite")


def test_rotatory_power_direction_law(device):
    c = np.array([1.0, 0.5, 0.0])
    got = rotatory_powers(c, 0.4, -0.5, device=device)
    np.testing.assert_allclose(got, 0.4 * (c**2 - 0.5 * (1 - c**2)), atol=1e-7)


def _f32(x):
    return np.asarray(x, dtype=np.float32).astype(np.float64)


@pytest.mark.parametrize("tilt_deg", [0.0, 5.0, 30.0, 60.0])
def test_active_plate_at_normal_incidence_is_the_n_slice_product(device, tilt_deg):
    # quartz-like plate, optic axis tilted by tilt_deg from the normal, in a mount of index n_o:
    # the o wave crosses the faces unreflected, the e wave loses ((n_e' - n_o) / 2n)^2 < 1e-5
    # of its power per face, so the bare N-slice product is the reference.  Inputs rounded to
    # float32 first: the absolute phase is 2 pi n d / lambda ~ 1.6e4 rad.  The wave solver
    # returns the normal wave-vector components in float32 (1 ulp = 1.2e-7, i.e. 1.3e-3 rad of
    # phase at 1 mm), so the closed-form reference holds to k0 d 2.4e-7; the strict check takes
    # the two waves' phases from the code's own activity-free plate (tested against the
    # Berreman solution in tests/test_plate.py) and so isolates the coupling, within 1e-4.
    no, ne, lam, d = _f32(1.5443), _f32(1.5534), 589.3, 1.0
    rho = _f32(np.radians(21.72))
    t = np.radians(tilt_deg)
    axis = np.array([np.sin(t) * np.cos(0.3), np.sin(t) * np.sin(0.3), np.cos(t)])
    kw = dict(optic_axis=axis, n_ambient=no, device=device)
    j, s = active_plate_jones([0.0, 0.0, 1.0], lam, [no, 0.0, ne], d, rho, **kw)
    j_lin, _ = active_plate_jones([0.0, 0.0, 1.0], lam, [no, 0.0, ne], d, 0.0, **kw)
    ne_t = 1.0 / np.sqrt(np.cos(t) ** 2 / no**2 + np.sin(t) ** 2 / ne**2)
    k0d = 2 * np.pi * d * 1e6 / lam
    tau = rho * np.cos(t) ** 2 * d  # along the normal: path d, rho(theta) = rho cos^2(theta)
    # right-handed basis about +z: (e wave, o wave); e vibrates along the axis' transverse part
    u = np.array([np.cos(0.3), np.sin(0.3), 0.0])
    e_e, e_o = u, np.cross([0.0, 0.0, 1.0], u)
    y = np.cross([0.0, 0.0, 1.0], s)
    b = np.array([[e_e @ s, e_o @ s], [e_e @ y, e_o @ y]])

    def reference(phi_e, phi_o):
        # the slices carry the e-minus-o retardation with the e wave first: _n_slice(-delta)
        return b @ (np.exp(0.5j * (phi_e + phi_o)) * _n_slice(-(phi_e - phi_o), tau)) @ b.T

    closed = reference(k0d * (ne_t - no), 0.0)
    assert np.max(np.abs(j - closed)) < k0d * 2.4e-7 + 1e-4
    # the waves' phases of the code's linear plate (unwrapped near the closed form)
    lin = b.T @ j_lin @ b
    assert np.max(np.abs(lin - np.diag(np.diag(lin)))) < 1e-6  # (e, o) are its eigenwaves
    phi_e = k0d * (ne_t - no) + np.angle(lin[0, 0] * np.exp(-1j * k0d * (ne_t - no)))
    phi_o = np.angle(lin[1, 1])
    assert np.max(np.abs(j - reference(phi_e, phi_o))) < 1e-4
    # and activity matters here: far above the tolerance
    assert np.max(np.abs(j - j_lin)) > 1e-3  # ten times the tolerance


def test_activity_off_is_todays_plate(device):
    rng = np.random.default_rng(3)
    k = rng.normal(size=(16, 3)) * [0.3, 0.3, 0.0] + [0.0, 0.0, 1.0]
    n3 = [1.5443, 0.0, 1.5534]
    axis = (1.0, 1.0, 0.2)
    j_act, s1 = active_plate_jones(k, 589.3, n3, 0.5, 0.0, optic_axis=axis, device=device)
    j_old, s2 = plate_jones(k, 589.3, n3, 0.5, crystal_axes=axis, device=device)
    assert np.max(np.abs(j_act - j_old)) < 1e-6
    np.testing.assert_array_equal(s1, s2)
    with pytest.raises(InputError, match="uniaxial"):
        active_plate_jones(k, 589.3, [1.6, 1.61, 1.62], 0.5, 0.1, device=device)


def _fresnel_axis(n):
    return (4 * n / (1 + n) ** 2) ** 2  # power through both faces at normal incidence


@pytest.mark.parametrize("hand", ["right", "left"])
def test_along_the_axis_a_rotation_by_rho_d(device, hand):
    quartz = wo.materials.get("quartz")
    act = optical_activity("quartz", hand)
    d = 1.5
    kw = dict(optic_axis=(0.0, 0.0, 1.0), device=device)
    crossed = ms.interference_colour(quartz, d, optical_activity=hand, **kw)
    lam = crossed.wavelength_nm
    sel = (lam >= 380) & (lam <= 780)
    ref = _fresnel_axis(quartz.n(lam)[:, 0]) * np.sin(act.rho_rad_mm(lam) * d) ** 2
    assert np.max(np.abs(crossed.transmission[sel] - ref[sel])) < 1e-4
    # without activity the axis is dark
    assert np.max(ms.interference_colour(quartz, d, **kw).transmission) < 1e-7
    # the sense: at 589.3 nm the light leaves vibrating at the polarizer turned by rot
    r589 = float(act.rho_rad_mm(589.3) * d)
    t589 = float(_fresnel_axis(quartz.n([589.3])[0, 0]))
    for beta, want in ((r589, 1.0), (-r589, np.cos(2 * r589) ** 2)):
        got = ms.conoscope_profile(
            quartz, d, [0.0], analyzer_deg=np.degrees(beta), optical_activity=hand, device=device
        )[0]
        assert abs(got - t589 * want) < 1e-4


def _elliptic_crossed(delta, tau, sin2_2a):
    om = np.sqrt((delta / 2) ** 2 + tau**2)
    return np.sinc(om / np.pi) ** 2 * ((delta / 2) ** 2 * sin2_2a + tau**2)


def test_conoscopic_bullseye(device):
    """2 mm quartz cut across the axis at 589.3 nm, NA 0.5, in a mount of index n_o (Fresnel
    losses below 1e-4): the centre transmits sin^2(rho d) (no isogyre there), the isogyres
    are present in the outer rings, and the profiles follow the elliptic-retarder closed form."""
    quartz = wo.materials.get("quartz")
    lam, d, na = 589.3, 2.0, 0.5
    no, ne = quartz.n([lam])[0]
    rho = abs(float(optical_activity("quartz").rho_rad_mm(lam)))
    r = np.linspace(0.0, 1.0, 41)
    kw = dict(wavelength_nm=lam, numerical_aperture=na, n_ambient=float(no), device=device)
    on_pol = ms.conoscope_profile(quartz, d, r, azimuth_deg=0.0, optical_activity="right", **kw)
    diag = ms.conoscope_profile(quartz, d, r, azimuth_deg=45.0, optical_activity="right", **kw)
    plain = ms.conoscope_profile(quartz, d, r, azimuth_deg=0.0, **kw)
    # the closed form
    s = na * r
    qo = np.sqrt(no**2 - s**2)
    qe = (no / ne) * np.sqrt(ne**2 - s**2)  # index surface s^2 / n_e^2 + q^2 / n_o^2 = 1
    delta = 2 * np.pi * d * 1e6 * (qe - qo) / lam
    cos_t = qo / no
    tau = rho * cos_t**2 * d / cos_t  # rho cos^2(theta) along the wave normal, path d / cos(theta)
    # centre: sin^2(rho d), not the black of the uniaxial cross
    assert abs(on_pol[0] - np.sin(rho * d) ** 2) < 1e-4
    assert on_pol[0] > 0.4 and plain[0] < 1e-7
    assert np.max(np.abs(on_pol - _elliptic_crossed(delta, tau, 0.0))) < 2e-3
    assert np.max(np.abs(diag - _elliptic_crossed(delta, tau, 1.0))) < 2e-3
    # the cross in the outer rings (delta > 3 pi): on the polarizer's azimuth the light is
    # below 3 % of the brightest ring on the diagonal, bounded by tau^2 / ((delta / 2)^2 + tau^2)
    outer = delta > 3 * np.pi
    assert outer.sum() >= 8
    assert np.max(on_pol[outer]) < 0.03 * np.max(diag[outer])
    assert np.all(on_pol[outer] <= tau[outer] ** 2 / ((delta[outer] / 2) ** 2 + tau[outer] ** 2) + 1e-4)
    # without activity the cross is black everywhere on that azimuth
    assert np.max(plain) < 1e-7


def test_activity_refused_for_biaxial_and_bad_values(device):
    topaz = wo.materials.get("topaz")
    with pytest.raises(InputError, match="uniaxial"):
        ms.conoscope_profile(topaz, 0.1, [0.0], optical_activity="right", device=device)
    with pytest.raises(InputError, match="optical_activity"):
        ms.conoscope_profile(wo.materials.get("quartz"), 0.1, [0.0], optical_activity=3, device=device)

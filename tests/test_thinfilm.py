"""Thin films: exact stacks against tmm and closed forms, the Smits–Meyer model against its
equations, colour tables against independent colour integrals, CLI and scripts as subprocesses.

Tolerances: the stacks run in float64 inside the kernels; tmm (Byrnes) is float64 NumPy, so the
two agree to ~1e-14 and the issue's 1e-6 leaves a wide margin.  The float32 renderer front end
is compared with 2e-5 (a few float32 ulps on the inputs times a phase of at most ~20 rad).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import tmm

import warpoptics as wo
from warpoptics.color import gamut_clip
from warpoptics.errors import InputError
from warpoptics.optics.thinfilm import tables as thinfilm_tables

tf = wo.thinfilm
ROOT = Path(__file__).resolve().parents[1]
WL = np.linspace(380.0, 780.0, 21)
ANGLES = [0.0, 30.0, 60.0, 85.0]

# (name, incident, layers, thicknesses, substrate)
_rng = np.random.default_rng(5)
STACKS = [
    ("soap film", 1.0, [1.33], [420.0], 1.0),
    ("film on glass", 1.0, [1.38], [99.6], 1.52),
    ("high-index film on glass", 1.0, [2.35], [260.0], 1.52),
    (
        "twelve layers",
        1.0,
        [1.46, 2.3] * 6,
        list(_rng.uniform(40.0, 200.0, 12)),
        1.52,
    ),
    ("absorbing", 1.0, [1.5 + 0.0j, 0.18 + 3.4j, 2.0 + 0.3j], [120.0, 15.0, 60.0], 1.7 + 0.02j),
    ("metal substrate", 1.0, [1.45], [200.0], 0.13 + 3.9j),
]


def _tmm(pol, n_inc, layers, d, n_sub, angle, wl, key):
    n_list = [n_inc, *layers, n_sub]
    d_list = [np.inf, *d, np.inf]
    th = np.radians(angle)
    if pol == "unpolarized":
        return np.array([tmm.unpolarized_RT(n_list, d_list, th, w)[key] for w in wl])
    return np.array([tmm.coh_tmm(pol, n_list, d_list, th, w)[key] for w in wl])


@pytest.mark.parametrize("name,n_inc,layers,d,n_sub", STACKS, ids=[s[0] for s in STACKS])
@pytest.mark.parametrize("pol", ["s", "p", "unpolarized"])
def test_reflectance_matches_tmm(device, name, n_inc, layers, d, n_sub, pol):
    wl = WL[:, None]
    ang = np.array(ANGLES)[None, :]
    R = tf.reflectance(wl, layers, d, n_inc, n_sub, ang, pol, device=device)
    T = tf.transmittance(wl, layers, d, n_inc, n_sub, ang, pol, device=device)
    assert R.shape == (WL.size, len(ANGLES))
    for j, a in enumerate(ANGLES):
        ref_r = _tmm(pol, n_inc, layers, d, n_sub, a, WL, "R")
        np.testing.assert_allclose(R[:, j], ref_r, rtol=0, atol=1e-6)
        # (into an absorbing substrate: the flux just behind the last interface, as in tmm)
        ref_t = _tmm(pol, n_inc, layers, d, n_sub, a, WL, "T")
        np.testing.assert_allclose(T[:, j], ref_t, rtol=0, atol=1e-6)


@pytest.mark.parametrize("name,n_inc,layers,d,n_sub", STACKS[3:5], ids=[s[0] for s in STACKS[3:5]])
def test_amplitudes_match_tmm(device, name, n_inc, layers, d, n_sub):
    """Complex r and t, phases included (tmm uses the same Born & Wolf / Hecht signs)."""
    for a in (0.0, 50.0):
        rs, rp, ts, tp = tf.amplitudes(WL, layers, d, n_inc, n_sub, a, device=device)
        for pol, r, t in (("s", rs, ts), ("p", rp, tp)):
            np.testing.assert_allclose(r, _tmm(pol, n_inc, layers, d, n_sub, a, WL, "r"), rtol=0, atol=1e-6)
            np.testing.assert_allclose(t, _tmm(pol, n_inc, layers, d, n_sub, a, WL, "t"), rtol=0, atol=1e-6)


def test_worst_error_against_tmm_is_tiny(device):
    """The float64 kernel is far inside 1e-6: record the margin (worst |dR| < 1e-12)."""
    name, n_inc, layers, d, n_sub = STACKS[3]
    R = tf.reflectance(WL, layers, d, n_inc, n_sub, 60.0, "p", device=device)
    assert np.abs(R - _tmm("p", n_inc, layers, d, n_sub, 60.0, WL, "R")).max() < 1e-12


def test_from_substrate_matches_reversed_tmm(device):
    layers = [1.46, 2.3 + 0.05j, 1.8]
    d = [110.0, 70.0, 40.0]
    for a in (0.0, 35.0):
        R = tf.reflectance(WL, layers, d, 1.0, 1.52, a, "s", from_substrate=True, device=device)
        ref = _tmm("s", 1.52, layers[::-1], d[::-1], 1.0, a, WL, "R")
        np.testing.assert_allclose(R, ref, atol=1e-6)


def test_energy_conservation_lossless(device):
    rng = np.random.default_rng(1)
    count = 200
    L = 7
    n_layers = rng.uniform(1.2, 2.6, (count, L))
    d = rng.uniform(0.0, 300.0, (count, L))
    wl = rng.uniform(360.0, 830.0, count)
    ang = rng.uniform(0.0, 89.0, count)
    n_sub = rng.uniform(1.0, 2.5, count)
    for side in (False, True):
        for pol in ("s", "p"):
            R = tf.reflectance(wl, n_layers, d, 1.0, n_sub, ang, pol, from_substrate=side, device=device)
            T = tf.transmittance(wl, n_layers, d, 1.0, n_sub, ang, pol, from_substrate=side, device=device)
            # from the substrate side, angles beyond the critical angle give TIR: T = 0, R = 1
            np.testing.assert_allclose(R + T, 1.0, atol=1e-10)
    # reciprocity: T is the same from both sides when the angles correspond by Snell's law
    ang = rng.uniform(0.0, 60.0, count)
    sin_sub = np.sin(np.radians(ang)) / n_sub
    ang_sub = np.degrees(np.arcsin(sin_sub))
    for pol in ("s", "p"):
        Tf = tf.transmittance(wl, n_layers, d, 1.0, n_sub, ang, pol, device=device)
        Tb = tf.transmittance(wl, n_layers, d, 1.0, n_sub, ang_sub, pol, from_substrate=True, device=device)
        np.testing.assert_allclose(Tf, Tb, atol=1e-10)


def _fresnel_closed_form(n1, n2, angle_deg):
    """Hecht's amplitudes for a bare interface (written here independently of the kernels)."""
    n1 = np.asarray(n1, dtype=complex)
    n2 = np.asarray(n2, dtype=complex)
    ci = np.cos(np.radians(angle_deg))
    si = np.sin(np.radians(angle_deg))
    ct = np.sqrt(1 - (n1 * si / n2) ** 2 + 0j)
    ct = np.where((n2 * ct).imag < 0, -ct, ct)
    rs = (n1 * ci - n2 * ct) / (n1 * ci + n2 * ct)
    rp = (n2 * ci - n1 * ct) / (n2 * ci + n1 * ct)
    ts = 2 * n1 * ci / (n1 * ci + n2 * ct)
    tp = 2 * n1 * ci / (n2 * ci + n1 * ct)
    return rs, rp, ts, tp


@pytest.mark.parametrize("n1,n2", [(1.0, 1.5), (1.5, 1.0), (1.0, 2.4 + 0.1j), (2.42, 1.33)])
def test_zero_thickness_film_is_bare_interface(device, n1, n2):
    ang = np.array([0.0, 20.0, 40.0, 41.8, 60.0, 75.0, 89.0])
    ref = _fresnel_closed_form(n1, n2, ang)
    zero_film = tf.amplitudes(550.0, [1.8 + 0.2j], [0.0], n1, n2, ang, device=device)
    no_layer = tf.amplitudes(550.0, [], [], n1, n2, ang, device=device)
    for got0, got1, want in zip(zero_film, no_layer, ref, strict=True):
        np.testing.assert_allclose(got0, want, atol=1e-12)
        np.testing.assert_allclose(got1, want, atol=1e-12)


def test_zero_layer_stack_equals_fresnel(device):
    """Cross-check with the single-interface law ``wo.optics.fresnel(cos_i, n1, n2) -> (rs, rp, ts,
    tp)`` (docs/conventions.md).  Both follow the Born & Wolf / Hecht signs stated in ``thinfilm.py``;
    float32 there, hence 1e-5."""
    ang = np.array([0.0, 20.0, 40.0, 60.0, 75.0, 89.0])
    for n1, n2 in ((1.0, 1.5), (1.5, 1.0), (1.0, 2.4 + 0.1j)):
        want = tf.amplitudes(550.0, [], [], n1, n2, ang, device=device)
        got = wo.optics.fresnel(np.cos(np.radians(ang)), n1, n2, device=device)
        for g, w in zip(got, want, strict=True):
            assert np.iscomplexobj(g) and g.shape == ang.shape
            np.testing.assert_allclose(g, w, atol=1e-5)


def test_black_film_with_phase_change(device):
    """Air | soap | air: R -> 0 as t -> 0, like t^2 (the black film of Smits & Meyer §2)."""
    t = np.array([0.0, 0.1, 1.0, 3.0, 10.0, 30.0])
    R = tf.reflectance(550.0, 1.33 * np.ones((t.size, 1)), t[:, None], 1.0, 1.0, 0.0, device=device)
    assert R[0] == 0.0
    assert np.all(np.diff(R) > 0)
    # thin-layer limit of the characteristic matrix (Born & Wolf 1.6 (33) to first order in
    # k0 t): r = i k0 t (n^2 - 1) / 2, so R ~ (pi t (n^2 - 1) / lambda)^2; corrections O((k0 n t)^2)
    lim = (np.pi * t[1:4] * (1.33**2 - 1) / 550.0) ** 2
    np.testing.assert_allclose(R[1:4], lim, rtol=1e-2)
    # without the phase change (a film on a higher-index substrate) the thin film is not black
    R2 = tf.reflectance(550.0, [1.33], [0.1], 1.0, 1.77, 0.0, device=device)
    assert R2 > 0.05


def test_edge_cases_are_finite(device):
    cases = [
        dict(
            n_layers=[1.5],
            thickness_nm=[1e7],
            n_incident=1.0,
            n_substrate=1.0,
            angle=[0.0, 45.0, 89.99, 90.0],
        ),
        dict(
            n_layers=[1.0],
            thickness_nm=[200.0],
            n_incident=1.5,
            n_substrate=1.0,
            angle=[41.81031489, 60.0, 90.0],
        ),
        dict(n_layers=[1.2 + 1e3j], thickness_nm=[1e6], n_incident=1.0, n_substrate=1.5, angle=[0.0, 70.0]),
        dict(n_layers=[1.0, 1.0], thickness_nm=[0.0, 1e5], n_incident=1.0, n_substrate=1.0, angle=[90.0]),
        dict(n_layers=[], thickness_nm=[], n_incident=1.0, n_substrate=1.0, angle=[90.0]),
        dict(
            n_layers=[1.33],
            thickness_nm=[500.0],
            n_incident=1.33,
            n_substrate=1.0,
            angle=[48.753, 48.7535, 90.0],
        ),
    ]
    for c in cases:
        amps = tf.amplitudes(550.0, **c, device=device)
        for a in amps:
            assert np.all(np.isfinite(a)), c
        for pol in ("s", "p"):
            R = tf.reflectance(550.0, **c, polarization=pol, device=device)
            T = tf.transmittance(550.0, **c, polarization=pol, device=device)
            assert np.all(np.isfinite(R)) and np.all(np.isfinite(T)), c
            assert np.all(R <= 1 + 1e-12) and np.all(R + T <= 1 + 1e-9), c
    # total internal reflection through a film: |r| = 1, T = 0
    R = tf.reflectance(550.0, [1.38], [100.0], 1.5, 1.0, [60.0, 75.0], "s", device=device)
    np.testing.assert_allclose(R, 1.0, atol=1e-12)
    # a thick evanescent gap still tunnels (frustrated TIR) but a thin one tunnels more
    T_thin, T_thick = tf.transmittance(
        550.0, [[1.0], [1.0]], [[50.0], [500.0]], 1.5, 1.5, 60.0, "s", device=device
    )
    assert T_thin > T_thick > 0.0


def test_per_wavelength_layer_indices(device):
    """Layer indices given per wavelength (shape (W, L)) broadcast against the wavelengths."""
    n_of = 1.45 + 3000.0 / WL**2
    R = tf.reflectance(
        WL, np.stack([n_of, np.full_like(WL, 2.1)], -1), [100.0, 60.0], 1.0, 1.52, 30.0, device=device
    )
    ref = [
        tmm.unpolarized_RT([1.0, n, 2.1, 1.52], [np.inf, 100.0, 60.0, np.inf], np.radians(30.0), w)["R"]
        for n, w in zip(n_of, WL, strict=True)
    ]
    np.testing.assert_allclose(R, ref, atol=1e-6)


def test_float32_coating_front_end(device):
    """The renderer's float32 entry point with a dispersive multi-coating stack on the device."""
    grid = np.arange(360.0, 835.0, 5.0)
    n_disp = 1.45 + 4000.0 / grid**2 + 0.0j
    stack = tf.make_coating_stack(
        [
            [(1.38, 100.0)],
            [(n_disp, 80.0), (2.3 + 0.01j, 55.0), (n_disp, 120.0)],
            [],
        ],
        wavelength_start_nm=360.0,
        wavelength_step_nm=5.0,
        device=device,
    )
    wl = np.array([402.5, 550.0, 700.0])
    angles = np.array([0.0, 40.0])
    n_at = np.interp(wl, grid, n_disp.real)  # the stack interpolates its samples linearly too
    for coating, layers, d in (
        (0, [np.full(wl.shape, 1.38 + 0j)], [100.0]),
        (1, [n_at + 0j, np.full(wl.shape, 2.3 + 0.01j), n_at + 0j], [80.0, 55.0, 120.0]),
        (2, [], []),
    ):
        nl = np.stack(layers, -1)[:, None, :] if layers else []
        for back in (False, True):
            got = tf.evaluate_coating(
                stack, coating, wl[:, None], angles[None, :], 1.0, 1.7, from_back=back, device=device
            )
            want = tf.amplitudes(
                wl[:, None], nl, d, 1.0, 1.7, angles[None, :], from_substrate=back, device=device
            )
            for g, w in zip(got, want, strict=True):
                assert g.dtype == np.complex64 and g.shape == (3, 2)
                np.testing.assert_allclose(g, w, atol=2e-5)


# ---------------------------------------------------------------------------------------------
# Smits & Meyer model


def test_smits_meyer_equations(device):
    wl = np.linspace(380.0, 780.0, 9)[:, None]
    tp = np.array([0.0, 50.0, 137.5, 400.0])[None, :]
    np.testing.assert_allclose(
        tf.smits_meyer_film(wl, tp, True, 0.5, device=device),
        (0.5 * np.cos(2 * np.pi * tp / wl + np.pi / 2)) ** 2,
        atol=2e-6,
    )
    np.testing.assert_allclose(
        tf.smits_meyer_film(wl, tp, False, 0.5, device=device),
        (0.5 * np.cos(2 * np.pi * tp / wl)) ** 2,
        atol=2e-6,
    )
    ang = np.array([0.0, 30.0, 60.0, 80.0])
    th = np.radians(ang)
    np.testing.assert_allclose(
        tf.smits_meyer_optical_thickness(300.0, 1.33, ang, device=device),
        300.0 * 1.33 * np.cos(th),
        rtol=1e-6,
    )
    np.testing.assert_allclose(
        tf.smits_meyer_effective_thickness(300.0, 1.53, ang, device=device),
        300.0 * np.sqrt(1.53**2 - np.sin(th) ** 2),
        rtol=1e-6,
    )
    np.testing.assert_allclose(
        tf.smits_meyer_morpho_thickness(150.0, 50.0, 1.53, ang, device=device),
        150.0 * np.cos(th) + 50.0 * np.sqrt(1.53**2 - np.sin(th) ** 2),
        rtol=1e-6,
    )
    t = 226.5
    x = 2 * np.pi * t / wl
    ref = 0.5 * 2.0 * (np.sin(13 * x) / np.sin(x)) ** 2
    np.testing.assert_allclose(
        tf.smits_meyer_multilayer(wl, t, 12, 2.0, device=device), ref, rtol=2e-4, atol=1e-4
    )
    # the limit at sin(2 pi t / lambda) = 0: peak height A0 (l + 1)^2 / 2 at lambda = 2 t / m
    peak = tf.smits_meyer_multilayer(np.array([2 * t, t]), t, 12, 2.0, device=device)
    np.testing.assert_allclose(peak, 169.0, rtol=1e-3)


def test_smits_meyer_two_beam_limit_of_exact(device):
    """For a weakly reflecting film the exact reflectance approaches eq. 7 with K = 2|r|,
    once the phase t' uses the refraction angle (eq. 10), not the viewing angle (eq. 11)."""
    # |r| = 0.024.  The two-beam sum misses the (1 - r^2) factor of the second beam and the
    # multiple reflections, a relative error ~2 r^2 on R <= 4 r^2: |dR| <= ~8 r^4 (3e-6 here)
    n = 1.05
    r = (n - 1) / (n + 1)
    wl = np.linspace(400.0, 700.0, 7)[:, None]
    t = np.array([80.0, 300.0, 900.0])[None, :]
    exact = tf.reflectance(wl, n, t[..., None], 1.0, 1.0, 0.0, device=device)
    model = tf.smits_meyer_film(wl, t * n, True, 2 * r, device=device)
    np.testing.assert_allclose(exact, model, rtol=0, atol=10 * r**4)
    assert np.abs(exact - model).max() > 0.5 * r**4  # and the difference is really there


def test_thickness_fields(device):
    x = np.linspace(-1.0, 1.0, 7)
    y = np.linspace(-0.5, 0.8, 7)
    t = wo.fields.oil_slick_thickness(x, y, k1=3.0, k2=0.0, max_thickness_nm=800.0, device=device)
    np.testing.assert_allclose(t, 800.0 * np.exp(-3.0 * (x**2 + y**2)), rtol=1e-5)  # eq. 12
    tt = wo.fields.oil_slick_thickness(x, y, k1=3.0, k2=0.4, max_thickness_nm=800.0, device=device)
    turb = wo.fields.turbulence_field(x * 4.0, y * 4.0, octaves=6, device=device)
    np.testing.assert_allclose(tt, 800.0 * np.exp(-3.0 * (x**2 + y**2 + 0.4 * turb)), rtol=1e-5)  # eq. 13
    assert np.all(turb >= 0.0) and np.ptp(turb) > 0.0
    s = wo.fields.soap_film_thickness(x, np.abs(y), k2=0.0, max_thickness_nm=500.0, device=device)
    np.testing.assert_allclose(s, 500.0 * np.abs(y), rtol=1e-6)


# ---------------------------------------------------------------------------------------------
# Colour tables


def _xyz_reference(wl, reflect, illuminant="D65"):
    """Independent colour integral: colour-science's CMFs and D65, trapezoid on a 1 nm grid."""
    import colour

    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    shape = colour.SpectralShape(360, 830, 1)
    c = cmfs.copy().align(shape).values
    e = colour.SDS_ILLUMINANTS[illuminant].copy().align(shape).values
    e = e * (c[:, 1].sum() / (e * c[:, 1]).sum())
    num = np.trapezoid(reflect[..., :, None] * (e * 1.0)[:, None] * c, wl, axis=-2)
    return num / np.trapezoid(c[:, 1], wl)


def test_film_table_against_independent_colour(device):
    axis_stop = 600.0
    table = tf.film_color_table(
        phase_change=True,
        model="exact",
        max_optical_thickness_nm=axis_stop,
        count=7,
        step_nm=1.0,
        device=device,
    )
    wl = np.arange(360.0, 831.0)
    R = np.array(
        [
            [tmm.coh_tmm("s", [1.0, 1.33, 1.0], [np.inf, tp / 1.33, np.inf], 0.0, w)["R"] for w in wl]
            for tp in table.axis
        ]
    )
    ref = _xyz_reference(wl, R)
    np.testing.assert_allclose(table.xyz, ref, atol=2e-4)  # float32 accumulation over 471 terms
    sm = tf.film_color_table(
        phase_change=False, max_optical_thickness_nm=axis_stop, count=7, step_nm=1.0, device=device
    )
    rho = (np.cos(2 * np.pi * sm.axis[:, None] / wl[None, :])) ** 2  # eq. 8, K = 1
    np.testing.assert_allclose(sm.xyz, _xyz_reference(wl, rho), atol=2e-4)
    # the RGB table is the Smits–Meyer clip of exposure * XYZ (the foundation's clip wrapper)
    np.testing.assert_allclose(sm.rgb, gamut_clip(sm.xyz * sm.exposure, device=device), atol=1e-6)


def test_table_lookup_equals_direct_evaluation(device):
    table = tf.film_color_table(phase_change=True, max_optical_thickness_nm=800.0, count=801, device=device)
    # at the nodes the lookup is the table
    np.testing.assert_allclose(table.lookup(table.axis, "xyz", device=device), table.xyz, atol=1e-7)
    # between nodes: direct evaluation at those thicknesses (a table whose axis is exactly them)
    rng = np.random.default_rng(3)
    x = np.sort(rng.uniform(0.0, 800.0, 40))
    x[0], x[1] = 0.0, 800.0
    direct = thinfilm_tables._fill_table(  # the same kernel, sampled exactly at x
        thinfilm_tables._table_model(0, wo.device.get_device(device), phase=1.0, K=1.0),
        x,
        "optical_thickness_nm",
        "smits-meyer",
        True,
        "D65",
        5.0,
        table.exposure,
        1.0,
        "",
        device,
    )
    got = table.lookup(x, "xyz", device=device)
    # linear interpolation over 1 nm: |f''| h^2 / 8 with |f''| <= (4 pi / 380 nm)^2 ~ 1.1e-3
    np.testing.assert_allclose(got, direct.xyz, atol=2e-4)
    np.testing.assert_allclose(table.lookup(x, "rgb", device=device), direct.rgb, atol=2e-3)
    # clamped outside the axis
    np.testing.assert_allclose(table.lookup([-5.0, 1e4], device=device), table.rgb[[0, -1]], atol=1e-7)


def test_multilayer_tables(device):
    ex = tf.multilayer_color_table(model="exact", count=4, max_angle=60.0, device=device)
    sm = tf.multilayer_color_table(model="smits-meyer", count=4, max_angle=60.0, device=device)
    assert ex.xyz.shape == sm.xyz.shape == (4, 3)
    assert np.all(np.isfinite(ex.xyz)) and np.all(np.isfinite(sm.xyz))
    # exact table entry at 20 degrees against tmm + the independent colour integral
    idx, thick = tf.morpho_stack()
    assert idx.size == 23 and np.isclose(thick.sum(), 12 * 50.0 + 11 * 150.0)
    wl = np.arange(360.0, 831.0)
    R = tf.reflectance(wl, idx, thick, 1.0, 1.0, 20.0, device=device)
    R_tmm = np.array(
        [
            tmm.unpolarized_RT([1.0, *idx, 1.0], [np.inf, *thick, np.inf], np.radians(20.0), w)["R"]
            for w in wl[::10]
        ]
    )
    np.testing.assert_allclose(R[::10], R_tmm, atol=1e-6)
    one = tf.multilayer_color_table(model="exact", count=2, max_angle=20.0, step_nm=1.0, device=device)
    np.testing.assert_allclose(one.xyz[1], _xyz_reference(wl, R), atol=2e-4)
    # the Morpho blue: at normal incidence the exact stack reflects blue (Z > Y, X)
    assert ex.xyz[0, 2] > ex.xyz[0, 1] and ex.xyz[0, 2] > ex.xyz[0, 0]


def test_input_errors(device):
    with pytest.raises(InputError):
        tf.reflectance(550.0, [1.5 - 0.1j], [10.0], device=device)
    with pytest.raises(InputError):
        tf.reflectance(550.0, [1.5, 1.6], [10.0], device=device)
    with pytest.raises(InputError):
        tf.reflectance(550.0, [1.5], [10.0], angle=95.0, device=device)
    with pytest.raises(InputError):
        tf.reflectance(550.0, [1.5], [-1.0], device=device)
    with pytest.raises(InputError, match="polarization"):
        tf.reflectance(550.0, [1.5], [10.0], polarization="circular", device=device)
    with pytest.raises(InputError):
        tf.film_color_table(model="thin", device=device)
    with pytest.raises(InputError):
        tf.smits_meyer_multilayer(500.0, 200.0, 0, device=device)


# ---------------------------------------------------------------------------------------------
# CLI and scripts (subprocesses, tiny options)


def _run(args, tmp_path):
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run(
        [sys.executable, *args], capture_output=True, text=True, env=env, cwd=tmp_path, timeout=300
    )


def test_cli_table(tmp_path, capsys):
    out = tmp_path / "newton.png"
    p = _run(
        [
            "-m",
            "warpoptics.cli",
            "thinfilm",
            "table",
            "--phase-change",
            "--model",
            "exact",
            "--count",
            "40",
            "-o",
            str(out),
        ],
        tmp_path,
    )
    assert p.returncode == 0, p.stderr
    assert out.stat().st_size > 1000 and "exact table, 40 entries" in p.stdout
    from warpoptics.cli import main

    csv = tmp_path / "t.csv"
    assert main(["thinfilm", "table", "--multilayer", "--count", "5", "-o", str(csv)]) == 0
    data = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert data.shape == (5, 7)
    np.testing.assert_allclose(data[:, 0], np.linspace(0.0, 89.0, 5), rtol=1e-5)
    assert main(["thinfilm", "table", "-o", str(tmp_path / "x.txt")]) == 2
    assert "unsupported output type" in capsys.readouterr().err


@pytest.mark.parametrize(
    "script,extra",
    [
        ("smits_meyer_oil_slick.py", ["--size", "24", "--refraction-angle", "--model", "exact"]),
        ("smits_meyer_soap_film.py", ["--size", "24"]),
        ("smits_meyer_morpho.py", ["--size", "24"]),
        ("smits_meyer_model_vs_exact.py", ["--quick"]),
    ],
)
def test_scripts(tmp_path, script, extra):
    out = tmp_path / "out.png"
    p = _run([str(ROOT / "scripts" / "reproduce" / script), "-o", str(out), *extra], tmp_path)
    assert p.returncode == 0, p.stderr
    assert out.stat().st_size > 200

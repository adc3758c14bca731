"""Fluorescent media as data (materials/fluorescence.py, materials/datasets/fluorescence.py).

Independent references: Gaussian band closed forms written here, scipy's quadrature of the
slab's depth profile, a NumPy Monte-Carlo photon simulation of the slab, histogram checks of the
device's wavelength sampling; physical invariants of the data (unit-area emission, alpha_x <=
alpha, yield <= 1, Stokes shift: energy yield < 1).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate

import warpoptics as wo
from warpoptics.errors import InputError
from warpoptics.materials import fluorescence as F
from warpoptics.materials.spec import material_from_spec
from warpoptics.scene import Scene
from warpoptics.spectra import light_grid

LIBRARY = {"diamond_n3": (415.2, 440.0), "red_spinel": (540.0, 685.5), "uranium_glass": (415.0, 525.0)}


@pytest.mark.parametrize("name", list(LIBRARY))
def test_library_data_invariants(name):
    mat = wo.materials.get(name)
    fl = mat.fluorescence
    assert fl is not None and 0.0 < fl.quantum_yield <= 1.0
    assert fl.source and fl.fit  # provenance and what is a fit are stated
    g = light_grid()
    assert np.trapezoid(fl.emission_pdf(g), g) == pytest.approx(1.0, abs=1e-12)
    # the centre's absorption is part of the material's: alpha_x <= alpha inside its range
    lo, hi = mat.wavelength_range_nm
    inside = g[(g >= lo) & (g <= hi)]
    assert np.all(fl.excitation_alpha(inside) <= mat.alpha(inside) * (1 + 1e-5) + 1e-7)
    # emission peak where the literature puts it (datasets/fluorescence.py), 6 nm: the band fit
    _, em_peak = LIBRARY[name]
    fine = np.arange(380.0, 800.0, 0.25)
    assert abs(fine[np.argmax(fl.emission_pdf(fine))] - em_peak) <= 6.0
    # Stokes shift: at the excitation maximum the energy re-emitted is below the energy absorbed
    lam_x = g[np.argmax(fl.excitation_alpha(g))]
    assert fl.quantum_yield * lam_x / fl.mean_emission_nm() < 1.0
    assert fl.mean_emission_nm() > lam_x


def test_n3_is_excited_by_the_long_wave_lamp_and_emits_blue():
    fl = wo.materials.get("diamond_n3").fluorescence
    ax = fl.excitation_alpha(np.array([365.0, 394.0, 415.2, 450.0, 550.0]))
    assert ax[0] > 0.2 * ax.max() and ax[3] < 1e-3 * ax.max() and ax[4] < 1e-30
    g = light_grid()
    blue = (g >= 400) & (g <= 500)
    assert np.trapezoid(fl.emission_pdf(g) * blue, g) > 0.95
    assert fl.quantum_yield == 0.29  # Thomaz & Davies 1978


def test_device_channels_match_numpy(device):
    """excitation alpha, emission density and yield in the device material table."""
    mat = wo.materials.get("diamond_n3")
    fl = mat.fluorescence
    wl = np.array([241.3, 300.0, 365.0, 394.5, 415.2, 439.9, 500.0, 829.5])
    ax, em, q = F.fluorescence_values(mat, wl, device=device)
    np.testing.assert_allclose(ax, fl.excitation_alpha(wl), rtol=1e-5, atol=1e-9)  # float32 table
    np.testing.assert_allclose(em, fl.emission_pdf(wl), rtol=1e-5, atol=1e-9)
    assert np.all(q == np.float32(0.29))
    # a material without a centre reads zeros
    ax0, em0, q0 = F.fluorescence_values(wo.materials.get("diamond"), wl, device=device)
    assert not ax0.any() and not em0.any() and not q0.any()
    # several materials in one table: each row its own
    table, ids = wo.materials.build_material_table(
        [wo.materials.get("diamond"), wo.materials.get("uranium_glass"), mat], device=device, rgb3=False
    )
    assert table.fl_row.numpy().tolist() == [-1, 0, 1]


def test_device_sampling_follows_the_emission(device):
    """The sampled re-emitted wavelengths have the emission density (histogram over 2 nm bins)
    and each sample's pdf is the density of its 1 nm bin; the same for the excitation."""
    mat = wo.materials.get("uranium_glass")
    fl = mat.fluorescence
    n = 200_000
    u = (np.arange(n) + 0.5) / n  # stratified: the histogram's error is the bins' discreteness
    for excitation, density in ((False, fl.emission_pdf), (True, fl.excitation_alpha)):
        wl, pdf = F.sample_emission_wavelengths(mat, u, excitation=excitation, device=device)
        edges = np.arange(240.0, 831.0, 2.0)
        hist, _ = np.histogram(wl, bins=edges, density=True)
        g = light_grid()
        ref = density(g) / np.trapezoid(density(g), g)
        ref_bins = np.array(
            [np.trapezoid(ref[(g >= a) & (g <= a + 2)], g[(g >= a) & (g <= a + 2)]) / 2 for a in edges[:-1]]
        )
        # piecewise-constant sampling of a piecewise-linear density: bin masses agree exactly,
        # 2e-3 of the peak is float32 CDF round-off and the stratification's edges
        np.testing.assert_allclose(hist, ref_bins, atol=2e-3 * ref_bins.max())
        # pdf of each sample = mass of its 1 nm bin (samples within 1e-3 nm of a bin edge are
        # left out: float32 rounding of the wavelength may put them across the edge)
        x = wl.astype(np.float64) - 240.0
        keep = np.abs(x - np.round(x)) > 1e-3
        j = np.floor(x[keep]).astype(int)
        mass = 0.5 * (ref[j] + ref[j + 1])
        np.testing.assert_allclose(pdf[keep], mass, rtol=2e-3, atol=1e-6)


def _slab_monte_carlo(alpha, alpha_x, q, d, n, seed):
    """Independent photon simulation: exponential free paths in the slab, the absorbing
    species chosen by its share of alpha, emission with probability q."""
    rng = np.random.default_rng(seed)
    depth = rng.exponential(1.0 / alpha, n)
    absorbed = depth < d
    by_centre = absorbed & (rng.random(n) < alpha_x / alpha)
    emitted = by_centre & (rng.random(n) < q)
    return absorbed.mean(), by_centre.mean(), emitted.mean()


@pytest.mark.parametrize(
    "name,wl,d", [("diamond_n3", 394.0, 3.0), ("uranium_glass", 365.0, 5.0), ("red_spinel", 540.0, 2.0)]
)
def test_slab_energy_balance(name, wl, d):
    """Re-emitted photons = yield x photons the centre absorbs, for the library data: the
    closed form against scipy's quadrature of the absorption depth profile and a Monte Carlo."""
    mat = wo.materials.get(name)
    fl = mat.fluorescence
    alpha = float(mat.alpha(wl))
    # red spinel absorbs only through Cr3+: alpha (float32 table) = alpha_x to 1e-7
    ax = min(float(fl.excitation_alpha(wl)), alpha)
    res = F.slab_reemission(fl, alpha, d, wl)
    # depth profile of the centre's absorption: N0 alpha_x exp(-alpha z) on 0 < z < d
    quad, _ = integrate.quad(lambda z: ax * math.exp(-alpha * z), 0.0, d, epsabs=1e-14, epsrel=1e-12)
    assert res["absorbed_by_centre"] == pytest.approx(quad, rel=1e-10)
    assert res["emitted"] == pytest.approx(fl.quantum_yield * quad, rel=1e-10)
    n = 1_000_000
    mc = _slab_monte_carlo(alpha, ax, fl.quantum_yield, d, n, seed=5)
    for got, p in zip(mc, (res["absorbed"], res["absorbed_by_centre"], res["emitted"]), strict=True):
        sigma = math.sqrt(p * (1 - p) / n)
        assert abs(got - p) < 4.5 * sigma  # binomial standard error
    # within 1 % (the tolerance) at this sample size, and never more than absorbed
    assert res["emitted"] <= res["absorbed_by_centre"] <= res["absorbed"] <= 1.0
    assert abs(mc[2] - res["emitted"]) < 0.01 * res["emitted"]


def test_slab_refuses_inconsistent_absorption():
    fl = wo.materials.get("diamond_n3").fluorescence
    with pytest.raises(InputError, match="absorbs more"):
        F.slab_reemission(fl, 1e-6, 1.0, 394.0)


def test_scene_spec_and_sweep_path():
    """Inline fluorescence tables; the yield is a plain scene value a sweep can set."""
    m = material_from_spec(
        {"base": "diamond", "fluorescence": {"centre": "N3", "quantum_yield": 0.5, "strength": 2.0}}
    )
    assert m.fluorescence.quantum_yield == 0.5
    # strength doubles alpha_x, added to diamond's own absorption
    base = wo.materials.get("diamond")
    n3 = wo.materials.get("diamond_n3")
    added = float(n3.alpha(394.0) - base.alpha(394.0))
    assert float(m.alpha(394.0) - base.alpha(394.0)) == pytest.approx(2 * added, rel=1e-4)
    # the library entry's own centre with another yield: the absorption is unchanged
    m2 = material_from_spec({"base": "diamond_n3", "fluorescence": {"quantum_yield": 0.05}})
    assert m2.fluorescence.quantum_yield == 0.05
    assert float(m2.alpha(394.0)) == pytest.approx(float(n3.alpha(394.0)), rel=1e-6)
    # ruby holds the Cr3+ bands already: alpha_x is the weaker wave's alpha, nothing added
    ruby = wo.materials.get("ruby")
    r = material_from_spec(
        {"base": "ruby", "fluorescence": {"centre": "Cr3+ corundum", "add_absorption": False}}
    )
    np.testing.assert_array_equal(r.alpha([556.0]), ruby.alpha([556.0]))
    assert r.fluorescence.excitation_alpha(556.0) == pytest.approx(float(ruby.alpha(556.0).min()), rel=1e-6)
    # sweep axis: object.0.material.fluorescence.quantum_yield
    data = {
        "camera": {"width": 8, "height": 8},
        "object": [
            {
                "shape": "round_brilliant",
                "diameter": 3.0,
                "material": {"base": "diamond_n3", "fluorescence": {"quantum_yield": 0.29}},
            }
        ],
    }
    sc = Scene.from_dict(data).with_overrides({"object.0.material.fluorescence.quantum_yield": 0.9})
    assert material_from_spec(sc.objects[0].material).fluorescence.quantum_yield == pytest.approx(0.9)


@pytest.mark.parametrize(
    "spec,match",
    [
        ({"base": "diamond", "fluorescence": {"centre": "N4"}}, "fluorescence.centre"),
        ({"base": "diamond", "fluorescence": {"centre": "N3", "quantum_yield": 1.5}}, "quantum_yield"),
        (
            {"base": "diamond", "fluorescence": {"centre": "N3", "yield": 0.5}},
            "fluorescence.yield: unknown key",
        ),
        ({"base": "diamond", "fluorescence": 3}, "centre name or a table"),
    ],
)
def test_bad_fluorescence_is_one_line(spec, match):
    with pytest.raises(InputError, match=match):
        material_from_spec(spec)

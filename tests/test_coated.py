"""Coated interfaces, thin shells and film surfaces in the camera tracer (stages/coated.py).

References are independent of the code under test: the bare Fresnel interface
(``optics.fresnel``, what ``trace._isotropic_children`` uses) and a bare render, the ``tmm``
package (Byrnes), the white furnace (energy conservation), closed forms of the thickness
profiles (Smits & Meyer 1990 eq. 12, §4.2), and the thin-film colour table of
``optics.thinfilm`` (a separate kernel integrating the exact stack against the CMFs).

Tolerances: the event runs in float32 around a float64 stack, so reflectances agree with
float64 references to ~1e-6 (2e-6 used); renders use few wavelengths and pixels, and their
tolerances are the stratified-sampling and split-threshold errors stated at each test.
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
from warpoptics.errors import InputError
from warpoptics.stages.coated import FilmConfig, film_event, film_thickness

ROOT = Path(__file__).resolve().parents[1]

ANGLES = np.array([0.0, 20.0, 45.0, 70.0, 85.0])
WAVELENGTHS = np.array([400.0, 480.0, 550.0, 620.0, 700.0])


def _rays(angles_deg, wavelengths, sign=-1.0):
    a, w = np.meshgrid(np.radians(angles_deg), wavelengths, indexing="ij")
    d = np.stack([np.sin(a), np.zeros_like(a), sign * np.cos(a)], axis=-1)
    return a, w, d


def _tmm_R(pol, n_list, d_list, angle_rad, wl):
    return tmm.coh_tmm(pol, n_list, d_list, angle_rad, wl)["R"]


# ---------------------------------------------------------------------------------------------
# The event function
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("inside", [False, True])
def test_zero_thickness_coating_is_the_bare_interface(device, inside):
    """A coated interface whose film has zero thickness reflects and transmits like the bare
    Fresnel interface, in both directions (entering: light from glass is transmitted; leaving:
    from inside, with total internal reflection beyond 41.8 degrees)."""
    n_glass = 1.5
    cfg = FilmConfig(surface="solid", layers=((complex(2.3, 0.0), 0.0),))
    a, w, d = _rays(
        np.array([0.0, 15.0, 30.0, 40.0, 45.0, 60.0, 80.0]),
        np.array([450.0, 600.0]),
        sign=1.0 if inside else -1.0,
    )
    # backward ray d arrives from medium A; the outward normal is +z
    ev = film_event(cfg, d, np.array([0.0, 0.0, 1.0]), w, material={"cauchy": [n_glass]}, device=device)
    n_a, n_b = (n_glass, 1.0) if inside else (1.0, n_glass)
    cos_a = np.cos(a)
    rs, rp, _, _ = wo.optics.fresnel(cos_a, n_a, n_b)
    R = 0.5 * (np.abs(rs) ** 2 + np.abs(rp) ** 2)
    # transmission: light from B with the Snell cosine, power-normalised
    sin_b = n_a / n_b * np.sin(a)
    tir = sin_b >= 1.0
    cos_b = np.sqrt(np.clip(1.0 - sin_b**2, 0.0, 1.0))
    _, _, ts, tp = wo.optics.fresnel(cos_b, n_b, n_a)
    T = np.where(
        tir, 0.0, 0.5 * (np.abs(ts) ** 2 + np.abs(tp) ** 2) * n_a * cos_a / np.maximum(n_b * cos_b, 1e-30)
    )
    count = ev["count"]
    np.testing.assert_array_equal(count, np.where(tir, 1, 2))
    e = ev["energy"]
    R_ev = np.where(count == 2, e[..., 1], e[..., 0])
    T_ev = np.where(count == 2, e[..., 0], 0.0)
    np.testing.assert_allclose(R_ev, R, atol=2e-6)
    np.testing.assert_allclose(T_ev, T, atol=2e-6)
    # refracted direction: Snell
    d_t = ev["direction"][..., 0, :]
    ok = ~tir
    np.testing.assert_allclose(np.hypot(d_t[..., 0], d_t[..., 1])[ok], sin_b[ok], atol=2e-6)


@pytest.mark.parametrize("inside", [False, True])
def test_coated_interface_against_tmm(device, inside):
    """Rs, Rp and T of a two-layer coating on glass, seen from air and from the glass side,
    against tmm; R + T = 1 (a lossless stack), up to total internal reflection."""
    layers = ((complex(2.3, 0.0), 120.0), (complex(1.46, 0.0), 90.0))
    cfg = FilmConfig(surface="solid", layers=layers)
    a, w, d = _rays(np.array([0.0, 30.0, 40.0, 60.0]), WAVELENGTHS, sign=1.0 if inside else -1.0)
    ev = film_event(cfg, d, np.array([0.0, 0.0, 1.0]), w, material={"cauchy": [1.5]}, device=device)
    n_list = [1.0, 2.3, 1.46, 1.5]
    d_list = [np.inf, 120.0, 90.0, np.inf]
    if inside:
        n_list, d_list = n_list[::-1], d_list[::-1]
    jr = ev["jones"][..., -1, :, :]  # reflection is the last child
    count = ev["count"]
    for i in range(a.shape[0]):
        for k in range(a.shape[1]):
            Rs = _tmm_R("s", n_list, d_list, a[i, k], w[i, k])
            Rp = _tmm_R("p", n_list, d_list, a[i, k], w[i, k])
            j = ev["jones"][i, k, count[i, k] - 1]
            # parent frame = the s/p frame of the outgoing wave (basis x = s): diag(rs, rp) up to signs
            assert abs(abs(j[0, 0]) ** 2 - Rs) < 2e-6 and abs(abs(j[1, 1]) ** 2 - Rp) < 2e-6
            assert abs(j[0, 1]) < 1e-6 and abs(j[1, 0]) < 1e-6
            total = ev["energy"][i, k].sum()
            assert abs(total - 1.0) < 2e-6
    assert jr.shape[-2:] == (2, 2)


def test_shell_R_plus_T_and_tmm(device):
    """A soap film shell (air | water-like 1.33, 420 nm | air): R matches tmm (s, p and
    unpolarized) at several angles and wavelengths, R + T = 1, and the transmitted child goes
    straight on."""
    cfg = FilmConfig(surface="shell", layers=((complex(1.33, 0.0), 420.0),))
    a, w, d = _rays(ANGLES, WAVELENGTHS)
    for side in (1.0, -1.0):  # the front and the back of the shell
        ev = film_event(cfg, d, np.array([0.0, 0.0, side]), w, device=device)
        assert np.all(ev["count"] == 2)
        T, R = ev["energy"][..., 0], ev["energy"][..., 1]
        np.testing.assert_allclose(R + T, 1.0, atol=2e-6)
        np.testing.assert_allclose(ev["direction"][..., 0, :], d, atol=1e-6)
        for i in range(a.shape[0]):
            for k in range(a.shape[1]):
                args = ([1.0, 1.33, 1.0], [np.inf, 420.0, np.inf], a[i, k], w[i, k])
                Rs, Rp = _tmm_R("s", *args), _tmm_R("p", *args)
                assert abs(R[i, k] - 0.5 * (Rs + Rp)) < 2e-6
                j = ev["jones"][i, k, 1]
                assert abs(abs(j[0, 0]) ** 2 - Rs) < 2e-6 and abs(abs(j[1, 1]) ** 2 - Rp) < 2e-6


def test_film_surface_absorbs_transmission(device):
    """An opaque film surface (oil on water) has one child, the reflection, with the stack's R
    over the substrate (tmm); roughness 0 keeps it specular."""
    cfg = FilmConfig(surface="film", layers=((complex(1.47, 0.0), 300.0),))
    a, w, d = _rays(ANGLES[:-1], WAVELENGTHS)
    ev = film_event(cfg, d, np.array([0.0, 0.0, 1.0]), w, material={"cauchy": [1.33]}, device=device)
    assert np.all(ev["count"] == 1)
    for i in range(a.shape[0]):
        for k in range(a.shape[1]):
            args = ([1.0, 1.47, 1.33], [np.inf, 300.0, np.inf], a[i, k], w[i, k])
            R = 0.5 * (_tmm_R("s", *args) + _tmm_R("p", *args))
            assert abs(ev["energy"][i, k, 0] - R) < 2e-6
    mirror = d * np.array([1.0, 1.0, -1.0])
    np.testing.assert_allclose(ev["direction"][..., 0, :], mirror, atol=1e-6)


def test_rough_film_surface_is_unbiased_for_a_mirror_like_film(device):
    """With a small GGX roughness the mean reflected energy (microfacet estimator) stays close to
    the smooth one for a near-normal view (Walter et al. 2007: G ~ 1, D normalised); the
    directions spread around the mirror direction."""
    cfg = FilmConfig(surface="film", layers=((complex(1.47, 0.0), 300.0),), roughness=0.05)
    smooth = FilmConfig(surface="film", layers=((complex(1.47, 0.0), 300.0),))
    n = 4000
    d = np.tile(np.array([np.sin(0.3), 0.0, -np.cos(0.3)]), (n, 1))
    w = np.full(n, 550.0)
    ev = film_event(cfg, d, np.array([0.0, 0.0, 1.0]), w, material={"cauchy": [1.33]}, device=device)
    ev0 = film_event(
        smooth, d[:1], np.array([0.0, 0.0, 1.0]), w[:1], material={"cauchy": [1.33]}, device=device
    )
    mean = ev["energy"][:, 0].mean()
    ref = ev0["energy"][0, 0]
    # D-sampled microfacets: the weight G |i.m| / (|i.n| |m.n|) is within a few % of 1 at alpha 0.05
    assert abs(mean / ref - 1.0) < 0.03
    spread = ev["direction"][:, 0, 0].std()
    assert 0.01 < spread < 0.3


def test_thickness_profiles(device):
    """Gravity (Smits & Meyer §4.2) without turbulence is linear in depth below the top; the oil
    drop without turbulence is eq. 12, t_max exp(-k1 (u^2 + v^2))."""
    g = FilmConfig(
        surface="shell",
        layers=((complex(1.33, 0.0), 500.0),),
        profile="gravity",
        profile_params={
            "top_nm": 10.0,
            "bottom_nm": 910.0,
            "noise": 0.0,
            "noise_scale": 2.0,
            "seed": 0,
            "octaves": 3,
        },
    )
    z = np.linspace(-2.0, 2.0, 9)
    p = np.stack([np.zeros_like(z), np.zeros_like(z), z], -1)
    t = film_thickness(g, p, frame=(-2.0, 2.0, 2.0), device=device)
    np.testing.assert_allclose(t, 10.0 + 900.0 * (2.0 - z) / 4.0, rtol=1e-5)
    o = FilmConfig(
        surface="film",
        layers=((complex(1.47, 0.0), 1.0),),
        profile="oil_drop",
        profile_params={"max_nm": 1200.0, "k1": 2.5, "k2": 0.0, "noise_scale": 3.0, "seed": 0, "octaves": 2},
    )
    x = np.linspace(-10.0, 10.0, 11)
    p = np.stack([x, 0.5 * x, np.zeros_like(x)], -1)
    t = film_thickness(o, p, frame=(0.0, 0.0, 10.0), device=device)
    u = x / 10.0
    np.testing.assert_allclose(t, 1200.0 * np.exp(-2.5 * (u**2 + (0.5 * u) ** 2)), rtol=1e-5)
    # turbulence perturbs (k2 > 0) but keeps the thickness finite and non-negative
    o2 = FilmConfig(
        surface="film", layers=o.layers, profile="oil_drop", profile_params={**o.profile_params, "k2": 0.4}
    )
    t2 = film_thickness(o2, p, frame=(0.0, 0.0, 10.0), device=device)
    assert np.all(np.isfinite(t2)) and np.all(t2 >= 0) and not np.allclose(t2, t)


# ---------------------------------------------------------------------------------------------
# Renders
# ---------------------------------------------------------------------------------------------

FURNACE = {
    "camera": {
        "position": [0.0, -30.0, 20.0],
        "look_at": [0.0, 0.0, 0.0],
        "fov": 14.0,
        "width": 16,
        "height": 16,
    },
    "render": {
        "spectral": "stratified",
        "wavelengths": 4,
        "max_depth": 256,
        "split_threshold": 0.002,
        "rr_threshold": 1e-4,
    },
    "light": [{"type": "constant", "intensity": 1.0}],
    "object": [
        {
            "shape": "round_brilliant",
            "diameter": 6.5,
            "material": {"cauchy": [1.62, 0.0043]},
            "coating": [
                {"n": 2.3, "thickness_nm": 160.0},
                {"material": "fused_silica", "thickness_nm": 110.0},
            ],
        }
    ],
}


@pytest.mark.parametrize(
    "polarization, estimator",
    [(True, "point"), (False, "point"), (True, "beam")],
    ids=["point-polarized", "point-scalar", "beam-polarized"],
)
def test_white_furnace_coated_stone(device, polarization, estimator):
    """A non-absorbing coated stone in a constant environment is invisible: Y / Y_empty = 1
    within 1 % in every pixel (the point tracer's splitting cut-offs are unbiased; pixel beams
    roulette parts below 1e-4 of a pixel's light, measured min 0.995, max 1.004)."""
    render = {"polarization": polarization, "estimator": estimator}
    if estimator == "beam":
        render.update(split_threshold=1e-4)
    data = {**FURNACE, "render": {**FURNACE["render"], **render}}
    sc = wo.Scene.from_dict(data)
    img = wo.render(sc, device=device)
    empty = wo.render(sc.with_overrides({"object.0.position": [1e4, 1e4, 1e4]}), device=device)
    assert img.alpha.sum() > 40 and empty.alpha.max() == 0
    ratio = img.xyz[..., 1] / empty.xyz[..., 1]
    print(f"coated furnace polarized={polarization}: min {ratio.min():.6f} max {ratio.max():.6f}")
    assert ratio.min() > 0.99 and ratio.max() < 1.01


def test_zero_thickness_coated_render_equals_bare(device):
    """Renders of a stone with a zero-thickness coating and of the bare stone agree (same
    random streams; the float64 stack equals the float32 Fresnel coefficients to ~1e-7)."""
    data = {
        **FURNACE,
        # one estimator for both: coated stones never take spectral bundles (stages/bundle.py)
        "render": {**FURNACE["render"], "bundle": False},
        "light": [{"type": "environment", "map": "studio"}],
        "object": [{**FURNACE["object"][0], "coating": [{"n": 2.3, "thickness_nm": 0.0}]}],
    }
    coated = wo.render(wo.Scene.from_dict(data), device=device)
    bare_obj = {k: v for k, v in data["object"][0].items() if k != "coating"}
    bare = wo.render(wo.Scene.from_dict({**data, "object": [bare_obj]}), device=device)
    rel = np.abs(coated.xyz - bare.xyz).max() / bare.xyz.max()
    print(f"zero-thickness coating vs bare: max |dXYZ| / max XYZ = {rel:.2e}")
    assert rel < 1e-3
    assert abs(coated.xyz.mean() / bare.xyz.mean() - 1.0) < 1e-4


def test_flat_film_colour_matches_colour_table(device):
    """An oil film (n 1.47, 250 nm) on water seen straight down under a constant white (E)
    environment has the XYZ of the exact thin-film colour table at t' = t n (Smits & Meyer §2.1,
    normal incidence).  64 stratified wavelengths: integration error < 1 % of Y."""
    t_nm = 250.0
    data = {
        "camera": {
            "type": "orthographic",
            "position": [0.0, 0.0, 10.0],
            "look_at": [0.0, 0.0, 0.0],
            "up": [0.0, 1.0, 0.0],
            "view_height": 2.0,
            "width": 4,
            "height": 4,
        },
        "render": {"spectral": "stratified", "wavelengths": 64, "spp": 4, "max_depth": 2},
        "light": [{"type": "constant", "intensity": 1.0}],
        "object": [
            {
                "shape": "wavy_sheet",
                "width": 10.0,
                "length": 10.0,
                "surface": "film",
                "material": {"cauchy": [1.33]},
                "coating": [{"n": 1.47, "thickness_nm": t_nm}],
            }
        ],
    }
    sc = wo.Scene.from_dict(data)
    # non-dispersive materials, but the film's reflectance depends on the wavelength: one path
    # tree per wavelength (not render.py's shared-spectrum shortcut)
    assert wo.pipelines.render.Renderer(sc, device=device).shared_spectrum is False
    img = wo.render(sc, device=device)
    xyz = img.xyz.reshape(-1, 3).mean(axis=0)
    table = wo.thinfilm.film_color_table(
        model="exact",
        n_film=1.47,
        n_front=1.0,
        n_substrate=1.33,
        illuminant="E",
        step_nm=1.0,
        count=301,
        max_optical_thickness_nm=600.0,
        device=device,
    )
    ref = table.lookup(np.array([t_nm * 1.47]), which="xyz", device=device)[0]
    print("render", xyz, "table", ref)
    np.testing.assert_allclose(xyz, ref, atol=0.01 * ref[1] + 1e-4, rtol=0.02)
    # the film is coloured: not the bare water's flat 2 % grey
    assert np.ptp(xyz / xyz.sum()) > 0.05


def test_shell_furnace(device):
    """A non-absorbing soap bubble in a constant environment is invisible (R + T = 1 at every
    hit, the transmitted ray goes on unchanged)."""
    data = {
        "camera": {
            "position": [0.0, -60.0, 0.0],
            "look_at": [0.0, 0.0, 0.0],
            "fov": 30.0,
            "width": 12,
            "height": 12,
        },
        "render": {"spectral": "stratified", "wavelengths": 4, "max_depth": 32},
        "light": [{"type": "constant", "intensity": 1.0}],
        "object": [
            {
                "shape": "sphere",
                "diameter": 20.0,
                "subdivisions": 3,
                "surface": "shell",
                "coating": [{"n": 1.33, "thickness_nm": 500.0}],
                "film_thickness": {"profile": "gravity", "top_nm": 10.0, "bottom_nm": 900.0},
            }
        ],
    }
    sc = wo.Scene.from_dict(data)
    img = wo.render(sc, device=device)
    empty = wo.render(sc.with_overrides({"object.0.position": [1e4, 1e4, 1e4]}), device=device)
    assert img.alpha.sum() > 20 and empty.alpha.max() == 0
    ratio = img.xyz[..., 1] / empty.xyz[..., 1]
    print(f"shell furnace: min {ratio.min():.6f} max {ratio.max():.6f}")
    assert ratio.min() > 0.99 and ratio.max() < 1.01


# ---------------------------------------------------------------------------------------------
# Scene validation, scenes, CLI
# ---------------------------------------------------------------------------------------------


def _bad(tmp_path, obj, field, value=None):
    data = {"object": [{"shape": "round_brilliant", "material": {"cauchy": [1.6]}, **obj}]}
    with pytest.raises(InputError) as exc:
        wo.Scene.from_dict(data, path=str(tmp_path / "bad.toml"))
    e = exc.value
    text = str(e)
    assert e.file.endswith("bad.toml") and "bad.toml" in text
    assert e.field == field and field in text
    if value is not None:
        assert str(value) in text
    return e


def test_bad_coatings_name_file_field_value(tmp_path):
    _bad(tmp_path, {"coating": [{"n": 2.0, "thickness_nm": -5.0}]}, "object.0.coating.0.thickness_nm", -5.0)
    _bad(
        tmp_path,
        {"coating": [{"material": "unobtainium", "thickness_nm": 50.0}]},
        "object.0.coating.0.material",
        "unobtainium",
    )
    _bad(
        tmp_path,
        {"coating": [{"material": "main/TiO2/Nobody", "thickness_nm": 50.0}]},
        "object.0.coating.0.material",
        "main/TiO2/Nobody",
    )
    _bad(tmp_path, {"coating": [{"thickness_nm": 50.0}]}, "object.0.coating.0.material")
    _bad(tmp_path, {"coating": [{"n": 2.0}]}, "object.0.coating.0.thickness_nm")
    _bad(tmp_path, {"surface": "bubble"}, "object.0.surface", "bubble")
    _bad(tmp_path, {"surface": "shell"}, "object.0.coating")
    _bad(
        tmp_path,
        {"coating": [{"n": 2.0, "thickness_nm": 5.0}], "film_thickness": {"profile": "gravity", "top": 3}},
        "object.0.film_thickness.top",
    )
    _bad(
        tmp_path, {"coating": [{"n": 2.0, "thickness_nm": 5.0}], "roughness": 0.1}, "object.0.roughness", 0.1
    )


@pytest.mark.parametrize("material", ["topaz", "topaz_uniaxial", "tanzanite"])
def test_coated_birefringent_stone_is_refused(tmp_path, material):
    """Uniaxial and biaxial stones (topaz is biaxial) are not coated here."""
    data = {
        "object": [
            {"shape": "round_brilliant", "material": material, "coating": [{"n": 2.0, "thickness_nm": 100.0}]}
        ]
    }
    sc = wo.Scene.from_dict(data, path=str(tmp_path / "topaz.toml"))
    with pytest.raises(InputError, match="isotropic"):
        wo.render(sc, width=4, height=4)


@pytest.mark.parametrize("name", ["mystic_topaz", "soap_bubble", "oil_slick", "morpho"])
def test_film_scenes_render(device, name):
    img = wo.render(
        ROOT / "scenes" / f"{name}.toml", device=device, width=12, height=12, wavelengths=4, spp=1
    )
    assert np.isfinite(img.xyz).all() and img.alpha.sum() > 0
    # interference colours: the rendered chromaticities are not all grey
    xyz = img.xyz.reshape(-1, 3)[img.alpha.reshape(-1) > 0]
    chroma = xyz / np.maximum(xyz.sum(axis=1, keepdims=True), 1e-12)
    assert np.ptp(chroma[:, 0]) > 0.02


def test_cli_renders_soap_bubble(tmp_path):
    out = tmp_path / "bubble.png"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "warpoptics.cli",
            "render",
            str(ROOT / "scenes" / "soap_bubble.toml"),
            "-o",
            str(out),
            "--width",
            "8",
            "--height",
            "8",
            "--set",
            "render.wavelengths=4",
            "--set",
            "render.spp=1",
        ],
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
    )
    assert r.returncode == 0, r.stderr
    assert out.is_file() and out.stat().st_size > 0


def test_tilted_film_colour_matches_tmm_colour(device):
    """The same oil film seen at 40 degrees: the rendered XYZ equals the CIE 1931 integral
    (colour-science CMFs, illuminant E, 1 nm) of tmm's unpolarized reflectance at 40 degrees —
    the angle enters only through the exact stack (no t n cos(theta) table approximation)."""
    import colour

    t_nm, theta = 250.0, 40.0
    th = np.radians(theta)
    data = {
        "camera": {
            "type": "orthographic",
            "position": [0.0, -10.0 * np.sin(th), 10.0 * np.cos(th)],
            "look_at": [0.0, 0.0, 0.0],
            "up": [0.0, 0.0, 1.0],
            "view_height": 1.0,
            "width": 4,
            "height": 4,
        },
        "render": {"spectral": "stratified", "wavelengths": 64, "spp": 4, "max_depth": 2},
        "light": [{"type": "constant", "intensity": 1.0}],
        "object": [
            {
                "shape": "wavy_sheet",
                "width": 10.0,
                "length": 10.0,
                "surface": "film",
                "material": {"cauchy": [1.33]},
                "coating": [{"n": 1.47, "thickness_nm": t_nm}],
            }
        ],
    }
    img = wo.render(wo.Scene.from_dict(data), device=device)
    xyz = img.xyz.reshape(-1, 3).mean(axis=0)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    wl = np.arange(360.0, 831.0, 1.0)
    cmf = cmfs.copy().align(colour.SpectralShape(360, 830, 1)).values
    args = ([1.0, 1.47, 1.33], [np.inf, t_nm, np.inf], th)
    R = np.array([0.5 * (_tmm_R("s", *args, w) + _tmm_R("p", *args, w)) for w in wl])
    ref = (R[:, None] * cmf).sum(axis=0) / cmf[:, 1].sum()
    print("render", xyz, "tmm + CMFs", ref)
    np.testing.assert_allclose(xyz, ref, atol=0.01 * ref[1] + 1e-4, rtol=0.02)


def test_open_mesh_file_as_shell(device, tmp_path):
    """A soap film spanning an open mesh read from a file (a disc): accepted as a shell (open
    surfaces need no volume), invisible in the white furnace, coloured under the sky; the same
    file as a solid is refused (not watertight)."""
    import trimesh

    disc = trimesh.creation.annulus(r_min=0.0, r_max=5.0, height=1.0, sections=48)
    top = disc.faces[disc.face_normals[:, 2] > 0.9]
    mesh = trimesh.Trimesh(disc.vertices, top, process=True)
    mesh.remove_unreferenced_vertices()
    path = tmp_path / "disc.ply"
    mesh.export(path)
    obj = {
        "shape": "mesh",
        "path": str(path),
        "surface": "shell",
        "rotation": [80.0, 0.0, 0.0],
        "coating": [{"n": 1.33, "thickness_nm": 300.0}],
    }
    data = {
        "camera": {
            "position": [0.0, -40.0, 0.0],
            "look_at": [0.0, 0.0, 0.0],
            "fov": 20.0,
            "width": 8,
            "height": 8,
        },
        "render": {"spectral": "stratified", "wavelengths": 4, "max_depth": 8},
        "light": [{"type": "constant", "intensity": 1.0}],
        "object": [obj],
    }
    sc = wo.Scene.from_dict(data, path=str(tmp_path / "disc.toml"))
    img = wo.render(sc, device=device)
    empty = wo.render(sc.with_overrides({"object.0.position": [1e4, 1e4, 1e4]}), device=device)
    assert img.alpha.sum() > 10
    ratio = img.xyz[..., 1] / empty.xyz[..., 1]
    assert ratio.min() > 0.99 and ratio.max() < 1.01
    solid = {k: v for k, v in obj.items() if k not in ("surface", "coating")}
    with pytest.raises(InputError, match="watertight"):
        wo.render(
            wo.Scene.from_dict({**data, "object": [solid]}, path=str(tmp_path / "disc.toml")), device=device
        )

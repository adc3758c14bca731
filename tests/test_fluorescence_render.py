"""Fluorescent re-emission in the camera tracer (stages/fluorescence.py, stages/trace.py).

Independent references written here: the photon balance of a slab (``slab_reemission``, the
closed form of materials/fluorescence.py) integrated over the directions of a uniform light
(quadrature in mu, checked against the E_3 exponential-integral closed form of scipy), the
depth profile of the emission (E_2) with the slab's own transmission at the emission
wavelength, and colour-science CIELAB / CIEDE2000 of the renders.  Index-matched slabs
(ambient index = the slab's) make every interface transparent, so the closed forms hold.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy import integrate, special

import warpoptics as wo
from warpoptics.materials import fluorescence as F
from warpoptics.materials.spec import material_from_spec
from warpoptics.pipelines.render import Renderer
from warpoptics.scene import Scene
from warpoptics.spectra import light_grid, light_spectrum, register_spectrum, spectrum_to_xyz

N_HOST = 1.5
EXCITATION_NM = 365.0
THICKNESS = 5.0


def _line(centre_nm: float) -> str:
    """A 2 nm-wide triangular line (monochromatic to the 1 nm light grid), by radiant power."""
    return register_spectrum(
        [centre_nm - 1.0, centre_nm, centre_nm + 1.0], [0.0, 1.0, 0.0], normalize="power"
    )


def _slab_scene(
    material: dict, spectrum: str, *, px: int, spp: int, seed: int = 1, thickness: float = THICKNESS
) -> Scene:
    return Scene.from_dict(
        {
            "camera": {
                "type": "orthographic",
                "position": [0.0, 0.0, 20.0],
                "look_at": [0.0, 0.0, 0.0],
                "up": [0.0, 1.0, 0.0],
                "view_height": 2.0,
                "width": px,
                "height": px,
            },
            "render": {
                "spectral": "stratified",
                "wavelengths": 16,
                "spp": spp,
                "seed": seed,
                "ambient_index": N_HOST,
                "max_depth": 8,
                "tone": "clip",
            },
            "light": [{"type": "constant", "intensity": 1.0, "spectrum": spectrum}],
            "object": [
                {
                    "shape": "plate",
                    "width": 80.0,
                    "length": 80.0,
                    "thickness": thickness,
                    "material": material,
                }
            ],
        }
    )


def _direct_xyz(spectrum: str, mat, d: float) -> np.ndarray:
    """XYZ of the light seen straight through the slab: the line's tail inside the colour range
    (360-366 nm, where zbar is ~1e-3) attenuated by exp(-alpha d)."""
    wl = np.linspace(360.0, 367.0, 701)
    return spectrum_to_xyz(wl, light_spectrum(spectrum, wl) * np.exp(-mat.alpha(wl) * d))


def _mean_and_error(xyz: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Mean XYZ over the pixels and its standard error (pixels are independent samples)."""
    v = xyz.reshape(-1, 3)
    return v.mean(axis=0), v.std(axis=0, ddof=1) / math.sqrt(len(v))


URANYL = {"cauchy": [N_HOST], "fluorescence": {"centre": "uranyl glass"}}


def _normal_exit_per_photon(fl, alpha: float, d: float, wl: float) -> float:
    """Photons leaving the slab along its normal per unit solid angle and unit area, per incident
    photon radiance of a uniform light (both sides), with no absorption at the emission
    wavelengths: (1 / 4 pi) int dw' of the beam balance at incidence mu' (its photons absorbed
    per unit area are mu' x slab_reemission at thickness d / mu'), i.e. int_0^1 mu
    emitted(d / mu) d mu."""
    val, _ = integrate.quad(
        lambda mu: mu * F.slab_reemission(fl, alpha, d / mu, wl)["emitted"], 0.0, 1.0, epsabs=1e-13, limit=200
    )
    return val


def test_slab_closed_forms_agree():
    """The mu quadrature of slab_reemission equals Q alpha_x / alpha (1/2 - E_3(alpha d))."""
    mat = material_from_spec(URANYL)
    fl = mat.fluorescence
    alpha = float(mat.alpha(EXCITATION_NM))
    ax = float(fl.excitation_alpha(EXCITATION_NM))
    got = _normal_exit_per_photon(fl, alpha, THICKNESS, EXCITATION_NM)
    ref = fl.quantum_yield * min(ax / alpha, 1.0) * (0.5 - special.expn(3, alpha * THICKNESS))
    assert got == pytest.approx(ref, rel=1e-7)


def test_slab_reemits_yield_times_absorbed_photons():
    """Energy: an index-matched uranyl slab (alpha d = 1.0 at 365 nm) in a uniform monochromatic
    365 nm light re-emits Q x the photons its centre absorbs: the normal radiance of the render
    (XYZ) against the slab closed form with the emission spectrum and the photon energy ratio
    l_x / l_e, within 1 % (and within 4 standard errors of the render's own noise)."""
    spectrum = _line(EXCITATION_NM)
    mat = material_from_spec(URANYL)
    fl = mat.fluorescence
    # the light's spectral radiance over its line, and the re-emission of each of its wavelengths
    wl_x = np.linspace(EXCITATION_NM - 1.0, EXCITATION_NM + 1.0, 41)  # the line (linear on 1 nm)
    s_x = light_spectrum(spectrum, wl_x)
    g = light_grid()
    # (alpha from the material's k curve and alpha_x from the centre's table agree to 1e-5)
    alphas = [max(float(mat.alpha(w)), float(fl.excitation_alpha(w))) for w in wl_x]
    per_photon = np.array(
        [_normal_exit_per_photon(fl, a, THICKNESS, w) for a, w in zip(alphas, wl_x, strict=True)]
    )
    wl_e = g[g >= 360.0]
    # energy radiance at l_e: photons (per unit energy radiance at l_x: l_x) re-emitted at l_e
    exit_e = np.trapezoid(s_x * per_photon * wl_x, wl_x) * fl.emission_pdf(wl_e) / wl_e
    # re-absorption on the way out is negligible: the centre absorbs < 0.1 % of its emission
    # across the whole slab (its bands lie to the blue of the emission)
    lost = np.trapezoid(fl.emission_pdf(wl_e) * -np.expm1(-mat.alpha(wl_e) * THICKNESS), wl_e)
    assert lost < 1e-3
    ref = spectrum_to_xyz(wl_e, exit_e) + _direct_xyz(spectrum, mat, THICKNESS)
    img = Renderer(_slab_scene(URANYL, spectrum, px=40, spp=32)).run()
    got, err = _mean_and_error(img.xyz)
    assert ref[1] > 0
    np.testing.assert_array_less(err, 0.005 * ref)  # standard error < 0.5 %: a 1 % check is > 2 sigma
    np.testing.assert_allclose(got, ref, rtol=0.01)
    assert np.all(np.abs(got - ref) < 4.0 * err + 1e-12)
    # the light itself is invisible (365 nm) and the slab clear in the visible: all of it is emission
    plain = Renderer(_slab_scene({"cauchy": [N_HOST]}, spectrum, px=4, spp=1)).run()
    assert float(plain.xyz[..., 1].max()) < 1e-3 * ref[1]


def _gauss_legendre(a: float, b: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (b - a) * x + 0.5 * (b + a), 0.5 * (b - a) * w


def test_emission_seen_through_the_stone_has_its_transmission():
    """The spectrum leaving a fluorescent stone that absorbs part of its own emission (a host
    band at 525 nm on the uranyl emission) is the emission shape times the stone's transmission
    from each depth: L(l_e) = Q f_em(l_e) (alpha_x / 2) int_0^d [E_2(alpha z) + E_2(alpha (d - z))]
    exp(-alpha(l_e) z) dz per unit photon radiance of a uniform light (E_2: scipy), l_x / l_e
    for energy -- against the render's XYZ; without the transmission factor the colour would be
    far outside the tolerance."""
    d = 2.0
    spec = {
        "cauchy": [N_HOST],
        "bands": [{"center_nm": 530.0, "width_nm": 20.0, "peak_alpha_per_mm": 0.6}],
        "fluorescence": {"centre": "uranyl glass", "strength": 2.0},
    }
    spectrum = _line(EXCITATION_NM)
    mat = material_from_spec(spec)
    fl = mat.fluorescence
    wl_x = np.linspace(EXCITATION_NM - 1.0, EXCITATION_NM + 1.0, 21)
    s_x = light_spectrum(spectrum, wl_x)
    a_x = np.array([float(mat.alpha(w)) for w in wl_x])
    ax_x = np.minimum(fl.excitation_alpha(wl_x), a_x)
    wl_e = np.arange(400.0, 700.0, 1.0)
    a_e = mat.alpha(wl_e)
    z, wz = _gauss_legendre(0.0, d, 400)
    # depth profile of the centre's absorption per unit photon radiance, for each l_x
    profile = special.expn(2, a_x[:, None] * z[None, :]) + special.expn(2, a_x[:, None] * (d - z)[None, :])
    trans = np.exp(-a_e[:, None] * z[None, :])  # from depth z up to the top face, at l_e
    seen = (profile[:, None, :] * trans[None, :, :]) @ wz  # (l_x, l_e)
    clear = profile @ wz  # the same without the stone's absorption at l_e
    weight_x = s_x * wl_x * ax_x / 2.0  # energy radiance -> photons (l_x), times alpha_x / 2
    dx = np.gradient(wl_x)

    def exit_spectrum(depth_integral):
        per_e = (weight_x * dx) @ depth_integral.reshape(len(wl_x), -1)
        return fl.quantum_yield * fl.emission_pdf(wl_e) * per_e / wl_e

    direct = _direct_xyz(spectrum, mat, d)
    ref = spectrum_to_xyz(wl_e, exit_spectrum(seen)) + direct
    no_transmission = (
        spectrum_to_xyz(wl_e, exit_spectrum(np.repeat(clear[:, None], len(wl_e), axis=1))) + direct
    )
    img = Renderer(_slab_scene(spec, spectrum, px=24, spp=16, thickness=d)).run()
    got, err = _mean_and_error(img.xyz)

    def xy(v):
        return v[:2] / v.sum()

    np.testing.assert_array_less(err, 0.015 * ref)
    np.testing.assert_allclose(got, ref, rtol=0.03)
    assert np.abs(xy(got) - xy(ref)).max() < 0.004
    # the stone's transmission matters far beyond the tolerance
    assert np.abs(xy(no_transmission) - xy(ref)).max() > 0.02
    assert no_transmission[1] > 1.3 * ref[1]


SCENES = Path(__file__).resolve().parents[1] / "scenes" / "fluorescence"
VERY_STRONG = 8.0  # x the library's N3 concentration (the gallery's "very strong")


def _diamond(light: str, quantum_yield: float, *, px: int = 24, spp: int = 2):
    """The gallery's diamond (scenes/fluorescence/diamond_<light>.toml), very strong N3, one
    path tree per wavelength: with the re-emission's own random stream the camera trees are then
    those of the same stone without fluorescence, and a difference of two renders is the emission."""
    sc = Scene.load(SCENES / f"diamond_{light}.toml").with_overrides(
        {
            "object.0.material.fluorescence.strength": VERY_STRONG,
            "object.0.material.fluorescence.quantum_yield": quantum_yield,
        },
        width=px,
        height=px,
        spp=spp,
        wavelengths=16,
    )
    return Renderer(sc, spectral_bundle=False).run()


def test_fluorescent_diamond_differs_only_in_the_blue_and_glows_under_uv():
    """Daylight (D65 dome with its ultraviolet): the strongly fluorescent diamond minus the same
    stone without fluorescence is light of the N3 emission's colour (its chromaticity within
    0.01 of the emission spectrum's, energy units, computed here), i.e. only blue; the mean
    colour moves by a measurable CIEDE2000 toward blue (b* down).  Under the 365 nm lamp the
    render is emission: > 99 % of its luminance and of X + Y + Z."""
    from warpoptics import metrics

    fl = wo.materials.get("diamond_n3").fluorescence
    wl = np.arange(360.0, 831.0)
    em = spectrum_to_xyz(wl, fl.emission_pdf(wl) / wl)  # photons -> energy
    em_xy = em[:2] / em.sum()
    on, off = _diamond("daylight", 0.29), _diamond("daylight", 0.0)
    np.testing.assert_array_equal(on.alpha, off.alpha)
    m_on, m_off = metrics.mean_color(on.xyz, on.alpha), metrics.mean_color(off.xyz, off.alpha)
    diff = np.array([m_on[k] - m_off[k] for k in "XYZ"])
    assert diff[2] > 0.005 * m_off["Z"]  # measurable: > 0.5 % more Z
    np.testing.assert_allclose(diff[:2] / diff.sum(), em_xy, atol=0.01)
    de = metrics.delta_e_mean_color(on.xyz, on.alpha, off.xyz, off.alpha)
    assert de > 0.3
    assert m_on["b"] < m_off["b"] - 0.3
    uv_on, uv_off = _diamond("uv365", 0.29), _diamond("uv365", 0.0)
    s_on, s_off = metrics.mean_color(uv_on.xyz, uv_on.alpha), metrics.mean_color(uv_off.xyz, uv_off.alpha)
    assert s_off["Y"] < 0.01 * s_on["Y"]
    assert sum(s_off[k] for k in "XYZ") < 0.01 * sum(s_on[k] for k in "XYZ")


def test_strength_and_size_sweep_axes_change_the_result():
    """scenes/sweeps/fluorescence_strength.toml: the strength axis sets the centre's alpha_x and
    the size axis the absorption scale; under the 365 nm lamp the glow grows with both."""
    from warpoptics import metrics
    from warpoptics.sweep import Sweep
    from warpoptics.sweep.spec import scene_for

    sw = Sweep.load(Path(__file__).resolve().parents[1] / "scenes" / "sweeps" / "fluorescence_strength.toml")
    jobs = sw.jobs()
    assert len(jobs) == 16
    data, scene_path, _ = sw.scene_source()
    uv = {"light.0.spectrum": "UV365", "camera.width": 12, "camera.height": 12, "render.wavelengths": 8}

    def glow(strength, size):
        job = next(j for j in jobs if j.values["strength"] == strength and j.values["size_mm"] == size)
        sc = scene_for(data, scene_path, {**job.overrides, **uv}, sw.base_dir)
        mat = material_from_spec(sc.objects[0].material)
        assert mat.fluorescence.excitation_alpha(394.0) == pytest.approx(
            strength * wo.materials.get("diamond_n3").fluorescence.excitation_alpha(394.0), rel=1e-6
        )
        assert sc.objects[0].absorption_scale == pytest.approx(size / 6.5)
        img = Renderer(sc).run()
        return metrics.mean_color(img.xyz, img.alpha)["Y"]

    base = glow(1.0, 6.5)
    assert glow(4.0, 6.5) > 1.5 * base
    assert glow(1.0, 1.0) < 0.5 * base


def test_fluorescent_scenes_trace_per_wavelength_and_refuse_birefringent_hosts():
    """Re-emission changes a path's wavelength: no spectral bundles and no shared spectrum for a
    fluorescent stone (yield 0 keeps them); a birefringent fluorescent host is refused."""
    from warpoptics.errors import InputError

    sc = Scene.load(SCENES / "diamond_daylight.toml").with_overrides(width=4, height=4)
    r = Renderer(sc)
    assert r.fluorescence and not r.spectral_bundle and not r.shared_spectrum
    assert r.trace.params.reemission.enabled == 1
    off = Renderer(sc.with_overrides({"object.0.material.fluorescence.quantum_yield": 0.0}))
    assert not off.fluorescence and off.spectral_bundle and off.trace.params.reemission.enabled == 0
    ruby = {"base": "ruby", "fluorescence": {"centre": "Cr3+ corundum", "add_absorption": False}}
    with pytest.raises(InputError, match="isotropic stones only"):
        Renderer(_slab_scene(ruby, "D65", px=4, spp=1))


def test_gallery_script_quick(tmp_path):
    """scripts/reproduce/fluorescence_gallery.py --quick writes its three PNGs and the JSON with
    the emission-dominated UV render and the colour-change numbers."""
    import json
    import subprocess
    import sys

    root = Path(__file__).resolve().parents[1]
    subprocess.run(
        [
            sys.executable,
            str(root / "scripts/reproduce/fluorescence_gallery.py"),
            "--quick",
            "--out-dir",
            str(tmp_path),
        ],
        check=True,
        capture_output=True,
        timeout=600,
    )
    for name in ("diamond", "cube", "colour_change"):
        assert (tmp_path / f"fluorescence_{name}.png").stat().st_size > 1000
    data = json.loads((tmp_path / "fluorescence.json").read_text())
    assert data["diamond"]["uv365"]["very_strong_vs_off"]["emission_share_Y"] > 0.99
    assert data["cube"]["glow"]["Y"] > 0 and data["cube"]["yield_0"]["Y"] == 0
    assert set(data["colour_change"]) == {"alexandrite", "colour_change_garnet"}

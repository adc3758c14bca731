"""Light spectra on every light (spectra.py light table, stages/environment.py, stages/surfaces.py).

References are independent of the code under test: colour-science's illuminant tables and its
``sd_to_XYZ`` integration, the Mallett–Yuksel basis from colour-science, closed forms of the
Gaussian UV line shapes; and two identities of the renderer: a D65 light gives the same bytes as
the default light, and a light with no power inside the colour range renders exactly black.
"""

from __future__ import annotations

import colour
import numpy as np
import pytest

from warpoptics import spectra
from warpoptics.errors import InputError
from warpoptics.pipelines.render import Renderer
from warpoptics.scene import Scene

CMFS = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]


def _xyz(wl, values):
    """colour-science's XYZ with the luminance normalisation (Y of E = 1)."""
    sd = colour.SpectralDistribution(values, wl)
    return colour.sd_to_XYZ(sd, CMFS, k=1.0 / CMFS.values[:, 1].sum(), method="Integration")


@pytest.mark.parametrize("name", ["D50", "D65", "A", "FL2", "FL11", "LED-B3", "LED-V1", "HP1"])
def test_cie_illuminants_match_colour_science(name):
    """Each row's visible part has colour-science's chromaticity (Y = 1 by construction)."""
    wl = spectra.grid()
    ours = spectra.light_spectrum(name, wl)
    assert _xyz(wl, ours)[1] == pytest.approx(1.0, abs=1e-9)
    ref = colour.SDS_ILLUMINANTS[name]
    xy_ref = colour.XYZ_to_xy(colour.sd_to_XYZ(ref, CMFS))
    # colour integrates its own 5 nm table; ours is that table interpolated to 1 nm, 360-830 nm:
    # the two integrations differ by interpolation error, 5e-4 in xy
    np.testing.assert_allclose(colour.XYZ_to_xy(_xyz(wl, ours)), xy_ref, atol=5e-4)


def test_ultraviolet_parts_come_from_the_data():
    """D65 below 360 nm is colour-science's tabulated D65 (scaled like the visible part); FL and
    LED tables start at 380 nm and get no invented ultraviolet; E is flat over the light range."""
    lg = spectra.light_grid()
    assert lg[0] == spectra.LIGHT_MIN_NM == 240.0 and lg[-1] == 830.0
    d65 = spectra.light_spectrum("D65", lg)
    raw = colour.SDS_ILLUMINANTS["D65"]
    scale = d65[lg == 560.0][0] / raw[560.0]
    for w in (300.0, 320.0, 340.0, 355.0):
        assert d65[lg == w][0] == pytest.approx(raw[w] * scale, rel=1e-9)
    assert np.all(d65[lg < 300.0] == 0.0)
    for name in ("FL2", "LED-B1"):
        assert np.all(spectra.light_spectrum(name, lg)[lg < 380.0] == 0.0)
    assert np.all(spectra.light_spectrum("E", lg) == 1.0)
    # inside the colour range the light rows are the colour tables (E, D65, A bit for bit)
    g = spectra.grid()
    for name in ("E", "D65", "A"):
        np.testing.assert_array_equal(spectra.light_spectrum(name, g), spectra.illuminant(name, g))


@pytest.mark.parametrize("name", ["UV365", "UV254"])
def test_uv_lamps(name):
    """Gaussian lines (module docstring) with the radiant power of a Y = 1 D65 over 360-830 nm."""
    centre, fwhm = spectra.UV_LAMPS[name]
    lg = spectra.light_grid()
    s = spectra.light_spectrum(name, lg)
    d65_power = np.trapezoid(spectra.illuminant("D65", spectra.grid()), spectra.grid())
    assert np.trapezoid(s, lg) == pytest.approx(d65_power, rel=1e-12)
    # peak where the line is, half maximum one half-width away (closed form of a Gaussian)
    fine = np.linspace(centre - fwhm, centre + fwhm, 2001)
    v = spectra.light_spectrum(name, fine)
    assert abs(fine[np.argmax(v)] - centre) <= 0.5  # the 1 nm table's resolution
    y = _xyz(spectra.grid(), spectra.light_spectrum(name, spectra.grid()))[1]
    if name == "UV254":
        assert np.all(spectra.light_spectrum(name, spectra.grid()) == 0.0) and y == 0.0
    else:
        # the Gaussian's tail: a few 1e-5 of the luminance of a D65 lamp of the same power
        assert 0.0 < y < 1e-4


def test_device_light_value_matches_numpy(device):
    """light_spectrum_value on the device against the NumPy rows and the colour-science basis."""
    wl = np.array([245.5, 300.0, 330.25, 359.5, 360.0, 420.7, 555.0, 700.0, 829.0])
    basis = colour.recovery.MSDS_BASIS_FUNCTIONS_sRGB_MALLETT2019
    b = np.stack([np.interp(wl, basis.wavelengths, basis.values[:, c]) for c in range(3)], axis=-1)
    rgb = np.array([0.2, 0.5, 0.9])
    for name in ("A", "UV365", "FL2", "LED-V2"):
        ours = spectra.light_values(name, rgb, wl, device=device)
        ref = (b @ rgb) * spectra.light_spectrum(name, wl)
        np.testing.assert_allclose(ours, ref, rtol=2e-5, atol=1e-6 * ref.max())  # float32 tables
    # the default (-1): D65 x basis, with D65's ultraviolet below 360 nm
    ours = spectra.light_values(-1, rgb, wl, device=device)
    ref = (b @ rgb) * spectra.light_spectrum("D65", wl)
    np.testing.assert_allclose(ours, ref, rtol=2e-5, atol=1e-6)


def test_measured_spectrum_registration(tmp_path):
    """A measured spectrum becomes a row (Y = 1), the same data the same row; bad data refused."""
    wl = [380.0, 480.0, 580.0, 680.0, 780.0]
    name = spectra.register_spectrum(wl, [0.2, 1.0, 0.7, 0.3, 0.1])
    assert name == spectra.register_spectrum(wl, [0.4, 2.0, 1.4, 0.6, 0.2])  # scale-free
    g = spectra.grid()
    assert _xyz(g, spectra.light_spectrum(name, g))[1] == pytest.approx(1.0, abs=1e-9)
    with pytest.raises(InputError, match="increase"):
        spectra.register_spectrum([400.0, 400.0], [1.0, 1.0])
    with pytest.raises(InputError, match="no visible light"):
        spectra.register_spectrum([300.0, 340.0], [1.0, 1.0])
    uv = spectra.register_spectrum([300.0, 340.0], [1.0, 1.0], normalize="power")
    assert spectra.light_spectrum(uv, 320.0) > 0
    # the scene schema reads CSV files and inline tables
    csv = tmp_path / "lamp.csv"
    csv.write_text(
        "# wavelength, power\n" + "\n".join(f"{w},{v}" for w, v in zip(wl, [1, 2, 3, 2, 1], strict=True))
    )
    d = _scene()
    d["light"] = [{"type": "environment", "map": "dome", "spectrum": str(csv)}]
    sc = Scene.from_dict(d)
    assert sc.lights[0].spectrum.startswith("measured:")
    d["light"] = [{"type": "area", "spectrum": {"wavelength_nm": wl, "values": [1, 1, 1, 1, 1]}}]
    assert Scene.from_dict(d).lamps[0].spectrum.startswith("measured:")


@pytest.mark.parametrize(
    "spectrum,match",
    [("D66", "unknown value; did you mean 'D65'"), (3, "must be a spectrum name"), ("x.csv", "not found")],
)
def test_bad_spectrum_is_one_line(spectrum, match):
    d = _scene()
    d["light"] = [{"type": "spot", "spectrum": spectrum}]
    with pytest.raises(InputError, match=match) as exc:
        Scene.from_dict(d)
    assert "light.0.spectrum" in str(exc.value) and "\n" not in str(exc.value)


def _scene(width=12, height=12):
    return {
        "camera": {
            "type": "perspective",
            "position": [0.0, -18.0, 14.0],
            "look_at": [0.0, 0.0, 0.5],
            "fov": 25.0,
            "width": width,
            "height": height,
        },
        "render": {"spectral": "stratified", "wavelengths": 8, "spp": 1, "seed": 3, "max_depth": 6},
        "object": [{"shape": "round_brilliant", "diameter": 4.0, "material": "sapphire"}],
        "surface": [{"type": "plane", "height": -1.5, "color": [0.6, 0.6, 0.6]}],
    }


def _render(d, device):
    return Renderer(Scene.from_dict(d), device=device).run()


@pytest.mark.parametrize("env", ["studio", "dome"])
def test_d65_light_is_byte_identical_to_the_default(device, env):
    """Every kind of light with spectrum = "D65" renders the same bytes as with no spectrum
    (the default lights' values are read from the same table entries), and E on a constant
    sky is the default constant sky."""
    lights = [
        {"type": "environment", "map": env, "intensity": 0.5},
        {"type": "area", "center": [0, -4, 8], "normal": [0, 0.4, -1], "size": [4, 4], "radiance": 2.0},
        {"type": "directional", "direction": [0.3, 0.2, -1], "irradiance": 1.5, "tint": [1, 0.8, 0.6]},
        {"type": "spot", "center": [3, -3, 9], "direction": [-0.3, 0.3, -1], "intensity": 40.0},
    ]
    d = _scene()
    d["light"] = lights
    default = _render(d, device)
    assert default.xyz.max() > 0
    d["light"] = [dict(lt, spectrum="D65") for lt in lights]
    explicit = _render(d, device)
    np.testing.assert_array_equal(default.xyz, explicit.xyz)
    np.testing.assert_array_equal(default.stokes, explicit.stokes)
    d["light"] = [{"type": "constant", "intensity": 0.7}]
    a = _render(d, device)
    d["light"] = [{"type": "constant", "intensity": 0.7, "spectrum": "E"}]
    np.testing.assert_array_equal(a.xyz, _render(d, device).xyz)


def test_uv_only_lamp_on_a_non_fluorescent_scene_is_black(device):
    """A short-wave lamp (nothing at or above 360 nm) lights nothing the camera sees: the
    camera's wavelengths are the colour range; the same lamps in daylight light the scene."""
    d = _scene()
    lamps = [
        {"type": "area", "center": [0, -4, 8], "normal": [0, 0.4, -1], "size": [4, 4], "radiance": 5.0},
        {"type": "spot", "center": [3, -3, 9], "direction": [-0.3, 0.3, -1], "intensity": 80.0},
    ]
    d["light"] = [dict(lp, spectrum="UV254") for lp in lamps]
    img = _render(d, device)
    assert np.all(img.xyz == 0.0)
    d["light"] = [dict(lp, spectrum="D65") for lp in lamps]
    assert _render(d, device).xyz[..., 1].mean() > 1e-3


def test_illuminant_a_changes_the_white(device):
    """A dome of illuminant A seen directly has A's chromaticity (colour-science), not D65's."""
    d = _scene(8, 8)
    d["surface"] = []  # the stone is behind the camera, which looks up into the dome
    d["camera"].update(position=[0.0, 0.0, 5.0], look_at=[0.0, 0.0, 10.0], up=[0.0, 1.0, 0.0])
    d["render"].update(wavelengths=64)
    d["light"] = [{"type": "environment", "map": "dome", "spectrum": "A"}]
    xyz = _render(d, device).xyz.reshape(-1, 3).mean(axis=0)
    xy_a = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["A"]
    # 64 jittered strata per pixel, 64 pixels: the chromaticity of the mean within 2e-3
    np.testing.assert_allclose(colour.XYZ_to_xy(xyz), xy_a, atol=2e-3)
    assert xyz[1] == pytest.approx(1.0, rel=0.01)

"""Polarization views (warpoptics.views, optics.polarizer) and the per-channel Stokes film.

References independent of the code under test: Malus's law I cos^2(theta - psi); the
incoherent o/e sum of a birefringent plate between polarizers, sin^2(2 phi)/2 of the light
behind the polarizer (the renderer keeps o and e incoherent, so a thick plate gives the
high-order-white average of sin^2(2 phi) sin^2(delta/2)); Bouguer-Lambert plus normal-incidence
Fresnel transmission of a plate with the §6.1 tourmaline spectra, integrated here with
colour-science's CMFs and D65.
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import warpoptics as wo
from warpoptics.errors import InputError
from warpoptics.film.views import analyzer, apply_view, dichroscope, parse_view, polariscope
from warpoptics.optics.polarizer import analyze, mueller_polarizer, sheet_polarizer_stokes

ROOT = Path(__file__).resolve().parents[1]

# camera under the object looking up (+z) into the dome (upper hemisphere, D65, Y = 1): a light
# table behind the stone, as in a polariscope.  Image right = world -x, image up = world +y.
BASE = {
    "camera": {
        "type": "orthographic",
        "position": [0.0, 0.0, -20.0],
        "look_at": [0.0, 0.0, 0.0],
        "up": [0.0, 1.0, 0.0],
        "view_height": 7.0,
        "width": 24,
        "height": 24,
    },
    "render": {"spectral": "stratified", "wavelengths": 8, "max_depth": 10},
    "light": [{"type": "environment", "map": "dome"}],
}


def scene(obj: dict, *, polarizer=None, width=24, wavelengths=8, **render) -> wo.Scene:
    light = dict(BASE["light"][0])
    if polarizer is not None:
        light["polarizer"] = polarizer
    return wo.Scene.from_dict(
        {
            "camera": {**BASE["camera"], "width": width, "height": width},
            "render": {**BASE["render"], "wavelengths": wavelengths, **render},
            "light": [light],
            "object": [obj],
        }
    )


PLATE = {"shape": "plate", "width": 5.0, "length": 5.0, "thickness": 1.0}
SPHERE = {"shape": "sphere", "diameter": 6.0}
BRILLIANT = {"shape": "round_brilliant", "diameter": 6.0, "rotation": [180.0, 0.0, 0.0]}


# ----------------------------------------------------------------------------------------------
# the polarizer formulas


def test_malus_law(device):
    rng = np.random.default_rng(1)
    psi = rng.uniform(-180, 180, 50)
    theta = rng.uniform(-180, 180, 50)
    intensity = rng.uniform(0.1, 10.0, 50)
    r = np.radians(psi)
    s = intensity[:, None] * np.stack([np.ones(50), np.cos(2 * r), np.sin(2 * r), np.zeros(50)], -1)
    out = analyze(s, theta, device=device)
    # float32 polarizer (angle rounded to float32 radians, ~2e-7 rad at 180 deg) on float64
    # Stokes: absolute error a few 1e-7 of the intensity
    np.testing.assert_allclose(out[:, 0] / intensity, np.cos(np.radians(theta - psi)) ** 2, rtol=0, atol=2e-6)
    # behind the analyzer the light is polarized along it (DOP 1, azimuth theta)
    big = out[:, 0] > 0.1 * intensity
    np.testing.assert_allclose(out[big, 1] / out[big, 0], np.cos(2 * np.radians(theta[big])), atol=1e-4)
    # unpolarized and circular light lose half at any angle
    for s_in in ([1.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 1.0]):
        np.testing.assert_allclose(analyze(np.array(s_in), theta, device=device)[:, 0], 0.5, atol=1e-6)


def test_polarizer_is_a_projector(device):
    m = mueller_polarizer(np.array([0.0, 17.0, 45.0, 90.0, 123.0]), device=device)
    np.testing.assert_allclose(m @ m, m, atol=1e-6)  # a second identical polarizer changes nothing
    crossed = m @ mueller_polarizer(np.array([90.0, 107.0, 135.0, 180.0, 213.0]), device=device)
    np.testing.assert_allclose(crossed, 0.0, atol=1e-6)  # crossed polarizers extinguish


def test_sheet_polarizer_passes_the_field_perpendicular_to_its_absorbing_axis(device):
    rng = np.random.default_rng(2)
    k = rng.normal(size=(64, 3))
    k /= np.linalg.norm(k, axis=1, keepdims=True)
    a = rng.normal(size=(64, 3))
    a /= np.linalg.norm(a, axis=1, keepdims=True)
    bx = np.cross(k, rng.normal(size=(64, 3)))
    bx /= np.linalg.norm(bx, axis=1, keepdims=True)
    s = sheet_polarizer_stokes(a, k, bx, device=device)
    np.testing.assert_allclose(s[:, 0], 0.5, atol=1e-6)  # half of unpolarized light
    np.testing.assert_allclose(np.linalg.norm(s[:, 1:], axis=1), 0.5, atol=1e-5)  # fully polarized
    # an analyzer along the projected absorbing axis extinguishes it
    y = np.cross(k, bx)
    ang = np.degrees(np.arctan2(np.sum(a * y, 1), np.sum(a * bx, 1)))
    np.testing.assert_allclose(analyze(s, ang, device=device)[:, 0], 0.0, atol=1e-6)
    # no polarizer (zero axis): unpolarized, full intensity
    s0 = sheet_polarizer_stokes(np.zeros(3), k, bx, device=device)
    np.testing.assert_allclose(s0, np.tile([1.0, 0.0, 0.0, 0.0], (64, 1)), atol=1e-7)


def test_parse_view():
    assert parse_view("analyzer:30") == ("analyzer", 30.0)
    assert parse_view("polariscope") == ("polariscope", "crossed")
    assert parse_view("polariscope:parallel") == ("polariscope", "parallel")
    assert parse_view("dichroscope") == ("dichroscope", 0.0)
    assert parse_view("dichroscope", 20.0) == ("dichroscope", 20.0)
    assert parse_view("dichroscope:auto") == ("dichroscope", "auto")
    for bad in ("analyzer", "analyser:3", "analyzer:x", "polariscope:sideways", "", "dichroscope:nan"):
        with pytest.raises(InputError):
            parse_view(bad)


# ----------------------------------------------------------------------------------------------
# renders


@pytest.fixture(scope="module")
def calcite_image():
    data = {**BRILLIANT, "material": "calcite", "optic_axis": [0.7071, 0.0, 0.7071]}
    return wo.render(scene(data, wavelengths=6), device="cpu")


def test_per_channel_stokes_film(calcite_image):
    img = calcite_image
    s = img.stokes_xyz
    assert s.shape == (*img.xyz.shape[:2], 3, 4) and s.dtype == np.float64
    np.testing.assert_array_equal(s[..., 1, :], img.stokes)  # the Y row is the classic Stokes image
    np.testing.assert_array_equal(s[..., :, 0], img.xyz)  # S0 of each channel is X, Y, Z
    # physical per channel: S0 >= |S| (float32 per-path Stokes summed in float64: 1e-5 relative)
    pol = np.linalg.norm(s[..., 1:], axis=-1)
    assert np.all(pol <= s[..., 0] * (1 + 1e-5) + 1e-12)
    # the stone polarizes (Fresnel) in every channel
    inside = img.alpha > 0.5
    for c in range(3):
        assert (pol[..., c][inside] / np.maximum(s[..., c, 0][inside], 1e-12)).max() > 0.05


def test_orthogonal_analyzers_sum_to_s0(calcite_image, device):
    for a in (0.0, 30.0, 77.0):
        total = (
            analyzer(calcite_image, a, device=device).xyz
            + analyzer(calcite_image, a + 90.0, device=device).xyz
        )
        np.testing.assert_allclose(total, calcite_image.xyz, rtol=1e-6, atol=1e-9)
    d = dichroscope(calcite_image, 10.0, gap=3, device=device)
    w = calcite_image.xyz.shape[1]
    assert d.xyz.shape[1] == 2 * w + 3
    np.testing.assert_allclose(d.xyz[:, :w] + d.xyz[:, w + 3 :], calcite_image.xyz, rtol=1e-6, atol=1e-9)
    assert np.all(d.xyz[:, w : w + 3] == 0) and np.all(d.alpha[:, w : w + 3] == 0)


def test_empty_field_between_crossed_polarizers_is_black(device):
    # the object is outside the view: the camera sees the polarized dome only
    far = {**PLATE, "material": "bk7", "position": [100.0, 0.0, 0.0]}
    theta = 30.0
    img = wo.render(scene(far, polarizer=theta), device=device)
    assert img.source_polarizer == theta
    par = polariscope(img, parallel=True, device=device).xyz
    crossed = polariscope(img, device=device).xyz
    # the dome is D65 at Y = 1 and the polarizer passes half: Y = 0.5 (up to wavelength sampling)
    assert abs(par[..., 1].mean() - 0.5) < 0.03
    np.testing.assert_allclose(img.xyz, par, rtol=1e-5)  # all of it is polarized along theta
    assert crossed.max() < 1e-6 * par.max()  # extinction (float32 frames)
    # Malus's law through the whole chain (source sheet -> camera frame -> analyzer)
    for phi in (20.0, 45.0, 70.0):
        seen = analyzer(img, theta + phi, device=device).xyz
        np.testing.assert_allclose(seen, par * math.cos(math.radians(phi)) ** 2, rtol=1e-5, atol=1e-7)


@pytest.mark.parametrize("phi", [0.0, 22.5, 45.0])
def test_birefringent_plate_between_crossed_polarizers(device, phi):
    """A 1 mm quartz plate, optic axis in its plane at phi to the polarizer, seen along its normal:
    o and e (incoherent in the renderer, the high-order-white average of a thick plate) each carry
    half of sin^2(2 phi) across the analyzer, so crossed / all = sin^2(2 phi) / 2.  An isotropic
    plate stays black."""
    # image right = world -x: an axis at image angle phi is (-cos phi, sin phi, 0) in the world
    p = math.radians(phi)
    quartz = {**PLATE, "material": "quartz", "optic_axis": [-math.cos(p), math.sin(p), 0.0]}
    img = wo.render(scene(quartz, polarizer=0.0), device=device)
    inside = img.alpha > 0.99
    ratio = polariscope(img, device=device).xyz[..., 1][inside].mean() / img.xyz[..., 1][inside].mean()
    # tolerance: o and e have slightly different Fresnel transmission (n_o 1.544, n_e 1.553 give
    # 0.1 % different T) and the oblique rays of the edge pixels are excluded by alpha > 0.99
    print(
        f"quartz plate phi {phi}: crossed/all {ratio:.5f} (sin^2(2 phi)/2 = {math.sin(2 * p) ** 2 / 2:.5f})"
    )
    assert abs(ratio - math.sin(2 * p) ** 2 / 2) < 0.005, ratio
    glass = wo.render(scene({**PLATE, "material": "bk7"}, polarizer=0.0), device=device)
    g = polariscope(glass, device=device).xyz[..., 1][inside].mean() / glass.xyz[..., 1][inside].mean()
    assert g < 1e-5


def test_crossed_polarizers_isotropic_sphere_dark_birefringent_bright(device):
    """A garnet sphere leaks only by the Fresnel rotation at oblique incidence (the Maltese-cross
    quadrants near the rim: measured crossed/parallel 0.068); a quartz sphere, axis across the
    view at 45 deg to the polarizers, lights up (0.93)."""
    ratios = {}
    for name, mat, axis in (("garnet", "garnet", None), ("quartz", "quartz", [-1.0, 0.0, 0.0])):
        obj = {**SPHERE, "material": mat}
        if axis:
            obj["optic_axis"] = axis
        img = wo.render(scene(obj, polarizer=45.0), device=device)
        inside = img.alpha > 0.99
        crossed = polariscope(img, device=device).xyz[..., 1][inside].mean()
        par = polariscope(img, parallel=True, device=device).xyz[..., 1][inside].mean()
        ratios[name] = crossed / par
    print("crossed/parallel", ratios)
    assert ratios["garnet"] < 0.1
    assert ratios["quartz"] > 0.6
    assert ratios["quartz"] > 8 * ratios["garnet"]


def _plate_reference_xyz(mat, thickness: float, polarization: str) -> np.ndarray:
    """XYZ (Y = 1 for the D65 dome) of a plate seen along its normal, optic axis in the plate:
    e (E along the axis) or o; Bouguer-Lambert with eq. 7 at theta = 90 deg (kappa_e = K_e
    (n_o/n_e)^2), Fresnel at normal incidence with incoherent multiple reflections, times 1/2
    for the analyzer on unpolarized light."""
    import colour

    lam = np.arange(360.0, 831.0, 1.0)
    cmfs = (
        colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
        .copy()
        .align(colour.SpectralShape(360, 830, 1))
        .values
    )
    d65 = colour.SDS_ILLUMINANTS["D65"].copy().align(colour.SpectralShape(360, 830, 1)).values
    n = mat.n(lam)
    a = mat.alpha(lam)
    if polarization == "e":
        nn = n[:, 1]
        kappa = a[:, 1] * (n[:, 0] / n[:, 1]) ** 2
    else:
        nn = n[:, 0]
        kappa = a[:, 0]
    r = ((nn - 1) / (nn + 1)) ** 2
    tau = np.exp(-kappa * thickness)
    t = (1 - r) ** 2 * tau / (1 - r**2 * tau**2)
    xyz = (cmfs * (d65 * t * 0.5)[:, None]).sum(0) / (cmfs[:, 1] * d65).sum()
    return xyz


def test_dichroscope_shows_tourmaline_pleochroism(device):
    """A 4 mm tourmaline plate (Guy & Soler 2004 §6.1 spectra), optic axis across the view (image
    horizontal): the dichroscope's left window (analyzer at 0 deg, along the axis) shows the e
    colour, the right one the o colour, each within dE00 1.5 of the reference integrated here; the
    two windows differ by as much as the references do (measured: e 0.38, o 0.77 from the
    references; windows 27.1 apart, references 27.7)."""
    thickness = 4.0
    obj = {**PLATE, "thickness": thickness, "material": "tourmaline", "optic_axis": [1.0, 0.0, 0.0]}
    img = wo.render(scene(obj, wavelengths=16, max_depth=8), device=device)
    d = dichroscope(img, 0.0, gap=2, device=device)
    w = img.xyz.shape[1]
    inside = img.alpha > 0.99
    left = d.xyz[:, :w][inside].mean(axis=0)
    right = d.xyz[:, w + 2 :][inside].mean(axis=0)
    mat = wo.materials.get("tourmaline")
    ref_e = _plate_reference_xyz(mat, thickness, "e")
    ref_o = _plate_reference_xyz(mat, thickness, "o")
    de = wo.color.delta_e2000
    ref_gap = float(de(ref_e, ref_o))
    print(
        f"tourmaline dichroscope: dE00 e {float(de(left, ref_e)):.2f} o {float(de(right, ref_o)):.2f} "
        f"windows {float(de(left, right)):.2f} reference {ref_gap:.2f}"
    )
    assert ref_gap > 5.0  # the premise: e and o transmit clearly different colours
    assert float(de(left, ref_e)) < 1.5 and float(de(right, ref_o)) < 1.5
    assert float(de(left, right)) > 0.7 * ref_gap


def test_dichroscope_isotropic_stone_halves_match(device):
    """An isotropic garnet sphere on the light table: the oblique Fresnel transmission at its rim
    polarizes partially, nearly independently of wavelength, so the two windows may differ in
    brightness but keep the same chromaticity."""
    img = wo.render(scene({**SPHERE, "material": "garnet"}, wavelengths=8), device=device)
    d = dichroscope(img, 0.0, gap=0, device=device)
    w = img.xyz.shape[1]
    inside = img.alpha > 0.99
    left = d.xyz[:, :w][inside].mean(axis=0)
    right = d.xyz[:, w:][inside].mean(axis=0)

    def xy(v):
        return v[:2] / v.sum()

    assert np.abs(xy(left) - xy(right)).max() < 0.003
    # (measured 0.0008; the tourmaline plate's windows are 27 dE00 apart)
    assert float(wo.color.delta_e2000(left / left[1], right / right[1])) < 1.0


def test_exr_round_trip(calcite_image, tmp_path, device):
    p = calcite_image.save(tmp_path / "calcite.exr")
    back = wo.Image.load(p)
    np.testing.assert_allclose(back.stokes_xyz, calcite_image.stokes_xyz, rtol=1e-6, atol=1e-30)
    np.testing.assert_allclose(back.xyz, calcite_image.xyz, rtol=1e-6)
    assert back.source_polarizer is None
    a = back.view("analyzer:30").xyz
    np.testing.assert_allclose(a, calcite_image.view("analyzer", 30.0).xyz, rtol=1e-5, atol=1e-9)
    # the polarizer angle of a polarized render travels in the header
    img = wo.render(scene({**PLATE, "material": "bk7"}, polarizer=12.5, width=8), device=device)
    q = img.view("polariscope").save(tmp_path / "pol.exr")
    assert wo.Image.load(q).source_polarizer == 12.5


def test_polariscope_needs_polarized_light(calcite_image):
    with pytest.raises(InputError, match="polarized light"):
        calcite_image.view("polariscope")
    with pytest.raises(InputError, match="polarization = true"):
        wo.pipelines.render.Renderer(scene({**PLATE, "material": "bk7"}, polarizer=0.0, polarization=False))
    with pytest.raises(InputError, match="light.0.polarizer"):
        scene({**PLATE, "material": "bk7"}, polarizer="sideways")
    s = scene({**PLATE, "material": "bk7"}, polarizer="none")
    assert s.lights[0].polarizer is None


def test_scene_view_table():
    data = {**BASE, "object": [{**PLATE, "material": "bk7"}], "view": {"kind": "analyzer", "angle": 30.0}}
    assert wo.Scene.from_dict(data).view == "analyzer:30.0"
    s = wo.Scene.from_dict({**data, "view": {"kind": "dichroscope"}})
    assert s.view == "dichroscope:0.0"
    assert s.with_overrides({"view.kind": "none"}).view is None
    with pytest.raises(InputError, match="view.kind"):
        wo.Scene.from_dict({**data, "view": {"kind": "kaleidoscope"}})
    with pytest.raises(InputError, match="view.colour"):
        wo.Scene.from_dict({**data, "view": {"kind": "analyzer", "colour": 1}})


def test_apply_view_none_is_identity(calcite_image):
    assert apply_view(calcite_image, "none") is calcite_image
    assert apply_view(calcite_image, None) is calcite_image


def _cli(*args):
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run(
        [sys.executable, "-m", "warpoptics.cli", *map(str, args)],
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
        check=False,
    )


def test_cli_views(tmp_path):
    sc = ROOT / "scenes" / "tourmaline_polariscope.toml"
    small = ["--width", "12", "--height", "12", "--set", "render.wavelengths=4", "--quiet"]
    # the scene's [view] (crossed polarizers) by default
    r = _cli("render", sc, "-o", tmp_path / "p.exr", *small)
    assert r.returncode == 0, r.stderr
    p = wo.Image.load(tmp_path / "p.exr")
    assert p.source_polarizer == 45.0
    corner = p.xyz[0, 0]  # the empty field, black between crossed polarizers (perspective: < 1e-3)
    assert corner[1] < 1e-3 * 0.5
    r = _cli("render", sc, "-o", tmp_path / "d.exr", "--view", "dichroscope", *small)
    assert r.returncode == 0, r.stderr
    assert wo.Image.load(tmp_path / "d.exr").xyz.shape[1] == 2 * 12 + 2
    # dichroscope:auto: the analyzer along the o-wave's D of the view axis (D perpendicular to the
    # world optic axis and the view axis), written here from the scene's own numbers
    r = _cli("render", sc, "-o", tmp_path / "a.exr", "--view", "dichroscope:auto", *small)
    assert r.returncode == 0, r.stderr
    s = wo.Scene.load(sc)
    c = s.camera
    f = np.subtract(c.look_at, c.position) / np.linalg.norm(np.subtract(c.look_at, c.position))
    right = np.cross(f, c.up) / np.linalg.norm(np.cross(f, c.up))
    up = np.cross(right, f)
    ob = s.objects[0]
    axis = ob.rotation_matrix() @ np.asarray(ob.optic_axis or wo.materials.get(ob.material).optic_axis)
    d = np.cross(axis, f)
    want = math.degrees(math.atan2(d @ up, d @ right)) % 180.0
    line = next(ln for ln in r.stdout.splitlines() if ln.startswith("dichroscope:auto ->"))
    assert float(line.split()[2]) == pytest.approx(want, abs=0.01)
    r = _cli(
        "render",
        sc,
        "-o",
        tmp_path / "x.png",
        "--view",
        "polariscope",
        "--set",
        'light.0.polarizer="none"',
        *small,
    )
    assert r.returncode == 2 and "polarized light" in r.stderr


def test_eigenwave_angle_biaxial_oblique(device):
    """eigenwave_angle of a biaxial stone viewed obliquely to its principal axes: the fast wave's
    D from an independent eigen-solution (the section of the impermeability tensor eps^-1 by the
    plane perpendicular to the wave normal, numpy.linalg.eigh; fast = the larger eigenvalue
    1/n^2), projected on the image.  Tolerance 0.01°: the kernel's D is float32."""
    rng = np.random.default_rng(7)
    tz = wo.materials.get("iolite")
    right, up = np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
    fwd = np.cross(up, right)  # right = fwd x up
    for _ in range(5):
        q, _r = np.linalg.qr(rng.normal(size=(3, 3)))
        axes = q.T * np.sign(np.linalg.det(q))  # rows X, Y, Z, right-handed
        mat = tz.with_crystal_axes(axes)
        got = wo.film.views.eigenwave_angle(mat, fwd, right, up, wavelength_nm=550.0, device=device)
        n = tz.n(550.0).astype(np.float64)
        inv_eps = axes.T @ np.diag(n**-2.0) @ axes  # world frame
        basis = np.stack([right, up])  # the plane perpendicular to fwd
        w, v = np.linalg.eigh(basis @ inv_eps @ basis.T)
        d = v[:, np.argmax(w)]
        want = math.degrees(math.atan2(d[1], d[0])) % 180.0
        diff = (got - want + 90.0) % 180.0 - 90.0
        assert abs(diff) < 0.01, (got, want)


def test_dichroscope_auto_needs_the_scene(calcite_image):
    with pytest.raises(InputError, match="dichroscope:auto needs the stone"):
        apply_view(calcite_image, "dichroscope:auto")

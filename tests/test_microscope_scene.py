"""Polarizing-microscope scenes (scene/microscope.py, pipelines.microscope.microscope_view,
``warpoptics microscope``): validation, thin-section grains against a single plate and against
the closed form, the stage rotation, the scene files and the command.

The independent reference for a grain (uniaxial, 30 um, in Canada balsam, light along the
microscope axis z between crossed polarizers): its o wave vibrates normal to the plane of the
optic axis a and z, its e wave along the projection of a on the section, at azimuth psi; the
e index for the wave normal z at angle theta from a is the index ellipsoid's
n_e(theta) = (cos^2 theta / n_o^2 + sin^2 theta / n_e^2)^(-1/2) (Born & Wolf §15.3), so
Delta(lambda) = d (n_e(theta) - n_o) and the transmission is sin^2(2 (psi - polarizer))
sin^2(pi Delta / lambda) (Born & Wolf §15.4.1).  The faces' Fresnel losses against a mounting
index 1.54 are below 1e-4 (R = ((n - 1.54) / (n + 1.54))^2 <= 1e-5 per face) and are left out.
Colours: colour-science's CIE 1931 2 degree CMFs and D65 at 1 nm, normalised so that D65 itself
has Y = 1 (the microscope's parallel polarizers without a sample).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import warpoptics as wo
from warpoptics.errors import InputError
from warpoptics.pipelines import microscope as ms
from warpoptics.scene.microscope import MicroscopeScene

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "scenes" / "microscope"


def _section(**mic) -> MicroscopeScene:
    return MicroscopeScene.from_dict(
        {
            "microscope": {"size": 32, "mounting_index": 1.54, **mic},
            "sample": {"kind": "thin_section", "material": "quartz", "grains": 6, "seed": 3},
        }
    )


@pytest.mark.parametrize(
    "data,field,text",
    [
        (
            {"microscope": {"stage_rotaton": 10.0}},
            "microscope.stage_rotaton",
            "did you mean 'stage_rotation'",
        ),
        ({"microscope": {"mode": "conoscopy"}}, "microscope.mode", "did you mean 'conoscopic'"),
        ({"microscope": {"accessory": "gypsum"}}, "microscope.accessory", "first_order_red"),
        ({"microscope": {"size": 2}}, "microscope.size", "out of range"),
        ({"microscope": {"analyzer": "off"}}, "microscope.analyzer", "must be a number"),
        ({"sample": {"kind": "thin_section", "material": "quartz", "grain": 5}}, "sample.grain", "grains"),
        ({"sample": {"material": "quartz"}}, "sample.thickness_mm", "missing key"),
        ({"sample": {"material": "quarts", "thickness_mm": 0.03}}, "sample.material", "quartz"),
        (
            {"sample": {"material": "topaz", "thickness_mm": 1.0, "optic_axis": [0, 0, 1]}},
            "sample.optic_axis",
            "crystal_axes",
        ),
        (
            {"microscope": {"mode": "conoscopic"}, "sample": {"kind": "thin_section", "material": "quartz"}},
            "sample.kind",
            "one crystal",
        ),
        (
            {"microscope": {"mode": "conoscopic", "accessory": "quartz_wedge"}},
            "microscope.accessory",
            "orthoscopic",
        ),
        ({"microscope": {}, "sample": {}, "camera": {}}, "camera", "unknown key"),
    ],
)
def test_validation_errors_name_file_field_value(data, field, text):
    full = {"microscope": {}, "sample": {"material": "calcite", "thickness_mm": 0.03}, **data}
    with pytest.raises(InputError) as exc:
        MicroscopeScene.from_dict(full, path="scope.toml")
    msg = str(exc.value)
    assert msg.startswith(f"scope.toml: {field}"), msg
    assert text in msg, msg
    assert "\n" not in msg


def _colour_science_xyz(transmission_of_lambda) -> np.ndarray:
    colour = pytest.importorskip("colour")
    shape = colour.SpectralShape(360, 830, 1)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(shape)
    d65 = colour.SDS_ILLUMINANTS["D65"].copy().align(shape)
    lam = cmfs.wavelengths
    t = transmission_of_lambda(lam)  # (..., L)
    w = d65.values[None, :, None] * cmfs.values[None, :, :]
    return (t[..., :, None] * w).sum(axis=-2) / (d65.values * cmfs.values[:, 1]).sum()


def test_thin_section_grain_colours(device):
    """Each grain's colour is the interference colour of one plate with that grain's orientation
    (the same code path: equal to 1e-12), and every grain's XYZ is the closed form of the module
    docstring integrated with colour-science (measured: largest |dXYZ| 9.8e-5, dE00 0.006;
    bounds 1e-3 and 0.2 for the code's 5 nm colour grid against 1 nm here)."""
    colour = pytest.importorskip("colour")
    sc = _section()
    view = ms.microscope_view(sc, device=device)
    assert view.srgb.shape == (32, 32, 3) and view.grain.shape == (32, 32)
    quartz = wo.materials.get("quartz")
    for k in np.unique(view.grain):
        ref = ms.interference_colour(
            quartz, 0.03, optic_axis=tuple(view.orientations[k]), n_ambient=1.54, device=device
        )
        np.testing.assert_allclose(view.grain_xyz[k], ref.xyz, rtol=0, atol=1e-12)
        np.testing.assert_allclose(
            view.xyz[view.grain == k], np.broadcast_to(ref.xyz, (int((view.grain == k).sum()), 3))
        )
    a = view.orientations
    cos_t = np.abs(a[:, 2])
    psi = np.arctan2(a[:, 1], a[:, 0])

    def transmission(lam):
        n = quartz.n(lam)
        no, ne = n[:, 0], n[:, 1]
        ne_t = 1.0 / np.sqrt(cos_t[:, None] ** 2 / no**2 + (1.0 - cos_t[:, None] ** 2) / ne**2)
        delta = 0.03e6 * (ne_t - no)
        return np.sin(2.0 * psi)[:, None] ** 2 * np.sin(np.pi * delta / lam) ** 2

    ref = _colour_science_xyz(transmission)
    white = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]
    de = colour.delta_E(
        colour.XYZ_to_Lab(view.grain_xyz, white), colour.XYZ_to_Lab(ref, white), method="CIE 2000"
    )
    err = np.abs(view.grain_xyz - ref).max()
    print(f"grains vs closed form: max |dXYZ| {err:.2e}, max dE00 {de.max():.3f}; Y {np.round(ref[:, 1], 4)}")
    assert err < 1e-3
    assert de.max() < 0.2


def test_stage_rotation_extinction_to_brightest(device):
    """A grain goes extinct when the projection of its optic axis on the section lies along the
    polarizer (sin^2(2 phi) = 0, whatever its tilt) and is brightest 45 degrees from there.  The
    grain with the axis nearest the section plane: stage at -psi (extinct), then -psi + 15 ...
    + 90 degrees; its Y must peak at +45 and vanish at 0 and 90 (below 1e-6 of the peak; float32
    Jones matrices)."""
    base = ms.microscope_view(_section(), device=device)
    k = int(np.argmin(np.abs(base.orientations[:, 2])))
    a = base.orientations[k]
    psi = math.degrees(math.atan2(a[1], a[0]))
    steps = np.arange(0.0, 91.0, 15.0)
    ys = np.array(
        [ms.microscope_view(_section(stage_rotation=-psi + s), device=device).grain_xyz[k, 1] for s in steps]
    )
    print(f"grain {k} (axis tilt {math.degrees(math.acos(abs(a[2]))):.1f} deg from z): Y {np.round(ys, 5)}")
    assert steps[int(np.argmax(ys))] == 45.0
    assert ys[0] < 1e-6 * ys.max() and ys[-1] < 1e-6 * ys.max()
    # sin^2(2 phi) between: 15 degrees -> 1/4 of the peak, 30 -> 3/4
    np.testing.assert_allclose(ys[1:3] / ys[3], [0.25, 0.75], atol=1e-4)


def test_stage_rotation_turns_the_grain_map():
    """Turning the stage by 90 degrees turns the image counter-clockwise by 90 degrees."""
    g0, _ = ms.voronoi_grains(12, 5, 40, 2.0, 0.0)
    g90, _ = ms.voronoi_grains(12, 5, 40, 2.0, 90.0)
    assert np.mean(np.rot90(g0) == g90) > 0.99  # ties at cell edges may differ by float round-off


def test_random_orientations_are_uniform_on_the_sphere():
    """Z of random_crystal_axes uniform on the sphere: |z| uniform on [0, 1] (Archimedes), the
    frames orthonormal and right-handed."""
    ax = ms.random_crystal_axes(4000, 7)
    np.testing.assert_allclose(
        np.einsum("nij,nkj->nik", ax, ax), np.broadcast_to(np.eye(3), (4000, 3, 3)), atol=1e-12
    )
    assert np.all(np.linalg.det(ax) > 0.999)
    hist, _ = np.histogram(np.abs(ax[:, 2, 2]), bins=10, range=(0.0, 1.0))
    assert np.all(np.abs(hist - 400) < 4 * math.sqrt(400))


def test_quartz_wedge_ramp_is_michel_levy_with_the_plate_added(device):
    """scenes/microscope/quartz_wedge.toml with the plate parallel (addition) and turned 90
    degrees (subtraction): at a column the wedge's Gamma and the plate's Delta add or subtract,
    so the subtraction image is darkest (the compensation band) where Gamma = Delta, within the
    ramp's strip width (2000 / 128 nm) and the plate's dispersion against the ideal wedge."""
    import dataclasses

    sc = MicroscopeScene.load(SCENES / "quartz_wedge.toml")
    small = dataclasses.replace(sc.microscope, size=128)
    sub = ms.microscope_view(
        dataclasses.replace(sc, microscope=dataclasses.replace(small, stage_rotation=90.0)), device=device
    )
    y = sub.xyz[0, :, 1]
    delta = ms.plate_retardation(sc.sample.material, 0.03, optic_axis=sc.sample.optic_axis)
    gamma = (np.arange(128) + 0.5) / 128 * 2000.0
    j = int(np.argmin(y))
    print(f"compensation band at {gamma[j]:.0f} nm, plate retardation {delta:.0f} nm, Y there {y[j]:.2e}")
    assert abs(gamma[j] - delta) < 2000.0 / 128 + 5.0  # dispersion of quartz vs the ideal wedge
    assert y[j] < 0.02 * y.max()


@pytest.mark.parametrize(
    "name",
    ["quartz_thin_section", "calcite_thin_section", "calcite_conoscope", "topaz_conoscope", "quartz_wedge"],
)
def test_scene_files_load(name):
    sc = MicroscopeScene.load(SCENES / f"{name}.toml")
    assert sc.sample.material is not None


def test_command_writes_image_and_refuses_bad_scene(tmp_path, capsys):
    """``warpoptics microscope`` (in-process: cli.main, as the subprocess tests of test_cli.py
    run it, without a second interpreter start): an image of the asked size; a misspelt key is
    one line on stderr with the suggestion, exit status 2."""
    from warpoptics.cli import main
    from warpoptics.film.image import read_image

    out = tmp_path / "fig.png"
    assert main(["microscope", str(SCENES / "calcite_conoscope.toml"), "-o", str(out), "--size", "24"]) == 0
    img, _ = read_image(out)
    assert img.shape[:2] == (24, 24)
    bad = tmp_path / "bad.toml"
    bad.write_text(
        '[microscope]\nmode = "orthoscopic"\nanalyser = 90\n'
        '[sample]\nmaterial = "quartz"\nthickness_mm = 0.03\n'
    )
    capsys.readouterr()
    assert main(["microscope", str(bad), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "microscope.analyser" in err and "did you mean 'analyzer'" in err


def test_optical_activity_key_reaches_the_plate(device):
    """``optical_activity = "right"`` on a quartz basal plate (the other helper's coupled-wave
    plate, pipelines.microscope.resolve_activity): at the centre of the conoscopic figure (light
    along the optic axis, no birefringence) crossed polarizers pass sin^2(rho d) of the light
    with the rotation, nothing without it (the cross's centre); refused for calcite (no data).
    Reference: rho = 21.72 deg/mm at 589.3 nm (the widely quoted value for quartz along its axis
    in sodium light, e.g. Hecht, Optics, on optical activity), times the two faces' Fresnel
    transmission (1 - R)^2 at normal incidence, R = ((n_o - 1) / (n_o + 1))^2; tolerance 0.005
    for the rotatory-dispersion fit of the material data (~0.1 deg/mm)."""
    data = {
        "microscope": {"mode": "conoscopic", "wavelength": 589.3, "size": 17},
        "sample": {"material": "quartz", "thickness_mm": 3.0, "optic_axis": [0.0, 0.0, 1.0]},
    }
    plain = ms.microscope_view(MicroscopeScene.from_dict(data), device=device).xyz[8, 8, 1]
    data["sample"]["optical_activity"] = "right"
    active = ms.microscope_view(MicroscopeScene.from_dict(data), device=device).xyz[8, 8, 1]
    print(f"quartz basal plate centre: {plain:.2e} without, {active:.3f} with optical activity")
    assert plain < 1e-4
    n_o = float(wo.materials.get("quartz").n(589.3)[0])
    t_faces = (1.0 - ((n_o - 1.0) / (n_o + 1.0)) ** 2) ** 2
    ref = t_faces * math.sin(math.radians(21.72 * 3.0)) ** 2
    assert abs(active - ref) < 0.005, (active, ref)
    data["sample"]["material"] = "calcite"
    with pytest.raises(InputError, match="sample.optical_activity"):
        MicroscopeScene.from_dict(data, path="a.toml")

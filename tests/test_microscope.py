"""The polarizing microscope (pipelines/microscope.py, commands/chart.py): Michel-Lévy colours,
interference-colour readout, the uniaxial conoscopic figure.

References independent of the code under test:
- Michel-Lévy: colour-science's CIE 1931 2 degree CMFs and D65 at 1 nm times the closed form
  I = sin^2(pi Delta / lambda) of a plate at 45 degrees between crossed polarizers, CIELAB and
  CIEDE2000 from colour-science (no warpoptics colour code);
- conoscope: the analytic isochromes of a plate of thickness d cut across the optic axis, the
  retardation of direction theta being Delta(theta) = d (q_o - q_e) with
  q_o = sqrt(n_o^2 - sin^2 theta), q_e = (n_o / n_e) sqrt(n_e^2 - sin^2 theta) (the normal
  wave-vector components of the two waves; Born & Wolf §15.4.2); the k-th dark ring at
  Delta = k lambda, solved here with scipy's brentq.
"""

from __future__ import annotations

import numpy as np
import pytest

import warpoptics as wo
from warpoptics.errors import InputError
from warpoptics.pipelines import microscope as ms


def _colour_science_xyz(retardation_nm):
    colour = pytest.importorskip("colour")
    cmfs = (
        colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
        .copy()
        .align(colour.SpectralShape(360, 830, 1))
    )
    d65 = colour.SDS_ILLUMINANTS["D65"].copy().align(colour.SpectralShape(360, 830, 1))
    lam = cmfs.wavelengths
    cmf = cmfs.values
    s = d65.values
    t = np.sin(np.pi * np.asarray(retardation_nm)[:, None] / lam[None, :]) ** 2
    xyz = (t * s)[:, :, None] * cmf[None, :, :]
    return xyz.sum(axis=1) / (s * cmf[:, 1]).sum()


def test_michel_levy_colours_match_colour_science(device):
    colour = pytest.importorskip("colour")
    chart = ms.michel_levy_chart(max_retardation_nm=1500.0, columns=151, device=device)
    ref = _colour_science_xyz(chart.retardation_nm)
    white = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]
    de = colour.delta_E(colour.XYZ_to_Lab(chart.xyz, white), colour.XYZ_to_Lab(ref, white), method="CIE 2000")
    assert np.max(de) < 1.0, (float(np.max(de)), chart.retardation_nm[int(np.argmax(de))])
    # and the display colours are the chart's own clipped XYZ, in range
    assert chart.srgb.shape == (151, 3) and np.all((chart.srgb >= 0) & (chart.srgb <= 1))


def test_first_order_sequence_is_michel_levy(device):
    # hue landmarks of the chart: grey/white (~200 nm), the sensitive tint (first-order red /
    # violet, ~550 nm: the least luminous colour after black) and second-order blue (~650 nm)
    chart = ms.michel_levy_chart(max_retardation_nm=800.0, columns=161, device=device)
    y = chart.xyz[:, 1]
    ret = chart.retardation_nm
    first_min = ret[20 + int(np.argmin(y[20:]))]  # skip the black at 0
    assert 520.0 <= first_min <= 580.0
    blue = chart.xyz[np.argmin(abs(ret - 650.0))]
    assert blue[2] > blue[0]


def test_interference_colour_readout(device):
    quartz = wo.materials.get("quartz")
    ic = ms.interference_colour(quartz, 0.030, device=device)
    n = quartz.n(550.0)
    assert ic.retardation_nm == pytest.approx(30e3 * abs(n[1] - n[0]), rel=1e-5)
    # the transmission is the quartz plate's own (dispersion, Fresnel losses in air) formula
    nl = quartz.n(ic.wavelength_nm)
    t_o = 4 * nl[:, 0] / (1 + nl[:, 0]) ** 2
    t_e = 4 * nl[:, 1] / (1 + nl[:, 1]) ** 2
    delta = 2 * np.pi * 0.030e6 * (nl[:, 1] - nl[:, 0]) / ic.wavelength_nm
    ref = 0.25 * np.abs(t_e * np.exp(1j * delta) - t_o) ** 2
    assert np.max(np.abs(ic.transmission - ref)) < 1e-4
    # an extinction position: optic axis along the polarizer
    dark = ms.interference_colour(quartz, 0.030, optic_axis=(1.0, 0.0, 0.0), device=device)
    assert float(np.max(dark.transmission)) < 1e-8
    # a biaxial section normal to Z: retardation d (n_beta - n_alpha)
    tz = wo.materials.get("tanzanite")
    ib = ms.interference_colour(tz, 0.030, device=device)
    n3 = tz.n(550.0)
    assert ib.retardation_nm == pytest.approx(30e3 * (n3[1] - n3[0]), rel=1e-3)
    assert ib.xyz[1] > 0.01


def _analytic_rings(no, ne, d_mm, lam, na, count):
    from scipy.optimize import brentq

    def delta(s):
        return d_mm * 1e6 * (np.sqrt(no**2 - s**2) - no / ne * np.sqrt(ne**2 - s**2))

    return np.array([brentq(lambda s, k=k: delta(s) - k * lam, 1e-9, na) / na for k in range(1, count + 1)])


def _minima(r, i):
    """Sub-sample positions of the dark rings: local minima below 5 % of the peak, after the
    profile first rises above half of it (the centre is dark too), refined by a parabola."""
    start = int(np.argmax(i > 0.5 * i.max()))
    out = []
    for j in range(max(start, 1), r.size - 1):
        if i[j] < i[j - 1] and i[j] <= i[j + 1] and i[j] < 0.05 * i.max():
            y0, y1, y2 = i[j - 1], i[j], i[j + 1]
            out.append(r[j] + 0.5 * (r[1] - r[0]) * (y0 - y2) / (y0 - 2 * y1 + y2))
    return np.array(out)


@pytest.mark.parametrize("azimuth", [45.0, 135.0, 200.0])
def test_uniaxial_isochromes_match_analytic_radii(device, azimuth):
    calcite = wo.materials.get("calcite")
    lam, d, na = 589.0, 0.25, 0.5
    no, ne = calcite.n(lam)
    r = np.linspace(0.0, 1.0, 2001)
    prof = ms.conoscope_profile(
        calcite, d, r, azimuth_deg=azimuth, wavelength_nm=lam, numerical_aperture=na, device=device
    )
    found = _minima(r, prof)
    expect = _analytic_rings(no, ne, d, lam, na, 5)
    assert found.size >= 5
    np.testing.assert_allclose(found[:5], expect, rtol=0.01)


def test_isogyres_form_a_cross_along_the_polarizers(device):
    calcite = wo.materials.get("calcite")
    size = 81
    fig = ms.conoscopic_figure(calcite, 0.25, size=size, numerical_aperture=0.5, device=device)
    img = fig.intensity
    assert img.shape == (size, size) and fig.pupil.sum() > 0.7 * size * size
    c = size // 2  # the centre row and column: world x (polarizer) and y (analyzer) directions
    peak = img.max()
    assert np.max(img[c, :]) < 1e-4 * peak and np.max(img[:, c]) < 1e-4 * peak
    # off the cross the rings are bright: along the diagonals the mean is a quarter of the peak
    diag = np.array([img[j, j] for j in range(size) if fig.pupil[j, j]])
    assert diag.mean() > 0.25 * peak
    # a polarizer pair turned by 30 degrees turns the cross with it
    fig30 = ms.conoscopic_figure(
        calcite,
        0.25,
        size=size,
        numerical_aperture=0.5,
        polarizer_deg=30.0,
        analyzer_deg=120.0,
        device=device,
    )
    r = np.linspace(0.05, 0.95, 50)
    on = ms.conoscope_profile(
        calcite, 0.25, r, azimuth_deg=30.0, polarizer_deg=30.0, analyzer_deg=120.0, device=device
    )
    off = ms.conoscope_profile(
        calcite, 0.25, r, azimuth_deg=75.0, polarizer_deg=30.0, analyzer_deg=120.0, device=device
    )
    assert np.max(on) < 1e-4 * np.max(off)
    assert fig30.intensity.max() == pytest.approx(peak, rel=0.05)


def test_white_light_figure_and_bad_inputs(device):
    calcite = wo.materials.get("calcite")
    fig = ms.conoscopic_figure(calcite, 0.25, size=24, wavelength_nm=None, step_nm=20.0, device=device)
    assert fig.xyz.shape == (24, 24, 3) and fig.srgb.shape == (24, 24, 3)
    with pytest.raises(InputError, match="numerical_aperture"):
        ms.conoscopic_figure(calcite, 0.25, numerical_aperture=1.2, device=device)
    with pytest.raises(InputError, match="illuminant"):
        ms.interference_colour(calcite, 0.01, illuminant="nope", device=device)
    with pytest.raises(InputError, match="thickness_mm"):
        ms.interference_colour(calcite, -1.0, device=device)


def test_chart_command_writes_the_figure(tmp_path, capsys):
    from warpoptics.cli import main

    out = tmp_path / "ml.png"
    assert main(["chart", "michel-levy", "-o", str(out), "--max-retardation", "600"]) == 0
    assert out.stat().st_size > 1000
    fig = tmp_path / "cono.png"
    assert (
        main(
            [
                "chart",
                "conoscope",
                "--thickness",
                "0.25",
                "--size",
                "16",
                "--accessory-nm",
                "550",
                "-o",
                str(fig),
            ]
        )
        == 0
    )
    assert fig.stat().st_size > 1000
    assert main(["chart", "colour", "--material", "quartz", "--thickness", "0.03"]) == 0
    text = capsys.readouterr().out
    assert "retardation    274.8 nm" in text and "not modelled" in text


def test_thick_plate_in_white_light_is_the_incoherent_colour(device):
    # a 2 mm quartz plate (Delta ~ 18 um, higher-order white): the fringes of the coherent sum
    # are ~14 nm apart in wavelength, far finer than the CMFs, so its colour is that of the o and
    # e powers added (the incoherent model); a 30 um plate is not. XYZ and CIEDE2000 from
    # colour-science on the two transmission spectra the stage returns.
    colour = pytest.importorskip("colour")
    white = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    d65 = colour.SDS_ILLUMINANTS["D65"]

    def xyz(lam, t):
        c = np.array([cmfs[w] for w in lam])
        s = np.array([d65[w] for w in lam])
        return (t[:, None] * s[:, None] * c).sum(axis=0) / (s * c[:, 1]).sum()

    quartz = wo.materials.get("quartz")
    thick = ms.interference_colour(quartz, 2.0, step_nm=1.0, device=device)
    lam = thick.wavelength_nm
    de_thick = colour.delta_E(
        colour.XYZ_to_Lab(xyz(lam, thick.transmission), white),
        colour.XYZ_to_Lab(xyz(lam, thick.incoherent), white),
        method="CIE 2000",
    )
    thin = ms.interference_colour(quartz, 0.03, step_nm=1.0, device=device)
    de_thin = colour.delta_E(
        colour.XYZ_to_Lab(xyz(lam, thin.transmission), white),
        colour.XYZ_to_Lab(xyz(lam, thin.incoherent), white),
        method="CIE 2000",
    )
    assert de_thick < 1.0 and de_thin > 10.0, (de_thick, de_thin)


@pytest.mark.parametrize("accessory_deg, sign", [(45.0, +1), (135.0, -1)])
def test_accessory_plate_adds_or_subtracts_retardation(device, accessory_deg, sign):
    # quartz (positive: e slow) with its axis at 45 degrees, a first-order red plate (550 nm)
    # slow along the axis (addition) or across it (subtraction), crossed polarizers:
    # I = 1/4 |T_e exp(i (delta +- Gamma')) - T_o|^2 (Fresnel of the specimen's two faces only,
    # the accessory being an ideal retarder), Gamma' = 2 pi 550 / lambda
    quartz = wo.materials.get("quartz")
    d = 0.02
    ic = ms.interference_colour(quartz, d, accessory_nm=550.0, accessory_deg=accessory_deg, device=device)
    lam = ic.wavelength_nm
    n = quartz.n(lam)
    t_o = 4 * n[:, 0] / (1 + n[:, 0]) ** 2
    t_e = 4 * n[:, 1] / (1 + n[:, 1]) ** 2
    delta = 2 * np.pi * d * 1e6 * (n[:, 1] - n[:, 0]) / lam + sign * 2 * np.pi * 550.0 / lam
    ref = 0.25 * np.abs(t_e * np.exp(1j * delta) - t_o) ** 2
    assert np.max(np.abs(ic.transmission - ref)) < 1e-4
    # a glass interface pair instead of the specimen: the accessory alone between crossed polarizers,
    # sin^2(pi Gamma / lambda) times the two faces. Fresnel transmissions (4 n / (1 + n)^2)^2
    bk7 = wo.materials.get("bk7")
    bare = ms.interference_colour(bk7, 0.0, accessory_nm=550.0, device=device)  # no absorption
    t_g = (4 * bk7.n(lam) / (1 + bk7.n(lam)) ** 2) ** 2
    assert np.max(np.abs(bare.transmission - t_g * np.sin(np.pi * 550.0 / lam) ** 2)) < 1e-4


def test_gypsum_plate_tells_the_optic_sign(device):
    # a uniaxial figure with the first-order red plate (slow NE-SW): the isochromes of a
    # positive crystal (slow e vibration radial) add in the NE/SW quadrants and subtract in
    # NW/SE; a negative one the reverse. At 0.2 of the aperture both plates have Delta ~ 185 nm
    # at 589 nm: addition gives sin^2(pi 735/589) ~ 0.49, subtraction sin^2(pi 365/589) ~ 0.86
    # (less the Fresnel losses of the plate's faces).
    calcite = wo.materials.get("calcite")  # negative
    quartz = wo.materials.get("quartz")  # positive
    out = {}
    for name, mat, d in (("calcite", calcite, 0.25), ("quartz", quartz, 5.0)):
        ne_sw, nw_se = (
            ms.conoscope_profile(mat, d, [0.2], azimuth_deg=az, accessory_nm=550.0, device=device)[0]
            for az in (45.0, 135.0)
        )
        out[name] = (ne_sw, nw_se)
    assert out["calcite"][0] > 1.5 * out["calcite"][1]
    assert out["quartz"][1] > 1.5 * out["quartz"][0]

"""The inverse of the chromophore model (materials.fit): concentrations from a spectrum or a colour.

References: synthetic spectra of known concentrations (with noise), the decadic-absorbance
conversion alpha = ln 10 · A / d written out here, and colour-science's own spectral
integration and CIEDE2000 for the colour targets.
"""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from warpoptics.errors import InputError
from warpoptics.materials import chromophore_material, fit_chromophores, read_absorption_csv
from warpoptics.materials.chromophores import chromophore_alpha
from warpoptics.metrics import plate_transmittance
from warpoptics.spectra import grid

TOURMALINE = {"Mn3+": 0.6, "Fe2+": 1.2, "Fe2+-Ti4+": 0.2, "Cu2+": 0.9}


def _noisy(a, seed=1, level=0.005):
    rng = np.random.default_rng(seed)
    return a * (1.0 + level * rng.standard_normal(a.size))


def _rel(got: dict, want: dict) -> float:
    return max(abs(got[k] - v) / v for k, v in want.items())


def test_spectrum_fit_recovers_concentrations_within_2_percent():
    lam = np.arange(380.0, 751.0, 2.0)
    a = _noisy(chromophore_alpha("tourmaline", TOURMALINE, lam, "o"))
    r = fit_chromophores("tourmaline", spectrum=(lam, a), polarization="o", chromophores=list(TOURMALINE))
    print(r.summary())
    assert r.kind == "spectrum"
    assert _rel(r.concentrations, TOURMALINE) < 0.02
    assert r.relative_residual < 0.01  # 0.5 % noise
    # every chromophore of the host offered: the absent one comes back (near) zero
    r_all = fit_chromophores("tourmaline", spectrum=(lam, a), polarization="o")
    assert _rel({k: r_all.concentrations[k] for k in TOURMALINE}, TOURMALINE) < 0.02
    assert r_all.concentrations["Fe2+-Fe3+"] < 0.02


def test_spectrum_fit_mean_polarization_and_baseline():
    """Unpolarized data: the mean of the host's polarizations; a flat offset in the data is
    returned as the baseline, not as absorption."""
    want = {"amethyst centre": 0.25, "Fe3+": 0.4, "smoky centre": 0.1}
    lam = np.arange(400.0, 701.0, 1.0)
    mean = np.mean([chromophore_alpha("quartz", want, lam, p) for p in ("o", "e")], axis=0)
    r = fit_chromophores(
        "quartz", spectrum=(lam, _noisy(mean + 0.05, seed=3)), baseline=True, chromophores=list(want)
    )
    print(r.summary())
    assert _rel(r.concentrations, want) < 0.02
    assert r.baseline_per_mm == pytest.approx(0.05, rel=0.02)


def test_csv_absorbance_is_converted_with_the_path(tmp_path):
    """A decadic absorbance A over d mm is alpha = ln(10) A / d (1/mm, base e)."""
    want = {"Fe2+-Fe3+": 2.5, "Fe2+": 1.0}
    lam = np.arange(400.0, 701.0, 5.0)
    alpha = chromophore_alpha("cordierite", want, lam, "z")
    d = 0.5  # mm, the thickness of the Caltech GRR 262 section
    absorbance = alpha * d / math.log(10.0)
    f = tmp_path / "cordierite_z.csv"
    f.write_text(
        "# synthetic: cordierite, D along Z\nwavelength_nm,absorbance\n"
        + "".join(f"{x:g},{y:.8g}\n" for x, y in zip(lam, absorbance, strict=True))
    )
    lam_r, alpha_r = read_absorption_csv(f, quantity="absorbance", path_mm=d)
    np.testing.assert_allclose(lam_r, lam)
    np.testing.assert_allclose(alpha_r, alpha, rtol=1e-6)
    r = fit_chromophores("cordierite", spectrum=str(f), quantity="absorbance", path_mm=d, polarization="z")
    assert _rel(r.concentrations, want) < 0.02
    # alpha per cm is alpha per mm times 10
    g = tmp_path / "per_cm.csv"
    g.write_text("".join(f"{x:g},{10 * y:.8g}\n" for x, y in zip(lam, alpha, strict=True)))
    np.testing.assert_allclose(read_absorption_csv(g, quantity="alpha_per_cm")[1], alpha, rtol=1e-6)


def _lab_colour_science(wl, t, illuminant="D65"):
    """CIELAB of a transmittance by colour-science alone (its D65, CIE 1931 2°, 1 nm)."""
    import colour

    shape = colour.SpectralShape(360, 830, 1)
    sd = colour.SpectralDistribution(dict(zip(wl, t, strict=True))).align(shape)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(shape)
    ill = colour.SDS_ILLUMINANTS[illuminant].copy().align(shape)
    xyz = colour.sd_to_XYZ(sd, cmfs, ill, method="Integration") / 100.0
    white = colour.sd_to_XYZ(colour.sd_ones(shape), cmfs, ill, method="Integration") / 100.0
    return colour.XYZ_to_Lab(xyz, colour.XYZ_to_xy(white))


def test_colour_fit_reaches_a_target_within_de00_1():
    """A target made from known concentrations (tanzanite, 5 mm) is reached from the fit's own
    starting points; the fitted colour, recomputed by colour-science, is within ΔE00 1."""
    import colour

    g = grid()
    want = {"V3+": 0.55, "V 455 nm": 0.1}
    t = plate_transmittance(chromophore_material("zoisite", want), 5.0, g)
    target = _lab_colour_science(g, t)
    r = fit_chromophores("zoisite", target_lab=target, thickness_mm=5.0)
    print(r.summary())
    assert r.kind == "colour" and r.residual < 1.0
    t_fit = plate_transmittance(chromophore_material("zoisite", r.concentrations), 5.0, g)
    assert colour.delta_E(_lab_colour_science(g, t_fit), target, method="CIE 2000") < 1.0
    # a target not made by the model (turquoise) with the five tourmaline chromophores
    r2 = fit_chromophores("tourmaline", target_lab=(70.0, -30.0, -10.0), thickness_mm=5.0)
    assert r2.residual < 1.0


def test_colour_fit_reports_an_unreachable_target():
    """Two zoisite chromophores cannot make a saturated pink: the residual says so."""
    r = fit_chromophores("zoisite", target_lab=(60.0, 50.0, 10.0), thickness_mm=5.0)
    assert r.residual > 5.0


@pytest.mark.parametrize(
    "text, quantity, path, match",
    [
        ("400,0.1\n500,abc\n", "absorbance", 1.0, r"row 2 = '500,abc': not a number"),
        ("wavelength,A\n400,0.1\n500\n", "absorbance", 1.0, r"row 3 = '500': needs two comma-separated"),
        ("400,0.1\n500,nan\n", "alpha_per_mm", None, r"row 2 = '500,nan': must be finite"),
        (
            "400,0.1\n400,0.2\n",
            "alpha_per_mm",
            None,
            r"row 2: wavelength 400 nm given twice \(rows 1 and 2\)",
        ),
        ("-5,0.1\n500,0.2\n", "alpha_per_mm", None, r"row 1 = '-5,0.1': wavelength must be > 0"),
        ("# only a comment\n400,0.1\n", "alpha_per_mm", None, r"needs at least two data rows"),
        ("400,0.1\n500,0.2\n", "absorbance", None, r"path_mm: a decadic absorbance needs the path length"),
        ("400,0.1\n500,0.2\n", "absorbance", -1.0, r"path_mm = -1.0: must be a number > 0"),
        ("400,0.1\n500,0.2\n", "transmittance", None, r"unknown quantity"),
    ],
)
def test_bad_csv_names_file_and_row(tmp_path, text, quantity, path, match):
    f = tmp_path / "bad.csv"
    f.write_text(text)
    with pytest.raises(InputError, match=match) as exc:
        read_absorption_csv(f, quantity=quantity, path_mm=path)
    assert str(f) in str(exc.value)


def test_fit_input_errors(tmp_path):
    with pytest.raises(InputError, match="spectrum file not found"):
        fit_chromophores("quartz", spectrum=str(tmp_path / "missing.csv"))
    with pytest.raises(InputError, match="either a spectrum or a target colour"):
        fit_chromophores("quartz")
    with pytest.raises(InputError, match="no such chromophore in quartz"):
        fit_chromophores("quartz", target_lab=(50, 0, 0), thickness_mm=2.0, chromophores=["Cr3+"])
    with pytest.raises(InputError, match="no such polarization in quartz"):
        fit_chromophores("quartz", spectrum=([400, 500, 600], [0.1, 0.2, 0.1]), polarization="x")
    with pytest.raises(InputError, match="needs the plate thickness"):
        fit_chromophores("quartz", target_lab=(50, 0, 0))
    with pytest.raises(InputError, match="0 <= L"):
        fit_chromophores("quartz", target_lab=(150, 0, 0), thickness_mm=2.0)
    with pytest.raises(InputError, match="too few data points"):
        fit_chromophores("quartz", spectrum=([300, 310], [0.1, 0.2]))


def _cli(*args):
    return subprocess.run(
        [sys.executable, "-m", "warpoptics.cli", "material", "fit", *args], capture_output=True, text=True
    )


def test_cli_fit_spectrum_and_errors(tmp_path):
    lam = np.arange(400.0, 701.0, 5.0)
    want = {"Cu2+": 1.8, "Mn3+": 0.2}
    a = chromophore_alpha("tourmaline", want, lam, "o")
    f = tmp_path / "paraiba_o.csv"
    f.write_text(
        "wavelength_nm,alpha_per_mm\n" + "".join(f"{x:g},{y:.8g}\n" for x, y in zip(lam, a, strict=True))
    )
    r = _cli("tourmaline", "--spectrum", str(f), "--quantity", "alpha_per_mm", "--polarization", "o")
    assert r.returncode == 0, r.stderr
    assert "Cu2+" in r.stdout and "residual" in r.stdout
    got = float(next(line for line in r.stdout.splitlines() if "Cu2+" in line).split()[1])
    assert got == pytest.approx(1.8, rel=0.02)
    bad = tmp_path / "bad.csv"
    bad.write_text("400,0.1\n500,x\n")
    r = _cli("tourmaline", "--spectrum", str(bad), "--path-mm", "1")
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert f"{bad}: row 2" in r.stderr
    r = _cli("tourmaline", "--lab", "70,-30")
    assert r.returncode == 2 and "--lab" in r.stderr and "Traceback" not in r.stderr


def test_a_variety_name_fits_its_host():
    """``"tanzanite"`` fits the zoisite band sets; an unknown name is an error naming the field."""
    lam = np.arange(400.0, 701.0, 2.0)
    a = chromophore_alpha("zoisite", {"V3+": 0.3}, lam, "y")
    r = fit_chromophores("tanzanite", spectrum=(lam, a), polarization="y")
    assert r.host == "zoisite"
    assert r.concentrations["V3+"] == pytest.approx(0.3, rel=0.02)
    assert r.concentrations["V 455 nm"] == 0.0 and "not determined: V 455 nm" in r.summary()
    with pytest.raises(InputError, match="host = 'tanzanit': unknown chromophore host"):
        fit_chromophores("tanzanit", spectrum=(lam, a))

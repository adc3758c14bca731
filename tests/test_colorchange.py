"""Colour change between two illuminants (metrics.colour_change, `warpoptics colorchange`).

Independent reference: colour-science's own spectral integration (``sd_to_XYZ`` with its CIE
illuminant tables), CIELAB and CIEDE2000 of the same transmission spectrum, the plate's
transmittance written out here ((1 - R)^2 exp(-alpha d), R = ((n - 1)/(n + 1))^2).
"""

from __future__ import annotations

import os
import subprocess
import sys

import colour
import numpy as np
import pytest

import warpoptics as wo
from warpoptics.errors import InputError
from warpoptics.metrics import colour_change, plate_transmittance
from warpoptics.spectra import grid

CMFS = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]


@pytest.mark.parametrize("level", [0.05, 0.5, 1.0])
@pytest.mark.parametrize("pair", [("D65", "A"), ("D50", "FL11")])
def test_flat_spectrum_has_no_colour_change(level, pair):
    g = grid()
    r = colour_change(g, np.full_like(g, level), illuminants=pair)
    assert r["delta_e00"] < 1e-9 and r["delta_hue"] == 0.0
    assert r["lab"][0][0] == pytest.approx(r["lab"][1][0], abs=1e-9)


def _colour_science_change(wl, t, pair=("D65", "A")):
    """The same colour change computed by colour-science alone (5 nm CIE illuminant tables,
    its sd_to_XYZ integration, each illuminant's own white)."""
    sd = colour.SpectralDistribution(t, wl)
    labs = []
    for name in pair:
        ill = colour.SDS_ILLUMINANTS[name]
        xyz = colour.sd_to_XYZ(sd, CMFS, ill) / 100.0
        white = colour.sd_to_XYZ(colour.sd_ones(ill.shape), CMFS, ill) / 100.0
        labs.append(colour.XYZ_to_Lab(xyz, colour.XYZ_to_xy(white)))
    h = [np.degrees(np.arctan2(lab[2], lab[1])) % 360 for lab in labs]
    dh = abs(h[0] - h[1]) % 360
    return labs, min(dh, 360 - dh), float(colour.delta_E(labs[0], labs[1], method="CIE 2000"))


@pytest.mark.parametrize("thickness", [2.0, 4.0, 8.0])
def test_garnet_plate_matches_colour_science(thickness):
    mat = wo.materials.get("colour_change_garnet")
    g = grid()
    t = plate_transmittance(mat, thickness, g)
    n, alpha = mat.n(g), mat.alpha(g)
    r0 = ((n - 1) / (n + 1)) ** 2
    np.testing.assert_allclose(t, (1 - r0) ** 2 * np.exp(-alpha * thickness), rtol=2e-6)  # float32 Fresnel
    ours = colour_change(g, t)
    labs, dh, de = _colour_science_change(g, t)
    # the tolerance: ΔE00 0.5 between the two computations, under each illuminant
    for k in range(2):
        assert colour.delta_E(ours["lab"][k], labs[k], method="CIE 2000") < 0.5
    assert abs(ours["delta_e00"] - de) < 0.5 and abs(ours["delta_hue"] - dh) < 2.0
    # and it is a colour change: bluish green in daylight, purplish red in incandescent light
    if thickness == 4.0:
        h65, ha = ours["hue"]
        assert 120 < h65 < 200 and (ha > 300 or ha < 20) and ours["delta_e00"] > 15


def test_any_material_and_uniaxial():
    """Uniaxial plates average their two waves; a colourless stone barely changes."""
    g = grid()
    ruby = plate_transmittance("ruby", 3.0, g)
    mat = wo.materials.get("ruby")
    n, a = mat.n(g), mat.alpha(g)
    r0 = ((n - 1) / (n + 1)) ** 2
    np.testing.assert_allclose(ruby, ((1 - r0) ** 2 * np.exp(-a * 3.0)).mean(axis=-1), rtol=2e-6)
    quartz = colour_change(g, plate_transmittance("quartz", 5.0, g))
    # only the dispersion of the Fresnel loss (0.5 % across the visible): far below the
    # just-noticeable ΔE00 of about 1
    assert quartz["delta_e00"] < 0.2
    with pytest.raises(InputError, match="no visible light"):
        colour_change(g, np.ones_like(g), illuminants=("D65", "UV254"))
    with pytest.raises(InputError, match="increasing"):
        colour_change([500.0, 400.0], [1.0, 1.0])


def _cli(*args, cwd):
    env = dict(os.environ, PYTHONPATH=os.getcwd())
    return subprocess.run(
        [sys.executable, "-m", "warpoptics.cli", "colorchange", *args],
        capture_output=True,
        text=True,
        env=env,
        cwd=cwd,
        timeout=300,
    )


def test_cli(tmp_path):
    out = tmp_path / "cc.png"
    p = _cli("colour_change_garnet", "--thickness", "4", "--plot", str(out), cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert "hue-angle change" in p.stdout and "CIEDE2000" in p.stdout and out.stat().st_size > 1000
    csv = tmp_path / "flat.csv"
    csv.write_text("\n".join(f"{w},0.5" for w in range(360, 831, 10)))
    p = _cli(str(csv), "--illuminants", "D50,LED-B3", cwd=tmp_path)
    assert p.returncode == 0 and "hue-angle change 0.0 deg, CIEDE2000 0.00" in p.stdout
    p = _cli("ruby", "--illuminants", "D65", cwd=tmp_path)
    assert p.returncode == 2 and len(p.stderr.strip().splitlines()) == 1 and "two illuminants" in p.stderr

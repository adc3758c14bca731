"""The dispersive benchmark stone against Mitsuba 3 rendered band by band.

``scripts/bench/fire_reference.py`` (read its docstring) builds the reference: for each of a
set of wavelength bands, Mitsuba's ``scalar_spectral_polarized`` renders the stone with the
library diamond's index in that band through a ``specfilm`` box response; the band images are
summed with the CIE 1931 functions and D65 from colour-science.  The environment is a grey
map, whose spectrum (g(direction) x D65) both renderers define alike, so no RGB-to-spectrum
model enters.  Here at a tiny size under a blurred grey studio map (soft edges: little noise per
sample, so that a few seconds of rendering resolve a 2 % difference), with the noise of both
renderers removed by the split-halves estimator.  The full-size comparison is the script's.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest

mi = pytest.importorskip("mitsuba")

import warpoptics as wo  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts" / "bench"))
import fire_reference as fr  # noqa: E402

BLUR = 8.0  # degrees; see test_dispersive_render_matches_mitsuba_band_by_band


def test_bands_partition_the_spectrum():
    """The bands tile 360-830 nm and their CIE weights add up to D65's tristimulus values at
    Y = 1 (colour-science's D65 white point, computed there from its own tables: xy = 0.3127,
    0.3290, to 4 decimals)."""
    n = wo.materials.get("diamond").n
    bands = fr.spectral_bands(12, n)
    assert bands[0]["lo"] == 360 and bands[-1]["hi"] == 830
    assert all(a["hi"] == b["lo"] for a, b in zip(bands[:-1], bands[1:], strict=True))
    xyz = np.sum([b["xyz"] for b in bands], axis=0)
    assert xyz[1] == pytest.approx(1.0, abs=1e-12)
    assert xyz[0] / xyz.sum() == pytest.approx(0.3127, abs=2e-4)
    assert xyz[1] / xyz.sum() == pytest.approx(0.3290, abs=2e-4)
    # each band's index is a mean of n over the band: between its values at the band's ends
    # (n falls with the wavelength), and the bands are narrow where the eye is sensitive
    for b in bands:
        assert n(np.array([b["hi"]]))[0] <= b["n"] <= n(np.array([b["lo"]]))[0]
    widths = [b["hi"] - b["lo"] for b in bands if 500 <= b["lo"] <= 600]
    assert max(widths) <= 25


def test_dispersive_render_matches_mitsuba_band_by_band(device):
    """24x24, 12 bands x 256 spp x 2 passes of Mitsuba, 6 passes of 16 spp x 45 wavelengths of
    ours (about 14 + 5 CPU-seconds).  The blur (8 degrees) sets the noise: the split-halves
    estimate of the squared relative RMSE has a standard error of about 1e-4 here (measured:
    2-sigma upper bound 1.4 % at an estimate of 0), so a true 0 exceeds 2 % (4e-4) with a
    probability below 1e-4, while the stone without dispersion (5.2 % measured) is refused with
    the same margin; with a 3-degree blur it would be 0.035 against 0.099 but a 25 % chance of
    a false alarm."""
    with tempfile.TemporaryDirectory() as tmp:
        gmap = fr.grey_map(fr.STUDIO_MAP, Path(tmp) / "grey.exr", blur_deg=BLUR)
        scene = fr.reference_scene(gmap, width=24, height=24).with_overrides({"render.spp": 16})
        res = fr.compare(scene, n_bands=12, mitsuba_spp=256, ours_passes=6, device=device, twins=("clear",))
    a, clear = res["agreement"], res["nondispersive_vs_reference"]
    print(
        f"ours vs Mitsuba band by band: converged rel. RMSE {a['converged_rel_rmse']:.4f} (2-sigma upper "
        f"{a['converged_rel_rmse_upper_2sigma']:.4f}), raw {a['raw_rel_rmse_of_means']:.4f}, mean "
        f"{a['mean_rel_diff']:+.4f}; stone only {res['agreement_stone']['converged_rel_rmse']:.4f}; "
        f"clear twin {clear['converged_rel_rmse']:.4f}; noise of one pass {res['rel_noise_one_pass']}; "
        f"CPU s: Mitsuba {res['mitsuba_cpu_seconds']:.1f}, ours {res['ours_cpu_seconds']:.1f}"
    )
    assert res["stone_pixels"] > 100  # the stone fills a good part of the view
    # the issue's criterion: < 2 % relative RMSE of linear sRGB between the converged images
    assert a["converged_rel_rmse"] < 0.02
    # resolved, not only hidden in noise: the 2-sigma bound (sqrt(2 x 1e-4) = 1.4 % at a true 0)
    assert a["converged_rel_rmse_upper_2sigma"] < 0.03
    # the mean (noise about 0.2 %): a band weight, white point or normalisation error is percents
    assert abs(a["mean_rel_diff"]) < 0.01
    # the test can fail: the same stone without dispersion (a constant index) is refused
    assert clear["converged_rel_rmse"] > 0.035

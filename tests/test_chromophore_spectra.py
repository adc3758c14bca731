"""Band sets against the measured spectra they were fitted to (tests/data/chromophores/spectra/).

Each spectrum file holds numeric data of a published figure or database file (cross sections of a
SIMS-analysed sample, or the absorbance of a slab of stated thickness) with its source, sample,
polarization, thickness, concentration and how it was obtained in the header
(:mod:`warpoptics.materials.chromophore_spectra` reads it).  At the sample's concentration the
library's band set must reproduce it: every stated band maximum within 5 nm, the alpha there within
15 %, and the RMS relative error over 400-700 nm below 20 % at the points where the measured alpha
exceeds 5 % of its maximum in that range (below that, a relative error of a near-zero value says
nothing about the colour and is dominated by the baseline).  ``scripts/fit_chromophore_bands.py``
regenerates the fitted numbers.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from warpoptics.materials import chromophores as C
from warpoptics.materials.chromophore_spectra import (
    CRITERIA,
    compare,
    concentrations,
    read_measured_spectrum,
    rms_mask,
)

SPECTRA = sorted((Path(__file__).parent / "data" / "chromophores" / "spectra").glob("*.csv"))


@pytest.fixture(scope="module", params=SPECTRA, ids=lambda p: p.stem)
def measured(request):
    sp = read_measured_spectrum(request.param)
    conc = concentrations(sp)  # the band set, and any other band sets the sample holds

    def alpha(lam, pol):
        return C.chromophore_alpha(sp.host, conc, lam, pol)

    return sp, compare(sp, alpha)


def test_the_file_says_where_it_comes_from(measured):
    sp, _ = measured
    text = "\n".join(sp.comments).lower()
    for word in ("source:", "sample:", "polarization:", "thickness:", "how obtained:"):
        assert word in text, (sp.path.name, word)
    assert set(sp.alpha) == set(sp.peaks_nm)
    assert set(sp.alpha) <= set(C.host_info(sp.host)["polarizations"])
    # the band set cites the file, and its note says what is measured
    bs = C.band_set(sp.host, sp.chromophore)
    assert sp.path.name in bs.source and "measured:" in bs.note
    for name in sp.also:  # other band sets the sample holds exist in the host
        assert C.band_set(sp.host, name).source, name


def test_band_centres_within_5_nm(measured):
    sp, result = measured
    for pol, r in result.items():
        for p in r["peaks"]:
            assert abs(p["measured_nm"] - p["stated_nm"]) <= 5.0, (pol, p)  # the file's own maxima
            assert p["centre_error_nm"] <= CRITERIA["centre_nm"], (sp.path.name, pol, p)


def test_peak_alpha_within_15_percent(measured):
    sp, result = measured
    for pol, r in result.items():
        for p in r["peaks"]:
            assert abs(p["peak_ratio"] - 1.0) <= CRITERIA["peak_rel"], (sp.path.name, pol, p)


def test_rms_relative_error_below_20_percent(measured):
    sp, result = measured
    for pol, r in result.items():
        assert r["n_rms"] >= 20, (sp.path.name, pol, r["n_rms"])
        assert r["rms"] < CRITERIA["rms_rel"], (sp.path.name, pol, r["rms"])


def test_rms_mask_and_conversions():
    """The comparison's own arithmetic: the 5 % floor and the 400-700 nm range, and the two
    conversions (cross section x number density; decadic absorbance less baseline over path)."""
    lam = np.array([390.0, 400.0, 500.0, 600.0, 700.0, 710.0])
    a = np.array([9.0, 1.0, 0.09, 0.11, 2.0, 9.0])  # 5 % of 2.0 = 0.1
    assert rms_mask(lam, a).tolist() == [False, True, False, True, True, False]
    for path in SPECTRA:
        sp = read_measured_spectrum(path)
        if sp.meta["quantity"] == "sigma_cm2":
            n = float(sp.meta["number_density_cm3"])
            assert all(np.max(v) < 10.0 and np.max(v) > 1e-4 for v in sp.alpha.values()), (path.name, n)
        else:
            # the baseline is each column's smallest absorbance, so alpha >= 0 and = 0 somewhere
            assert all(abs(np.min(v)) < 1e-9 for v in sp.alpha.values()), path.name

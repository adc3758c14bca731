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

Files with ``role: check`` are independent measured spectra the band set was not fitted to (the
same criteria apply).  Where one is not reproduced, :data:`MISFITS` holds the measured numbers and
the reason, and that test is a strict xfail: it fails loudly once the band set reproduces it.
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

#: (file, criterion) -> the measured misfit and its reason (`compare` at the file's concentration)
MISFITS = {
    ("corundum_cr3_caltech_grr1843.csv", "rms"): (
        "natural Thai ruby GRR 1843 (no analysis), E perp c: RMS 21.9 % over 382 points, mostly from "
        "430-470 nm where the stone absorbs 25-58 % more than the set fitted to the SIMS-analysed "
        "synthetic GIA 1110 (centres 4.75 and 2.5 nm, violet peak -11.8 %, both within the "
        "criteria).  A joint refit of the E perp c bands to both spectra passes both (GIA 1110 RMS "
        "3.6 -> 14.2 %, GRR 1843 12.1 %) but would assign the unanalysed stone's extra blue "
        "absorption to Cr3+; not done (docs/design/chromophore_spectra.md)"
    ),
    ("corundum_feti_caltech_grr1020a_o.csv", "peak"): (
        "blue sapphire GRR 1020a, E perp c: model alpha at the 451 nm maximum -35.6 % (Fe2+-Ti4+ "
        "0.387 + Fe3+ 0.065 in their units); the Fe3+ line sits on a broad shoulder the library's "
        "sets do not have"
    ),
    ("corundum_feti_caltech_grr1020a_o.csv", "rms"): (
        "blue sapphire GRR 1020a, E perp c: RMS 49.5 % over 230 points; above 600 nm the stone's "
        "absorption rises towards its Fe2+-Fe3+ band at 870-890 nm (no corundum band set), while "
        "Fe2+-Ti4+ (GIA's 14-wafer average, maximum 580 nm) falls: one set cannot do both"
    ),
    ("corundum_feti_caltech_grr1020a_e.csv", "peak"): (
        "blue sapphire GRR 1020a, E par c: model alpha at the 453 nm maximum -29.0 %"
    ),
    ("corundum_feti_caltech_grr1020a_e.csv", "rms"): (
        "blue sapphire GRR 1020a, E par c: RMS 335 % over 363 points: the file's minimum (538 nm), "
        "removed as baseline, lies on the broad Fe2+-Ti4+ E par c band (model 0.13/mm there), so "
        "the measured alpha is near zero at 500-560 nm; plus the Fe2+-Fe3+ flank above 600 nm"
    ),
}


def _expect(request, sp, criterion: str) -> None:
    """Mark a known misfit of a check spectrum as a strict xfail (its reason: the numbers)."""
    reason = MISFITS.get((sp.path.name, criterion))
    if reason is not None:
        request.applymarker(pytest.mark.xfail(strict=True, reason=reason))


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
    assert sp.meta.get("role", "fit") in ("fit", "check"), sp.path.name
    bs = C.band_set(sp.host, sp.chromophore)
    if sp.meta.get("role", "fit") == "fit":  # the band set cites the file it was fitted to
        assert sp.path.name in bs.source and "measured:" in bs.note
    for name in sp.also:  # other band sets the sample holds exist in the host
        assert C.band_set(sp.host, name).source, name


def test_band_centres_within_5_nm(measured, request):
    sp, result = measured
    _expect(request, sp, "centre")
    for pol, r in result.items():
        for p in r["peaks"]:
            assert abs(p["measured_nm"] - p["stated_nm"]) <= 5.0, (pol, p)  # the file's own maxima
            assert p["centre_error_nm"] <= CRITERIA["centre_nm"], (sp.path.name, pol, p)


def test_peak_alpha_within_15_percent(measured, request):
    sp, result = measured
    _expect(request, sp, "peak")
    for pol, r in result.items():
        for p in r["peaks"]:
            assert abs(p["peak_ratio"] - 1.0) <= CRITERIA["peak_rel"], (sp.path.name, pol, p)


def test_rms_relative_error_below_20_percent(measured, request):
    sp, result = measured
    _expect(request, sp, "rms")
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

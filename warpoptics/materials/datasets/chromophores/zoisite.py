"""Zoisite (Ca2Al3(SiO4)(Si2O7)O(OH), orthorhombic, biaxial +; gem variety tanzanite): V3+ and the
440-455 nm band that heat treatment removes.

Polarizations ``x``, ``y``, ``z``: D along the principal axes X, Y, Z (n_alpha, n_beta, n_gamma).

Measured: G. R. Rossman, Caltech Mineral Spectroscopy Server, polarized spectra of the unheated
tanzanite GRR 1265 (files zo1265.a/.b/.c, absorbance normalised to 3.00 mm; the alpha ray along b
taken as X, the beta ray along c as Y, the gamma ray along a as Z, as the files name them;
``tests/data/chromophores/spectra/zoisite_v3_caltech_grr1265.csv``).  Maxima: X 545 nm (red-violet),
Y 605 nm with a shoulder near 537 nm and a band near 728 nm (blue), Z 442 and 605 nm (yellow-green
before heating).  The two band sets are fitted together to 400-700 nm
(``scripts/fit_chromophore_bands.py``): "V 455 nm" takes the Z band at 444 nm and the steep Z rise
below 420 nm (a band placed at 375 nm, outside the data: only its long-wavelength side is
measured), "V3+" everything else.  No usable analysis: the V3+ unit is the alpha (1/mm) at the
605 nm maximum along Y (the sample has 0.0804/mm), that of "V 455 nm" the peak alpha of its 444 nm
band along Z (the sample has 0.146/mm).  The split between the two sets is the model's choice:
heating removes the 450-460 nm band along c (T. Pluthametwisute et al., Molecules 25, 3743 (2020),
abstract), which is what "V 455 nm" stands for.

The positions quoted from M. O'Donoghue (ed.), *Gems*, 6th ed. (2006) (595 nm, fainter 528 and
455 nm; unpolarized) lie 10-17 nm from these polarized maxima and are no longer used.  P. Bačík et
al., Mineral. Mag. (2023), abstract: vanadium is the dominant chromophore of tanzanite.

The value of tanzanite (heated: V3+ only) in :mod:`..varieties` is chosen for its trade colour.
"""

from __future__ import annotations

__all__ = ["HOST", "BAND_SETS"]

HOST = dict(
    polarizations=("x", "y", "z"),
    index=("biaxial", 1.692, 1.694, 1.700, 0.019),
    source=(
        "tanzanite (zoisite), GIA: RI 1.691-1.700, biaxial (+), dispersion 0.019; n_alpha 1.692, "
        "n_gamma 1.700 (O'Donoghue 2006), n_beta 1.694 within GIA's range; Cauchy fits"
    ),
    description="zoisite, orthorhombic, biaxial (+); tanzanite X red-violet, Y blue, Z violet (heated)",
)

_GW = "gaussian_wavenumber"

BAND_SETS = {
    "V3+": dict(
        unit="1/mm (alpha at the 605 nm maximum, D along Y)",
        reference_concentration=1.0,
        bands=dict(
            x=((553.5, 49.99, 2.344, _GW), (431.8, 55.35, 1.593, _GW)),
            y=(
                (606.5, 25.42, 0.9728, _GW),
                (536.7, 24.73, 0.5787, _GW),
                (727.7, 24.04, 0.5904, _GW),
                (385.0, 26.35, 1.424, _GW),
            ),
            z=((606.6, 27.06, 0.8342, _GW), (550.1, 24.12, 0.2188, _GW), (717.6, 14.67, 0.2526, _GW)),
        ),
        source=(
            "Rossman, Caltech Mineral Spectroscopy Server, tanzanite GRR 1265 (unheated), zo1265.a/.b/.c, "
            "3.00 mm; tests/data/chromophores/spectra/zoisite_v3_caltech_grr1265.csv; Bačík et al. 2023 "
            "(vanadium the chromophore)"
        ),
        note=(
            "measured: centres, widths and strengths along X, Y, Z fitted at 400-700 nm (unit: the "
            "sample's alpha at 605 nm along Y); the split from the 444 nm band set is chosen"
        ),
    ),
    "V 455 nm": dict(
        unit="1/mm (peak alpha of the 444 nm band, D along Z)",
        reference_concentration=1.0,
        bands=dict(
            x=(),
            y=(),
            z=((444.0, 20.35, 1.0, _GW), (375.0, 15.72, 20.67, _GW)),
        ),
        source=(
            "Rossman, Caltech Mineral Spectroscopy Server, tanzanite GRR 1265 (unheated); "
            "tests/data/chromophores/spectra/zoisite_v3_caltech_grr1265.csv; Pluthametwisute et al. "
            "2020, Molecules 25, 3743 (abstract: the 450-460 nm band along c falls on heating)"
        ),
        note=(
            "measured: the Z band at 444 nm and the Z rise below 420 nm (a band at 375 nm outside the "
            "data) fitted with the V3+ set; present in unheated zoisite, absent from heated "
            "tanzanite; which bands belong to this set is chosen"
        ),
    ),
}

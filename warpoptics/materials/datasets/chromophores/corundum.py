"""Corundum (alpha-Al2O3, trigonal, uniaxial -): Cr3+ (ruby), V3+, the Fe2+-Ti4+ intervalence
charge transfer (blue sapphire), Fe3+ (yellow sapphire) and the Mg-related trapped-hole centre.

Polarizations ``o`` (E⊥c) and ``e`` (E∥c).  Charge-transfer bands are Gaussians in wavenumber
(``"gaussian_wavenumber"``, width = sigma in nm at the centre); the Cr3+ and V3+ bands and the
sharp lines are Gaussians in wavelength (sigma in nm).

Measured: Cr3+, V3+ and Fe2+-Ti4+ are fitted (``scripts/fit_chromophore_bands.py``, 400-700 nm)
to the absorption cross sections of E. V. Dubinsky, J. Stone-Sundberg, J. L. Emmett, Gems &
Gemology 56(1), 2-28 (2020), data of the paper's cross-section figures (SIMS-analysed samples),
kept with their provenance in ``tests/data/chromophores/spectra/corundum_*_gia2020*.csv``:

- Cr3+: GIA sample 1110, synthetic ruby, 134 ppma Cr = 0.050 wt% Cr2O3; maxima E⊥c 409 and
  558 nm, E∥c 398 and 546 nm (not the 570 nm the library once took from McClure 1962), R line
  693 nm.  Unit wt% Cr2O3.
- V3+: a V-doped synthetic, 116 ppma V; maxima E⊥c 400 and 577 nm, E∥c 405 and 575 nm (the data
  sheet's values; the paper's text gives a larger E⊥c cross section at 580 nm).  Unit ppma V.
- Fe2+-Ti4+: cross section per pair (14 Yogo Gulch wafers); maxima E⊥c 580 nm, E∥c ~707 nm.  Unit:
  alpha (1/mm) at 580 nm E⊥c, the varieties' unit; 1 ppma of pairs gives 0.0233/mm.
The number of bands and their shapes are the model's choice; docs/design/chromophore_spectra.md
lists measured against model.

Chosen (no measured spectrum with a concentration could be read):
- Fe3+: GRS journal no. 1 (2002), p. 16, fig. 26 caption (Fe3+ line 388 nm, Fe3+-pair line
  450 nm); R. G. Burns, *Mineralogical Applications of Crystal Field Theory* (2nd ed. 1993),
  fig. 3.16 caption after Ferguson & Fielding 1972 (pair band near 17,600 cm-1, 568 nm); the
  violet edge is the tail of the UV O2- -> Fe3+ charge transfer (K. Tippins, Phys. Rev. B 1, 126
  (1970), abstract), an Urbach tail.  Widths, o/e ratios, strengths chosen; unit the peak alpha
  (1/mm) of the 450 nm line.
- Trapped-hole centre ("h-centre", Mg2+-related): GRS fig. 26 caption, "general absorption in the
  blue region"; an Urbach tail whose reference point, slope and o/e ratio are chosen.

The concentrations of the corundum varieties (:mod:`..varieties`) are chosen for their trade
colour (no analysis of a stone is used).
"""

from __future__ import annotations

__all__ = ["HOST", "BAND_SETS"]

HOST = dict(
    polarizations=("o", "e"),
    index=("pages", "main/Al2O3/Malitson-o", "main/Al2O3/Malitson-e"),
    source="refractiveindex.info main/Al2O3/Malitson-o/-e",
    description="corundum alpha-Al2O3, trigonal, uniaxial (-); o = E⊥c, e = E∥c",
)

_CHOSEN = (
    "band positions from the sources; widths, o/e ratio and absolute strength chosen (no measured spectrum)"
)

BAND_SETS = {
    "Cr3+": dict(
        unit="wt% Cr2O3",
        reference_concentration=0.05,
        bands=dict(
            o=(
                (558.8, 26.59, 0.2547, "gaussian"),
                (409.0, 23.03, 0.2585, "gaussian"),
                (511.4, 19.20, 0.04347, "gaussian"),
                (473.8, 8.42, 0.008193, "gaussian"),
                (693.4, 2.03, 0.01367, "gaussian"),
            ),
            e=(
                (547.3, 24.55, 0.07271, "gaussian"),
                (398.1, 21.20, 0.4411, "gaussian"),
                (475.0, 83.37, 0.02154, "gaussian"),
            ),
        ),
        source=(
            "Dubinsky, Stone-Sundberg & Emmett 2020, Gems & Gemology 56(1) 2-28, Cr3+ cross-section "
            "data (GIA sample 1110, synthetic ruby, 134 ppma Cr = 0.050 wt% Cr2O3 by SIMS, E⊥c and "
            "E∥c); tests/data/chromophores/spectra/corundum_cr3_gia2020_sample1110.csv"
        ),
        note=(
            "measured: band centres, widths, strengths and o/e ratio fitted to the sample's cross "
            "sections at 400-700 nm (scripts/fit_chromophore_bands.py); the number of bands and "
            "their Gaussian shape are the model's choice"
        ),
    ),
    "V3+": dict(
        unit="ppma V (atoms per million atoms)",
        reference_concentration=116.0,
        bands=dict(
            o=((577.4, 34.67, 0.04612, "gaussian"), (399.8, 24.79, 0.1392, "gaussian")),
            e=((574.9, 37.65, 0.03915, "gaussian"), (404.8, 21.75, 0.6526, "gaussian")),
        ),
        source=(
            "Dubinsky, Stone-Sundberg & Emmett 2020, Gems & Gemology 56(1) 2-28, V3+ cross-section "
            "data (V-doped synthetic corundum, 116 ppma V by SIMS, E⊥c and E∥c; the data sheet's "
            "values); tests/data/chromophores/spectra/corundum_v3_gia2020.csv"
        ),
        note=(
            "measured: centres, widths, strengths and o/e ratio fitted to the cross sections at "
            "400-700 nm; two Gaussian bands per polarization are the model's choice"
        ),
    ),
    "Fe3+": dict(
        unit="1/mm (peak alpha of the 450 nm Fe3+-pair line, E⊥c)",
        reference_concentration=1.0,
        bands=dict(
            o=(
                (388.0, 4.0, 1.6, "gaussian"),
                (450.0, 5.0, 1.0, "gaussian"),
                (568.0, 30.0, 0.08, "gaussian_wavenumber"),
            ),
            e=(
                (388.0, 4.0, 1.2, "gaussian"),
                (450.0, 5.0, 0.7, "gaussian"),
                (568.0, 30.0, 0.05, "gaussian_wavenumber"),
            ),
        ),
        tails=dict(o=(360.0, 1.0, 0.25), e=(360.0, 0.8, 0.25)),
        source=(
            "GRS journal no. 1 (2002) fig. 26 caption (Fe3+ 388 nm, Fe3+-pair 450 nm); Burns 1993 "
            "fig. 3.16 caption after Ferguson & Fielding 1972 (pair band ~17,600 cm-1); Tippins "
            "1970, Phys. Rev. B 1, 126 (UV charge transfer, the violet edge)"
        ),
        note=_CHOSEN + "; the UV edge's alpha at 360 nm and its slope (0.25 eV) chosen",
    ),
    "Fe2+-Ti4+": dict(
        unit="1/mm (alpha at 580 nm, E⊥c; 1 ppma of Fe2+-Ti4+ pairs gives 0.0233)",
        reference_concentration=1.0,
        bands=dict(
            o=(
                (581.6, 72.42, 0.9574, "gaussian_wavenumber"),
                (731.4, 62.68, 0.3825, "gaussian_wavenumber"),
                (425.0, 66.24, 0.1701, "gaussian_wavenumber"),
            ),
            e=((728.5, 128.96, 0.4913, "gaussian_wavenumber"), (505.0, 126.00, 0.264, "gaussian_wavenumber")),
        ),
        tails=dict(e=(380.0, 0.02292, 3.0)),
        source=(
            "Dubinsky, Stone-Sundberg & Emmett 2020, Gems & Gemology 56(1) 2-28, Fe2+-Ti4+ cross "
            "section per pair (average of 14 Yogo Gulch sapphire wafers, E⊥c maximum 580 nm, E∥c "
            "near 707 nm); tests/data/chromophores/spectra/corundum_feti_gia2020.csv; Townsend 1968, "
            "Solid State Commun. 6, 81 (the assignment)"
        ),
        note=(
            "measured: centres, widths, strengths and o/e ratio fitted to the cross sections at "
            "400-700 nm (three bands E⊥c, two and a UV edge E∥c: the model's choice)"
        ),
    ),
    "h-centre": dict(
        unit="1/mm (alpha of the edge at 400 nm, E⊥c)",
        reference_concentration=1.0,
        bands=dict(o=(), e=()),
        tails=dict(o=(400.0, 1.0, 0.45), e=(400.0, 0.8, 0.45)),
        source=(
            "GRS journal no. 1 (2002) fig. 26 caption: Mg2+-trapped-hole colour centres, 'general "
            "absorption in the blue region'"
        ),
        note="modelled as an Urbach tail; its reference point, slope and o/e ratio chosen",
    ),
}

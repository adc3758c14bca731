"""Beryl (Be3Al2Si6O18, hexagonal, uniaxial -): Cr3+ (emerald), Fe2+ and Fe3+ (aquamarine,
heliodor), the Fe2+-Fe3+ intervalence band of deep blue beryl, and manganese (morganite).

Polarizations ``o`` (E⊥c) and ``e`` (E∥c).  Bands are Gaussians in wavenumber
(``"gaussian_wavenumber"``, width = sigma in nm at the centre).

What the sources give, and what they do not
-------------------------------------------
- Cr3+ (measured): G. R. Rossman, Caltech Mineral Spectroscopy Server, polarized spectra of emerald
  GRR 3570 (Afghanistan, 0.859 mm; files Emerald_3570_a.asc, E⊥c, and Emerald_3570_c.asc, E∥c;
  ``tests/data/chromophores/spectra/beryl_cr3_caltech_grr3570.csv``): maxima E⊥c 435 and 605 nm,
  E∥c 420 and 645 nm with the R lines near 683 nm.  Centres, widths, strengths and the o/e ratio
  are fitted to 400-700 nm (``scripts/fit_chromophore_bands.py``).  No analysis of the sample was
  published, so the unit is the alpha (1/mm) at the 605 nm maximum E⊥c (the sample has 1.286/mm);
  the sample's violet edge (below 420 nm E⊥c, not separated from Cr3+: probably Fe3+) is part of
  the band set as an Urbach tail.  D. L. Wood, K. Nassau, Am. Mineral. 53, 777 (1968): E⊥c 430 and
  600 nm, E∥c 420 and 640 nm, within 5 nm of the measured maxima.
- Fe2+ and Fe2+-Fe3+: K. M. Goldman, G. R. Rossman, K. M. Parkin, "Channel constituents in beryl",
  Phys. Chem. Minerals 3, 225 (1978), abstract: Fe2+ in the octahedral site absorbs at about
  820 nm and 970 nm for E∥c; Fe2+ in the channel at 820 nm for E⊥c (and 2100 nm for E∥c);
  deeply blue beryls have an Fe2+/Fe3+ intervalence band at about 700 nm for E∥c.
- Fe3+: Gems & Gemology Fall 2014 Gem News, "Aquamarine with unusually strong dichroism": a peak
  at about 427 nm in both o and e spectra (ferric iron) and one at about 370 nm in the o spectrum;
  the deep blue of aquamarine lies along the e-ray.  Gems & Gemology Spring 2020, "Color
  characteristics of blue to yellow beryl", abstract: yellow from an absorption edge in the
  violet-blue (an Urbach tail here).
- Manganese (morganite): abstract of an IGC-2023 contribution on morganite irradiation
  (impulse.mlz-garching.de record 341406): Mn2+ and Mn3+ give "a series of spin-allowed absorption
  bands between 450 to 600 nm"; pleochroism pale pink (o) and a deeper bluish pink (e), "the
  stronger colour in the extraordinary ray" (gemfame.com morganite page).  The band is placed
  at 525 nm, the middle of that range: a choice.
- V3+ beryl: no source with band positions or a spectrum was readable here; not modelled.

For Fe2+, Fe3+, Fe2+-Fe3+ and Mn no measured spectrum with a stated concentration was readable:
their unit is the peak alpha (1/mm, base e) of the main band, and widths, o/e ratios and strengths
are chosen.  The values of the beryl varieties in :mod:`..varieties` are chosen to give each variety
its trade colour.
"""

from __future__ import annotations

__all__ = ["HOST", "BAND_SETS"]

HOST = dict(
    polarizations=("o", "e"),
    index=("constants", 1.583, 1.577, 0.014),
    source="emerald (beryl), GIA: n_o 1.583, n_e 1.577 (nD), dispersion 0.014; Cauchy fit",
    description="beryl Be3Al2Si6O18, hexagonal, uniaxial (-); o = E⊥c, e = E∥c",
)

_CHOSEN = "band positions from the sources; widths, o/e ratio and absolute strength chosen"

BAND_SETS = {
    "Cr3+": dict(
        unit="1/mm (alpha at the 605 nm maximum, E⊥c)",
        reference_concentration=1.0,
        bands=dict(
            o=(
                (605.1, 35.95, 0.9899, "gaussian"),
                (435.8, 27.55, 1.068, "gaussian"),
                (674.7, 19.66, 0.1395, "gaussian"),
            ),
            e=(
                (629.6, 44.44, 1.21, "gaussian"),
                (420.3, 26.35, 0.8642, "gaussian"),
                (685.9, 2.66, 0.4881, "gaussian"),
                (651.3, 14.87, 0.3392, "gaussian"),
            ),
        ),
        tails=dict(o=(380.0, 0.1967, 0.405)),
        source=(
            "Rossman, Caltech Mineral Spectroscopy Server, emerald GRR 3570 (Afghanistan), 0.859 mm, "
            "E⊥c and E∥c (Emerald_3570_a/_c.asc); tests/data/chromophores/spectra/"
            "beryl_cr3_caltech_grr3570.csv; Wood & Nassau 1968, Am. Mineral. 53, 777 (assignment)"
        ),
        note=(
            "measured: centres, widths, strengths and o/e ratio fitted to the sample's spectra at "
            "400-700 nm; no analysis of the sample, so the unit is its alpha at 605 nm E⊥c; the "
            "number of bands (4T2, 4T1, lines and the sample's violet edge) is the model's choice"
        ),
    ),
    "Fe2+": dict(
        unit="1/mm (peak alpha of the 820 nm band, E∥c)",
        reference_concentration=1.0,
        bands=dict(
            o=((820.0, 110.0, 0.35, "gaussian_wavenumber"),),
            e=((820.0, 110.0, 1.0, "gaussian_wavenumber"), (970.0, 30.0, 0.8, "gaussian_wavenumber")),
        ),
        source=(
            "Goldman, Rossman & Parkin 1978, Phys. Chem. Minerals 3, 225, abstract (octahedral Fe2+ "
            "820 and 970 nm E∥c; channel Fe2+ 820 nm E⊥c)"
        ),
        note=_CHOSEN,
    ),
    "Fe3+": dict(
        unit="1/mm (peak alpha of the 427 nm band, E⊥c)",
        reference_concentration=1.0,
        bands=dict(
            o=((427.0, 8.0, 1.0, "gaussian"), (370.0, 10.0, 1.5, "gaussian")),
            e=((427.0, 8.0, 0.8, "gaussian"),),
        ),
        tails=dict(o=(380.0, 1.0, 0.3), e=(380.0, 0.8, 0.3)),
        source=(
            "Gems & Gemology 50(3) 2014 Gem News, aquamarine dichroism (427 nm o and e, 370 nm o); "
            "Gems & Gemology 56(1) 2020, blue to yellow beryl (yellow from a violet-blue edge)"
        ),
        note=_CHOSEN + "; the edge's alpha at 380 nm and its slope (0.3 eV) chosen",
    ),
    "Fe2+-Fe3+": dict(
        unit="1/mm (peak alpha of the 700 nm band, E∥c)",
        reference_concentration=1.0,
        bands=dict(o=(), e=((700.0, 70.0, 1.0, "gaussian_wavenumber"),)),
        source="Goldman, Rossman & Parkin 1978, abstract (intervalence band ~700 nm, E∥c, deep blue beryl)",
        note=_CHOSEN,
    ),
    "Mn3+": dict(
        unit="1/mm (peak alpha of the 525 nm band, E∥c)",
        reference_concentration=1.0,
        bands=dict(
            o=((525.0, 45.0, 0.35, "gaussian_wavenumber"),),
            e=((525.0, 45.0, 1.0, "gaussian_wavenumber"),),
        ),
        source=(
            "IGC-2023 morganite irradiation abstract (Mn2+/Mn3+ spin-allowed bands 450-600 nm); "
            "morganite pleochroism pale pink (o) / deeper bluish pink (e)"
        ),
        note="one band in the middle of the stated 450-600 nm range; position, width, e/o ratio and "
        "strength chosen",
    ),
}

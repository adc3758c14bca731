"""Beryl (Be3Al2Si6O18, hexagonal, uniaxial -): Cr3+ (emerald), Fe2+ and Fe3+ (aquamarine,
heliodor), the Fe2+-Fe3+ intervalence band of deep blue beryl, and manganese (morganite).

Polarizations ``o`` (E⊥c) and ``e`` (E∥c).  Bands are Gaussians in wavenumber
(``"gaussian_wavenumber"``, width = sigma in nm at the centre).

What the sources give, and what they do not
-------------------------------------------
- Cr3+: D. L. Wood, K. Nassau, Am. Mineral. 53, 777 (1968): E⊥c bands at 430 and 600 nm, E∥c at
  420 and 640 nm (the positions the library has always used); J.-M. Derochette's emerald page
  (jm-derochette.be): the two-band structure at 430 and 600 nm of a 2 mm Brazilian crystal.
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
- V3+ beryl: no source with band positions was found; not modelled.

No absorption coefficient with a stated concentration was readable for any of these, so each
band set's unit is the peak alpha (1/mm, base e) of its main band: the "concentration" is that
band's strength, widths and o/e ratios are chosen, and the values of the beryl varieties in
:mod:`..varieties` are chosen to give each variety its trade colour.
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
        unit="1/mm (peak alpha of the 600 nm band, E⊥c)",
        reference_concentration=1.0,
        bands=dict(
            o=((600.0, 38.0, 1.0, "gaussian_wavenumber"), (430.0, 24.0, 1.3, "gaussian_wavenumber")),
            e=((640.0, 40.0, 0.8, "gaussian_wavenumber"), (420.0, 24.0, 1.1, "gaussian_wavenumber")),
        ),
        source=(
            "Wood & Nassau 1968, Am. Mineral. 53, 777 (E⊥c 430/600 nm, E∥c 420/640 nm); Derochette, "
            "emerald spectra (430/600 nm)"
        ),
        note=_CHOSEN,
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

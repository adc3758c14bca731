"""Grossular garnet (Ca3Al2Si3O12, cubic): V3+ and Cr3+ (tsavorite).

One polarization, ``iso``.  Spin-allowed V3+ bands (Gaussians in wavenumber, sigma in nm at the
centre).

- V3+ positions: "the colour of tsavorite is related significantly to the absorption bands at
  about 430 nm and 605 nm" (Variation in gemological characteristics in tsavorites with different
  tones from East Africa, Crystals 12, 1677 (2022), abstract: V and Cr are responsible); J.
  Feneyrol et al., Eur. J. Mineral. 26, 293 (2014), abstract: V-rich tsavorite absorbs totally
  below 430 nm.
- Cr3+ positions: the Fe-rich, Cr-dominant tsavorite of the Lelatema Mountains (Tanzania), abstract
  "Characterization of new gem Fe-rich tsavorite from Tanzania" (Masaryk University record
  2213857): Fe3+ and Cr3+ bands at 451, 609 and 889 nm, the Cr3+ 4T2 band taken as the 609 nm one;
  the 4T1 band at about 430 nm (Crystals 12, 1677, as above); Feneyrol et al. 2014: the Cr3+
  lines at 697 and 701 nm of Cr-bearing tsavorite.
- Index: n 1.740, dispersion 0.028 (GIA Gem Reference Guide, grossular).

No measured spectrum with a stated concentration was readable for either: each band set's unit is
the peak alpha (1/mm, base e) of its 4T2 band (605 or 609 nm); widths, the 4T1/4T2 ratios, the
lines' strengths and the edge are chosen, and the values of tsavorite in :mod:`..varieties` are
chosen.
"""

from __future__ import annotations

__all__ = ["HOST", "BAND_SETS"]

HOST = dict(
    polarizations=("iso",),
    index=("isotropic_constants", 1.740, 0.028),
    source="grossular, GIA Gem Reference Guide: n 1.740, dispersion 0.028 (nD); Cauchy fit",
    description="grossular garnet, cubic (isotropic)",
)

BAND_SETS = {
    "V3+": dict(
        unit="1/mm (peak alpha of the 605 nm band)",
        reference_concentration=1.0,
        bands=dict(
            iso=((605.0, 40.0, 1.0, "gaussian_wavenumber"), (430.0, 24.0, 1.4, "gaussian_wavenumber")),
        ),
        tails=dict(iso=(390.0, 1.0, 0.3)),
        source=(
            "tsavorite V3+ bands at about 430 and 605 nm (Crystals 12, 1677 (2022), abstract); total "
            "absorption below 430 nm in V-rich stones (Feneyrol et al. 2014, abstract)"
        ),
        note="band positions from the sources; widths, 430/605 ratio, edge and absolute strength chosen",
    ),
    "Cr3+": dict(
        unit="1/mm (peak alpha of the 609 nm band)",
        reference_concentration=1.0,
        bands=dict(
            iso=(
                (609.0, 40.0, 1.0, "gaussian_wavenumber"),
                (430.0, 24.0, 1.2, "gaussian_wavenumber"),
                (697.0, 1.2, 0.06, "gaussian"),
                (701.0, 1.2, 0.06, "gaussian"),
            ),
        ),
        source=(
            "Cr3+ 4T2 band at 609 nm of a Cr-dominant tsavorite (Lelatema, Tanzania; Masaryk University "
            "abstract, record 2213857); 4T1 at about 430 nm (Crystals 12, 1677 (2022), abstract); the "
            "lines at 697 and 701 nm (Feneyrol et al. 2014, Eur. J. Mineral. 26, 293, abstract)"
        ),
        note=(
            "band positions from the sources; widths, 430/609 ratio, line strengths and absolute "
            "strength chosen"
        ),
    ),
}

"""Grossular garnet (Ca3Al2Si3O12, cubic): V3+ (tsavorite).

One polarization, ``iso``.  Spin-allowed V3+ bands (Gaussians in wavenumber, sigma in nm at the
centre).

- Positions: "the colour of tsavorite is related significantly to the absorption bands at about
  430 nm and 605 nm" (Variation in gemological characteristics in tsavorites with different tones
  from East Africa, Crystals 12, 1677 (2022), abstract); J. Feneyrol et al., Eur. J. Mineral. 26,
  293 (2014), abstract: V-rich tsavorite absorbs totally below 430 nm; Cr3+ adds bands at 697 and
  701 nm (not modelled).
- Index: n 1.740, dispersion 0.028 (GIA Gem Reference Guide, grossular).

No absorption coefficient with a stated concentration was readable: the band set's unit is the
peak alpha (1/mm, base e) of the 605 nm band; widths, the 430/605 ratio and the edge are chosen,
and the value of tsavorite in :mod:`..varieties` is chosen.
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
}

"""Spessartine garnet (Mn3Al2Si3O12, cubic): Mn2+ (spessartine, "mandarin" garnet).

One polarization, ``iso``.  Spin-forbidden Mn2+ bands (Gaussians in wavelength, sigma in nm).

- Positions: "bands at 410, 420, 430 nm (or merging to form cutoff below 430 nm); also bands at
  460, 480, 520 nm; possible weak bands at 504 or 573 nm" (Wikipedia "Spessartine" infobox, 2007,
  after the GIA Gem Reference Guide); M. N. Taran, C. A. Geiger et al. (Phys. Chem. Minerals,
  abstract): the Mn2+ spin-forbidden bands of a 97 mol% spessartine and the ligand -> metal
  charge-transfer edge in the near UV (the "cutoff", an Urbach tail here).
- Index: n 1.810, dispersion 0.027 (same infobox, GIA).

No absorption coefficient with a stated concentration was readable: the band set's unit is the
peak alpha (1/mm, base e) of the 410-430 nm group; widths, heights and the edge are chosen, and
the value of spessartine in :mod:`..varieties` is chosen.
"""

from __future__ import annotations

__all__ = ["HOST", "BAND_SETS"]

HOST = dict(
    polarizations=("iso",),
    index=("isotropic_constants", 1.810, 0.027),
    source="spessartine, GIA: n 1.810, dispersion 0.027 (nD); Cauchy fit",
    description="spessartine garnet, cubic (isotropic)",
)

BAND_SETS = {
    "Mn2+": dict(
        unit="1/mm (peak alpha of the 410-430 nm bands)",
        reference_concentration=1.0,
        bands=dict(
            iso=(
                (410.0, 3.0, 1.0, "gaussian"),
                (420.0, 3.0, 1.0, "gaussian"),
                (430.0, 3.0, 1.0, "gaussian"),
                (460.0, 7.0, 0.35, "gaussian"),
                (480.0, 7.0, 0.3, "gaussian"),
                (520.0, 8.0, 0.1, "gaussian"),
            ),
        ),
        tails=dict(iso=(400.0, 0.5, 0.3)),
        source=(
            "spessartine bands 410, 420, 430 (or a cutoff below 430), 460, 480, 520 nm (GIA, as in the "
            "Wikipedia 'Spessartine' infobox); Taran, Geiger et al. (abstract: Mn2+ bands, UV edge)"
        ),
        note="band positions from the sources; widths, heights, the edge and absolute strength chosen",
    ),
}

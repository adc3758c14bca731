"""Andradite garnet (Ca3Fe2Si3O12, cubic): Fe3+ and Cr3+ (demantoid).

One polarization, ``iso``.

- Positions: J. Štubňa et al., "Gem-quality green Cr-bearing andradite (var. demantoid) from
  Dobšiná, Slovakia", Minerals 9, 164 (2019), abstract: "an intense band at 438 nm and two broad
  bands at 587 and 623 nm and last one at 861 nm, which were assigned to Fe3+ and Cr3+";
  transmission below 390 nm, at 700-800 nm and around 530 nm (the green).  Here 438 and 861 nm
  are Fe3+ (spin-forbidden, the 438 nm band a Gaussian in wavelength; 861 nm in wavenumber) and
  587/623 nm Cr3+ (Gaussians in wavenumber): the assignment of each band to one ion is a choice
  (the source assigns the set to both).
- Index: n 1.888, dispersion 0.057 (GIA Gem Reference Guide, andradite).

No absorption coefficient with a stated concentration was readable: each band set's unit is the
peak alpha (1/mm, base e) of its main band; widths and heights are chosen, and the values of
demantoid in :mod:`..varieties` are chosen.
"""

from __future__ import annotations

__all__ = ["HOST", "BAND_SETS"]

HOST = dict(
    polarizations=("iso",),
    index=("isotropic_constants", 1.888, 0.057),
    source="andradite, GIA Gem Reference Guide: n 1.888, dispersion 0.057 (nD); Cauchy fit",
    description="andradite garnet, cubic (isotropic)",
)

_SOURCE = "Štubňa et al. 2019, Minerals 9, 164, abstract (bands 438, 587, 623, 861 nm; Fe3+ and Cr3+)"

BAND_SETS = {
    "Fe3+": dict(
        unit="1/mm (peak alpha of the 438 nm band)",
        reference_concentration=1.0,
        bands=dict(iso=((438.0, 8.0, 1.0, "gaussian"), (861.0, 60.0, 0.25, "gaussian_wavenumber"))),
        source=_SOURCE,
        note="band positions from the source; assignment to Fe3+, widths, heights and strength chosen",
    ),
    "Cr3+": dict(
        unit="1/mm (peak alpha of the 623 nm band)",
        reference_concentration=1.0,
        bands=dict(
            iso=((587.0, 14.0, 0.8, "gaussian_wavenumber"), (623.0, 14.0, 1.0, "gaussian_wavenumber"))
        ),
        source=_SOURCE,
        note="band positions from the source; assignment to Cr3+, widths, heights and strength chosen",
    ),
}

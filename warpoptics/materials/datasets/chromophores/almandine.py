"""Pyrope-almandine garnet ((Mg,Fe)3Al2Si3O12, cubic): Fe2+ (almandine, rhodolite).

One polarization, ``iso``.  The visible Fe2+ bands of almandine are spin-forbidden transitions of
eight-coordinated Fe2+ (Gaussians in wavelength, sigma in nm); the spin-allowed Fe2+ bands lie in
the near infrared and do not colour the stone.

- Positions: the almandine absorption spectrum "usually at 504, 520, and 573 nm, may also have
  faint lines at 423, 460, 610 and 680-690 nm" (Wikipedia "Almandine" infobox, after the GIA Gem
  Reference Guide); M. N. Taran, C. A. Geiger, G. R. Rossman et al. (Phys. Chem. Minerals, and
  Am. Mineral. 108, 1149 (2023), abstracts): several overlapping Fe2+/Fe3+ spin-forbidden bands
  between about 14,000 and 25,000 cm-1 (400-714 nm) whose intensities depend on composition.
- Index: n 1.790, dispersion 0.024 (the same infobox, GIA); rhodolite (pyrope-almandine) is
  given this host too.

No absorption coefficient with a stated concentration was readable: the band set's unit is the
peak alpha (1/mm, base e) of the 573 nm band; widths and relative heights are chosen, and the
values of almandine and rhodolite in :mod:`..varieties` are chosen.
"""

from __future__ import annotations

__all__ = ["HOST", "BAND_SETS"]

HOST = dict(
    polarizations=("iso",),
    index=("isotropic_constants", 1.790, 0.024),
    source="almandine, GIA: n 1.790, dispersion 0.024 (nD); Cauchy fit",
    description="pyrope-almandine garnet, cubic (isotropic)",
)

BAND_SETS = {
    "Fe2+": dict(
        unit="1/mm (peak alpha of the 573 nm band)",
        reference_concentration=1.0,
        bands=dict(
            iso=(
                (504.0, 5.0, 0.9, "gaussian"),
                (520.0, 5.0, 0.8, "gaussian"),
                (573.0, 15.0, 1.0, "gaussian"),
                (423.0, 8.0, 0.25, "gaussian"),
                (460.0, 10.0, 0.3, "gaussian"),
                (610.0, 5.0, 0.2, "gaussian"),
                (685.0, 10.0, 0.06, "gaussian"),
            ),
        ),
        tails=dict(iso=(400.0, 0.4, 0.35)),
        source=(
            "almandine spectrum 504, 520, 573 nm, faint 423, 460, 610, 680-690 nm (GIA, as in the "
            "Wikipedia 'Almandine' infobox); Taran, Geiger, Rossman et al. 2023 (abstracts)"
        ),
        note=(
            "band positions from the sources; widths, relative heights (strong 504/520/573, faint "
            "others), the violet edge (alpha at 400 nm, 0.35 eV slope) and absolute strength chosen"
        ),
    ),
}

"""Spinel (MgAl2O4, cubic): Cr3+ (red spinel).

One polarization, ``iso``.  Bands are Gaussians in wavelength (sigma in nm), as chosen for Cr3+ in
corundum.

- Cr3+: 4A2 -> 4T2 near 540 nm and 4A2 -> 4T1 near 400 nm (W. Mikenda, A. Preisinger, J. Lumin. 26,
  53 and 67 (1981), the positions the library's fluorescent red spinel already uses).
  T. Pluthametwisute et al., Minerals 12, 928 (2022), abstract: the red of spinel comes from Cr
  and V together; V is not modelled (no band positions found).

No absorption coefficient with a stated concentration was readable: the band set's unit is the
peak alpha (1/mm, base e) of the 540 nm band, widths and the 400/540 ratio are chosen, and the
value of red spinel in :mod:`..varieties` is chosen.
"""

from __future__ import annotations

__all__ = ["HOST", "BAND_SETS"]

HOST = dict(
    polarizations=("iso",),
    index=("page", "main/MgAl2O4/Tropf"),
    source="refractiveindex.info main/MgAl2O4/Tropf",
    description="spinel MgAl2O4, cubic (isotropic)",
)

BAND_SETS = {
    "Cr3+": dict(
        unit="1/mm (peak alpha of the 540 nm band)",
        reference_concentration=1.0,
        bands=dict(
            iso=((540.0, 36.0, 1.0, "gaussian"), (400.0, 32.0, 1.9, "gaussian")),
        ),
        source="Mikenda & Preisinger 1981, J. Lumin. 26, 53 and 67 (Cr3+ 4T2 ~540 nm, 4T1 ~400 nm)",
        note="band positions from the source; widths, 4T1/4T2 ratio and absolute strength chosen",
    ),
}

"""Zoisite (Ca2Al3(SiO4)(Si2O7)O(OH), orthorhombic, biaxial +; gem variety tanzanite): V3+ and the
455 nm band that heat treatment removes.

Polarizations ``x``, ``y``, ``z``: D along the principal axes X, Y, Z (n_alpha, n_beta, n_gamma).

What the sources give, and what they do not
-------------------------------------------
- M. O'Donoghue (ed.), *Gems*, 6th ed. (2006), zoisite (as quoted by gemfame.com): tanzanite
  "shows an absorption band centred at 595 nm with fainter bands at 528 and 455 nm"; trichroism
  blue, red-violet and green/gold (unheated).  The band positions come from there.
- T. Pluthametwisute et al., "Cause of color modification in tanzanite after heat treatment",
  Molecules 25, 3743 (2020), abstract: heating turns the trichroic (violet, blue, brown) crystal
  dichroic violet-blue; the violet-blue absorption band at 450-460 nm and the green band near
  520 nm decrease along the c axis; vanadium is the colouring agent (its oxidation state rises).
- P. Bačík et al., Mineral. Mag. (2023), abstract: vanadium is the dominant trace element and
  chromophore of tanzanite.
- Assignment (as in the library's earlier tanzanite entry): D along X red-violet (the 528 nm band
  strongest), along Y blue (595 nm strongest), along Z yellow-brown before heating (the 455 nm
  band) and violet after it.  No polarized absorption coefficients were available: widths, the
  ratios between axes and the strengths are chosen; the unit is the peak alpha of the 595 nm
  band along Y.
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
        unit="1/mm (peak alpha of the 595 nm band, D along Y)",
        reference_concentration=1.0,
        bands=dict(
            x=((528.0, 38.0, 0.9, _GW), (595.0, 48.0, 0.12, _GW)),
            y=((595.0, 48.0, 1.0, _GW), (528.0, 38.0, 0.12, _GW)),
            z=((595.0, 48.0, 0.45, _GW), (528.0, 38.0, 0.25, _GW)),
        ),
        source=(
            "O'Donoghue 2006, Gems (6th ed.), zoisite: bands at 595 and 528 nm; Pluthametwisute "
            "et al. 2020, Molecules 25, 3743 (abstract: vanadium, the 520 nm band)"
        ),
        note=(
            "band positions from the sources' text; the axis assignment follows the stated "
            "pleochroism; widths, ratios and strength chosen (no measured absorption coefficients)"
        ),
    ),
    "V 455 nm": dict(
        unit="1/mm (peak alpha of the 455 nm band, D along Z)",
        reference_concentration=1.0,
        bands=dict(
            x=(),
            y=(),
            z=((455.0, 32.0, 1.0, _GW),),
        ),
        source=(
            "O'Donoghue 2006 (the 455 nm band); Pluthametwisute et al. 2020, Molecules 25, 3743 "
            "(abstract: the 450-460 nm band along c falls on heating, V oxidised)"
        ),
        note=(
            "present in unheated (brownish) zoisite, absent from heated tanzanite; width and "
            "strength chosen; placed along Z (the yellow-brown direction)"
        ),
    ),
}

"""Chrysoberyl (BeAl2O4, orthorhombic, biaxial +): Cr3+ (alexandrite).

Polarizations ``x``, ``y``, ``z``: light polarized along the principal axes X, Y, Z (n_alpha,
n_beta, n_gamma).  Bands are Gaussians in wavelength (sigma in nm; the shape is a choice, as for
Cr3+ in corundum).

What the sources give, and what they do not
-------------------------------------------
- The alexandrite spectrum: "transmission maxima in the blue-green and red regions and ... a
  transmission minimum in the yellow region" (E. Gübelin, K. Schmetzer, "Gemstones with
  alexandrite effect", Gems & Gemology 18(4), 1982, abstract); intense Cr3+ absorption over the
  yellow, 520-620 nm (bangkokgemsmarket.com alexandrite page), with its maximum near 570-580 nm
  (grokipedia "Alexandrite effect", summarising the same literature).  J.-M. Derochette
  (jm-derochette.be, alexandrite spectra of a 0.5 mm Brazilian section): the bimodal Cr3+
  absorption "quite comparable to ruby", pleochroism green / yellow / pink.
- Y. Liu, J. E. Shigley, E. Fritsch, S. Hemphill, Mineral. Mag. 59, 111 (1995), abstract: the
  spectra along the three crystallographic axes are "generally similar"; the colour change is
  largest for light travelling along a.
- Not found in a source readable here: the band positions per principal axis, the position of
  the 4T1 band (placed near 420 nm, as in ruby, after Derochette's comparison), the assignment
  of the pleochroic colours to X, Y, Z, and any absolute absorption.  The per-axis positions
  (570-585 nm, within the stated 520-620 nm range), widths and strengths are chosen so that D
  along X is purple-red, along Y orange-yellow and along Z green (the trichroism gemmology texts
  describe).

The band set's unit is the peak alpha (1/mm, base e) of the 4T2 band for D along X; the value of
alexandrite in :mod:`..varieties` is chosen.
"""

from __future__ import annotations

__all__ = ["HOST", "BAND_SETS"]

HOST = dict(
    polarizations=("x", "y", "z"),
    index=("biaxial", 1.746, 1.749, 1.755, 0.015),
    source=(
        "chrysoberyl: n_alpha 1.746, n_beta 1.749, n_gamma 1.755 (nD; Deutsche Gemmologische "
        "Gesellschaft table), biaxial (+), dispersion 0.015 (GIA); Cauchy fits"
    ),
    description="chrysoberyl BeAl2O4, orthorhombic, biaxial (+); x, y, z = D along X, Y, Z",
)

BAND_SETS = {
    "Cr3+": dict(
        unit="1/mm (peak alpha of the 4T2 band, D along X)",
        reference_concentration=1.0,
        bands=dict(
            x=((575.0, 36.0, 1.0, "gaussian"), (420.0, 32.0, 1.5, "gaussian")),
            y=((570.0, 36.0, 0.9, "gaussian"), (418.0, 32.0, 1.6, "gaussian")),
            z=((585.0, 38.0, 1.1, "gaussian"), (425.0, 32.0, 1.2, "gaussian")),
        ),
        source=(
            "Gübelin & Schmetzer 1982, Gems & Gemology 18(4) (transmission minimum in the yellow, "
            "maxima blue-green and red); Cr3+ absorption 520-620 nm, maximum ~570-580 nm; Liu et al. "
            "1995, Mineral. Mag. 59, 111 (spectra along a, b, c generally similar)"
        ),
        note=(
            "only the band region and maximum are sourced: per-axis positions within 570-585 nm, the "
            "4T1 band near 420 nm, widths, pleochroic assignment and strengths chosen"
        ),
    ),
}

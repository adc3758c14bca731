"""Topaz (Al2SiO4(F,OH)2, orthorhombic, biaxial +): chromium (imperial topaz's pink-orange) and the
yellow-brown colour centre.

Polarizations ``x``, ``y``, ``z``: D along the principal axes X, Y, Z (n_alpha, n_beta, n_gamma).

What the sources give, and what they do not
-------------------------------------------
- Bao Hanwei, Pei Jingcheng, "Gemmological and spectroscopic characteristics of imperial topaz",
  Journal of Gems & Gemmology 26(6), 25-33 (2024), abstract: absorption "around 420 nm and
  530 nm" from chromium (the authors write Cr4+; most of the literature assigns the pink of topaz
  to Cr3+) gives imperial topaz its orange; pleochroism "medium orange - light orange".
- G. R. Rossman, "The Color of Topaz" (2011, abstract): apart from pink, topaz colours come from
  natural or laboratory irradiation; many brown topazes fade in sunlight.  The yellow-brown is
  modelled as a UV edge (an Urbach tail), the absorption of O- hole / Fe3+ charge-transfer
  centres proposed for yellow topaz.
- No polarized spectra or absorption coefficients were available: the same bands are used for X,
  Y, Z (weaker along X, chosen), widths and strengths are chosen.
"""

from __future__ import annotations

__all__ = ["HOST", "BAND_SETS"]

HOST = dict(
    polarizations=("x", "y", "z"),
    index=("biaxial", 1.619, 1.621, 1.627, 0.014),
    source=(
        "topaz: n_alpha 1.619, n_gamma 1.627 (nD), dispersion 0.014 (GIA); n_beta 1.621 = n_alpha "
        "+ 0.002 (Handbook of Mineralogy index ranges), biaxial (+); Cauchy fits"
    ),
    description="topaz, orthorhombic, biaxial (+)",
)

_GW = "gaussian_wavenumber"

_NOTE = (
    "band positions from the source's text; the same bands for X, Y, Z (X weaker), widths and "
    "strengths chosen (no polarized or absolute data available)"
)

BAND_SETS = {
    "Cr": dict(
        unit="1/mm (peak alpha of the 530 nm band, D along Y and Z)",
        reference_concentration=1.0,
        bands=dict(
            x=((530.0, 42.0, 0.7, _GW), (420.0, 30.0, 0.7, _GW)),
            y=((530.0, 42.0, 1.0, _GW), (420.0, 30.0, 1.0, _GW)),
            z=((530.0, 42.0, 1.0, _GW), (420.0, 30.0, 1.0, _GW)),
        ),
        source=(
            "Bao & Pei 2024, J. Gems & Gemmology 26(6), 25 (abstract: chromium bands around 420 "
            "and 530 nm give imperial topaz its orange)"
        ),
        note=_NOTE,
    ),
    "colour centre": dict(
        unit="1/mm (alpha of the UV edge at 400 nm, D along Y and Z)",
        reference_concentration=1.0,
        bands=dict(x=(), y=(), z=()),
        tails=dict(x=(400.0, 0.7, 0.3), y=(400.0, 1.0, 0.3), z=(400.0, 1.0, 0.3)),
        source=(
            "Rossman 2011, The Color of Topaz (abstract: yellow-brown from irradiation); yellow "
            "topaz O2- -> Fe3+ charge transfer and O- centres (as proposed for natural yellow topaz)"
        ),
        note="an Urbach edge; its value at 400 nm, slope (0.3 eV) and X/Y/Z ratios chosen",
    ),
}

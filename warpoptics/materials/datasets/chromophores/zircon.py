"""Zircon (ZrSiO4, tetragonal, uniaxial +): the blue of heat-treated zircon and the brown centre.

Polarizations ``o`` (E⊥c) and ``e`` (E∥c).

What the sources give, and what they do not
-------------------------------------------
- N. D. Renfro, "Reversible color modification of blue zircon by long-wave ultraviolet
  radiation", Gems & Gemology 52(3) (2016), abstract: "blue color in zircon is due to a broad
  absorption band in the ordinary ray, starting at 500 nm and centered at approximately 650 nm";
  long-wave UV induces "a broad band centered at 485 nm that was responsible for the brown color".
- Caltech Mineral Spectroscopy Server, zircon page (G. R. Rossman): "U4+ substituting in zircon
  causes the blue color of heat-treated zircon"; radiation damage gives red-brown colours that
  heating removes.
- M. Zeug et al., "Blue zircon from Ratanakiri, Cambodia", J. Gemmology 36, 112 (2018), abstract:
  a strongly pleochroic band at 18,200-13,000 cm-1 (550-770 nm) causes the treated blue; its
  assignment "remains unresolved" (it differs from U4+-doped synthetic zircon); ~120 ppm U.
  Hence the name "blue centre" (U4+ per Rossman, unresolved per Zeug et al.).
- No absorption coefficients were available: the width (sigma 55 nm, from "starting at 500 nm"),
  the small E∥c share and the strengths are chosen.
"""

from __future__ import annotations

__all__ = ["HOST", "BAND_SETS"]

HOST = dict(
    polarizations=("o", "e"),
    index=("constants", 1.925, 1.984, 0.039),
    source="high zircon, GIA: n_o 1.925, n_e 1.984 (nD), dispersion 0.039; Cauchy fit",
    description="zircon ZrSiO4, tetragonal, uniaxial (+); o = E⊥c, e = E∥c",
)

_GW = "gaussian_wavenumber"

BAND_SETS = {
    "blue centre": dict(
        unit="1/mm (peak alpha of the 650 nm band, E⊥c)",
        reference_concentration=1.0,
        bands=dict(
            o=((650.0, 55.0, 1.0, _GW),),
            e=((650.0, 55.0, 0.1, _GW),),
        ),
        source=(
            "Renfro 2016, Gems & Gemology 52(3) (abstract: the blue from a broad ordinary-ray band "
            "from 500 nm, centred near 650 nm); Caltech zircon page (U4+); Zeug et al. 2018, "
            "J. Gemmology 36, 112 (band at 550-770 nm, assignment unresolved)"
        ),
        note=(
            "centre and the ordinary-ray polarization from the sources' text; width, the 10 % "
            "E∥c share and the strength chosen (no measured absorption coefficient available)"
        ),
    ),
    "brown centre": dict(
        unit="1/mm (peak alpha of the 485 nm band)",
        reference_concentration=1.0,
        bands=dict(
            o=((485.0, 50.0, 1.0, _GW),),
            e=((485.0, 50.0, 1.0, _GW),),
        ),
        source=(
            "Renfro 2016, Gems & Gemology 52(3) (abstract: the UV-induced broad band centred at "
            "485 nm, responsible for the brown colour)"
        ),
        note="centre from the source's text; width, polarization and strength chosen",
    ),
}

"""Tourmaline (elbaite group, trigonal, uniaxial −): Mn3+ (rubellite), Fe2+, Fe2+ enhanced by
Fe3+, Fe2+-Ti4+ charge transfer and Cu2+ (Paraíba).

Polarizations ``o`` (E⊥c) and ``e`` (E∥c).

What the sources give, and what they do not
-------------------------------------------
- Mn3+: G. H. Manning, "An optical absorption study of the origin of colour and pleochroism in
  pink and brown tourmalines", Can. Mineral. 9, 678 (1969), abstract: pink tourmalines have a
  band at 19,000 cm-1 (520 nm), brown ones at 22,000 cm-1 (450 nm, assigned there to Ti); both
  strongest with the electric vector in the (001) plane (E⊥c).  G. R. Rossman, "Rubellite color"
  (Caltech, 2019): rubellite's colour is dominated by Mn3+, made from Mn2+ by natural
  irradiation.
- Fe2+: H. F. Simon, MIT thesis (1973), abstract: the Fe2+ crystal-field band near 9000 cm-1
  (1111 nm) and a component at 14000 cm-1 (714 nm); J.-M. Derochette's green tourmaline spectra
  (Fe2+ bands near 700 and 1100 nm).  S. M. Mattson, G. R. Rossman, "Fe2+-Fe3+ interactions in
  tourmaline", Phys. Chem. Minerals 14, 163 (1987), abstract: at low iron the Fe2+ absorption is
  about the same for E∥c and E⊥c; at high iron the E⊥c intensity grows more than ten times as
  much as E∥c (Fe2+ intensified by adjacent Fe3+, no new band) - the "Fe2+-Fe3+" set below.
- Fe2+-Ti4+: G. R. Rossman, S. M. Mattson, Am. Mineral. 71, 599 (1986), abstract: brown from
  Fe2+-Ti4+ charge transfer; the 450 nm position and E⊥c polarization from Manning 1969.
- Cu2+: G. R. Rossman, E. Fritsch, J. E. Shigley, "Origin of color in cuprian elbaite from São
  José de Batalha, Paraíba, Brazil", Am. Mineral. 76, 1479 (1991), abstract: "two bands with
  maxima in the 695- to 940-nm region that are more intense in the E⊥c direction"; up to 1.4 wt%
  Cu.  The two bands are placed at the ends of that range.  Typical turquoise-blue Paraíba
  elbaite: 1.5-2.3 wt% CuO (Mineralogical Record, "Cuprian elbaite", the Batalha mine).
- No absorption coefficients were available: widths, o/e ratios beyond the stated orderings, and
  strengths are chosen.
"""

from __future__ import annotations

__all__ = ["HOST", "BAND_SETS"]

HOST = dict(
    polarizations=("o", "e"),
    index=("constants", 1.644, 1.624, 0.017),
    source=(
        "tourmaline (elbaite), GIA Gem Reference Guide: RI 1.624-1.644, uniaxial (-), dispersion "
        "0.017; n_o 1.644, n_e 1.624 (nD); Cauchy fit"
    ),
    description="tourmaline (elbaite), trigonal, uniaxial (-); o = E⊥c, e = E∥c",
)

_GW = "gaussian_wavenumber"

_NOTE = (
    "band positions and the stronger polarization from the source's text; widths, ratios and the "
    "absolute strength chosen (no measured absorption coefficients available)"
)

BAND_SETS = {
    "Mn3+": dict(
        unit="1/mm (peak alpha of the 520 nm band, E⊥c)",
        reference_concentration=1.0,
        bands=dict(
            o=((520.0, 40.0, 1.0, _GW),),
            e=((520.0, 40.0, 0.35, _GW),),
        ),
        source=(
            "Manning 1969, Can. Mineral. 9, 678 (abstract: pink tourmaline band at 19,000 cm-1, "
            "strongest E⊥c); Rossman 2019, rubellite colour (Mn3+)"
        ),
        note=_NOTE,
    ),
    "Fe2+": dict(
        unit="wt% FeO",
        reference_concentration=1.0,
        bands=dict(
            o=((714.0, 73.0, 0.25, _GW), (1111.0, 185.0, 0.5, _GW)),
            e=((714.0, 73.0, 0.25, _GW), (1111.0, 185.0, 0.5, _GW)),
        ),
        source=(
            "Simon 1973, MIT thesis (abstract: Fe2+ at 9000 and 14000 cm-1); Mattson & Rossman "
            "1987, Phys. Chem. Minerals 14, 163 (at low Fe, E∥c ~ E⊥c)"
        ),
        note=_NOTE,
    ),
    "Fe2+-Fe3+": dict(
        unit="wt% FeO in Fe2+-Fe3+ neighbour pairs",
        reference_concentration=1.0,
        bands=dict(
            o=((714.0, 73.0, 1.0, _GW), (1111.0, 185.0, 2.0, _GW)),
            e=((714.0, 73.0, 0.08, _GW), (1111.0, 185.0, 0.16, _GW)),
        ),
        source=(
            "Mattson & Rossman 1987, Phys. Chem. Minerals 14, 163 (abstract: Fe2+ bands "
            "intensified by adjacent Fe3+, E⊥c growing > 10x E∥c)"
        ),
        note=_NOTE + "; E⊥c/E∥c = 12.5, above the source's 'more than ten times'",
    ),
    "Fe2+-Ti4+": dict(
        unit="1/mm (peak alpha of the 450 nm band, E⊥c)",
        reference_concentration=1.0,
        bands=dict(
            o=((450.0, 36.0, 1.0, _GW),),
            e=((450.0, 36.0, 0.35, _GW),),
        ),
        source=(
            "Rossman & Mattson 1986, Am. Mineral. 71, 599 (abstract: brown from Fe2+-Ti4+); "
            "Manning 1969 (the 22,000 cm-1 band, strongest E⊥c)"
        ),
        note=_NOTE,
    ),
    "Cu2+": dict(
        unit="wt% CuO",
        reference_concentration=1.5,
        bands=dict(
            o=((695.0, 60.0, 1.0, _GW), (940.0, 110.0, 1.0, _GW)),
            e=((695.0, 60.0, 0.4, _GW), (940.0, 110.0, 0.4, _GW)),
        ),
        source=(
            "Rossman, Fritsch & Shigley 1991, Am. Mineral. 76, 1479 (abstract: two Cu2+ bands with "
            "maxima in the 695-940 nm region, more intense E⊥c)"
        ),
        note=_NOTE + "; the two centres are the ends of the stated range",
    ),
}

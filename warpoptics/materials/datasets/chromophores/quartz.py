"""Quartz (alpha-SiO2, trigonal, uniaxial +): the amethyst centre, citrine's Fe3+ edge and the smoky
quartz centres.

Polarizations ``o`` (E⊥c) and ``e`` (E∥c).  Bands are Gaussians in wavenumber
(``"gaussian_wavenumber"``, width = sigma in nm at the centre).

What the sources give, and what they do not
-------------------------------------------
- Amethyst: G. Lehmann, W. J. Moore, "Color center in amethyst quartz", Science 152, 1061 (1966),
  abstract: the colour-centre absorption "near 545 mµ", proportional to the Fe3+-hole EPR signal.
  S. Pancharatnam, Proc. Indian Acad. Sci. A 40, 196 (1954), abstract: amethyst is trichroic with
  absorption maxima near 500, 525 and 575 nm for its three vibration directions (a monoclinic
  frame, not o/e).  No absorption coefficient with a stated concentration was found: the band is
  placed at 545 nm for both o and e, and its width, its e/o ratio and its strength are chosen.
- Smoky quartz: K. Nassau, B. E. Prescott, "Smoky, blue, greenish yellow, and other
  irradiation-related colors in quartz", Mineral. Mag. 41, 301 (1977), abstract: the smoky colour
  is the A3 band at 2.90 eV (427.5 nm); the blue A1 and A2 bands lie at 1.85 eV (670.2 nm) and
  2.55 eV (486.2 nm); greenish-yellow colours come from the tail of a strong UV band.  Positions
  from there; widths, polarization and strengths chosen.
- Citrine (heated amethyst, Fe3+): G. R. Rossman, "Colored varieties of the silica minerals",
  Rev. Mineral. 29, 433 (1994), and A. J. Cohen, F. Hassan, Am. Mineral. 59, 719 (1974)
  (abstracts: Fe3+ in quartz and its heat/radiation-induced centres).  The yellow is modelled as
  the long-wavelength tail of the UV O2- -> Fe3+ charge-transfer absorption (an Urbach edge); the
  edge's alpha at 400 nm and its slope are chosen.

Hence every band set here has the unit "peak alpha (1/mm)" of its main band: the "concentration"
is the band's strength itself, and the values in :mod:`..varieties` are chosen to give each
variety its trade colour (not measured).
"""

from __future__ import annotations

__all__ = ["HOST", "BAND_SETS"]

HOST = dict(
    polarizations=("o", "e"),
    index=("pages", "main/SiO2/Ghosh-o", "main/SiO2/Ghosh-e"),
    source="refractiveindex.info main/SiO2/Ghosh-o/-e",
    description="alpha-quartz SiO2, trigonal, uniaxial (+); o = E⊥c, e = E∥c",
)

_POSITIONS_ONLY = (
    "band positions from the source's text; widths, o/e ratio and absolute strength chosen "
    "(no measured absorption coefficient with a concentration was available)"
)

BAND_SETS = {
    "amethyst centre": dict(
        unit="1/mm (peak alpha of the 545 nm band, E⊥c)",
        reference_concentration=1.0,
        bands=dict(
            o=((545.0, 45.0, 1.0, "gaussian_wavenumber"),),
            e=((545.0, 45.0, 0.7, "gaussian_wavenumber"),),
        ),
        source=(
            "Lehmann & Moore 1966, Science 152, 1061 (abstract: the amethyst colour-centre band "
            "near 545 nm); Pancharatnam 1954, Proc. Indian Acad. Sci. A 40, 196 (trichroic maxima "
            "500/525/575 nm)"
        ),
        note=_POSITIONS_ONLY,
    ),
    "Fe3+": dict(
        unit="1/mm (alpha of the UV charge-transfer edge at 400 nm, E⊥c)",
        reference_concentration=1.0,
        bands=dict(o=(), e=()),
        tails=dict(o=(400.0, 1.0, 0.25), e=(400.0, 1.0, 0.25)),
        source=(
            "Rossman 1994, Rev. Mineral. 29, 433 and Cohen & Hassan 1974, Am. Mineral. 59, 719 "
            "(abstracts: citrine's colour from Fe3+, the heated amethyst precursor); an Urbach "
            "edge for the O2- -> Fe3+ charge-transfer tail"
        ),
        note="edge alpha at 400 nm and slope (0.25 eV) chosen; no measured edge was available",
    ),
    "smoky centre": dict(
        unit="1/mm (peak alpha of the A3 band at 427.5 nm, E⊥c)",
        reference_concentration=1.0,
        bands=dict(
            o=((427.5, 59.0, 1.0, "gaussian_wavenumber"),),
            e=((427.5, 59.0, 1.0, "gaussian_wavenumber"),),
        ),
        source=(
            "Nassau & Prescott 1977, Mineral. Mag. 41, 301 (abstract: the smoky A3 band at "
            "2.90 eV = 427.5 nm)"
        ),
        note=_POSITIONS_ONLY,
    ),
    "blue centres": dict(
        unit="1/mm (peak alpha of the A1 band at 670.2 nm, E⊥c)",
        reference_concentration=1.0,
        bands=dict(
            o=((670.2, 70.0, 1.0, "gaussian_wavenumber"), (486.2, 45.0, 0.5, "gaussian_wavenumber")),
            e=((670.2, 70.0, 1.0, "gaussian_wavenumber"), (486.2, 45.0, 0.5, "gaussian_wavenumber")),
        ),
        source=(
            "Nassau & Prescott 1977, Mineral. Mag. 41, 301 (abstract: the A1 and A2 bands at "
            "1.85 and 2.55 eV = 670.2 and 486.2 nm give the blue colour)"
        ),
        note=_POSITIONS_ONLY + "; A2/A1 height ratio 0.5 chosen",
    ),
}

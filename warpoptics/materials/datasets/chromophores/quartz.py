"""Quartz (alpha-SiO2, trigonal, uniaxial +): the amethyst centre, citrine's Fe3+ edge and the smoky
quartz centres.

Polarizations ``o`` (E⊥c) and ``e`` (E∥c).  Bands are Gaussians in wavenumber
(``"gaussian_wavenumber"``, width = sigma in nm at the centre).

What the sources give, and what they do not
-------------------------------------------
- Amethyst (E⊥c measured): G. R. Rossman, Caltech Mineral Spectroscopy Server, amethyst from the
  Anahi mine, Bolivia, unheated, file ameth.bo: a 6.17 mm slab cut perpendicular to c (o-ray only;
  ``tests/data/chromophores/spectra/quartz_amethyst_caltech_ameth_bo.csv``): the colour-centre band
  with its maximum at 542-545 nm (G. Lehmann, W. J. Moore, Science 152, 1061 (1966), abstract:
  "near 545 mµ") and a rise below 450 nm.  The band's centre, width and strength are fitted to
  400-700 nm (``scripts/fit_chromophore_bands.py``) together with the strength of the Fe3+ edge
  below (its shape unchanged), to which the rise is attributed (a choice: the Anahi mine is the
  ametrine locality).  No analysis with the file: the unit is the band's peak alpha (1/mm) E⊥c
  (the sample has 0.080/mm, and Fe3+ 0.072).  No E∥c spectrum was available: the e-ray is the
  same band at 0.7 times the o-ray's, chosen.  S. Pancharatnam, Proc. Indian
  Acad. Sci. A 40, 196 (1954), abstract: amethyst is trichroic with maxima near 500, 525 and
  575 nm in a monoclinic frame (not used).
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

Hence every band set here has the unit "alpha (1/mm)" of its main band at its maximum: the
"concentration" is the band's strength itself, and the values in :mod:`..varieties` are chosen to
give each variety its trade colour (not measured).
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
        unit="1/mm (peak alpha of the band, E⊥c)",
        reference_concentration=1.0,
        bands=dict(
            o=((544.6, 54.84, 1.0, "gaussian_wavenumber"),),
            e=((544.6, 54.84, 0.7, "gaussian_wavenumber"),),
        ),
        source=(
            "Rossman, Caltech Mineral Spectroscopy Server, amethyst, Anahi (Bolivia), unheated, "
            "6.17 mm, E⊥c (ameth.bo); tests/data/chromophores/spectra/"
            "quartz_amethyst_caltech_ameth_bo.csv; Lehmann & Moore 1966, Science 152, 1061 (the "
            "colour centre near 545 nm)"
        ),
        note=(
            "E⊥c measured: the band fitted at 400-700 nm with the sample's Fe3+ edge (unit: its peak "
            "alpha); no E∥c spectrum: the e/o ratio 0.7 is chosen"
        ),
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

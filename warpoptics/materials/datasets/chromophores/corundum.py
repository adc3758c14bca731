"""Corundum (alpha-Al2O3, trigonal, uniaxial -): Cr3+ (ruby), Fe3+ (yellow sapphire), the
Fe2+-Ti4+ intervalence charge transfer (blue sapphire) and the Mg-related trapped-hole centre.

Polarizations ``o`` (E⊥c) and ``e`` (E∥c).  The charge-transfer bands are Gaussians in wavenumber
(``"gaussian_wavenumber"``, width = sigma in nm at the centre); the Cr3+ bands and the sharp
spin-forbidden Fe3+ lines are Gaussians in wavelength (the Cr3+ band shape is a choice: a Gaussian
in wavelength falls off faster on the red side of the 556 nm band than one in wavenumber).

What the sources give, and what they do not
-------------------------------------------
- Cr3+: D. S. McClure, J. Chem. Phys. 36, 2757 (1962): 4A2 -> 4T2 at 556 nm and 4A2 -> 4T1 at
  407 nm for E⊥c, 570 and 400 nm for E∥c (the positions the library has always used).  The
  GRS (GemResearch Swisslab) journal no. 1 (2002), p. 16, fig. 26 caption, gives the same bands
  "centered at 405-410 nm and 550-560 nm" in natural sapphire.
- Fe3+: same GRS caption: the Fe3+ line at 388 nm and the Fe3+-pair line at 450 nm, whose
  intensity grows with Fe; R. G. Burns, *Mineralogical Applications of Crystal Field Theory*
  (2nd ed. 1993), fig. 3.16 caption: the polarized yellow-sapphire spectrum after Ferguson &
  Fielding (1972), with a paired-Fe3+ band near 17,600 cm-1 (568 nm).  The violet edge is the
  long-wavelength tail of the O2- -> Fe3+ charge transfer in the UV (K. Tippins, Phys. Rev. B 1,
  126 (1970), abstract: strong charge-transfer peaks of Fe3+ and other ions at 3-9 eV, widths
  about 0.7 eV): an Urbach tail here.
- Fe2+-Ti4+: "the 563 nm broad absorption band contributed by the intervalence charge transfer
  of Fe2+-Ti4+" (abstract of a heat-treatment study of purplish-red sapphire, as indexed by
  researcher.life); H. R. Townsend, Solid State Commun. 6, 81 (1968), "Visible charge transfer
  band in blue sapphire" (title).  The E⊥c band is placed at 563 nm.  The E∥c band's position
  (700 nm, the value usually quoted for the e-ray of blue sapphire) was not found in a source
  readable here: it is a choice, and so is its strength.
- Trapped-hole centre (Mg2+-related, "h-centre"): GRS journal no. 1 (2002), fig. 26 caption:
  "Mg2+-trapped hole colour centres, general absorption in the blue region".  Modelled as an
  Urbach tail; its reference point and slope are chosen.
- V3+ (named by E. V. Dubinsky, J. Stone-Sundberg, J. L. Emmett, Gems & Gemology 56(1), 2-28
  (2020), with the absorption cross section of every corundum chromophore): that paper's
  numbers were not readable here, so V3+ is not modelled and no band set uses its cross sections.

No absorption coefficient with a stated concentration was readable for any of these, so each
band set's unit is the peak alpha (1/mm, base e) of its main band: the "concentration" is that
band's strength, widths and o/e ratios are chosen, and the values of the corundum varieties in
:mod:`..varieties` are chosen to give each variety its trade colour.
"""

from __future__ import annotations

__all__ = ["HOST", "BAND_SETS"]

HOST = dict(
    polarizations=("o", "e"),
    index=("pages", "main/Al2O3/Malitson-o", "main/Al2O3/Malitson-e"),
    source="refractiveindex.info main/Al2O3/Malitson-o/-e",
    description="corundum alpha-Al2O3, trigonal, uniaxial (-); o = E⊥c, e = E∥c",
)

_CHOSEN = "band positions from the sources; widths, o/e ratio and absolute strength chosen"

BAND_SETS = {
    "Cr3+": dict(
        unit="1/mm (peak alpha of the 556 nm band, E⊥c)",
        reference_concentration=1.0,
        bands=dict(
            o=((556.0, 36.0, 1.0, "gaussian"), (407.0, 32.0, 1.9, "gaussian")),
            e=((570.0, 38.0, 0.75, "gaussian"), (400.0, 32.0, 1.5, "gaussian")),
        ),
        source=(
            "McClure 1962, J. Chem. Phys. 36, 2757 (4T2 556/570 nm, 4T1 407/400 nm for E⊥c/E∥c); "
            "GRS journal no. 1 (2002) fig. 26 caption (405-410 and 550-560 nm)"
        ),
        note=_CHOSEN,
    ),
    "Fe3+": dict(
        unit="1/mm (peak alpha of the 450 nm Fe3+-pair line, E⊥c)",
        reference_concentration=1.0,
        bands=dict(
            o=(
                (388.0, 4.0, 1.6, "gaussian"),
                (450.0, 5.0, 1.0, "gaussian"),
                (568.0, 30.0, 0.08, "gaussian_wavenumber"),
            ),
            e=(
                (388.0, 4.0, 1.2, "gaussian"),
                (450.0, 5.0, 0.7, "gaussian"),
                (568.0, 30.0, 0.05, "gaussian_wavenumber"),
            ),
        ),
        tails=dict(o=(360.0, 1.0, 0.25), e=(360.0, 0.8, 0.25)),
        source=(
            "GRS journal no. 1 (2002) fig. 26 caption (Fe3+ 388 nm, Fe3+-pair 450 nm); Burns 1993 "
            "fig. 3.16 caption after Ferguson & Fielding 1972 (pair band ~17,600 cm-1); Tippins "
            "1970, Phys. Rev. B 1, 126 (UV charge transfer, the violet edge)"
        ),
        note=_CHOSEN + "; the UV edge's alpha at 360 nm and its slope (0.25 eV) chosen",
    ),
    "Fe2+-Ti4+": dict(
        unit="1/mm (peak alpha of the 563 nm band, E⊥c)",
        reference_concentration=1.0,
        bands=dict(
            o=((563.0, 55.0, 1.0, "gaussian_wavenumber"),),
            e=((700.0, 80.0, 0.8, "gaussian_wavenumber"),),
        ),
        source=(
            "Fe2+-Ti4+ intervalence charge transfer at 563 nm (heat-treatment study of a purplish-red "
            "sapphire, abstract); Townsend 1968, Solid State Commun. 6, 81 (title)"
        ),
        note=(
            "E⊥c position from the source; the E∥c band at 700 nm is the value usually quoted, not "
            "read in a source here; widths, e/o ratio and strength chosen"
        ),
    ),
    "h-centre": dict(
        unit="1/mm (alpha of the edge at 400 nm, E⊥c)",
        reference_concentration=1.0,
        bands=dict(o=(), e=()),
        tails=dict(o=(400.0, 1.0, 0.45), e=(400.0, 0.8, 0.45)),
        source=(
            "GRS journal no. 1 (2002) fig. 26 caption: Mg2+-trapped-hole colour centres, 'general "
            "absorption in the blue region'"
        ),
        note="modelled as an Urbach tail; its reference point, slope and o/e ratio chosen",
    ),
}

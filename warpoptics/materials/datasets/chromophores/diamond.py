"""Diamond (C, cubic): the N3 centre and the N2 band (cape yellow), the 550 nm band (pink) and boron
(blue).

One polarization, ``iso``.

- N3 (three nitrogen atoms around a vacancy): zero-phonon line at 415.2 nm (2.985 eV) with its
  vibronic absorption band on the short-wavelength side, maxima near 403, 394 and 384 nm and a
  tail to about 340 nm (A. M. Zaitsev, *Optical Properties of Diamond: A Data Handbook*, Springer
  2001, the 2.985 eV centre; G. Davies, J. Phys. C 7, 3797 (1974)), the positions of the library's
  N3 luminescent centre (datasets/fluorescence).
- N2 and the cape lines: "a strong band at about 4155 A, a fairly strong [one] at 4780 A, and four
  weaker lines between these two" (Lunn's glossary, "Cape lines"); the weaker lines at 4650, 4510,
  4350 and 4230 A, the 4780 band the most prominent (B. W. Anderson's readings, as quoted on
  menswomenfashion.blogspot.com, 2013).  The 478 nm band is the N2 absorption of cape diamonds.
- 550 nm band: "the 550 nm absorption band", the most common cause of pink colour in natural
  diamonds, associated with plastic deformation (S. Eaton-Magaña, T. Ardon, K. V. Smit, C. M.
  Breeding, J. E. Shigley, Gems & Gemology 54(4), 2018, "Natural-color pink, purple, red, and brown
  diamonds: band of many colors", figure 1 caption and abstract); width chosen.
- Boron (type IIb): boron absorbs from the infrared (absorption coefficient up to about 5 at
  2500 nm) with a tail through the red, so that red, orange and yellow are absorbed more than
  blue (J.-P. Chalain, SSEF Facette 25 (2019), "Why is a diamond of type IIb blue to greyish
  blue?").  Modelled as a Gaussian in wavenumber centred at 2500 nm whose tail reaches the
  visible; its width (hence the visible slope) is chosen.

No absorption coefficient with a stated concentration was readable for the visible: each band
set's unit is the peak alpha (1/mm, base e) of its main feature (for boron, of the 2500 nm
band), widths and the vibronic heights are chosen, and the values of the coloured diamonds in
:mod:`..varieties` are chosen.
"""

from __future__ import annotations

__all__ = ["HOST", "BAND_SETS"]

HOST = dict(
    polarizations=("iso",),
    index=("page", "main/C/Peter"),
    source="refractiveindex.info main/C/Peter",
    description="diamond, cubic (isotropic)",
)

BAND_SETS = {
    "N3": dict(
        unit="1/mm (peak alpha of the 394 nm vibronic maximum)",
        reference_concentration=1.0,
        bands=dict(
            iso=(
                (415.2, 1.5, 0.55, "gaussian"),
                (403.0, 3.5, 0.85, "gaussian"),
                (394.0, 3.5, 1.0, "gaussian"),
                (384.0, 3.5, 0.8, "gaussian"),
                (365.0, 15.0, 0.45, "gaussian"),
            ),
        ),
        source=(
            "Zaitsev 2001, Optical Properties of Diamond, the 2.985 eV (N3) centre; Davies 1974, J. "
            "Phys. C 7, 3797 (ZPL 415.2 nm, vibronic maxima 403, 394, 384 nm, tail to ~340 nm)"
        ),
        note="positions from the sources; widths, vibronic heights and absolute strength chosen",
    ),
    "N2": dict(
        unit="1/mm (peak alpha of the 478 nm band)",
        reference_concentration=1.0,
        bands=dict(
            iso=(
                (478.0, 5.0, 1.0, "gaussian"),
                (465.0, 4.0, 0.4, "gaussian"),
                (451.0, 4.0, 0.3, "gaussian"),
                (435.0, 4.0, 0.25, "gaussian"),
                (423.0, 4.0, 0.2, "gaussian"),
            ),
        ),
        source=(
            "'Cape lines': a strong band at 415.5 nm (N3), a fairly strong one at 478.0 nm and four weaker "
            "lines between, at 465, 451, 435 and 423 nm (B. W. Anderson's spectroscope readings, as "
            "quoted by the Lunn's 'Cape lines' glossary and menswomenfashion.blogspot.com 2013)"
        ),
        note="positions from the source; widths, heights and absolute strength chosen",
    ),
    "550 nm band": dict(
        unit="1/mm (peak alpha of the 550 nm band)",
        reference_concentration=1.0,
        bands=dict(iso=((550.0, 45.0, 1.0, "gaussian_wavenumber"),)),
        source="Eaton-Magaña et al. 2018, Gems & Gemology 54(4), pink diamonds (the 550 nm band)",
        note="position from the source; width and absolute strength chosen",
    ),
    "boron": dict(
        unit="1/mm (peak alpha of the 2500 nm band)",
        reference_concentration=1.0,
        bands=dict(iso=((2500.0, 4000.0, 1.0, "gaussian_wavenumber"),)),
        source=(
            "Chalain 2019, SSEF Facette 25 (type IIb: boron absorption rising from the visible into "
            "the infrared, up to ~5 at 2500 nm)"
        ),
        note="the infrared maximum at 2500 nm from the source; the band's width (the visible slope) "
        "and absolute strength chosen",
    ),
}

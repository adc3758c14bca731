"""Chrysoberyl (BeAl2O4, orthorhombic, biaxial +): Cr3+ (alexandrite).

Polarizations ``x``, ``y``, ``z``: light polarized along the principal axes X, Y, Z (n_alpha,
n_beta, n_gamma).  Bands are Gaussians in wavelength (sigma in nm).

Measured, and what is still chosen
----------------------------------
- Y and Z (measured): G. R. Rossman, Caltech Mineral Spectroscopy Server, polarized spectra of
  alexandrite GRR 874 (Lake Manyara, Tanzania, 0.717 mm; files ch874.a and ch874.b): the beta ray
  (E along the 9.40 A axis) and the gamma ray (E along the 5.48 A axis), taken here as D along Y
  and Z (``tests/data/chromophores/spectra/chrysoberyl_cr3_caltech_grr874.csv``).  Maxima: Y 428
  and 565 nm, Z 415 and 596 nm with an R line near 681 nm.  Centres, widths and strengths are
  fitted to 400-700 nm (``scripts/fit_chromophore_bands.py``).  No analysis of the sample was
  published, so the sample is the unit: 1.0 = the Cr3+ of GRR 874 (alpha 5.62/mm at the 595 nm
  maximum for D along Z).
- X (chosen): the server has no alpha-ray spectrum.  The X bands keep the positions chosen before
  (575 and 420 nm, within the 520-620 nm Cr3+ absorption and its maximum near 570-580 nm: E.
  Gübelin, K. Schmetzer, Gems & Gemology 18(4), 1982, abstract, and the alexandrite-effect
  literature) with the widths of the measured Z bands; their strengths, 1.5 and 2.25 times the
  Z 4T2 maximum, are chosen so that D along X is purple-red and the face-up stone (D along X
  and Y) changes colour from daylight to incandescent light.
- Y. Liu, J. E. Shigley, E. Fritsch, S. Hemphill, Mineral. Mag. 59, 111 (1995), abstract: the
  colour change is largest for light travelling along a.  In the Handbook of Mineralogy's cell as
  Wikipedia's chrysoberyl articles quote it (Pbnm, a 5.48, b 9.42, c 4.43 A; X = c red-violet,
  Y = b yellow-orange, Z = a emerald-green) a is Z, the variety's face-up direction; the
  abstract names no cell, so this is assumed.
- Face up (D along X and Y) the colour rests mostly on the chosen X bands: at the variety's 0.5,
  3 mm along X is dark and near grey under D65 (L* 21, C* 5), red under A; not red-violet.

The value of alexandrite in :mod:`..varieties` is chosen for its colour change.
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
        unit="this sample (1.0 = the Cr3+ of Caltech GRR 874; alpha 5.62/mm at 595 nm, D along Z)",
        reference_concentration=1.0,
        bands=dict(
            x=((575.0, 34.53, 8.445, "gaussian"), (420.0, 28.35, 12.67, "gaussian")),
            y=(
                (564.9, 34.26, 1.102, "gaussian"),
                (430.4, 21.72, 5.871, "gaussian"),
                (393.0, 18.33, 1.758, "gaussian"),
            ),
            z=(
                (595.8, 34.53, 5.63, "gaussian"),
                (415.1, 28.35, 3.446, "gaussian"),
                (681.6, 1.11, 1.991, "gaussian"),
            ),
        ),
        source=(
            "Rossman, Caltech Mineral Spectroscopy Server, alexandrite GRR 874 (Lake Manyara), "
            "0.717 mm, beta and gamma rays (ch874.a/.b); tests/data/chromophores/spectra/"
            "chrysoberyl_cr3_caltech_grr874.csv; Gübelin & Schmetzer 1982, Gems & Gemology 18(4); "
            "Liu et al. 1995, Mineral. Mag. 59, 111"
        ),
        note=(
            "Y and Z measured: centres, widths and strengths fitted at 400-700 nm (unit: the sample); "
            "X has no measured spectrum: its positions and strengths are chosen (widths as Z)"
        ),
    ),
}

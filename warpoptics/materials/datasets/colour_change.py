"""A colour-change garnet as data: gemological constants and absorption bands.

``COLOUR_CHANGE_GARNET``: a pyrope–spessartine garnet with V3+/Cr3+, the "alexandrite-like"
garnet that is bluish green in daylight and purplish red in incandescent light.

- Index: n_D 1.762, dispersion 0.025 (B–G interval; pyrope 0.022, spessartine 0.027): refractive
  index 1.760–1.765 measured on such stones (Gems & Gemology 53(3), 2017, Gem News
  International, "Blue-green pyrope-spessartine garnet with high vanadium"; 1.74–1.77 in
  D. V. Manson, C. M. Stockton, Gems & Gemology 20(4), 200–207, 1984), a two-term Cauchy fit.
- Absorption (the cited spectra, as a fit): the V3+/Cr3+ band at 574 nm that separates the two
  transmission windows, red 650–700 nm and blue-green 460–510 nm, is "the main cause" of the
  colour change ("Explaining colour change in pyrope-spessartine garnets", Minerals 11(8), 865,
  2021, doi:10.3390/min11080865; also Manson & Stockton 1984, fig. 4); Mn2+ (spessartine) bands
  at 409, 422 and 430 nm and the second V3+/Cr3+ band near 410 nm close the violet; a weak Fe2+
  band near 504 nm (almandine component) and the rise of the absorption toward the ultraviolet
  (a band at 330 nm standing for the charge-transfer edge).  Widths and strengths are a fit,
  not a digitised measurement: chosen (on a grid of band strengths and widths) to give the
  largest hue change x chroma of a 4 mm plate between D65 and A, with the windows where the
  papers have them.  Result (``warpoptics colorchange colour_change_garnet --thickness 4``):
  h_ab 152 deg (bluish green) in D65, 342 deg (purplish red) in A, C*ab 9.5 and 11, ΔE00 25.7.
"""

from __future__ import annotations

__all__ = ["COLOUR_CHANGE_GARNET"]

COLOUR_CHANGE_GARNET = dict(
    n_d=1.762,
    dispersion=0.025,
    # (centre nm, FWHM nm, peak alpha 1/mm) of Gaussian bands
    bands=(
        (574.0, 80.0, 0.40),
        (410.0, 70.0, 0.80),
        (409.0, 6.0, 0.25),
        (422.0, 8.0, 0.35),
        (430.0, 8.0, 0.30),
        (504.0, 14.0, 0.08),
        (330.0, 60.0, 1.5),
    ),
    source=(
        "pyrope-spessartine colour-change garnet: n_D 1.762, dispersion 0.025 (G&G 2017, Manson & "
        "Stockton 1984), Cauchy fit; absorption: Gaussian fit on the V3+/Cr3+ 574 nm band, Mn2+ "
        "409/422/430 nm and Fe2+ 504 nm (Minerals 11, 865 (2021); Manson & Stockton 1984)"
    ),
)

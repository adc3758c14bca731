"""Olivine ((Mg,Fe)2SiO4, orthorhombic, biaxial +; gem variety peridot): Fe2+ in the M1 and M2
sites and the Fe3+ ultraviolet edge.

Polarizations ``x``, ``y``, ``z``: D along the principal axes X, Y, Z (n_alpha, n_beta, n_gamma).
In forsterite-rich olivine X = b (the 10 Å axis), Y = c (6 Å), Z = a (4.7 Å) (Pbnm), the
orientation convention of the Caltech Mineral Spectroscopy Server's olivine page (G. R. Rossman,
minerals.gps.caltech.edu/FILES/Visible/olivine: "10 Ångstrom axis = alpha; 6 Ångstrom axis =
beta; 4.7 Ångstrom axis = gamma").

What the sources give, and what they do not
-------------------------------------------
- M. N. Taran, S. S. Matsyuk, "Fe2+,Mg-partitioning between octahedral sites of forsterite
  according to polarized electronic absorption spectra", Phys. Chem. Minerals 40 (2013), on
  olivine Fa10Fo90 (abstract): the spin-allowed Fe2+(M2) band at 9560 cm-1 (1046 nm), polarized
  Z > X, with a shoulder at ~8300 cm-1 (1205 nm); a weaker Fe2+(M1) band at ~11600 cm-1
  (862 nm); the UV absorption edge (ligand-to-metal charge transfer of Fe3+) polarized
  Y > X >> Z.  Positions and these orderings come from there.
- The Caltech olivine page: olivine's colour is "primarily from Fe2+ content", green at low and
  brown at high Fe2+.  Peridot's yellowish green is the window between the red tail of the
  near-infrared Fe2+ bands and the violet Fe3+ edge.
- No absorption coefficients were available: widths (1200 cm-1 sigma), the ratios beyond the
  stated orderings and the absolute strengths are chosen.  The Fe2+ unit is wt% FeO with the
  reference 9.16 wt%, the analysed FeO of the Fo89 "green sand beach" olivine GDS70 (USGS
  spectral library, Clark et al. 2003, microprobe by W. I. Ridley), a typical peridot
  composition; the peaks at that reference are chosen, not measured.
"""

from __future__ import annotations

__all__ = ["HOST", "BAND_SETS"]

HOST = dict(
    polarizations=("x", "y", "z"),
    index=("biaxial", 1.635, 1.651, 1.670, 0.020),
    source=(
        "peridot (forsterite-rich olivine): n_alpha 1.635, n_beta 1.651, n_gamma 1.670 (Handbook of "
        "Mineralogy, forsterite), biaxial (+), dispersion 0.020 (GIA); Cauchy fits"
    ),
    description="olivine (Mg,Fe)2SiO4, orthorhombic, biaxial (+); X = b, Y = c, Z = a (Pbnm)",
)

_GW = "gaussian_wavenumber"

BAND_SETS = {
    "Fe2+": dict(
        unit="wt% FeO",
        reference_concentration=9.16,
        bands=dict(
            x=((1046.0, 131.0, 2.5, _GW), (1205.0, 110.0, 0.6, _GW), (862.0, 89.0, 1.25, _GW)),
            y=((1046.0, 131.0, 1.75, _GW), (862.0, 89.0, 1.75, _GW)),
            z=((1046.0, 131.0, 5.0, _GW), (1205.0, 110.0, 0.8, _GW), (862.0, 89.0, 1.25, _GW)),
        ),
        source=(
            "Taran & Matsyuk 2013, Phys. Chem. Minerals 40 (abstract, olivine Fa10Fo90): Fe2+(M2) "
            "9560 cm-1 Z > X with a shoulder at 8300 cm-1, Fe2+(M1) ~11600 cm-1"
        ),
        note=(
            "band positions and the Z > X ordering from the source's text; widths, other ratios "
            "and the peaks at 9.16 wt% FeO chosen (no measured absorption coefficient available)"
        ),
    ),
    "Fe3+": dict(
        unit="1/mm (alpha of the UV edge at 400 nm, D along Y)",
        reference_concentration=1.0,
        bands=dict(x=(), y=(), z=()),
        tails=dict(x=(400.0, 0.6, 0.3), y=(400.0, 1.0, 0.3), z=(400.0, 0.15, 0.3)),
        source=(
            "Taran & Matsyuk 2013, Phys. Chem. Minerals 40 (abstract): the UV absorption edge, "
            "ligand-to-metal charge transfer of Fe3+, polarized Y > X >> Z"
        ),
        note="an Urbach edge; the ordering from the source, its ratios, slope and strength chosen",
    ),
}

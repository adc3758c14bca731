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
- Measured: the Fe2+ band set is fitted to the Caltech polarized spectra of the San Carlos
  forsterite GRR 418 (files ol418.a/.b/.g, slabs 1.141, 1.1381 and 0.66 mm; numeric data,
  tests/data/chromophores/spectra/olivine_fe2_caltech_grr418_{alpha,beta,gamma}.csv; see
  docs/design/chromophore_spectra.md): the weak spin-forbidden Fe2+ bands of 400-500 nm, the
  ~635 nm band and the red tail of the near-infrared absorption, whose maxima (1052 / 1093 /
  1048 nm for X / Y / Z) the fit also matches; Z > X there, as Taran & Matsyuk state.  No
  composition is published with the spectra, so the unit is that sample (1.0); the peridot
  variety's concentration in it is chosen for the trade hue.  Chosen: the template, the split of
  the near-infrared absorption into two bands per ray (720-1000 nm is not fitted), and the sample's
  violet-UV rise kept inside the Fe2+ set.
- The Fe3+ edge: ordering from Taran & Matsyuk; its ratios, slope and strength are chosen.
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
        unit="the sample GRR 418 (San Carlos forsterite, no analysis published)",
        reference_concentration=1.0,
        bands=dict(
            x=(
                (398.9, 23.53, 0.3824, _GW),
                (456.8, 16.65, 0.1662, _GW),
                (495.6, 22.16, 0.08353, _GW),
                (634.5, 22.15, 0.07315, _GW),
                (1052.4, 230.71, 1.661, _GW),
                (859.9, 145.56, 0.004027, _GW),
            ),
            y=(
                (402.8, 18.94, 0.1433, _GW),
                (434.2, 8.64, 0.1315, _GW),
                (455.3, 9.07, 0.2102, _GW),
                (471.8, 5.67, 0.1374, _GW),
                (492.7, 10.42, 0.1794, _GW),
                (639.3, 28.18, 0.09637, _GW),
                (1120.0, 256.94, 1.582, _GW),
                (855.0, 116.06, 0.3111, _GW),
            ),
            z=(
                (379.9, 17.16, 0.4741, _GW),
                (429.1, 16.04, 0.1652, _GW),
                (448.6, 5.04, 0.03098, _GW),
                (465.0, 28.31, 0.1291, _GW),
                (631.7, 23.16, 0.06185, _GW),
                (1049.0, 49.90, 4.985, _GW),
                (895.0, 135.62, 0.6078, _GW),
            ),
        ),
        tails=dict(x=(380.0, 0.233, 0.066), y=(380.0, 0.5135, 0.319)),
        source=(
            "Rossman, Caltech Mineral Spectroscopy Server, forsterite GRR 418 (San Carlos), files "
            "ol418.a/.b/.g (1.141, 1.1381, 0.66 mm), fitted: tests/data/chromophores/spectra/"
            "olivine_fe2_caltech_grr418_alpha.csv, olivine_fe2_caltech_grr418_beta.csv, "
            "olivine_fe2_caltech_grr418_gamma.csv; positions of the near-infrared bands: Taran & "
            "Matsyuk 2013, Phys. Chem. Minerals 40"
        ),
        note=(
            "measured: the three rays of one sample, fitted over 380-720 nm and at the near-infrared "
            "maxima (1052 / 1093 / 1048 nm for X / Y / Z; visible centres within 2 nm, peaks within "
            "3 %, RMS 5.6 / 10.6 / 5.8 %); chosen: the template (bands in wavenumber, the sample's "
            "violet-UV rise kept in this set as bands and an edge), the unit (the sample; no "
            "composition published) and the split of the near-infrared absorption into two bands per "
            "ray (the 720-1000 nm points are not fitted)"
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

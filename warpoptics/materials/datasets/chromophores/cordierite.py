"""Cordierite ((Mg,Fe)2Al4Si5O18·n(H2O,CO2), orthorhombic, biaxial −; gem variety iolite):
Fe2+-Fe3+ intervalence charge transfer and octahedral Fe2+.

Polarizations ``x``, ``y``, ``z``: D along the principal axes X, Y, Z (n_alpha, n_beta, n_gamma);
in cordierite X = c, Y = a, Z = b (Handbook of Mineralogy, cordierite: optical orientation).

What the sources give, and what they do not
-------------------------------------------
- Caltech Mineral Spectroscopy Server, cordierite page (G. R. Rossman,
  minerals.caltech.edu/Files/Visible/CORDIERIte): "The color is predominantly due to the
  Fe2+ - Fe3+ intervalence charge transfer band near 600 nm"; octahedral Fe2+ gives "the pair of
  absorption bands near 1000 and 1300 nm which have almost no effect on the color" (spectrum GRR
  262, GECO Mine, Ontario, 0.5 mm thick).
- C. A. Geiger, H. Rager, M. Czank, "Cordierite III: the site occupation and concentration of
  Fe3+", Contrib. Mineral. Petrol. (2000), abstract: "The blue color in cordierite arises from a
  broad absorption band (E//b and weaker with E//a) around 18,000 cm-1" (555.6 nm), charge
  transfer between octahedral Fe2+ and Fe3+ on the edge-shared T11 tetrahedron.  E//b is D along
  Z (blue), E//a along Y (violet), E//c along X (pale yellow, no band).
- Typical concentration: gem cordierite with 1.68-4.60 wt% FeO (electron microprobe; Crystals
  14(7), 637 (2024), table 2).
- No absorption coefficients were available: the width (2000 cm-1 sigma), the Y/Z ratio and the
  strengths are chosen; the band is taken linear in FeO at a fixed Fe3+/Fe2+ (the pair
  absorption really scales with Fe2+ × Fe3+).
"""

from __future__ import annotations

__all__ = ["HOST", "BAND_SETS"]

HOST = dict(
    polarizations=("x", "y", "z"),
    index=("biaxial", 1.542, 1.547, 1.551, 0.017),
    source=(
        "iolite (cordierite), GIA: RI 1.542-1.551, biaxial (-), dispersion 0.017; n_beta 1.547 "
        "within the range; Cauchy fits"
    ),
    description="cordierite, orthorhombic, biaxial (-); X = c (pale yellow), Y = a (violet), Z = b (blue)",
)

_GW = "gaussian_wavenumber"

BAND_SETS = {
    "Fe2+-Fe3+": dict(
        unit="wt% FeO",
        reference_concentration=2.0,
        bands=dict(
            x=(),
            y=((555.6, 80.0, 0.14, _GW),),
            z=((555.6, 80.0, 0.4, _GW),),
        ),
        source=(
            "Geiger, Rager & Czank 2000 (abstract: the blue colour from a broad band around "
            "18,000 cm-1, E//b and weaker E//a); Caltech cordierite page (IVCT near 600 nm)"
        ),
        note=(
            "position and polarization from the sources' text; width, Y/Z ratio and the peak at "
            "2 wt% FeO chosen (no measured absorption coefficient available)"
        ),
    ),
    "Fe2+": dict(
        unit="wt% FeO",
        reference_concentration=2.0,
        bands=dict(
            x=((1000.0, 120.0, 0.08, _GW), (1300.0, 200.0, 0.08, _GW)),
            y=((1000.0, 120.0, 0.08, _GW), (1300.0, 200.0, 0.08, _GW)),
            z=((1000.0, 120.0, 0.08, _GW), (1300.0, 200.0, 0.08, _GW)),
        ),
        source="Caltech cordierite page (octahedral Fe2+ bands near 1000 and 1300 nm)",
        note=(
            "positions from the source's text ('almost no effect on the color'); widths, "
            "polarization and strength chosen"
        ),
    ),
}

"""Guy & Soler 2004 §6.1 "System parameters": the gem table, verbatim, as plain data.

Provenance: S. Guy, C. Soler, "Graphics gems revisited", ACM TOG 23(3), 2004, §6.1 table.  The
paper states no unit for the absorbances (K_r, K_g, K_b); warpoptics reads them as base-e
absorbance per mm (:data:`GUY_SOLER_2004_ALPHA_PER_MM`; the reasoning is in
:mod:`warpoptics.materials.absorption`).  Used by :func:`warpoptics.materials.guy_soler_2004_spectra`
and the gem library.
"""

from __future__ import annotations

__all__ = ["GUY_SOLER_2004_ALPHA_PER_MM", "GUY_SOLER_2004_GEMS"]

#: alpha (1/mm) per unit of the Guy & Soler table's absorbances (read as base-e per mm; see module doc)
GUY_SOLER_2004_ALPHA_PER_MM = 1.0

#: Guy & Soler 2004 §6.1 "System parameters", verbatim: type (I/U/B), (K_r, K_g, K_b) for the o
#: and e rays (isotropic: o only), colours, n_o / n_e at the green channel and the ± that gives
#: red (−) and blue (+) (half the gemological dispersion).  Sapphire's row lists e before o.
GUY_SOLER_2004_GEMS: dict[str, dict] = {
    "garnet": dict(
        type="I",
        K_o=(0.136, 0.153, 0.175),
        K_e=None,
        colors=("orange-red",),
        n_o=1.730,
        n_e=None,
        half_dispersion=0.014,
    ),
    "tourmaline": dict(
        type="U",
        K_o=(0.033, 0.034, 0.082),
        K_e=(0.010, 0.076, 0.015),
        colors=("yellow green", "blue green"),
        n_o=1.642,
        n_e=1.619,
        half_dispersion=0.011,
    ),
    "peridot": dict(
        type="B",
        K_o=(0.023, 0.015, 0.051),
        K_e=(0.011, 0.003, 0.028),
        colors=("green", "yellow green"),
        n_o=1.680,
        n_e=1.640,
        half_dispersion=0.010,
    ),
    "diamond": dict(
        type="I",
        K_o=(0.001, 0.001, 0.001),
        K_e=None,
        colors=("white",),
        n_o=2.410,
        n_e=None,
        half_dispersion=0.022,
    ),
    "sapphire": dict(
        type="U",
        K_o=(0.165, 0.147, 0.185),
        K_e=(0.332, 0.270, 0.156),
        colors=("violetish blue", "light blue"),
        n_o=1.768,
        n_e=1.760,
        half_dispersion=0.009,
    ),
    "andalusite": dict(
        type="B",
        K_o=(0.0056, 0.006, 0.0183),
        K_e=(0.170, 0.175, 0.257),
        colors=("greenish red", "yellowish green"),
        n_o=1.635,
        n_e=1.644,
        half_dispersion=0.005,
    ),
}

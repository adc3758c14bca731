"""Densities (g/cm³) of the chromophore hosts, for the carat weight of a cut stone.

The values are the usual specific gravities of gem tables: GIA Gem Reference Guide (1995),
property tables, and R. Webster, *Gems*, 5th ed. (1994).  A species varies with its composition
(the ranges of those tables are a few percent: beryl 2.67-2.90, almandine 3.93-4.30, tourmaline
3.00-3.26); one typical value stands for each host, so a carat weight computed from it is good to
those few percent.  A variety whose composition sits far from its host's typical value has its own
entry in :data:`VARIETY_DENSITY` (rhodolite, a pyrope-almandine, is lighter than almandine).
"""

from __future__ import annotations

__all__ = ["HOST_DENSITY", "VARIETY_DENSITY", "SOURCE"]

SOURCE = "GIA Gem Reference Guide (1995) and R. Webster, Gems, 5th ed. (1994): typical specific gravities"

#: typical density (g/cm³) of each host of :mod:`warpoptics.materials.chromophores`
HOST_DENSITY: dict[str, float] = {
    "almandine": 4.05,
    "andradite": 3.84,
    "beryl": 2.72,
    "chrysoberyl": 3.73,
    "cordierite": 2.61,
    "corundum": 4.00,
    "diamond": 3.52,
    "grossular": 3.61,
    "olivine": 3.34,
    "quartz": 2.66,
    "spessartine": 4.15,
    "spinel": 3.60,
    "topaz": 3.53,
    "tourmaline": 3.06,
    "zircon": 4.70,
    "zoisite": 3.35,
}

#: varieties whose typical density differs from their host's (g/cm³)
VARIETY_DENSITY: dict[str, float] = {
    "rhodolite": 3.84,  # pyrope-almandine
}

"""Dye data of the Kramers–Kronig solutions (Weidlich & Wilkie 2009 §4.2, fig. 1, 4–5), plain data.

Provenance: rose bengal (disodium salt, 1017.6 g/mol) in water: absorption maximum 549 nm, molar
absorptivity ≈ 9.8·10⁴ L mol⁻¹ cm⁻¹, vibronic shoulder near 510 nm (D. C. Neckers, J. Photochem.
Photobiol. A 47, 1 (1989); PhotochemCAD database).  Fuchsine (basic fuchsin, rosaniline
hydrochloride, 337.85 g/mol) in water: maximum ≈ 543 nm, ≈ 9·10⁴ L mol⁻¹ cm⁻¹.  Band widths are
fits by eye to those published spectra: approximate.  Used by
:func:`warpoptics.materials.kramers_kronig.rose_bengal_absorption` and ``fuchsine_absorption``.
"""

from __future__ import annotations

__all__ = [
    "ROSE_BENGAL_CONCENTRATIONS",
    "ROSE_BENGAL_MOLAR_MASS",
    "ROSE_BENGAL_EPSILON",
    "ROSE_BENGAL_BANDS",
    "FUCHSINE_MOLAR_MASS",
    "FUCHSINE_EPSILON",
    "FUCHSINE_BANDS",
    "LIBRARY_SOLUTIONS",
]

#: rose bengal solutions of Weidlich & Wilkie §4.2, in % (read as g per 100 mL of water)
ROSE_BENGAL_CONCENTRATIONS = (10.0, 3.3, 1.0)

ROSE_BENGAL_MOLAR_MASS = 1017.6  # g/mol, disodium salt
ROSE_BENGAL_EPSILON = 9.8e4  # L mol^-1 cm^-1 at 549 nm (decadic), water
# (centre nm, sigma nm, relative height): main band and vibronic shoulder
ROSE_BENGAL_BANDS = ((549.0, 12.5, 1.0), (510.0, 17.0, 0.30))

FUCHSINE_MOLAR_MASS = 337.85  # g/mol, rosaniline hydrochloride
FUCHSINE_EPSILON = 9.0e4  # L mol^-1 cm^-1 at 543 nm (decadic), water
FUCHSINE_BANDS = ((543.0, 22.0, 1.0), (500.0, 20.0, 0.20))

#: the gem library's solutions: library name -> (dye, concentration in %)
LIBRARY_SOLUTIONS: dict[str, tuple[str, float]] = {
    "rose_bengal_10": ("rose_bengal", 10.0),
    "rose_bengal_3.3": ("rose_bengal", 3.3),
    "rose_bengal_1": ("rose_bengal", 1.0),
    "fuchsine": ("fuchsine", 1.0),
}

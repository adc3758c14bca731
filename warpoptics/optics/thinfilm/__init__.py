"""Thin films: exact multilayer amplitudes and the Smits–Meyer interference model.

* the **exact stack**: complex amplitudes rs, rp, ts, tp of any number of homogeneous layers
  between an incident medium and a substrate, for complex indices and any angle, by the
  characteristic-matrix (Abelès) method in a normalised "Airy" form, so that thick or strongly
  absorbing layers never overflow; float64 inside the kernels (docs/design/thin_films.md);
* the **paper's model** (Smits & Meyer 1990): two-beam interference of a single film with and
  without the phase change (eq. 7, 8), the optical thickness t' = t n cos(theta) (eq. 11), and
  the Anderson–Richards multilayer iridescence (eq. 9, 10, 14); colour tables indexed by optical
  thickness or angle (§2.1, §3.2) and the thickness fields of :mod:`warpoptics.fields`.

The package, by topic: :mod:`.stack` (the exact stack and its wrappers), :mod:`.smits_meyer`
(eq. 5–14), :mod:`.tables` (colour tables); the wrappers' argument checks are in :mod:`.inputs`.

Conventions (see also ``optics/complex.py``):

* time dependence exp(-i omega t); indices ``n + i k`` with k >= 0 absorbing; wavelengths and
  thicknesses in nanometres; angles of incidence in degrees in the NumPy wrappers (cosines in
  the ``@wp.func``s), measured in the incident medium;
* the stack runs from the *front* (ambient) medium through layers 0..L-1 to the *back* medium
  (the substrate); light may arrive from either side (``from_back``);
* amplitudes are ratios of complex field amplitudes at the first / last interface, with the
  signs of Born & Wolf, Hecht and ``tmm``: for a bare interface
  ``rs = (N1 cos i - N2 cos t) / (N1 cos i + N2 cos t)``,
  ``rp = (N2 cos i - N1 cos t) / (N2 cos i + N1 cos t)`` (rp = -rs at normal incidence),
  ``ts = 2 N1 cos i / (N1 cos i + N2 cos t)``, ``tp = 2 N1 cos i / (N2 cos i + N1 cos t)``;
* powers: R = |r|^2, T_s = |ts|^2 Re(N2 cos t) / Re(N1 cos i),
  T_p = |tp|^2 Re(conj(N2) cos t) / Re(conj(N1) cos i) (R + T + A = 1 for a transparent
  incident medium).

References: Smits & Meyer, "Newton's colors: simulating interference phenomena in realistic
image synthesis", 1990, eq. 5–14; Born & Wolf, Principles of Optics, 7th ed., §1.6.2–1.6.4;
Macleod, Thin-Film Optical Filters, 4th ed., §2.2; Byrnes, "Multilayer optical calculations",
arXiv:1603.02720 (``tmm``); Anderson & Richards, J. Appl. Phys. 13, 748 (1942).
"""

from __future__ import annotations

from .smits_meyer import (
    smits_meyer_effective_thickness,
    smits_meyer_effective_thickness_wp,
    smits_meyer_film,
    smits_meyer_film_reflectance,
    smits_meyer_morpho_thickness,
    smits_meyer_morpho_thickness_wp,
    smits_meyer_multilayer,
    smits_meyer_multilayer_intensity,
    smits_meyer_optical_thickness,
    smits_meyer_optical_thickness_wp,
)
from .stack import (
    CoatingStack,
    amplitudes,
    coating_amplitudes,
    coating_amplitudes_scaled,
    evaluate_coating,
    make_coating_stack,
    reflectance,
    stack_amplitudes,
    stack_amplitudes_scaled,
    stack_layer_index,
    stack_power,
    transmittance,
)
from .tables import (
    ColorTable,
    TableModel,
    color_table_lookup,
    film_color_table,
    morpho_stack,
    multilayer_color_table,
    table_spectral_reflectance,
)

__all__ = [
    "CoatingStack",
    "stack_layer_index",
    "stack_amplitudes",
    "stack_amplitudes_scaled",
    "stack_power",
    "coating_amplitudes",
    "coating_amplitudes_scaled",
    "smits_meyer_film_reflectance",
    "smits_meyer_optical_thickness_wp",
    "smits_meyer_effective_thickness_wp",
    "smits_meyer_morpho_thickness_wp",
    "smits_meyer_multilayer_intensity",
    "make_coating_stack",
    "amplitudes",
    "reflectance",
    "transmittance",
    "smits_meyer_film",
    "smits_meyer_optical_thickness",
    "smits_meyer_effective_thickness",
    "smits_meyer_morpho_thickness",
    "smits_meyer_multilayer",
    "evaluate_coating",
    "TableModel",
    "table_spectral_reflectance",
    "color_table_lookup",
    "ColorTable",
    "film_color_table",
    "multilayer_color_table",
    "morpho_stack",
]

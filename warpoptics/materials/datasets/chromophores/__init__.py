"""Chromophore band sets, one module per host crystal (plain literals, no computing imports).

Each host module defines

``HOST``       ``dict(polarizations=..., index=..., source=..., description=...)``:
               ``polarizations`` ``("o", "e")`` (E⊥c, E∥c) for a uniaxial host, ``("x", "y", "z")``
               (D along the principal axes X, Y, Z: n_alpha, n_beta, n_gamma) for a biaxial one,
               ``("iso",)`` for a cubic one; ``index`` the colourless crystal's refractive index in
               the format of :data:`warpoptics.materials.datasets.gems.GEMS` ``index``; ``source``
               its provenance; ``description`` one line on the host.
``BAND_SETS``  ``{chromophore: dict(unit=..., reference_concentration=..., bands=..., tails=...,
               source=..., note=...)}``: ``bands`` maps each polarization to a tuple of
               ``(centre_nm, width_nm, peak_alpha_per_mm, shape)`` (shape ``"gaussian"``: width =
               sigma in nm; ``"lorentzian"``: width = half width at half maximum;
               ``"gaussian_wavenumber"``: a Gaussian in wavenumber, width = sigma in nm at the
               centre), peaks base-e alpha in 1/mm at ``reference_concentration`` (in ``unit``);
               ``tails`` (optional) maps a polarization to ``(reference_nm, alpha_per_mm,
               width_ev)``, an Urbach edge alpha exp((E - E_ref)/width); ``source`` the measured
               spectrum (paper, figure/table, sample, concentration, path length); ``note`` what
               the numbers are when the source gives less than absolute absorption.

:data:`HOSTS` maps each host name (the module's name) to its module; a new host is a new module
here, found without registration.
"""

from __future__ import annotations

import importlib
import pkgutil
from types import ModuleType

__all__ = ["HOSTS"]

#: host name -> its data module (every module of this package, in alphabetical order)
HOSTS: dict[str, ModuleType] = {
    info.name: importlib.import_module(f"{__name__}.{info.name}")
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name)
    if not info.name.startswith("_")
}

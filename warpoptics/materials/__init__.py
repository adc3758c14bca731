"""Materials: dispersion models, refractiveindex.info, the gem library, absorption, Kramers–Kronig.

Public API: ``get(name)``, ``mat.n(wavelength_nm)``, ``Sellmeier(B, C)``,
``Cauchy(...)``, ``Tabulated(wavelength_nm, n, k=None)``, ``from_refractiveindex("main/C/Peter")``,
``dispersion_bg(mat)``, ``kramers_kronig(wavelength_nm, k, n_background)``.  The renderer's
device-side interface (``MaterialTable``, ``build_material_table``, ``material_eval``,
``material_alpha``) is documented in :mod:`warpoptics.materials.dispersion`.
"""

from __future__ import annotations

from .absorption import (
    AbsorptionSpectrum,
    Band,
    guy_soler_2004_spectra,
    pleochroic_alpha,
    rgb_absorbance,
    spectrum_from_rgb,
    with_absorption,
)
from .activity import OpticalActivity, optical_activity
from .datasets.guy_soler_2004 import GUY_SOLER_2004_ALPHA_PER_MM, GUY_SOLER_2004_GEMS
from .dispersion import (
    CIE_RGB_PRIMARIES_NM,
    Biaxial,
    Cauchy,
    Formula,
    Isotropic,
    Material,
    MaterialTable,
    Sellmeier,
    Tabulated,
    Uniaxial,
    abbe_number,
    build_material_table,
    dispersion_bg,
    material_alpha,
    material_eval,
    material_eval_channel,
    rgb3_alpha_of,
)
from .fit import FitResult, fit_chromophores, read_absorption_csv
from .kramers_kronig import anomalous, kramers_kronig, rose_bengal_absorption
from .library import chromophore_material, fuchsine_solution, get, names, rose_bengal_solution
from .refractiveindex import from_refractiveindex
from .rgb_weights import RGB_CMFS
from .spec import material_from_spec
from .units import absorbance_per_cm_from_alpha, alpha_from_absorbance_per_cm, alpha_from_k, k_from_alpha

__all__ = [
    "OpticalActivity",
    "optical_activity",
    "GUY_SOLER_2004_ALPHA_PER_MM",
    "material_from_spec",
    "get",
    "names",
    "chromophore_material",
    "fit_chromophores",
    "FitResult",
    "read_absorption_csv",
    "Material",
    "Isotropic",
    "Uniaxial",
    "Biaxial",
    "Sellmeier",
    "Cauchy",
    "Tabulated",
    "Formula",
    "from_refractiveindex",
    "dispersion_bg",
    "abbe_number",
    "kramers_kronig",
    "anomalous",
    "rose_bengal_absorption",
    "rose_bengal_solution",
    "fuchsine_solution",
    "AbsorptionSpectrum",
    "Band",
    "alpha_from_k",
    "k_from_alpha",
    "alpha_from_absorbance_per_cm",
    "absorbance_per_cm_from_alpha",
    "pleochroic_alpha",
    "rgb_absorbance",
    "spectrum_from_rgb",
    "rgb3_alpha_of",
    "RGB_CMFS",
    "with_absorption",
    "guy_soler_2004_spectra",
    "GUY_SOLER_2004_GEMS",
    "CIE_RGB_PRIMARIES_NM",
    "MaterialTable",
    "build_material_table",
    "material_eval",
    "material_eval_channel",
    "material_alpha",
]

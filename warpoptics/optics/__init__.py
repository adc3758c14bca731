"""Optics kernels: complex algebra, Fresnel, Jones and coherency matrices, birefringence (uniaxial
and biaxial), thin films.

Each physical law is a ``@wp.func`` in its module (``fresnel``, ``jones``, ``birefringence``),
called per ray by the renderer's kernels; the NumPy wrappers re-exported here launch exactly
those functions.
"""

from . import biaxial, birefringence, complex, jones, photoelastic, plate, polarizer, zoning  # noqa: F401
from .biaxial import biaxial_absorption, biaxial_fresnel_coefficients, biaxial_waves, optic_axial_angle
from .birefringence import (
    GeneralizedFresnelResult,
    attenuation,
    extraordinary_index,
    fresnel_matrices,
    generalized_fresnel_coefficients,
    kappa_e,
    oe_polarizations,
    reflect_extraordinary,
    refract_extraordinary,
)
from .fresnel import fresnel, fresnel_power, reflect, refract
from .jones import (
    coherency_apply,
    coherency_from_stokes,
    dop,
    frame_change_matrix,
    jones_product,
    s_vectors,
    stokes,
    transport_bases,
)
from .plate import plate_jones
from .polarizer import analyze, mueller_polarizer, sheet_polarizer_stokes
from .zoning import segment_optical_depth

__all__ = [
    "biaxial",
    "birefringence",
    "complex",
    "jones",
    "photoelastic",
    "plate",
    "polarizer",
    "zoning",
    # Fresnel (isotropic)
    "fresnel",
    "fresnel_power",
    "refract",
    "reflect",
    # Jones / coherency / Stokes
    "jones_product",
    "coherency_apply",
    "stokes",
    "coherency_from_stokes",
    "dop",
    "frame_change_matrix",
    "s_vectors",
    "transport_bases",
    # ideal linear polarizers (Mueller matrix, sheet polarizer)
    "mueller_polarizer",
    "analyze",
    "sheet_polarizer_stokes",
    # uniaxial crystals
    "extraordinary_index",
    "refract_extraordinary",
    "reflect_extraordinary",
    "oe_polarizations",
    "generalized_fresnel_coefficients",
    "GeneralizedFresnelResult",
    "fresnel_matrices",
    "kappa_e",
    "attenuation",
    # biaxial crystals
    "biaxial_waves",
    "biaxial_fresnel_coefficients",
    "biaxial_absorption",
    "optic_axial_angle",
    # crystal plates (coherent o/e sum)
    "plate_jones",
    # colour zoning: a segment's optical depth through zones
    "segment_optical_depth",
]

"""Optics kernels: complex algebra, Fresnel, Jones and coherency matrices, birefringence, thin films.

Each physical law is a ``@wp.func`` in its module (called per ray by the renderer's kernels) with
a NumPy wrapper re-exported here.
"""

from . import complex  # noqa: F401  (the complex helpers other physics modules build on)
from . import fresnel as _fresnel_module
from . import jones  # noqa: F401
from .fresnel import fresnel, fresnel_power
from .jones import coherency_apply, coherency_from_stokes, dop, jones_product, stokes

__all__ = [
    "complex",
    "jones",
    "fresnel",
    "fresnel_power",
    "jones_product",
    "coherency_apply",
    "stokes",
    "coherency_from_stokes",
    "dop",
]

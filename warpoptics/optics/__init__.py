"""Optics kernels: complex algebra, Fresnel, Jones and coherency matrices, birefringence, thin films."""

from . import complex  # noqa: F401  (the complex helpers other physics modules build on)

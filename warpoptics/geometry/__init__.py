"""Geometry: gem cuts, mesh loading and validation, GemCAD designs, device ray queries.

Submodules: :mod:`.cuts` (parametric cuts), :mod:`.mesh` (files, validation, facet planes),
:mod:`.gemcad` (GemCAD ``.asc``), :mod:`.query` (BVH and convex closest-hit on the device;
imported on demand since it compiles Warp kernels).
"""

from . import cuts, gemcad, mesh

__all__ = ["cuts", "gemcad", "mesh"]

"""Geometry: gem cuts, mesh loading and validation, GemCAD designs, device ray queries.

Submodules: :mod:`.cuts` (parametric cuts), :mod:`.mesh` (files, validation, facet planes),
:mod:`.gemcad` (GemCAD ``.asc``), :mod:`.query` (BVH and convex closest-hit on the device; its
Warp module compiles on first launch).
"""

from . import cuts, gemcad, mesh, query

__all__ = ["cuts", "gemcad", "mesh", "query"]

"""Colour zoning of a stone: absorption that changes from zone to zone inside one host crystal.

A :class:`Zoning` describes the zones of a stone in its own (object) frame — their family, their
boundaries and one absorption per zone — and :func:`zoned_material` attaches it to the host
material: the stone keeps the host's refractive indices and birefringence everywhere, and each
zone's absorption is that of the zone's own material (a library name or an inline material
table, as a scene's ``material``; only its absorption is used).  ``build_material_table`` packs
the zones into the device table (each zone's material becomes an entry of its own), and the
tracers integrate a segment's optical depth through them (``optics/zoning.py``).

Families (``kind``):

- ``"planar"``: bands parallel to a crystal face, planes ``normal . (x - origin) = offset`` —
  the hexagonal growth banding of sapphire;
- ``"halves"``: one such plane splitting the stone in two — ametrine's amethyst and citrine;
- ``"core_rim"``: coaxial cylinders of the given radii about the line through ``origin`` along
  ``axis`` — watermelon tourmaline's pink core in a green rim.

The zones are listed from the side opposite the normal (planar, halves) or from the core outward.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

__all__ = ["Zoning", "ZONING_KINDS", "zoned_material", "MAX_ZONES"]

#: the zone families of a scene's ``zoning.type``
ZONING_KINDS = ("planar", "core_rim", "halves")
#: most zones per stone (``optics.zoning.MAX_ZONES``; kept equal by a test)
MAX_ZONES = 8


@dataclass(frozen=True)
class Zoning:
    """Zones of one stone (module docstring), object frame, millimetres before the object's scale.

    ``kind``: one of :data:`ZONING_KINDS`; ``axis``: unit normal of the planes or axis of the
    cylinders; ``origin``: a point of the middle plane or of the cylinders' axis; ``bounds``: the
    K - 1 increasing offsets along the normal (planar, halves) or radii (core_rim) between the K
    zones; ``absorption``: K material specs (names, inline tables) or, once resolved by the
    pipelines, :class:`~warpoptics.materials.dispersion.Material` objects; ``world_to_object``:
    the stone's 4x4 world -> object transform (set by the pipelines; identity if None)."""

    kind: str
    axis: tuple[float, float, float]
    bounds: tuple[float, ...]
    absorption: tuple[Any, ...]
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)
    world_to_object: tuple[tuple[float, ...], ...] | None = None

    @property
    def family(self) -> str:
        """``"cylinders"`` for core and rim, ``"planes"`` otherwise (``optics.zoning``)."""
        return "cylinders" if self.kind == "core_rim" else "planes"

    def frame(self) -> np.ndarray:
        """The 4x4 world -> object transform (identity if not set)."""
        if self.world_to_object is None:
            return np.eye(4)
        return np.asarray(self.world_to_object, dtype=np.float64)

    def placed(self, object_to_world: np.ndarray) -> Zoning:
        """This zoning in a stone placed by ``object_to_world`` (4x4)."""
        inv = np.linalg.inv(np.asarray(object_to_world, dtype=np.float64))
        return replace(self, world_to_object=tuple(tuple(float(v) for v in row) for row in inv))

    def zone_of(self, points_object) -> np.ndarray:
        """Index of the zone holding each point (..., 3), object frame (a NumPy reference)."""
        p = np.asarray(points_object, dtype=np.float64) - np.asarray(self.origin)
        ax = np.asarray(self.axis, dtype=np.float64)
        s = p @ ax
        if self.family == "cylinders":
            s = np.linalg.norm(p - s[..., None] * ax, axis=-1)
        return np.searchsorted(np.asarray(self.bounds), s, side="right")


def zoned_material(host, zoning: Zoning):
    """A copy of ``host`` carrying ``zoning`` (resolved: its ``absorption`` are materials), for
    ``build_material_table``; every other property is the host's."""
    out = copy.copy(host)
    out.__dict__.pop("_table_cache", None)
    out.zoning = zoning
    return out

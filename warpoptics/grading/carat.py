"""Carat weight of a cut stone and the size of a stone of a given weight.

A stone's mass is its density times the volume of its cut (the closed mesh of
:mod:`warpoptics.geometry.cuts` at the object table's dimensions and ``scale``); one metric carat
is 0.2 g.  Every proportion of a parametric cut is a fraction or an angle, so the volume goes as
the cube of the linear dimensions and :func:`size_for_carats` scales those (``diameter``,
``length``, ``width``, ``size``, ``thickness``) by one factor.

Densities (:func:`density_of`) are the typical specific gravities of
:mod:`warpoptics.materials.datasets.densities` (good to the few percent a species varies); a 1 ct
round brilliant diamond comes out 6.4-6.5 mm across, as the trade's tables give.
"""

from __future__ import annotations

import inspect
from pathlib import Path
from typing import Any

from ..errors import InputError

__all__ = ["CARAT_G", "density_of", "stone_mesh", "carat_weight", "size_for_carats"]

#: one metric carat in grams
CARAT_G = 0.2

#: the keyword arguments of the cut functions that are lengths (mm); the rest are ratios or angles
_LINEAR = ("diameter", "length", "width", "size", "thickness")


def density_of(material: Any) -> float:
    """Density (g/cm³) of a variety (``"ruby"``), a chromophore host (``"corundum"``), a material
    spec with a ``host`` or a ``base`` (``{"base": "ruby", "chromophores": {...}}``), or a
    :class:`~warpoptics.materials.Material` that carries ``chromophore_host``."""
    from ..materials.datasets.densities import HOST_DENSITY, VARIETY_DENSITY
    from ..materials.datasets.varieties import VARIETIES

    if isinstance(material, dict):
        for key in ("base", "host"):
            if key in material:
                return density_of(material[key])
        raise InputError(
            "a material table needs a host or a base to have a density", field="material", value=material
        )
    if not isinstance(material, str):
        host = getattr(material, "chromophore_host", None)
        if host is None:
            raise InputError("no density known for this material", field="material", value=repr(material))
        return density_of(host)
    key = material.strip().lower()
    if key in VARIETY_DENSITY:
        return VARIETY_DENSITY[key]
    if key in VARIETIES:
        return HOST_DENSITY[VARIETIES[key]["host"]]
    if key in HOST_DENSITY:
        return HOST_DENSITY[key]
    raise InputError(
        "no density known: give a variety, a chromophore host or density=",
        field="material",
        value=material,
        allowed=", ".join(sorted({*VARIETIES, *HOST_DENSITY})),
    )


def _cut_function(stone: dict):
    from ..geometry import cuts
    from ..scene.schema import SHAPES

    shape = stone.get("shape")
    if shape not in SHAPES or shape in ("mesh", "gemcad") or not hasattr(cuts, str(shape)):
        raise InputError("needs a parametric cut", field="shape", value=shape)
    return getattr(cuts, shape)


def stone_mesh(stone: dict):
    """The closed mesh (mm, before ``scale``) of an ``[[object]]`` table of a parametric cut."""
    from ..scene.schema import object_config

    fn = _cut_function(stone)
    cfg = object_config(dict(stone), 0, None, Path("."))
    return fn(**cfg.params)


def carat_weight(stone: dict, density: float | None = None) -> float:
    """Weight (ct) of ``stone`` (an ``[[object]]`` table) of ``density`` (g/cm³; default
    :func:`density_of` its ``material``)."""
    if density is None:
        density = density_of(stone.get("material", "diamond"))
    if not density > 0:
        raise InputError("must be > 0", field="density", value=density)
    scale = float(stone.get("scale", 1.0))
    volume_mm3 = float(stone_mesh(stone).volume) * scale**3
    return volume_mm3 * 1.0e-3 * float(density) / CARAT_G


def size_for_carats(stone: dict, carats: float, density: float | None = None) -> dict:
    """A copy of ``stone`` with its linear dimensions (those it gives, else the cut's defaults)
    scaled so that it weighs ``carats`` (:func:`carat_weight`); its proportions are kept."""
    if not carats > 0:
        raise InputError("must be > 0", field="carats", value=carats)
    fn = _cut_function(stone)
    out = dict(stone)
    sig = inspect.signature(fn).parameters
    for k in _LINEAR:
        if k not in out and k in sig and isinstance(sig[k].default, (int, float)):
            out[k] = float(sig[k].default)
    f = (float(carats) / carat_weight(out, density)) ** (1.0 / 3.0)
    for k in _LINEAR:
        if k in out:
            out[k] = float(out[k]) * f
    return out

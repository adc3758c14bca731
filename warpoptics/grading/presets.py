"""Lighting and viewing presets of cut grading: named lightings, the observer, face-up scenes.

A grading view is a stone seen face-up by an observer at ``observer_distance_mm`` (default 250 mm,
the near point of the eye at which graders and the AGS/GIA models place the viewer) through a
perspective camera on the +z axis, under one of :data:`LIGHTINGS`, with the observer's head
blocking a cone of light of angular radius ``head_radius_deg`` about the viewing axis
(``EnvironmentConfig.head_radius_deg``; the cone stays with the observer when the stone tilts).

Lightings (``[[light]]`` tables, :func:`lighting_table`):

- ``iso`` — GemRay's ISO lighting: isotropic (equal radiance from every direction above the
  girdle plane; the built-in ``dome``, D65 with Y = 1), with the head.
- ``cos`` — GemRay's COS lighting: radiance proportional to the cosine of the angle from the
  zenith (overhead light falling to zero at the horizon; built-in ``cos``), with the head.
  GemRay (R. W. Strickland's ray tracer of the GemCad suite, with the BOG brightness optimizer)
  offers these two lighting models for its brightness numbers, ISO approximating an evenly lit
  room or integrating sphere and COS a room lit from overhead; the manual's text was not
  available to us offline, so the angular laws above are the models as their names define them,
  and GemRay's exact head-shadow size is not reproduced: the head here is a parameter.
- ``grading_dome`` — the dome of GIA's brightness modelling: ``iso`` with the head of
  :data:`GIA_DARK_RADIUS_DEG` (GIA's Diamond Cut Research Technical FAQ: "the dark area in the
  GIA brightness metric is 23 degrees in radius"); the head size stays configurable.
- ``lightbox`` — a diffuse light box with lamps overhead and at the sides over a dark surround
  (the built-in ``studio`` map; GIA's DiamondDock-like trade lighting).
- ``daylight`` — a blue sky with a sun over a grey ground (the built-in ``sky``).
- ``spots`` — the fire lighting of the light-performance sweeps (``scenes/sweeps/spots.exr``,
  written by ``scripts/make_sweep_maps.py``): 24 small bright discs (0.75 deg radius) over
  10-70 deg from the zenith above a dim dome, with the head.  GIA's fire metric (DCLR, Reinitz
  et al. 2001) uses directed, point-like light; the tilt protocol measures fire and
  scintillation under it (:mod:`warpoptics.grading.performance`).

References:
    R. W. Strickland, *GemRay* and *BOG* documentation (GemCad suite, gemcad.com).
    GIA, "Diamond Cut Research Technical FAQ" (gia.org/research, 2008), Modeling: head shadow and
    the 23 degree dark area of the brightness metric.
    T. M. Moses et al., "A foundation for grading the overall cut quality of round brilliant cut
    diamonds", Gems & Gemology 40(3), 202-228 (2004): the observer, tilting, viewing environment.
"""

from __future__ import annotations

import copy
import math
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError

__all__ = [
    "LIGHTINGS",
    "OBSERVER_DISTANCE_MM",
    "HEAD_RADIUS_DEG",
    "GIA_DARK_RADIUS_DEG",
    "SPOTS_MAP",
    "head_radius_for",
    "lighting_table",
    "tilt_rotation",
    "face_up_scene",
]

#: the observer's distance from the stone (mm): the near point of the eye (250 mm)
OBSERVER_DISTANCE_MM = 250.0
#: the default angular radius (degrees) of the observer's head obscuration in the light-return
#: protocol (:mod:`warpoptics.grading.performance`): a 88 mm wide obstruction (face) at 250 mm
HEAD_RADIUS_DEG = 10.0
#: the dark cap of GIA's brightness metric (GIA Diamond Cut Research Technical FAQ)
GIA_DARK_RADIUS_DEG = 23.0

#: the lat-long map of the ``spots`` lighting (module docstring), in the repository's scenes
SPOTS_MAP = Path(__file__).resolve().parents[2] / "scenes" / "sweeps" / "spots.exr"

LIGHTINGS: dict[str, dict[str, Any]] = {
    "iso": {"map": "dome", "head": True},
    "cos": {"map": "cos", "head": True},
    "grading_dome": {"map": "dome", "head": True, "head_radius": GIA_DARK_RADIUS_DEG},
    "lightbox": {"map": "studio", "head": False},
    "daylight": {"map": "sky", "head": False},
    "spots": {"map": str(SPOTS_MAP), "head": True},
}


def head_radius_for(width_mm: float, distance_mm: float = OBSERVER_DISTANCE_MM) -> float:
    """Angular radius (degrees) of an obstruction ``width_mm`` wide, centred on the line of sight,
    seen from the stone at ``distance_mm``: atan(w / 2 / d)."""
    if not (width_mm >= 0 and distance_mm > 0):
        raise InputError("needs width >= 0 and distance > 0", field="head", value=(width_mm, distance_mm))
    return math.degrees(math.atan2(width_mm / 2.0, distance_mm))


def lighting_table(name: str, *, head_radius_deg: float | None = None, intensity: float = 1.0) -> dict:
    """The ``[[light]]`` table of lighting ``name`` (:data:`LIGHTINGS`): the head (when the
    lighting has one) of ``head_radius_deg`` (default: the lighting's own, else
    :data:`HEAD_RADIUS_DEG`) about +z, the face-up observer's side."""
    if name not in LIGHTINGS:
        raise InputError("unknown lighting", field="lighting", value=name, allowed=", ".join(LIGHTINGS))
    spec = LIGHTINGS[name]
    if name == "spots" and not SPOTS_MAP.is_file():
        raise InputError(
            "the spots map is missing (python scripts/make_sweep_maps.py writes it)",
            file=str(SPOTS_MAP),
            field="lighting",
            value=name,
        )
    table: dict[str, Any] = {"type": "environment", "map": spec["map"], "intensity": float(intensity)}
    if spec["head"] or head_radius_deg is not None:
        r = head_radius_deg if head_radius_deg is not None else spec.get("head_radius", HEAD_RADIUS_DEG)
        if not (isinstance(r, (int, float)) and 0.0 <= r <= 90.0):
            raise InputError("must be in [0, 90] degrees", field="head_radius", value=r)
        table["head_radius"] = float(r)
        table["head_direction"] = [0.0, 0.0, 1.0]
    return table


def tilt_rotation(tilt_deg: float, azimuth_deg: float = 0.0) -> list[float]:
    """``object.rotation`` (degrees about x, then y, then z) that tilts a stone by ``tilt_deg``
    toward the observer's -y about the world x axis after turning it by ``azimuth_deg`` about its
    own axis: R = Rx(tilt) Rz(azimuth), decomposed as Rz(c) Ry(b) Rx(a) (the scene's order).
    Azimuth 0 tilts across a pavilion main of a brilliant, 22.5 deg between two mains."""
    t, p = math.radians(tilt_deg), math.radians(azimuth_deg)
    ct, st, cp, sp = math.cos(t), math.sin(t), math.cos(p), math.sin(p)
    rx = np.array([[1, 0, 0], [0, ct, -st], [0, st, ct]])
    rz = np.array([[cp, -sp, 0], [sp, cp, 0], [0, 0, 1]])
    r = rx @ rz
    b = math.asin(max(-1.0, min(1.0, -r[2, 0])))
    a = math.atan2(r[2, 1], r[2, 2])
    c = math.atan2(r[1, 0], r[0, 0])
    return [math.degrees(a), math.degrees(b), math.degrees(c)]


def face_up_scene(
    stone: dict,
    *,
    lighting: str = "iso",
    head_radius_deg: float | None = None,
    observer_distance_mm: float = OBSERVER_DISTANCE_MM,
    tilt_deg: float = 0.0,
    azimuth_deg: float = 0.0,
    size: int = 96,
    wavelengths: int = 16,
    max_depth: int = 12,
    frame_mm: float | None = None,
) -> dict:
    """A scene dict (``Scene.from_dict``) of ``stone`` (an ``[[object]]`` table, e.g.
    ``{"shape": "round_brilliant", "diameter": 6.5, "pavilion_angle": 41.0, "material":
    "diamond"}``) seen face-up from ``observer_distance_mm`` on +z by a ``size`` x ``size``
    perspective camera framing the girdle (``frame_mm``, default the stone's ``diameter`` or
    ``length``; give it for mesh and GemCAD objects) with 8 % margin, tilted by ``tilt_deg`` at
    ``azimuth_deg`` (:func:`tilt_rotation`), under ``lighting`` (:func:`lighting_table`)."""
    if not observer_distance_mm > 0:
        raise InputError("must be > 0", field="observer_distance", value=observer_distance_mm)
    ob = copy.deepcopy(stone)
    d = float(ob.get("diameter", 1.0))
    if ob.get("shape") in ("oval", "pear", "marquise", "emerald", "cushion", "princess"):
        d = float(ob.get("length", d))
    if frame_mm is not None:
        d = float(frame_mm)
    if not d > 0:
        raise InputError("must be > 0", field="frame_mm", value=d)
    ob["rotation"] = tilt_rotation(tilt_deg, azimuth_deg)
    fov = 2.0 * math.degrees(math.atan2(0.54 * d, observer_distance_mm))
    return {
        "camera": {
            "type": "perspective",
            "position": [0.0, 0.0, float(observer_distance_mm)],
            "look_at": [0.0, 0.0, 0.0],
            "up": [0.0, 1.0, 0.0],
            "fov": fov,
            "width": int(size),
            "height": int(size),
        },
        "render": {
            "spectral": "stratified",
            "wavelengths": int(wavelengths),
            "polarization": True,
            "max_depth": int(max_depth),
            "seed": 0,
            "tone": "filmic",
        },
        "light": [lighting_table(lighting, head_radius_deg=head_radius_deg)],
        "object": [ob],
    }

"""Cut design and grading: lighting and viewing presets, scope views (ASET, Ideal Scope, Hearts &
Arrows), light-performance metrics over a tilt protocol with the observer's head, and design
tools (critical angles per tier, retargeting to another index, perturbed brilliants).

What runs many renders through the sweep runner (resumable, on Dask) sits one layer up, beside
the runner: :mod:`warpoptics.sweep.grading` (the full protocol with fire and scintillation, the
tilt series with its tables, plots and animation) and :mod:`warpoptics.sweep.optimize` (the cut
optimizer).

Modules: :mod:`.presets` (lightings, the observer, face-up scenes), :mod:`.scopes` (direction-band
decomposition and the scope views), :mod:`.performance` (the protocol and the metrics),
:mod:`.design` (design tools), :mod:`.appearance` (the face-up colour of a stone under a named
light), :mod:`.carat` (carat weight and the size of a stone of a given weight).
"""

from __future__ import annotations

from .appearance import adapted_display, face_up_colour, illuminant_white
from .carat import carat_weight, density_of, size_for_carats, stone_mesh
from .design import brilliant_with_misaligned_main, critical_angle, retarget, tier_report
from .performance import (
    PROTOCOL,
    Protocol,
    average_views,
    bow_tie,
    brightness_map,
    contrast,
    extinction,
    tilted_light_return,
    windowing,
)
from .presets import (
    HEAD_RADIUS_DEG,
    LIGHTINGS,
    OBSERVER_DISTANCE_MM,
    face_up_scene,
    head_radius_for,
    lighting_table,
    tilt_rotation,
)
from .scopes import (
    aset,
    count_dark_lobes,
    count_pattern,
    direction_bands,
    hearts_and_arrows,
    ideal_scope,
    ring_profile,
    rotational_asymmetry,
)

__all__ = [
    "LIGHTINGS",
    "OBSERVER_DISTANCE_MM",
    "HEAD_RADIUS_DEG",
    "head_radius_for",
    "lighting_table",
    "tilt_rotation",
    "face_up_scene",
    "direction_bands",
    "aset",
    "ideal_scope",
    "hearts_and_arrows",
    "ring_profile",
    "count_dark_lobes",
    "count_pattern",
    "rotational_asymmetry",
    "Protocol",
    "PROTOCOL",
    "tilted_light_return",
    "contrast",
    "extinction",
    "windowing",
    "bow_tie",
    "brightness_map",
    "average_views",
    "critical_angle",
    "tier_report",
    "retarget",
    "brilliant_with_misaligned_main",
    "face_up_colour",
    "illuminant_white",
    "adapted_display",
    "carat_weight",
    "density_of",
    "size_for_carats",
    "stone_mesh",
]

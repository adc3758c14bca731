"""Pipelines: plain Python composing the stages.  :mod:`.render` (camera: ``render(scene) -> Image``),
:mod:`.bench` (optical bench: ``bench(scene) -> BenchResult``), :mod:`.caustics` (the light tracer
in the camera pipeline), :mod:`.objects` (the scene-geometry builder both call), :mod:`.adaptive`,
:mod:`.mitsuba_export`, :mod:`.microscope` (the polarizing microscope: interference colours, the
Michel-Lévy chart, conoscopic figures), :mod:`.photoelastic` (strained glass between polarizers).

The modules ``render`` and ``bench`` are reached as ``warpoptics.pipelines.render`` /
``.bench``; the functions of the same names are ``warpoptics.render`` / ``warpoptics.bench``.
"""

from . import adaptive, bench, caustics, microscope, mitsuba_export, objects, photoelastic, render

__all__ = [
    "adaptive",
    "bench",
    "caustics",
    "microscope",
    "mitsuba_export",
    "objects",
    "photoelastic",
    "render",
]

"""warpoptics: spectral, polarized light transport in gemstones, prisms and thin films (NVIDIA Warp).

Public API (the guide is docs/; units and frames in docs/conventions.md)::

    import warpoptics as wo
    wo.materials.get("diamond").n(589.3)
    wo.optics.fresnel(cos_i, n1, n2)
    wo.cuts.round_brilliant(diameter=6.5)
    image = wo.render(wo.Scene.load("scenes/diamond.toml"))
"""

from __future__ import annotations

# first, before the heavy imports below: importing it guards Ctrl-C while the command starts
from . import interrupt  # noqa: F401

# isort: split
from importlib import metadata as _metadata

try:
    __version__ = _metadata.version("warpoptics")
except _metadata.PackageNotFoundError:  # running from a source tree without install
    __version__ = "0.0.0+unknown"

from . import (
    color,
    device,
    errors,
    film,
    geometry,
    materials,
    metrics,
    optics,
    pipelines,
    scene,
    spectra,
    stages,
    sweep,
    validate,
)
from .errors import InputError
from .film.image import Image
from .geometry import cuts
from .optics import thinfilm
from .pipelines.bench import bench
from .pipelines.render import render
from .scene import Scene

__all__ = [
    "__version__",
    # subpackages and modules
    "color",
    "cuts",
    "device",
    "errors",
    "fields",
    "film",
    "geometry",
    "materials",
    "metrics",
    "optics",
    "pipelines",
    "scene",
    "spectra",
    "stages",
    "sweep",
    "thinfilm",
    "validate",
    # the top-level names: the one sanctioned second path (homes: scene.load, pipelines.render,
    # pipelines.bench, film.image, errors)
    "Scene",
    "render",
    "bench",
    "Image",
    "InputError",
]

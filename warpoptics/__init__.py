"""warpoptics: spectral, polarized light transport in gemstones, prisms and thin films (NVIDIA Warp).

Public API (see DESIGN.md)::

    import warpoptics as wo
    wo.materials.get("diamond").n(589.3)
    wo.optics.fresnel(cos_i, n1, n2)
    wo.cuts.round_brilliant(diameter=6.5)
    image = wo.render(wo.Scene.load("scenes/diamond.toml"))
"""

from __future__ import annotations

from importlib import metadata as _metadata

try:
    __version__ = _metadata.version("warpoptics")
except _metadata.PackageNotFoundError:  # running from a source tree without install
    __version__ = "0.0.0+unknown"

from . import color, device, image, materials, metrics, optics, spectra, sweep, views
from .bench import BenchScene, bench
from .errors import InputError
from .geometry import cuts
from .optics import thinfilm
from .render import Image, Renderer, render
from .scene import Scene

__all__ = [
    "__version__",
    "color",
    "cuts",
    "device",
    "image",
    "materials",
    "metrics",
    "optics",
    "spectra",
    "sweep",
    "thinfilm",
    "views",
    "InputError",
    "BenchScene",
    "bench",
    "Image",
    "Renderer",
    "Scene",
    "render",
]

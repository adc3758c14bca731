"""warpoptics: spectral, polarized light transport in gemstones, prisms and thin films (NVIDIA Warp)."""

from __future__ import annotations

from importlib import metadata as _metadata

try:
    __version__ = _metadata.version("warpoptics")
except _metadata.PackageNotFoundError:  # running from a source tree without install
    __version__ = "0.0.0+unknown"

from . import device
from .optics import thinfilm

__all__ = ["__version__", "device", "thinfilm"]

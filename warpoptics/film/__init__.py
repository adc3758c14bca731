"""What pipelines produce: :mod:`.image` (:class:`~.image.Image` with its Stokes layers, EXR/PNG
files), :mod:`.views` (polarization views of an image), :mod:`.screen` (the bench's detector
planes and their binned images)."""

from . import image, screen, views

__all__ = ["image", "screen", "views"]

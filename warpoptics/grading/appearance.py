"""Face-up colour of a stone under a named light: the measurement of the variety tests and sheet.

:func:`face_up_colour` renders ``stone`` face up (:func:`.presets.face_up_scene`, by default
under the ``grading_dome``: GIA's dome with the 23 deg dark head) with the dome's spectrum set to
``light`` (a CIE illuminant such as ``"D65"`` or ``"A"``, or any name of
:func:`warpoptics.spectra.light_spectrum`), and returns the image with the alpha-weighted mean
CIELAB of the stone's pixels (:func:`warpoptics.metrics.mean_color`) against that light's own
white (:func:`illuminant_white`): the colour an observer adapted to the light sees, so a
colourless stone is neutral under every light.

:func:`adapted_display` re-expresses an image's XYZ under D65 (the Bradford transform of the
light's white to D65) for an sRGB picture that shows the adapted colour beside its numbers.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["illuminant_white", "face_up_colour", "adapted_display"]


def illuminant_white(light: str) -> np.ndarray:
    """XYZ (Y = 1) of the light ``light`` itself (1 nm grid, CIE 1931 2 deg)."""
    from ..spectra import grid, light_spectrum, spectrum_to_xyz

    g = grid()
    w = spectrum_to_xyz(g, light_spectrum(light, g))
    return w / w[1]


def face_up_colour(
    stone: dict,
    light: str = "D65",
    *,
    lighting: str = "grading_dome",
    size: int = 32,
    wavelengths: int = 16,
    render: dict | None = None,
    **scene: Any,
):
    """Render ``stone`` (an ``[[object]]`` table) face up under ``lighting`` with the light's
    spectrum ``light``; return ``(image, colour)`` with ``colour`` the dict of
    :func:`warpoptics.metrics.mean_color` (``L``, ``a``, ``b``, ``C``, ``h``, ``coverage``, ...)
    against :func:`illuminant_white`.  ``render`` updates the ``[render]`` table (e.g.
    ``{"estimator": "point"}``); ``scene`` goes to :func:`.presets.face_up_scene` (``frame_mm``,
    ``tilt_deg``, ``max_depth``, ...)."""
    from .. import metrics
    from ..pipelines.render import Renderer
    from ..scene import Scene
    from .presets import face_up_scene

    d = face_up_scene(stone, lighting=lighting, size=size, wavelengths=wavelengths, **scene)
    d["render"].update(render or {})
    for table in d["light"]:
        table["spectrum"] = light
    img = Renderer(Scene.from_dict(d)).run()
    return img, metrics.mean_color(img.xyz, img.alpha, white_xyz=illuminant_white(light))


def adapted_display(image, light: str) -> np.ndarray:
    """Display-encoded sRGB (H, W, 3 in [0, 1]) of ``image`` as an observer adapted to ``light``
    sees it: XYZ taken from the light's white to D65 by the Bradford transform, then the image's
    own tone curve and exposure.  Under D65 this is ``image.display()``."""
    import colour as cs

    from .. import color

    xyz = np.asarray(image.xyz, dtype=np.float64)
    src = illuminant_white(light)
    dst = illuminant_white("D65")
    if not np.allclose(src, dst, rtol=1e-9, atol=1e-12):
        m = cs.adaptation.matrix_chromatic_adaptation_VonKries(src, dst, transform="Bradford")
        xyz = xyz @ np.asarray(m).T
    rgb = color.gamut_clip(xyz.reshape(-1, 3), 1.0e30).reshape(xyz.shape)
    mapped = color.tone_map(rgb, exposure=image.exposure, curve=image.tone)
    return color.encode_srgb(mapped)

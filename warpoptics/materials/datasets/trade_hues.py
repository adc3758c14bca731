"""Trade hue ranges of the main varieties: CIELAB hue angles h_ab (degrees) of the face-up colour.

Each entry of :data:`TRADE_HUES` maps a variety of :mod:`.varieties` to ``{light: (lo, hi)}``, the
hue range (degrees, wrapping through 0 when ``lo > hi``) that the trade's colour name covers under
that light (the observer adapted to it).  The ranges are the colour names ("red to purplish red",
"violetish blue to blue", ...) turned into hue angles; alexandrite's is its colour change: green to
bluish green in daylight (D65), red to purplish red in incandescent light (A).  They are bounds of
a colour name, not measurements of stones; ``tests/test_varieties.py`` checks the rendered stones
against them.
"""

from __future__ import annotations

__all__ = ["TRADE_HUES", "in_hue_range"]

TRADE_HUES: dict[str, dict[str, tuple[float, float]]] = {
    "ruby": {"D65": (345.0, 25.0)},
    "blue_sapphire": {"D65": (250.0, 300.0)},
    "emerald": {"D65": (135.0, 190.0)},
    "almandine": {"D65": (350.0, 45.0)},
    "aquamarine": {"D65": (185.0, 245.0)},
    "tanzanite": {"D65": (270.0, 310.0)},
    "peridot": {"D65": (95.0, 130.0)},
    "amethyst": {"D65": (285.0, 330.0)},
    "alexandrite": {"D65": (120.0, 220.0), "A": (330.0, 40.0)},
}


def in_hue_range(h: float, lo: float, hi: float) -> bool:
    """Whether hue angle ``h`` (degrees) lies in [lo, hi], the range wrapping through 0 when lo > hi."""
    h = float(h) % 360.0
    return lo <= h <= hi if lo <= hi else (h >= lo or h <= hi)

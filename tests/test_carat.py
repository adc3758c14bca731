"""Carat weight and size of cut stones (grading.carat), the hosts' densities, the trade hue ranges'
wrap-around, and the adapted display of grading.appearance.

References: the trade's size of a 1 ct round brilliant diamond (about 6.4-6.5 mm; Tolkowsky
proportions give 6.5 mm), the cube law of volume, and an illuminant's own white, which an observer
adapted to it sees as neutral."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

import warpoptics as wo
from warpoptics.errors import InputError
from warpoptics.grading import adapted_display, carat_weight, density_of, illuminant_white, size_for_carats
from warpoptics.materials import chromophores as C
from warpoptics.materials.datasets.densities import HOST_DENSITY
from warpoptics.materials.datasets.trade_hues import TRADE_HUES, in_hue_range
from warpoptics.materials.datasets.varieties import VARIETIES


def test_one_carat_round_brilliant_diamond_is_about_6_5_mm():
    stone = size_for_carats({"shape": "round_brilliant", "material": "diamond"}, 1.0)
    assert 6.4 <= stone["diameter"] <= 6.6
    assert carat_weight(stone) == pytest.approx(1.0, rel=1e-9)
    # mass = density x volume: the volume of the mesh at 3.52 g/cm3, 0.2 g a carat
    mesh_ct = wo.grading.stone_mesh(stone).volume * 1e-3 * 3.52 / 0.2
    assert carat_weight(stone) == pytest.approx(mesh_ct, rel=1e-12)


@pytest.mark.parametrize(
    "stone",
    [
        {"shape": "oval", "length": 1.3, "width": 1.0, "material": "ruby"},
        {"shape": "emerald", "length": 1.4, "width": 1.0, "material": "emerald"},
        {"shape": "pear", "length": 1.5, "width": 1.0, "material": "imperial_topaz"},
        {"shape": "round_brilliant", "diameter": 2.0, "crown_angle": 37.0, "material": "almandine"},
    ],
)
def test_size_for_carats_keeps_the_proportions(stone):
    two = size_for_carats(stone, 2.0)
    one = size_for_carats(stone, 1.0)
    assert carat_weight(two) == pytest.approx(2.0, rel=1e-9)
    for k in ("diameter", "length", "width"):
        if k in stone:
            # weight goes as the cube of the size; the ratios of the stone stay
            assert two[k] / one[k] == pytest.approx(2.0 ** (1.0 / 3.0), rel=1e-9)
    if "length" in stone:
        assert two["length"] / two["width"] == pytest.approx(stone["length"] / stone["width"])
    assert {k: v for k, v in two.items() if k not in ("diameter", "length", "width")} == {
        k: v for k, v in stone.items() if k not in ("diameter", "length", "width")
    }


def test_scale_enters_the_weight_as_its_cube():
    stone = {"shape": "round_brilliant", "diameter": 6.5, "material": "diamond"}
    assert carat_weight({**stone, "scale": 2.0}) == pytest.approx(8.0 * carat_weight(stone), rel=1e-9)


def test_every_host_and_variety_has_a_density():
    assert set(HOST_DENSITY) == set(C.hosts())
    for name, v in VARIETIES.items():
        d = density_of(name)
        assert 2.5 < d < 5.0
        if name != "rhodolite":
            assert d == HOST_DENSITY[v["host"]]
    assert density_of("rhodolite") < density_of("almandine")
    assert density_of({"host": "corundum", "chromophores": {"Cr3+": 0.4}}) == 4.00
    assert density_of({"base": "emerald"}) == HOST_DENSITY["beryl"]
    assert density_of(wo.materials.get("tanzanite")) == HOST_DENSITY["zoisite"]
    with pytest.raises(InputError, match="no density known"):
        density_of("cubic_zirconia_nope")
    with pytest.raises(InputError, match="needs a parametric cut"):
        carat_weight({"shape": "gemcad", "path": "x.asc"}, density=3.5)
    with pytest.raises(InputError, match="must be > 0"):
        size_for_carats({"shape": "round_brilliant"}, 0.0, density=3.52)


def test_trade_hue_ranges_wrap_through_zero():
    lo, hi = TRADE_HUES["ruby"]["D65"]
    assert lo > hi
    assert in_hue_range(355.0, lo, hi) and in_hue_range(10.0, lo, hi) and in_hue_range(370.0, lo, hi)
    assert not in_hue_range(90.0, lo, hi)
    assert in_hue_range(200.0, *TRADE_HUES["aquamarine"]["D65"])
    assert set(TRADE_HUES["alexandrite"]) == {"D65", "A"}
    assert set(TRADE_HUES) <= set(VARIETIES)


def test_adapted_display_shows_the_lights_white_as_neutral():
    """A's own white, adapted to D65 (Bradford), is the grey of D65: equal sRGB channels."""
    white_a = illuminant_white("A")
    assert white_a[1] == pytest.approx(1.0)
    assert white_a[0] > 1.0 > white_a[2]  # A is yellow against D65
    img = SimpleNamespace(xyz=np.tile(0.18 * white_a, (2, 2, 1)), exposure=0.0, tone="filmic")
    rgb = adapted_display(img, "A")
    assert np.ptp(rgb[0, 0]) < 2e-3
    raw = adapted_display(SimpleNamespace(xyz=img.xyz, exposure=0.0, tone="filmic"), "D65")
    assert raw[0, 0, 0] > raw[0, 0, 2] + 0.05  # unadapted, A's white shows orange
    assert math.isclose(float(rgb[0, 0, 1]), float(rgb[1, 1, 1]))

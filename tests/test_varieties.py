"""Named gem varieties (materials/datasets/varieties.py): library entries built from chromophores,
the scene hook that changes their concentrations, and the face-up colour of 6.5 mm round
brilliants under the D65 grading dome (GIA's 23 deg dark head): the alpha-weighted mean CIELAB of
the stone's pixels (grading.appearance.face_up_colour: metrics.mean_color, white = the light's
own) must fall in the trade hue range.

The band strengths of these hosts are chosen (no absorption coefficient with a stated
concentration was readable; see each host module), so the hue test checks that the chosen
concentrations, the band shapes from the sources and the renderer together give each variety its
trade colour: a consistency check of the whole path, not a validation against measured stones.
Renders are 32 x 32 pixels at 16 wavelengths (24 x 24 for the varieties outside the trade-range
list), about 2-6 s each on one core."""

from __future__ import annotations

import numpy as np
import pytest

import warpoptics as wo
from warpoptics.errors import InputError
from warpoptics.grading.appearance import face_up_colour
from warpoptics.grading.presets import face_up_scene
from warpoptics.materials import chromophores as C
from warpoptics.materials.datasets.trade_hues import TRADE_HUES, in_hue_range
from warpoptics.materials.datasets.varieties import VARIETIES

#: colour names of the other varieties as hue ranges (D65): yellow, pinkish orange, pink, red,
#: purplish red, orange, green, yellowish green, blue
OTHER_HUES = {
    "yellow_sapphire": (70.0, 110.0),
    "padparadscha": (10.0, 60.0),
    "morganite": (300.0, 360.0),
    "red_spinel": (345.0, 25.0),
    "rhodolite": (330.0, 20.0),
    "spessartine": (40.0, 80.0),
    "tsavorite": (130.0, 170.0),
    "demantoid": (110.0, 170.0),
    "cape_diamond": (80.0, 115.0),
    "pink_diamond": (300.0, 360.0),
    "blue_diamond": (220.0, 280.0),
    # quartz, cordierite, tourmaline, topaz, zircon: yellow, violet-blue, red to pinkish red, green,
    # turquoise to blue-green, orange, blue
    "citrine": (60.0, 110.0),
    "iolite": (260.0, 310.0),
    "rubellite": (335.0, 20.0),
    "green_tourmaline": (120.0, 170.0),
    "paraiba_tourmaline": (170.0, 215.0),
    "imperial_topaz": (20.0, 60.0),
    "blue_zircon": (200.0, 250.0),
}


def _face_up(material, light: str = "D65", *, size: int = 32) -> dict:
    stone = {"shape": "round_brilliant", "diameter": 6.5, "material": material}
    return face_up_colour(stone, light, lighting="grading_dome", size=size, wavelengths=16)[1]


def test_every_variety_builds_from_its_host():
    for name, v in VARIETIES.items():
        mat = wo.materials.get(name)
        assert mat.chromophore_host == C.host_info(v["host"])["name"]
        assert mat.chromophore_concentrations == C.normalize_concentrations(v["host"], v["concentrations"])
        assert v["source"] and v["orientation"]
        assert "chromophores:" in mat.source
    assert isinstance(wo.materials.get("ruby"), wo.materials.Uniaxial)
    assert isinstance(wo.materials.get("alexandrite"), wo.materials.Biaxial)
    assert isinstance(wo.materials.get("almandine"), wo.materials.Isotropic)
    # the aquamarine is cut with the table parallel to c
    assert wo.materials.get("aquamarine").optic_axis == pytest.approx((1.0, 0.0, 0.0))


def test_variety_alpha_is_its_hosts_chromophores():
    ruby = wo.materials.get("ruby")
    lam = np.array([410.0, 556.0, 650.0])
    conc = VARIETIES["ruby"]["concentrations"]
    ref = np.stack([C.chromophore_alpha("corundum", conc, lam, p) for p in ("o", "e")], axis=-1)
    np.testing.assert_allclose(ruby.alpha(lam), ref, rtol=1e-4, atol=1e-7)
    alex = wo.materials.get("alexandrite")
    conc = VARIETIES["alexandrite"]["concentrations"]
    ref = np.stack([C.chromophore_alpha("chrysoberyl", conc, lam, p) for p in "xyz"], axis=-1)
    np.testing.assert_allclose(alex.alpha(lam), ref, rtol=1e-4, atol=1e-7)


def test_scene_overrides_a_varietys_concentration():
    """material = "ruby" with --set object.0.material.chromophores.Cr=0.8: twice the alpha."""
    from warpoptics.scene import Scene

    d = face_up_scene({"shape": "round_brilliant", "diameter": 6.5, "material": "ruby"}, size=8)
    sc = Scene.from_dict(d).with_overrides({"object.0.material.chromophores.Cr": 0.8})
    spec = sc.objects[0].material
    assert spec == {"base": "ruby", "chromophores": {"Cr": 0.8}}
    mat = wo.materials.material_from_spec(spec)
    np.testing.assert_allclose(mat.alpha([556.0]), 2.0 * wo.materials.get("ruby").alpha([556.0]), rtol=1e-5)
    assert mat.chromophore_concentrations == {"Cr3+": 0.8}
    # other chromophores of the variety stay: blue sapphire with more Fe3+
    blue = wo.materials.material_from_spec({"base": "blue_sapphire", "chromophores": {"Fe3+": 0.2}})
    assert blue.chromophore_concentrations == {"Fe2+-Ti4+": 0.25, "Fe3+": 0.2}
    # "Fe" names one band set in corundum (Fe3+; the other is the Fe2+-Ti4+ pair) but two in beryl
    assert wo.materials.material_from_spec(
        {"base": "ruby", "chromophores": {"Fe": 0.1}}
    ).chromophore_concentrations == {
        "Cr3+": 0.4,
        "Fe3+": 0.1,
    }
    with pytest.raises(InputError, match=r"chromophores\.Fe: no such chromophore in beryl \(ambiguous"):
        wo.materials.material_from_spec({"base": "emerald", "chromophores": {"Fe": 0.1}})


@pytest.mark.parametrize("name", [n for n in TRADE_HUES if n != "alexandrite"])
def test_face_up_hue_in_trade_range(name):
    m = _face_up(name)
    lo, hi = TRADE_HUES[name]["D65"]
    assert m["C"] > 3.0, m
    assert in_hue_range(m["h"], lo, hi), (name, m)


@pytest.mark.parametrize("name", list(OTHER_HUES))
def test_face_up_hue_other_varieties(name):
    m = _face_up(name, size=24)
    assert m["C"] > 3.0, m
    assert in_hue_range(m["h"], *OTHER_HUES[name]), (name, m)


def test_alexandrite_changes_colour():
    """Green to bluish green under D65 (120-220 deg), red under A (330-40 deg), dh >= 60 deg."""
    day = _face_up("alexandrite", "D65")
    lamp = _face_up("alexandrite", "A")
    assert in_hue_range(day["h"], *TRADE_HUES["alexandrite"]["D65"]), day
    assert in_hue_range(lamp["h"], *TRADE_HUES["alexandrite"]["A"]), lamp
    dh = abs((day["h"] - lamp["h"] + 180.0) % 360.0 - 180.0)
    assert dh >= 60.0
    # a colourless chrysoberyl shows no such change: the change is the Cr3+ bands'
    clear = [_face_up({"host": "chrysoberyl"}, light) for light in ("D65", "A")]
    assert max(c["C"] for c in clear) < 2.0

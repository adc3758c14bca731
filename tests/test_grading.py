"""Cut grading (warpoptics.grading): lightings, the tilt protocol, scope views, H&A, design tools.

Renders are tiny (32-96 px, a few wavelengths, non-dispersive where the quantity is geometric);
each assertion is backed by a closed form or an independent construction in the test.
"""

from __future__ import annotations

import functools
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from warpoptics.errors import InputError
from warpoptics.geometry.cuts import round_brilliant
from warpoptics.geometry.gemcad import design_from_mesh
from warpoptics.grading import (
    bow_tie,
    brilliant_with_misaligned_main,
    contrast,
    critical_angle,
    extinction,
    face_up_scene,
    head_radius_for,
    lighting_table,
    retarget,
    tier_report,
    tilt_rotation,
)
from warpoptics.grading.performance import PROTOCOL, tilted_light_return
from warpoptics.grading.scopes import aset, count_dark_lobes, count_pattern, hearts_and_arrows, ring_profile
from warpoptics.scene.load import Scene
from warpoptics.stages.environment import EnvironmentConfig, EnvironmentLight

DIAMOND = {"shape": "round_brilliant", "diameter": 6.5, "material": "diamond"}
# the gallery's deep stone ("deep pavilion 43 deg with crown 34.5"; table 55 %)
DEEP = {**DIAMOND, "table": 0.55, "crown_angle": 34.5, "pavilion_angle": 43.0}

# the independent NumPy path tree and the meridional closed form (scripts/reproduce)
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts" / "reproduce"))


@functools.cache
def _aset48(pavilion: float, table: float = 0.53, tilt: float = 0.0):
    """ASET zones and bands at 48 px (shared by the tests below: 4 renders each)."""
    _img, zones, bands = aset({**DIAMOND, "table": table, "pavilion_angle": pavilion}, size=48, tilt_deg=tilt)
    return zones, bands


def _env_y(config, dirs, device):
    from warpoptics.pipelines.mitsuba_export import environment_rgb

    rgb = np.asarray(environment_rgb(EnvironmentLight(config, device), dirs, device=device), dtype=np.float64)
    return rgb.sum(axis=-1)  # D65 white maps to equal linear sRGB; the sum is proportional to Y


def test_cos_lighting_and_head_cone(device):
    # radiance of "cos" against cos(zenith) (closed form); the head cone is black inside, lit outside
    th = np.radians([0.0, 20.0, 40.0, 60.0, 80.0])
    dirs = np.stack([np.sin(th), 0 * th, np.cos(th)], axis=-1)
    y = _env_y(EnvironmentConfig(map="cos"), dirs, device)
    np.testing.assert_allclose(y / y[0], np.cos(th), rtol=2e-5)  # float32 kernel arithmetic
    y = _env_y(EnvironmentConfig(map="dome", head_radius_deg=30.0), dirs, device)
    assert y[0] == 0 and y[1] == 0 and y[2] > 0 and np.allclose(y[2:], y[2])
    tilted = EnvironmentConfig(map="dome", head_radius_deg=10.0, head_direction=(1.0, 0.0, 1.0))
    y = _env_y(tilted, dirs, device)
    assert y[2] == 0 and y[0] > 0  # 45 deg away from +z toward +x: 40 deg is inside, the zenith outside


def test_head_config_errors():
    with pytest.raises(InputError, match="head_radius"):
        EnvironmentConfig(map="dome", head_radius_deg=120.0)
    with pytest.raises(InputError, match="head_direction"):
        EnvironmentConfig(map="dome", head_radius_deg=10.0, head_direction=(0.0, 0.0, 0.0))
    with pytest.raises(InputError, match="lighting"):
        lighting_table("candle")


def test_presets_scene_and_tilt_rotation():
    # the scene order (Rz Ry Rx) reproduces Rx(tilt) Rz(azimuth), built independently here
    data = face_up_scene(DIAMOND, lighting="cos", tilt_deg=17.0, azimuth_deg=22.5)
    sc = Scene.from_dict(data)
    t, p = math.radians(17.0), math.radians(22.5)
    rx = np.array([[1, 0, 0], [0, math.cos(t), -math.sin(t)], [0, math.sin(t), math.cos(t)]])
    rz = np.array([[math.cos(p), -math.sin(p), 0], [math.sin(p), math.cos(p), 0], [0, 0, 1]])
    np.testing.assert_allclose(sc.objects[0].rotation_matrix(), rx @ rz, atol=1e-12)
    assert tilt_rotation(0.0) == [0.0, 0.0, 0.0]
    assert sc.camera.position[2] == 250.0 and sc.lights[0].map == "cos"
    assert sc.lights[0].head_radius_deg == PROTOCOL.head_radius_deg
    # TOML keys reach the config
    data["light"][0]["head_radius"] = 23.0
    assert Scene.from_dict(data).lights[0].head_radius_deg == 23.0
    assert head_radius_for(2 * 250.0 * math.tan(math.radians(10.0))) == pytest.approx(10.0)


def test_light_return_peaks_inside_gia_excellent_range():
    # the tilted, head-obscured protocol (reduced: 32 px, face-up + 10 deg, one azimuth) puts the
    # maximum of 40 / 41 / 42 deg at 41 deg, inside GIA's Excellent 40.6-41.8 deg; the face-up
    # dome without the head (the old metric) prefers the shallower 40 deg (grading guide: 39.5)
    import dataclasses

    proto = dataclasses.replace(PROTOCOL, tilts=(0.0, 10.0), azimuths=(0.0,), size=32, wavelengths=4)
    lr = [
        tilted_light_return({**DIAMOND, "table": 0.55, "pavilion_angle": p}, proto)["light_return"]
        for p in (40.0, 41.0, 42.0)
    ]
    assert lr[1] > lr[0] and lr[1] > lr[2], lr


def test_aset_zone_fractions():
    tolk = _aset48(40.75)[0]
    deep = _aset48(43.0, 0.55)[0]
    shallow = _aset48(22.0)[0]
    for z in (tolk, deep, shallow):  # the four zones split all of the light, and all of the area
        assert sum(z[k] for k in ("blue", "red", "green", "leak")) == pytest.approx(1.0, abs=1e-9)
        assert sum(z[f"area_{k}"] for k in ("blue", "red", "green", "leak")) == pytest.approx(1.0, abs=1e-9)
    # the deep stone leaks more light overall than the Tolkowsky (measured 0.116 vs 0.065 at 48 px)
    assert deep["leak"] > 1.3 * tolk["leak"]
    # closed form: a ray entering the table along the axis meets a pavilion main at incidence p (the
    # pavilion angle) and the opposite one at 180 - 3p; both exceed the critical angle 24.4 deg for
    # 24.4 < p < 51.9, so neither the Tolkowsky's nor the 43 deg stone's pavilion centre is a
    # window, while a 22 deg pavilion (p < 24.4) is one (measured 0.74; Fresnel transmission at
    # 22 deg is about 0.8)
    assert shallow["leak_centre"] > 0.5 and shallow["area_leak_centre"] > 0.9
    assert tolk["area_leak_centre"] < 0.02 and deep["area_leak_centre"] < 0.02
    # and the deep stone returns more of its light from low angles (green) than the Tolkowsky
    assert deep["green"] > tolk["green"]


def test_aset_deep_pavilion_leaks_under_the_crown_not_through_the_centre():
    # The grading work's acceptance check ("ASET of a deep-pavilion (43 deg) brilliant shows leakage
    # through the pavilion centre and the Tolkowsky does not") against the physics.  Leakage "shows" where it
    # dominates a pixel (area_*, the white of the ASET image); energy shares (leak_*) count every
    # path order.  Regions in girdle radii: centre r < 0.3, crown r >= table.
    from aset_hand_trace import centre_leak_onset, trace_zones

    tolk_z, tolk_b = _aset48(40.75)
    deep_z, deep_b = _aset48(43.0, 0.55)
    # 1. neither pavilion centre leaks: no leak-dominated pixel (0.02 is 3 of its ~140 pixels), and
    #    the deep centre's leakage energy is small (measured 0.013; its centre is red: 19.7 deg)
    assert tolk_z["area_leak_centre"] < 0.02 and deep_z["area_leak_centre"] < 0.02
    assert deep_z["leak_centre"] < 0.05
    # 2. the deep stone leaks where it really does, through the crown (under the stars and bezels
    #    just outside the table edge, and at the girdle): measured area 0.108 vs 0.029, energy
    #    0.138 vs 0.046; a factor 2 leaves room for the pixel jitter at facet edges
    assert deep_z["area_leak_crown"] > 0.08
    assert deep_z["area_leak_crown"] > 2.0 * tolk_z["area_leak_crown"]
    assert deep_z["leak_crown"] > 2.0 * tolk_z["leak_crown"]
    # 3. tilted 10 deg (the grading protocol's tilt) the deep stone leaks under the table ring
    #    (0.3 <= r < the table's inradius), the Tolkowsky hardly: measured area 0.167 vs 0.008
    for pav, table, lo, hi in ((43.0, 0.55, 0.1, 1.0), (40.75, 0.53, 0.0, 0.05)):
        b = _aset48(pav, table, 10.0)[1]
        r = b.radius()
        ring = (r >= 0.3) & (r < table * math.cos(math.pi / 8))
        assert lo < b.areas(ring)["leak"] < hi, (pav, b.areas(ring))
        assert b.areas(r < 0.3)["leak"] < 0.02  # and still no leaking centre
    # 4. an independent NumPy path tree (facet planes, unpolarized Fresnel, 40 bounces, one ray
    #    per pixel centre) gives the renderer's zone energies in every region: measured within
    #    0.017 (the renderer's Jones matrices vs unpolarized weights on multi-bounce paths, its
    #    jittered sub-rays at facet edges), asserted within 0.03
    for stone, b in (({**DIAMOND, "pavilion_angle": 40.75}, tolk_b), (DEEP, deep_b)):
        ref = trace_zones(stone, size=48)
        r, on = ref["r"], ref["dominant"] >= 0
        e_r = np.concatenate([b.bands, b.leak[..., None]], axis=-1)
        for region in (r < 0.3, r >= stone.get("table", 0.53), np.ones_like(on)):
            w = b.alpha * region
            rend = (e_r * w[..., None]).sum(axis=(0, 1))
            hand = ref["energy"][on & region].sum(axis=0)
            np.testing.assert_allclose(rend / rend.sum(), hand / hand.sum(), atol=0.03)
        if stone is not DEEP:
            # the Tolkowsky centre's 0.116 leakage energy is second order: none on paths of total
            # reflections only, all after one or more Fresnel partial reflections (the table
            # returns R ~ 0.17 of the 45 deg exit ray; it meets a main at 23.75 deg < 24.4)
            c = on & (r < 0.3)
            lb = ref["leak_by_partial"][c].sum(axis=0) / ref["energy"][c].sum()
            assert lb[0] < 0.002 and lb[1:].sum() > 0.09, lb
    # 5. where the centre does start to leak: the axial ray leaves the second main from below the
    #    girdle plane for p > 55.48 deg (closed form, aset_hand_trace.meridional); the renderer's
    #    leak-dominated centre crosses one half between 55 and 56 deg (measured 0.25 -> 0.70)
    onset = centre_leak_onset()
    assert 55.0 < onset < 56.0
    assert _aset48(55.0, 0.55)[0]["area_leak_centre"] < 0.4
    assert _aset48(56.0, 0.55)[0]["area_leak_centre"] > 0.5


def _mode(values):
    vals, counts = np.unique(np.asarray(values), return_counts=True)
    return int(vals[np.argmax(counts)])


def _asym90(img):
    # 90 deg is one of the exact 8-fold symmetries and maps the (even-sized) pixel grid onto itself;
    # 2x2 block means first, so that the one-sample-per-pixel jitter at facet edges averages down
    img = img.reshape(img.shape[0] // 2, 2, img.shape[1] // 2, 2).mean(axis=(1, 3))
    q = np.rot90(img)
    return float(np.abs(img - q).sum() / (img + q).sum())


def test_hearts_and_arrows(tmp_path):
    images = {}
    for delta in (0.0, 0.5):
        p = tmp_path / f"brilliant_{delta}.ply"
        brilliant_with_misaligned_main(delta, diameter=6.5).export(p)
        stone = {"shape": "mesh", "path": str(p), "material": "diamond"}
        for face_down in (False, True):
            img, _ = hearts_and_arrows(stone, face_down=face_down, size=96, frame_mm=6.5)
            images[delta, face_down] = img
    half = 96 / 2 / 1.08  # the girdle radius in pixels
    arrows = [
        count_dark_lobes(ring_profile(images[0.0, False], r * half)) for r in np.linspace(0.15, 0.45, 9)
    ]
    hearts = [count_dark_lobes(ring_profile(images[0.0, True], r * half)) for r in np.linspace(0.12, 0.3, 7)]
    assert _mode(arrows) == 8, arrows
    assert _mode(hearts) == 8, hearts
    # the pattern counter (rings low-passed to harmonics <= 24, 8 lobes on 2/3 of the rings)
    for face_down in (False, True):
        lc = count_pattern(images[0.0, face_down], face_down=face_down)
        assert lc.count == 8 and lc.verdict == "intact", lc
        # a re-cut main is 8 lobes or a broken pattern, never another number of hearts
        assert count_pattern(images[0.5, face_down], face_down=face_down).count in (8, None)
    # the deep 43 deg stone's hearts: its outer rings read 16 lobes (two per main), and the gallery
    # (256 px) used to report "16 hearts"; the counter calls the pattern broken (8 lobes on 3-4 of
    # the 7 rings at 96-256 px, against 5-7 for the Tolkowsky and GIA-reference stones)
    deep, _b = hearts_and_arrows(DEEP, face_down=True, size=96)
    lc = count_pattern(deep, face_down=True)
    assert lc.count is None and lc.verdict.startswith("broken"), lc
    assert 16 in lc.per_ring
    # 0.5 deg on one pavilion main breaks the symmetry measurably, face-up and face-down
    for face_down in (False, True):
        exact, bent = _asym90(images[0.0, face_down]), _asym90(images[0.5, face_down])
        # measured 0.021 -> 0.051 face-up, 0.029 -> 0.053 face-down; the exact stone's floor is the
        # one-sample-per-pixel jitter at facet edges
        assert bent > 1.5 * exact and bent - exact > 0.01, (face_down, exact, bent)


def test_misaligned_main_geometry():
    exact = brilliant_with_misaligned_main(0.0, diameter=1.0)
    ref = round_brilliant(diameter=1.0)
    assert exact.volume == pytest.approx(ref.volume, rel=1e-9)
    bent = brilliant_with_misaligned_main(0.5, diameter=1.0)
    names = bent.metadata["facet_names"]
    n = bent.metadata["planes"][names.index("pavilion main 0")][:3]
    assert math.degrees(math.acos(-n[2])) == pytest.approx(40.75 + 0.5, abs=1e-9)


def test_critical_angle_and_retarget():
    assert critical_angle(2.417) == pytest.approx(math.degrees(math.asin(1 / 2.417)))
    design = design_from_mesh(round_brilliant(diameter=1.0, pavilion_angle=38.0))
    quartz = 1.544
    rows = tier_report(design, n=quartz)
    mains = [r for r in rows if r["part"] == "pavilion" and abs(abs(r["angle"]) - 38.0) < 1e-6]
    assert mains and all(r["windows"] for r in mains)  # 38 < asin(1/1.544) = 40.4 deg
    assert not any(r["windows"] for r in tier_report(design))  # in diamond it is total reflection
    new, report = retarget(design, quartz)
    assert new.index == quartz and not any(r["windows"] for r in report)
    d_tc = critical_angle(quartz) - critical_angle(design.index)
    m2 = [r for r in report if r["part"] == "pavilion" and abs(abs(r["angle"]) - (38.0 + d_tc)) < 1e-6]
    assert len(m2) == len(mains)


def test_view_metrics_closed_forms():
    y = np.zeros((4, 4, 3))
    y[..., 1] = [[1, 1, 0, 0]] * 4
    a = np.ones((4, 4))
    assert contrast(y, a) == pytest.approx(1.0)  # half at 1, half at 0: sd 0.5 / mean 0.5
    assert extinction(y, a) == pytest.approx(0.5)
    # a dark band across the middle rows of a stone long along y
    z = np.ones((8, 4, 3))
    z[3:5, :, 1] = 0.0
    assert bow_tie(z, np.ones((8, 4)), band=0.25) == pytest.approx(1.0)
    assert bow_tie(np.ones((8, 4, 3)), np.ones((8, 4))) == pytest.approx(0.0)


def test_preset_scenes_load():
    # the named lighting presets under scenes/grading are valid scenes with the stated lightings
    from pathlib import Path

    root = Path(__file__).resolve().parents[1] / "scenes" / "grading"
    want = {"iso": ("dome", 10.0), "cos": ("cos", 10.0), "grading_dome": ("dome", 23.0)}
    want |= {"lightbox": ("studio", 0.0), "daylight": ("sky", 0.0)}
    for name, (m, head) in want.items():
        sc = Scene.load(root / f"{name}.toml")
        assert (sc.lights[0].map, sc.lights[0].head_radius_deg) == (m, head)
        assert sc.camera.position[2] == 250.0


def test_aset_centre_of_deep_stones_sees_the_head_not_leakage():
    # A ray entering the table along the axis meets two opposite pavilion mains (incidences p and
    # 180 - 3p, both above the critical angle for 24.4 < p < 51.9) and leaves the table at
    # asin(n sin|180 - 4p|) from the zenith: 19.7 deg for p = 43 (the red zone, 10-45 deg) and
    # 4.8 deg for p = 44.5 (inside the 10 deg head: blue).  The toggle at 45 deg (red/green) falls
    # at p = 40.76, as the AGS/ASET literature states (Whiteflash, "ASET table reflection": "at
    # pavilion angles right about 40.76 the reflection draws light from the point where red meets
    # green").  So the dark centre of a deep stone is the observer's reflection, not leakage.
    n = 2.4175  # diamond at 589 nm
    for p, zone in ((43.0, "band1"), (44.5, "band0")):
        src = math.degrees(math.asin(n * math.sin(math.radians(abs(180.0 - 4.0 * p)))))
        assert (zone == "band0") == (src < PROTOCOL.head_radius_deg)
        b = _aset48(p, 0.55 if p == 43.0 else 0.53)[1]
        centre = b.fractions(b.radius() < 0.1)
        # measured 0.80 (43) and 0.98 (44.5); leakage 0.03 and 0.00
        assert centre[zone] > 0.7 and centre["leak"] < 0.05, (p, centre)
    # the exit angle moves ~10 deg per degree of pavilion here: 0.25 deg is 0.025 deg of pavilion
    # ("right about 40.76"; n of diamond 2.417-2.4175)
    toggle = math.degrees(math.asin(n * math.sin(math.radians(180.0 - 4 * 40.76))))
    assert toggle == pytest.approx(45.0, abs=0.25)

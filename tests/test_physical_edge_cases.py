"""Physical edge cases stay finite and are what they should be; a NaN/Inf scan of tiny renders
over random scenes."""

from __future__ import annotations

import importlib

import numpy as np
import pytest
from _helpers import BASE, FILE

import warpoptics as wo
from warpoptics.scene import Scene

# the modules (``warpoptics.optics`` re-exports functions with the same names)
fr = importlib.import_module("warpoptics.optics.fresnel")
tf = importlib.import_module("warpoptics.optics.thinfilm")


def _scene_data(obj, **render):
    return {**BASE, "render": {**BASE["render"], **render}, "object": obj}


def _finite_render(data, device, **kw):
    img = wo.render(Scene.from_dict(data, path=FILE), device=device, **kw)
    assert np.isfinite(img.xyz).all() and np.isfinite(img.stokes).all() and np.isfinite(img.alpha).all()
    assert (img.xyz[..., 1] >= -1e-6).all()
    return img


def test_fresnel_grazing_critical_and_normal_are_finite(device):
    n1, n2 = 2.417, 1.0
    cos_c = np.sqrt(1 - (n2 / n1) ** 2)
    cos_i = np.array([0.0, 1e-7, cos_c, np.nextafter(cos_c, 1), np.nextafter(cos_c, 0), 1.0])
    for a, b in ((n1, n2), (n2, n1), (1.0, 1.0), (1.5, 2.0 + 1e3j)):
        rs, rp, ts, tp = fr.fresnel(cos_i, a, b, device=device)
        Rs, Rp, Ts, Tp = fr.fresnel_power(cos_i, a, b, device=device)
        for x in (rs, rp, ts, tp, Rs, Rp, Ts, Tp):
            assert np.all(np.isfinite(x))
        assert np.all(Rs <= 1 + 1e-5) and np.all(Rp <= 1 + 1e-5) and np.all(Rs >= 0) and np.all(Rp >= 0)
    # grazing incidence from the rare side reflects everything (the limit of Fresnel's equations)
    Rs, Rp, _, _ = fr.fresnel_power(np.array([0.0]), 1.0, 1.5, device=device)
    assert Rs[0] == pytest.approx(1.0, abs=1e-5) and Rp[0] == pytest.approx(1.0, abs=1e-5)


def test_birefringent_interface_along_the_optic_axis_is_finite(device):
    """Incidence exactly along the optic axis: the o/e frame is degenerate (any transverse axis is
    ordinary); eq. 5 must still give finite coefficients conserving energy."""
    from warpoptics.optics import birefringence as bi

    for axis in ((0.0, 0.0, 1.0), (0.0, 0.0, -1.0)):
        res = bi.generalized_fresnel_coefficients(
            (0.0, 0.0, -1.0), (0.0, 0.0, 1.0), 1.0, (1.658, 1.486, axis), mode="o", device=device
        )
        assert np.all(np.isfinite(res.coefficients)) and np.all(np.isfinite(res.flux))
        mr, mt = bi.fresnel_matrices(
            (0.0, 0.0, -1.0), (0.0, 0.0, 1.0), 1.0, (1.658, 1.486, axis), device=device
        )
        assert np.all(np.isfinite(mr)) and np.all(np.isfinite(mt))
    # along the axis both modes see n_o: the reflectance is the isotropic one, for both
    r_iso = ((1.658 - 1) / (1.658 + 1)) ** 2
    assert np.allclose(np.abs(mr) ** 2 * np.eye(2), r_iso * np.eye(2), atol=2e-5)


def test_thin_film_zero_and_very_thick(device):
    lam = np.linspace(380.0, 780.0, 9)
    # zero thickness: the bare interface, exactly (independent: Fresnel at normal incidence)
    r0 = tf.reflectance(lam, [1.38], [0.0], 1.0, 1.52, device=device)
    assert np.allclose(r0, ((1.52 - 1) / 2.52) ** 2, atol=1e-6)
    # 1 m thick lossless film: finite, 0 <= R <= 1, R + T = 1
    r = tf.reflectance(lam, [1.38], [1e9], 1.0, 1.52, angle=60.0, device=device)
    t = tf.transmittance(lam, [1.38], [1e9], 1.0, 1.52, angle=60.0, device=device)
    assert np.all(np.isfinite(r)) and np.all(np.isfinite(t))
    assert np.allclose(r + t, 1.0, atol=1e-4)
    # a thick absorbing film underflows to zero transmission, not NaN
    t = tf.transmittance(lam, [1.5 + 0.5j], [1e7], 1.0, 1.52, device=device)
    assert np.all(np.isfinite(t)) and np.all(t == 0.0)


def test_enormous_absorption_underflows_to_black(device):
    obj = [
        {
            "shape": "cube",
            "size": 6.0,
            "material": {
                "base": "diamond",
                "bands": [{"center_nm": 550.0, "width_nm": 200.0, "peak_alpha_per_mm": 10.0}],
            },
            "absorption_scale": 1e6,
        }
    ]
    img = _finite_render(_scene_data(obj), device)
    clear = _finite_render(_scene_data([{**obj[0], "absorption_scale": 0.0}]), device)
    inside = img.alpha > 0.99
    assert inside.any()
    # only the surface reflection survives: darker than the clear stone
    assert img.xyz[inside, 1].mean() < 0.8 * clear.xyz[inside, 1].mean()


def test_camera_on_and_inside_a_surface(device):
    """Rays starting exactly on a face (and inside the solid) must not NaN or self-intersect."""
    cube = [{"shape": "cube", "size": 4.0, "material": "sapphire"}]
    for pos in ([0.0, 0.0, 2.0], [0.0, 0.0, 0.0], [2.0, 2.0, 2.0]):
        data = _scene_data(cube)
        data["camera"] = {"position": pos, "look_at": [0.3, 0.2, -5.0], "fov": 60.0, "width": 4, "height": 4}
        _finite_render(data, device)


def test_coincident_objects(device):
    """Two identical stones at the same place: coincident faces tie and the closest-hit query
    resolves the tie the same way every time, so the light only ever meets one of them: the
    image equals the one-stone image exactly, byte for byte (Y mean 0.30119 both). Coincident
    solids are not merged or treated as one medium."""
    stone = {"shape": "round_brilliant", "diameter": 6.5, "material": "diamond"}
    # point samples for both (the one stone alone would be traced in beams, which need one solid)
    one = _finite_render(_scene_data([stone], estimator="point"), device)
    two = _finite_render(_scene_data([stone, dict(stone)], estimator="point"), device)
    # every output layer, not only the coverage mask: a second stone that the light met anywhere
    # would change the values there
    for a, b in ((one.xyz, two.xyz), (one.stokes, two.stokes), (one.alpha, two.alpha)):
        assert a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()
    assert float(one.xyz[..., 1].mean()) > 0.0


# ---- NaN/Inf scan over random tiny scenes ----------------------------------------------------------


def _random_scene(rng) -> dict:
    from warpoptics.materials import Uniaxial
    from warpoptics.materials.library import get, names

    shapes = [
        {
            "shape": "round_brilliant",
            "diameter": float(rng.uniform(3, 8)),
            "pavilion_angle": float(rng.uniform(38, 44)),
        },
        {"shape": "oval", "length": 8.0, "width": 6.0},
        {"shape": "princess"},
        {"shape": "cube", "size": float(rng.uniform(2, 6))},
        {"shape": "prism", "apex_angle": float(rng.uniform(30, 70)), "size": 5.0, "length": 5.0},
        {"shape": "sphere", "diameter": 5.0, "subdivisions": 2},
    ]
    obj = dict(shapes[rng.integers(len(shapes))])
    obj["material"] = str(rng.choice(names()))
    obj["rotation"] = [float(x) for x in rng.uniform(-90, 90, 3)]
    if rng.random() < 0.5:
        if isinstance(get(obj["material"]), Uniaxial):
            obj["optic_axis"] = [float(x) for x in rng.normal(size=3)]
    theta, phi = rng.uniform(0, np.pi), rng.uniform(0, 2 * np.pi)
    dist = rng.uniform(15, 40)
    pos = [
        float(dist * np.sin(theta) * np.cos(phi)),
        float(dist * np.sin(theta) * np.sin(phi)),
        float(dist * np.cos(theta)),
    ]
    spectral = str(rng.choice(["rgb3", "uniform", "importance", "stratified"]))
    render = {
        "spectral": spectral,
        "wavelengths": 3,
        "polarization": bool(rng.random() < 0.5),
        "birefringence": str(rng.choice(["exact", "approx"])),
        "max_depth": int(rng.integers(1, 10)),
        "seed": int(rng.integers(0, 1000)),
    }
    if spectral in ("uniform", "importance"):
        render["wavelengths"] = 2
    light = {"type": "environment", "map": str(rng.choice(["studio", "sky", "dome", "constant"]))}
    up = [0.0, 0.0, 1.0] if abs(np.cos(theta)) < 0.95 else [0.0, 1.0, 0.0]
    return {
        "camera": {
            "position": pos,
            "look_at": [0.0, 0.0, 0.0],
            "up": up,
            "fov": 25.0,
            "width": 8,
            "height": 8,
        },
        "render": render,
        "light": [light],
        "object": [obj],
    }


def test_random_scenes_render_finite(device):
    rng = np.random.default_rng(12)
    for _ in range(10):
        data = _random_scene(rng)
        img = wo.render(Scene.from_dict(data, path=FILE), device=device)
        ok = np.isfinite(img.xyz).all() and np.isfinite(img.stokes).all()
        assert ok, data
        s = img.stokes
        pol = np.linalg.norm(s[..., 1:], axis=-1)
        assert np.all(pol <= s[..., 0] * (1 + 1e-3) + 1e-6), data
        assert np.all(img.xyz[..., 1] >= -1e-6), data

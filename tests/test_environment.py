"""Lat-long map conventions of the environment light (stages/environment.py).

The column of each axis is checked against the conventions as their owners document them
(Blender: ``u = -atan2(y, x) / 2 pi + 0.5``, gpu_shader_material_tex_environment.glsl; Mitsuba 3
envmap: ``u = atan2(x, -z) / 2 pi`` in its y-up frame, turned to z up by rotate(x, 90 deg)),
the kernel's lookup against the NumPy twin ``latlong_uv``, and what a camera sees.
"""

import dataclasses

import numpy as np
import pytest

import warpoptics as wo
from warpoptics.errors import InputError
from warpoptics.film.image import write_exr
from warpoptics.pipelines.mitsuba_export import environment_rgb
from warpoptics.stages.environment import (
    LATLONG_CONVENTIONS,
    EnvironmentConfig,
    EnvironmentLight,
    latlong_directions,
    latlong_frame,
    latlong_uv,
)

AXES = np.array([[1.0, 0, 0], [0, 1.0, 0], [-1.0, 0, 0], [0, -1.0, 0]])


def blender_u(d):
    return np.mod(-np.arctan2(d[..., 1], d[..., 0]) / (2 * np.pi) + 0.5, 1.0)


def mitsuba_u(d):
    # Mitsuba's local frame is world turned back by rotate(x, -90): local = (x, z, -y)
    local = np.stack([d[..., 0], d[..., 2], -d[..., 1]], axis=-1)
    return np.mod(np.arctan2(local[..., 0], -local[..., 2]) / (2 * np.pi), 1.0)


def test_axis_columns():
    """+x, +y, -x, -y land on the documented columns (u from the left edge), z up, v = 0 at the
    zenith: blender 0.5, 0.25, 0 | 1, 0.75; mitsuba 0.25, 0, 0.75, 0.5; mirrored 0.5, 0.75, 0, 0.25."""
    table = {
        "blender": [0.5, 0.25, 0.0, 0.75],
        "mitsuba": [0.25, 0.0, 0.75, 0.5],
        "mirrored": [0.5, 0.75, 0.0, 0.25],
    }
    for conv, expected in table.items():
        u = latlong_uv(AXES, conv)[:, 0]
        # u = 0 and u = 1 are the same column (the seam)
        assert np.allclose(np.minimum(np.abs(u - expected), 1 - np.abs(u - expected)), 0, atol=1e-12), conv
    assert latlong_uv([0, 0, 1.0])[1] == pytest.approx(0.0)
    assert latlong_uv([0, 0, -1.0])[1] == pytest.approx(1.0)
    rng = np.random.default_rng(1)
    d = rng.normal(size=(500, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    # against the owners' own formulas
    assert np.allclose(latlong_uv(d, "blender")[:, 0], blender_u(d), atol=1e-12)
    w = np.abs(latlong_uv(d, "mitsuba")[:, 0] - mitsuba_u(d))
    assert np.allclose(np.minimum(w, 1 - w), 0, atol=1e-12)
    assert np.allclose(latlong_uv(d, "mirrored")[:, 0], 1 - blender_u(d), atol=1e-12)
    # the frames are rotations, except the mirror
    dets = {c: np.linalg.det(latlong_frame(c)) for c in LATLONG_CONVENTIONS}
    assert dets == pytest.approx({"blender": 1.0, "mitsuba": 1.0, "mirrored": -1.0})


def test_rotation_turns_counter_clockwise():
    """rotation = 90 deg puts what the convention shows along +x along +y (counter-clockwise seen
    from above), in every convention; the texel-centre directions invert latlong_uv."""
    for conv in LATLONG_CONVENTIONS:
        assert latlong_uv([0, 1.0, 0], conv, 90.0) == pytest.approx(latlong_uv([1.0, 0, 0], conv))
        d = latlong_directions(16, 8, conv, 30.0)
        uv = latlong_uv(d, conv, 30.0)
        assert np.allclose(uv[..., 0], ((np.arange(16) + 0.5) / 16)[None, :], atol=1e-12)
        assert np.allclose(uv[..., 1], ((np.arange(8) + 0.5) / 8)[:, None], atol=1e-12)


@pytest.mark.parametrize(
    "conv,rot",
    [("blender", 0.0), ("mitsuba", 0.0), ("mirrored", 0.0), ("blender", 37.0), ("mirrored", -120.0)],
)
def test_kernel_reads_the_texel_latlong_uv_names(tmp_path, device, conv, rot):
    """The kernel (environment_radiance, through its spectral XYZ) toward the texel centre that
    latlong_uv names returns that texel: a grey map of random levels (grey = D65 x level
    exactly in both colour models), every texel probed."""
    rng = np.random.default_rng(3)
    h, w = 8, 16
    lum = rng.uniform(0.1, 1.0, size=(h, w)).astype(np.float32)
    path = tmp_path / "grey.exr"
    write_exr(path, np.repeat(lum[..., None], 3, -1), ["R", "G", "B"])
    light = EnvironmentLight(EnvironmentConfig(map=str(path), convention=conv, rotation_deg=rot), device)
    d = latlong_directions(w, h, conv, rot).reshape(-1, 3).astype(np.float32)
    rgb = environment_rgb(light, d, step=1.0, device=device).reshape(h, w, 3)
    # the 1 nm trapezoid of D65 x basis x CMFs reproduces RGB white to ~1e-3; float32 directions
    # put the lookup within ~1e-6 texel of the centre
    assert np.allclose(rgb, lum[..., None], rtol=3e-3, atol=1e-4)


def test_kernel_interpolates_across_the_seam(tmp_path, device):
    """Bilinear lookup next to the seam (u near 0 and 1, where column w-1 meets column 0) and in
    the map's interior, against a NumPy bilinear interpolation that wraps the column index with
    np.mod: the kernel's azimuth wrap must join the two edge columns."""
    rng = np.random.default_rng(5)
    h, w = 8, 16
    lum = rng.uniform(0.1, 1.0, size=(h, w)).astype(np.float32)
    path = tmp_path / "grey.exr"
    write_exr(path, np.repeat(lum[..., None], 3, -1), ["R", "G", "B"])
    light = EnvironmentLight(EnvironmentConfig(map=str(path)), device)
    u = np.array([1e-4, 0.01, 0.5 / w, 0.2, 0.61, 1 - 0.5 / w, 0.99, 1 - 1e-4])
    v = np.full_like(u, 3.5 / h)  # a row centre: only the columns interpolate
    phi, theta = (0.5 - u) * 2 * np.pi, v * np.pi  # Blender: u = 0.5 - atan2(y, x) / 2 pi
    d = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], -1)
    assert np.allclose(latlong_uv(d), np.stack([u, v], -1), atol=1e-9)
    x = u * w - 0.5
    i0 = np.floor(x).astype(int)
    fx = x - i0
    want = (1 - fx) * lum[3, np.mod(i0, w)] + fx * lum[3, np.mod(i0 + 1, w)]
    rgb = environment_rgb(light, d.astype(np.float32), step=1.0, device=device)
    assert np.allclose(rgb, want[:, None], rtol=3e-3, atol=1e-4)


def test_camera_sees_the_right_side_on_the_right(tmp_path, device):
    """A camera looking along +x with z up: the map's columns right of the centre (u > 0.5,
    Blender: toward -y) appear on the image's right, as in Blender; with "mirrored" on its left."""
    h, w = 16, 32
    img = np.zeros((h, w, 3), np.float32)
    img[:, : w // 2] = [1.0, 0.05, 0.05]  # left half of the file: red
    img[:, w // 2 :] = [0.05, 0.05, 1.0]  # right half: blue
    path = tmp_path / "halves.exr"
    write_exr(path, img, ["R", "G", "B"])
    scene = wo.Scene.from_dict(
        {
            "camera": {
                "position": [0.0, 0.0, 0.0],
                "look_at": [1.0, 0.0, 0.0],
                "up": [0.0, 0.0, 1.0],
                "fov": 60.0,
                "width": 16,
                "height": 8,
            },
            "render": {"spectral": "stratified", "wavelengths": 16, "spp": 1, "max_depth": 1},
            "light": [{"type": "environment", "map": str(path)}],
            "object": [
                {
                    "shape": "cube",
                    "size": 1.0,
                    "position": [1.0e4, 1.0e4, 1.0e4],
                    "material": {"cauchy": [1.5]},
                }
            ],
        }
    )
    for conv, right_is_blue in (("blender", True), ("mirrored", False)):
        s = dataclasses.replace(scene, lights=(dataclasses.replace(scene.lights[0], convention=conv),))
        rgb = wo.render(s, device=device).rgb
        left, right = rgb[:, :6].mean(axis=(0, 1)), rgb[:, -6:].mean(axis=(0, 1))
        blue_right = right[2] > 5 * right[0] and left[0] > 5 * left[2]
        red_right = right[0] > 5 * right[2] and left[2] > 5 * left[0]
        assert blue_right if right_is_blue else red_right, (conv, left, right)


def test_unknown_convention_is_one_clear_error():
    with pytest.raises(InputError) as exc:
        EnvironmentConfig(map="x.exr", convention="polyhaven", source="s.toml")
    msg = str(exc.value)
    assert "light.convention" in msg and "polyhaven" in msg and "blender" in msg and "\n" not in msg
    with pytest.raises(InputError):
        latlong_frame("left-handed")

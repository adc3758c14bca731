"""Colour zoning: a segment's optical depth through zones, the scene's ``zoning`` table, the
tracers' absorption in zoned stones.

References written here, not taken from the code under test: the lengths of a straight line in
parallel slabs (t_i / cos theta) and in a circle's chord (2 sqrt(r^2 - h^2)), a dense midpoint
quadrature of each zone's length with the NumPy point-in-zone rule (``Zoning.zone_of``), and
Bouguer-Lambert's exp(-sum alpha_i L_i) with the materials' own alpha(lambda) from NumPy.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import warp as wp

import warpoptics as wo
from warpoptics.errors import InputError
from warpoptics.materials import material_from_spec
from warpoptics.materials.dispersion import build_material_table
from warpoptics.materials.zoning import MAX_ZONES, Zoning, zoned_material
from warpoptics.optics import zoning as oz
from warpoptics.optics.zoning import segment_optical_depth
from warpoptics.scene.schema import zoning_config
from warpoptics.stages.media import object_medium, segment_kappa, zoned_kappa

ROOT = Path(__file__).resolve().parents[1]


# ---------------------------------------------------------------------------------------------
# the optical depth law (optics/zoning.py)
# ---------------------------------------------------------------------------------------------


def test_max_zones_agree():
    assert MAX_ZONES == oz.MAX_ZONES


@pytest.mark.parametrize("theta_deg", [0.0, 35.0, 70.0])
def test_zoned_plate_depth_is_the_slab_closed_form(device, theta_deg):
    """A straight line through a plate of three bands (thicknesses 0.5, 0.8, 0.7 mm along the
    normal) at angle theta: L_i = t_i / cos theta, depth = sum kappa_i L_i."""
    th = math.radians(theta_deg)
    d = np.array([math.sin(th), 0.0, math.cos(th)])
    t = 2.0 / math.cos(th)
    o = np.array([0.3, -0.2, -1.0])
    kappa = [0.7, 2.5, 0.1]
    depth, lengths = segment_optical_depth(
        o, d, t, kind="planes", axis=[0, 0, 1], bounds=[-0.5, 0.3], kappa=kappa, device=device
    )
    want_l = np.array([0.5, 0.8, 0.7]) / math.cos(th)
    np.testing.assert_allclose(lengths, want_l, rtol=2e-6, atol=2e-6)
    assert depth == pytest.approx(float(np.dot(kappa, want_l)), rel=2e-6)
    # a normal not along z, a shifted origin: the same slabs in another frame
    rot = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0]])
    c = np.array([4.0, -3.0, 2.0])
    depth2, lengths2 = segment_optical_depth(
        rot @ o + c,
        rot @ d,
        t,
        kind="planes",
        axis=rot @ [0, 0, 1],
        bounds=[-0.5, 0.3],
        kappa=kappa,
        centre=c,
        device=device,
    )
    np.testing.assert_allclose(lengths2, want_l, rtol=1e-5, atol=1e-5)


def test_zoned_plate_depth_backwards_and_parallel(device):
    """The same segment traced the other way has the same lengths; a segment parallel to the
    planes lies in one band."""
    o = np.array([[0.0, 0.0, -1.0], [0.0, 0.0, 1.0], [-3.0, 0.0, 0.1], [-3.0, 0.0, -0.9]])
    d = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    _, ln = segment_optical_depth(
        o, d, 2.0, kind="planes", axis=[0, 0, 1], bounds=[-0.5, 0.3], kappa=[1, 2, 3], device=device
    )
    np.testing.assert_allclose(ln[0], [0.5, 0.8, 0.7], atol=1e-6)
    np.testing.assert_allclose(ln[1], [0.5, 0.8, 0.7], atol=1e-6)
    assert ln[2].tolist() == [0.0, 2.0, 0.0]
    assert ln[3].tolist() == [2.0, 0.0, 0.0]


@pytest.mark.parametrize("h", [0.0, 0.3, 0.7, 0.99])
def test_cylinder_chords_against_geometry(device, h):
    """A line at distance h from the axis of cylinders r = 0.5, 1: chords 2 sqrt(r^2 - h^2),
    the shells' lengths their differences; a tilt out of the cross-section (angle phi to the
    axis) stretches every chord by 1 / sin phi."""
    for phi_deg in (90.0, 40.0):
        phi = math.radians(phi_deg)
        d = np.array([math.sin(phi), 0.0, math.cos(phi)])
        o = np.array([-2.0 * math.sin(phi), h, -2.0 * math.cos(phi) + 0.4])
        t = 4.0
        _, ln = segment_optical_depth(
            o, d, t, kind="cylinders", axis=[0, 0, 1], bounds=[0.5, 1.0], kappa=[1, 1, 1], device=device
        )
        c = [2.0 * math.sqrt(max(r * r - h * h, 0.0)) / math.sin(phi) for r in (0.5, 1.0)]
        want = [c[0], c[1] - c[0], t - c[1]]
        np.testing.assert_allclose(ln, want, rtol=1e-5, atol=2e-5)


@pytest.mark.parametrize("kind", ["planes", "cylinders"])
def test_random_segments_against_quadrature(device, kind):
    """Random segments starting and ending anywhere (inside a zone, on either side of every
    boundary): lengths against a 20,000-point midpoint quadrature of the NumPy zone rule."""
    rng = np.random.default_rng(7)
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    centre = rng.normal(size=3) * 0.2
    bounds = [0.3, 0.8, 1.4] if kind == "cylinders" else [-0.9, -0.2, 0.4, 1.1]
    kappa = rng.uniform(0.0, 3.0, size=len(bounds) + 1)
    n = 24
    o = rng.uniform(-2.0, 2.0, size=(n, 3))
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    t = rng.uniform(0.1, 4.0, size=n)
    depth, ln = segment_optical_depth(
        o, d, t, kind=kind, axis=axis, bounds=bounds, kappa=kappa, centre=centre, device=device
    )
    zoning = Zoning(
        kind="core_rim" if kind == "cylinders" else "planar",
        axis=tuple(axis),
        bounds=tuple(bounds),
        absorption=("none",) * len(kappa),
        origin=tuple(centre),
    )
    m = 20000
    s = (np.arange(m) + 0.5) / m
    for i in range(n):
        pts = o[i] + d[i] * (s * t[i])[:, None]
        z = zoning.zone_of(pts)
        want = np.bincount(z, minlength=len(kappa)) * t[i] / m
        np.testing.assert_allclose(ln[i], want, atol=2.5 * t[i] / m + 1e-5)
        assert ln[i].sum() == pytest.approx(t[i], rel=1e-5)
        assert depth[i] == pytest.approx(float(kappa @ ln[i]), rel=1e-5, abs=1e-6)


def test_segment_in_one_zone_is_exact(device):
    """Wholly inside one zone: that zone gets the whole length, the others exact zeros."""
    _, ln = segment_optical_depth(
        [[0.1, 0.0, 0.0], [3.0, 0.0, -1.0]],
        [[0.0, 0.6, 0.8], [0.0, 0.0, 1.0]],
        [0.3, 2.0],
        kind="cylinders",
        axis=[0, 0, 1],
        bounds=[1.0, 2.0],
        kappa=[1, 2, 3],
        device=device,
    )
    assert ln[0].tolist() == [np.float32(0.3), 0.0, 0.0]
    assert ln[1].tolist() == [0.0, 0.0, 2.0]


def test_wrapper_refuses_bad_zones(device):
    kw = dict(kind="planes", axis=[0, 0, 1], device=device)
    with pytest.raises(InputError, match="one boundary fewer"):
        segment_optical_depth([0, 0, 0], [0, 0, 1], 1.0, bounds=[0.0, 1.0], kappa=[1, 2], **kw)
    with pytest.raises(InputError, match="must increase"):
        segment_optical_depth([0, 0, 0], [0, 0, 1], 1.0, bounds=[1.0, 0.0], kappa=[1, 2, 3], **kw)
    with pytest.raises(InputError, match="unknown zone family"):
        segment_optical_depth(
            [0, 0, 0], [0, 0, 1], 1.0, kind="spheres", axis=[0, 0, 1], bounds=[1.0], kappa=[1, 2]
        )


# ---------------------------------------------------------------------------------------------
# the scene's zoning table
# ---------------------------------------------------------------------------------------------


def test_zoning_config_reads_each_type():
    z = zoning_config(
        {"type": "core_rim", "axis": [0, 0, 2], "radii": [1.0], "absorption": ["garnet", "none"]},
        "object.0.zoning",
        "s.toml",
    )
    assert z.kind == "core_rim" and z.axis == (0.0, 0.0, 1.0) and z.bounds == (1.0,)
    z = zoning_config(
        {"type": "halves", "normal": [1, 0, 0], "absorption": ["ruby", "sapphire"]}, "f", "s.toml"
    )
    assert z.bounds == (0.0,) and z.family == "planes"
    z = zoning_config(
        {
            "type": "planar",
            "normal": [0, 1, 0],
            "offsets": [-1, 0, 1],
            "origin": [0, 0, 0.5],
            "absorption": ["none", {"absorption_rgb": [0.1, 0.2, 0.3]}, "none", "ruby"],
        },
        "f",
        "s.toml",
    )
    assert z.bounds == (-1.0, 0.0, 1.0) and z.origin == (0.0, 0.0, 0.5)


@pytest.mark.parametrize(
    "table, field, message",
    [
        ({"type": "stripes"}, "object.0.zoning.type", "unknown value"),
        ({"normal": [0, 0, 1]}, "object.0.zoning.type", "missing key"),
        (
            {"type": "planar", "normal": [0, 0, 0], "offsets": [1.0], "absorption": ["a", "b"]},
            "object.0.zoning.normal",
            "zero vector",
        ),
        (
            {"type": "planar", "normal": [0, 0, 1], "offsets": [1, 0], "absorption": ["a", "b", "c"]},
            "object.0.zoning.offsets",
            "must increase",
        ),
        (
            {"type": "core_rim", "axis": [0, 0, 1], "radii": [-1.0], "absorption": ["a", "b"]},
            "object.0.zoning.radii",
            "out of range",
        ),
        (
            {"type": "halves", "normal": [0, 0, 1], "absorption": ["a"]},
            "object.0.zoning.absorption",
            "one absorption per zone",
        ),
        (
            {"type": "halves", "normal": [0, 0, 1], "absorption": ["a", 3]},
            "object.0.zoning.absorption.1",
            "material name",
        ),
        (
            {"type": "halves", "axis": [0, 0, 1], "absorption": ["a", "b"]},
            "object.0.zoning.axis",
            "unknown key",
        ),
        (
            {"type": "planar", "normal": [0, 0, 1], "offsets": list(range(8)), "absorption": ["a"] * 9},
            "object.0.zoning.offsets",
            "1 to 7",
        ),
    ],
)
def test_zoning_config_errors_name_file_field_value(table, field, message):
    with pytest.raises(InputError) as err:
        zoning_config(table, "object.0.zoning", "s.toml")
    assert err.value.file == "s.toml"
    assert err.value.field == field
    assert message in str(err.value)


def _scene_text(zoning: str, material: str = '"quartz"') -> str:
    return f"""
[camera]
type = "orthographic"
position = [0.0, 0.0, 20.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
width = 8
height = 8
[render]
wavelengths = 4
[[light]]
type = "constant"
[[object]]
shape = "plate"
width = 6.0
length = 6.0
thickness = 1.0
material = {material}
zoning = {zoning}
"""


def test_scene_zone_material_errors_name_the_zone(tmp_path):
    p = tmp_path / "z.toml"
    p.write_text(
        _scene_text('{ type = "halves", normal = [1, 0, 0], absorption = ["quartz", "no_such_stone"] }')
    )
    with pytest.raises(InputError) as err:
        wo.render(wo.Scene.load(p))
    assert err.value.field == "object.0.zoning.absorption.1"
    assert err.value.file == str(p)
    p.write_text(
        _scene_text(
            '{ type = "halves", normal = [1, 0, 0], absorption = ["none", { bands = 3 }] }',
            material="{ cauchy = [1.5] }",
        )
    )
    with pytest.raises(InputError) as err:
        wo.render(wo.Scene.load(p))
    assert err.value.field == "object.0.zoning.absorption.1.bands"


# ---------------------------------------------------------------------------------------------
# the tracers' per-wave kappa in a zoned stone (stages/media.py) against the closed form
# ---------------------------------------------------------------------------------------------


@wp.kernel
def _zoned_kappa_kernel(
    mats: wo.materials.MaterialTable,
    mat_id: int,
    axis: wp.vec3f,
    wl: float,
    mode: int,
    wn: wp.vec3f,
    o: wp.array(dtype=wp.vec3f),
    d: wp.array(dtype=wp.vec3f),
    t: wp.array(dtype=wp.float32),
    out: wp.array(dtype=wp.float32),
    out_plain: wp.array(dtype=wp.float32),
):
    i = wp.tid()
    med, no, ne, alpha = object_medium(mats, mat_id, axis, wl)
    k = segment_kappa(mats, mat_id, alpha, -1, mode, wn, med, 1.0)
    out_plain[i] = k
    out[i] = zoned_kappa(mats, mat_id, k, -1, mode, wn, med, 1.0, wl, o[i], d[i], t[i])


def _kappas(mats, mat_id, axis, wl, mode, wn, o, d, t, device):
    n = len(t)
    out = wp.zeros(n, dtype=wp.float32, device=device)
    plain = wp.zeros(n, dtype=wp.float32, device=device)
    wp.launch(
        _zoned_kappa_kernel,
        dim=n,
        inputs=[
            mats,
            mat_id,
            wp.vec3f(*axis),
            float(wl),
            mode,
            wp.vec3f(*wn),
            wp.array(np.asarray(o, dtype=np.float32), dtype=wp.vec3f, device=device),
            wp.array(np.asarray(d, dtype=np.float32), dtype=wp.vec3f, device=device),
            wp.array(np.asarray(t, dtype=np.float32), dtype=wp.float32, device=device),
        ],
        outputs=[out, plain],
        device=device,
    )
    return out.numpy(), plain.numpy()


def test_zoned_uniaxial_stone_each_wave_by_its_zone(device):
    """A tourmaline host in a core and a rim of other uniaxial absorptions, placed rotated and
    shifted in the world: each wave's mean kappa through the zones is sum kappa_i L_i / L with
    kappa_i from the zone's own (alpha_o, alpha_e) and the host's indices (Guy & Soler eq. 7,
    written out here); a segment inside the rim alone is the rim material's kappa, to the bit."""
    host = wo.materials.get("tourmaline")
    core = material_from_spec("ruby")
    rim = host
    zoning = Zoning(kind="core_rim", axis=(0.0, 0.0, 1.0), bounds=(1.0,), absorption=(core, rim))
    place = np.eye(4)
    place[:3, :3] = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]  # 90 deg about z
    place[:3, 3] = [5.0, 0.0, 0.0]
    stone = zoned_material(host, zoning.placed(place))
    table, ids = build_material_table([stone, host], device)
    assert ids == [0, 1]
    wl = 550.0
    axis_w = (0.0, 0.0, 1.0)
    # world segments: across the core's centre (x = 5), and one wholly in the rim
    o = [[5.0, -3.0, 0.0], [7.5, -3.0, 0.2]]
    d = [[0.0, 1.0, 0.0], [0.0, 1.0, 0.0]]
    t = [6.0, 6.0]
    wn = (0.0, 0.6, 0.8)
    cos2 = 0.8**2
    no_, ne_ = host.n(wl)[..., 0], host.n(wl)[..., 1]
    a_core, a_rim = core.alpha(wl), rim.alpha(wl)

    def k_e(a):
        return a[0] * cos2 + a[1] * (no_ / ne_) ** 2 * (1.0 - cos2)

    for mode, law in ((0, lambda a: a[0]), (1, k_e)):
        got, _ = _kappas(table, 0, axis_w, wl, mode, wn, o, d, t, device)
        want0 = (law(a_core) * 2.0 + law(a_rim) * 4.0) / 6.0
        assert got[0] == pytest.approx(float(want0), rel=2e-4)
        # the rim alone: bit for bit the unzoned host's kappa of that wave
        _, plain = _kappas(table, 1, axis_w, wl, mode, wn, o, d, t, device)
        assert got[1] == plain[1]


def test_unzoned_material_kappa_is_untouched(device):
    host = wo.materials.get("sapphire")
    table, _ = build_material_table([host], device)
    got, plain = _kappas(
        table, 0, (0.0, 0.0, 1.0), 470.0, 1, (0.0, 0.0, 1.0), [[0, 0, 0]], [[1, 0, 0]], [2.0], device
    )
    assert got[0] == plain[0]


# ---------------------------------------------------------------------------------------------
# the forward (bench) tracer: a zoned plate's transmission is the closed form
# ---------------------------------------------------------------------------------------------

_BANDS = [
    "{ cauchy = [1.5], bands = [{ center_nm = 480, width_nm = 80, peak_alpha_per_mm = 0.9 }] }",
    '"none"',
    "{ cauchy = [1.5], bands = [{ center_nm = 620, width_nm = 60, peak_alpha_per_mm = 1.6 }] }",
]


def _bench_plate(tmp_path, theta_deg, zoned):
    th = math.radians(theta_deg)
    d = np.array([math.sin(th), 0.0, -math.cos(th)])
    src = -10.0 * d
    screen = 10.0 * d
    zones = ", ".join(_BANDS)
    zoning = (
        f'zoning = {{ type = "planar", normal = [0, 0, 1], offsets = [-0.5, 0.3], absorption = [{zones}] }}'
        if zoned
        else ""
    )
    text = f"""
[source]
type = "beam"
kind = "collimated"
position = {src.tolist()}
direction = {d.tolist()}
width = 0.0
spectrum = "E"
rays = 1
[render]
wavelengths = 6
max_depth = 2
[[sensor]]
type = "screen"
name = "screen"
center = {screen.tolist()}
normal = {(-d).tolist()}
up = [0.0, 1.0, 0.0]
size = [4.0, 4.0]
resolution = [16, 16]
[[object]]
shape = "plate"
width = 30.0
length = 30.0
thickness = 2.0
material = {{ cauchy = [1.5] }}
{zoning}
"""
    p = tmp_path / f"plate_{theta_deg}_{int(zoned)}.toml"
    p.write_text(text)
    from warpoptics.pipelines.bench import bench
    from warpoptics.scene.bench import BenchScene

    return bench(BenchScene.load(p), device=wo.device.get_device("cpu"))


@pytest.mark.parametrize("theta_deg", [0.0, 40.0])
def test_bench_zoned_plate_transmission_is_the_closed_form(tmp_path, theta_deg):
    """The beam through the plate (two interfaces, depth 2) with and without zones: the ratio per
    wavelength is exp(-sum alpha_i t_i / cos theta_t) (Snell: sin theta_t = sin theta / 1.5;
    Fresnel cancels in the ratio)."""
    zoned = _bench_plate(tmp_path, theta_deg, True)
    clear = _bench_plate(tmp_path, theta_deg, False)
    cos_t = math.sqrt(1.0 - (math.sin(math.radians(theta_deg)) / 1.5) ** 2)
    wl = zoned.wavelengths
    alpha = [material_from_spec({"cauchy": [1.5], "bands": [b]}).alpha(wl) for b in _band_tables()]
    want = np.exp(-(alpha[0] * 0.5 + alpha[1] * 0.7) / cos_t)
    got = []
    for r in (zoned, clear):
        dp = r.deposits
        sel = dp["depth"] == 2
        idx = np.argmin(np.abs(dp["wavelength"][sel][:, None] - wl[None, :]), axis=1)
        got.append(np.bincount(idx, weights=dp["power"][sel], minlength=len(wl)))
    np.testing.assert_allclose(got[0] / got[1], want, rtol=2e-4)


def _band_tables():
    return [
        {"center_nm": 480, "width_nm": 80, "peak_alpha_per_mm": 0.9},
        {"center_nm": 620, "width_nm": 60, "peak_alpha_per_mm": 1.6},
    ]


# ---------------------------------------------------------------------------------------------
# the scenes: each zone shows in its own colour (tiny renders, seen from straight above in a
# uniform white light so that every path carries the body colour)
# ---------------------------------------------------------------------------------------------


def _top_view(name, size=24, view=12.0, **extra):
    sc = wo.Scene.load(ROOT / "scenes" / f"zoning_{name}.toml")
    over = {
        "camera.type": "orthographic",
        "camera.position": [0.0, 0.0, 30.0],
        "camera.look_at": [0.0, 0.0, 0.0],
        "camera.up": [0.0, 1.0, 0.0],
        "camera.view_height": view,
        "camera.width": size,
        "camera.height": size,
        "render.wavelengths": 8,
        **extra,
    }
    data = sc.with_overrides(over).data
    data["light"] = [{"type": "constant"}]
    return wo.Scene.from_dict(data, path=sc.path)


def _lch(img, mask):
    """CIELAB L*, C*, h (degrees) of the alpha-weighted mean XYZ of the pixels in ``mask``."""
    import colour

    w = img.alpha[mask][:, None]
    xyz = (img.xyz[mask] * w).sum(axis=0) / w.sum()
    lab = colour.XYZ_to_Lab(xyz / xyz[1] * 0.5)  # the hue does not depend on the exposure
    return lab[0], float(np.hypot(lab[1], lab[2])), float(np.degrees(np.arctan2(lab[2], lab[1])) % 360.0)


def _x_of_columns(size, view):
    return (np.arange(size) + 0.5) / size * view - 0.5 * view


def test_ametrine_halves_are_purple_and_yellow(device):
    size, view = 24, 12.0
    img = wo.render(_top_view("ametrine", size, view), device=device)
    x = np.broadcast_to(_x_of_columns(size, view)[None, :], (size, size))
    stone = img.alpha > 0.5
    # the middle of each half (the step cut's ends reflect light along the stone's length,
    # through both halves: they blend to orange and red)
    middle = (np.abs(x) > 0.5) & (np.abs(x) < 3.0)
    _, c_a, h_a = _lch(img, stone & middle & (x < 0.0))
    _, c_c, h_c = _lch(img, stone & middle & (x > 0.0))
    assert 290.0 < h_a < 335.0 and c_a > 10.0  # amethyst: purple (measured 326)
    assert 70.0 < h_c < 105.0 and c_c > 10.0  # citrine: yellow (measured 88)


def test_watermelon_core_is_pink_and_rim_green(device):
    size, view = 32, 10.0
    img = wo.render(_top_view("watermelon", size, view), device=device)
    x = _x_of_columns(size, view)
    r = np.hypot(x[None, :], x[:, None])
    stone = img.alpha > 0.5
    _, c_core, h_core = _lch(img, stone & (r < 1.2))
    _, c_rim, h_rim = _lch(img, stone & (r > 3.2))
    assert (h_core > 320.0 or h_core < 20.0) and c_core > 10.0  # pink to red (measured 339)
    assert 110.0 < h_rim < 180.0 and c_rim > 10.0  # green (measured 142)


def test_sapphire_bands_alternate(device):
    """Columns inside the strong bands are more saturated than those inside the pale bands;
    without the zoning (every band strong) the columns are alike."""
    size, view = 36, 12.0
    sc = _top_view("sapphire", size, view)
    img = wo.render(sc, device=device)
    x = _x_of_columns(size, view)
    offsets = [-2.6, -1.4, -0.6, 0.4, 1.1, 2.2]
    band = np.searchsorted(offsets, x)
    clear_of_edges = np.min(np.abs(x[:, None] - np.asarray(offsets)[None, :]), axis=1) > 0.25
    stone = img.alpha > 0.5
    strong = stone & (clear_of_edges & (band % 2 == 0) & (np.abs(x) < 3.0))[None, :]
    pale = stone & (clear_of_edges & (band % 2 == 1))[None, :]
    _, c_s, h_s = _lch(img, strong)
    _, c_p, _ = _lch(img, pale)
    assert 240.0 < h_s < 300.0  # blue
    assert c_s > 1.5 * c_p
    strong_all = {"bands": [{"center_nm": 640, "width_nm": 60, "peak_alpha_per_mm": 0.8}]}
    uniform = sc.with_overrides({"object.0.zoning.absorption": [strong_all] * 7})
    img_u = wo.render(uniform, device=device)
    _, c_su, _ = _lch(img_u, strong)
    _, c_pu, _ = _lch(img_u, pale)
    assert c_pu > 0.75 * c_su


# ---------------------------------------------------------------------------------------------
# every camera estimator: point samples, spectral bundles and pixel beams see the same zones
# ---------------------------------------------------------------------------------------------


def _halves_scene(estimator, zoned=True, spp=1, light="constant"):
    obj = {"shape": "round_brilliant", "diameter": 6.5, "material": {"cauchy": [1.72]}}
    if zoned:
        obj["zoning"] = {
            "type": "halves",
            "normal": [1.0, 0.0, 0.0],
            "absorption": [
                {"bands": [{"center_nm": 530, "width_nm": 50, "peak_alpha_per_mm": 0.3}]},  # pink
                {"bands": [{"center_nm": 640, "width_nm": 70, "peak_alpha_per_mm": 0.3}]},  # blue
            ],
        }
    return wo.Scene.from_dict(
        {
            "camera": {
                "type": "orthographic",
                "position": [0.0, -22.0, 30.0],
                "look_at": [0.0, 0.0, -0.3],
                "view_height": 8.0,
                "width": 12,
                "height": 12,
            },
            "render": {
                "spectral": "stratified",
                "wavelengths": 16,
                "max_depth": 12,
                "spp": spp,
                "split_threshold": 0.0,
                "estimator": estimator,
            },
            "light": [{"type": "constant"} if light == "constant" else {"type": "environment", "map": light}],
            "object": [obj],
        }
    )


def _half_means(img):
    """Alpha-weighted mean XYZ of the left (x < 0) and right image halves."""
    w = img.alpha[..., None]
    h = img.xyz.shape[1] // 2
    return [(img.xyz[:, s] * w[:, s]).sum(axis=(0, 1)) / w[:, s].sum() for s in (slice(0, h), slice(h, None))]


def test_every_estimator_sees_the_zones(device):
    """Point samples (one tree per wavelength), spectral bundles and pixel beams (orthographic:
    unbiased) give the same colour, within their noise (1.5 % between seeds), to each half of an
    isotropic stone in two halves under a uniform light, and the halves differ as their
    absorptions do (pink left, blue right; the clear stone's halves are alike)."""
    from warpoptics.pipelines.render import Renderer

    point = Renderer(_halves_scene("point", spp=16), device=device, spectral_bundle=False).run()
    bundle = Renderer(_halves_scene("point", spp=16), device=device).run()
    beam = Renderer(_halves_scene("beam"), device=device).run()
    assert beam.stats["estimator"] == "beam" and point.stats["estimator"] == "point"
    ref = _half_means(point)
    for img in (bundle, beam):
        for got, want in zip(_half_means(img), ref, strict=True):
            np.testing.assert_allclose(got, want, rtol=0.03)
    # pink (red over blue: X/Z high) on the left, blue on the right
    (lx, _ly, lz), (rx, _ry, rz) = ref
    assert lx / lz > 1.1 * (rx / rz)
    clear = _half_means(Renderer(_halves_scene("beam", zoned=False), device=device).run())
    assert clear[0][0] / clear[0][2] == pytest.approx(clear[1][0] / clear[1][2], rel=0.05)


# ---------------------------------------------------------------------------------------------
# shadow rays (stages/surfaces.py): the straight-through filter of a zoned stone
# ---------------------------------------------------------------------------------------------


def _shadow_scene(obj, *, nested=False):
    s = 1 / math.sqrt(2)
    objects = [obj]
    if nested:  # the plate inside a clear box of index 1: the nested shadow path
        objects = [
            {"shape": "cube", "size": 8.0, "position": [0.0, 0.0, 4.6], "material": {"cauchy": [1.0]}},
            obj,
        ]
    return wo.Scene.from_dict(
        {
            "camera": {
                "type": "orthographic",
                "position": [3.0, 0.0, 20.0],
                "look_at": [3.0, 0.0, 0.0],
                "up": [0.0, 1.0, 0.0],
                "view_height": 0.5,
                "width": 4,
                "height": 4,
            },
            "render": {"spectral": "rgb3", "wavelengths": 3, "diffuse_depth": 1, "seed": 1},
            "surface": [{"type": "plane", "height": 0.0, "color": [0.8, 0.8, 0.8]}],
            "light": [{"type": "directional", "direction": [s, 0.0, -s], "irradiance": 1.0}],
            "object": objects,
        }
    )


@pytest.mark.parametrize("nested", [False, True], ids=["plain", "nested"])
def test_shadow_through_a_zoned_plate(device, nested):
    """A 1 mm plate whose lower half (0.5 mm) absorbs like garnet and whose upper half is clear:
    its shadow at 45 degrees is exp(-K chord / 2) per rgb3 channel, K the garnet's eq. 9
    absorbances (the same test as the unzoned garnet plate's in test_surfaces.py)."""
    from warpoptics.pipelines.render import Renderer

    plate = {"shape": "plate", "width": 4.0, "length": 4.0, "thickness": 1.0, "position": [0.0, 0.0, 3.0]}
    zoning = {"type": "halves", "normal": [0.0, 0.0, 1.0], "absorption": ["garnet", "none"]}
    clear = Renderer(
        _shadow_scene(dict(plate, material="garnet", absorption_scale=0.0), nested=nested), device=device
    )
    zoned = Renderer(
        _shadow_scene(dict(plate, material="garnet", zoning=zoning), nested=nested), device=device
    )
    ratio = zoned.run().rgb.mean(axis=(0, 1)) / clear.run().rgb.mean(axis=(0, 1))
    table, ids = build_material_table([material_from_spec("garnet")], device)
    k = table.rgb3_alpha_o.numpy()[ids[0]]
    chord = 1.0 / math.cos(math.radians(45.0))
    np.testing.assert_allclose(ratio, np.exp(-k * chord * 0.5), rtol=0.02)


def test_zone_absorption_from_a_variety_or_chromophores(tmp_path):
    """A zone's absorption is a material spec like ``material``: a library variety, a host with
    its chromophores inline, ``"none"``; each zone material absorbs as that spec's material."""
    from warpoptics.pipelines.objects import build_objects

    inline = {"host": "tourmaline", "chromophores": {"Mn3+": 0.8}}
    p = tmp_path / "z.toml"
    p.write_text(
        _scene_text(
            '{ type = "planar", normal = [0, 0, 1], offsets = [-0.2, 0.2], absorption = ["rubellite", '
            '{ host = "tourmaline", chromophores = { "Mn3+" = 0.8 } }, "none"] }',
            material='"tourmaline"',
        )
    )
    sc = wo.Scene.load(p)
    (mat,) = build_objects(sc.objects, file=str(p)).materials
    wl = np.linspace(400.0, 700.0, 7)
    a_var, a_inline, a_none = (z.alpha(wl) for z in mat.zoning.absorption)
    np.testing.assert_allclose(a_var, material_from_spec("rubellite").alpha(wl), rtol=1e-6)
    np.testing.assert_allclose(a_inline, material_from_spec(inline).alpha(wl), rtol=1e-6)
    assert np.all(a_none == 0.0) and a_inline.max() > 0.1
    # the zones are placed with the object (identity here) and keep their bounds
    assert mat.zoning.bounds == (-0.2, 0.2) and np.allclose(mat.zoning.frame(), np.eye(4))


def test_mitsuba_export_refuses_a_zoned_absorbing_stone():
    """Mitsuba's dielectric is clear: a clear host with an absorbing zone is refused too."""
    from warpoptics.pipelines.mitsuba_export import _stone_index
    from warpoptics.pipelines.objects import build_objects

    zoning = {"type": "halves", "normal": [0, 0, 1], "absorption": ["none", "garnet"]}
    sc = wo.Scene.from_dict(
        {"object": [{"shape": "sphere", "material": {"cauchy": [1.5]}, "zoning": zoning}]}
    )
    (mat,) = build_objects(sc.objects).materials
    with pytest.raises(InputError, match="absorbing stone"):
        _stone_index(mat, 589.3, "object.0", "s.toml")
    clear = dict(zoning, absorption=["none", "none"])
    sc = wo.Scene.from_dict({"object": [{"shape": "sphere", "material": {"cauchy": [1.5]}, "zoning": clear}]})
    (mat,) = build_objects(sc.objects).materials
    assert _stone_index(mat, 589.3, "object.0", "s.toml") == pytest.approx(1.5)

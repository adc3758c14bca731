"""Pixel beams (stages/pixel_beam.py): a pixel's footprint traced through a convex stone as exact
parallel beams.

Checked against what the beam code does not compute: the stone's projected area from its mesh
(trimesh: half the sum of |n . d| over the faces of a convex solid), energy conservation in the
white furnace, and the unbiased point-sampling estimator (an orthographic camera, where the beam
is exact).  Tiny images; the perspective camera's bias is measured by
scripts/bench/beam_bias.py, not here.
"""

from pathlib import Path

import numpy as np
import pytest

import warpoptics as wo
from warpoptics.errors import InputError
from warpoptics.pipelines.objects import build_objects
from warpoptics.pipelines.render import Renderer

VIEW = 8.0  # mm, the orthographic view's height
ORTHO = {
    "camera": {
        "type": "orthographic",
        "position": [0.0, -22.0, 30.0],
        "look_at": [0.0, 0.0, -0.3],
        "view_height": VIEW,
        "width": 12,
        "height": 12,
    },
    "render": {
        "spectral": "stratified",
        "wavelengths": 8,
        "max_depth": 16,
        "spp": 1,
        "split_threshold": 0.0,
        "estimator": "beam",
    },
    "light": [{"type": "environment", "map": "studio"}],
    "object": [{"shape": "round_brilliant", "diameter": 6.5, "material": {"cauchy": [2.4173]}}],
}


def _scene(light=None, obj=None, **render):
    data = {**ORTHO, "render": {**ORTHO["render"], **render}}
    if light is not None:
        data["light"] = [light]
    if obj is not None:
        data["object"] = [obj]
    return wo.Scene.from_dict(data)


def _render(sc, device, **kw):
    # a constant index traces as one shared tree unless told otherwise: beams need the bundles
    return Renderer(sc, device=device, shared_spectrum=False, **kw).run()


@pytest.mark.parametrize("block", [1, 5], ids=["pixel", "block5"])
def test_coverage_is_the_projected_area(device, block):
    """The beams' coverage (alpha) over the image times the pixel's area is the stone's area
    seen along the view: exact up to float32 (the footprints tile the view).  Beams of 5x5
    pixels on the 12x12 image (blocks cut short at the right and bottom edges) share their
    pieces among the pixels by area, which is as exact."""
    sc = _scene(wavelengths=1, bundle_lanes=1, beam_block=block)
    img = _render(sc, device)
    ((mesh, xf),) = build_objects(sc.objects).meshes
    v = np.asarray(mesh.vertices) @ np.asarray(xf)[:3, :3].T
    tri = v[np.asarray(mesh.faces)]
    n2a = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])  # 2 x area x normal
    c = sc.camera
    d = np.subtract(c.look_at, c.position)
    d /= np.linalg.norm(d)
    projected = 0.25 * np.abs(n2a @ d).sum()
    pixel = (VIEW / c.height) ** 2
    assert img.alpha.min() >= 0.0 and img.alpha.max() <= 1.0 + 1e-6
    assert img.alpha.sum() * pixel == pytest.approx(projected, rel=2e-4)
    # the silhouette's pixels are partly covered (a point sampler gives 0 or 1 per sample)
    assert ((img.alpha > 0.01) & (img.alpha < 0.99)).sum() > 20


@pytest.mark.parametrize("block", [1, 5], ids=["pixel", "block5"])
def test_white_furnace(device, block):
    """A clear stone in a uniform white environment: no absorption and Fresnel's R + T = 1 at
    every face, so no pixel sees more than the environment's radiance, and what it sees less is
    the light still inside after max_depth interfaces, the same as for point samples (no
    roulette at split_threshold 0: the beams are deterministic).  Blocks of 5x5 pixels: each
    pixel takes its area's share of every part, so the same holds pixel by pixel."""
    kw = dict(light={"type": "environment", "map": "constant"}, max_depth=16, wavelengths=64, bundle_lanes=16)
    img = _render(_scene(**kw, beam_block=block), device)
    y = img.xyz[..., 1]
    stone = img.alpha > 0.0
    ref = y[~stone].mean()
    # the background's spectral noise (64 stratified wavelengths of a flat spectrum): 0.045 %
    assert np.abs(y[~stone] / ref - 1.0).max() < 1e-3
    ratio = y[stone] / ref
    assert ratio.max() < 1.0 + 1e-3  # no light is made
    pts = _render(_scene(**kw, estimator="point", spp=64), device)
    want = pts.xyz[..., 1][stone] / pts.xyz[..., 1][~stone].mean()
    # 16 interfaces leave ~8 % of the light inside; the point samples' mean is good to ~0.3 %
    assert ratio.mean() == pytest.approx(want.mean(), abs=5e-3)
    assert 0.85 < ratio.mean() < 0.97


DISPERSIVE = {"shape": "round_brilliant", "diameter": 6.5, "material": "diamond"}
FLUORESCENT = {"shape": "round_brilliant", "diameter": 6.5, "material": "uranium_glass"}
COATED = {
    "shape": "round_brilliant",
    "diameter": 6.5,
    "material": {"cauchy": [1.6076, 0.0043]},
    "coating": [{"material": "fused_silica", "thickness_nm": 110.0}],
}


@pytest.mark.parametrize(
    "polarization, obj, beam_noise, blocks",
    [(True, None, 0.0024, (1,)), (False, None, 0.0024, (1, 5)), (True, DISPERSIVE, 0.001, (1, 5))],
    ids=["polarized", "scalar", "dispersive"],
)
def test_orthographic_beams_equal_point_sampling(device, polarization, obj, beam_noise, blocks):
    """With an orthographic camera a pixel's rays are parallel and the beam is exact: one beam
    render equals the mean of many point samples (for a constant index the shared-spectrum
    tracer, for the dispersive diamond spectral bundles at R2 points: independent estimators,
    unbiased), within the point samples' noise; the Stokes vectors stay physical.  The
    dispersive case checks the beams' wavelength lattice and lookup sequence stay unbiased;
    beams of 5x5 pixels (cut by the pixels at the leaves, blocks cut short at the image's
    edges) as well."""
    # 64 stratified wavelengths: the beam's own noise is 0.24 % of the mean for the constant
    # index, 0.09 % for the diamond (XYZ, measured between seeds); the point samples' is measured here
    beams = [
        _render(
            _scene(polarization=polarization, obj=obj, wavelengths=64, bundle_lanes=16, beam_block=b), device
        )
        for b in blocks
    ]
    pts = []
    for seed in (1, 2):
        ref_sc = _scene(polarization=polarization, obj=obj, estimator="point", spp=256, seed=seed)
        pts.append(Renderer(ref_sc, device=device).run().xyz)
    ref = 0.5 * (pts[0] + pts[1])
    noise = np.sqrt(((pts[0] - pts[1]) ** 2).mean()) / 2.0  # of their mean
    scale = ref.mean()
    for beam in beams:
        err = np.sqrt(((beam.xyz - ref) ** 2).mean())
        assert err < 3.0 * noise + 3.0 * beam_noise * scale, (err / scale, noise / scale)
        assert beam.xyz.mean() == pytest.approx(scale, rel=3e-3)
        s = beam.stokes
        assert np.all(np.linalg.norm(s[..., 1:], axis=-1) <= s[..., 0] * (1 + 1e-5) + 1e-7)


def test_scenes_beams_cannot_trace_are_refused(device):
    lens = wo.Scene.from_dict(
        {
            **ORTHO,
            "camera": {
                "type": "thin_lens",
                "position": [0.0, -22.0, 30.0],
                "look_at": [0.0, 0.0, -0.3],
                "fov": 15.0,
                "aperture": 0.5,
                "focus_distance": 37.0,
                "width": 8,
                "height": 8,
            },
        }
    )
    with pytest.raises(InputError, match="render.estimator"):
        Renderer(lens, device=device)


SMALL = {"shape": "round_brilliant", "diameter": 4.0, "material": "diamond"}


def _two_stones(**render):
    """Two diamonds, the second 8 mm further along the view and 3 mm aside: in the orthographic
    view it is partly hidden by the first, whose light partly reaches it."""
    view = np.subtract(ORTHO["camera"]["look_at"], ORTHO["camera"]["position"])
    behind = np.array([1.5, 0.0, 0.0]) + 8.0 * view / np.linalg.norm(view)
    return wo.Scene.from_dict(
        {
            **ORTHO,
            "render": {**ORTHO["render"], **render},
            "object": [
                {**SMALL, "position": [-1.5, 0, 0]},
                {**SMALL, "position": behind.tolist()},
            ],
        }
    )


def test_beams_through_several_stones_equal_point_sampling(device):
    """Two stones, one partly behind the other: a block's beam enters the stone in front where
    nothing may stand before it (``beam_target``), blocks that see both edges are point-sampled,
    and the parts that leave the front stone toward the other continue as point samples.  With
    an orthographic camera every beam is exact, so one beam render equals the mean of many
    point samples within their noise (as for one stone, above)."""
    beams = [_render(_two_stones(wavelengths=32, bundle_lanes=16, seed=s), device) for s in (11, 12)]
    assert Renderer(_two_stones(estimator="auto"), device=device).estimator == "beam"
    pts = [Renderer(_two_stones(estimator="point", spp=256, seed=s), device=device).run().xyz for s in (1, 2)]
    _agree_within_noise([b.xyz for b in beams], pts)


def _agree_within_noise(beams, pts):
    """Two beam renders and two point renders (independent seeds) agree: the RMSE of their
    means is within 1.5x what their noises (each from its two seeds) predict — over 100
    pixels x 3 channels a chi-square of that many degrees of freedom stays within 1.5x — and
    the image means within 3 sigma of the mean's noise (plus 0.1 %)."""
    ref = 0.5 * (pts[0] + pts[1])
    bm = 0.5 * (beams[0] + beams[1])
    var_p = ((pts[0] - pts[1]) ** 2).mean() / 4.0  # of the mean of two
    var_b = ((beams[0] - beams[1]) ** 2).mean() / 4.0
    err = np.sqrt(((bm - ref) ** 2).mean())
    assert err < 1.5 * np.sqrt(var_p + var_b), (err, np.sqrt(var_p), np.sqrt(var_b))
    sigma_mean = np.sqrt((var_p + var_b) / bm[..., 1].size)
    assert abs(bm[..., 1].mean() - ref[..., 1].mean()) < 3.0 * sigma_mean + 1e-3 * ref[..., 1].mean()


def _on_a_table(**render):
    """A diamond resting on its culet on a grey glossy table, lit by a lamp and the studio."""
    return wo.Scene.from_dict(
        {
            **ORTHO,
            "camera": {**ORTHO["camera"], "width": 10, "height": 10},
            "render": {**ORTHO["render"], "wavelengths": 16, "diffuse_depth": 2, **render},
            "light": [
                {"type": "environment", "map": "studio", "intensity": 0.5},
                {"type": "area", "center": [-10, -8, 14], "normal": [0.5, 0.4, -0.77], "size": [8, 8]},
            ],
            "surface": [{"type": "plane", "height": 0.0, "size": 200.0, "bsdf": "glossy", "roughness": 0.4}],
            "object": [
                {**SMALL, "position": [0, 0, 1.7664]}  # on its culet
            ],
        }
    )


def test_beams_meet_surfaces_and_lamps_by_point_samples(device):
    """A stone on a table under a lamp, in beams by name: parts that may meet the table or the
    lamp, and the pixels' misses, continue as point samples (next-event estimation and MIS as
    in the point tracer), which keeps the image unbiased: it equals point sampling within the
    two estimators' noise.  ``auto`` keeps point samples for such scenes and says why."""
    auto = Renderer(_on_a_table(estimator="auto"), device=device)
    assert auto.estimator == "point" and "surfaces or lamps" in auto.estimator_reason
    beams = [_render(_on_a_table(spp=2, seed=s), device) for s in (11, 12)]
    assert all(b.stats["estimator"] == "beam" for b in beams)
    pts = [Renderer(_on_a_table(estimator="point", spp=256, seed=s), device=device).run().xyz for s in (1, 2)]
    _agree_within_noise([b.xyz for b in beams], pts)


def test_the_fire_scene_renders_in_beams(device):
    """scenes/diamond_fire.toml (the main job's stone in pixel beams) is traced by the beams
    and gives a physical image: finite, coverage within [0, 1] with partly covered silhouette
    pixels, Stokes vectors with DOP <= 1."""
    path = Path(__file__).resolve().parents[1] / "scenes" / "diamond_fire.toml"
    sc = wo.Scene.load(path).with_overrides({"camera.width": 20, "camera.height": 20})
    r = Renderer(sc, device=device)
    assert r.pixel_beam
    img = r.run()
    assert np.all(np.isfinite(img.xyz)) and img.xyz.mean() > 0.0
    assert img.alpha.min() >= 0.0 and img.alpha.max() <= 1.0 + 1e-6
    assert ((img.alpha > 0.01) & (img.alpha < 0.99)).sum() > 4
    s = img.stokes
    assert np.all(np.linalg.norm(s[..., 1:], axis=-1) <= s[..., 0] * (1 + 1e-5) + 1e-7)


def test_block_beams_with_adaptive_sampling(device):
    """Adaptive sampling gives each pixel its own count; a block traces its pixels' largest and
    each pixel keeps only its own samples.  The main job's stone at 20x20 in blocks of 3 (cut
    short at the edges): every pixel's spp is what the allocator gave (the film divides by it),
    the image is physical and its mean agrees with the non-adaptive render's (2 % covers both
    renders' spectral noise at 16 wavelengths)."""
    path = Path(__file__).resolve().parents[1] / "scenes" / "diamond_fire.toml"
    over = {"camera.width": 20, "camera.height": 20, "render.wavelengths": 16, "render.beam_block": 3}
    sc = wo.Scene.load(path).with_overrides(over)
    plain = Renderer(sc, device=device).run()
    r = Renderer(sc.with_overrides({"render.adaptive": True, "render.spp": 6}), device=device)
    img = r.run()
    assert r.spp_per_pixel.min() >= 2 and r.spp_per_pixel.max() > r.spp_per_pixel.min()
    assert np.all(np.isfinite(img.xyz)) and img.alpha.max() <= 1.0 + 1e-6
    assert np.abs(img.alpha - plain.alpha).max() < 1e-5  # coverage is the same in every sample
    assert img.xyz.mean() == pytest.approx(plain.xyz.mean(), rel=0.02)


def test_beam_block_is_validated():
    with pytest.raises(InputError, match="render.beam_block"):
        _scene(beam_block=-1)
    with pytest.raises(InputError, match="render.beam_block"):
        _scene(beam_block=17)


def test_auto_blocks_stay_within_their_bias_bound(device):
    """render.beam_block = 0 (the default) takes blocks up to 0.12 degrees wide through a
    pinhole: 4x4 pixels for scenes/diamond_fire.toml at 512x512, one pixel at 20x20 and for an
    orthographic camera.  At the 512x512 render's pixel angle (a 64x64 crop of the stone's
    centre, fov 15/8 degrees) the 4x4 blocks agree with one beam per pixel within 1 %: the
    full frame's block bias measured 0.47 % (scripts/bench/diamond512.py, 128 wavelengths
    against 128-wavelength one-pixel beams) plus three times the two renders' noise here
    (0.13 % each at 64 wavelengths, measured between seeds; scripts/bench/beam_block_bias.py
    --res 64 --fov 1.875: bias 0.04 %).  The same blocks at 32x32, 1.9 degrees wide, are
    biased by 9.6 % (--res 32): what the bound keeps away."""
    from pathlib import Path

    from warpoptics.pipelines.render import beam_block

    path = Path(__file__).resolve().parents[1] / "scenes" / "diamond_fire.toml"
    sc = wo.Scene.load(path)
    assert beam_block(sc) == 4
    assert beam_block(sc.with_overrides({"camera.width": 20, "camera.height": 20})) == 1
    assert beam_block(_scene()) == 1  # orthographic
    assert beam_block(sc.with_overrides({"render.beam_block": 2})) == 2
    crop = sc.with_overrides({"camera.fov": 15.0 / 8, "camera.width": 64, "camera.height": 64})
    crop = crop.with_overrides({"render.wavelengths": 64})
    assert beam_block(crop) == 4
    blocks = Renderer(crop, device=device).run().rgb.astype(np.float64)
    pixels = Renderer(crop.with_overrides({"render.beam_block": 1}), device=device).run().rgb
    diff = np.sqrt(((blocks - pixels) ** 2).mean()) / pixels.mean()
    assert diff < 0.01, diff


def test_auto_takes_beams_where_they_apply_and_says_why(device):
    """``render.estimator = "auto"`` (the default) traces a convex dispersive stone and a
    birefringent one in beams and a fluorescent one in point samples, and ``Image.stats`` names
    the estimator and the reason."""
    sc = _scene(estimator="auto", obj={"shape": "round_brilliant", "diameter": 6.5, "material": "diamond"})
    r = Renderer(sc, device=device)
    assert r.estimator == "beam" and r.pixel_beam
    clear = Renderer(_scene(estimator="auto"), device=device)  # a constant index: one shared tree
    assert clear.estimator == "point" and "non-dispersive" in clear.estimator_reason
    uni = _scene(estimator="auto", obj={"shape": "round_brilliant", "diameter": 6.5, "material": "sapphire"})
    assert Renderer(uni, device=device).estimator == "beam"
    r = Renderer(
        _scene(estimator="auto", obj=FLUORESCENT).with_overrides(None, width=4, height=4), device=device
    )
    assert r.estimator == "point" and not r.pixel_beam
    assert "fluoresces" in r.estimator_reason
    img = r.run()
    assert img.stats["estimator"] == "point" and "fluoresces" in img.stats["estimator_reason"]
    pts = Renderer(_scene(estimator="point"), device=device)
    assert pts.estimator == "point" and pts.estimator_reason == 'render.estimator = "point"'


def test_beams_by_name_refuse_what_they_cannot_trace(device):
    with pytest.raises(InputError, match="fluoresces") as e:
        Renderer(_scene(estimator="beam", obj=FLUORESCENT), device=device)
    assert e.value.field == "render.estimator"


def test_pixel_beam_is_a_deprecated_alias():
    """``render.pixel_beam`` (the old switch) still works, warns, and maps onto the estimator."""
    data = {**ORTHO, "render": {k: v for k, v in ORTHO["render"].items() if k != "estimator"}}
    with pytest.warns(DeprecationWarning, match="render.estimator"):
        sc = wo.Scene.from_dict({**data, "render": {**data["render"], "pixel_beam": True}})
    assert sc.render.estimator == "beam"
    with pytest.warns(DeprecationWarning):
        sc = wo.Scene.from_dict({**data, "render": {**data["render"], "pixel_beam": False}})
    assert sc.render.estimator == "point"
    with pytest.raises(InputError, match="contradicts"):
        wo.Scene.from_dict({**data, "render": {**data["render"], "pixel_beam": False, "estimator": "beam"}})
    with pytest.raises(InputError, match="render.estimator"):
        wo.Scene.from_dict({**data, "render": {**data["render"], "estimator": "beams"}})


def test_the_command_line_says_which_estimator_ran(tmp_path, capsys):
    from warpoptics.cli import main

    out = tmp_path / "d.png"
    root = Path(__file__).resolve().parents[1]
    assert (
        main(
            [
                "render",
                str(root / "scenes" / "diamond.toml"),
                "-o",
                str(out),
                "--width",
                "8",
                "--height",
                "8",
                "--quiet",
            ]
        )
        == 0
    )
    assert "estimator: pixel beams (render.estimator = 'auto')" in capsys.readouterr().out


@pytest.mark.parametrize("camera", ["orthographic", "perspective"])
def test_rays_beside_a_side_facet_miss_the_stone(device, camera):
    """A plate beside the view, its side facets parallel to the orthographic rays: every ray
    misses it, so the beams see the empty dome (Y = 1) as point samples do.  A plane that does
    not face a ray used to set no bound on its entry even with the ray outside it (0.918)."""
    cam = {"type": camera, "position": [0.0, 0.0, -20.0], "look_at": [0.0, 0.0, 0.0], "up": [0.0, 1.0, 0.0]}
    cam.update({"view_height": 7.0} if camera == "orthographic" else {"fov": 15.0})
    data = {
        "camera": {**cam, "width": 8, "height": 8},
        "render": {"spectral": "stratified", "wavelengths": 8, "max_depth": 10},
        "light": [{"type": "environment", "map": "dome"}],
        "object": [
            {
                "shape": "plate",
                "width": 5.0,
                "length": 5.0,
                "thickness": 1.0,
                "material": "bk7",
                "position": [100.0, 0.0, 0.0],
            }
        ],
    }
    imgs = {}
    for est in ("point", "beam"):
        sc = wo.Scene.from_dict({**data, "render": {**data["render"], "estimator": est}})
        img = Renderer(sc, device=device).run()
        assert img.stats["estimator"] == est and img.alpha.max() == 0.0
        imgs[est] = img.xyz
    np.testing.assert_allclose(imgs["beam"], imgs["point"], rtol=1e-5)


CRYSTALS = {
    # a clear uniaxial stone (exact and approximate o/e transport) and a clear biaxial one
    "uniaxial": {
        "shape": "round_brilliant",
        "diameter": 6.5,
        "material": "sapphire",
        "absorption_scale": 0.0,
    },
    "biaxial": {"shape": "round_brilliant", "diameter": 6.5, "material": "peridot", "absorption_scale": 0.0},
}


@pytest.mark.parametrize(
    "kind, birefringence",
    [("uniaxial", "exact"), ("uniaxial", "approx"), ("biaxial", "exact")],
    ids=["uniaxial-exact", "uniaxial-approx", "biaxial-exact"],
)
def test_white_furnace_in_crystals(device, kind, birefringence):
    """Beams through a clear crystal in a uniform white environment: each part is one wave (o or
    e, fast or slow) whose vertices move by their own waves, and the generalized Fresnel event
    conserves energy, so a pixel sees the environment's radiance less the light still inside
    after max_depth interfaces, as for point samples.  A crystal's reflections split every part
    in two (o and e), so weak parts are rouletted (split_threshold): the beams are random, and
    their pixels scatter around the mean.  A wrong wave normal at a vertex or at the centre (the
    ray and wave normal differ in a crystal) loses a third of the light here."""
    obj = CRYSTALS[kind]
    kw = dict(light={"type": "environment", "map": "constant"}, obj=obj, max_depth=12, wavelengths=16)
    img = _render(_scene(**kw, birefringence=birefringence, bundle_lanes=16, split_threshold=0.002), device)
    assert img.stats["estimator"] == "beam"
    y = img.xyz[..., 1]
    stone = img.alpha > 0.99
    ref = y[img.alpha == 0.0].mean()
    ratio = y[stone] / ref
    # roulette's noise: a part below 0.2 % of a pixel's light lives with probability e / 0.002 and
    # then carries 0.2 %; a few such per pixel give a spread of ~1 % (measured: max 1.06)
    assert np.all(np.isfinite(ratio)) and ratio.max() < 1.1
    pts = _render(_scene(**kw, birefringence=birefringence, estimator="point", spp=64), device)
    want = pts.xyz[..., 1][stone] / pts.xyz[..., 1][pts.alpha == 0.0].mean()
    # the point samples' mean over the stone's pixels is good to ~0.5 % (64 spp, 16 interfaces)
    assert ratio.mean() == pytest.approx(want.mean(), abs=8e-3)
    assert 0.9 < ratio.mean() < 1.005


@pytest.mark.parametrize(
    "obj, beam_noise",
    [
        ({"shape": "round_brilliant", "diameter": 6.5, "material": "sapphire"}, 0.003),
        (
            {"shape": "round_brilliant", "diameter": 6.5, "material": "tourmaline", "optic_axis": [1, 0, 0]},
            0.003,
        ),
        ({"shape": "round_brilliant", "diameter": 6.5, "material": "tanzanite"}, 0.003),
    ],
    ids=["sapphire", "tourmaline-pleochroic", "tanzanite-biaxial"],
)
def test_orthographic_beams_equal_point_sampling_in_crystals(device, obj, beam_noise):
    """Orthographic beams through absorbing, pleochroic uniaxial and biaxial stones equal the
    mean of many point samples within the point samples' noise: every part's rays are parallel,
    so its one wave's Fresnel amplitudes, Jones matrix and kappa (Guy & Soler 2004 eq. 5, 7)
    are exact for all of them."""
    kw = dict(obj=obj, polarization=True, wavelengths=16, max_depth=10)
    pts = []
    for seed in (1, 2):
        sc = _scene(**kw, estimator="point", spp=96, seed=seed).with_overrides(None, width=8, height=8)
        pts.append(Renderer(sc, device=device).run().xyz)
    b = _render(
        _scene(**kw, bundle_lanes=16, split_threshold=0.001).with_overrides(None, width=8, height=8), device
    )
    assert b.stats["estimator"] == "beam"
    ref = 0.5 * (pts[0] + pts[1])
    noise = np.sqrt(((pts[0] - pts[1]) ** 2).mean()) / 2.0
    scale = ref.mean()
    err = np.sqrt(((b.xyz - ref) ** 2).mean())
    assert err < 3.0 * noise + 3.0 * beam_noise * scale, (err / scale, noise / scale)
    assert b.xyz.mean() == pytest.approx(scale, rel=max(0.01, 3.0 * noise / scale))
    s = b.stokes
    assert np.all(np.linalg.norm(s[..., 1:], axis=-1) <= s[..., 0] * (1 + 1e-5) + 1e-7)


def test_coated_stone_in_beams(device):
    """A coated stone (scenes/mystic_topaz.toml's three-layer stack on a clear brilliant) in
    beams: the stack's amplitudes at each part's centre (exact for a uniform coating seen
    orthographically, where every ray of a part meets the facet at one angle) equal point
    sampling within its noise; in a white environment the lossless stack conserves energy."""
    coated = {
        **COATED,
        "coating": [
            {"material": "main/TiO2/Devore-o", "thickness_nm": 160.0},
            {"material": "fused_silica", "thickness_nm": 110.0},
            {"material": "main/TiO2/Devore-o", "thickness_nm": 60.0},
        ],
    }
    kw = dict(obj=coated, polarization=True, wavelengths=16, max_depth=12)
    b = _render(
        _scene(**kw, bundle_lanes=16, split_threshold=0.001).with_overrides(None, width=8, height=8), device
    )
    assert b.stats["estimator"] == "beam"
    pts = []
    for seed in (1, 2):
        sc = _scene(**kw, estimator="point", spp=96, seed=seed).with_overrides(None, width=8, height=8)
        pts.append(Renderer(sc, device=device).run().xyz)
    ref = 0.5 * (pts[0] + pts[1])
    noise = np.sqrt(((pts[0] - pts[1]) ** 2).mean()) / 2.0
    scale = ref.mean()
    err = np.sqrt(((b.xyz - ref) ** 2).mean())
    assert err < 3.0 * noise + 0.01 * scale, (err / scale, noise / scale)
    white = dict(light={"type": "environment", "map": "constant"}, obj=coated, max_depth=12, wavelengths=16)
    img = _render(_scene(**white, bundle_lanes=16), device)
    y = img.xyz[..., 1]
    ratio = y[img.alpha > 0.99] / y[img.alpha == 0.0].mean()
    assert ratio.max() < 1.0 + 2e-3 and 0.85 < ratio.mean() < 1.0

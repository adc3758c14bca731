"""Bad scene input (TOML values, scene files, ``--set`` overrides, bench scenes) is refused with a
clear InputError naming the file, the field and the value."""

from __future__ import annotations

import pytest
from _helpers import BASE, DEL, FILE, ROOT, assert_clear_scene_error, mod

from warpoptics.errors import InputError
from warpoptics.scene import Scene

# (category, id, scene modifications (a callable of the bad-file folder), regex the message must
# match, field that must appear in the message, value that must appear (None: none))
BAD_SCENES = [
    ("toml", "unknown top key", lambda d: mod(rendr={}), "did you mean 'render'", "rendr", None),
    ("toml", "unknown render key", lambda d: mod(render__sp=2), "did you mean 'spp'", "render.sp", None),
    (
        "toml",
        "unknown camera key",
        lambda d: mod(camera__widht=3),
        "did you mean 'width'",
        "camera.widht",
        None,
    ),
    ("toml", "spp string", lambda d: mod(render__spp="4"), "must be an integer", "render.spp", "'4'"),
    ("toml", "spp zero", lambda d: mod(render__spp=0), "out of range", "render.spp", "0"),
    ("toml", "spp float", lambda d: mod(render__spp=1.5), "integer", "render.spp", "1.5"),
    (
        "toml",
        "wavelengths 0",
        lambda d: mod(render__wavelengths=0),
        "out of range",
        "render.wavelengths",
        "0",
    ),
    (
        "toml",
        "spectral typo",
        lambda d: mod(render__spectral="rgb"),
        "did you mean 'rgb3'",
        "render.spectral",
        "'rgb'",
    ),
    (
        "toml",
        "polarization string",
        lambda d: mod(render__polarization="yes"),
        "true or false",
        "render.polarization",
        "'yes'",
    ),
    (
        "toml",
        "exposure nan",
        lambda d: mod(render__exposure=float("nan")),
        "finite",
        "render.exposure",
        "nan",
    ),
    (
        "toml",
        "ambient index < 1",
        lambda d: mod(render__ambient_index=0.5),
        "out of range",
        "render.ambient_index",
        "0.5",
    ),
    ("toml", "width 0", lambda d: mod(camera__width=0), "pixel count", "camera.width", "0"),
    ("toml", "width float", lambda d: mod(camera__width=3.5), "pixel count", "camera.width", "3.5"),
    ("toml", "height string", lambda d: mod(camera__height="big"), "pixel count", "camera.height", "'big'"),
    ("toml", "fov 180", lambda d: mod(camera__fov=180.0), "field of view", "camera.fov", "180"),
    (
        "toml",
        "camera type",
        lambda d: mod(camera__type="fisheye"),
        "camera type",
        "camera.type",
        "'fisheye'",
    ),
    (
        "toml",
        "look_at = position",
        lambda d: mod(camera__look_at=[0.0, -22.0, 30.0]),
        "no direction",
        "camera.look_at",
        None,
    ),
    (
        "toml",
        "up parallel to view",
        lambda d: mod(camera__up=[0.0, 22.0, -30.3]),
        "parallel",
        "camera.up",
        None,
    ),
    (
        "toml",
        "position 2 numbers",
        lambda d: mod(camera__position=[1.0, 2.0]),
        "three numbers",
        "camera.position",
        "[1.0, 2.0]",
    ),
    (
        "toml",
        "position inf",
        lambda d: mod(camera__position=[1.0, 2.0, float("inf")]),
        "finite",
        "camera.position",
        "inf",
    ),
    ("toml", "aperture < 0", lambda d: mod(camera__aperture=-1.0), ">= 0", "camera.aperture", "-1.0"),
    ("toml", "camera not a table", lambda d: mod(camera=[1]), "table", "camera", None),
    ("toml", "no objects", lambda d: mod(object=[]), "at least one", "object", None),
    ("toml", "object not a table", lambda d: mod(object=[5]), "must be a table", "object.0", "5"),
    ("toml", "light not a table", lambda d: mod(light=["studio"]), "must be a table", "light.0", "'studio'"),
    ("toml", "shape missing", lambda d: mod(object__0__shape=DEL), "missing key", "object.0.shape", None),
    (
        "toml",
        "shape typo",
        lambda d: mod(object__0__shape="round_briliant"),
        "did you mean 'round_brilliant'",
        "object.0.shape",
        "'round_briliant'",
    ),
    (
        "toml",
        "cut parameter typo",
        lambda d: mod(object__0__pavilion_angel=41.0),
        "did you mean 'pavilion_angle'",
        "object.0.pavilion_angel",
        None,
    ),
    (
        "toml",
        "diameter < 0",
        lambda d: mod(object__0__diameter=-1.0),
        "out of range",
        "object.0.diameter",
        "-1.0",
    ),
    (
        "toml",
        "pavilion 90 deg",
        lambda d: mod(object__0__pavilion_angle=90.0),
        "out of range",
        "object.0.pavilion_angle",
        "90.0",
    ),
    ("toml", "table 1.5", lambda d: mod(object__0__table=1.5), "out of range", "object.0.table", "1.5"),
    (
        "toml",
        "girdle facets 3",
        lambda d: mod(object__0__girdle_facets=3),
        "girdle facet",
        "object.0.girdle_facets",
        "3",
    ),
    ("toml", "scale 0", lambda d: mod(object__0__scale=0.0), "out of range", "object.0.scale", "0.0"),
    (
        "toml",
        "scale 1e9",
        lambda d: mod(object__0__scale=1e9),
        "out of range",
        "object.0.scale",
        "1000000000.0",
    ),
    (
        "toml",
        "absorption_scale < 0",
        lambda d: mod(object__0__absorption_scale=-1.0),
        "out of range",
        "object.0.absorption_scale",
        "-1.0",
    ),
    (
        "toml",
        "rotation string",
        lambda d: mod(object__0__rotation="x"),
        "three numbers",
        "object.0.rotation",
        "'x'",
    ),
    (
        "toml",
        "two lights",
        lambda d: mod(light=[{"type": "constant"}, {"type": "constant"}]),
        "exactly one",
        "light",
        "2",
    ),
    (
        "toml",
        "intensity < 0",
        lambda d: mod(light__0__intensity=-1.0),
        "out of range",
        "light.0.intensity",
        "-1.0",
    ),
    (
        "toml",
        "light type",
        lambda d: mod(light__0__type="point"),
        "unknown value",
        "light.0.type",
        "'point'",
    ),
    ("toml", "tint < 0", lambda d: mod(light__0__tint=[1.0, -1.0, 1.0]), ">= 0", "light.0.tint", None),
]


@pytest.mark.parametrize(
    ("category", "case", "make", "match", "field", "value"),
    BAD_SCENES,
    ids=[f"{c[0]}-{c[1]}" for c in BAD_SCENES],
)
def test_bad_scene_input_is_a_clear_input_error(category, case, make, match, field, value):
    data = make(None)
    assert_clear_scene_error(data, match, field, value)


@pytest.mark.parametrize(
    ("name", "content", "match"),
    [
        ("missing.toml", None, "scene file not found"),
        ("empty.toml", "", "at least one"),
        ("malformed.toml", "[camera\nwidth = 3\n", "not valid TOML"),
        ("binary.toml", b"\xff\xfe\x00garbage", "not a UTF-8"),
    ],
)
def test_bad_scene_files(tmp_path, name, content, match):
    p = tmp_path / name
    if isinstance(content, bytes):
        p.write_bytes(content)
    elif content is not None:
        p.write_text(content)
    with pytest.raises(InputError, match=match) as info:
        Scene.load(p)
    assert str(p) in str(info.value)


@pytest.mark.parametrize(
    ("overrides", "match", "field"),
    [
        ({"renderspp": 3}, "dotted path", "renderspp"),
        ({"object.5.diameter": 3.0}, "no element '5'", "object.5"),
        ({"object.x.diameter": 3.0}, "no element 'x'", "object.x"),
        ({"render.spp": "abc"}, "integer", "render.spp"),
        ({"object.0.diamter": 5.0}, "did you mean 'diameter'", "object.0.diamter"),
        ({"camera.fov": float("inf")}, "finite", "camera.fov"),
        ({"light.0": 1}, "cannot replace a whole table", "light.0"),
    ],
)
def test_bad_overrides(overrides, match, field):
    scene = Scene.from_dict(BASE, path=FILE)
    with pytest.raises(InputError, match=match) as info:
        scene.with_overrides(overrides)
    assert field in str(info.value) and FILE in str(info.value)


BAD_BENCH = [
    ("source.type", "lamp", "unknown value"),
    ("source.direction", [0.0, 0.0, 0.0], "non-zero"),
    ("source.lines", [100000.0], "out of range"),
    ("source.rays", 0, "out of range"),
    ("source.positon", [0.0, 0.0, 1.0], "did you mean 'position'"),
    ("sensor.0.normal", [0.0, 0.0, 0.0], "non-zero"),
    ("sensor.0.resolution", [100000, 100000], "pixel counts"),
    ("sensor.0.up", [0.0, 0.0, 1.0], "parallel"),
]


@pytest.mark.parametrize(
    ("path", "value", "match"), BAD_BENCH, ids=[c[0] + "=" + str(c[1]) for c in BAD_BENCH]
)
def test_bad_bench_input(path, value, match):
    import tomllib

    from warpoptics.scene.bench import BenchScene

    data = tomllib.loads((ROOT / "scenes" / "bench" / "calcite.toml").read_text())
    node = data
    parts = path.split(".")
    for p in parts[:-1]:
        node = node[int(p)] if isinstance(node, list) else node[p]
    node[parts[-1]] = value
    with pytest.raises(InputError, match=match) as info:
        BenchScene.from_dict(data, path=FILE)
    assert FILE in str(info.value) and path in str(info.value)

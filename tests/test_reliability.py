"""Reliability (issue 12): bad input gives a clear InputError (file, field, value, allowed) and a
one-line CLI error with exit 2; physical edge cases stay finite; property-based checks of the
optics/thin-film wrappers; a NaN/Inf scan of tiny renders over random scenes; byte-identical EXR
for any thread count through the CLI; atomic writers; renders too large for memory are refused.
"""

from __future__ import annotations

import copy
import importlib
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import warpoptics as wo
from warpoptics import cli
from warpoptics.errors import InputError
from warpoptics.image import read_image, write_exr
from warpoptics.render import Renderer, check_render_memory, estimate_render_bytes
from warpoptics.scene import Scene

# the modules (``warpoptics.optics`` re-exports functions with the same names)
fr = importlib.import_module("warpoptics.optics.fresnel")
jo = importlib.import_module("warpoptics.optics.jones")
tf = importlib.import_module("warpoptics.optics.thinfilm")

ROOT = Path(__file__).resolve().parents[1]
FILE = "/scenes/x.toml"  # the file name every API error must name

BASE = {
    "camera": {
        "position": [0.0, -22.0, 30.0],
        "look_at": [0.0, 0.0, -0.3],
        "fov": 15.0,
        "width": 4,
        "height": 4,
    },
    "render": {"spectral": "stratified", "wavelengths": 3, "max_depth": 6},
    "light": [{"type": "environment", "map": "studio"}],
    "object": [{"shape": "round_brilliant", "diameter": 6.5, "material": "diamond"}],
}
_DEL = object()


def _mod(**mods) -> dict:
    """BASE with ``a__b__0__c=value`` replacements (``_DEL`` deletes the key)."""
    d = copy.deepcopy(BASE)
    for k, v in mods.items():
        parts = k.split("__")
        node = d
        for p in parts[:-1]:
            node = node[int(p)] if isinstance(node, list) else node.setdefault(p, {})
        last = int(parts[-1]) if isinstance(node, list) else parts[-1]
        if v is _DEL:
            del node[last]
        else:
            node[last] = v
    return d


@pytest.fixture(scope="module")
def bad_files(tmp_path_factory) -> Path:
    d = tmp_path_factory.mktemp("bad")
    (d / "empty.toml").write_text("")
    (d / "malformed.toml").write_text("[camera\nwidth = 3\n")
    (d / "binary.toml").write_bytes(b"\xff\xfe\x00garbage")
    box = trimesh.creation.box(extents=(2.0, 2.0, 2.0))
    m = box.copy()
    m.faces = m.faces[:-2]
    m.export(d / "open.ply")
    m = box.copy()
    m.invert()
    m.export(d / "inverted.ply")
    m = box.copy()
    m.apply_scale(1e6)
    m.export(d / "huge.ply")
    m = box.copy()
    m.apply_scale(1e-7)
    m.export(d / "tiny.ply")
    (d / "garbage.ply").write_text("not a mesh at all")
    (d / "degenerate.obj").write_text("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")
    (d / "garbage.asc").write_text("this is no GemCAD file\n")
    write_exr(d / "square.exr", np.ones((8, 8, 3), np.float32))
    write_exr(d / "negative.exr", -np.ones((8, 16, 3), np.float32))
    nan = np.ones((8, 16, 3), np.float32)
    nan[0, 0, 0] = np.nan
    write_exr(d / "nan.exr", nan)
    (d / "notimage.exr").write_text("hello")
    return d


def _mesh(path: str) -> dict:
    return {"shape": "mesh", "path": path}


# (category, id, scene modifications (a callable of the bad-file folder), regex the message must
# match, field that must appear in the message, value that must appear (None: none))
BAD_SCENES = [
    ("toml", "unknown top key", lambda d: _mod(rendr={}), "did you mean 'render'", "rendr", None),
    ("toml", "unknown render key", lambda d: _mod(render__sp=2), "did you mean 'spp'", "render.sp", None),
    (
        "toml",
        "unknown camera key",
        lambda d: _mod(camera__widht=3),
        "did you mean 'width'",
        "camera.widht",
        None,
    ),
    ("toml", "spp string", lambda d: _mod(render__spp="4"), "must be an integer", "render.spp", "'4'"),
    ("toml", "spp zero", lambda d: _mod(render__spp=0), "out of range", "render.spp", "0"),
    ("toml", "spp float", lambda d: _mod(render__spp=1.5), "integer", "render.spp", "1.5"),
    (
        "toml",
        "wavelengths 0",
        lambda d: _mod(render__wavelengths=0),
        "out of range",
        "render.wavelengths",
        "0",
    ),
    (
        "toml",
        "spectral typo",
        lambda d: _mod(render__spectral="rgb"),
        "did you mean 'rgb3'",
        "render.spectral",
        "'rgb'",
    ),
    (
        "toml",
        "polarization string",
        lambda d: _mod(render__polarization="yes"),
        "true or false",
        "render.polarization",
        "'yes'",
    ),
    (
        "toml",
        "exposure nan",
        lambda d: _mod(render__exposure=float("nan")),
        "finite",
        "render.exposure",
        "nan",
    ),
    (
        "toml",
        "ambient index < 1",
        lambda d: _mod(render__ambient_index=0.5),
        "out of range",
        "render.ambient_index",
        "0.5",
    ),
    ("toml", "width 0", lambda d: _mod(camera__width=0), "pixel count", "camera.width", "0"),
    ("toml", "width float", lambda d: _mod(camera__width=3.5), "pixel count", "camera.width", "3.5"),
    ("toml", "height string", lambda d: _mod(camera__height="big"), "pixel count", "camera.height", "'big'"),
    ("toml", "fov 180", lambda d: _mod(camera__fov=180.0), "field of view", "camera.fov", "180"),
    (
        "toml",
        "camera type",
        lambda d: _mod(camera__type="fisheye"),
        "camera type",
        "camera.type",
        "'fisheye'",
    ),
    (
        "toml",
        "look_at = position",
        lambda d: _mod(camera__look_at=[0.0, -22.0, 30.0]),
        "no direction",
        "camera.look_at",
        None,
    ),
    (
        "toml",
        "up parallel to view",
        lambda d: _mod(camera__up=[0.0, 22.0, -30.3]),
        "parallel",
        "camera.up",
        None,
    ),
    (
        "toml",
        "position 2 numbers",
        lambda d: _mod(camera__position=[1.0, 2.0]),
        "three numbers",
        "camera.position",
        "[1.0, 2.0]",
    ),
    (
        "toml",
        "position inf",
        lambda d: _mod(camera__position=[1.0, 2.0, float("inf")]),
        "finite",
        "camera.position",
        "inf",
    ),
    ("toml", "aperture < 0", lambda d: _mod(camera__aperture=-1.0), ">= 0", "camera.aperture", "-1.0"),
    ("toml", "camera not a table", lambda d: _mod(camera=[1]), "table", "camera", None),
    ("toml", "no objects", lambda d: _mod(object=[]), "at least one", "object", None),
    ("toml", "object not a table", lambda d: _mod(object=[5]), "must be a table", "object.0", "5"),
    ("toml", "light not a table", lambda d: _mod(light=["studio"]), "must be a table", "light.0", "'studio'"),
    ("toml", "shape missing", lambda d: _mod(object__0__shape=_DEL), "missing key", "object.0.shape", None),
    (
        "toml",
        "shape typo",
        lambda d: _mod(object__0__shape="round_briliant"),
        "did you mean 'round_brilliant'",
        "object.0.shape",
        "'round_briliant'",
    ),
    (
        "toml",
        "cut parameter typo",
        lambda d: _mod(object__0__pavilion_angel=41.0),
        "did you mean 'pavilion_angle'",
        "object.0.pavilion_angel",
        None,
    ),
    (
        "toml",
        "diameter < 0",
        lambda d: _mod(object__0__diameter=-1.0),
        "out of range",
        "object.0.diameter",
        "-1.0",
    ),
    (
        "toml",
        "pavilion 90 deg",
        lambda d: _mod(object__0__pavilion_angle=90.0),
        "out of range",
        "object.0.pavilion_angle",
        "90.0",
    ),
    ("toml", "table 1.5", lambda d: _mod(object__0__table=1.5), "out of range", "object.0.table", "1.5"),
    (
        "toml",
        "girdle facets 3",
        lambda d: _mod(object__0__girdle_facets=3),
        "girdle facet",
        "object.0.girdle_facets",
        "3",
    ),
    ("toml", "scale 0", lambda d: _mod(object__0__scale=0.0), "out of range", "object.0.scale", "0.0"),
    (
        "toml",
        "scale 1e9",
        lambda d: _mod(object__0__scale=1e9),
        "out of range",
        "object.0.scale",
        "1000000000.0",
    ),
    (
        "toml",
        "absorption_scale < 0",
        lambda d: _mod(object__0__absorption_scale=-1.0),
        "out of range",
        "object.0.absorption_scale",
        "-1.0",
    ),
    (
        "toml",
        "rotation string",
        lambda d: _mod(object__0__rotation="x"),
        "three numbers",
        "object.0.rotation",
        "'x'",
    ),
    (
        "toml",
        "two lights",
        lambda d: _mod(light=[{"type": "constant"}, {"type": "constant"}]),
        "exactly one",
        "light",
        "2",
    ),
    (
        "toml",
        "intensity < 0",
        lambda d: _mod(light__0__intensity=-1.0),
        "out of range",
        "light.0.intensity",
        "-1.0",
    ),
    (
        "toml",
        "light type",
        lambda d: _mod(light__0__type="point"),
        "unknown value",
        "light.0.type",
        "'point'",
    ),
    ("toml", "tint < 0", lambda d: _mod(light__0__tint=[1.0, -1.0, 1.0]), ">= 0", "light.0.tint", None),
    (
        "mesh",
        "mesh without path",
        lambda d: _mod(object__0={"shape": "mesh"}),
        "needs path",
        "object.0.path",
        None,
    ),
    (
        "mesh",
        "mesh file missing",
        lambda d: _mod(object__0=_mesh("nope.ply")),
        "file not found",
        "object.0.path",
        "'nope.ply'",
    ),
    (
        "mesh",
        "not watertight",
        lambda d: _mod(object__0=_mesh(str(d / "open.ply"))),
        "not watertight",
        "open.ply",
        None,
    ),
    (
        "mesh",
        "inverted",
        lambda d: _mod(object__0=_mesh(str(d / "inverted.ply"))),
        "inverted",
        "inverted.ply",
        None,
    ),
    (
        "mesh",
        "absurd scale (km)",
        lambda d: _mod(object__0=_mesh(str(d / "huge.ply"))),
        "absurd scale",
        "huge.ply",
        None,
    ),
    (
        "mesh",
        "absurd scale (nm)",
        lambda d: _mod(object__0=_mesh(str(d / "tiny.ply"))),
        "absurd scale",
        "tiny.ply",
        None,
    ),
    (
        "mesh",
        "not a mesh file",
        lambda d: _mod(object__0=_mesh(str(d / "garbage.ply"))),
        "cannot read mesh",
        "garbage.ply",
        None,
    ),
    (
        "mesh",
        "degenerate faces",
        lambda d: _mod(object__0=_mesh(str(d / "degenerate.obj"))),
        "degenerate",
        "degenerate.obj",
        None,
    ),
    (
        "mesh",
        "repair not boolean",
        lambda d: _mod(object__0={**_mesh(str(d / "open.ply")), "repair": "yes"}),
        "must be a number",
        "object.0.repair",
        "'yes'",
    ),
    (
        "mesh",
        "gemcad file missing",
        lambda d: _mod(object__0={"shape": "gemcad", "path": "nope.asc"}),
        "file not found",
        "object.0.path",
        "'nope.asc'",
    ),
    (
        "mesh",
        "gemcad garbage",
        lambda d: _mod(object__0={"shape": "gemcad", "path": str(d / "garbage.asc")}),
        "not a GemCAD .asc file",
        "garbage.asc",
        None,
    ),
    (
        "material",
        "unknown name",
        lambda d: _mod(object__0__material="diamnod"),
        "did you mean 'diamond'",
        "object.0.material",
        "'diamnod'",
    ),
    ("material", "number", lambda d: _mod(object__0__material=5), "material name", "object.0.material", "5"),
    (
        "material",
        "cauchy n < 1",
        lambda d: _mod(object__0__material={"cauchy": [0.5]}),
        ">= 1",
        "object.0.material.cauchy",
        "[0.5]",
    ),
    (
        "material",
        "cauchy n < 1 in range",
        lambda d: _mod(object__0__material={"cauchy": [1.2, -1e6]}),
        "below 1 at",
        "object.0.material.n",
        None,
    ),
    (
        "material",
        "cauchy n = 1e30",
        lambda d: _mod(object__0__material={"cauchy": [1e30]}),
        "absurdly large",
        "object.0.material.n",
        None,
    ),
    (
        "material",
        "cauchy empty",
        lambda d: _mod(object__0__material={"cauchy": []}),
        "list of numbers",
        "object.0.material.cauchy",
        "[]",
    ),
    (
        "material",
        "cauchy string",
        lambda d: _mod(object__0__material={"cauchy": ["a"]}),
        "list of numbers",
        "object.0.material.cauchy",
        "['a']",
    ),
    (
        "material",
        "inline key typo",
        lambda d: _mod(object__0__material={"cauchy": [1.5], "colr": 1}),
        "unknown key",
        "object.0.material.colr",
        None,
    ),
    (
        "material",
        "base and cauchy",
        lambda d: _mod(object__0__material={"cauchy": [1.5], "base": "diamond"}),
        "exactly one",
        "object.0.material",
        None,
    ),
    (
        "material",
        "negative band",
        lambda d: _mod(
            object__0__material={
                "base": "diamond",
                "bands": [{"center_nm": 500, "width_nm": 20, "peak_alpha_per_mm": -1}],
            }
        ),
        "negative absorption",
        "object.0.material.bands.0.peak_alpha_per_mm",
        "-1",
    ),
    (
        "material",
        "band width 0",
        lambda d: _mod(
            object__0__material={
                "base": "diamond",
                "bands": [{"center_nm": 500, "width_nm": 0, "peak_alpha_per_mm": 1}],
            }
        ),
        "> 0 nm",
        "object.0.material.bands.0",
        None,
    ),
    (
        "material",
        "band centre string",
        lambda d: _mod(
            object__0__material={
                "base": "diamond",
                "bands": [{"center_nm": "x", "width_nm": 20, "peak_alpha_per_mm": 1}],
            }
        ),
        "must be a number",
        "object.0.material.bands.0.center_nm",
        "'x'",
    ),
    (
        "material",
        "band key missing",
        lambda d: _mod(object__0__material={"base": "diamond", "bands": [{"center_nm": 500}]}),
        "missing key",
        "object.0.material.bands.0.width_nm",
        None,
    ),
    (
        "material",
        "negative absorption_rgb",
        lambda d: _mod(object__0__material={"base": "diamond", "absorption_rgb": [-1, 0, 0]}),
        "negative absorption",
        "object.0.material",
        "-1",
    ),
    (
        "material",
        "zero optic axis (inline)",
        lambda d: _mod(object__0__material={"base": "calcite", "optic_axis": [0, 0, 0]}),
        "non-zero",
        "object.0.material.optic_axis",
        "[0, 0, 0]",
    ),
    (
        "material",
        "zero optic axis (object)",
        lambda d: _mod(object__0__material="calcite", object__0__optic_axis=[0.0, 0.0, 0.0]),
        "must not be zero",
        "object.0.optic_axis",
        None,
    ),
    (
        "material",
        "optic axis on isotropic",
        lambda d: _mod(object__0__optic_axis=[0.0, 0.0, 1.0]),
        "uniaxial",
        "object.0.optic_axis",
        None,
    ),
    (
        "env",
        "unknown map",
        lambda d: _mod(light__0__map="stuido"),
        "unknown environment map",
        "light",
        "'stuido'",
    ),
    (
        "env",
        "map file missing",
        lambda d: _mod(light__0__map=str(d / "none.exr")),
        "not found",
        "light",
        "none.exr",
    ),
    (
        "env",
        "map unreadable",
        lambda d: _mod(light__0__map=str(d / "notimage.exr")),
        "unreadable",
        "light",
        "notimage.exr",
    ),
    (
        "env",
        "map not 2:1",
        lambda d: _mod(light__0__map=str(d / "square.exr")),
        "twice as wide",
        "light",
        "square.exr",
    ),
    (
        "env",
        "map negative",
        lambda d: _mod(light__0__map=str(d / "negative.exr")),
        "negative",
        "light",
        "negative.exr",
    ),
    ("env", "map NaN", lambda d: _mod(light__0__map=str(d / "nan.exr")), "non-finite", "light", "nan.exr"),
]


@pytest.mark.parametrize(
    ("category", "case", "make", "match", "field", "value"),
    BAD_SCENES,
    ids=[f"{c[0]}-{c[1]}" for c in BAD_SCENES],
)
def test_bad_scene_input_is_a_clear_input_error(bad_files, category, case, make, match, field, value):
    data = make(bad_files)
    with pytest.raises(InputError, match=match) as info:
        Renderer(Scene.from_dict(data, path=FILE))
    msg = str(info.value)
    # the message names the file (the scene, or the mesh file at fault), the field and the value
    assert FILE in msg or (field.endswith((".ply", ".obj", ".asc")) and field in msg), msg
    assert field in msg, msg
    if value is not None:
        assert value in msg, msg
    assert "\n" not in msg


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


def test_gemcad_object_in_a_scene(tmp_path):
    """A GemCAD design written by ``warpoptics cut`` loads as a scene object (it used to fail with
    an ImportError)."""
    from warpoptics.geometry import cuts, gemcad

    asc = tmp_path / "rb.asc"
    gemcad.write(cuts.round_brilliant(), asc)
    data = _mod(object__0={"shape": "gemcad", "path": str(asc), "diameter": 6.5})
    from warpoptics.render import _build_objects

    scene = Scene.from_dict(data, path=FILE)
    Renderer(scene)
    ((mesh, _),) = _build_objects(scene, None)[0]
    lo, hi = mesh.bounds
    assert abs(max((hi - lo)[:2]) - 6.5) < 0.05  # scaled to the girdle width asked for


@pytest.mark.parametrize(
    ("wavelength", "match"),
    [
        (100.0, "outside the data range of diamond"),
        (5000.0, "outside the data range of diamond"),
        (float("nan"), "must be finite"),
    ],
)
def test_material_wavelength_outside_its_data(device, wavelength, match):
    from warpoptics.materials import get

    with pytest.raises(InputError, match=match) as info:
        get("diamond").n(wavelength, device=device)
    assert "wavelength_nm" in str(info.value)


# ---- the command line: one line on stderr, exit 2, no traceback (in-process for speed) ----------

CLI_CASES = [
    (["render", "{scene}", "-o", "{tmp}/a.exr", "--width", "0"], "camera.width = 0"),
    (["render", "{scene}", "-o", "{tmp}/a.exr", "--spp", "0"], "render.spp = 0"),
    (["render", "{scene}", "-o", "{tmp}/a.bmp"], "unsupported output format"),
    (["render", "{scene}", "-o", "{tmp}/a.exr", "--width", "100000", "--height", "100000"], "GiB"),
    (["render", "{tmp}/missing.toml", "-o", "{tmp}/a.exr"], "scene file not found"),
    (["render", "{scene}", "-o", "{tmp}/a.exr", "--set", "render.spp"], "expected KEY=VALUE"),
    (["render", "{scene}", "-o", "{tmp}/a.exr", "--set", "object.0.diamter=5"], "did you mean 'diameter'"),
    (["render", "{scene}", "-o", "{tmp}/a.exr", "--set", "render.spp=abc"], "render.spp = 'abc'"),
    (["render", "{scene}", "-o", "/dev/null/a.exr", "--width", "2"], "cannot create the output"),
    (["bench", "{tmp}/missing.toml", "-o", "{tmp}/b.png"], "scene file not found"),
    (["bench", "{scene}", "-o", "{tmp}/b.png"], "camera: unknown key"),
    (["cut", "round_brilliant", "-o", "{tmp}/c.xyz"], "unsupported output format"),
    (["cut", "roundbrilliant", "-o", "{tmp}/c.ply"], "unknown shape"),
    (["cut", "round_brilliant", "--pavilion-angle", "80", "-o", "{tmp}/c.ply"], "pavilion_angle = 80.0"),
    (["cut", "round_brilliant", "--apex-angle", "30", "-o", "{tmp}/c.ply"], "not a parameter"),
    (["cut", "{tmp}/missing.asc", "-o", "{tmp}/c.ply"], "no such file"),
    (["cut", "step_cut", "--crown-angles", "30,x", "-o", "{tmp}/c.ply"], "comma-separated"),
    (["material", "diamnod"], "did you mean 'diamond'"),
    (["material", "diamond", "--plot", "{tmp}/m.xyz"], "unsupported plot format"),
    (["spectrum", "-o", "{tmp}/s.xyz"], "unsupported plot format"),
    (["--device", "bogus", "info"], "not available"),
    (["thinfilm", "table", "-o", "{tmp}/t.xyz"], "unsupported output type"),
    (["thinfilm", "table", "-o", "{tmp}/t.png", "--count", "100000000"], "--count = 100000000"),
    (["thinfilm", "table", "-o", "{tmp}/t.png", "--model", "exact", "--n-film", "0.5"], "--n-film = 0.5"),
    (["thinfilm", "table", "-o", "{tmp}/t.png", "--multilayer", "--d1", "-3"], "--d1 = -3.0"),
    (["thinfilm", "table", "-o", "{tmp}/t.png", "--multilayer", "--layers", "0"], "--layers = 0"),
    (["thinfilm", "table", "-o", "{tmp}/t.png", "--illuminant", "X99"], "unknown illuminant"),
]


@pytest.mark.parametrize(
    ("argv", "match"), CLI_CASES, ids=[" ".join(c[0][:2]) + f"-{i}" for i, c in enumerate(CLI_CASES)]
)
def test_cli_bad_input_one_line_exit_2(tmp_path, capsys, monkeypatch, argv, match):
    monkeypatch.setenv("WARPOPTICS_DEVICE", "cpu")  # restored afterwards ("--device bogus" sets it)
    scene = str(ROOT / "scenes" / "diamond.toml")
    args = [a.format(scene=scene, tmp=tmp_path) for a in argv]
    rc = cli.main(args)
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if ln.startswith("warpoptics")]
    assert rc == 2, err
    assert len(lines) == 1 and match in lines[0], err
    assert "Traceback" not in err


def test_cli_unwritable_output_is_one_line(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    rc = cli.main(["cut", "cube", "-o", str(blocker / "sub" / "c.ply")])
    err = capsys.readouterr().err
    assert rc == 2 and "Traceback" not in err and err.count("\n") == 1, err


def test_cli_subprocess_exit_code_and_debug(tmp_path):
    """The real command: one line, exit 2, no traceback; ``--debug`` (even after the subcommand)
    shows the traceback."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    base = [
        sys.executable,
        "-m",
        "warpoptics.cli",
        "render",
        str(ROOT / "scenes" / "diamond.toml"),
        "-o",
        str(tmp_path / "a.exr"),
        "--set",
        "render.sp=2",
    ]
    p = subprocess.run(base, capture_output=True, text=True, env=env, timeout=120)
    assert p.returncode == 2
    ours = [ln for ln in p.stderr.splitlines() if ln.startswith("warpoptics")]
    assert len(ours) == 1 and "render.sp: unknown key; did you mean 'spp'?" in ours[0], p.stderr
    assert "Traceback" not in p.stderr
    p = subprocess.run([*base, "--debug"], capture_output=True, text=True, env=env, timeout=120)
    assert p.returncode != 0 and "Traceback" in p.stderr and "InputError" in p.stderr


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

    from warpoptics.bench import BenchScene

    data = tomllib.loads((ROOT / "scenes" / "bench" / "calcite.toml").read_text())
    node = data
    parts = path.split(".")
    for p in parts[:-1]:
        node = node[int(p)] if isinstance(node, list) else node[p]
    node[parts[-1]] = value
    with pytest.raises(InputError, match=match) as info:
        BenchScene.from_dict(data, path=FILE)
    assert FILE in str(info.value) and path in str(info.value)


# ---- memory ----------------------------------------------------------------------------------------


def test_render_too_large_for_memory_is_refused(monkeypatch):
    need = estimate_render_bytes(100_000, 100_000)
    assert need > 100_000 * 100_000 * 72  # at least the float64 film
    # film and image with per-channel Stokes (polarization views): 564 bytes per pixel
    with pytest.raises(InputError, match=r"about 5252\.7 GiB") as info:
        check_render_memory(100_000, 100_000, available=8 * 2**30, file=FILE)
    assert "100000x100000" in str(info.value) and FILE in str(info.value)
    assert check_render_memory(64, 64, available=8 * 2**30) == estimate_render_bytes(64, 64)
    # the renderer checks before it allocates anything
    wr = importlib.import_module("warpoptics.render")
    monkeypatch.setattr(wr, "available_memory_bytes", lambda: 1000)
    with pytest.raises(InputError, match="GiB"):
        Renderer(Scene.from_dict(BASE, path=FILE))


# ---- physical edge cases: finite, and what they should be ------------------------------------------


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
    resolves the tie the same way every time, so the light only ever meets one of them;
    measured on this scene: the image equals the one-stone image exactly (Y mean 0.30119 both).
    Coincident solids are not merged or treated as one medium; the check here is only that
    nothing crashes or goes NaN."""
    stone = {"shape": "round_brilliant", "diameter": 6.5, "material": "diamond"}
    one = _finite_render(_scene_data([stone]), device)
    two = _finite_render(_scene_data([stone, dict(stone)]), device)
    assert np.array_equal(one.alpha > 0, two.alpha > 0)


# ---- property-based tests --------------------------------------------------------------------------

_PROP = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


@_PROP
@given(
    cos_i=st.floats(0.0, 1.0),
    n1=st.floats(1.0, 4.0),
    n2=st.floats(1.0, 4.0),
    k2=st.one_of(st.just(0.0), st.floats(1e-6, 50.0)),
)
def test_fresnel_power_is_physical(device, cos_i, n1, n2, k2):
    rs, rp, ts, tp = fr.fresnel(np.array([cos_i]), n1, n2 + 1j * k2, device=device)
    Rs, Rp, Ts, Tp = fr.fresnel_power(np.array([cos_i]), n1, n2 + 1j * k2, device=device)
    for x in (rs, rp, ts, tp, Rs, Rp, Ts, Tp):
        assert np.all(np.isfinite(x))
    # energy: R + T = 1 (float32: 2e-4), reflectances in [0, 1]; at exactly grazing incidence the
    # normal flux is zero and T (a flux ratio) is reported as 0
    for R, T in ((Rs, Ts), (Rp, Tp)):
        assert -1e-6 <= R[0] <= 1 + 1e-5 and T[0] >= -1e-5 and R[0] + T[0] <= 1 + 2e-4
        if cos_i > 1e-3:
            assert R[0] + T[0] == pytest.approx(1.0, abs=2e-4)
    # an interface turns a coherency matrix into a Hermitian PSD one with DOP <= 1
    m = np.zeros((1, 2, 2), complex)
    m[0, 0, 0], m[0, 1, 1] = rs[0], rp[0]
    j = jo.coherency_apply(m, np.eye(2)[None] * 0.5, device=device)
    assert np.allclose(j, np.conj(np.swapaxes(j, -1, -2)), atol=1e-6)
    assert np.linalg.eigvalsh(j).min() >= -1e-6
    p = jo.dop(j, device=device)
    assert np.all(np.isfinite(p)) and np.all((p >= 0) & (p <= 1 + 1e-6))


@_PROP
@given(
    layers=st.lists(
        st.tuples(st.floats(1.0, 3.0), st.floats(0.0, 2.0), st.floats(0.0, 5000.0)), min_size=0, max_size=5
    ),
    angle=st.floats(0.0, 90.0),
    n_sub=st.floats(1.0, 3.0),
    k_sub=st.floats(0.0, 5.0),
    wl=st.floats(300.0, 1000.0),
)
def test_thin_film_energy_never_exceeds_one(device, layers, angle, n_sub, k_sub, wl):
    n = [a + 1j * b for a, b, _ in layers]
    d = [c for _, _, c in layers]
    for pol in ("s", "p"):
        r = tf.reflectance(wl, n, d, 1.0, n_sub + 1j * k_sub, angle=angle, polarization=pol, device=device)
        t = tf.transmittance(wl, n, d, 1.0, n_sub + 1j * k_sub, angle=angle, polarization=pol, device=device)
        assert np.isfinite(r) and np.isfinite(t)
        assert -1e-6 <= r <= 1 + 1e-5 and t >= -1e-6
        assert r + t <= 1 + 1e-4
        if all(b == 0 for b, *_ in [(x[1],) for x in layers]) and k_sub == 0:
            assert r + t == pytest.approx(1.0, abs=1e-4)


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


# ---- determinism through the command line ---------------------------------------------------------


def test_cli_render_is_byte_identical_for_any_thread_count(tmp_path):
    scene = ROOT / "scenes" / "calcite.toml"
    outs = []
    for threads in ("1", "2"):
        out = tmp_path / f"t{threads}.exr"
        env = {**os.environ, "PYTHONPATH": str(ROOT), "WARPOPTICS_THREADS": threads}
        p = subprocess.run(
            [
                sys.executable,
                "-m",
                "warpoptics.cli",
                "render",
                str(scene),
                "-o",
                str(out),
                "--width",
                "12",
                "--height",
                "10",
                "--quiet",
                "--set",
                "render.wavelengths=4",
            ],
            capture_output=True,
            text=True,
            env=env,
            timeout=300,
        )
        assert p.returncode == 0, p.stderr
        outs.append(out.read_bytes())
    assert outs[0] == outs[1]
    px, names = read_image(tmp_path / "t1.exr")
    assert "S3" in names and np.isfinite(px).all() and px[..., names.index("Y")].max() > 0


# ---- atomic writers -------------------------------------------------------------------------------


def test_writers_are_atomic(tmp_path, monkeypatch):
    """A writer that fails midway leaves the old file untouched and no temporary file behind."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from warpoptics.geometry import cuts, gemcad
    from warpoptics.image import save_figure

    dest = tmp_path / "plot.png"
    dest.write_bytes(b"old")
    fig = plt.figure()

    def boom(*a, **k):
        raise RuntimeError("disk full")

    monkeypatch.setattr(fig, "savefig", boom)
    with pytest.raises(RuntimeError):
        save_figure(fig, dest)
    plt.close(fig)
    assert dest.read_bytes() == b"old" and sorted(p.name for p in tmp_path.iterdir()) == ["plot.png"]

    asc = tmp_path / "stone.asc"
    gemcad.write(cuts.round_brilliant(), asc)
    assert asc.read_bytes().startswith(b"GemCad") or asc.stat().st_size > 100
    assert sorted(p.name for p in tmp_path.iterdir()) == ["plot.png", "stone.asc"]


def test_no_writer_bypasses_atomic_path():
    """Source scan: every savefig / mesh export / open(..., 'w') in the package and scripts goes
    through ``atomic_path`` or ``save_figure`` (a new writer must too)."""
    import re

    offenders = []
    files = list((ROOT / "warpoptics").rglob("*.py")) + list((ROOT / "scripts").rglob("*.py"))
    for f in files:
        text = f.read_text(encoding="utf-8")
        for i, line in enumerate(text.splitlines(), 1):
            s = line.strip()
            if s.startswith("#"):
                continue
            writes = (
                re.search(r"\.savefig\(", s)
                or re.search(r"\.export\(", s)
                or re.search(r"np\.save(txt)?\(", s)
                or re.search(r"open\([^)]*['\"][wa]b?['\"]", s)
                or re.search(r"\.write_(text|bytes)\(", s)
            )
            # "not-a-replace:" marks the two intended non-atomic writes (an append-only journal
            # with fsync per row, a lock file); anything else must go through a temporary file
            if writes and "tmp" not in s and "not-a-replace:" not in s:
                offenders.append(f"{f.relative_to(ROOT)}:{i}: {s}")
    assert not offenders, "\n".join(offenders)

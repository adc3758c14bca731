"""Bad mesh and GemCAD files, bad materials and bad environment maps are refused with a clear
InputError naming the file, the field and the value."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh
from _helpers import FILE, assert_clear_scene_error, mod

from warpoptics.errors import InputError
from warpoptics.film.image import write_exr
from warpoptics.pipelines.render import Renderer
from warpoptics.scene import Scene


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
    (
        "mesh",
        "mesh without path",
        lambda d: mod(object__0={"shape": "mesh"}),
        "needs path",
        "object.0.path",
        None,
    ),
    (
        "mesh",
        "mesh file missing",
        lambda d: mod(object__0=_mesh("nope.ply")),
        "file not found",
        "object.0.path",
        "'nope.ply'",
    ),
    (
        "mesh",
        "not watertight",
        lambda d: mod(object__0=_mesh(str(d / "open.ply"))),
        "not watertight",
        "open.ply",
        None,
    ),
    (
        "mesh",
        "inverted",
        lambda d: mod(object__0=_mesh(str(d / "inverted.ply"))),
        "inverted",
        "inverted.ply",
        None,
    ),
    (
        "mesh",
        "absurd scale (km)",
        lambda d: mod(object__0=_mesh(str(d / "huge.ply"))),
        "object size .* out of range",
        "huge.ply",
        None,
    ),
    (
        "mesh",
        "absurd scale (nm)",
        lambda d: mod(object__0=_mesh(str(d / "tiny.ply"))),
        "object size .* out of range",
        "tiny.ply",
        None,
    ),
    (
        "mesh",
        "not a mesh file",
        lambda d: mod(object__0=_mesh(str(d / "garbage.ply"))),
        "cannot read mesh",
        "garbage.ply",
        None,
    ),
    (
        "mesh",
        "degenerate faces",
        lambda d: mod(object__0=_mesh(str(d / "degenerate.obj"))),
        "degenerate",
        "degenerate.obj",
        None,
    ),
    (
        "mesh",
        "repair not boolean",
        lambda d: mod(object__0={**_mesh(str(d / "open.ply")), "repair": "yes"}),
        "must be a number",
        "object.0.repair",
        "'yes'",
    ),
    (
        "mesh",
        "gemcad file missing",
        lambda d: mod(object__0={"shape": "gemcad", "path": "nope.asc"}),
        "file not found",
        "object.0.path",
        "'nope.asc'",
    ),
    (
        "mesh",
        "gemcad garbage",
        lambda d: mod(object__0={"shape": "gemcad", "path": str(d / "garbage.asc")}),
        "not a GemCAD .asc file",
        "garbage.asc",
        None,
    ),
    (
        "material",
        "unknown name",
        lambda d: mod(object__0__material="diamnod"),
        "did you mean 'diamond'",
        "object.0.material",
        "'diamnod'",
    ),
    ("material", "number", lambda d: mod(object__0__material=5), "material name", "object.0.material", "5"),
    (
        "material",
        "cauchy n < 1",
        lambda d: mod(object__0__material={"cauchy": [0.5]}),
        ">= 1",
        "object.0.material.cauchy",
        "[0.5]",
    ),
    (
        "material",
        "cauchy n < 1 in range",
        lambda d: mod(object__0__material={"cauchy": [1.2, -1e6]}),
        "below 1 at",
        "object.0.material.n",
        None,
    ),
    (
        "material",
        "cauchy n = 1e30",
        lambda d: mod(object__0__material={"cauchy": [1e30]}),
        "absurdly large",
        "object.0.material.n",
        None,
    ),
    (
        "material",
        "cauchy empty",
        lambda d: mod(object__0__material={"cauchy": []}),
        "list of numbers",
        "object.0.material.cauchy",
        "[]",
    ),
    (
        "material",
        "cauchy string",
        lambda d: mod(object__0__material={"cauchy": ["a"]}),
        "list of numbers",
        "object.0.material.cauchy",
        "['a']",
    ),
    (
        "material",
        "inline key typo",
        lambda d: mod(object__0__material={"cauchy": [1.5], "colr": 1}),
        "unknown key",
        "object.0.material.colr",
        None,
    ),
    (
        "material",
        "base and cauchy",
        lambda d: mod(object__0__material={"cauchy": [1.5], "base": "diamond"}),
        "exactly one",
        "object.0.material",
        None,
    ),
    (
        "material",
        "negative band",
        lambda d: mod(
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
        lambda d: mod(
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
        lambda d: mod(
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
        lambda d: mod(object__0__material={"base": "diamond", "bands": [{"center_nm": 500}]}),
        "missing key",
        "object.0.material.bands.0.width_nm",
        None,
    ),
    (
        "material",
        "negative absorption_rgb",
        lambda d: mod(object__0__material={"base": "diamond", "absorption_rgb": [-1, 0, 0]}),
        "negative absorption",
        "object.0.material",
        "-1",
    ),
    (
        "material",
        "zero optic axis (inline)",
        lambda d: mod(object__0__material={"base": "calcite", "optic_axis": [0, 0, 0]}),
        "non-zero",
        "object.0.material.optic_axis",
        "[0, 0, 0]",
    ),
    (
        "material",
        "zero optic axis (object)",
        lambda d: mod(object__0__material="calcite", object__0__optic_axis=[0.0, 0.0, 0.0]),
        "must not be zero",
        "object.0.optic_axis",
        None,
    ),
    (
        "material",
        "optic axis on isotropic",
        lambda d: mod(object__0__optic_axis=[0.0, 0.0, 1.0]),
        "uniaxial",
        "object.0.optic_axis",
        None,
    ),
    (
        "env",
        "unknown map",
        lambda d: mod(light__0__map="stuido"),
        "unknown environment map",
        "light",
        "'stuido'",
    ),
    (
        "env",
        "map file missing",
        lambda d: mod(light__0__map=str(d / "none.exr")),
        "not found",
        "light",
        "none.exr",
    ),
    (
        "env",
        "map unreadable",
        lambda d: mod(light__0__map=str(d / "notimage.exr")),
        "unreadable",
        "light",
        "notimage.exr",
    ),
    (
        "env",
        "map not 2:1",
        lambda d: mod(light__0__map=str(d / "square.exr")),
        "twice as wide",
        "light",
        "square.exr",
    ),
    (
        "env",
        "map negative",
        lambda d: mod(light__0__map=str(d / "negative.exr")),
        "negative",
        "light",
        "negative.exr",
    ),
    ("env", "map NaN", lambda d: mod(light__0__map=str(d / "nan.exr")), "non-finite", "light", "nan.exr"),
]


@pytest.mark.parametrize(
    ("category", "case", "make", "match", "field", "value"),
    BAD_SCENES,
    ids=[f"{c[0]}-{c[1]}" for c in BAD_SCENES],
)
def test_bad_scene_input_is_a_clear_input_error(bad_files, category, case, make, match, field, value):
    data = make(bad_files)
    assert_clear_scene_error(data, match, field, value)


def test_gemcad_object_in_a_scene(tmp_path):
    """A GemCAD design written by ``warpoptics cut`` loads as a scene object (it used to fail with
    an ImportError)."""
    from warpoptics.geometry import cuts, gemcad

    asc = tmp_path / "rb.asc"
    gemcad.write(cuts.round_brilliant(), asc)
    data = mod(object__0={"shape": "gemcad", "path": str(asc), "diameter": 6.5})
    from warpoptics.pipelines.objects import build_objects

    scene = Scene.from_dict(data, path=FILE)
    Renderer(scene)
    ((mesh, _),) = build_objects(scene.objects, file=FILE).meshes
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

"""Mesh loading and validation: every defect is built by hand and must give its InputError;
repair must fix what it claims to fix."""

import numpy as np
import pytest
import trimesh

from warpoptics.errors import InputError
from warpoptics.geometry import cuts
from warpoptics.geometry.mesh import facet_planes, load_mesh, validate_mesh


def box():
    return trimesh.creation.box(extents=(2.0, 3.0, 4.0))


@pytest.mark.parametrize("ext", ["stl", "obj", "ply", "glb", "off"])
def test_load_formats(tmp_path, ext):
    path = tmp_path / f"gem.{ext}"
    gem = cuts.round_brilliant(6.5)
    gem.export(path)
    m = load_mesh(path)
    assert m.is_watertight and m.volume == pytest.approx(gem.volume, rel=1e-6)
    planes, face_facet = facet_planes(m)  # recomputed from the triangles: the 73 facets
    assert len(planes) == 73 and len(face_facet) == len(m.faces)


def test_facet_planes_of_a_box():
    m = box()
    planes, face_facet = facet_planes(m)
    assert len(planes) == 6
    assert np.all(np.bincount(face_facet) == 2)
    expect = {
        (1, 0, 0, 1.0),
        (-1, 0, 0, 1.0),
        (0, 1, 0, 1.5),
        (0, -1, 0, 1.5),
        (0, 0, 1, 2.0),
        (0, 0, -1, 2.0),
    }
    assert {tuple(np.round(p, 9) + 0.0) for p in planes} == expect


def test_not_watertight_and_repair():
    m = box()
    m.update_faces(np.arange(len(m.faces)) != 0)  # a hole
    with pytest.raises(InputError, match="not watertight"):
        validate_mesh(m, name="holey.stl")
    fixed = validate_mesh(m, repair=True)
    assert fixed.is_watertight and fixed.volume == pytest.approx(24.0)


def test_inconsistent_winding_and_repair():
    m = box()
    faces = m.faces.copy()
    faces[3] = faces[3][::-1]
    bad = trimesh.Trimesh(m.vertices, faces, process=False)
    with pytest.raises(InputError, match="winding"):
        validate_mesh(bad)
    fixed = validate_mesh(bad, repair=True)
    assert fixed.is_winding_consistent and fixed.volume == pytest.approx(24.0)


def test_inverted_and_repair():
    m = box()
    bad = trimesh.Trimesh(m.vertices, m.faces[:, ::-1], process=False)
    with pytest.raises(InputError, match="inverted"):
        validate_mesh(bad)
    fixed = validate_mesh(bad, repair=True)
    assert fixed.volume == pytest.approx(24.0)


def test_degenerate_faces_and_repair():
    m = box()
    v = np.vstack([m.vertices, m.vertices[0]])  # a duplicate of vertex 0
    faces = np.vstack([m.faces, [[0, len(v) - 1, 1]]])  # zero area: two coincident corners
    bad = trimesh.Trimesh(v, faces, process=False)
    with pytest.raises(InputError, match="degenerate"):
        validate_mesh(bad)
    fixed = validate_mesh(bad, repair=True)
    assert fixed.is_watertight and len(fixed.faces) == 12


@pytest.mark.parametrize("factor", [1e-5, 1e6])
def test_absurd_scale(tmp_path, factor):
    m = box()
    m.apply_scale(factor)
    path = tmp_path / "scaled.stl"
    m.export(path)
    with pytest.raises(InputError, match="scale") as err:
        load_mesh(path)
    assert "scaled.stl" in str(err.value)
    ok = load_mesh(path, scale=1.0 / factor)
    assert ok.extents == pytest.approx([2.0, 3.0, 4.0], rel=1e-5)


def test_file_errors(tmp_path):
    with pytest.raises(InputError, match="unsupported"):
        load_mesh(tmp_path / "x.xyz")
    with pytest.raises(InputError, match="no such file"):
        load_mesh(tmp_path / "missing.stl")
    bad = tmp_path / "junk.stl"
    bad.write_bytes(b"solid junk\nthis is not an stl\n")
    with pytest.raises(InputError):
        load_mesh(bad)


def test_facet_planes_of_a_real_design_loaded_from_a_file(tmp_path):
    # facets are found by plane: reloaded from a PLY (float32, no metadata) a real design has the
    # facets it was built with, the convex fast path stays available
    from pathlib import Path

    from warpoptics.geometry import gemcad

    gem = gemcad.read(Path(__file__).parent / "data" / "gemcad" / "forfun.asc", diameter=6.5)
    gem.export(tmp_path / "g.ply")
    m = load_mesh(tmp_path / "g.ply")
    planes, _ = facet_planes(m)
    assert len(planes) == len(gem.metadata["planes"]) == 56
    assert m.is_convex

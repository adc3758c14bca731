"""GemCAD .asc: round trip of a brilliant, hand-made designs checked against hand geometry,
encoding and parsing details, errors."""

import math

import numpy as np
import pytest
from scipy.spatial.distance import cdist

from warpoptics.errors import InputError
from warpoptics.geometry import cuts, gemcad


def test_brilliant_round_trip_same_planes(tmp_path):
    # 64 girdle facets put facets on fractional gear indices (1.5 teeth apart)
    mesh = cuts.round_brilliant(6.5, culet=0.02, girdle=0.03, girdle_facets=64)
    path = tmp_path / "brilliant.asc"
    gemcad.write(mesh, path, title="Tolkowsky brilliant 34.5\u00b0/40.75\u00b0")
    raw = path.read_bytes()
    assert raw.startswith(b"GemCad 5.0\r\n") and b"\r\n" in raw and b"\n" not in raw.replace(b"\r\n", b"")
    assert b"\xb0" in raw  # the degree sign in Windows-1252
    design = gemcad.read_design(path)
    assert design.gear == 96 and design.symmetry == 8 and design.mirror
    assert design.headers[0] == "Tolkowsky brilliant 34.5\u00b0/40.75\u00b0"
    back = gemcad.read(path, diameter=6.5)
    p1, p2 = mesh.metadata["planes"], back.metadata["planes"]
    assert len(p1) == len(p2) == 58 + 64
    # every plane read back matches one written, and vice versa: 6-decimal angles (1.7e-8 rad)
    # and 8-decimal distances relative to the girdle radius
    dist = cdist(p1, p2)
    assert dist.min(axis=1).max() < 1e-6 and dist.min(axis=0).max() < 1e-6
    np.testing.assert_allclose(back.volume, mesh.volume, rtol=1e-6)
    prop = back.metadata["proportions"]
    ref = cuts.measure_proportions(mesh)
    for k in ("crown_height", "pavilion_depth", "total_depth", "table", "girdle"):
        assert getattr(prop, k) == pytest.approx(getattr(ref, k), abs=1e-6), k


def test_brilliant_round_trip_proportions(tmp_path):
    # with 16 girdle facets the measured proportions of the design are the nominal ones
    mesh = cuts.round_brilliant(1.0, pavilion_angle=41.0)
    gemcad.write(mesh, tmp_path / "b.asc")
    back = gemcad.read(tmp_path / "b.asc", diameter=1.0)
    prop, ref = back.metadata["proportions"], mesh.metadata["proportions"]
    for k in ("crown_height", "pavilion_depth", "total_depth", "table", "girdle"):
        assert getattr(prop, k) == pytest.approx(getattr(ref, k), abs=1e-6), k


def _design(*tiers):
    return "\r\n".join(["GemCad 5.0", "g 96 0.0", "y 4 y", "I 1.54", "H hand-made", *tiers, ""])


def test_hand_made_square_design(tmp_path):
    # girdle square |x|, |y| <= 1; crown and pavilion pyramids at 45 deg, mast 1; table at z = 0.5
    text = _design(
        "a -45.000000 1.0 96 24 48 72 n P",
        "a 90.000000 1.0 96 24 48 72 n G",
        "a 45.000000 1.0 96 24 48 72 n C",
        "a 0.000000 0.5 96 n T",
    )
    path = tmp_path / "square.asc"
    path.write_bytes(text.encode("cp1252"))
    mesh = gemcad.read(path, diameter=2.0)  # width 2 = design units
    s2 = math.sqrt(2)
    # by hand: pavilion apex at z = -sqrt 2; girdle from z = -(sqrt2 - 1) to sqrt2 - 1;
    # crown meets the table z = 0.5 at |x| = sqrt2 - 0.5
    np.testing.assert_allclose(mesh.bounds, [[-1, -1, -s2], [1, 1, 0.5]], atol=1e-12)
    v = mesh.vertices
    top = v[np.isclose(v[:, 2], 0.5)]
    top = top[np.linalg.norm(top[:, :2], axis=1) > 1e-9]  # not the table's centre (a fan vertex)
    np.testing.assert_allclose(np.abs(top[:, :2]), s2 - 0.5, atol=1e-12)
    # volume: pavilion pyramid below the girdle band + band + crown frustum
    h = s2 - 1
    pyramid = 4 * (s2 - h) / 3  # base 2x2 at z = -h, apex at -sqrt2
    band = 4 * 2 * h
    a, b, hf = 2.0, 2 * (s2 - 0.5), 0.5 - h  # frustum from side a at z=h to side b at z=0.5
    frustum = hf / 3 * (a * a + b * b + a * b)
    np.testing.assert_allclose(mesh.volume, pyramid + band + frustum, rtol=1e-12)
    assert len(mesh.metadata["planes"]) == 13
    # index 24 is the +x azimuth (index 96 = +y, clockwise from above)
    names = mesh.metadata["facet_names"]
    n24 = mesh.metadata["planes"][names.index("G @24"), :3]
    np.testing.assert_allclose(n24, [1, 0, 0], atol=1e-12)


def test_hand_made_triangle_design_measured_angles(tmp_path):
    # a trilliant-like stone: 3-fold, girdle triangle, two pavilion tiers and a crown tier
    text = _design(
        "a -43.0 0.8 96 32 64 n P1",
        "a -60.0 0.95 16 48 80 n P2",
        "a 90 1.0 96 32 64 n G",
        "a 30.0 0.75 96 32 64 n C",
        "a 0 0.4 96 n T",
    )
    path = tmp_path / "tri.asc"
    path.write_bytes(text.encode("cp1252"))
    mesh = gemcad.read(path, diameter=5.0)
    assert mesh.is_watertight and mesh.is_convex and mesh.volume > 0
    n = np.unique(np.round(mesh.face_normals, 9), axis=0)
    tilt = np.round(np.degrees(np.arccos(np.abs(n[:, 2]))), 6)
    assert sorted(set(tilt[n[:, 2] < -1e-9])) == [43.0, 60.0]
    assert sorted(set(tilt[n[:, 2] > 1e-9])) == [0.0, 30.0]
    assert np.sum(np.abs(n[:, 2]) < 1e-9) == 3
    assert min(mesh.extents[:2]) == pytest.approx(5.0)


def test_parser_details(tmp_path):
    text = "\r\n".join(
        [
            "GemCad 5.0",
            "g96 0.0",
            "y 8 y",
            "I 2.417",
            "H Round \xb0 test",
            "H second line",
            "a -40.75 0.65 96 n P1 12 24 36",
            "48 60 72 84 G Cut to center",
            "point",
            "a 90 1 3 9 15 21 27 33 39 45",
            "51 57 63 69 75 81 87 93 n G",
            "a 34.5 0.6 96 12 24 36 48 60 72 84 n C1",
            "a 0.000000 -0.02 96 n Cu",
            "a 0 0.36 96 n T",
            "F a footnote",
            "",
        ]
    )
    path = tmp_path / "d.asc"
    path.write_bytes(text.encode("cp1252"))
    d = gemcad.read_design(path)
    assert d.gear == 96 and d.symmetry == 8 and d.refractive_index == pytest.approx(2.417)
    assert d.headers == ["Round \xb0 test", "second line"] and d.footnotes == ["a footnote"]
    t0 = d.tiers[0]
    assert t0.angle == -40.75 and t0.indices == [96, 12, 24, 36, 48, 60, 72, 84]
    assert t0.names == {0: "P1"} and t0.instruction == "Cut to center point"
    assert len(d.tiers[1].indices) == 16 and d.tiers[1].names == {15: "G"}
    assert d.tiers[3].is_culet and d.tiers[4].is_table
    mesh = gemcad.design_to_mesh(d, 1.0)
    assert mesh.is_watertight and np.isclose(mesh.extents[0], 1.0)
    # writer -> reader keeps tiers
    d2 = gemcad.parse(gemcad.dumps(d))
    assert [(t.angle, t.distance, t.indices) for t in d2.tiers] == [
        (t.angle, t.distance, t.indices) for t in d.tiers
    ]


@pytest.mark.parametrize(
    "text,match",
    [
        ("hello\r\n", "not a GemCAD"),
        ("GemCad 5.0\r\ng 96 0\r\n", "no facet tiers"),
        ("GemCad 5.0\r\ng 96 0\r\na 45 1.0 96 24 48 72\r\na 0 0.5 96\r\n", "bounded"),
        ("GemCad 5.0\r\ng 96 0\r\na 45 x 96\r\n", "distance"),
        ("GemCad 5.0\r\ng 0 0\r\n", "gear"),
        ("GemCad 5.0\r\na 120 1 3\r\n", "angle"),
    ],
)
def test_bad_designs(tmp_path, text, match):
    path = tmp_path / "bad.asc"
    path.write_bytes(text.encode("cp1252"))
    with pytest.raises(InputError, match=match) as err:
        gemcad.read(path)
    assert "bad.asc" in str(err.value)


@pytest.mark.parametrize("name", ["oval", "pear", "marquise", "emerald", "princess", "prism"])
def test_round_trip_other_shapes(tmp_path, name):
    # fancy brilliants put facets on fractional gear indices; step cuts and prisms on whole ones
    mesh = cuts.SHAPES[name]()
    gemcad.write(mesh, tmp_path / "x.asc")
    back = gemcad.read(tmp_path / "x.asc", diameter=float(min(mesh.extents[:2])))
    dist = cdist(mesh.metadata["planes"], back.metadata["planes"])
    assert len(back.metadata["planes"]) == len(mesh.metadata["planes"])
    assert dist.min(axis=1).max() < 1e-6 and dist.min(axis=0).max() < 1e-6
    assert back.volume == pytest.approx(mesh.volume, rel=1e-6)

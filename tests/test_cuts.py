"""Gem cuts: facet angles, counts and proportions measured on the generated meshes.

Everything is measured from the mesh geometry (face normals, vertex positions), not read back
from the metadata the generator writes, and compared with the requested parameters and with
published values (Tolkowsky 1919: crown height 16.2 %, pavilion depth 43.1 %).  The meshes are
float64, so angle tolerances of 1e-7 deg only allow round-off.
"""

import math
import os
import subprocess
import sys

import numpy as np
import pytest
import trimesh

import warpoptics as wo
from warpoptics.errors import InputError
from warpoptics.geometry import cuts

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def facet_normals(mesh):
    """Distinct face normals (one per planar facet), from the triangles alone."""
    n = np.round(mesh.face_normals, 9)
    return np.unique(n, axis=0)


def azimuth_deg(n):
    return np.degrees(np.arctan2(n[..., 1], n[..., 0])) % 360.0


def tilt_deg(n):
    """Angle between the facet and the girdle plane (= between its normal and the z axis)."""
    return np.degrees(np.arccos(np.clip(np.abs(n[..., 2]), 0, 1)))


def check_closed_convex(mesh):
    assert mesh.is_watertight
    assert mesh.is_winding_consistent
    assert mesh.volume > 0  # outward normals
    # convexity from the triangles: every vertex on the inner side of every face plane
    v = mesh.vertices
    scale = np.max(mesh.extents)
    s = (
        np.einsum("fk,vk->fv", mesh.face_normals, v)
        - np.einsum("fk,fk->f", mesh.face_normals, mesh.triangles[:, 0])[:, None]
    )
    assert s.max() < 1e-9 * scale
    # no degenerate triangles
    assert mesh.area_faces.min() > 1e-12 * scale**2


@pytest.mark.parametrize("name", sorted(cuts.SHAPES))
def test_every_shape_closed_convex_outward(name):
    mesh = cuts.SHAPES[name]()
    check_closed_convex(mesh)
    assert mesh.is_convex
    planes = mesh.metadata["planes"]
    ff = mesh.metadata["face_facet"]
    # the recorded facet planes are the planes of their triangles
    np.testing.assert_allclose(planes[ff, :3], mesh.face_normals, atol=1e-9)
    np.testing.assert_allclose(
        planes[ff, 3],
        np.einsum("ij,ij->i", mesh.face_normals, mesh.triangles_center),
        atol=1e-9 * np.max(mesh.extents),
    )


def brilliant_facets(mesh):
    n = facet_normals(mesh)
    horiz = np.hypot(n[:, 0], n[:, 1])
    az = azimuth_deg(n)
    return n, horiz, az


@pytest.mark.parametrize(
    "params",
    [
        {},  # Tolkowsky
        {"pavilion_angle": 41.0, "crown_angle": 33.0, "table": 0.57},
        {
            "pavilion_angle": 42.5,
            "crown_angle": 36.0,
            "table": 0.60,
            "star_length": 0.45,
            "lower_girdle_length": 0.8,
            "girdle": 0.035,
            "culet": 0.015,
            "girdle_facets": 64,
        },
    ],
)
def test_brilliant_angles_and_proportions(params):
    D = 6.5
    p = dict(
        table=0.53,
        crown_angle=34.5,
        pavilion_angle=40.75,
        star_length=0.5,
        lower_girdle_length=0.75,
        girdle=0.02,
        culet=0.0,
        girdle_facets=16,
    )
    p.update(params)
    mesh = cuts.round_brilliant(D, **p)
    check_closed_convex(mesh)
    n, horiz, az = brilliant_facets(mesh)
    crown = (n[:, 2] > 1e-9) & (horiz > 1e-9)
    pav = (n[:, 2] < -1e-9) & (horiz > 1e-9)
    on45 = np.isclose((az + 1e-9) % 45.0, 0.0, atol=1e-6)
    on225 = np.isclose(az % 45.0, 22.5, atol=1e-6)
    # bezels and pavilion mains: the facets whose normals point along the 8 main azimuths
    np.testing.assert_allclose(tilt_deg(n[crown & on45]), p["crown_angle"], atol=1e-7)
    np.testing.assert_allclose(tilt_deg(n[pav & on45]), p["pavilion_angle"], atol=1e-7)
    assert (crown & on45).sum() == 8 and (pav & on45).sum() == 8
    # 57 facets + culet + vertical girdle facets
    vertical = np.abs(n[:, 2]) < 1e-9
    n_expected = 57 + (p["culet"] > 0)
    assert len(n) - vertical.sum() == n_expected
    assert vertical.sum() == (p["girdle_facets"] if p["girdle"] > 0 else 0)
    assert (crown & on225).sum() == 8  # stars
    assert crown.sum() == 8 + 8 + 16 and pav.sum() == 8 + 16

    # proportions from vertices; girdle points: the 16 vertices at the girdle radius, |z| = girdle/2
    v = mesh.vertices
    r = np.hypot(v[:, 0], v[:, 1])
    R = D / 2
    g_pts = v[r > R * (1 - 1e-9)]
    assert r.max() <= R * (1 + 1e-12)
    g_top, g_bot = g_pts[:, 2].max(), g_pts[:, 2].min()
    zmax, zmin = v[:, 2].max(), v[:, 2].min()
    np.testing.assert_allclose(g_top, -g_bot, atol=1e-12)  # girdle centred on z = 0
    np.testing.assert_allclose((g_top - g_bot) / D, p["girdle"], atol=1e-12)
    table_v = v[np.isclose(v[:, 2], zmax, atol=1e-12)]
    table = np.ptp(table_v[:, 0]) / D  # corner to corner (corners on the x axis)
    np.testing.assert_allclose(table, p["table"], atol=1e-12)
    crown_h = (zmax - g_top) / D
    # crown height = (1 - table)/2 tan(crown angle)  (GIA; Tolkowsky's profile)
    np.testing.assert_allclose(
        crown_h, (1 - p["table"]) / 2 * math.tan(math.radians(p["crown_angle"])), rtol=1e-12
    )
    pav_d = (g_bot - zmin) / D
    culet_drop = p["culet"] / 2 * math.tan(math.radians(p["pavilion_angle"]))
    np.testing.assert_allclose(
        pav_d, 0.5 * math.tan(math.radians(p["pavilion_angle"])) - culet_drop, rtol=1e-12
    )
    reported = mesh.metadata["proportions"]
    np.testing.assert_allclose(
        [
            reported.crown_height,
            reported.pavilion_depth,
            reported.total_depth,
            reported.table,
            reported.girdle,
        ],
        [crown_h, pav_d, (zmax - zmin) / D, table, p["girdle"]],
        atol=1e-12,
    )
    # star length: radial reach of the stars from the table edge, towards the girdle
    star = np.flatnonzero(np.isin(np.round(mesh.face_normals, 9), n[crown & on225]).all(axis=1))
    rs = r[np.unique(mesh.faces[star])].max()
    rt_edge = p["table"] * R * math.cos(math.radians(22.5))
    np.testing.assert_allclose((rs - rt_edge) / (R - rt_edge), p["star_length"], atol=1e-9)
    # lower girdle length: radial reach of the lower girdle facets from the girdle
    lg_normals = n[pav & ~on45]
    lg = np.flatnonzero(np.isin(np.round(mesh.face_normals, 9), lg_normals).all(axis=1))
    rl = r[np.unique(mesh.faces[lg])].min()
    np.testing.assert_allclose(1 - rl / R, p["lower_girdle_length"], atol=1e-9)
    if p["culet"] > 0:
        bottom = v[np.isclose(v[:, 2], zmin, atol=1e-12)]
        np.testing.assert_allclose(np.ptp(bottom[:, 0]) / D, p["culet"], atol=1e-9)


def test_tolkowsky_published_proportions():
    prop = cuts.round_brilliant(girdle=0.0).metadata["proportions"]
    assert abs(100 * prop.crown_height - 16.2) < 0.05
    assert abs(100 * prop.pavilion_depth - 43.1) < 0.05
    assert abs(100 * prop.total_depth - 59.3) < 0.1  # 16.2 + 43.1, each rounded to 0.05
    mesh = cuts.round_brilliant(girdle=0.0)
    assert len(facet_normals(mesh)) == 57  # knife-edge girdle: exactly the 57 facets


@pytest.mark.parametrize(
    "fn,length,width", [(cuts.oval, 8.0, 6.0), (cuts.pear, 9.0, 6.0), (cuts.marquise, 12.0, 6.0)]
)
def test_fancy_brilliants(fn, length, width):
    mesh = fn(length, width)
    check_closed_convex(mesh)
    ext = mesh.extents
    np.testing.assert_allclose(ext[:2], [length, width], rtol=1e-9)
    n = facet_normals(mesh)
    assert len(n) == 57 + 16  # the brilliant's facets survive the stretch, + 16 girdle facets
    # where the outline is symmetric and round to first order (across the width of ovals and
    # marquises, the round end of a pear) the bezel and pavilion main keep the requested angles
    if fn is cuts.pear:
        up = n[(np.abs(n[:, 1]) < 1e-9) & (n[:, 0] < 0)]
    else:
        up = n[(np.abs(n[:, 0]) < 1e-9) & (n[:, 1] > 0)]
    np.testing.assert_allclose(sorted(tilt_deg(up)), [34.5, 40.75], atol=1e-7)
    prop = mesh.metadata["proportions"]
    assert prop.width == pytest.approx(width) and prop.length == pytest.approx(length)


def test_step_cuts():
    crown, pav = (45.0, 30.0), (50.0, 43.0, 38.0)
    mesh = cuts.emerald(
        8.0, 6.0, corner=0.15, table=0.6, crown_angles=crown, pavilion_angles=pav, girdle=0.02
    )
    check_closed_convex(mesh)
    n = facet_normals(mesh)
    tilts = np.round(tilt_deg(n), 6)
    crown_t = sorted(set(tilts[(n[:, 2] > 1e-9) & (tilts > 0)]))
    pav_t = sorted(set(tilts[n[:, 2] < -1e-9]))
    assert crown_t == sorted(crown) and pav_t == sorted(pav)
    np.testing.assert_allclose(mesh.extents[:2], [8.0, 6.0], rtol=1e-12)
    v = mesh.vertices
    top = v[np.isclose(v[:, 2], v[:, 2].max())]
    np.testing.assert_allclose(np.ptp(top[:, 1]) / 6.0, 0.6, atol=1e-12)
    # crown height: two equal insets of (1 - 0.6)/2/2 width at 45 and 30 deg
    expect = 0.1 * (math.tan(math.radians(45)) + math.tan(math.radians(30)))
    np.testing.assert_allclose(mesh.metadata["proportions"].crown_height, expect, rtol=1e-12)
    np.testing.assert_allclose((v[:, 2].max() - 0.06) / 6.0, expect, rtol=1e-9)
    pr = cuts.princess(5.0)
    check_closed_convex(pr)
    np.testing.assert_allclose(pr.extents[:2], [5.0, 5.0], rtol=1e-12)
    with pytest.raises(InputError, match="decrease"):
        cuts.emerald(crown_angles=(30.0, 45.0))


def test_prism_plate_cube_sphere_ground():
    pr = cuts.prism(apex_angle=60.0, size=10.0, length=20.0)
    names = pr.metadata["facet_names"]
    planes = pr.metadata["planes"]
    a, b = planes[names.index("face +x"), :3], planes[names.index("face -x"), :3]
    apex = 180.0 - math.degrees(math.acos(np.dot(a, b)))
    assert apex == pytest.approx(60.0, abs=1e-9)
    np.testing.assert_allclose(pr.extents, [10.0, 20.0, 10.0 * math.cos(math.radians(30))], rtol=1e-12)
    np.testing.assert_allclose(pr.volume, 0.5 * 10 * 10 * math.sin(math.radians(60)) * 20, rtol=1e-12)
    assert cuts.plate(4.0, 5.0, 0.5).volume == pytest.approx(10.0)
    assert cuts.cube(2.0).volume == pytest.approx(8.0)
    sp = cuts.sphere(2.0, subdivisions=3)
    assert sp.volume == pytest.approx(4 / 3 * math.pi, rel=0.02)
    g = cuts.ground_plane(50.0, 2.0, z=-3.0)
    assert g.bounds[1][2] == pytest.approx(-3.0) and g.bounds[0][2] == pytest.approx(-5.0)


@pytest.mark.parametrize(
    "kw",
    [
        {"pavilion_angle": 80.0},
        {"table": 1.2},
        {"diameter": -1.0},
        {"girdle_facets": 20},
        {"crown_angle": float("nan")},
    ],
)
def test_bad_parameters(kw):
    with pytest.raises(InputError):
        cuts.round_brilliant(**kw)


def test_convex_from_planes_errors():
    with pytest.raises(InputError, match="do not close"):
        # an open pyramid: no base
        cuts.convex_from_planes([[1, 0, 1], [-1, 0, 1], [0, 1, 1], [0, -1, 1]], [1, 1, 1, 1])
    with pytest.raises(InputError):
        cuts.convex_from_planes(
            [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], [1, -2, 1, 1, 1, 1]
        )  # x <= 1 and x >= 2: empty


def test_wo_cuts_reexport():
    assert wo.cuts.round_brilliant is cuts.round_brilliant


def _cli(*args, cwd):
    env = dict(os.environ, PYTHONPATH=REPO)
    return subprocess.run(
        [sys.executable, "-m", "warpoptics.cli", *args],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )


def test_cli_cut(tmp_path):
    r = _cli(
        "cut", "round_brilliant", "--pavilion-angle", "41", "--diameter", "6.5", "-o", "gem.ply", cwd=tmp_path
    )
    assert r.returncode == 0, r.stderr
    assert "pavilion depth   43.5 %" in r.stdout and "crown height     16.2 %" in r.stdout
    m = trimesh.load(tmp_path / "gem.ply")
    assert m.is_watertight and m.extents[0] == pytest.approx(6.5, rel=1e-6)
    r = _cli("cut", "round_brilliant", "--culet", "0.02", "-o", "design.asc", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "design.asc").read_bytes().startswith(b"GemCad 5.0\r\n")
    r = _cli("cut", "design.asc", "--diameter", "5", "-o", "gem2.stl", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "74 facets" in r.stdout  # 58 + 16 girdle facets
    r = _cli("cut", "prism", "--crown-angle", "3", "-o", "x.ply", cwd=tmp_path)
    assert r.returncode == 2 and "not a parameter of prism" in r.stderr
    r = _cli("cut", "round_brilliant", "--pavilion-angle", "75", "-o", "x.ply", cwd=tmp_path)
    assert r.returncode == 2 and "pavilion_angle" in r.stderr

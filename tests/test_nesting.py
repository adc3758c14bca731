"""Nested solids: a stone inside water, a glass or another solid.

References the tracers are checked against, each independent of the code under test:

- an index-matched container (n = 1.0 in air) changes nothing: the bare stone's image, traced
  with the same deterministic settings (every branch split, no roulette) and the container's two
  extra interfaces added to max_depth;
- at normal incidence an incoherent stack of slabs has the closed form of the intensity
  (Stokes) recursion: per interface R = ((n1 - n2) / (n1 + n2))^2, T = 1 - R, and two elements
  combine as T = T1 T2 / (1 - R1b R2f), Rf = R1f + T1^2 R2f / (1 - R1b R2f) (Born & Wolf §1.6 for
  the interface; the multiple-reflection sum is a geometric series);
- a stone in water seen by a camera in water (ambient index 1.333, the water body index-matched
  to it) is the stone of relative index n / 1.333 in air: Fresnel amplitudes and flux ratios are
  homogeneous in the two indices, so every branch carries the same amplitude.
"""

from __future__ import annotations

import copy

import numpy as np
import pytest
import trimesh

from warpoptics.errors import InputError
from warpoptics.geometry.nesting import OverlapError, object_parents, point_medium, winding_number
from warpoptics.pipelines.bench import bench
from warpoptics.pipelines.render import Renderer
from warpoptics.scene import Scene
from warpoptics.scene.bench import BenchScene

DIAMOND = {
    "camera": {
        "position": [0.0, -22.0, 30.0],
        "look_at": [0.0, 0.0, -0.3],
        "fov": 15.0,
        "width": 16,
        "height": 16,
    },
    # deterministic trees: every branch split (the trees here have < 2^10 branches), no roulette
    "render": {
        "spectral": "stratified",
        "wavelengths": 3,
        "max_depth": 8,
        "split_threshold": 0.0,
        "rr_threshold": 0.0,
        "max_splits": 4096,
    },
    "light": [{"type": "environment", "map": "studio"}],
    "object": [{"shape": "round_brilliant", "diameter": 6.5, "material": "diamond"}],
}


def _render(data, device, **kw):
    r = Renderer(Scene.from_dict(data, path="/x.toml"), device=device, **kw)
    return r, r.run().xyz


def _stack(ns):
    """(R from the front, T) of an incoherent stack of media ``ns`` at normal incidence."""
    el = None
    for a, b in zip(ns[:-1], ns[1:], strict=True):
        r = ((a - b) / (a + b)) ** 2
        e = (r, r, 1.0 - r)
        if el is None:
            el = e
        else:
            (rf1, rb1, t1), (rf2, rb2, t2) = el, e
            den = 1.0 - rb1 * rf2
            el = (rf1 + t1 * t1 * rf2 / den, rb2 + t2 * t2 * rb1 / den, t1 * t2 / den)
    return el[0], el[2]


def test_diamond_in_index_matched_cube_is_the_bare_diamond(device):
    """A clear diamond inside an invisible n = 1.0 cube once rendered nearly black
    (stone Y 0.0098 vs 0.489), then 4.9 % darker at the same max_depth (the cube's entry and
    exit counted as two scattering events).  Now, at the same max_depth 8, the image is the bare
    stone's to float32 round-off: an index-matched crossing without a film spends no depth."""
    bare = copy.deepcopy(DIAMOND)
    nested = copy.deepcopy(DIAMOND)
    assert nested["render"]["max_depth"] == 8
    nested["object"].append({"shape": "cube", "size": 12.0, "material": {"cauchy": [1.0]}})
    r, b = _render(nested, device)
    assert list(r.geometry.geometry.parent.numpy()) == [1, -1]
    _, a = _render(bare, device, spectral_bundle=False)  # the nested scene is traced per wavelength
    y_a, y_b = a[..., 1], b[..., 1]
    assert y_a.mean() > 0.05
    # float32 round-off of the extra refractions (measured 4e-6 of Y ~ 1 at most)
    np.testing.assert_allclose(y_b, y_a, atol=1e-4 * y_a.max())


def _ortho(objects, z=20.0):
    return {
        "camera": {
            "type": "orthographic",
            "position": [0.0, 0.0, z],
            "look_at": [0.0, 0.0, 0.0],
            "up": [0.0, 1.0, 0.0],
            "view_height": 2.0,
            "width": 4,
            "height": 4,
        },
        "render": {
            "spectral": "stratified",
            "wavelengths": 2,
            "max_depth": 40,
            "split_threshold": 1.0e-9,
            "rr_threshold": 0.0,
            "max_splits": 4096,
        },
        "light": [{"type": "environment", "map": "studio"}],
        "object": objects,
    }


@pytest.mark.parametrize("n_glass", [1.5, 2.4])
def test_glass_in_water_at_normal_incidence_is_the_closed_form(device, n_glass):
    """An orthographic camera looks straight down through a water cube (n 1.333) holding a glass
    cube: every pixel is T L(down) + R L(up) with (R, T) of air|water|glass|water|air — the
    glass's interfaces are water/glass (on main they were air/glass and the glass was not even
    found from inside the water).  Non-dispersive media: one exact path tree per pixel."""
    far = {"shape": "cube", "size": 1.0, "material": {"cauchy": [1.5]}, "position": [1000.0, 0.0, 0.0]}
    water = {"shape": "cube", "size": 10.0, "material": {"cauchy": [1.333]}}
    glass = {"shape": "cube", "size": 4.0, "material": {"cauchy": [n_glass]}}
    down = _render(_ortho([far]), device)[1][..., 1].mean()  # the environment straight down
    up = _render(_ortho([far], z=-20.0), device)[1][..., 1].mean()  # and straight up
    img = _render(_ortho([water, glass]), device)[1][..., 1]
    r, t = _stack([1.0, 1.333, n_glass, 1.333, 1.0])
    # float32 amplitudes over ~40 interfaces: 1e-6 relative
    np.testing.assert_allclose(img, t * down + r * up, rtol=1e-5)
    r_w, t_w = _stack([1.0, 1.333, 1.0])
    assert abs((t * down + r * up) - (t_w * down + r_w * up)) > 1e-3 * up  # the glass shows


def test_stone_in_water_is_the_relative_index_stone_in_air(device):
    """Camera, stone and lights in water: ambient index 1.333 and a water sphere (n 1.333) around
    the camera and the stone, so the camera starts inside a solid.  The same image as the stone of
    relative index 2.4 / 1.333 in air (exact: every Fresnel amplitude depends on the ratio)."""
    water = copy.deepcopy(DIAMOND)
    water["object"][0]["material"] = {"cauchy": [2.4]}
    water["render"]["ambient_index"] = 1.333
    # the same max_depth: leaving the water sphere into water (ambient 1.333) spends no depth
    water["object"].append({"shape": "sphere", "diameter": 200.0, "material": {"cauchy": [1.333]}})
    rel = copy.deepcopy(DIAMOND)
    rel["object"][0]["material"] = {"cauchy": [2.4 / 1.333]}
    r, a = _render(water, device)
    assert r.camera_medium == 1
    _, b = _render(rel, device)
    assert b[..., 1].mean() > 0.05
    np.testing.assert_allclose(a[..., 1], b[..., 1], atol=1e-4 * b[..., 1].max())


def test_bench_beam_through_glass_in_water_is_the_closed_form(device):
    """The forward tracer (bench; the caustic tracer shares its step): a beam at normal incidence
    through a water cube holding a glass cube puts T of air|water|glass|water|air on the screen
    behind (the reflected power escapes)."""
    data = {
        "source": {
            "type": "beam",
            "position": [0.0, 0.0, 10.0],
            "direction": [0.0, 0.0, -1.0],
            "width": 0.5,
            "lines": [550.0],
            "rays": 16,
        },
        "render": {"max_depth": 40, "split_threshold": 1.0e-9, "max_deposits": 512},
        "object": [
            {"shape": "cube", "size": 10.0, "material": {"cauchy": [1.333]}},
            {"shape": "cube", "size": 4.0, "material": {"cauchy": [1.5]}},
        ],
        "sensor": [
            {
                "type": "screen",
                "center": [0.0, 0.0, -10.0],
                "normal": [0.0, 0.0, 1.0],
                "up": [0.0, 1.0, 0.0],
                "size": [20.0, 20.0],
                "resolution": [8, 8],
            }
        ],
    }
    r = bench(BenchScene.from_dict(data), device=device)
    _, t = _stack([1.0, 1.333, 1.5, 1.333, 1.0])
    assert r.ledger["screen"] == pytest.approx(t, rel=1e-5)
    assert r.ledger["screen"] + r.ledger["escaped"] == pytest.approx(1.0, abs=1e-5)


def test_bench_beam_through_an_index_matched_cube_spends_no_depth(device):
    """The forward tracer: a glass cube (n 1.5) at max_depth 2 passes T = (1 - R)^2 straight
    through (two interfaces); inside an invisible n = 1.0 cube, at the same max_depth, the same
    power reaches the screen (the container's two crossings are no scattering events)."""
    screen = {
        "type": "screen",
        "center": [0.0, 0.0, -10.0],
        "normal": [0.0, 0.0, 1.0],
        "up": [0.0, 1.0, 0.0],
        "size": [20.0, 20.0],
        "resolution": [8, 8],
    }
    data = {
        "source": {
            "type": "beam",
            "position": [0.0, 0.0, 10.0],
            "direction": [0.0, 0.0, -1.0],
            "width": 0.5,
            "lines": [550.0],
            "rays": 16,
        },
        "render": {"max_depth": 2, "split_threshold": 1.0e-9, "max_deposits": 512},
        "object": [{"shape": "cube", "size": 4.0, "material": {"cauchy": [1.5]}}],
        "sensor": [screen],
    }
    bare = bench(BenchScene.from_dict(copy.deepcopy(data)), device=device).ledger["screen"]
    data["object"].insert(0, {"shape": "cube", "size": 10.0, "material": {"cauchy": [1.0]}})
    boxed = bench(BenchScene.from_dict(data), device=device).ledger["screen"]
    _, t = _stack([1.0, 1.5, 1.0])
    t_single = (1.0 - ((1.5 - 1.0) / 2.5) ** 2) ** 2  # no multiple reflections at max_depth 2
    assert bare == pytest.approx(t_single, rel=1e-5) and t_single < t
    assert boxed == pytest.approx(bare, rel=1e-5)


def _box(size, at=(0.0, 0.0, 0.0)):
    xf = np.eye(4)
    xf[:3, 3] = at
    return (trimesh.creation.box(extents=(size, size, size)), xf)


def test_parents_of_nested_disjoint_and_instanced_solids():
    """Three levels (glass in water in a tank), a stone beside them, and 2,000 disjoint instances
    of one mesh (the sort-and-sweep finds no candidate pair among them)."""
    objs = [_box(10.0), _box(6.0), _box(2.0, (1.0, 0.0, 0.0)), _box(1.0, (20.0, 0.0, 0.0))]
    assert list(object_parents(objs)) == [-1, 0, 1, -1]
    assert point_medium(objs, object_parents(objs), (1.0, 0.0, 0.0)) == 2
    assert point_medium(objs, object_parents(objs), (4.0, 0.0, 0.0)) == 0
    assert point_medium(objs, object_parents(objs), (50.0, 0.0, 0.0)) == -1
    mesh = trimesh.creation.box(extents=(1.0, 1.0, 1.0))
    grid = [(mesh, np.eye(4)) for _ in range(2000)]
    for k, (_, xf) in enumerate(grid):
        xf[:3, 3] = (2.0 * (k % 50), 2.0 * (k // 50), 0.0)
    assert np.all(object_parents(grid) == -1)


def test_winding_number_of_a_closed_mesh():
    """1 inside, 0 outside (the solid angle of a closed surface seen from inside is 4 pi)."""
    box = trimesh.creation.box(extents=(2.0, 2.0, 2.0))
    w = winding_number(box, np.array([[0.0, 0.0, 0.0], [0.9, -0.9, 0.5], [3.0, 0.0, 0.0]]))
    np.testing.assert_allclose(w, [1.0, 1.0, 0.0], atol=1e-12)


@pytest.mark.parametrize(
    "second, message",
    [
        (
            {"shape": "cube", "size": 6.0, "position": [4.0, 0.0, 0.0]},
            "surfaces of object.0 and object.1 intersect",
        ),
        (
            {"shape": "cube", "size": 5.0, "position": [0.0, 0.0, 0.0]},
            "surfaces of object.0 and object.1 intersect",
        ),
    ],
)
def test_overlapping_solids_are_refused(second, message):
    """A stone that pokes out of a cube and a cube cutting through it: one line naming the file
    and both objects.  (Two coincident stones stay accepted: the light meets one of them,
    tests/test_physical_edge_cases.py::test_coincident_objects.)"""
    data = copy.deepcopy(DIAMOND)
    data["object"].append({"material": "diamond", **second})
    with pytest.raises(InputError, match=message) as info:
        Renderer(Scene.from_dict(data, path="/scenes/x.toml"))
    msg = str(info.value)
    assert "/scenes/x.toml" in msg and "object.0" in msg and "object.1" in msg and "\n" not in msg
    assert "nested" in msg  # says what is allowed


def test_overlap_error_carries_the_objects():
    with pytest.raises(OverlapError) as info:
        object_parents([_box(2.0), _box(2.0, (1.0, 0.5, 0.25))])
    assert (info.value.first, info.value.second) == (0, 1)


def test_a_shell_cannot_hold_a_stone():
    """A thin shell (a soap bubble) has air inside: a stone in it is refused, not traced wrong."""
    data = copy.deepcopy(DIAMOND)
    data["object"].append(
        {
            "shape": "sphere",
            "diameter": 20.0,
            "material": {"cauchy": [1.33]},
            "surface": "shell",
            "coating": [{"n": 1.33, "thickness_nm": 300.0}],
        }
    )
    with pytest.raises(InputError, match="only solids nest"):
        Renderer(Scene.from_dict(data, path="/scenes/x.toml"))


def test_box_pairs_are_the_brute_force_pairs():
    """The broad phase (a grid of the typical box size, large boxes against all) finds exactly the
    overlapping or touching pairs of random boxes, some five times the typical size."""
    from warpoptics.geometry.nesting import _box_pairs

    rng = np.random.default_rng(1)
    for _ in range(200):
        n = int(rng.integers(1, 40))
        lo = rng.uniform(0.0, 10.0, (n, 3))
        hi = lo + rng.uniform(0.1, 3.0, (n, 3)) * np.where(rng.random((n, 1)) < 0.1, 5.0, 1.0)
        got = {(int(i), int(j)) for i, j in _box_pairs(lo, hi)}
        ref = {
            (i, j) for i in range(n) for j in range(i + 1, n) if np.all((lo[i] <= hi[j]) & (lo[j] <= hi[i]))
        }
        assert got == ref


def test_stone_shadow_through_an_index_matched_cube(device):
    """Stone shadows on a table (the straight-through filter of stages/surfaces.py) cross nested
    media in turn: a stone floating over a lit table inside an invisible n = 1.0 cube casts the
    bare stone's shadow, and the table and lamp light arrive as without the cube."""
    base = {
        "camera": {
            "position": [0.0, -40.0, 30.0],
            "look_at": [0.0, 0.0, 3.0],
            "fov": 30.0,
            "width": 16,
            "height": 16,
        },
        "render": {**DIAMOND["render"], "max_depth": 6, "spp": 1, "diffuse_depth": 1},
        "light": [
            {"type": "environment", "map": "studio", "intensity": 0.2},
            {
                "type": "area",
                "center": [0.0, 0.0, 40.0],
                "normal": [0.0, 0.0, -1.0],
                "size": [6.0, 6.0],
                "radiance": 20.0,
            },
        ],
        "surface": [
            {"type": "plane", "height": 0.0, "size": 200.0, "bsdf": "diffuse", "color": [0.5, 0.5, 0.5]}
        ],
        "object": [
            {"shape": "round_brilliant", "diameter": 6.5, "material": "diamond", "position": [0.0, 0.0, 10.0]}
        ],
    }
    nested = copy.deepcopy(base)  # the same max_depth: the invisible cube spends no depth
    nested["object"].append(
        {"shape": "cube", "size": 11.0, "material": {"cauchy": [1.0]}, "position": [0.0, 0.0, 10.0]}
    )
    _, a = _render(base, device)
    _, b = _render(nested, device)
    assert a[..., 1].mean() > 0.05
    np.testing.assert_allclose(b[..., 1], a[..., 1], atol=1e-4 * a[..., 1].max())


def test_bench_source_inside_a_solid_is_refused():
    """Beam rays start in the ambient medium: a source inside a solid would be traced as if in
    air (silently wrong); it is refused with one line naming the field and the object."""
    data = {
        "source": {
            "type": "beam",
            "position": [0.0, 0.0, 1.0],
            "direction": [0.0, 0.0, -1.0],
            "lines": [550.0],
        },
        "object": [{"shape": "cube", "size": 10.0, "material": {"cauchy": [1.333]}}],
        "sensor": [
            {"type": "screen", "center": [0.0, 0.0, -10.0], "normal": [0.0, 0.0, 1.0], "size": [20.0, 20.0]}
        ],
    }
    with pytest.raises(InputError, match="inside object.0") as info:
        bench(BenchScene.from_dict(data, path="/scenes/b.toml"))
    assert "source.position" in str(info.value) and "\n" not in str(info.value)

"""Spectral bundles (stages/bundle.py): a dispersive stone traced for many wavelengths at once.

The bundle must give the same expected image as one path tree per wavelength (the estimator it
replaces), conserve energy in the white furnace, keep polarization physical, and its cheap exit
test must agree with the full exit query.  Tiny images: a few seconds in all.
"""

import numpy as np
import pytest
import warp as wp

import warpoptics as wo
from warpoptics.errors import InputError
from warpoptics.geometry.query import GeometryScene, SceneGeometry, convex_exit_near, object_exit_hit
from warpoptics.pipelines.render import Renderer
from warpoptics.stages.bundle import LANES

wp.set_module_options({"enable_backward": False})

STONE = {
    "camera": {
        "position": [0.0, -22.0, 30.0],
        "look_at": [0.0, 0.0, -0.3],
        "fov": 15.0,
        "width": 16,
        "height": 16,
    },
    "render": {
        "spectral": "stratified",
        "wavelengths": 8,
        "max_depth": 16,
        "spp": 8,
        "split_threshold": 0.05,
        "estimator": "point",  # the bundles of point samples (auto would trace this stone in beams)
    },
    "light": [{"type": "environment", "map": "studio"}],
    # the library diamond: dispersive and (Guy & Soler's 0.001/mm) absorbing, so the bundle's lanes
    # differ in index and in absorption
    "object": [
        {"shape": "round_brilliant", "diameter": 6.5, "material": "diamond", "absorption_scale": 50.0}
    ],
}


def _scene(data, **render):
    return wo.Scene.from_dict({**data, "render": {**data["render"], **render}})


def _passes(sc, seeds, device):
    out = []
    for s in seeds:
        r = Renderer(sc.with_overrides(None, seed=s), device=device)
        img = r.run()
        out.append(np.concatenate([img.xyz, img.stokes[..., 1:3]], axis=-1))
    return r, np.array(out)


@pytest.mark.parametrize("polarization", [True, False])
def test_bundle_mean_equals_separate_traces(device, polarization):
    """Mean of the new estimator (bundles) = mean of the old one (a tree per wavelength): per
    pixel and channel (X, Y, Z, S1, S2) the difference of the two means over 8 seeds each is
    compared with its standard error.  Unbiased estimators give z-scores of RMS ~1 (a bias at
    facet edges would show as |z| >> 1 there); the image means agree within 4 standard errors."""
    seeds = range(8)
    rb, b = _passes(_scene(STONE, polarization=polarization, bundle=True), seeds, device)
    rs, s = _passes(_scene(STONE, polarization=polarization, bundle=False), seeds, device)
    assert rb.spectral_bundle and not rs.spectral_bundle
    se = np.sqrt(b.var(0, ddof=1) / len(b) + s.var(0, ddof=1) / len(s))
    diff = b.mean(0) - s.mean(0)
    noisy = se > 1e-6 * np.abs(s.mean(0)).max()  # pixels with any variance (the stone)
    z = diff[noisy] / se[noisy]
    rms_z = float(np.sqrt((z**2).mean()))
    # image means: per-seed image averages are independent samples
    mb, ms = b.mean(axis=(1, 2)), s.mean(axis=(1, 2))
    z_img = (mb.mean(0) - ms.mean(0)) / np.sqrt(mb.var(0, ddof=1) / 8 + ms.var(0, ddof=1) / 8 + 1e-30)
    print(f"polarized={polarization}: rms z {rms_z:.3f} over {z.size}, image z {np.round(z_img, 2)}")
    # 8 + 8 samples: the t-distributed z has RMS ~1.2; a 1.5 bound still flags any real bias
    assert rms_z < 1.5
    assert np.all(np.abs(z_img) < 4.0)


@pytest.mark.parametrize(
    "polarization, split", [(True, None), (False, None), (True, 0.0)], ids=["pol", "scalar", "pol-split-all"]
)
def test_white_furnace_bundle(device, polarization, split):
    """Energy conservation through bundles: a clear dispersive diamond in a constant environment
    is invisible (Y with the stone / Y of the empty furnace, same wavelengths).  Each lane is an
    exact tree except where the group continues stochastically by the lanes' mean energy: that
    choice is unbiased but not energy-exact per sample (per-lane traces measured 1 +- 3e-6,
    bundles 1 +- 2.2e-4), hence 1e-3."""
    data = {
        **STONE,
        "render": {
            "spectral": "stratified",
            "wavelengths": 8,
            "max_depth": 256,
            "polarization": polarization,
            "estimator": "point",  # the bundles' own balance (beams: tests/test_pixel_beam.py)
            # split 0: every node with two children splits (the deterministic tree; stochastic
            # only where the stack is full), so energy is exact up to roulette-free truncation
            **({} if split is None else {"split_threshold": split}),
        },
        "light": [{"type": "constant", "intensity": 1.0}],
        "object": [{**STONE["object"][0], "absorption_scale": 0.0}],
    }
    sc = wo.Scene.from_dict(data)
    r = Renderer(sc, device=device)
    img = r.run()
    assert r.spectral_bundle
    empty = Renderer(sc.with_overrides({"object.0.position": [1e4, 1e4, 1e4]}), device=device).run()
    assert empty.alpha.max() == 0 and img.alpha.sum() > 40
    ratio = img.xyz[..., 1] / empty.xyz[..., 1]
    print(f"bundle furnace polarized={polarization}: {ratio.min():.6f} .. {ratio.max():.6f}")
    assert ratio.min() > 1 - 1e-3 and ratio.max() < 1 + 1e-3


def test_bundle_polarization_is_physical(device):
    """Per pixel the degree of polarization of the summed coherency is <= 1, and polarization
    appears at all (Fresnel at the facets polarizes the returned light)."""
    img = Renderer(_scene(STONE, polarization=True, spp=4), device=device).run()
    s = img.stokes
    dop = np.sqrt((s[..., 1:] ** 2).sum(-1)) / np.maximum(s[..., 0], 1e-30)
    assert dop.max() <= 1.0 + 1e-4
    assert dop[img.alpha > 0.5].max() > 0.05


@wp.kernel
def _exit_pair(
    geom: SceneGeometry,
    origins: wp.array(dtype=wp.vec3f),
    directions: wp.array(dtype=wp.vec3f),
    guess: wp.array(dtype=wp.int32),
    facet: wp.array(dtype=wp.int32),
    t_full: wp.array(dtype=wp.float32),
    ok: wp.array(dtype=wp.int32),
    t_near: wp.array(dtype=wp.float32),
    facet_near: wp.array(dtype=wp.int32),
    n_err: wp.array(dtype=wp.float32),
):
    i = wp.tid()
    h = object_exit_hit(geom, 0, origins[i], directions[i], 1.0e6)
    facet[i] = h.facet
    t_full[i] = h.t
    g = guess[i]
    if g < 0:
        g = h.facet
    hn, o = convex_exit_near(geom, 0, g, origins[i], directions[i], 1.0e6)
    ok[i] = o
    t_near[i] = hn.t
    facet_near[i] = hn.facet
    n_err[i] = wp.length(hn.normal - h.normal)


def test_convex_exit_near_agrees_with_the_exit_query(device):
    """The lanes' cheap exit (through this facet or an edge neighbour?) against the full exit
    query on 20,000 random rays inside a brilliant: from the true facet it is always found with
    the same t and normal; from a random wrong facet it is found exactly when the true facet
    neighbours the guess (the same hit), and refused otherwise (then the full query runs)."""
    mesh = wo.cuts.round_brilliant(diameter=6.5)
    scene = GeometryScene([mesh], device=device)
    rng = np.random.default_rng(3)
    planes = scene.geometry.planes.numpy()
    o = rng.uniform(-1, 1, (60000, 3)) * [3.0, 3.0, 1.5] - [0.0, 0.0, 0.8]
    o = o[(o @ planes[:, :3].T - planes[:, 3]).max(axis=1) < -0.02][:20000].astype(np.float32)  # inside
    n = len(o)
    assert n == 20000
    d = rng.normal(size=(n, 3))
    d = (d / np.linalg.norm(d, axis=1, keepdims=True)).astype(np.float32)
    nplanes = len(planes)
    args = [wp.array(o, dtype=wp.vec3f, device=device), wp.array(d, dtype=wp.vec3f, device=device)]

    def run(guess):
        types = (wp.int32, wp.float32, wp.int32, wp.float32, wp.int32, wp.float32)
        outs = [wp.zeros(n, dtype=t, device=device) for t in types]
        g = wp.array(guess.astype(np.int32), dtype=wp.int32, device=device)
        wp.launch(_exit_pair, dim=n, inputs=[scene.geometry, *args, g, *outs], device=device)
        return [a.numpy() for a in outs]

    facet, t_full, ok, t_near, facet_near, n_err = run(np.full(n, -1))
    assert (facet >= 0).all()
    assert ok.all() and (facet_near == facet).all()
    np.testing.assert_allclose(t_near, t_full, rtol=1e-5)
    assert n_err.max() < 1e-6
    # a wrong guess: found iff the true exit facet is one of the guess's edge neighbours
    start, nb = wo.geometry.mesh.facet_neighbours(mesh, wo.geometry.mesh.facet_planes(mesh)[1], nplanes)
    neighbours = [set(nb[start[f] : start[f + 1]].tolist()) for f in range(nplanes)]
    assert all(len(x) >= 3 for x in neighbours)  # every facet of a closed solid has edges
    wrong = (facet + 1 + rng.integers(0, nplanes - 1, n)) % nplanes
    _, _, ok_w, t_w, facet_w, n_err_w = run(wrong)
    adjacent = np.array([facet[i] in neighbours[wrong[i]] for i in range(n)])
    assert adjacent.sum() > 500  # the case the lanes meet at a dispersed facet edge
    assert ok_w[adjacent].mean() > 0.999
    found = ok_w == 1
    assert (facet_w[found] == facet[found]).mean() > 0.999  # others: within round-off of an edge
    np.testing.assert_allclose(t_w[found], t_full[found], rtol=1e-4)
    assert ok_w[~adjacent].mean() < 1e-3


def test_facet_neighbours_of_a_cube():
    """A cube's face touches the four faces around it, never the opposite one."""
    import trimesh

    cube = trimesh.creation.box(extents=(2.0, 2.0, 2.0))
    planes, face_facet = wo.geometry.mesh.facet_planes(cube)
    start, nb = wo.geometry.mesh.facet_neighbours(cube, face_facet, len(planes))
    assert len(planes) == 6 and np.all(np.diff(start) == 4)
    for f in range(6):
        others = planes[nb[start[f] : start[f + 1]], :3]
        assert np.allclose(others @ planes[f, :3], 0.0)  # perpendicular: not the opposite face


def test_bundle_applies_only_where_it_is_exact(device):
    base = _scene(STONE)
    assert Renderer(base, device=device).spectral_bundle
    assert not Renderer(_scene(STONE, bundle=False), device=device).spectral_bundle
    assert not Renderer(_scene(STONE, spectral="rgb3", wavelengths=3), device=device).spectral_bundle
    crystal = {**STONE, "object": [{**STONE["object"][0], "material": "calcite"}]}
    assert not Renderer(wo.Scene.from_dict(crystal), device=device).spectral_bundle  # o/e: per wavelength
    clear = {
        **STONE,
        "object": [{**STONE["object"][0], "material": {"cauchy": [2.4]}, "absorption_scale": 0.0}],
    }
    r = Renderer(wo.Scene.from_dict(clear), device=device)
    assert r.shared_spectrum and not r.spectral_bundle  # one tree for the whole spectrum instead
    # 45 wavelengths in bundles of 8: 6 bundles (pixel positions) per sample
    assert Renderer(_scene(STONE, wavelengths=45), device=device).film.groups == 6


@pytest.mark.parametrize("value", [0, LANES + 1, 2.5])
def test_bundle_lanes_validated(value):
    with pytest.raises(InputError, match="bundle_lanes"):
        _scene(STONE, bundle_lanes=value)


def test_fire_convergence_benchmark_quick():
    """The benchmark script runs (16x16, a short ladder) and prints its table."""
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    out = subprocess.run(
        [sys.executable, str(root / "scripts" / "bench" / "fire_convergence.py"), "--quick"],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=root,
    )
    assert out.returncode == 0, out.stderr
    assert "| bundle |" in out.stdout and "| separate |" in out.stdout and "| clear |" in out.stdout

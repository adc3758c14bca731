"""The optical bench (beam -> forward trace -> screens) against independent references.

References written here, not taken from the code under test: the prism's ray path by Snell's law
in NumPy (float64), the calcite walk-off angle from no, ne and the axis angle (Born & Wolf
§15.3), the thin-film reflectance from the ``tmm`` package, and energy conservation.
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import tmm

import warpoptics as wo
from warpoptics.errors import InputError
from warpoptics.pipelines.bench import Bench, bench
from warpoptics.scene.bench import BenchScene
from warpoptics.spectra import cmf

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "scenes" / "bench"
APEX_Z = 0.9396926  # apex of the 40 deg, 2 mm prism of prism.toml (bounding box centred)


def _prism(material, depth_below_apex, device, *, wavelengths=24):
    scene = BenchScene.load(SCENES / "prism.toml").with_overrides(
        {
            "object.0.material": material,
            "source.position": [-5.0, 0.0, APEX_Z - depth_below_apex],
            "source.width": 0.0,
            "source.rays": 1,
            "render.wavelengths": wavelengths,
        }
    )
    return bench(scene, device=device)


def _snell(d, normal, n1, n2):
    """Refracted unit direction (normal: unit, on the incident side)."""
    cos_i = -d @ normal
    eta = n1 / n2
    cos_t = math.sqrt(1.0 - eta**2 * (1.0 - cos_i**2))
    return eta * d + (eta * cos_i - cos_t) * normal


def _prism_spot_u(n, z0):
    """Screen coordinate u (mm) of a ray along +x at height z0 through the 40 deg prism (apex at
    (0, 0, APEX_Z), faces through the apex with outward normals (-+cos 20, 0, sin 20)) onto the
    screen x = 100 (right = -z, centre z = -30): NumPy, float64."""
    a = math.radians(20.0)
    apex = np.array([0.0, 0.0, APEX_Z])
    n_l = np.array([-math.cos(a), 0.0, math.sin(a)])
    n_r = np.array([math.cos(a), 0.0, math.sin(a)])
    o = np.array([-5.0, 0.0, z0])
    d = np.array([1.0, 0.0, 0.0])
    o = o + d * (n_l @ (apex - o)) / (n_l @ d)
    d = _snell(d, n_l, 1.0, n)
    o = o + d * (n_r @ (apex - o)) / (n_r @ d)
    d = _snell(d, -n_r, n, 1.0)
    z = o[2] + d[2] * (100.0 - o[0]) / d[0]
    return -(z + 30.0)


def _transmitted(result, min_fraction=1e-3):
    sp = result.spot_positions(0, depth=2)
    ok = sp["power"] >= min_fraction * result.weights
    return sp["wavelength"][ok], sp["u"][ok], sp


def _reversals(u):
    s = np.sign(np.diff(u))
    return int(np.count_nonzero(s[1:] != s[:-1]))


def test_prism_spots_follow_snell_and_order(device):
    """Spot positions match a NumPy Snell trace (same indices); BK7 and water keep the colour
    order, the 10 % rose bengal prism reverses it and fans out wider (Weidlich & Wilkie 2009 §4)."""
    z0 = APEX_Z - 0.007
    fans = {}
    for mat in ("bk7", "water", "rose_bengal_10"):
        r = _prism(mat, 0.007, device)
        wl, u, _ = _transmitted(r)
        assert wl.size >= 12
        n = wo.materials.get(mat).n(wl)
        ref = np.array([_prism_spot_u(float(ni), z0) for ni in n])
        # float32 geometry and indices over a 100 mm lever arm: a few um
        np.testing.assert_allclose(u, ref, atol=5e-3)
        fans[mat] = u.max() - u.min()
        if mat in ("bk7", "water"):
            assert _reversals(u) == 0 and np.all(np.diff(u) < 0)  # red deviates least
        else:
            assert _reversals(u) >= 2
        # ledger: every watt accounted for
        assert abs(r.balance()) < 1e-2
    assert fans["rose_bengal_10"] > 2.0 * fans["water"]


def test_prism_thick_edge_fades(device):
    """Moving the beam 0.5 mm below the apex swallows the dye's band (470-590 nm) but not BK7's."""
    for mat, limit in (("rose_bengal_10", 1e-2), ("bk7", None)):
        thin = _prism(mat, 0.007, device)
        thick = _prism(mat, 0.5, device)

        def band(r):
            return r.spot_positions(0, depth=2)["power"][
                (r.wavelengths >= 470) & (r.wavelengths <= 590)
            ].sum()

        if limit is None:
            assert band(thick) == pytest.approx(band(thin), rel=1e-3)
        else:
            assert band(thin) > 0.01
            assert band(thick) < limit * band(thin)


def _walkoff(no, ne, theta):
    # angle between wave normal and ray of an e-wave whose normal is at theta to the optic axis:
    # tan(theta_ray) = (no/ne)^2 tan(theta)  =>  tan(theta_ray - theta) = ... (Born & Wolf §15.3.3)
    t_ray = math.atan((no / ne) ** 2 * math.tan(theta))
    return t_ray - theta


def test_calcite_two_orthogonally_polarized_spots(device):
    scene = BenchScene.load(SCENES / "calcite.toml").with_overrides({"source.rays": 64})
    r = bench(scene, device=device)
    cal = wo.materials.get("calcite")
    no, ne = float(cal.ordinary.n(589.3)), float(cal.extraordinary.n(589.3))
    pred = 10.0 * abs(math.tan(_walkoff(no, ne, math.radians(45.0))))
    assert pred == pytest.approx(1.0921, abs=2e-3)  # the textbook ~6.2 deg walk-off of calcite
    s1, s2 = r.spots(0, count=2, radius=0.25)
    sep = math.hypot(s1["u"] - s2["u"], s1["v"] - s2["v"])
    # a monochromatic (589.3 nm) collimated beam at normal incidence splits deterministically and
    # both spots have the beam's footprint, so the centroids differ by the walk-off alone: only
    # float32 rounding of ~10 mm positions (~1e-6 mm) remains; measured -3e-7 relative with 64 rays
    assert sep == pytest.approx(pred, rel=1e-4)
    for s in (s1, s2):
        assert s["dop"] > 0.999
        assert s["power"] == pytest.approx(0.45, abs=0.02)  # half of the (1 - R)^2 transmitted
    d_angle = abs((s1["angle"] - s2["angle"] + 90.0) % 180.0 - 90.0)
    assert d_angle == pytest.approx(90.0, abs=0.1)
    # the o spot (straight through) vibrates perpendicular to the principal plane (x-z): screen y
    o_spot = min((s1, s2), key=lambda s: abs(s["u"]))
    assert abs(o_spot["u"]) < 0.05
    assert abs(abs(o_spot["angle"]) - 90.0) < 0.1
    assert abs(r.balance()) < 1e-2


@pytest.mark.parametrize("angle, bright", [(0.0, "e"), (90.0, "o")])
def test_calcite_polarized_beam_picks_one_ray(device, angle, bright):
    """Light polarized in the principal plane (beam x = -world x here) travels as the e ray only;
    perpendicular to it, as the o ray only."""
    scene = BenchScene.load(SCENES / "calcite.toml").with_overrides(
        {"source.rays": 16, "source.polarization": "linear", "source.polarization_angle": angle}
    )
    r = bench(scene, device=device)
    dp = r.deposits
    main = dp["depth"] == 2
    e_side = main & (np.abs(dp["u"] + 1.092) < 0.3)
    o_side = main & (np.abs(dp["u"]) < 0.3)
    p_e, p_o = dp["power"][e_side].sum(), dp["power"][o_side].sum()
    on, off = (p_e, p_o) if bright == "e" else (p_o, p_e)
    assert on > 0.85
    assert off < 1e-5


def test_energy_ledger_diamond(device):
    """Power on screens + absorbed + escaped = emitted within 1 %, and the full ledger closes."""
    scene = BenchScene.load(SCENES / "diamond_fire.toml").with_overrides(
        {"source.rays": 128, "render.wavelengths": 4}
    )
    r = bench(scene, device=device)
    lg = r.ledger
    assert abs(r.balance()) < 1e-2
    total = sum(v for k, v in lg.items() if k != "emitted")
    assert total == pytest.approx(lg["emitted"], rel=1e-5)
    assert lg["overflow"] == 0.0 and lg["lost"] < 1e-4
    # the table reflects (n - 1)^2 / (n + 1)^2 of the beam back up (normal incidence), ~17 %
    dp = r.deposits
    specular = dp["power"][(dp["screen"] == 0) & (dp["depth"] == 1)].sum()
    n = wo.materials.get("diamond").n(r.wavelengths)
    assert specular == pytest.approx(float((r.weights * ((n - 1) / (n + 1)) ** 2).sum()), rel=1e-3)
    assert r.screens[0].xyz.dtype == np.float64 and r.screens[0].stokes.shape == (640, 640, 4)


def test_soap_film_spot_matches_tmm(device):
    thickness = 400.0
    scene = BenchScene.load(SCENES / "soap_film.toml").with_overrides(
        {"source.rays": 8, "render.wavelengths": 24, "object.0.coating.0.thickness_nm": thickness}
    )
    r = bench(scene, device=device)
    dp = r.deposits
    front = (dp["screen"] == 0) & (dp["depth"] == 1)
    xyz = dp["xyz"][front].sum(axis=0)
    n_w = wo.materials.get("water").n(r.wavelengths)
    R = np.array(
        [
            0.5
            * sum(
                tmm.coh_tmm(p, [1.0, float(n), 1.0], [np.inf, thickness, np.inf], math.pi / 4, lam)["R"]
                for p in ("s", "p")
            )
            for lam, n in zip(r.wavelengths, n_w, strict=True)
        ]
    )
    cm = cmf(r.wavelengths)
    ref = ((r.weights * R)[:, None] * cm).sum(axis=0) / float((r.weights * cm[:, 1]).sum())
    # float32 amplitudes, water index interpolated on a 5 nm grid in the coating table
    np.testing.assert_allclose(xyz, ref, rtol=2e-4)
    assert float(wo.color.delta_e2000(xyz * 0.5 / ref[1], ref * 0.5 / ref[1])) < 0.05


def test_deterministic_across_threads(device):
    scene = BenchScene.load(SCENES / "diamond_fire.toml").with_overrides(
        {"source.rays": 64, "render.wavelengths": 3}
    )
    b = Bench(scene, device=device)
    r1 = b.run(threads=1)
    r2 = b.run(threads=2, tile_size=7)
    r3 = b.run(threads=2, tile_size=5, chunk=48)
    for r in (r2, r3):
        for k in r1.deposits:
            assert np.array_equal(r1.deposits[k], r.deposits[k])
        for a, c in zip(r1.screens, r.screens, strict=True):
            assert a.xyz.tobytes() == c.xyz.tobytes() and a.stokes.tobytes() == c.stokes.tobytes()
        assert r1.ledger == r.ledger


def test_bench_scene_errors(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text('[source]\ntype = "beam"\nwidht = 1.0\n[[sensor]]\ntype = "screen"\n')
    with pytest.raises(InputError, match="width") as exc:
        BenchScene.load(p)
    assert exc.value.field == "source.widht"
    p.write_text('[[sensor]]\ntype = "screen"\n')
    with pytest.raises(InputError) as exc:
        BenchScene.load(p)
    assert exc.value.field == "source"
    p.write_text('[source]\ntype = "beam"\n[[sensor]]\ntype = "screen"\nnormal = [0.0, 0.0, 0.0]\n')
    with pytest.raises(InputError) as exc:
        BenchScene.load(p)
    assert "normal" in exc.value.field
    p.write_text(
        '[source]\ntype = "beam"\n[[sensor]]\n[[object]]\nshape = "plate"\ncoating = [{ n = 1.3 }]\n'
    )
    with pytest.raises(InputError) as exc:
        BenchScene.load(p)
    assert exc.value.field == "object.0.coating.0.thickness_nm"


def _run(*args):
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run(
        [sys.executable, *map(str, args)], capture_output=True, text=True, env=env, timeout=600, check=False
    )


def test_cli_bench(tmp_path, device):
    out = tmp_path / "calcite.png"
    r = _run(
        "-m",
        "warpoptics.cli",
        "--device",
        str(device),
        "bench",
        SCENES / "calcite.toml",
        "-o",
        out,
        "--rays",
        "16",
    )
    assert r.returncode == 0, r.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "closure" in r.stdout
    # `warpoptics render` hands bench scenes to the bench (in-process: same code path)
    from warpoptics.cli import main

    out2 = tmp_path / "calcite.exr"
    assert (
        main(
            [
                "--device",
                str(device),
                "render",
                str(SCENES / "calcite.toml"),
                "-o",
                str(out2),
                "--set",
                "source.rays=8",
            ]
        )
        == 0
    )
    assert out2.is_file() and out2.stat().st_size > 1000
    assert (
        main(
            [
                "bench",
                str(SCENES / "calcite.toml"),
                "-o",
                str(tmp_path / "x.png"),
                "--set",
                'source.kind="laser"',
            ]
        )
        == 2
    )


_SCRIPTS = [
    ("bench_prism_anomalous.py", ["--wavelengths", "12", "--rays", "1"]),
    ("bench_calcite.py", ["--rays", "16"]),
    ("bench_diamond_fire.py", ["--rays", "32", "--wavelengths", "3"]),
    ("bench_soap_film.py", ["--rays", "4", "--thicknesses", "300"]),
]


def test_bench_scripts(tmp_path, device):
    """The four bench scripts, with tiny options, in ONE subprocess (each run as __main__ by
    runpy; the import of Warp and the kernel cache are paid once)."""
    calls = []
    for script, args in _SCRIPTS:
        argv = [script, "-o", str(tmp_path / (script + ".png")), "--device", str(device), *args]
        calls.append((str(ROOT / "scripts" / "reproduce" / script), argv))
    driver = (
        "import runpy, sys\n"
        f"calls = {calls!r}\n"
        "for path, argv in calls:\n"
        "    sys.argv = argv\n"
        "    try:\n"
        "        runpy.run_path(path, run_name='__main__')\n"
        "    except SystemExit as e:\n"
        "        if e.code not in (0, None):\n"
        "            raise\n"
    )
    r = _run("-c", driver)
    assert r.returncode == 0, r.stderr
    for script, _ in _SCRIPTS:
        assert (tmp_path / (script + ".png")).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "measured separation" in r.stdout and "returned through the crown" in r.stdout
    assert "fan-out rose bengal 10 % / water" in r.stdout and "dE2000" in r.stdout


def _free_beam(device, **source):
    data = {
        "source": {
            "type": "beam",
            "position": [0.0, 0.0, 10.0],
            "direction": [0.0, 0.0, -1.0],
            "width": 0.1,
            "lines": [550.0],
            "rays": 64,
            **source,
        },
        "sensor": [
            {
                "type": "screen",
                "center": [0.0, 0.0, -10.0],
                "normal": [0.0, 0.0, 1.0],
                "up": [0.0, 1.0, 0.0],
                "size": [20.0, 20.0],
                "resolution": [40, 40],
            }
        ],
    }
    return bench(BenchScene.from_dict(data), device=device)


@pytest.mark.parametrize(
    "pol, expected",
    [
        ({"polarization": "linear", "polarization_angle": 30.0}, (1.0, 0.5, math.sqrt(3) / 2, 0.0)),
        ({"polarization": "right"}, (1.0, 0.0, 0.0, 1.0)),
        ({"polarization": "left"}, (1.0, 0.0, 0.0, -1.0)),
        ({}, (1.0, 0.0, 0.0, 0.0)),
    ],
)
def test_source_polarization_reaches_screen(device, pol, expected):
    """A beam straight onto a screen facing it: the screen frame (right = normal x up = -x) is the
    beam's frame (x = perpendicular(-z) = -x), so the Stokes vector arrives unchanged:
    S = (1, cos 2a, sin 2a, 0) for linear light at a, S3 = +-1 for right/left circular."""
    r = _free_beam(device, **pol)
    s = r.screens[0].stokes.reshape(-1, 4).sum(axis=0)
    np.testing.assert_allclose(s, expected, atol=1e-5)
    assert r.ledger["screen"] == pytest.approx(1.0, abs=1e-6)


def test_spot_beam_cone(device):
    """A spot light of 20 deg full divergence 20 mm above the screen: the lit disc has radius
    20 tan(10 deg), and equal solid-angle rays give equal power per ray."""
    r = _free_beam(device, kind="spot", divergence=20.0, rays=400)
    dp = r.deposits
    rad = np.hypot(dp["u"], dp["v"])
    assert rad.max() == pytest.approx(20.0 * math.tan(math.radians(10.0)), rel=2e-3)
    np.testing.assert_allclose(dp["power"], 1.0 / 400, rtol=1e-5)
    assert r.ledger["screen"] == pytest.approx(1.0, abs=1e-6)


def _e_ray(kt, m, no, ne, a):
    """Independent float64 e-wave: k = kt + q m on the index ellipsoid k^T M k = 1,
    M = I/ne^2 + (1/no^2 - 1/ne^2) a a^T, the root whose ray M k points along m; returns the unit
    ray (Poynting) direction (Born & Wolf §15.3; Beyerle & McDermid 1998)."""
    M = np.eye(3) / ne**2 + (1 / no**2 - 1 / ne**2) * np.outer(a, a)
    qa, qb, qc = m @ M @ m, kt @ M @ m, kt @ M @ kt - 1.0
    for q in ((-qb + math.sqrt(qb * qb - qa * qc)) / qa, (-qb - math.sqrt(qb * qb - qa * qc)) / qa):
        t = M @ (kt + q * m)
        if t @ m > 0:
            return t / np.linalg.norm(t)
    raise AssertionError("no e root")


def test_calcite_oblique_o_and_e_rays(device):
    """30 deg incidence in the y-z plane (the optic axis tilts in x-z, so the e ray leaves the plane
    of incidence): both spots where a float64 Snell (o) and index-ellipsoid (e) trace put them."""
    th = math.radians(30.0)
    d = np.array([0.0, math.sin(th), -math.cos(th)])
    scene = BenchScene.load(SCENES / "calcite.toml").with_overrides(
        {
            "source.rays": 16,
            "source.width": 0.0,
            "source.direction": list(d),
            "object.0.width": 60.0,
            "object.0.length": 60.0,
            "sensor.0.center": [0.0, 8.0, -10.0],
            "sensor.0.size": [8.0, 8.0],
        }
    )
    r = bench(scene, device=device)
    cal = wo.materials.get("calcite")
    no, ne = float(cal.ordinary.n(589.3)), float(cal.extraordinary.n(589.3))
    a = np.array([1.0, 0.0, 1.0]) / math.sqrt(2.0)
    o = np.array([0.0, 0.0, 10.0])
    entry = o + d * (5.0 / math.cos(th))  # top face z = 5
    kt = d - np.array([0.0, 0.0, d[2]])  # tangential wave vector (units of k0), air n = 1
    m = np.array([0.0, 0.0, -1.0])
    t_o = kt + m * math.sqrt(no**2 - kt @ kt)
    t_o /= np.linalg.norm(t_o)
    t_e = _e_ray(kt, m, no, ne, a)
    spots_ref = []
    for t in (t_o, t_e):
        exit_ = entry + t * (10.0 / -t[2])  # bottom face z = -5
        hit = exit_ + d * (5.0 / math.cos(th))  # screen z = -10, leaving parallel to d
        spots_ref.append((-(hit[0] - 0.0), hit[1] - 8.0))  # screen right = -x, up = y
    s = r.spots(0, count=2, radius=0.2)
    got = sorted((x["u"], x["v"]) for x in s)
    np.testing.assert_allclose(got, sorted(spots_ref), atol=2e-3)
    assert abs(r.balance()) < 1e-2
    for x in s:
        assert x["dop"] > 0.999


def test_rgb_beam_colour(device):
    """A beam of sRGB red lands with the chromaticity of the sRGB red primary (0.64, 0.33)
    (Mallett-Yuksel spectra, 64 stratified samples)."""
    data = {
        "source": {
            "type": "beam",
            "position": [0.0, 0.0, 10.0],
            "direction": [0.0, 0.0, -1.0],
            "width": 0.1,
            "spectrum": [1.0, 0.0, 0.0],
            "rays": 4,
        },
        "render": {"wavelengths": 64},
        "sensor": [
            {
                "type": "screen",
                "center": [0.0, 0.0, -10.0],
                "normal": [0.0, 0.0, 1.0],
                "size": [2.0, 2.0],
                "resolution": [4, 4],
            }
        ],
    }
    r = bench(BenchScene.from_dict(data), device=device)
    xyz = r.screens[0].xyz.reshape(-1, 3).sum(axis=0)
    assert xyz[1] == pytest.approx(1.0, rel=1e-6)  # the whole beam on the screen: Y = 1 by definition
    np.testing.assert_allclose(xyz[:2] / xyz.sum(), (0.64, 0.33), atol=0.01)

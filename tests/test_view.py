"""The progressive preview (pipelines/preview.py) and `warpoptics view` (commands/view.py).

Tiny images (24x16 to 48x32) keep this to seconds; the server runs on an ephemeral 127.0.0.1 port
and is always shut down; every HTTP call has a timeout.  The headless-Chromium test skips where no
Chromium is installed (CI has none).
"""

import io
import json
import math
import os
import shutil
import subprocess
import urllib.error
import urllib.request

import numpy as np
import pytest

import warpoptics as wo
from warpoptics.commands.view import ViewServer
from warpoptics.errors import InputError
from warpoptics.pipelines.preview import BLOCK, Orbit, Preview
from warpoptics.pipelines.render import Renderer

TIMEOUT = 120  # seconds per HTTP call: a pass of these images takes milliseconds; a loaded CI machine is slow

DIAMOND = {
    "camera": {
        "position": [0.0, -22.0, 30.0],
        "look_at": [0.0, 0.0, -0.3],
        "fov": 15.0,
        "width": 32,
        "height": 24,
    },
    "render": {"spectral": "stratified", "wavelengths": 45, "polarization": True, "max_depth": 12},
    "light": [{"type": "environment", "map": "studio"}],
    "object": [{"shape": "round_brilliant", "diameter": 6.5, "material": "diamond"}],
}


def _scene(data=DIAMOND, overrides=None, **kw):
    s = wo.Scene.from_dict(data)
    return s.with_overrides(overrides, **kw) if overrides or kw else s


def _passes(p, n):
    """Step until ``n`` full-resolution passes are in (the draft after a restart comes first)."""
    while p.passes < n:
        assert p.step()
    return p.image()


# -- the orbit: closed form -------------------------------------------------------------------------
def test_orbit_round_trip_and_rotation():
    cam = _scene().camera
    o = Orbit.from_camera(cam)
    np.testing.assert_allclose(o.position(cam.look_at), cam.position, atol=1e-12)
    # the scene camera sits at -y, 54.02 deg up: atan2(30.3, 22) (look_at is 0.3 mm below the origin)
    assert o.azimuth == pytest.approx(-90.0)
    assert o.elevation == pytest.approx(math.degrees(math.atan2(30.3, 22.0)))
    # +90 deg of azimuth is a rotation about +z through look_at, counter-clockwise seen from above
    rot = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    turned = Orbit(o.azimuth + 90.0, o.elevation, o.distance).position(cam.look_at)
    expect = np.asarray(cam.look_at) + rot @ (np.asarray(cam.position) - np.asarray(cam.look_at))
    np.testing.assert_allclose(turned, expect, atol=1e-12)


# -- the pipeline ---------------------------------------------------------------------------------
def test_passes_continue_the_pixel_sequence(device):
    """With every branch split deterministically (split threshold 0, a shallow tree) the trace
    draws no random numbers, so n one-spp passes must give the image of one n-spp render: the
    same wavelengths and R2 pixel positions in the same order (only the float64 sums differ)."""
    data = {**DIAMOND, "render": {**DIAMOND["render"], "max_depth": 4, "split_threshold": 0.0}}
    sc = _scene(data)
    p = Preview(sc, wavelengths=2, device=device, estimator="point")
    n = 5
    img = _passes(p, n)
    over = {
        "render.spp": n,
        "render.wavelengths": 2,
        "render.spectral": "importance",
        "render.estimator": "point",
    }  # the preview's default (its passes are point samples)
    ref = Renderer(sc.with_overrides(over), device=device).run()
    np.testing.assert_allclose(img.xyz, ref.xyz, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(img.stokes, ref.stokes, rtol=1e-9, atol=1e-12)
    assert img.stats["rays"] == ref.stats["rays"]


def test_beam_bands_make_the_passes_of_a_beam_render(device):
    """Where pixel beams apply the passes are beams (4 stratified wavelengths), rendered in bands
    of blocks: n passes, each cut into many bands, give the image of one n-spp beam render with
    the same settings (a deterministic tree: split threshold 0, no roulette), and while a pass
    is in bands its pixels are not yet divided by the next pass count."""
    data = {**DIAMOND, "render": {**DIAMOND["render"], "max_depth": 4, "split_threshold": 0.0}}
    sc = _scene(data)
    p = Preview(sc, device=device, band_seconds=1e-6)  # one block per band
    assert p.pass_estimator == "beam"
    n = 2
    steps = 0
    while p.passes < n:
        assert p.step()
        steps += 1
    assert steps > 2 * 12  # many bands per pass (blocks of 3x3 pixels of 32x24)
    img = p.image()
    assert img.stats["estimator"] == "beam"
    over = {
        "render.spp": n,
        "render.wavelengths": 4,
        "render.bundle_lanes": 4,
        "render.spectral": "stratified",
        "render.estimator": "beam",
    }
    ref = Renderer(sc.with_overrides(over), device=device).run()
    np.testing.assert_allclose(img.xyz, ref.xyz, rtol=1e-6, atol=1e-9)
    # half way through a pass: the done pixels hold n + 1 samples, the rest n, each its own mean
    p.step()
    assert 0 < (p.pixel_passes == n + 1).sum() < p.pixel_passes.size
    mid = p.image().xyz
    np.testing.assert_allclose(mid[p.pixel_passes == n], img.xyz[p.pixel_passes == n], rtol=1e-12)


def test_next_block_draws_new_samples(device):
    """Pass BLOCK starts a new block of the R2 sequence (its own random rotation), not a repeat
    of pass 0: the sample it adds differs from the first pass's."""
    p = Preview(_scene(width=8, height=6), device=device, estimator="point")
    first = _passes(p, 1).xyz.copy()
    _passes(p, BLOCK)
    before = p.film.xyz.numpy().copy()
    p.step()
    added = (p.film.xyz.numpy() - before).reshape(first.shape)
    assert p.passes == BLOCK + 1
    assert np.abs(added - first).max() > 1e-3 * np.abs(first).max()


@pytest.mark.parametrize("estimator", ["point", "auto"])
def test_white_furnace_after_orbit_restart(device, estimator):
    """Energy conservation: a clear stone in a uniform environment is invisible (Y equals the empty
    furnace's, pixel by pixel, same samples).  Both previews are orbited after some passes first,
    so a film that was not cleared at the restart would show the old view."""
    furnace = {
        "camera": {
            "position": [0.0, -30.0, 20.0],
            "look_at": [0.0, 0.0, 0.0],
            "fov": 14.0,
            "width": 24,
            "height": 16,
        },
        "render": {"spectral": "stratified", "max_depth": 256},
        "light": [{"type": "constant", "intensity": 1.0}],
        "object": [
            {"shape": "round_brilliant", "diameter": 6.5, "material": "diamond", "absorption_scale": 0.0}
        ],
    }
    # beams: roulette below split_threshold of a pixel's light is the furnace's only noise
    # (0.002: pixels within 2 %, 0.0002: 0.5 %)
    split = {} if estimator == "point" else {"render.split_threshold": 0.0002}
    images = []
    for position in ([0.0, 0.0, 0.0], [1e4, 1e4, 1e4]):
        sc = _scene(furnace, {"object.0.position": position, **split})
        p = Preview(sc, wavelengths=2, device=device, estimator=estimator)
        assert p.pass_estimator == ("point" if estimator == "point" else "beam")
        _passes(p, 1 if split else 2)
        gen = p.update({"azimuth": 30.0, "elevation": 50.0})
        assert gen == 1 and p.passes == 0
        images.append(_passes(p, 2 if split else 3))
    stone, empty = images
    assert empty.alpha.max() == 0 and stone.alpha.sum() > 20
    ratio = stone.xyz[..., 1] / empty.xyz[..., 1]
    # tolerance as tests/test_render.py's furnace: the transport conserves energy to 2e-4 (docs/accuracy.md);
    # 1 % leaves room for the few Russian-roulette paths of 3 samples
    assert ratio.min() > 0.99 and ratio.max() < 1.01


def test_restart_equals_a_fresh_preview(device):
    """After a change the preview is exactly a new preview of the changed scene: orbit, cut,
    material and light, each compared with a preview built from a scene that has the change."""
    sc = _scene()
    p = Preview(sc, device=device)
    _passes(p, 3)
    changes = {
        "azimuth": -60.0,
        "elevation": 35.0,
        "object.0.pavilion_angle": 41.5,
        "object.0.material": "cubic_zirconia",
        "light.0.intensity": 2.0,
        "light.0.rotation": 45.0,
    }
    assert p.update(changes) == 1
    assert p.passes == 0
    got = _passes(p, 2)
    pos = Orbit(-60.0, 35.0, Orbit.from_camera(sc.camera).distance).position(sc.camera.look_at)
    fresh_scene = sc.with_overrides(
        {
            "camera.position": list(pos),
            "object.0.pavilion_angle": 41.5,
            "object.0.material": "cubic_zirconia",
            "light.0.intensity": 2.0,
            "light.0.rotation": 45.0,
        }
    )
    fresh = _passes(Preview(fresh_scene, device=device), 2)
    np.testing.assert_allclose(got.xyz, fresh.xyz, rtol=1e-6, atol=1e-9)  # float32 camera basis
    assert p.values()["object.0.material"] == "cubic_zirconia"


def test_draft_is_the_scene_at_lower_resolution(device):
    """The first step after a restart is one pass at half the resolution, shown enlarged: exactly
    the frame of a preview of the half-size image, each pixel repeated 2x2."""
    sc = _scene(width=32, height=24)
    p = Preview(sc, device=device, estimator="point")
    p.update({"azimuth": 10.0})
    assert p.step() and p.draft and p.showing_draft and p.passes == 0
    big = p.frame()
    small_scene = sc.with_overrides(
        {"camera.position": list(p.orbit.position(sc.camera.look_at))}, width=16, height=12
    )
    small = Preview(small_scene, draft_scale=1, device=device, estimator="point")
    small.step()
    np.testing.assert_array_equal(big, np.repeat(np.repeat(small.frame(), 2, axis=0), 2, axis=1))
    assert p.step() and p.passes == 1 and not p.showing_draft
    assert p.frame().shape == (24, 32, 3)


def test_exposure_does_not_restart(device):
    p = Preview(_scene(), device=device)
    _passes(p, 2)
    dark = p.frame().astype(int)
    assert p.update({"render.exposure": 1.0}) == 0 and p.passes == 2
    assert p.frame().astype(int).mean() > dark.mean()


def test_max_passes_stops_refining(device):
    p = Preview(_scene(width=8, height=6), max_passes=2, draft_scale=1, device=device, estimator="point")
    assert p.step() and p.step() and not p.step()
    assert p.passes == 2


@pytest.mark.parametrize(
    "values,match",
    [
        ({"pavilion": 41.0}, "no such control"),
        ({"object.0.pavilion_angle": 60.0}, "out of range"),
        ({"object.0.crown_angle": "steep"}, "object.0.crown_angle"),
        ({"object.0.material": "diamnd"}, "did you mean 'diamond'"),
        ({"elevation": 90.0}, "out of range"),
        ({"distance": float("nan")}, "distance"),
        ([1, 2], "expected an object"),
    ],
)
def test_bad_values_change_nothing(device, values, match):
    p = Preview(_scene(width=8, height=6), device=device)
    _passes(p, 1)
    before = p.values()
    with pytest.raises(InputError, match=match) as exc:
        p.update(values)
    assert "\n" not in str(exc.value)
    assert p.values() == before and p.generation == 0 and p.passes == 1


# -- the server -----------------------------------------------------------------------------------
def _get(url):
    with urllib.request.urlopen(url, timeout=TIMEOUT) as r:
        return r.status, dict(r.headers), r.read()


def _post(url, body: bytes, token: str):
    headers = {"Content-Type": "application/json", "X-Warpoptics-Token": token}
    req = urllib.request.Request(url, data=body, method="POST", headers=headers)
    try:
        with urllib.request.urlopen(req, timeout=TIMEOUT) as r:
            return r.status, json.loads(r.read())
    except urllib.error.HTTPError as e:
        return e.code, json.loads(e.read())


def _decode(data):
    from PIL import Image as PILImage

    return np.asarray(PILImage.open(io.BytesIO(data)).convert("RGB"))


def test_server_frames_refine_and_restart(device):
    p = Preview(_scene(width=48, height=32), device=device, estimator="point")
    with ViewServer(p, port=0) as srv:
        assert srv.url.startswith("http://127.0.0.1:")
        status, headers, page = _get(srv.url)
        assert status == 200 and headers["Content-Type"].startswith("text/html")
        assert b"/frame.jpg" in page and b"/controls" in page
        state = json.loads(_get(srv.url + "state")[2])
        assert (state["width"], state["height"], state["passes"]) == (48, 32, 0)
        names = {c["name"] for c in state["controls"]}
        assert {
            "azimuth",
            "elevation",
            "object.0.crown_angle",
            "object.0.material",
            "light.0.intensity",
        } <= names
        # the first frame is the half-resolution draft, then each frame adds one pass
        _, headers, _ = _get(srv.url + "frame.jpg")
        assert (headers["X-Draft"], headers["X-Passes"]) == ("1", "0")
        for k in (1, 2, 3):
            _, headers, body = _get(srv.url + "frame.jpg")
            assert (
                headers["X-Passes"] == str(k) and headers["X-Generation"] == "0" and headers["X-Draft"] == "0"
            )
        rgb = _decode(body)
        assert rgb.shape == (32, 48, 3)
        # JPEG at quality 90 keeps each 8x8 block's mean (its DC coefficient) but not the pixel-scale
        # colour noise of a 3-pass, one-wavelength frame, and decoding clips that noise at 0 in this
        # dark image (a bias of 1-2 levels): the blocks' means must follow the frame's closely
        frame = p.frame().astype(float)
        a, b = (x.reshape(4, 8, 6, 8, 3).mean(axis=(1, 3)).ravel() for x in (rgb.astype(float), frame))
        print(f"JPEG vs frame, 8x8 block means: r = {np.corrcoef(a, b)[0, 1]:.4f}, bias {np.mean(a - b):.2f}")
        assert np.corrcoef(a, b)[0, 1] > 0.95 and abs(np.mean(a - b)) < 3.0
        assert rgb.std() > 5.0  # a gem, not a blank frame
        # a change restarts the accumulation: the draft of generation 1, then its pass 1
        status, reply = _post(
            srv.url + "controls", json.dumps({"object.0.crown_angle": 30.0}).encode(), srv.token
        )
        assert status == 200 and reply["generation"] == 1 and reply["values"]["object.0.crown_angle"] == 30.0
        _, headers, _ = _get(srv.url + "frame.jpg")
        assert (headers["X-Draft"], headers["X-Passes"], headers["X-Generation"]) == ("1", "0", "1")
        _, headers, _ = _get(srv.url + "frame.jpg")
        assert (headers["X-Draft"], headers["X-Passes"], headers["X-Generation"]) == ("0", "1", "1")
        # bad input: 400 and one line, nothing changed
        status, reply = _post(
            srv.url + "controls", json.dumps({"object.0.crown_angle": 80.0}).encode(), srv.token
        )
        assert status == 400 and "out of range" in reply["error"] and "\n" not in reply["error"]
        status, reply = _post(srv.url + "controls", b"{not json", srv.token)
        assert status == 400
        assert p.generation == 1 and p.passes == 1
        # the PNG snapshot is the frame, lossless, and adds no pass
        _, headers, png = _get(srv.url + "frame.png")
        assert headers["Content-Type"] == "image/png" and p.passes == 1
        np.testing.assert_array_equal(_decode(png), p.frame())
        with pytest.raises(urllib.error.HTTPError) as exc:
            _get(srv.url + "nothing")
        assert exc.value.code == 404
    # shut down: the port no longer answers
    with pytest.raises(OSError):
        _get(srv.url + "state")


def test_bench_view_quick():
    """scripts/bench/bench_view.py --quick: the real command as a subprocess, a few frames each
    of refining and orbiting (the script fails unless every orbit frame restarted the view)."""
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    r = subprocess.run(
        [sys.executable, str(root / "scripts" / "bench" / "bench_view.py"), "--quick", "--draft-scales", "2"],
        capture_output=True,
        text=True,
        timeout=600,
        cwd=root,
    )
    assert r.returncode == 0, r.stderr[-2000:]
    assert "every orbit frame restarted the accumulation: True" in r.stdout


def test_cli_refuses_bad_input(tmp_path, capsys):
    from warpoptics.cli import main

    assert main(["view", str(tmp_path / "missing.toml")]) == 2
    assert "scene file not found" in capsys.readouterr().err
    assert main(["view", "scenes/diamond.toml", "--port", "70000"]) == 2
    assert "--port" in capsys.readouterr().err
    assert main(["view", "scenes/diamond.toml", "--draft-scale", "0"]) == 2
    err = capsys.readouterr().err
    assert "draft_scale = 0" in err and len(err.strip().splitlines()) == 1


# -- the page in a real browser (skips without Chromium) ---------------------------------------------
def _chromium():
    for name in ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable"):
        path = shutil.which(name)
        if path:
            return path
    return None


@pytest.mark.skipif(_chromium() is None, reason="no Chromium installed (apt-get install chromium)")
def test_page_in_headless_chromium(device, tmp_path):
    """The page loads its controls, fetches frames and draws them: a screenshot's image area is the
    server's last frame (the page stops after 3 frames, ?frames=3, so that the browser settles)."""
    w, h = 48, 32
    p = Preview(_scene(width=w, height=h), device=device, estimator="point")
    shot = tmp_path / "page.png"
    with ViewServer(p, port=0) as srv:
        cmd = [
            _chromium(),
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
            "--force-device-scale-factor=1",
            "--window-size=800,400",
            "--virtual-time-budget=20000",
            f"--user-data-dir={tmp_path / 'profile'}",
            f"--screenshot={shot}",
            srv.url + "?frames=3",
        ]
        subprocess.run(cmd, timeout=120, capture_output=True, env={**os.environ, "HOME": str(tmp_path)})
        assert shot.is_file()
        assert p.passes == 2  # the page asked for exactly three frames: the draft and two passes
        expect = p.frame().astype(int)
    from PIL import Image as PILImage

    page = np.asarray(PILImage.open(shot).convert("RGB")).astype(int)
    # the image sits at the body's 12 px margin (view_page.py); JPEG q90 + browser decoding: a few levels
    crop = page[12 : 12 + h, 12 : 12 + w]
    assert np.abs(crop - expect).mean() < 6.0
    # the control panel was built from /state: the page is not just the image
    assert page[:, 12 + w + 16 :].std() > 5.0


@pytest.mark.skipif(_chromium() is None, reason="no Chromium installed (apt-get install chromium)")
def test_page_sends_its_changes_with_the_token(device, tmp_path):
    """The real page's POST passes the server's checks (same origin, JSON, the launch's token):
    ``?set=azimuth=10`` makes the page send one change, as a slider does, and the preview takes it."""
    p = Preview(_scene(width=16, height=12), device=device)
    with ViewServer(p, port=0) as srv:
        cmd = [
            _chromium(),
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--virtual-time-budget=20000",
            f"--user-data-dir={tmp_path / 'profile'}",
            "--dump-dom",
            srv.url + "?frames=3&set=azimuth=10",
        ]
        subprocess.run(cmd, timeout=120, capture_output=True, env={**os.environ, "HOME": str(tmp_path)})
        assert p.values()["azimuth"] == 10.0 and p.generation == 1

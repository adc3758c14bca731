"""scripts/bench/bench_fire.py: the fire benchmark's smoke run and its peer export.

The peer (indicatrix, a Rust binary in scripts/bench/indicatrix_peer/) is never built by CI:
the smoke run must then skip it and still measure our two renders; where it is built, a second
smoke run includes it.  The peer's frame is checked against indicatrix's own lat-long formula
(renderer/env_map.rs, ``direction_to_uv``: u = atan2(x, z) / 2 pi, v = acos(y) / pi, y up),
written here, not taken from the script.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "scripts" / "bench" / "bench_fire.py"
sys.path.insert(0, str(ROOT / "scripts" / "bench"))
import bench_fire as bf  # noqa: E402


def _run(tmp_path, *extra):
    out = tmp_path / "fire.json"
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    cmd = [sys.executable, str(SCRIPT), "--quick", "--width", "16", "--height", "16", "--min-passes", "4"]
    cmd += ["--max-passes", "4", "--json", str(out), "--log", str(tmp_path / "fire.log"), *extra]
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return proc, json.loads(out.read_text())


def test_smoke_without_the_peer(tmp_path):
    proc, res = _run(tmp_path, "--peer-bin", str(tmp_path / "not_built"))
    assert "not built" in res["peer"] and "skipped" in proc.stdout
    assert set(res["renderers"]) == {"ours dispersive", "ours clear"}
    for who in res["renderers"].values():
        for t in ("5%", "2%", "1%"):
            c = who[t]
            assert c["passes"] == 4 and c["seconds_to_target"] > 0 and c["cpu_seconds_to_target"] > 0
        # the time to a target grows as 1 / target^2 once past one pass
        assert who["1%"]["samples_to_target"] >= who["5%"]["samples_to_target"]
    assert res["width"] == 16 and (tmp_path / "fire.log").read_text().count("warm-up") == 2
    # the clear twin and the dispersive stone are the same stone: the same mean within noise
    assert abs(res["agreement"]["clear_vs_dispersive"]["mean_rel_diff"]) < 0.15


@pytest.mark.skipif(
    not bf.PEER_BIN.exists(), reason="indicatrix_peer not built (bench-only, see bench_fire.py)"
)
def test_smoke_with_the_peer(tmp_path):
    _, res = _run(tmp_path)
    assert res["renderers"]["indicatrix"]["1%"]["passes"] == 4
    # indicatrix's white texel: the XYZ of D65 at Y = 1 (its RGB-to-spectrum keeps sRGB white)
    assert np.allclose(res["peer_white_xyz"], [0.9505, 1.0, 1.089], atol=0.01)
    assert abs(res["agreement"]["dispersive_vs_indicatrix"]["mean_rel_diff"]) < 0.15


def test_peer_frame_reads_the_same_texel():
    """TO_PEER is a proper rotation under which indicatrix's lat-long formula reads the
    left-right mirrored map at the texel our Blender layout reads (u = 0.5 - atan2(y, x) / 2 pi,
    v = acos(z) / pi): the same picture, not its mirror image."""
    r = bf.TO_PEER
    assert np.allclose(r @ r.T, np.eye(3)) and np.linalg.det(r) == pytest.approx(1.0)
    rng = np.random.default_rng(1)
    d = rng.normal(size=(1000, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    u_ours = (0.5 - np.arctan2(d[:, 1], d[:, 0]) / (2 * np.pi)) % 1.0
    v_ours = np.arccos(d[:, 2]) / np.pi
    p = d @ r.T
    u_peer = (np.arctan2(p[:, 0], p[:, 2]) / (2 * np.pi)) % 1.0
    v_peer = np.arccos(p[:, 1]) / np.pi
    assert np.allclose(v_peer, v_ours, atol=1e-12)
    assert np.allclose(
        np.minimum(abs(u_peer - (1 - u_ours)) % 1.0, 1 - abs(u_peer - (1 - u_ours)) % 1.0), 0, atol=1e-9
    )


def test_facet_planes_of_a_cube_and_refusal_of_a_concave_mesh():
    import trimesh

    box = trimesh.creation.box(extents=(2.0, 2.0, 2.0))
    planes = bf.facet_planes(np.asarray(box.vertices), np.asarray(box.faces))
    assert len(planes) == 6  # 12 triangles, 6 faces
    assert np.allclose(np.sort(np.abs(planes[:, :3]).sum(1)), 1.0) and np.allclose(planes[:, 3], -1.0)
    v = np.asarray(box.vertices, dtype=float).copy()
    v[0] *= 0.3  # push a corner inward: no longer convex
    with pytest.raises(ValueError, match="not convex"):
        bf.facet_planes(v, np.asarray(box.faces))


def test_pfm_round_trip(tmp_path):
    img = np.random.default_rng(0).random((5, 7, 3)).astype(np.float32)
    bf.write_pfm(tmp_path / "a.pfm", img)
    assert np.array_equal(bf.read_pfm(tmp_path / "a.pfm"), img.astype(np.float64))


def test_noise_sources_smoke(tmp_path):
    """scripts/bench/fire_noise_sources.py at 16x16 runs and writes its figures: noises of the
    sharp and blurred maps, and first-hit edge pixels that are a part of the stone's pixels."""
    out = tmp_path / "sources.json"
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    cmd = [sys.executable, str(ROOT / "scripts" / "bench" / "fire_noise_sources.py"), "--res", "16"]
    cmd += ["--spp", "4", "--sigma", "8", "--sub", "4", "--json", str(out)]
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    res = json.loads(out.read_text())
    assert len(res["rows"]) == 4 and all(0.0 < r["noise"] < 1.0 for r in res["rows"])
    for e in res["first_hit_edges"]:
        assert 0.0 < e["edge_pixels"] <= e["stone_pixels"] < 1.0
        assert 0.0 < e["variance_share_of_edge_pixels"] <= 1.0

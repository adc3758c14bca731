"""glTF 2.0 interchange of gems (geometry/gltf.py): export -> import keeps the facets and the
optical parameters; the extension values follow the Khronos specs; the file passes the Khronos
glTF validator (npm ``gltf-validator``, run with node where available) and a structural check
of the GLB container and accessors everywhere."""

import json
import math
import os
import shutil
import struct
import subprocess
from pathlib import Path

import numpy as np
import pytest

import warpoptics as wo
from warpoptics.errors import InputError
from warpoptics.geometry import gltf
from warpoptics.materials import AbsorptionSpectrum, Cauchy, abbe_number, with_absorption


@pytest.fixture(scope="module")
def stone():
    mesh = wo.cuts.round_brilliant(diameter=6.5)
    mat = wo.materials.material_from_spec({"base": "spinel", "absorption_rgb": [0.05, 0.3, 0.1]})
    return mesh, mat


def _sorted_triangles(tri):
    # order-free comparison: each triangle's vertices sorted, then the triangles
    t = np.sort(np.round(np.asarray(tri, dtype=np.float64), 5).view("f8,f8,f8").reshape(-1, 3), axis=1)
    return np.sort(t.view(np.float64).reshape(-1, 9), axis=0)


@pytest.mark.parametrize("suffix", [".glb", ".gltf"])
def test_round_trip_keeps_geometry_and_optics(tmp_path, stone, suffix):
    mesh, mat = stone
    path = gltf.export_gltf(
        tmp_path / f"gem{suffix}", mesh, mat, film_ior=1.38, film_thickness_nm=120.0, name="spinel"
    )
    (gem,) = gltf.import_gltf(path)
    # geometry in mm again: the same facets (float32 metres in the file: ~1e-6 mm)
    assert len(gem.mesh.faces) == len(mesh.faces)
    assert np.abs(_sorted_triangles(gem.mesh.triangles) - _sorted_triangles(mesh.triangles)).max() < 1e-4
    assert gem.mesh.is_watertight
    assert gem.mesh.volume == pytest.approx(mesh.volume, rel=1e-6)
    # optics as written (JSON float64)
    ref = gltf.gem_optics(
        mat, size_mm=float(np.max(mesh.extents)), film_ior=1.38, film_thickness_nm=120.0, name="spinel"
    )
    o = gem.optics
    assert o.name == "spinel"
    assert o.ior == pytest.approx(ref.ior, rel=1e-12) and o.abbe == pytest.approx(ref.abbe, rel=1e-12)
    assert np.allclose(o.absorption_rgb, ref.absorption_rgb, rtol=1e-9, atol=1e-12)
    assert o.thickness_mm == pytest.approx(6.5, rel=1e-12)
    assert (o.film_ior, o.film_thickness_nm) == (1.38, 120.0)
    # the imported material: n_d and the Abbe number (materials.abbe_number, independent of the
    # Cauchy fit) of the original, and its D65/sRGB absorbance (spectrum_from_rgb's inversion)
    m2 = o.material()
    assert float(m2.n(np.array([587.56]))[0]) == pytest.approx(float(mat.n(np.array([587.56]))[0]), rel=1e-6)
    assert abbe_number(m2) == pytest.approx(abbe_number(mat), rel=1e-4)
    again = gltf.gem_optics(m2, size_mm=6.5)
    assert np.allclose(again.absorption_rgb, ref.absorption_rgb, rtol=2e-3, atol=1e-5)


def test_extension_values_follow_the_specs(tmp_path):
    """A flat absorption alpha0 = 0.2 /mm gives every channel alpha0 (any normalised weighting),
    so attenuationColor = exp(-0.2 d) at attenuationDistance d; dispersion = 20 / V_d with V_d
    computed here from n(lambda) (KHR_materials_dispersion); lengths in metres."""
    a0 = 0.2
    mat = with_absorption(Cauchy(1.6, 0.01), AbsorptionSpectrum([300.0, 900.0], [a0, a0]))
    mesh = wo.cuts.oval(length=3.0, width=2.0)
    size = float(np.max(mesh.extents))
    path = gltf.export_gltf(tmp_path / "g.glb", mesh, mat)
    tree = gltf._read_json(path)
    ext = tree["materials"][0]["extensions"]
    n = lambda lam: 1.6 + 0.01 / (lam / 1000.0) ** 2  # noqa: E731
    v_d = (n(587.56) - 1) / (n(486.13) - n(656.27))
    assert ext["KHR_materials_ior"]["ior"] == pytest.approx(n(587.56), rel=1e-6)
    assert ext["KHR_materials_dispersion"]["dispersion"] == pytest.approx(20.0 / v_d, rel=1e-4)
    vol = ext["KHR_materials_volume"]
    assert vol["attenuationDistance"] == pytest.approx(size / 1000.0, rel=1e-12)
    assert vol["thicknessFactor"] == pytest.approx(size / 1000.0, rel=1e-12)
    assert np.allclose(vol["attenuationColor"], math.exp(-a0 * size), rtol=1e-6)
    assert ext["KHR_materials_transmission"]["transmissionFactor"] == 1.0
    assert "KHR_materials_iridescence" not in ext  # no film
    # a non-dispersive clear stone: dispersion 0, no attenuation, imported as n = const
    path = gltf.export_gltf(tmp_path / "clear.glb", mesh, Cauchy(1.8))
    ext = gltf._read_json(path)["materials"][0]["extensions"]
    assert ext["KHR_materials_dispersion"]["dispersion"] == 0.0
    assert "attenuationDistance" not in ext["KHR_materials_volume"]
    (gem,) = gltf.import_gltf(path)
    assert gem.optics.abbe == math.inf and gem.optics.absorption_rgb == (0.0, 0.0, 0.0)
    assert np.allclose(gem.optics.material().n(np.array([400.0, 700.0])), 1.8, rtol=1e-6)


def test_uniaxial_exports_its_ordinary_index(tmp_path):
    mat = wo.materials.get("sapphire")
    path = gltf.export_gltf(tmp_path / "s.glb", wo.cuts.round_brilliant(diameter=3.0), mat)
    ior = gltf._read_json(path)["materials"][0]["extensions"]["KHR_materials_ior"]["ior"]
    assert ior == pytest.approx(float(mat.ordinary.n(np.array([587.56]))[0]), rel=1e-6)


def test_biaxial_exports_its_beta_index(tmp_path):
    # peridot (Handbook of Mineralogy forsterite n_beta 1.651 at the sodium D line, Cauchy fit)
    mat = wo.materials.get("peridot")
    path = gltf.export_gltf(tmp_path / "p.glb", wo.cuts.round_brilliant(diameter=3.0), mat)
    ior = gltf._read_json(path)["materials"][0]["extensions"]["KHR_materials_ior"]["ior"]
    assert ior == pytest.approx(1.651, abs=2e-4)  # 587.56 vs 589.3 nm: 3e-5 apart


def test_glb_structure(tmp_path, stone):
    """The GLB container (glTF 2.0 spec §4.4) and the accessors, checked by hand: header and
    chunk lengths, 4-byte alignment, POSITION min/max equal to the decoded data, indices in
    range, unit normals equal to the face normals, extensionsUsed covering the materials."""
    mesh, mat = stone
    path = gltf.export_gltf(tmp_path / "gem.glb", mesh, mat, film_ior=1.38, film_thickness_nm=120.0)
    raw = path.read_bytes()
    magic, version, length = struct.unpack_from("<4sII", raw, 0)
    assert (magic, version, length) == (b"glTF", 2, len(raw))
    jlen, jtype = struct.unpack_from("<I4s", raw, 12)
    assert jtype == b"JSON" and jlen % 4 == 0
    tree = json.loads(raw[20 : 20 + jlen])
    blen, btype = struct.unpack_from("<I4s", raw, 20 + jlen)
    assert btype == b"BIN\x00" and 28 + jlen + blen == len(raw)
    binary = raw[28 + jlen :]
    assert tree["asset"]["version"] == "2.0" and tree["buffers"][0]["byteLength"] <= blen

    def accessor(i, dtype, width):
        a = tree["accessors"][i]
        v = tree["bufferViews"][a["bufferView"]]
        off = v.get("byteOffset", 0) + a.get("byteOffset", 0)
        assert off % 4 == 0 and off + a["count"] * width * np.dtype(dtype).itemsize <= len(binary)
        data = np.frombuffer(binary, dtype=dtype, count=a["count"] * width, offset=off)
        return a, data.reshape(a["count"], width)

    (prim,) = tree["meshes"][0]["primitives"]
    a, pos = accessor(prim["attributes"]["POSITION"], "<f4", 3)
    assert np.allclose(a["min"], pos.min(axis=0)) and np.allclose(a["max"], pos.max(axis=0))
    assert np.allclose(np.ptp(pos, axis=0) * 1000.0, mesh.extents, rtol=1e-5)  # metres
    _, idx = accessor(prim["indices"], "<u4", 1)
    assert idx.min() >= 0 and idx.max() < len(pos) and len(idx) == 3 * len(mesh.faces)
    _, nrm = accessor(prim["attributes"]["NORMAL"], "<f4", 3)
    assert np.allclose(np.linalg.norm(nrm, axis=1), 1.0, atol=1e-5)
    tri = pos[idx.reshape(-1, 3)]
    face_n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    face_n /= np.linalg.norm(face_n, axis=1, keepdims=True)
    # flat shading, outward normals, counter-clockwise winding (spec: front faces CCW)
    assert np.allclose(nrm[idx.reshape(-1, 3)[:, 0]], face_n, atol=1e-4)
    used = set(tree["extensionsUsed"])
    mat_ext = tree["materials"][prim["material"]]["extensions"]
    assert set(mat_ext) <= used and set(gltf.EXTENSIONS) == set(mat_ext)


def _validator():
    node = shutil.which("node")
    if node is None:
        return None, None
    probe = subprocess.run(
        [node, "-e", "require.resolve('gltf-validator')"], capture_output=True, env=os.environ.copy()
    )
    return (node, os.environ.copy()) if probe.returncode == 0 else (None, None)


VALIDATE_JS = """
const fs = require("fs");
const v = require("gltf-validator");
const data = new Uint8Array(fs.readFileSync(process.argv[1]));
v.validateBytes(data, {uri: process.argv[1], externalResourceFunction: () => Promise.reject("none")})
  .then((r) => console.log(JSON.stringify(r.issues)))
  .catch((e) => { console.error(String(e)); process.exit(2); });
"""


@pytest.mark.parametrize("suffix", [".glb", ".gltf"])
def test_khronos_validator(tmp_path, stone, suffix):
    """The Khronos glTF-Validator (npm gltf-validator; resolvable by node, e.g. through
    NODE_PATH): no errors, warnings, infos or hints -- in particular every extension is known."""
    node, env = _validator()
    if node is None:
        pytest.skip("node with the npm package gltf-validator not available")
    mesh, mat = stone
    path = gltf.export_gltf(tmp_path / f"gem{suffix}", mesh, mat, film_ior=1.38, film_thickness_nm=120.0)
    proc = subprocess.run(
        [node, "-e", VALIDATE_JS, str(path)], capture_output=True, text=True, env=env, timeout=120
    )
    assert proc.returncode == 0, proc.stderr
    issues = json.loads(proc.stdout)
    assert issues["numErrors"] == 0 and issues["numWarnings"] == 0, issues["messages"]
    assert issues["numInfos"] == 0 and issues["numHints"] == 0, issues["messages"]


def test_bad_input_is_one_clear_error(tmp_path, stone):
    mesh, mat = stone
    with pytest.raises(InputError, match="allowed: .glb, .gltf"):
        gltf.export_gltf(tmp_path / "gem.obj", mesh, mat)
    with pytest.raises(InputError, match="not found"):
        gltf.import_gltf(tmp_path / "none.glb")
    bad = Path(tmp_path / "bad.glb")
    bad.write_bytes(b"glTF\x02\x00\x00\x00garbage")
    with pytest.raises(InputError) as exc:
        gltf.import_gltf(bad)
    assert "\n" not in str(exc.value)

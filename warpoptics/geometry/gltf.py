"""Gems as glTF 2.0: a stone's mesh with its optical properties, for Blender and web viewers.

``export_gltf(path, mesh, material, film=...)`` writes a ``.glb`` (or ``.gltf`` with embedded
buffers) through trimesh: the facets flat-shaded (each triangle its own vertices and normal),
in metres as glTF requires (our meshes are in millimetres), and one material carrying

- ``KHR_materials_ior``: ``ior`` = n_d, the index at 587.56 nm (KHR_materials_dispersion defines
  the glTF ior as n_d);
- ``KHR_materials_dispersion``: ``dispersion`` = 20 / V_d, V_d = (n_d - 1) / (n_F - n_C) the Abbe
  number (486.13 and 656.27 nm); 0 for a non-dispersive stone;
- ``KHR_materials_transmission`` (``transmissionFactor`` 1: a clear dielectric; glTF's volume
  needs it) and ``KHR_materials_volume``: Beer-Lambert absorption as "the colour white light
  turns into after ``attenuationDistance``": ``attenuationColor`` = exp(-alpha_c d) per linear
  sRGB channel c, with alpha_c the D65-weighted linear-sRGB mean of alpha(lambda) (Guy & Soler
  2004 eq. 9, ``materials.rgb_absorbance``) and d the stone's largest extent (so the colour is
  that of light crossing the stone, well resolved in 8 bits); ``thicknessFactor`` the same d;
- ``KHR_materials_iridescence`` for a single thin-film coating: ``iridescenceIor`` the film's
  index, ``iridescenceThicknessMaximum`` its thickness (nm; with no thickness texture the
  spec uses the maximum), factor 1.

``import_gltf(path)`` reads such a file back (geometry in millimetres) and each material's
parameters as :class:`GltfOptics`; ``GltfOptics.material()`` makes a warpoptics material from
them: a two-term Cauchy law through n_d with the Abbe number V_d, and the smooth absorption
spectrum whose D65/sRGB absorbance is alpha_c (``materials.spectrum_from_rgb``).  A glTF material
is isotropic: a uniaxial stone is exported with its ordinary index and the mean of its o and e
absorption, a biaxial one with n_beta and the mean of its three principal absorptions.  A file
without the extensions gives glTF's defaults (ior 1.5, no dispersion, clear).

References:
    Khronos Group, glTF 2.0 specification and the ratified extensions KHR_materials_ior,
    KHR_materials_dispersion, KHR_materials_transmission, KHR_materials_volume,
    KHR_materials_iridescence (github.com/KhronosGroup/glTF, extensions/2.0/Khronos/).
    Guy, S. & Soler, C. 2004. Graphical gems rendering, eq. 9 (RGB absorbance).
"""

from __future__ import annotations

import json
import math
import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh

from ..atomic import atomic_path
from ..errors import InputError

__all__ = ["GltfOptics", "GltfGem", "gem_optics", "export_gltf", "import_gltf", "EXTENSIONS"]

#: Fraunhofer d, F, C lines (nm): the Abbe number's wavelengths (as materials.abbe_number)
LAMBDA_D, LAMBDA_F, LAMBDA_C = 587.56, 486.13, 656.27
EXTENSIONS = (
    "KHR_materials_ior",
    "KHR_materials_dispersion",
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_materials_iridescence",
)
_MM_PER_M = 1000.0
_ABSORPTION = {"illuminant": "D65", "cmfs": "srgb"}  # alpha_c: the renderer's linear-sRGB channels


@dataclass(frozen=True)
class GltfOptics:
    """The optical parameters a glTF material carries (lengths in mm, film thickness in nm).

    ``ior``: n_d; ``abbe``: V_d (``math.inf``: non-dispersive); ``absorption_rgb``: alpha per
    linear-sRGB channel, 1/mm (base e); ``thickness_mm``: glTF's volume thickness and the
    attenuation distance; ``film_ior`` / ``film_thickness_nm``: one thin-film coating, or None."""

    ior: float
    abbe: float = math.inf
    absorption_rgb: tuple[float, float, float] = (0.0, 0.0, 0.0)
    thickness_mm: float = 1.0
    film_ior: float | None = None
    film_thickness_nm: float | None = None
    name: str = "gem"

    def material(self):
        """A warpoptics material with this n_d, V_d and (D65/sRGB) absorption."""
        from ..materials import Cauchy, spectrum_from_rgb, with_absorption

        b = 0.0
        if math.isfinite(self.abbe) and self.abbe > 0:
            # n = A + B / lambda^2 (um): n_F - n_C = (n_d - 1) / V_d fixes B, n(lambda_d) = n_d fixes A
            b = (self.ior - 1.0) / self.abbe / ((1e3 / LAMBDA_F) ** 2 - (1e3 / LAMBDA_C) ** 2)
        mat = Cauchy(self.ior - b * (1e3 / LAMBDA_D) ** 2, b, name=self.name)
        if max(self.absorption_rgb) > 0:
            mat = with_absorption(mat, spectrum_from_rgb(list(self.absorption_rgb), **_ABSORPTION))
        return mat


@dataclass(frozen=True)
class GltfGem:
    """One mesh of a glTF file: ``mesh`` in millimetres (world placement applied), its optics."""

    mesh: trimesh.Trimesh
    optics: GltfOptics


def gem_optics(
    material,
    *,
    size_mm: float,
    film_ior: float | None = None,
    film_thickness_nm: float | None = None,
    name: str = "gem",
) -> GltfOptics:
    """The glTF parameters of a warpoptics ``material`` for a stone of largest extent
    ``size_mm`` (see the module docstring); ``film_*``: one thin-film coating."""
    from ..materials import Biaxial, Uniaxial, rgb_absorbance

    lam = np.array([LAMBDA_D, LAMBDA_F, LAMBDA_C])
    if isinstance(material, Biaxial):
        # glTF has one index: n_beta (between the other two), alpha averaged over D along X, Y, Z
        n = np.asarray(material.beta.n(lam), dtype=np.float64)

        def alpha(wl):
            return np.asarray(material.alpha(wl), dtype=np.float64).mean(axis=-1)
    elif isinstance(material, Uniaxial):
        n = np.asarray(material.ordinary.n(lam), dtype=np.float64)

        def alpha(wl):
            return np.asarray(material.alpha(wl), dtype=np.float64).mean(axis=-1)
    else:
        n = np.asarray(material.n(lam), dtype=np.float64)

        def alpha(wl):
            return np.asarray(material.alpha(wl), dtype=np.float64)

    dn = float(n[1] - n[2])
    abbe = (float(n[0]) - 1.0) / dn if dn > 1e-12 else math.inf
    a = np.maximum(rgb_absorbance(alpha, **_ABSORPTION), 0.0)  # negative CMF lobes: no gain
    if not (math.isfinite(size_mm) and size_mm > 0):
        raise InputError("must be a finite length > 0 (mm)", field="size_mm", value=size_mm)
    if (film_ior is None) != (film_thickness_nm is None):
        raise InputError(
            "a film needs both its index and its thickness",
            field="film_ior",
            value=(film_ior, film_thickness_nm),
        )
    return GltfOptics(
        ior=float(n[0]),
        abbe=abbe,
        absorption_rgb=tuple(float(v) for v in a),
        thickness_mm=float(size_mm),
        film_ior=film_ior,
        film_thickness_nm=film_thickness_nm,
        name=name,
    )


def _extensions(o: GltfOptics) -> dict:
    d_m = o.thickness_mm / _MM_PER_M
    ext = {
        "KHR_materials_ior": {"ior": o.ior},
        # the spec's dispersion = 20 / V_d (0: none)
        "KHR_materials_dispersion": {"dispersion": 20.0 / o.abbe if math.isfinite(o.abbe) else 0.0},
        "KHR_materials_transmission": {"transmissionFactor": 1.0},
        "KHR_materials_volume": {"thicknessFactor": d_m},
    }
    if max(o.absorption_rgb) > 0:
        ext["KHR_materials_volume"]["attenuationDistance"] = d_m
        ext["KHR_materials_volume"]["attenuationColor"] = [
            math.exp(-a * o.thickness_mm) for a in o.absorption_rgb
        ]
    if o.film_ior is not None:
        ext["KHR_materials_iridescence"] = {
            "iridescenceFactor": 1.0,
            "iridescenceIor": float(o.film_ior),
            # without a thickness texture the film is the maximum (the minimum has no effect)
            "iridescenceThicknessMaximum": float(o.film_thickness_nm),
        }
    return ext


def _set_view_targets(tree: dict) -> None:
    # bufferView targets (ARRAY_BUFFER for vertex data, ELEMENT_ARRAY_BUFFER for indices), which
    # trimesh leaves out and the Khronos validator hints at
    views = tree.get("bufferViews", [])
    for prim in (q for m in tree.get("meshes", []) for q in m.get("primitives", [])):
        pairs = [(a, 34962) for a in prim.get("attributes", {}).values()] + [(prim.get("indices"), 34963)]
        for acc, target in pairs:
            view = tree["accessors"][acc].get("bufferView") if acc is not None else None
            if view is not None and view < len(views):
                views[view]["target"] = target


def export_gltf(
    path,
    mesh: trimesh.Trimesh,
    material=None,
    *,
    optics: GltfOptics | None = None,
    film_ior: float | None = None,
    film_thickness_nm: float | None = None,
    name: str = "gem",
) -> Path:
    """Write ``mesh`` (mm) with ``material`` (a warpoptics material; or ready ``optics``) as
    glTF 2.0: ``.glb`` binary or ``.gltf`` JSON with embedded buffers.  Returns the path."""
    p = Path(path)
    ext = p.suffix.lower()
    if ext not in (".glb", ".gltf"):
        raise InputError("unsupported glTF file", field="output", value=str(path), allowed=".glb, .gltf")
    if optics is None:
        if material is None:
            raise InputError("give a material or optics", field="material")
        size = float(np.max(mesh.extents))
        optics = gem_optics(
            material, size_mm=size, film_ior=film_ior, film_thickness_nm=film_thickness_nm, name=name
        )
    # flat facets: every triangle its own three vertices, so the exported normals are face normals
    flat = trimesh.Trimesh(
        np.asarray(mesh.triangles).reshape(-1, 3) / _MM_PER_M,
        np.arange(3 * len(mesh.faces)).reshape(-1, 3),
        process=False,
    )
    flat.vertex_normals = np.repeat(np.asarray(mesh.face_normals), 3, axis=0)
    mat_name = f"warpoptics:{name}"
    flat.visual = trimesh.visual.TextureVisuals(
        material=trimesh.visual.material.PBRMaterial(
            name=mat_name, baseColorFactor=[1.0, 1.0, 1.0, 1.0], metallicFactor=0.0, roughnessFactor=0.0
        )
    )
    scene = trimesh.Scene()
    scene.add_geometry(flat, geom_name=name, node_name=name)

    def add_extensions(tree: dict) -> None:
        _set_view_targets(tree)
        used = set(tree.get("extensionsUsed", []))
        for m in tree.get("materials", []):
            if m.get("name") == mat_name:
                m.setdefault("extensions", {}).update(_extensions(optics))
                used.update(m["extensions"])
        tree["extensionsUsed"] = sorted(used)

    kw = {"include_normals": True, "tree_postprocessor": add_extensions}
    if ext == ".glb":
        data = trimesh.exchange.gltf.export_glb(scene, **kw)
    else:
        files = trimesh.exchange.gltf.export_gltf(scene, embed_buffers=True, **kw)
        tree = json.loads(files["model.gltf"])
        _set_view_targets(tree)  # trimesh builds a .gltf's views after the hook
        data = json.dumps(tree).encode("utf-8")
    with atomic_path(p) as tmp:  # a crash never leaves a half-written file
        Path(tmp).write_bytes(data)
    return p


def _read_json(p: Path) -> dict:
    raw = p.read_bytes()
    if raw[:4] == b"glTF":
        # GLB: 12-byte header, then the JSON chunk (length, type "JSON", data)
        length, kind = struct.unpack_from("<I4s", raw, 12)
        if kind != b"JSON":
            raise InputError("GLB without a JSON chunk", field="path", value=str(p))
        return json.loads(raw[20 : 20 + length])
    return json.loads(raw)


def _optics_of(m: dict, name: str, file: str | None = None) -> GltfOptics:
    """The optics of glTF material ``m``, every number checked (finite, in range) with an
    InputError naming the file, the material and the extension's key."""
    from .. import validate as val

    where = f"materials[{name!r}].extensions."

    def num(table: dict, ext: str, key: str, default: float, **rng) -> float:
        if not isinstance(table, dict):
            raise InputError("must be an object", file=file, field=where + ext, value=type(table).__name__)
        return float(val.number(table.get(key, default), file=file, field=f"{where}{ext}.{key}", **rng))

    ext = m.get("extensions", {})
    if not isinstance(ext, dict):
        raise InputError("must be an object", file=file, field=where[:-1], value=type(ext).__name__)
    ior = num(
        ext.get("KHR_materials_ior", {}), "KHR_materials_ior", "ior", 1.5, lo=1.0, hi=10.0
    )  # spec default
    disp = num(ext.get("KHR_materials_dispersion", {}), "KHR_materials_dispersion", "dispersion", 0.0, lo=0.0)
    vol = ext.get("KHR_materials_volume", {})
    thickness_mm = num(vol, "KHR_materials_volume", "thicknessFactor", 0.0, lo=0.0) * _MM_PER_M
    absorption = (0.0, 0.0, 0.0)
    if "attenuationDistance" in vol:
        d_mm = num(vol, "KHR_materials_volume", "attenuationDistance", 1.0, lo=0.0, lo_open=True) * _MM_PER_M
        colour = val.rgb(
            vol.get("attenuationColor", [1.0, 1.0, 1.0]),
            file=file,
            field=f"{where}KHR_materials_volume.attenuationColor",
            hi=1.0,
        )
        absorption = tuple(max(0.0, -math.log(max(float(c), 1e-30)) / d_mm) for c in colour)
    film = ext.get("KHR_materials_iridescence")
    film_kw: dict = {"film_ior": None, "film_thickness_nm": None}
    if film:
        film_kw = {
            "film_ior": num(film, "KHR_materials_iridescence", "iridescenceIor", 1.3, lo=1.0, hi=10.0),
            "film_thickness_nm": num(
                film, "KHR_materials_iridescence", "iridescenceThicknessMaximum", 400.0, lo=0.0, hi=1.0e5
            ),
        }
    return GltfOptics(
        ior=ior,
        abbe=20.0 / disp if disp > 0 else math.inf,
        absorption_rgb=absorption,
        thickness_mm=thickness_mm or 1.0,
        name=name.removeprefix("warpoptics:"),
        **film_kw,
    )


def import_gltf(path) -> list[GltfGem]:
    """The meshes of a glTF 2.0 file (``.glb``/``.gltf``), in millimetres with their node
    transforms applied, each with its material's :class:`GltfOptics`."""
    p = Path(path)
    if not p.is_file():
        raise InputError("glTF file not found", field="path", value=str(path))
    try:
        tree = _read_json(p)
        scene = trimesh.load(p, force="scene", process=False)
    except (ValueError, KeyError, json.JSONDecodeError, struct.error) as exc:
        raise InputError(f"unreadable glTF file ({exc})", field="path", value=str(path)) from None
    by_name = {m.get("name", ""): m for m in tree.get("materials", [])}
    gems = []
    for node in scene.graph.nodes_geometry:
        xf, geom_name = scene.graph[node]
        g = scene.geometry[geom_name]
        mat = getattr(getattr(g, "visual", None), "material", None)
        mname = getattr(mat, "name", None) or ""
        mesh = trimesh.Trimesh(g.vertices, g.faces, process=False)
        mesh.apply_transform(xf)
        mesh.apply_scale(_MM_PER_M)
        mesh.merge_vertices()
        optics = _optics_of(by_name.get(mname, {}), mname or geom_name, file=str(p))
        gems.append(GltfGem(mesh=mesh, optics=optics))
    return gems

"""Our scenes as Mitsuba 3 scenes: the independent peer of the renderer's tests and benchmark.

``mitsuba_scene_dict(scene, directory)`` turns a :class:`~warpoptics.scene.Scene` into a
``mi.load_dict`` dictionary with the same meshes (built as the renderer builds them, written as
flat-shaded PLY files), a ``dielectric`` BSDF with each stone's index at one wavelength (a
non-dispersive comparison), the same perspective camera and the same environment light.
``render_mitsuba(scene, spp=...)`` renders it and returns images in our conventions: CIE Y and
the Y-weighted Stokes vector S0..S3 in the camera frame (x = image right, y = image up).

Conventions matched (each checked in ``tests/test_mitsuba.py``; how: docs/design/mitsuba_comparison.md):
- Camera: ``perspective``, ``fov_axis = "y"``, ``to_world = look_at(...)``, a ``box`` filter.
- Environment: a map is *baked* for Mitsuba's y-up ``envmap`` through our own
  ``environment_radiance`` (:data:`ENVMAP_TO_WORLD`), ``W x (2H + 1)`` texels so that Mitsuba's
  bilinear interpolation reproduces ours; ``constant`` becomes a ``constant`` emitter.
- Stokes vectors: Mitsuba's ``stokes`` integrator uses our frame and handedness, so
  :data:`STOKES_SIGNS` is all +1 (flipping any sign breaks the test).
- ``max_depth``: Mitsuba counts the emitter vertex (ours + 1); ``ext_ior`` is our ambient index.

Mitsuba is an optional dependency (the ``test`` and ``bench`` extras), imported lazily; its LLVM
variants need ``DRJIT_LIBLLVM_PATH`` (Debian: libllvm19,
``/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1``).

References: Jakob, Speierer, Roussel et al. 2022, Mitsuba 3 (plugins ``envmap``,
``perspective``, ``dielectric``, ``stokes``; ``include/mitsuba/render/mueller.h``); CIE 015:2018.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np
import warp as wp

from ..atomic import atomic_path
from ..color import SRGB_TO_XYZ, xyz_to_rgb
from ..device import elementwise, get_device
from ..errors import InputError
from ..scene import Scene
from ..spectra import SpectralTables, cmf_xyz, spectral_tables
from ..stages.environment import Environment, EnvironmentLight, environment_radiance, latlong_directions
from .objects import build_objects

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "ENVMAP_TO_WORLD",
    "STOKES_SIGNS",
    "bake_environment",
    "environment_rgb",
    "mitsuba_directions",
    "bake_latlong",
    "mitsuba_scene_dict",
    "load_mitsuba_scene",
    "render_mitsuba",
]

#: Rotation (world = R @ local) that turns Mitsuba's y-up envmap frame into our z-up world:
#: local y -> world z, local -z (u = 0) -> world x, local x -> world -y.  det = +1.
ENVMAP_TO_WORLD = np.array([[0.0, 0.0, -1.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])

#: Multipliers that turn Mitsuba's stokes-integrator S0..S3 into ours: all +1 (same frame and
#: handedness; measured by tests/test_mitsuba.py::test_stokes_against_mitsuba).
STOKES_SIGNS = np.array([1.0, 1.0, 1.0, 1.0])


# ----------------------------------------------------------------------------------------------
# kernels


@wp.func
def environment_xyz(env: Environment, tables: SpectralTables, direction: wp.vec3f, step: float):
    """CIE XYZ (luminance normalisation, Y = 1 for a Y = 1 illuminant) of the environment's
    radiance spectrum toward ``direction``: the trapezoidal rule over 360-830 nm with ``step`` nm
    of ``environment_radiance`` times the colour-matching functions."""
    n = int(wp.floor((tables.lambda_max - tables.lambda_min) / step + 0.5))
    xyz = wp.vec3f(0.0, 0.0, 0.0)
    for k in range(n + 1):
        wl = wp.min(tables.lambda_min + float(k) * step, tables.lambda_max)
        w = step
        if k == 0 or k == n:
            w = 0.5 * step
        xyz += cmf_xyz(tables, wl) * (environment_radiance(env, tables, direction, wl) * w)
    return xyz


@wp.kernel
def _environment_rgb_kernel(
    offset: int,
    direction: wp.array(dtype=wp.vec3f),
    env: Environment,
    tables: SpectralTables,
    step: float,
    rgb: wp.array(dtype=wp.vec3f),
):
    i = wp.tid() + offset
    rgb[i] = xyz_to_rgb(environment_xyz(env, tables, wp.normalize(direction[i]), step))


# ----------------------------------------------------------------------------------------------
# environment


def environment_rgb(light: EnvironmentLight, directions, *, step: float = 1.0, device=None) -> np.ndarray:
    """Linear-sRGB colour (XYZ of our spectral radiance, converted) of the environment toward
    world ``directions`` ``(..., 3)``.  Wraps :func:`environment_xyz`."""
    (rgb,) = elementwise(
        _environment_rgb_kernel,
        [(directions, wp.vec3f)],
        [wp.vec3f],
        extra=[light.struct, spectral_tables(device), float(step)],
        device=device,
    )
    return rgb


def mitsuba_directions(width: int, height: int) -> np.ndarray:
    """World directions ``(height, width, 3)`` of the texels of a Mitsuba ``envmap`` of
    ``width x height`` with ``to_world`` = :data:`ENVMAP_TO_WORLD` (Mitsuba: u = (i + 0.5) / W,
    v = j / (H - 1), local direction (sin phi sin theta, cos theta, -cos phi sin theta))."""
    u = (np.arange(width) + 0.5) / width
    v = np.arange(height) / (height - 1)
    phi = 2.0 * np.pi * u[None, :]
    theta = np.pi * v[:, None]
    local = np.stack(
        np.broadcast_arrays(
            np.sin(phi) * np.sin(theta), np.cos(theta) + 0 * phi, -np.cos(phi) * np.sin(theta)
        ),
        axis=-1,
    )
    return local @ ENVMAP_TO_WORLD.T


def bake_latlong(
    light: EnvironmentLight,
    width: int = 1024,
    height: int = 512,
    *,
    convention: str = "blender",
    step: float = 1.0,
    device=None,
) -> np.ndarray:
    """Our environment (procedural or not) as a lat-long map ``(height, width, 3)`` in
    ``convention`` (not rotated: read it back with ``rotation = 0``), linear sRGB >= 0 (for an
    EXR that both renderers read, or that Blender shows as we do with the default convention)."""
    rgb = environment_rgb(
        light, latlong_directions(width, height, convention).astype(np.float32), step=step, device=device
    )
    return np.ascontiguousarray(np.maximum(rgb, 0.0), dtype=np.float32)


def bake_environment(
    light: EnvironmentLight,
    *,
    width: int | None = None,
    height: int | None = None,
    step: float = 1.0,
    device=None,
) -> np.ndarray:
    """A Mitsuba lat-long bitmap ``(H, W, 3)`` (linear sRGB, >= 0) of our environment, to be used
    with ``to_world`` = :data:`ENVMAP_TO_WORLD`.  Lat-long maps of ``w x h`` default to ``w x
    (2h + 1)`` (texel-exact, see the module docstring); procedural maps to 1024 x 513."""
    if light.struct.kind == 4 and width is None and height is None:
        h, w = light.texture.shape[:2]
        width, height = w, 2 * h + 1
        if w % 2:
            raise InputError(
                "a lat-long map exported to Mitsuba needs an even width", field="light.map", value=w
            )
    width = int(width or 1024)
    height = int(height or (width // 2 + 1))
    if width < 2 or height < 3:
        raise InputError(
            "environment bake too small", field="width x height", value=(width, height), allowed=">= 2 x 3"
        )
    rgb = environment_rgb(
        light, mitsuba_directions(width, height).astype(np.float32), step=step, device=device
    )
    return np.ascontiguousarray(np.maximum(rgb, 0.0), dtype=np.float32)


# ----------------------------------------------------------------------------------------------
# scene


def _write_ply(path: Path, vertices: np.ndarray, faces: np.ndarray) -> None:
    v = np.ascontiguousarray(vertices, dtype="<f4")
    f = np.ascontiguousarray(faces, dtype="<u4")
    rec = np.empty(len(f), dtype=[("n", "u1"), ("i", "<u4", (3,))])
    rec["n"] = 3
    rec["i"] = f
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {len(v)}\nproperty float x\nproperty float y\nproperty float z\n"
        f"element face {len(f)}\nproperty list uchar uint vertex_indices\nend_header\n"
    )
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        fh.write(header.encode("ascii"))
        fh.write(v.tobytes())
        fh.write(rec.tobytes())


def _stone_index(mat, wavelength: float, where: str, file) -> float:
    from ..materials.dispersion import Biaxial, Uniaxial

    if isinstance(mat, (Uniaxial, Biaxial)):
        raise InputError(
            "Mitsuba's dielectric is isotropic: a birefringent stone cannot be exported",
            file=file,
            field=f"{where}.material",
        )
    n = float(np.asarray(mat.n(np.array([wavelength]))).ravel()[0])
    a = float(np.asarray(mat.alpha(np.array([wavelength]))).ravel()[0])
    zoning = getattr(mat, "zoning", None)
    for z in zoning.absorption if zoning is not None else ():  # a colour-zoned stone's zones
        a = max(a, float(np.asarray(z.alpha(np.array([wavelength]))).max()))
    if a > 0.0:
        raise InputError(
            "Mitsuba's dielectric is clear: an absorbing stone cannot be exported",
            file=file,
            field=f"{where}.material",
            value=f"alpha = {a:g} /mm at {wavelength} nm",
        )
    return n


def mitsuba_scene_dict(
    scene: Scene,
    directory: str | os.PathLike,
    *,
    wavelength: float = 589.3,
    spp: int = 64,
    seed: int = 0,
    max_depth: int | None = None,
    stokes: bool = False,
    rr_depth: int = 5,
    sampler: str = "independent",
    env_width: int | None = None,
    env_height: int | None = None,
    env_step: float = 1.0,
    device=None,
) -> dict:
    """A ``mi.load_dict`` dictionary of ``scene`` (a Mitsuba variant must be set).

    ``directory``: where the PLY meshes are written (must exist until ``mi.load_dict``).
    ``wavelength`` (nm): where each stone's index is taken.  ``max_depth``: ours (interfaces per
    path), default the scene's; Mitsuba gets ``max_depth + 1``.  ``stokes``: wrap the path
    tracer in the ``stokes`` integrator (polarized variants).  ``env_width``, ``env_height``,
    ``env_step``: the envmap bake (see :func:`bake_environment`).
    """
    import mitsuba as mi

    device = get_device(device)
    cam = scene.camera
    if cam.type != "perspective":
        raise InputError(
            "only perspective cameras are exported to Mitsuba",
            file=scene.path,
            field="camera.type",
            value=cam.type,
            allowed="perspective",
        )
    directory = Path(directory)
    built = build_objects(scene.objects, file=scene.path)
    meshes, mats = built.meshes, built.materials
    d = {"type": "scene"}
    ambient = float(scene.render.ambient_index)
    for i, ((mesh, xf), mat) in enumerate(zip(meshes, mats, strict=True)):
        verts = np.asarray(mesh.vertices, dtype=np.float64) @ xf[:3, :3].T + xf[:3, 3]
        faces = np.asarray(mesh.faces, dtype=np.int64)
        if np.linalg.det(xf[:3, :3]) < 0:
            faces = faces[:, ::-1]
        path = directory / f"object_{i}.ply"
        _write_ply(path, verts, faces)
        n = _stone_index(mat, wavelength, f"object.{i}", scene.path)
        d[f"object_{i}"] = {
            "type": "ply",
            "filename": str(path),
            "face_normals": True,
            "bsdf": {"type": "dielectric", "int_ior": n, "ext_ior": ambient},
        }
    light = EnvironmentLight(scene.lights[0], device)
    if light.struct.kind == 0:  # constant: a flat spectrum, as ours (CIE E)
        d["light"] = {
            "type": "constant",
            "radiance": {"type": "uniform", "value": float(light.config.intensity)},
        }
    else:
        bitmap = bake_environment(light, width=env_width, height=env_height, step=env_step, device=device)
        m = np.eye(4)
        m[:3, :3] = ENVMAP_TO_WORLD
        d["light"] = {
            "type": "envmap",
            "bitmap": mi.Bitmap(bitmap),
            "to_world": mi.ScalarTransform4f(m.tolist()),
        }
    depth = scene.render.max_depth if max_depth is None else int(max_depth)
    integrator = {"type": "path", "max_depth": depth + 1, "rr_depth": int(rr_depth), "hide_emitters": False}
    d["integrator"] = {"type": "stokes", "integrator": integrator} if stokes else integrator
    d["sensor"] = {
        "type": "perspective",
        "fov": float(cam.fov),
        "fov_axis": "y",
        "near_clip": 1.0e-3,
        "far_clip": 1.0e7,
        "to_world": mi.ScalarTransform4f().look_at(
            origin=list(cam.position), target=list(cam.look_at), up=list(cam.up)
        ),
        "film": {
            "type": "hdrfilm",
            "width": int(cam.width),
            "height": int(cam.height),
            "rfilter": {"type": "box"},
            "pixel_format": "rgb",
            "sample_border": False,
        },
        "sampler": {"type": sampler, "sample_count": int(spp), "seed": int(seed)},
    }
    return d


def load_mitsuba_scene(scene: Scene, **kw):
    """``mi.load_dict(mitsuba_scene_dict(scene, tmpdir, **kw))`` (the meshes in a temporary
    directory that is removed afterwards)."""
    import mitsuba as mi

    with tempfile.TemporaryDirectory(prefix="warpoptics_mi_") as tmp:
        return mi.load_dict(mitsuba_scene_dict(scene, tmp, **kw))


def _luminance(rgb: np.ndarray) -> np.ndarray:
    return rgb @ SRGB_TO_XYZ[1]


def render_mitsuba(
    scene: Scene | str | os.PathLike,
    *,
    spp: int = 64,
    seed: int = 0,
    variant: str | None = None,
    mi_scene=None,
    **kw,
) -> dict:
    """Render ``scene`` with Mitsuba 3 and return ``{"rgb": (H, W, 3) linear sRGB, "y": (H, W)
    luminance, "stokes": (H, W, 4) Y-weighted S0..S3 in our frame (polarized variants, else
    S1..S3 = 0), "seconds": render time}``.  ``variant`` (e.g. "scalar_spectral_polarized",
    "llvm_ad_spectral") is set first when given; polarized variants use the stokes integrator.
    ``mi_scene``: a scene loaded before (``load_mitsuba_scene``), to render it again."""
    import time

    import mitsuba as mi

    if variant is not None:
        mi.set_variant(variant)
    if not isinstance(scene, Scene):
        scene = Scene.load(scene)
    polarized = "polarized" in mi.variant()
    if mi_scene is None:
        mi_scene = load_mitsuba_scene(scene, spp=spp, seed=seed, stokes=polarized, **kw)
    t0 = time.perf_counter()
    img = np.asarray(mi.render(mi_scene, spp=int(spp), seed=int(seed)), dtype=np.float64)
    seconds = time.perf_counter() - t0
    rgb = img[..., :3]
    y = _luminance(rgb)
    stokes = np.zeros(y.shape + (4,))
    stokes[..., 0] = y
    if polarized:
        names = list(mi_scene.integrator().aov_names())
        for i in range(4):
            c = [3 + names.index(f"S{i}.{ch}") for ch in "RGB"]
            stokes[..., i] = _luminance(img[..., c]) * STOKES_SIGNS[i]
    return {"rgb": rgb, "y": y, "stokes": stokes, "seconds": seconds, "scene": mi_scene}

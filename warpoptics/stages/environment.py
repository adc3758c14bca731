"""The environment light: spectral radiance arriving from every direction at infinity.

Kinds (``Environment.kind``):
- ``constant``: a flat spectrum (CIE E) times ``intensity`` everywhere — the white furnace;
- ``dome``: uniform white (D65, Y = intensity) over the upper hemisphere, black below — the
  lighting of the light-return metrics (GemRay's ``ISO``, :mod:`warpoptics.grading`);
- ``cos``: D65 over the upper hemisphere with radiance ``intensity * cos(zenith)`` — GemRay's
  ``COS`` lighting;
- ``studio``: dark surroundings with soft boxes overhead and at the sides, like the light boxes
  over a plane of the three-wavelength diamond paper;
- ``sky``: a smooth blue sky over a grey ground;
- ``latlong``: an equirectangular RGB map (EXR/HDR/PNG through OpenImageIO).

Lat-long maps (z up, row 0 at the zenith, v = acos(z) / pi): ``"blender"`` (the default,
u = 0.5 - atan2(y, x) / 2 pi, as Blender's Environment Texture and Poly Haven place a panorama),
``"mitsuba"`` (Mitsuba 3's ``envmap`` with ``to_world = rotate(x, 90 deg)``: Blender's layout
turned 90 deg about z) and ``"mirrored"`` (the mirror image of ``"blender"``, warpoptics' earlier
mapping); docs/conventions.md, "Environment maps", has the layouts.  ``rotation`` (degrees) turns
the map counter-clockwise about +z, seen from above, after the convention placed it; both are
one world -> map matrix (:func:`latlong_frame`), so nothing is compiled per convention.

Observer obscuration: ``head_radius_deg`` > 0 blacks out a cone about ``head_direction`` (world,
default the zenith), the grader's head over a face-up stone; the cone is fixed in the world, so a
tilted stone sees the head move across its crown.

RGB radiance becomes a spectrum through D65 x the Mallett–Yuksel sRGB basis
(``spectra.rgb_spectrum_value``), so RGB white is D65; a light ``spectrum`` replaces that white
(``spectra.light_spectrum_value``: an RGB texel c emits dot(c, basis(l)) S(l)).  Defaults: E for
``constant``, D65 for everything else.

References: Blender manual, Environment Texture (Equirectangular) and
``gpu_shader_material_tex_environment.glsl``; Mitsuba 3, emitter ``envmap``
(``src/emitters/envmap.cpp``, ``direction_to_uv``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import warp as wp

from ..device import get_device
from ..errors import InputError
from ..geometry.directions import polar_azimuth
from ..spectra import (
    SpectralTables,
    illuminant_value,
    light_spectrum_row,
    rgb_spectrum_value,
    sample_wavelength,
    srgb_basis_value,
    strategy_id,
)

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "Environment",
    "EnvironmentConfig",
    "EnvironmentLight",
    "environment_radiance",
    "environment_coefficients",
    "environment_basis",
    "spectral_response",
    "environment_spectrum_row",
    "ENV_KINDS",
    "LATLONG_CONVENTIONS",
    "latlong_frame",
    "latlong_uv",
    "latlong_directions",
]

ENV_KINDS = {"constant": 0, "dome": 1, "studio": 2, "sky": 3, "latlong": 4, "cos": 5}
_CONSTANT = wp.constant(0)
_DOME = wp.constant(1)
_STUDIO = wp.constant(2)
_SKY = wp.constant(3)
_LATLONG = wp.constant(4)
_COS = wp.constant(5)

#: Lat-long map conventions (module docstring), each as the matrix that turns world directions
#: into the frame in which Blender's formula reads the map: "mitsuba" is Blender's layout turned
#: by +90 deg about z (atan2(y, x) grows by pi / 2), "mirrored" is y -> -y (a reflection).
LATLONG_CONVENTIONS = {
    "blender": np.eye(3),
    "mitsuba": np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]),
    "mirrored": np.diag([1.0, -1.0, 1.0]),
}


# the brightest environment-map pixel accepted (the sun's disc in a real HDR is ~1e5-1e9)
MAX_MAP_VALUE = 1.0e20


def latlong_frame(convention: str = "blender", rotation_deg: float = 0.0) -> np.ndarray:
    """World -> map-frame matrix (3x3) of a lat-long map in ``convention`` turned by
    ``rotation_deg`` about +z: the map is read at ``u = 0.5 - atan2(m_y, m_x) / 2 pi``,
    ``v = acos(m_z) / pi`` of ``m = M d``."""
    if convention not in LATLONG_CONVENTIONS:
        raise InputError(
            "unknown lat-long convention",
            field="light.convention",
            value=convention,
            allowed=", ".join(LATLONG_CONVENTIONS),
        )
    a = math.radians(rotation_deg)
    c, s = math.cos(a), math.sin(a)
    unrotate = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])  # rotation by -angle about z
    return LATLONG_CONVENTIONS[convention] @ unrotate


def latlong_uv(directions, convention: str = "blender", rotation_deg: float = 0.0) -> np.ndarray:
    """Map coordinates ``(..., 2)`` (u from the left edge, v from the top, both in [0, 1]) at which
    a lat-long map in ``convention`` is read toward world ``directions`` ``(..., 3)`` -- the
    NumPy twin of the kernel's lookup (tests check the two against each other)."""
    d = np.asarray(directions, dtype=np.float64)
    d = d / np.linalg.norm(d, axis=-1, keepdims=True)
    m = d @ latlong_frame(convention, rotation_deg).T
    u = np.mod(0.5 - np.arctan2(m[..., 1], m[..., 0]) / (2.0 * np.pi), 1.0)
    v = np.arccos(np.clip(m[..., 2], -1.0, 1.0)) / np.pi
    return np.stack([u, v], axis=-1)


def latlong_directions(
    width: int, height: int, convention: str = "blender", rotation_deg: float = 0.0
) -> np.ndarray:
    """World directions ``(height, width, 3)`` of the texel centres ((i + 0.5) / W, (j + 0.5) / H)
    of a ``width x height`` lat-long map in ``convention``: the inverse of :func:`latlong_uv`."""
    phi = 2.0 * np.pi * (0.5 - (np.arange(width) + 0.5) / width)[None, :]
    theta = np.pi * ((np.arange(height) + 0.5) / height)[:, None]
    m = np.stack(
        np.broadcast_arrays(
            np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta) + 0.0 * phi
        ),
        axis=-1,
    )
    # M is orthogonal: world = M^T m
    return m @ latlong_frame(convention, rotation_deg)


@wp.struct
class Environment:
    kind: int
    intensity: float
    tint: wp.vec3f  # linear-sRGB multiplier of procedural maps and lat-long maps
    rotation: wp.mat33f  # world -> map frame (latlong_frame: convention and rotation about z)
    texture: wp.array2d(dtype=wp.vec3f)  # lat-long map (height, width), linear sRGB
    width: int
    height: int
    # polarized illumination (polariscope): absorbing axis (world, unit) of an ideal sheet
    # polarizer every environment ray passes (optics.polarizer.sheet_polarizer_coherency);
    # zero: unpolarized.  Set by the Renderer from ``EnvironmentConfig.polarizer`` and the camera.
    polarizer: wp.vec3f
    # observer obscuration: radiance is 0 toward directions d with dot(d, head) > head_cos (world
    # frame); head_cos = 2 (> any cosine) when there is no head
    head: wp.vec3f
    head_cos: float
    # light-spectrum row (spectra.light_spectrum_row) of the light's white; constant and dome
    # always have one (E, D65 by default); -1 for the RGB kinds: the D65 x basis table
    spectrum: int


@wp.func
def _soft_box(d: wp.vec3f, centre: wp.vec3f, cos_radius: float, softness: float):
    # smooth-edged disc on the sphere: 1 inside, 0 outside, a smoothstep over `softness` in cos
    c = wp.dot(d, centre)
    return wp.smoothstep(cos_radius - softness, cos_radius + softness, c)


@wp.func
def _studio_rgb(d: wp.vec3f):
    base = wp.vec3f(0.02, 0.02, 0.022)
    if d[2] < 0.0:
        base = wp.vec3f(0.01, 0.01, 0.01)
    # overhead box (25 deg radius), two side boxes, a back rim box: bright sources on a dark
    # surround, so facets alternate between lit and dark (contrast) as in gem photography
    top = _soft_box(d, wp.vec3f(0.0, 0.0, 1.0), 0.906, 0.02) * 2.5
    left = _soft_box(d, wp.normalize(wp.vec3f(-0.8, -0.5, 0.45)), 0.97, 0.01) * 3.0
    right = _soft_box(d, wp.normalize(wp.vec3f(0.8, -0.5, 0.45)), 0.97, 0.01) * 3.0
    back = _soft_box(d, wp.normalize(wp.vec3f(0.0, 1.0, 0.25)), 0.97, 0.01) * 2.0
    # thin bright strips give sparkle (scintillation) on small facets
    strip = _soft_box(d, wp.normalize(wp.vec3f(0.3, -0.9, 0.8)), 0.997, 0.001) * 8.0
    w = top + left + right + back + strip
    return base + wp.vec3f(w, w, w)


@wp.func
def _sky_rgb(d: wp.vec3f):
    z = d[2]
    if z < 0.0:
        return wp.vec3f(0.18, 0.17, 0.16)
    horizon = wp.vec3f(1.0, 1.0, 1.0)
    zenith = wp.vec3f(0.25, 0.45, 1.0)
    t = wp.sqrt(z)
    sun = _soft_box(d, wp.normalize(wp.vec3f(0.5, -0.3, 0.8)), 0.9995, 0.0002) * 2000.0
    return horizon * (1.0 - t) + zenith * t + wp.vec3f(sun, sun, sun * 0.9)


@wp.func
def _latlong_rgb(env: Environment, d: wp.vec3f):
    # Blender's equirectangular layout in the map frame (module docstring; latlong_uv in NumPy)
    theta, phi = polar_azimuth(d)
    u = 0.5 - phi / (2.0 * wp.pi)
    v = theta / wp.pi
    x = u * float(env.width) - 0.5
    y = v * float(env.height) - 0.5
    x0 = wp.floor(x)
    y0 = wp.floor(y)
    fx = x - x0
    fy = y - y0
    ix0 = int(x0)
    iy0 = int(y0)
    # wrap in azimuth, clamp in elevation: u in [0, 1] puts ix0 in [-1, width - 1], so one
    # conditional add wraps it (three integer modulos, i.e. divisions, cost ~7 ns of the ~45 ns
    # lookup; scripts/bench/bench_lane_cost.py); the clamp keeps a non-finite direction's index
    # inside the map, as the modulo did
    if ix0 < 0:
        ix0 += env.width
    ix0 = wp.clamp(ix0, 0, env.width - 1)
    ix1 = ix0 + 1
    if ix1 >= env.width:
        ix1 = 0
    iy1 = wp.clamp(iy0 + 1, 0, env.height - 1)
    iy0 = wp.clamp(iy0, 0, env.height - 1)
    a = env.texture[iy0, ix0] * (1.0 - fx) + env.texture[iy0, ix1] * fx
    b = env.texture[iy1, ix0] * (1.0 - fx) + env.texture[iy1, ix1] * fx
    return a * (1.0 - fy) + b * fy


@wp.func
def environment_coefficients(env: Environment, direction: wp.vec3f):
    """The radiance toward unit ``direction`` (world frame) as coefficients of the environment's
    three basis spectra (:func:`environment_basis`): linear sRGB (times intensity and tint) for
    the RGB kinds (studio, sky, lat-long); ``(intensity, 0, 0)`` (0 below a dome's horizon) for
    the spectral kinds."""
    if wp.dot(direction, env.head) > env.head_cos:
        return wp.vec3f(0.0, 0.0, 0.0)  # the observer's head blocks this direction
    if env.kind == _CONSTANT:
        return wp.vec3f(env.intensity, 0.0, 0.0)
    d = env.rotation * direction
    if env.kind == _DOME:
        if d[2] < 0.0:
            return wp.vec3f(0.0, 0.0, 0.0)
        return wp.vec3f(env.intensity, 0.0, 0.0)
    if env.kind == _COS:
        return wp.vec3f(env.intensity * wp.max(d[2], 0.0), 0.0, 0.0)
    rgb = wp.vec3f(0.0, 0.0, 0.0)
    if env.kind == _STUDIO:
        rgb = _studio_rgb(d)
    elif env.kind == _SKY:
        rgb = _sky_rgb(d)
    else:
        rgb = _latlong_rgb(env, d)
    return wp.cw_mul(rgb, env.tint) * env.intensity


@wp.func
def environment_basis(env: Environment, t: SpectralTables, wavelength: float):
    """Values at ``wavelength`` (nm) of the environment's three basis spectra: D65 x the
    Mallett–Yuksel sRGB basis for the RGB kinds, (illuminant, 0, 0) for constant (E), dome and
    cos (D65).  Radiance = dot(coefficients, basis): the wavelength enters only here, so one path
    tree can be weighted for many wavelengths at once."""
    if env.kind == _CONSTANT or env.kind == _DOME or env.kind == _COS:
        return wp.vec3f(illuminant_value(t, env.spectrum, wavelength), 0.0, 0.0)
    if env.spectrum < 0 and wavelength >= t.lambda_min:
        return wp.vec3f(
            rgb_spectrum_value(t, wp.vec3f(1.0, 0.0, 0.0), wavelength),
            rgb_spectrum_value(t, wp.vec3f(0.0, 1.0, 0.0), wavelength),
            rgb_spectrum_value(t, wp.vec3f(0.0, 0.0, 1.0), wavelength),
        )
    # basis x the light's white (D65's ultraviolet below the colour range for the default);
    # the same law as spectra.light_spectrum_value, per basis function
    row = env.spectrum
    if row < 0:
        row = 1
    return srgb_basis_value(t, wavelength) * illuminant_value(t, row, wavelength)


@wp.func
def spectral_response(env: Environment, t: SpectralTables, wavelength: float, weight: wp.vec3f):
    """3x3 matrix R with XYZ = R c for light of unit weight from environment coefficients c
    (environment_coefficients), estimated by one wavelength sample (spectra.sample_wavelength:
    ``wavelength`` and its XYZ ``weight``): the outer product of the weight and the basis
    spectra at that wavelength."""
    return wp.outer(weight, environment_basis(env, t, wavelength))


@wp.kernel
def _response_kernel(
    env: Environment, t: SpectralTables, strategy: int, n: int, out: wp.array(dtype=wp.mat33d)
):
    # one row of the quadrature: the midpoints u = (j + 1/2) / n of one stratum-free draw
    j = wp.tid()
    wl, w = sample_wavelength(t, strategy, (float(j) + 0.5) / float(n), 0, 1)
    r = spectral_response(env, t, wl, w)
    out[j] = wp.mat33d(r)


@wp.func
def environment_radiance(env: Environment, t: SpectralTables, direction: wp.vec3f, wavelength: float):
    """Spectral radiance arriving from ``direction`` (unit, world frame, pointing away from the
    scene toward the environment) at ``wavelength`` (nm).  Unpolarized."""
    return wp.dot(environment_coefficients(env, direction), environment_basis(env, t, wavelength))


@dataclass(frozen=True)
class EnvironmentConfig:
    """Settings of the environment light (scene ``[[light]] type = "environment"`` or
    ``"constant"``).  ``map`` is a built-in name or a path to an .exr/.hdr lat-long image;
    ``convention`` how that image is laid out (:data:`LATLONG_CONVENTIONS`, see the module
    docstring; procedural maps are defined in world directions and ignore it)."""

    map: str = "studio"
    intensity: float = 1.0
    tint: tuple[float, float, float] = (1.0, 1.0, 1.0)
    rotation_deg: float = 0.0  # rotation of the map about +z, counter-clockwise seen from above
    convention: str = "blender"
    # an ideal linear polarizer facing the camera in front of the light: transmission axis in
    # degrees from image right toward image up (None: unpolarized light); see optics.polarizer
    polarizer: float | None = None
    # the observer's head: a black cone of this angular radius (degrees, 0: none) about
    # head_direction (world; normalised here)
    head_radius_deg: float = 0.0
    head_direction: tuple[float, float, float] = (0.0, 0.0, 1.0)
    # the light's white (module docstring): a name of spectra.light_spectrum_names() -- CIE
    # illuminant, UV lamp or a registered measured spectrum; None: E (constant) or D65
    spectrum: str | None = None
    source: str | None = field(default=None, compare=False)  # scene file, for messages

    def __post_init__(self):
        if self.spectrum is not None:
            light_spectrum_row(self.spectrum, file=self.source, field="light.spectrum")
        if not (math.isfinite(self.intensity) and self.intensity >= 0):
            raise InputError(
                "must be a finite number >= 0",
                file=self.source,
                field="light.intensity",
                value=self.intensity,
            )
        if len(self.tint) != 3 or not all(math.isfinite(c) and c >= 0 for c in self.tint):
            raise InputError(
                "must be three finite numbers >= 0", file=self.source, field="light.tint", value=self.tint
            )
        if self.polarizer is not None and not (
            isinstance(self.polarizer, (int, float))
            and not isinstance(self.polarizer, bool)
            and math.isfinite(self.polarizer)
        ):
            raise InputError(
                'must be an angle in degrees or "none"',
                file=self.source,
                field="light.polarizer",
                value=self.polarizer,
            )
        if not (
            isinstance(self.head_radius_deg, (int, float))
            and math.isfinite(self.head_radius_deg)
            and 0.0 <= self.head_radius_deg <= 90.0
        ):
            raise InputError(
                "must be an angle in degrees in [0, 90]",
                file=self.source,
                field="light.head_radius",
                value=self.head_radius_deg,
            )
        h = np.asarray(self.head_direction, dtype=np.float64)
        if h.shape != (3,) or not np.isfinite(h).all() or np.linalg.norm(h) == 0:
            raise InputError(
                "must be a non-zero vector [x, y, z]",
                file=self.source,
                field="light.head_direction",
                value=self.head_direction,
            )
        object.__setattr__(self, "head_direction", tuple(float(c) for c in h / np.linalg.norm(h)))
        if self.convention not in LATLONG_CONVENTIONS:
            raise InputError(
                "unknown lat-long convention",
                file=self.source,
                field="light.convention",
                value=self.convention,
                allowed=", ".join(LATLONG_CONVENTIONS),
            )


def environment_spectrum_row(kind: int, spectrum: str | None) -> int:
    """The ``Environment.spectrum`` row of an environment of ``kind`` (:data:`ENV_KINDS`) with
    light spectrum ``spectrum``: E (constant) or D65 (dome) when None; -1 (the D65 x basis table)
    for an RGB kind whose white is D65 -- the same values as before light spectra, bit for bit."""
    spectral = kind in (ENV_KINDS["constant"], ENV_KINDS["dome"], ENV_KINDS["cos"])
    if spectrum is None:
        return (0 if kind == ENV_KINDS["constant"] else 1) if spectral else -1
    row = light_spectrum_row(spectrum)
    if not spectral and row == 1:
        return -1
    return row


class EnvironmentLight:
    """Stage owning the environment struct and its texture on a device."""

    def __init__(self, config: EnvironmentConfig, device=None):
        self.config = config
        self.device = get_device(device)
        env = Environment()
        name = config.map
        tex = np.zeros((1, 1, 3), dtype=np.float32)
        if name in ENV_KINDS and name != "latlong":
            env.kind = ENV_KINDS[name]
        else:
            env.kind = ENV_KINDS["latlong"]
            tex = self._load_map(name)
        env.intensity = float(config.intensity)
        env.tint = wp.vec3f(*config.tint)
        # world -> map: rotate by -angle about z, then the convention (lat-long maps only: the
        # procedural maps are defined in world directions)
        convention = config.convention if env.kind == ENV_KINDS["latlong"] else "blender"
        env.rotation = wp.mat33f(*(float(x) for x in latlong_frame(convention, config.rotation_deg).ravel()))
        env.texture = wp.array(tex, dtype=wp.vec3f, device=self.device)
        env.height, env.width = tex.shape[0], tex.shape[1]
        env.polarizer = wp.vec3f(0.0, 0.0, 0.0)  # unpolarized (the Renderer sets a polarizer)
        env.head = wp.vec3f(*config.head_direction)
        env.head_cos = math.cos(math.radians(config.head_radius_deg)) if config.head_radius_deg > 0 else 2.0
        env.spectrum = environment_spectrum_row(env.kind, config.spectrum)
        self.struct = env
        self.texture = tex

    def exact_response(self, tables: SpectralTables, strategy: str, n: int = 4096) -> np.ndarray:
        """The expectation over the wavelength draw of :func:`spectral_response` (float64 3x3):
        XYZ = R c integrates the whole spectrum of environment light with coefficients c, the
        noise-free estimate for path trees that do not depend on the wavelength (non-dispersive,
        non-absorbing scenes).  Midpoint quadrature in the sampling variable u with ``n`` nodes
        (4096: 0.11 nm steps over 360-830 nm, far below the 1 nm CMF tables; the same sampling
        density as the estimator, so importance sampling integrates the same integrand)."""
        out = wp.empty(n, dtype=wp.mat33d, device=self.device)
        wp.launch(
            _response_kernel,
            dim=n,
            inputs=[self.struct, tables, strategy_id(strategy), n, out],
            device=self.device,
        )
        return out.numpy().mean(axis=0)

    def _load_map(self, path: str) -> np.ndarray:
        from ..film.image import read_image

        field_name = "light.map"
        allowed = ", ".join(k for k in ENV_KINDS if k != "latlong") + ", or an .exr/.hdr/.png path"
        from pathlib import Path

        p = Path(path)
        if not p.suffix:
            raise InputError(
                "unknown environment map",
                file=self.config.source,
                field=field_name,
                value=path,
                allowed=allowed,
            )
        if not p.is_file():
            raise InputError(
                "environment map file not found",
                file=self.config.source,
                field=field_name,
                value=path,
                allowed=allowed,
            )
        try:
            pixels, _names = read_image(p)
        except InputError as exc:
            raise InputError(
                f"unreadable environment map ({exc.message})",
                file=self.config.source,
                field=field_name,
                value=path,
            ) from None
        h, w, c = pixels.shape
        if c < 3:
            pixels = np.repeat(pixels[..., :1], 3, axis=2)
        pixels = pixels[..., :3]
        if w != 2 * h:
            raise InputError(
                f"a lat-long map must be twice as wide as high, got {w}x{h}",
                file=self.config.source,
                field=field_name,
                value=path,
            )
        if not np.isfinite(pixels).all() or pixels.min() < 0:
            raise InputError(
                "the map has negative or non-finite pixels",
                file=self.config.source,
                field=field_name,
                value=path,
            )
        if pixels.max() > MAX_MAP_VALUE:
            # finite float32 values near 3e38 overflow to inf in the map's row sums (importance
            # sampling) and in radiance x throughput: bright, but never that bright
            raise InputError(
                f"the map has pixels up to {float(pixels.max()):.3g}; scale it down (intensity = ...)",
                file=self.config.source,
                field=field_name,
                value=path,
                allowed=f"pixel values <= {MAX_MAP_VALUE:g}",
            )
        if p.suffix.lower() not in (".exr", ".hdr"):
            # display-encoded 8-bit image: decode sRGB to linear
            from colour import cctf_decoding

            pixels = np.asarray(cctf_decoding(pixels, function="sRGB"), dtype=np.float32)
        return np.ascontiguousarray(pixels, dtype=np.float32)

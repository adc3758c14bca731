"""The progressive preview: a :class:`~.render.Renderer` adding passes of one sample per pixel into
a film the preview owns, restarted whenever the view or the scene changes.

``Preview(scene)`` builds the Renderer once (kernels load from the cache, nothing is compiled
afterwards: every setting below is a value passed to the same kernel).  :meth:`Preview.step`
renders one pass (``Renderer.render_pass``: 1 spp, ``wavelengths`` wavelengths per sample,
default 1) and :meth:`Preview.frame` shows the mean of the passes so far.  Passes continue each
pixel's R2 sequence in blocks of :data:`BLOCK` samples (then a fresh random rotation), so the
preview converges like a render of that many spp.  Where pixel beams apply, the full-resolution
passes are beams (the whole spectrum in a lattice of :data:`BEAM_WAVELENGTHS`), rendered in bands
of rows of about :data:`BAND_SECONDS`: a frame per band.

Wavelengths are drawn by importance (XYZ-weighted, ``spectra.sample_wavelength``) unless asked
otherwise: an unbiased estimator of the same image as the scene's own strategy, and with one
wavelength per sample the cheapest to a given noise (noise² x CPU time of 4 passes of
``diamond.toml`` at 100x75: importance 0.080, stratified 0.27, importance with 3 wavelengths
0.099; ``rgb3`` scenes keep their three wavelengths).

What can change (:meth:`Preview.update`, names as :meth:`Preview.controls` lists them):

* the orbit of the camera about its ``look_at`` point: ``azimuth`` (degrees about world +z,
  counter-clockwise seen from above, 0 = +x), ``elevation`` (degrees above the horizontal plane
  through ``look_at``) and ``distance`` (mm).  Only the camera struct changes;
* the cut of the first object (``object.0.crown_angle``, ``.pavilion_angle``, ``.table`` where
  its shape takes them), its material (a library name) and the environment light
  (``light.0.intensity``, ``.rotation``, ``.map``): the scene is re-validated
  (``Scene.with_overrides``) and the Renderer rebuilt (new mesh and material table: data, not code);
* ``render.exposure``: display only, the accumulation goes on.

Every change but the exposure restarts the accumulation (the film is cleared, ``passes`` = 0) and
increments :attr:`Preview.generation`.  The first step after a restart renders a *draft*: one
pass at 1/``draft_scale`` of the resolution (default 2: a quarter of the pixels) into a small
film of its own, shown enlarged (nearest pixel) until the first full-resolution pass is in.
While the camera is dragged every frame is such a draft (each one a restart), which is how the
view keeps up with the mouse; when it stops, full-resolution passes follow.  Bad values raise a
one-line ``InputError`` naming the control, the value and the allowed range, and leave the
preview as it was.
"""

from __future__ import annotations

import inspect
import math
import threading
import time
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import warp as wp

from .. import validate as val
from ..device import get_device
from ..errors import InputError
from ..film.image import Image
from ..geometry import cuts
from ..materials.library import names as material_names
from ..scene import Scene
from ..stages.camera import Camera, CameraConfig
from .render import Renderer

__all__ = [
    "Preview",
    "PreviewFilm",
    "Control",
    "Orbit",
    "BLOCK",
    "BEAM_WAVELENGTHS",
    "BAND_SECONDS",
    "ORBIT_KEYS",
]

# samples per R2 block: pass p continues sample p % BLOCK of block p // BLOCK (a pixel's skip of
# its earlier camera draws grows with the sample index; blocks keep it below 3 x BLOCK x wavelengths)
BLOCK = 64
#: wavelengths of a pass in pixel beams (one stratified lattice: no colour speckle)
BEAM_WAVELENGTHS = 4
#: seconds a band of a pass in pixel beams aims at (a frame each while refining)
BAND_SECONDS = 0.15
ORBIT_KEYS = ("azimuth", "elevation", "distance")
_ELEVATION_LIMIT = 89.0  # degrees: the camera never looks along the up axis (no defined image right)
_SCENE_OWN = "(scene)"  # the choice that keeps the scene's own inline material


@dataclass(frozen=True)
class Orbit:
    """Camera position about ``look_at``: ``azimuth`` (degrees about world +z, counter-clockwise
    seen from above, 0 = +x), ``elevation`` (degrees above the plane z = look_at.z), ``distance``
    (mm)."""

    azimuth: float
    elevation: float
    distance: float

    @classmethod
    def from_camera(cls, camera: CameraConfig) -> Orbit:
        off = np.subtract(camera.position, camera.look_at).astype(np.float64)
        d = float(np.linalg.norm(off))  # > 0: CameraConfig refuses position == look_at
        return cls(
            azimuth=math.degrees(math.atan2(off[1], off[0])),
            elevation=math.degrees(math.asin(max(-1.0, min(1.0, off[2] / d)))),
            distance=d,
        )

    def position(self, look_at) -> tuple[float, float, float]:
        """The camera position (mm) this orbit puts about ``look_at``."""
        az, el = math.radians(self.azimuth), math.radians(self.elevation)
        c = math.cos(el)
        x, y, z = (float(v) for v in look_at)
        d = self.distance
        return (x + d * c * math.cos(az), y + d * c * math.sin(az), z + d * math.sin(el))


@dataclass(frozen=True)
class Control:
    """One adjustable value of a preview: ``name`` is an orbit key or a dotted scene path;
    ``kind`` is ``"range"`` (``lo``..``hi`` in steps of ``step``, ``unit``) or ``"choice"``
    (``choices``); ``restarts`` whether a change clears the accumulation."""

    name: str
    label: str
    kind: str
    value: Any
    lo: float = 0.0
    hi: float = 0.0
    step: float = 0.0
    unit: str = ""
    choices: tuple[str, ...] = ()
    restarts: bool = True

    def as_dict(self) -> dict:
        d = {"name": self.name, "label": self.label, "kind": self.kind, "value": self.value}
        d["restarts"] = self.restarts
        if self.kind == "range":
            d.update(lo=self.lo, hi=self.hi, step=self.step, unit=self.unit)
        else:
            d["choices"] = list(self.choices)
        return d


class PreviewFilm:
    """The preview's accumulation buffers, laid out like the Renderer's film (sums over passes):
    ``xyz`` (N, vec3d) CIE XYZ, ``sq`` (N, vec3d) its squares per sample, ``stokes`` (N, vec4d)
    Y-weighted Stokes, ``alpha`` (N, float64) hits, ``rays`` (N, int64), ``stokes_xyz`` (N, 3,
    vec4d); N = width x height, row-major from the top-left pixel."""

    def __init__(self, width: int, height: int, device=None):
        self.width, self.height = int(width), int(height)
        n = self.width * self.height
        dev = get_device(device)
        self.xyz = wp.zeros(n, dtype=wp.vec3d, device=dev)
        self.sq = wp.zeros(n, dtype=wp.vec3d, device=dev)
        self.stokes = wp.zeros(n, dtype=wp.vec4d, device=dev)
        self.alpha = wp.zeros(n, dtype=wp.float64, device=dev)
        self.rays = wp.zeros(n, dtype=wp.int64, device=dev)
        self.stokes_xyz = wp.zeros((n, 3), dtype=wp.vec4d, device=dev)

    def zero(self) -> None:
        for a in (self.xyz, self.sq, self.stokes, self.alpha, self.rays, self.stokes_xyz):
            a.zero_()


def _cut_keys(shape: str) -> tuple[str, ...]:
    """The cut parameters among crown angle, pavilion angle and table that ``shape`` takes
    (the brilliant family forwards its keywords to ``round_brilliant``)."""
    fn = getattr(cuts, shape, None)
    if fn is None:
        return ()
    sig = inspect.signature(fn).parameters
    if any(p.kind == p.VAR_KEYWORD for p in sig.values()):
        sig = {**sig, **inspect.signature(cuts.round_brilliant).parameters}
    return tuple(k for k in ("crown_angle", "pavilion_angle", "table") if k in sig)


def _default_param(shape: str, key: str):
    fn = getattr(cuts, shape)
    p = inspect.signature(fn).parameters.get(key) or inspect.signature(cuts.round_brilliant).parameters[key]
    return p.default


# slider ranges of the cut parameters: wide enough to show light leaking through a too deep or
# too shallow pavilion (Tolkowsky's ideal: crown 34.5 deg, pavilion 40.75 deg, table 53 %)
_CUT_RANGES = {
    "crown_angle": ("crown angle", 20.0, 45.0, 0.25, "deg"),
    "pavilion_angle": ("pavilion angle", 36.0, 46.0, 0.05, "deg"),
    "table": ("table (of the diameter)", 0.40, 0.75, 0.005, ""),
}


class Preview:
    """A progressive preview of a camera scene.

    ``width``/``height`` override the camera's image size; ``draft_scale`` the resolution divider
    of the draft pass after each restart (1: no draft); ``wavelengths`` sets the wavelengths
    per sample of a pass and ``spectral`` how they are drawn (default ``"importance"``; an
    ``rgb3`` scene keeps its 3 wavelengths); ``max_passes``
    stops adding passes once reached (the image is then that many spp); ``threads`` as in
    :func:`warpoptics.device.launch_tiled`.  ``estimator`` (``"auto"``, ``"beam"``, ``"point"``):
    where pixel beams apply (as ``render.estimator`` decides) the full-resolution passes are
    beams of ``beam_wavelengths`` stratified wavelengths, rendered in bands of rows of about
    ``band_seconds`` each (a frame per band; rows not yet in show the draft); else, and for the
    draft, point samples as above.  ``step()``, ``update()`` and ``frame()`` may be called from
    different threads: passes and rebuilds are serialized by a lock.
    """

    def __init__(
        self,
        scene: Scene,
        *,
        width: int | None = None,
        height: int | None = None,
        wavelengths: int = 1,
        spectral: str | None = None,
        max_passes: int = 4096,
        draft_scale: int = 2,
        device=None,
        threads: int | None = None,
        estimator: str = "auto",
        beam_wavelengths: int = BEAM_WAVELENGTHS,
        band_seconds: float = BAND_SECONDS,
    ):
        self.device = get_device(device)
        self.threads = threads
        self.max_passes = val.integer(max_passes, field="max_passes", lo=1, hi=1 << 30)
        self.draft_scale = val.integer(draft_scale, field="draft_scale", lo=1, hi=64)
        if spectral is None:
            spectral = "rgb3" if scene.render.spectral == "rgb3" else "importance"
        spectral = val.choice(spectral, ("importance", "stratified", "uniform", "rgb3"), field="spectral")
        wl = 3 if spectral == "rgb3" else val.integer(wavelengths, field="wavelengths", lo=1, hi=1000)
        self.estimator = val.choice(estimator, ("auto", "beam", "point"), field="estimator")
        bw = val.integer(beam_wavelengths, field="beam_wavelengths", lo=1, hi=64)
        self.band_seconds = float(val.number(band_seconds, field="band_seconds", lo=0.0, hi=60.0))
        over: dict[str, Any] = {
            "render.spp": 1,
            "render.adaptive": False,
            "render.spectral": spectral,
            "render.wavelengths": wl,
            # the draft (and every pass where beams do not apply): point samples of one wavelength
            "render.estimator": "point",
        }
        if scene.render.caustics:
            over["render.caustics"] = False  # the light tracer is not progressive; the preview leaves it out
        self.base = scene.with_overrides(over, width=width, height=height)
        # the passes in pixel beams: a stratified lattice of beam_wavelengths per pass, in bands
        self.beam_base = None
        if self.estimator != "point" and spectral != "rgb3":
            b_over = {
                **over,
                "render.spectral": "stratified",
                "render.wavelengths": bw,
                "render.bundle_lanes": bw,
            }
            b_over["render.estimator"] = self.estimator
            self.beam_base = scene.with_overrides(b_over, width=width, height=height)
        self._values: dict[str, Any] = {}  # scene overrides in effect (dotted path -> value)
        self._orbit = Orbit.from_camera(self.base.camera)
        self.exposure = float(self.base.render.exposure)
        self.renderer = Renderer(self.base, device=self.device)
        self.renderer.load_kernels()  # the first frame renders, it does not load the module
        self.beam_renderer = self._beam_renderer(self.beam_base)
        self.scene = self.base
        self.camera = Camera(self.base.camera)
        self.film = PreviewFilm(self.camera.width, self.camera.height, self.device)
        s = self.draft_scale
        self.draft_film = None  # the low-resolution film of the draft pass (None: no drafts)
        if s > 1:
            dw, dh = max(1, self.camera.width // s), max(1, self.camera.height // s)
            self.draft_film = PreviewFilm(dw, dh, self.device)
        self.draft = False  # whether the draft of this generation is rendered (and shown until pass 1)
        self.passes = 0
        # beams: the next band's first block, blocks per band (adapted to band_seconds), and each
        # pixel's passes (a band's pixels are one ahead until the pass is done)
        self.band_row = 0
        self._band_blocks = 1
        self.pixel_passes = np.zeros((self.camera.height, self.camera.width), dtype=np.int64)
        self._launch_map = self._launch_indices()
        self.generation = 0
        self.seconds = 0.0  # wall seconds of the last pass (render only)
        self.cpu_seconds = 0.0  # process CPU seconds of the last pass (all threads)
        self.rebuild_seconds = 0.0  # wall seconds of the last Renderer rebuild
        self._lock = threading.RLock()
        self._controls = self._make_controls()

    # -- what can change ------------------------------------------------------------------------
    @property
    def width(self) -> int:
        return self.film.width

    @property
    def height(self) -> int:
        return self.film.height

    @property
    def orbit(self) -> Orbit:
        return self._orbit

    def _make_controls(self) -> dict[str, Control]:
        o = self._orbit
        c = [
            Control("azimuth", "orbit (azimuth)", "range", round(o.azimuth, 3), -180.0, 180.0, 0.5, "deg"),
            Control(
                "elevation",
                "tilt (elevation)",
                "range",
                round(o.elevation, 3),
                -_ELEVATION_LIMIT,
                _ELEVATION_LIMIT,
                0.5,
                "deg",
            ),
            Control(
                "distance",
                "distance",
                "range",
                round(o.distance, 4),
                float(f"{0.2 * o.distance:.4g}"),
                float(f"{5.0 * o.distance:.4g}"),
                float(f"{o.distance / 200.0:.2g}"),
                "mm",
            ),
        ]
        data = self.base.data
        objs = data.get("object", [])
        if objs:
            t0 = objs[0]
            shape = t0.get("shape", "")
            for key in _cut_keys(shape):
                label, lo, hi, step, unit = _CUT_RANGES[key]
                v = float(t0.get(key, _default_param(shape, key)))
                c.append(Control(f"object.0.{key}", label, "range", v, min(lo, v), max(hi, v), step, unit))
            mat = t0.get("material", "diamond")
            choices = tuple(material_names())
            if isinstance(mat, str):
                if mat not in choices:
                    choices = (mat, *choices)  # an alias or a refractiveindex.info page: keep it selectable
            else:
                mat = _SCENE_OWN
                choices = (_SCENE_OWN, *choices)
            c.append(Control("object.0.material", "material", "choice", mat, choices=choices))
        lights = data.get("light", [{"type": "environment", "map": "studio"}])
        env_i = next(
            (i for i, t in enumerate(lights) if t.get("type", "environment") in ("environment", "constant")),
            None,
        )
        if env_i is not None:
            lt = lights[env_i]
            inten = float(lt.get("intensity", 1.0))
            c.append(
                Control(
                    f"light.{env_i}.intensity",
                    "light intensity",
                    "range",
                    inten,
                    0.0,
                    max(4.0, 4.0 * inten),
                    max(4.0, 4.0 * inten) / 200.0,
                )
            )
            c.append(
                Control(
                    f"light.{env_i}.rotation",
                    "light rotation",
                    "range",
                    float(lt.get("rotation", 0.0)),
                    -180.0,
                    180.0,
                    1.0,
                    "deg",
                )
            )
            if lt.get("type", "environment") == "environment":
                m = lt.get("map", "studio")
                maps = ("studio", "dome", "sky", "constant")
                c.append(
                    Control(
                        f"light.{env_i}.map",
                        "environment",
                        "choice",
                        m,
                        choices=maps if m in maps else (m, *maps),
                    )
                )
        c.append(
            Control(
                "render.exposure", "exposure", "range", self.exposure, -6.0, 6.0, 0.1, "stops", restarts=False
            )
        )
        return {k.name: k for k in c}

    def controls(self) -> list[Control]:
        """The adjustable values with their current settings."""
        with self._lock:
            return list(self._controls.values())

    def values(self) -> dict[str, Any]:
        with self._lock:
            return {k: c.value for k, c in self._controls.items()}

    def update(self, values: dict[str, Any]) -> int:
        """Change controls (``{name: value}``, names from :meth:`controls`); validates every value
        first (InputError: nothing changes), then applies them: the next :meth:`step` starts a new
        accumulation unless only the exposure changed.  Returns the new :attr:`generation`."""
        if not isinstance(values, dict):
            raise InputError("expected an object {name: value}", field="controls", value=values)
        with self._lock:
            checked: dict[str, Any] = {}
            for name, v in values.items():
                ctl = self._controls.get(name)
                if ctl is None:
                    raise InputError("no such control", field=name, allowed=", ".join(self._controls))
                if ctl.kind == "choice":
                    checked[name] = val.choice(v, ctl.choices, field=name)
                else:
                    x = float(val.number(v, field=name))
                    if name == "azimuth":
                        x = (x + 180.0) % 360.0 - 180.0  # the orbit goes round: any angle, wrapped
                    elif not ctl.lo <= x <= ctl.hi:
                        raise InputError(
                            "out of range",
                            field=name,
                            value=v,
                            allowed=f"{ctl.lo:g} to {ctl.hi:g} {ctl.unit}".rstrip(),
                        )
                    checked[name] = x
            orbit = replace(self._orbit, **{k: v for k, v in checked.items() if k in ORBIT_KEYS})
            scene_values = dict(self._values)
            for k, v in checked.items():
                if k in ORBIT_KEYS or k == "render.exposure":
                    continue
                if v == _SCENE_OWN:
                    scene_values.pop(k, None)
                else:
                    scene_values[k] = v
            restart = any(
                self._controls[k].restarts and self._controls[k].value != v for k, v in checked.items()
            )
            camera = CameraConfig(
                **{**self._camera_kw(), "position": orbit.position(self.base.camera.look_at)}
            )
            scene = self.scene
            if scene_values != self._values or (restart and self.renderer.source_polarizer is not None):
                # the light's polarizer faces the camera: moving the camera rebuilds the light too
                over = dict(scene_values)
                if self.renderer.source_polarizer is not None:
                    over["camera.position"] = list(camera.position)
                scene = self.base.with_overrides(over)
                t0 = time.perf_counter()
                self.renderer = Renderer(scene, device=self.device)  # new mesh / materials / light: data only
                if self.beam_base is not None:
                    self.beam_renderer = self._beam_renderer(self.beam_base.with_overrides(over))
                    self._launch_map = self._launch_indices()
                self.rebuild_seconds = time.perf_counter() - t0
            self.scene = scene
            self._values = scene_values
            self._orbit = orbit
            self.camera = Camera(camera)
            if "render.exposure" in checked:
                self.exposure = checked["render.exposure"]
            for k, v in checked.items():
                self._controls[k] = replace(self._controls[k], value=v)
            if restart:
                self.film.zero()
                if self.draft_film is not None:
                    self.draft_film.zero()
                self.draft = False
                self.passes = 0
                self.band_row = 0
                self.pixel_passes[:] = 0
                self.generation += 1
            return self.generation

    def _beam_renderer(self, scene) -> Renderer | None:
        """The Renderer of the passes in pixel beams, or None where beams do not apply (then the
        passes are the point Renderer's)."""
        if scene is None:
            return None
        r = Renderer(scene, device=self.device)
        if not r.pixel_beam:
            return None
        r.load_kernels()
        return r

    def _launch_indices(self) -> np.ndarray:
        r = self.beam_renderer or self.renderer
        return r.launch_indices(self.camera.width, self.camera.height)

    @property
    def pass_estimator(self) -> str:
        """``"beam"`` when the passes are pixel beams (in bands of rows), else ``"point"``."""
        return "point" if self.beam_renderer is None else "beam"

    def _camera_kw(self) -> dict:
        c = self.base.camera
        return {k: getattr(c, k) for k in c.__dataclass_fields__}

    # -- rendering ------------------------------------------------------------------------------
    def _draft_camera(self):
        assert self.draft_film is not None
        c = self.camera.config
        return Camera(replace(c, width=self.draft_film.width, height=self.draft_film.height)).params

    def step(self) -> bool:
        """Render the draft after a restart (:attr:`draft` becomes True, ``passes`` stays 0), else
        add one full-resolution pass (1 spp in every pixel) unless ``max_passes`` are done; returns
        whether it rendered anything."""
        with self._lock:
            if self.passes >= self.max_passes:
                return False
            t0, c0 = time.perf_counter(), time.process_time()
            if self.draft_film is not None and self.passes == 0 and self.band_row == 0 and not self.draft:
                self.renderer.render_pass(self.draft_film, camera=self._draft_camera(), threads=self.threads)
                self.draft = True
            elif self.beam_renderer is not None:
                self._beam_band()
            else:
                self.renderer.render_pass(
                    self.film,
                    pass_index=self.passes // BLOCK,
                    spp_begin=self.passes % BLOCK,
                    camera=self.camera.params,
                    threads=self.threads,
                )
                self.passes += 1
                self.pixel_passes += 1
            self.seconds = time.perf_counter() - t0
            self.cpu_seconds = time.process_time() - c0
            return True

    def _beam_band(self) -> None:
        """The next band of the current pass in pixel beams: the next blocks in launch order, as
        many as fit in ``band_seconds`` at the last band's rate (at most twice as many as the
        last, and 1/64 of the image: a stone's blocks cost far more than the background's; a
        whole pass when ``band_seconds`` is 0); the pass is done when the band reaches the end."""
        r = self.beam_renderer
        assert r is not None
        total = int(self._launch_map.max()) + 1
        n = total if self.band_seconds <= 0.0 else max(1, self._band_blocks)
        first = self.band_row
        t0 = time.perf_counter()
        r.render_pass(
            self.film,
            pass_index=self.passes // BLOCK,
            spp_begin=self.passes % BLOCK,
            camera=self.camera.params,
            threads=self.threads,
            launch=(first, n),
        )
        dt = time.perf_counter() - t0
        end = min(total, first + n)
        done = (self._launch_map >= first) & (self._launch_map < end)
        self.pixel_passes[done] += 1
        if self.band_seconds > 0.0:
            grow = min(2.0, self.band_seconds / max(dt, 1e-4))
            self._band_blocks = int(min(max(1, total // 64), max(1.0, n * grow)))
        if end >= total:
            self.band_row = 0
            self.passes += 1
        else:
            self.band_row = end

    @property
    def showing_draft(self) -> bool:
        """Whether :meth:`frame` shows the draft alone (rendered, and no full-resolution pass or
        band yet)."""
        return self.draft and not self.pixel_passes.any()

    def image(self) -> Image:
        """The mean of the passes so far as an :class:`Image` (zeros before the first pass)."""
        with self._lock:
            h, w = self.height, self.width
            inv = 1.0 / np.maximum(self.pixel_passes, 1).astype(np.float64)  # a band's pixels are ahead
            xyz = self.film.xyz.numpy().reshape(h, w, 3) * inv[..., None]
            stokes = self.film.stokes.numpy().reshape(h, w, 4) * inv[..., None]
            alpha = self.film.alpha.numpy().reshape(h, w) * inv
            stokes_xyz = self.film.stokes_xyz.numpy().reshape(h, w, 3, 4) * inv[..., None, None]
            rays = int(self.film.rays.numpy().sum())
            r = self.scene.render
            stats = {
                "passes": self.passes,
                "estimator": self.pass_estimator,
                "generation": self.generation,
                "rays": rays,
                "width": w,
                "height": h,
            }
            return Image(
                xyz=xyz,
                stokes=stokes,
                alpha=alpha,
                exposure=self.exposure,
                tone=r.tone,
                stats=stats,
                stokes_xyz=stokes_xyz,
                source_polarizer=self.renderer.source_polarizer,
            )

    def frame(self) -> np.ndarray:
        """The display image (height, width, 3) uint8 sRGB of the passes so far, or the draft
        enlarged to that size (each draft pixel repeated, nearest pixel) before the first pass."""
        with self._lock:
            h, w = self.height, self.width
            if self.showing_draft and self.draft_film is not None:
                d = self.draft_film
                xyz = d.xyz.numpy().reshape(d.height, d.width, 3)
            else:
                xyz = self.film.xyz.numpy().reshape(h, w, 3) / np.maximum(self.pixel_passes, 1)[..., None]
            if (
                self.draft
                and self.draft_film is not None
                and not self.showing_draft
                and not self.pixel_passes.all()
            ):
                # the draft (each of its pixels repeated) where no full-resolution pass is in yet
                d = self.draft_film
                dx = d.xyz.numpy().reshape(d.height, d.width, 3)
                rows = np.arange(h) * d.height // h
                cols = np.arange(w) * d.width // w
                todo = self.pixel_passes == 0
                xyz[todo] = dx[rows[:, None], cols[None, :]][todo]
            img = Image(
                xyz=xyz,
                stokes=np.zeros((*xyz.shape[:2], 4)),
                alpha=np.zeros(xyz.shape[:2]),
                exposure=self.exposure,
                tone=self.scene.render.tone,
            )
        rgb = np.round(np.clip(img.display(), 0.0, 1.0) * 255.0).astype(np.uint8)
        if rgb.shape[:2] != (h, w):  # the draft alone: each of its pixels repeated
            rows = np.arange(h) * rgb.shape[0] // h
            cols = np.arange(w) * rgb.shape[1] // w
            rgb = rgb[rows[:, None], cols[None, :]]
        return rgb

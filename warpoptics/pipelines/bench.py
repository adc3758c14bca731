"""The optical bench pipeline: Beam -> forward trace -> Screens, with an energy ledger.

``bench(scene, **overrides) -> BenchResult``; the scene schema is :mod:`warpoptics.scene.bench`.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import warp as wp

from ..device import get_device
from ..errors import InputError
from ..film.screen import Screen, ScreenImage, screen_set
from ..geometry import cuts
from ..geometry.nesting import point_medium
from ..geometry.query import GeometryScene
from ..materials import get as get_material
from ..materials.dispersion import build_material_table
from ..optics.thinfilm import make_coating_stack
from ..scene.bench import BenchScene
from ..spectra import COARSE_STEP_NM, cmf
from ..spectra import grid as spectral_grid
from ..stages.coated import layer_index_samples
from ..stages.forward import LEDGER, ForwardConfig, ForwardStage
from .objects import build_objects

__all__ = ["BenchResult", "Bench", "bench"]


@dataclass
class BenchResult:
    """What a bench run measured.

    ``screens``: one :class:`ScreenImage` per sensor.  ``ledger``: power (W) per fate
    (``emitted`` and the columns of ``stages.forward.LEDGER``).  ``deposits``: every recorded
    screen hit, as NumPy arrays in a fixed order - ``screen``, ``u``, ``v`` (mm on the screen),
    ``wavelength`` (nm), ``power`` (W), ``stokes`` (N, 4; W), ``depth`` (interfaces crossed),
    ``ray`` (beam position index), ``xyz`` (N, 3; this deposit's share of the XYZ image).
    ``wavelengths``, ``weights``: the beam's spectral samples and
    their power fractions."""

    screens: list[ScreenImage]
    ledger: dict[str, float]
    deposits: dict[str, np.ndarray]
    wavelengths: np.ndarray
    weights: np.ndarray
    stats: dict = field(default_factory=dict)
    sensors: tuple[Screen, ...] = ()
    exposure: float = 0.0
    tone: str = "filmic"

    def screen_image(self, screen: int = 0, *, select: np.ndarray | None = None) -> ScreenImage:
        """Bin the deposits on ``screen`` (optionally only those where the boolean array ``select``
        over all deposits is true, e.g. ``result.deposits["depth"] >= 2``) into XYZ and Stokes
        pixels, in deposit order (deterministic)."""
        sc = self.sensors[screen]
        dp = self.deposits
        s = dp["screen"] == screen
        if select is not None:
            s &= np.asarray(select, dtype=bool)
        pix = sc.pixel_index(dp["u"][s], dp["v"][s])
        nx, ny = (int(r) for r in sc.resolution)
        npx = nx * ny
        xyz = np.stack([np.bincount(pix, weights=dp["xyz"][s, c], minlength=npx) for c in range(3)], axis=-1)
        st = np.stack(
            [np.bincount(pix, weights=dp["stokes"][s, c], minlength=npx) for c in range(4)], axis=-1
        )
        return ScreenImage(
            screen=sc,
            xyz=xyz.reshape(ny, nx, 3),
            stokes=st.reshape(ny, nx, 4),
            power=float(dp["power"][s].sum()),
            exposure=self.exposure,
            tone=self.tone,
        )

    def balance(self) -> float:
        """(screen + absorbed + escaped) / emitted - 1: the part of the power the ledger's three
        physical fates miss (truncated, lost, overflow, interface)."""
        lg = self.ledger
        return (lg["screen"] + lg["absorbed"] + lg["escaped"]) / lg["emitted"] - 1.0

    def spot_positions(self, screen: int = 0, *, depth: int | None = None) -> dict[str, np.ndarray]:
        """Per wavelength sample: power-weighted centroid ``u``, ``v`` (mm; NaN where nothing
        arrived) and ``power`` (W) on ``screen`` (optionally only deposits with that ``depth``)."""
        dp = self.deposits
        sel = dp["screen"] == screen
        if depth is not None:
            sel &= dp["depth"] == depth
        idx = np.searchsorted(self.wavelengths, dp["wavelength"][sel])
        nw = self.wavelengths.size
        p = np.bincount(idx, weights=dp["power"][sel], minlength=nw)
        pu = np.bincount(idx, weights=dp["power"][sel] * dp["u"][sel], minlength=nw)
        pv = np.bincount(idx, weights=dp["power"][sel] * dp["v"][sel], minlength=nw)
        with np.errstate(invalid="ignore", divide="ignore"):
            u = np.where(p > 0, pu / p, np.nan)
            v = np.where(p > 0, pv / p, np.nan)
        return {"wavelength": self.wavelengths.copy(), "u": u, "v": v, "power": p}

    def spots(self, screen: int = 0, *, count: int = 2, radius: float | None = None) -> list[dict]:
        """The ``count`` brightest spots on ``screen``: greedily, from the brightest pixel, the
        deposits within ``radius`` mm (default 10 pixels) of their own centroid (mean shift),
        removed before the next spot.  Each spot:
        ``u``, ``v`` (power-weighted centroid, mm), ``power`` (W), ``stokes`` (summed, W),
        ``dop`` (degree of polarization), ``angle`` (deg, of linear polarization from the
        screen's x toward y)."""
        img = self.screens[screen]
        sc = img.screen
        if radius is None:
            radius = 10.0 * max(sc.size[0] / sc.resolution[0], sc.size[1] / sc.resolution[1])
        dp = self.deposits
        sel = np.nonzero(dp["screen"] == screen)[0]
        u, v, p, st = dp["u"][sel], dp["v"][sel], dp["power"][sel], dp["stokes"][sel]
        alive = np.ones(sel.size, dtype=bool)
        out = []
        for _ in range(count):
            if not alive.any():
                break
            pix = sc.pixel_index(u[alive], v[alive])
            nx, ny = (int(r) for r in sc.resolution)
            best = int(np.argmax(np.bincount(pix, weights=p[alive], minlength=nx * ny)))
            cu, cv = sc.pixel_centers()
            u0, v0 = cu.ravel()[best], cv.ravel()[best]
            for _it in range(8):  # mean shift: re-centre on the centroid within the radius
                near = alive & ((u - u0) ** 2 + (v - v0) ** 2 <= radius**2)
                u1 = float((p[near] * u[near]).sum() / p[near].sum())
                v1 = float((p[near] * v[near]).sum() / p[near].sum())
                if (u1 - u0) ** 2 + (v1 - v0) ** 2 < 1e-18:
                    break
                u0, v0 = u1, v1
            near = alive & ((u - u0) ** 2 + (v - v0) ** 2 <= radius**2)
            pw = p[near].sum()
            s = st[near].sum(axis=0)
            out.append(
                {
                    "u": float((p[near] * u[near]).sum() / pw),
                    "v": float((p[near] * v[near]).sum() / pw),
                    "power": float(pw),
                    "stokes": s,
                    "dop": float(np.linalg.norm(s[1:]) / s[0]),
                    "angle": float(np.degrees(0.5 * np.arctan2(s[2], s[1]))),
                }
            )
            alive &= ~near
        return out

    def save(self, path: str | Path, screen: int = 0) -> Path:
        return self.screens[screen].save(path)


class Bench:
    """The bench pipeline for a scene; owns every stage's device data.  ``run()`` traces."""

    def __init__(self, scene: BenchScene, *, device=None):
        self.scene = scene
        self.device = get_device(device)
        r = scene.render
        self.wavelengths, self.weights = scene.source.spectral_samples(r.wavelengths)
        if scene.objects:
            built = build_objects(scene.objects, file=scene.path)
            meshes, mats, axes = built.meshes, built.materials, built.axes
            parents = built.parents
            inside = point_medium(meshes, parents, scene.source.position)
            if inside >= 0:
                # beam rays start in the ambient medium: a source inside a solid is refused
                raise InputError(
                    f"the source lies inside object.{inside}; place it outside the solids",
                    file=scene.path,
                    field="source.position",
                    value=list(scene.source.position),
                )
        else:
            # an empty bench: one tiny object far away keeps the geometry struct valid
            far = np.eye(4)
            far[:3, 3] = (1.0e5, 1.0e5, 1.0e5)
            meshes, mats, axes = [(cuts.cube(1.0e-3), far)], [get_material("water")], [None]
            parents = None
        self.geometry = GeometryScene(meshes, parents=parents, device=self.device)
        self.materials, ids = build_material_table(mats, self.device, rgb3=False)
        world_axes = []
        for i, (mat, ax) in enumerate(zip(mats, axes, strict=True)):
            a = np.asarray(
                ax if ax is not None else getattr(mat, "optic_axis", (0.0, 0.0, 1.0)), dtype=np.float64
            )
            if scene.objects:
                a = scene.objects[i].rotation_matrix() @ a
            world_axes.append(a / max(np.linalg.norm(a), 1e-30))
        # coatings: one CoatingStack for all coated objects
        coat_ids, layers = [], []
        grid = spectral_grid(COARSE_STEP_NM)
        for c in scene.coatings if scene.objects else (None,):
            if c is None:
                coat_ids.append(-1)
                continue
            coat_ids.append(len(layers))
            rows = []
            for index, d in c:
                if isinstance(index, complex):
                    rows.append((np.full(grid.size, index), d))
                else:  # a material: its n + ik on the grid (clipped to its data range)
                    rows.append((layer_index_samples(index), d))
            layers.append(rows)
        self.coatings = make_coating_stack(
            layers or [[]],
            wavelength_start_nm=float(grid[0]),
            wavelength_step_nm=COARSE_STEP_NM,
            device=self.device,
        )
        absorption = [ob.absorption_scale for ob in scene.objects] or [1.0]
        self.forward = ForwardStage(
            ForwardConfig(
                max_depth=r.max_depth,
                split_threshold=r.split_threshold,
                max_deposits=r.max_deposits,
                seed=r.seed,
            ),
            np.asarray(ids, dtype=np.int32),
            np.asarray(absorption, dtype=np.float32),
            np.asarray(world_axes),
            np.asarray(coat_ids, dtype=np.int32),
            ambient=(r.ambient_index, 0.0),
            device=self.device,
        )
        self.beam = scene.source.params()
        self.screens = screen_set(list(scene.sensors), self.device)
        self.wl_device = wp.array(self.wavelengths.astype(np.float32), dtype=wp.float32, device=self.device)

    def run(
        self, *, threads: int | None = None, tile_size: int | None = None, chunk: int = 1 << 15
    ) -> BenchResult:
        """Trace every beam ray; ``chunk`` beam rays (times wavelengths) per launch round."""
        src = self.scene.source
        n_wl = self.wavelengths.size
        total = src.rays * n_wl
        k_dep = self.forward.config.max_deposits
        ray_power = src.power / src.rays * self.weights  # W per beam ray, per wavelength sample
        chunk = max(n_wl, (int(chunk) // n_wl) * n_wl)
        out = self.forward.buffers(chunk)
        self.forward.load()  # compile (first run) outside the timed region
        ledger_rows = []  # per beam ray, summed once at the end: the same sums for any chunking
        parts: dict[str, list] = {
            k: [] for k in ("screen", "u", "v", "wl_index", "stokes", "depth", "ray", "scale")
        }
        t0 = time.perf_counter()
        for start in range(0, total, chunk):
            count = min(chunk, total - start)
            self.forward.run(
                start,
                count,
                out,
                geometry=self.geometry.geometry,
                materials=self.materials,
                coatings=self.coatings,
                beam=self.beam,
                screens=self.screens,
                wavelengths=self.wl_device,
                threads=threads,
                tile_size=tile_size,
            )
            thread = np.arange(start, start + count)
            p_ray = ray_power[thread % n_wl]
            ledger_rows.append(out.ledger.numpy()[:count] * p_ray[:, None])
            scr = out.screen.numpy()[: count * k_dep]
            sel = np.nonzero(scr >= 0)[0]
            th = start + sel // k_dep
            parts["screen"].append(scr[sel])
            uv = out.uv.numpy()[: count * k_dep][sel].astype(np.float64)
            parts["u"].append(uv[:, 0])
            parts["v"].append(uv[:, 1])
            parts["wl_index"].append(th % n_wl)
            parts["stokes"].append(out.stokes.numpy()[: count * k_dep][sel].astype(np.float64))
            parts["depth"].append(out.depth.numpy()[: count * k_dep][sel])
            parts["ray"].append(th // n_wl)
            parts["scale"].append(ray_power[th % n_wl])
        elapsed = time.perf_counter() - t0
        ledger = np.concatenate(ledger_rows).sum(axis=0)
        cat = {k: np.concatenate(v) for k, v in parts.items()}
        stokes = cat["stokes"] * cat["scale"][:, None]
        wl = self.wavelengths[cat["wl_index"]]
        deposits = {
            "screen": cat["screen"].astype(np.int64),
            "u": cat["u"],
            "v": cat["v"],
            "wavelength": wl,
            "power": stokes[:, 0].copy(),
            "stokes": stokes,
            "depth": cat["depth"].astype(np.int64),
            "ray": cat["ray"].astype(np.int64),
        }
        # XYZ normalised so that the whole beam in one pixel has Y = 1
        cm = cmf(self.wavelengths)
        y_norm = float((self.weights * cm[:, 1]).sum())
        y_norm = y_norm if y_norm > 0 else 1.0
        xyz_w = cm[cat["wl_index"]] * (deposits["power"] / (src.power * y_norm))[:, None]
        deposits["xyz"] = xyz_w
        led = {"emitted": float(src.power)}
        led.update({name: float(v) for name, v in zip(LEDGER, ledger, strict=True)})
        stats = {"seconds": elapsed, "beam_rays": total, "deposits": int(deposits["power"].size)}
        result = BenchResult(
            screens=[],
            ledger=led,
            deposits=deposits,
            wavelengths=self.wavelengths.copy(),
            weights=self.weights.copy(),
            stats=stats,
            sensors=tuple(self.scene.sensors),
            exposure=self.scene.render.exposure,
            tone=self.scene.render.tone,
        )
        result.screens = [result.screen_image(k) for k in range(len(self.scene.sensors))]
        return result


def bench(
    scene: BenchScene | str | Path, *, device=None, threads: int | None = None, overrides: dict | None = None
) -> BenchResult:
    """Run an optical-bench scene (a :class:`BenchScene` or a TOML path) and return what its
    screens recorded, with the energy ledger.  ``overrides``: dotted paths (``{"source.rays": 64}``)."""
    if not isinstance(scene, BenchScene):
        scene = BenchScene.load(scene)
    if overrides:
        scene = scene.with_overrides(overrides)
    return Bench(scene, device=device).run(threads=threads)

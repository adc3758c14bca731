"""Cut grading on the sweep runner: the full light-performance protocol and the tilt series.

Both are :class:`~warpoptics.sweep.Sweep` objects built in Python and run by
:class:`~warpoptics.sweep.SweepRunner`, so they resume after a kill (``resume=True``: the
finished jobs' rows in ``results.csv`` are kept) and run in a pool or on Dask
(``dask_local=N``, ``scheduler=...``) with the same job function; their own outputs (tables,
plots, the animation) are written atomically once every job is done.

- :func:`protocol_sweep` / :func:`light_performance` — the protocol of
  :mod:`warpoptics.grading.performance` (face-up and tilted views with the observer's head):
  per view an ISO render (light return, contrast, extinction) and a spot-lit render (fire,
  scintillation against the stone turned by the protocol's small step); one job per stone,
  :func:`protocol_scores` averages the views of a results row.  The cut optimizer
  (:mod:`warpoptics.sweep.optimize`) evaluates its candidates as jobs of this sweep.
- :func:`tilt_series_sweep` / :func:`tilt_series` — brightness, contrast, fire and scintillation
  of one stone against the tilt angle about several azimuths: one job per (azimuth, tilt);
  :func:`write_tilt_series` writes ``tilt_series.csv`` (one row per azimuth and tilt),
  ``tilt_series.png`` (the four metrics against tilt, a line per azimuth) and
  ``tilt_series.gif`` (the ISO and spot-lit views side by side, frame by frame in tilt order,
  through Pillow).
"""

from __future__ import annotations

import io
import tempfile
from collections.abc import Sequence
from pathlib import Path

from ..errors import InputError
from ..grading.performance import PROTOCOL, Protocol, average_views
from ..grading.presets import face_up_scene, lighting_table, tilt_rotation
from .results import csv_line, write_text_atomic
from .runner import SweepRunner
from .spec import Axis, Sweep, View

__all__ = [
    "BRIGHTNESS_METRICS",
    "SPOT_METRICS",
    "protocol_scene",
    "protocol_views",
    "protocol_sweep",
    "protocol_scores",
    "renders_per_job",
    "light_performance",
    "tilt_series_sweep",
    "tilt_series",
    "write_tilt_series",
]

#: the tilt series' default tilts: 0-30 deg in 2 deg steps
DEFAULT_TILTS: tuple[float, ...] = tuple(float(t) for t in range(0, 31, 2))

#: metrics of each view's ISO render and of its spot-lit render
BRIGHTNESS_METRICS = ("light_return", "contrast", "extinction")
SPOT_METRICS = ("fire", "scintillation")
_ALL = BRIGHTNESS_METRICS + SPOT_METRICS


def protocol_scene(stone: dict, protocol: Protocol = PROTOCOL, *, frame_mm: float | None = None):
    """The base :class:`~warpoptics.scene.Scene`: ``stone`` face-up under the protocol's lighting
    and head, at the protocol's image size and wavelengths."""
    from ..scene.load import Scene

    return Scene.from_dict(
        face_up_scene(
            stone,
            lighting=protocol.lighting,
            head_radius_deg=protocol.head_radius_deg,
            size=protocol.size,
            wavelengths=protocol.wavelengths,
            frame_mm=frame_mm,
        )
    )


def _spot_map(protocol: Protocol) -> str:
    return str(lighting_table(protocol.fire_lighting)["map"])


def protocol_views(
    protocol: Protocol = PROTOCOL, *, fire: bool = True, save: bool = False
) -> tuple[View, ...]:
    """Sweep views of the protocol: ``iso_<view>`` (the stone turned to the view's tilt and
    azimuth; :data:`BRIGHTNESS_METRICS`) and, with ``fire``, ``spots_<view>`` (the same turn under
    the fire lighting; :data:`SPOT_METRICS`, the scintillation tilt one step about x); ``save``
    writes the face-up ISO image of each job."""
    step = float(protocol.scintillation_step_deg)
    spot = _spot_map(protocol) if fire else None
    views = []
    for name, t, _a, rot in protocol.view_rotations():
        views.append(
            View(
                name=f"iso_{name}",
                set={"object.0.rotation": rot},
                metrics=BRIGHTNESS_METRICS,
                save=bool(save and t == 0.0),
            )
        )
        if fire:
            views.append(
                View(
                    name=f"spots_{name}",
                    set={"object.0.rotation": rot, "light.0.map": spot},
                    metrics=SPOT_METRICS,
                    tilts=((step, 0.0, 0.0),),
                    save=False,
                )
            )
    return tuple(views)


def renders_per_job(sweep: Sweep) -> int:
    """Renders one job of ``sweep`` costs: one per view, plus its scintillation tilts and the
    dispersion-free twin of ``fire_excess`` (what :func:`~warpoptics.sweep.run_job` renders)."""
    n = 0
    for v in sweep.views:
        n += 1 + (len(v.tilts) if "scintillation" in v.metrics else 0) + ("fire_excess" in v.metrics)
    return n


def protocol_sweep(
    stone: dict,
    protocol: Protocol = PROTOCOL,
    *,
    axes: Sequence[Axis] | None = None,
    mode: str = "zip",
    fire: bool = True,
    save: bool = False,
    frame_mm: float | None = None,
    name: str = "light_performance",
    set: dict | None = None,
    expr: dict | None = None,
) -> Sweep:
    """The protocol as a sweep: one job per combination of ``axes`` (dotted paths into the stone,
    e.g. ``Axis("pavilion", (40.0, 41.0), path="object.0.pavilion_angle")``; none: one job),
    each rendering every view of :func:`protocol_views`."""
    ax = tuple(axes) if axes else (Axis("stone", ("stone",)),)
    return Sweep(
        scene=protocol_scene(stone, protocol, frame_mm=frame_mm),
        axes=ax,
        mode=mode,
        set=dict(set or {}),
        expr=dict(expr or {}),
        views=protocol_views(protocol, fire=fire, save=save),
        name=name,
        description="light performance under the tilted, head-obscured protocol (warpoptics.grading)",
    )


def protocol_scores(row: dict, protocol: Protocol = PROTOCOL, *, fire: bool = True) -> dict[str, float]:
    """The protocol's metrics of one results row of :func:`protocol_sweep` (values may be the
    CSV's strings): the plain means over the views (:func:`~warpoptics.grading.average_views`)
    of light_return, contrast, extinction and, with ``fire``, fire and scintillation."""
    rotations = protocol.view_rotations()
    several = len(rotations) * (2 if fire else 1) > 1  # the sweep's column rule (Sweep.columns)

    def col(view: str, m: str) -> float:
        return float(row[f"{view}_{m}" if several else m])

    per_view = []
    for vname, _t, _a, _rot in rotations:
        d = {m: col(f"iso_{vname}", m) for m in BRIGHTNESS_METRICS}
        if fire:
            d.update({m: col(f"spots_{vname}", m) for m in SPOT_METRICS})
        per_view.append(d)
    return average_views(per_view)


def _runner(sweep, out_dir, **kw) -> SweepRunner:
    return SweepRunner(sweep, out_dir, **kw)


def light_performance(
    stone: dict,
    protocol: Protocol = PROTOCOL,
    *,
    out_dir: str | Path | None = None,
    fire: bool = True,
    frame_mm: float | None = None,
    **runner_kw,
) -> dict:
    """The protocol's metrics of ``stone`` (:func:`protocol_scores`) plus ``per_view`` (the view
    columns of the results row), ``renders`` (the renders one evaluation costs) and ``out_dir``.
    ``out_dir`` (default a temporary folder, removed after) holds the sweep's files;
    ``runner_kw`` go to :class:`SweepRunner` (``resume``, ``overwrite``, ``dask_local``, ...)."""
    sweep = protocol_sweep(stone, protocol, fire=fire, save=out_dir is not None, frame_mm=frame_mm)
    runner_kw.setdefault("progress", False)
    with tempfile.TemporaryDirectory(prefix="warpoptics-grade-") as tmp:
        out = Path(out_dir) if out_dir is not None else Path(tmp)
        res = _runner(sweep, out, **runner_kw).run()
        if len(res.rows) != 1:
            raise InputError("the protocol's job did not finish", file=str(out / "results.csv"))
        row = res.rows[0]
        scores = protocol_scores(row, protocol, fire=fire)
        per_view = {k: float(row[k]) for k in sweep.columns()}
    return {**scores, "per_view": per_view, "renders": renders_per_job(sweep), "out_dir": out_dir}


# -- the tilt series -------------------------------------------------------------------------


def tilt_series_sweep(
    stone: dict,
    *,
    tilts: Sequence[float] = DEFAULT_TILTS,
    azimuths: Sequence[float] = (0.0, 22.5),
    protocol: Protocol = PROTOCOL,
    frame_mm: float | None = None,
    name: str = "tilt_series",
) -> Sweep:
    """One job per (azimuth, tilt) (product, azimuth outermost): the stone turned by
    :func:`~warpoptics.grading.tilt_rotation` under the protocol's lighting and head (view
    ``iso``: light return, contrast, extinction) and under its fire lighting (view ``spots``:
    fire, scintillation against a further step); both views' images are saved (the
    animation's frames)."""
    tl = tuple(float(t) for t in tilts)
    az = tuple(float(a) for a in azimuths)
    if not tl or any(not -80.0 <= t <= 80.0 for t in tl):
        raise InputError("tilts must be in [-80, 80] degrees", field="tilts", value=list(tl))
    if not az:
        raise InputError("needs at least one azimuth", field="azimuths")
    step = float(protocol.scintillation_step_deg)
    return Sweep(
        scene=protocol_scene(stone, protocol, frame_mm=frame_mm),
        axes=(Axis("azimuth", az), Axis("tilt", tl)),
        expr={"object.0.rotation": lambda v: tilt_rotation(v["tilt"], v["azimuth"])},
        views=(
            View(name="iso", metrics=BRIGHTNESS_METRICS, save=True),
            View(
                name="spots",
                set={"light.0.map": _spot_map(protocol)},
                metrics=SPOT_METRICS,
                tilts=((step, 0.0, 0.0),),
                save=True,
            ),
        ),
        name=name,
        label="tilt {tilt:g}° azimuth {azimuth:g}°",
        description="brightness, contrast, fire and scintillation against tilt (warpoptics.grading)",
    )


def _table(result) -> list[dict]:
    out = []
    for r in result.rows:
        d = {"azimuth": float(r["azimuth"]), "tilt": float(r["tilt"])}
        d.update({m: float(r[f"{'iso' if m in BRIGHTNESS_METRICS else 'spots'}_{m}"]) for m in _ALL})
        out.append(d)
    return out


def _frame(runner: SweepRunner, job, caption: str, scale: int):
    from PIL import Image as PILImage
    from PIL import ImageDraw

    tiles = [PILImage.open(runner.image_path(job, v, "png")).convert("RGB") for v in ("iso", "spots")]
    tiles = [t.resize((t.width * scale, t.height * scale), PILImage.Resampling.NEAREST) for t in tiles]
    w, h = tiles[0].size
    bar = 14
    out = PILImage.new("RGB", (2 * w, h + bar), (0, 0, 0))
    for i, t in enumerate(tiles):
        out.paste(t, (i * w, bar))
    ImageDraw.Draw(out).text((3, 1), caption, fill=(230, 230, 230))
    return out


def write_tilt_series(runner: SweepRunner, result, *, fps: float = 6.0) -> dict[str, Path]:
    """The tilt series' table, plot and animation (module docstring) beside the sweep's files in
    ``runner.out_dir``; every file written atomically."""
    from ..atomic import atomic_path

    rows = _table(result)
    out = runner.out_dir
    files: dict[str, Path] = {}
    cols = ["azimuth", "tilt", *_ALL]
    text = csv_line(cols) + "".join(csv_line([f"{r[c]:.6g}" for c in cols]) for r in rows)
    files["table"] = out / "tilt_series.csv"
    write_text_atomic(files["table"], text)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    titles = {
        "light_return": "brightness (light return)",
        "contrast": "contrast (CV of luminance)",
        "fire": "fire (Y × s_uv, spots)",
        "scintillation": "scintillation (Δ pattern, spots)",
    }
    fig, axs = plt.subplots(2, 2, figsize=(8, 5.6), sharex=True)
    azs = sorted({r["azimuth"] for r in rows})
    for ax, (m, title) in zip(axs.ravel(), titles.items(), strict=True):
        for a in azs:
            sel = sorted((r for r in rows if r["azimuth"] == a), key=lambda r: r["tilt"])
            ax.plot([r["tilt"] for r in sel], [r[m] for r in sel], "o-", ms=3, label=f"azimuth {a:g}°")
        ax.set_title(title, fontsize=9)
        ax.grid(alpha=0.3)
    for ax in axs[-1]:
        ax.set_xlabel("tilt (°)")
    axs[0, 0].legend(fontsize=8)
    fig.tight_layout()
    files["plot"] = out / "tilt_series.png"
    with atomic_path(files["plot"]) as tmp:
        fig.savefig(tmp, dpi=100)
    plt.close(fig)

    by_key = {(float(j.values["azimuth"]), float(j.values["tilt"])): j for j in result.jobs}
    scale = max(1, 160 // max(1, runner.sweep.scene.camera.height))
    frames = []
    for a in azs:
        tl = sorted(t for (aa, t) in by_key if aa == a)
        for t in [*tl, *tl[-2:0:-1]]:  # there and back, so that the loop does not jump
            frames.append(_frame(runner, by_key[a, t], f"tilt {t:g} az {a:g}  ISO | spots", scale))
    buf = io.BytesIO()
    frames[0].save(
        buf, format="GIF", save_all=True, append_images=frames[1:], duration=int(1000 / fps), loop=0
    )
    files["animation"] = out / "tilt_series.gif"
    with atomic_path(files["animation"]) as tmp:
        Path(tmp).write_bytes(buf.getvalue())
    return files


def tilt_series(
    stone: dict,
    out_dir: str | Path,
    *,
    tilts: Sequence[float] = DEFAULT_TILTS,
    azimuths: Sequence[float] = (0.0, 22.5),
    protocol: Protocol = PROTOCOL,
    frame_mm: float | None = None,
    fps: float = 6.0,
    **runner_kw,
) -> dict:
    """Run the tilt series of ``stone`` into ``out_dir`` (:func:`tilt_series_sweep`;
    ``runner_kw`` to :class:`SweepRunner`) and, once every job is done, write its table, plot and
    animation.  Returns ``{"rows", "files", "rendered", "complete"}``."""
    sweep = tilt_series_sweep(stone, tilts=tilts, azimuths=azimuths, protocol=protocol, frame_mm=frame_mm)
    runner = _runner(sweep, out_dir, **runner_kw)
    res = runner.run()
    complete = len(res.rows) == len(res.jobs)
    files = dict(res.files)
    if complete:
        files.update(write_tilt_series(runner, res, fps=fps))
    return {
        "rows": _table(res) if complete else [],
        "files": files,
        "rendered": res.rendered,
        "renders": res.rendered * renders_per_job(sweep),
        "complete": complete,
    }

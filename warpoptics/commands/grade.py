"""`warpoptics grade`: cut grading of a stone, a GemCAD design or a scene's first object.

    warpoptics grade report round_brilliant --set pavilion_angle=41 -o out/report   # protocol metrics
    warpoptics grade aset design.asc -o aset.png                   # ASET zones (AGS)
    warpoptics grade idealscope scene.toml -o is.png               # Ideal Scope
    warpoptics grade hearts round_brilliant -o arrows.png [--face-down]
    warpoptics grade map sapphire.toml --reference stone -o map.png   # brightness/contrast map
    warpoptics grade tilt design.asc -o out/tilt [--tilts 0:30:2 --azimuths 0,22.5 --dask-local 2]
    warpoptics grade optimize round_brilliant --param pavilion_angle=38:44:43 \\
        --param crown_angle=25:40:30 --budget 40 -o out/opt [--resume --dask-local 2]
    warpoptics grade optimize design.asc --param tier:2=40:44 -o out/opt   # a GemCAD tier angle
    warpoptics grade retarget design.asc --index 1.544 -o quartz.asc

STONE is a cut name (``warpoptics.geometry.cuts``: round_brilliant, oval, ...; keywords with
``--set KEY=VALUE``), a GemCAD design (.asc/.gem), a mesh (.ply/.stl/.obj/.glb/.off) or a scene
(.toml: its first ``[[object]]``).  Every file is written atomically; the runs of ``report``,
``tilt`` and ``optimize`` go through the sweep runner (``--resume`` after a kill, ``--dask-local
N``).  Errors are one line.
"""

from __future__ import annotations

import dataclasses
import json
import math
import sys
from pathlib import Path

from .. import validate as val
from ..errors import InputError

_MESH_EXT = (".ply", ".stl", ".obj", ".glb", ".off")
SUBCOMMANDS = ("report", "aset", "idealscope", "hearts", "map", "tilt", "optimize", "retarget")

#: the limits of the flags (docs/limits.md): image size in pixels, wavelengths per pixel, and
#: the most values a list (``--tilts``, ``--azimuths``) may expand to
MIN_SIZE = 4
MAX_SIZE = 2048
MAX_WAVELENGTHS = 256
MAX_LIST = 1000


def _lightings() -> tuple[str, ...]:
    from ..grading.presets import LIGHTINGS

    return tuple(LIGHTINGS)


def _lighting(text: str) -> str:
    """argparse ``type=`` of ``--lighting``: a name of ``grading.presets.LIGHTINGS``."""
    import argparse

    names = _lightings()
    if text not in names:
        raise argparse.ArgumentTypeError(f"{text[:40]!r} is not a lighting (allowed: {', '.join(names)})")
    return text


def _numbers(text: str, field: str) -> list[float]:
    """``a,b,c`` or ``start:stop:step`` (stop included), finite, at most :data:`MAX_LIST` values."""
    import numpy as np

    try:
        if ":" in text:
            a, b, s = (float(x) for x in text.split(":"))
            if not (s > 0 and math.isfinite(a) and math.isfinite(b) and math.isfinite(s)) or b < a:
                raise ValueError
            count = math.floor((b - a) / s + 0.5) + 1
        else:
            vals = [float(x) for x in text.split(",") if x.strip()]
            count = len(vals)
    except ValueError:
        raise InputError(
            "expected comma-separated numbers or start:stop:step", field=field, value=text
        ) from None
    if count > MAX_LIST:
        raise InputError(
            f"gives {count:,} values, more than {MAX_LIST:,}: take a larger step or fewer values",
            field=field,
            value=text,
        )
    if ":" in text:
        return [float(v) for v in np.round(np.arange(a, b + 0.5 * s, s), 9)]
    if not vals or not all(math.isfinite(v) for v in vals):
        raise InputError("expected one or more finite numbers", field=field, value=text)
    return vals


def stone_from_args(args) -> tuple[dict, float | None]:
    """The ``[[object]]`` table of STONE (module docstring) with ``--set`` and ``--material``
    applied, and the frame (mm) the face-up camera needs for meshes (None: from the table)."""

    from ..geometry import cuts
    from ..scene.load import parse_set_options
    from ..scene.schema import SHAPES

    src = args.stone
    diameter = 6.5 if args.diameter is None else args.diameter
    p = Path(src)
    ext = p.suffix.lower()
    frame = None
    if ext == ".toml":
        data = val.toml_file(p)
        objs = data.get("object")
        if not isinstance(objs, list) or not objs or not isinstance(objs[0], dict):
            raise InputError("the scene has no [[object]]", file=src, field="object")
        stone = dict(objs[0])
        stone.pop("rotation", None)
        stone.pop("position", None)
        if "path" in stone and not Path(stone["path"]).is_absolute():
            stone["path"] = str((p.parent / stone["path"]).resolve())
        if stone.get("shape") == "mesh":
            frame = diameter
    elif ext in (".asc", ".gem"):
        if not p.is_file():
            raise InputError("GemCAD file not found", file=src)
        stone = {"shape": "gemcad", "path": str(p.resolve()), "diameter": diameter}
    elif ext in _MESH_EXT:
        if not p.is_file():
            raise InputError("mesh file not found", file=src)
        stone = {"shape": "mesh", "path": str(p.resolve())}
        frame = diameter
    else:
        names = [n for n in SHAPES if n not in ("mesh", "gemcad") and hasattr(cuts, n)]
        if src not in names:
            raise InputError("not a cut name or a file", field="STONE", value=src, allowed=", ".join(names))
        stone = {"shape": src}
        if _takes_diameter(src):
            stone["diameter"] = diameter
    if args.material:
        stone["material"] = args.material
    stone.update(parse_set_options(args.set))
    if stone.get("shape") not in ("mesh", "gemcad") and "diameter" not in stone and frame is None:
        # a cut without a girdle diameter (cube, plate, prism, ...): framed by its own extent,
        # or by --diameter when given
        frame = args.diameter if args.diameter is not None else _extent(stone)
    return stone, frame


def _takes_diameter(shape: str) -> bool:
    """Whether the cut function of ``shape`` has a ``diameter`` keyword (the brilliant family
    forwards its keywords to ``round_brilliant``)."""
    import inspect

    from ..geometry import cuts

    sig = inspect.signature(getattr(cuts, shape)).parameters
    return "diameter" in sig or any(v.kind == v.VAR_KEYWORD for v in sig.values())


def _extent(stone: dict) -> float:
    """The larger horizontal extent (mm) of a cut built from its table (its face-up frame)."""
    from ..sweep.optimize import stone_mesh

    b = stone_mesh(stone).bounds
    return float(max(b[1][0] - b[0][0], b[1][1] - b[0][1]))


def _protocol(args):
    from ..grading.performance import PROTOCOL

    kw = {"size": args.size, "wavelengths": args.wavelengths, "lighting": args.lighting}
    if args.head is not None:
        kw["head_radius_deg"] = args.head
    if getattr(args, "protocol_tilts", None):
        kw["tilts"] = tuple(_numbers(args.protocol_tilts, "--protocol-tilts"))
    if getattr(args, "protocol_azimuths", None):
        kw["azimuths"] = tuple(_numbers(args.protocol_azimuths, "--protocol-azimuths"))
    return dataclasses.replace(PROTOCOL, **kw)


def _runner_kw(args) -> dict:
    return {
        "resume": args.resume,
        "overwrite": args.overwrite,
        "dask_local": args.dask_local,
        "workers": args.workers,
        "progress": not args.quiet,
    }


def _write_json(path: Path, data) -> None:
    from ..sweep.results import write_text_atomic

    write_text_atomic(path, json.dumps(data, indent=1, default=str) + "\n")


def _png(path: str, rgb_linear) -> None:
    from ..color import encode_srgb
    from ..film.image import write_png

    if Path(path).suffix.lower() != ".png":
        raise InputError("the output must be a .png", field="-o", value=path)
    write_png(path, encode_srgb(rgb_linear))


def _print_fractions(name: str, fr: dict) -> None:
    print(f"{name}: " + ", ".join(f"{k} {v:.3f}" for k, v in fr.items()))


def run(args) -> int:
    sub = args.grade
    if sub == "retarget":
        return _retarget(args)
    if sub in ("aset", "idealscope", "hearts", "map") and Path(args.output).suffix.lower() != ".png":
        raise InputError("the output must be a .png", field="-o", value=args.output)
    from ..atomic import check_writable

    # before any render: an image beside its .json, or the files of a run's folder
    is_file = sub in ("aset", "idealscope", "hearts", "map")
    check_writable(args.output, folder=not is_file)
    stone, frame = stone_from_args(args)
    kw = {"frame_mm": frame} if frame is not None else {}
    if sub in ("aset", "idealscope", "hearts") and args.wavelengths is not None:
        kw["wavelengths"] = args.wavelengths
    if sub == "aset":
        from ..grading.presets import HEAD_RADIUS_DEG
        from ..grading.scopes import aset

        head = HEAD_RADIUS_DEG if args.head is None else args.head
        img, zones, _b = aset(stone, head_radius_deg=head, size=args.size, **kw)
        _png(args.output, img)
        _write_json(Path(args.output).with_suffix(".json"), {"stone": stone, "zones": zones})
        _print_fractions("ASET zones", zones)
    elif sub == "idealscope":
        from ..grading.scopes import ideal_scope

        img, fr, _b = ideal_scope(stone, size=args.size, **kw)
        _png(args.output, img)
        _write_json(Path(args.output).with_suffix(".json"), {"stone": stone, "fractions": fr})
        _print_fractions("Ideal Scope", fr)
    elif sub == "hearts":
        import numpy as np

        from ..grading.scopes import count_pattern, hearts_and_arrows

        img, _b = hearts_and_arrows(stone, face_down=args.face_down, size=args.size, **kw)
        lc = count_pattern(img, face_down=args.face_down)
        _png(args.output, np.repeat(np.clip(img, 0, 1)[..., None], 3, axis=-1))
        what = "hearts" if args.face_down else "arrows"
        _write_json(
            Path(args.output).with_suffix(".json"),
            {"stone": stone, what: lc.count, "verdict": lc.verdict, "per_ring": list(lc.per_ring)},
        )
        shown = lc.count if lc.count is not None else "none"
        print(f"{what}: {shown}, {lc.verdict} (dark lobes per ring: {list(lc.per_ring)})")
    elif sub == "map":
        from ..grading.performance import brightness_map
        from ..grading.presets import face_up_scene
        from ..pipelines.render import render
        from ..scene.load import Scene

        sc = face_up_scene(
            stone,
            lighting=args.lighting,
            head_radius_deg=args.head,
            size=args.size,
            wavelengths=args.wavelengths,
            tilt_deg=args.tilt,
            frame_mm=kw.get("frame_mm"),
        )
        im = render(Scene.from_dict(sc))
        img, fr, _rel = brightness_map(im.xyz, im.alpha, reference=args.reference)
        _png(args.output, img)
        _write_json(Path(args.output).with_suffix(".json"), {"stone": stone, "fractions": fr})
        _print_fractions("brightness map", fr)
    elif sub == "report":
        _report(args, stone, kw)
    elif sub == "tilt":
        from ..sweep.grading import tilt_series

        res = tilt_series(
            stone,
            args.output,
            tilts=_numbers(args.tilts, "--tilts"),
            azimuths=_numbers(args.azimuths, "--azimuths"),
            protocol=_protocol(args),
            fps=args.fps,
            **kw,
            **_runner_kw(args),
        )
        print(f"{args.output}: {res['rendered']} jobs rendered now ({res['renders']} renders)")
        for k in ("table", "plot", "animation"):
            if k in res["files"]:
                print(f"{k}: {res['files'][k]}")
    elif sub == "optimize":
        _optimize(args, stone, kw)
    sys.stdout.flush()
    return 0


def _report(args, stone, kw) -> None:
    from ..sweep.grading import light_performance

    proto = _protocol(args)
    out = Path(args.output)
    r = light_performance(
        stone, proto, out_dir=out / "sweep", fire=not args.no_fire, **kw, **_runner_kw(args)
    )
    names = ["light_return", "contrast", "extinction"] + ([] if args.no_fire else ["fire", "scintillation"])
    lines = [
        "# Light-performance report",
        "",
        f"Stone: `{json.dumps(stone)}`",
        "",
        f"Protocol (warpoptics.grading.performance): tilts {list(proto.tilts)} deg about azimuths "
        f"{list(proto.azimuths)} deg, {proto.lighting} light with a {proto.head_radius_deg:g} deg head, "
        f"observer at 250 mm, {proto.size} px, {proto.wavelengths} wavelengths; fire and scintillation "
        f"under `{proto.fire_lighting}`. {r['renders']} renders.",
        "",
        "| metric | protocol mean |",
        "|---|---|",
        *[f"| {k} | {r[k]:.4f} |" for k in names],
        "",
        "Per view: see `report.json`; the face-up image: `sweep/images/`.",
        "",
    ]
    from ..sweep.results import write_text_atomic

    write_text_atomic(out / "report.md", "\n".join(lines))
    _write_json(out / "report.json", {"stone": stone, "protocol": dataclasses.asdict(proto), **r})
    for k in names:
        print(f"{k:14s} {r[k]:.4f}")
    print(f"report: {out / 'report.md'}")


def _optimize(args, stone, kw) -> None:
    from ..sweep.optimize import Constraints, CutOptimizer, Parameter

    params = []
    for item in args.param or []:
        name, _, rng = item.partition("=")
        vals = rng.split(":")
        try:
            nums = [float(v) for v in vals]
        except ValueError:
            nums = []
        if not name or len(nums) not in (2, 3):
            raise InputError("expected KEYWORD=LOW:HIGH[:START]", field="--param", value=item)
        name = name.strip()
        if name.startswith("tier:"):  # a GemCAD tier angle: tier:<name or #k> (gemcad.recut_tiers)
            tier = name[len("tier:") :]
            if not tier or "." in tier:
                raise InputError(
                    "expected tier:<tier name or #k>=LOW:HIGH[:START]", field="--param", value=item
                )
            safe = "".join(c if c.isalnum() or c == "_" else "_" for c in tier)
            params.append(Parameter(f"tier_{safe}", f"object.0.tier_angles.{tier}", *nums))
        else:
            params.append(Parameter(name, f"object.0.{name}", *nums))
    if not params:
        raise InputError("give at least one --param KEYWORD=LOW:HIGH[:START]", field="--param")
    objective = {}
    for part in args.objective.split(","):
        k, _, w = part.partition("=")
        try:
            objective[k.strip()] = float(w) if w else 1.0
        except ValueError:
            raise InputError("expected METRIC=WEIGHT,...", field="--objective", value=part) from None

    def span(text, field):
        if text is None:
            return None
        v = _numbers(text.replace(":", ","), field)
        if len(v) != 2:
            raise InputError("expected MIN:MAX", field=field, value=text)
        return (v[0], v[1])

    cons = Constraints(
        depth=span(args.depth, "--depth"),
        table=span(args.table_range, "--table-range"),
        min_weight_retention=args.min_weight,
        rough_height=args.rough_height,
    )
    opt = CutOptimizer(
        stone,
        params,
        args.output,
        objective=objective,
        protocol=_protocol(args),
        constraints=cons,
        budget=args.budget,
        popsize=args.popsize,
        seed=args.seed,
        **kw,
        **_runner_kw(args),
    )
    r = opt.run()
    best = r["best"]
    print(
        "best: "
        + ", ".join(f"{k} {v:.3f}" for k, v in best["values"].items())
        + f"; objective {best['objective']:.4f} ({r['evaluations']} evaluations, {r['renders']} renders)"
    )
    print(f"design: {r['files']['best']}; report: {r['files']['report']}")


def _retarget(args) -> int:
    from ..geometry import gemcad
    from ..grading.design import retarget, tier_report

    src = Path(args.stone)
    if src.suffix.lower() not in (".asc", ".gem") or not src.is_file():
        raise InputError("retarget needs a GemCAD design file (.asc/.gem)", field="STONE", value=args.stone)
    if args.index is None:
        raise InputError("give the new refractive index", field="--index")
    design = gemcad.read_design(src)
    before = tier_report(design, n=args.index)
    new, after = retarget(design, args.index)
    if not args.output.lower().endswith(".asc"):
        raise InputError("the output must be a .asc", field="-o", value=args.output)
    gemcad.write(new, args.output)
    print(f"critical angle {before[0]['critical_angle']:.2f} deg at n = {args.index:g}")
    print(f"{'tier':>4} {'part':9s} {'angle':>8} {'windows as cut':>15} {'retargeted':>11} {'windows':>8}")
    for b, a in zip(before, after, strict=True):
        if b["part"] in ("pavilion", "crown"):
            print(
                f"{b['tier']:4d} {b['part']:9s} {b['angle']:8.2f} {('yes' if b['windows'] else 'no'):>15} "
                f"{a['angle']:11.2f} {('yes' if a['windows'] else 'no'):>8}"
            )
    print(f"wrote {args.output}")
    return 0


def register(sub) -> None:
    p = sub.add_parser(
        "grade", help="cut grading: light performance, ASET, Ideal Scope, H&A, tilt, optimizer"
    )
    gs = p.add_subparsers(dest="grade", metavar="WHAT", required=True)
    helps = {
        "report": "light-performance report under the tilted, head-obscured protocol (folder)",
        "aset": "ASET image (AGS zones) and zone fractions (.png + .json)",
        "idealscope": "Ideal Scope image and fractions (.png + .json)",
        "hearts": "Hearts & Arrows viewer image and the count of dark lobes (.png + .json)",
        "map": "brightness/contrast map (colourless or coloured stones) (.png + .json)",
        "tilt": "tilt series: metrics vs tilt over azimuths, CSV, plot, GIF (folder)",
        "optimize": "CMA-ES cut optimizer: best design (.asc), journal, report (folder)",
        "retarget": "re-cut a GemCAD design for another index; tiers that window",
    }
    for name in SUBCOMMANDS:
        q = gs.add_parser(name, help=helps[name])
        q.add_argument("stone", metavar="STONE", help="cut name, .asc/.gem, mesh or scene .toml")
        q.add_argument("-o", "--output", required=True, help="output file or folder")
        q.add_argument(
            "--diameter",
            type=val.flag(float, lo=0.0, lo_open=True, hi=1000.0, unit="mm"),
            default=None,
            help="girdle diameter, mm (default 6.5; meshes and cuts without a diameter: the frame)",
        )
        q.add_argument("--material", help="material name (default diamond, or the design's index)")
        q.add_argument(
            "--set", action="append", metavar="KEY=VALUE", help="a cut keyword, e.g. pavilion_angle=41"
        )
        if name == "retarget":
            q.add_argument("--index", type=val.flag(float, lo=1.0, hi=5.0), help="the new refractive index")
            q.set_defaults(func=run)
            continue
        scope = name in ("aset", "idealscope", "hearts")
        q.add_argument(
            "--size",
            type=val.flag(int, lo=MIN_SIZE, hi=MAX_SIZE, unit="pixels"),
            default=96 if name in ("aset", "idealscope", "hearts", "map") else 64,
            help=f"image size, pixels ({MIN_SIZE} to {MAX_SIZE})",
        )
        q.add_argument(
            "--wavelengths",
            type=val.flag(int, lo=1, hi=MAX_WAVELENGTHS),
            default=None if scope else 8,
            help="wavelengths per pixel (default "
            + ("4" if scope else "8")
            + f"; at most {MAX_WAVELENGTHS})",
        )
        if not scope:  # the scopes light the stone with their own coloured bands
            q.add_argument(
                "--lighting", type=_lighting, default="iso", help="one of " + ", ".join(_lightings())
            )
        if name not in ("idealscope", "hearts"):  # their dark cones are fixed by the instrument
            hi = 45.0 if name == "aset" else 90.0
            q.add_argument(
                "--head",
                type=val.flag(float, lo=0.0, lo_open=True, hi=hi, hi_open=name == "aset", unit="degrees"),
                default=None,
                help="head radius, degrees (default 10)",
            )
        if name in ("report", "tilt", "optimize"):
            q.add_argument("--resume", action="store_true", help="continue after a kill")
            q.add_argument("--overwrite", action="store_true", help="start again in a folder with results")
            q.add_argument(
                "--dask-local",
                type=val.flag(int, lo=1, hi=256),
                metavar="N",
                help="run on a local Dask cluster of N",
            )
            q.add_argument(
                "--workers", type=val.flag(int, lo=1, hi=256), default=1, help="jobs at once on this machine"
            )
            q.add_argument("--quiet", action="store_true", help="no progress bar")
        if name in ("report", "optimize"):
            q.add_argument("--protocol-tilts", help="protocol tilts, degrees (default 0,5,10,15,20)")
            q.add_argument("--protocol-azimuths", help="protocol azimuths, degrees (default 0,22.5)")
        if name == "report":
            q.add_argument(
                "--no-fire", action="store_true", help="skip fire and scintillation (1/3 the renders)"
            )
        if name == "hearts":
            q.add_argument("--face-down", action="store_true", help="pavilion up: hearts (default arrows)")
        if name == "map":
            q.add_argument("--reference", choices=("white", "stone"), default="white")
            q.add_argument(
                "--tilt",
                type=val.flag(float, lo=-80.0, hi=80.0, unit="degrees"),
                default=0.0,
                help="tilt, degrees",
            )
        if name == "tilt":
            q.add_argument("--tilts", default="0:30:2", help="degrees: a,b,c or start:stop:step")
            q.add_argument("--azimuths", default="0,22.5", help="degrees (default 0,22.5)")
            q.add_argument(
                "--fps",
                # a GIF frame's delay is 16 bits of 10 ms: 655 s at most (1e-9 overflowed it)
                type=val.flag(float, lo=0.01, hi=100.0),
                default=6.0,
                help="animation frames per second (default 6; 0.01 to 100)",
            )
        if name == "optimize":
            q.add_argument(
                "--param",
                action="append",
                metavar="KEYWORD=LOW:HIGH[:START]",
                help="a cut keyword, or tier:<name|#k> for a GemCAD tier angle (repeatable)",
            )
            q.add_argument(
                "--objective", default="light_return", help="METRIC=WEIGHT,... (default light_return)"
            )
            q.add_argument(
                "--budget",
                type=val.flag(int, lo=1, hi=100_000),
                default=40,
                help="evaluations that render (default 40)",
            )
            q.add_argument("--popsize", type=val.flag(int, lo=2, hi=1000), default=None)
            q.add_argument("--seed", type=val.flag(int, lo=0, hi=2**32 - 1), default=1)
            q.add_argument("--depth", metavar="MIN:MAX", help="total depth / diameter range")
            q.add_argument("--table-range", metavar="MIN:MAX", help="table / diameter range")
            q.add_argument(
                "--min-weight",
                type=val.flag(float, lo=0.0, lo_open=True, hi=1.0, hi_open=True),
                help="minimum weight retention (V / V_rough)",
            )
            q.add_argument(
                "--rough-height",
                type=val.flag(float, lo=0.0, lo_open=True, hi=100.0),
                default=1.0,
                help="rough height / diameter",
            )
        q.set_defaults(func=run)

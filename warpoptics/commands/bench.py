"""`warpoptics bench SCENE.toml -o SCREEN.{png,exr}`: trace an optical-bench scene forward.

Writes the first screen's image to ``-o`` (other screens beside it as ``NAME-<screen>.ext``) and
prints the energy ledger and each screen's power.
"""

from __future__ import annotations

from pathlib import Path

_FORMATS = (".exr", ".png", ".jpg", ".jpeg", ".tif", ".tiff")


def run(args) -> int:
    from ..errors import InputError
    from ..pipelines.bench import Bench
    from ..scene.bench import BenchScene
    from ..scene.load import parse_set_options

    out = Path(args.output)
    if out.suffix.lower() not in _FORMATS:
        raise InputError("unsupported output format", field="-o", value=str(out), allowed=", ".join(_FORMATS))
    scene = BenchScene.load(args.scene)
    overrides = parse_set_options(args.set)
    if getattr(args, "rays", None) is not None:
        overrides["source.rays"] = args.rays
    if getattr(args, "wavelengths", None) is not None:
        overrides["render.wavelengths"] = args.wavelengths
    if overrides:
        scene = scene.with_overrides(overrides)
    result = Bench(scene, device=args.device).run(threads=getattr(args, "threads", None))
    written = []
    for k, img in enumerate(result.screens):
        path = out if k == 0 else out.with_name(f"{out.stem}-{img.screen.name}{out.suffix}")
        img.save(path)
        written.append(path)
    s = result.stats
    print(
        f"{', '.join(map(str, written))}: {s['beam_rays']} beam rays, {s['deposits']} deposits, "
        f"{s['seconds']:.2f} s"
    )
    for img in result.screens:
        print(f"screen {img.screen.name}: {img.power:.6f} W")
    print("ledger (W): " + ", ".join(f"{k} {v:.6f}" for k, v in result.ledger.items()))
    print(f"closure (screen + absorbed + escaped) / emitted - 1 = {result.balance():+.2e}")
    return 0


def register(sub) -> None:
    p = sub.add_parser("bench", help="trace an optical-bench scene (beam -> objects -> screens)")
    p.add_argument(
        "scene", help='bench scene file (.toml with [source] type = "beam" and [[sensor]] screens)'
    )
    p.add_argument("-o", "--output", required=True, help="screen image: .exr (RGB, A, S0..S3, XYZ) or .png")
    p.add_argument("--rays", type=int, help="override source.rays (beam positions)")
    p.add_argument("--wavelengths", type=int, help="override render.wavelengths")
    p.add_argument("--threads", type=int, help="CPU worker threads (default: all cores)")
    p.add_argument(
        "--set",
        action="append",
        metavar="KEY=VALUE",
        help='override any scene value by dotted path, e.g. --set object.0.material="water"',
    )
    p.set_defaults(func=run)

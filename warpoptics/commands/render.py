"""`warpoptics render SCENE.toml -o OUT.{exr,png}`: render a scene with the standard pipeline."""

from __future__ import annotations

import sys


def _check_writable(out: str) -> None:
    """Fail before rendering, not after, when the output cannot be written (no finished render is
    lost to a bad ``-o``)."""
    import os
    from pathlib import Path

    from ..errors import InputError

    parent = Path(out).resolve().parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot create the output folder ({exc.strerror})", field="-o", value=out) from None
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError("the output folder is not writable", field="-o", value=out)
    if Path(out).is_dir():
        raise InputError("is a folder, not an image file", field="-o", value=out)


def _auto_dichroscope(scene, *, file=None) -> str:
    """``dichroscope:auto``: the dichroscope at the angle of the fast eigenwave travelling along
    the camera's view axis in the scene's first birefringent stone (its world crystal frame)."""
    from ..errors import InputError
    from ..film.views import eigenwave_angle
    from ..materials import Biaxial, Uniaxial
    from ..pipelines.objects import build_objects, world_axes
    from ..stages.camera import camera_basis

    built = build_objects(scene.objects, file=file)
    axes = world_axes(scene.objects, built, file=file)
    fwd, right, up = camera_basis(scene.camera)
    for i, mat in enumerate(built.materials):
        if isinstance(mat, Uniaxial):
            mat = Uniaxial(mat.ordinary, mat.extraordinary, optic_axis=tuple(axes[i]), name=mat.name)
        if isinstance(mat, (Biaxial, Uniaxial)):
            angle = eigenwave_angle(mat, fwd, right, up)
            waves = "fast wave left, slow right" if isinstance(mat, Biaxial) else "o-wave left, e-wave right"
            print(f"dichroscope:auto -> {angle:.2f} deg (object.{i} {mat.name}: {waves})")
            return f"dichroscope:{angle:.6g}"
    raise InputError(
        "dichroscope:auto needs a birefringent stone in the scene",
        file=file,
        field="--view",
        value="dichroscope:auto",
    )


def run(args) -> int:
    from ..errors import InputError
    from ..pipelines.render import Renderer
    from ..scene.bench import is_bench_scene
    from ..scene.load import Scene, parse_set_options
    from ..scene.schema import RenderConfig

    if is_bench_scene(args.scene):
        # an optical-bench scene ([source] type = "beam"): trace it forward onto its screens
        from . import bench as bench_command

        camera_only = [
            f"--{k}" for k in ("width", "height", "spp", "view") if getattr(args, k, None) is not None
        ]
        if camera_only:
            raise InputError(
                "a bench scene has no camera, so these options do not apply",
                file=args.scene,
                field=", ".join(camera_only),
                allowed="--rays, --wavelengths, --set (or warpoptics bench)",
            )

        return bench_command.run(args)
    scene = Scene.load(args.scene)
    overrides = parse_set_options(args.set)
    kw = {k: getattr(args, k) for k in ("width", "height", "spp") if getattr(args, k) is not None}
    out = args.output
    if not out.lower().endswith((".exr", ".png", ".jpg", ".jpeg", ".tif", ".tiff")):
        raise InputError("unsupported output format", field="-o", value=out, allowed=".exr, .png, .jpg, .tif")
    if "width" in kw or "height" in kw:
        # refuse an image that cannot fit in memory before the pixel-count limits, with an estimate
        from ..pipelines.render import check_render_memory

        check_render_memory(
            kw.get("width", scene.camera.width),
            kw.get("height", scene.camera.height),
            file=args.scene,
            beams=scene.render.estimator != "point",
        )
    _check_writable(out)
    spp = kw.get("spp", overrides.get("render.spp"))
    if isinstance(spp, int) and scene.render.adaptive and "render.adaptive" not in overrides:
        # a quick look (--spp 1 or 2) at an adaptive scene: too few samples for a pilot and an
        # adaptive rest, so sample every pixel alike instead of refusing (a pilot_spp the
        # command sets is left to the scene's validation)
        pilot_spp = scene.render.pilot_spp
        if "render.pilot_spp" not in overrides and not RenderConfig.pilot_fits(spp, pilot_spp):
            overrides["render.adaptive"] = False
            print(
                f"render.adaptive off: spp = {spp} leaves no samples to allocate after a pilot of "
                f"{RenderConfig.pilot_for(spp, pilot_spp)} (adaptive sampling needs spp >= 3)"
            )
    if overrides or kw:
        scene = scene.with_overrides(overrides, **kw)
    view = args.view if args.view is not None else scene.view
    if view is not None:
        # check the view (and that the light is polarized for a polariscope) before rendering
        from ..film.views import parse_view

        kind, arg = parse_view(view)
        if kind == "dichroscope" and arg == "auto":
            view = _auto_dichroscope(scene, file=args.scene)
        if kind in ("analyzer", "dichroscope") and not scene.render.polarization:
            print(
                f"warpoptics render: warning: {view} of an unpolarized render (render.polarization = "
                "false) passes half of the light whatever its angle",
                file=sys.stderr,
            )
        if kind == "polariscope" and scene.lights[0].polarizer is None:
            raise InputError(
                "a polariscope view needs polarized light",
                field="--view",
                value=view,
                allowed="--set light.0.polarizer=ANGLE (degrees)",
            )
    renderer = Renderer(scene, device=args.device)
    image = renderer.run(progress=not args.quiet and sys.stderr.isatty() or args.progress)
    if view is not None:
        image = image.view(view)
    image.save(out)
    for i, ob in enumerate(scene.objects):
        if ob.material_source == "gemcad":
            n = ob.material["cauchy"][0]
            print(
                f"object.{i}: material n = {n:g}, the GemCAD file's index (set object.{i}.material to change)"
            )
    s = image.stats
    print(
        f"{out}: {s['width']}x{s['height']}, {s['seconds']:.2f} s, {s['rays'] / 1e6:.2f} M rays, "
        f"{s['rays_per_second'] / 1e6:.2f} M rays/s"
        + (
            f", adaptive: {s['spp_mean']:.1f} spp per pixel on average, {s['spp_max']} at most"
            if scene.render.adaptive
            else ""
        )
    )
    # which camera estimator ran and why (render.estimator; Image.stats)
    kind = "pixel beams" if s["estimator"] == "beam" else "point samples"
    print(f"estimator: {kind} ({s['estimator_reason']})")
    return 0


def register(sub) -> None:
    p = sub.add_parser("render", help="render a scene (TOML) to an EXR or PNG image")
    p.add_argument("scene", help="scene file (.toml)")
    p.add_argument("-o", "--output", required=True, help="output image: .exr (RGB, A, S0..S3, XYZ) or .png")
    p.add_argument("--width", type=int, help="override camera.width")
    p.add_argument("--height", type=int, help="override camera.height")
    p.add_argument("--spp", type=int, help="override render.spp")
    p.add_argument(
        "--set",
        action="append",
        metavar="KEY=VALUE",
        help="override any scene value by dotted path, e.g. --set object.0.pavilion_angle=41",
    )
    p.add_argument(
        "--view",
        metavar="VIEW",
        help="polarization view: analyzer:ANGLE (degrees from image right toward up), "
        "polariscope (crossed; polariscope:parallel), dichroscope[:ANGLE|auto] (two orthogonal "
        "analyzers side by side) or none; default the scene's [view]",
    )
    p.add_argument("--progress", action="store_true", help="show a progress bar even when not on a terminal")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=run)

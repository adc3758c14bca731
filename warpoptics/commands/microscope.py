"""`warpoptics microscope`: a polarizing-microscope scene (TOML) rendered to an image.

    warpoptics microscope scenes/microscope/quartz_thin_section.toml -o section.png
    warpoptics microscope scenes/microscope/calcite_conoscope.toml -o figure.png [--size 301]
    warpoptics microscope SCENE.toml -o out.png --stage 45      (turn the stage by 45 degrees)

A scene has a ``[microscope]`` table (mode orthoscopic | conoscopic, polarizer and analyzer,
stage rotation, accessory plate: none | first_order_red | quarter_wave | quartz_wedge,
illuminant, numerical aperture, size, field) and a ``[sample]`` table (a plate of a material,
thickness and orientation, or a thin section: a mosaic of Voronoi grains with random
orientations); see ``warpoptics/scene/microscope.py``.  Colours come from the coherent plate
(``pipelines/microscope.py``): the o and e waves added as amplitudes.
"""

from __future__ import annotations

import argparse
import dataclasses

import numpy as np

from .. import validate as val

__all__ = ["register", "run"]


def run(args) -> int:
    from ..errors import InputError
    from ..film.image import write_png
    from ..pipelines.microscope import microscope_view
    from ..scene.microscope import MicroscopeScene

    if args.output is None:
        raise InputError("an output image is required", field="-o")
    from ..atomic import check_writable

    check_writable(args.output)  # before the work
    scene = MicroscopeScene.load(args.scene)
    mic = scene.microscope
    if args.size is not None:
        mic = dataclasses.replace(mic, size=args.size)
    if args.stage is not None:
        mic = dataclasses.replace(mic, stage_rotation=float(args.stage))
    scene = dataclasses.replace(scene, microscope=mic)
    view = microscope_view(scene, device=args.device)
    path = write_png(args.output, np.clip(view.srgb, 0.0, 1.0))
    print(view.title)
    if view.grain is not None:
        print(f"grains         {int(np.unique(view.grain).size)} in the field")
    print(f"wrote {path}")
    return 0


def register(sub) -> None:
    p = sub.add_parser(
        "microscope",
        help="polarizing microscope scene (TOML): orthoscopic thin sections and plates, conoscopic figures",
        description=__doc__.split("\n\n", 1)[1] if __doc__ else None,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("scene", help="microscope scene file (.toml)")
    p.add_argument("-o", "--output", default=None, help="output image (.png)")
    p.add_argument(
        "--size",
        type=val.flag(int, lo=8, hi=4096, unit="pixels"),
        default=None,
        help="image size in pixels, 8 to 4096 (overrides microscope.size)",
    )
    p.add_argument(
        "--stage",
        type=val.flag(float, lo=-360.0, hi=360.0, unit="degrees"),
        default=None,
        help="stage rotation in degrees (overrides the scene)",
    )
    p.set_defaults(func=run)

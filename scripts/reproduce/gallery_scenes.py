"""Render one of the showcase scenes of ``scenes/`` into the gallery (docs/gallery/scene_<name>.png).

The scenes are the ones the papers' figures describe and that need the whole renderer (tables,
lamps, lenses, films, polarizers), so the "script" for each is the scene file itself rendered at
a gallery size; this wrapper picks the size, prints the render statistics and writes the PNG
atomically.

    python scripts/reproduce/gallery_scenes.py dof                  # instanced diamonds, thin lens
    python scripts/reproduce/gallery_scenes.py soap_bubble          # Smits & Meyer fig. 6: a bubble in 3D
    python scripts/reproduce/gallery_scenes.py diamonds_on_table    # two gems, two light boxes
    python scripts/reproduce/gallery_scenes.py calcite              # the double image of a calcite rhomb
    python scripts/reproduce/gallery_scenes.py caustics             # a gem's fire on the table (light tracer)
    python scripts/reproduce/gallery_scenes.py mystic_topaz | oil_slick | morpho
    python scripts/reproduce/gallery_scenes.py dof --quick          # tiny, for the tests
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _gallery import GALLERY, ROOT, Timer, write_json  # noqa: E402

# name: (scene file, width, height, [render] overrides) — sizes chosen to stay under 5 min on 2 cores
SCENES = {
    "dof": ("dof.toml", 320, 200, {"spp": 12}),
    "soap_bubble": ("soap_bubble.toml", 240, 240, {}),
    "diamonds_on_table": ("diamonds_on_table.toml", 320, 240, {"spp": 12}),
    "calcite": ("calcite.toml", 240, 240, {}),
    "mystic_topaz": ("mystic_topaz.toml", 240, 240, {}),
    "oil_slick": ("oil_slick.toml", 256, 192, {}),
    "morpho": ("morpho.toml", 256, 192, {}),
    "caustics": ("caustics.toml", 384, 288, {}),
}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("name", choices=sorted(SCENES))
    ap.add_argument("-o", "--output", help="PNG path (default docs/gallery/scene_<name>.png)")
    ap.add_argument("--quick", action="store_true", help="a 48-pixel-wide smoke render")
    ap.add_argument("--device", default=None)
    args = ap.parse_args(argv)

    import warpoptics as wo

    file, w, h, over = SCENES[args.name]
    if args.quick:
        w, h = 48, max(1, 48 * h // w)
        if args.name == "caustics":
            over = {**over, "caustic_paths": 20000}
    out = Path(args.output) if args.output else GALLERY / f"scene_{args.name}.png"
    with Timer() as t:
        img = wo.render(ROOT / "scenes" / file, width=w, height=h, device=args.device, **over)
    img.save(out)
    s = img.stats
    readout = {
        "scene": f"scenes/{file}",
        "width": w,
        "height": h,
        "wall_seconds": round(t.seconds, 2),
        "render_seconds": round(s["seconds"], 2),
        "rays": s["rays"],
        "rays_per_second": round(s["rays_per_second"]),
        "mean_Y": float(img.xyz[..., 1].mean()),
    }
    print(json.dumps(readout))
    if not args.quick:
        write_json(out.with_suffix(".json"), readout)
    return 0


if __name__ == "__main__":
    sys.exit(main())

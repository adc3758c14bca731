"""`warpoptics cut`: build a gem cut (or read a GemCAD design), write it, print its proportions.

warpoptics cut round_brilliant --pavilion-angle 41 -o gem.ply
warpoptics cut design.asc --diameter 6.5 -o gem.ply
warpoptics cut oval --length 8 --width 6 -o oval.asc      # GemCAD output
"""

from __future__ import annotations

import inspect
import os
import sys
import warnings

from ..errors import InputError

# option name -> (type, help); passed to the shape function when given and accepted by it
_OPTIONS = {
    "diameter": (float, "girdle diameter / width (mm); also the girdle width a .asc design is scaled to"),
    "length": (float, "length (mm; fancy shapes, plate, prism extrusion)"),
    "width": (float, "width (mm)"),
    "table": (float, "table size / diameter (fraction, e.g. 0.53)"),
    "crown_angle": (float, "crown (bezel) angle, degrees"),
    "pavilion_angle": (float, "pavilion main angle, degrees"),
    "star_length": (float, "star length (fraction)"),
    "lower_girdle_length": (float, "lower girdle length (fraction)"),
    "girdle": (float, "girdle thickness / diameter (fraction)"),
    "culet": (float, "culet size / diameter (fraction)"),
    "girdle_facets": (int, "number of girdle facets (16, 32, 64, 128)"),
    "corner": (float, "step cut corner size / width (fraction)"),
    "crown_angles": (str, "step cut crown tier angles, comma-separated degrees"),
    "pavilion_angles": (str, "step cut pavilion tier angles, comma-separated degrees"),
    "apex_angle": (float, "prism apex angle, degrees"),
    "size": (float, "prism face width / cube edge (mm)"),
    "thickness": (float, "plate / ground thickness (mm)"),
    "subdivisions": (int, "sphere subdivisions"),
}
_MESH_EXT = (".ply", ".stl", ".obj", ".glb", ".off")


def _angles(text: str, name: str) -> tuple[float, ...]:
    try:
        return tuple(float(x) for x in text.split(",") if x.strip())
    except ValueError:
        raise InputError(
            "expected comma-separated numbers", field=f"--{name.replace('_', '-')}", value=text
        ) from None


def run(args) -> int:
    from ..geometry import cuts, gemcad

    out = args.output
    ext = os.path.splitext(out)[1].lower()
    if ext not in (*_MESH_EXT, ".asc"):
        raise InputError(
            "unsupported output format", field="-o", value=out, allowed=", ".join((*_MESH_EXT, ".asc"))
        )
    given = {k: getattr(args, k) for k in _OPTIONS if getattr(args, k) is not None}
    src = args.shape
    if src.lower().endswith(".asc"):
        extra = set(given) - {"diameter"}
        if extra:
            raise InputError(
                "a GemCAD design takes only --diameter", field="--" + sorted(extra)[0].replace("_", "-")
            )
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            design = gemcad.read_design(src)
        for w in caught:
            print(f"warning: {w.message}", file=sys.stderr)
        mesh = gemcad.design_to_mesh(design, given.get("diameter", 1.0), source=src)
    else:
        if src not in cuts.SHAPES:
            raise InputError(
                "unknown shape", field="shape", value=src, allowed=", ".join(cuts.SHAPES) + " or a .asc file"
            )
        fn = cuts.SHAPES[src]
        params = inspect.signature(fn).parameters
        accepts_kw = any(p.kind is p.VAR_KEYWORD for p in params.values())
        kwargs = {}
        for k, v in given.items():
            if k in ("crown_angles", "pavilion_angles"):
                v = _angles(v, k)
            if k == "diameter" and "diameter" not in params and "width" in params:
                k = "width"
            if k in kwargs:
                raise InputError("given twice (--diameter means --width here)", field=f"--{k}")
            if k not in params and not (accepts_kw and k in _OPTIONS):
                raise InputError(
                    f"not a parameter of {src}",
                    field=f"--{k.replace('_', '-')}",
                    allowed=", ".join(f"--{p.replace('_', '-')}" for p in params if p != "kw"),
                )
            kwargs[k] = v
        mesh = fn(**kwargs)
    from ..atomic import atomic_path

    with atomic_path(out) as tmp:  # a crash never leaves a half-written mesh
        if ext == ".asc":
            # a design read from a file is written as it was read (index, titles, notes, gear),
            # not re-derived from its mesh
            gemcad.write(mesh.metadata.get("design", mesh), tmp)
        else:
            mesh.export(tmp, file_type=ext.lstrip("."))
    n_facets = len(mesh.metadata.get("planes", []))
    print(f"wrote {out}: {n_facets} facets, {len(mesh.faces)} triangles, volume {mesh.volume:.6g} mm^3")
    prop = mesh.metadata.get("proportions")
    if prop is not None:
        print(prop.summary())
    return 0


def register(sub) -> None:
    p = sub.add_parser(
        "cut",
        help="build a gem cut or read a GemCAD .asc design; write a mesh or .asc",
        description=__doc__.split("\n\n")[0],
    )
    p.add_argument(
        "shape",
        help="a cut name (round_brilliant, oval, pear, marquise, emerald, princess, "
        "step_cut, prism, plate, cube, sphere, ground_plane) or a GemCAD .asc file",
    )
    p.add_argument(
        "-o", "--output", required=True, help="output: .ply, .stl, .obj, .glb, .off or .asc (GemCAD)"
    )
    for k, (typ, hlp) in _OPTIONS.items():
        p.add_argument(f"--{k.replace('_', '-')}", dest=k, type=typ, default=None, help=hlp)
    p.set_defaults(func=run)

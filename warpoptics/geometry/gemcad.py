"""GemCAD ``.asc`` faceting designs: reader, writer, and the stone as an intersection of half-spaces.

The file (GemCAD for Windows text export) holds a gear line ``g <teeth> <offset>``, symmetry
``y``, index ``I``, header ``H`` and footnote ``F`` lines and one ``a`` record per tier: the facet
angle from the girdle plane (negative: pavilion, positive: crown), the distance of the facet
planes from the centre and the index-gear positions of its facets (``n <name>`` names a facet,
``G <instruction>`` ends the record).

Conventions.  Index ``i`` is the facet azimuth ``phi = 90 deg - 360 deg (i - offset) / gear``
(gear signed; the offset in teeth rotates the design, GemCad 4.51 manual, Index gear key),
counter-clockwise from +x: for ``g 96 0`` index 0 points to +y and index 24 to +x, as in
GemCAD's crown view.  A facet at angle ``theta`` has the outward normal
``(sin|theta| cos phi, sin|theta| sin phi, +-cos theta)`` (+ crown) and is the plane
``n . x = distance``; the stone is the intersection of these half-spaces, scaled so that its
girdle width is the requested diameter in mm.

The reader accepts a BOM, any line ends, glued keywords and continuation lines, merges a facet
listed twice (with a warning) and refuses binary ``.gem`` files; the writer emits
Windows-1252/CRLF and keeps every record read, so dumps of a parsed file is a fixed point.
:func:`recut_tiers` re-cuts named tiers at new angles as a cutter would: each facet keeps its
azimuth and is lowered to the meet point it was cut to (the centre-point rule of faceting
diagrams, GemCad 4.51 tutorial, lesson 4).

The format in full, the frame against GemCAD's views and the re-cutting rule's details:
docs/design/gemcad.md.

References: R. W. Strickland, GemCad User's Manual 4.51 (1992) and GemCad for Windows User's
Guide; mbparker/gemcad-file-reader (MIT), ``GemCadAscImport.cs``.
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
import warnings

import numpy as np
import trimesh

from ..errors import InputError
from .cuts import convex_from_planes, direction_words, measure_proportions, open_direction

__all__ = [
    "Tier",
    "Design",
    "parse",
    "read_design",
    "read",
    "design_to_mesh",
    "design_from_mesh",
    "dumps",
    "write",
    "tier_index",
    "check_tier_angles",
    "recut_tiers",
]


@dataclasses.dataclass
class Tier:
    """One ``a`` record: facets at one angle and distance, one per index."""

    angle: float  # degrees, signed (negative: pavilion)
    distance: float  # design units; negative only for a culet written as angle 0
    indices: list[float]
    names: dict[int, str] = dataclasses.field(default_factory=dict)  # position in indices -> name
    instruction: str = ""
    pavilion_zero: bool = False  # angle written as "-0": a culet
    line: int = 0  # line of the record in the file it was read from (0: not read from a file)

    @property
    def is_culet(self) -> bool:
        return self.angle == 0 and (self.distance < 0 or self.pavilion_zero)

    @property
    def is_table(self) -> bool:
        return self.angle == 0 and not self.is_culet


@dataclasses.dataclass
class Design:
    """A GemCAD design: header records and tiers.

    ``gear`` is signed (its sign the direction the indices run), ``offset`` the index offset in
    teeth of the ``g`` line (see module doc); ``refractive_index`` the ``I`` line.
    """

    tiers: list[Tier]
    gear: int = 96
    offset: float = 0.0
    symmetry: int = 1
    mirror: bool = False
    refractive_index: float = 1.54
    headers: list[str] = dataclasses.field(default_factory=list)
    footnotes: list[str] = dataclasses.field(default_factory=list)
    version: str = "5.0"

    @property
    def index(self) -> float:
        """The refractive index the design was made for (its ``I`` line)."""
        return self.refractive_index

    @property
    def title(self) -> str:
        """The first ``H`` line (GemCAD's title), or ``""``."""
        return self.headers[0] if self.headers else ""

    def azimuth(self, idx: float) -> float:
        """Azimuth (radians, counter-clockwise from +x) of the facet normal at gear index ``idx``."""
        return math.radians(90.0 - 360.0 * (idx - self.offset) / self.gear)

    def facets(self) -> list[tuple[int, int, np.ndarray, float, str]]:
        """One ``(tier, position, unit normal, distance, name)`` per facet plane, in design units."""
        out = []
        for t, tier in enumerate(self.tiers):
            base = next(iter(tier.names.values()), None)
            if tier.angle == 0:
                culet = tier.is_culet
                nrm = np.array([0.0, 0.0, -1.0 if culet else 1.0])
                out.append(
                    (
                        t,
                        0,
                        nrm,
                        abs(tier.distance) if culet else tier.distance,
                        base or ("culet" if culet else "table"),
                    )
                )
                continue
            th = math.radians(abs(tier.angle))
            sz, st = (1.0 if tier.angle > 0 else -1.0) * math.cos(th), math.sin(th)
            for j, idx in enumerate(tier.indices):
                phi = self.azimuth(idx)
                nrm = np.array([st * math.cos(phi), st * math.sin(phi), sz])
                name = tier.names.get(j, base or f"tier {t + 1}")
                out.append((t, j, nrm, tier.distance, f"{name} @{_fmt_index(idx)}"))
        return out

    def planes(self) -> tuple[np.ndarray, np.ndarray, list[str]]:
        """Facet planes ``(normals (K,3), distances (K,), names)`` in design units (see module doc)."""
        f = self.facets()
        normals = np.array([x[2] for x in f], dtype=np.float64).reshape(-1, 3)
        return normals, np.array([x[3] for x in f], dtype=np.float64), [x[4] for x in f]

    def merge_duplicates(self, source: str | None = None) -> list[str]:
        """Drop facets that repeat an earlier one's plane (and tiers left empty); warn about each.

        Two facets are the same plane when their normals and distances agree to 1e-9 (design
        units; far below the 6-8 decimals of the format, far above the round-off of the
        trigonometry).  Returns the warning messages.
        """
        seen: dict[tuple, int] = {}
        drop: dict[int, set[int]] = {}
        messages = []
        for t, j, nrm, dist, name in self.facets():
            key = tuple(np.round(np.append(nrm, dist), 9) + 0.0)
            if key in seen:
                first = self.tiers[seen[key]]
                here = self.tiers[t]
                where = f"line {here.line}" if here.line else f"tier {t + 1}"
                was = f"line {first.line}" if first.line else f"tier {seen[key] + 1}"
                msg = f"{where}: facet {name} repeats the plane of {was}; merged"
                messages.append(f"{source}: {msg}" if source else msg)
                drop.setdefault(t, set()).add(j)
            else:
                seen[key] = t
        tiers = []
        for t, tier in enumerate(self.tiers):
            gone = drop.get(t, set())
            if not gone:
                tiers.append(tier)
                continue
            if tier.angle == 0:
                continue  # a table or culet repeated: one plane, the whole record goes
            keep = [j for j in range(len(tier.indices)) if j not in gone]
            if not keep:
                continue
            renum = {old: new for new, old in enumerate(keep)}
            names = {renum[j]: nm for j, nm in tier.names.items() if j in renum}
            lost = [nm for j, nm in tier.names.items() if j not in renum]
            if lost and not names:  # a tier's name sits after its first index: keep it on the tier
                names = {0: lost[0]}
            tiers.append(dataclasses.replace(tier, indices=[tier.indices[j] for j in keep], names=names))
        self.tiers = tiers
        for msg in messages:
            warnings.warn(msg, UserWarning, stacklevel=3)
        return messages


_KEY = re.compile(r"^(GemCad|[gyIHFa])(?=$|[\s\-+\d.])")
_BARE_GEAR = re.compile(r"^[-+]?\d+\s+[-+]?\d*\.?\d+$")


def _num(tok: str, source, lineno: int, what: str) -> float:
    try:
        v = float(tok)
    except ValueError:
        raise InputError(f"line {lineno}: expected a number for {what}", file=source, value=tok) from None
    if not math.isfinite(v):
        raise InputError(f"line {lineno}: {what} must be finite", file=source, value=tok)
    return v


def _gear_line(design: Design, tok: list[str], source, lineno: int) -> None:
    if not tok:
        raise InputError(f"line {lineno}: 'g' needs the gear tooth count", file=source)
    gear = _num(tok[0], source, lineno, "the gear tooth count")
    if gear == 0 or gear != int(gear) or abs(gear) > 720:
        raise InputError(
            f"line {lineno}: bad index gear",
            file=source,
            value=tok[0],
            allowed="a non-zero integer up to 720 (negative: indices run the other way)",
        )
    design.gear = int(gear)
    design.offset = _num(tok[1], source, lineno, "the index offset") if len(tok) > 1 else 0.0


def parse(text: str, *, source: str | None = None, merge: bool = True) -> Design:
    """Parse the text of a ``.asc`` design (already decoded).

    ``merge``: merge repeated facets (:meth:`Design.merge_duplicates`, with a warning each).
    """
    text = text.lstrip("\ufeff").replace("\r\n", "\n").replace("\r", "\n")
    design = Design(tiers=[])
    seen_header = False
    seen_gear = False
    open_tier: Tier | None = None
    in_instruction = False
    for lineno, raw in enumerate(text.split("\n"), start=1):
        line = raw.strip()
        if not line:
            continue
        m = _KEY.match(line)
        key = m.group(1) if m else None
        rest = line[m.end() :].strip() if m else line
        if key == "GemCad":
            design.version = rest or design.version
            seen_header = True
            open_tier = None
            continue
        if not seen_header:
            raise InputError(
                f"line {lineno}: not a GemCAD .asc file (expected 'GemCad <version>' first)",
                file=source,
                value=line[:40],
            )
        if key is None and not seen_gear and not design.tiers and _BARE_GEAR.match(line):
            key = "g"  # "96 0.0": a gear line without its keyword
        if key == "H":
            design.headers.append(rest)
            open_tier = None
        elif key == "F":
            design.footnotes.append(rest)
            open_tier = None
        elif key == "g":
            _gear_line(design, rest.split(), source, lineno)
            seen_gear = True
            open_tier = None
        elif key == "y":
            tok = rest.split()
            if tok:
                design.symmetry = int(_num(tok[0], source, lineno, "the symmetry"))
            if len(tok) > 1:
                design.mirror = tok[1].lower().startswith("y")
            open_tier = None
        elif key == "I":
            tok = rest.split()
            if tok:
                design.refractive_index = _num(tok[0], source, lineno, "the refractive index")
            open_tier = None
        elif key == "a":
            tok = rest.split()
            if len(tok) < 2:
                raise InputError(
                    f"line {lineno}: a tier needs an angle and a distance", file=source, value=line
                )
            angle = _num(tok[0], source, lineno, "the facet angle")
            if abs(angle) > 90:
                raise InputError(
                    f"line {lineno}: facet angle out of range",
                    file=source,
                    value=angle,
                    allowed="[-90, 90] deg",
                )
            dist = _num(tok[1], source, lineno, "the facet distance")
            open_tier = Tier(
                angle=angle if angle != 0 else 0.0,
                distance=dist,
                indices=[],
                pavilion_zero=angle == 0 and tok[0].lstrip().startswith("-"),
                line=lineno,
            )
            design.tiers.append(open_tier)
            in_instruction = _parse_tail(open_tier, tok[2:], source, lineno)
        else:
            if open_tier is None:
                raise InputError(
                    f"line {lineno}: unrecognised record",
                    file=source,
                    value=line[:40],
                    allowed="GemCad, g, y, I, H, F, a",
                )
            if in_instruction:
                open_tier.instruction = f"{open_tier.instruction} {line}".strip()
            else:
                in_instruction = _parse_tail(open_tier, line.split(), source, lineno)
    if not seen_header:
        raise InputError("empty file or not a GemCAD .asc file", file=source)
    if not design.tiers:
        raise InputError("the design has no facet tiers ('a' records)", file=source)
    for tier in design.tiers:
        if tier.angle != 0 and not tier.indices:
            raise InputError(f"line {tier.line}: a tier has no gear indices", file=source)
    if merge:
        design.merge_duplicates(source)
    return design


def _parse_tail(tier: Tier, tok: list[str], source, lineno: int) -> bool:
    """Indices, names and instruction of an ``a`` record; True once ``G`` has started."""
    k = 0
    while k < len(tok):
        t = tok[k]
        if t == "G":
            extra = " ".join(tok[k + 1 :])
            tier.instruction = f"{tier.instruction} {extra}".strip()
            return True
        if t == "n":
            if k + 1 >= len(tok):
                raise InputError(f"line {lineno}: 'n' without a facet name", file=source)
            tier.names[max(len(tier.indices) - 1, 0)] = tok[k + 1]
            k += 2
            continue
        tier.indices.append(_num(t, source, lineno, "a gear index"))
        k += 1
    return False


def read_design(path: str | os.PathLike) -> Design:
    """Read a ``.asc`` file (Windows-1252, or UTF-8 with a byte-order mark)."""
    path = os.fspath(path)
    try:
        with open(path, "rb") as f:
            data = f.read()
    except FileNotFoundError:
        raise InputError("no such file", file=path) from None
    if _is_binary(data):
        raise InputError("binary GemCad .gem files are not supported; export .asc from GemCad", file=path)
    if data.startswith(b"\xef\xbb\xbf"):
        text = data[3:].decode("utf-8", errors="replace")
    else:
        text = data.decode("cp1252", errors="replace")
    return parse(text, source=path)


def _is_binary(data: bytes) -> bool:
    """A GemCad ``.gem`` project (binary doubles) rather than ``.asc`` text: a NUL byte, or more
    than 10 % control bytes other than tab/CR/LF, in the first kilobyte."""
    head = data[:1024]
    if data.lstrip(b"\xef\xbb\xbf").startswith(b"GemCad"):
        return False
    if b"\x00" in head:
        return True
    ctrl = sum(1 for c in head if c < 32 and c not in (9, 10, 13))
    return len(head) > 0 and ctrl > 0.1 * len(head)


def tier_index(design: Design, key: str) -> int:
    """The position in ``design.tiers`` of the tier ``key`` names (module docstring: a facet name
    as the diagram lists it, or ``#k`` for the k-th record, from 1)."""
    field = f"tier_angles.{key}"
    names = {}
    for i, t in enumerate(design.tiers):
        if t.names:
            names.setdefault(str(t.names[min(t.names)]), []).append(i)
    listed = ", ".join(f"{n!r}" for n in names) or "none"
    key = str(key)
    if key in names:
        if len(names[key]) > 1:
            raise InputError(
                f"tiers {', '.join(f'#{i + 1}' for i in names[key])} share this name: give #k",
                field=field,
                value=key,
            )
        return names[key][0]
    if key.startswith("#") and key[1:].isdigit() and 1 <= int(key[1:]) <= len(design.tiers):
        return int(key[1:]) - 1
    raise InputError(
        "no such tier", field=field, value=key, allowed=f"a tier name ({listed}) or #1..#{len(design.tiers)}"
    )


def _check_angle(tier: Tier, key: str, angle) -> float:
    field = f"tier_angles.{key}"
    if isinstance(angle, bool) or not isinstance(angle, (int, float)) or not math.isfinite(angle):
        raise InputError("must be a finite number (degrees)", field=field, value=angle)
    if tier.angle == 0 or abs(abs(tier.angle) - 90.0) < 1e-9:
        what = "the culet" if tier.is_culet else "the table" if tier.angle == 0 else "a girdle tier"
        raise InputError(f"this tier is {what}: its angle cannot change", field=field, value=angle)
    side = "pavilion" if tier.angle < 0 else "crown"
    if not 0.0 < abs(angle) < 90.0 or (angle < 0 and side == "crown"):
        raise InputError(
            f"a {side} angle must be in (0, 90) degrees",
            field=field,
            value=angle,
            allowed="(0, 90)" + (" or (-90, 0) as the .asc file writes it" if side == "pavilion" else ""),
        )
    return -abs(float(angle)) if side == "pavilion" else abs(float(angle))


def check_tier_angles(design: Design, angles) -> dict[int, tuple[str, float]]:
    """Tier position -> (key, signed angle) of ``angles`` (a table tier -> degrees; module
    docstring), or a one-line :class:`InputError` naming ``tier_angles[.<tier>]``."""
    if not isinstance(angles, dict):
        raise InputError(
            "must be a table of tier = angle (degrees)",
            field="tier_angles",
            value=angles,
            allowed="{ 2 = 41.0 }",
        )
    todo: dict[int, tuple[str, float]] = {}
    for key, angle in angles.items():
        i = tier_index(design, str(key))
        if i in todo:
            raise InputError(
                f"names the same tier as {todo[i][0]!r}", field=f"tier_angles.{key}", value=angle
            )
        todo[i] = (str(key), _check_angle(design.tiers[i], str(key), angle))
    return todo


def recut_tiers(design: Design, angles: dict) -> Design:
    """``design`` with the tiers named in ``angles`` (tier -> degrees) re-cut at those angles,
    their heights re-solved through each tier's innermost meet point (module docstring)."""
    if not angles:
        return design
    todo = check_tier_angles(design, angles)
    normals, dist, _names = design.planes()
    solid = convex_from_planes(normals, dist)
    verts = np.asarray(solid.vertices)
    tol = 1e-6 * float(np.max(np.abs(dist)))
    on_plane = np.abs(verts @ normals.T - dist[None, :]) < 10 * tol  # (V, K)
    meets = on_plane.sum(axis=1) >= 3  # a meet point: three or more facets (not a fan centre)
    tiers = list(design.tiers)
    facets = design.facets()
    for i, (key, angle) in todo.items():
        old = tiers[i]
        new = dataclasses.replace(old, angle=angle)
        heights = []
        for k, (t, j, _n, _d, _name) in enumerate(facets):
            if t != i:
                continue
            pts = verts[meets & on_plane[:, k]]
            if not len(pts):
                continue  # a facet the design cuts away
            p = pts[np.argmin(np.hypot(pts[:, 0], pts[:, 1]))]
            th, phi = math.radians(abs(angle)), design.azimuth(old.indices[j])
            n = np.array(
                [
                    math.sin(th) * math.cos(phi),
                    math.sin(th) * math.sin(phi),
                    math.copysign(math.cos(th), angle),
                ]
            )
            heights.append(float(n @ p))
        if not heights:
            raise InputError("the design has no facet of this tier on the stone", field=f"tier_angles.{key}")
        tiers[i] = dataclasses.replace(new, distance=max(heights))
    out = dataclasses.replace(design, tiers=tiers)
    n2, d2, _ = out.planes()
    kept = convex_from_planes(n2, d2).metadata["planes"]
    for i, (key, angle) in todo.items():
        for t, _j, n, d, _name in out.facets():
            if t == i and not np.any(np.all(np.abs(kept - np.append(n, d)) < 1e-9 + 10 * tol, axis=1)):
                raise InputError(
                    "at this angle the tier's facets are cut away by the other tiers",
                    field=f"tier_angles.{key}",
                    value=abs(angle),
                )
    return out


def _part(tier: Tier) -> str:
    """The part of the stone a tier cuts: table, culet, girdle, crown or pavilion."""
    if tier.angle == 0:
        return "table" if tier.distance >= 0 else "culet"
    if abs(tier.angle) == 90:
        return "girdle"
    return "pavilion" if tier.angle < 0 else "crown"


def design_to_mesh(design: Design, diameter: float = 1.0, *, source: str | None = None) -> trimesh.Trimesh:
    """The stone of a design, girdle width scaled to ``diameter`` mm (see module doc)."""
    if not (math.isfinite(diameter) and diameter > 0):
        raise InputError("must be a positive length in mm", field="diameter", value=diameter)
    normals, dist, names = design.planes()
    way = open_direction(normals) if len(normals) else None
    if way is not None:
        tiers = "; ".join(
            f"tier {k + 1} at {t.angle:g} deg ({_part(t)}, {len(t.indices)} facets)"
            for k, t in enumerate(design.tiers)
        )
        raise InputError(
            f"the facets do not close: the stone is open toward {direction_words(way)}, where no tier "
            f"faces (a crown, pavilion or girdle missing?); its tiers: {tiers}",
            file=source,
        )
    mesh = convex_from_planes(normals, dist, names, source=source)
    ext = mesh.extents
    s = diameter / float(min(ext[0], ext[1]))
    mesh.apply_scale(s)
    mesh.metadata["planes"] = np.column_stack(
        [mesh.metadata["planes"][:, :3], mesh.metadata["planes"][:, 3] * s]
    )
    mesh.metadata["proportions"] = measure_proportions(mesh, shape="gemcad")
    mesh.metadata["symmetry"] = (design.symmetry, design.mirror)
    mesh.metadata["refractive_index"] = design.refractive_index
    mesh.metadata["design_scale"] = s  # mm per design unit
    mesh.metadata["design"] = design
    mesh.metadata["shape"] = "gemcad"
    return mesh


def read(
    path: str | os.PathLike, diameter: float = 1.0, *, tier_angles: dict | None = None
) -> trimesh.Trimesh:
    """Read a ``.asc`` design and build its stone with girdle width ``diameter`` mm; the tiers
    named in ``tier_angles`` (tier -> degrees) re-cut at those angles (:func:`recut_tiers`)."""
    path = os.fspath(path)
    design = read_design(path)
    if tier_angles:
        design = recut_tiers(design, dict(tier_angles))
    return design_to_mesh(design, diameter, source=path)


def _fmt_index(idx: float) -> str:
    r = round(idx)
    return str(int(r)) if idx == r else _fmt_short(idx)


def _tier_name(name: str) -> str:
    base = re.sub(r"\s*(\d+|@\S+)$", "", name).strip() or "f"
    return re.sub(r"\s+", "_", base)


def design_from_mesh(
    mesh: trimesh.Trimesh,
    *,
    gear: int = 96,
    refractive_index: float | None = None,
    title: str | None = None,
    unit: float | None = None,
) -> Design:
    """A design from a convex faceted mesh (its facet planes), distances in units of ``unit`` mm.

    ``unit`` defaults to half the girdle width, so distances are relative to the girdle radius.
    Facets with equal angle and distance become one tier.  ``refractive_index`` defaults to the
    mesh's (a design read from a file keeps its ``I`` line), else diamond's 2.417.
    """
    if refractive_index is None:
        refractive_index = float(mesh.metadata.get("refractive_index", 2.417))
    from .mesh import facet_planes

    planes, _ = facet_planes(mesh)
    names = mesh.metadata.get("facet_names") or [f"f{i}" for i in range(len(planes))]
    if unit is None:
        ext = mesh.extents
        unit = 0.5 * float(min(ext[0], ext[1]))
    tiers: dict[tuple, Tier] = {}
    order: list[tuple] = []
    for (nx, ny, nz, d), name in zip(planes, names, strict=True):
        nz = float(np.clip(nz, -1.0, 1.0))
        horiz = math.hypot(nx, ny)
        theta = math.degrees(math.atan2(horiz, abs(nz)))
        dist = d / unit
        if horiz < 1e-9:
            angle, idxs = 0.0, [float(gear)]
            if nz < 0:
                dist = -dist
        else:
            angle = theta if nz >= 0 else -theta
            if abs(nz) < 1e-12:
                angle = 90.0
            phi = math.degrees(math.atan2(ny, nx))
            idx = ((90.0 - phi) * gear / 360.0) % gear
            if abs(idx - round(idx)) < 1e-6:
                idx = float(round(idx))
            if idx < 1e-6:
                idx = float(gear)
            idxs = [idx]
        key = (round(angle, 6), round(dist, 8))
        if key not in tiers:
            tiers[key] = Tier(angle=angle, distance=dist, indices=[], names={0: _tier_name(name)})
            order.append(key)
        tiers[key].indices.extend(idxs)

    def sort_key(k):
        a, dd = k
        group = 0 if a < 0 or (a == 0 and dd < 0) else 1 if a == 90 else 2 if a > 0 else 3
        return (group, -abs(a) if group == 0 else -a, dd)

    tier_list = [tiers[k] for k in sorted(order, key=sort_key)]
    for t in tier_list:
        t.indices.sort()
    sym, mirror = mesh.metadata.get("symmetry", (1, False))
    headers = [title or f"warpoptics {mesh.metadata.get('shape', 'design')}"]
    return Design(
        tiers=tier_list,
        gear=gear,
        symmetry=int(sym),
        mirror=bool(mirror),
        refractive_index=refractive_index,
        headers=headers,
    )


def _fmt_fixed(v: float, decimals: int) -> str:
    """``v`` with GemCAD's fixed decimals, or with all the digits it has if those would round it."""
    text = f"{v:.{decimals}f}"
    return text if float(text) == v else repr(float(v))


def _fmt_short(v: float) -> str:
    """Shortest text that reads back as ``v``, with at least one decimal (``48.0``, ``2.417``)."""
    text = repr(float(v))
    return text if ("." in text or "e" in text) else f"{text}.0"


def dumps(design: Design) -> str:
    """The ``.asc`` text of a design (LF line ends; :func:`write` converts to CRLF).

    Angles get GemCAD's six decimals and distances eight (more where the design has more), so
    ``dumps(parse(dumps(d))) == dumps(d)`` and the planes are those of ``d``.
    """
    out = [
        f"GemCad {design.version}",
        f"g {design.gear} {_fmt_short(design.offset)}",
        f"y {design.symmetry} {'y' if design.mirror else 'n'}",
        f"I {_fmt_short(design.refractive_index)}",
    ]
    out += [f"H {h}".rstrip() for h in design.headers]
    for t in design.tiers:
        angle = "-0.000000" if t.pavilion_zero and t.angle == 0 else _fmt_fixed(t.angle, 6)
        parts = [f"a {angle} {_fmt_fixed(t.distance, 8)}"]
        for j, idx in enumerate(t.indices):
            parts.append(_fmt_index(idx))
            if j in t.names:
                parts.append(f"n {t.names[j]}")
        if t.instruction:
            parts.append(f"G {t.instruction}")
        out.append(" ".join(parts))
    out += [f"F {f}".rstrip() for f in design.footnotes]
    return "\n".join(out) + "\n"


def write(obj: trimesh.Trimesh | Design, path: str | os.PathLike, **kw) -> Design:
    """Write a design (or a convex faceted mesh, via :func:`design_from_mesh` with ``kw``) as a
    GemCAD ``.asc`` file: Windows-1252, CRLF.  Returns the design written."""
    design = obj if isinstance(obj, Design) else design_from_mesh(obj, **kw)
    text = dumps(design).replace("\n", "\r\n")
    from ..atomic import atomic_path

    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        f.write(text.encode("cp1252", errors="replace"))
    return design

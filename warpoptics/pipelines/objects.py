"""The scene-geometry builder both pipelines call: ``[[object]]`` configs -> meshes (cuts, mesh
files, GemCAD designs; instances share one mesh), materials and optic axes."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from ..errors import InputError
from ..geometry import cuts
from ..geometry.gemcad import read as read_gemcad
from ..geometry.mesh import SIZE_ALLOWED, SIZE_MAX, SIZE_MIN, load_mesh, scale_problem, size_problem
from ..geometry.nesting import OverlapError, object_parents, world_boxes
from ..materials import material_from_spec
from ..materials.dispersion import Biaxial, Uniaxial
from ..materials.zoning import zoned_material
from ..scene.schema import ObjectConfig

__all__ = ["SceneObjects", "build_objects", "world_axes", "crystal_axes_of"]


@dataclass(frozen=True)
class SceneObjects:
    """What :func:`build_objects` returns, one entry per object: ``meshes`` (trimesh, 4x4 object ->
    world transform), ``materials`` (dispersion models), ``axes`` (the object's ``optic_axis``
    override in the object frame, or None), ``parents`` (the innermost object containing it, -1:
    none; ``geometry.nesting.object_parents``)."""

    meshes: list
    materials: list
    axes: list
    parents: np.ndarray

    @property
    def nested(self) -> bool:
        """Whether any object lies inside another."""
        return bool(np.any(self.parents >= 0))


def build_objects(objects: Sequence[ObjectConfig], *, file: str | None = None) -> SceneObjects:
    """Meshes and materials of a scene's objects (camera and bench scenes alike); errors of a cut,
    a mesh file or a material become InputErrors naming ``file`` and ``object.<i>``."""
    meshes, mats, axes = [], [], []
    cache: dict = {}  # instancing: objects with the same shape and parameters share one mesh
    for i, ob in enumerate(objects):
        where = f"object.{i}"
        key = (ob.shape, ob.path, tuple(sorted((k, repr(v)) for k, v in ob.params.items())))
        try:
            if key in cache:
                mesh = cache[key]
            elif ob.shape == "mesh":
                film = getattr(ob, "film", None)  # films: shells and film surfaces may be open meshes
                mesh = load_mesh(
                    str(ob.path),
                    repair=bool(ob.params.get("repair", False)),
                    check_size=False,  # the size rule applies to the world size (_check_scale)
                    closed=film is None or film.surface == "solid",
                )
            elif ob.shape == "gemcad":
                mesh = read_gemcad(
                    str(ob.path),
                    diameter=float(ob.params.get("diameter", 1.0)),
                    tier_angles=dict(ob.params.get("tier_angles", ())),
                )
            else:
                mesh = getattr(cuts, ob.shape)(**ob.params)
        except InputError as exc:
            if exc.file is None:
                exc = InputError(
                    exc.message,
                    file=file,
                    field=f"{where}.{exc.field or 'shape'}",
                    value=exc.value,
                    allowed=exc.allowed,
                )
            elif exc.field is None:  # a mesh or GemCAD file's error: name the object too
                exc = InputError(
                    exc.message, file=exc.file, field=where, value=exc.value, allowed=exc.allowed
                )
            raise exc from None
        except (ValueError, TypeError) as exc:
            raise InputError(str(exc), file=file, field=f"{where}.shape", value=ob.shape) from None
        cache[key] = mesh
        meshes.append((mesh, ob.transform()))
        try:
            mat = material_from_spec(ob.material)
        except InputError as exc:
            sub = f".{exc.field}" if exc.field and exc.field != "material" else ""
            raise InputError(
                exc.message, file=file, field=f"{where}.material{sub}", value=exc.value, allowed=exc.allowed
            ) from None
        if isinstance(mat, Biaxial):
            # each biaxial object gets its own table entry with the world principal axes
            mat = mat.with_crystal_axes(
                crystal_axes_of(ob, mat, file=file, where=where) @ ob.rotation_matrix().T
            )
        elif getattr(ob, "crystal_axes", None) is not None:
            raise InputError(
                "crystal axes need a biaxial material",
                file=file,
                field=f"{where}.crystal_axes",
                value=ob.material,
            )
        if getattr(ob, "zoning", None) is not None:
            mat = _zoned(ob, mat, file=file, where=where)
        mats.append(mat)
        axes.append(ob.optic_axis)
    if meshes:
        _check_scale(objects, meshes, file)
    solid = [getattr(ob, "film", None) is None or ob.film.surface == "solid" for ob in objects]
    try:
        parents = object_parents(meshes, solid=solid)
    except OverlapError as exc:
        raise InputError(
            f"{exc}: solids may be nested (one wholly inside another) or apart, not partly overlapping",
            file=file,
            field=f"object.{exc.first}",
            value=f"object.{exc.second}",
        ) from None
    return SceneObjects(meshes=meshes, materials=mats, axes=axes, parents=parents)


# what an inline material table starts from (materials/spec.py); a zone's table may omit it
_STARTS = ("base", "host", "cauchy")


def _zoned(ob: ObjectConfig, host, *, file: str | None, where: str):
    """The host material of a colour-zoned object with its zones (materials/zoning.py): each
    zone's absorption spec resolved as a material (an inline table without ``base``, ``host``
    or ``cauchy`` takes the object's), the zones placed with the object."""
    zoning = ob.zoning
    assert zoning is not None
    resolved = []
    for j, spec in enumerate(zoning.absorption):
        if spec == "none":
            spec = {"cauchy": [1.0]}  # a clear zone (only a zone's absorption is used)
        if isinstance(spec, dict) and not any(k in spec for k in _STARTS):
            # the object's own base (a library name), chromophore host or Cauchy index
            host_spec = ob.material
            if isinstance(host_spec, str):
                host_spec = {"base": host_spec}
            lent = {}
            if isinstance(host_spec, dict):
                lent = {k: host_spec[k] for k in _STARTS if k in host_spec}
            if not lent:
                raise InputError(
                    'an inline zone absorption needs base = "<library name>", host = "<crystal>" '
                    "or cauchy = [...]",
                    file=file,
                    field=f"{where}.zoning.absorption.{j}.base",
                )
            spec = {**lent, **spec}
        try:
            resolved.append(material_from_spec(spec))
        except InputError as exc:
            sub = f".{exc.field}" if exc.field and exc.field != "material" else ""
            raise InputError(
                exc.message,
                file=file,
                field=f"{where}.zoning.absorption.{j}{sub}",
                value=exc.value,
                allowed=exc.allowed,
            ) from None
    placed = replace(zoning, absorption=tuple(resolved)).placed(ob.transform())
    return zoned_material(host, placed)


def _check_scale(objects: Sequence[ObjectConfig], meshes: list, file: str | None) -> None:
    """The one size and placement rule of every object (``geometry.query.scale_problem``), on its
    world bounding box; the error names the field that sets the size (``diameter``, ``size`` or
    ``scale``) or the ``position``."""
    lo, hi = world_boxes(meshes)
    sizes = (hi - lo).max(axis=1)
    far = np.maximum(np.abs(lo), np.abs(hi)).max(axis=1)
    # the rule's boundaries, vectorized, then the rule itself for the objects near or past them
    suspect = (sizes < 2.0 * SIZE_MIN) | (sizes > 0.5 * SIZE_MAX) | (far > 1.0e3 * sizes)
    for i in np.flatnonzero(suspect):
        ob = objects[int(i)]
        why = size_problem(float(sizes[i]))
        if why is not None:
            key = next((k for k in ("diameter", "size") if k in ob.params and ob.scale == 1.0), "scale")
            value = ob.params[key] if key != "scale" else ob.scale
            mesh = f"{ob.shape} file {ob.path}: " if ob.path is not None else ""
            raise InputError(
                mesh + why,
                file=file,
                field=f"object.{i}.{key}",
                value=value,
                allowed=SIZE_ALLOWED,
            )
        why = scale_problem(float(sizes[i]), float(far[i]))
        if why is not None:
            raise InputError(why, file=file, field=f"object.{i}.position", value=list(ob.position))


def crystal_axes_of(
    ob: ObjectConfig, mat: Biaxial, *, file: str | None = None, where: str = "object"
) -> np.ndarray:
    """(3, 3) principal axes X, Y, Z (rows, object frame) of a biaxial object: its
    ``crystal_axes``, or from ``optic_axial_plane`` + ``acute_bisectrix`` (Z = bisectrix for an
    optically positive material, X = bisectrix for a negative one), or the material's."""
    rows = getattr(ob, "crystal_axes", None)
    if rows is None:
        return mat.crystal_axes
    a = np.asarray(rows, dtype=np.float64)
    if getattr(ob, "crystal_axes_kind", "axes") == "bisectrix":
        b, y = a[0], a[1]
        if mat.optic_sign == "+":
            a = np.array([np.cross(y, b), y, b])
        else:
            a = np.array([b, y, np.cross(b, y)])
    return a


def world_axes(
    objects: Sequence[ObjectConfig], built: SceneObjects, *, file: str | None = None
) -> np.ndarray:
    """Optic axis of each object in world space (zero rows for isotropic materials): the object's
    ``optic_axis`` or its material's, both in the object frame, turned by the object's rotation."""
    mats, axes = built.materials, built.axes
    out = np.zeros((len(mats), 3))
    for i, (ob, mat, ax) in enumerate(zip(objects, mats, axes, strict=True)):
        if not isinstance(mat, Uniaxial):
            if ax is not None:
                raise InputError(
                    "an optic axis needs a uniaxial material",
                    file=file,
                    field=f"object.{i}.optic_axis",
                    value=list(ax),
                )
            continue
        a = np.asarray(ax if ax is not None else mat.optic_axis, dtype=np.float64)
        a = ob.rotation_matrix() @ a
        out[i] = a / np.linalg.norm(a)
    return out

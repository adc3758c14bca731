"""The caustics composition of the camera pipeline: a scene with ``[render] caustics = true`` gets
a light tracer (:class:`~warpoptics.stages.caustics.CausticStage`, lamp -> gem -> surface -> eye)
whose film the Renderer adds to its camera film."""

from __future__ import annotations

from ..errors import InputError
from ..scene import Scene
from ..stages.caustics import MAX_PATHS, CausticConfig, CausticStage
from .objects import SceneObjects, world_axes

__all__ = ["check_caustic_scene", "caustic_stage"]


def check_caustic_scene(scene: Scene) -> None:
    """Refuse what the light tracer does not model (coated objects / films)."""
    for i, ob in enumerate(scene.objects):
        if ob.film is not None:
            raise InputError(
                "caustics do not support coated objects or films",
                file=scene.path,
                field=f"object.{i}",
                value=ob.shape,
                allowed="render.caustics = false",
            )


def caustic_stage(
    scene: Scene,
    built: SceneObjects,
    object_material,
    *,
    camera,
    surfaces,
    geometry,
    materials,
    tables,
    device=None,
) -> CausticStage:
    """The light tracer of ``scene`` over the Renderer's stages (camera, surfaces, geometry, material
    table, spectral tables); ``caustic_paths`` 0 takes one light path per pixel sample."""
    check_caustic_scene(scene)
    r, cam = scene.render, scene.camera
    paths = r.caustic_paths or cam.width * cam.height * r.spp
    if paths > MAX_PATHS:  # the default, one path per pixel sample, of a large image
        raise InputError(
            f"caustic_paths = 0 takes one light path per pixel sample: {cam.width} x {cam.height} x "
            f"spp {r.spp} = {paths:,} paths, more than one run can index",
            file=scene.path,
            field="render.caustic_paths",
            value=r.caustic_paths,
            allowed=f"1 to {MAX_PATHS:,} paths (int32 path indices)",
        )
    config = CausticConfig(
        paths=paths,
        spectral=r.spectral,
        wavelengths=r.wavelengths,
        max_depth=r.max_depth,
        ambient_index=r.ambient_index,
        seed=r.seed,
    )
    return CausticStage(
        config,
        meshes=built.meshes,
        lamps=scene.lamps,
        object_material=object_material,
        absorption_scale=[ob.absorption_scale for ob in scene.objects],
        object_axis=world_axes(scene.objects, built, file=scene.path),
        camera=camera,
        surfaces=surfaces.struct,
        geometry=geometry.geometry,
        materials=materials,
        tables=tables,
        device=device,
    )

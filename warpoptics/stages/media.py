"""The media of a scene's objects on the device: indices, optic axis and absorption per object.

Every tracer (camera, bench, caustics, shadow rays) resolves the medium of an object here, from
the device-side material table (``materials.dispersion.MaterialTable``) and the per-object arrays
of its parameters (material id, world optic axis, absorption multiplier), so that what a stone is
made of is decided in one place.  The laws themselves live in ``optics/`` (``absorption.py``:
Bouguer–Lambert and kappa per wave; ``birefringence.py``: the uniaxial medium).

A biaxial material (``table.beta_channel[m] >= 0``) gives the medium struct of
``optics.biaxial.biaxial_medium``: n_alpha, n_beta, n_gamma at the wavelength, the world principal
axes of the object (its own table entry, turned into the world by the pipelines) and alpha_Y;
(alpha_o, alpha_e) are then alpha_X and alpha_Z, and each wave absorbs by its own D
(``optics.biaxial.biaxial_kappa``).  Every other material costs one extra table read.

Interfaces use the real part of the index in the camera tracer: a dielectric's k (< 1e-3 for any
stone or dye solution one can see through) changes Fresnel coefficients by O(k^2), while with an
absorbing *incident* medium the plane-wave reflectance is no longer bounded by 1.  k acts where it
matters, as Bouguer–Lambert attenuation exp(-4 pi k l / lambda) along each segment.
"""

from __future__ import annotations

import warp as wp

from ..materials.dispersion import MaterialTable, material_eval_beta, material_optics
from ..materials.units import alpha_from_k_wp
from ..optics.absorption import wave_kappa
from ..optics.biaxial import biaxial_kappa, biaxial_medium, is_biaxial
from ..optics.birefringence import UniaxialMedium, uniaxial_medium
from ..optics.zoning import ZoneVector, zone_lengths, zoned_optical_depth

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "object_medium",
    "medium_alpha",
    "segment_kappa",
    "isotropic_optics",
    "zone_alpha",
    "zoned_kappa",
    "zoned_isotropic_kappa",
    "zoned_alpha_pair",
]


@wp.func
def object_medium(mats: MaterialTable, mat_id: int, axis: wp.vec3f, wavelength: float):
    """(UniaxialMedium with real indices and the world optic ``axis`` — the zero axis for an
    isotropic material —, complex N_o, complex N_e, (alpha_o, alpha_e) in 1/mm) of material
    ``mat_id`` at ``wavelength`` nm, from one evaluation of the material."""
    no, ne, alpha = material_optics(mats, mat_id, wavelength)
    if mats.beta_channel[mat_id] >= 0:
        nb = material_eval_beta(mats, mat_id, wavelength)
        a_y = alpha_from_k_wp(nb[1], wp.max(wavelength, 1.0e-3))
        med = biaxial_medium(no[0], nb[0], ne[0], mats.crystal_frame[mat_id], a_y)
        return med, no, ne, alpha
    ax = wp.vec3f(0.0, 0.0, 0.0)
    if mats.uniaxial[mat_id] != 0:
        ax = axis
    return uniaxial_medium(no[0], ne[0], ax), no, ne, alpha


@wp.func
def medium_alpha(mats: MaterialTable, mat_id: int, alpha: wp.vec2f, rgb3_channel: int):
    """(alpha_o, alpha_e), 1/mm: the material's spectral ``alpha`` at the sample's wavelength, or
    in the rgb3 mode (``rgb3_channel`` 0..2; -1 otherwise) its Guy & Soler eq. 9 RGB absorbance
    of that channel."""
    if rgb3_channel >= 0:
        return mats.rgb3_alpha_o[mat_id][rgb3_channel], mats.rgb3_alpha_e[mat_id][rgb3_channel]
    return alpha[0], alpha[1]


@wp.func
def segment_kappa(
    mats: MaterialTable,
    mat_id: int,
    alpha: wp.vec2f,
    rgb3_channel: int,
    mode: int,
    wave_normal: wp.vec3f,
    med: UniaxialMedium,
    scale: float,
):
    """Intensity absorption coefficient (1/mm, base e) of a wave (mode -1 isotropic, 0 o, 1 e,
    with unit ``wave_normal``) on a segment inside a medium: K^o, or kappa^e(theta) of Guy & Soler
    2004 eq. 7 (``optics.absorption.wave_kappa``); in a biaxial medium (mode 0 fast, 1 slow) the
    trichroic kappa of the wave's D; times the object's absorption multiplier."""
    a_o, a_e = medium_alpha(mats, mat_id, alpha, rgb3_channel)
    a_y = med.alpha_y
    if is_biaxial(med) and rgb3_channel >= 0:
        a_y = mats.rgb3_alpha_b[mat_id][rgb3_channel]
    return _wave_kappa(mode, wave_normal, med, a_o, a_y, a_e) * scale


@wp.func
def _wave_kappa(mode: int, wave_normal: wp.vec3f, med: UniaxialMedium, a_o: float, a_y: float, a_e: float):
    """kappa of a wave from the principal absorption coefficients (alpha_o, -, alpha_e) of an
    isotropic or uniaxial medium or (alpha_X, alpha_Y, alpha_Z) of a biaxial one."""
    if is_biaxial(med):
        return biaxial_kappa(mode, wave_normal, med, a_o, a_y, a_e)
    return wave_kappa(mode, wp.dot(wave_normal, med.axis), a_o, a_e, med.no, med.ne)


@wp.func
def isotropic_optics(mats: MaterialTable, mat_id: int, axis: wp.vec3f, wavelength: float, scale: float):
    """(real index, absorption coefficient in 1/mm times the object's ``scale``) of an isotropic
    material at ``wavelength`` nm: :func:`object_medium` and :func:`segment_kappa` for a
    medium whose every segment absorbs alike (the spectral bundles and pixel beams evaluate it
    once per lane and solid, not per segment)."""
    med, no, ne, alpha = object_medium(mats, mat_id, axis, wavelength)
    kappa = segment_kappa(
        mats,
        mat_id,
        wp.vec2f(alpha[0], alpha[0]),
        -1,
        -1,
        wp.vec3f(0.0, 0.0, 1.0),
        uniaxial_medium(no[0], no[0], wp.vec3f(0.0, 0.0, 0.0)),
        scale,
    )
    return no[0], kappa


@wp.func
def zone_alpha(mats: MaterialTable, zone_id: int, rgb3_channel: int, wavelength: float):
    """Principal absorption coefficients (1/mm) of a zone's material entry: (alpha_o, alpha_o,
    alpha_e) of an isotropic or uniaxial one, (alpha_X, alpha_Y, alpha_Z) of a biaxial one; at
    ``wavelength`` nm, or its Guy & Soler eq. 9 RGB absorbances in the rgb3 mode."""
    biaxial = mats.beta_channel[zone_id] >= 0
    if rgb3_channel >= 0:
        a_o = mats.rgb3_alpha_o[zone_id][rgb3_channel]
        a_y = a_o
        if biaxial:
            a_y = mats.rgb3_alpha_b[zone_id][rgb3_channel]
        return wp.vec3f(a_o, a_y, mats.rgb3_alpha_e[zone_id][rgb3_channel])
    no, ne, alpha = material_optics(mats, zone_id, wavelength)
    a_y = alpha[0]
    if biaxial:
        nb = material_eval_beta(mats, zone_id, wavelength)
        a_y = alpha_from_k_wp(nb[1], wp.max(wavelength, 1.0e-3))
    return wp.vec3f(alpha[0], a_y, alpha[1])


@wp.func
def _zone_lengths_of(mats: MaterialTable, mat_id: int, origin: wp.vec3f, direction: wp.vec3f, length: float):
    """``optics.zoning.zone_lengths`` of a world segment in zoned material ``mat_id``'s zones
    (the segment turned into its stone's frame)."""
    m = mats.zone_frame[mat_id]
    return zone_lengths(
        mats.zone_kind[mat_id],
        mats.zone_axis[mat_id],
        mats.zone_origin[mat_id],
        mats.zone_bound,
        mats.zone_start[mat_id],
        mats.zone_count[mat_id],
        wp.transform_point(m, origin),
        wp.transform_vector(m, direction),
        length,
    )


@wp.func
def zoned_kappa(
    mats: MaterialTable,
    mat_id: int,
    kappa: float,
    rgb3_channel: int,
    mode: int,
    wave_normal: wp.vec3f,
    med: UniaxialMedium,
    scale: float,
    wavelength: float,
    origin: wp.vec3f,
    direction: wp.vec3f,
    length: float,
):
    """Mean absorption coefficient (1/mm) of a wave along the segment ``origin + direction s``,
    ``s`` in [0, ``length``] (world, unit direction, mm) inside a solid of material ``mat_id``:
    ``kappa`` (the wave's :func:`segment_kappa`) unless the material is zoned; in a zoned stone
    the optical depth through its zones (``optics.zoning``: the exact lengths in each zone times
    each zone's kappa of this wave, from the zone's own absorption and the host's indices,
    ``med``), divided by ``length``, so that ``bouguer_lambert(mean, length)`` is exp(-depth).
    A segment wholly in one zone gets that zone's kappa itself, bit for bit."""
    count = mats.zone_count[mat_id]
    if count == 0:
        return kappa
    start = mats.zone_start[mat_id]
    lengths = _zone_lengths_of(mats, mat_id, origin, direction, length)
    kap = ZoneVector()
    held = int(-1)
    for i in range(count):
        if lengths[i] > 0.0:
            a = zone_alpha(mats, mats.zone_material[start + i], rgb3_channel, wavelength)
            kap[i] = _wave_kappa(mode, wave_normal, med, a[0], a[1], a[2]) * scale
            if lengths[i] >= length:
                held = i
    if held >= 0:
        return kap[held]
    if length <= 0.0:
        return 0.0
    return zoned_optical_depth(lengths, kap, count) / length


@wp.func
def zoned_isotropic_kappa(
    mats: MaterialTable,
    mat_id: int,
    kappa: float,
    n: float,
    scale: float,
    wavelength: float,
    origin: wp.vec3f,
    direction: wp.vec3f,
    length: float,
):
    """:func:`zoned_kappa` in an isotropic solid of real index ``n`` whose unzoned absorption
    coefficient is ``kappa`` (:func:`isotropic_optics`): the spectral bundles' and pixel beams'
    per-segment absorption (``kappa`` itself, one table read, for an unzoned material)."""
    if mats.zone_count[mat_id] == 0:
        return kappa
    return zoned_kappa(
        mats,
        mat_id,
        kappa,
        -1,
        -1,
        wp.vec3f(0.0, 0.0, 1.0),
        uniaxial_medium(n, n, wp.vec3f(0.0, 0.0, 0.0)),
        scale,
        wavelength,
        origin,
        direction,
        length,
    )


@wp.func
def zoned_alpha_pair(
    mats: MaterialTable,
    mat_id: int,
    alpha_o: float,
    alpha_e: float,
    rgb3_channel: int,
    wavelength: float,
    origin: wp.vec3f,
    direction: wp.vec3f,
    length: float,
):
    """Mean (alpha_o, alpha_e) in 1/mm along a world segment inside material ``mat_id``: the
    given pair for an unzoned material, else each zone's o and e absorption weighted by the
    segment's length in it (``optics.zoning.zoned_optical_depth`` / length): the straight
    shadow rays' filter (``stages.surfaces.gem_transmittance``)."""
    count = mats.zone_count[mat_id]
    if count == 0 or length <= 0.0:
        return wp.vec2f(alpha_o, alpha_e)
    start = mats.zone_start[mat_id]
    lengths = _zone_lengths_of(mats, mat_id, origin, direction, length)
    k_o = ZoneVector()
    k_e = ZoneVector()
    for i in range(count):
        if lengths[i] > 0.0:
            a = zone_alpha(mats, mats.zone_material[start + i], rgb3_channel, wavelength)
            k_o[i] = a[0]
            k_e[i] = a[2]
    return wp.vec2f(
        zoned_optical_depth(lengths, k_o, count) / length, zoned_optical_depth(lengths, k_e, count) / length
    )

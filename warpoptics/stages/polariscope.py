"""The polarizing-microscope stage: plane waves through a crystal plate between a polarizer and
an analyzer, for each direction of a beam (orthoscopic: one direction; conoscopic: the cone of
a condenser) and each wavelength.

Geometry: the microscope axis is world +z (light travels up, toward the observer); the plate's
faces are normal to it (``optics.plate``: normal (0, 0, -1) on the incident side); the
polarizer and the analyzer are ideal linear polarizers in the collimated beam before the
condenser and after the objective, their transmission axes at ``polarizer_deg`` and
``analyzer_deg`` from world x toward world y (image right toward image up for an observer
looking down the tube).  An optional accessory plate (first-order red, quarter-wave) sits in the
collimated beam in front of the analyzer.  Each direction of the cone sees them through the aplanatic lenses
(``optics.polarizer.lens_polarizer_field``).

Per (direction, wavelength) the stage writes the transmitted intensity (unit incident power
behind the polarizer) of the coherent plate (the plate's two waves added as amplitudes,
``optics.plate.plate_mode_jones``) and of the incoherent model (their powers added), so that a
caller sees both from one launch.  Optical activity (quartz) is optional: a rotatory power per
wavelength couples the two waves in the coherent result (``optics.plate.plate_active_jones``).

Arrays (all on the stage's device; the caller owns the outputs):
    directions   (N,) vec3   unit propagation directions (k_z > 0)
    thickness    (N,) float  plate thickness per direction, mm
    wavelength   (W,) float  nm
    indices      (W,) vec3   (n_o, 0, n_e) | (n_alpha, n_beta, n_gamma) | (n, 0, n)
    alpha        (W,) vec3   intensity absorption coefficients, 1/mm (see ``optics.plate``)
    frames       (N,) mat33  the crystal frame per direction (rows X, Y, Z, world): one plate seen
                             in many directions, or many plates (a thin section's grains) at once
    out_coherent, out_incoherent  (N, W) float
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import warp as wp

from .. import validate as val
from ..device import get_device, to_warp
from ..errors import InputError
from ..optics.birefringence import uniaxial_medium
from ..optics.complex import c_abs2, c_mul
from ..optics.jones import Jones, jones_entry, s_vector
from ..optics.plate import plate_active_jones, plate_medium, plate_mode_jones, wave_plate_jones
from ..optics.polarizer import lens_polarizer_field

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = ["PolariscopeConfig", "StagePolariscope", "plate_between_polarizers"]

_NORMAL = wp.constant(wp.vec3f(0.0, 0.0, -1.0))
_BEAM = wp.constant(wp.vec3f(0.0, 0.0, 1.0))


@dataclass(frozen=True)
class PolariscopeConfig:
    """Polarizer and analyzer (transmission axes, degrees from world x toward y) and the
    isotropic medium around the plate (air 1.0; a mounting medium such as Canada balsam 1.54)."""

    polarizer_deg: float = 0.0
    analyzer_deg: float = 90.0
    n_ambient: float = 1.0
    #: an accessory plate in the collimated beam before the analyzer (ideal retarder,
    #: ``optics.plate.wave_plate_jones``): retardation in nm (0: none; 550 the first-order red
    #: "gypsum" plate, 147 a quarter-wave "mica" plate at 589 nm) and its slow direction
    accessory_nm: float = 0.0
    accessory_deg: float = 45.0

    def __post_init__(self) -> None:
        val.number(self.polarizer_deg, field="polarizer_deg")
        val.number(self.analyzer_deg, field="analyzer_deg")
        val.number(self.n_ambient, field="n_ambient", lo=1.0, hi=3.0)
        val.number(self.accessory_nm, field="accessory_nm", lo=0.0, hi=1.0e5)
        val.number(self.accessory_deg, field="accessory_deg")

    def axes(self) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        p = math.radians(self.polarizer_deg)
        a = math.radians(self.analyzer_deg)
        return (math.cos(p), math.sin(p), 0.0), (math.cos(a), math.sin(a), 0.0)


@wp.func
def _analyzed(jm: Jones, p: wp.vec2f, a_re: wp.vec2f, a_im: wp.vec2f):
    # a^T J p (complex) for real polarizer components p and complex analyzer components a
    out = wp.vec2f(0.0, 0.0)
    for r in range(2):
        a = wp.vec2f(a_re[r], a_im[r])
        for c in range(2):
            out = out + c_mul(a, jones_entry(jm, r, c)) * p[c]
    return out


@wp.func
def _analyzer_through(acc: Jones, ana: wp.vec3f, x: wp.vec3f):
    """(Re, Im) of the analyzer's components in the frame (x, k x x) of a cone direction, seen
    through the accessory plate ``acc`` (world x, y frame of the collimated beam): the analyzer
    passes a^T A E of a field E, i.e. the complex axis A^T a, which the objective maps into the
    cone as ``lens_polarizer_field`` (a linear map: real and imaginary parts apart)."""
    v_re = wp.vec3f(
        acc.re[0, 0] * ana[0] + acc.re[1, 0] * ana[1], acc.re[0, 1] * ana[0] + acc.re[1, 1] * ana[1], 0.0
    )
    v_im = wp.vec3f(
        acc.im[0, 0] * ana[0] + acc.im[1, 0] * ana[1], acc.im[0, 1] * ana[0] + acc.im[1, 1] * ana[1], 0.0
    )
    return lens_polarizer_field(v_re, _BEAM, x), lens_polarizer_field(v_im, _BEAM, x)


@wp.kernel
def _polariscope_kernel(
    directions: wp.array(dtype=wp.vec3f),
    thickness: wp.array(dtype=float),
    wavelength: wp.array(dtype=float),
    indices: wp.array(dtype=wp.vec3f),
    alpha: wp.array(dtype=wp.vec3f),
    frames: wp.array(dtype=wp.mat33),
    n_ambient: float,
    pol: wp.vec3f,
    ana: wp.vec3f,
    acc_angle: float,
    acc_nm: float,
    rotatory: wp.array(dtype=float),
    rotatory_ratio: float,
    out_coherent: wp.array2d(dtype=float),
    out_incoherent: wp.array2d(dtype=float),
):
    i, j = wp.tid()
    k = wp.normalize(directions[i])
    amb = uniaxial_medium(n_ambient, n_ambient, wp.vec3f(0.0, 0.0, 0.0))
    med = plate_medium(indices[j], frames[i])
    j0, j1 = plate_mode_jones(k, _NORMAL, amb, med, thickness[i], wavelength[j], alpha[j])
    x = s_vector(k, _NORMAL)
    p = lens_polarizer_field(pol, _BEAM, x)
    a_re, a_im = _analyzer_through(wave_plate_jones(acc_angle, acc_nm, wavelength[j]), ana, x)
    e0 = _analyzed(j0, p, a_re, a_im)
    e1 = _analyzed(j1, p, a_re, a_im)
    if rotatory[j] != 0.0:
        # optical activity: the two waves coupled inside the plate (the incoherent model below
        # keeps them independent, without activity)
        ja = plate_active_jones(
            k, _NORMAL, amb, med, thickness[i], wavelength[j], alpha[j], rotatory[j], rotatory_ratio
        )
        out_coherent[i, j] = c_abs2(_analyzed(ja, p, a_re, a_im))
    else:
        out_coherent[i, j] = c_abs2(e0 + e1)
    out_incoherent[i, j] = c_abs2(e0) + c_abs2(e1)


class StagePolariscope:
    """Owns the polariscope kernel for one :class:`PolariscopeConfig`; :meth:`run` fills the
    caller's (N, W) outputs from the arrays of the module docstring without allocating."""

    def __init__(self, config: PolariscopeConfig | None = None, *, device=None) -> None:
        self.config = config or PolariscopeConfig()
        if not isinstance(self.config, PolariscopeConfig):
            raise TypeError("config must be a PolariscopeConfig")
        self.device = get_device(device)
        p, a = self.config.axes()
        self._pol = wp.vec3f(*p)
        self._ana = wp.vec3f(*a)
        self._no_rotation: wp.array | None = None

    def run(
        self,
        directions: wp.array,
        thickness: wp.array,
        wavelength: wp.array,
        indices: wp.array,
        alpha: wp.array,
        crystal_frame,
        out_coherent: wp.array,
        out_incoherent: wp.array,
        rotatory: wp.array | None = None,
        rotatory_ratio: float = 0.0,
    ) -> None:
        """``rotatory`` (W,) the plate's rotatory power along its optic axis, rad/mm, positive
        counter-clockwise about the propagation direction (None: no optical activity; uniaxial
        or isotropic plates only), ``rotatory_ratio`` G11 / G33 (``optics.plate``)."""
        n, w = directions.shape[0], wavelength.shape[0]
        if rotatory is None:
            if self._no_rotation is None or self._no_rotation.shape[0] != w:
                self._no_rotation = wp.zeros(w, dtype=float, device=self.device)
            rotatory = self._no_rotation
        elif rotatory.shape[0] != w:
            raise ValueError(f"rotatory has {rotatory.shape[0]} entries, expected {w}")
        for name, arr, length in (("thickness", thickness, n), ("indices", indices, w), ("alpha", alpha, w)):
            if arr.shape[0] != length:
                raise ValueError(f"{name} has {arr.shape[0]} entries, expected {length}")
        for name, arr in (("out_coherent", out_coherent), ("out_incoherent", out_incoherent)):
            if tuple(arr.shape) != (n, w):
                raise ValueError(f"{name} has shape {tuple(arr.shape)}, expected {(n, w)}")
        f = np.asarray(crystal_frame, dtype=np.float64).reshape(-1, 3, 3)
        if f.shape[0] not in (1, n):
            raise ValueError(f"crystal_frame has {f.shape[0]} frames, expected 1 or {n}")
        frames = wp.array(
            np.ascontiguousarray(np.broadcast_to(f, (n, 3, 3)), dtype=np.float32),
            dtype=wp.mat33,
            device=self.device,
        )
        wp.launch(
            _polariscope_kernel,
            dim=(n, w),
            inputs=[
                directions,
                thickness,
                wavelength,
                indices,
                alpha,
                frames,
                float(self.config.n_ambient),
                self._pol,
                self._ana,
                math.radians(self.config.accessory_deg),
                float(self.config.accessory_nm),
                rotatory,
                float(rotatory_ratio),
            ],
            outputs=[out_coherent, out_incoherent],
            device=self.device,
        )


def plate_between_polarizers(
    directions,
    thickness_mm,
    wavelength_nm,
    indices,
    *,
    crystal_frame=None,
    alpha=None,
    config: PolariscopeConfig | None = None,
    rotatory_rad_mm=None,
    rotatory_ratio: float = 0.0,
    device=None,
) -> tuple[np.ndarray, np.ndarray]:
    """NumPy form of :class:`StagePolariscope`: ``directions`` (N, 3), ``thickness_mm`` (N,) or
    a scalar, ``wavelength_nm`` (W,), ``indices`` (W, 3), ``alpha`` (W, 3) or None (lossless),
    ``crystal_frame`` (3, 3) rows X, Y, Z (Z the optic axis of a uniaxial plate; default the
    identity), or (N, 3, 3): a frame per direction (many plates in one launch);
    ``rotatory_rad_mm`` (W,) or a scalar: optical activity (:meth:`StagePolariscope.run`; None:
    none).  Returns (coherent, incoherent) transmitted intensities, each (N, W)."""
    dev = get_device(device)
    k = val.finite_array(np.asarray(directions, dtype=np.float64).reshape(-1, 3), field="directions")
    if np.any(k[:, 2] <= 0.0):
        raise InputError("directions must travel along +z", field="directions", allowed="k_z > 0")
    lam = val.finite_array(np.atleast_1d(np.asarray(wavelength_nm, dtype=np.float64)), field="wavelength_nm")
    if np.any(lam <= 0):
        raise InputError("must be > 0", field="wavelength_nm", value=float(lam.min()), allowed="> 0")
    n3 = val.finite_array(np.asarray(indices, dtype=np.float64).reshape(-1, 3), field="indices")
    if n3.shape[0] != lam.size:
        n3 = np.broadcast_to(n3, (lam.size, 3))
    a3 = np.zeros((lam.size, 3)) if alpha is None else np.asarray(alpha, dtype=np.float64).reshape(-1, 3)
    a3 = val.finite_array(np.broadcast_to(a3, (lam.size, 3)), field="alpha")
    d = val.finite_array(
        np.broadcast_to(np.asarray(thickness_mm, dtype=np.float64), (k.shape[0],)), field="thickness_mm"
    )
    if np.any(d < 0):
        raise InputError("must be >= 0", field="thickness_mm", value=float(d.min()), allowed=">= 0")
    frame = val.finite_array(np.eye(3) if crystal_frame is None else crystal_frame, field="crystal_frame")
    rot = None
    if rotatory_rad_mm is not None:
        rot = val.finite_array(
            np.broadcast_to(np.asarray(rotatory_rad_mm, dtype=np.float64), (lam.size,)),
            field="rotatory_rad_mm",
        )
        if np.any(n3[:, 1] > 0) and np.any(rot != 0):
            raise InputError(
                "optical activity is modelled for uniaxial (or isotropic) plates only",
                field="rotatory_rad_mm",
            )
        val.number(rotatory_ratio, field="rotatory_ratio")
        rot = to_warp(rot, wp.float32, dev)
    stage = StagePolariscope(config, device=dev)
    out_c = wp.zeros((k.shape[0], lam.size), dtype=float, device=dev)
    out_i = wp.zeros((k.shape[0], lam.size), dtype=float, device=dev)
    stage.run(
        to_warp(k, wp.vec3f, dev),
        to_warp(d, wp.float32, dev),
        to_warp(lam, wp.float32, dev),
        to_warp(n3, wp.vec3f, dev),
        to_warp(a3, wp.vec3f, dev),
        frame,
        out_c,
        out_i,
        rotatory=rot,
        rotatory_ratio=float(rotatory_ratio),
    )
    return out_c.numpy().astype(np.float64), out_i.numpy().astype(np.float64)

"""Exact thin-film stacks: complex amplitudes rs, rp, ts, tp of any number of homogeneous layers.

The layers lie between an incident medium and a substrate, with complex indices and any angle;
the characteristic-matrix (Abelès) method is written in the normalised "Airy" form of
:func:`stack_amplitudes_scaled` so that thick or strongly absorbing layers never overflow.

Conventions (see also ``optics/complex.py``):

* time dependence exp(-i omega t); indices ``n + i k`` with k >= 0 absorbing; wavelengths and
  thicknesses in nanometres; angles of incidence in degrees in the NumPy wrappers (cosines in
  the ``@wp.func``s), measured in the incident medium;
* the stack is described from the *front* (ambient) medium through layers 0..L-1 to the *back*
  medium (the substrate); light may arrive from either side (``from_back``);
* amplitudes are ratios of complex electric-field amplitudes (reflected or transmitted over
  incident) at the first / last interface.  Sign convention of Born & Wolf, Hecht and ``tmm``
  (Byrnes): for a bare interface
  ``rs = (N1 cos i - N2 cos t) / (N1 cos i + N2 cos t)``,
  ``rp = (N2 cos i - N1 cos t) / (N2 cos i + N1 cos t)`` (so rp = -rs at normal incidence),
  ``ts = 2 N1 cos i / (N1 cos i + N2 cos t)``, ``tp = 2 N1 cos i / (N2 cos i + N1 cos t)``;
* powers: R = |r|^2, T_s = |ts|^2 Re(N2 cos t) / Re(N1 cos i),
  T_p = |tp|^2 Re(conj(N2) cos t) / Re(conj(N1) cos i)  (normal Poynting flux; the incident
  medium should be transparent for R + T + A = 1 to hold).

The stacks run in float64 inside the kernels (``wp.vec2d`` complex numbers): the same matrix
product in float32 (NumPy complex64) differed from ``tmm`` by up to 5.7e-6 in R for twelve-layer
stacks (20 random stacks, 380–780 nm, 0–85 degrees, s), beyond the 1e-6 the project asks for;
the float64 kernels agree with ``tmm`` to < 1e-12.  The renderer calls
:func:`coating_amplitudes` (float32 in, float32 out, float64 inside) with layer data in a
:class:`CoatingStack` of device arrays, so no kernel is regenerated for a new stack.

References
----------
* M. Born and E. Wolf, *Principles of Optics*, 7th ed., §1.6.2–1.6.4 (characteristic matrix of
  a stratified medium, eq. 1.6 (33)–(35), (58)–(59)).
* H. A. Macleod, *Thin-Film Optical Filters*, 4th ed., §2.2 (admittances, tilted admittances).
* S. J. Byrnes, "Multilayer optical calculations", arXiv:1603.02720 (the ``tmm`` package; the
  sign and power conventions used here).
"""

from __future__ import annotations

import numpy as np
import warp as wp

from ...device import device_function, elementwise, get_device
from ...errors import InputError
from ..complex import c_abs2, c_div, c_exp, c_mul, c_normal_component
from ..fresnel import flux_transmittance, p_normal_flux
from .inputs import complex_pairs, cos_angle, positive

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "CoatingStack",
    "stack_layer_index",
    "stack_amplitudes",
    "stack_amplitudes_scaled",
    "stack_power",
    "coating_amplitudes",
    "coating_amplitudes_scaled",
    "make_coating_stack",
    "amplitudes",
    "reflectance",
    "transmittance",
    "evaluate_coating",
]


@wp.struct
class CoatingStack:
    """Layer data of a set of coatings, on the device.

    ``index``               [layer, sample] complex index n + ik (``wp.vec2d``) of each layer,
                            sampled at ``wavelength_start_nm + j * wavelength_step_nm``
                            (linear interpolation, clamped; one column = dispersionless)
    ``thickness_nm``        [layer] geometric thickness, nm (float64)
    ``first_layer``         [coating] row of the coating's front-most layer in ``index``
    ``layer_count``         [coating] number of layers (0 = bare interface)
    ``wavelength_start_nm`` first sample wavelength, nm
    ``wavelength_step_nm``  sample spacing, nm
    """

    index: wp.array2d(dtype=wp.vec2d)
    thickness_nm: wp.array(dtype=wp.float64)
    first_layer: wp.array(dtype=wp.int32)
    layer_count: wp.array(dtype=wp.int32)
    wavelength_start_nm: wp.float64
    wavelength_step_nm: wp.float64


@wp.func
def stack_layer_index(stack: CoatingStack, layer: int, wavelength_nm: wp.float64):
    """Complex index of row ``layer`` of ``stack.index`` at ``wavelength_nm`` (linear interpolation)."""
    samples = stack.index.shape[1]
    if samples == 1:
        return stack.index[layer, 0]
    x = (wavelength_nm - stack.wavelength_start_nm) / stack.wavelength_step_nm
    x = wp.clamp(x, wp.float64(0.0), wp.float64(samples - 1))
    j = wp.min(int(x), samples - 2)
    f = x - wp.float64(j)
    return stack.index[layer, j] * (wp.float64(1.0) - f) + stack.index[layer, j + 1] * f


@wp.func
def _expm1_over(z: wp.vec2d):
    """(exp(z) - 1) / z for complex z, accurate near z = 0 (series for |z| < 1e-3)."""
    one = wp.float64(1.0)
    if c_abs2(z) < wp.float64(1.0e-6):
        z2 = c_mul(z, z)
        return (
            wp.vec2d(one, wp.float64(0.0))
            + z * wp.float64(0.5)
            + z2 * (one / wp.float64(6.0))
            + c_mul(z2, z) * (one / wp.float64(24.0))
        )
    return c_div(c_exp(z) - wp.vec2d(one, wp.float64(0.0)), z)


@wp.func
def _times_i(a: wp.vec2d):
    return wp.vec2d(-a[1], a[0])


@wp.func
def stack_amplitudes_scaled(
    stack: CoatingStack,
    coating: int,
    wavelength_nm: wp.float64,
    cos_i: wp.float64,
    n_front: wp.vec2d,
    n_back: wp.vec2d,
    from_back: int,
    thickness_scale: wp.float64,
):
    """Exact (rs, rp, ts, tp) of coating ``coating`` of ``stack`` (float64 complex ``wp.vec2d``)
    with every layer thickness multiplied by ``thickness_scale`` (a per-hit value: films whose
    thickness varies over a surface, Smits & Meyer 1990 eq. 12–13 and §4.2).

    Characteristic matrix of each layer (Born & Wolf §1.6, eq. 1.6 (33); time dependence
    exp(-i omega t)), with the normal wave-vector component q = N cos(theta) from Snell's law
    (``c_normal_component``) and the phase thickness delta = 2 pi q d / lambda::

        M = [[cos delta, -i sin delta / y], [-i y sin delta, cos delta]],
        y = q (s), y = q / N^2 (p; the field continued is H, the TM dual of the s case).

    Each M is multiplied by exp(i delta) (|exp(i delta)| <= 1 since Im q >= 0), giving entries
    (1 + w)/2, -i k0 d E(z) (s) or -i k0 d N^2 E(z) (p), y (1 - w)/2 with w = exp(2 i delta),
    z = 2 i delta and E(z) = (exp(z) - 1)/z: no overflow for thick or absorbing layers, no
    division by q at grazing incidence or at a layer's critical angle.  With
    [B, C] = M_0 M_1 ... M_{L-1} [1, y_sub]:  r = (y0 B - C)/(y0 B + C), t_tangential =
    2 y0 prod(exp(i delta)) / (y0 B + C); ts = t_tangential, tp = t_tangential N0 / N_sub
    (the p recursion carries H = N E).

    ``cos_i`` is the cosine of the angle of incidence in the incident medium, which is
    ``n_front`` (light enters layer 0 first) when ``from_back == 0`` and ``n_back`` (layers in
    reverse order) otherwise.  Zero layers give the bare-interface Fresnel amplitudes; two
    identical media at exactly grazing incidence give r = 0, t = 1.
    """
    zero = wp.float64(0.0)
    one = wp.float64(1.0)
    half = wp.float64(0.5)
    czero = wp.vec2d(zero, zero)
    cone = wp.vec2d(one, zero)

    n_in = n_front
    n_out = n_back
    if from_back != 0:
        n_in = n_back
        n_out = n_front
    first = stack.first_layer[coating]
    count = stack.layer_count[coating]
    k0 = wp.float64(6.283185307179586) / wavelength_nm  # 2 pi / lambda, 1/nm

    # running products of the normalised matrices, s and p: [[a, b], [c, d]]
    sa = cone
    sb = czero
    sc = czero
    sd = cone
    pa = cone
    pb = czero
    pc = czero
    pd = cone
    phase = cone  # prod exp(i delta)
    for k in range(count):
        layer = first + k
        if from_back != 0:
            layer = first + count - 1 - k
        n = stack_layer_index(stack, layer, wavelength_nm)
        d = stack.thickness_nm[layer] * thickness_scale
        q = c_normal_component(n_in, n, cos_i)
        delta = q * (k0 * d)
        z = wp.vec2d(delta[1] * wp.float64(-2.0), delta[0] * wp.float64(2.0))  # 2 i delta
        w = c_exp(z)
        e = _expm1_over(z)
        m11 = (cone + w) * half
        omw = (cone - w) * half
        n2 = c_mul(n, n)
        yp = c_div(q, n2)
        # s layer matrix
        s12 = _times_i(e) * (-k0 * d)
        s21 = c_mul(q, omw)
        # p layer matrix
        p12 = _times_i(c_mul(n2, e)) * (-k0 * d)
        p21 = c_mul(yp, omw)
        # right-multiply the running products
        ta = c_mul(sa, m11) + c_mul(sb, s21)
        tb = c_mul(sa, s12) + c_mul(sb, m11)
        tc = c_mul(sc, m11) + c_mul(sd, s21)
        td = c_mul(sc, s12) + c_mul(sd, m11)
        sa = ta
        sb = tb
        sc = tc
        sd = td
        ta = c_mul(pa, m11) + c_mul(pb, p21)
        tb = c_mul(pa, p12) + c_mul(pb, m11)
        tc = c_mul(pc, m11) + c_mul(pd, p21)
        td = c_mul(pc, p12) + c_mul(pd, m11)
        pa = ta
        pb = tb
        pc = tc
        pd = td
        phase = c_mul(phase, c_exp(wp.vec2d(-delta[1], delta[0])))

    q0 = c_normal_component(n_in, n_in, cos_i)
    qs = c_normal_component(n_in, n_out, cos_i)
    # s
    y0 = q0
    ys = qs
    b = sa + c_mul(sb, ys)
    c = sc + c_mul(sd, ys)
    den = c_mul(y0, b) + c
    rs = czero
    ts = cone
    if c_abs2(den) > zero:
        rs = c_div(c_mul(y0, b) - c, den)
        ts = c_div(c_mul(y0, phase) * wp.float64(2.0), den)
    # p
    y0 = c_div(q0, c_mul(n_in, n_in))
    ys = c_div(qs, c_mul(n_out, n_out))
    b = pa + c_mul(pb, ys)
    c = pc + c_mul(pd, ys)
    den = c_mul(y0, b) + c
    rp = czero
    tp = cone
    if c_abs2(den) > zero:
        rp = c_div(c_mul(y0, b) - c, den)
        tp = c_div(c_mul(c_mul(y0, phase), n_in) * wp.float64(2.0), c_mul(den, n_out))
    return rs, rp, ts, tp


@wp.func
def stack_amplitudes(
    stack: CoatingStack,
    coating: int,
    wavelength_nm: wp.float64,
    cos_i: wp.float64,
    n_front: wp.vec2d,
    n_back: wp.vec2d,
    from_back: int,
):
    """:func:`stack_amplitudes_scaled` at the stack's own thicknesses (scale 1)."""
    return stack_amplitudes_scaled(
        stack, coating, wavelength_nm, cos_i, n_front, n_back, from_back, wp.float64(1.0)
    )


@wp.func
def stack_power(
    rs: wp.vec2d,
    rp: wp.vec2d,
    ts: wp.vec2d,
    tp: wp.vec2d,
    cos_i: wp.float64,
    n_in: wp.vec2d,
    n_out: wp.vec2d,
):
    """(Rs, Rp, Ts, Tp) from the amplitudes of :func:`stack_amplitudes` (normal Poynting flux).

    R = |r|^2; Ts = |ts|^2 Re(q_out) / Re(q_in); Tp = |tp|^2 Re(conj(N_out) cos t) /
    Re(conj(N_in) cos i) with q = N cos(theta) (Byrnes 2016, eq. 21–22).  T = 0 where the
    incident flux vanishes (grazing incidence) or the exit wave is evanescent (TIR).
    """
    q_in = c_normal_component(n_in, n_in, cos_i)
    q_out = c_normal_component(n_in, n_out, cos_i)
    # the flux laws of the bare interface (optics/fresnel.py), in double precision
    Ts = flux_transmittance(c_abs2(ts), q_in[0], q_out[0])
    Tp = flux_transmittance(c_abs2(tp), p_normal_flux(q_in, n_in), p_normal_flux(q_out, n_out))
    return wp.vec4d(c_abs2(rs), c_abs2(rp), Ts, Tp)


@wp.func
def _to_d(a: wp.vec2f):
    return wp.vec2d(wp.float64(a[0]), wp.float64(a[1]))


@wp.func
def _to_f(a: wp.vec2d):
    return wp.vec2f(wp.float32(a[0]), wp.float32(a[1]))


@wp.func
def coating_amplitudes_scaled(
    stack: CoatingStack,
    coating: int,
    wavelength_nm: float,
    cos_i: float,
    n_front: wp.vec2f,
    n_back: wp.vec2f,
    from_back: int,
    thickness_scale: float,
):
    """Float32 front end of :func:`stack_amplitudes_scaled` for the renderer's trace kernel.

    Same arguments and conventions; inputs and the returned (rs, rp, ts, tp) are float32
    (``wp.vec2f``), the stack itself is evaluated in float64.
    """
    rs, rp, ts, tp = stack_amplitudes_scaled(
        stack,
        coating,
        wp.float64(wavelength_nm),
        wp.float64(cos_i),
        _to_d(n_front),
        _to_d(n_back),
        from_back,
        wp.float64(thickness_scale),
    )
    return _to_f(rs), _to_f(rp), _to_f(ts), _to_f(tp)


@wp.func
def coating_amplitudes(
    stack: CoatingStack,
    coating: int,
    wavelength_nm: float,
    cos_i: float,
    n_front: wp.vec2f,
    n_back: wp.vec2f,
    from_back: int,
):
    """:func:`coating_amplitudes_scaled` at the stack's own thicknesses (scale 1)."""
    return coating_amplitudes_scaled(stack, coating, wavelength_nm, cos_i, n_front, n_back, from_back, 1.0)


# ---------------------------------------------------------------------------------------------
# Kernels (element-wise, launched through device.elementwise)
# ---------------------------------------------------------------------------------------------


@wp.kernel
def _stack_kernel(
    offset: int,
    wavelength_nm: wp.array(dtype=wp.float64),
    cos_i: wp.array(dtype=wp.float64),
    n_front: wp.array(dtype=wp.vec2d),
    n_back: wp.array(dtype=wp.vec2d),
    stack: CoatingStack,
    coating_stride: int,
    from_back: int,
    rs_out: wp.array(dtype=wp.vec2d),
    rp_out: wp.array(dtype=wp.vec2d),
    ts_out: wp.array(dtype=wp.vec2d),
    tp_out: wp.array(dtype=wp.vec2d),
    power_out: wp.array(dtype=wp.vec4d),
):
    i = wp.tid() + offset
    rs, rp, ts, tp = stack_amplitudes(
        stack, i * coating_stride, wavelength_nm[i], cos_i[i], n_front[i], n_back[i], from_back
    )
    rs_out[i] = rs
    rp_out[i] = rp
    ts_out[i] = ts
    tp_out[i] = tp
    n_in = n_front[i]
    n_out = n_back[i]
    if from_back != 0:
        n_in = n_back[i]
        n_out = n_front[i]
    power_out[i] = stack_power(rs, rp, ts, tp, cos_i[i], n_in, n_out)


@wp.kernel
def _coating_f32_kernel(
    offset: int,
    wavelength_nm: wp.array(dtype=float),
    cos_i: wp.array(dtype=float),
    n_front: wp.array(dtype=wp.vec2f),
    n_back: wp.array(dtype=wp.vec2f),
    stack: CoatingStack,
    coating_stride: int,
    from_back: int,
    rs_out: wp.array(dtype=wp.vec2f),
    rp_out: wp.array(dtype=wp.vec2f),
    ts_out: wp.array(dtype=wp.vec2f),
    tp_out: wp.array(dtype=wp.vec2f),
):
    i = wp.tid() + offset
    rs, rp, ts, tp = coating_amplitudes(
        stack, i * coating_stride, wavelength_nm[i], cos_i[i], n_front[i], n_back[i], from_back
    )
    rs_out[i] = rs
    rp_out[i] = rp
    ts_out[i] = ts
    tp_out[i] = tp


# ---------------------------------------------------------------------------------------------
# Python wrappers
# ---------------------------------------------------------------------------------------------


def make_coating_stack(
    layers: list[list[tuple[complex | np.ndarray, float]]],
    *,
    wavelength_start_nm: float = 360.0,
    wavelength_step_nm: float = 5.0,
    device=None,
) -> CoatingStack:
    """Build a :class:`CoatingStack` from coatings given as lists of (index, thickness_nm).

    Each coating is a list of layers from the front (ambient) side to the substrate; each
    layer's index is a complex number (dispersionless) or an array of complex samples on the
    grid ``wavelength_start_nm + j * wavelength_step_nm`` (all layers of the set then need the
    same number of samples).  Arrays are uploaded once; coatings are addressed by their
    position in ``layers``.
    """
    dev = get_device(device)
    rows = []
    thick = []
    first = []
    count = []
    for coating in layers:
        first.append(len(rows))
        count.append(len(coating))
        for index, d in coating:
            rows.append(np.atleast_1d(np.asarray(index, dtype=np.complex128)))
            thick.append(d)
    samples = max((v.size for v in rows), default=1)
    for r, v in enumerate(rows):
        if v.size not in (1, samples):
            raise InputError(
                f"layer row {r}: {v.size} index samples, others have {samples}",
                field="index",
                allowed="one value (dispersionless) or the same wavelength grid for every layer",
            )
    table = np.zeros((max(len(rows), 1), samples, 2), dtype=np.float64)
    for r, v in enumerate(rows):
        pairs = complex_pairs(v, "index")
        table[r] = pairs if v.size == samples else pairs[0]
    d = positive(np.asarray(thick if thick else [0.0]), "thickness_nm", allow_zero=True)
    stack = CoatingStack()
    stack.index = wp.array(table, dtype=wp.vec2d, device=dev)
    stack.thickness_nm = wp.array(d, dtype=wp.float64, device=dev)
    stack.first_layer = wp.array(np.asarray(first or [0], dtype=np.int32), dtype=wp.int32, device=dev)
    stack.layer_count = wp.array(np.asarray(count or [0], dtype=np.int32), dtype=wp.int32, device=dev)
    stack.wavelength_start_nm = wp.float64(wavelength_start_nm)
    stack.wavelength_step_nm = wp.float64(wavelength_step_nm)
    return stack


def _run_stack(wavelength_nm, n_layers, thickness_nm, n_incident, n_substrate, angle, from_substrate, device):
    dev = get_device(device)
    wl = positive(wavelength_nm, "wavelength_nm")
    cos_i = cos_angle(angle)
    n_in = complex_pairs(n_incident, "n_incident")
    n_sub = complex_pairs(n_substrate, "n_substrate")
    nl = np.asarray(n_layers, dtype=np.complex128)
    d = positive(thickness_nm, "thickness_nm", allow_zero=True)
    if nl.ndim == 0:
        nl = nl.reshape(1)
    if d.ndim == 0:
        d = d.reshape(1)
    if nl.shape[-1] != d.shape[-1]:
        raise InputError(
            f"n_layers has {nl.shape[-1]} layers (last axis) but thickness_nm has {d.shape[-1]}",
            field="thickness_nm",
            value=f"shape {d.shape} vs n_layers shape {nl.shape}",
            allowed="one thickness per layer (same last axis)",
        )
    L = nl.shape[-1]
    nl_pairs = complex_pairs(nl, "n_layers") if L else np.zeros((*nl.shape, 2))
    shape = np.broadcast_shapes(
        wl.shape, cos_i.shape, n_in.shape[:-1], n_sub.shape[:-1], nl.shape[:-1], d.shape[:-1]
    )
    stack = CoatingStack()
    if nl.shape[:-1] == () and d.shape[:-1] == ():
        stride = 0
        table = nl_pairs.reshape(L, 1, 2) if L else np.zeros((1, 1, 2))
        thick = d if L else np.zeros(1)
        first = np.zeros(1, np.int32)
        count = np.full(1, L, np.int32)
    else:
        stride = 1
        n = int(np.prod(shape, dtype=np.int64))
        if L:
            table = np.broadcast_to(nl_pairs, (*shape, L, 2)).reshape(n * L, 1, 2)
            thick = np.broadcast_to(d, (*shape, L)).reshape(n * L)
        else:
            table = np.zeros((1, 1, 2))
            thick = np.zeros(1)
        first = (np.arange(n, dtype=np.int32) * L).astype(np.int32)
        count = np.full(n, L, np.int32)
    stack.index = wp.array(np.ascontiguousarray(table), dtype=wp.vec2d, device=dev)
    stack.thickness_nm = wp.array(np.ascontiguousarray(thick, dtype=np.float64), dtype=wp.float64, device=dev)
    stack.first_layer = wp.array(first, dtype=wp.int32, device=dev)
    stack.layer_count = wp.array(count, dtype=wp.int32, device=dev)
    stack.wavelength_start_nm = wp.float64(0.0)
    stack.wavelength_step_nm = wp.float64(1.0)
    outs = elementwise(
        _stack_kernel,
        [
            (np.broadcast_to(wl, shape), wp.float64),
            (np.broadcast_to(cos_i, shape), wp.float64),
            (np.broadcast_to(n_in, (*shape, 2)), wp.vec2d),
            (np.broadcast_to(n_sub, (*shape, 2)), wp.vec2d),
        ],
        [wp.vec2d, wp.vec2d, wp.vec2d, wp.vec2d, wp.vec4d],
        extra=(stack, stride, int(bool(from_substrate))),
        device=dev,
    )
    amps = [o[..., 0] + 1j * o[..., 1] for o in outs[:4]]
    return amps, outs[4]


@device_function(stack_amplitudes)
def amplitudes(
    wavelength_nm,
    n_layers,
    thickness_nm,
    n_incident=1.0,
    n_substrate=1.0,
    angle=0.0,
    *,
    from_substrate: bool = False,
    device=None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Exact complex amplitudes (rs, rp, ts, tp) of a thin-film stack (:func:`stack_amplitudes`).

    Parameters
    ----------
    wavelength_nm : array_like
        Vacuum wavelength, nm.
    n_layers : array_like, complex
        Layer indices n + ik (k >= 0), front (incident side) to substrate, along the **last
        axis**; leading axes broadcast with the other arguments (e.g. shape (W, L) for indices
        per wavelength).  A scalar is one layer; an empty list is the bare interface.
    thickness_nm : array_like
        Geometric layer thicknesses, nm, same last axis as ``n_layers``.
    n_incident, n_substrate : array_like, complex
        Indices of the front medium and of the substrate.
    angle : array_like
        Angle of incidence in degrees, 0..90, in the medium the light comes from.
    from_substrate : bool
        Light arrives from the substrate (layers traversed in reverse order).

    Returns
    -------
    rs, rp, ts, tp : complex128 arrays with the broadcast shape; sign conventions in the
    module docstring (Born & Wolf / Hecht / ``tmm``).
    """
    amps, _ = _run_stack(
        wavelength_nm, n_layers, thickness_nm, n_incident, n_substrate, angle, from_substrate, device
    )
    return tuple(amps)


_POL = {"s": 0, "p": 1}


def _select(power: np.ndarray, polarization: str, offset: int) -> np.ndarray:
    if polarization == "unpolarized":
        return 0.5 * (power[..., offset] + power[..., offset + 1])
    if polarization in _POL:
        return power[..., offset + _POL[polarization]].copy()
    raise InputError(
        "unknown polarization", field="polarization", value=polarization, allowed='"s", "p", "unpolarized"'
    )


@device_function(stack_power)
def reflectance(
    wavelength_nm,
    n_layers,
    thickness_nm,
    n_incident=1.0,
    n_substrate=1.0,
    angle=0.0,
    polarization: str = "unpolarized",
    *,
    from_substrate: bool = False,
    device=None,
) -> np.ndarray:
    """Exact reflectance R of a thin-film stack (any number of layers); arguments as :func:`amplitudes`.

    ``polarization``: "s", "p" or "unpolarized" (the mean of the two).
    """
    if polarization not in ("s", "p", "unpolarized"):
        _select(np.zeros((1, 4)), polarization, 0)
    _, power = _run_stack(
        wavelength_nm, n_layers, thickness_nm, n_incident, n_substrate, angle, from_substrate, device
    )
    return _select(power, polarization, 0)


@device_function(stack_power)
def transmittance(
    wavelength_nm,
    n_layers,
    thickness_nm,
    n_incident=1.0,
    n_substrate=1.0,
    angle=0.0,
    polarization: str = "unpolarized",
    *,
    from_substrate: bool = False,
    device=None,
) -> np.ndarray:
    """Exact transmittance T (normal energy flux into the exit medium); arguments as :func:`reflectance`."""
    if polarization not in ("s", "p", "unpolarized"):
        _select(np.zeros((1, 4)), polarization, 2)
    _, power = _run_stack(
        wavelength_nm, n_layers, thickness_nm, n_incident, n_substrate, angle, from_substrate, device
    )
    return _select(power, polarization, 2)


@device_function(coating_amplitudes)
def evaluate_coating(
    stack: CoatingStack,
    coating,
    wavelength_nm,
    angle,
    n_front,
    n_back,
    *,
    from_back: bool = False,
    device=None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """NumPy wrapper of the renderer's float32 :func:`coating_amplitudes` (float32 in and out).

    ``coating`` (index into ``stack``), ``wavelength_nm``, ``angle`` (degrees) and the complex
    ``n_front`` / ``n_back`` broadcast together.  Returns complex64 (rs, rp, ts, tp).
    """
    dev = get_device(device)
    coating = np.asarray(coating)
    ncoat = stack.layer_count.shape[0]
    if not np.issubdtype(coating.dtype, np.integer) or np.any(coating < 0) or np.any(coating >= ncoat):
        raise InputError(
            "coating index out of range", field="coating", value=coating, allowed=f"0..{ncoat - 1}"
        )
    wl = positive(wavelength_nm, "wavelength_nm")
    cos_i = cos_angle(angle)
    nf = complex_pairs(n_front, "n_front")
    nb = complex_pairs(n_back, "n_back")
    shape = np.broadcast_shapes(coating.shape, wl.shape, cos_i.shape, nf.shape[:-1], nb.shape[:-1])
    # the kernel addresses coating i * stride; pass the per-element coating through a gather
    outs = []
    flat_coat = np.broadcast_to(coating, shape).reshape(-1)
    uniq = np.unique(flat_coat)
    res = [np.zeros(shape, np.complex64) for _ in range(4)]
    for c in uniq:
        sel = np.broadcast_to(coating, shape) == c
        sub = CoatingStack()
        sub.index = stack.index
        sub.thickness_nm = stack.thickness_nm
        sub.first_layer = wp.array(stack.first_layer.numpy()[c : c + 1], dtype=wp.int32, device=dev)
        sub.layer_count = wp.array(stack.layer_count.numpy()[c : c + 1], dtype=wp.int32, device=dev)
        sub.wavelength_start_nm = stack.wavelength_start_nm
        sub.wavelength_step_nm = stack.wavelength_step_nm
        outs = elementwise(
            _coating_f32_kernel,
            [
                (np.broadcast_to(wl, shape)[sel], wp.float32),
                (np.broadcast_to(cos_i, shape)[sel], wp.float32),
                (np.broadcast_to(nf, (*shape, 2))[sel], wp.vec2f),
                (np.broadcast_to(nb, (*shape, 2))[sel], wp.vec2f),
            ],
            [wp.vec2f, wp.vec2f, wp.vec2f, wp.vec2f],
            extra=(sub, 0, int(bool(from_back))),
            device=dev,
        )
        for r, o in zip(res, outs, strict=True):
            r[sel] = o[..., 0] + 1j * o[..., 1]
    return tuple(res)

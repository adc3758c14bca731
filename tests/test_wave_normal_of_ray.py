"""The wave normal of a crystal wave from its ray (optics.biaxial.medium_wave_normal), which pixel
beams use at every vertex: checked against the forward map it inverts, the ray of the wave of
a given wave normal (``medium_incident_wave``: the uniaxial index metric, the biaxial
eigenproblem), and against Born & Wolf §15.3's tan theta_s = (no/ne)^2 tan theta_k for a
uniaxial e-wave (calcite, ~6 deg of walk-off at 45 deg from the axis)."""

import math

import numpy as np
import pytest
import warp as wp

from warpoptics.optics.biaxial import biaxial_medium, medium_incident_wave, medium_wave_normal
from warpoptics.optics.birefringence import uniaxial_medium


@wp.kernel
def _round_trip(
    k: wp.array(dtype=wp.vec3),
    mode: int,
    n3: wp.vec3,
    biaxial: int,
    frame: wp.mat33,
    ray: wp.array(dtype=wp.vec3),
    back: wp.array(dtype=wp.vec3),
):
    i = wp.tid()
    med = uniaxial_medium(n3[0], n3[2], wp.vec3(0.0, 0.0, 1.0))
    if biaxial != 0:
        med = biaxial_medium(n3[0], n3[1], n3[2], frame, 0.0)
    w = medium_incident_wave(k[i], mode, med, wp.vec3(0.0, 0.0, 1.0))
    ray[i] = w.ray
    back[i] = medium_wave_normal(w.ray, mode, med)


def _directions(n=400, seed=3):
    v = np.random.default_rng(seed).normal(size=(n, 3))
    return (v / np.linalg.norm(v, axis=1, keepdims=True)).astype(np.float32)


def _run(n3, mode, device, frame=None):
    k = _directions()
    ka = wp.array(k, dtype=wp.vec3, device=device)
    ray = wp.zeros(len(k), dtype=wp.vec3, device=device)
    back = wp.zeros(len(k), dtype=wp.vec3, device=device)
    f = np.eye(3, dtype=np.float32) if frame is None else frame
    inputs = [ka, mode, wp.vec3(*n3), int(frame is not None), wp.mat33(*f.ravel()), ray, back]
    wp.launch(_round_trip, dim=len(k), inputs=inputs, device=device)
    return k, ray.numpy(), back.numpy()


@pytest.mark.parametrize("mode", [0, 1], ids=["o", "e"])
def test_uniaxial_wave_normal_inverts_the_ray(device, mode):
    # calcite at 589 nm (refractiveindex.info, Ghosh): the strongest walk-off of any common crystal
    k, ray, back = _run((1.6584, 0.0, 1.4864), mode, device)
    assert np.abs(back - k).max() < 2e-6
    if mode == 1:
        cos_k = np.abs(k[:, 2])
        cos_s = np.abs(ray[:, 2])
        tan_k = np.sqrt(1 - cos_k**2) / cos_k
        tan_s = np.sqrt(np.clip(1 - cos_s**2, 0, None)) / cos_s
        ok = cos_k > 0.05
        np.testing.assert_allclose(tan_s[ok], (1.6584 / 1.4864) ** 2 * tan_k[ok], rtol=2e-4)
        assert math.degrees(np.max(np.arccos(np.clip(np.sum(ray * k, axis=1), -1, 1)))) > 6.0


@pytest.mark.parametrize("mode", [0, 1], ids=["fast", "slow"])
def test_biaxial_wave_normal_inverts_the_ray(device, mode):
    # peridot-like principal indices (1.654, 1.672, 1.690) in a turned frame; directions within
    # 3 degrees of an optic axis (conical refraction: the ray map is singular there) excluded
    c, s = math.cos(0.4), math.sin(0.4)
    frame = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]], dtype=np.float32)
    a, b, g = 1.654, 1.672, 1.690
    k, ray, back = _run((a, b, g), mode, device, frame)
    # the optic axes (binormals) lie in the X-Z plane at +-V from Z, where the wave with D in
    # that plane has index n_beta: cos^2 V = (b^-2 - g^-2) / (a^-2 - g^-2)
    v = math.acos(math.sqrt((b**-2 - g**-2) / (a**-2 - g**-2)))
    axes = [frame.T @ np.array([math.sin(sv * v), 0.0, math.cos(v)]) for sv in (1, -1)]
    near = np.zeros(len(k), bool)
    for ax in axes:
        near |= np.abs(k @ ax) > math.cos(math.radians(3.0))
    err = np.linalg.norm(back - k, axis=1)[~near]
    assert err.max() < 1e-5

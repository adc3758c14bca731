"""Jones / coherency algebra, frames and Stokes vectors (warpoptics.optics.jones).

References are NumPy complex128 matrix algebra, scipy rotations and the time-domain field.
Tolerances: float32 products of O(1) entries: a few 1e-7 relative; 1e-5 leaves margin for sums
of four products.
"""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import warpoptics as wo

opt = wo.optics


def _random_complex(rng, shape):
    return rng.normal(size=shape) + 1j * rng.normal(size=shape)


def _random_coherency(rng, n):
    # sum of two random pure states with random weights: Hermitian PSD, any DOP
    e1 = _random_complex(rng, (n, 2))
    e2 = _random_complex(rng, (n, 2))
    w = rng.uniform(0, 1, (n, 1, 1))
    return w * np.einsum("ni,nj->nij", e1, e1.conj()) + (1 - w) * np.einsum("ni,nj->nij", e2, e2.conj())


def _random_unitary(rng, n):
    q, _ = np.linalg.qr(_random_complex(rng, (n, 2, 2)))
    return q


def _check_hermitian_psd(j, tol):
    scale = np.abs(np.trace(j, axis1=-2, axis2=-1))[..., None, None] + 1e-30
    assert np.abs(j - np.conj(np.swapaxes(j, -1, -2))).max() == 0.0  # exactly Hermitian
    eig = np.linalg.eigvalsh(j)
    assert (eig / scale[..., 0, 0, None]).min() > -tol


def test_jones_product_vs_numpy(device):
    rng = np.random.default_rng(0)
    a = _random_complex(rng, (1000, 2, 2))
    b = _random_complex(rng, (1000, 2, 2))
    got = opt.jones_product(a, b, device=device)
    np.testing.assert_allclose(got, a @ b, atol=1e-5 * np.abs(a @ b).max())


def test_coherency_transform_vs_numpy_and_psd(device):
    rng = np.random.default_rng(1)
    m = _random_complex(rng, (5000, 2, 2))
    j = _random_coherency(rng, 5000)
    got = opt.coherency_apply(m, j, device=device)
    want = m @ j @ np.conj(np.swapaxes(m, -1, -2))
    err = np.abs(got - want).max(axis=(-1, -2)) / np.abs(want).max(axis=(-1, -2))
    eig = np.linalg.eigvalsh(got) / np.trace(got, axis1=-2, axis2=-1).real[:, None]
    print(f"M J M^dagger: worst relative error {err.max():.2e}, smallest eigenvalue / trace {eig.min():.2e}")
    assert err.max() < 2e-6, err.max()
    _check_hermitian_psd(got, 1e-5)
    p = opt.dop(got, device=device)
    assert np.all(p >= 0) and np.all(p <= 1)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    seed=st.integers(0, 2**32 - 1),
    depth=st.integers(1, 16),
    absorbing=st.booleans(),
)
def test_coherency_chain_stays_hermitian_psd(device, seed, depth, absorbing):
    """A path of up to 16 interface events (random Fresnel-like and rotation matrices)."""
    rng = np.random.default_rng(seed)
    j = _random_coherency(rng, 64)
    for _ in range(depth):
        if absorbing:
            m = np.zeros((64, 2, 2), complex)
            m[:, 0, 0] = _random_complex(rng, 64) * 0.5
            m[:, 1, 1] = _random_complex(rng, 64) * 0.5
        else:
            # U diag(s1, s2) V with singular values in [0.1, 1] (condition number <= 10, an
            # interface's transmission or reflection between Brewster extremes).  Unbounded Gaussian
            # matrices are no interface's and can be so ill-conditioned that float32 loses the small
            # eigenvalue of a nearly pure state (seed 7995, depth 15: -1.4e-5 of the trace); with
            # the bound, 600 seeds x 64 chains of 16 steps give at worst -5.7e-7
            sv = rng.uniform(0.1, 1.0, (64, 2))
            m = _random_unitary(rng, 64) @ (sv[:, :, None] * np.eye(2)) @ _random_unitary(rng, 64)
        j = opt.coherency_apply(m, j, device=device)
        j = j / np.maximum(np.trace(j, axis1=-2, axis2=-1).real, 1e-30)[:, None, None]
    _check_hermitian_psd(j, 1e-5)
    p = opt.dop(j, device=device)
    assert np.all(np.isfinite(p)) and np.all(p >= 0) and np.all(p <= 1)


def test_stokes_convention_and_handedness(device):
    s2 = np.sqrt(0.5)
    fields = {
        "x": np.array([1, 0]),
        "y": np.array([0, 1]),
        "+45": np.array([s2, s2]),
        "right": np.array([s2, -1j * s2]),  # S3 = +1
        "left": np.array([s2, 1j * s2]),
    }
    want = {
        "x": [1, 1, 0, 0],
        "y": [1, -1, 0, 0],
        "+45": [1, 0, 1, 0],
        "right": [1, 0, 0, 1],
        "left": [1, 0, 0, -1],
    }
    j = np.array([np.outer(e, e.conj()) for e in fields.values()])
    s = opt.stokes(j, device=device)
    np.testing.assert_allclose(s, np.array(list(want.values())), atol=1e-6)
    # handedness in the time domain with exp(-i w t): S3 > 0 turns clockwise in the (x, y) plane
    # seen by an observer facing the oncoming wave (looking down -d onto a right-handed (x, y, d)
    # frame), i.e. "right-handed" in Born & Wolf's naming
    for name, e in fields.items():
        t = np.linspace(0, 2 * np.pi, 9)
        real = np.real(e[None, :] * np.exp(-1j * t)[:, None])
        cross_z = real[:-1, 0] * real[1:, 1] - real[:-1, 1] * real[1:, 0]
        s3 = want[name][3]
        if s3 > 0:
            assert np.all(cross_z < 0)  # clockwise
        elif s3 < 0:
            assert np.all(cross_z > 0)
        else:
            assert np.allclose(cross_z, 0)


def test_stokes_roundtrip_and_dop(device):
    rng = np.random.default_rng(2)
    j = _random_coherency(rng, 2000)
    s = opt.stokes(j, device=device)
    back = opt.coherency_from_stokes(s, device=device)
    np.testing.assert_allclose(back, j, atol=1e-5 * np.abs(j).max())
    # DOP vs NumPy reference from eigenvalues: (l1 - l2) / (l1 + l2)
    eig = np.linalg.eigvalsh(j)
    want = (eig[:, 1] - eig[:, 0]) / (eig[:, 1] + eig[:, 0])
    np.testing.assert_allclose(opt.dop(j, device=device), want, atol=2e-5)
    assert opt.dop(0.5 * np.eye(2), device=device) == pytest.approx(0.0, abs=1e-7)
    assert opt.dop(np.zeros((2, 2)), device=device) == 0.0
    assert opt.dop(np.array([[0.5, 0.5j], [-0.5j, 0.5]]), device=device) == pytest.approx(1.0, abs=1e-6)


def _rand_perp(rng, d):
    v = rng.normal(size=d.shape)
    v -= d * np.sum(v * d, axis=-1, keepdims=True)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def test_frame_change_is_rotation_r_theta(device):
    rng = np.random.default_rng(3)
    d = rng.normal(size=(500, 3))
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    x0 = _rand_perp(rng, d)
    theta = rng.uniform(-np.pi, np.pi, 500)
    # x1 = x0 turned by +theta about d
    x1 = Rotation.from_rotvec(d * theta[:, None]).apply(x0)
    b = opt.frame_change_matrix(d, x0, x1, device=device)
    c, s = np.cos(theta), np.sin(theta)
    r_theta = np.stack([np.stack([c, s], -1), np.stack([-s, c], -1)], -2)  # Guy & Soler §4.2
    np.testing.assert_allclose(b, r_theta, atol=2e-6)
    # a frame change preserves the intensity and DOP of a coherency matrix
    j = _random_coherency(rng, 500)
    j2 = opt.coherency_apply(b.astype(complex), j, device=device)
    np.testing.assert_allclose(
        np.trace(j2, axis1=-2, axis2=-1).real, np.trace(j, axis1=-2, axis2=-1).real, rtol=2e-6
    )
    np.testing.assert_allclose(opt.dop(j2, device=device), opt.dop(j, device=device), atol=2e-5)


def test_s_vector_and_normal_incidence(device):
    rng = np.random.default_rng(4)
    d = rng.normal(size=(200, 3))
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    n = rng.normal(size=(200, 3))
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    s = opt.s_vectors(d, n, device=device)
    want = np.cross(n, d)
    want /= np.linalg.norm(want, axis=-1, keepdims=True)
    np.testing.assert_allclose(s, want, atol=2e-6)
    # normal incidence: finite, unit, perpendicular, independent of the sign of d
    z = np.array([0.0, 0.0, 1.0])
    s_a = opt.s_vectors(-z, z, device=device)
    s_b = opt.s_vectors(z, z, device=device)
    assert np.all(np.isfinite(s_a)) and abs(np.linalg.norm(s_a) - 1) < 1e-6 and abs(s_a @ z) < 1e-7
    np.testing.assert_array_equal(s_a, s_b)


def test_transport_basis_vs_scipy(device):
    rng = np.random.default_rng(5)
    d0 = rng.normal(size=(500, 3))
    d0 /= np.linalg.norm(d0, axis=-1, keepdims=True)
    d1 = rng.normal(size=(500, 3))
    d1 /= np.linalg.norm(d1, axis=-1, keepdims=True)
    x = _rand_perp(rng, d0)
    got = opt.transport_bases(x, d0, d1, device=device)
    axis = np.cross(d0, d1)
    angle = np.arctan2(np.linalg.norm(axis, axis=-1), np.sum(d0 * d1, -1))
    axis /= np.linalg.norm(axis, axis=-1, keepdims=True)
    want = Rotation.from_rotvec(axis * angle[:, None]).apply(x)
    np.testing.assert_allclose(got, want, atol=2e-5)
    assert np.abs(np.sum(got * d1, -1)).max() < 1e-6
    # same and opposite directions: finite, x kept
    same = opt.transport_bases(x[:3], d0[:3], d0[:3], device=device)
    opp = opt.transport_bases(x[:3], d0[:3], -d0[:3], device=device)
    np.testing.assert_allclose(same, x[:3], atol=1e-6)
    np.testing.assert_allclose(opp, x[:3], atol=1e-6)

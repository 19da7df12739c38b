"""Rotation vectors and matrices (core/rotations.py) against scipy.spatial.transform.Rotation,
over angles from 0 through π and above."""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation   # a requirement of both test environments

from easyidp_toolbox.core.rotations import rotation_matrix, rotation_vector

ANGLES = [0.0, 1e-12, 1e-6, 0.3, 1.5, np.pi / 2, 3.0, np.pi - 1e-6, np.pi - 1e-9, np.pi,
          np.pi + 1e-6, 4.0, 2 * np.pi - 0.1, 7.0]


def _axes(seed=0, n=6):
    a = np.random.default_rng(seed).normal(size=(n, 3))
    a = np.vstack([np.eye(3), -np.eye(3), a])
    return a / np.linalg.norm(a, axis=1, keepdims=True)


@pytest.mark.parametrize("angle", ANGLES)
def test_matrix_of_vector_matches_scipy(angle):
    v = _axes() * angle
    assert np.allclose(rotation_matrix(v), Rotation.from_rotvec(v).as_matrix(), atol=1e-13)
    assert np.allclose(rotation_matrix(v[0]), Rotation.from_rotvec(v[0]).as_matrix(), atol=1e-13)


@pytest.mark.parametrize("angle", ANGLES)
def test_vector_of_matrix_matches_scipy(angle):
    R = Rotation.from_rotvec(_axes(1) * angle).as_matrix()
    v = rotation_vector(R)
    ref = Rotation.from_matrix(R).as_rotvec()
    theta = np.linalg.norm(ref, axis=1)
    assert np.allclose(np.linalg.norm(v, axis=1), theta, atol=1e-7)
    assert (np.linalg.norm(v, axis=1) <= np.pi + 1e-12).all()
    # at π the axis's sign is arbitrary: the same rotation either way
    sure = theta < np.pi - 1e-5
    assert np.allclose(v[sure], ref[sure], atol=1e-9)
    assert np.allclose(rotation_matrix(v), R, atol=1e-9)
    assert np.allclose(rotation_vector(R[0]), v[0]) and rotation_vector(R[0]).shape == (3,)


def test_random_rotations_round_trip():
    R = Rotation.random(200, random_state=3).as_matrix()
    v = rotation_vector(R)
    assert np.allclose(v, Rotation.from_matrix(R).as_rotvec(), atol=1e-10)
    assert np.allclose(rotation_matrix(v), R, atol=1e-12)

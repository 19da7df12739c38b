"""Rotations between rotation vectors and matrices.

A rotation vector (axis-angle) is (…, 3): its direction the axis, its norm the angle in
radians, counter-clockwise (right-handed) about the axis; a rotation matrix (…, 3, 3) maps
``p`` to ``R @ p``. Any angle is taken (0, π, above π); :func:`rotation_vector` gives the
angle in [0, π].
"""
import numpy as np


def rotation_matrix(v) -> np.ndarray:
    """Rotation matrices (…, 3, 3) of rotation vectors (…, 3) (Rodrigues' formula)."""
    v = np.asarray(v, dtype=np.float64)
    a = np.linalg.norm(v, axis=-1)[..., None, None]
    k = v / np.where(a[..., 0] > 0, a[..., 0], 1.0)
    K = np.zeros(v.shape[:-1] + (3, 3))
    K[..., 0, 1], K[..., 0, 2], K[..., 1, 2] = -k[..., 2], k[..., 1], -k[..., 0]
    K[..., 1, 0], K[..., 2, 0], K[..., 2, 1] = k[..., 2], -k[..., 1], k[..., 0]
    return np.eye(3) + np.sin(a) * K + (1.0 - np.cos(a)) * (K @ K)


def rotation_vector(R) -> np.ndarray:
    """Rotation vectors (…, 3), angle in [0, π], of rotation matrices (…, 3, 3): the inverse of
    :func:`rotation_matrix`, through the unit quaternion (Shepperd's choice of its largest
    component), so it is accurate near 0 and π."""
    R = np.asarray(R, dtype=np.float64)
    M = R.reshape(-1, 3, 3)
    t = np.trace(M, axis1=1, axis2=2)
    case = np.argmax(np.column_stack([t, M[:, 0, 0], M[:, 1, 1], M[:, 2, 2]]), axis=1)
    q = np.zeros((len(M), 3))
    w = np.zeros(len(M))
    s = case == 0
    if s.any():
        m = M[s]
        w[s] = 0.5 * np.sqrt(1.0 + t[s])
        q[s] = np.column_stack([m[:, 2, 1] - m[:, 1, 2], m[:, 0, 2] - m[:, 2, 0],
                                m[:, 1, 0] - m[:, 0, 1]]) / (4.0 * w[s, None])
    for i in range(3):
        s = case == i + 1
        if not s.any():
            continue
        j, k = (i + 1) % 3, (i + 2) % 3
        m = M[s]
        qi = 0.5 * np.sqrt(1.0 + m[:, i, i] - m[:, j, j] - m[:, k, k])
        q[s, i] = qi
        w[s] = (m[:, k, j] - m[:, j, k]) / (4.0 * qi)
        q[s, j] = (m[:, j, i] + m[:, i, j]) / (4.0 * qi)
        q[s, k] = (m[:, k, i] + m[:, i, k]) / (4.0 * qi)
    flip = w < 0
    w[flip], q[flip] = -w[flip], -q[flip]
    n = np.linalg.norm(q, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.where(n[:, None] > 0, q * (2.0 * np.arctan2(n, w) / n)[:, None], 0.0)
    return out.reshape(R.shape[:-1])

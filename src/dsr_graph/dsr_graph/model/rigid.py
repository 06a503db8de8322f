"""Rigid 4x4 transforms: building, checking, inverting, describing. numpy + transforms3d only.

Conventions (the CORTEX C++ code's): a matrix is Translation * Rx(a) * Ry(b) * Rz(c) for
``rotation_euler_xyz = [a, b, c]`` in radians, i.e. transforms3d's rotating-axes 'rxyz' order.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from transforms3d import euler, quaternions

from dsr_graph.exceptions import NotRigidError

# Tolerance for "orthonormal with det +1": world files store float32 angles and matrices
# round-tripped through JSON, so exact equality would reject real data.
RIGID_TOLERANCE = 1e-6
EULER_AXES = "rxyz"


def from_translation_euler(translation: Sequence[float], euler_xyz: Sequence[float]) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3] = euler.euler2mat(*_floats(euler_xyz, 3, "rotation_euler_xyz"), axes=EULER_AXES)
    m[:3, 3] = _floats(translation, 3, "translation")
    return m


def from_translation_quaternion(
    translation: Sequence[float], quaternion_wxyz: Sequence[float]
) -> np.ndarray:
    q = np.asarray(_floats(quaternion_wxyz, 4, "quaternion_wxyz"))
    norm = np.linalg.norm(q)
    if abs(norm - 1.0) > 1e-6:
        raise NotRigidError(f"quaternion_wxyz must have unit norm, has norm {norm:.9g}")
    m = np.eye(4)
    m[:3, :3] = quaternions.quat2mat(q)
    m[:3, 3] = _floats(translation, 3, "translation")
    return m


def check_rigid(matrix: Any) -> np.ndarray:
    """``matrix`` as a float 4x4 array, or ``NotRigidError`` naming what is wrong."""
    try:
        m = np.array(matrix, dtype=float)
    except (TypeError, ValueError) as e:
        raise NotRigidError(f"matrix is not numeric: {e}") from e
    if m.shape != (4, 4):
        raise NotRigidError(f"matrix must be 4x4, got shape {list(m.shape)}")
    if not np.all(np.isfinite(m)):
        raise NotRigidError("matrix has non-finite entries")
    if np.max(np.abs(m[3] - (0.0, 0.0, 0.0, 1.0))) > RIGID_TOLERANCE:
        raise NotRigidError(f"last row must be [0, 0, 0, 1], got {m[3].tolist()}")
    r = m[:3, :3]
    err = np.max(np.abs(r.T @ r - np.eye(3)))
    if err > RIGID_TOLERANCE:
        raise NotRigidError(f"rotation is not orthonormal (max |R^T R - I| = {err:.3g})")
    det = np.linalg.det(r)
    if abs(det - 1.0) > RIGID_TOLERANCE:
        raise NotRigidError(f"rotation must have determinant +1, has {det:.6g} (a reflection?)")
    m[3] = (0.0, 0.0, 0.0, 1.0)
    return m


def from_json(spec: Any) -> np.ndarray:
    """A checked matrix from one of the JSON pose forms (see docs/FORMAT.md):
    ``{"matrix": 4x4}``, ``{"translation", "rotation_euler_xyz"}``,
    ``{"translation", "quaternion_wxyz"}``."""
    if not isinstance(spec, Mapping):
        raise NotRigidError(f"rt must be an object, got {type(spec).__name__}")
    keys = set(spec)
    if keys == {"matrix"}:
        return check_rigid(spec["matrix"])
    if keys == {"translation", "rotation_euler_xyz"}:
        return from_translation_euler(spec["translation"], spec["rotation_euler_xyz"])
    if keys == {"translation", "quaternion_wxyz"}:
        return from_translation_quaternion(spec["translation"], spec["quaternion_wxyz"])
    raise NotRigidError(
        "rt must be exactly one of {matrix}, {translation, rotation_euler_xyz}, "
        f"{{translation, quaternion_wxyz}}; got keys {sorted(keys)}"
    )


def to_json(matrix: np.ndarray) -> dict:
    """The canonical, lossless JSON form of a transform."""
    return {"matrix": matrix.tolist()}


def inverse(matrix: np.ndarray) -> np.ndarray:
    """Inverse of a rigid transform: [R^T, -R^T t] (exact, cheaper than a general inverse)."""
    inv = np.eye(4)
    rt = matrix[:3, :3].T
    inv[:3, :3] = rt
    inv[:3, 3] = -rt @ matrix[:3, 3]
    return inv


def quaternion_wxyz(matrix: np.ndarray) -> list:
    """Unit quaternion [w, x, y, z] of the rotation, with w >= 0 so the answer is unique.
    Through the Euler angles: the matrix is rigid (checked when it entered the graph), and this
    is 4x cheaper than ``mat2quat``'s eigendecomposition (7 vs 29 us; /tf turns every joint of a
    30 Hz skeleton into one), equal to 1e-15 (gimbal lock included: test_kinematics)."""
    q = euler.euler2quat(*euler.mat2euler(matrix[:3, :3], axes=EULER_AXES), axes=EULER_AXES)
    if q[0] < 0:
        q = -q
    return [float(v) for v in q]


def euler_xyz(matrix: np.ndarray) -> list:
    return [float(v) for v in euler.mat2euler(matrix[:3, :3], axes=EULER_AXES)]


def pose_json(matrix: np.ndarray) -> dict:
    """The ``dsr transform`` answer: matrix, translation and quaternion."""
    return {
        "matrix": matrix.tolist(),
        "translation": [float(v) for v in matrix[:3, 3]],
        "quaternion_wxyz": quaternion_wxyz(matrix),
    }


def _floats(values: Any, n: int, what: str) -> list:
    if not isinstance(values, (list, tuple, np.ndarray)) or len(values) != n:
        raise NotRigidError(f"{what} must be a list of {n} numbers, got {values!r}")
    out = []
    for v in values:
        if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)):
            raise NotRigidError(f"{what} must hold numbers, got {v!r}")
        f = float(v)
        if not np.isfinite(f):
            raise NotRigidError(f"{what} must be finite, got {v!r}")
        out.append(f)
    return out

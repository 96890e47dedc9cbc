"""The frames a suite env's state is told in: the server's rows (a floating base observed at
its first geom's centre of mass and frame, world angular velocity) and MuJoCo's ``qpos`` and
``qvel`` (the body's origin and orientation, angular velocity in its own frame), both ways:
``split_rows`` reads MuJoCo's state out of rows, ``server_state`` writes MuJoCo's state in
the server's layout (``set_state``)."""

from __future__ import annotations

from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``np.cross`` of (n, 3) (or (3,)) vectors, the same products and differences without its
    axis handling, which cost more than the arithmetic for a batch (16 calls per step)."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    # Written into one array (np.stack's own checks cost more than the arithmetic).
    out = np.empty(np.broadcast_shapes(a.shape, b.shape), dtype=np.result_type(a, b))
    out[..., 0] = a1 * b2 - a2 * b1
    out[..., 1] = a2 * b0 - a0 * b2
    out[..., 2] = a0 * b1 - a1 * b0
    return out


def _quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton products of (n, 4) and (4,) quaternions (w, x, y, z)."""
    w1, v1 = a[:, :1], a[:, 1:]
    w2, v2 = b[0], b[1:]
    # The dot product written out, in the order `_base_row` takes it (a matmul may fuse).
    dot = (v1[:, :1] * v2[0] + v1[:, 1:2] * v2[1]) + v1[:, 2:] * v2[2]
    return np.concatenate([w1 * w2 - dot, w1 * v2 + w2 * v1 + _cross(v1, v2)], axis=1)


def _rotate(quat: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Vectors ``x`` (n, 3) turned by orientations ``quat`` (n, 4; w, x, y, z)."""
    s, u = quat[:, :1], quat[:, 1:]
    return x + 2.0 * s * _cross(u, x) + 2.0 * _cross(u, _cross(u, x))


def _in_body_frame(quat: np.ndarray, w: np.ndarray) -> np.ndarray:
    """World vectors ``w`` (n, 3) in the frames of orientations ``quat`` (n, 4; w, x,
    y, z): rotated by each conjugate."""
    s, u = quat[:, :1], quat[:, 1:]
    return w - 2.0 * s * _cross(u, w) + 2.0 * _cross(u, _cross(u, w))


Vec = Tuple[float, ...]


def _cross3(a: Vec, b: Vec) -> Vec:
    """``_cross`` of two 3-vectors of Python floats."""
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _base_row(
    pose: np.ndarray, velocity: np.ndarray, root_geom: Optional[Tuple[np.ndarray, np.ndarray]]
) -> Tuple[Vec, Vec]:
    """``split_rows``'s floating base of one row, on Python floats (float64, each operation
    numpy's on a batch, in its order): MuJoCo's free-joint qpos (7) and qvel (6)."""
    p = pose.tolist()
    position, quat = p[:3], p[3:7]
    velocity_list = velocity.tolist()
    linear, angular = velocity_list[:3], velocity_list[3:6]
    if root_geom is not None:
        centre, geom_quat = root_geom
        g = geom_quat.tolist()
        w2, x2, y2, z2 = g[0], -g[1], -g[2], -g[3]
        w1, v1 = quat[0], quat[1:]
        dot = (v1[0] * x2 + v1[1] * y2) + v1[2] * z2
        c = _cross3(v1, (x2, y2, z2))
        quat = [w1 * w2 - dot] + [w1 * b + w2 * a + ci for a, b, ci in zip(v1, (x2, y2, z2), c)]
        s, u, x = quat[0], quat[1:], centre.tolist()
        c = _cross3(u, x)
        cc = _cross3(u, c)
        arm = [xi + 2.0 * s * ci + 2.0 * cci for xi, ci, cci in zip(x, c, cc)]
        position = [a - b for a, b in zip(position, arm)]
        linear = [a - b for a, b in zip(linear, _cross3(angular, arm))]
    s, u = quat[0], quat[1:]
    c = _cross3(u, angular)
    cc = _cross3(u, c)
    spin = [wi - 2.0 * s * ci + 2.0 * cci for wi, ci, cci in zip(angular, c, cc)]
    return (*position, *quat), (*linear, *spin)


def segments(layout: Sequence[Tuple[str, int]]) -> Dict[str, slice]:
    """Where each segment of the server's ``observation_layout`` lies in a flat row: the
    env's own layout, read, never restated here."""
    out, start = {}, 0
    for name, size in layout:
        out[name] = slice(start, start + size)
        start += size
    return out


def split_rows(
    raw: np.ndarray,
    segments: Dict[str, slice],
    root_geom: Optional[Tuple[np.ndarray, np.ndarray]] = None,
) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """MuJoCo's qpos and qvel, and the end effectors' positions, of raw rows (n, dim),
    split along the server's layout (``segments``). With a floating base, qpos starts
    with its body's position and orientation (w, x, y, z) and qvel with the linear
    velocity of the body's origin (world) and its angular velocity (its own frame), as
    MuJoCo's free joint has them. The server observes the base instance, the body's
    first geom: its centre of mass and its frame, which ``root_geom`` (the geom's centre
    and orientation in the body's frame) takes back to the body's."""
    q, v = raw[:, segments["joint_positions"]], raw[:, segments["joint_velocities"]]
    if "base_pose" in segments and len(raw) == 1:
        # One row (a single env): the same operations on Python floats, without a numpy
        # call per product (the same bits: `test_one_row_splits_as_a_batch_does`).
        base_q, base_v = _base_row(raw[0, segments["base_pose"]], raw[0, segments["base_velocity"]], root_geom)
        q = np.concatenate([np.array([base_q], dtype=raw.dtype), q], axis=1)
        v = np.concatenate([np.array([base_v], dtype=raw.dtype), v], axis=1)
    elif "base_pose" in segments:
        pose, velocity = raw[:, segments["base_pose"]], raw[:, segments["base_velocity"]]
        position, quat = pose[:, :3].astype(np.float64), pose[:, 3:7].astype(np.float64)
        linear, angular = velocity[:, :3].astype(np.float64), velocity[:, 3:6].astype(np.float64)
        if root_geom is not None:
            centre, geom_quat = root_geom
            quat = _quat_mul(quat, np.array([geom_quat[0], *(-geom_quat[1:])]))
            arm = _rotate(quat, np.broadcast_to(centre, position.shape))
            position = position - arm
            linear = linear - _cross(angular, arm)
        spin = _in_body_frame(quat, angular)
        q = np.concatenate([position.astype(raw.dtype), quat.astype(raw.dtype), q], axis=1)
        v = np.concatenate([linear.astype(raw.dtype), spin.astype(raw.dtype), v], axis=1)
    poses = raw[:, segments["end_effector_poses"]].reshape(len(raw), -1, 7)
    return q, v, poses[:, :, :3]


def server_state(
    qpos: np.ndarray,
    qvel: np.ndarray,
    base: bool,
    root_geom: Optional[Tuple[np.ndarray, np.ndarray]] = None,
) -> Tuple[List[float], List[float], List[float]]:
    """MuJoCo's ``qpos`` and ``qvel`` (float64) as the server's joint positions, joint
    velocities and floating-base state (13: the base instance's centre, orientation, its
    centre's velocity and the world angular velocity; none without a base): the inverse of
    ``split_rows``."""
    if not base:
        return qpos.tolist(), qvel.tolist(), []
    position, quat = qpos[None, 0:3], qpos[None, 3:7]
    quat = quat / np.linalg.norm(quat)
    linear, spin = qvel[None, 0:3], qvel[None, 3:6]
    angular = _rotate(quat, spin)
    if root_geom is not None:
        centre, geom_quat = root_geom
        arm = _rotate(quat, centre[None, :])
        position = position + arm
        linear = linear + _cross(angular, arm)
        quat = _quat_mul(quat, geom_quat)
    state = np.concatenate([position[0], quat[0], linear[0], angular[0]])
    return qpos[7:].tolist(), qvel[6:].tolist(), state.tolist()

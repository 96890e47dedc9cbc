"""manipulator-bring_ball: dm_control's planar arm brings a ball to a target
(``suite/manipulator.py``, ``Bring`` with the ball prop), in the server's terms.

The target, which dm_control moves in its model each episode, is a mocap body here,
drawn in the same box and turned by the same angle. The ball starts in the hand (at the
grasp site, 10 %), in the target (10 %) or anywhere, with a velocity (80 %), as
``reset_noise.choice``; the hand is made symmetric (``finger`` at ``thumb``), and a start
with overlapping colliders is drawn again. A planar body's ``xquat`` components (qw, qy)
are read from its joint angles: every hinge on the way turns about the same axis, so the
quaternion is the half-angle of their sum, as MuJoCo composes it."""

from __future__ import annotations

import math

import numpy as np

from . import terms as t
from .spec import Key, Task, _observed, _qpos, _qvel

#: dm_control's ``_ARM_JOINTS`` as qpos indices: the converted model keeps MuJoCo's order
#: (arm_root, arm_shoulder, arm_elbow, arm_wrist, thumb, thumbtip, finger, fingertip,
#: ball_x, ball_z, ball_y).
_ARM = [0, 1, 2, 3, 6, 7, 4, 5]
_TOUCH = ["palm_touch", "finger_touch", "thumb_touch", "fingertip_touch", "thumbtip_touch"]
_CLOSE = 0.01


def _bounded(v: np.ndarray) -> np.ndarray:
    """``bounded_joint_pos``: (sin, cos) of each arm joint, joint by joint."""
    a = v[:, _ARM]
    return np.stack([np.sin(a), np.cos(a)], axis=2).reshape(len(v), -1)


def _arm_velocity(v: np.ndarray) -> np.ndarray:
    return v[:, _ARM]


def _half_turn(x: np.ndarray, z: np.ndarray, angle: np.ndarray, sign: float) -> np.ndarray:
    """``body_2d_pose``: x, z, and the quaternion's w and y of a turn about ``sign``·y."""
    return np.stack([x, z, np.cos(angle / 2), sign * np.sin(angle / 2)], axis=1)


def _hand(v: np.ndarray) -> np.ndarray:
    # The arm's hinges turn about −y (the ``arm`` class's axis).
    return _half_turn(v[:, 0], v[:, 1], v[:, 2:6].sum(axis=1), -1.0)


def _ball(v: np.ndarray) -> np.ndarray:
    return _half_turn(v[:, 0], v[:, 1], v[:, 2], 1.0)


def _target(v: np.ndarray) -> np.ndarray:
    # xmat's xz (= sin) and xx (= cos) entries of a turn about +y, in (−π, π).
    return _half_turn(v[:, 0], v[:, 1], np.arctan2(v[:, 2], v[:, 3]), 1.0)


def _bring_ball() -> Task:
    touch = [t.value(n, t.sensor(n), observe=True) for n in _TOUCH]
    poses = [t.value(f"hand_{a}", t.xpos("hand", a), observe=True) for a in "xz"]
    poses += [t.value(f"target_{a}", t.xpos("target_ball", a), observe=True) for a in "xz"]
    poses += [t.value(f"target_{e}", t.xmat("target_ball", e), observe=True)
              for e in ("xz", "xx")]
    goal = [t.value(f"goal_{a}", t.site_xpos("target_ball", a)) for a in "xyz"]
    ball = [t.value(f"ball_{a}", t.site_xpos("ball", a)) for a in "xyz"]
    terms = [
        *touch, *poses, *goal, *ball,
        *[t.total(f"ball_to_target_{a}", [(f"goal_{a}", 1.0, 0.0), (f"ball_{a}", -1.0, 0.0)])
          for a in "xyz"],
        t.norm("ball_to_target", [f"ball_to_target_{a}" for a in "xyz"]),
        t.tolerance("bring", "ball_to_target", (0.0, _CLOSE), margin=2 * _CLOSE),
        t.reward("bring"),
    ]
    keys = [
        Key("arm_pos", [_qpos(0, 8)], transform=_bounded, shape=(8, 2)),
        Key("arm_vel", [_qvel(0, 8)], transform=_arm_velocity),
        Key("touch", [_observed(*_TOUCH)], transform=np.log1p),
        Key("hand_pos", [_observed("hand_x", "hand_z"), _qpos(0, 4)], transform=_hand),
        Key("object_pos", [_qpos(8, 11)], transform=_ball),
        Key("object_vel", [_qvel(8, 11)]),
        Key("target_pos", [_observed("target_x", "target_z", "target_xz", "target_xx")],
            transform=_target),
    ]
    ball_joints = ["ball_x", "ball_z", "ball_y"]
    noise = {
        "limited": True, "rotational": True, "reject_contacts": True,
        "equal": [["finger", "thumb"]],
        "mocap": [{"body": "target_ball",
                   "boxes": [{"low": [-0.4, 0.001, 0.1], "high": [0.4, 0.001, 0.4]}],
                   "turn": {"axis": [0.0, 1.0, 0.0], "angle": [-math.pi, math.pi]}}],
        "choice": {"joints": ball_joints, "options": [
            # In the hand: at the grasp site, turned half a turn from it
            # (dm_control: π − atan2(xmat zx, xmat xx)).
            {"weight": 0.1, "frame": "grasp", "from": ["x", "z", "angle_y"],
             "offset": [0.0, 0.0, math.pi]},
            {"weight": 0.1, "frame": "target_ball", "from": ["x", "z", "angle_y"]},
            {"weight": 0.8, "low": [-0.5, 0.0, 0.0], "high": [0.5, 0.7, 2 * math.pi],
             "velocity_low": [-5.0, 0.0, 0.0], "velocity_high": [5.0, 0.0, 0.0]},
        ]},
    }
    target = '<body name="target_ball" pos=".4 .001 .4" childclass="ghost">'
    moved = '<body name="target_ball" pos=".4 .001 .4" childclass="ghost" mocap="true">'
    return Task("manipulator", "bring_ball", "manipulator.xml", 10, 10.0, terms, keys, noise,
                note="the target is a mocap body (dm_control moves the body in the model)",
                edits=[(target, moved)],
                targets=[("body_pos", "target_ball", "target_ball"),
                         ("body_quat", "target_ball", "target_ball")],
                generated=(False, False), maker="make_model")

"""The Control Suite's tasks as gymfleet plans (the registry, and the classic and
locomotion tasks; `goals.py` the tasks with goals, `manipulator.py` the arm): for each, what dm_control's
``suite/<domain>.py`` does, in the server's terms: its observation keys (``Key``, from
qpos, qvel and observed terms), its reward (``terms.py``), its episode's start
(``reset_noise``: dm_control's ``initialize_episode``), its control timestep and time
limit. The contract tests check each against dm_control's own environment
(``client/python/tests/test_dmc.py``)."""


from __future__ import annotations

import math
from typing import Any, Dict

import numpy as np

from . import terms as t
from .goals import (
    _ball_in_cup_catch,
    _finger_spin,
    _finger_turn,
    _fish_swim,
    _fish_upright,
    _reacher,
    _swimmer,
)
from .manipulator import _bring_ball
from .spec import _RANDOMIZE, Key, Part, Task, _observed, _qpos, _qvel

__all__ = ["Key", "Part", "Task", "TASKS", "find"]


def _cheetah_run() -> Task:
    terms = [
        t.value("speed", t.sensor("torso_subtreelinvel", 0)),
        t.tolerance("run", "speed", (10.0, math.inf), margin=10.0, sigmoid="linear",
                    value_at_margin=0.0),
        t.reward("run"),
    ]
    keys = [Key("position", [_qpos(1)]), Key("velocity", [_qvel()])]
    return Task("cheetah", "run", "cheetah.xml", 1, 10.0, terms, keys,
                {"limited": True, "settle_substeps": 200})


_WALKER_BODIES = ("torso", "right_thigh", "right_leg", "right_foot", "left_thigh", "left_leg",
                  "left_foot")


def _walker(task: str, speed: float) -> Task:
    orientations = []
    names = []
    for body in _WALKER_BODIES:
        for entry in ("xx", "xz"):
            names.append(f"{body}_{entry}")
            orientations.append(t.value(names[-1], t.xmat(body, entry), observe=True))
    terms = orientations + [
        t.value("height", t.xpos("torso", "z"), observe=True),
        t.value("upright", t.xmat("torso", "zz")),
        t.value("horizontal_velocity", t.sensor("torso_subtreelinvel", 0)),
        t.tolerance("standing", "height", (1.2, math.inf), margin=0.6),
        t.total("stand_reward", [("standing", 0.75, 0.0), ("upright", 0.125, 0.125)]),
    ]
    if speed == 0:
        terms.append(t.reward("stand_reward"))
    else:
        terms += [
            t.tolerance("move_reward", "horizontal_velocity", (speed, math.inf),
                        margin=speed / 2, sigmoid="linear", value_at_margin=0.5),
            t.product("walk_reward", ["stand_reward", ("move_reward", 5.0 / 6.0, 1.0 / 6.0)]),
            t.reward("walk_reward"),
        ]
    keys = [
        Key("orientations", [_observed(*names)]),
        Key("height", [_observed("height")], scalar=True),
        Key("velocity", [_qvel()]),
    ]
    return Task("walker", task, "walker.xml", 10, 25.0, terms, keys, dict(_RANDOMIZE))


def _hopper(task: str) -> Task:
    terms = [
        t.value("touch_toe", t.sensor("touch_toe"), observe=True),
        t.value("touch_heel", t.sensor("touch_heel"), observe=True),
        t.value("torso_z", t.xipos(["torso", "nose"], "z")),
        t.value("foot_z", t.xipos(["foot"], "z")),
        t.total("height", [("torso_z", 1.0, 0.0), ("foot_z", -1.0, 0.0)]),
        t.tolerance("standing", "height", (0.6, 2.0)),
    ]
    if task == "hop":
        terms += [
            t.value("speed", t.sensor("torso_subtreelinvel", 0)),
            t.tolerance("hopping", "speed", (2.0, math.inf), margin=1.0, sigmoid="linear",
                        value_at_margin=0.5),
            t.product("hop_reward", ["standing", "hopping"]),
            t.reward("hop_reward"),
        ]
    else:
        terms += t.small_control(4)
        terms += [t.product("stand_reward", ["standing", "small_control"]),
                  t.reward("stand_reward")]
    keys = [
        Key("position", [_qpos(1)]),
        Key("velocity", [_qvel()]),
        Key("touch", [_observed("touch_toe", "touch_heel")], transform=np.log1p),
    ]
    return Task("hopper", task, "hopper.xml", 4, 20.0, terms, keys, dict(_RANDOMIZE))


def _cartpole(task: str, swing_up: bool, sparse: bool) -> Task:
    terms = [
        t.value("pole_zz", t.xmat("pole_1", "zz"), observe=True),
        t.value("pole_xz", t.xmat("pole_1", "xz"), observe=True),
        t.value("cart_position", t.joint("slider")),
    ]
    if sparse:
        terms += [
            t.tolerance("cart_in_bounds", "cart_position", (-0.25, 0.25)),
            t.tolerance("angle_in_bounds", "pole_zz", (0.995, 1.0)),
            t.product("sparse_reward", ["cart_in_bounds", "angle_in_bounds"]),
            t.reward("sparse_reward"),
        ]
    else:
        terms += [
            t.value("angular_velocity", t.joint_velocity("hinge_1")),
            t.tolerance("centered", "cart_position", margin=2.0),
            t.value("control", t.action(0)),
            t.tolerance("small_control", "control", margin=1.0, sigmoid="quadratic",
                        value_at_margin=0.0),
            t.tolerance("small_velocity", "angular_velocity", margin=5.0),
            t.product("smooth_reward", [
                ("pole_zz", 0.5, 0.5),
                ("small_control", 0.2, 0.8),
                ("small_velocity", 0.5, 0.5),
                ("centered", 0.5, 0.5),
            ]),
            t.reward("smooth_reward"),
        ]
    if swing_up:
        noise: Dict[str, Any] = {"set": [{"joints": ["slider", "hinge_1"], "mean": [0.0, math.pi],
                                          "std": [0.01, 0.01], "at_rest": False}]}
    else:
        noise = {"set": [{"joints": ["slider", "hinge_1"], "low": [-0.1, -0.034],
                          "high": [0.1, 0.034], "at_rest": False}]}
    noise["velocity"] = {"normal": 0.01}
    keys = [
        Key("position", [_qpos(0, 1), _observed("pole_zz", "pole_xz")]),
        Key("velocity", [_qvel()]),
    ]
    return Task("cartpole", task, "cartpole.xml", 1, 10.0, terms, keys, noise)


def _pendulum_swingup() -> Task:
    terms = [
        t.value("pole_zz", t.xmat("pole", "zz"), observe=True),
        t.value("pole_xz", t.xmat("pole", "xz"), observe=True),
        t.tolerance("vertical", "pole_zz", (math.cos(math.radians(8.0)), 1.0)),
        t.reward("vertical"),
    ]
    keys = [Key("orientation", [_observed("pole_zz", "pole_xz")]), Key("velocity", [_qvel()])]
    noise = {"set": [{"joints": ["hinge"], "low": [-math.pi], "high": [math.pi]}]}
    return Task("pendulum", "swingup", "pendulum.xml", 1, 20.0, terms, keys, noise)


def _acrobot(task: str, sparse: bool) -> Task:
    terms = [
        t.value("upper_arm_xz", t.xmat("upper_arm", "xz"), observe=True),
        t.value("lower_arm_xz", t.xmat("lower_arm", "xz"), observe=True),
        t.value("upper_arm_zz", t.xmat("upper_arm", "zz"), observe=True),
        t.value("lower_arm_zz", t.xmat("lower_arm", "zz"), observe=True),
        t.distance("to_target", {"site": "tip"}, {"site": "target"}),
        # The target site's radius (acrobot.xml: size 0.2).
        t.tolerance("in_target", "to_target", (0.0, 0.2), margin=0.0 if sparse else 1.0),
        t.reward("in_target"),
    ]
    keys = [
        Key("orientations", [_observed("upper_arm_xz", "lower_arm_xz", "upper_arm_zz",
                                       "lower_arm_zz")]),
        Key("velocity", [_qvel()]),
    ]
    noise = {"set": [{"joints": ["shoulder", "elbow"], "low": [-math.pi] * 2,
                      "high": [math.pi] * 2}]}
    return Task("acrobot", task, "acrobot.xml", 1, 10.0, terms, keys, noise)


def _point_mass_easy() -> Task:
    # The target geom's radius (point_mass.xml: size .015).
    size = 0.015
    terms = [
        t.distance("to_target", {"instance": "pointmass"}, {"instance": "target"}),
        t.tolerance("near_target", "to_target", (0.0, size), margin=size),
        *t.small_control(2),
        t.product("reach_reward", ["near_target", "small_control"]),
        t.reward("reach_reward"),
    ]
    keys = [Key("position", [_qpos()]), Key("velocity", [_qvel()])]
    return Task("point_mass", "easy", "point_mass.xml", 1, 20.0, terms, keys, dict(_RANDOMIZE))


_HUMANOID_LIMBS = ("left_hand", "left_foot", "right_hand", "right_foot")


def _humanoid(task: str, speed: float) -> Task:
    """dm_control's humanoid (``pure_state`` false): 21 motors."""
    extremities = []
    for limb in _HUMANOID_LIMBS:
        for axis in "xyz":
            extremities.append(t.value(f"{limb}_{axis}", {"site": limb, "relative_to": "torso",
                                                           "axis": axis}, observe=True))
    vertical = [t.value(f"torso_z{a}", t.xmat("torso", "z" + a), observe=True) for a in "xyz"]
    com = [t.value(f"com_velocity_{a}", t.sensor("torso_subtreelinvel", k), observe=True)
           for k, a in enumerate("xyz")]
    terms = [
        t.value("head_height", t.xpos("head", "z"), observe=True),
        *extremities, *vertical, *com,
        t.tolerance("standing", "head_height", (1.4, math.inf), margin=1.4 / 4),
        t.tolerance("upright", "torso_zz", (0.9, math.inf), sigmoid="linear", margin=1.9,
                    value_at_margin=0.0),
        *t.small_control(21),
    ]
    if speed == 0:
        terms += [
            t.tolerance("still_x", "com_velocity_x", margin=2.0),
            t.tolerance("still_y", "com_velocity_y", margin=2.0),
            t.total("dont_move", [("still_x", 0.5, 0.0), ("still_y", 0.5, 0.0)]),
            t.product("stand_reward", ["small_control", "standing", "upright", "dont_move"]),
            t.reward("stand_reward"),
        ]
    else:
        terms += [
            t.norm("horizontal_speed", ["com_velocity_x", "com_velocity_y"]),
            t.tolerance("move", "horizontal_speed", (speed, math.inf), margin=speed,
                        sigmoid="linear", value_at_margin=0.0),
            t.product("move_reward", ["small_control", "standing", "upright",
                                      ("move", 5.0 / 6.0, 1.0 / 6.0)]),
            t.reward("move_reward"),
        ]
    keys = [
        Key("joint_angles", [_qpos(7)]),
        Key("head_height", [_observed("head_height")], scalar=True),
        Key("extremities", [_observed(*[e["name"] for e in extremities])]),
        Key("torso_vertical", [_observed("torso_zx", "torso_zy", "torso_zz")]),
        Key("com_velocity", [_observed("com_velocity_x", "com_velocity_y", "com_velocity_z")]),
        Key("velocity", [_qvel()]),
    ]
    return Task("humanoid", task, "humanoid.xml", 5, 25.0, terms, keys,
                {**_RANDOMIZE, "reject_contacts": True},
                note="the free body turns about its torso geom's centre (MuJoCo: the body's "
                "origin; the same point)")


#: The registered tasks, by id.
TASKS: Dict[str, Task] = {
    task.id: task
    for task in [
        _acrobot("swingup", sparse=False),
        _ball_in_cup_catch(),
        _finger_spin(),
        _finger_turn("turn_easy", 0.07),
        _finger_turn("turn_hard", 0.03),
        _fish_upright(),
        _fish_swim(),
        _humanoid("stand", 0.0),
        _humanoid("walk", 1.0),
        _humanoid("run", 10.0),
        _bring_ball(),
        _acrobot("swingup_sparse", sparse=True),
        _cartpole("balance", swing_up=False, sparse=False),
        _cartpole("balance_sparse", swing_up=False, sparse=True),
        _cartpole("swingup", swing_up=True, sparse=False),
        _cartpole("swingup_sparse", swing_up=True, sparse=True),
        _cheetah_run(),
        _hopper("stand"),
        _hopper("hop"),
        _pendulum_swingup(),
        _point_mass_easy(),
        _reacher("easy", 0.05),
        _reacher("hard", 0.015),
        _swimmer(6),
        _swimmer(15),
        _walker("stand", 0.0),
        _walker("walk", 1.0),
        _walker("run", 8.0),
    ]
}


def find(domain: str, task: str) -> Task:
    """The task ``domain``-``task``, or an ``InvalidArgument`` listing the served ones."""
    from ..errors import InvalidArgument

    for spec in TASKS.values():
        if spec.domain == domain and spec.task == task:
            return spec
    served = ", ".join(f"{s.domain}-{s.task}" for s in TASKS.values())
    raise InvalidArgument(
        f"({domain!r}, {task!r}) is not one of the Control Suite tasks gymfleet serves ({served})"
    )

"""The Control Suite's tasks as gymfleet plans: for each, what dm_control's
``suite/<domain>.py`` does, in the server's terms: its observation keys (``Key``, from
qpos, qvel and observed terms), its reward (``terms.py``), its episode's start
(``reset_noise``: dm_control's ``initialize_episode``), its control timestep and time
limit. The contract tests check each against dm_control's own environment
(``client/python/tests/test_dmc.py``)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np

from . import terms as t

#: One part of an observation key: ``("qpos", start, stop)``, ``("qvel", start, stop)``
#: (``stop`` None: to the end) or ``("terms", names)`` (observed terms, in that order).
Part = Tuple[Any, ...]


@dataclass
class Key:
    """One key of dm_control's observation dict."""

    name: str
    parts: List[Part]
    #: dm_control's spec shape is ``()`` (one float).
    scalar: bool = False
    #: Applied to the key's values (hopper's touch: ``log1p``).
    transform: Optional[Callable[[np.ndarray], np.ndarray]] = None


@dataclass
class Task:
    """One of the suite's tasks: ``domain``-``task``, its XML file in dm_control's suite,
    and what the server and the wrapper do with it."""

    domain: str
    task: str
    xml: str
    #: dm_control's defaults: the physics steps per control step and the episode's length
    #: in seconds (1000 control steps in every benchmarking task).
    n_sub_steps: int
    time_limit: float
    terms: List[Dict[str, Any]]
    keys: List[Key]
    reset_noise: Dict[str, Any] = field(default_factory=dict)
    #: What differs from dm_control's task, if anything.
    note: str = ""
    #: dm_control's edits of the XML before compiling, as (old, new) text (finger: the
    #: spinner's damping).
    edits: List[Tuple[str, str]] = field(default_factory=list)
    #: What dm_control moves in its model each episode and gymfleet draws as a mocap body:
    #: (the model field, its name there, the instance here), for the contract tests.
    targets: List[Tuple[str, str, str]] = field(default_factory=list)
    #: The arguments of dm_control's ``get_model_and_assets`` when the model is made in
    #: Python (swimmer: its number of links), else ``None``: the file ``xml``.
    generated: Optional[Tuple[Any, ...]] = None

    @property
    def name(self) -> str:
        """EnvPool's name: ``CheetahRun``, ``BallInCupCatch``, ``SwimmerSwimmer6``."""
        words = (self.domain + "_" + self.task).split("_")
        return "".join(w[:1].upper() + w[1:] for w in words)

    @property
    def id(self) -> str:
        return f"gymfleet/{self.name}-v1"


def _qpos(start: int = 0, stop: Optional[int] = None) -> Part:
    return ("qpos", start, stop)


def _qvel(start: int = 0, stop: Optional[int] = None) -> Part:
    return ("qvel", start, stop)


def _observed(*names: str) -> Part:
    return ("terms", list(names))


_RANDOMIZE = {"limited": True, "rotational": True}


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


def _tip_minus_spinner(v: np.ndarray) -> np.ndarray:
    """finger's ``bounded_position``: the joints, then tip − spinner (x, z)."""
    return np.concatenate([v[:, :2], v[:, 2:4] - v[:, 4:6]], axis=1)


def _finger_spin() -> Task:
    sensors = [("proximal", None), ("distal", None), ("tip", 0), ("tip", 2), ("spinner", 0),
               ("spinner", 2)]
    position = [t.value(f"{n}_{c}" if c is not None else n, t.sensor(n, c), observe=True)
                for n, c in sensors]
    velocity = [t.value(n, t.sensor(n), observe=True)
                for n in ("proximal_velocity", "distal_velocity", "hinge_velocity")]
    touch = [t.value(n, t.sensor(n), observe=True) for n in ("touchtop", "touchbottom")]
    terms = [
        *position, *velocity, *touch,
        t.tolerance("spinning", "hinge_velocity", (-math.inf, -15.0)),
        t.reward("spinning"),
    ]
    keys = [
        Key("position", [_observed(*[p["name"] for p in position])], transform=_tip_minus_spinner),
        Key("velocity", [_observed(*[v["name"] for v in velocity])]),
        Key("touch", [_observed("touchtop", "touchbottom")], transform=np.log1p),
    ]
    return Task("finger", "spin", "finger.xml", 2, 20.0, terms, keys,
                {**_RANDOMIZE, "reject_contacts": True},
                edits=[('<joint name="hinge" frictionloss=".1" damping=".5"/>',
                        '<joint name="hinge" frictionloss=".1" damping=".03"/>')])


def _finger_turn(task: str, radius: float) -> Task:
    spin = _finger_spin()
    target = [t.value(f"target_{c}", t.sensor("target", k), observe=True)
              for c, k in (("x", 0), ("z", 2))]
    terms = [term for term in spin.terms if term.get("observe")] + target + [
        t.total("dtx", [("target_x", 1.0, 0.0), ("tip_0", -1.0, 0.0)]),
        t.total("dtz", [("target_z", 1.0, 0.0), ("tip_2", -1.0, 0.0)]),
        t.norm("tip_to_target", ["dtx", "dtz"]),
        t.tolerance("in_target", "tip_to_target", (-math.inf, radius)),
        t.reward("in_target"),
    ]

    def dist_to_target(v: np.ndarray) -> np.ndarray:
        return np.linalg.norm(v[:, :2] - v[:, 2:], axis=1, keepdims=True) - radius

    keys = spin.keys + [
        Key("target_position", [_observed("target_x", "target_z", "spinner_0", "spinner_2")],
            transform=_to_target),
        Key("dist_to_target", [_observed("target_x", "target_z", "tip_0", "tip_2")],
            scalar=True, transform=dist_to_target),
    ]
    # The goal on the circle the tip sweeps: about the hinge (the spinner's origin, .2 0 .4)
    # at cap1's size summed (.04 + .09).
    noise = {**spin.reset_noise, "mocap": [{"body": "target_body", "polar": {
        "plane": "xz", "center": [0.2, 0.0, 0.4], "radius": [0.13, 0.13],
        "angle": [-math.pi, math.pi]}}]}
    site = '<site name="target" type="sphere" size=".03" pos="0 0 .4" material="target"/>'
    moved = ('<body name="target_body" mocap="true" pos="0 0 .4"><geom name="target_mark" '
             'type="sphere" size=".001" contype="0" conaffinity="0" mass="0"/><site '
             f'name="target" type="sphere" size="{radius}" material="target"/></body>')
    return Task("finger", task, "finger.xml", 2, 20.0, terms, keys, noise,
                note="the goal is a mocap body (dm_control moves the site in the model)",
                edits=[(site, moved)], targets=[("site_pos", "target", "target_body")])


def _ball_in_cup_catch() -> Task:
    # in_target: |target − ball| < target size − ball radius (.05 − .025) in x and z.
    inside = 0.05 - 0.025
    terms = [
        t.value("target_x", t.site_xpos("target", "x")),
        t.value("target_z", t.site_xpos("target", "z")),
        t.value("ball_x", t.xpos("ball", "x")),
        t.value("ball_z", t.xpos("ball", "z")),
        t.total("dx", [("target_x", 1.0, 0.0), ("ball_x", -1.0, 0.0)]),
        t.total("dz", [("target_z", 1.0, 0.0), ("ball_z", -1.0, 0.0)]),
        t.tolerance("in_x", "dx", (-inside, inside)),
        t.tolerance("in_z", "dz", (-inside, inside)),
        t.product("in_target", ["in_x", "in_z"]),
        t.reward("in_target"),
    ]
    keys = [Key("position", [_qpos()]), Key("velocity", [_qvel()])]
    noise = {"set": [{"joints": ["ball_x", "ball_z"], "low": [-0.2, 0.2], "high": [0.2, 0.5]}],
             "reject_contacts": True}
    return Task("ball_in_cup", "catch", "ball_in_cup.xml", 10, 20.0, terms, keys, noise,
                note="in the cup is |offset| <= size − radius (dm_control: <)")


def _to_target(v: np.ndarray) -> np.ndarray:
    """The target's coordinates minus the effector's (the first half minus the second)."""
    half = v.shape[1] // 2
    return v[:, :half] - v[:, half:]


def _reacher(task: str, size: float) -> Task:
    coords = [t.value(f"{g}_{a}", {"instance": g, "axis": a}, observe=True)
              for g in ("target", "finger") for a in "xy"]
    terms = [
        *coords,
        t.total("dx", [("target_x", 1.0, 0.0), ("finger_x", -1.0, 0.0)]),
        t.total("dy", [("target_y", 1.0, 0.0), ("finger_y", -1.0, 0.0)]),
        t.norm("finger_to_target", ["dx", "dy"]),
        # The target's radius and the finger's (.01).
        t.tolerance("reached", "finger_to_target", (0.0, size + 0.01)),
        t.reward("reached"),
    ]
    keys = [
        Key("position", [_qpos()]),
        Key("to_target", [_observed(*[c["name"] for c in coords])], transform=_to_target),
        Key("velocity", [_qvel()]),
    ]
    noise = {**_RANDOMIZE, "mocap": [{"body": "target", "polar": {
        "plane": "xy", "center": [0.0, 0.0, 0.01], "radius": [0.05, 0.20],
        "angle": [0.0, 2 * math.pi]}}]}
    target = '<geom name="target" pos="0 0 .01" material="target" type="sphere" size=".05"/>'
    moved = ('<body name="target" mocap="true" pos="0 0 .01"><geom name="target" '
             f'material="target" type="sphere" size="{size}"/></body>')
    return Task("reacher", task, "reacher.xml", 1, 20.0, terms, keys, noise,
                note="the target is a mocap body (dm_control moves the geom in the model)",
                edits=[(target, moved)], targets=[("geom_pos", "target", "target")])


_FISH_JOINTS = ("tail1", "tail_twist", "tail2", "finright_roll", "finright_pitch",
                "finleft_roll", "finleft_pitch")


def _fish_upright() -> Task:
    terms = [
        t.value("upright", t.xmat("torso", "zz"), observe=True),
        t.tolerance("upright_reward", "upright", (1.0, 1.0), margin=1.0),
        t.reward("upright_reward"),
    ]
    keys = [
        Key("joint_angles", [_qpos(7)]),
        Key("upright", [_observed("upright")], scalar=True),
        Key("velocity", [_qvel()]),
    ]
    n = len(_FISH_JOINTS)
    noise = {"rotational": True, "set": [{"joints": list(_FISH_JOINTS), "low": [-0.2] * n,
                                          "high": [0.2] * n}]}
    return Task("fish", "upright", "fish.xml", 10, 40.0, terms, keys, noise,
                note="the free body turns about its first geom's centre (the mouth; MuJoCo: "
                "the torso's origin)")


def _swimmer(n: int) -> Task:
    rel = []
    for geom in ("target", "nose"):
        for a in "xy":
            rel.append(t.value(f"{geom}_{a}", {"instance": geom, "point": [0.0, 0.0, 0.0],
                                                "relative_to": "head", "axis": a},
                               observe=True))
    # body_velocities: each body's velocimeter x, y and gyro z (the head's, then the links').
    velocities = []
    for vel, gyro in [("head_vel", "head_gyro")] + [(f"velocimeter_{k}", f"gyro_{k}")
                                                   for k in range(n - 1)]:
        velocities += [t.value(f"{vel}_x", t.sensor(vel, 0), observe=True),
                       t.value(f"{vel}_y", t.sensor(vel, 1), observe=True),
                       t.value(f"{gyro}_z", t.sensor(gyro, 2), observe=True)]
    terms = [
        *rel, *velocities,
        t.total("dx", [("target_x", 1.0, 0.0), ("nose_x", -1.0, 0.0)]),
        t.total("dy", [("target_y", 1.0, 0.0), ("nose_y", -1.0, 0.0)]),
        t.norm("nose_to_target", ["dx", "dy"]),
        # The target's radius (.1).
        t.tolerance("near", "nose_to_target", (0.0, 0.1), margin=0.5, sigmoid="long_tail"),
        t.reward("near"),
    ]
    keys = [
        Key("joints", [_qpos(3)]),
        Key("to_target", [_observed(*[r["name"] for r in rel])], transform=_to_target),
        Key("body_velocities", [_observed(*[v["name"] for v in velocities])]),
    ]
    noise = {**_RANDOMIZE, "mocap": [{"body": "target", "boxes": [
        {"weight": 0.2, "low": [-0.3, -0.3, 0.05], "high": [0.3, 0.3, 0.05]},
        {"weight": 0.8, "low": [-2.0, -2.0, 0.05], "high": [2.0, 2.0, 0.05]}]}]}
    target = '<geom name="target" type="sphere" pos="1 1 .05" size=".1" material="target"/>'
    moved = ('<body name="target" mocap="true" pos="1 1 .05"><geom name="target" '
             'type="sphere" size=".1" material="target"/></body>')
    return Task("swimmer", f"swimmer{n}", "swimmer.xml", 15, 30.0, terms, keys, noise,
                note="the target is a mocap body (dm_control moves the geom in the model)",
                edits=[(target, moved)], targets=[("geom_pos", "target", "target")],
                generated=(n,))


def _fish_swim() -> Task:
    upright = _fish_upright()
    target = [t.value(f"mouth_to_target_{a}", {"instance": "target", "point": [0.0, 0.0, 0.0],
                                                "relative_to": "mouth_frame", "axis": a},
                      observe=True) for a in "xyz"]
    radii = 0.005 + 0.04  # the mouth's and the target's radii
    terms = [
        upright.terms[0], *target,
        t.norm("mouth_to_target", [x["name"] for x in target]),
        t.tolerance("in_target", "mouth_to_target", (0.0, radii), margin=2 * radii),
        t.total("swim_reward", [("in_target", 7.0 / 8.0, 0.0), ("upright", 1.0 / 16.0, 1.0 / 16.0)]),
        t.reward("swim_reward"),
    ]
    keys = [upright.keys[0], upright.keys[1],
            Key("target", [_observed(*[x["name"] for x in target])]), upright.keys[2]]
    noise = {**upright.reset_noise, "mocap": [{"body": "target", "boxes": [
        {"low": [-0.4, -0.4, 0.1], "high": [0.4, 0.4, 0.3]}]}]}
    # The mouth geom's frame as a site (MuJoCo's geom_xmat['mouth']), and the target a
    # mocap body.
    mouth = '<geom name="mouth" type="capsule" fromto="0 .079 0 0 .07 0" size=".005" material="effector" mass="0"/>'
    target_geom = '<geom name="target" type="sphere" pos="0 .4 .1" size=".04" material="target"/>'
    moved = ('<body name="target" mocap="true" pos="0 .4 .1"><geom name="target" '
             'type="sphere" size=".04" material="target"/></body>')
    return Task("fish", "swim", "fish.xml", 10, 40.0, terms, keys, noise,
                note=upright.note + "; the target is a mocap body",
                # The mocap body after the fish (the first body is the free one).
                edits=[(mouth, mouth + '<site name="mouth_frame" fromto="0 .079 0 0 .07 0"/>'),
                       (target_geom, ""), ("</worldbody>", moved + "</worldbody>")],
                targets=[("geom_pos", "target", "target")])


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

"""The tasks with goals and contact-free starts: finger, ball_in_cup, reacher, fish and
swimmer (what dm_control's ``suite/<domain>.py`` does, in the server's terms). A target
dm_control moves in its model each episode is a mocap body here, drawn as it draws it."""

from __future__ import annotations

import math

import numpy as np

from . import terms as t
from .spec import _RANDOMIZE, Key, Task, _observed, _qpos, _qvel, _to_target


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

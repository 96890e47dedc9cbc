"""Gymnasium's MuJoCo v5 environments as gymfleet plans: for each, from the model and
the env's keyword arguments (their defaults are in ``specs.py``), what they make: the server's terms task (reward terms,
healthy conditions, reset noise), the observation taken from the server's SI joint state,
and the ``info`` scalars Gymnasium's env reports. Each plan mirrors the corresponding
``gymnasium/envs/mujoco/<name>_v5.py``; the contract tests check it against that file's
env (``client/python/tests/test_suite.py``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, List, Mapping, Optional, Tuple

import numpy as np

from ..errors import InvalidArgument
from .model import Model

#: Arrays per env: positions (n, dof), and the terms task's values by name (n,) each.
Positions = np.ndarray
Terms = Mapping[str, np.ndarray]
#: The key under which a plan's ``observe`` finds the observed terms' values, (n, k), in the
#: order the task lists its ``observe`` terms: the rows' ``terms`` segment as it is.
OBSERVED = "observed terms"


@dataclass
class Plan:
    """One env's configuration on the server, and how its observation and info are
    made from what the server returns."""

    #: The terms task (``gymfleet.make(..., task=...)``).
    task: Dict[str, Any]
    #: The observation from the positions and velocities (n, dof) each, the end
    #: effectors' positions (n, len(end_effectors), 3), in SI, and the term values (zeros
    #: at a reset).
    observe: Callable[[np.ndarray, np.ndarray, np.ndarray, Terms], np.ndarray]
    #: The observation's length.
    observation_dim: int
    #: The step's info from the positions and the term values.
    step_info: Callable[[Positions, Terms], Dict[str, np.ndarray]]
    #: The reset's info from the positions.
    reset_info: Callable[[Positions], Dict[str, np.ndarray]] = field(
        default=lambda q: {}
    )
    #: Sites (or instances) observed as end effectors: MuJoCo's body positions (xpos)
    #: that the observation holds.
    end_effectors: List[str] = field(default_factory=list)
    #: Fixed tendons reported in ``info["tendon_length"]``/``["tendon_velocity"]`` (at
    #: resets and steps): each as (qpos index, qvel index, coef) per joint.
    tendons: List[List[Tuple[int, int, float]]] = field(default_factory=list)
    #: The step's reward from its info values (float64), with Gymnasium's operations in
    #: Gymnasium's order, so that it equals the sum Gymnasium's tests take of the same
    #: info terms exactly. ``None``: the server's reward (widened).
    reward: Optional[Callable[[Mapping[str, np.ndarray]], np.ndarray]] = None
    #: Info velocities Gymnasium takes as ``Δqpos[k] / dt`` (key: qpos index), which a
    #: single env recomputes from its qpos as Gymnasium does, and the weight of the forward
    #: reward made from ``x_velocity``.
    qpos_velocity: Dict[str, int] = field(default_factory=dict)
    forward_weight: float = 0.0

    def tendon_info(self, q: np.ndarray, v: np.ndarray) -> Dict[str, np.ndarray]:
        """MuJoCo's ``ten_length`` and ``ten_velocity`` (n, tendons) from qpos and qvel."""
        if not self.tendons:
            return {}
        length = np.stack([sum(c * q[:, i] for i, _, c in t) for t in self.tendons], axis=1)
        rate = np.stack([sum(c * v[:, j] for _, j, c in t) for t in self.tendons], axis=1)
        return {"tendon_length": length.astype(np.float64), "tendon_velocity": rate.astype(np.float64)}


def _joint_state(
    skip: int, clip: Optional[float]
) -> Callable[[np.ndarray, np.ndarray, np.ndarray, Terms], np.ndarray]:
    """Gymnasium's ``concatenate(qpos[skip:], qvel)``, the velocities clipped to ±clip."""

    def observe(q: np.ndarray, v: np.ndarray, ee: np.ndarray, t: Terms) -> np.ndarray:
        if clip is not None:
            v = np.clip(v, -clip, clip)
        return np.concatenate([q[:, skip:], v], axis=1)

    return observe


# Gymnasium's rewards from the info terms, in the order its envs compute them (`_get_rew`):
# a cost is the negated info term (negation is exact).


def _forward_survive_ctrl(i: Mapping[str, np.ndarray]) -> np.ndarray:
    """Hopper, Walker2d: ``(forward + healthy) - ctrl_cost``."""
    return (i["reward_forward"] + i["reward_survive"]) - (-i["reward_ctrl"])


def _forward_ctrl(i: Mapping[str, np.ndarray]) -> np.ndarray:
    """HalfCheetah, Swimmer: ``forward - ctrl_cost``."""
    return i["reward_forward"] - (-i["reward_ctrl"])


def forward_survive_costs(i: Mapping[str, np.ndarray]) -> np.ndarray:
    """Ant, Humanoid: ``(forward + healthy) - (ctrl_cost + contact_cost)``."""
    return (i["reward_forward"] + i["reward_survive"]) - (
        (-i["reward_ctrl"]) + (-i["reward_contact"])
    )


def norm_xy(q: np.ndarray, ix: int, iy: int) -> np.ndarray:
    """Gymnasium's ``distance_from_origin``, ``np.linalg.norm(qpos[x, y], ord=2)``, per row:
    one row exactly as Gymnasium computes it (its ``dot``), a batch as ``sqrt(x² + y²)``."""
    if len(q) == 1:
        return np.array([np.linalg.norm(q[0, [ix, iy]], ord=2)])
    return np.sqrt(q[:, ix] * q[:, ix] + q[:, iy] * q[:, iy])


def _noise(kind_position: str, kind_velocity: str, scale: float) -> Dict[str, Any]:
    return {"position": {kind_position: scale}, "velocity": {kind_velocity: scale}}


def _exclude(kwargs: Mapping[str, Any]) -> bool:
    return bool(kwargs["exclude_current_positions_from_observation"])


def _range(pair: Any, name: str) -> Tuple[Optional[float], Optional[float]]:
    try:
        lo, hi = (float(v) for v in pair)
    except (TypeError, ValueError):
        raise InvalidArgument(f"{name}: expected (min, max), got {pair!r}") from None
    return (None if math.isinf(lo) else lo), (None if math.isinf(hi) else hi)


def _bound(of: Dict[str, Any], pair: Any, name: str) -> Dict[str, Any]:
    lo, hi = _range(pair, name)
    out: Dict[str, Any] = {"of": of}
    if lo is not None:
        out["min"] = lo
    if hi is not None:
        out["max"] = hi
    return out


def _walker(model: Model, kw: Mapping[str, Any], with_state_range: bool) -> Plan:
    """Hopper and Walker2d: forward reward from rootx, healthy z (rootz) and angle
    (rooty), Hopper's state range; velocities clipped to ±10."""
    x, z, angle = model.joints[0], model.joints[1], model.joints[2]
    healthy: Dict[str, Any] = {
        "ranges": [
            _bound({"joint": z}, kw["healthy_z_range"], "healthy_z_range"),
            _bound({"joint": angle}, kw["healthy_angle_range"], "healthy_angle_range"),
        ],
        "terminate": bool(kw["terminate_when_unhealthy"]),
    }
    if with_state_range:
        lo, hi = _range(kw["healthy_state_range"], "healthy_state_range")
        healthy["state_range"] = {
            "min": -1e9 if lo is None else lo,
            "max": 1e9 if hi is None else hi,
            "skip_positions": 2,
        }
    fw, cw, hw = (
        float(kw["forward_reward_weight"]),
        float(kw["ctrl_cost_weight"]),
        float(kw["healthy_reward"]),
    )
    task = {
        "terms": [
            {"name": "x_velocity", "weight": fw, "velocity": {"joint": x}},
            {"name": "ctrl_cost", "weight": -cw, "ctrl_cost": {}},
            {"name": "healthy", "weight": hw, "healthy": {}},
        ],
        "healthy": healthy,
        "reset_noise": _noise("uniform", "uniform", float(kw["reset_noise_scale"])),
    }
    ix, iz = model.index(x), model.index(z)
    skip = 1 if _exclude(kw) else 0
    # MuJoCo's init_qpos is each joint's ref: what the server reports at the pose.
    z0 = model.refs[iz]

    def reset_info(q: Positions) -> Dict[str, np.ndarray]:
        return {"x_position": q[:, ix], "z_distance_from_origin": q[:, iz] - z0}

    def step_info(q: Positions, t: Terms) -> Dict[str, np.ndarray]:
        return {
            **reset_info(q),
            "x_velocity": t["x_velocity"],
            "reward_forward": fw * t["x_velocity"],
            "reward_ctrl": -cw * t["ctrl_cost"],
            "reward_survive": hw * t["healthy"],
        }

    n = len(model.joints)
    return Plan(task, _joint_state(skip, 10.0), 2 * n - skip, step_info, reset_info,
                reward=_forward_survive_ctrl, qpos_velocity={"x_velocity": ix},
                forward_weight=fw)


def _hopper(model: Model, kw: Mapping[str, Any]) -> Plan:
    return _walker(model, kw, with_state_range=True)


def _walker2d(model: Model, kw: Mapping[str, Any]) -> Plan:
    return _walker(model, kw, with_state_range=False)


def _half_cheetah(model: Model, kw: Mapping[str, Any]) -> Plan:
    x = model.joints[0]
    fw, cw = float(kw["forward_reward_weight"]), float(kw["ctrl_cost_weight"])
    task = {
        "terms": [
            {"name": "x_velocity", "weight": fw, "velocity": {"joint": x}},
            {"name": "ctrl_cost", "weight": -cw, "ctrl_cost": {}},
        ],
        "reset_noise": _noise("uniform", "normal", float(kw["reset_noise_scale"])),
    }
    ix = model.index(x)
    skip = 1 if _exclude(kw) else 0

    def reset_info(q: Positions) -> Dict[str, np.ndarray]:
        return {"x_position": q[:, ix]}

    def step_info(q: Positions, t: Terms) -> Dict[str, np.ndarray]:
        return {
            "x_position": q[:, ix],
            "x_velocity": t["x_velocity"],
            "reward_forward": fw * t["x_velocity"],
            "reward_ctrl": -cw * t["ctrl_cost"],
        }

    n = len(model.joints)
    return Plan(task, _joint_state(skip, None), 2 * n - skip, step_info, reset_info,
                reward=_forward_ctrl, qpos_velocity={"x_velocity": ix}, forward_weight=fw)


def _xy_infos(
    ix: int, iy: int, fw: float, cw: float
) -> Tuple[Callable[[Positions], Dict[str, np.ndarray]], Callable[[Positions, Terms], Dict[str, np.ndarray]]]:
    """The reset and step infos of a robot moving in the plane (Swimmer, Ant): its x and y
    (positions ``ix``, ``iy``), their rates, and the forward and control rewards."""

    def reset_info(q: Positions) -> Dict[str, np.ndarray]:
        return {
            "x_position": q[:, ix],
            "y_position": q[:, iy],
            "distance_from_origin": norm_xy(q, ix, iy),
        }

    def step_info(q: Positions, t: Terms) -> Dict[str, np.ndarray]:
        return {
            **reset_info(q),
            "x_velocity": t["x_velocity"],
            "y_velocity": t["y_velocity"],
            "reward_forward": fw * t["x_velocity"],
            "reward_ctrl": -cw * t["ctrl_cost"],
        }

    return reset_info, step_info


def _swimmer(model: Model, kw: Mapping[str, Any]) -> Plan:
    x, y = model.joints[0], model.joints[1]
    fw, cw = float(kw["forward_reward_weight"]), float(kw["ctrl_cost_weight"])
    task = {
        "terms": [
            {"name": "x_velocity", "weight": fw, "velocity": {"joint": x}},
            {"name": "y_velocity", "weight": 0.0, "velocity": {"joint": y}},
            {"name": "ctrl_cost", "weight": -cw, "ctrl_cost": {}},
        ],
        "reset_noise": _noise("uniform", "uniform", float(kw["reset_noise_scale"])),
    }
    skip = 2 if _exclude(kw) else 0
    reset_info, step_info = _xy_infos(model.index(x), model.index(y), fw, cw)

    n = len(model.joints)
    return Plan(task, _joint_state(skip, None), 2 * n - skip, step_info, reset_info,
                reward=_forward_ctrl,
                qpos_velocity={"x_velocity": model.index(x), "y_velocity": model.index(y)},
                forward_weight=fw)


def _inverted_pendulum(model: Model, kw: Mapping[str, Any]) -> Plan:
    hinge = model.joints[1]
    task = {
        "terms": [{"name": "alive", "weight": 1.0, "healthy": {}}],
        # Gymnasium ends the episode once |qpos[1]| > 0.2 (or the state is not finite).
        "healthy": {"ranges": [{"of": {"joint": hinge}, "min": -0.2, "max": 0.2}]},
        "reset_noise": _noise("uniform", "uniform", float(kw["reset_noise_scale"])),
    }

    def step_info(q: Positions, t: Terms) -> Dict[str, np.ndarray]:
        return {"reward_survive": t["alive"]}

    n = len(model.joints)
    return Plan(task, _joint_state(0, None), 2 * n, step_info,
                reward=lambda i: i["reward_survive"])


def _inverted_double_pendulum(model: Model, kw: Mapping[str, Any]) -> Plan:
    """The tip held high: penalties on its offset from (0, 2) m and on the hinges'
    speeds, a survival bonus while it is above 1 m; the cart's limit force observed."""
    cart, hinge, hinge2 = model.joints[:3]
    tip = {"site": "tip"}
    task = {
        "terms": [
            {"name": "alive", "weight": float(kw["healthy_reward"]), "healthy": {}},
            {"name": "tip_x2", "weight": -0.01, "square": {"of": {**tip, "axis": "x"}}},
            {"name": "tip_dz2", "weight": -1.0,
             "square": {"of": {**tip, "axis": "z"}, "center": 2.0}},
            {"name": "v1_2", "weight": -1e-3, "square": {"of": {"joint_velocity": hinge}}},
            {"name": "v2_2", "weight": -5e-3, "square": {"of": {"joint_velocity": hinge2}}},
            # MuJoCo's qfrc_constraint[0]: the slider's stops.
            {"name": "cart_limit", "weight": 0.0, "value": {"joint_limit_force": cart}},
        ],
        # Gymnasium ends the episode once the tip is at or below 1 m.
        "healthy": {"ranges": [{"of": {**tip, "axis": "z"}, "min": 1.0}]},
        "reset_noise": _noise("uniform", "normal", float(kw["reset_noise_scale"])),
    }
    hw = float(kw["healthy_reward"])

    def observe(q: np.ndarray, v: np.ndarray, ee: np.ndarray, t: Terms) -> np.ndarray:
        return np.concatenate(
            [
                q[:, :1],
                np.sin(q[:, 1:]),
                np.cos(q[:, 1:]),
                np.clip(v, -10.0, 10.0),
                np.clip(np.asarray(t["cart_limit"], dtype=q.dtype), -10.0, 10.0)[:, None],
            ],
            axis=1,
        )

    def step_info(q: Positions, t: Terms) -> Dict[str, np.ndarray]:
        return {
            "reward_survive": hw * t["alive"],
            "distance_penalty": -(0.01 * t["tip_x2"] + t["tip_dz2"]),
            "velocity_penalty": -(1e-3 * t["v1_2"] + 5e-3 * t["v2_2"]),
        }

    def reward(i: Mapping[str, np.ndarray]) -> np.ndarray:
        # alive_bonus - dist_penalty - vel_penalty
        return (i["reward_survive"] - (-i["distance_penalty"])) - (-i["velocity_penalty"])

    n = len(model.joints)
    return Plan(task, observe, 3 * n, step_info, reward=reward)


#: A wrench's components, MuJoCo's cfrc_ext order: torque x, y, z, then force x, y, z.
_WRENCH = 6


def _ant(model: Model, kw: Mapping[str, Any]) -> Plan:
    """A quadruped on a free joint: forward reward from the main body's displacement, a
    healthy torso height, control and contact costs; the observation is MuJoCo's qpos
    (x, y left out), qvel and each body's clipped contact wrench (cfrc_ext)."""
    if model.free is None:
        raise InvalidArgument(f"xml_file: {model.path} has no free joint; Ant needs one")
    unnamed = [name or f"body {k + 1}" for k, (name, geoms) in enumerate(model.bodies) if "" in geoms]
    if unnamed:
        raise InvalidArgument(
            f"xml_file: every geom needs a name (its body's contact forces are read from "
            f"it); {', '.join(unnamed)} has an unnamed geom"
        )
    main = kw["main_body"]
    names = [name for name, _ in model.bodies]
    if isinstance(main, (int, np.integer)) and not isinstance(main, bool):
        if not 1 <= main <= len(names):
            raise InvalidArgument(f"main_body: expected a body index 1 to {len(names)}, got {main}")
        main_name = names[main - 1]
    elif isinstance(main, str) and main in names:
        main_name = main
    else:
        raise InvalidArgument(f"main_body: expected a body name or index, got {main!r}")
    if not main_name:
        raise InvalidArgument("main_body: the body has no name (its position is read as a site)")
    root = names[0]
    fw, cw, ccw, hw = (
        float(kw["forward_reward_weight"]),
        float(kw["ctrl_cost_weight"]),
        float(kw["contact_cost_weight"]),
        float(kw["healthy_reward"]),
    )
    lo, hi = _range(kw["contact_force_range"], "contact_force_range")
    lo = -1e9 if lo is None else lo
    hi = 1e9 if hi is None else hi
    groups = [geoms for _, geoms in model.bodies]
    with_cfrc = bool(kw["include_cfrc_ext_in_observation"])
    cfrc = [f"cfrc_ext_{b}_{k}" for b in range(len(groups)) for k in range(_WRENCH)]
    terms: List[Dict[str, Any]] = [
        {"name": "x_velocity", "weight": fw, "velocity": {"site": main_name, "axis": "x"}},
        {"name": "y_velocity", "weight": 0.0, "velocity": {"site": main_name, "axis": "y"}},
        {"name": "healthy", "weight": hw, "healthy": {}},
        {"name": "ctrl_cost", "weight": -cw, "ctrl_cost": {}},
        {"name": "contact_cost", "weight": -ccw,
         "contact_cost": {"groups": groups, "min": lo, "max": hi}},
    ]
    if with_cfrc:
        terms += [
            {"name": name, "weight": 0.0,
             "value": {"contact_wrench": groups[b], "component": k}, "observe": True}
            for name, (b, k) in zip(cfrc, ((b, k) for b in range(len(groups)) for k in range(_WRENCH)))
        ]
    task = {
        "terms": terms,
        "healthy": {
            "ranges": [_bound({"site": root, "axis": "z"}, kw["healthy_z_range"], "healthy_z_range")],
            "terminate": bool(kw["terminate_when_unhealthy"]),
        },
        "reset_noise": {**_noise("uniform", "normal", float(kw["reset_noise_scale"])), "base": True},
    }
    skip = 2 if _exclude(kw) else 0

    def observe(q: np.ndarray, v: np.ndarray, ee: np.ndarray, t: Terms) -> np.ndarray:
        parts = [q[:, skip:], v]
        if with_cfrc:
            # The 78 wrench terms are the task's observed terms: one block, in their order.
            parts.append(np.clip(np.asarray(t[OBSERVED], dtype=q.dtype), lo, hi))
        return np.concatenate(parts, axis=1)

    # MuJoCo's qpos starts with the free joint's x and y.
    reset_info, planar_step_info = _xy_infos(0, 1, fw, cw)

    def step_info(q: Positions, t: Terms) -> Dict[str, np.ndarray]:
        return {
            **planar_step_info(q, t),
            "reward_contact": -ccw * t["contact_cost"],
            "reward_survive": hw * t["healthy"],
        }

    dim = 7 + 6 + 2 * len(model.joints) - skip + (len(cfrc) if with_cfrc else 0)
    # Gymnasium's velocities are the main body's xpos difference: qpos[0:2] for the root.
    velocity = {"x_velocity": 0, "y_velocity": 1} if main_name == root else {}
    return Plan(task, observe, dim, step_info, reset_info, reward=forward_survive_costs,
                qpos_velocity=velocity, forward_weight=fw)


def _reacher(model: Model, kw: Mapping[str, Any]) -> Plan:
    """The fingertip to a goal drawn in a disk of 0.2 m; bodies' positions as sites."""
    wd, wc = float(kw["reward_dist_weight"]), float(kw["reward_control_weight"])
    goal = model.joints[2:4]
    task = {
        "terms": [
            {"name": "distance", "weight": -wd,
             "distance": [{"site": "fingertip"}, {"site": "target"}]},
            {"name": "ctrl_cost", "weight": -wc, "ctrl_cost": {}},
        ],
        "reset_noise": {
            "position": {"uniform": 0.1},
            "velocity": {"uniform": 0.005},
            # Gymnasium draws the goal until its norm is under 0.2; it starts at rest.
            "set": [{"joints": goal, "low": [-0.2, -0.2], "high": [0.2, 0.2], "max_norm": 0.2}],
        },
    }

    def observe(q: np.ndarray, v: np.ndarray, ee: np.ndarray, t: Terms) -> np.ndarray:
        theta = q[:, :2]
        return np.concatenate(
            [np.cos(theta), np.sin(theta), q[:, 2:], v[:, :2], (ee[:, 0] - ee[:, 1])[:, :2]],
            axis=1,
        )

    def step_info(q: Positions, t: Terms) -> Dict[str, np.ndarray]:
        return {"reward_dist": -wd * t["distance"], "reward_ctrl": -wc * t["ctrl_cost"]}

    return Plan(task, observe, 10, step_info, end_effectors=["fingertip", "target"],
                reward=lambda i: i["reward_dist"] + i["reward_ctrl"])


def _pusher(model: Model, kw: Mapping[str, Any]) -> Plan:
    """The arm's tip pushes the object to the goal; the object is placed away from it."""
    wn, wd, wc = (
        float(kw["reward_near_weight"]),
        float(kw["reward_dist_weight"]),
        float(kw["reward_control_weight"]),
    )
    obj, goal = model.joints[-4:-2], model.joints[-2:]
    task = {
        "terms": [
            {"name": "near", "weight": -wn,
             "distance": [{"site": "object"}, {"site": "tips_arm"}]},
            {"name": "distance", "weight": -wd,
             "distance": [{"site": "object"}, {"site": "goal"}]},
            {"name": "ctrl_cost", "weight": -wc, "ctrl_cost": {}},
        ],
        "reset_noise": {
            "velocity": {"uniform": 0.005},
            "set": [
                # Gymnasium draws the object until it is more than 0.17 from the goal.
                {"joints": obj, "low": [-0.3, -0.2], "high": [0.0, 0.2], "min_norm": 0.17},
                {"joints": goal, "low": [0.0, 0.0], "high": [0.0, 0.0]},
            ],
        },
    }

    def observe(q: np.ndarray, v: np.ndarray, ee: np.ndarray, t: Terms) -> np.ndarray:
        return np.concatenate([q[:, :7], v[:, :7], ee.reshape(len(ee), -1)], axis=1)

    def step_info(q: Positions, t: Terms) -> Dict[str, np.ndarray]:
        return {
            "reward_dist": -wd * t["distance"],
            "reward_ctrl": -wc * t["ctrl_cost"],
            "reward_near": -wn * t["near"],
        }

    return Plan(task, observe, 23, step_info, end_effectors=["tips_arm", "object", "goal"],
                reward=lambda i: (i["reward_dist"] + i["reward_ctrl"]) + i["reward_near"])

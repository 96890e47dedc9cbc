"""Humanoid and HumanoidStandup (``humanoid_v5.py``, ``humanoidstandup_v5.py``): a free
joint, 17 motors, two fixed tendons, and an observation of MuJoCo's body-level quantities
besides qpos and qvel: ``cinert``, ``cvel``, ``qfrc_actuator`` and ``cfrc_ext`` of every
body but the world. The server computes each as a weight-0 term (``body_inertia``,
``body_velocity``, ``actuator_force``, ``contact_wrench``: each body is the instances its
geoms became); here they are only put in MuJoCo's order.
"""

from __future__ import annotations

from typing import Any, Dict, List, Mapping, Tuple

import numpy as np

from ..errors import InvalidArgument
from .model import Model
from .plans import (
    OBSERVED,
    Plan,
    Positions,
    Terms,
    _WRENCH,
    _bound,
    _exclude,
    _noise,
    _range,
    forward_survive_costs,
    norm_xy,
)

#: Floats per body in cinert (inertia xx yy zz xy xz yz, mass × offset, mass) and cvel.
_CINERT = 10
_CVEL = 6


def _groups(model: Model, env: str) -> List[List[str]]:
    """Each body's geoms (the instances the conversion makes of it)."""
    unnamed = [name or f"body {k + 1}" for k, (name, geoms) in enumerate(model.bodies) if "" in geoms]
    if unnamed:
        raise InvalidArgument(
            f"xml_file: every geom needs a name ({env} reads each body's quantities from its "
            f"geoms); {', '.join(unnamed)} has an unnamed geom"
        )
    if model.free is None:
        raise InvalidArgument(f"xml_file: {model.path} has no free joint; {env} needs one")
    return [geoms for _, geoms in model.bodies]


def _body_terms(model: Model, kw: Mapping[str, Any], env: str) -> Tuple[List[Dict[str, Any]], List[Tuple[str, List[str]]]]:
    """The weight-0 terms of the observation's body-level parts (those ``include_*``
    asks for), and the names of each part's terms in order."""
    groups = _groups(model, env)
    parts: List[Tuple[str, List[str]]] = []
    terms: List[Dict[str, Any]] = []

    def add(part: str, names: List[str], values: List[Dict[str, Any]]) -> None:
        parts.append((part, names))
        terms.extend({"name": n, "weight": 0.0, "value": v, "observe": True} for n, v in zip(names, values))

    body_parts = [
        ("cinert", "include_cinert_in_observation", "body_inertia", _CINERT),
        ("cvel", "include_cvel_in_observation", "body_velocity", _CVEL),
    ]
    for part, flag, quantity, size in body_parts:
        if kw[flag]:
            add(
                part,
                [f"{part}_{b}_{k}" for b in range(len(groups)) for k in range(size)],
                [{quantity: groups[b], "component": k} for b in range(len(groups)) for k in range(size)],
            )
    if kw["include_qfrc_actuator_in_observation"]:
        add("qfrc_actuator", [f"qfrc_actuator_{j}" for j in model.joints],
            [{"actuator_force": j} for j in model.joints])
    if kw["include_cfrc_ext_in_observation"]:
        add(
            "cfrc_ext",
            [f"cfrc_ext_{b}_{k}" for b in range(len(groups)) for k in range(_WRENCH)],
            [{"contact_wrench": groups[b], "component": k} for b in range(len(groups)) for k in range(_WRENCH)],
        )
    return terms, parts


def _observe(model: Model, kw: Mapping[str, Any], parts: List[Tuple[str, List[str]]]):
    skip = 2 if _exclude(kw) else 0

    def observe(q: np.ndarray, v: np.ndarray, ee: np.ndarray, t: Terms) -> np.ndarray:
        out = [q[:, skip:], v]
        if parts:
            # The parts' terms are the task's observed terms, in the parts' order.
            out.append(np.asarray(t[OBSERVED], dtype=q.dtype))
        return np.concatenate(out, axis=1)

    # qpos (the free joint's 7, x and y left out) and qvel (its 6), then the body parts.
    dim = 7 + 6 + 2 * len(model.joints) - skip + sum(len(n) for _, n in parts)
    return observe, dim


def _tendons(model: Model) -> List[List[Tuple[int, int, float]]]:
    """The tendons' joints as qpos and qvel indices (after the free joint's 7 and 6)."""
    return [[(7 + model.index(j), 6 + model.index(j), c) for j, c in pairs] for _, pairs in model.tendons]


def _positive_lower_bound(pair: Any, name: str) -> float:
    lo, hi = _range(pair, name)
    if lo is not None and lo > 0:
        raise InvalidArgument(f"{name}: a positive lower bound ({lo}) is not supported")
    return np.inf if hi is None else hi


def _contact_cost(groups: List[List[str]], weight: float, upper: float) -> Dict[str, Any]:
    """Σ cfrc_ext², its weighted value clipped at ``upper`` (Gymnasium clips the cost)."""
    cost: Dict[str, Any] = {"groups": groups, "min": -1e9, "max": 1e9}
    if weight > 0 and np.isfinite(upper):
        cost["sum_max"] = upper / weight
    return cost


def _humanoid(model: Model, kw: Mapping[str, Any]) -> Plan:
    """Walk forward: the whole body's centre of mass's x velocity, a healthy torso
    height, control and (clipped) contact costs."""
    fw, cw, ccw, hw = (
        float(kw["forward_reward_weight"]),
        float(kw["ctrl_cost_weight"]),
        float(kw["contact_cost_weight"]),
        float(kw["healthy_reward"]),
    )
    upper = _positive_lower_bound(kw["contact_cost_range"], "contact_cost_range")
    groups = _groups(model, "Humanoid")
    body_terms, parts = _body_terms(model, kw, "Humanoid")
    root = model.bodies[0][0]
    terms: List[Dict[str, Any]] = [
        {"name": "x_velocity", "weight": fw, "velocity": {"center_of_mass": True, "axis": "x"}},
        {"name": "y_velocity", "weight": 0.0, "velocity": {"center_of_mass": True, "axis": "y"}},
        {"name": "healthy", "weight": hw, "healthy": {}},
        {"name": "ctrl_cost", "weight": -cw, "ctrl_cost": {}},
        {"name": "contact_cost", "weight": -ccw, "contact_cost": _contact_cost(groups, ccw, upper)},
        *body_terms,
    ]
    task = {
        "terms": terms,
        "healthy": {
            "ranges": [_bound({"site": root, "axis": "z"}, kw["healthy_z_range"], "healthy_z_range")],
            "terminate": bool(kw["terminate_when_unhealthy"]),
        },
        "reset_noise": {**_noise("uniform", "uniform", float(kw["reset_noise_scale"])), "base": True},
    }
    observe, dim = _observe(model, kw, parts)

    def reset_info(q: Positions) -> Dict[str, np.ndarray]:
        return {"x_position": q[:, 0], "y_position": q[:, 1], "distance_from_origin": norm_xy(q, 0, 1)}

    def step_info(q: Positions, t: Terms) -> Dict[str, np.ndarray]:
        return {
            **reset_info(q),
            "x_velocity": t["x_velocity"],
            "y_velocity": t["y_velocity"],
            "reward_survive": hw * t["healthy"],
            "reward_forward": fw * t["x_velocity"],
            "reward_ctrl": -cw * t["ctrl_cost"],
            "reward_contact": -ccw * t["contact_cost"],
        }

    return Plan(task, observe, dim, step_info, reset_info, tendons=_tendons(model),
                reward=forward_survive_costs)


def _humanoid_standup(model: Model, kw: Mapping[str, Any]) -> Plan:
    """Stand up from lying down: the torso's height over MuJoCo's timestep (not dt, as
    Gymnasium has it), control and (clipped) impact costs, and 1 per step; never ends."""
    uw, cw, iw = float(kw["uph_cost_weight"]), float(kw["ctrl_cost_weight"]), float(kw["impact_cost_weight"])
    upper = _positive_lower_bound(kw["impact_cost_range"], "impact_cost_range")
    groups = _groups(model, "HumanoidStandup")
    body_terms, parts = _body_terms(model, kw, "HumanoidStandup")
    root = model.bodies[0][0]
    terms: List[Dict[str, Any]] = [
        {"name": "height", "weight": uw / model.timestep, "value": {"site": root, "axis": "z"}},
        {"name": "alive", "weight": 1.0, "healthy": {}},
        {"name": "ctrl_cost", "weight": -cw, "ctrl_cost": {}},
        {"name": "impact_cost", "weight": -iw, "contact_cost": _contact_cost(groups, iw, upper)},
        *body_terms,
    ]
    task = {
        "terms": terms,
        "healthy": {"ranges": [], "terminate": False},
        "reset_noise": {**_noise("uniform", "uniform", float(kw["reset_noise_scale"])), "base": True},
    }
    observe, dim = _observe(model, kw, parts)
    start_z = model.root_z

    def reset_info(q: Positions) -> Dict[str, np.ndarray]:
        return {"x_position": q[:, 0], "y_position": q[:, 1], "z_distance_from_origin": q[:, 2] - start_z}

    def step_info(q: Positions, t: Terms) -> Dict[str, np.ndarray]:
        return {
            **reset_info(q),
            "reward_linup": uw / model.timestep * t["height"],
            "reward_quadctrl": -cw * t["ctrl_cost"],
            "reward_impact": -iw * t["impact_cost"],
        }

    def reward(i: Mapping[str, np.ndarray]) -> np.ndarray:
        # uph_cost - quad_ctrl_cost - quad_impact_cost + 1
        return ((i["reward_linup"] - (-i["reward_quadctrl"])) - (-i["reward_impact"])) + 1

    return Plan(task, observe, dim, step_info, reset_info, tendons=_tendons(model),
                reward=reward)

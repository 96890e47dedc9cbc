"""Builders of the server's terms task for the Control Suite's tasks: the quantities
dm_control's ``Physics`` methods read (an upright is ``xmat[zz]``, a height ``xpos[z]``),
dm_control's ``rewards.tolerance`` of a term, and sums and products of terms. Every
builder returns one term of the task's ``terms`` list (the server's JSON); a task's
reward is the term named ``reward`` (weight 1), every other term is reported only."""

from __future__ import annotations

import math
from typing import Any, Dict, List, Optional, Sequence, Tuple

Term = Dict[str, Any]
Quantity = Dict[str, Any]


def value(name: str, quantity: Quantity, observe: bool = False) -> Term:
    """A quantity's value after each step (observed: read at resets too, and part of the
    server's observation row, in term order)."""
    return {"name": name, "weight": 0.0, "value": quantity, "observe": observe}


def xmat(body: str, entry: str) -> Quantity:
    """MuJoCo's ``xmat[body, entry]`` (``"zz"``: the world z component of the body's z
    axis), read at the body's origin site (a converted MJCF names it after the body)."""
    world, local = entry
    return {"site": body, "axis": world, "frame_axis": local}


def xpos(body: str, axis: str) -> Quantity:
    """MuJoCo's ``xpos[body, axis]``: the body's origin, world."""
    return {"site": body, "axis": axis}


def site_xpos(site: str, axis: str) -> Quantity:
    return {"site": site, "axis": axis}


def xipos(geoms: Sequence[str], axis: str) -> Quantity:
    """MuJoCo's ``xipos[body, axis]``: the centre of mass of the body its ``geoms`` make."""
    return {"body_center": list(geoms), "axis": axis}


def sensor(name: str, component: Optional[int] = None) -> Quantity:
    q: Quantity = {"sensor": name}
    if component is not None:
        q["component"] = component
    return q


def joint(name: str) -> Quantity:
    return {"joint": name}


def joint_velocity(name: str) -> Quantity:
    return {"joint_velocity": name}


def action(k: int) -> Quantity:
    return {"action": k}


def tolerance(
    name: str,
    of: str,
    bounds: Tuple[float, float] = (0.0, 0.0),
    margin: float = 0.0,
    sigmoid: str = "gaussian",
    value_at_margin: float = 0.1,
    weight: float = 0.0,
) -> Term:
    """dm_control's ``rewards.tolerance`` of term ``of``; infinite bounds are open ends."""
    lo, hi = (None if math.isinf(b) else float(b) for b in bounds)
    return {
        "name": name,
        "weight": weight,
        "tolerance": {
            "of": of,
            "bounds": [lo, hi],
            "margin": float(margin),
            "sigmoid": sigmoid,
            "value_at_margin": float(value_at_margin),
        },
    }


def _factors(factors: Sequence[Any]) -> List[Dict[str, Any]]:
    """Factors as names, or (name, scale, offset): ``scale · value + offset``."""
    out = []
    for f in factors:
        name, scale, offset = (f, 1.0, 0.0) if isinstance(f, str) else f
        out.append({"term": name, "scale": float(scale), "offset": float(offset)})
    return out


def product(name: str, factors: Sequence[Any], weight: float = 0.0) -> Term:
    return {"name": name, "weight": weight, "product": _factors(factors)}


def total(name: str, addends: Sequence[Any], weight: float = 0.0) -> Term:
    return {"name": name, "weight": weight, "sum": _factors(addends)}


def norm(name: str, parts: Sequence[Any], weight: float = 0.0) -> Term:
    """The length of the vector of terms ``parts``."""
    return {"name": name, "weight": weight, "norm": _factors(parts)}


def distance(name: str, a: Dict[str, str], b: Dict[str, str]) -> Term:
    """The distance between two points (``{"site": ...}`` or ``{"instance": ...}``)."""
    return {"name": name, "weight": 0.0, "distance": [a, b]}


def small_control(n: int) -> List[Term]:
    """dm_control's ``(4 + mean(tolerance(control, margin=1, value_at_margin=0,
    sigmoid='quadratic'))) / 5`` over ``n`` action values, as ``small_control``."""
    terms: List[Term] = [value(f"control_{k}", action(k)) for k in range(n)]
    terms += [
        tolerance(f"small_control_{k}", f"control_{k}", margin=1.0, sigmoid="quadratic",
                  value_at_margin=0.0)
        for k in range(n)
    ]
    addends = [(f"small_control_{k}", 1.0 / (5.0 * n), 0.8 if k == 0 else 0.0) for k in range(n)]
    terms.append(total("small_control", addends))
    return terms


def reward(of: str) -> Term:
    """The task's reward: term ``of``, weight 1."""
    return total("reward", [of], weight=1.0)

"""The registered ids: for each of Gymnasium's MuJoCo v5 environments, its name, XML file,
frame skip, episode length, keyword arguments with Gymnasium's defaults (``defaults``),
and the plan that builds it (``plans.py``); and the keywords every suite env takes.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Dict, Mapping, Optional

import numpy as np

from ..errors import InvalidArgument
from .humanoid import _humanoid, _humanoid_standup
from .model import Model
from .plans import (
    _ant,
    _half_cheetah,
    _hopper,
    _inverted_double_pendulum,
    _inverted_pendulum,
    _pusher,
    _reacher,
    _swimmer,
    _walker2d,
    Plan,
)

#: Keywords every suite env takes besides its own: Gymnasium's ``MujocoEnv`` ones (the
#: renderer's are accepted and ignored but ``render_mode``, ``width`` and ``height``) and
#: gymfleet's (``server``, ``timeout``, ``token``, and ``dtype``: the observations' type,
#: float32 by default, float64 as Gymnasium's, the same values widened).
COMMON_KWARGS: Dict[str, Any] = {
    "xml_file": None,
    "frame_skip": None,
    "render_mode": None,
    "width": 480,
    "height": 480,
    "camera_id": None,
    "camera_name": None,
    "default_camera_config": None,
    "max_geom": 1000,
    "visual_options": None,
    "server": None,
    "timeout": None,
    "token": None,
    "dtype": np.float32,
}

#: The renderer options gymfleet cannot honour (its pictures come from its own renderer).
IGNORED_KWARGS = ("camera_id", "camera_name", "default_camera_config", "max_geom", "visual_options")


@dataclass
class SuiteSpec:
    """One registered env: its Gymnasium name, defaults and plan."""

    name: str
    xml_file: str
    frame_skip: int
    max_episode_steps: int
    reward_threshold: Optional[float]
    defaults: Dict[str, Any]
    plan: Callable[[Model, Mapping[str, Any]], Plan]
    #: What differs from Gymnasium's env, if anything (the Ant's ankles' start).
    note: str = ""
    #: Gymnasium v5's ``observation_structure`` of the env, from its keywords and the
    #: model's ``nq``, ``nv`` and ``nbody``; ``None`` where Gymnasium's env has none
    #: (Reacher, Pusher, InvertedDoublePendulum).
    structure: Optional[Callable[[Mapping[str, Any], int, int, int], Dict[str, int]]] = None

    @property
    def id(self) -> str:
        return f"gymfleet/{self.name}-v5"

    def kwargs(self, given: Mapping[str, Any]) -> Dict[str, Any]:
        """Gymnasium's defaults updated with ``given``; an unknown keyword is an
        ``InvalidArgument`` naming the known ones."""
        known = {**COMMON_KWARGS, **self.defaults}
        unknown = sorted(set(given) - set(known))
        if unknown:
            raise InvalidArgument(
                f"{self.id}: unknown keyword argument(s) {', '.join(unknown)}; the keywords "
                f"are {', '.join(sorted(known))}"
            )
        out = dict(known)
        out.update(given)
        if out["xml_file"] is None:
            out["xml_file"] = self.xml_file
        if out["frame_skip"] is None:
            out["frame_skip"] = self.frame_skip
        try:
            dtype = np.dtype(out["dtype"])
        except TypeError:
            dtype = None
        if dtype not in (np.dtype(np.float32), np.dtype(np.float64)):
            raise InvalidArgument(
                f"dtype: expected numpy.float32 (the default) or numpy.float64, got {out['dtype']!r}"
            )
        out["dtype"] = dtype
        frame_skip = out["frame_skip"]
        if isinstance(frame_skip, bool) or not isinstance(frame_skip, (int, np.integer)) or frame_skip < 1:
            raise InvalidArgument(f"frame_skip: expected an integer >= 1, got {frame_skip!r}")
        return out


def _skipping(skipped: int) -> Callable[[Mapping[str, Any], int, int, int], Dict[str, int]]:
    """Gymnasium's ``observation_structure`` of an env whose observation leaves out the
    first ``skipped`` qpos entries unless ``exclude_current_positions_from_observation``
    is false (HalfCheetah, Hopper, Walker2d: 1; Swimmer: 2)."""

    def structure(kw: Mapping[str, Any], nq: int, nv: int, nbody: int) -> Dict[str, int]:
        skip = skipped * int(bool(kw["exclude_current_positions_from_observation"]))
        return {"skipped_qpos": skip, "qpos": nq - skip, "qvel": nv}

    return structure


def _ant_structure(kw: Mapping[str, Any], nq: int, nv: int, nbody: int) -> Dict[str, int]:
    """Ant v5's: ``cfrc_ext[1:]`` (6 per body but the world) when observed."""
    return {
        **_skipping(2)(kw, nq, nv, nbody),
        "cfrc_ext": (nbody - 1) * 6 * int(bool(kw["include_cfrc_ext_in_observation"])),
    }


def _humanoid_structure(kw: Mapping[str, Any], nq: int, nv: int, nbody: int) -> Dict[str, int]:
    """Humanoid v5's and HumanoidStandup v5's: the body parts each observation switch
    adds (``qfrc_actuator`` leaves out the free joint's 6 DOFs), and no tendons."""

    def part(switch: str, size: int) -> int:
        return size * int(bool(kw[f"include_{switch}_in_observation"]))

    return {
        **_skipping(2)(kw, nq, nv, nbody),
        "cinert": part("cinert", (nbody - 1) * 10),
        "cvel": part("cvel", (nbody - 1) * 6),
        "qfrc_actuator": part("qfrc_actuator", nv - 6),
        "cfrc_ext": part("cfrc_ext", (nbody - 1) * 6),
        "ten_length": 0,
        "ten_velocity": 0,
    }


def _whole_state(kw: Mapping[str, Any], nq: int, nv: int, nbody: int) -> Dict[str, int]:
    """InvertedPendulum v5's: all of qpos and qvel."""
    return {"qpos": nq, "qvel": nv}


_WALKER_DEFAULTS = {
    "forward_reward_weight": 1.0,
    "ctrl_cost_weight": 1e-3,
    "healthy_reward": 1.0,
    "terminate_when_unhealthy": True,
    "reset_noise_scale": 5e-3,
    "exclude_current_positions_from_observation": True,
}

#: Humanoid's and HumanoidStandup's observation switches.
_BODY_PARTS = {
    "exclude_current_positions_from_observation": True,
    "include_cinert_in_observation": True,
    "include_cvel_in_observation": True,
    "include_qfrc_actuator_in_observation": True,
    "include_cfrc_ext_in_observation": True,
}

_KNEES = (
    "the knees start at -2 degrees, the end of their ranges nearest MuJoCo's pose (0, which "
    "their ranges exclude), where MuJoCo's soft limits push them"
)

SUITE: Dict[str, SuiteSpec] = {
    s.id: s
    for s in [
        SuiteSpec(
            "InvertedPendulum",
            "inverted_pendulum.xml",
            2,
            1000,
            950.0,
            {"reset_noise_scale": 0.01},
            _inverted_pendulum,
            structure=_whole_state,
        ),
        SuiteSpec(
            "InvertedDoublePendulum",
            "inverted_double_pendulum.xml",
            5,
            1000,
            9100.0,
            {"healthy_reward": 10.0, "reset_noise_scale": 0.1},
            _inverted_double_pendulum,
        ),
        SuiteSpec(
            "Reacher",
            "reacher.xml",
            2,
            50,
            -3.75,
            {"reward_dist_weight": 1.0, "reward_control_weight": 1.0},
            _reacher,
        ),
        SuiteSpec(
            "Pusher",
            "pusher_v5.xml",
            5,
            100,
            0.0,
            {"reward_near_weight": 0.5, "reward_dist_weight": 1.0, "reward_control_weight": 0.1},
            _pusher,
        ),
        SuiteSpec(
            "HalfCheetah",
            "half_cheetah.xml",
            5,
            1000,
            4800.0,
            {
                "forward_reward_weight": 1.0,
                "ctrl_cost_weight": 0.1,
                "reset_noise_scale": 0.1,
                "exclude_current_positions_from_observation": True,
            },
            _half_cheetah,
            structure=_skipping(1),
        ),
        SuiteSpec(
            "Hopper",
            "hopper.xml",
            4,
            1000,
            3800.0,
            {
                **_WALKER_DEFAULTS,
                "healthy_state_range": (-100.0, 100.0),
                "healthy_z_range": (0.7, float("inf")),
                "healthy_angle_range": (-0.2, 0.2),
            },
            _hopper,
            structure=_skipping(1),
        ),
        SuiteSpec(
            "Walker2d",
            "walker2d_v5.xml",
            4,
            1000,
            None,
            {
                **_WALKER_DEFAULTS,
                "healthy_z_range": (0.8, 2.0),
                "healthy_angle_range": (-1.0, 1.0),
            },
            _walker2d,
            structure=_skipping(1),
        ),
        SuiteSpec(
            "Ant",
            "ant.xml",
            5,
            1000,
            6000.0,
            {
                "forward_reward_weight": 1.0,
                "ctrl_cost_weight": 0.5,
                "contact_cost_weight": 5e-4,
                "healthy_reward": 1.0,
                "main_body": 1,
                "terminate_when_unhealthy": True,
                "healthy_z_range": (0.2, 1.0),
                "contact_force_range": (-1.0, 1.0),
                "reset_noise_scale": 0.1,
                "exclude_current_positions_from_observation": True,
                "include_cfrc_ext_in_observation": True,
            },
            _ant,
            note="the ankles start at the ends of their ranges nearest MuJoCo's pose (0, "
            "which their ranges exclude), where MuJoCo's limits push them",
            structure=_ant_structure,
        ),
        SuiteSpec(
            "Swimmer",
            "swimmer.xml",
            4,
            1000,
            360.0,
            {
                "forward_reward_weight": 1.0,
                "ctrl_cost_weight": 1e-4,
                "reset_noise_scale": 0.1,
                "exclude_current_positions_from_observation": True,
            },
            _swimmer,
            structure=_skipping(2),
        ),
        SuiteSpec(
            "Humanoid",
            "humanoid.xml",
            5,
            1000,
            None,
            {
                "forward_reward_weight": 1.25,
                "ctrl_cost_weight": 0.1,
                "contact_cost_weight": 5e-7,
                "contact_cost_range": (-np.inf, 10.0),
                "healthy_reward": 5.0,
                "terminate_when_unhealthy": True,
                "healthy_z_range": (1.0, 2.0),
                "reset_noise_scale": 1e-2,
                **_BODY_PARTS,
            },
            _humanoid,
            note=_KNEES,
            structure=_humanoid_structure,
        ),
        SuiteSpec(
            "HumanoidStandup",
            "humanoidstandup.xml",
            5,
            1000,
            None,
            {
                "uph_cost_weight": 1.0,
                "ctrl_cost_weight": 0.1,
                "impact_cost_weight": 0.5e-6,
                "impact_cost_range": (-np.inf, 10.0),
                "reset_noise_scale": 1e-2,
                **_BODY_PARTS,
            },
            _humanoid_standup,
            note=_KNEES,
            structure=_humanoid_structure,
        ),
    ]
}

"""What a Control Suite task is, as gymfleet serves it (``Task``), and the pieces of its
observation keys (``Key``, parts from qpos, qvel and observed terms)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Dict, List, Optional, Tuple

import numpy as np


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
    #: dm_control's spec shape when it is neither flat nor ``()`` (manipulator's
    #: ``arm_pos``: ``(8, 2)``); the values are reshaped to it, row-major.
    shape: Optional[Tuple[int, ...]] = None

    def spec_shape(self, size: int) -> Tuple[int, ...]:
        """The key's shape in dm_control's spec, for ``size`` values."""
        return () if self.scalar else self.shape or (size,)

    def shaped(self, values: np.ndarray) -> np.ndarray:
        """Rows of ``values`` (one per env) in the key's shape."""
        return values.reshape((len(values),) + self.spec_shape(values.shape[1]))


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
    #: The function of dm_control's ``suite.<domain>`` that ``generated`` calls
    #: (manipulator's is ``make_model(use_peg, insert)``).
    maker: str = "get_model_and_assets"

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


def _to_target(v: np.ndarray) -> np.ndarray:
    """The target's coordinates minus the effector's (the first half minus the second)."""
    half = v.shape[1] // 2
    return v[:, :half] - v[:, half:]



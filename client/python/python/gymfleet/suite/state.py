"""MuJoCo-shaped read access to a suite env's state: ``env.unwrapped.data`` with ``qpos``,
``qvel`` and ``ctrl``, ``env.unwrapped.model`` with its counts, timestep and control
ranges, in SI units and MuJoCo's layouts, read from the rows the server already returns (no
extra call). The rest of MuJoCo's ``MjData`` and ``MjModel`` (bodies' and sites' poses,
contact forces, masses) and ``set_state`` are not offered yet: asking for them says so."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any, Tuple

import numpy as np

#: What ``data`` offers, as the error for anything else lists it.
DATA_FIELDS = ("qpos", "qvel", "ctrl")
#: What ``model`` offers.
MODEL_FIELDS = ("nq", "nv", "nu", "opt.timestep", "actuator_ctrlrange")


def _frozen(values: np.ndarray) -> np.ndarray:
    out = np.array(values, dtype=np.float64)
    out.flags.writeable = False
    return out


class SuiteData:
    """A snapshot of the env's state after its last reset or step, as MuJoCo's ``MjData``
    names it: ``qpos`` (nq), ``qvel`` (nv) and ``ctrl`` (nu, the last action as given; 0
    after a reset), float64, read-only (the server holds the state: writing here would
    change nothing)."""

    __slots__ = DATA_FIELDS

    def __init__(self, qpos: np.ndarray, qvel: np.ndarray, ctrl: np.ndarray) -> None:
        self.qpos, self.qvel, self.ctrl = _frozen(qpos), _frozen(qvel), _frozen(ctrl)

    def __getattr__(self, name: str) -> Any:
        raise AttributeError(
            f"data.{name} is not offered by gymfleet's envs yet (they offer data."
            f"{', data.'.join(DATA_FIELDS)}); save_state()/load_state() on "
            f"env.unwrapped.gymfleet_env hold the whole state"
        )


class SuiteModel:
    """The model's counts and constants MuJoCo's ``MjModel`` names: ``nq``, ``nv``,
    ``nu``, ``opt.timestep`` and ``actuator_ctrlrange`` (nu, 2; the action space's float32
    bounds, widened, where MuJoCo's are the file's float64). Read-only: the server
    simulates the file it was given (make the env with another ``xml_file`` or
    ``frame_skip`` instead)."""

    def __init__(self, nq: int, nv: int, timestep: float, ctrlrange: np.ndarray) -> None:
        object.__setattr__(self, "nq", int(nq))
        object.__setattr__(self, "nv", int(nv))
        object.__setattr__(self, "nu", int(len(ctrlrange)))
        object.__setattr__(self, "opt", _Options(timestep))
        object.__setattr__(self, "actuator_ctrlrange", _frozen(ctrlrange))

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError(
            f"model.{name} cannot be changed on a gymfleet env: the server simulates the file "
            "it was given (make the env with another xml_file or frame_skip instead)"
        )

    def __getattr__(self, name: str) -> Any:
        raise AttributeError(
            f"model.{name} is not offered by gymfleet's envs yet (they offer model."
            f"{', model.'.join(MODEL_FIELDS)})"
        )


class _Options(SimpleNamespace):
    """``model.opt``: the timestep, read-only."""

    def __init__(self, timestep: float) -> None:
        super().__init__()
        object.__setattr__(self, "timestep", float(timestep))

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError(
            f"model.opt.{name} cannot be changed on a gymfleet env: the server simulates the "
            "file it was given (make the env with another xml_file or frame_skip instead)"
        )


def state_vector(qpos: np.ndarray, qvel: np.ndarray) -> np.ndarray:
    """MuJoCo's ``state_vector()``: qpos, then qvel."""
    return np.concatenate([qpos, qvel]).astype(np.float64)


def qpos_qvel(q: np.ndarray, v: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """One row's qpos and qvel (float64) from ``_Setup.split``'s (1, n) arrays."""
    return np.asarray(q[0], dtype=np.float64), np.asarray(v[0], dtype=np.float64)

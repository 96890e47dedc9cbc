""":class:`DmcEnv` and :class:`DmcVectorEnv`: the Control Suite's tasks on a gymfleet
server, with dm_control's observation (its dict flattened in key order), reward, control
timestep and time limit.

The server simulates the task's XML file from the installed dm_control (includes
inlined), in SI units, one MuJoCo timestep per substep and ``n_sub_steps`` substeps per
env step, and computes the reward as the task's terms (``tasks.py``); it draws each
episode's start as the task's ``initialize_episode`` does. This module only assembles the
observation's keys from the server's joint state and observed terms.
"""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from ..env import GymfleetEnv
from ..errors import InvalidArgument
from ..pipeline import OverBatch
from ..suite.kinematics import segments, server_state, split_rows
from ..suite.model import parse_model
from ..suite.state import checked_state
from ..vector import GymfleetVectorEnv
from .model import body_names, generated_xml, read_suite_xml, timestep
from .tasks import TASKS, Task

#: The keywords every Control Suite id takes: dm_control's ``suite.load`` ones
#: (``task_kwargs``: ``random``, ``time_limit``; ``environment_kwargs``:
#: ``control_timestep``, ``n_sub_steps``, ``time_limit``, ``flat_observation``) and
#: gymfleet's (``server``, ``timeout``, ``token``, ``render_mode``, ``width``,
#: ``height``, and ``dtype``: the observations' type, float64 as dm_control's by
#: default, float32 on request).
KWARGS: Dict[str, Any] = {
    "task_kwargs": None,
    "environment_kwargs": None,
    "server": None,
    "timeout": None,
    "token": None,
    "render_mode": None,
    "width": 480,
    "height": 480,
    "dtype": np.float64,
}
_TASK_KWARGS = ("random", "time_limit")
_ENVIRONMENT_KWARGS = ("control_timestep", "n_sub_steps", "time_limit", "flat_observation")


def _mapping(value: Any, name: str, known: Sequence[str]) -> Dict[str, Any]:
    if value is None:
        return {}
    if not isinstance(value, Mapping):
        raise InvalidArgument(f"{name}: expected a dict, got {type(value).__name__}")
    unknown = sorted(set(value) - set(known))
    if unknown:
        raise InvalidArgument(
            f"{name}: unknown key(s) {', '.join(unknown)}; the keys are {', '.join(known)}"
        )
    return dict(value)


class Setup:
    """What every form of a task (single, vector, dm_env) builds from an id and its
    keywords: the model's text, the server's options, the observation's layout."""

    def __init__(self, env_id: str, kwargs: Mapping[str, Any]) -> None:
        if env_id not in TASKS:
            raise InvalidArgument(
                f"env_id: {env_id!r} is not one of gymfleet's Control Suite ids ({', '.join(TASKS)})"
            )
        self.task: Task = TASKS[env_id]
        unknown = sorted(set(kwargs) - set(KWARGS))
        if unknown:
            raise InvalidArgument(
                f"{env_id}: unknown keyword argument(s) {', '.join(unknown)}; the keywords are "
                f"{', '.join(KWARGS)}"
            )
        self.kw = {**KWARGS, **kwargs}
        task_kw = _mapping(self.kw["task_kwargs"], "task_kwargs", _TASK_KWARGS)
        env_kw = _mapping(self.kw["environment_kwargs"], "environment_kwargs", _ENVIRONMENT_KWARGS)
        dtype = np.dtype(self.kw["dtype"]) if self.kw["dtype"] in (np.float32, np.float64, "float32", "float64") else None
        if dtype is None:
            raise InvalidArgument(
                f"dtype: expected numpy.float64 (the default) or numpy.float32, got {self.kw['dtype']!r}"
            )
        self.dtype = dtype
        self.text = (
            read_suite_xml(self.task.xml) if self.task.generated is None
            else generated_xml(self.task.domain, *self.task.generated, maker=self.task.maker)
        )
        for old, new in self.task.edits:
            if old not in self.text:
                raise InvalidArgument(
                    f"{self.task.id}: the installed dm_control's {self.task.xml} lacks {old!r}, "
                    "which the task edits"
                )
            self.text = self.text.replace(old, new)
        self.physics_timestep = timestep(self.text)
        #: MuJoCo's bodies but the world, in body order ("" for an unnamed one).
        self.body_names = body_names(self.text)
        self.n_sub_steps = self._sub_steps(env_kw)
        self.control_timestep = self.physics_timestep * self.n_sub_steps
        time_limit = task_kw.get("time_limit", env_kw.get("time_limit", self.task.time_limit))
        try:
            time_limit = float(time_limit)
        except (TypeError, ValueError):
            raise InvalidArgument(f"time_limit: expected seconds, got {time_limit!r}") from None
        if not time_limit > 0:
            raise InvalidArgument(f"time_limit: expected a positive number of seconds, got {time_limit}")
        self.time_limit = time_limit
        #: dm_control's step limit: the control steps in ``time_limit`` (1000 by default).
        self.step_limit = (
            (1 << 32) - 1 if math.isinf(time_limit)
            else max(1, math.ceil(time_limit / self.control_timestep - 1e-9))
        )
        random = task_kw.get("random")
        if random is not None and not isinstance(random, (int, np.integer)):
            raise InvalidArgument(
                "task_kwargs['random']: gymfleet takes an integer seed (the server draws the "
                f"episodes' starts), got {type(random).__name__}"
            )
        #: The seed of the first reset without one.
        self.seed: Optional[int] = None if random is None else int(random)
        if self.kw["render_mode"] not in (None, "rgb_array"):
            raise InvalidArgument(
                f"render_mode: {self.kw['render_mode']!r} is not supported (render_modes: ['rgb_array'])"
            )
        self.observed = [term["name"] for term in self.task.terms if term.get("observe")]
        self.structure: Dict[str, int] = {}

    def _sub_steps(self, env_kw: Mapping[str, Any]) -> int:
        """dm_control's ``n_sub_steps``: given, or ``control_timestep / timestep`` (which
        must divide), or the task's."""
        if "n_sub_steps" in env_kw and "control_timestep" in env_kw:
            raise InvalidArgument(
                "environment_kwargs: give control_timestep or n_sub_steps, not both (as dm_control)"
            )
        if "n_sub_steps" in env_kw:
            n = env_kw["n_sub_steps"]
            if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
                raise InvalidArgument(f"n_sub_steps: expected an integer >= 1, got {n!r}")
            return int(n)
        if "control_timestep" in env_kw:
            ratio = float(env_kw["control_timestep"]) / self.physics_timestep
            n = int(round(ratio))
            if n < 1 or abs(ratio - n) > 1e-6:
                raise InvalidArgument(
                    f"control_timestep: {env_kw['control_timestep']} is not a multiple of the "
                    f"physics timestep {self.physics_timestep}"
                )
            return n
        return self.task.n_sub_steps

    def options(self) -> Dict[str, Any]:
        return {
            "server": self.kw["server"],
            "timeout": self.kw["timeout"],
            "token": self.kw["token"],
            "units": "si",
            "dt": self.control_timestep,
            "substeps": self.n_sub_steps,
            "max_steps": self.step_limit,
            "task": {"terms": self.task.terms, "reset_noise": self.task.reset_noise},
            "render_mode": self.kw["render_mode"],
            "render_options": {"width": int(self.kw["width"]), "height": int(self.kw["height"])},
        }

    def check(self, info: Dict[str, Any]) -> None:
        """Reads the server's observation layout, and checks that every observed term is
        where the task put it; fills ``structure`` (each key's length)."""
        self.segments = segments(info["observation_layout"])
        self.base = "base_pose" in self.segments
        #: With a free joint: the root geom's frame in its body (what the server observes
        #: as the floating base), to give MuJoCo's qpos and qvel.
        self.root_geom = parse_model(self.task.xml, self.text).root_geom if self.base else None
        names = list(info.get("term_names") or [])
        observed = [n for n in names if n in self.observed]
        if observed != self.observed:
            raise InvalidArgument(f"{self.task.id}: the server observes {observed}, not {self.observed}")
        self._plan = self._parts()
        q = np.zeros((1, info["observation_dim"]), dtype=np.float32)
        self.structure = {k: int(np.size(v[0])) for k, v in self.keys(q).items()}

    def _parts(self) -> List[List[Tuple[str, Any]]]:
        """Each key's parts as what ``keys`` indexes: ("qpos"|"qvel", a slice) or
        ("terms", the observed terms' columns), worked out once."""
        plan = []
        for key in self.task.keys:
            parts: List[Tuple[str, Any]] = []
            for part in key.parts:
                if part[0] == "terms":
                    parts.append(("terms", np.array([self.observed.index(n) for n in part[1]])))
                else:
                    parts.append((part[0], slice(part[1], part[2])))
            plan.append(parts)
        return plan

    def keys(self, raw: np.ndarray) -> Dict[str, np.ndarray]:
        """dm_control's observation dict of rows ``raw`` (n, dim): each key (n, ...),
        float64."""
        q, v, _ = split_rows(raw, self.segments, self.root_geom)
        rows = {"qpos": q, "qvel": v}
        if self.observed:
            rows["terms"] = raw[:, self.segments["terms"]]
        out: Dict[str, np.ndarray] = {}
        for key, parts in zip(self.task.keys, self._plan):
            values = np.concatenate([rows[kind][:, at] for kind, at in parts], axis=1)
            values = values.astype(np.float64)
            if key.transform is not None:
                values = key.transform(values)
            out[key.name] = key.shaped(values)
        return out

    def flat(self, raw: np.ndarray) -> np.ndarray:
        """The observation dict of rows ``raw`` flattened in key order, in ``dtype``."""
        keys = self.keys(raw)
        n = len(raw)
        return np.concatenate([np.reshape(keys[k.name], (n, -1)) for k in self.task.keys], axis=1).astype(
            self.dtype, copy=False
        )

    def observation_space(self) -> spaces.Box:
        return spaces.Box(-np.inf, np.inf, shape=(sum(self.structure.values()),), dtype=self.dtype)


class DmcEnv(gym.Env):
    """One of the Control Suite's tasks on gymfleet; made by
    ``gymnasium.make("gymfleet/<DomainTask>-v1", **kwargs)``. Episodes are truncated at
    dm_control's step limit (1000 control steps), never terminated, as dm_control's
    (whose discount stays 1)."""

    metadata: Dict[str, Any] = {"render_modes": ["rgb_array"], "render_fps": 30}

    def __init__(self, env_id: str, **kwargs: Any) -> None:
        setup = Setup(env_id, kwargs)
        self._setup = setup
        self._made_with = (env_id, dict(kwargs))
        self._env = GymfleetEnv(setup.text, **setup.options())
        setup.check(self._env.env_info)
        self.action_space = self._env.action_space
        self.observation_space = setup.observation_space()
        #: Each key's length in the flat observation, in order.
        self.observation_structure = dict(setup.structure)
        self.render_mode = setup.kw["render_mode"]
        self.dt = setup.control_timestep
        self.metadata = {**type(self).metadata, "render_fps": int(np.round(1.0 / self.dt))}
        self._raw: Optional[np.ndarray] = None
        self._first_seed = setup.seed

    @property
    def gymfleet_env(self) -> GymfleetEnv:
        """The server-side env underneath (SI joint state, the reward's terms)."""
        return self._env

    @property
    def task(self) -> Task:
        return self._setup.task

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[Dict[str, Any]] = None
    ) -> Tuple[np.ndarray, Dict[str, Any]]:
        if seed is None and self._first_seed is not None:
            seed, self._first_seed = self._first_seed, None
        super().reset(seed=seed)
        raw, _ = self._env.reset(seed=seed)
        self._raw = raw[None, :]
        info = {"observation_structure": dict(self._setup.structure), "discount": 1.0}
        return self._setup.flat(self._raw)[0], info

    def step(self, action: Any) -> Tuple[np.ndarray, float, bool, bool, Dict[str, Any]]:
        shape = np.shape(action)
        if shape != self.action_space.shape:
            raise ValueError(
                f"Action dimension mismatch. Expected {self.action_space.shape}, found {shape}"
            )
        raw, reward, terminated, truncated, _ = self._env.step_terms(action)
        self._raw = raw[None, :]
        obs = self._setup.flat(self._raw)[0]
        return obs, float(reward), bool(terminated), bool(truncated), {"discount": 1.0}

    def observation_dict(self) -> Dict[str, np.ndarray]:
        """dm_control's observation dict of the state now (float64)."""
        if self._raw is None:
            raise gym.error.ResetNeeded("reset the env before reading its observation")
        return {k: v[0] for k, v in self._setup.keys(self._raw).items()}

    @property
    def data(self) -> SimpleNamespace:
        """The state after the last reset, step or ``set_state``: MuJoCo's ``qpos`` and
        ``qvel`` (float64 copies of the server's float32 state)."""
        if self._raw is None:
            raise gym.error.ResetNeeded("reset the env before reading its state")
        q, v, _ = split_rows(self._raw, self._setup.segments, self._setup.root_geom)
        return SimpleNamespace(qpos=q[0].astype(np.float64), qvel=v[0].astype(np.float64))

    def set_state(self, qpos: Any, qvel: Any) -> None:
        """Puts the model in the state ``qpos`` and ``qvel`` (MuJoCo's layouts, as
        dm_control's ``physics.set_state``); the episode goes on. As the v5 ids'
        ``set_state``: a position past a hard limit is set at it, with a warning."""
        nv = sum(j["dof"] for j in self._env.env_info["joints"]) + 6 * int(self._setup.base)
        nq = nv + int(self._setup.base)
        qpos, qvel = checked_state(qpos, qvel, nq, nv)
        positions, velocities, base = server_state(
            qpos, qvel, self._setup.base, self._setup.root_geom
        )
        raw, warnings = self._env.set_joint_state(positions, velocities, base)
        for warning in warnings:
            gym.logger.warn(f"set_state: {warning}")
        self._raw = np.asarray(raw)[None, :]

    def render(self) -> Optional[np.ndarray]:
        return self._env.render()

    def close(self) -> None:
        self._env.close()
        super().close()

    def __getstate__(self) -> Dict[str, Any]:
        """As the v5 ids: the id and keywords, and the server-side env's saved state."""
        env_id, kwargs = self._made_with
        return {"env_id": env_id, "kwargs": kwargs, "state": self._env.saved_state_or_none(),
                "spec": self.spec}

    def __setstate__(self, pickled: Dict[str, Any]) -> None:
        self.__init__(pickled["env_id"], **pickled["kwargs"])  # type: ignore[misc]
        self.spec = pickled["spec"]
        if pickled["state"] is not None:
            self._raw = np.asarray(self._env.load_state(pickled["state"]))[None, :]

    def __repr__(self) -> str:
        return f"<DmcEnv {self._setup.task.id} on {self._env.server}>"


class DmcVectorEnv(OverBatch, VectorEnv):
    """``num_envs`` of one Control Suite task as one gymfleet batch; made by
    ``gymnasium.make_vec("gymfleet/<DomainTask>-v1", num_envs)`` or
    ``gymfleet.make_vec``. Autoreset is the server's, in gymnasium's three modes."""

    metadata: Dict[str, Any] = {
        "render_modes": ["rgb_array"],
        "render_fps": 30,
        "autoreset_mode": AutoresetMode.NEXT_STEP,
    }

    def __init__(
        self,
        env_id: str,
        num_envs: int = 1,
        *,
        autoreset_mode: Union[AutoresetMode, str] = AutoresetMode.NEXT_STEP,
        batch_size: Optional[int] = None,
        **kwargs: Any,
    ) -> None:
        setup = Setup(env_id, kwargs)
        self._setup = setup
        self._envs = GymfleetVectorEnv(
            setup.text, num_envs, autoreset_mode=autoreset_mode, batch_size=batch_size,
            **setup.options(),
        )
        setup.check(self._envs.batch_info)
        self.num_envs = self._envs.num_envs
        self.render_mode = setup.kw["render_mode"]
        self.dt = setup.control_timestep
        self.metadata = {
            **type(self).metadata,
            "render_fps": int(np.round(1.0 / self.dt)),
            "autoreset_mode": self._envs.metadata["autoreset_mode"],
        }
        self.observation_structure = dict(setup.structure)
        self.single_action_space = self._envs.single_action_space
        self.single_observation_space = setup.observation_space()
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)

    @property
    def gymfleet_envs(self) -> GymfleetVectorEnv:
        return self._envs

    def reset(
        self,
        *,
        seed: Union[int, Sequence[Optional[int]], None] = None,
        options: Optional[Dict[str, Any]] = None,
    ) -> Tuple[np.ndarray, Dict[str, Any]]:
        if seed is None and self._setup.seed is not None:
            seed, self._setup.seed = self._setup.seed, None
        if seed is not None and isinstance(seed, (int, np.integer)):
            super().reset(seed=int(seed))
        raw, _ = self._envs.reset(seed=seed, options=options)
        return self._setup.flat(raw), {}

    # The asynchronous API (EnvPool's, over the batch's: `gymfleet/pipeline.py`).

    def recv(self, timeout: Optional[float] = None) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, Dict[str, Any]]:
        """The next :attr:`batch_size` envs that finished a step (or their reset), as
        :meth:`step` gives each env, with ``info["env_id"]``."""
        raw = self._envs.recv(timeout)
        obs, rewards, terminated, truncated, infos = self._finish(*raw)
        infos["env_id"] = raw[4]["env_id"]
        return obs, rewards, terminated, truncated, infos

    def _finish(
        self, raw: np.ndarray, rewards: Any, terminated: Any, truncated: Any, raw_infos: Dict[str, Any]
    ) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, Dict[str, Any]]:
        """dm_control's flat observations of the server's rows, and the final ones."""
        infos: Dict[str, Any] = {}
        if "final_obs" in raw_infos:
            has_final = raw_infos["_final_obs"]
            final = np.full(len(raw), None, dtype=object)
            for env in np.flatnonzero(has_final):
                final[env] = self._setup.flat(np.asarray(raw_infos["final_obs"][env])[None, :])[0]
            infos["final_obs"], infos["_final_obs"] = final, has_final
            infos["final_info"], infos["_final_info"] = {}, has_final.copy()
        rewards = np.asarray(rewards, dtype=np.float64)
        return self._setup.flat(raw), rewards, np.asarray(terminated), np.asarray(truncated), infos

    def render(self) -> Optional[Tuple[np.ndarray, ...]]:
        return self._envs.render()

    def close_extras(self, **kwargs: Any) -> None:
        self._envs.close()

    def __reduce__(self) -> Any:
        raise TypeError(
            "a DmcVectorEnv does not pickle: it is a batch on its server; make it again in the "
            "other process with gymnasium.make_vec (a single env pickles, with its state)"
        )

    def __repr__(self) -> str:
        return f"<DmcVectorEnv {self._setup.task.id} x {self.num_envs}>"

"""The Control Suite through the ``dm_env`` interface, as ``dm_control.suite.load`` gives it:

>>> from gymfleet import dm_control
>>> env = dm_control.load("cheetah", "run", task_kwargs={"random": 0})
>>> timestep = env.reset()                      # dm_env.TimeStep, StepType.FIRST
>>> timestep = env.step(np.zeros(6))            # MID ... LAST at dm_control's step limit

``load`` returns an :class:`Environment` (a ``dm_env.Environment``): ``reset``, ``step``
(the step after a LAST starts the next episode, as dm_control's), ``observation_spec`` (an
ordered dict of ``Array`` specs), ``action_spec`` (a ``BoundedArray``), ``reward_spec``,
``discount_spec``, ``control_timestep()``, and ``physics`` (read access to ``qpos``,
``qvel``, ``xpos`` and ``sensordata``, by index or by name through ``physics.named.data``)
and ``task`` (the gymfleet task: its terms and keys). :func:`load_batch` serves many envs
of one task as one server-side batch, EnvPool's ``dm`` way: one ``TimeStep`` of arrays.

The same tasks are the gymnasium ids ``gymfleet/<DomainTask>-v1`` (:mod:`gymfleet.dmc`).
"""

from __future__ import annotations

import collections
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np

from .dmc.envs import DmcEnv, DmcVectorEnv
from .dmc.tasks import TASKS, Task, find

try:
    import dm_env
    from dm_env import specs
except ImportError:  # pragma: no cover - the [dmc] extra brings it
    dm_env = None  # type: ignore[assignment]


def _require() -> None:
    if dm_env is None:
        from .errors import InvalidArgument

        raise InvalidArgument(
            "gymfleet.dm_control needs dm_env: pip install './client/python[dmc]' (or dm-env)"
        )


class _Named:
    """Rows of one MuJoCo field indexed by name (``qpos['rootz']``, ``xpos['torso', 'z']``)."""

    _AXES = {"x": 0, "y": 1, "z": 2}

    def __init__(self, values: np.ndarray, names: Sequence[str], sizes: Optional[Sequence[int]] = None):
        self._values = values
        sizes = [1] * len(names) if sizes is None else list(sizes)
        starts = np.concatenate([[0], np.cumsum(sizes)]).astype(int)
        self._slices = {name: slice(starts[k], starts[k + 1]) for k, name in enumerate(names)}

    def _row(self, key: Any) -> Any:
        if isinstance(key, str):
            if key not in self._slices:
                raise KeyError(f"{key!r} (names: {', '.join(self._slices)})")
            s = self._slices[key]
            return s.start if s.stop - s.start == 1 and self._values.ndim == 2 else s
        if isinstance(key, (list, tuple)) and key and all(isinstance(k, str) for k in key):
            return [self._row(k) for k in key]
        return key

    def __getitem__(self, key: Any) -> np.ndarray:
        if isinstance(key, tuple) and len(key) == 2 and self._values.ndim == 2:
            row, column = key
            column = self._AXES.get(column, column) if isinstance(column, str) else column
            return np.array(self._values[self._row(row), column])
        return np.array(self._values[self._row(key)])


class Physics:
    """Read access to an env's state, as dm_control's ``physics.data`` and
    ``physics.named.data`` name it (float64 copies of the server's float32 state): ``qpos``,
    ``qvel`` (by joint), ``xpos`` (by body: its origin, world), ``sensordata`` (by
    sensor); ``timestep()``."""

    def __init__(self, env: DmcEnv) -> None:
        self._env = env

    def timestep(self) -> float:
        return self._env._setup.physics_timestep

    @property
    def data(self) -> Any:
        state = self._env.data
        bodies = self._env.gymfleet_env.bodies()
        names = [j["name"] for j in self._env.gymfleet_env.env_info["joints"]]
        sites = list(bodies["sites"])
        poses = np.asarray(bodies["site_poses"], dtype=np.float64).reshape(-1, 7)
        body_names = [b for b in self._env._setup.body_names if b in sites]
        xpos = np.array([poses[sites.index(b), :3] for b in body_names]).reshape(-1, 3)
        sensordata = np.asarray(bodies["sensordata"], dtype=np.float64)
        sensors, dims = list(bodies["sensors"]), [int(d) for d in bodies["sensor_dims"]]
        named = collections.namedtuple("Named", "qpos qvel xpos sensordata")(
            _Named(state.qpos, names), _Named(state.qvel, names),
            _Named(np.vstack([np.zeros((1, 3)), xpos]), ["world", *body_names]),
            _Named(sensordata, sensors, dims),
        )
        data = collections.namedtuple("Data", "qpos qvel xpos sensordata named")(
            state.qpos, state.qvel, np.vstack([np.zeros((1, 3)), xpos]), sensordata, named
        )
        return data

    @property
    def named(self) -> Any:
        return collections.namedtuple("NamedPhysics", "data")(self.data.named)

    def set_state(self, state: Any) -> None:
        """MuJoCo's ``concatenate(qpos, qvel)``, as dm_control's ``physics.set_state``."""
        state = np.asarray(state, dtype=np.float64).reshape(-1)
        n = len(state) // 2
        self._env.set_state(state[:n], state[n:])


def _spec_dict(setup: Any) -> "collections.OrderedDict[str, Any]":
    out: "collections.OrderedDict[str, Any]" = collections.OrderedDict()
    for key in setup.task.keys:
        shape = key.spec_shape(setup.structure[key.name])
        out[key.name] = specs.Array(shape=shape, dtype=np.float64, name=key.name)
    return out


def _action_spec(space: Any) -> Any:
    """dm_control's action spec of a Box: float64 bounds."""
    return specs.BoundedArray(shape=space.shape, dtype=np.float64,
                              minimum=space.low.astype(np.float64),
                              maximum=space.high.astype(np.float64))


class Environment(dm_env.Environment if dm_env is not None else object):  # type: ignore[misc]
    """One Control Suite task as a ``dm_env.Environment`` on a gymfleet server."""

    def __init__(self, env: DmcEnv, flat_observation: bool = False) -> None:
        self._env = env
        self._flat = flat_observation
        self._reset_next_step = True
        self.physics = Physics(env)

    @property
    def task(self) -> Task:
        return self._env.task

    def _observation(self) -> Any:
        keys = self._env.observation_dict()
        if self._flat:
            return collections.OrderedDict(
                observations=np.concatenate([np.reshape(v, -1) for v in keys.values()])
            )
        return collections.OrderedDict(
            (k, np.float64(v) if np.ndim(v) == 0 else v) for k, v in keys.items()
        )

    def reset(self) -> Any:
        self._reset_next_step = False
        self._env.reset()
        return dm_env.restart(self._observation())

    def step(self, action: Any) -> Any:
        if self._reset_next_step:
            return self.reset()
        action = np.asarray(action, dtype=np.float32).reshape(self._env.action_space.shape)
        _, reward, terminated, truncated, _ = self._env.step(action)
        observation = self._observation()
        if terminated or truncated:
            self._reset_next_step = True
            return dm_env.truncation(reward, observation)
        return dm_env.transition(reward, observation)

    def observation_spec(self) -> Any:
        if self._flat:
            size = sum(self._env._setup.structure.values())
            return collections.OrderedDict(
                observations=specs.Array(shape=(size,), dtype=np.float64, name="observations")
            )
        return _spec_dict(self._env._setup)

    def action_spec(self) -> Any:
        return _action_spec(self._env.action_space)

    def control_timestep(self) -> float:
        return self._env.dt

    def close(self) -> None:
        self._env.close()


def _kwargs(task_kwargs: Optional[Mapping[str, Any]], environment_kwargs: Optional[Mapping[str, Any]],
            extra: Mapping[str, Any]) -> Dict[str, Any]:
    env_kw = dict(environment_kwargs or {})
    flat = bool(env_kw.pop("flat_observation", False))
    return {"task_kwargs": task_kwargs, "environment_kwargs": env_kw, **extra, "_flat": flat}


def load(
    domain_name: str,
    task_name: str,
    task_kwargs: Optional[Mapping[str, Any]] = None,
    environment_kwargs: Optional[Mapping[str, Any]] = None,
    visualize_reward: bool = False,
    **gymfleet_kwargs: Any,
) -> Environment:
    """``dm_control.suite.load``'s signature: the task ``domain_name``-``task_name`` as a
    ``dm_env.Environment`` on a gymfleet server (``server=``, ``timeout=``, ``token=``
    among ``gymfleet_kwargs``; the embedded one by default). ``visualize_reward`` is
    accepted and ignored (gymfleet renders with its own renderer)."""
    _require()
    task = find(domain_name, task_name)
    kw = _kwargs(task_kwargs, environment_kwargs, gymfleet_kwargs)
    flat = kw.pop("_flat")
    return Environment(DmcEnv(task.id, **kw), flat_observation=flat)


class BatchEnvironment:
    """``num_envs`` envs of one task as one server-side batch, in the ``dm_env`` way
    EnvPool's ``dm`` envs take: ``reset()`` and ``step(actions)`` return one
    ``TimeStep`` whose fields are arrays over the envs (``step_type``, ``reward``,
    ``discount``, and each observation key with the envs first). An env whose last step
    was LAST starts its next episode on the next ``step`` (FIRST, reward 0), the others
    step on."""

    def __init__(self, envs: DmcVectorEnv) -> None:
        self._envs = envs
        self.num_envs = envs.num_envs
        self._last = np.zeros(self.num_envs, dtype=bool)

    def _observation(self, flat: np.ndarray) -> "collections.OrderedDict[str, np.ndarray]":
        out: "collections.OrderedDict[str, np.ndarray]" = collections.OrderedDict()
        start = 0
        for key in self._envs._setup.task.keys:
            size = self._envs._setup.structure[key.name]
            values = flat[:, start:start + size].astype(np.float64)
            out[key.name] = key.shaped(values)
            start += size
        return out

    def reset(self, seed: Union[int, Sequence[int], None] = None) -> Any:
        obs, _ = self._envs.reset(seed=seed)
        self._last[:] = False
        n = self.num_envs
        return dm_env.TimeStep(np.full(n, dm_env.StepType.FIRST), np.zeros(n), np.ones(n),
                               self._observation(obs))

    def step(self, actions: Any) -> Any:
        obs, rewards, terminated, truncated, _ = self._envs.step(np.asarray(actions, dtype=np.float32))
        first = self._last.copy()
        self._last = np.asarray(terminated) | np.asarray(truncated)
        step_type = np.where(first, dm_env.StepType.FIRST,
                             np.where(self._last, dm_env.StepType.LAST, dm_env.StepType.MID))
        rewards = np.where(first, 0.0, rewards)
        return dm_env.TimeStep(step_type, rewards, np.ones(self.num_envs), self._observation(obs))

    def observation_spec(self) -> Any:
        return _spec_dict(self._envs._setup)

    def action_spec(self) -> Any:
        return _action_spec(self._envs.single_action_space)

    def close(self) -> None:
        self._envs.close()


def load_batch(
    domain_name: str,
    task_name: str,
    num_envs: int,
    task_kwargs: Optional[Mapping[str, Any]] = None,
    environment_kwargs: Optional[Mapping[str, Any]] = None,
    **gymfleet_kwargs: Any,
) -> BatchEnvironment:
    """:func:`load` for ``num_envs`` envs of one task, as one server-side batch."""
    _require()
    task = find(domain_name, task_name)
    kw = _kwargs(task_kwargs, environment_kwargs, gymfleet_kwargs)
    if kw.pop("_flat"):
        from .errors import InvalidArgument

        raise InvalidArgument("load_batch: flat_observation is not supported (use the gymnasium ids)")
    return BatchEnvironment(DmcVectorEnv(task.id, num_envs, **kw))


__all__: List[str] = ["load", "load_batch", "Environment", "BatchEnvironment", "Physics", "TASKS"]

"""Stable-Baselines3 on one gymfleet batch: a ``VecEnv`` whose every ``step`` is one
``StepBatch`` on the server.

>>> from stable_baselines3 import PPO
>>> from gymfleet.sb3 import make_vec_env
>>> venv = make_vec_env("gymfleet/Hopper-v5", n_envs=8, seed=0)
>>> PPO("MlpPolicy", venv).learn(10_000)

SB3 is an optional extra (``pip install stable-baselines3``); this module imports it, the
rest of the package never does. The adapter keeps SB3's own conventions, as its
``DummyVecEnv`` over the same envs would:

- a finished env is reset in the same step: the step returns the new episode's first
  observation, ``infos[i]["terminal_observation"]`` the last one, ``infos[i]
  ["TimeLimit.truncated"]`` whether the episode was cut by its time limit (not ended by the
  task), and ``reset_infos[i]`` the reset's info;
- ``infos[i]["episode"] = {"r", "l", "t"}`` at each episode's end, as SB3's ``Monitor``
  writes it (so ``PPO``'s logs and ``evaluate_policy`` see episode returns without a
  wrapper; ``env_is_wrapped(Monitor)`` says so);
- ``seed(s)`` gives env ``i`` the seed ``s + i`` at the next ``reset()``; ``set_options``
  likewise;
- rewards are ``float32``, dones ``bool``; ``get_attr``/``set_attr``/``env_method`` reach the
  underlying vector env (the same object for every index: one batch).

With ``n_envs=1`` (rl-zoo's setting for Hopper and most MuJoCo tasks) the adapter steps the
id's single env (``gymnasium.make``) instead of a batch of one: the same bits, without the
batch's per-step vector bookkeeping in Python (BENCHMARKS.md G); ``get_attr`` and the
others then reach that env.
"""

from __future__ import annotations

import time
from concurrent.futures import Future, ThreadPoolExecutor
from typing import Any, Dict, Iterable, List, Optional, Sequence, Type, Union

import gymnasium
import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv

try:
    from stable_baselines3.common.vec_env.base_vec_env import VecEnv
except ImportError as exc:  # pragma: no cover - exercised only without SB3
    raise ImportError(
        "gymfleet.sb3 needs Stable-Baselines3: pip install stable-baselines3"
    ) from exc

__all__ = ["GymfleetSb3VecEnv", "make_vec_env"]

Indices = Union[None, int, Iterable[int]]


def make_vec_env(
    env_id: str,
    n_envs: int = 1,
    seed: Optional[int] = None,
    **kwargs: Any,
) -> "GymfleetSb3VecEnv":
    """``n_envs`` envs of a registered gymfleet id (``gymfleet/Hopper-v5``, or an id made by
    ``gymfleet.register``) as one batch, wrapped for SB3. ``kwargs`` go to
    ``gymnasium.make_vec`` (e.g. ``server="host:port"``, the env's keywords); ``seed``
    seeds the first ``reset()`` as SB3's ``make_vec_env`` does (env ``i`` gets
    ``seed + i``)."""
    if "autoreset_mode" in kwargs:
        raise ValueError(
            "make_vec_env: autoreset_mode is set by the adapter (SB3 resets a finished env "
            "in the same step); leave it out"
        )
    if n_envs == 1:
        venv: Union[VectorEnv, gymnasium.Env] = gymnasium.make(env_id, **kwargs)
    else:
        venv = gymnasium.make_vec(
            env_id,
            n_envs,
            vectorization_mode="vector_entry_point",
            autoreset_mode=AutoresetMode.SAME_STEP,
            **kwargs,
        )
    adapter = GymfleetSb3VecEnv(venv)
    if seed is not None:
        adapter.seed(seed)
    return adapter


class GymfleetSb3VecEnv(VecEnv):
    """An SB3 ``VecEnv`` over a gymnasium ``VectorEnv`` that resets finished envs in the
    same step (``autoreset_mode="same_step"``; gymfleet's batches and suite envs do), or
    over one gymnasium ``Env``, which the adapter resets itself as SB3's ``DummyVecEnv``
    does."""

    def __init__(self, venv: Union[VectorEnv, gymnasium.Env]) -> None:
        #: The one env stepped directly (no vector env underneath), if so.
        self._one: Optional[gymnasium.Env] = None if isinstance(venv, VectorEnv) else venv
        # One env is reset by the adapter itself; a vector env must do it in the same step.
        mode = venv.metadata.get("autoreset_mode") if self._one is None else AutoresetMode.SAME_STEP
        if mode != AutoresetMode.SAME_STEP:
            raise ValueError(
                "GymfleetSb3VecEnv: the vector env must reset in the same step "
                f"(autoreset_mode=AutoresetMode.SAME_STEP), got {mode!r}; "
                "gymfleet.sb3.make_vec_env does this for you"
            )
        self.venv = venv
        # `step_async` hands the step to this thread and returns: the server steps (no GIL
        # held while it waits) while the caller works, until `step_wait`.
        self._worker = ThreadPoolExecutor(max_workers=1, thread_name_prefix="gymfleet-sb3")
        self._pending: Optional["Future[Any]"] = None
        n = 1 if self._one is not None else venv.num_envs
        self._returns = np.zeros(n, dtype=np.float64)
        self._lengths = np.zeros(n, dtype=np.int64)
        self._start = time.time()
        if self._one is not None:
            super().__init__(1, venv.observation_space, venv.action_space)
        else:
            super().__init__(n, venv.single_observation_space, venv.single_action_space)
        self.metadata = {**venv.metadata, **self.metadata}

    # -- stepping -----------------------------------------------------------------------

    def reset(self) -> np.ndarray:
        seeds = None if all(s is None for s in self._seeds) else list(self._seeds)
        options = self._options[0]
        if any(o != options for o in self._options):
            raise ValueError(
                "GymfleetSb3VecEnv.reset: one batch takes one set of reset options for all "
                "envs; got different options per env"
            )
        if self._one is not None:
            one, info = self._one.reset(seed=None if seeds is None else seeds[0], options=options or None)
            obs, self.reset_infos = one[None], [info]
        else:
            obs, infos = self.venv.reset(seed=seeds, options=options or None)
            self.reset_infos = _per_env(infos, self.num_envs)
        self._reset_seeds()
        self._reset_options()
        self._returns[:] = 0.0
        self._lengths[:] = 0
        return obs

    def step_async(self, actions: np.ndarray) -> None:
        """Starts the step and returns at once (the step runs on the adapter's thread,
        or, if it has not started by then, in ``step_wait``)."""
        if self._pending is not None:
            raise RuntimeError("GymfleetSb3VecEnv.step_async: a step is pending; call step_wait first")
        actions = np.asarray(actions)
        step = self.venv.step if self._one is None else self._step_one
        self._pending = (self._worker.submit(step, actions), actions)

    def step_wait(self) -> Any:
        if self._pending is None:
            raise RuntimeError("GymfleetSb3VecEnv.step_wait: call step_async first")
        (pending, actions), self._pending = self._pending, None
        # A step the thread has not started (SB3's own `step` calls `step_wait` right after
        # `step_async`: nothing overlaps) is taken back and run here, without the two thread
        # hand-offs (about 100 µs a step on this VM); a caller that works in between lets
        # the thread run it meanwhile.
        if self._one is not None:
            return pending.result() if not pending.cancel() else self._step_one(actions)
        if pending.cancel():
            obs, rewards, terminated, truncated, infos = self.venv.step(actions)
        else:
            obs, rewards, terminated, truncated, infos = pending.result()
        dones = np.logical_or(terminated, truncated)
        rewards = np.asarray(rewards, dtype=np.float32)
        self._returns += rewards
        self._lengths += 1
        finished = np.flatnonzero(dones)
        # A finished env's top-level info is its reset's; its step's is in `final_info`.
        step_infos = _per_env(infos, self.num_envs)
        if finished.size:
            final_infos = _per_env(infos.get("final_info", {}), self.num_envs)
            final_obs = infos["final_obs"]
            for i in finished:
                self.reset_infos[i] = step_infos[i]
                info = final_infos[i]
                info["terminal_observation"] = final_obs[i]
                info["episode"] = {
                    "r": float(self._returns[i]),
                    "l": int(self._lengths[i]),
                    "t": round(time.time() - self._start, 6),
                }
                step_infos[i] = info
            self._returns[finished] = 0.0
            self._lengths[finished] = 0
        for i in range(self.num_envs):
            step_infos[i]["TimeLimit.truncated"] = bool(truncated[i] and not terminated[i])
        return obs, rewards, dones, step_infos

    def _step_one(self, actions: np.ndarray) -> Any:
        """The one env's step, reset in the same step when it ends, as ``DummyVecEnv``
        steps a ``Monitor``-wrapped env."""
        env = self._one
        assert env is not None
        obs, reward, terminated, truncated, info = env.step(actions[0])
        self._returns[0] += reward
        self._lengths[0] += 1
        done = bool(terminated or truncated)
        info = dict(info)
        if done:
            info["terminal_observation"] = obs
            info["episode"] = {
                "r": float(self._returns[0]),
                "l": int(self._lengths[0]),
                "t": round(time.time() - self._start, 6),
            }
            obs, reset_info = env.reset()
            self.reset_infos[0] = reset_info
            self._returns[0] = 0.0
            self._lengths[0] = 0
        info["TimeLimit.truncated"] = bool(truncated and not terminated)
        return obs[None], np.array([reward], dtype=np.float32), np.array([done]), [info]

    def close(self) -> None:
        self._worker.shutdown(wait=True)
        self.venv.close()

    # -- what SB3 asks of the envs --------------------------------------------------------

    def get_images(self) -> Sequence[Optional[np.ndarray]]:
        frames = self.venv.render()
        if frames is None:
            return [None] * self.num_envs
        return [frames] if self._one is not None else list(frames)

    def has_attr(self, attr_name: str) -> bool:
        return hasattr(self.venv, attr_name)

    def get_attr(self, attr_name: str, indices: Indices = None) -> List[Any]:
        targets = list(self._get_indices(indices))
        value = getattr(self.venv, attr_name)
        return [value for _ in targets]

    def set_attr(self, attr_name: str, value: Any, indices: Indices = None) -> None:
        targets = list(self._get_indices(indices))
        if sorted(targets) != list(range(self.num_envs)):
            raise ValueError(
                f"GymfleetSb3VecEnv.set_attr({attr_name!r}): the envs are one batch; an "
                "attribute can be set for all of them only (indices=None)"
            )
        setattr(self.venv, attr_name, value)

    def env_method(
        self, method_name: str, *method_args: Any, indices: Indices = None, **method_kwargs: Any
    ) -> List[Any]:
        targets = list(self._get_indices(indices))
        if sorted(targets) != list(range(self.num_envs)):
            raise ValueError(
                f"GymfleetSb3VecEnv.env_method({method_name!r}): the envs are one batch; a "
                "method is called once for all of them (indices=None)"
            )
        result = getattr(self.venv, method_name)(*method_args, **method_kwargs)
        return [result for _ in targets]

    def env_is_wrapped(self, wrapper_class: Type[Any], indices: Indices = None) -> List[bool]:
        # The adapter writes SB3's Monitor's `episode` info itself.
        monitor = (
            wrapper_class.__name__ == "Monitor"
            and wrapper_class.__module__ == "stable_baselines3.common.monitor"
        )
        return [monitor for _ in self._get_indices(indices)]

    def __repr__(self) -> str:
        return f"GymfleetSb3VecEnv({self.venv!r})"


def _per_env(infos: Dict[str, Any], n: int) -> List[Dict[str, Any]]:
    """Gymnasium's vector info (a dict of arrays with ``_key`` masks, nested dicts alike) as
    one dict per env."""
    out: List[Dict[str, Any]] = [{} for _ in range(n)]
    for key, values in infos.items():
        if key.startswith("_") or key in ("final_obs", "final_info"):
            continue
        mask = infos.get(f"_{key}")
        nested = _per_env(values, n) if isinstance(values, dict) else None
        for i in range(n):
            if mask is None or mask[i]:
                out[i][key] = nested[i] if nested is not None else values[i]
    return out

""":class:`SuiteVectorEnv`: ``num_envs`` of one of Gymnasium's MuJoCo v5 envs as one
gymfleet batch, with Gymnasium's observations, rewards and ``info`` (``envs.py`` makes them
from the server's rows, as for the single env), and EnvPool's asynchronous API over the
batch's (``send``/``recv`` with ``batch_size``, ``step_async``/``step_wait``)."""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from ..pipeline import OverBatch
from ..vector import GymfleetVectorEnv
from .envs import (
    _Setup,
    _observed_terms,
    _reset_rows,
    _reset_values,
    _rewards,
    _step_values,
    _velocities_from_qpos,
    _zeros,
)


def _merged(
    parts: List[Tuple[np.ndarray, np.ndarray, np.ndarray, Dict[str, Any]]], n: int
) -> Tuple[np.ndarray, np.ndarray, Dict[str, Any]]:
    """One ``recv``'s observations, rewards and ``info`` from groups of its rows (a reset's
    and a step's), each ``(rows, observations, rewards, info)``: every key in the rows'
    order, with its mask off where a group has no value for it."""
    if len(parts) == 1:
        return parts[0][1], np.asarray(parts[0][2], dtype=np.float64), parts[0][3]
    first = parts[0][1]
    obs = np.empty((n,) + first.shape[1:], dtype=first.dtype)
    rewards = np.zeros(n, dtype=np.float64)
    infos: Dict[str, Any] = {}
    keys = [k for _, _, _, i in parts for k in i if not k.startswith("_")]
    for rows, o, r, _ in parts:
        obs[rows], rewards[rows] = o, r
    for key in dict.fromkeys(keys):
        present = [(rows, i) for rows, _, _, i in parts if key in i]
        sample = np.asarray(present[0][1][key])
        column = np.zeros((n,) + sample.shape[1:], dtype=sample.dtype) if sample.dtype != object else np.full(n, None, dtype=object)
        mask = np.zeros(n, dtype=np.bool_)
        for rows, i in present:
            column[rows] = i[key]
            mask[rows] = i.get("_" + key, True)
        infos[key], infos["_" + key] = column, mask
    return obs, rewards, infos


class SuiteVectorEnv(OverBatch, VectorEnv):
    """``num_envs`` of one of Gymnasium's MuJoCo v5 envs as one gymfleet batch; made by
    ``gymnasium.make_vec("gymfleet/<Name>-v5", num_envs)`` or ``gymfleet.make_vec``.
    Autoreset is the server's, in gymnasium's three modes."""

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
        max_episode_steps: Optional[int] = None,
        batch_size: Optional[int] = None,
        **kwargs: Any,
    ) -> None:
        setup = _Setup(env_id, kwargs)
        self._setup = setup
        limit = setup.suite.max_episode_steps if max_episode_steps is None else max_episode_steps
        self._envs = GymfleetVectorEnv(
            setup.model.text,
            num_envs,
            autoreset_mode=autoreset_mode,
            batch_size=batch_size,
            **setup.options(limit),
        )
        self._dofs, self._base = setup.check(self._envs.batch_info)
        self.num_envs = self._envs.num_envs
        self.render_mode = setup.kw["render_mode"]
        self.dt = setup.dt
        self.metadata = {
            **type(self).metadata,
            "render_fps": int(np.round(1.0 / self.dt)),
            "autoreset_mode": self._envs.metadata["autoreset_mode"],
        }
        setup.check_actions(self._envs.batch_info)
        self.single_action_space = self._envs.single_action_space
        self.single_observation_space = setup.observation_space()
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        #: The qpos rows before the next step (float64), for Gymnasium's Δqpos / dt.
        self._last_q: Optional[np.ndarray] = None

    @property
    def gymfleet_envs(self) -> GymfleetVectorEnv:
        """The server-side batch underneath."""
        return self._envs

    def _observe(
        self,
        raw: np.ndarray,
        terms: Dict[str, np.ndarray],
        split: Optional[Tuple[np.ndarray, np.ndarray, np.ndarray]] = None,
    ) -> np.ndarray:
        """The observations of rows ``raw``; ``split`` is their ``_Setup.split`` if known."""
        q, v, ee = self._setup.split(raw) if split is None else split
        terms = {**terms, **_observed_terms(raw, self._setup)}
        return self._setup.typed(self._setup.plan.observe(q, v, ee, terms))

    def _infos(self, values: Dict[str, np.ndarray], n: int) -> Dict[str, Any]:
        every = np.ones(n, dtype=np.bool_)
        out: Dict[str, Any] = {}
        for key, value in values.items():
            out[key] = np.asarray(value, dtype=np.float64)
            out["_" + key] = every
        return out

    def reset(
        self,
        *,
        seed: Union[int, Sequence[Optional[int]], None] = None,
        options: Optional[Dict[str, Any]] = None,
    ) -> Tuple[np.ndarray, Dict[str, Any]]:
        if seed is not None and isinstance(seed, (int, np.integer)):
            super().reset(seed=int(seed))
        raw, _ = self._envs.reset(seed=seed, options=options)
        split = self._setup.split(raw)
        self._last_q = split[0].astype(np.float64)
        # `_observe` adds the observed terms.
        terms = _zeros(self._envs.batch_info["term_names"], len(raw))
        infos = self._infos(_reset_values(self._setup.plan, split[0], split[1]), len(raw))
        return self._observe(raw, terms, split), infos

    # The asynchronous API (EnvPool's, over the batch's: `gymfleet/pipeline.py`).

    def recv(self, timeout: Optional[float] = None) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, Dict[str, Any]]:
        """The next :attr:`batch_size` envs that finished a step (or their reset), with
        Gymnasium's observations, rewards and ``info`` as :meth:`step` gives each env,
        and ``info["env_id"]``."""
        raw, rewards, terminated, truncated, raw_infos = self._envs.recv(timeout)
        ids = raw_infos.pop("env_id")
        names = self._envs.batch_info["term_names"]
        # A reset's rows carry no term values (their masks are off).
        fresh = ~raw_infos["_" + names[0]] if names and "_" + names[0] in raw_infos else np.ones(len(ids), dtype=bool)
        parts = []
        if fresh.any():
            rows = np.flatnonzero(fresh)
            split = self._setup.split(raw[rows])
            if self._last_q is None:
                self._last_q = np.zeros((self.num_envs, split[0].shape[1]), dtype=np.float64)
            self._last_q[ids[rows]] = split[0]
            zeros = _zeros(names, len(rows))
            infos = self._infos(_reset_values(self._setup.plan, split[0], split[1]), len(rows))
            parts.append((rows, self._observe(raw[rows], zeros, split), np.zeros(len(rows)), infos))
        if not fresh.all():
            rows = np.flatnonzero(~fresh)
            taken = {k: v[rows] for k, v in raw_infos.items()}
            obs, rew, _, _, infos = self._finish(raw[rows], rewards[rows], terminated[rows], truncated[rows], taken, ids[rows])
            parts.append((rows, obs, rew, infos))
        obs, rew, infos = _merged(parts, len(ids))
        infos["env_id"] = ids
        return obs, rew, np.asarray(terminated), np.asarray(truncated), infos

    def _finish(
        self,
        raw: np.ndarray,
        rewards: np.ndarray,
        terminated: np.ndarray,
        truncated: np.ndarray,
        raw_infos: Dict[str, Any],
        ids: Optional[np.ndarray] = None,
    ) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, Dict[str, Any]]:
        """Gymnasium's results of the server's step of every env, or of the envs ``ids``
        (rows in that order)."""
        n = len(raw)
        names = self._envs.batch_info["term_names"]
        terms = {name: raw_infos[name] for name in names}  # float64 arrays (`vector.py`)
        # The step's values come from the rows the step produced; with same-step autoreset
        # a finished env's row is already its next episode's first: its final row is kept
        # in `final_obs`, and the step's info (terms included) in `final_info`.
        rows = raw
        if "final_obs" in raw_infos:
            rows = raw.copy()
            for env in np.flatnonzero(raw_infos["_final_obs"]):
                rows[env] = raw_infos["final_obs"][env]
        split = self._setup.split(rows)
        q, v, _ = split
        plan = self._setup.plan
        values = _step_values(plan, q, v, terms)
        server_rewards = np.asarray(rewards, dtype=np.float64)
        # The returned rows' split (the rows after an autoreset): the next step's "before".
        raw_split = split if rows is raw else self._setup.split(raw)
        if plan.qpos_velocity:
            # As the single env; a row the server reset instead of stepping keeps its 0.
            stepped = ~_reset_rows(server_rewards, terms) if terms else True
            q64 = q.astype(np.float64)
            last = q64 if self._last_q is None else (self._last_q if ids is None else self._last_q[ids])
            _velocities_from_qpos(plan, values, last, q64, self.dt, stepped)
        if ids is None:
            self._last_q = raw_split[0].astype(np.float64)
        else:
            self._last_q[ids] = raw_split[0]
        infos = self._infos(values, n)
        # The returned rows' term values: an env reset in this step starts from zeros (the
        # server's, in next-step mode; here, in same-step mode).
        now = terms
        if "final_obs" in raw_infos:
            # As gymnasium's SyncVectorEnv in same-step mode: a finished env's info is its
            # reset's, and its step's info is in `final_info`.
            has_final = raw_infos["_final_obs"]
            ended = np.flatnonzero(has_final)
            final = np.full(n, None, dtype=object)
            ended_terms = {name: value[ended] for name, value in terms.items()}
            for env, row in zip(ended, self._observe(rows[ended], ended_terms)):
                final[env] = row
            now = {name: np.where(has_final, 0.0, value) for name, value in terms.items()}
            final_info = {k: (v & has_final if k.startswith("_") else v) for k, v in infos.items()}
            q_now, v_now, _ = raw_split
            reset = _reset_values(self._setup.plan, q_now, v_now)
            for key in values:
                if key in reset:
                    mask = has_final.reshape((-1,) + (1,) * (np.ndim(reset[key]) - 1))
                    infos[key] = np.where(mask, reset[key], infos[key])
                else:
                    infos["_" + key] = ~has_final
            for key in reset.keys() - values.keys():
                infos[key], infos["_" + key] = reset[key], has_final.copy()
            infos["final_obs"], infos["_final_obs"] = final, has_final
            infos["final_info"], infos["_final_info"] = final_info, has_final.copy()
        observation = self._observe(raw, now, raw_split)
        rewards = _rewards(plan, values, server_rewards, terms)
        return observation, rewards, terminated, truncated, infos

    def render(self) -> Optional[Tuple[np.ndarray, ...]]:
        return self._envs.render()

    def close_extras(self, **kwargs: Any) -> None:
        self._envs.close()

    def __reduce__(self) -> Any:
        raise TypeError(
            "a SuiteVectorEnv does not pickle: it is a batch on its server; make it again in "
            "the other process with gymnasium.make_vec (a single env pickles, with its state)"
        )

    def __repr__(self) -> str:
        return f"<SuiteVectorEnv {self._setup.suite.id} x {self.num_envs}>"

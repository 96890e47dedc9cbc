""":class:`GymfleetVectorEnv`: a server-side batch as a :class:`gymnasium.vector.VectorEnv`."""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from . import _core
from .errors import InvalidArgument
from .pipeline import Pipeline
from ._common import (
    ActionMap,
    HandleOwner,
    Document,
    action_kind,
    check_action_type,
    create_options,
    document_json,
    ENV_KEYWORDS,
    keyframe_name,
    located,
    named_draws,
    observation_space,
    state_bytes,
)

_MODES = {
    AutoresetMode.NEXT_STEP: "next_step",
    AutoresetMode.SAME_STEP: "same_step",
    AutoresetMode.DISABLED: "disabled",
}

_U64 = 1 << 64


def autoreset_mode(mode: Union[AutoresetMode, str]) -> AutoresetMode:
    """gymnasium's mode from the enum, its value (``"NextStep"``) or its name
    (``"NEXT_STEP"``, any case)."""
    if isinstance(mode, AutoresetMode):
        return mode
    if isinstance(mode, str):
        for m in AutoresetMode:
            if mode in (m.value, m.name) or mode.upper() == m.name:
                return m
    raise ValueError(
        f"autoreset_mode: expected a gymnasium.vector.AutoresetMode or one of "
        f"{[m.value for m in AutoresetMode]}, got {mode!r}"
    )


class GymfleetVectorEnv(HandleOwner, VectorEnv):
    """``num_envs`` gymfleet environments of one document, stepped together as one
    server-side batch (sharded over a fleet when ``server`` lists several servers).

    Use :func:`gymfleet.make_vec`. Autoreset is done by the server, in gymnasium's three
    modes: ``NEXT_STEP`` (the default), ``SAME_STEP`` (``infos["final_obs"]`` and
    ``infos["final_info"]``) and ``DISABLED`` (``reset(options={"reset_mask": mask})``).
    """

    metadata: Dict[str, Any] = {
        "render_modes": ["rgb_array"],
        "render_fps": 30,
        "autoreset_mode": AutoresetMode.NEXT_STEP,
    }

    def __init__(
        self,
        document: Optional[Document] = None,
        num_envs: int = 1,
        *,
        server: Optional[str] = None,
        autoreset_mode: Union[AutoresetMode, str] = AutoresetMode.NEXT_STEP,
        action_type: str = "torque",
        normalize_actions: bool = False,
        timeout: Optional[float] = None,
        render_mode: Optional[str] = None,
        render_options: Optional[Dict[str, Any]] = None,
        token: Optional[str] = None,
        batch_size: Optional[int] = None,
        **options: Any,
    ) -> None:
        if render_mode not in (None, "rgb_array"):
            raise ValueError(
                f"render_mode: {render_mode!r} is not supported (render_modes: ['rgb_array'])"
            )
        self.render_mode = render_mode
        # What made this batch, for `fork()`.
        self._creation: Dict[str, Any] = {
            "document": document,
            "num_envs": num_envs,
            "server": server,
            "autoreset_mode": autoreset_mode,
            "action_type": action_type,
            "normalize_actions": normalize_actions,
            "timeout": timeout,
            "render_mode": render_mode,
            "render_options": render_options,
            "token": token,
            "batch_size": batch_size,
            **options,
        }
        # Camera and size for `render()`, as for `GymfleetEnv`.
        self.render_options: Dict[str, Any] = dict(render_options or {})
        mode = globals()["autoreset_mode"](autoreset_mode)
        self.action_type = check_action_type(action_type)
        self._action_kind = action_kind(action_type)
        try:
            self._handle = _core.BatchHandle.create(
                server,
                document_json(document, options.get("model")),
                int(num_envs),
                _MODES[mode],
                create_options(options, (*ENV_KEYWORDS, "autoreset_mode"), document),
                timeout,
                token,
            )
        except InvalidArgument as err:
            raise located(err, document) from None
        self._info: Dict[str, Any] = self._handle.info
        self.num_envs = self._info["n_envs"]
        self.metadata = {**type(self).metadata, "autoreset_mode": mode}
        self._actions = ActionMap(self._info, action_type, normalize_actions)
        self.single_action_space = self._actions.space
        self.single_observation_space = observation_space(self._info)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self._action_dim = self._info["action_dim"]
        # Mocap targets for the next step (`set_mocap_poses`), flat; None: they stay.
        self._mocap_poses: Optional[np.ndarray] = None
        # The asynchronous API's state (`pipeline.py`), made at its first use.
        self._batch_size = self.num_envs if batch_size is None else batch_size
        Pipeline.check_batch_size(self._batch_size, self.num_envs)
        self._pipeline: Optional[Pipeline] = None
        self._pending_step: Optional[Any] = None

    @property
    def batch_info(self) -> Dict[str, Any]:
        """What the server(s) said about the batch; ``shards`` lists ``(server,
        batch_id, start, stop)`` per shard (where they are now: :meth:`recover` moves
        the lost ones)."""
        return self._info

    def reset(
        self,
        *,
        seed: Union[int, Sequence[Optional[int]], None] = None,
        options: Optional[Dict[str, Any]] = None,
    ) -> Tuple[np.ndarray, Dict[str, Any]]:
        """Resets every env, or those of ``options["reset_mask"]``. ``seed``: ``None``
        (generators continue), an int (env ``i`` gets ``seed + i``) or one seed (or
        ``None``) per env. ``options["keyframe"]`` (a name or an index of
        ``batch_info["keyframes"]``) starts them from one of the document's keyframes,
        the noise on top; without, from its initial keyframe, if any."""
        self._no_async("reset")
        if self._pipeline is not None:
            self._pipeline.drain()  # the steps sent are taken first
        keyframe = keyframe_name(self._info, options)
        mask = None
        if options is not None and "reset_mask" in options:
            mask = self._check_mask(options["reset_mask"])
        if seed is not None and not isinstance(seed, (int, np.integer)):
            seeds = list(seed)
            if len(seeds) != self.num_envs:
                raise ValueError(
                    f"If seeds are passed as a list the length must match "
                    f"num_envs={self.num_envs} but got length={len(seeds)}."
                )
        if seed is not None:
            # gymnasium's VectorEnv keeps a generator of its own, seeded the same way.
            super().reset(seed=int(seed) if isinstance(seed, (int, np.integer)) else None)
        chosen = np.ones(self.num_envs, dtype=bool) if mask is None else mask
        if seed is None or isinstance(seed, (int, np.integer)):
            indices = None if mask is None else np.flatnonzero(mask).astype(np.uint32)
            obs = self._handle.reset(None if seed is None else int(seed), indices, keyframe)
        else:
            obs = self._reset_per_env_seeds(list(seed), chosen, keyframe)
        return obs, {}

    def _reset_per_env_seeds(
        self, seeds: List[Optional[int]], chosen: np.ndarray, keyframe: str
    ) -> np.ndarray:
        # The server reseeds env i with `seed + i`: envs whose seeds share `seed_i - i`
        # (mod 2^64) are reset by one call, the unseeded ones by one more.
        groups: Dict[Optional[int], List[int]] = {}
        for i, s in enumerate(seeds):
            if chosen[i]:
                key = None if s is None else (int(s) - i) % _U64
                groups.setdefault(key, []).append(i)
        obs = None
        for key, envs in groups.items():
            obs = self._handle.reset(key, np.array(envs, dtype=np.uint32), keyframe)
        return obs if obs is not None else self._handle.observe()

    def _check_mask(self, mask: Any) -> np.ndarray:
        if not isinstance(mask, np.ndarray):
            raise TypeError(f"`options['reset_mask']` must be a numpy array, got {type(mask)}")
        if mask.shape != (self.num_envs,):
            raise ValueError(
                f"`options['reset_mask']` must have shape `({self.num_envs},)`, got {mask.shape}"
            )
        if mask.dtype != np.bool_:
            raise TypeError(f"`options['reset_mask']` must have `dtype=np.bool_`, got {mask.dtype}")
        if not np.any(mask):
            raise ValueError(
                "`options['reset_mask']` must contain a boolean array with at least one True "
                f"value, got reset_mask={mask}"
            )
        return mask

    def step(
        self, actions: Any, env_id: Any = None
    ) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, Dict[str, Any]]:
        """Steps every env once; ``actions`` is ``(num_envs, action_dim)``. Mocap targets
        set with :meth:`set_mocap_poses` travel with this step. With ``env_id``:
        EnvPool's ``send(actions, env_id)`` then ``recv()``."""
        if env_id is not None:
            self.send(actions, env_id)
            return self.recv()
        self._no_async("step")
        values = self._actions.to_server(actions).reshape(self.num_envs, self._action_dim)
        mocap, self._mocap_poses = self._mocap_poses, None
        return self._whole_step(values, mocap)

    def _whole_step(
        self, values: np.ndarray, mocap: Optional[np.ndarray]
    ) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, Dict[str, Any]]:
        return self._whole_result(self._handle.step(self._action_kind, values, mocap))

    def _whole_result(
        self, raw: Tuple[Any, ...]
    ) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, Dict[str, Any]]:
        """A whole step's reply (``BatchHandle.step``'s) as :meth:`step` returns it."""
        (
            obs,
            rewards,
            terminated,
            truncated,
            final_envs,
            final_obs,
            reasons,
            terms,
        ) = raw
        infos: Dict[str, Any] = {}
        # A terms task's values (the step's, before a same-step autoreset), one array per
        # term name, as gymnasium's vector envs write per-env info.
        if terms.shape[1]:
            every = np.ones(self.num_envs, dtype=np.bool_)
            # One conversion for every term (Humanoid has 308): each name's values are a
            # row of it.
            by_term = np.ascontiguousarray(terms.T, dtype=np.float64)
            for name, values in zip(self._info["term_names"], by_term):
                infos[name] = values
                infos["_" + name] = every
        why: Dict[str, Any] = {}
        if reasons:
            reason = np.full(self.num_envs, None, dtype=object)
            has_reason = np.zeros(self.num_envs, dtype=np.bool_)
            for env, text in reasons.items():
                reason[env] = text
                has_reason[env] = True
            why = {"termination_reason": reason, "_termination_reason": has_reason}
        if len(final_envs):
            # As gymnasium's SyncVectorEnv: the returned row is the reset observation; the
            # ended episode's last one (and its info: why it ended) are beside it.
            final = np.full(self.num_envs, None, dtype=object)
            has_final = np.zeros(self.num_envs, dtype=np.bool_)
            for row, env in enumerate(final_envs):
                final[env] = final_obs[row]
                has_final[env] = True
            infos["final_obs"], infos["_final_obs"] = final, has_final
            infos["final_info"], infos["_final_info"] = why, has_final.copy()
        else:
            infos.update(why)
        return obs, rewards, terminated, truncated, infos

    # The asynchronous API (EnvPool's, and AsyncVectorEnv's step_async/step_wait).

    def _async(self) -> Pipeline:
        if self._pipeline is None:
            self._pipeline = Pipeline(self, self._batch_size)
        return self._pipeline

    def _no_async(self, call: str) -> None:
        if self._pending_step is not None:
            raise RuntimeError(f"{call}: a step_async is pending; call step_wait first")

    @property
    def batch_size(self) -> int:
        """How many envs :meth:`recv` returns (``make_vec(..., batch_size=M)``; default
        ``num_envs``)."""
        return self._batch_size

    def async_reset(self) -> None:
        """Resets every env (as :meth:`reset` without a seed); their first observations
        are what the next :meth:`recv` calls return, in env order."""
        self._no_async("async_reset")
        pipeline = self._async()
        pipeline.drain()
        obs, infos = self.reset()
        pipeline.reset(obs, infos)

    def send(self, actions: Any, env_id: Any) -> None:
        """Steps the envs ``env_id`` (distinct, not in flight) with ``actions``
        (``(len(env_id), action_dim)``, in ``env_id``'s order) and returns at once; their
        results come back from :meth:`recv`. Each env steps as in :meth:`step`."""
        self._no_async("send")
        self._async().send(actions, env_id)

    def recv(self, timeout: Optional[float] = None) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, Dict[str, Any]]:
        """The next :attr:`batch_size` envs that finished, with ``info["env_id"]``; an
        error of a send is raised here, with the envs it concerns as its ``env_ids``."""
        return self._async().recv(timeout)

    def step_async(self, actions: Any) -> None:
        """Starts a step of every env (:meth:`step`'s) and returns at once: the trainer's
        work until :meth:`step_wait` overlaps the server's."""
        self._no_async("step_async")
        if self._pipeline is not None and self._pipeline.busy():
            raise RuntimeError("step_async: envs are in flight (send): recv them first")
        values = self._actions.to_server(actions).reshape(self.num_envs, self._action_dim)
        mocap, self._mocap_poses = self._mocap_poses, None
        self._pending_step = (self._async().submit(self._whole_step, values, mocap), values, mocap)

    def step_wait(self, timeout: Optional[float] = None) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, Dict[str, Any]]:
        """The result of the pending :meth:`step_async` (its error, if it failed)."""
        if self._pending_step is None:
            raise RuntimeError("step_wait: call step_async first")
        (pending, values, mocap), self._pending_step = self._pending_step, None
        # A step its worker has not started yet (the caller did nothing between that let
        # the worker run: SB3's `step` is `step_async` then `step_wait`) is taken back and
        # run on this thread, without the two thread hand-offs.
        if pending.cancel():
            return self._whole_step(values, mocap)
        return pending.result(timeout)

    def _step_columns(self, ids: np.ndarray, values: np.ndarray) -> Tuple[Any, ...]:
        """Steps the envs ``ids`` (ascending) on the server; their results column by
        column (see :meth:`_columns`), for :class:`Pipeline`."""
        return self._columns(self._handle.step_envs(self._action_kind, ids, values))

    @staticmethod
    def _columns(step: Tuple[Any, ...]) -> Tuple[Any, ...]:
        """A subset step's rows (``BatchHandle.step_envs``'s) column by column:
        observations, rewards, terminated, truncated, term values, and the termination
        reasons and final observations by env id."""
        obs, rewards, terminated, truncated, final_envs, final_obs, reasons, terms = step
        finals = {int(env): final_obs[k] for k, env in enumerate(final_envs)}
        return (obs, np.asarray(rewards, dtype=np.float32), np.asarray(terminated, dtype=np.bool_),
                np.asarray(truncated, dtype=np.bool_), np.asarray(terms), dict(reasons), finals)

    # Fleet recovery (a gymfleet extension; the Rust client's `FleetBatch::recover`).

    def checkpoint_every(self, steps: int) -> None:
        """Checkpoints every env's state every ``steps`` steps (whole or :meth:`send`'s;
        0: stops), starting now, and logs what is done since, so that :meth:`recover`
        can rebuild the envs of a server that is lost."""
        if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 0:
            raise ValueError(f"steps: expected a non-negative integer, got {steps!r}")
        self._no_async("checkpoint_every")
        if self._pipeline is not None:
            self._pipeline.drain()
        self._handle.checkpoint_every(int(steps))

    def recover(
        self, server: Optional[str] = None
    ) -> Optional[Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, Dict[str, Any]]]:
        """After :class:`ServerLost`: rebuilds the lost server's envs from the last
        checkpoint on ``server`` (``None``: the surviving servers), replays what was done
        since, and goes on with every env in its place, as if nothing had been lost.

        The survivors had taken the step that found the loss. From :meth:`step`, that
        step's result (every env's) is returned. In the asynchronous API, the envs of the
        send that found the loss come back from :meth:`recv` with that step's result,
        and the sends refused after it (they stepped nowhere) go out again: nothing is
        lost or stepped twice. Returns ``None`` then, or when nothing was lost."""
        self._no_async("recover")
        pipeline = self._pipeline
        if pipeline is not None:
            pipeline.drain()
        try:
            found = self._handle.recover(server)
        finally:
            # Rebuilt shards live elsewhere now, even if another failed (the only change
            # to the batch's info).
            self._info["shards"] = self._handle.info["shards"]
        if pipeline is not None:
            pipeline.recovered(found)
        if found is None or len(found[0]):
            return None
        return self._whole_result(found[1])

    def set_mocap_poses(self, poses: Any) -> None:
        """Sets where every env's mocap bodies (``env_info["mocap_bodies"]``) are to be at
        the end of the next step: ``poses`` is ``(num_envs, mocap bodies, 7)``, each
        ``[x, y, z, qw, qx, qy, qz]`` (world mm, or m with ``units="si"``). They travel with
        that step's request (no call of their own) and stay until set again."""
        m = len(self._info["mocap_bodies"])
        array = np.asarray(poses, dtype=np.float32)
        if array.size != self.num_envs * m * 7:
            raise ValueError(
                f"poses: expected {self.num_envs} envs × {m} mocap bodies × 7 values "
                f"(x, y, z, qw, qx, qy, qz), got an array of shape {array.shape}"
            )
        self._mocap_poses = np.ascontiguousarray(array.reshape(-1))

    def randomization(self, env_index: int) -> Dict[str, Any]:
        """Env ``env_index``'s domain-randomisation factors drawn at its last reset (see
        :meth:`GymfleetEnv.randomization`)."""
        return named_draws(self._handle.randomization(int(env_index)))

    def render(self) -> Optional[Tuple[np.ndarray, ...]]:
        """With ``render_mode="rgb_array"``: one picture per env (a ``height x width x 3``
        uint8 array each), as gymnasium's vector envs return them; one ``Render`` call per
        env, so a large batch renders slowly. Without a render mode: ``None``."""
        if self.render_mode is None:
            gym.logger.warn(
                "render() was called without a render_mode; make the envs with "
                'render_mode="rgb_array"'
            )
            return None
        return tuple(self.picture(i, **self.render_options) for i in range(self.num_envs))

    def picture(
        self,
        env_index: int,
        camera: str = "iso",
        width: int = 0,
        height: int = 0,
        eye: Optional[Tuple[float, float, float]] = None,
        target: Optional[Tuple[float, float, float]] = None,
        fov_deg: float = 0.0,
        orthographic: bool = False,
    ) -> np.ndarray:
        """A picture of env ``env_index`` now (see :meth:`GymfleetEnv.picture`)."""
        return self._handle.render(
            int(env_index), camera, int(width), int(height), eye, target, float(fov_deg),
            bool(orthographic),
        )

    def observe(self) -> np.ndarray:
        """Every env's current observation, without stepping."""
        return self._handle.observe()

    def set_heightfield(
        self, name: str, heights: Any, env_indices: Optional[Sequence[int]] = None
    ) -> None:
        """:meth:`GymfleetEnv.set_heightfield` for the envs at ``env_indices`` (ascending,
        distinct; ``None``: every env), the same heights for each."""
        if env_indices is not None and len(env_indices) == 0:
            return
        array = np.asarray(heights, dtype=np.float32).reshape(-1)
        self._handle.set_heightfield(str(name), array.tolist(), self._indices(env_indices))

    def save_states(self, env_indices: Optional[Sequence[int]] = None) -> List[bytes]:
        """The saved states (see :meth:`GymfleetEnv.save_state`) of the envs at
        ``env_indices`` (ascending, distinct; ``None``: every env), in that order."""
        if env_indices is not None and len(env_indices) == 0:
            return []
        return self._handle.save_states(self._indices(env_indices))

    def load_states(
        self, states: Sequence[bytes], env_indices: Optional[Sequence[int]] = None
    ) -> np.ndarray:
        """Loads ``states[k]`` into the env at ``env_indices[k]`` (``None``: every env,
        one state each) and returns every env's observation. States of another document
        or options are ``InvalidArgument``."""
        blobs = [state_bytes(f"states[{k}]", s) for k, s in enumerate(states)]
        if env_indices is not None and len(env_indices) == 0 and not blobs:
            return self.observe()
        return self._handle.load_states(blobs, self._indices(env_indices))

    def fork(self) -> "GymfleetVectorEnv":
        """A new batch on the same server(s), made with this batch's document and options
        and put in its envs' states now (see :meth:`GymfleetEnv.fork`): the two then run
        independently. The caller closes it."""
        twin = GymfleetVectorEnv(**self._creation)
        try:
            twin.load_states(self.save_states())
        except BaseException:
            twin.close()
            raise
        return twin

    @staticmethod
    def _indices(env_indices: Optional[Sequence[int]]) -> Optional[np.ndarray]:
        if env_indices is None:
            return None
        return np.asarray(list(env_indices), dtype=np.uint32).reshape(-1)

    def close_extras(self, **kwargs: Any) -> None:
        """Frees the batch on its server(s), after the steps in flight. A server that is
        gone has nothing left to free, so that is not an error."""
        if self._pipeline is not None:
            self._pipeline.close()
        self._close_handle()

    def __reduce__(self) -> Any:
        raise TypeError(
            "a GymfleetVectorEnv does not pickle: it is a batch on its server; make it again "
            "in the other process (a single GymfleetEnv pickles, with its state)"
        )

    def __repr__(self) -> str:
        return f"<GymfleetVectorEnv {self._info['batch_id']} ({self.num_envs} envs)>"

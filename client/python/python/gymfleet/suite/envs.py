""":class:`SuiteEnv` (and what :class:`~gymfleet.suite.vector_env.SuiteVectorEnv` shares
with it): Gymnasium's MuJoCo v5 environments on a gymfleet server, with Gymnasium's
observation, reward, termination and ``info``.

The server simulates the XML file of the installed gymnasium package (converted on the
server), in SI units, with actions as MuJoCo's ctrl (torque = gear · clip(ctrl)), one
MuJoCo timestep per substep and ``frame_skip`` substeps per env step, and computes the
reward terms inside the step. This module only picks the observation's entries out of
the server's SI joint state (Gymnasium's ``qpos[k:]``, ``clip(qvel)``) and names the
term values as Gymnasium's ``info`` does.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Dict, Iterator, Optional, Sequence, Tuple

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from ..env import GymfleetEnv
from ..errors import InvalidArgument
from .model import Model, read_model
from .plans import OBSERVED, Plan, Terms
from .kinematics import segments, server_state, split_rows
from .state import (
    BodyLayout,
    FrameCache,
    SuiteData,
    SuiteModel,
    checked_state,
    qpos_qvel,
    state_vector,
)
from .specs import IGNORED_KWARGS, SUITE, SuiteSpec

#: A single env's server-side episode limit: none that matters; gymnasium's TimeLimit
#: (``max_episode_steps`` on the spec) truncates.
_NO_LIMIT = (1 << 32) - 1


class _Setup:
    """What both classes build from an id and its keywords."""

    def __init__(self, env_id: str, kwargs: Dict[str, Any]) -> None:
        if env_id not in SUITE:
            raise InvalidArgument(
                f"env_id: {env_id!r} is not one of gymfleet's Gymnasium ids ({', '.join(SUITE)})"
            )
        self.suite: SuiteSpec = SUITE[env_id]
        self.kw = self.suite.kwargs(kwargs)
        for name in IGNORED_KWARGS:
            if name in kwargs:
                gym.logger.warn(
                    f"{env_id}: {name} is ignored (gymfleet renders with its own renderer)"
                )
        self.model: Model = read_model(str(self.kw["xml_file"]))
        self.plan: Plan = self.suite.plan(self.model, self.kw)
        #: The terms the server observes (the observation's tail), in order.
        self.observed = [t["name"] for t in self.plan.task.get("terms", []) if t.get("observe")]
        self.frame_skip = int(self.kw["frame_skip"])
        self.dt = self.model.timestep * self.frame_skip
        render_mode = self.kw["render_mode"]
        if render_mode not in (None, "rgb_array"):
            raise InvalidArgument(
                f"render_mode: {render_mode!r} is not supported (render_modes: ['rgb_array'])"
            )

    def options(self, max_steps: int) -> Dict[str, Any]:
        return {
            "server": self.kw["server"],
            "timeout": self.kw["timeout"],
            "token": self.kw["token"],
            "units": "si",
            "dt": self.dt,
            "substeps": self.frame_skip,
            "max_steps": int(max_steps),
            "task": self.plan.task,
            "end_effector_ids": list(self.plan.end_effectors),
            "render_mode": self.kw["render_mode"],
            "render_options": {"width": int(self.kw["width"]), "height": int(self.kw["height"])},
        }

    def check(self, info: Dict[str, Any]) -> Tuple[int, bool]:
        """The converted robot's joints must be MuJoCo's, in qpos order, one DOF each,
        and its floating base MuJoCo's free joint; returns the number of DOFs and whether
        the base is observed."""
        names = [j["name"] for j in info["joints"]]
        dofs = sum(j["dof"] for j in info["joints"])
        if names != self.model.joints or dofs != len(names):
            raise InvalidArgument(
                f"{self.suite.id}: {self.model.path} converts to joints {names} ({dofs} DOFs); "
                f"the env needs MuJoCo's {self.model.joints}, one DOF each"
            )
        #: Where each of the server's observation segments lies in a row, by name.
        self.segments = segments(info["observation_layout"])
        base = "base_pose" in self.segments
        self.dofs, self.base = dofs, base
        if base != (self.model.free is not None):
            raise InvalidArgument(
                f"{self.suite.id}: {self.model.path} converts "
                f"{'with' if base else 'without'} a floating base; MuJoCo's model has "
                f"{'a' if self.model.free is not None else 'no'} free joint"
            )
        return dofs, base

    def check_actions(self, info: Dict[str, Any]) -> None:
        """Gymnasium's actions are MuJoCo's ctrl, in actuator order, and so are the
        server's for a converted MJCF (its actuated joints when its motors are in joint
        order, else its actuators): checks that the server's action drives MuJoCo's
        actuators' joints, in that order."""
        driven = [j["name"] for j in info["joints"] if j.get("actuated", True)]
        driven += [a["target"] for a in info.get("actuators") or []]
        if driven != self.model.actuators:
            raise InvalidArgument(
                f"{self.suite.id}: {self.model.path}'s actuators drive {self.model.actuators}; "
                f"the converted robot's actions drive {driven}"
            )

    def split(self, raw: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """MuJoCo's qpos and qvel and the end effectors' positions of raw rows (after
        ``check``)."""
        return split_rows(raw, self.segments, self.model.root_geom)

    def observation_space(self) -> spaces.Box:
        # float32 by default where Gymnasium's is float64 (the server's values are float32);
        # `dtype=np.float64` gives Gymnasium's type, the same values widened.
        return spaces.Box(-np.inf, np.inf, shape=(self.plan.observation_dim,), dtype=self.kw["dtype"])

    def typed(self, observations: np.ndarray) -> np.ndarray:
        """Observations as the float32 the server's values make, then in the env's dtype."""
        return observations.astype(np.float32, copy=False).astype(self.kw["dtype"], copy=False)


def _zeros(names: Sequence[str], n: int) -> Dict[str, np.ndarray]:
    """Term values at a reset: zeros."""
    return {name: np.zeros(n, dtype=np.float64) for name in names}


def _first(x: np.ndarray) -> Any:
    """One env's info value from (1, ...) rows: a float, or an array (the tendons')."""
    return float(x[0]) if np.ndim(x) == 1 else np.asarray(x[0], dtype=np.float64)


def _scalar(x: Any) -> Any:
    """One env's info value: a float as it is, a (1, ...) row's first entry otherwise."""
    if type(x) is float:
        return x
    if type(x) is np.ndarray and x.shape == (1,):
        return x.item() if x.dtype == np.float64 else float(x[0])
    return float(x) if np.ndim(x) == 0 else _first(x)


class _TermValues(Mapping):
    """A single env's term values by name, read without a dict built per step: Python
    floats (``values`` a list) for the plan's info and reward, or (1,) float64 rows
    (``values`` a float64 array, each row a view) for its ``observe``, with the observed
    block under ``OBSERVED`` (``extra``)."""

    def __init__(self, values: Any, index: Dict[str, int], extra: Optional[Dict[str, np.ndarray]] = None) -> None:
        self._values, self._index, self._extra = values, index, extra or {}
        self._rows = isinstance(values, np.ndarray)

    def __getitem__(self, name: str) -> Any:
        if name in self._extra:
            return self._extra[name]
        k = self._index[name]
        return self._values[k : k + 1] if self._rows else self._values[k]

    def __iter__(self) -> Iterator[str]:
        return iter([*self._index, *self._extra])

    def __len__(self) -> int:
        return len(self._index) + len(self._extra)


def _reset_values(plan: Plan, q: np.ndarray, v: np.ndarray) -> Dict[str, np.ndarray]:
    q64, v64 = q.astype(np.float64), v.astype(np.float64)
    return {**plan.reset_info(q64), **plan.tendon_info(q64, v64)}


def _step_values(plan: Plan, q: np.ndarray, v: np.ndarray, terms: Terms) -> Dict[str, np.ndarray]:
    q64, v64 = q.astype(np.float64), v.astype(np.float64)
    return {**plan.step_info(q64, terms), **plan.tendon_info(q64, v64)}


def _rewards(
    plan: Plan, values: Dict[str, np.ndarray], server: np.ndarray, terms: Terms
) -> np.ndarray:
    """The step's rewards (n,), float64: Gymnasium's sum of the step's info terms, in its
    order, so that it equals the same sum taken of ``info`` exactly (the server's reward is
    that sum in float32). A row the server reset instead of stepping (next-step autoreset:
    its reward and every term 0) keeps the server's 0."""
    if plan.reward is None:
        return server.astype(np.float64)
    summed = np.asarray(plan.reward(values), dtype=np.float64)
    if terms:
        summed = np.where(_reset_rows(server, terms), 0.0, summed)
    return summed


def _reset_rows(server: np.ndarray, terms: Terms) -> np.ndarray:
    """The rows the server reset instead of stepping (next-step autoreset): their reward
    and every term 0. Stops reading terms once no row is left: a step whose rewards are
    all non-zero reads none (Humanoid's 300-odd terms cost 0.35 ms a step otherwise)."""
    reset = server == 0.0
    for value in terms.values():
        if not reset.any():
            break
        reset &= np.asarray(value) == 0.0
    return reset


def _initial_state(setup: _Setup) -> Tuple[np.ndarray, np.ndarray]:
    """The env's qpos and qvel without reset noise (float64): a twin made without the
    task's ``reset_noise``, observed at creation, then closed."""
    options = setup.options(_NO_LIMIT)
    options["task"] = {k: v for k, v in setup.plan.task.items() if k != "reset_noise"}
    options["render_mode"] = None
    twin = GymfleetEnv(setup.model.text, **options)
    try:
        setup.check(twin.env_info)
        q, v, _ = setup.split(twin.observe()[None, :])
    finally:
        twin.close()
    return tuple(np.array(x) for x in qpos_qvel(q, v))  # type: ignore[return-value]


def _velocities_from_qpos(
    plan: Plan,
    values: Dict[str, np.ndarray],
    before: np.ndarray,
    after: np.ndarray,
    dt: float,
    stepped: Any = True,
) -> None:
    """Gymnasium's ``x_velocity`` (and ``y_velocity``) where it is ``Δqpos / dt``: from
    the qpos rows (n, nq) before and after the step, in float64 as Gymnasium takes it (the
    server's term is the same difference, rounded to float32 on the wire), and the forward
    reward from it. Rows where ``stepped`` is false (the server reset them instead) keep
    the server's value."""
    if not plan.qpos_velocity:
        return
    for key, k in plan.qpos_velocity.items():
        values[key] = np.where(stepped, (after[:, k] - before[:, k]) / dt, values[key])
    if "reward_forward" in values:
        values["reward_forward"] = plan.forward_weight * values["x_velocity"]


def _observed_terms(raw: np.ndarray, setup: "_Setup") -> Dict[str, np.ndarray]:
    """The observed terms' values, under ``OBSERVED``: the rows' ``terms`` segment (the
    server reads them from the state at resets too, where the step's term values are not
    sent), in the task's order, as one block (Humanoid observes 303 terms)."""
    if not setup.observed:
        return {}
    return {OBSERVED: raw[:, setup.segments["terms"]]}


class SuiteEnv(gym.Env):
    """One of Gymnasium's MuJoCo v5 envs on gymfleet; made by
    ``gymnasium.make("gymfleet/<Name>-v5", **gymnasium_kwargs)``."""

    metadata: Dict[str, Any] = {"render_modes": ["rgb_array"], "render_fps": 30}

    def __init__(self, env_id: str, **kwargs: Any) -> None:
        setup = _Setup(env_id, kwargs)
        #: What it was made from, for pickling.
        self._made_with = (env_id, dict(kwargs))
        self._setup = setup
        # MuJoCo's init_qpos and init_qvel (qpos0, zeros): where this engine starts, without
        # reset noise. An env is reset with noise when it is created, so a twin without the
        # noise says where (made and closed first: a server with room for one env has room).
        self.init_qpos, self.init_qvel = _initial_state(setup)
        self._env = GymfleetEnv(setup.model.text, **setup.options(_NO_LIMIT))
        observed = set(setup.observed)
        #: Where each term the plan reads by name lies in a step's term values.
        self._term_index = {
            name: k for k, name in enumerate(self._env.env_info["term_names"]) if name not in observed
        }
        self._dofs, self._base = setup.check(self._env.env_info)
        self.render_mode = setup.kw["render_mode"]
        self.frame_skip = setup.frame_skip
        self.dt = setup.dt
        setup.check_actions(self._env.env_info)
        self.action_space = self._env.action_space
        self.observation_space = setup.observation_space()
        self.metadata = {**type(self).metadata, "render_fps": int(np.round(1.0 / self.dt))}
        self._qpos, self._qvel = self.init_qpos.copy(), self.init_qvel.copy()
        self._ctrl = np.zeros(self.action_space.shape, dtype=np.float64)
        self._layout = BodyLayout.read(setup.model.text)
        #: The body-level fields of `data`, read from the server on first use per state.
        self._frames = FrameCache(self._env, self._layout, self._base, lambda: self._qpos)
        self._model = SuiteModel(
            len(self.init_qpos), len(self.init_qvel), setup.model.timestep,
            np.stack([self.action_space.low, self.action_space.high], axis=1),
            self._layout, self._frames,
        )
        if setup.suite.structure is not None:
            #: Gymnasium v5's: how many observation entries each part takes, in order
            #: (``skipped_qpos``: the qpos entries left out). Not on Reacher, Pusher and
            #: InvertedDoublePendulum, as on Gymnasium's.
            self.observation_structure = setup.suite.structure(
                setup.kw, self._model.nq, self._model.nv, self._model.nbody
            )

    @property
    def gymfleet_env(self) -> GymfleetEnv:
        """The server-side env underneath (SI joint state, term values in its info)."""
        return self._env

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[Dict[str, Any]] = None
    ) -> Tuple[np.ndarray, Dict[str, Any]]:
        super().reset(seed=seed)
        raw, _ = self._env.reset(seed=seed)
        q, v, ee = self._setup.split(raw[None, :])
        self._qpos, self._qvel = qpos_qvel(q, v)
        self._ctrl = np.zeros_like(self._ctrl)
        self._frames.clear()
        info = {k: _first(x) for k, x in _reset_values(self._setup.plan, q, v).items()}
        terms = _zeros(self._env.env_info["term_names"], 1)
        terms.update(_observed_terms(raw[None, :], self._setup))
        return self._setup.typed(self._setup.plan.observe(q, v, ee, terms)[0]), info

    def step(self, action: Any) -> Tuple[np.ndarray, float, bool, bool, Dict[str, Any]]:
        # As Gymnasium's MujocoEnv.do_simulation: the action is one value per actuator, in
        # that shape (a (3, 1) array is not Hopper's action).
        shape = np.shape(action)
        if shape != self.action_space.shape:
            raise ValueError(
                f"Action dimension mismatch. Expected {self.action_space.shape}, found {shape}"
            )
        raw, reward, terminated, truncated, term_values = self._env.step_terms(action)
        setup, plan = self._setup, self._setup.plan
        rows = raw[None, :]
        q, v, ee = setup.split(rows)
        before = self._qpos
        self._qpos, self._qvel = qpos_qvel(q, v)
        self._ctrl = np.array(action, dtype=np.float64)
        self._frames.clear()
        # The plan's arithmetic on Python floats (float64): bit for bit what it does on a
        # batch's (n,) float64 arrays, without an array per value.
        scalars = _TermValues(term_values.tolist(), self._term_index)
        q64, v64 = self._qpos[None, :], self._qvel[None, :]
        values = {**plan.step_info(q64, scalars), **plan.tendon_info(q64, v64)}
        for key, k in plan.qpos_velocity.items():
            values[key] = (float(self._qpos[k]) - float(before[k])) / self.dt
        if plan.qpos_velocity and "reward_forward" in values:
            values["reward_forward"] = plan.forward_weight * values["x_velocity"]
        info = {k: _scalar(x) for k, x in values.items()}
        # A single env steps every call (no autoreset): no reset rows to tell apart.
        summed = float(plan.reward(info)) if plan.reward is not None else float(reward)
        rows64 = np.asarray(term_values, dtype=np.float64)
        terms = _TermValues(rows64, self._term_index, _observed_terms(rows, setup))
        obs = setup.typed(plan.observe(q, v, ee, terms)[0])
        return obs, summed, bool(terminated), bool(truncated), info

    @property
    def data(self) -> SuiteData:
        """The state after the last reset, step or ``set_state``, as MuJoCo's ``MjData``
        names it (SI, MuJoCo's layouts; read-only): see :class:`SuiteData`."""
        return SuiteData(self._qpos, self._qvel, self._ctrl, self._frames, self._layout)

    @property
    def model(self) -> SuiteModel:
        """``nq``, ``nv``, ``nu``, ``nbody``, ``nsite``, ``body_mass``, ``opt.timestep``,
        ``actuator_ctrlrange``, as MuJoCo's ``MjModel`` names them."""
        return self._model

    def set_state(self, qpos: Any, qvel: Any) -> None:
        """MuJoCo's ``set_state``: puts the robot in the state ``qpos`` (nq) and ``qvel``
        (nv), MuJoCo's layouts; the episode goes on. Only a wrong shape or a non-finite
        value is refused (``InvalidArgument``, nothing changes). A position past a hard
        limit is set at the limit (MuJoCo's limits are soft: recorded states sit slightly
        past them), and a joint on a kinematic loop keeps its position, each with a
        warning. ``data.qpos`` and ``data.qvel`` are the values given until the next step,
        as MuJoCo's are; the physics holds them as float32, clamped as warned, and the
        body-level fields of ``data`` read that state."""
        qpos, qvel = checked_state(qpos, qvel, self._model.nq, self._model.nv)
        positions, velocities, base = server_state(qpos, qvel, self._base, self._setup.model.root_geom)
        _, warnings = self._env.set_joint_state(positions, velocities, base)
        for warning in warnings:
            gym.logger.warn(f"set_state: {warning}")
        self._qpos, self._qvel = qpos, qvel
        self._frames.clear()

    def get_body_com(self, body_name: str) -> np.ndarray:
        """As Gymnasium's ``MujocoEnv.get_body_com``: the body's ``xpos`` (its frame's
        origin, world)."""
        return self.data.body(body_name).xpos

    def state_vector(self) -> np.ndarray:
        """``concatenate(qpos, qvel)``, as MuJoCo's envs give it."""
        return state_vector(self._qpos, self._qvel)

    def render(self) -> Optional[np.ndarray]:
        return self._env.render()

    def close(self) -> None:
        self._env.close()
        super().close()

    def __getstate__(self) -> Dict[str, Any]:
        """What a pickle holds: the id and keyword arguments, as Gymnasium's MuJoCo envs
        (``EzPickle``) rebuild from theirs, and, a gymfleet extension, the server-side
        env's pickle (its saved state). Unpickling makes the env again on the same server
        (``server=None``: the unpickling process's embedded one) and puts it in that state,
        so an env that has stepped continues bit for bit as the original would."""
        env_id, kwargs = self._made_with
        return {"env_id": env_id, "kwargs": kwargs, "state": self._env.saved_state_or_none(),
                "spec": self.spec, "np_random": self._np_random}

    def __setstate__(self, pickled: Dict[str, Any]) -> None:
        self.__init__(pickled["env_id"], **pickled["kwargs"])  # type: ignore[misc]
        self.spec = pickled["spec"]
        self._np_random = pickled["np_random"]
        if pickled["state"] is not None:
            q, v, _ = self._setup.split(self._env.load_state(pickled["state"])[None, :])
            self._qpos, self._qvel = qpos_qvel(q, v)

    def __repr__(self) -> str:
        return f"<SuiteEnv {self._setup.suite.id} on {self._env.server}>"

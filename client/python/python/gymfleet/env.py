""":class:`GymfleetEnv`: one server-side environment as a :class:`gymnasium.Env`."""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Tuple

import gymnasium as gym
import numpy as np
from gymnasium.envs.registration import EnvSpec

from . import _core
from .errors import FailedPrecondition, InvalidArgument
from ._common import (
    ActionMap,
    HandleOwner,
    Document,
    action_kind,
    check_action_type,
    create_options,
    document_json,
    keyframe_name,
    located,
    named_draws,
    observation_space,
    seed_or_none,
    state_bytes,
)


class GymfleetEnv(HandleOwner, gym.Env):
    """A gymfleet environment: the robot of ``document``, simulated on a server.

    Use :func:`gymfleet.make`, which takes the same arguments. The observation is the
    measured joint positions (deg or mm), joint velocities (deg/s or mm/s) and one
    ``[x, y, z, qw, qx, qy, qz]`` pose per end effector (mm, world frame), as float32.
    """

    metadata: Dict[str, Any] = {"render_modes": ["rgb_array"], "render_fps": 30}

    def __init__(
        self,
        document: Optional[Document] = None,
        *,
        server: Optional[str] = None,
        action_type: str = "torque",
        normalize_actions: bool = False,
        timeout: Optional[float] = None,
        render_mode: Optional[str] = None,
        render_options: Optional[Dict[str, Any]] = None,
        token: Optional[str] = None,
        **options: Any,
    ) -> None:
        if render_mode not in (None, "rgb_array"):
            raise ValueError(
                f"render_mode: {render_mode!r} is not supported (render_modes: ['rgb_array'])"
            )
        self.render_mode = render_mode
        # Camera and size for `render()`: camera ("iso", "front", "side", "top"), width,
        # height, eye, target, fov_deg, orthographic (see `GymfleetEnv.render`).
        self.render_options: Dict[str, Any] = dict(render_options or {})
        self.action_type = check_action_type(action_type)
        self._action_kind = action_kind(action_type)
        text = document_json(document, options.get("model"))
        try:
            self._handle = _core.EnvHandle.create(
                server, text, create_options(options, document=document), timeout, token
            )
        except InvalidArgument as err:
            raise located(err, document) from None
        # gymnasium.make sets the spec of registered envs; one made here gets its own, so
        # `gymnasium.make(env.spec)` (and gymnasium's tools that use it) re-create it.
        self.spec = EnvSpec(
            id="gymfleet/Document-v0",
            entry_point="gymfleet.env:GymfleetEnv",
            kwargs={
                "document": text or None,
                "server": server,
                "action_type": action_type,
                "normalize_actions": normalize_actions,
                "timeout": timeout,
                "render_mode": render_mode,
                "render_options": render_options,
                **options,
            },
        )
        # The token stays out of the spec (which gets printed and logged).
        self._token = token
        self._info: Dict[str, Any] = self._handle.info
        self._actions = ActionMap(self._info, action_type, normalize_actions)
        self.action_space = self._actions.space
        self.observation_space = observation_space(self._info)
        self.metadata = {**type(self).metadata, "render_fps": max(1, round(1.0 / self._info["dt"]))}

    @property
    def env_id(self) -> str:
        """The env's id on its server, ``"sim_<n>"``."""
        return self._info["env_id"]

    @property
    def server(self) -> str:
        """The address of the server the env lives on."""
        return self._info["server"]

    @property
    def env_info(self) -> Dict[str, Any]:
        """What the server said about the env: dims, dt, substeps, max_steps, joints
        (with their limits and ``max_effort``)."""
        return self._info

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[Dict[str, Any]] = None
    ) -> Tuple[np.ndarray, Dict[str, Any]]:
        """Resets the episode. With ``seed``, the env's generator (``reset_noise``) is
        reseeded first; without, it continues. ``options={"keyframe": name_or_index}``
        starts from one of the document's keyframes (``env_info["keyframes"]``), the
        noise on top; without, from its initial keyframe, if any, else its pose."""
        super().reset(seed=seed)
        obs = self._handle.reset(seed_or_none(seed), keyframe_name(self._info, options))
        return obs, {}

    def step_terms(self, action: Any) -> Tuple[np.ndarray, float, bool, bool, Any]:
        """:meth:`step` without its ``info`` dict: the observation, reward, flags and the
        terms task's values (in ``env_info["term_names"]`` order), for wrappers that make
        their own ``info`` (the suite's v5 envs)."""
        values = self._actions.to_server(action).reshape(-1)
        obs, reward, terminated, truncated, _, _, terms = self._handle.step(self._action_kind, values)
        return obs, reward, terminated, truncated, terms

    def step(self, action: Any) -> Tuple[np.ndarray, float, bool, bool, Dict[str, Any]]:
        """One env step of ``dt`` seconds; ``action`` has one value per DOF."""
        values = self._actions.to_server(action).reshape(-1)
        obs, reward, terminated, truncated, reason, episode_step, terms = self._handle.step(
            self._action_kind, values
        )
        info: Dict[str, Any] = {"episode_step": episode_step}
        for name, value in zip(self._info["term_names"], terms):
            info[name] = float(value)
        if reason is not None:
            info["termination_reason"] = reason
        return obs, float(reward), terminated, truncated, info

    def set_mocap_pose(self, name: str, pos: Any, quat: Any = (1.0, 0.0, 0.0, 0.0)) -> None:
        """Sets where mocap body ``name`` (one of ``env_info["mocap_bodies"]``) is to be at
        the end of the next step, and stay: ``pos`` is ``(x, y, z)`` in the world (mm, or
        m with ``units="si"``), ``quat`` its orientation ``(qw, qx, qy, qz)``, as MuJoCo's
        ``data.mocap_pos`` and ``data.mocap_quat`` take them. What a constraint joins to it
        is pulled along, and what it touches is pushed."""
        pose = np.concatenate(
            [np.asarray(pos, dtype=np.float32).reshape(3), np.asarray(quat, dtype=np.float32).reshape(4)]
        )
        self._handle.set_mocap_pose(str(name), pose.tolist())

    def set_heightfield(self, name: str, heights: Any) -> None:
        """Replaces heightfield ``name``'s terrain (one of ``env_info["heightfields"]``,
        ``(name, rows, columns)``): ``heights`` is ``(rows, columns)`` (or flat) in [0, 1],
        times the heightfield's top elevation, row 0 at −y, as dm_control's tasks write
        ``physics.model.hfield_data``. It stays through resets and travels in saved
        states. A bad name, count or height is ``InvalidArgument`` and changes nothing."""
        array = np.asarray(heights, dtype=np.float32).reshape(-1)
        self._handle.set_heightfield(str(name), array.tolist())

    def randomization(self) -> Dict[str, Any]:
        """The domain-randomisation factors drawn at the last reset:
        ``{"instances": [InstanceDraw(name, mass_scale, friction_scale)], "joints":
        [JointDraw(name, damping_scale, gain_scale)]}`` (named tuples).
        ``FailedPrecondition`` if the env was made without ``randomize``."""
        return named_draws(self._handle.randomization())

    def render(self) -> Optional[np.ndarray]:
        """With ``render_mode="rgb_array"``: a picture of the env as it is now, a
        ``height x width x 3`` uint8 array (default 320 x 240, the robot framed from the
        ``iso`` direction; ``render_options`` chooses camera and size). Without a render
        mode: ``None``, as gymnasium specifies."""
        if self.render_mode is None:
            gym.logger.warn(
                "render() was called without a render_mode; make the env with "
                'render_mode="rgb_array"'
            )
            return None
        return self.picture(**self.render_options)

    def picture(
        self,
        camera: str = "iso",
        width: int = 0,
        height: int = 0,
        eye: Optional[Tuple[float, float, float]] = None,
        target: Optional[Tuple[float, float, float]] = None,
        fov_deg: float = 0.0,
        orthographic: bool = False,
    ) -> np.ndarray:
        """A picture of the env now, whatever the render mode: ``camera`` is ``"iso"``,
        ``"front"``, ``"side"`` or ``"top"`` (framing the robot) unless ``eye`` (world
        mm) is given; ``target`` defaults to the robot's centre; ``fov_deg`` 0 means 45;
        ``width`` x ``height`` 0 x 0 means 320 x 240 (16 to 2048 a side)."""
        return self._handle.render(
            camera, int(width), int(height), eye, target, float(fov_deg), bool(orthographic)
        )

    def observe(self) -> np.ndarray:
        """The current observation, without stepping."""
        return self._handle.observe()

    def save_state(self) -> bytes:
        """Everything that determines the env's future (robot state, episode, task
        target, random generator, and the document and options) as opaque bytes, for
        :meth:`load_state` on this env or any env made with the same document and
        options, on any server. Try actions, then load the state to take them back: the
        env continues bit for bit as if they never happened. ``FailedPrecondition`` for
        a diverged env."""
        return self._handle.save_state()

    def load_state(self, state: bytes) -> np.ndarray:
        """Returns to a state from :meth:`save_state` and gives the observation there.
        ``InvalidArgument`` (with the reason) for a state of another document, options
        or format version, or corrupted bytes; the env is then unchanged."""
        return self._handle.load_state(state_bytes("state", state))

    def set_joint_state(
        self, positions: Any, velocities: Any, base: Any = ()
    ) -> Tuple[np.ndarray, List[str]]:
        """Sets the robot's joint state from values, as MuJoCo's ``set_state(qpos,
        qvel)`` does: one position and one velocity per DOF as the observation has them
        (units and reference included) and, with a floating base, its 13 floats (the
        observation's ``base_pose`` then ``base_velocity``). The episode goes on. Returns
        the observation there and the server's warnings (a position past a hard limit is
        set at the limit; a joint on a kinematic loop keeps its position).
        ``InvalidArgument`` for a wrong count or a non-finite value; nothing changes then."""
        return self._handle.set_joint_state(_floats(positions), _floats(velocities), _floats(base))

    def bodies(self) -> Dict[str, Any]:
        """Every instance's and site's state now: ``instances`` and ``sites`` (names),
        ``masses``, ``centers_of_mass`` (3 each), ``inertias`` (MuJoCo's ``cinert``, 10
        each), ``velocities`` (``cvel``, 6 each), ``contact_wrenches`` (``cfrc_ext``, 6
        each) about ``about`` (the robot's centre of mass), ``site_poses`` (7 each),
        ``actuator_forces`` (``qfrc_actuator``, one per DOF) and ``sensordata`` (every
        sensor's reading, SI, MuJoCo's ``sensordata``), flat float64 arrays; ``sensors``,
        ``sensor_types`` and ``sensor_dims`` name the sensors, in order."""
        return self._handle.bodies()

    def fork(self) -> "GymfleetEnv":
        """A new env on the same server, made with this env's document and options and
        put in its state now (episode, task target, random generator, draws): the two then
        run independently, and the same actions give both the same observations. The
        caller closes it. ``FailedPrecondition`` for a diverged env."""
        twin = GymfleetEnv(**self.spec.kwargs, token=self._token)
        try:
            twin.load_state(self.save_state())
        except BaseException:
            twin.close()
            raise
        return twin

    def close(self) -> None:
        """Frees the env on its server (again: nothing). A server that is gone has
        nothing left to free, so that is not an error."""
        self._close_handle()
        super().close()

    def __getstate__(self) -> Dict[str, Any]:
        """What a pickle holds: the arguments the env was made with (its token too, to
        connect again) and, a gymfleet extension, its saved state (``save_state``); a
        diverged env has none. Unpickling makes a new env on the same server (with
        ``server=None``, the unpickling process's embedded one) and loads the state: it
        continues bit for bit as the original would. The original stays open."""
        return {"kwargs": dict(self.spec.kwargs), "token": self._token,
                "state": self.saved_state_or_none(), "np_random": self._np_random}

    def saved_state_or_none(self) -> Optional[bytes]:
        """:meth:`save_state`, or ``None`` for a diverged env (which has no state)."""
        try:
            return self.save_state()
        except FailedPrecondition:
            return None

    def __setstate__(self, pickled: Dict[str, Any]) -> None:
        self.__init__(**pickled["kwargs"], token=pickled["token"])  # type: ignore[misc]
        self._np_random = pickled["np_random"]
        if pickled["state"] is not None:
            self.load_state(pickled["state"])

    def __repr__(self) -> str:
        return f"<GymfleetEnv {self._info['env_id']} on {self._info['server']}>"


def _floats(values: Any) -> List[float]:
    """Values as a list of Python floats (a 1-D array or sequence of numbers)."""
    return [float(v) for v in np.asarray(values, dtype=np.float64).reshape(-1)]

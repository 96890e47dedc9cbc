"""Type stubs of ``gymfleet._core``, the Rust extension module (``client/python/src``).

A thin layer over the Rust client: every call blocks with the GIL released until the
server answers, and raises the classes of :mod:`gymfleet.errors`. Use the gymnasium
classes of :mod:`gymfleet` rather than these handles.
"""

from typing import Any, Dict, List, Optional, Sequence, Tuple, TypedDict

import numpy as np
import numpy.typing as npt

__version__: str

class CreateOptions(TypedDict):
    """`CreateEnvRequest`'s options; ``None`` takes the server's default."""

    end_effector_ids: List[str]
    dt: Optional[float]
    substeps: Optional[int]
    max_steps: Optional[int]
    seed: Optional[int]
    reset_noise: Optional[float]
    kp: Optional[List[float]]
    kd: Optional[List[float]]
    task: Optional[Dict[str, Any]]
    randomize: Optional[Dict[str, Any]]
    model: Optional[str]
    assets: Optional[bytes]
    document_path: Optional[str]
    units: Optional[str]

class EnvHandle:
    """One env on a server."""

    @staticmethod
    def create(
        server: Optional[str],
        document_json: str,
        options: CreateOptions,
        timeout_s: Optional[float] = None,
    ) -> "EnvHandle":
        """Creates an env of ``document_json`` on ``server`` (``None``: the embedded
        server; ``"host:port"``; a comma-separated fleet, where it goes to the least
        loaded server)."""
    @property
    def info(self) -> Dict[str, Any]:
        """``env_id``, ``server``, ``num_joints``, ``action_dim``, ``observation_dim``,
        ``end_effector_ids``, ``dt``, ``substeps``, ``max_steps`` and ``joints`` (each
        with ``name``, ``type``, ``dof``, ``parent``, ``child``, ``max_effort`` and per-DOF
        ``limits`` of ``unit``, ``min``, ``max``)."""
    timeout: Optional[float]
    """Seconds a call may take before it raises ``DeadlineExceeded`` (``None``: none)."""
    def reset(self, seed_value: Optional[int] = None) -> npt.NDArray[np.float32]:
        """Resets (reseeding first when a seed is given); the observation."""
    def step(
        self,
        kind: "ActionKind",
        action: npt.NDArray[np.float32],
        mocap_poses: Optional[npt.NDArray[np.float32]] = None,
    ) -> Tuple[
        npt.NDArray[np.float32], float, bool, bool, Optional[str], int, npt.NDArray[np.float32]
    ]:
        """``(observation, reward, terminated, truncated, termination_reason,
        episode_step, terms)``; ``action`` is 1-D float32, one value per DOF; ``terms``
        a terms task's values (``info["term_names"]`` order; empty without one);
        ``mocap_poses``: 7 floats per mocap body, its target (``None``: they stay)."""
    def set_mocap_pose(self, body: str, pose: Sequence[float]) -> None:
        """Mocap body ``body``'s target for the next step: ``[x, y, z, qw, qx, qy, qz]``."""
    def observe(self) -> npt.NDArray[np.float32]:
        """The current observation, without stepping."""
    def save_state(self) -> bytes:
        """The env's saved state (the env is re-seated from it)."""
    def load_state(self, state: bytes) -> npt.NDArray[np.float32]:
        """Loads a saved state; the observation there."""
    def render(
        self,
        camera: str = "iso",
        width: int = 0,
        height: int = 0,
        eye: Optional[Tuple[float, float, float]] = None,
        target: Optional[Tuple[float, float, float]] = None,
        fov_deg: float = 0.0,
        orthographic: bool = False,
    ) -> npt.NDArray[np.uint8]:
        """A picture of the env now: ``height x width x 3`` uint8 RGB."""
    def close(self) -> bool:
        """Closes the env on its server: ``True`` the first time, ``False`` after."""
    @property
    def closed(self) -> bool: ...

class ActionKind:
    """How a step's action values are read (the package maps its ``action_type`` string
    to one of these once)."""

    Torque: "ActionKind"
    Position: "ActionKind"
    Velocity: "ActionKind"

class BatchHandle:
    """A batch of envs on one server, or sharded over a fleet."""

    @staticmethod
    def create(
        server: Optional[str],
        document_json: str,
        n_envs: int,
        autoreset: str,
        options: CreateOptions,
        timeout_s: Optional[float] = None,
    ) -> "BatchHandle":
        """Creates ``n_envs`` envs; ``autoreset`` is ``"disabled"``, ``"same_step"`` or
        ``"next_step"``. Env ``i`` is seeded with ``seed + i``."""
    @property
    def info(self) -> Dict[str, Any]:
        """As :attr:`EnvHandle.info` with ``batch_id`` and ``n_envs`` instead of
        ``env_id`` and ``server``, and ``shards``: ``(server, batch_id, start, stop)``
        per shard."""
    timeout: Optional[float]
    def reset(
        self,
        seed_value: Optional[int] = None,
        env_indices: Optional[npt.NDArray[np.uint32]] = None,
    ) -> npt.NDArray[np.float32]:
        """Resets every env, or those of ``env_indices`` (ascending); env ``i`` is
        reseeded with ``seed + i`` when a seed is given. Every env's observation,
        ``(n_envs, observation_dim)``."""
    def step(
        self,
        kind: "ActionKind",
        actions: npt.NDArray[np.float32],
        mocap_poses: Optional[npt.NDArray[np.float32]] = None,
    ) -> Tuple[
        npt.NDArray[np.float32],
        npt.NDArray[np.float32],
        npt.NDArray[np.bool_],
        npt.NDArray[np.bool_],
        npt.NDArray[np.uint32],
        npt.NDArray[np.float32],
        Dict[int, str],
        npt.NDArray[np.float32],
    ]:
        """Steps every env with ``actions`` ``(n_envs, action_dim)``: observations,
        rewards, terminated, truncated, the envs reset within the step (same-step
        autoreset) and their final observations ``(k, observation_dim)``, the
        termination reasons by env, and a terms task's values ``(n_envs, len(term_names))``.
        ``mocap_poses``: every env's mocap targets, flat ``n_envs × mocap bodies × 7``
        (``None``: they stay)."""
    def step_envs(
        self,
        kind: "ActionKind",
        env_indices: npt.NDArray[np.uint32],
        actions: npt.NDArray[np.float32],
    ) -> Tuple[
        npt.NDArray[np.float32],
        npt.NDArray[np.float32],
        npt.NDArray[np.bool_],
        npt.NDArray[np.bool_],
        npt.NDArray[np.uint32],
        npt.NDArray[np.float32],
        Dict[int, str],
        npt.NDArray[np.float32],
    ]:
        """:meth:`step` of the envs ``env_indices`` only (ascending, distinct), with one
        action row each in that order: one row per listed env; the finished envs and the
        termination reasons name batch indices."""
    def checkpoint_every(self, steps: int) -> None:
        """Checkpoints every env every ``steps`` steps (0: stops), starting now."""
    def recover(
        self, server: Optional[str] = None, token: Optional[str] = None
    ) -> Optional[Tuple[List[int], Tuple[Any, ...]]]:
        """Rebuilds a lost server's envs from the checkpoint (on ``server``, or the
        survivors); the step that found the loss, as ``step_envs`` returns it, with its
        env indices (empty: every env), or ``None``."""
    def open_stream(self, window: int) -> Optional["StepStream"]:
        """A ``StreamBatch`` stream of this batch for the asynchronous API (up to
        ``window`` sends in flight); ``None`` when the batch is sharded over a fleet."""
    def observe(self) -> npt.NDArray[np.float32]:
        """Every env's current observation."""
    def save_states(
        self, env_indices: Optional[npt.NDArray[np.uint32]] = None
    ) -> List[bytes]:
        """The saved states of the envs of ``env_indices`` (ascending; ``None``: all)."""
    def load_states(
        self, states: List[bytes], env_indices: Optional[npt.NDArray[np.uint32]] = None
    ) -> npt.NDArray[np.float32]:
        """Loads ``states[k]`` into env ``env_indices[k]`` (``None``: every env, one
        state each); every env's observation."""
    def render(
        self,
        env_index: int,
        camera: str = "iso",
        width: int = 0,
        height: int = 0,
        eye: Optional[Tuple[float, float, float]] = None,
        target: Optional[Tuple[float, float, float]] = None,
        fov_deg: float = 0.0,
        orthographic: bool = False,
    ) -> npt.NDArray[np.uint8]:
        """A picture of env ``env_index`` now: ``height x width x 3`` uint8 RGB."""
    def close(self) -> bool:
        """Closes the batch on its server(s): ``True`` the first time, ``False`` after."""
    @property
    def closed(self) -> bool: ...

class Server:
    """A gymfleet server in this process, on ``127.0.0.1:<free port>``; a context
    manager."""

    def __init__(
        self,
        *,
        threads: int = 0,
        max_envs: Optional[int] = None,
        max_batch_size: Optional[int] = None,
        idle_ttl: Optional[float] = None,
        auth_tokens: Optional[str] = None,
        models: Optional[str] = None,
        pool_niceness: int = 0,
    ) -> None:
        """``threads``: simulation threads (0: one per core this process may use);
        limits default to the server's (``None``); ``idle_ttl`` in seconds (``None`` or
        0: never); ``auth_tokens``: a ``TENANT TOKEN`` file, and every call needs a
        token; ``models``: a model library folder (``--models DIR``) that
        ``make(model=...)`` names; ``pool_niceness``: the simulation threads'
        scheduling niceness (``--pool-niceness``; 0, the default: this process's own
        priority; 1..19 favours the server's network threads over its pool, for a
        process that serves many tenants and runs nothing else)."""
    @property
    def address(self) -> str:
        """``"127.0.0.1:<port>"``, what ``server=`` takes."""
    @property
    def running(self) -> bool: ...
    def stop(self) -> None:
        """Stops serving; its envs are gone. Stopping twice is a no-op."""
    def __enter__(self) -> "Server": ...
    def __exit__(self, *exc: Any) -> bool: ...

def embedded_address() -> str:
    """The process's embedded server's address, started on first use."""

def server_info(server: Optional[str] = None) -> Any:
    """A server's ``version``, ``threads``, ``envs``, ``batches``, ``batch_envs``,
    ``limits``, the caller's ``tenant``, ``auth_required`` and ``instance_id`` (random, new
    at every server start; a list of those for a
    fleet). With auth on, the counts are the caller's tenant's own."""

def convert_document(
    document: str,
    server: Optional[str] = None,
    assets: Optional[bytes] = None,
    token: Optional[str] = None,
    document_path: Optional[str] = None,
) -> Tuple[str, List[str]]:
    """The assembly JSON text a server builds from ``document`` (MJCF, URDF or JSON, its
    mesh files in the ``assets`` archive, its includes and meshes read from the folder of
    ``document_path`` there), and the conversion's warnings."""
def stateful_set(
    name: str, service: str, namespace: str = "default", replicas: int = 1, port: int = 50051
) -> List[str]:
    """The per-pod addresses of a StatefulSet behind a headless Service."""

def seed_model(name: str) -> str:
    """The JSON of seed model ``pendulum``, ``arm2``, ``arm6`` or ``chain20``."""

def _raise_status(code: int, message: str, reason: Optional[str] = None) -> None:
    """Raises the exception gRPC status ``code`` with ``message`` becomes (for tests)."""


class StepStream:
    """One server's batch's open stream: subset steps sent one after another, their
    results taken in the order sent. An error ends it (the server answers nothing
    after it)."""

    def send_envs(
        self,
        kind: "ActionKind",
        env_indices: npt.NDArray[np.uint32],
        actions: npt.NDArray[np.float32],
    ) -> None:
        """Sends a step of the envs ``env_indices``; returns once it is on its way.
        ``Unavailable`` if the stream has ended (this step was not sent)."""
    def next(self, timeout: Optional[float] = None) -> Tuple[
        npt.NDArray[np.float32],
        npt.NDArray[np.float32],
        npt.NDArray[np.bool_],
        npt.NDArray[np.bool_],
        npt.NDArray[np.uint32],
        npt.NDArray[np.float32],
        Dict[int, str],
        npt.NDArray[np.float32],
    ]:
        """The oldest sent step's rows, as :meth:`BatchHandle.step_envs` returns them;
        ``DeadlineExceeded`` after ``timeout`` seconds (the step stays pending)."""

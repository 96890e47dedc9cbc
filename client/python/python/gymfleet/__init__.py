"""gymfleet: robot assemblies simulated on a gymfleet server, as gymnasium environments.

>>> import gymfleet
>>> envs = gymfleet.make_vec("models/arm2.json", 256, end_effector_ids=["forearm"])
>>> obs, info = envs.reset(seed=42)
>>> obs, rewards, terminated, truncated, infos = envs.step(envs.action_space.sample() * 0)

``server=None`` (the default) runs a server inside this process; ``"host:port"`` uses a
running one; ``"a:50051,b:50051"`` shards batches over a fleet.
"""

from __future__ import annotations

import json as _json
from typing import Any, Dict, List, Optional, Tuple, Union

import gymnasium as _gymnasium
from gymnasium.vector import AutoresetMode as _AutoresetMode

from . import _core
from ._common import Document as _Document
from ._common import InstanceDraw, JointDraw
from ._common import assets_bytes as _assets_bytes
from ._common import document_json as _document_json
from ._common import path_in_assets as _path_in_assets
from .env import GymfleetEnv
from .errors import (
    DeadlineExceeded,
    FailedPrecondition,
    GymfleetError,
    Internal,
    InvalidArgument,
    NotFound,
    ResourceExhausted,
    ServerLost,
    Unauthenticated,
    Unavailable,
)
from .registration import register_envs as _register_envs
from .suite import register_suite as _register_suite
from .dmc import register_dmc as _register_dmc
from .vector import GymfleetVectorEnv

__version__: str = _core.__version__

#: A gymfleet server run inside this process: ``gymfleet.Server(threads=2)``; its
#: ``address`` is what ``server=`` takes. A context manager; ``stop()`` ends it.
Server = _core.Server

__all__ = [
    "make",
    "make_vec",
    "GymfleetEnv",
    "GymfleetVectorEnv",
    "Server",
    "FleetEndpoints",
    "embedded_server_address",
    "server_info",
    "convert",
    "list_models",
    "InstanceDraw",
    "JointDraw",
    "GymfleetError",
    "InvalidArgument",
    "NotFound",
    "ResourceExhausted",
    "FailedPrecondition",
    "Unauthenticated",
    "DeadlineExceeded",
    "Unavailable",
    "Internal",
    "ServerLost",
]


def make(
    document: Optional[_Document] = None,
    *,
    server: Optional[str] = None,
    end_effector_ids: Optional[List[str]] = None,
    dt: Optional[float] = None,
    substeps: Optional[int] = None,
    max_steps: Optional[int] = None,
    seed: Optional[int] = None,
    reset_noise: Optional[float] = None,
    action_type: str = "torque",
    **kwargs: Any,
) -> GymfleetEnv:
    """One environment of ``document`` (a dict, JSON, MJCF or URDF text, or a path) as a
    :class:`gymnasium.Env`; or, given a registered id such as ``"gymfleet/Hopper-v5"``,
    ``gymnasium.make(id, server=server, **kwargs)``. Options are the proto's ``CreateEnvRequest`` fields; unset
    ones take the server's defaults (dt 1/240 s, 5 substeps, 1000 steps, seed 0).
    Other keywords: ``pd_gains``, ``normalize_actions``, ``timeout`` (seconds per call),
    ``token`` (the bearer token of a server that requires one; default ``GYMFLEET_TOKEN``),
    ``model`` (a name of the server's ``--models`` library, instead of ``document``) and
    ``assets`` (the description's mesh files: a folder, a zip/tar file, or its bytes).
    """
    if _registered(document):
        _only_gymnasium_keywords(document, end_effector_ids, dt, substeps, max_steps, seed, reset_noise, action_type)
        return _gymnasium.make(document, server=server, **kwargs)
    return GymfleetEnv(
        document,
        server=server,
        end_effector_ids=end_effector_ids,
        dt=dt,
        substeps=substeps,
        max_steps=max_steps,
        seed=seed,
        reset_noise=reset_noise,
        action_type=action_type,
        **kwargs,
    )


def make_vec(
    document: Optional[_Document] = None,
    num_envs: int = 1,
    *,
    server: Optional[str] = None,
    autoreset_mode: Union[_AutoresetMode, str] = _AutoresetMode.NEXT_STEP,
    end_effector_ids: Optional[List[str]] = None,
    dt: Optional[float] = None,
    substeps: Optional[int] = None,
    max_steps: Optional[int] = None,
    seed: Optional[int] = None,
    reset_noise: Optional[float] = None,
    action_type: str = "torque",
    **kwargs: Any,
) -> GymfleetVectorEnv:
    """``num_envs`` environments of ``document`` as one :class:`gymnasium.vector.VectorEnv`
    (one server-side batch; sharded when ``server`` lists several servers). Env ``i`` is
    seeded with ``seed + i``. Same options as :func:`make`, plus ``autoreset_mode``. Given
    a registered id such as ``"gymfleet/Hopper-v5"``: ``gymnasium.make_vec(id, num_envs,
    server=server, autoreset_mode=..., **kwargs)``, one server batch.
    """
    if _registered(document):
        _only_gymnasium_keywords(document, end_effector_ids, dt, substeps, max_steps, seed, reset_noise, action_type)
        return _gymnasium.make_vec(
            document,
            num_envs,
            vectorization_mode="vector_entry_point",
            server=server,
            autoreset_mode=autoreset_mode,
            **kwargs,
        )
    return GymfleetVectorEnv(
        document,
        num_envs,
        server=server,
        autoreset_mode=autoreset_mode,
        end_effector_ids=end_effector_ids,
        dt=dt,
        substeps=substeps,
        max_steps=max_steps,
        seed=seed,
        reset_noise=reset_noise,
        action_type=action_type,
        **kwargs,
    )


def _registered(document: Any) -> bool:
    """Whether ``document`` is a gymfleet id registered with gymnasium."""
    return isinstance(document, str) and document.startswith("gymfleet/") and document in _gymnasium.registry


def _only_gymnasium_keywords(env_id: str, *given: Any) -> None:
    defaults = (None, None, None, None, None, None, None, "torque")
    if any(g != d for g, d in zip(given, defaults[1:])):
        raise InvalidArgument(
            f"{env_id} takes its registered env's keywords (and server); end_effector_ids, "
            "dt, substeps, max_steps, seed, reset_noise and action_type are for documents"
        )


def embedded_server_address() -> str:
    """The address of this process's embedded server (started now if not yet), for
    sharing it, e.g. with gymfleet-load or another process. Envs made with
    ``server=None`` reach the same server in process, with no socket (faster); this
    address goes over loopback TCP."""
    return _core.embedded_address()


def server_info(server: Optional[str] = None, token: Optional[str] = None) -> Any:
    """What a server says about itself: ``version``, ``threads``, open ``envs``,
    ``batches`` and ``batch_envs``, and its ``limits``. ``server=None``: this process's
    embedded server; a comma-separated list: a list, one per server. ``token``: the
    bearer token for a server that requires one (default: ``GYMFLEET_TOKEN``)."""
    return _core.server_info(server, token)


def convert(
    document: _Document,
    server: Optional[str] = None,
    assets: Any = None,
    token: Optional[str] = None,
) -> Tuple[Dict[str, Any], List[str]]:
    """The assembly JSON (as a dict) a server builds from ``document`` (MJCF or URDF text
    or a path to an ``.xml``/``.urdf`` file; JSON is checked and returned), and what the
    conversion ignored. ``assets``: the mesh files, as for :func:`make` (their hulls are
    read into the JSON). ``make``/``make_vec`` take MJCF and URDF directly; this shows
    (and lets you edit) what they build."""
    text, warnings = _core.convert_document(
        _document_json(document),
        server,
        _assets_bytes(assets),
        token,
        _path_in_assets(document, assets),
    )
    return _json.loads(text), list(warnings)


def list_models(server: Optional[str] = None, token: Optional[str] = None) -> List[Dict[str, Any]]:
    """The server's model library (``--models DIR``; ``gymfleet.Server(models=DIR)``):
    ``[{"name", "format", "dofs", "action_dim"}]`` sorted by name, each name what
    ``make(model=NAME)`` takes instead of a document; empty without a library."""
    return list(_core.list_models(server, token))


class FleetEndpoints:
    """Fleet address lists for ``server=``."""

    @staticmethod
    def stateful_set(
        name: str,
        service: str,
        namespace: str = "default",
        replicas: int = 1,
        port: int = 50051,
    ) -> str:
        """The pods of a Kubernetes StatefulSet behind a headless Service
        (``NAME-<i>.SERVICE.NAMESPACE.svc.cluster.local:PORT``), comma-separated."""
        return ",".join(_core.stateful_set(name, service, namespace, replicas, port))


_register_envs()
_register_suite()
_register_dmc()

# The names the package's own code was written with (typing's among them) are not part of
# it: only `__all__`, the submodules and `__version__` are.
del annotations, Any, Dict, List, Optional, Tuple, Union

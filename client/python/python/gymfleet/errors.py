"""The exceptions of gymfleet: one class per status the server answers with, all under
:class:`GymfleetError`, each also a subclass of the builtin that fits.

Every exception's text is the server's message, which names the offending field (with its
JSON path for documents), id or limit. ``server`` is the address of the server the
error names, or ``None``. ``reason`` says why for programs: the server's ``ErrorReason``
as it travels (the proto's name without ``ERROR_REASON_``, e.g. ``"ENV_NOT_FOUND"``,
``"INVALID_ACTION"``, ``"LIMIT_EXCEEDED"``), or ``None`` for what the package found itself
(a connection, a deadline, an argument it checks before calling). ``limit`` is the server
flag that raises the limit a :class:`ResourceExhausted` was for (``"--max-envs"``), or
``None``.
"""

from __future__ import annotations

from typing import List, Optional, Tuple

__all__ = [
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


class GymfleetError(Exception):
    """Base class of every error gymfleet raises for a failed call."""

    server: Optional[str] = None
    reason: Optional[str] = None
    limit: Optional[str] = None

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


class InvalidArgument(GymfleetError, ValueError):
    """INVALID_ARGUMENT: a bad document, option or action; nothing was created or stepped."""


class NotFound(GymfleetError, KeyError):
    """NOT_FOUND: the env or batch is unknown on its server: closed, reclaimed after idling,
    or the server restarted."""


class ResourceExhausted(GymfleetError):
    """RESOURCE_EXHAUSTED: a server limit (envs, batch size, message size) was hit; the
    message names the limit and how to raise it."""


class FailedPrecondition(GymfleetError):
    """FAILED_PRECONDITION: the call is not possible in the env's state, e.g. stepping an
    env whose physics diverged before resetting it."""


class Unauthenticated(GymfleetError):
    """UNAUTHENTICATED: the server requires a token and got none, or a bad one."""


class DeadlineExceeded(GymfleetError, TimeoutError):
    """DEADLINE_EXCEEDED: no reply within the ``timeout``. Whether the server did the work
    is unknown (a batch may have stepped some envs): reset before going on."""


class Unavailable(GymfleetError, ConnectionError):
    """UNAVAILABLE: the server cannot be reached, or is shutting down."""


class Internal(GymfleetError):
    """INTERNAL: a server bug (or a reply this client does not understand)."""


class ServerLost(Unavailable):
    """A server of a fleet failed while it held envs of a sharded batch: their state is
    gone, unless the batch checkpoints (``checkpoint_every``): then ``recover()`` rebuilds
    them. ``server`` names it; ``envs`` lists the lost env ranges as ``(start, stop)``."""

    envs: List[Tuple[int, int]] = []

"""Asynchronous stepping of a :class:`~gymfleet.GymfleetVectorEnv`, EnvPool's way
(``send``/``recv`` with ``batch_size`` M of ``num_envs`` N), and ``step_async`` /
``step_wait`` that overlap, as :class:`gymnasium.vector.AsyncVectorEnv`'s.

On one server, the sends go out over one ``StreamBatch`` stream, in order, without a
thread each: ``send`` returns once its step is on its way, and ``recv`` takes results off
the stream (the GIL released while it waits), so the trainer's own work (the policy on the
envs it has) overlaps the server's stepping. A fleet batch's sends run on a worker thread
of the vector env instead, one at a time. ``send`` steps only the envs it names (the server's subset step,
``StepBatchRequest.env_indices``), each exactly as a whole-batch step would, so the same
seeds and the same actions per env give the same per-env trajectories, bit for bit, in
whatever order and grouping envs are sent and come back. On one server every send is on
the wire at once (an env is in at most one), so the server has the next one queued while
it answers one.

Errors (a bad action, a lost server) surface at the next ``recv``, as the gymfleet error
the synchronous call raises, with ``env_ids`` (the envs of that send) as an attribute:
those envs did not step and are no longer in flight; nothing else is lost or stepped
twice. (The server answers nothing on a stream after a failed step: the sends behind it,
which it did not step, go out again on a new stream.)
"""

from __future__ import annotations

import collections
import threading
from concurrent.futures import Future, ThreadPoolExecutor
from typing import Any, Deque, Dict, List, Optional, Tuple

import numpy as np

from .errors import DeadlineExceeded, GymfleetError, ServerLost

class _Chunk:
    """The results of one send (or of the reset), column by column, in ascending env
    order: env ids (k,), observations (k, d), rewards (k,), terminated, truncated, the term
    values (k, terms) (``None`` for a reset's), and the termination reasons and final
    observations by env id. ``recv`` hands out whole chunks where it can (EnvPool's loop
    sends what it received: one chunk a ``recv``), and slices one only where it must."""

    __slots__ = ("ids", "obs", "rewards", "terminated", "truncated", "terms", "reasons", "finals")

    def __init__(self, ids: np.ndarray, obs: np.ndarray, rewards: np.ndarray, terminated: np.ndarray,
                 truncated: np.ndarray, terms: Optional[np.ndarray], reasons: Dict[int, str],
                 finals: Dict[int, np.ndarray]) -> None:
        self.ids, self.obs, self.rewards = ids, obs, rewards
        self.terminated, self.truncated, self.terms = terminated, truncated, terms
        self.reasons, self.finals = reasons, finals

    def __len__(self) -> int:
        return len(self.ids)

    def split(self, m: int) -> "Tuple[_Chunk, _Chunk]":
        """The first ``m`` envs, and the rest."""
        def part(cut: slice) -> "_Chunk":
            return _Chunk(self.ids[cut], self.obs[cut], self.rewards[cut], self.terminated[cut],
                          self.truncated[cut], None if self.terms is None else self.terms[cut],
                          self.reasons, self.finals)
        return part(slice(None, m)), part(slice(m, None))


#: Worker threads: a fleet batch's sends (which it takes one at a time) and step_async.
IN_FLIGHT = 2


class _Send:
    """A send on the stream whose result has not been taken: its envs and actions (to go
    out again on a new stream if the stream ended before it was stepped)."""

    __slots__ = ("ids", "values", "sent")

    def __init__(self, ids: np.ndarray, values: np.ndarray) -> None:
        self.ids, self.values, self.sent = ids, values, False


class Pipeline:
    """The asynchronous state of one vector env: what was sent, what came back."""

    @staticmethod
    def check_batch_size(batch_size: Any, n: int) -> None:
        if isinstance(batch_size, bool) or not isinstance(batch_size, (int, np.integer)) or not 1 <= batch_size <= n:
            raise ValueError(f"batch_size: expected an integer in [1, num_envs={n}], got {batch_size!r}")

    def __init__(self, envs: Any, batch_size: int) -> None:
        n = envs.num_envs
        self.check_batch_size(batch_size, n)
        self._envs = envs
        self.batch_size = int(batch_size)
        self._worker = ThreadPoolExecutor(max_workers=IN_FLIGHT, thread_name_prefix="gymfleet-steps")
        self._lock = threading.Condition()
        self._pending: "set[Future[Any]]" = set()
        self._ready: Deque[_Chunk] = collections.deque()
        self._n_ready = 0
        self._errors: Deque[BaseException] = collections.deque()
        self._in_flight = np.zeros(n, dtype=bool)
        self._sent = 0
        # The stream (one server's batch): opened at the first send; `False` for a fleet.
        self._stream: Any = None
        # Whether it takes more sends (not after a send found it ended).
        self._accepting = False
        self._on_stream: Deque[_Send] = collections.deque()
        # The sends that failed with ServerLost (on a fleet), until `recovered`.
        self._lost: List[Tuple[np.ndarray, np.ndarray]] = []

    # The worker's side.

    def submit(self, call: Any, *args: Any) -> "Future[Any]":
        """Runs ``call(*args)`` on a worker thread."""
        future = self._worker.submit(call, *args)
        with self._lock:
            self._pending.add(future)
        future.add_done_callback(self._done)
        return future

    def _done(self, future: "Future[Any]") -> None:
        with self._lock:
            self._pending.discard(future)

    def _step(self, ids: np.ndarray, actions: np.ndarray) -> None:
        try:
            chunk = _Chunk(ids.astype(np.int32), *self._envs._step_columns(ids, actions))
        except BaseException as err:  # noqa: B902 - handed to recv, which raises it
            err.env_ids = ids.copy()  # type: ignore[attr-defined]
            with self._lock:
                if isinstance(err, ServerLost):
                    self._lost.append((ids, actions))  # for `recovered`
                self._in_flight[ids] = False
                self._errors.append(err)
                self._lock.notify_all()
            return
        with self._lock:
            self._ready.append(chunk)
            self._n_ready += len(chunk)
            self._in_flight[ids] = False
            self._lock.notify_all()

    # The trainer's side.

    def reset(self, observations: np.ndarray, infos: Dict[str, Any]) -> None:
        """After every env was reset: each one's first observation is ready, in env
        order (what ``recv`` returns first)."""
        self.drain()
        n = len(observations)
        with self._lock:
            self._ready.clear()
            self._errors.clear()
            self._lost.clear()
            self._ready.append(_Chunk(np.arange(n, dtype=np.int32), np.asarray(observations),
                                      np.zeros(n, dtype=np.float32), np.zeros(n, dtype=np.bool_),
                                      np.zeros(n, dtype=np.bool_), None, {}, {}))
            self._n_ready = n

    def send(self, actions: Any, env_id: Any) -> None:
        """Steps the envs ``env_id`` (distinct, none in flight) with ``actions`` (one row
        per env, in ``env_id``'s order) on the worker; returns at once."""
        n = self._envs.num_envs
        ids = np.asarray(env_id).reshape(-1)
        if ids.size == 0 or not np.issubdtype(ids.dtype, np.integer):
            raise ValueError(f"env_id: expected one or more integer env ids, got {env_id!r}")
        if ids.min() < 0 or ids.max() >= n:
            raise ValueError(f"env_id: expected ids in [0, {n}), got {ids.tolist()}")
        order = np.argsort(ids, kind="stable")
        ids = ids[order].astype(np.uint32)
        if np.any(ids[1:] == ids[:-1]):
            raise ValueError(f"env_id: expected distinct ids, got {np.asarray(env_id).tolist()}")
        values = self._envs._actions.to_server(actions)
        values = np.asarray(values, dtype=np.float32).reshape(ids.size, -1)[order]
        with self._lock:
            busy = ids[self._in_flight[ids]]
            if busy.size:
                raise ValueError(f"env_id: envs {busy.tolist()} are in flight: recv them first")
            self._in_flight[ids] = True
        self._sent += 1
        values = np.ascontiguousarray(values)
        if self._streams():
            send = _Send(ids, values)
            self._on_stream.append(send)
            self._stream_send(send)
        else:
            self.submit(self._step, ids, values)

    # The stream's side (one server).

    def _open(self) -> Any:
        """One server's batch's new stream (`False` on a fleet)."""
        stream = self._envs._handle.open_stream(max(2, min(self._envs.num_envs, 1024))) or False
        self._accepting = stream is not False
        return stream

    def _streams(self) -> bool:
        if self._stream is None:
            self._stream = self._open()
        return self._stream is not False

    def _stream_send(self, send: _Send) -> None:
        if not self._accepting:
            return  # the stream has ended: this send goes out on the next one
        try:
            self._stream.send_envs(self._envs._action_kind, send.ids, send.values)
            send.sent = True
        except GymfleetError:
            # The stream has ended (a step before failed, or the server went away): the
            # cause is among the results still to take off it; this send goes out again.
            self._accepting = False

    def _reopen(self) -> None:
        """A new stream, with every send not stepped yet (all those left: the ones sent
        before were taken) sent on it, in order."""
        try:
            self._stream = self._open()
        except GymfleetError as err:
            self._fail_all(err)
            raise
        for send in self._on_stream:
            self._stream_send(send)

    def _fail_all(self, err: BaseException) -> None:
        """Every send still on the stream fails with ``err``: its envs leave the flight."""
        ids = np.concatenate([s.ids for s in self._on_stream]) if self._on_stream else np.zeros(0, np.uint32)
        err.env_ids = ids  # type: ignore[attr-defined]
        self._on_stream.clear()
        with self._lock:
            self._in_flight[ids] = False

    def _take(self, timeout: Optional[float]) -> None:
        """Takes the oldest send's result off the stream into the ready results, or
        raises its error (with its ``env_ids``; the sends behind it go out again)."""
        send = self._on_stream[0]
        if not send.sent:
            self._reopen()
            return
        try:
            columns = self._envs._columns(self._stream.next(timeout))
        except DeadlineExceeded:
            raise TimeoutError(f"recv: no {self.batch_size} envs ready within {timeout} s") from None
        except GymfleetError as err:
            self._on_stream.popleft()
            err.env_ids = send.ids.copy()  # type: ignore[attr-defined]
            with self._lock:
                self._in_flight[send.ids] = False
            # The server stepped nothing after it: those sends go out again when taken.
            self._accepting = False
            for rest in self._on_stream:
                rest.sent = False
            raise
        self._on_stream.popleft()
        with self._lock:
            self._ready.append(_Chunk(send.ids.astype(np.int32), *columns))
            self._n_ready += len(send.ids)
            self._in_flight[send.ids] = False

    def recv(self, timeout: Optional[float] = None) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, Dict[str, Any]]:
        """The next ``batch_size`` envs that finished a step (or their reset), in the order
        they finished: observations, rewards, terminated, truncated and ``info`` with
        ``env_id`` (and per-env term values, termination reasons and final observations
        as the synchronous step gives them). Raises a send's error first."""
        m = self.batch_size
        while self._on_stream and not self._errors and self._n_ready < m:
            self._take(timeout)
        with self._lock:
            while not self._errors and self._n_ready < m:
                if not self._in_flight.any():
                    raise RuntimeError(
                        f"recv: {self._n_ready} envs are ready and none in flight, fewer "
                        f"than batch_size={m}: send their actions first (or async_reset)"
                    )
                if not self._lock.wait(timeout):
                    raise TimeoutError(f"recv: no {m} envs ready within {timeout} s")
            if self._errors:
                raise self._errors.popleft()
            pieces, need = [], m
            while need:
                chunk = self._ready.popleft()
                if len(chunk) > need:
                    chunk, rest = chunk.split(need)
                    self._ready.appendleft(rest)
                pieces.append(chunk)
                need -= len(chunk)
            self._n_ready -= m
        return _joined(pieces, self._envs._info["term_names"])

    def recovered(self, found: Optional[Tuple[Any, Tuple[Any, ...]]]) -> None:
        """After the fleet batch rebuilt a lost server's envs (``BatchHandle.recover``,
        nothing in flight): the send that found the loss (``found``: its env indices and
        rows) is ready with that step's result; the sends refused after it stepped
        nowhere and go out again. Their :class:`ServerLost` errors, raised or not, are
        settled."""
        ids = None
        if found is not None and len(found[0]):
            ids = np.asarray(found[0], dtype=np.int32)
            chunk = _Chunk(ids, *self._envs._columns(found[1]))
        with self._lock:
            again = [(sent, values) for sent, values in self._lost
                     if ids is None or not np.array_equal(sent, ids)]
            self._lost.clear()
            self._errors = collections.deque(e for e in self._errors if not isinstance(e, ServerLost))
            if ids is not None:
                self._ready.append(chunk)
                self._n_ready += len(ids)
            for sent, _ in again:
                self._in_flight[sent] = True
        for sent, values in again:
            self.submit(self._step, sent, values)

    def drain(self) -> None:
        """Waits until every step sent has been taken (a stream's errors kept for
        ``recv``)."""
        while self._on_stream:
            try:
                self._take(None)
            except GymfleetError as err:
                with self._lock:
                    self._errors.append(err)
        while True:
            with self._lock:
                pending = list(self._pending)
            if not pending:
                return
            for future in pending:
                future.exception()  # waits; its outcome went to recv or step_wait

    def busy(self) -> bool:
        """Whether any env is in flight."""
        with self._lock:
            return bool(self._in_flight.any())

    def close(self) -> None:
        self._worker.shutdown(wait=True)


class OverBatch:
    """The asynchronous API of a vector env that wraps a :class:`GymfleetVectorEnv`
    (``self._envs``) and makes its own results from the batch's with ``self._finish(raw,
    rewards, terminated, truncated, raw_infos)`` (the suite ids' vector envs): ``step``
    with ``env_id``, ``batch_size``, ``async_reset``, ``send``, ``step_async`` and
    ``step_wait`` pass through; the class supplies ``recv`` and ``_finish``."""

    _envs: Any

    def _finish(self, *raw: Any) -> Any:  # pragma: no cover - supplied by the class
        raise NotImplementedError

    def recv(self, timeout: Optional[float] = None) -> Any:  # pragma: no cover - supplied by the class
        raise NotImplementedError

    def step(self, actions: Any, env_id: Any = None) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, Dict[str, Any]]:
        """Every env's step; with ``env_id``, EnvPool's ``send(actions, env_id)`` then
        ``recv()``."""
        if env_id is not None:
            self.send(actions, env_id)
            return self.recv()
        return self._finish(*self._envs.step(actions))

    @property
    def batch_size(self) -> int:
        """How many envs :meth:`recv` returns (``batch_size=M``; default ``num_envs``)."""
        return self._envs.batch_size

    def async_reset(self) -> None:
        """Resets every env (as ``reset`` without a seed); their first observations are
        what the next :meth:`recv` calls return, in env order."""
        self._envs.async_reset()

    def send(self, actions: Any, env_id: Any) -> None:
        """Steps the envs ``env_id`` with ``actions`` (one row per env, in ``env_id``'s
        order) and returns at once; each steps as in :meth:`step`."""
        self._envs.send(actions, env_id)

    def step_async(self, actions: Any) -> None:
        """Starts every env's step (:meth:`step`'s) and returns at once."""
        self._envs.step_async(actions)

    def step_wait(self, timeout: Optional[float] = None) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, Dict[str, Any]]:
        """The result of the pending :meth:`step_async`."""
        return self._finish(*self._envs.step_wait(timeout))


def _joined(pieces: List[_Chunk], names: List[str]) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, Dict[str, Any]]:
    """``recv``'s result from chunks in the order they finished: the columns joined (one
    chunk's as they are), and ``info`` with ``env_id``, each term's values (float64) and,
    where any env has one, termination reasons and final observations (object columns);
    each key with its ``_key`` mask of the envs that have it (a reset's envs have no
    terms)."""
    def column(name: str) -> np.ndarray:
        parts = [getattr(p, name) for p in pieces]
        return parts[0] if len(parts) == 1 else np.concatenate(parts)

    ids = column("ids")
    info: Dict[str, Any] = {"env_id": ids}
    extra: Dict[str, Any] = {}
    with_terms = [p.terms is not None for p in pieces]
    if any(with_terms):
        width = len(names)
        terms = np.concatenate([
            p.terms.astype(np.float64) if p.terms is not None else np.zeros((len(p), width))
            for p in pieces
        ]) if len(pieces) > 1 else pieces[0].terms.astype(np.float64)
        has = np.concatenate([np.full(len(p), t) for p, t in zip(pieces, with_terms)])
        for k, name in enumerate(names):
            extra[name], extra["_" + name] = terms[:, k], has
    for key, attribute in (("termination_reason", "reasons"), ("final_obs", "finals")):
        by_env = [getattr(p, attribute) for p in pieces]
        if not any(by_env):
            continue
        values = np.empty(len(ids), dtype=object)
        has = np.zeros(len(ids), dtype=np.bool_)
        row = 0
        # Each piece's own envs only: a sliced chunk's dicts name the other slice's too.
        for piece, found in zip(pieces, by_env):
            for env in piece.ids.tolist():
                if env in found:
                    values[row], has[row] = found[env], True
                row += 1
        extra[key], extra["_" + key] = values, has
    for key in sorted(k for k in extra if not k.startswith("_")):
        info[key], info["_" + key] = extra[key], extra["_" + key]
    return column("obs"), column("rewards"), column("terminated"), column("truncated"), info

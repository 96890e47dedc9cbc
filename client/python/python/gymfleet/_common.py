"""What :class:`~gymfleet.GymfleetEnv` and :class:`~gymfleet.GymfleetVectorEnv` share:
reading a document, checking the creation options, the spaces and the action mapping."""

from __future__ import annotations

import io
import json
import os
import zipfile
from typing import Any, Dict, List, Mapping, NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np
from gymnasium import spaces

from . import _core
from .errors import InvalidArgument, NotFound, Unavailable

#: A document: the parsed JSON (a dict), its text, or the path of a file holding it.
Document = Union[Mapping[str, Any], str, "os.PathLike[str]"]

#: The creation options, named as the proto's `CreateEnvRequest` fields.
OPTION_NAMES = (
    "end_effector_ids",
    "dt",
    "substeps",
    "max_steps",
    "seed",
    "reset_noise",
    "pd_gains",
    "task",
    "randomize",
    "model",
    "assets",
    "units",
)

#: The units a creation can ask for: the document's (deg, mm) or SI (rad, m).
UNITS = ("document", "si")

ACTION_TYPES = ("torque", "position", "velocity")


def document_json(document: Optional[Document], model: Optional[str] = None) -> str:
    """The document's text, from a dict, JSON, MJCF or URDF text, or a path (the server
    detects the format: MJCF and URDF are converted into assembly JSON); ``""`` when a
    library ``model`` is named instead."""
    if model is not None:
        if document is not None:
            raise InvalidArgument("model: give a document or a model, not both")
        return ""
    if document is None:
        raise InvalidArgument("document: expected a document (or model=NAME of the server's library)")
    if isinstance(document, Mapping):
        return json.dumps(document)
    if isinstance(document, os.PathLike):
        with open(document, encoding="utf-8") as f:
            return f.read()
    if isinstance(document, str):
        if document.lstrip().startswith(("{", "<")):
            return document
        if os.path.isfile(document):
            with open(document, encoding="utf-8") as f:
                return f.read()
        raise InvalidArgument(
            f"document: expected a dict, JSON, MJCF or URDF text or the path of a file, got "
            f"{document[:80]!r} (neither, and no such file)"
        )
    raise TypeError(
        f"document: expected a dict, a JSON string or a path, got {type(document).__name__}"
    )


class InstanceDraw(NamedTuple):
    """The domain-randomisation factors an instance drew at the last reset."""

    name: str
    mass_scale: float
    friction_scale: float


class JointDraw(NamedTuple):
    """The domain-randomisation factors a joint drew at the last reset."""

    name: str
    damping_scale: float
    gain_scale: float


def named_draws(raw: Mapping[str, Any]) -> Dict[str, Any]:
    """The extension's draws with named fields (still tuples: ``name, mass, friction =
    draw`` unpacks them as before)."""
    return {
        "instances": [InstanceDraw(*d) for d in raw["instances"]],
        "joints": [JointDraw(*d) for d in raw["joints"]],
    }


def document_path(document: Optional[Document]) -> Optional[str]:
    """The path ``document`` was read from, if it was given as one."""
    if isinstance(document, os.PathLike):
        return os.fspath(document)
    if isinstance(document, str) and not document.lstrip().startswith(("{", "<")):
        return document
    return None


def located(err: InvalidArgument, document: Optional[Document]) -> InvalidArgument:
    """``err`` of a creation, saying ``document`` (not the request's ``document_json``
    field) and, when the document was read from a file, which file."""
    message = str(err)
    if message.startswith("document_json"):
        message = "document" + message[len("document_json"):]
    path = document_path(document)
    if path is not None:
        message = f"{path}: {message}"
    located_err = type(err)(message)
    located_err.server, located_err.reason, located_err.limit = err.server, err.reason, err.limit
    return located_err


def assets_bytes(assets: Any) -> Optional[bytes]:
    """The ``assets`` option as the archive the server reads: bytes as they are, a zip,
    tar or tar.gz file's bytes, or a folder zipped in memory (its hidden files left out)."""
    if assets is None:
        return None
    if isinstance(assets, (bytes, bytearray, memoryview)):
        return bytes(assets)
    if isinstance(assets, (str, os.PathLike)):
        path = os.fspath(assets)
        if os.path.isdir(path):
            buffer = io.BytesIO()
            with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
                for folder, folders, files in os.walk(path):
                    folders[:] = sorted(f for f in folders if not f.startswith("."))
                    for name in sorted(files):
                        if not name.startswith("."):
                            full = os.path.join(folder, name)
                            archive.write(full, os.path.relpath(full, path))
            return buffer.getvalue()
        if os.path.isfile(path):
            with open(path, "rb") as f:
                return f.read()
        raise InvalidArgument(f"assets: {path!r} is neither a folder nor a file")
    raise TypeError(
        f"assets: expected bytes, or the path of a folder or of a zip/tar file, got {type(assets).__name__}"
    )


#: The keywords of ``make`` besides the creation options (``make_vec`` adds
#: ``autoreset_mode``).
ENV_KEYWORDS = (
    "server",
    "action_type",
    "normalize_actions",
    "timeout",
    "render_mode",
    "render_options",
    "token",
)


def path_in_assets(document: Optional[Document], assets: Any) -> Optional[str]:
    """Where ``document``, given as a path inside the ``assets`` folder, sits in it
    (``"fetch/push.xml"``, forward slashes): its includes and mesh files are then read
    from its own folder there, as MuJoCo reads them. ``None`` otherwise."""
    path = document_path(document)
    if path is None or not isinstance(assets, (str, os.PathLike)) or not os.path.isdir(assets):
        return None
    inside = os.path.relpath(os.path.realpath(path), os.path.realpath(os.fspath(assets)))
    if inside.startswith(os.pardir):
        return None
    return inside.replace(os.sep, "/")


def create_options(
    options: Dict[str, Any],
    keywords: Sequence[str] = ENV_KEYWORDS,
    document: Optional[Document] = None,
) -> Dict[str, Any]:
    """The options as the extension takes them (every key present, None when unset); an
    unknown one is a ``TypeError`` listing every keyword the caller takes."""
    unknown = sorted(set(options) - set(OPTION_NAMES))
    if unknown:
        known = [*OPTION_NAMES, *keywords]
        raise TypeError(
            f"unexpected option(s) {', '.join(unknown)}; the options are "
            f"{', '.join(known[:-1])} and {known[-1]}"
        )
    ids = options.get("end_effector_ids")
    if isinstance(ids, str):
        ids = [ids]
    gains = options.get("pd_gains") or {}
    if not isinstance(gains, Mapping) or set(gains) - {"kp", "kd"}:
        raise InvalidArgument(
            "pd_gains: expected a dict with 'kp' and/or 'kd', each one gain per DOF (SI units)"
        )
    return {
        "end_effector_ids": list(ids or []),
        "dt": options.get("dt"),
        "substeps": options.get("substeps"),
        "max_steps": options.get("max_steps"),
        "seed": options.get("seed"),
        "reset_noise": options.get("reset_noise"),
        "kp": None if gains.get("kp") is None else [float(v) for v in gains["kp"]],
        "kd": None if gains.get("kd") is None else [float(v) for v in gains["kd"]],
        "task": None if options.get("task") is None else task_fields(options["task"]),
        "randomize": None if options.get("randomize") is None else randomize_fields(options["randomize"]),
        "model": options.get("model"),
        "assets": assets_bytes(options.get("assets")),
        "document_path": path_in_assets(document, options.get("assets")),
        "units": check_units(options.get("units")),
    }


def check_units(units: Optional[str]) -> Optional[str]:
    if units is None or units in UNITS:
        return units
    raise InvalidArgument(f'units: expected "document" or "si", got {units!r}')


RANDOMIZE_FIELDS = ("mass_scale", "friction_scale", "damping_scale", "gain_scale")


def randomize_fields(randomize: Mapping[str, Any]) -> Dict[str, Any]:
    """``{"mass_scale": [min, max], ...}`` with every field present (None: unset)."""
    if not isinstance(randomize, Mapping):
        raise InvalidArgument(f"randomize: expected a dict of [min, max] ranges, got {type(randomize).__name__}")
    unknown = sorted(set(randomize) - set(RANDOMIZE_FIELDS))
    if unknown:
        raise InvalidArgument(
            f"randomize: unknown field(s) {', '.join(unknown)}; the fields are {', '.join(RANDOMIZE_FIELDS)}"
        )
    out: Dict[str, Any] = {}
    for field in RANDOMIZE_FIELDS:
        value = randomize.get(field)
        if value is not None:
            if isinstance(value, Mapping):
                value = [value.get("min"), value.get("max")]
            try:
                value = [float(v) for v in value]
            except (TypeError, ValueError):
                value = []
            if len(value) != 2:
                raise InvalidArgument(f"randomize.{field}: expected [min, max] or {{'min', 'max'}}, got {randomize.get(field)!r}")
        out[field] = value
    return out


#: Each task kind's fields (the proto's), with their defaults (None: required or unset).
TASK_FIELDS: Dict[str, Dict[str, Any]] = {
    "reach": {
        "end_effector": None,
        "point": None,
        "target": None,
        "target_box": None,
        "success_radius": 0.0,
        "terminate_on_success": False,
    },
    "track": {"targets": None, "tolerance": 0.0, "terminate_on_success": False},
    "upright": {"instance": None, "axis": None, "max_tilt_deg": 0.0},
}


def _vec3(path: str, value: Any) -> Optional[List[float]]:
    if value is None:
        return None
    if isinstance(value, Mapping):
        value = [value.get(k, 0.0) for k in ("x", "y", "z")]
    try:
        v = [float(c) for c in value]
    except (TypeError, ValueError):
        v = []
    if len(v) != 3:
        raise InvalidArgument(f"{path}: expected [x, y, z] (mm) or {{'x', 'y', 'z'}}, got {value!r}")
    return v


#: A terms task's own fields (see docs/tasks.md, "Terms tasks").
TERMS_FIELDS = ("terms", "healthy", "reset_noise")


def _unset_task_fields() -> Dict[str, Any]:
    """Every kind's fields at their defaults, as the extension reads them all."""
    out: Dict[str, Any] = {f: d for fields in TASK_FIELDS.values() for f, d in fields.items()}
    out.update(target_min=None, target_max=None, json=None)
    return out


def task_fields(task: Mapping[str, Any]) -> Dict[str, Any]:
    """A task as the proto writes it (``{"reach": {...}, "action_cost": 0.01}``), flattened
    for the extension: ``kind``, ``action_cost`` and every field of every kind. A terms
    task (``{"terms": [...], "healthy": {...}, "reset_noise": {...}}``) travels as its
    JSON (``json``), checked by the server."""
    if not isinstance(task, Mapping):
        raise InvalidArgument(f"task: expected a dict like {{'reach': {{...}}}}, got {type(task).__name__}")
    if "terms" in task:
        extra = sorted(set(task) - set(TERMS_FIELDS) - {"action_cost"})
        if extra:
            raise InvalidArgument(
                f"task: unknown field(s) {', '.join(extra)} beside terms; a terms task has "
                f"{', '.join(TERMS_FIELDS)} and action_cost"
            )
        body = {k: task[k] for k in TERMS_FIELDS if k in task}
        try:
            text = json.dumps(body, allow_nan=False)
        except (TypeError, ValueError) as e:
            raise InvalidArgument(f"task.terms: expected JSON-serialisable values, {e}") from None
        out = _unset_task_fields()
        out.update(kind="terms", json=text, action_cost=float(task.get("action_cost", 0.0)))
        return out
    kinds = [k for k in TASK_FIELDS if k in task]
    extra = sorted(set(task) - set(TASK_FIELDS) - {"action_cost"})
    if extra:
        raise InvalidArgument(f"task: unknown field(s) {', '.join(extra)}; expected one of reach, track, upright, and action_cost")
    if len(kinds) != 1:
        raise InvalidArgument(f"task: expected exactly one of reach, track, upright, got {kinds or 'none'}")
    kind = kinds[0]
    body = task[kind]
    if not isinstance(body, Mapping):
        raise InvalidArgument(f"task.{kind}: expected a dict, got {type(body).__name__}")
    unknown = sorted(set(body) - set(TASK_FIELDS[kind]))
    if unknown:
        raise InvalidArgument(
            f"task.{kind}: unknown field(s) {', '.join(unknown)}; the fields are "
            f"{', '.join(TASK_FIELDS[kind])}"
        )
    out = _unset_task_fields()
    out.update(body)
    box = out.pop("target_box")
    if box is not None:
        if not isinstance(box, Mapping) or set(box) != {"min", "max"}:
            raise InvalidArgument(f"task.reach.target_box: expected {{'min': [x, y, z], 'max': [x, y, z]}}, got {box!r}")
    out["target_min"] = None if box is None else _vec3(f"task.{kind}.target_box.min", box["min"])
    out["target_max"] = None if box is None else _vec3(f"task.{kind}.target_box.max", box["max"])
    for f in ("point", "target", "axis"):
        out[f] = _vec3(f"task.{kind}.{f}", out[f])
    if out["targets"] is not None:
        out["targets"] = [float(t) for t in out["targets"]]
    out["kind"] = kind
    out["action_cost"] = float(task.get("action_cost", 0.0))
    for f in ("success_radius", "tolerance", "max_tilt_deg"):
        out[f] = float(out[f])
    out["terminate_on_success"] = bool(out["terminate_on_success"])
    if kind in ("reach",) and not isinstance(out["end_effector"], str):
        raise InvalidArgument("task.reach.end_effector: expected an instance name")
    if kind == "upright" and not isinstance(out["instance"], str):
        raise InvalidArgument("task.upright.instance: expected an instance name")
    return out


def check_action_type(action_type: str) -> str:
    if action_type not in ACTION_TYPES:
        raise InvalidArgument(
            f'action_type: expected "torque", "position" or "velocity", got {action_type!r}'
        )
    return action_type


def action_kind(action_type: str) -> "_core.ActionKind":
    """The extension's enum for a checked ``action_type``, which each step hands it."""
    return {
        "torque": _core.ActionKind.Torque,
        "position": _core.ActionKind.Position,
        "velocity": _core.ActionKind.Velocity,
    }[check_action_type(action_type)]


def action_bounds(info: Mapping[str, Any], action_type: str) -> Tuple[np.ndarray, np.ndarray]:
    """Each actuated DOF's action range: for torque, ±the server's action bound
    (``max_effort / |gear|`` where the document sets a clamp, else a default the server
    derives from the model: twice the effort that holds the joint's subtree against
    gravity, over the gear); the joint limits (shifted by the joint's reference, as
    positions are observed) for position; unbounded for velocity (and wherever there is no
    bound). Passive joints take no action. Then each actuator's control (MuJoCo's ctrl,
    whatever the action type): its ``ctrl_range``, else unbounded."""
    low: List[float] = []
    high: List[float] = []
    for joint in info["joints"]:
        if not joint["actuated"]:
            continue
        torque_bounds = joint.get("action_bounds") or []
        for k, limit in enumerate(joint["limits"]):
            lo, hi = -np.inf, np.inf
            if action_type == "torque" and len(torque_bounds) == joint["dof"]:
                lo, hi = -torque_bounds[k], torque_bounds[k]
            elif action_type == "torque" and joint["max_effort"] is not None:
                # A server before action bounds: the clamp alone.
                bound = joint["max_effort"] / abs(joint.get("gear") or 1.0)
                lo, hi = -bound, bound
            elif action_type == "position":
                reference = joint.get("reference") or 0.0
                lo = -np.inf if limit["min"] is None else limit["min"] + reference
                hi = np.inf if limit["max"] is None else limit["max"] + reference
            low.append(lo)
            high.append(hi)
    for actuator in info.get("actuators") or []:
        lo, hi = actuator["ctrl_range"] or (-np.inf, np.inf)
        low.append(lo)
        high.append(hi)
    return np.array(low, dtype=np.float32), np.array(high, dtype=np.float32)


def dof_names(info: Mapping[str, Any]) -> List[str]:
    names = []
    for joint in info["joints"]:
        if not joint["actuated"]:
            continue
        for k in range(joint["dof"]):
            names.append(joint["name"] if joint["dof"] == 1 else f"{joint['name']}[{k}]")
    names.extend(actuator["name"] for actuator in info.get("actuators") or [])
    return names


class ActionMap:
    """The action space, and the map from it to what the server takes."""

    def __init__(self, info: Mapping[str, Any], action_type: str, normalize: bool) -> None:
        self.low, self.high = action_bounds(info, action_type)
        self.normalize = normalize
        if normalize:
            unbounded = [
                name
                for name, lo, hi in zip(dof_names(info), self.low, self.high)
                if not (np.isfinite(lo) and np.isfinite(hi))
            ]
            if unbounded and action_type == "velocity":
                raise InvalidArgument(
                    "normalize_actions: velocity targets have no range to normalise; use "
                    'action_type="torque" (bounded by each joint\'s action bound) or '
                    '"position" (by its limits)'
                )
            if unbounded:
                what = "max_effort" if action_type == "torque" else "joint limits"
                if set(unbounded) & {a["name"] for a in info.get("actuators") or []}:
                    what += ", or an actuator's ctrl_range,"
                raise InvalidArgument(
                    f"normalize_actions: every DOF needs a finite {action_type} range, but "
                    f"{', '.join(unbounded)} has none (set {what} in the document)"
                )
            self.space = spaces.Box(-1.0, 1.0, shape=self.low.shape, dtype=np.float32)
        else:
            self.space = spaces.Box(self.low, self.high, dtype=np.float32)

    def to_server(self, action: Any) -> np.ndarray:
        """`action` (any float array-like) as contiguous float32 in the server's units."""
        values = np.ascontiguousarray(action, dtype=np.float32)
        if self.normalize:
            values = np.ascontiguousarray(
                self.low + (np.clip(values, -1.0, 1.0) + 1.0) * 0.5 * (self.high - self.low),
                dtype=np.float32,
            )
        return values


def observation_space(info: Mapping[str, Any]) -> spaces.Box:
    """Positions, velocities and poses are unbounded, as in gymnasium's MuJoCo envs."""
    return spaces.Box(-np.inf, np.inf, shape=(info["observation_dim"],), dtype=np.float32)


def keyframe_name(info: Mapping[str, Any], options: Optional[Mapping[str, Any]]) -> str:
    """The keyframe a reset's ``options["keyframe"]`` names (a name, or an index into
    ``env_info["keyframes"]``, as MuJoCo's ``mj_resetDataKeyframe`` takes one); ``""``
    without one: the document's initial keyframe, if any. A bad index or type is an
    ``InvalidArgument`` (an unknown name is the server's)."""
    if options is None or options.get("keyframe") is None:
        return ""
    key = options["keyframe"]
    names = list(info.get("keyframes", []))
    if isinstance(key, str):
        return key
    if isinstance(key, (int, np.integer)) and not isinstance(key, bool):
        if 0 <= int(key) < len(names):
            return names[int(key)]
        raise InvalidArgument(
            f"options['keyframe']: index {int(key)} is out of range: the document has "
            f"{len(names)} keyframe{'s' if len(names) != 1 else ''}"
            + (f" ({', '.join(names)})" if names else "")
        )
    raise InvalidArgument(
        f"options['keyframe']: expected a keyframe's name or index, got {type(key).__name__}"
    )


def seed_or_none(seed: Optional[int]) -> Optional[int]:
    if seed is None:
        return None
    if isinstance(seed, (bool,)) or not isinstance(seed, (int, np.integer)):
        raise TypeError(f"seed: expected an int or None, got {type(seed).__name__}")
    return int(seed)


class HandleOwner:
    """What both gymnasium classes do with their extension handle: the settable per-call
    ``timeout``, and closing it once."""

    _handle: Any

    @property
    def timeout(self) -> Optional[float]:
        """Seconds each call may take before it fails with ``DeadlineExceeded``
        (``None``: no limit). Settable, e.g. a long one for creation, then a short one."""
        return self._handle.timeout

    @timeout.setter
    def timeout(self, seconds: Optional[float]) -> None:
        self._handle.timeout = seconds

    def _close_handle(self) -> None:
        """Frees the server's envs (again: nothing). A server that is gone has nothing
        left to free, so that is not an error."""
        handle = getattr(self, "_handle", None)
        if handle is None:
            return
        try:
            handle.close()
        except (NotFound, Unavailable):
            pass

    def __del__(self) -> None:
        try:
            self.close()  # type: ignore[attr-defined]
        except Exception:  # noqa: BLE001 - a finaliser must not raise
            pass


def state_bytes(path: str, state: Any) -> bytes:
    """A saved state as ``bytes``, or a ``TypeError`` naming ``path``."""
    if isinstance(state, (bytes, bytearray, memoryview)):
        return bytes(state)
    raise TypeError(
        f"{path}: expected the bytes save_state returned, got {type(state).__name__}"
    )

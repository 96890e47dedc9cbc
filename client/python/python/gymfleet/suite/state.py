"""MuJoCo-shaped access to a suite env's state: ``env.unwrapped.data`` (``MjData``'s
``qpos``, ``qvel``, ``ctrl``, ``xpos``, ``xquat``, ``xipos``, ``site_xpos``, ``cinert``,
``cvel``, ``cfrc_ext``, ``qfrc_actuator``, ``body(name)``, ``site(name)``) and
``env.unwrapped.model`` (``MjModel``'s counts, ``body_mass``, ``opt.timestep``,
``actuator_ctrlrange``), in SI units and MuJoCo's layouts and orders.

``qpos``, ``qvel`` and ``ctrl`` come from the rows the server already returns. The body-level
fields are read from the server (``GymfleetEnv.bodies``) on first use after each reset,
step or ``set_state``, then kept until the next: a step costs nothing extra when they are
not read. Each MuJoCo body is the instances its geoms became (an MJCF body's origin is a
site of the converted document); masses, centres and ``cinert`` sum over them."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from types import SimpleNamespace
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

import numpy as np

from ..errors import InvalidArgument

#: What ``data`` offers, as the error for anything else lists it.
DATA_FIELDS = (
    "qpos", "qvel", "ctrl", "xpos", "xquat", "xipos", "site_xpos", "cinert", "cvel",
    "cfrc_ext", "qfrc_actuator", "body()", "site()",
)
#: What ``model`` offers.
MODEL_FIELDS = (
    "nq", "nv", "nu", "nbody", "nsite", "body_mass", "opt.timestep", "actuator_ctrlrange",
    "body()",
)
#: The body-level fields, read from the server on first use.
_BODY_FIELDS = ("xpos", "xquat", "xipos", "site_xpos", "cinert", "cvel", "cfrc_ext", "qfrc_actuator")


def _frozen(values: np.ndarray) -> np.ndarray:
    out = np.array(values, dtype=np.float64)
    out.flags.writeable = False
    return out


@dataclass
class BodyLayout:
    """MuJoCo's bodies and sites of an XML file, in MuJoCo's orders, and where each is in
    the converted document: each body's instances (its geoms' names, an unnamed geom's as
    the conversion names it), and the converted document's sites in its order (every
    body's origin, then within the body its ``<site>``s and child bodies as written, then
    the world's ``<site>``s)."""

    #: MuJoCo's bodies, the world first ("" for an unnamed one).
    bodies: List[str] = field(default_factory=lambda: ["world"])
    #: Each body's instances (the world's: none).
    instances: List[List[str]] = field(default_factory=lambda: [[]])
    #: MuJoCo's sites ("" for an unnamed one) and the body each is on.
    sites: List[str] = field(default_factory=list)
    site_bodies: List[int] = field(default_factory=list)
    #: The converted document's sites, in order: ("body", body index) or ("site", site index).
    document_sites: List[Tuple[str, int]] = field(default_factory=list)
    #: The world's own sites' positions, as written (they do not move).
    world_sites: List[np.ndarray] = field(default_factory=list)

    @classmethod
    def read(cls, text: str) -> "BodyLayout":
        layout = cls()
        world = ET.fromstring(text).find("worldbody")
        if world is None:
            return layout
        taken: set = set()
        per_body_sites: List[List[int]] = [[]]

        def geom_name(geom: ET.Element, body: str) -> str:
            # The conversion's names: a geom's own, an unnamed one's `<body>_geom`, made unique.
            wanted = geom.get("name") or f"{body or 'body'}_geom"
            name, k = wanted, 2
            while geom.get("name") is None and name in taken:
                name, k = f"{wanted}_{k}", k + 1
            taken.add(name)
            return name

        order: List[Tuple[int, int]] = []  # (body, k-th site of that body), document order

        def visit(node: ET.Element) -> None:
            b = len(layout.bodies)
            name = node.get("name", "")
            layout.bodies.append(name)
            geoms = [geom_name(g, name) for g in node.findall("geom")]
            layout.instances.append(geoms or [name or "body"])
            per_body_sites.append([])
            layout.document_sites.append(("body", b))
            for child in node:
                if child.tag == "body":
                    visit(child)
                elif child.tag == "site":
                    per_body_sites[b].append(len(order))
                    order.append((b, len(per_body_sites[b]) - 1))
                    layout.sites.append(child.get("name", ""))
                    layout.site_bodies.append(b)
                    layout.document_sites.append(("site", len(order) - 1))

        for child in world:
            if child.tag == "site":
                pos = np.array([float(x) for x in (child.get("pos") or "0 0 0").split()])
                layout.world_sites.append(pos)
        for child in world:
            if child.tag == "body":
                visit(child)
        # MuJoCo numbers sites body by body (the world's first); `order` is by document.
        by_body = sorted(range(len(order)), key=lambda k: (order[k][0], order[k][1]))
        renumber = {old: len(layout.world_sites) + new for new, old in enumerate(by_body)}
        layout.sites = [""] * len(layout.world_sites) + [layout.sites[k] for k in by_body]
        layout.site_bodies = [0] * len(layout.world_sites) + [layout.site_bodies[k] for k in by_body]
        layout.document_sites = [
            (kind, renumber[i] if kind == "site" else i) for kind, i in layout.document_sites
        ]
        # The world's sites come last in the converted document.
        layout.document_sites += [("site", k) for k in range(len(layout.world_sites))]
        return layout


class _Frames:
    """The body-level fields of one state, from the server's ``bodies()`` reply."""

    def __init__(self, layout: BodyLayout, reply: Dict[str, Any], qpos: np.ndarray, free: bool) -> None:
        index = {name: k for k, name in enumerate(reply["instances"])}
        nbody, nsite = len(layout.bodies), len(layout.sites)
        masses = np.asarray(reply["masses"])
        com = np.asarray(reply["centers_of_mass"]).reshape(-1, 3)
        inertias = np.asarray(reply["inertias"]).reshape(-1, 10)
        velocities = np.asarray(reply["velocities"]).reshape(-1, 6)
        wrenches = np.asarray(reply["contact_wrenches"]).reshape(-1, 6)
        poses = np.asarray(reply["site_poses"]).reshape(-1, 7)
        if len(poses) != len(layout.document_sites):
            raise InvalidArgument(
                f"the converted document has {len(poses)} sites; its XML file's bodies and "
                f"sites make {len(layout.document_sites)} (was the env made from another file?)"
            )
        self.xpos, self.xquat = np.zeros((nbody, 3)), np.tile([1.0, 0.0, 0.0, 0.0], (nbody, 1))
        self.site_xpos = np.zeros((nsite, 3))
        for k, position in enumerate(layout.world_sites):
            self.site_xpos[k] = position
        for (kind, i), pose in zip(layout.document_sites, poses):
            if kind == "body":
                self.xpos[i], self.xquat[i] = pose[:3], pose[3:]
            else:
                self.site_xpos[i] = pose[:3]
        if free:
            # A free joint's body is where its qpos says, as in MuJoCo (exactly).
            self.xpos[1] = qpos[0:3]
            self.xquat[1] = qpos[3:7] / np.linalg.norm(qpos[3:7])
        self.body_mass, self.xipos = np.zeros(nbody), self.xpos.copy()
        self.cinert, self.cvel, self.cfrc_ext = np.zeros((nbody, 10)), np.zeros((nbody, 6)), np.zeros((nbody, 6))
        for b in range(1, nbody):
            members = [index[name] for name in layout.instances[b] if name in index]
            if not members:
                continue
            m = masses[members]
            self.body_mass[b] = m.sum()
            if self.body_mass[b] > 0:
                self.xipos[b] = (m[:, None] * com[members]).sum(axis=0) / self.body_mass[b]
            self.cinert[b] = inertias[members].sum(axis=0)
            self.cvel[b] = velocities[members[0]]
            self.cfrc_ext[b] = wrenches[members].sum(axis=0)
        forces = np.asarray(reply["actuator_forces"])
        self.qfrc_actuator = np.concatenate([np.zeros(6), forces]) if free else forces.copy()
        for name in _BODY_FIELDS + ("body_mass",):
            getattr(self, name).flags.writeable = False


def _lookup(names: List[str], key: Union[int, str], what: str, count: int) -> int:
    if isinstance(key, (int, np.integer)):
        if not 0 <= int(key) < count:
            raise KeyError(f"Invalid {what} id {key}: the model has {count} ({what}s 0..{count - 1})")
        return int(key)
    if key not in names or key == "":
        known = ", ".join(repr(n) for n in names if n)
        raise KeyError(f"Invalid name '{key}'. Valid names: [{known}]")
    return names.index(key)


class SuiteData:
    """The env's state after its last reset, step or ``set_state``, as MuJoCo's ``MjData``
    names it, float64, read-only (the server holds the state: ``set_state`` changes it).
    ``qpos`` (nq), ``qvel`` (nv), ``ctrl`` (nu: the last action as given; 0 after a reset);
    per body, world first: ``xpos``, ``xquat``, ``xipos`` (its centre of mass), ``cinert``,
    ``cvel``, ``cfrc_ext`` (MuJoCo's c-frame quantities, about the robot's centre of mass);
    ``site_xpos`` per site; ``qfrc_actuator`` (nv); ``body(name)`` and ``site(name)``."""

    def __init__(self, qpos: np.ndarray, qvel: np.ndarray, ctrl: np.ndarray,
                 frames: Callable[[], _Frames], layout: BodyLayout) -> None:
        self.qpos, self.qvel, self.ctrl = _frozen(qpos), _frozen(qvel), _frozen(ctrl)
        self._frames, self._layout = frames, layout

    def body(self, key: Union[int, str]) -> SimpleNamespace:
        """One body's fields, as MuJoCo's ``data.body(name)``: ``id``, ``name``, ``xpos``,
        ``xquat``, ``xipos``, ``cinert``, ``cvel``, ``cfrc_ext``."""
        names = self._layout.bodies
        b = _lookup(names, key, "body", len(names))
        f = self._frames()
        return SimpleNamespace(id=b, name=names[b], xpos=f.xpos[b], xquat=f.xquat[b], xipos=f.xipos[b],
                               cinert=f.cinert[b], cvel=f.cvel[b], cfrc_ext=f.cfrc_ext[b])

    def site(self, key: Union[int, str]) -> SimpleNamespace:
        """One site's fields, as MuJoCo's ``data.site(name)``: ``id``, ``name``, ``xpos``."""
        names = self._layout.sites
        k = _lookup(names, key, "site", len(names))
        return SimpleNamespace(id=k, name=names[k], xpos=self._frames().site_xpos[k])

    def __getattr__(self, name: str) -> Any:
        if name in _BODY_FIELDS:
            return getattr(self._frames(), name)
        raise AttributeError(
            f"data.{name} is not offered by gymfleet's envs (they offer data."
            f"{', data.'.join(DATA_FIELDS)}); save_state()/load_state() on "
            f"env.unwrapped.gymfleet_env hold the whole state"
        )


class SuiteModel:
    """The model's counts and constants MuJoCo's ``MjModel`` names: ``nq``, ``nv``, ``nu``,
    ``nbody``, ``nsite``, ``body_mass`` (kg per body, world first: this episode's, read
    from the server), ``opt.timestep``, ``actuator_ctrlrange`` (nu, 2; the action space's
    float32 bounds, widened, where MuJoCo's are the file's float64) and ``body(name)``.
    Read-only: the server simulates the file it was given (make the env with another
    ``xml_file`` or ``frame_skip`` instead)."""

    def __init__(self, nq: int, nv: int, timestep: float, ctrlrange: np.ndarray,
                 layout: BodyLayout, frames: Callable[[], _Frames]) -> None:
        object.__setattr__(self, "nq", int(nq))
        object.__setattr__(self, "nv", int(nv))
        object.__setattr__(self, "nu", int(len(ctrlrange)))
        object.__setattr__(self, "nbody", len(layout.bodies))
        object.__setattr__(self, "nsite", len(layout.sites))
        object.__setattr__(self, "opt", _Options(timestep))
        object.__setattr__(self, "actuator_ctrlrange", _frozen(ctrlrange))
        object.__setattr__(self, "_layout", layout)
        object.__setattr__(self, "_frames", frames)

    @property
    def body_mass(self) -> np.ndarray:
        return self._frames().body_mass

    def body(self, key: Union[int, str]) -> SimpleNamespace:
        """One body's ``id``, ``name`` and ``mass`` (an array of one, as MuJoCo's)."""
        names = self._layout.bodies
        b = _lookup(names, key, "body", len(names))
        return SimpleNamespace(id=b, name=names[b], mass=self._frames().body_mass[b : b + 1])

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError(
            f"model.{name} cannot be changed on a gymfleet env: the server simulates the file "
            "it was given (make the env with another xml_file or frame_skip instead)"
        )

    def __getattr__(self, name: str) -> Any:
        raise AttributeError(
            f"model.{name} is not offered by gymfleet's envs (they offer model."
            f"{', model.'.join(MODEL_FIELDS)})"
        )


class _Options(SimpleNamespace):
    """``model.opt``: the timestep, read-only."""

    def __init__(self, timestep: float) -> None:
        super().__init__()
        object.__setattr__(self, "timestep", float(timestep))

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError(
            f"model.opt.{name} cannot be changed on a gymfleet env: the server simulates the "
            "file it was given (make the env with another xml_file or frame_skip instead)"
        )


class FrameCache:
    """The body-level fields of the env's state now: read from the server on first use,
    kept until ``clear()`` (each reset, step and ``set_state``)."""

    def __init__(self, env: Any, layout: BodyLayout, free: bool, qpos: Callable[[], np.ndarray]) -> None:
        self._env, self._layout, self._free, self._qpos = env, layout, free, qpos
        self._frames: Optional[_Frames] = None

    def clear(self) -> None:
        self._frames = None

    def __call__(self) -> _Frames:
        if self._frames is None:
            self._frames = _Frames(self._layout, self._env.bodies(), self._qpos(), self._free)
        return self._frames


def checked_state(qpos: Any, qvel: Any, nq: int, nv: int) -> Tuple[np.ndarray, np.ndarray]:
    """``set_state``'s arguments as float64 arrays of MuJoCo's shapes ``(nq,)`` and
    ``(nv,)``, finite; else ``InvalidArgument`` saying which and why."""
    out = []
    for name, values, n in (("qpos", qpos, nq), ("qvel", qvel, nv)):
        try:
            array = np.array(values, dtype=np.float64)
        except (TypeError, ValueError):
            raise InvalidArgument(f"set_state: {name} must be numbers, got {type(values).__name__}") from None
        if array.shape != (n,):
            raise InvalidArgument(
                f"set_state: {name} has shape {array.shape}; the model's is ({n},) "
                f"(model.{'nq' if name == 'qpos' else 'nv'})"
            )
        bad = np.flatnonzero(~np.isfinite(array))
        if len(bad):
            raise InvalidArgument(f"set_state: {name}[{bad[0]}] is {array[bad[0]]}; expected finite numbers")
        out.append(array)
    return out[0], out[1]


def state_vector(qpos: np.ndarray, qvel: np.ndarray) -> np.ndarray:
    """MuJoCo's ``state_vector()``: qpos, then qvel."""
    return np.concatenate([qpos, qvel]).astype(np.float64)


def qpos_qvel(q: np.ndarray, v: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """One row's qpos and qvel (float64) from ``_Setup.split``'s (1, n) arrays."""
    return np.asarray(q[0], dtype=np.float64), np.asarray(v[0], dtype=np.float64)

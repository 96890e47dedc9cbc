"""The MuJoCo XML files the suite's envs read (by default Gymnasium's own, from the
installed gymnasium's ``envs/mujoco/assets``), and what the plans take from one: MuJoCo's
joints in qpos order, its bodies and their geoms, actuators, tendons, the root geom's frame
(``read_model``)."""

from __future__ import annotations

import os
import pathlib
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from typing import List, Optional, Tuple

import numpy as np

from ..errors import InvalidArgument


@dataclass
class Model:
    """What the plans read from the XML file: MuJoCo's joints in qpos order (a free
    joint apart: it is the converted robot's floating base), its bodies and its
    timestep."""

    path: str
    text: str
    #: The joints with one DOF each, in qpos order.
    joints: List[str]
    #: Each joint's ``ref`` as written (MuJoCo's qpos0; metres for slide joints).
    refs: List[float]
    timestep: float
    #: The free joint's name, if the first body has one (qpos[0:7], qvel[0:6]).
    free: Optional[str] = None
    #: MuJoCo's bodies but the world, in body order: each name and its geoms' names
    #: (the instances the conversion makes of it).
    bodies: List[Tuple[str, List[str]]] = field(default_factory=list)
    #: The joint each actuator drives, in actuator (ctrl) order.
    actuators: List[str] = field(default_factory=list)
    #: Fixed tendons: each name and its (joint, coef) pairs.
    tendons: List[Tuple[str, List[Tuple[str, float]]]] = field(default_factory=list)
    #: The first body's height as written (MuJoCo's init_qpos[2] with a free joint).
    root_z: float = 0.0
    #: The first body's first geom (what the server observes as a floating base): its
    #: centre and orientation (w, x, y, z) in the body's frame; ``None`` when it is at the
    #: body's origin, unturned.
    root_geom: Optional[Tuple[np.ndarray, np.ndarray]] = None

    def index(self, name: str) -> int:
        return self.joints.index(name)


def assets_dir() -> pathlib.Path:
    import gymnasium

    return pathlib.Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"


def xml_path(xml_file: str) -> str:
    """As Gymnasium's ``MujocoEnv`` finds a model: a path starting with ``.``, ``/`` or
    ``~`` as it is, any other name in the installed gymnasium's assets."""
    if xml_file.startswith((".", "/")):
        return xml_file
    if xml_file.startswith("~"):
        return os.path.expanduser(xml_file)
    return str(assets_dir() / xml_file)


def read_model(xml_file: str) -> Model:
    path = xml_path(xml_file)
    if not os.path.isfile(path):
        raise InvalidArgument(f"xml_file: {path!r} does not exist")
    with open(path, encoding="utf-8") as f:
        text = f.read()
    return parse_model(path, text)


def parse_model(path: str, text: str) -> Model:
    """``read_model`` of XML ``text`` (``path`` names it in errors)."""
    try:
        root = ET.fromstring(text)
    except ET.ParseError as e:
        raise InvalidArgument(f"xml_file: {path!r} is not XML: {e}") from None
    world = root.find("worldbody")
    joints: List[str] = []
    refs: List[float] = []
    free: Optional[str] = None
    bodies: List[Tuple[str, List[str]]] = []
    if world is not None:
        for j in world.iter():
            if j.tag == "body":
                geoms = [g.get("name", "") for g in j.findall("geom")]
                bodies.append((j.get("name", ""), geoms))
            if j.tag == "freejoint" or (j.tag == "joint" and j.get("type") == "free"):
                if free is None and not joints:
                    free = j.get("name", "")
                    continue
            if j.tag in ("joint", "freejoint"):
                joints.append(j.get("name", ""))
                refs.append(float(j.get("ref", 0.0)))
    tendons: List[Tuple[str, List[Tuple[str, float]]]] = []
    for k, fixed in enumerate(root.iter("fixed")):
        pairs = [(j.get("joint", ""), float(j.get("coef", 0.0))) for j in fixed.findall("joint")]
        tendons.append((fixed.get("name", f"tendon{k}"), pairs))
    first = world.find("body") if world is not None else None
    root_z = float((first.get("pos") or "0 0 0").split()[2]) if first is not None else 0.0
    geom = first.find("geom") if first is not None else None
    compiler = root.find("compiler")
    radians = compiler is not None and compiler.get("angle") == "radian"
    root_geom = _geom_frame(geom, path, radians) if free is not None and geom is not None else None
    actuator = root.find("actuator")
    actuators = [a.get("joint", "") for a in actuator] if actuator is not None else []
    option = root.find("option")
    timestep = float(option.get("timestep", 0.002)) if option is not None else 0.002
    return Model(
        path=path,
        text=text,
        joints=joints,
        refs=refs,
        timestep=timestep,
        free=free,
        bodies=bodies,
        actuators=actuators,
        tendons=tendons,
        root_z=root_z,
        root_geom=root_geom,
    )


def _geom_frame(
    geom: ET.Element, path: str, radians: bool = False
) -> Optional[Tuple[np.ndarray, np.ndarray]]:
    """A geom's centre and orientation in its body's frame, as the conversion places its
    instance: ``fromto``'s midpoint and the shortest turn of z onto its axis, or ``pos``
    and ``quat``; ``None`` for the body's own frame."""

    def numbers(name: str, n: int) -> Optional[np.ndarray]:
        text = geom.get(name)
        if text is None:
            return None
        values = np.array([float(x) for x in text.split()])
        if len(values) != n:
            raise InvalidArgument(f"xml_file: {path}: the first geom's {name} needs {n} numbers")
        return values

    unsupported = [a for a in ("axisangle", "xyaxes", "zaxis") if geom.get(a) is not None]
    if unsupported:
        raise InvalidArgument(
            f"xml_file: {path}: the free body's first geom is turned by {unsupported[0]}; "
            "the suite reads the body's frame from a geom placed by fromto, or pos and quat or euler"
        )
    fromto = numbers("fromto", 6)
    if fromto is not None:
        a, b = fromto[:3], fromto[3:]
        axis = (b - a) / np.linalg.norm(b - a)
        d = axis[2]
        if d < -1.0 + 1e-9:
            quat = np.array([0.0, 1.0, 0.0, 0.0])  # half a turn about x
        else:
            quat = np.array([1.0 + d, -axis[1], axis[0], 0.0])  # w = 1 + z·axis, z × axis
            quat /= np.linalg.norm(quat)
        centre = (a + b) / 2.0
    else:
        centre = numbers("pos", 3)
        centre = np.zeros(3) if centre is None else centre
        quat = numbers("quat", 4)
        euler = numbers("euler", 3)
        if euler is not None:
            quat = _euler_xyz(euler if radians else np.radians(euler))
        quat = np.array([1.0, 0.0, 0.0, 0.0]) if quat is None else quat / np.linalg.norm(quat)
    if np.allclose(centre, 0.0) and np.allclose(quat, [1.0, 0.0, 0.0, 0.0]):
        return None
    return centre, quat


def _euler_xyz(angles: np.ndarray) -> np.ndarray:
    """MuJoCo's ``euler`` with its default ``eulerseq="xyz"`` (turns about the frame's own
    x, then y, then z) as a quaternion (w, x, y, z); the angles in radians."""
    out = np.array([1.0, 0.0, 0.0, 0.0])
    for axis, angle in enumerate(angles):
        turn = np.zeros(4)
        turn[0], turn[1 + axis] = np.cos(angle / 2), np.sin(angle / 2)
        w1, x1, y1, z1 = out
        w2, x2, y2, z2 = turn
        out = np.array([
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        ])
    return out

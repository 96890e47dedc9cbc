"""The Control Suite's XML files, read from the installed ``dm_control`` (the ``[dmc]``
extra), with their ``<include>``s of ``./common/*.xml`` written in place, so that the
text alone makes the model on any server (embedded, remote or a fleet)."""

from __future__ import annotations

import pathlib
import re
import xml.etree.ElementTree as ET
from typing import List

from ..errors import InvalidArgument

_INCLUDE = re.compile(r"<include\s+file=\"([^\"]+)\"\s*/>")
_BODY = re.compile(r"<mujoco[^>]*>(.*)</mujoco>", re.S)


def suite_dir() -> pathlib.Path:
    """The installed dm_control's ``suite`` folder (its XML files)."""
    try:
        import importlib.util

        spec = importlib.util.find_spec("dm_control")
    except (ImportError, ValueError):
        spec = None
    if spec is None or not spec.submodule_search_locations:
        raise InvalidArgument(
            "the Control Suite's ids read their models from dm_control, which is not installed: "
            "pip install './client/python[dmc]' (or pip install dm-control)"
        )
    return pathlib.Path(list(spec.submodule_search_locations)[0]) / "suite"


def read_suite_xml(xml: str) -> str:
    """The text of ``xml`` (a file of dm_control's suite), its includes inlined."""
    folder = suite_dir()
    path = folder / xml
    if not path.is_file():
        raise InvalidArgument(f"{path} does not exist (is the installed dm_control complete?)")
    text = path.read_text(encoding="utf-8")

    def inline(match: "re.Match[str]") -> str:
        included = (folder / match.group(1)).resolve()
        if not included.is_file() or folder.resolve() not in included.parents:
            raise InvalidArgument(f"{path}: include {match.group(1)!r} is not in {folder}")
        body = _BODY.search(included.read_text(encoding="utf-8"))
        if body is None:
            raise InvalidArgument(f"{included}: expected a <mujoco> root")
        return body.group(1)

    return _INCLUDE.sub(inline, text)


def generated_xml(domain: str, *args: object, maker: str = "get_model_and_assets") -> str:
    """The model dm_control's ``suite.<domain>.<maker>(*args)`` makes in Python
    (swimmer's links, manipulator's props), its includes inlined from the assets it
    returns."""
    import importlib
    import warnings

    suite_dir()  # a clear error without dm_control
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # glfw: no display
        module = importlib.import_module(f"dm_control.suite.{domain}")
    xml, assets = getattr(module, maker)(*args)
    text = xml.decode("utf-8") if isinstance(xml, bytes) else str(xml)

    def inline(match: "re.Match[str]") -> str:
        name = match.group(1)
        data = assets.get(name)
        if data is None:
            raise InvalidArgument(f"dm_control's {domain} model includes {name!r}, which it does not ship")
        body = _BODY.search(data.decode("utf-8") if isinstance(data, bytes) else str(data))
        if body is None:
            raise InvalidArgument(f"{name}: expected a <mujoco> root")
        return body.group(1)

    return _INCLUDE.sub(inline, text)


def timestep(text: str) -> float:
    """The model's ``<option timestep>`` (MuJoCo's default 0.002)."""
    match = re.search(r"<option[^>]*\btimestep=\"([^\"]+)\"", text)
    return float(match.group(1)) if match else 0.002



def body_names(text: str) -> List[str]:
    """MuJoCo's bodies but the world, in body order ("" for an unnamed one)."""
    world = ET.fromstring(text).find("worldbody")
    return [] if world is None else [b.get("name", "") for b in world.iter("body")]

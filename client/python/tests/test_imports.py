"""MuJoCo's own descriptions from Python: Gymnasium's Reacher (the XML in the gymnasium
wheel) made with gymfleet moves as MuJoCo moves it, within 2 % over 0.5 s."""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

import gymfleet

gymnasium = pytest.importorskip("gymnasium")
mujoco = pytest.importorskip("mujoco")

ASSETS = pathlib.Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"
REACHER = ASSETS / "reacher.xml"


def _torque(k: int) -> np.ndarray:
    t = 0.01 * k
    return np.array([0.3 * np.sin(4 * t) + 0.1, 0.2 * np.cos(6 * t)])


def test_reacher_follows_mujocos_trajectory_within_two_percent():
    # MuJoCo: its own model, RK4 at 0.01 s, motor ctrl = torque / gear (gear 200).
    model = mujoco.MjModel.from_xml_path(str(REACHER))
    data = mujoco.MjData(model)
    steps = 50
    reference = []
    for k in range(steps):
        data.ctrl[:] = _torque(k) / 200.0
        mujoco.mj_step(model, data)
        reference.append(data.qpos[:2].copy())
    reference = np.array(reference)

    # gymfleet: the same file, converted by the server; one env step per MuJoCo step.
    env = gymfleet.make(REACHER, end_effector_ids=["fingertip"], dt=0.01)
    assert env.action_space.shape == (2,)
    env.reset(seed=0)
    ours = []
    for k in range(steps):
        obs, *_ = env.step(_torque(k).astype(np.float32))
        ours.append(np.radians(obs[:2]))
    env.close()
    ours = np.array(ours)

    span = reference.max(axis=0) - reference.min(axis=0)
    error = np.abs(ours - reference).max(axis=0) / span
    assert (error < 0.02).all(), f"per-joint error {error} of MuJoCo's range {span}"


def test_convert_shows_the_json_and_the_warnings():
    document, warnings = gymfleet.convert(REACHER)
    names = [j["name"] for j in document["assembly"]["joints"] if j["type"] != "fixed"]
    assert names == ["joint0", "joint1", "target_x", "target_y"]
    assert any("timestep 0.01 s not applied" in w for w in warnings), warnings
    # The dict builds the same env.
    env = gymfleet.make(document, end_effector_ids=["fingertip"])
    assert env.action_space.shape == (2,)
    env.close()


def test_unsupported_mjcf_raises_with_element_and_line():
    xml = "<mujoco>\n<worldbody>\n<body><freejoint/><geom size='.1'/></body>\n</worldbody>\n</mujoco>"
    with pytest.raises(gymfleet.InvalidArgument, match=r"line 3: <freejoint>: a free joint"):
        gymfleet.make(xml)

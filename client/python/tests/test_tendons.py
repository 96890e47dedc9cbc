"""Fixed tendons (`<tendon><fixed>`) against MuJoCo: a springy, damped tendon coupling a
double pendulum's joints follows MuJoCo's trajectory, its length and rate read as terms;
Gymnasium's Humanoid converts with its two tendons."""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

import gymfleet

gymnasium = pytest.importorskip("gymnasium")
mujoco = pytest.importorskip("mujoco")

def _double_pendulum(tendon: str) -> str:
    """A horizontal double pendulum (hinges `shoulder` and `elbow` about y) with `tendon`."""
    return f"""<mujoco>
  <option timestep="0.002"/>
  <worldbody>
    <geom type="plane" size="1 1 0.1" contype="0" conaffinity="0"/>
    <body name="upper" pos="0 0 1">
      <joint name="shoulder" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
      <body name="lower" pos="0.3 0 0">
        <joint name="elbow" type="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
      </body>
    </body>
  </worldbody>
  <tendon>
    {tendon}
  </tendon>
</mujoco>"""


XML = _double_pendulum(
    """<fixed name="coupling" stiffness="8" damping="0.3" springlength="0.2">
      <joint joint="shoulder" coef="1"/><joint joint="elbow" coef="-0.5"/>
    </fixed>"""
)

TASK = {
    "terms": [
        {"name": "length", "weight": 0, "value": {"tendon_length": "coupling"}},
        {"name": "rate", "weight": 0, "value": {"tendon_velocity": "coupling"}},
    ]
}


def test_a_springy_tendon_follows_mujocos_trajectory():
    env = gymfleet.make(XML, units="si", task=TASK, dt=0.002)
    env.reset(seed=0)
    model = mujoco.MjModel.from_xml_string(XML)
    data = mujoco.MjData(model)
    worst_angle = worst_length = 0.0
    for _ in range(500):  # 1 s: the pendulum swings through large angles
        obs, _, _, _, info = env.step(np.zeros(env.action_space.shape, np.float32))
        mujoco.mj_step(model, data)
        worst_angle = max(worst_angle, float(np.abs(obs[:2] - data.qpos).max()))
        worst_length = max(worst_length, abs(info["length"] - data.ten_length[0]))
        # The terms are the length and rate of the observed joints (SI).
        assert info["length"] == pytest.approx(obs[0] - 0.5 * obs[1], abs=1e-5)
        assert info["rate"] == pytest.approx(obs[2] - 0.5 * obs[3], abs=1e-4)
    assert worst_angle < 0.02, f"joint angles {worst_angle} rad from MuJoCo's"
    assert worst_length < 0.01, f"tendon length {worst_length} from MuJoCo's"
    # Without the tendon the same pendulum moves quite differently: the test can tell.
    free = gymfleet.make(XML.replace('stiffness="8" damping="0.3"', ""), units="si", dt=0.002)
    free.reset(seed=0)
    for _ in range(500):
        free_obs, *_ = free.step(np.zeros(free.action_space.shape, np.float32))
    assert np.abs(free_obs[:2] - data.qpos).max() > 0.3


def test_the_humanoid_converts_with_its_tendons():
    path = pathlib.Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets" / "humanoid.xml"
    document, _ = gymfleet.convert(str(path))
    tendons = {t["name"]: t["joints"] for t in document["assembly"]["tendons"]}
    assert tendons == {
        "left_hipknee": [{"joint": "left_hip_y", "coef": -1.0}, {"joint": "left_knee", "coef": 1.0}],
        "right_hipknee": [{"joint": "right_hip_y", "coef": -1.0}, {"joint": "right_knee", "coef": 1.0}],
    }
    task = {"terms": [{"name": "l", "weight": 0, "value": {"tendon_length": "left_hipknee"}}]}
    env = gymfleet.make(str(path), units="si", task=task)
    obs, _ = env.reset(seed=0)
    names = [j["name"] for j in env.env_info["joints"]]
    for _ in range(5):
        obs, _, _, _, info = env.step(np.zeros(env.action_space.shape, np.float32))
    q = dict(zip(names, obs[: len(names)]))
    assert info["l"] == pytest.approx(q["left_knee"] - q["left_hip_y"], abs=1e-5)


RANGED = _double_pendulum(
    '<fixed name="stop" range="-0.4 0.6"><joint joint="shoulder" coef="1"/>'
    '<joint joint="elbow" coef="0.5"/></fixed>'
)


def test_a_ranged_tendon_stops_the_fall_where_mujocos_does():
    """A horizontal double pendulum falls until shoulder + elbow/2 reaches the tendon's 0.6:
    gymfleet's stop is hard (never past it), MuJoCo's soft (slightly past, then back);
    both come to rest on it."""
    task = {"terms": [{"name": "length", "weight": 0, "value": {"tendon_length": "stop"}}]}
    env = gymfleet.make(RANGED, units="si", task=task, dt=0.002)
    env.reset(seed=0)
    model = mujoco.MjModel.from_xml_string(RANGED)
    data = mujoco.MjData(model)
    ours, theirs = [], []
    for _ in range(1500):
        _, _, _, _, info = env.step(np.zeros(env.action_space.shape, np.float32))
        mujoco.mj_step(model, data)
        ours.append(info["length"])
        theirs.append(data.ten_length[0])
    ours, theirs = np.array(ours), np.array(theirs)
    assert ours.max() <= 0.6 + 1e-4, "a hard stop"
    assert theirs.max() > 0.6, "MuJoCo's soft limit lets it past a little"
    # Both reach it at about the same time and rest on it at the end.
    assert abs(np.argmax(ours > 0.59) - np.argmax(theirs > 0.59)) <= 10
    assert ours[-1] == pytest.approx(0.6, abs=1e-3)
    assert theirs[-1] == pytest.approx(0.6, abs=0.01)


SPATIAL = """<mujoco>
  <option timestep="0.002" gravity="0 0 0"/>
  <worldbody>
    <site name="anchor" pos="0 0 0"/>
    <site name="via" pos="0.2 0.1 0"/>
    <body name="ball" pos="0.4 0 0">
      <joint name="x" type="slide" axis="1 0 0"/>
      <joint name="y" type="slide" axis="0 1 0"/>
      <geom type="sphere" size="0.03" mass="0.5" contype="0" conaffinity="0"/>
      <site name="ball" pos="0 0.02 0"/>
    </body>
  </worldbody>
  <tendon>
    <spatial name="s" stiffness="20" damping="0.5" springlength="0.3">
      <site site="anchor"/><site site="via"/><site site="ball"/>
    </spatial>
  </tendon>
  <actuator><motor name="pull" tendon="s" gear="2"/></actuator>
</mujoco>"""


def test_a_spatial_tendon_through_a_via_point_follows_mujocos_trajectory():
    """A ball on two slides pulled by a springy, damped spatial tendon through a fixed
    via-point, and by a motor on the tendon: the ball's path, the tendon's length and
    rate follow MuJoCo's."""
    task = {"terms": [
        {"name": "length", "weight": 0, "value": {"tendon_length": "s"}},
        {"name": "rate", "weight": 0, "value": {"tendon_velocity": "s"}},
    ]}
    env = gymfleet.make(SPATIAL, units="si", task=task, dt=0.002)
    env.reset(seed=0)
    model = mujoco.MjModel.from_xml_string(SPATIAL)
    data = mujoco.MjData(model)
    worst = {"position": 0.0, "length": 0.0, "rate": 0.0}
    for k in range(500):
        ctrl = -0.5 if k < 250 else 0.3
        data.ctrl[0] = ctrl
        obs, _, _, _, info = env.step(np.array([ctrl], np.float32))
        mujoco.mj_step(model, data)
        mujoco.mj_forward(model, data)
        worst["position"] = max(worst["position"], float(np.abs(obs[:2] - data.qpos).max()))
        worst["length"] = max(worst["length"], abs(info["length"] - data.ten_length[0]))
        worst["rate"] = max(worst["rate"], abs(info["rate"] - data.ten_velocity[0]))
    assert worst["position"] < 2e-3, worst
    assert worst["length"] < 2e-3, worst
    assert worst["rate"] < 2e-2, worst
    # The ball went somewhere: over 5 cm from its start.
    assert np.linalg.norm(data.qpos) > 0.05


def test_a_spatial_tendon_pulls_a_free_body_as_mujocos_does():
    """A free ball tied to a world site by a springy, damped spatial tendon (no gravity),
    released 0.1 m past the rest length: its path follows MuJoCo's (the knot is off its
    centre, so the string turns it too)."""
    xml = """<mujoco>
  <option timestep="0.002" gravity="0 0 0"/>
  <worldbody>
    <site name="hook" pos="0 0 0"/>
    <body name="ball" pos="0.3 0 0"><freejoint/>
      <geom type="sphere" size="0.04" mass="0.3" contype="0" conaffinity="0"/>
      <site name="knot" pos="-0.03 0.01 0"/></body>
  </worldbody>
  <tendon><spatial name="s" stiffness="15" damping="0.2" springlength="0.2">
    <site site="hook"/><site site="knot"/></spatial></tendon>
</mujoco>"""
    env = gymfleet.make(xml, units="si", dt=0.002)
    env.reset(seed=0)
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    worst = 0.0
    at = 0
    for segment, size in env.env_info["observation_layout"]:
        if segment == "free_body_poses":
            break
        at += size
    for _ in range(500):
        obs, *_ = env.step(np.zeros(env.action_space.shape, np.float32))
        mujoco.mj_step(model, data)
        worst = max(worst, float(np.abs(obs[at:at + 3] - data.qpos[:3]).max()))
    assert worst < 2e-3, f"{worst} m from MuJoCo's path"
    # The string pulled it well in from 0.3 m.
    assert np.linalg.norm(data.qpos[:3]) < 0.25

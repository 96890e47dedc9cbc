"""Keyframes: an MJCF file's ``<key>`` elements are the document's named initial states;
``reset(options={"keyframe": name_or_index})`` starts from one, checked against MuJoCo's
``mj_resetDataKeyframe`` on the same file: the same qpos and qvel, and every body within
1 µm."""

from __future__ import annotations

import numpy as np
import pytest

import gymfleet
from gymfleet.errors import InvalidArgument

mujoco = pytest.importorskip("mujoco")

#: A floating torso (its box off the body's origin and turned, so that its instance's frame
#: is not the body's) with a hip (ref 10°, limited), a knee and a sliding ankle below, and
#: three keys: one moving every joint and the base, one unnamed, one setting the hip only.
XML = """<mujoco>
  <option timestep="0.002"/>
  <worldbody>
    <geom type="plane" size="5 5 .1"/>
    <body name="torso" pos="0 0 1">
      <freejoint/>
      <geom type="box" size=".1 .05 .02" pos=".03 0 .01" euler="0 0 20"/>
      <body name="thigh" pos=".1 0 0">
        <joint name="hip" type="hinge" axis="0 1 0" range="-90 90" ref="10"/>
        <geom type="capsule" fromto="0 0 0 0 0 -.3" size=".02"/>
        <body name="shin" pos="0 0 -.3">
          <joint name="knee" type="hinge" axis="0 1 0"/>
          <geom type="capsule" fromto="0 0 0 0 0 -.3" size=".02"/>
          <body name="foot" pos="0 0 -.3">
            <joint name="ankle" type="slide" axis="1 0 0" range="-.1 .1"/>
            <geom type="sphere" size=".03"/>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
  <keyframe>
    <key name="crouch" qpos="0.2 -0.1 0.8 0.9659258 0 0.258819 0 0.5 -1.0 0.05"
         qvel="0.3 0 -0.1 0 0.5 0.2 1.0 -2 0.1"/>
    <key qpos="0 0 1.2 0.7071068 0 0 0.7071068 -0.3 0.4 -0.02"/>
    <key name="hip_only" qpos="0 0 1 1 0 0 0 0.6 0 0"/>
  </keyframe>
</mujoco>"""

BODIES = ["torso", "thigh", "shin", "foot"]


def made(**options):
    return gymfleet.make(XML, units="si", end_effector_ids=[f"site:{b}" for b in BODIES], **options)


def layout(env):
    out, at = {}, 0
    for segment, size in env.env_info["observation_layout"]:
        out[segment] = slice(at, at + size)
        at += size
    return out


def mujocos(key: int):
    model = mujoco.MjModel.from_xml_string(XML)
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, key)
    mujoco.mj_forward(model, data)
    return model, data


@pytest.mark.parametrize("key", [0, 1, 2])
def test_a_keyframe_reset_is_mujocos(key):
    env = made()
    assert env.env_info["keyframes"] == ["crouch", "key1", "hip_only"]
    name = env.env_info["keyframes"][key]
    obs, _ = env.reset(options={"keyframe": name})
    model, data = mujocos(key)
    at = layout(env)
    # The joints: qpos[7:] and qvel[6:], as observed with SI units.
    np.testing.assert_allclose(obs[at["joint_positions"]], data.qpos[7:], atol=1e-6)
    np.testing.assert_allclose(obs[at["joint_velocities"]], data.qvel[6:], atol=1e-5)
    # Every body's frame within 1 µm, its orientation within 1e-6 rad.
    poses = obs[at["end_effector_poses"]].reshape(-1, 7)
    for body, pose in zip(BODIES, poses):
        b = model.body(body).id
        np.testing.assert_allclose(pose[:3], data.xpos[b], atol=1e-6, err_msg=f"{body}'s position")
        dot = abs(float(np.dot(pose[3:], data.xquat[b])))
        assert dot > 1 - 1e-6, f"{body} is turned from MuJoCo's: {pose[3:]} vs {data.xquat[b]}"
    # The base's velocity: its centre's (the torso's xipos) and its angular one, world.
    torso = model.body("torso").id
    omega = data.xmat[torso].reshape(3, 3) @ data.qvel[3:6]
    centre = data.qvel[0:3] + np.cross(omega, data.xipos[torso] - data.xpos[torso])
    velocity = obs[at["base_velocity"]]
    np.testing.assert_allclose(velocity[:3], centre, atol=1e-5)
    np.testing.assert_allclose(velocity[3:], omega, atol=1e-5)
    env.close()


def test_a_keyframe_by_index_and_a_plain_reset():
    env = made()
    by_name, _ = env.reset(options={"keyframe": "hip_only"})
    by_index, _ = env.reset(options={"keyframe": 2})
    np.testing.assert_array_equal(by_name, by_index)
    plain, _ = env.reset()
    at = layout(env)
    # The file's pose: the hip at its ref, 10°.
    np.testing.assert_allclose(plain[at["joint_positions"]], [np.radians(10), 0, 0], atol=1e-6)
    env.close()


def test_bad_keyframes_say_what_the_document_has():
    env = made()
    with pytest.raises(InvalidArgument, match=r'keyframe: no keyframe is named "home"; the '
                       r'document\'s are "crouch", "key1", "hip_only"'):
        env.reset(options={"keyframe": "home"})
    with pytest.raises(InvalidArgument, match=r"options\['keyframe'\]: index 3 is out of range: "
                       r"the document has 3 keyframes \(crouch, key1, hip_only\)"):
        env.reset(options={"keyframe": 3})
    with pytest.raises(InvalidArgument, match=r"options\['keyframe'\]: expected a keyframe's name "
                       r"or index, got float"):
        env.reset(options={"keyframe": 1.5})
    env.close()


def test_a_vector_env_resets_to_a_keyframe_with_the_noise_on_top():
    envs = gymfleet.make_vec(XML, 3, units="si", reset_noise=1.0)
    at = layout_of(envs.batch_info)
    keyed, _ = envs.reset(seed=5, options={"keyframe": "hip_only"})
    plain, _ = envs.reset(seed=5)
    # The same draws (1 mm or 1°, in the document's units), from the keyframe's hip.
    hip = keyed[:, at["joint_positions"]][:, 0] - plain[:, at["joint_positions"]][:, 0]
    np.testing.assert_allclose(hip, 0.6 - np.radians(10), atol=1e-5)
    assert len({round(float(v), 6) for v in plain[:, at["joint_positions"]][:, 1]}) == 3
    envs.close()


def layout_of(info):
    out, at = {}, 0
    for segment, size in info["observation_layout"]:
        out[segment] = slice(at, at + size)
        at += size
    return out


#: A hinged arm (a motor and a filtered actuator on it) with a ball-jointed forearm, a free
#: box and a mocap body, and a key that moves them all (the forearm turned and spinning,
#: the box moving and spinning, the mocap body turned) and holds controls and an activation.
SCENE = """<mujoco>
  <worldbody>
    <geom type="plane" size="5 5 .1"/>
    <body name="arm" pos="0 0 .5">
      <joint name="hinge" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 .3 0 0" size=".02"/>
      <body name="fore" pos=".3 0 0">
        <joint name="wrist" type="ball"/>
        <geom type="capsule" fromto="0 0 0 .2 0 0" size=".02"/>
      </body>
    </body>
    <body name="box" pos="1 0 .1">
      <freejoint/>
      <geom type="box" size=".05 .04 .03"/>
    </body>
    <body name="hand" mocap="true" pos="-1 0 .5">
      <geom type="sphere" size=".05" contype="0" conaffinity="0"/>
    </body>
  </worldbody>
  <actuator>
    <motor name="lift" joint="hinge" gear="2"/>
    <general name="slow" joint="hinge" dyntype="filter" dynprm="0.5" gainprm="3"/>
  </actuator>
  <sensor>
    <actuatorfrc actuator="lift"/>
    <actuatorfrc actuator="slow"/>
  </sensor>
  <keyframe>
    <key name="moved" qpos="0.4  0.9238795 0 0.3826834 0  0.8 0.3 0.6 0.9238795 0 0 0.3826834"
         qvel="1.5  0.5 0 1.0  0.2 -0.1 0.3 0 0 2.0"
         mpos="-0.5 0.2 0.7" mquat="0.7071068 0.7071068 0 0" ctrl="0.4 0.8" act="0.3"/>
  </keyframe>
</mujoco>"""


def test_a_keyframe_places_free_and_mocap_bodies_as_mujoco_does():
    """``qpos``/``qvel`` of a ball joint and a free body, ``mpos``/``mquat`` of a mocap body:
    after a reset to the key, the ball joint and the free body are observed as the key has
    them (MuJoCo's qpos and qvel), and the bodies are where ``mj_resetDataKeyframe`` puts
    them, within 1 µm and 1e-6 rad; ``ctrl`` and ``act`` are held (the actuators' forces are MuJoCo's); the mocap
    body stays there as the env steps."""
    bodies = ["box", "hand", "fore"]
    env = gymfleet.make(SCENE, units="si", end_effector_ids=[f"site:{b}" for b in bodies])
    assert env.env_info["free_bodies"] == ["box"] and env.env_info["mocap_bodies"] == ["hand"]
    obs, _ = env.reset(options={"keyframe": "moved"})
    model = mujoco.MjModel.from_xml_string(SCENE)
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    mujoco.mj_forward(model, data)
    at = layout(env)
    # The hinge, then the ball joint as a rotation vector (45° about y) and its angular
    # velocity in the parent's axes (MuJoCo's qvel is in the forearm's).
    turn = np.zeros(4)
    mujoco.mju_mulQuat(turn, data.qpos[1:5], np.array([0.0, *data.qvel[1:4]]))
    mujoco.mju_mulQuat(turn, turn, data.qpos[1:5] * [1, -1, -1, -1])
    np.testing.assert_allclose(obs[at["joint_positions"]], [0.4, 0, np.pi / 4, 0], atol=1e-6)
    np.testing.assert_allclose(obs[at["joint_velocities"]], [1.5, *turn[1:]], atol=1e-5)
    np.testing.assert_allclose(obs[at["free_body_poses"]], data.qpos[5:12], atol=1e-6)
    np.testing.assert_allclose(obs[at["free_body_velocities"]], data.qvel[4:10], atol=1e-5)
    ee = obs[at["end_effector_poses"]].reshape(-1, 7)
    for k, body in enumerate(bodies):
        b = model.body(body).id
        np.testing.assert_allclose(ee[k, :3], data.xpos[b], atol=1e-6, err_msg=body)
        assert abs(abs(ee[k, 3:] @ data.xquat[b]) - 1) < 1e-6, (body, ee[k, 3:], data.xquat[b])
    np.testing.assert_allclose(env.bodies()["sensordata"], data.sensordata, atol=1e-6)
    assert data.sensordata @ data.sensordata > 0
    for _ in range(10):
        obs, *_ = env.step(np.zeros(env.action_space.shape, dtype=np.float32))
    hand = obs[at["end_effector_poses"]].reshape(-1, 7)[1]
    np.testing.assert_allclose(hand[:3], [-0.5, 0.2, 0.7], atol=1e-6)
    env.close()

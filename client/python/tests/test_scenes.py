"""Scenes from Python (issue Z1): includes resolved as MuJoCo resolves them, mocap targets
set on one env and with a vector step, free bodies in the observation."""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

import gymfleet

mujoco = pytest.importorskip("mujoco")


def write(root: pathlib.Path, files: dict) -> None:
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)


def test_nested_includes_resolve_from_the_main_files_folder_as_in_mujoco(tmp_path):
    """models/main.xml includes sub/a.xml, which includes b.xml and ../shared/c.xml: MuJoCo
    reads every include from the main file's folder (models/), not the including file's."""
    write(tmp_path, {
        "models/main.xml": '<mujoco><include file="sub/a.xml"/>'
                           '<worldbody><geom name="floor" type="plane" size="1 1 0.1"/></worldbody></mujoco>',
        "models/sub/a.xml": '<mujoco><include file="b.xml"/><include file="../shared/c.xml"/></mujoco>',
        "models/b.xml": '<mujoco><worldbody><body name="from_models" pos="0 0 1">'
                        '<freejoint/><geom size="0.1"/></body></worldbody></mujoco>',
        "models/sub/b.xml": '<mujoco><worldbody><body name="from_sub" pos="0 0 2">'
                            '<freejoint/><geom size="0.1"/></body></worldbody></mujoco>',
        "shared/c.xml": '<mujoco><worldbody><body name="shared" pos="1 0 1">'
                        '<freejoint/><geom size="0.1"/></body></worldbody></mujoco>',
    })
    main = tmp_path / "models" / "main.xml"
    model = mujoco.MjModel.from_xml_path(str(main))
    theirs = {model.body(b).name: model.body_pos[b] for b in range(1, model.nbody)}
    assert set(theirs) == {"from_models", "shared"}
    env = gymfleet.make(main, assets=tmp_path, units="si")
    assert sorted(env.env_info["free_bodies"]) == sorted(theirs)
    obs, _ = env.reset(seed=0)
    layout = dict(env.env_info["observation_layout"])
    poses = obs[: layout["free_body_poses"]].reshape(-1, 7)
    for name, pose in zip(env.env_info["free_bodies"], poses):
        np.testing.assert_allclose(pose[:3], theirs[name], atol=1e-6, err_msg=name)
    env.close()
    # Sent from the model's own folder, the ../ include climbs out of the assets.
    with pytest.raises(gymfleet.InvalidArgument, match=r'"\.\./shared/c\.xml".*climbs above'):
        gymfleet.make(main, assets=tmp_path / "models")



def test_every_body_orientation_attribute_matches_mujoco():
    """quat, euler, axisangle, xyaxes (y not orthogonal to x) and zaxis: the free bodies'
    observed orientations are MuJoCo's qpos on the same model."""
    xml = ('<mujoco><worldbody>'
           '<body name="q" pos="0 0 1" quat="0.7 0.1 0.5 0.2"><freejoint/><geom size="0.1"/></body>'
           '<body name="e" pos="1 0 1" euler="30 -20 75"><freejoint/><geom size="0.1"/></body>'
           '<body name="a" pos="2 0 1" axisangle="1 2 3 40"><freejoint/><geom size="0.1"/></body>'
           '<body name="x" pos="3 0 1" xyaxes="1 1 0 0.3 1 1"><freejoint/><geom size="0.1"/></body>'
           '<body name="z" pos="4 0 1" zaxis="0 1 1"><freejoint/><geom size="0.1"/></body>'
           '</worldbody></mujoco>')
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    env = gymfleet.make(xml, units="si")
    obs, _ = env.reset(seed=0)
    layout = dict(env.env_info["observation_layout"])
    poses = obs[: layout["free_body_poses"]].reshape(-1, 7)
    for name, pose in zip(env.env_info["free_bodies"], poses):
        theirs = data.body(name).xquat
        # q and -q are one rotation.
        sign = 1.0 if np.dot(pose[3:], theirs) >= 0 else -1.0
        np.testing.assert_allclose(sign * pose[3:], theirs, atol=1e-6, err_msg=name)
        np.testing.assert_allclose(pose[:3], data.body(name).xpos, atol=1e-6, err_msg=name)
    env.close()

HANDLE = {
    "parts": [
        {"name": "Anchor", "primitive": {"type": "sphere", "radius": 1}},
        {"name": "Paddle", "primitive": {"type": "cube", "size": {"x": 40, "y": 40, "z": 10}}},
        {"name": "Cube", "primitive": {"type": "cube", "size": {"x": 20, "y": 20, "z": 20}}},
    ],
    "assembly": {"instances": [
        {"part": "Anchor", "name": "anchor", "collision": {"group": 0, "mask": 0}},
        {"part": "Paddle", "name": "paddle", "position": {"x": -20, "y": -20, "z": 0}, "mocap": True},
        {"part": "Cube", "name": "box", "position": {"x": -10, "y": -10, "z": 10}},
    ], "joints": []},
}


def test_a_mocap_target_set_on_one_env_moves_its_body():
    env = gymfleet.make(HANDLE, end_effector_ids=["paddle"])
    assert env.env_info["mocap_bodies"] == ["paddle"]
    assert env.env_info["free_bodies"] == ["box"]
    env.reset(seed=0)
    for k in range(1, 61):
        env.set_mocap_pose("paddle", (0.0, 0.0, 5.0 + 50.0 * k / 60), (1.0, 0.0, 0.0, 0.0))
        obs, *_ = env.step(np.zeros(0, dtype=np.float32))
    layout = dict(env.env_info["observation_layout"])
    start = layout["free_body_poses"] + layout["free_body_velocities"]
    paddle = obs[start:start + 7]
    assert abs(paddle[2] - 55.0) < 1e-3
    box = obs[: layout["free_body_poses"]]
    assert abs(box[2] - 70.0) < 0.5, f"the box rides on the paddle: {box}"
    with pytest.raises(gymfleet.InvalidArgument, match=r'unknown mocap body "hand" \(known: "paddle"\)'):
        env.set_mocap_pose("hand", (0, 0, 0))
    with pytest.raises(gymfleet.InvalidArgument, match="the quaternion .* is zero"):
        env.set_mocap_pose("paddle", (0, 0, 0), (0, 0, 0, 0))
    env.close()


def test_a_vector_env_sends_every_envs_mocap_targets_with_its_step():
    envs = gymfleet.make_vec(HANDLE, 3, end_effector_ids=["paddle"])
    envs.reset(seed=0)
    heights = np.array([10.0, 20.0, 30.0])
    for k in range(1, 61):
        poses = np.zeros((3, 1, 7), dtype=np.float32)
        poses[:, 0, 2] = 5.0 + heights * k / 60
        poses[:, 0, 3] = 1.0
        envs.set_mocap_poses(poses)
        obs, *_ = envs.step(np.zeros((3, 0), dtype=np.float32))
    paddle_z = obs[:, -7 + 2]
    np.testing.assert_allclose(paddle_z, 5.0 + heights, atol=1e-3)
    with pytest.raises(ValueError, match=r"poses: expected 3 envs × 1 mocap bodies × 7 values"):
        envs.set_mocap_poses(np.zeros((3, 6)))
    envs.close()

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
        # Actions are MuJoCo's ctrl, as in MuJoCo: the motor's torque is gear × ctrl.
        obs, *_ = env.step((_torque(k) / 200.0).astype(np.float32))
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
    assert document["simulation"]["dt"] == 0.01  # MuJoCo's timestep: the env step
    # The dict builds the same env.
    env = gymfleet.make(document, end_effector_ids=["fingertip"])
    assert env.action_space.shape == (2,)
    env.close()


def test_unsupported_mjcf_raises_with_element_and_line():
    xml = "<mujoco>\n<worldbody>\n<body><geom size='.1'/><body><freejoint/><geom size='.1'/></body></body>\n</worldbody>\n</mujoco>"
    with pytest.raises(gymfleet.InvalidArgument, match=r"line 3: <freejoint>: a free joint belongs to a top-level body"):
        gymfleet.make(xml)


def test_the_ant_has_a_floating_base_and_passes_gymnasiums_checker():
    """Gymnasium's Ant: its free joint is a floating base, observed after the joint
    velocities as the torso's pose and velocity; dropped, it lands on its legs."""
    from test_env import checked

    env = gymfleet.make(ASSETS / "ant.xml")
    assert checked(env) == []
    layout = env.env_info["observation_layout"]
    assert [name for name, _ in layout] == [
        "joint_positions", "joint_velocities", "base_pose", "base_velocity", "end_effector_poses",
    ]
    assert env.observation_space.shape == (8 + 8 + 13,)
    assert env.action_space.shape == (8,)
    obs, _ = env.reset(seed=0)
    np.testing.assert_array_equal(obs[16:19], np.float32([0.0, 0.0, 750.0]))
    for _ in range(480):
        obs, *_ = env.step(np.zeros(8, dtype=np.float32))
    assert 300.0 < obs[18] < 450.0, f"the torso's centre rests at {obs[18]} mm"
    env.close()


# ROS's descriptions: example-robot-data's UR5 (a URDF with STL meshes), kept in the import
# crate's test data in the wheel's own layout.
ROBOTS = pathlib.Path(__file__).parents[3] / "crates" / "import" / "tests" / "data"
UR5 = ROBOTS / "example-robot-data" / "robots" / "ur_description" / "urdf" / "ur5_robot.urdf"


def test_a_urdf_with_its_meshes_holds_still_under_pd():
    env = gymfleet.make(UR5, assets=ROBOTS, action_type="position", end_effector_ids=["ee_link"])
    assert env.action_space.shape == (6,)
    names = [j["name"] for j in env.env_info["joints"]]
    assert names[:2] == ["shoulder_pan_joint", "shoulder_lift_joint"], names
    env.reset(seed=0)
    for _ in range(120):
        obs, *_ = env.step(np.zeros(6, dtype=np.float32))
    assert np.abs(obs[:6]).max() < 1.0, obs[:6]
    env.close()


def test_assets_may_be_a_folder_an_archive_or_bytes(tmp_path):
    import shutil

    archive = shutil.make_archive(str(tmp_path / "robots"), "gztar", ROBOTS)
    from_folder, warnings = gymfleet.convert(UR5, assets=ROBOTS)
    from_archive, _ = gymfleet.convert(UR5, assets=archive)
    with open(archive, "rb") as f:
        from_bytes, _ = gymfleet.convert(UR5, assets=f.read())
    assert from_folder == from_archive == from_bytes
    meshes = [p["primitive"] for p in from_folder["parts"] if p["primitive"]["type"] == "mesh"]
    assert len(meshes) == 7 and all("vertices" in m and "file" not in m for m in meshes)
    assert any("<visual> ignored" in w for w in warnings), warnings


def test_a_urdf_without_its_meshes_names_the_file():
    with pytest.raises(gymfleet.InvalidArgument, match=r"collision/base\.stl.*a mesh file is read from the request's assets"):
        gymfleet.make(UR5)
    with pytest.raises(gymfleet.InvalidArgument, match="assets: 'no/such/place' is neither a folder nor a file"):
        gymfleet.make(UR5, assets="no/such/place")


def test_a_library_model_is_made_by_name(tmp_path):
    import shutil

    shutil.copy(UR5, tmp_path / "ur5.urdf")
    shutil.copytree(ROBOTS / "example-robot-data", tmp_path / "example-robot-data")
    with gymfleet.Server(threads=1, models=str(tmp_path)) as server:
        env = gymfleet.make(model="ur5", server=server.address)
        assert env.action_space.shape == (6,)
        envs = gymfleet.make_vec(num_envs=3, model="ur5", server=server.address)
        assert envs.action_space.shape == (3, 6)
        envs.close()
        env.close()
    with pytest.raises(gymfleet.InvalidArgument, match="model: give a document or a model, not both"):
        gymfleet.make(UR5, model="ur5")


def test_the_half_cheetah_converts_with_its_springs_and_passes_the_checker():
    """HalfCheetah: `settotalmass` and joint springs; a planar root of three passive joints."""
    from test_env import checked

    env = gymfleet.make(ASSETS / "half_cheetah.xml")
    assert checked(env) == []
    assert env.action_space.shape == (6,)
    assert env.observation_space.shape == (9 + 9,)
    env.close()


def test_assets_over_the_message_limit_are_refused_naming_the_sizes():
    with pytest.raises(gymfleet.InvalidArgument, match=r"of assets\) is over the message limit of 67108864 bytes"):
        gymfleet.make(REACHER, assets=bytes(65 * 1024 * 1024))

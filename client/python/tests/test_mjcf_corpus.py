"""Real MuJoCo models from PyPI (issue Z1): dm_control's suite files and gymnasium-robotics'
scenes, loaded by gymfleet and by MuJoCo itself and compared on the same state. The files
are read where pip put them (``pip install --no-deps dm-control gymnasium-robotics``: files
only, nothing of either package is imported).

Which files load is stated in ``LOADS`` and ``LEFT``: a file of ``LEFT`` must still be
refused, with the element and line of its first unsupported construct, so that the lists
stay true."""

from __future__ import annotations

import importlib.util
import re
import shutil
import json
import pathlib
from typing import Dict, List, Tuple

import numpy as np
import pytest

import gymfleet

mujoco = pytest.importorskip("mujoco")


def package_dir(name: str) -> pathlib.Path:
    spec = importlib.util.find_spec(name)
    if spec is None or not spec.submodule_search_locations:
        pytest.fail(f"{name} is not installed: pip install --no-deps {name.replace('_', '-')}")
    return pathlib.Path(list(spec.submodule_search_locations)[0])


def corpus() -> Dict[str, Tuple[pathlib.Path, pathlib.Path]]:
    """Every file by a short name: (the file, the assets folder it is loaded with)."""
    suite = package_dir("dm_control") / "suite"
    robotics = package_dir("gymnasium_robotics") / "envs" / "assets"
    files = {f"dmc/{p.stem}": (p, suite) for p in sorted(suite.glob("*.xml"))}
    for group, names in {
        "fetch": ["reach", "push", "slide", "pick_and_place"],
        "hand": [
            "reach", "manipulate_block", "manipulate_block_touch_sensors", "manipulate_egg",
            "manipulate_egg_touch_sensors", "manipulate_pen", "manipulate_pen_touch_sensors",
        ],
        "adroit_hand": ["adroit_door", "adroit_hammer", "adroit_pen", "adroit_relocate"],
    }.items():
        for name in names:
            files[f"{group}/{name}"] = (robotics / group / f"{name}.xml", robotics)
    kitchen = robotics / "kitchen_franka"
    files["kitchen"] = (kitchen / "kitchen_assets" / "kitchen_env_model.xml", kitchen)
    return files


FILES = corpus()

#: The files gymfleet loads.
LOADS = [
    "dmc/acrobot", "dmc/cartpole", "dmc/cheetah", "dmc/finger", "dmc/hopper", "dmc/humanoid",
    "dmc/pendulum", "dmc/reacher", "dmc/walker", "dmc/humanoid_CMU", "dmc/swimmer",
    "dmc/fish", "dmc/point_mass", "dmc/ball_in_cup", "dmc/manipulator", "dmc/stacker",
    "dmc/quadruped", "dmc/dog",
    "fetch/reach", "fetch/push", "fetch/slide", "fetch/pick_and_place",
    "hand/reach", "hand/manipulate_block", "hand/manipulate_block_touch_sensors",
    "hand/manipulate_egg", "hand/manipulate_egg_touch_sensors", "hand/manipulate_pen",
    "hand/manipulate_pen_touch_sensors",
    "adroit_hand/adroit_door", "adroit_hand/adroit_hammer", "adroit_hand/adroit_pen",
    "adroit_hand/adroit_relocate", "kitchen",
]

#: The files still refused, each with what refuses it first and the issue that brings it
#: ("-": no issue names it yet).
LEFT: Dict[str, Tuple[str, str]] = {
}

#: The files that load but weigh differently from MuJoCo, each with why: their mass (and
#: what reads it) is checked to differ still, so that the list stays true.
MASS_DIFFERS = {
    "dmc/dog": "its bone meshes weigh as their convex hulls here; MuJoCo weighs a mesh by its own volume",
}

#: dm_control's lqr.xml is a template its Python code fills with bodies: no model alone.
TEMPLATES = ["dmc/lqr"]


def test_every_file_is_listed_once():
    listed = set(LOADS) | set(LEFT) | set(TEMPLATES)
    assert listed == set(FILES), (set(FILES) - listed, listed - set(FILES))
    assert len(FILES) == 35


@pytest.mark.parametrize("name", sorted(LEFT))
def test_a_file_not_loaded_yet_is_refused_with_its_element_and_line(name):
    path, assets = FILES[name]
    reason, _issue = LEFT[name]
    with pytest.raises(gymfleet.InvalidArgument, match=r"line \d+: " + re.escape(reason)):
        gymfleet.make(path, assets=assets)


def named_bodies(model) -> List[str]:
    return [model.body(b).name for b in range(1, model.nbody) if model.body(b).name]


def made(name: str, **options):
    path, assets = FILES[name]
    return gymfleet.make(path, assets=assets, units="si", **options)


def segments(env) -> Dict[str, slice]:
    out, at = {}, 0
    for segment, size in env.env_info["observation_layout"]:
        out[segment] = slice(at, at + size)
        at += size
    return out


def angle_between(a: np.ndarray, b: np.ndarray) -> float:
    """The rotation angle from quaternion `a` to `b` (w first), well conditioned near 0."""
    a = np.asarray(a, dtype=np.float64) / np.linalg.norm(a)
    b = np.asarray(b, dtype=np.float64) / np.linalg.norm(b)
    w = a[0] * b[0] + a[1:] @ b[1:]
    v = a[0] * b[1:] - b[0] * a[1:] - np.cross(a[1:], b[1:])
    return float(2 * np.arctan2(np.linalg.norm(v), abs(w)))


def rotation_vector_to_quat(v: np.ndarray) -> np.ndarray:
    angle = float(np.linalg.norm(v))
    if angle < 1e-12:
        return np.array([1.0, 0.0, 0.0, 0.0])
    axis = v / angle
    return np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * axis])


def same_state(model, data, env, obs: np.ndarray, bodies: List[str]) -> None:
    """Puts gymfleet's state `obs` into MuJoCo's `data`: every joint by its name (in
    MuJoCo's units, as gymfleet observes them with SI units), every free body's free joint
    from its observed pose, a floating base's from its body's pose."""
    at = segments(env)
    info = env.env_info
    positions = obs[at["joint_positions"]]
    k = 0
    for joint in info["joints"]:
        j = model.joint(joint["name"])
        adr = j.qposadr[0]
        if joint["type"] == "ball":
            data.qpos[adr:adr + 4] = rotation_vector_to_quat(positions[k:k + 3])
        else:
            data.qpos[adr] = positions[k]
        k += joint["dof"]
    poses = obs[at["free_body_poses"]].reshape(-1, 7) if "free_body_poses" in at else []
    for body, pose in zip(info["free_bodies"], poses):
        adr = model.jnt_qposadr[model.body(body).jntadr[0]]
        data.qpos[adr:adr + 7] = pose
    if "base_pose" in at:
        free = [b for b in range(1, model.nbody)
                if model.body_jntnum[b] and model.jnt_type[model.body_jntadr[b]] == mujoco.mjtJoint.mjJNT_FREE]
        base = next(b for b in free if model.body(b).name not in info["free_bodies"])
        ee = obs[at["end_effector_poses"]].reshape(-1, 7)
        adr = model.jnt_qposadr[model.body_jntadr[base]]
        data.qpos[adr:adr + 7] = ee[bodies.index(model.body(base).name)]
    mujoco.mj_kinematics(model, data)


@pytest.mark.parametrize("name", LOADS)
def test_a_model_has_mujocos_mass_and_body_poses(name):
    """The mass of what moves, and every named body's pose on the same state (MuJoCo's
    xpos and xquat against gymfleet's body-origin sites): mass within 1e-6 relative plus
    1 mg per body and per geom (the conversion's helpers, and geoms of `mass="0"`, weigh
    1 mg each), positions within 0.01 mm, orientations within 1e-4 rad (the physics is
    f32)."""
    path, _ = FILES[name]
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    bodies = named_bodies(model)
    assert len(bodies) <= 64, "every body fits in the end effectors"
    env = made(name, end_effector_ids=[f"site:{b}" for b in bodies])
    moving = [b for b in range(1, model.nbody) if model.body_weldid[b] != 0 and model.body_mocapid[b] == -1]
    mass = sum(model.body_mass[b] for b in moving)
    helpers = 1e-6 * (model.nbody + model.ngeom)
    if name in MASS_DIFFERS:
        assert env.env_info["moving_mass"] > mass * 1.05, MASS_DIFFERS[name]
    else:
        assert env.env_info["moving_mass"] == pytest.approx(mass, rel=1e-6, abs=helpers)
    obs, _ = env.reset(seed=0)
    same_state(model, data, env, obs, bodies)
    ee = obs[segments(env)["end_effector_poses"]].reshape(-1, 7)
    for body, pose in zip(bodies, ee):
        b = model.body(body).id
        np.testing.assert_allclose(pose[:3], data.xpos[b], atol=1e-5, err_msg=f"{name}: {body}'s position")
        turn = angle_between(pose[3:], data.xquat[b])
        assert turn < 1e-4, f"{name}: {body} is turned {turn} rad from MuJoCo's"
    env.close()


def stays_finite_under_300_random_controls(name: str, env) -> None:
    env.action_space.seed(0)
    env.reset(seed=0)
    for k in range(300):
        obs, _, terminated, _, info = env.step(env.action_space.sample())
        assert np.isfinite(obs).all() and not terminated, f"{name}: step {k}: {info}"
    env.close()


@pytest.mark.parametrize("name", LOADS)
def test_a_model_stays_finite_under_300_random_controls(name):
    stays_finite_under_300_random_controls(name, made(name))


def fetch_push() -> dict:
    path, assets = FILES["fetch/push"]
    document, _ = gymfleet.convert(path, assets=assets)
    return document


def test_an_object_dropped_on_fetchs_table_comes_to_rest_on_it():
    """Fetch's push scene, its object moved from the floor to 75 mm above the table (top at
    z = 0.4 m): after 1 s it rests on the table, its centre 25 mm above the top."""
    document = fetch_push()
    instances = document["assembly"]["instances"]
    parts = {j["child"] for j in document["assembly"]["joints"] if j["parent"] == "object0"}
    shift = np.array([1.275, 0.725, 0.475]) * 1000  # mm: from (0.025, 0.025, 0.025) m
    for instance in instances:
        if instance["name"] == "object0" or instance["name"] in parts:
            p = instance["position"]
            p["x"], p["y"], p["z"] = (np.array([p["x"], p["y"], p["z"]]) + shift).tolist()
    env = gymfleet.make(document, units="si")
    assert env.env_info["free_bodies"] == ["object0"]
    obs, _ = env.reset(seed=0)
    at = segments(env)
    start = obs[at["free_body_poses"]][:3].copy()
    np.testing.assert_allclose(start, [1.3, 0.75, 0.5], atol=1e-6)
    steps = int(round(1.0 / env.env_info["dt"]))
    for _ in range(steps):
        obs, *_ = env.step(np.zeros(env.action_space.shape, dtype=np.float32))
    pose = obs[at["free_body_poses"]]
    velocity = obs[at["free_body_velocities"]]
    assert abs(pose[2] - 0.425) < 1e-3, f"the object's centre at z = {pose[2]}"
    np.testing.assert_allclose(pose[:2], [1.3, 0.75], atol=2e-3)
    assert np.abs(velocity).max() < 1e-2, f"still moving: {velocity}"


def test_a_mocap_driven_fetch_gripper_reaches_its_target():
    """Fetch moves its gripper with a mocap body welded to it (hard here; soft in MuJoCo):
    the mocap's target moved by (−100, 0, −100) mm, the gripper follows to within 1 mm in
    0.5 s at the file's own time step."""
    env = made("fetch/push", end_effector_ids=["robot0:grip", "robot0:mocap"])
    assert env.env_info["mocap_bodies"] == ["robot0:mocap"]
    obs, _ = env.reset(seed=0)
    ee = obs[segments(env)["end_effector_poses"]].reshape(-1, 7)
    grip, mocap = ee[0, :3].copy(), ee[1].copy()
    delta = np.array([-0.1, 0.0, -0.1])
    env.set_mocap_pose("robot0:mocap", mocap[:3] + delta, mocap[3:])
    for _ in range(int(round(0.5 / env.env_info["dt"]))):
        obs, *_ = env.step(np.zeros(env.action_space.shape, dtype=np.float32))
    ee = obs[segments(env)["end_effector_poses"]].reshape(-1, 7)
    np.testing.assert_allclose(ee[1, :3], mocap[:3] + delta, atol=1e-6)
    error = np.linalg.norm(ee[0, :3] - (grip + delta))
    assert error < 1e-3, f"the gripper is {error * 1000:.2f} mm from its target"


@pytest.mark.parametrize("name", ["dmc/manipulator", "dmc/stacker"])
def test_tendon_driven_files_convert_their_actuators_and_couple_their_fingers(name):
    """manipulator's and stacker's actuators (motors on fixed tendons, issue Z1b) convert in
    MuJoCo's order, and their `<equality><tendon>` (issue Z3) holds the fingers' coupling
    tendon at its qpos0 length (0: thumb and finger turn together) through 300
    random-control steps."""
    path, assets = FILES[name]
    model = mujoco.MjModel.from_xml_path(str(path))
    task = {"terms": [{"name": "coupling", "weight": 0, "value": {"tendon_length": "coupling"}},
                      {"name": "grasp", "weight": 0, "value": {"tendon_length": "grasp"}}]}
    env = gymfleet.make(path, assets=assets, units="si", task=task)
    targets = [a["target"] for a in env.env_info["actuators"]]
    mujoco_targets = [
        (model.tendon if model.actuator_trntype[k] == mujoco.mjtTrn.mjTRN_TENDON else model.joint)(
            model.actuator_trnid[k, 0]
        ).name
        for k in range(model.nu)
    ]
    assert targets == mujoco_targets
    assert any(model.actuator_trntype[k] == mujoco.mjtTrn.mjTRN_TENDON for k in range(model.nu))
    env.action_space.seed(0)
    env.reset(seed=0)
    grasps = []
    for k in range(300):
        obs, _, _, _, info = env.step(env.action_space.sample())
        assert np.isfinite(obs).all()
        assert abs(info["coupling"]) < 1e-5, f"{name}: step {k}: the fingers' coupling slipped to {info['coupling']}"
        grasps.append(info["grasp"])
    # The grasp tendon (the fingers' mean) moved: the coupling was tested under motion.
    assert np.ptp(grasps) > 0.02
    env.close()


def test_ball_in_cups_ball_hangs_at_the_strings_length_and_swings_at_mujocos_period():
    """ball_in_cup's string is a spatial tendon with a range (a rope, issue Z3): the ball
    hangs at the string's length, 0.3 m, within 1 mm (MuJoCo's soft limit stretches it by
    about 0.6 mm), and swings on it at MuJoCo's period within 2 %."""
    path, assets = FILES["dmc/ball_in_cup"]
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    dt = model.opt.timestep
    task = {"terms": [{"name": "string", "weight": 0, "value": {"tendon_length": "string"}}]}
    env = gymfleet.make(path, assets=assets, units="si", dt=dt, task=task)
    env.reset(seed=0)
    for _ in range(int(2.0 / dt)):  # released at rest below the cup: it drops 8 mm and hangs
        _, _, _, _, info = env.step(np.zeros(2, np.float32))
        assert info["string"] <= 0.3 + 1e-4, "the rope stretched"
    assert info["string"] == pytest.approx(0.3, abs=1e-3)
    # Swinging from 0.1 m to the side, the string taut.
    x = 0.1
    q = np.array([0.0, 0.0, x, 0.292 - np.sqrt(0.3**2 - x * x)])
    env.set_joint_state(q, np.zeros(4))
    data.qpos[:] = q
    ours, theirs = [], []
    for _ in range(int(3.0 / dt)):
        obs, *_ = env.step(np.zeros(2, np.float32))
        mujoco.mj_step(model, data)
        ours.append(obs[2])
        theirs.append(data.qpos[2])

    def period(xs):
        t = np.where(np.diff(np.sign(xs)) != 0)[0] * dt
        assert len(t) >= 4
        return 2 * np.mean(np.diff(t))

    assert period(np.array(ours)) == pytest.approx(period(np.array(theirs)), rel=0.02)
    # Without the rope the ball falls away: the test can tell.
    assert np.abs(np.array(ours)).max() == pytest.approx(x, rel=0.05)


def test_the_kitchens_knobs_turn_their_burners():
    """The kitchen's oven couples each knob to its burner's flame (`<equality><joint>`,
    polycoef 0 174): a knob turned to −1 rad puts its burner at −1/174 m."""
    path, assets = FILES["kitchen"]
    env = gymfleet.make(path, assets=assets, units="si")
    names = [j["name"] for j in env.env_info["joints"]]
    env.reset(seed=0)
    n = len(names)
    q = env.observe()[:n].copy()
    knob, burner = names.index("knob_Joint_1"), names.index("bottom_right_burner")
    q[knob] = -1.0
    env.set_joint_state(q, np.zeros(n))
    for _ in range(20):
        obs, *_ = env.step(np.zeros(env.action_space.shape, np.float32))
        assert obs[burner] == pytest.approx(obs[knob] / 174, abs=1e-6)
    assert obs[knob] == pytest.approx(-1.0, abs=1e-3)
    env.close()

"""Gymnasium's MuJoCo v5 contract, checked against Gymnasium's own envs (with MuJoCo from
PyPI): for every registered ``gymfleet/<Name>-v5``, the spaces, the observation's
contents and units at a noiseless reset, the info keys, each reward term recomputed from
the observation, info and action, ``x_velocity = Δx_position / dt``, the episode's end
within 20 % of MuJoCo's under a fixed action sequence, the reset noise's distributions,
the keyword arguments, and the vector env on one server batch, remote and on a fleet."""

from __future__ import annotations

import numpy as np
import pytest

import gymfleet
from gymfleet.suite import SUITE

gymnasium = pytest.importorskip("gymnasium")
pytest.importorskip("mujoco")

NAMES = [spec.name for spec in SUITE.values()]
#: Gymnasium defines x_velocity as Δx_position / dt for these.
WITH_X_VELOCITY = {"HalfCheetah", "Hopper", "Walker2d", "Swimmer", "Ant"}
#: The reward as the sum of its info terms (Gymnasium's `_get_rew`).
REWARD_TERMS = (
    "reward_forward",
    "reward_ctrl",
    "reward_survive",
    "reward_dist",
    "reward_near",
    "reward_contact",
    "distance_penalty",
    "velocity_penalty",
    "reward_linup",
    "reward_quadctrl",
    "reward_impact",
)
#: HumanoidStandup's reward adds 1 to its terms.
REWARD_OFFSET = {"HumanoidStandup": 1.0}
#: Humanoid's and HumanoidStandup's knees in the observation (qpos[2:]: z, the
#: orientation, then the joints) and its cinert part.
KNEES = [11, 15]
CINERT = slice(45, 45 + 130)


#: Reacher and Pusher draw their goals at every reset; they take no reset_noise_scale.
RANDOM_GOALS = {"Reacher", "Pusher"}


def noiseless(name: str) -> dict:
    return {} if name in RANDOM_GOALS else {"reset_noise_scale": 0.0}


def pair(name: str, **kwargs):
    ours = gymnasium.make(f"gymfleet/{name}-v5", **kwargs)
    theirs = gymnasium.make(f"{name}-v5", **kwargs)
    return ours, theirs


@pytest.mark.parametrize("name", NAMES)
def test_spaces_and_a_noiseless_reset_match_gymnasium(name):
    ours, theirs = pair(name, **noiseless(name))
    assert ours.observation_space.shape == theirs.observation_space.shape
    # float32 where Gymnasium's observations are float64 (the server's values are float32).
    assert ours.observation_space.dtype == np.float32
    assert ours.action_space.shape == theirs.action_space.shape
    assert ours.action_space.dtype == theirs.action_space.dtype
    np.testing.assert_array_equal(ours.action_space.low, theirs.action_space.low)
    np.testing.assert_array_equal(ours.action_space.high, theirs.action_space.high)
    assert ours.unwrapped.dt == pytest.approx(theirs.unwrapped.dt)
    assert ours.spec.max_episode_steps == theirs.spec.max_episode_steps
    # The same contents in the same order and units (metres, radians): MuJoCo's qpos0.
    obs, info = ours.reset(seed=0)
    ref, ref_info = theirs.reset(seed=0)
    if name == "Ant":
        # MuJoCo's pose has the ankles at 0, which their ranges (30° to 70°) exclude: the
        # conversion starts them at the nearest end, where MuJoCo's limits push them.
        ankles = [6, 8, 10, 12]
        np.testing.assert_allclose(np.abs(obs[ankles]), np.radians(30.0), rtol=1e-6)
        assert np.all(ref[ankles] == 0.0)
        obs, ref = np.delete(obs, ankles), np.delete(ref, ankles)
    if name in ("Humanoid", "HumanoidStandup"):
        # The knees start at -2°, the end of their ranges nearest MuJoCo's 0: the legs'
        # pose moves the centre of mass a little, which every cinert is taken about (the
        # same state's cinert is MuJoCo's: test_humanoid.py).
        np.testing.assert_allclose(obs[KNEES], np.radians(-2.0), rtol=1e-6)
        assert np.all(ref[KNEES] == 0.0)
        np.testing.assert_allclose(obs[CINERT], ref[CINERT], atol=0.03)
        obs[CINERT] = ref[CINERT]
        obs, ref = np.delete(obs, KNEES), np.delete(ref, KNEES)
        # The tendons (knee − hip_y) read the knees' -2°.
        np.testing.assert_allclose(info.pop("tendon_length"), np.radians(-2.0), atol=1e-6)
        assert np.all(ref_info.pop("tendon_length") == 0.0)
    if name not in RANDOM_GOALS:  # their goals are checked in their own test below
        np.testing.assert_allclose(obs, ref, atol=1e-6)
    assert set(info) == set(ref_info)
    for key in info:
        assert info[key] == pytest.approx(ref_info[key], abs=1e-6), key
    ours.close()
    theirs.close()


@pytest.mark.parametrize("name", NAMES)
def test_info_keys_and_every_reward_term_recomputed(name):
    ours, theirs = pair(name)
    spec = SUITE[f"gymfleet/{name}-v5"]
    obs, reset_info = ours.reset(seed=1)
    theirs.reset(seed=1)
    rng = np.random.default_rng(0)
    previous_x = reset_info.get("x_position", 0.0)
    dt = ours.unwrapped.dt
    for step in range(40):
        action = rng.uniform(-1, 1, ours.action_space.shape).astype(np.float32)
        obs, reward, terminated, truncated, info = ours.step(action)
        *_, ref_info = theirs.step(action)
        assert set(info) == set(ref_info), step
        assert obs.shape == ours.observation_space.shape
        offset = REWARD_OFFSET.get(name, 0.0)
        assert reward == pytest.approx(offset + sum(info.get(k, 0.0) for k in REWARD_TERMS), abs=1e-4)
        if "reward_ctrl" in info:
            weight = spec.defaults.get("ctrl_cost_weight", spec.defaults.get("reward_control_weight"))
            expected = -weight * float(np.sum(np.square(action.astype(np.float64))))
            assert info["reward_ctrl"] == pytest.approx(expected, rel=1e-5, abs=1e-9)
        if "reward_forward" in info:
            assert info["reward_forward"] == pytest.approx(
                spec.defaults["forward_reward_weight"] * info["x_velocity"], rel=1e-6
            )
        if "reward_survive" in info:
            alive = spec.defaults.get("healthy_reward", 1.0)
            assert info["reward_survive"] == (0.0 if terminated else alive)
        if name == "InvertedDoublePendulum":
            _check_double_pendulum_penalties(obs, info)
        if name == "Ant":
            # The contact cost from the observed (clipped) contact wrenches.
            expected = -5e-4 * float(np.sum(np.square(obs[27:].astype(np.float64))))
            assert info["reward_contact"] == pytest.approx(expected, rel=1e-4, abs=1e-9)
        if name in WITH_X_VELOCITY:
            assert info["x_velocity"] == pytest.approx(
                (info["x_position"] - previous_x) / dt, abs=2e-3
            ), step
            previous_x = info["x_position"]
        if name in ("Hopper", "Walker2d", "HalfCheetah", "Swimmer"):
            # The observation leaves out x (and Swimmer's y): it starts at qpos[1] (qpos[2]).
            skip = 2 if name == "Swimmer" else 1
            q = ours.unwrapped.gymfleet_env.observe()
            assert obs[0] == pytest.approx(q[skip], abs=1e-6)
        if name == "Ant":
            # z, the orientation, then the joints: x and y left out.
            pose = ours.unwrapped.gymfleet_env.observe()[16:23]
            np.testing.assert_allclose(obs[:5], pose[2:], atol=1e-6)
        if terminated or truncated:
            break
    ours.close()
    theirs.close()


def _check_double_pendulum_penalties(obs, info):
    """The penalties recomputed from the observation: the tip (0.6 m links above the
    cart) from the angles' sines and cosines, the hinges' speeds."""
    x, s1, s2, c1, c2 = (float(v) for v in obs[:5])
    # sin and cos of θ1 + θ2.
    s12, c12 = s1 * c2 + c1 * s2, c1 * c2 - s1 * s2
    tip_x, tip_z = x + 0.6 * (s1 + s12), 0.6 * (c1 + c12)
    assert info["distance_penalty"] == pytest.approx(
        -(0.01 * tip_x**2 + (tip_z - 2.0) ** 2), rel=1e-4, abs=1e-5
    )
    v1, v2 = float(obs[6]), float(obs[7])
    if max(abs(v1), abs(v2)) < 10.0:  # the observation clips them
        assert info["velocity_penalty"] == pytest.approx(
            -(1e-3 * v1**2 + 5e-3 * v2**2), rel=1e-4, abs=1e-6
        )


#: A fixed action sequence per env. Each drives the robot (a slow topple from a balanced
#: stance is chaotic: Walker2d under a constant 0.3 ends at step 59 here and 241 in MuJoCo,
#: under zero torque at 181 and 135; see bench/journal/2026-12-07-benchmarks-notebook.md, "Fidelity of the suite").
SEQUENCES = {
    "InvertedPendulum": lambda k: np.array([0.5]),
    "InvertedDoublePendulum": lambda k: np.array([0.2 * np.sin(0.3 * k)]),
    "Ant": lambda k: 0.5 * np.sin(0.1 * k + np.arange(8)),
    "Hopper": lambda k: np.array([0.4, -0.3, 0.2]) * np.sin(0.05 * k),
    "Walker2d": lambda k: np.sin(0.1 * k + np.arange(6)),
    "HalfCheetah": lambda k: np.sin(0.1 * k + np.arange(6)),
    "Reacher": lambda k: np.array([np.sin(0.2 * k), np.cos(0.3 * k)]),
    "Pusher": lambda k: 0.5 * np.sin(0.1 * k + np.arange(7)),
    "Swimmer": lambda k: np.array([np.sin(0.1 * k), np.cos(0.1 * k)]),
    "Humanoid": lambda k: 0.4 * np.sin(0.1 * k + np.arange(17)),
    "HumanoidStandup": lambda k: 0.4 * np.sin(0.1 * k + np.arange(17)),
}


def _episode_length(env, sequence) -> tuple:
    env.reset(seed=0)
    for k in range(2000):
        _, _, terminated, truncated, _ = env.step(sequence(k).astype(np.float32))
        if terminated or truncated:
            return k + 1, terminated
    raise AssertionError("no episode end in 2000 steps")


@pytest.mark.parametrize("name", NAMES)
def test_a_fixed_action_sequence_ends_within_20_percent_of_mujoco(name):
    ours, theirs = pair(name, **noiseless(name))
    ours_len, ours_terminated = _episode_length(ours, SEQUENCES[name])
    ref_len, ref_terminated = _episode_length(theirs, SEQUENCES[name])
    if not ref_terminated:
        assert (ours_len, ours_terminated) == (ref_len, False), "both truncate"
    else:
        assert ours_terminated, f"MuJoCo's ends at step {ref_len}, ours runs to {ours_len}"
        assert abs(ours_len - ref_len) <= 0.2 * ref_len, f"ours {ours_len}, MuJoCo's {ref_len}"
    ours.close()
    theirs.close()


def test_reacher_and_pusher_measure_mujocos_bodies():
    """Reacher's fingertip − target and Pusher's tip, object and goal are MuJoCo's body
    positions (xpos, kept as sites by the import); the distance terms recomputed from
    them; the goals drawn where Gymnasium draws them."""
    mujoco = pytest.importorskip("mujoco")
    env = gymnasium.make("gymfleet/Pusher-v5")
    theirs = gymnasium.make("Pusher-v5")
    for seed in range(20):
        obs, _ = env.reset(seed=seed)
        tip, obj, goal = obs[14:17], obs[17:20], obs[20:23]
        np.testing.assert_allclose(goal[:2], [0.45, -0.05], atol=1e-6)  # goal at (0, 0)
        assert np.linalg.norm(obj[:2] - goal[:2]) > 0.17 - 1e-6
        assert -0.3 - 1e-6 <= obj[1] - goal[1] <= 1e-6  # obj_slidey, drawn first, in [-0.3, 0]
        # The arm starts at MuJoCo's pose: the tip where MuJoCo puts tips_arm.
        theirs.reset(seed=seed)
        ref_tip = theirs.unwrapped.data.body("tips_arm").xpos
        np.testing.assert_allclose(tip, ref_tip, atol=2e-3)
        _, reward, _, _, info = env.step(np.zeros(7, dtype=np.float32))
        assert info["reward_near"] == pytest.approx(-0.5 * np.linalg.norm(obj - tip), abs=5e-3)
    env.close()
    env = gymnasium.make("gymfleet/Reacher-v5")
    model = mujoco.MjModel.from_xml_path(str(theirs.unwrapped.fullpath).replace("pusher_v5", "reacher"))
    data = mujoco.MjData(model)
    for seed in range(20):
        obs, _ = env.reset(seed=seed)
        goal = obs[4:6]
        assert np.linalg.norm(goal) <= 0.2 + 1e-6
        # MuJoCo at the same joint positions: the fingertip − target vector.
        theta = np.arctan2(obs[2:4], obs[0:2])
        data.qpos[:] = [theta[0], theta[1], goal[0], goal[1]]
        mujoco.mj_forward(model, data)
        ref = (data.body("fingertip").xpos - data.body("target").xpos)[:2]
        np.testing.assert_allclose(obs[8:10], ref, atol=1e-5)
        _, reward, _, _, info = env.step(np.zeros(2, dtype=np.float32))
    env.close()
    theirs.close()


def test_the_double_pendulums_cart_stop_force_is_mujocos(tmp_path):
    """The observation's last value is MuJoCo's constraint force on the cart, clipped to
    ±10: its slider's stop pushing back. With the poles held upright (hinge limits of
    ±0.01 rad, so the episode does not end) the cart is driven into its stop at 1 m and
    then let go."""
    from gymfleet.suite.model import assets_dir

    text = (assets_dir() / "inverted_double_pendulum.xml").read_text()
    for hinge in ("hinge", "hinge2"):
        text = text.replace(
            f'name="{hinge}" pos="0 0 0" type="hinge"',
            f'name="{hinge}" pos="0 0 0" type="hinge" limited="true" range="-0.01 0.01"',
        )
    held = tmp_path / "held.xml"
    held.write_text(text)
    runs = {}
    for name in ("InvertedDoublePendulum", "gymfleet/InvertedDoublePendulum"):
        env = gymnasium.make(f"{name}-v5", reset_noise_scale=0.0, xml_file=str(held))
        env.reset(seed=0)
        runs[name] = [
            env.step(np.array([0.3 if k < 20 else -0.02], dtype=np.float32))[0]
            for k in range(30)
        ]
        env.close()
    ours, theirs = (np.array(runs[n]) for n in ("gymfleet/InvertedDoublePendulum", "InvertedDoublePendulum"))
    # Both reach the stop within a step of each other (the file integrates with RK4, which
    # gymfleet integrates as implicit: its cart runs up to 2 cm ahead and, past the stop's
    # 1 cm margin between two substeps, is pushed back a step later), push against it, and
    # leave it.
    assert abs(np.flatnonzero(ours[:, -1])[0] - np.flatnonzero(theirs[:, -1])[0]) <= 1
    np.testing.assert_array_equal(ours[14:20, -1], -10.0)
    np.testing.assert_array_equal(theirs[14:20, -1], -10.0)
    np.testing.assert_array_equal(ours[22:, -1], 0.0)
    np.testing.assert_array_equal(theirs[22:, -1], 0.0)
    np.testing.assert_allclose(ours[14:20, 0], theirs[14:20, 0], atol=0.015)


def test_a_standing_ant_is_held_up_by_its_feet_as_in_mujoco():
    """The Ant at rest on its four feet: the observed contact wrenches (unclipped here)
    are on the feet only, they carry its weight, and each foot's load matches MuJoCo's
    within the two engines' differences in how a splayed stance shares it."""
    wide = {"reset_noise_scale": 0.0, "contact_force_range": (-1e3, 1e3)}
    ours, theirs = pair("Ant", **wide)
    ours.reset(seed=0)
    theirs.reset(seed=0)
    feet = [3, 6, 9, 12]  # the ankle bodies (the fifth body of each leg counts from 0)
    loads, ref_loads = [], []
    for k in range(100):
        obs, *_ = ours.step(np.zeros(8, dtype=np.float32))
        ref, *_ = theirs.step(np.zeros(8))
        if k >= 40:
            loads.append(obs[27:].reshape(13, 6)[feet, 5])
            ref_loads.append(ref[27:].reshape(13, 6)[feet, 5])
    ours_w, ref_w = obs[27:].reshape(13, 6), ref[27:].reshape(13, 6)
    others = [b for b in range(13) if b not in feet]
    assert np.all(ref_w[others] == 0.0)
    assert np.abs(ours_w[others]).max() < 1e-6
    weight = float(np.sum(theirs.unwrapped.model.body_mass)) * 9.81
    assert ours_w[feet, 5].sum() == pytest.approx(weight, rel=0.03)
    # Four feet hold a rigid body up in a statically indeterminate way: each engine shares
    # the load by its own contact compliance (MuJoCo's is even; ours sways between the feet
    # by up to ±22 % of it over steps 30-80, and settles). Over steps 40-99 each foot's mean
    # load is MuJoCo's within 12 % (measured: 9.3 %).
    np.testing.assert_allclose(np.mean(loads, 0), np.mean(ref_loads, 0), rtol=0.12)
    # The torques about the centre of mass have MuJoCo's signs; their sizes differ with
    # the stance: MuJoCo's ankles, pushed into their ranges by soft limits from 0, overshoot
    # and land at 54° (torso at 0.56 m), ours start at the 30° stop and stay (0.36 m).
    np.testing.assert_array_equal(np.sign(ours_w[feet, :2]), np.sign(ref_w[feet, :2]))
    ours.close()
    theirs.close()


def _swim(env, steps=400) -> np.ndarray:
    """A travelling wave down the body (period 1 s, the tail a quarter period behind),
    tracked by a PD on the joint angles; the torso's x, y per step."""
    obs, _ = env.reset(seed=0)
    path = []
    for k in range(steps):
        phase = 2 * np.pi * k * 0.04  # one wave per second at dt = 0.04 s
        target = 0.8 * np.sin([phase, phase - np.pi / 2])
        action = np.clip(2.0 * (target - obs[1:3]) - 0.2 * obs[6:8], -1, 1)
        obs, _, _, _, info = env.step(action.astype(np.float32))
        path.append((info["x_position"], info["y_position"]))
    return np.array(path)


def test_the_swimmer_swims_at_mujocos_speed_in_its_fluid():
    """Swimmer's `<option density viscosity>` is MuJoCo's inertia-box fluid: under the same
    gait both swim forward at the same speed (after 4 s of start-up, over 12 s)."""
    ours, theirs = pair("Swimmer", reset_noise_scale=0.0)
    speeds = []
    for env in (ours, theirs):
        path = _swim(env)
        speeds.append((path[-1] - path[99]) / (300 * 0.04))
        env.close()
    (ours_v, theirs_v) = speeds
    assert theirs_v[0] > 0.2, f"MuJoCo's swimmer moves forward: {theirs_v}"
    assert abs(ours_v[0] / theirs_v[0] - 1) < 0.1, f"ours {ours_v} m/s, MuJoCo's {theirs_v} m/s"
    assert abs(ours_v[1]) < 0.02, f"and straight: {ours_v}"


def test_reset_noise_has_gymnasiums_distributions():
    # Hopper: uniform ±0.005 on positions and velocities.
    env = gymnasium.make("gymfleet/Hopper-v5")
    starts = np.array([env.reset(seed=s)[0] for s in range(200)])
    assert np.abs(starts[:, 0] - 1.25).max() <= 0.005 + 1e-6  # z = qpos[1], ref 1.25
    assert np.abs(starts[:, 5:]).max() <= 0.005 + 1e-6  # velocities
    assert starts[:, 5:].std() == pytest.approx(0.005 / np.sqrt(3), rel=0.15)
    env.close()
    # HalfCheetah: normal velocities, σ = 0.1.
    env = gymnasium.make("gymfleet/HalfCheetah-v5")
    starts = np.array([env.reset(seed=s)[0] for s in range(200)])
    velocities = starts[:, 8:]
    assert velocities.std() == pytest.approx(0.1, rel=0.1)
    assert np.abs(velocities).max() > 0.2  # a uniform ±0.1 draw never gets there
    assert np.abs(starts[:, :8]).max() <= 0.1 + 1e-6
    env.close()
    # Ant: the free joint too: z uniform ±0.1 about 0.75, the orientation's components
    # noised (then normalized), the base's velocities normal σ = 0.1.
    env = gymnasium.make("gymfleet/Ant-v5", include_cfrc_ext_in_observation=False)
    starts = np.array([env.reset(seed=s)[0] for s in range(200)])
    assert starts.shape == (200, 27)
    assert np.abs(starts[:, 0] - 0.75).max() <= 0.1 + 0.02  # the COM turns with the torso
    assert starts[:, 0].std() == pytest.approx(0.1 / np.sqrt(3), rel=0.2)
    np.testing.assert_allclose(np.linalg.norm(starts[:, 1:5], axis=1), 1.0, atol=1e-5)
    assert 0.01 < starts[:, 2].std() < 0.1
    assert starts[:, 13:19].std() == pytest.approx(0.1, rel=0.15)
    env.close()


def test_keyword_arguments_change_what_gymnasiums_do():
    env = gymnasium.make("gymfleet/Hopper-v5", exclude_current_positions_from_observation=False)
    obs, _ = env.reset(seed=0)
    assert obs.shape == (12,) and abs(obs[0]) < 0.01  # x comes first
    env.close()
    env = gymnasium.make("gymfleet/Hopper-v5", ctrl_cost_weight=0.0, healthy_reward=2.0)
    env.reset(seed=0)
    _, reward, _, _, info = env.step(np.ones(3, dtype=np.float32))
    assert info["reward_ctrl"] == 0.0 and info["reward_survive"] == 2.0
    env.close()
    # Unhealthy at once (z starts at 1.25), but not terminated when told not to.
    env = gymnasium.make("gymfleet/Hopper-v5", healthy_z_range=(2.0, 3.0), terminate_when_unhealthy=False)
    env.reset(seed=0)
    _, _, terminated, _, info = env.step(np.zeros(3, dtype=np.float32))
    assert not terminated and info["reward_survive"] == 0.0
    env.close()
    env = gymnasium.make("gymfleet/Hopper-v5", healthy_z_range=(2.0, 3.0))
    env.reset(seed=0)
    assert env.step(np.zeros(3, dtype=np.float32))[2]
    env.close()
    env = gymnasium.make("gymfleet/HalfCheetah-v5", frame_skip=2)
    assert env.unwrapped.dt == pytest.approx(0.02)
    env.close()


def test_an_unknown_keyword_names_the_known_ones(pendulum):
    with pytest.raises(gymfleet.InvalidArgument) as e:
        gymnasium.make("gymfleet/Hopper-v5", forward_weight=2.0)
    message = str(e.value)
    assert "unknown keyword argument(s) forward_weight" in message
    assert "forward_reward_weight" in message and "healthy_z_range" in message
    with pytest.raises(gymfleet.InvalidArgument, match="frame_skip: expected an integer >= 1"):
        gymnasium.make("gymfleet/Hopper-v5", frame_skip=0)
    with pytest.raises(gymfleet.InvalidArgument, match="does not exist"):
        gymnasium.make("gymfleet/Hopper-v5", xml_file="no_such_robot.xml")
    with pytest.raises(
        gymfleet.InvalidArgument,
        match=r"render_mode: 'human' is not supported \(render_modes: \['rgb_array'\]\)",
    ):
        gymnasium.make("gymfleet/Hopper-v5", render_mode="human")
    with pytest.raises(gymfleet.InvalidArgument, match=r"healthy_z_range: expected \(min, max\), got 0.7"):
        gymnasium.make("gymfleet/Hopper-v5", healthy_z_range=0.7)
    with pytest.raises(gymfleet.InvalidArgument, match='units: expected "document" or "si", got \'furlongs\''):
        gymfleet.make(pendulum, units="furlongs")
    with pytest.raises(gymfleet.InvalidArgument, match=r"task: unknown field\(s\) reach beside terms"):
        gymfleet.make(pendulum, task={"terms": [], "reach": {}})


def test_gymnasiums_env_checker_passes():
    from gymnasium.utils.env_checker import check_env

    for name in NAMES:
        env = gymnasium.make(f"gymfleet/{name}-v5")
        check_env(env.unwrapped, skip_render_check=True)
        env.close()


def test_make_vec_is_one_batch_with_gymnasiums_vector_info():
    envs = gymnasium.make_vec("gymfleet/Hopper-v5", num_envs=4)
    assert envs.gymfleet_envs.batch_info["n_envs"] == 4
    obs, info = envs.reset(seed=3)
    assert obs.shape == (4, 11) and obs.dtype == np.float32
    assert info["_x_position"].all()
    single = gymnasium.make("gymfleet/Hopper-v5")
    # Env i of the batch is seeded with seed + i.
    np.testing.assert_array_equal(obs[2], single.reset(seed=5)[0])
    actions = np.zeros((4, 3), dtype=np.float32)
    obs, rewards, terminated, truncated, info = envs.step(actions)
    one = single.step(actions[2])
    np.testing.assert_array_equal(obs[2], one[0])
    assert rewards[2] == pytest.approx(one[1])
    for key in ("x_position", "x_velocity", "reward_forward", "reward_ctrl", "reward_survive"):
        assert info[key].shape == (4,) and info["_" + key].all()
        assert info[key][2] == pytest.approx(one[4][key], abs=1e-6)
    envs.close()
    single.close()
    # gymfleet's own entry points take the ids too.
    envs = gymfleet.make_vec("gymfleet/Walker2d-v5", 3, max_episode_steps=5)
    envs.reset(seed=0)
    for _ in range(5):
        *_, truncated, _ = envs.step(np.zeros((3, 6), dtype=np.float32))
    assert truncated.all(), "the server truncates at max_episode_steps"
    envs.close()
    env = gymfleet.make("gymfleet/InvertedPendulum-v5")
    assert env.spec.max_episode_steps == 1000
    env.close()
    with pytest.raises(gymfleet.InvalidArgument, match="takes its registered env's keywords"):
        gymfleet.make("gymfleet/Hopper-v5", dt=0.01)


def test_same_step_autoreset_keeps_the_final_observation_and_info():
    envs = gymfleet.make_vec(
        "gymfleet/Hopper-v5", 2, autoreset_mode="SameStep", healthy_z_range=(1.2, 3.0)
    )
    envs.reset(seed=0)
    for _ in range(50):
        obs, _, terminated, _, info = envs.step(np.full((2, 3), -1.0, dtype=np.float32))
        if terminated.any():
            break
    assert terminated.any(), "the hopper never dropped below 1.2 m"
    env = int(np.flatnonzero(terminated)[0])
    assert info["_final_obs"][env] and info["final_obs"][env].shape == (11,)
    z, angle = info["final_obs"][env][:2]
    assert z <= 1.2 or abs(angle) >= 0.2, "it ended unhealthy"
    assert abs(obs[env][0] - 1.25) <= 0.005 + 1e-6  # the next episode's start
    assert info["final_info"]["reward_survive"][env] == 0.0
    envs.close()


def test_remote_server_and_fleet(remote_server):
    envs = gymfleet.make_vec("gymfleet/HalfCheetah-v5", 4, server=remote_server)
    local = gymfleet.make_vec("gymfleet/HalfCheetah-v5", 4)
    a, _ = envs.reset(seed=9)
    b, _ = local.reset(seed=9)
    np.testing.assert_array_equal(a, b)
    actions = np.full((4, 6), 0.2, dtype=np.float32)
    np.testing.assert_array_equal(envs.step(actions)[0], local.step(actions)[0])
    envs.close()
    with gymfleet.Server(threads=1) as other:
        fleet = gymfleet.make_vec(
            "gymfleet/HalfCheetah-v5", 4, server=f"{remote_server},{other.address}"
        )
        assert len(fleet.gymfleet_envs.batch_info["shards"]) == 2
        np.testing.assert_array_equal(fleet.reset(seed=9)[0], local.reset(seed=9)[0])
        np.testing.assert_array_equal(fleet.step(actions)[0], local.step(actions)[0])
        fleet.close()
        # The Ant's observation holds 78 term values (its contact wrenches): sharded, each
        # env's come back with its rows.
        ants = [
            gymfleet.make_vec("gymfleet/Ant-v5", 4, server=s)
            for s in (f"{remote_server},{other.address}", None)
        ]
        starts = [a.reset(seed=5)[0] for a in ants]
        np.testing.assert_array_equal(starts[0], starts[1])
        push = np.tile(0.3 * np.sin(np.arange(8, dtype=np.float32)), (4, 1))
        for _ in range(12):
            (o0, r0, *_, i0), (o1, r1, *_, i1) = (a.step(push) for a in ants)
            np.testing.assert_array_equal(o0, o1)
            np.testing.assert_array_equal(r0, r1)
            np.testing.assert_array_equal(i0["reward_contact"], i1["reward_contact"])
        assert np.abs(o0[:, 27:]).max() > 0, "the feet touch the floor"
        for a in ants:
            a.close()
    local.close()


def _moved_joint(env_id: str, action: np.ndarray) -> int:
    """The joint (index into qpos[7:]) that ``action``, held for 3 steps from the
    noiseless start, moves most beyond what zero action does."""

    def joints(a):
        env = gymnasium.make(env_id, reset_noise_scale=0.0)
        env.reset(seed=0)
        for _ in range(3):
            obs, *_ = env.step(a.astype(np.float32))
        env.close()
        return obs[5:13]

    return int(np.argmax(np.abs(joints(action) - joints(np.zeros_like(action)))))


def test_actions_are_mujocos_ctrl_in_actuator_order():
    """Gymnasium's action k drives MuJoCo's actuator k: the Ant's actuators are hip_4,
    ankle_4, hip_1, … while its joints are hip_1, ankle_1, …. Each hip actuator moves the
    same joint here as in MuJoCo (the ankles start at their stops here, see above)."""
    for k in (0, 2, 4, 6):  # hip_4, hip_1, hip_2, hip_3
        action = np.zeros(8)
        action[k] = 1.0
        assert _moved_joint("gymfleet/Ant-v5", action) == _moved_joint("Ant-v5", action), k


def test_the_batched_cross_product_is_numpys_bit_for_bit():
    # The suite's floating-base conversions use their own cross product (np.cross's axis
    # handling cost more than its arithmetic); it must give numpy's bits.
    from gymfleet.suite.kinematics import _cross

    rng = np.random.default_rng(3)
    a, b = rng.normal(size=(64, 3)), rng.normal(size=(64, 3))
    assert np.array_equal(_cross(a, b), np.cross(a, b))
    assert np.array_equal(_cross(a, b[0]), np.cross(a, b[0]))
    f = a.astype(np.float32)
    assert _cross(f, f[::-1]).dtype == np.float32
    assert np.array_equal(_cross(f, f[::-1]), np.cross(f, f[::-1]))


@pytest.mark.parametrize("name", ["Ant", "Humanoid", "HumanoidStandup"])
def test_one_row_splits_as_a_batch_does(name):
    # A single env's row takes the floating base's frames on Python floats, a batch on
    # numpy arrays: the same operations in the same order, so the same bits.
    from gymfleet.suite.kinematics import split_rows

    env = gymnasium.make(f"gymfleet/{name}-v5")
    env.reset(seed=0)
    setup = env.unwrapped._setup
    rows = []
    for _ in range(3):
        env.step(env.action_space.sample())
        rows.append(env.unwrapped.gymfleet_env.observe())
    env.close()
    rows = np.stack(rows)
    rng = np.random.default_rng(0)
    base = setup.segments["base_velocity"]
    rows[:, base] += rng.normal(0.0, 1.0, (3, base.stop - base.start)).astype(np.float32)
    batch = split_rows(rows, setup.segments, setup.model.root_geom)
    for k in range(3):
        one = split_rows(rows[k : k + 1], setup.segments, setup.model.root_geom)
        for a, b in zip(one, batch):
            assert a.dtype == b.dtype
            np.testing.assert_array_equal(a[0], b[k])

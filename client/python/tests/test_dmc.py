"""The Control Suite ids against dm_control itself (``dm-control`` from PyPI, on the MuJoCo
it brings): the spec shapes and bounds, the control timestep and step limit, and, on the
same physics state, every observation key and the reward.

The state is gymfleet's own after one step from its reset (the same seed on both sides
cannot give the same start: each draws from its own generator): it is put into
dm_control's physics (``physics.set_state`` and the action as ``ctrl``), where
dm_control's task computes its observation and reward. Quantities that depend on contact
forces (hopper's ``touch``) are left out: each engine solves its own contacts.

Tolerances: gymfleet's physics is float32, so positions and orientations agree to about
1e-6 and the velocity sensors' readings to about 1e-5 relative; rewards are compared
within 1e-4.
"""

from __future__ import annotations

import warnings

import gymnasium as gym
import numpy as np
import pytest

import gymfleet
from gymfleet.dmc import TASKS

with warnings.catch_warnings():
    warnings.simplefilter("ignore")  # glfw: no display
    from dm_control import suite

#: Keys that read contact forces, compared in shape only.
CONTACT_KEYS = {("hopper", "touch"), ("finger", "touch"), ("manipulator", "touch")}
IDS = sorted(TASKS)


def _dm_env(task):
    return suite.load(task.domain, task.task, task_kwargs={"random": 0})


@pytest.fixture(scope="module", params=IDS)
def pair(request):
    task = TASKS[request.param]
    env = gym.make(task.id)
    theirs = _dm_env(task)
    theirs.reset()  # the task's edits of its model (reacher's target size)
    yield task, env, theirs
    env.close()


def test_the_ids_are_named_as_envpools_and_are_benchmarking_tasks():
    benchmarking = set(suite.BENCHMARKING)
    for env_id, task in TASKS.items():
        assert (task.domain, task.task) in benchmarking, env_id
        assert env_id in gym.registry
    assert "gymfleet/CheetahRun-v1" in TASKS
    assert "gymfleet/BallInCupCatch-v1" in TASKS and "gymfleet/SwimmerSwimmer6-v1" in TASKS
    assert "gymfleet/ManipulatorBringBall-v1" in TASKS
    assert len(TASKS) == len(suite.BENCHMARKING) == 28


def test_specs_timestep_and_step_limit_are_dm_controls(pair):
    task, env, theirs = pair
    spec = theirs.observation_spec()
    ours = env.unwrapped.observation_structure
    assert list(ours) == list(spec), "the keys, in dm_control's order"
    for key, array in spec.items():
        assert ours[key] == int(np.prod(array.shape)), key
    assert env.observation_space.shape == (sum(ours.values()),)
    assert env.observation_space.dtype == np.float64
    action = theirs.action_spec()
    assert env.action_space.shape == action.shape
    np.testing.assert_allclose(env.action_space.low, action.minimum, rtol=1e-6)
    np.testing.assert_allclose(env.action_space.high, action.maximum, rtol=1e-6)
    setup = env.unwrapped._setup
    assert setup.n_sub_steps == theirs._n_sub_steps
    assert setup.step_limit == int(theirs._step_limit)
    assert env.unwrapped.dt == pytest.approx(theirs.control_timestep())
    joints = [j["name"] for j in env.unwrapped.gymfleet_env.env_info["joints"]]
    model = theirs.physics.model
    # A free joint is the converted robot's floating base (qpos[0:7]).
    hinged = [model.joint(k).name for k in range(model.njnt) if model.jnt_type[k] != 0]
    assert joints == hinged, "qpos order"


def _sync_targets(task, env, theirs):
    """Puts the targets gymfleet drew (mocap bodies) where dm_control's model has them."""
    if not task.targets:
        return
    bodies = env.unwrapped.gymfleet_env.bodies()
    names = list(bodies["instances"])
    centers = np.asarray(bodies["centers_of_mass"]).reshape(-1, 3)
    poses = np.asarray(bodies["site_poses"]).reshape(-1, 7)
    for field, name, instance in task.targets:
        if field == "body_quat":
            # The body's origin site (named after it): its orientation, w first.
            value = poses[list(bodies["sites"]).index(instance)][3:]
        else:
            value = centers[names.index(instance)]
        getattr(theirs.physics.named.model, field)[name] = value


def _their_view(task, theirs, qpos, qvel, action, env=None):
    physics = theirs.physics
    if env is not None:
        _sync_targets(task, env, theirs)
    with physics.reset_context():
        physics.set_state(np.concatenate([qpos, qvel]))
        physics.data.ctrl[:] = action
    return theirs.task.get_observation(physics), theirs.task.get_reward(physics)


def test_observation_and_reward_on_the_same_state(pair):
    task, env, theirs = pair
    env.reset(seed=3)
    rng = np.random.default_rng(0)
    rewards = []
    for step in range(12):
        action = rng.uniform(-1.0, 1.0, env.action_space.shape).astype(np.float32)
        obs, reward, terminated, truncated, info = env.step(action)
        assert not terminated and not truncated and info["discount"] == 1.0
        data = env.unwrapped.data
        want, want_reward = _their_view(task, theirs, data.qpos, data.qvel, action, env)
        got = env.unwrapped.observation_dict()
        flat = []
        for key, value in want.items():
            assert np.shape(got[key]) == np.shape(value), key
            flat.append(np.reshape(got[key], -1))
            if (task.domain, key) in CONTACT_KEYS:
                continue
            np.testing.assert_allclose(got[key], value, rtol=1e-4, atol=2e-5,
                                       err_msg=f"{task.id} step {step}: {key}")
        np.testing.assert_array_equal(obs, np.concatenate(flat))
        assert reward == pytest.approx(want_reward, abs=1e-4), f"{task.id} step {step}"
        rewards.append(want_reward)
    assert np.all(np.isfinite(rewards))


def test_set_state_gives_dm_controls_observation(pair):
    """dm_control's own reset state, put into gymfleet's env."""
    task, env, theirs = pair
    env.reset(seed=0)
    theirs.reset()
    physics = theirs.physics
    qpos, qvel = physics.data.qpos.copy(), physics.data.qvel.copy()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a start past a hard stop is clamped, with a warning
        env.unwrapped.set_state(qpos, qvel)
    _sync_targets(task, env, theirs)
    with physics.reset_context():
        physics.set_state(np.concatenate([qpos, qvel]))
    want = theirs.task.get_observation(physics)
    got = env.unwrapped.observation_dict()
    data = env.unwrapped.data
    if np.allclose(data.qpos, qpos, atol=1e-5):
        for key, value in want.items():
            if (task.domain, key) not in CONTACT_KEYS:
                np.testing.assert_allclose(got[key], value, rtol=1e-4, atol=2e-5, err_msg=key)


def test_episodes_truncate_at_dm_controls_step_limit():
    task = TASKS["gymfleet/PendulumSwingup-v1"]
    env = gym.make(task.id)
    theirs = _dm_env(task)
    theirs.reset()
    env.reset(seed=0)
    zero = np.zeros(env.action_space.shape, dtype=np.float32)
    for k in range(1, 1001):
        _, _, terminated, truncated, info = env.step(zero)
        timestep = theirs.step(np.zeros(1))
        assert not terminated
        assert truncated == (k == 1000) == timestep.last(), k
        assert info["discount"] == timestep.discount == 1.0
    env.close()


def test_a_shorter_time_limit_and_control_timestep_are_honoured():
    env = gym.make("gymfleet/CartpoleBalance-v1", task_kwargs={"time_limit": 0.5},
                   environment_kwargs={"n_sub_steps": 2})
    assert env.unwrapped.dt == pytest.approx(0.02)
    env.reset(seed=0)
    zero = np.zeros(env.action_space.shape, dtype=np.float32)
    flags = [env.step(zero)[3] for _ in range(25)]
    assert flags == [False] * 24 + [True]
    env.close()


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"task_kwargs": {"seed": 1}}, "task_kwargs: unknown key(s) seed; the keys are random, time_limit"),
        ({"environment_kwargs": {"n_sub_steps": 0}}, "n_sub_steps: expected an integer >= 1, got 0"),
        ({"environment_kwargs": {"control_timestep": 0.015}},
         "control_timestep: 0.015 is not a multiple of the physics timestep 0.01"),
        ({"task_kwargs": {"time_limit": -1}}, "time_limit: expected a positive number of seconds, got -1.0"),
        ({"task_kwargs": {"random": np.random.RandomState(0)}},
         "task_kwargs['random']: gymfleet takes an integer seed"),
        ({"frame_skip": 2}, "unknown keyword argument(s) frame_skip"),
        ({"environment_kwargs": {"n_sub_steps": 2, "control_timestep": 0.02}},
         "environment_kwargs: give control_timestep or n_sub_steps, not both (as dm_control)"),
        ({"environment_kwargs": {"physics_timestep": 0.01}},
         "environment_kwargs: unknown key(s) physics_timestep; the keys are control_timestep"),
        ({"dtype": np.int32}, "dtype: expected numpy.float64 (the default) or numpy.float32"),
    ],
)
def test_bad_keywords_are_refused_with_a_clear_message(kwargs, message):
    with pytest.raises(gymfleet.InvalidArgument) as err:
        gym.make("gymfleet/CartpoleBalance-v1", **kwargs)
    assert message in str(err.value)


def test_the_tasks_starts_are_drawn_as_dm_controls():
    """Start distributions: pendulum's hinge uniform in [-pi, pi); cart-pole swing-up's
    pole down (pi +- 0.01 rad) with small velocities; the cheetah settled on the floor
    after 200 physics steps; the walker's torso at any angle."""
    def starts(env_id, n=40):
        env = gym.make(env_id)
        out = [env.unwrapped.data for _ in range(n) if env.reset(seed=None) is not None]
        env.close()
        return np.array([d.qpos for d in out]), np.array([d.qvel for d in out])

    q, _ = starts("gymfleet/PendulumSwingup-v1")
    assert q[:, 0].min() < -2.0 and q[:, 0].max() > 2.0 and np.all(np.abs(q[:, 0]) <= np.pi + 1e-6)
    q, v = starts("gymfleet/CartpoleSwingup-v1")
    assert np.all(np.abs(q[:, 1] - np.pi) < 0.05) and 0.002 < np.std(q[:, 1]) < 0.03
    assert 0.002 < np.std(v) < 0.03
    q, v = starts("gymfleet/CheetahRun-v1", n=8)
    assert np.all(np.abs(v[:, :2]) < 0.5), "settled: little motion left"
    # Settled on compliant contacts, starts cluster within a few mrad: compared to 1 µrad.
    assert len({round(x, 6) for x in q[:, 3]}) == 8, "each start's back thigh differs"
    assert np.std(q[:, 3]) > 1e-3, "and the starts spread"
    q, _ = starts("gymfleet/WalkerStand-v1")
    assert q[:, 2].min() < -2.0 and q[:, 2].max() > 2.0, "rooty uniform in [-pi, pi)"


def test_same_seed_same_episode_and_vector_env_equals_single():
    envs = gymfleet.make_vec("gymfleet/WalkerWalk-v1", 3)
    single = gym.make("gymfleet/WalkerWalk-v1")
    obs, _ = envs.reset(seed=[5, 6, 7])
    first, _ = single.reset(seed=6)
    np.testing.assert_array_equal(obs[1], first)
    rng = np.random.default_rng(1)
    for _ in range(5):
        actions = rng.uniform(-1, 1, envs.action_space.shape).astype(np.float32)
        obs, rewards, _, _, _ = envs.step(actions)
        one, reward, _, _, _ = single.step(actions[1])
        np.testing.assert_array_equal(obs[1], one)
        assert rewards[1] == reward
    envs.close()
    single.close()


def test_dm_env_interface_is_dm_controls():
    from gymfleet import dm_control as gdm
    import dm_env

    env = gdm.load("walker", "walk", task_kwargs={"random": 0, "time_limit": 0.1})
    theirs = suite.load("walker", "walk", task_kwargs={"random": 0, "time_limit": 0.1})
    assert isinstance(env, dm_env.Environment)
    spec, their_spec = env.observation_spec(), theirs.observation_spec()
    assert list(spec) == list(their_spec)
    for key in spec:
        assert spec[key].shape == their_spec[key].shape and spec[key].dtype == their_spec[key].dtype, key
    assert env.action_spec().shape == theirs.action_spec().shape
    np.testing.assert_array_equal(env.action_spec().minimum, theirs.action_spec().minimum)
    assert env.control_timestep() == pytest.approx(theirs.control_timestep())
    first, their_first = env.reset(), theirs.reset()
    assert first.step_type == their_first.step_type == dm_env.StepType.FIRST
    assert first.reward is None and first.discount is None
    for key, value in first.observation.items():
        assert np.shape(value) == np.shape(their_first.observation[key]), key
    kinds = []
    for _ in range(5):
        ts, their = env.step(np.zeros(6)), theirs.step(np.zeros(6))
        kinds.append(ts.step_type)
        assert ts.step_type == their.step_type and ts.discount == their.discount
    assert kinds == [dm_env.StepType.MID] * 3 + [dm_env.StepType.LAST, dm_env.StepType.FIRST]
    physics = env.physics
    assert physics.named.data.qpos["rootz"] == physics.data.qpos[0]
    ts = env.step(np.zeros(6))
    assert float(env.physics.named.data.xpos["torso", "z"]) == pytest.approx(float(ts.observation["height"]), abs=1e-6)
    assert env.physics.named.data.sensordata["torso_subtreelinvel"].shape == (3,)
    with pytest.raises(KeyError, match="'nose'"):
        env.physics.named.data.xpos["nose"]
    with pytest.raises(gymfleet.InvalidArgument, match="is not one of the Control Suite tasks gymfleet serves"):
        gdm.load("walker", "fly")
    with pytest.raises(gymfleet.InvalidArgument, match="load_batch: flat_observation is not supported"):
        gdm.load_batch("cartpole", "balance", 2, environment_kwargs={"flat_observation": True})
    with pytest.raises(gymfleet.InvalidArgument, match="'gymfleet/Nope-v1' is not one of gymfleet's Control Suite ids"):
        gymfleet.dmc.DmcEnv("gymfleet/Nope-v1")
    flat = gdm.load("cartpole", "balance", environment_kwargs={"flat_observation": True})
    assert flat.reset().observation["observations"].shape == (5,)
    env.close()
    flat.close()


def test_dm_env_batch_steps_many_envs_and_restarts_finished_ones():
    from gymfleet import dm_control as gdm
    import dm_env

    batch = gdm.load_batch("pendulum", "swingup", 4, task_kwargs={"time_limit": 0.06})
    ts = batch.reset(seed=0)
    assert ts.observation["orientation"].shape == (4, 2) and np.all(ts.step_type == dm_env.StepType.FIRST)
    kinds = [batch.step(np.zeros((4, 1))).step_type[0] for _ in range(4)]
    assert kinds == [dm_env.StepType.MID, dm_env.StepType.MID, dm_env.StepType.LAST, dm_env.StepType.FIRST]
    batch.close()


@pytest.mark.parametrize(
    "env_id, states",
    [
        # The spinner's velocity across finger-spin's threshold (-15 rad/s).
        ("gymfleet/FingerSpin-v1",
         [(None, {"hinge": w}) for w in np.linspace(-17.0, -13.0, 17)]),
        # The ball across the cup's target box (|offset| < 0.025 m), above and beside.
        ("gymfleet/BallInCupCatch-v1",
         [({"ball_z": 0.35 + dz}, None) for dz in np.linspace(-0.04, 0.04, 17)]
         + [({"ball_x": dx, "ball_z": 0.35}, None) for dx in np.linspace(-0.04, 0.04, 17)]),
        # The tip across acrobot's target sphere (radius 0.2 m, 4 m up).
        ("gymfleet/AcrobotSwingupSparse-v1",
         [({"shoulder": a}, None) for a in np.linspace(-0.12, 0.12, 13)]),
        ("gymfleet/CartpoleBalanceSparse-v1",
         [({"hinge_1": a}, None) for a in np.linspace(-0.15, 0.15, 13)]
         + [({"slider": x}, None) for x in np.linspace(-0.3, 0.3, 13)]),
    ],
)
def test_sparse_rewards_near_their_thresholds(env_id, states):
    """Indicator rewards on states either side of their thresholds: set on gymfleet's env,
    one step of zero action, then the step's state into dm_control's."""
    task = TASKS[env_id]
    env = gym.make(env_id)
    theirs = _dm_env(task)
    env.reset(seed=0)
    model = theirs.physics.model
    names = [model.joint(k).name for k in range(model.njnt)]
    zero = np.zeros(env.action_space.shape, dtype=np.float32)
    seen = set()
    for positions, velocities in states:
        qpos, qvel = np.zeros(model.nq), np.zeros(model.nv)
        for name, value in (positions or {}).items():
            qpos[names.index(name)] = value
        for name, value in (velocities or {}).items():
            qvel[names.index(name)] = value
        env.unwrapped.set_state(qpos, qvel)
        _, reward, _, _, _ = env.step(zero)
        data = env.unwrapped.data
        _, want = _their_view(task, theirs, data.qpos, data.qvel, zero)
        assert reward == want, f"{env_id} from {positions or velocities}: {reward} vs {want}"
        seen.add(want)
    assert seen == {0.0, 1.0}, "the states reach both sides"
    env.close()


@pytest.mark.parametrize("env_id", ["gymfleet/FingerSpin-v1", "gymfleet/BallInCupCatch-v1",
                                    "gymfleet/HumanoidStand-v1",
                                    "gymfleet/ManipulatorBringBall-v1"])
def test_starts_drawn_again_until_nothing_touches_touch_nothing_in_mujoco(env_id):
    """The starts dm_control draws again while ``ncon > 0``: gymfleet's, put into
    dm_control's physics, touch nothing there either; the humanoid's free body starts at
    every orientation."""
    task = TASKS[env_id]
    env = gym.make(env_id)
    theirs = _dm_env(task)
    physics = theirs.physics
    quats = []
    for k in range(12):
        env.reset(seed=k)
        data = env.unwrapped.data
        with physics.reset_context():
            physics.set_state(np.concatenate([data.qpos, data.qvel]))
        assert physics.data.ncon == 0, f"{env_id} seed {k}: {physics.data.ncon} contacts in MuJoCo"
        if task.domain == "humanoid":
            quats.append(data.qpos[3:7])
    if quats:
        # Uniform orientations: the torso's up axis points anywhere.
        up = [physics_up(q) for q in quats]
        assert min(up) < -0.3 and max(up) > 0.3
    env.close()


def physics_up(q):
    """The world z component of a body's z axis, from its quaternion (w, x, y, z)."""
    w, x, y, z = q / np.linalg.norm(q)
    return 1.0 - 2.0 * (x * x + y * y)


def test_remote_server_and_fleet_give_the_embedded_servers_bits(remote_server):
    """The ids on a remote server and on a fleet of two (a humanoid's batch sharded, its
    starts drawn again until nothing touches): the same seeds and actions, the same bits."""
    for env_id in ("gymfleet/WalkerWalk-v1", "gymfleet/HumanoidRun-v1"):
        local = gymfleet.make_vec(env_id, 4)
        with gymfleet.Server(threads=1) as other:
            for server in (remote_server, f"{remote_server},{other.address}"):
                envs = gymfleet.make_vec(env_id, 4, server=server)
                np.testing.assert_array_equal(envs.reset(seed=3)[0], local.reset(seed=3)[0])
                rng = np.random.default_rng(2)
                for _ in range(4):
                    actions = rng.uniform(-1, 1, envs.action_space.shape).astype(np.float32)
                    (o0, r0, *_), (o1, r1, *_) = envs.step(actions), local.step(actions)
                    np.testing.assert_array_equal(o0, o1)
                    np.testing.assert_array_equal(r0, r1)
                envs.close()
        local.close()


def test_a_stepped_env_pickles_and_continues_bit_for_bit():
    import pickle

    env = gym.make("gymfleet/CheetahRun-v1")
    env.reset(seed=4)
    zero = np.full(env.action_space.shape, 0.3, dtype=np.float32)
    for _ in range(3):
        env.step(zero)
    twin = pickle.loads(pickle.dumps(env))
    for _ in range(3):
        a, b = env.step(zero), twin.step(zero)
        np.testing.assert_array_equal(a[0], b[0])
        assert a[1] == b[1]
    env.close()
    twin.close()

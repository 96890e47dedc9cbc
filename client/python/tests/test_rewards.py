"""The v5 ids' rewards equal the sums of their ``info`` terms exactly, in the order
Gymnasium's envs add them (the sums Gymnasium's own tests take), single and batched; and
an action of the wrong shape is refused as Gymnasium's MuJoCo env refuses it."""

from __future__ import annotations

import numpy as np
import pytest

import gymfleet
from gymfleet.suite import SUITE

gymnasium = pytest.importorskip("gymnasium")

NAMES = [spec.name for spec in SUITE.values()]

#: Each id's reward from its info terms, written as Gymnasium's `test_reward_sum` and its
#: envs' `_get_rew` write it.
SUMS = {
    "Ant": lambda i: (i["reward_survive"] + i["reward_forward"])
    - (-i["reward_ctrl"] + -i["reward_contact"]),
    "Humanoid": lambda i: (i["reward_survive"] + i["reward_forward"])
    - (-i["reward_ctrl"] + -i["reward_contact"]),
    "HalfCheetah": lambda i: i["reward_forward"] + i["reward_ctrl"],
    "Swimmer": lambda i: i["reward_forward"] + i["reward_ctrl"],
    "Hopper": lambda i: i["reward_forward"] + i["reward_survive"] + i["reward_ctrl"],
    "Walker2d": lambda i: i["reward_forward"] + i["reward_survive"] + i["reward_ctrl"],
    "HumanoidStandup": lambda i: i["reward_linup"] + i["reward_quadctrl"] + i["reward_impact"] + 1,
    "InvertedPendulum": lambda i: i["reward_survive"],
    "InvertedDoublePendulum": lambda i: i["reward_survive"]
    + i["distance_penalty"]
    + i["velocity_penalty"],
    "Reacher": lambda i: i["reward_dist"] + i["reward_ctrl"],
    "Pusher": lambda i: i["reward_dist"] + i["reward_ctrl"] + i["reward_near"],
}


def test_every_id_has_its_sum():
    assert set(SUMS) == set(NAMES)


@pytest.mark.parametrize("name", NAMES)
def test_the_reward_is_exactly_the_sum_of_its_info_terms(name):
    env = gymnasium.make(f"gymfleet/{name}-v5")
    env.reset(seed=0)
    env.action_space.seed(0)
    for step in range(30):
        _, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert type(reward) is float, type(reward)
        assert reward == SUMS[name](info), (step, reward, info)
        if terminated or truncated:
            env.reset()
    env.close()


@pytest.mark.parametrize("name", ["Hopper", "HumanoidStandup", "InvertedDoublePendulum"])
def test_batched_rewards_are_the_same_sums(name):
    envs = gymnasium.make_vec(f"gymfleet/{name}-v5", 4, vectorization_mode="vector_entry_point")
    envs.reset(seed=0)
    envs.action_space.seed(0)
    for _ in range(30):
        _, rewards, terminated, truncated, infos = envs.step(envs.action_space.sample())
        assert rewards.dtype == np.float64
        for k in range(4):
            if "_final_info" in infos and infos["_final_info"][k]:
                continue
            row = {key: value[k] for key, value in infos.items() if not key.startswith("_")}
            if not all(infos["_" + key][k] for key in row if "_" + key in infos):
                continue  # a row the server reset (next-step autoreset): reward 0
            assert rewards[k] == SUMS[name](row), (k, rewards[k], row)
    envs.close()


@pytest.mark.parametrize("name", NAMES)
def test_a_single_env_gives_the_bits_of_a_batch_of_one(name):
    # The single env computes its info and reward on Python floats, a batch on float64
    # arrays: the same operations, so the same bits.
    env = gymnasium.make(f"gymfleet/{name}-v5")
    envs = gymnasium.make_vec(f"gymfleet/{name}-v5", 1, vectorization_mode="vector_entry_point")
    obs, _ = env.reset(seed=3)
    batch_obs, _ = envs.reset(seed=3)
    np.testing.assert_array_equal(obs, batch_obs[0])
    rng = np.random.default_rng(3)
    low, high = env.action_space.low, env.action_space.high
    for step in range(20):
        action = rng.uniform(low, high).astype(np.float32)
        obs, reward, terminated, truncated, info = env.step(action)
        batch_obs, rewards, batch_terminated, _, infos = envs.step(action[None, :])
        np.testing.assert_array_equal(obs, batch_obs[0], err_msg=f"step {step}")
        assert reward == rewards[0], (step, reward, rewards[0])
        assert terminated == batch_terminated[0]
        assert set(info) == {k for k in infos if not k.startswith("_")}
        for key, value in info.items():
            np.testing.assert_array_equal(value, infos[key][0], err_msg=f"step {step}: {key}")
            assert np.ndim(value) > 0 or type(value) is float, (key, type(value))
        if terminated or truncated:
            break
    env.close()
    envs.close()


def test_an_action_of_the_wrong_shape_is_refused_as_gymnasiums_env_refuses_it():
    env = gymnasium.make("gymfleet/Hopper-v5")
    env.reset(seed=0)
    for bad in (np.zeros((3, 1)), np.zeros(4), np.zeros((1, 3))):
        with pytest.raises(ValueError, match=r"^Action dimension mismatch\. Expected \(3,\), found "):
            env.step(bad)
    # As MuJoCo's: a list of the right length is an action.
    env.step([0.0, 0.0, 0.0])
    env.close()


@pytest.mark.parametrize("name", ["Hopper", "Ant", "Reacher"])
def test_float64_observations_on_request_are_the_float32_ones_widened(name):
    wide = gymnasium.make(f"gymfleet/{name}-v5", dtype=np.float64)
    narrow = gymnasium.make(f"gymfleet/{name}-v5")
    assert wide.observation_space.dtype == np.float64
    assert narrow.observation_space.dtype == np.float32
    a, _ = wide.reset(seed=2)
    b, _ = narrow.reset(seed=2)
    assert a.dtype == np.float64 and np.array_equal(a, b.astype(np.float64))
    wide.action_space.seed(1)
    for _ in range(10):
        action = wide.action_space.sample()
        a = wide.step(action)[0]
        b = narrow.step(action)[0]
        assert a.dtype == np.float64 and np.array_equal(a, b.astype(np.float64))
        assert wide.observation_space.contains(a)
    from gymnasium.utils.env_checker import check_env

    check_env(wide.unwrapped, skip_render_check=True)
    with pytest.raises(gymfleet.InvalidArgument, match=r"^dtype: expected numpy\.float32 \(the default\) or numpy\.float64, got <class 'numpy\.int32'>$"):
        gymnasium.make(f"gymfleet/{name}-v5", dtype=np.int32)
    wide.close()
    narrow.close()

"""The VectorEnv contract, checked as gymnasium checks its own vector envs: spaces,
shapes and dtypes, and step-by-step agreement with a `SyncVectorEnv` of the same envs
(gymnasium's reference implementation of the three autoreset modes), `final_obs`,
`final_info` and `reset_mask` included."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode, SyncVectorEnv
from gymnasium.vector.utils import batch_space

import gymfleet

N = 4
OPTIONS = dict(end_effector_ids=["forearm"], max_steps=5, reset_noise=2.0)


def pair(arm2, mode):
    ours = gymfleet.make_vec(arm2, N, autoreset_mode=mode, **OPTIONS)
    reference = SyncVectorEnv(
        [lambda: gymfleet.make(arm2, **OPTIONS) for _ in range(N)], autoreset_mode=mode
    )
    return ours, reference


def assert_same(a, b, what):
    if isinstance(a, tuple):
        assert len(a) == len(b), what
        for k, (x, y) in enumerate(zip(a, b)):
            assert_same(x, y, f"{what}[{k}]")
    elif isinstance(a, dict):
        assert a.keys() == b.keys(), f"{what}: {a.keys()} != {b.keys()}"
        for k in a:
            assert_same(a[k], b[k], f"{what}[{k!r}]")
    elif isinstance(a, np.ndarray) and a.dtype == object:
        assert a.shape == b.shape, what
        for x, y in zip(a, b):
            assert (x is None) == (y is None), what
            if x is not None:
                assert_same(np.asarray(x), np.asarray(y), what)
    else:
        np.testing.assert_array_equal(a, b, err_msg=what)


def without_episode_step(infos):
    """The reference's per-env infos carry the single env's `episode_step`, which a
    batch does not report."""
    out = {k: v for k, v in infos.items() if k not in ("episode_step", "_episode_step")}
    if "final_info" in out:
        out["final_info"] = without_episode_step(out["final_info"])
    return out


def test_spaces_and_metadata_follow_gymnasium(arm2):
    envs = gymfleet.make_vec(arm2, N, **OPTIONS)
    single = gymfleet.make(arm2, **OPTIONS)
    assert envs.num_envs == N
    assert envs.single_observation_space == single.observation_space
    assert envs.single_action_space == single.action_space
    assert envs.observation_space == batch_space(single.observation_space, N)
    assert envs.action_space == batch_space(single.action_space, N)
    assert envs.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP
    obs, infos = envs.reset(seed=1)
    assert obs.shape == (N, 11) and obs.dtype == np.float32 and infos == {}
    assert obs in envs.observation_space
    obs, rewards, terminations, truncations, infos = envs.step(np.zeros((N, 2)))
    assert obs.shape == (N, 11) and obs.dtype == np.float32
    assert rewards.shape == (N,) and rewards.dtype == np.float32
    assert terminations.shape == (N,) and terminations.dtype == np.bool_
    assert truncations.shape == (N,) and truncations.dtype == np.bool_
    envs.close()
    single.close()


@pytest.mark.parametrize(
    "mode", [AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP, AutoresetMode.DISABLED]
)
def test_every_step_equals_gymnasiums_sync_vector_env(arm2, mode):
    ours, reference = pair(arm2, mode)
    assert ours.metadata["autoreset_mode"] == mode
    rng = np.random.default_rng(0)
    assert_same(ours.reset(seed=7), reference.reset(seed=7), "reset")
    ended = 0
    for t in range(13):
        actions = rng.uniform(-2e-4, 2e-4, size=(N, 2)).astype(np.float32)
        o = ours.step(actions)
        r = reference.step(actions)
        assert_same(o[0], r[0], f"step {t}: observations")
        assert_same(o[1], r[1].astype(np.float32), f"step {t}: rewards")
        assert_same(o[2], r[2], f"step {t}: terminations")
        assert_same(o[3], r[3], f"step {t}: truncations")
        assert_same(o[4], without_episode_step(r[4]), f"step {t}: infos")
        if mode == AutoresetMode.DISABLED and (o[2] | o[3]).any():
            mask = o[2] | o[3]
            ended += 1
            assert_same(
                ours.reset(options={"reset_mask": mask}),
                reference.reset(options={"reset_mask": mask.copy()}),
                f"step {t}: reset_mask",
            )
    if mode == AutoresetMode.SAME_STEP:
        assert "final_obs" not in o[4]
    assert ended == (2 if mode == AutoresetMode.DISABLED else 0)
    ours.close()
    reference.close()


def test_same_step_autoreset_returns_the_final_observation(arm2):
    envs = gymfleet.make_vec(arm2, N, autoreset_mode="SameStep", **OPTIONS)
    envs.reset(seed=0)
    for _ in range(4):
        _, _, _, truncations, infos = envs.step(np.zeros((N, 2)))
        assert not truncations.any() and infos == {}
    last = envs.observe()
    obs, _, _, truncations, infos = envs.step(np.zeros((N, 2)))
    assert truncations.all()
    assert infos["_final_obs"].all() and infos["_final_info"].all()
    final = np.stack(infos["final_obs"])
    assert final.shape == (N, 11)
    assert not np.array_equal(final, last), "the final observation is after the step"
    assert not np.array_equal(final, obs), "the returned observation is the reset one"


def test_a_partial_reset_of_a_disabled_batch_leaves_the_other_envs_alone(arm2):
    envs = gymfleet.make_vec(arm2, N, autoreset_mode=AutoresetMode.DISABLED, **OPTIONS)
    first, _ = envs.reset(seed=3)
    envs.step(np.full((N, 2), 1e-4))
    moved = envs.observe()
    mask = np.array([True, False, True, False])
    obs, _ = envs.reset(seed=3, options={"reset_mask": mask})
    np.testing.assert_array_equal(obs[mask], first[mask])
    np.testing.assert_array_equal(obs[~mask], moved[~mask])
    with pytest.raises(ValueError, match="at least one True"):
        envs.reset(options={"reset_mask": np.zeros(N, dtype=bool)})
    with pytest.raises(TypeError, match="dtype=np.bool_"):
        envs.reset(options={"reset_mask": np.ones(N)})


def test_per_env_seeds_seed_each_env(arm2):
    envs = gymfleet.make_vec(arm2, 3, **OPTIONS)
    seeds = [11, None, 5]
    obs, _ = envs.reset(seed=seeds)
    for i, s in enumerate(seeds):
        if s is not None:
            single = gymfleet.make(arm2, **OPTIONS)
            np.testing.assert_array_equal(obs[i], single.reset(seed=s)[0])
    with pytest.raises(ValueError, match="length must match num_envs=3"):
        envs.reset(seed=[1, 2])


def test_gymnasium_make_vec_builds_one_batch():
    envs = gym.make_vec("gymfleet/Arm2-v0", num_envs=16)
    assert isinstance(envs.unwrapped, gymfleet.GymfleetVectorEnv)
    assert envs.single_action_space.high[0] == np.float32(1e-3)
    envs.reset(seed=0)
    obs, *_ = envs.step(envs.action_space.sample())
    assert obs.shape == (16, 11)
    envs.close()


def test_gymnasium_can_import_the_package_itself():
    # `module:env_id` imports the module before looking the id up.
    env = gym.make("gymfleet:gymfleet/Pendulum-v0", max_steps=10)
    assert env.unwrapped.env_info["max_steps"] == 10
    env.close()

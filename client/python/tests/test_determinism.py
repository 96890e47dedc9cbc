"""The same seed and actions give identical arrays: twice in a row, on the embedded
server, on a server in its own process, and sharded over a fleet."""

from __future__ import annotations

import numpy as np

import gymfleet

OPTIONS = dict(end_effector_ids=["forearm"], max_steps=20, reset_noise=3.0)


def rollout(arm2, server, steps=30, n=6):
    envs = gymfleet.make_vec(arm2, n, server=server, autoreset_mode="SameStep", **OPTIONS)
    rng = np.random.default_rng(1)
    frames = [envs.reset(seed=123)[0]]
    for _ in range(steps):
        obs, rewards, terminations, truncations, infos = envs.step(
            rng.uniform(-3e-4, 3e-4, size=(n, 2))
        )
        frames += [obs, rewards, terminations, truncations]
        if "final_obs" in infos:
            frames.append(np.stack(infos["final_obs"][infos["_final_obs"]]))
    envs.close()
    return frames


def single_rollout(arm2, server, steps=30):
    env = gymfleet.make(arm2, server=server, **OPTIONS)
    rng = np.random.default_rng(2)
    frames = [env.reset(seed=9)[0]]
    for _ in range(steps):
        obs, reward, terminated, truncated, _ = env.step(rng.uniform(-3e-4, 3e-4, size=2))
        frames += [obs, np.float32(reward), terminated, truncated]
    env.close()
    return frames


def assert_identical(a, b):
    assert len(a) == len(b)
    for x, y in zip(a, b):
        x, y = np.asarray(x), np.asarray(y)
        assert x.dtype == y.dtype and x.shape == y.shape
        assert x.tobytes() == y.tobytes()


def test_the_same_seed_and_actions_give_the_same_bits_embedded_and_remote(arm2, remote_server):
    embedded = rollout(arm2, None)
    assert_identical(embedded, rollout(arm2, None))
    assert_identical(embedded, rollout(arm2, remote_server))
    single = single_rollout(arm2, None)
    assert_identical(single, single_rollout(arm2, remote_server))


def test_a_fleet_batch_gives_the_bits_of_a_one_server_batch(arm2):
    with gymfleet.Server(threads=1) as a, gymfleet.Server(threads=2) as b:
        fleet = f"{a.address},{b.address}"
        assert_identical(rollout(arm2, a.address), rollout(arm2, fleet))
        envs = gymfleet.make_vec(arm2, 6, server=fleet, **OPTIONS)
        assert [s[0] for s in envs.batch_info["shards"]] == [a.address, b.address]
        assert [s[2:] for s in envs.batch_info["shards"]] == [(0, 2), (2, 6)]
        envs.close()


def test_a_partial_reset_over_a_fleet_resets_the_right_envs(arm2):
    with gymfleet.Server(threads=1) as a, gymfleet.Server(threads=1) as b:
        fleet = gymfleet.make_vec(arm2, 4, server=f"{a.address},{b.address}", **OPTIONS)
        one = gymfleet.make_vec(arm2, 4, server=a.address, **OPTIONS)
        for envs in (fleet, one):
            envs.reset(seed=5)
            envs.step(np.full((4, 2), 2e-4))
        mask = np.array([False, True, True, False])
        assert_identical(
            [fleet.reset(seed=8, options={"reset_mask": mask})[0]],
            [one.reset(seed=8, options={"reset_mask": mask})[0]],
        )
        fleet.close()
        one.close()

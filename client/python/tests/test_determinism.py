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


#: Terrain (replaced in some envs) with a ball on it, a rope (a ranged spatial tendon) and a
#: coupling: what issue Z3 added, under a motor's random controls.
TERRAIN_ROPE_COUPLING = """<mujoco>
  <option timestep="0.004"/>
  <asset><hfield name="ground" nrow="9" ncol="9" size="1 1 0.1 0.05"/></asset>
  <worldbody>
    <geom name="terrain" type="hfield" hfield="ground"/>
    <site name="hook" pos="0.5 0 1"/>
    <body name="bob" pos="0.7 0 0.75">
      <joint name="bob_x" type="slide" axis="1 0 0"/><joint name="bob_z" type="slide" axis="0 0 1"/>
      <geom type="sphere" size="0.04"/><site name="knot"/></body>
    <body name="ball" pos="-0.3 0.3 0.4"><freejoint/><geom type="sphere" size="0.05"/></body>
    <body name="crank" pos="-0.5 0 0.5">
      <joint name="a" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0 0 0.2" size="0.02"/>
    </body>
    <body name="rocker" pos="-0.2 0 0.5">
      <joint name="b" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0 0 0.2" size="0.02"/>
    </body>
  </worldbody>
  <tendon><spatial name="rope" range="0 0.4"><site site="hook"/><site site="knot"/></spatial></tendon>
  <equality><joint joint1="b" joint2="a" polycoef="0 -0.5 0 0 0"/></equality>
  <actuator><motor joint="a" gear="0.2"/></actuator>
</mujoco>"""


def terrain_rollout(server, steps=60, n=4):
    envs = gymfleet.make_vec(TERRAIN_ROPE_COUPLING, n, server=server, units="si")
    envs.reset(seed=5)
    bumps = np.random.default_rng(3).uniform(0, 1, (9, 9)).astype(np.float32)
    envs.set_heightfield("terrain", bumps, env_indices=[1, 3])
    rng = np.random.default_rng(4)
    frames = []
    for _ in range(steps):
        obs, *_ = envs.step(rng.uniform(-1, 1, size=(n, 1)).astype(np.float32))
        frames.append(obs)
    envs.close()
    return frames


def test_terrain_ropes_and_couplings_give_the_same_bits_however_a_batch_is_sharded():
    with gymfleet.Server(threads=1) as a, gymfleet.Server(threads=2) as b:
        one = terrain_rollout(a.address)
        assert_identical(one, terrain_rollout(f"{a.address},{b.address}"))
        # The replaced terrain made envs 1 and 3 move otherwise: the test can tell.
        assert not np.array_equal(one[-1][0], one[-1][1])

"""The asynchronous API on a fleet of two servers (issue A): each env's trajectory is one
server's synchronous one, bit for bit; a server stopped mid-run surfaces as
``ServerLost`` at ``recv`` with the envs of the send that found it, and after
``recover()`` every env goes on from where it was, nothing lost or stepped twice."""

from __future__ import annotations

import numpy as np
import pytest
from gymnasium.vector import AutoresetMode

import gymfleet

from test_async import N, OPTIONS, STEPS, action, async_trajectories, sync_trajectories


@pytest.fixture
def fleet():
    servers = [gymfleet.Server(threads=1), gymfleet.Server(threads=1)]
    yield servers
    for s in servers:
        s.stop()


def test_a_fleets_async_trajectories_are_one_servers_sync_ones(arm2, fleet):
    want = sync_trajectories(arm2, AutoresetMode.NEXT_STEP)
    got, order = async_trajectories(arm2, AutoresetMode.NEXT_STEP, 4, server=",".join(s.address for s in fleet))
    for e in range(N):
        assert got[e] == want[e][: len(got[e])], f"env {e}"
        assert len(got[e]) >= 2
    # Envs of both servers came back within one recv: the sends span the shards.
    assert any(min(ids) < N // 2 <= max(ids) for ids in order)


def test_a_server_lost_mid_run_is_recovered_and_nothing_is_lost_or_stepped_twice(arm2, fleet):
    want = sync_trajectories(arm2, AutoresetMode.NEXT_STEP)
    envs = gymfleet.make_vec(arm2, N, batch_size=N // 2, server=",".join(s.address for s in fleet), **OPTIONS)
    shards = envs.batch_info["shards"]
    assert [(start, stop) for _, _, start, stop in shards] == [(0, N // 2), (N // 2, N)]
    envs.checkpoint_every(3)
    envs.async_reset()
    seen = [[] for _ in range(N)]
    halves = (np.arange(N // 2, N), np.arange(N // 2))  # the second server's envs, the first's

    def take() -> None:
        obs, rew, term, trunc, info = envs.recv()
        for row, e in enumerate(info["env_id"]):
            seen[e].append((obs[row].tobytes(), float(rew[row]), bool(term[row]), bool(trunc[row])))

    take(), take()  # the resets
    lost = None
    for k in range(STEPS):
        if k == 4:
            fleet[1].stop()
        for ids in halves:
            envs.send(np.stack([action(e, k) for e in ids]), ids)
        got = 0
        while got < 2:
            try:
                take()
                got += 1
            except gymfleet.ServerLost as err:
                assert lost is None, "one loss, raised once"
                lost = err
                assert err.server == fleet[1].address and err.envs == [(N // 2, N)]
                # The send that found the loss (or the one refused after it, if the first
                # server's send went first): its envs are out of flight.
                assert err.env_ids.tolist() in (halves[0].tolist(), halves[1].tolist())
                assert envs.recover() is None
    assert lost is not None, "the stopped server was found lost"
    # Rebuilt on the survivor.
    assert {server for server, _, _, _ in envs.batch_info["shards"]} == {fleet[0].address}
    for e in range(N):
        assert len(seen[e]) == STEPS + 1, f"env {e}: every step once"
        assert seen[e] == want[e], f"env {e}"
    envs.close()


def test_recover_without_checkpoints_or_a_loss(arm2, fleet):
    envs = gymfleet.make_vec(arm2, N, server=",".join(s.address for s in fleet), **OPTIONS)
    envs.reset(seed=0)
    with pytest.raises(ValueError, match=r"steps: expected a non-negative integer, got -1"):
        envs.checkpoint_every(-1)
    fleet[1].stop()
    with pytest.raises(gymfleet.ServerLost):
        envs.step(np.zeros((N, 2), dtype=np.float32))
    no_checkpoint = "fleet: this fleet batch keeps no checkpoint to recover from: call checkpoint_every first"
    with pytest.raises(gymfleet.InvalidArgument, match=no_checkpoint):
        envs.recover()
    with pytest.raises(gymfleet.InvalidArgument, match="expected one replacement server's address, got the list"):
        envs.recover(server=f"{fleet[0].address},{fleet[1].address}")
    envs.close()
    # With checkpoints and nothing lost there is nothing to do.
    envs = gymfleet.make_vec(arm2, N, server=fleet[0].address, **OPTIONS)
    envs.checkpoint_every(5)
    envs.reset(seed=0)
    assert envs.recover() is None
    envs.close()


def test_a_whole_step_that_found_the_loss_is_recovers_result(arm2, fleet):
    reference = gymfleet.make_vec(arm2, N, **OPTIONS)
    envs = gymfleet.make_vec(arm2, N, server=",".join(s.address for s in fleet), **OPTIONS)
    reference.reset(), envs.reset()
    envs.checkpoint_every(2)
    for k in range(5):
        acts = np.stack([action(e, k) for e in range(N)])
        want = reference.step(acts)
        if k == 3:
            fleet[0].stop()
            with pytest.raises(gymfleet.ServerLost):
                envs.step(acts)
            got = envs.recover()
        else:
            got = envs.step(acts)
        for x, y in zip(want[:4], got[:4]):
            np.testing.assert_array_equal(x, y, err_msg=f"step {k}")
    envs.close(), reference.close()

"""The asynchronous API of the vector env, EnvPool's way (``make_vec(..., batch_size=M)``,
``async_reset``, ``send``, ``recv``, ``step(actions, env_id)``) and
``step_async``/``step_wait``: each env's trajectory is the synchronous path's, bit for bit,
in whatever order and grouping envs come back, in each autoreset mode, embedded and on a
remote server; errors surface at the next ``recv`` with the envs they concern."""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest
from gymnasium.vector import AutoresetMode

import gymfleet
from gymfleet.pipeline import IN_FLIGHT

N = 6
STEPS = 9
OPTIONS = dict(end_effector_ids=["forearm"], max_steps=4, reset_noise=5.0, seed=3)


def action(env, k):
    """Env ``env``'s action at its own step ``k`` (torques in the env's bounds)."""
    x = env * 7 + k * 3
    return np.array([0.4 * np.sin(x), -0.3 * np.cos(x)], dtype=np.float32)


def sync_trajectories(arm2, mode, **kwargs):
    """Each env's (observation, reward, terminated, truncated) at its own steps 0..STEPS
    (0: its reset), stepping every env together."""
    envs = gymfleet.make_vec(arm2, N, autoreset_mode=mode, **OPTIONS, **kwargs)
    obs, _ = envs.reset()
    seen = [[(obs[e].tobytes(), 0.0, False, False)] for e in range(N)]
    for k in range(STEPS):
        obs, rew, term, trunc, info = envs.step(np.stack([action(e, k) for e in range(N)]))
        for e in range(N):
            seen[e].append((obs[e].tobytes(), float(rew[e]), bool(term[e]), bool(trunc[e])))
    envs.close()
    return seen


def async_trajectories(arm2, mode, batch_size, **kwargs):
    """The same, EnvPool's loop: recv M envs, send their actions, until each env took
    STEPS steps; returns the trajectories and the order envs came back in."""
    envs = gymfleet.make_vec(arm2, N, autoreset_mode=mode, batch_size=batch_size, **OPTIONS, **kwargs)
    assert envs.batch_size == batch_size
    envs.async_reset()
    seen = [[] for _ in range(N)]
    order = []
    while True:
        try:
            obs, rew, term, trunc, info = envs.recv()
        except RuntimeError:
            break  # fewer than batch_size envs left to come back: done
        ids = info["env_id"]
        assert obs.shape == (batch_size, envs.single_observation_space.shape[0])
        order.append(ids.tolist())
        for row, e in enumerate(ids):
            seen[e].append((obs[row].tobytes(), float(rew[row]), bool(term[row]), bool(trunc[row])))
        # The envs that have steps to go go back out, in a reversed order.
        going = [int(e) for e in ids[::-1] if len(seen[e]) <= STEPS]
        if going:
            envs.send(np.stack([action(e, len(seen[e]) - 1) for e in going]), np.array(going))
    envs.close()
    return seen, order


@pytest.mark.parametrize("mode", [AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP])
@pytest.mark.parametrize("batch_size", [2, 3, 6])
def test_each_envs_trajectory_is_the_sync_paths_bit_for_bit(arm2, mode, batch_size):
    want = sync_trajectories(arm2, mode)
    got, order = async_trajectories(arm2, mode, batch_size)
    for e in range(N):
        n = len(got[e])
        assert n >= 2, f"env {e} stepped"
        assert got[e] == want[e][:n], f"env {e} ({mode}, batch_size {batch_size})"
    assert any(d for s in want for (_, _, t, u) in s for d in (t, u)), "episodes ended on the way"
    if batch_size < N:
        assert order[0] == list(range(batch_size)), "first the resets, in env order"
        assert len({tuple(o) for o in order}) > 1


def test_step_with_env_id_is_send_then_recv(arm2):
    envs = gymfleet.make_vec(arm2, N, batch_size=N, **OPTIONS)
    envs.async_reset()
    obs, *_ , info = envs.recv()
    assert info["env_id"].tolist() == list(range(N))
    ids = np.array([5, 0, 3, 1, 4, 2])
    obs, rew, term, trunc, info = envs.step(np.stack([action(e, 0) for e in ids]), ids)
    assert sorted(info["env_id"].tolist()) == list(range(N))
    want = sync_trajectories(arm2, AutoresetMode.NEXT_STEP)
    for row, e in enumerate(info["env_id"]):
        assert obs[row].tobytes() == want[e][1][0]
    envs.close()


def test_step_async_and_step_wait_overlap_and_equal_step(arm2):
    a = gymfleet.make_vec(arm2, N, **OPTIONS)
    b = gymfleet.make_vec(arm2, N, **OPTIONS)
    a.reset(), b.reset()
    for k in range(5):
        actions = np.stack([action(e, k) for e in range(N)])
        b.step_async(actions)
        started = time.perf_counter()
        # The trainer's own work goes on here while the server steps.
        want = a.step(actions)
        got = b.step_wait()
        assert time.perf_counter() - started < 60
        for x, y in zip(got[:4], want[:4]):
            np.testing.assert_array_equal(x, y)
    with pytest.raises(RuntimeError, match="step_wait: call step_async first"):
        b.step_wait()
    b.step_async(actions)
    with pytest.raises(RuntimeError, match="step: a step_async is pending; call step_wait first"):
        b.step(actions)
    b.step_wait()
    a.close(), b.close()


def test_errors_surface_at_recv_with_their_env_ids_and_nothing_else_is_lost(arm2):
    envs = gymfleet.make_vec(arm2, N, batch_size=2, **OPTIONS)
    envs.async_reset()
    _, _, _, _, info = envs.recv()
    assert info["env_id"].tolist() == [0, 1]
    bad = np.array([[np.nan, 0.0], [0.0, 0.0]], dtype=np.float32)
    held = threading.Event()
    for _ in range(IN_FLIGHT):
        envs._pipeline.submit(held.wait)
    envs.send(bad, np.array([1, 0]))  # returns at once; the server will refuse it
    # The four resets still waiting come first, then the error.
    assert [envs.recv()[4]["env_id"].tolist() for _ in range(2)] == [[2, 3], [4, 5]]
    held.set()
    with pytest.raises(gymfleet.InvalidArgument, match="expected a finite number") as err:
        envs.recv()
    assert err.value.env_ids.tolist() == [0, 1]
    # Those envs are not in flight any more: they can be sent again, and step.
    envs.send(np.stack([action(0, 0), action(1, 0)]), np.array([0, 1]))
    _, _, _, _, info = envs.recv()
    assert sorted(info["env_id"].tolist()) == [0, 1]
    for call, message in [
        (lambda: envs.send(np.zeros((1, 2)), np.array([6])), r"env_id: expected ids in \[0, 6\), got \[6\]"),
        (lambda: envs.send(np.zeros((2, 2)), np.array([2, 2])), r"env_id: expected distinct ids, got \[2, 2\]"),
        (lambda: envs.send(np.zeros((0, 2)), np.array([], dtype=np.int64)), "env_id: expected one or more integer env ids"),
    ]:
        with pytest.raises(ValueError, match=message):
            call()
    # A send stays in flight until recv takes it (on a fleet, the workers held busy).
    hold = threading.Event()
    for _ in range(IN_FLIGHT):
        envs._pipeline.submit(hold.wait)
    envs.send(np.zeros((1, 2)), np.array([3]))
    with pytest.raises(ValueError, match=r"env_id: envs \[3\] are in flight: recv them first"):
        envs.send(np.zeros((1, 2)), np.array([3]))
    with pytest.raises(RuntimeError, match=r"step_async: envs are in flight \(send\): recv them first"):
        envs.step_async(np.zeros((N, 2)))
    hold.set()
    envs.close()


def test_recv_with_too_few_envs_out_and_a_bad_batch_size_are_refused(arm2):
    envs = gymfleet.make_vec(arm2, N, batch_size=4, **OPTIONS)
    envs.async_reset()
    envs.recv()
    with pytest.raises(RuntimeError, match="recv: 2 envs are ready and none in flight, fewer than batch_size=4"):
        envs.recv()
    envs.close()
    for size in (0, 7, 2.5, True):
        with pytest.raises(ValueError, match=r"batch_size: expected an integer in \[1, num_envs=6\]"):
            gymfleet.make_vec(arm2, N, batch_size=size, **OPTIONS)


def test_a_remote_server_gives_the_embedded_servers_trajectories(arm2, remote_server):
    want = sync_trajectories(arm2, AutoresetMode.NEXT_STEP)
    got, _ = async_trajectories(arm2, AutoresetMode.NEXT_STEP, 3, server=remote_server)
    for e in range(N):
        assert got[e] == want[e][: len(got[e])], f"env {e}"


def test_each_envs_info_is_the_sync_paths(arm2):
    # Term values and final observations come back per env as the synchronous step
    # gives them, each key with its mask, whatever the grouping.
    task = {"terms": [{"name": "effort", "weight": -1.0, "ctrl_cost": {}}]}
    mode = AutoresetMode.SAME_STEP
    envs = gymfleet.make_vec(arm2, N, autoreset_mode=mode, task=task, **OPTIONS)
    envs.reset()
    want = [[] for _ in range(N)]
    for k in range(STEPS):
        _, _, _, _, info = envs.step(np.stack([action(e, k) for e in range(N)]))
        for e in range(N):
            want[e].append({key: info[key][e] for key in ("effort", "final_obs")
                            if key in info and info["_" + key][e]})
    envs.close()
    assert any("final_obs" in i for w in want for i in w), "episodes ended on the way"

    envs = gymfleet.make_vec(arm2, N, autoreset_mode=mode, task=task, batch_size=4, **OPTIONS)
    envs.async_reset()
    got = [[] for _ in range(N)]
    first = True
    while True:
        try:
            _, _, _, _, info = envs.recv()
        except RuntimeError:
            break
        for row, e in enumerate(info["env_id"].tolist()):
            has = {key: info[key][row] for key in info
                   if key != "env_id" and not key.startswith("_") and info["_" + key][row]}
            if first or not has:
                assert "effort" not in has  # a reset's row: no terms
            else:
                got[e].append(has)
        first = False
        going = [int(e) for e in info["env_id"][::-1] if len(got[e]) < STEPS]
        if going:
            envs.send(np.stack([action(e, len(got[e])) for e in going]), np.array(going))
    envs.close()
    for e in range(N):
        assert len(got[e]) >= 2
        for k, (g, w) in enumerate(zip(got[e], want[e])):
            assert set(g) == set(w), (e, k, g, w)
            for key in w:
                np.testing.assert_array_equal(np.asarray(g[key]), np.asarray(w[key]), err_msg=f"env {e} step {k}: {key}")


@pytest.mark.parametrize("remote", [False, True])
def test_the_sends_behind_a_failed_one_step_once(arm2, remote, request):
    # On a stream the server answers nothing after a failed step: the sends behind it go
    # out again on a new stream, and each of their envs steps exactly once.
    kwargs = {"server": request.getfixturevalue("remote_server")} if remote else {}
    want = sync_trajectories(arm2, AutoresetMode.NEXT_STEP, **kwargs)
    envs = gymfleet.make_vec(arm2, N, batch_size=2, **OPTIONS, **kwargs)
    envs.async_reset()
    for _ in range(3):
        envs.recv()  # the resets
    bad = np.array([[np.nan, 0.0], [0.0, 0.0]], dtype=np.float32)
    envs.send(bad, np.array([0, 1]))
    envs.send(np.stack([action(2, 0), action(3, 0)]), np.array([2, 3]))
    envs.send(np.stack([action(4, 0), action(5, 0)]), np.array([4, 5]))
    with pytest.raises(gymfleet.InvalidArgument, match="expected a finite number") as err:
        envs.recv()
    assert err.value.env_ids.tolist() == [0, 1]
    for ids in ([2, 3], [4, 5]):
        obs, rew, _, _, info = envs.recv()
        assert info["env_id"].tolist() == ids
        for row, e in enumerate(ids):
            assert (obs[row].tobytes(), float(rew[row])) == want[e][1][:2], f"env {e} stepped once"
    # The failed envs step again, from where they were.
    envs.send(np.stack([action(0, 0), action(1, 0)]), np.array([0, 1]))
    obs, _, _, _, info = envs.recv()
    assert [obs[row].tobytes() for row in range(2)] == [want[0][1][0], want[1][1][0]]
    envs.close()


def test_step_async_runs_on_its_worker_while_the_caller_works_and_is_taken_back_otherwise(arm2):
    a = gymfleet.make_vec(arm2, N, **OPTIONS)
    b = gymfleet.make_vec(arm2, N, **OPTIONS)
    a.reset(), b.reset()
    actions = np.stack([action(e, 0) for e in range(N)])
    # The caller waits without the GIL (as a policy's torch or numpy work does): the
    # worker steps meanwhile.
    b.step_async(actions)
    pending = b._pending_step[0]
    time.sleep(0.3)
    assert pending.done() and not pending.cancelled()
    got = b.step_wait()
    want = a.step(actions)
    for x, y in zip(want[:4], got[:4]):
        np.testing.assert_array_equal(x, y)
    # Back to back (SB3's `step`), the step is run by step_wait itself, with the same bits.
    actions = np.stack([action(e, 1) for e in range(N)])
    b.step_async(actions)
    pending = b._pending_step[0]
    got = b.step_wait()
    want = a.step(actions)
    assert pending.cancelled() or pending.done()
    for x, y in zip(want[:4], got[:4]):
        np.testing.assert_array_equal(x, y)
    a.close(), b.close()

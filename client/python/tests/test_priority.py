"""The simulation threads' scheduling priority (issue P2): the embedded server's pool runs
at this process's own priority, so that it does not starve beside the trainer's threads;
only a server asked for fairness between tenants (``pool_niceness``, the binary's
``--pool-niceness``) runs its pool nicer. Linux only: read from /proc."""

from __future__ import annotations

import os
import pathlib
import subprocess
import sys
import time

import pytest

import gymfleet
from conftest import REPO, _free_port, model

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc")


def step_threads(pid: int | str = "self") -> dict[int, int]:
    """The simulation pool's threads of process `pid`: thread id -> niceness."""
    found = {}
    for task in pathlib.Path(f"/proc/{pid}/task").iterdir():
        try:
            name = (task / "comm").read_text().strip()
            stat = (task / "stat").read_text()
        except FileNotFoundError:  # the thread ended meanwhile
            continue
        if name.startswith("gymfleet-step-"):
            # Fields after the command name (in parentheses); nice is field 19.
            found[int(task.name)] = int(stat.rsplit(")", 1)[1].split()[16])
    return found


def settled(read, expected: int, count: int) -> dict[int, int]:
    """`read()` once `count` threads show `expected`, or as it is after 10 s. A pool
    thread lowers its own priority as it starts, so a thread just spawned may not have."""
    deadline = time.monotonic() + 10
    while True:
        threads = read()
        if (len(threads) == count and set(threads.values()) == {expected}) or (
            time.monotonic() > deadline
        ):
            return threads
        time.sleep(0.01)


def test_the_embedded_servers_pool_runs_at_the_process_priority():
    env = gymfleet.make(model("pendulum"))
    env.reset(seed=0)
    env.step(env.action_space.sample())
    ours = os.getpriority(os.PRIO_PROCESS, 0)
    threads = step_threads()
    assert threads, "the embedded server's pool threads were not found"
    assert set(threads.values()) == {ours}, threads
    env.close()


def test_a_server_asked_for_fairness_runs_its_pool_nicer():
    before = set(step_threads())
    expected = max(10, os.getpriority(os.PRIO_PROCESS, 0))
    with gymfleet.Server(threads=2, pool_niceness=10) as server:
        envs = gymfleet.make_vec(model("arm2"), 4, server=server.address)
        envs.reset(seed=0)
        new = settled(
            lambda: {t: n for t, n in step_threads().items() if t not in before}, expected, 2
        )
        envs.close()
    assert len(new) == 2, new
    assert set(new.values()) == {expected}, new


def test_pool_niceness_out_of_range_is_refused():
    with pytest.raises(ValueError, match=r"pool_niceness: expected a niceness 0\.\.=19 "
                       r"\(0: this process's own priority\), got 20"):
        gymfleet.Server(pool_niceness=20)


@pytest.mark.parametrize("flag, expected", [([], 0), (["--pool-niceness", "10"], 10)])
def test_the_binary_runs_its_pool_at_the_niceness_it_is_given(flag, expected):
    binary = pathlib.Path(
        os.environ.get("GYMFLEET_SERVER_BIN", REPO / "target" / "debug" / "gymfleet-server")
    )
    addr = f"127.0.0.1:{_free_port()}"
    env = {k: v for k, v in os.environ.items() if not k.startswith("GYMFLEET_")}
    proc = subprocess.Popen([str(binary), "--listen", addr, "--threads", "2", *flag],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    try:
        deadline = time.monotonic() + 30
        while True:
            try:
                gymfleet.server_info(addr)
                break
            except gymfleet.Unavailable:
                assert proc.poll() is None and time.monotonic() < deadline, "no server"
                time.sleep(0.05)
        expected = max(expected, os.getpriority(os.PRIO_PROCESS, 0))
        threads = settled(lambda: step_threads(proc.pid), expected, 2)
        assert len(threads) == 2, threads
        assert set(threads.values()) == {expected}, threads
    finally:
        proc.terminate()
        proc.wait(timeout=30)

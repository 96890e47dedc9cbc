"""The GIL is released while a call is on the network: another Python thread runs."""

from __future__ import annotations

import threading
import time

import numpy as np

import gymfleet
from conftest import model


def test_a_python_thread_keeps_running_during_a_long_step():
    with gymfleet.Server(threads=1) as server:
        envs = gymfleet.make_vec(model("chain20"), 512, server=server.address)
        envs.reset(seed=0)
        actions = np.zeros((512, 20), dtype=np.float32)
        start = time.perf_counter()
        envs.step(actions)
        one_step = time.perf_counter() - start

        ticks = 0
        stop = threading.Event()

        def count():
            nonlocal ticks
            while not stop.is_set():
                ticks += 1

        counter = threading.Thread(target=count)
        counter.start()
        try:
            before = ticks
            steps = max(1, int(0.2 / one_step))
            for _ in range(steps):
                envs.step(actions)
            during = ticks - before
        finally:
            stop.set()
            counter.join()
        envs.close()
    # Holding the GIL for the whole call would leave the counter ~idle (only the
    # interpreter's 5 ms switch interval between calls).
    assert during > 10_000, f"only {during} ticks in {steps} steps of {one_step * 1e3:.0f} ms"

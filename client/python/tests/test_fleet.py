"""A batch sharded over two servers, one of which is stopped mid-run."""

from __future__ import annotations

import numpy as np
import pytest

import gymfleet


def test_a_server_lost_mid_run_raises_server_lost_naming_it_and_its_envs(arm2):
    a = gymfleet.Server(threads=1)
    b = gymfleet.Server(threads=1)
    try:
        envs = gymfleet.make_vec(arm2, 8, server=f"{a.address},{b.address}")
        envs.reset(seed=0)
        for _ in range(5):
            envs.step(np.zeros((8, 2)))
        b.stop()
        with pytest.raises(gymfleet.ServerLost) as caught:
            envs.step(np.zeros((8, 2)))
        lost = caught.value
        assert lost.server == b.address
        assert lost.envs == [(4, 8)]
        assert f"server {b.address} failed" in str(lost) and "lost envs 4..8" in str(lost)
        assert isinstance(lost, gymfleet.Unavailable)
        envs.close()  # frees the survivor's shard; the lost one has nothing to free
        assert gymfleet.server_info(a.address)["batches"] == 0
    finally:
        a.stop()
        b.stop()


def test_stateful_set_addresses():
    assert gymfleet.FleetEndpoints.stateful_set("sim", "sim-headless", "rl", 2) == (
        "sim-0.sim-headless.rl.svc.cluster.local:50051,"
        "sim-1.sim-headless.rl.svc.cluster.local:50051"
    )
    with pytest.raises(gymfleet.InvalidArgument, match="statefulset"):
        gymfleet.FleetEndpoints.stateful_set("Not_A_Label", "svc")

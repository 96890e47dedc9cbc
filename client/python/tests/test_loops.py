"""Closed kinematic chains against MuJoCo: a four-bar linkage written as MuJoCo writes it
(a tree plus an `<equality><connect>`) swings under gravity like MuJoCo's, and the shipped
four-bar of `models/` steps through the Python client like any robot."""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

import gymfleet

mujoco = pytest.importorskip("mujoco")

#: Crank 40 mm, coupler 120, rocker 100, ground 110 (a crank-rocker), passive, released from
#: a crank angle of 60°; the loop closed at the coupler's far end. The links do not collide
#: (in MuJoCo the coupler's and the rocker's capsules would push apart at the pin).
FOUR_BAR = """<mujoco>
  <option timestep="0.001"/>
  <worldbody>
    <body name="crank">
      <joint name="crank" type="hinge" axis="0 -1 0"/>
      <geom type="capsule" fromto="0 0 0 0.02 0 0.034641" size="0.004" contype="0" conaffinity="0"/>
      <body name="coupler" pos="0.02 0 0.034641">
        <joint name="elbow" type="hinge" axis="0 -1 0"/>
        <geom type="capsule" fromto="0 0 0 0.1010328 0 0.0647485" size="0.004" contype="0" conaffinity="0"/>
      </body>
    </body>
    <body name="rocker" pos="0.11 0 0">
      <joint name="rocker" type="hinge" axis="0 -1 0"/>
      <geom type="capsule" fromto="0 0 0 0.0110328 0 0.0993895" size="0.004" contype="0" conaffinity="0"/>
    </body>
  </worldbody>
  <equality>
    <connect name="pin" body1="coupler" body2="rocker" anchor="0.1010328 0 0.0647485"/>
  </equality>
</mujoco>"""


def test_a_connect_closed_four_bar_swings_like_mujocos():
    """The same Euler step on both sides (MuJoCo's 1 ms, one substep here): within 0.03 rad
    of MuJoCo's joint angles over the first 0.5 s, while the crank swings through more than a
    radian. (Later the passive linkage passes near its dead points, where the two solvers'
    constraint errors, MuJoCo's soft and ours hard, part the trajectories.)"""
    env = gymfleet.make(FOUR_BAR, units="si", dt=0.001, substeps=1)
    obs, _ = env.reset(seed=0)
    assert env.observation_space.shape[0] == 6, "crank, elbow, rocker: positions and velocities"
    model = mujoco.MjModel.from_xml_string(FOUR_BAR)
    data = mujoco.MjData(model)
    worst = 0.0
    swing = 0.0
    for _ in range(500):
        obs, *_ = env.step(np.zeros(env.action_space.shape, np.float32))
        mujoco.mj_step(model, data)
        worst = max(worst, float(np.abs(obs[:3] - data.qpos).max()))
        swing = max(swing, abs(float(data.qpos[0])))
    assert swing > 1.0, f"MuJoCo's crank swings {swing} rad"
    assert worst < 0.03, f"joint angles {worst} rad from MuJoCo's"
    # Without the connect the same bodies fall apart: the test can tell.
    free = gymfleet.make(FOUR_BAR.replace('<connect name="pin"', '<connect active="false" name="pin"'),
                         units="si", dt=0.001, substeps=1)
    free.reset(seed=0)
    for _ in range(500):
        free_obs, *_ = free.step(np.zeros(free.action_space.shape, np.float32))
    assert np.abs(free_obs[:3] - data.qpos).max() > 0.3


def test_the_shipped_four_bar_steps_through_the_client():
    path = pathlib.Path(__file__).resolve().parents[3] / "models" / "fourbar.json"
    env = gymfleet.make(path.read_text(), end_effector_ids=["coupler"])
    env.reset(seed=0)
    assert env.action_space.shape == (1,), "only the crank is driven"
    for _ in range(120):
        obs, *_ = env.step(np.array([1.0], np.float32))
    # Four observed joints (the loop's closing pin too), positions first (deg).
    assert np.all(np.isfinite(obs))
    assert abs(obs[0]) > 1.0, "the crank turns"
    assert abs(obs[2]) > 0.1, "the rocker follows"

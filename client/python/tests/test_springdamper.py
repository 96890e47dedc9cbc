"""A joint's `springdamper` (MuJoCo's spring-damper by time constant and damping ratio,
sized by the DOF's inertia at the model's pose): a hinge in a chain, released away from its
rest, follows MuJoCo's trajectory; the same `stiffness` and `damping` MuJoCo computes, given
outright, follow it too (the test can tell a wrong size)."""

from __future__ import annotations

import numpy as np
import pytest

import gymfleet

mujoco = pytest.importorskip("mujoco")


def chain(joint_b: str) -> str:
    """Two links on hinges about y, no gravity; hinge `b` (the elbow) carries `joint_b`."""
    return f"""<mujoco>
  <option timestep="0.001" gravity="0 0 0"/>
  <worldbody>
    <body name="upper">
      <joint name="a" type="hinge" axis="0 1 0" armature="0.01"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
      <body name="lower" pos="0.3 0 0">
        <joint name="b" type="hinge" axis="0 1 0" {joint_b}/>
        <geom type="capsule" fromto="0 0 0 0.25 0 0" size="0.025"/>
      </body>
    </body>
  </worldbody>
</mujoco>"""


def trajectory(xml: str, steps: int = 600) -> tuple:
    env = gymfleet.make(xml, units="si", dt=0.001)
    env.reset(seed=0)
    env.set_joint_state(np.array([0.0, 0.4]), np.zeros(2))
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    data.qpos[:] = [0.0, 0.4]
    ours, theirs = [], []
    for _ in range(steps):
        obs, *_ = env.step(np.zeros(env.action_space.shape, np.float32))
        mujoco.mj_step(model, data)
        ours.append(obs[:2].copy())
        theirs.append(data.qpos.copy())
    env.close()
    return np.array(ours), np.array(theirs), model


def test_a_springdamper_joint_follows_mujocos_trajectory():
    ours, theirs, model = trajectory(chain('springdamper="0.05 0.3"'))
    swing = np.abs(theirs[:, 1]).max()
    assert swing > 0.3, "the elbow swings"
    assert np.abs(ours - theirs).max() < 0.02 * swing
    # MuJoCo's sized stiffness and damping, given outright, move the chain the same way.
    k, b = model.jnt_stiffness[1], model.dof_damping[1]
    given, _, _ = trajectory(chain(f'stiffness="{k}" damping="{b}"'))
    assert np.abs(given - theirs).max() < 0.02 * swing
    # Half the stiffness moves it differently: the check can tell.
    wrong, _, _ = trajectory(chain(f'stiffness="{k / 2}" damping="{b}"'))
    assert np.abs(wrong - theirs).max() > 0.1 * swing

"""MJCF actuators against MuJoCo itself (issue Z1b): every actuator type's force equals
MuJoCo's ``actuator_force`` on the same state and ctrl, activations follow MuJoCo's over
100 steps of the same controls, actions are MuJoCo's ctrl in ``<actuator>`` order, and an
activation is part of a saved state.

Tolerances: the physics is f32, so positions and velocities carry about 1e-7 relative;
forces are compared at rtol 1e-4, atol 1e-5 (N or N·m), activations at rtol 1e-5,
atol 1e-6."""

from __future__ import annotations

import numpy as np
import pytest

import gymfleet

mujoco = pytest.importorskip("mujoco")

#: Nine links hanging from the world, one hinge or slide each, and a fixed tendon over
#: two of them; one actuator of each kind, in an order that is not the joints'. Explicit
#: inertials make MuJoCo's masses and ours the same numbers; nothing collides.
XML = """<mujoco>
  <option timestep="0.002"/>
  <default>
    <geom contype="0" conaffinity="0" type="capsule" size="0.02" fromto="0 0 0 0.2 0 0"/>
    <position kp="4"/>
  </default>
  <worldbody>
    <body name="b1" pos="0 0 1"><joint name="j1" axis="0 1 0"/><geom/>
      <inertial pos="0.1 0 0" mass="0.5" diaginertia="0.001 0.004 0.004"/></body>
    <body name="b2" pos="0 0.5 1"><joint name="j2" axis="0 1 0" armature="0.01"/><geom/>
      <inertial pos="0.1 0 0" mass="0.7" diaginertia="0.001 0.005 0.005"/></body>
    <body name="b3" pos="0 1 1"><joint name="j3" axis="0 1 0"/><geom/>
      <inertial pos="0.1 0 0" mass="0.3" diaginertia="0.001 0.002 0.002"/></body>
    <body name="b4" pos="0 1.5 1"><joint name="j4" axis="0 1 0"/><geom/>
      <inertial pos="0.1 0 0" mass="0.4" diaginertia="0.001 0.003 0.003"/></body>
    <body name="b5" pos="0 2 1"><joint name="j5" axis="0 1 0"/><geom/>
      <inertial pos="0.1 0 0" mass="0.6" diaginertia="0.001 0.004 0.004"/></body>
    <body name="b6" pos="0 2.5 1"><joint name="j6" type="slide" axis="1 0 0"/><geom/>
      <inertial pos="0.1 0 0" mass="0.8" diaginertia="0.001 0.004 0.004"/></body>
    <body name="b7" pos="0 3 1"><joint name="j7" axis="0 1 0"/><geom/>
      <inertial pos="0.1 0 0" mass="0.5" diaginertia="0.001 0.004 0.004"/></body>
    <body name="b8" pos="0 3.5 1"><joint name="j8" axis="0 1 0"/><geom/>
      <inertial pos="0.1 0 0" mass="0.5" diaginertia="0.001 0.004 0.004"/></body>
    <body name="b9" pos="0 4 1"><joint name="j9" axis="0 1 0"/><geom/>
      <inertial pos="0.1 0 0" mass="0.5" diaginertia="0.001 0.004 0.004"/></body>
  </worldbody>
  <tendon>
    <fixed name="t"><joint joint="j7" coef="1"/><joint joint="j8" coef="-0.5"/></fixed>
  </tendon>
  <actuator>
    <motor name="motor" joint="j9" gear="3" ctrlrange="-1 1" forcerange="-2 2"/>
    <position name="position" joint="j1" kv="0.2" ctrlrange="-1 1"/>
    <position name="dampratio" joint="j2" kp="10" dampratio="1"/>
    <velocity name="velocity" joint="j3" kv="0.5"/>
    <intvelocity name="intvelocity" joint="j4" kp="3" actrange="-0.3 0.3"/>
    <damper name="damper" joint="j5" kv="0.3" ctrlrange="0 1"/>
    <cylinder name="cylinder" joint="j6" timeconst="0.05" area="0.01" bias="0.5 -1 -0.2"/>
    <general name="general" tendon="t" gear="2" gaintype="affine" gainprm="1 0.1 -0.2"
             biastype="affine" biasprm="0 -1 -0.1" dyntype="filter" dynprm="0.1"/>
    <general name="filterexact" jointinparent="j8" dyntype="filterexact" dynprm="0.05"
             ctrlrange="-2 2"/>
  </actuator>
</mujoco>"""

NAMES = [
    "motor", "position", "dampratio", "velocity", "intvelocity", "damper", "cylinder",
    "general", "filterexact",
]

TASK = {
    "terms": [{"name": f"force_{n}", "weight": 0, "value": {"actuator": n}} for n in NAMES]
    + [{"name": f"act_{n}", "weight": 0, "value": {"actuator_activation": n}} for n in NAMES]
}


def _env():
    return gymfleet.make(XML, units="si", task=TASK, dt=0.002, substeps=1)


def _controls(rng: np.random.Generator) -> np.ndarray:
    # Beyond the ctrl ranges now and then: the clamps are part of what is compared.
    return rng.uniform(-1.5, 1.5, size=len(NAMES)).astype(np.float32)


def test_actions_are_the_actuators_controls_in_actuator_order():
    env = _env()
    assert [a["name"] for a in env.env_info["actuators"]] == NAMES
    assert [a["target"] for a in env.env_info["actuators"]][:3] == ["j9", "j1", "j2"]
    assert env.action_space.shape == (len(NAMES),)
    assert env.action_space.low[0] == -1 and env.action_space.high[0] == 1  # ctrlrange
    assert np.isinf(env.action_space.high[3])  # no ctrlrange: unbounded
    # The joints take no action of their own.
    assert not any(j["actuated"] for j in env.env_info["joints"])
    env.close()


def test_every_actuators_force_is_mujocos_on_the_same_state_and_ctrl():
    """After every step, MuJoCo is put in gymfleet's state (qpos, qvel, act) with the same
    ctrl; its ``actuator_force`` must be gymfleet's."""
    env = _env()
    env.reset(seed=0)
    model = mujoco.MjModel.from_xml_string(XML)
    data = mujoco.MjData(model)
    assert [model.actuator(k).name for k in range(model.nu)] == NAMES
    rng = np.random.default_rng(1)
    largest = np.zeros(len(NAMES))
    for step in range(200):
        ctrl = _controls(rng)
        obs, _, _, _, info = env.step(ctrl)
        n = model.nv
        data.qpos[:] = obs[:n]
        data.qvel[:] = obs[n : 2 * n]
        data.act[:] = [info[f"act_{a}"] for a in NAMES if model.actuator_actnum[NAMES.index(a)]]
        data.ctrl[:] = ctrl
        mujoco.mj_forward(model, data)
        ours = np.array([info[f"force_{a}"] for a in NAMES])
        np.testing.assert_allclose(ours, data.actuator_force, rtol=1e-4, atol=1e-5, err_msg=f"step {step}")
        largest = np.maximum(largest, np.abs(data.actuator_force))
    # Every actuator was exercised: each force went well past the tolerance.
    assert np.all(largest > 1e-2), dict(zip(NAMES, largest))
    env.close()


def test_activations_follow_mujocos_over_100_steps_of_the_same_ctrl():
    env = _env()
    env.reset(seed=0)
    model = mujoco.MjModel.from_xml_string(XML)
    data = mujoco.MjData(model)
    stateful = [a for k, a in enumerate(NAMES) if model.actuator_actnum[k]]
    assert stateful == ["intvelocity", "cylinder", "general", "filterexact"]
    rng = np.random.default_rng(2)
    moved = 0.0
    for step in range(100):
        ctrl = _controls(rng)
        _, _, _, _, info = env.step(ctrl)
        data.ctrl[:] = ctrl
        mujoco.mj_step(model, data)
        ours = np.array([info[f"act_{a}"] for a in stateful])
        np.testing.assert_allclose(ours, data.act, rtol=1e-5, atol=1e-6, err_msg=f"step {step}")
        moved = max(moved, float(np.max(np.abs(data.act))))
    assert moved > 0.05  # the activations moved
    # The integrator's activation reached its actrange and stayed inside it.
    assert abs(info["act_intvelocity"]) <= 0.3
    env.close()


def test_an_activation_is_part_of_a_saved_state_and_of_a_reset():
    env = _env()
    env.reset(seed=0)
    ctrl = np.full(len(NAMES), 0.7, dtype=np.float32)
    for _ in range(20):
        env.step(ctrl)
    state = env.save_state()
    after = [env.step(ctrl)[4]["act_cylinder"] for _ in range(5)]
    env.load_state(state)
    again = [env.step(ctrl)[4]["act_cylinder"] for _ in range(5)]
    assert after == again and after[0] != 0.0
    _, info = env.reset(seed=0)
    obs, _, _, _, info = env.step(np.zeros(len(NAMES), np.float32))
    assert info["act_cylinder"] == 0.0  # a reset clears it, and ctrl 0 keeps it there
    env.close()


def test_normalized_actions_need_every_actuators_ctrl_range():
    with pytest.raises(gymfleet.InvalidArgument) as refused:
        gymfleet.make(XML, normalize_actions=True)
    assert str(refused.value) == (
        "normalize_actions: every DOF needs a finite torque range, but dampratio, velocity, "
        "intvelocity, cylinder, general has none (set max_effort, or an actuator's ctrl_range, "
        "in the document)"
    )

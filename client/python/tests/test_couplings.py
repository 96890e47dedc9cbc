"""Couplings (MJCF's `<equality><joint>` and `<equality><tendon>`) against MuJoCo and a
closed form: two pendulums hinged side by side, one held at a ratio of the other's angle,
swing as one body with the period the coupling gives them; the kitchen's oven knobs turn
their burners. gymfleet's couplings are hard; MuJoCo's are soft, made stiff here
(`solref` at twice the timestep)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import gymfleet

mujoco = pytest.importorskip("mujoco")

#: Pendulum lengths (m) and masses (kg), and the inertia of each bob about its centre.
L_A, L_B, M_A, M_B, I_BOB = 0.3, 0.5, 1.0, 0.4, 1e-4
G = 9.81
DT = 0.002


def two_pendulums(equality: str, tendons: str = "") -> str:
    def pendulum(name: str, x: float, length: float, mass: float) -> str:
        return f"""<body name="{name}" pos="{x} 0 1">
      <joint name="{name}" type="hinge" axis="0 1 0"/>
      <inertial pos="0 0 -{length}" mass="{mass}" diaginertia="{I_BOB} {I_BOB} {I_BOB}"/>
      <geom type="sphere" pos="0 0 -{length}" size="0.02" contype="0" conaffinity="0"/>
    </body>"""

    return f"""<mujoco>
  <option timestep="{DT}"/>
  <worldbody>
    {pendulum("a", 0.0, L_A, M_A)}
    {pendulum("b", 0.5, L_B, M_B)}
  </worldbody>
  <tendon>{tendons}</tendon>
  <equality>{equality}</equality>
</mujoco>"""


def closed_form_period(ratio: float) -> float:
    """a = ratio · b: the pair's small swings, from its energy in b."""
    inertia = (M_A * L_A**2 + I_BOB) * ratio**2 + M_B * L_B**2 + I_BOB
    stiffness = M_A * G * L_A * ratio**2 + M_B * G * L_B
    return 2 * math.pi * math.sqrt(inertia / stiffness)


def period(angles: np.ndarray) -> float:
    """From the first to the last upward zero crossing."""
    crossings = [
        (k + 1 + (-angles[k] / (angles[k + 1] - angles[k]))) * DT
        for k in range(len(angles) - 1)
        if angles[k] < 0.0 <= angles[k + 1]
    ]
    assert len(crossings) >= 3, crossings
    return (crossings[-1] - crossings[0]) / (len(crossings) - 1)


def swing(xml: str, ratio: float, seconds: float = 4.0):
    """b released from 0.05 rad, a from ratio × that, in gymfleet and in MuJoCo: each
    one's b angles and gymfleet's worst coupling residual."""
    env = gymfleet.make(xml, units="si", dt=DT)
    env.reset(seed=0)
    q0 = np.array([0.05 * ratio, 0.05])
    env.set_joint_state(q0, np.zeros(2))
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    data.qpos[:] = q0
    ours, theirs, residual = [], [], 0.0
    for _ in range(int(seconds / DT)):
        obs, *_ = env.step(np.zeros(env.action_space.shape, np.float32))
        mujoco.mj_step(model, data)
        ours.append(obs[1])
        theirs.append(data.qpos[1])
        residual = max(residual, abs(float(obs[0]) - ratio * float(obs[1])))
    return np.array(ours), np.array(theirs), residual


STIFF = 'solref="0.004 1"'


@pytest.mark.parametrize("ratio", [2.0, -0.5])
def test_a_joint_coupling_swings_the_pair_at_the_closed_forms_period(ratio):
    xml = two_pendulums(f'<joint joint1="a" joint2="b" polycoef="0 {ratio} 0 0 0" {STIFF}/>')
    ours, theirs, residual = swing(xml, ratio)
    expected = closed_form_period(ratio)
    assert period(ours) == pytest.approx(expected, rel=0.02)
    assert period(theirs) == pytest.approx(expected, rel=0.02)
    assert period(ours) == pytest.approx(period(theirs), rel=0.02)
    assert residual < 1e-5, f"the coupling slipped by {residual} rad"
    # Uncoupled, b swings at its own period: the test can tell.
    free, _, _ = swing(two_pendulums(""), 1.0)
    assert abs(period(free) / expected - 1) > 0.05


def test_a_tendon_coupling_holds_a_fixed_tendon_at_its_length_as_mujoco_does():
    # t = a − 0.5·b held at its qpos0 length (0): a = 0.5·b.
    tendons = '<fixed name="t"><joint joint="a" coef="1"/><joint joint="b" coef="-0.5"/></fixed>'
    xml = two_pendulums(f'<tendon tendon1="t" {STIFF}/>', tendons)
    ours, theirs, residual = swing(xml, 0.5)
    expected = closed_form_period(0.5)
    assert period(ours) == pytest.approx(expected, rel=0.02)
    assert period(ours) == pytest.approx(period(theirs), rel=0.02)
    assert residual < 1e-5


def test_two_tendons_coupled_by_a_ratio():
    tendons = (
        '<fixed name="ta"><joint joint="a" coef="1"/></fixed>'
        '<fixed name="tb"><joint joint="b" coef="1"/></fixed>'
    )
    xml = two_pendulums(f'<tendon tendon1="ta" tendon2="tb" polycoef="0 1.5" {STIFF}/>', tendons)
    ours, theirs, residual = swing(xml, 1.5)
    assert period(ours) == pytest.approx(closed_form_period(1.5), rel=0.02)
    assert period(ours) == pytest.approx(period(theirs), rel=0.02)
    assert residual < 1e-5

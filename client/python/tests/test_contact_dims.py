"""MuJoCo's `condim` (vendored Rapier patch 47) against MuJoCo itself, on the same file and
state: torsional friction (`condim` 4) slows a spinning top and rolling friction (`condim`
6) a rolling ball as MuJoCo's do, on both friction cones; `condim` 1 is frictionless, and
a pair takes the larger `condim` of its two geoms. gymfleet runs one substep per MuJoCo
timestep."""

from __future__ import annotations

import numpy as np
import pytest

import gymfleet

mujoco = pytest.importorskip("mujoco")

DT = 0.002


def ball(condim: int, cone: str, friction: str, qvel: str, floor_condim: int | None = None) -> str:
    """A 1 kg ball of 5 cm radius on a free joint, resting on a plane, started at `qvel`."""
    floor_condim = condim if floor_condim is None else floor_condim
    return f"""<mujoco><option timestep="{DT}" cone="{cone}"/>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 .1" condim="{floor_condim}" friction="{friction}"/>
    <body name="ball" pos="0 0 0.05"><freejoint/>
      <geom type="sphere" size="0.05" mass="1" condim="{condim}" friction="{friction}"/></body>
  </worldbody>
  <keyframe><key qpos="0 0 0.0499 1 0 0 0" qvel="{qvel}"/></keyframe>
</mujoco>"""


def velocities(xml: str, seconds: float):
    """The free body's velocity (linear, then angular, world) after each step, in gymfleet
    and in MuJoCo (a ball's frame is its centre's, so MuJoCo's `qvel` is the same)."""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    env = gymfleet.make(xml, units="si", dt=DT, substeps=1)
    obs, _ = env.reset(options={"keyframe": 0})
    at = 0
    for segment, size in env.env_info["observation_layout"]:
        if segment == "free_body_velocities":
            velocity = slice(at, at + 6)
        at += size
    ours, theirs = [], []
    for _ in range(int(round(seconds / DT))):
        obs, *_ = env.step(np.zeros(env.action_space.shape, np.float32))
        mujoco.mj_step(model, data)
        ours.append(np.array(obs[velocity], dtype=np.float64))
        theirs.append(data.qvel.copy())
    env.close()
    return np.array(ours), np.array(theirs)


def first_below(values: np.ndarray, level: float) -> float:
    below = np.nonzero(values < level)[0]
    assert below.size, f"never below {level}: ends at {values[-1]}"
    return (below[0] + 1) * DT


@pytest.mark.parametrize("cone", ["pyramidal", "elliptic"])
@pytest.mark.parametrize("condim", [4, 6])
def test_a_spinning_top_slows_at_mujocos_rate(condim, cone):
    """Spun at 20 rad/s about the vertical, the ball's contact has no lever arm: only
    torsional friction (`μ_t·N`, 0.005 m here, MuJoCo's default) slows it, at 49 rad/s²
    while it slips."""
    xml = ball(condim, cone, "1 0.005 0.0001", "0 0 0 0 0 20")
    ours, theirs = velocities(xml, 0.6)
    for level in (15.0, 10.0, 5.0):
        t_ours, t_theirs = first_below(ours[:, 5], level), first_below(theirs[:, 5], level)
        assert t_ours == pytest.approx(t_theirs, rel=0.1), (level, t_ours, t_theirs)
    # While it slips, MuJoCo's torque is the cone's bound, and so is ours.
    rate = (ours[0, 5] - ours[50, 5]) / (50 * DT)
    assert rate == pytest.approx(0.005 * 9.81 / (0.4 * 0.05**2), rel=0.05)


def test_without_torsional_friction_a_top_keeps_spinning():
    ours, theirs = velocities(ball(3, "pyramidal", "1 0.005 0.0001", "0 0 0 0 0 20"), 0.5)
    assert abs(theirs[-1, 5] - 20.0) < 1e-3
    assert abs(ours[-1, 5] - 20.0) < 0.02, ours[-1, 5]


@pytest.mark.parametrize("cone", ["pyramidal", "elliptic"])
def test_a_rolling_ball_slows_at_mujocos_rate(cone):
    """Rolling at 1 m/s without slipping, rolling friction (`condim` 6, 2 mm) slows it as
    MuJoCo's: at the cone's bound on the ellipse, and more gently, at the pyramid's soft
    facets, on the pyramid. At `condim` 4 it keeps rolling on both."""
    rolling = "1 0 0 0 20 0"
    ours, theirs = velocities(ball(6, cone, "1 0.005 0.002", rolling), 2.0)
    lost_ours, lost_theirs = 1.0 - ours[-1, 0], 1.0 - theirs[-1, 0]
    assert lost_theirs > 0.3
    assert lost_ours == pytest.approx(lost_theirs, rel=0.1)
    # The whole slowing, not only its end.
    np.testing.assert_allclose(ours[::100, 0], theirs[::100, 0], atol=0.03)
    ours, theirs = velocities(ball(4, cone, "1 0.005 0.002", rolling), 0.5)
    assert 1.0 - theirs[-1, 0] < 2e-3
    assert 1.0 - ours[-1, 0] < 2e-3


@pytest.mark.parametrize("floor_condim", [1, 3])
def test_condim_one_is_frictionless_unless_the_other_geom_says_more(floor_condim):
    """A ball sliding at 1 m/s without turning: frictionless when both geoms say
    `condim="1"`, so it slides on; with the floor's 3 (a pair takes the larger), friction
    turns its slide into rolling, as MuJoCo's."""
    xml = ball(1, "pyramidal", "1 0.005 0.0001", "1 0 0 0 0 0", floor_condim=floor_condim)
    ours, theirs = velocities(xml, 0.3)
    if floor_condim == 1:
        assert abs(theirs[-1, 0] - 1.0) < 1e-6
        assert abs(ours[-1, 0] - 1.0) < 1e-4, ours[-1]
        assert abs(ours[-1, 4]) < 1e-3, ours[-1]
    else:
        # Rolling without slipping keeps 5/7 of the speed.
        assert theirs[-1, 0] == pytest.approx(5 / 7, rel=0.01)
        assert ours[-1, 0] == pytest.approx(theirs[-1, 0], rel=0.01)

"""Humanoid and HumanoidStandup against MuJoCo: the body-level parts of the observation
(cinert, cvel, qfrc_actuator) equal MuJoCo's computed from the same state (our qpos and
qvel put into MuJoCo's data), the tendons' info too; the rest of the contract is in
test_suite.py."""

from __future__ import annotations

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")
mujoco = pytest.importorskip("mujoco")

import gymfleet  # noqa: E402,F401  (registers the ids)

#: Humanoid's observation: qpos[2:] (22), qvel (23), cinert[1:] (13 × 10), cvel[1:]
#: (13 × 6), qfrc_actuator[6:] (17), cfrc_ext[1:] (13 × 6).
QPOS, QVEL, BODIES = 22, 23, 13
CINERT = slice(QPOS + QVEL, QPOS + QVEL + 10 * BODIES)
CVEL = slice(CINERT.stop, CINERT.stop + 6 * BODIES)
QFRC = slice(CVEL.stop, CVEL.stop + 17)


@pytest.mark.parametrize("name", ["Humanoid", "HumanoidStandup"])
def test_body_quantities_are_mujocos_on_the_same_state(name):
    ours = gymnasium.make(f"gymfleet/{name}-v5")
    theirs = gymnasium.make(f"{name}-v5").unwrapped
    obs, info = ours.reset(seed=3)
    rng = np.random.default_rng(0)
    for step in range(30):
        action = rng.uniform(-0.4, 0.4, 17).astype(np.float32)
        obs, _, terminated, _, info = ours.step(action)
        if terminated:
            break
        # Our state into MuJoCo's data: x and y from the info, the rest observed.
        qpos = np.concatenate([[info["x_position"], info["y_position"]], obs[:QPOS]])
        qvel = obs[QPOS : QPOS + QVEL].astype(np.float64)
        theirs.data.qpos[:] = qpos
        theirs.data.qvel[:] = qvel
        theirs.data.ctrl[:] = action
        mujoco.mj_forward(theirs.model, theirs.data)
        cinert = theirs.data.cinert[1:].ravel()
        np.testing.assert_allclose(obs[CINERT], cinert, rtol=1e-3, atol=2e-4, err_msg=f"cinert, step {step}")
        cvel = theirs.data.cvel[1:].ravel()
        np.testing.assert_allclose(obs[CVEL], cvel, rtol=1e-3, atol=2e-3, err_msg=f"cvel, step {step}")
        qfrc = theirs.data.qfrc_actuator[6:]
        np.testing.assert_allclose(obs[QFRC], qfrc, rtol=1e-5, atol=1e-4, err_msg=f"qfrc_actuator, step {step}")
        np.testing.assert_allclose(info["tendon_length"], theirs.data.ten_length, atol=1e-5)
        np.testing.assert_allclose(info["tendon_velocity"], theirs.data.ten_velocity, atol=1e-4)
    assert step >= 5
    ours.close()


def mujoco_landing() -> list:
    """MuJoCo's Humanoid-v5 dropped on its feet: cfrc_ext's vertical forces summed, per step."""
    env = gymnasium.make("Humanoid-v5", reset_noise_scale=0.0)
    env.reset(seed=0)
    lifted = []
    for _ in range(25):
        env.step(np.zeros(17))
        lifted.append(float(env.unwrapped.data.cfrc_ext[1:, 5].sum()))
    env.close()
    return lifted


def test_the_humanoid_lands_on_its_feet_and_the_contact_cost_is_clipped():
    """Dropped on its feet, its contact forces (cfrc_ext's vertical forces summed) peak at
    touchdown as MuJoCo's compliant contacts do (within a factor of 2: MuJoCo's peak is 10
    times the weight, a rigid contact's was under 3) and then carry about its weight, and
    the contact cost is w · Σ cfrc_ext², clipped at 10 (a weight 2000 times the default's
    reaches the clip)."""
    model = gymnasium.make("Humanoid-v5").unwrapped.model
    weight = float(model.body_mass.sum()) * 9.81
    theirs = mujoco_landing()
    for w in (5e-7, 1e-3):
        env = gymnasium.make("gymfleet/Humanoid-v5", reset_noise_scale=0.0, contact_cost_weight=w)
        env.reset(seed=0)
        lifted, clipped = [], 0
        for _ in range(25):
            obs, _, _, _, info = env.step(np.zeros(17, np.float32))
            cfrc = obs[QFRC.stop :].reshape(BODIES, 6).astype(np.float64)
            lifted.append(cfrc[:, 5].sum())
            cost = w * float(np.square(cfrc).sum())
            clipped += cost > 10.0
            assert -info["reward_contact"] == pytest.approx(min(cost, 10.0), rel=1e-4, abs=1e-9)
        # Landed (about step 10): the impact's peak, then the ground carries about its weight.
        assert 0.5 < max(lifted) / max(theirs) < 2.0, (lifted, theirs)
        settled = np.mean(lifted[15:])
        assert 0.5 * weight < settled < 1.5 * weight, (lifted, weight)
        assert settled == pytest.approx(np.mean(theirs[15:]), rel=0.25), (lifted, theirs)
        assert (clipped > 0) == (w == 1e-3)
        env.close()

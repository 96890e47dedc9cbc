"""Gymnasium's own tests of its MuJoCo v5 envs (`test_mujoco_v5.py`, copied unchanged from
Gymnasium 1.4.0, commit 95a790e19, MIT licence: see `LICENSE`) run against gymfleet's ids.

This conftest only redirects: `gymnasium.make("<Name>-v5")` makes `gymfleet/<Name>-v5`, and
the module's `MujocoEnv` also accepts gymfleet's `SuiteEnv`. The tests that cannot apply to
another engine, or that need what gymfleet does not offer yet, are listed below with the
reason; every other test runs, and passes."""

from __future__ import annotations

import pytest

gymnasium = pytest.importorskip("gymnasium")
pytest.importorskip("mujoco")

import gymfleet  # noqa: E402  (registers the ids)
from gymfleet.suite import SUITE  # noqa: E402
from gymfleet.suite.envs import SuiteEnv  # noqa: E402

NAMES = {spec.name for spec in SUITE.values()}

#: Tests (by name, or name[parameters]) that cannot apply to gymfleet, and why.
NOT_APPLICABLE = {
    "v4": "a v4 id: gymfleet registers Gymnasium's v5 ids only (the v4 side runs MuJoCo's own env)",
    "test_identical_behaviour_v45": "compares MuJoCo's v4 and v5 envs with each other",
    "test_model_object_count": "MuJoCo compiler internals (nbvh, nmesh, ngeom, ...) of MuJoCo's model",
    "test_model_sensors": "MuJoCo's sensor arrays of its own compiled model",
    "test_ant_com": "calls mujoco.mj_kinematics on MuJoCo's own model and data",
    "test_z_distance_from_origin_info": "calls mujoco.mj_kinematics on MuJoCo's own model and data",
    "test_reset_state": "check_mujoco_reset_state calls mujoco.mj_stateSize/mj_getState on "
    "MuJoCo's own model and data",
    "test_inverted_double_pendulum_max_height": "asserts MuJoCo's float64 number (site_xpos z == "
    "1.2 exactly); gymfleet's physics is float32 (1.2000000476837158; test_state_access.py "
    "checks it to float32 rounding)",
    "test_dt": "changes MuJoCo's compiled model at run time (model.opt.timestep = 0.05); "
    "gymfleet's model is read-only (make the env with another frame_skip instead)",
    # Whether an episode ends within 80 steps of these actions is MuJoCo's trajectory: its Ant
    # leaves the healthy height range, gymfleet's (Rapier, hard limits) keeps standing.
    "test_verify_reward_survive[v5-Ant]": "needs MuJoCo's trajectory: its Ant falls within 80 "
    "steps of action seed 2, gymfleet's does not (another engine)",
}

#: Tests whose check gymfleet cannot meet yet, with the reason. Strict: one that starts
#: passing fails the run until it is taken off this list.
KNOWN_GAPS = {
    # Humanoid's info x_velocity is the server's centre-of-mass velocity term (one float32
    # computation in the step); the test recomputes it from data.xipos and model.body_mass
    # as Δ(Σ m·xipos)/dt and asks for bit equality (issue G, item 3: close, not equal).
    "test_verify_info_xy_velocity_com": "info x_velocity is the server's float32 centre-of-mass "
    "velocity; Δ(Σ m·xipos)/dt from data agrees to float32 rounding, not bit for bit",
}


def _redirect(make):
    def made(env_id, *args, **kwargs):
        if isinstance(env_id, str) and env_id.endswith("-v5") and env_id[:-3] in NAMES:
            env_id = f"gymfleet/{env_id}"
        return make(env_id, *args, **kwargs)

    return made


@pytest.fixture(autouse=True)
def gymfleet_ids(monkeypatch, request):
    monkeypatch.setattr(gymnasium, "make", _redirect(gymnasium.make))
    module = request.module
    if getattr(module, "MujocoEnv", None) is not None and not isinstance(module.MujocoEnv, tuple):
        monkeypatch.setattr(module, "MujocoEnv", (module.MujocoEnv, SuiteEnv))


def pytest_collection_modifyitems(config, items):
    for item in items:
        name = item.originalname or item.name
        params = item.callspec.params if hasattr(item, "callspec") else {}
        version = params.get("version", "")
        env_id = str(params.get("env_id", ""))
        if version == "v4" or env_id.endswith("-v4") or "v4" in str(params.get("env_conf", "")):
            item.add_marker(pytest.mark.skip(reason=NOT_APPLICABLE["v4"]))
        elif item.name in NOT_APPLICABLE or name in NOT_APPLICABLE:
            reason = NOT_APPLICABLE.get(item.name) or NOT_APPLICABLE[name]
            item.add_marker(pytest.mark.skip(reason=reason))
        elif name in KNOWN_GAPS:
            item.add_marker(pytest.mark.xfail(reason=KNOWN_GAPS[name], strict=True))

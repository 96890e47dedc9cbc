"""An MJCF robot with meshes and includes from a package on PyPI: the Franka Panda of
gymnasium-robotics' kitchen (`franka_assets/`: `<include>`d assets and body chain, STL
collision meshes under `compiler meshdir`). It converts with its files sent as assets,
puts every body where MuJoCo puts it, weighs what MuJoCo weighs, steps and renders."""

from __future__ import annotations

import importlib.util
import os
import pathlib
import shutil

import numpy as np
import pytest

import gymfleet

mujoco = pytest.importorskip("mujoco")


def _franka_assets() -> pathlib.Path:
    # gymnasium-robotics is installed without its dependencies (CI: `pip install --no-deps`):
    # only its files are used, so it is found, not imported.
    spec = importlib.util.find_spec("gymnasium_robotics")
    if spec is None or spec.origin is None:
        if os.environ.get("CI"):
            pytest.fail("CI installs gymnasium-robotics (.ci/run); it is missing")
        pytest.skip("gymnasium-robotics is not installed")
    return pathlib.Path(spec.origin).parent / "envs" / "assets" / "kitchen_franka" / "franka_assets"


#: The arm on a floor, three of its joints driven by motors (the package's own actuators
#: are MuJoCo `<position>` servos, which gymfleet's MJCF import does not take).
PANDA = """<mujoco model="panda">
  <include file="franka_assets/assets.xml"/>
  <worldbody>
    <geom name="floor" type="plane" size="2 2 0.1"/>
    <include file="franka_assets/chain.xml"/>
  </worldbody>
  <actuator>
    <motor joint="robot:panda0_joint1" gear="50" ctrlrange="-1 1"/>
    <motor joint="robot:panda0_joint2" gear="50" ctrlrange="-1 1"/>
    <motor joint="robot:panda0_joint4" gear="50" ctrlrange="-1 1"/>
  </actuator>
</mujoco>
"""


@pytest.fixture(scope="module")
def panda(tmp_path_factory) -> pathlib.Path:
    folder = tmp_path_factory.mktemp("panda")
    shutil.copytree(_franka_assets(), folder / "franka_assets")
    (folder / "panda.xml").write_text(PANDA)
    return folder


def _rotation(euler_deg) -> np.ndarray:
    """gymfleet's rotation: about fixed X, then Y, then Z (R = Rz·Ry·Rx), degrees."""
    x, y, z = np.radians([euler_deg["x"], euler_deg["y"], euler_deg["z"]])
    rx = np.array([[1, 0, 0], [0, np.cos(x), -np.sin(x)], [0, np.sin(x), np.cos(x)]])
    ry = np.array([[np.cos(y), 0, np.sin(y)], [0, 1, 0], [-np.sin(y), 0, np.cos(y)]])
    rz = np.array([[np.cos(z), -np.sin(z), 0], [np.sin(z), np.cos(z), 0], [0, 0, 1]])
    return rz @ ry @ rx


def test_the_pandas_meshes_and_bodies_are_where_mujoco_puts_them(panda):
    document, warnings = gymfleet.convert(str(panda / "panda.xml"), assets=str(panda))
    meshes = [p for p in document["parts"] if p["primitive"]["type"] == "mesh"]
    # Nine collision meshes (links 0-7 and the hand); the visual copies are dropped.
    assert len(meshes) == 9, [p["name"] for p in meshes]
    assert all(len(p["primitive"]["vertices"]) >= 4 for p in meshes)
    assert any("massless geom that collides with nothing: dropped" in w for w in warnings)

    model = mujoco.MjModel.from_xml_path(str(panda / "panda.xml"))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)  # qpos0: the document's zero pose
    instances = {i["name"]: i for i in document["assembly"]["instances"]}
    given = sum(i["inertial"]["mass"] for i in instances.values() if "inertial" in i)
    assert given == pytest.approx(model.body_mass.sum(), abs=1e-4)  # 1 mg helpers aside
    checked = 0
    for site in document["assembly"]["sites"]:
        body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, site["name"])
        if body < 0:
            continue
        instance = instances[site["instance"]]
        position = np.array([instance["position"][k] for k in "xyz"])
        point = np.array([site["point"][k] for k in "xyz"])
        world = (position + _rotation(instance["rotation"]) @ point) / 1000.0
        np.testing.assert_allclose(world, data.xpos[body], atol=1e-6, err_msg=site["name"])
        checked += 1
    assert checked == model.nbody - 1  # every body but the world


def test_the_panda_steps_and_renders(panda):
    env = gymfleet.make(str(panda / "panda.xml"), assets=str(panda), render_mode="rgb_array")
    obs, _ = env.reset(seed=0)
    first = env.render()
    rng = np.random.default_rng(0)
    for _ in range(100):
        obs, _, terminated, _, _ = env.step(rng.uniform(-1, 1, 3).astype(np.float32))
        assert not terminated
    assert np.isfinite(obs).all()
    later = env.render()
    assert first.shape == (240, 320, 3)
    assert (first != later).any(), "the arm moved in the picture"
    env.close()

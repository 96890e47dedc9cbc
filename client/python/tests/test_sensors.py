"""Sensors (issue Z2): the MuJoCo corpus's ``<sensor>``s become the document's sensors, and
gymfleet's readings (``env.bodies()["sensordata"]``) are MuJoCo's ``sensordata`` on the same
state: the same qpos, qvel and ctrl put into MuJoCo's data, then ``mj_forward``.

What depends on each solver's contacts, limits and constraint forces (touch, force, torque,
accelerometer, framelinacc, frameangacc) is checked against closed forms in
``crates/env/tests/sensors.rs`` instead."""

from __future__ import annotations

import numpy as np
import pytest

import gymfleet

mujoco = pytest.importorskip("mujoco")

from test_mjcf_corpus import FILES, LOADS, MASS_DIFFERS, made, named_bodies, same_state, segments  # noqa: E402

#: Sensor types gymfleet converts, by MuJoCo's enum name.
CONVERTED = {
    "JOINTPOS", "JOINTVEL", "ACTUATORFRC", "TENDONPOS", "TENDONVEL", "FRAMEPOS", "FRAMEQUAT",
    "FRAMEXAXIS", "FRAMEYAXIS", "FRAMEZAXIS", "FRAMELINVEL", "FRAMEANGVEL", "FRAMELINACC",
    "FRAMEANGACC", "SUBTREECOM", "SUBTREELINVEL", "SUBTREEANGMOM", "GYRO", "ACCELEROMETER",
    "VELOCIMETER", "MAGNETOMETER", "TOUCH", "FORCE", "TORQUE", "RANGEFINDER",
}
#: Sensors read from the state alone: compared with MuJoCo's on the same state.
STATE_ONLY = CONVERTED - {"TOUCH", "FORCE", "TORQUE", "ACCELEROMETER", "FRAMELINACC", "FRAMEANGACC"}

WITH_SENSORS = [name for name in LOADS if mujoco.MjModel.from_xml_path(str(FILES[name][0])).nsensor]


def type_name(model, k: int) -> str:
    return mujoco.mjtSensor(model.sensor_type[k]).name.removeprefix("mjSENS_")


def mujoco_name(model, k: int) -> str:
    return model.sensor(k).name or f"sensor{k}"


def test_the_corpus_has_sensors_to_convert():
    assert len(WITH_SENSORS) == 23, WITH_SENSORS


@pytest.mark.parametrize("name", WITH_SENSORS)
def test_a_files_sensors_convert_in_order_with_their_sizes(name):
    """Every sensor of a type gymfleet has becomes a sensor of the document, in MuJoCo's
    order, with MuJoCo's name (``sensor<index>`` when unnamed), type and size."""
    path, _ = FILES[name]
    model = mujoco.MjModel.from_xml_path(str(path))
    env = made(name)
    bodies = env.bodies()
    want = [(mujoco_name(model, k), type_name(model, k).lower(), int(model.sensor_dim[k]))
            for k in range(model.nsensor) if type_name(model, k) in CONVERTED
            and not (model.sensor_objtype[k] == mujoco.mjtObj.mjOBJ_BODY and type_name(model, k).startswith("FRAME"))]
    got = list(zip(bodies["sensors"], bodies["sensor_types"], [int(d) for d in bodies["sensor_dims"]]))
    assert got == want
    assert len(bodies["sensordata"]) == sum(d for *_, d in want)
    env.close()


def put_state(model, data, env, obs, positions, velocities, bodies) -> None:
    """MuJoCo's data in gymfleet's state: qpos as ``same_state`` puts it; qvel from the
    joints' velocities and the free bodies' observed velocities (a floating base at rest)."""
    same_state(model, data, env, obs, bodies)
    data.qvel[:] = 0
    k = 0
    for joint in env.env_info["joints"]:
        j = model.joint(joint["name"])
        if joint["type"] in ("revolute", "prismatic"):
            data.qvel[j.dofadr[0]] = velocities[k]
        k += joint["dof"]
    at = segments(env)
    if "free_body_velocities" in at:
        for body, v in zip(env.env_info["free_bodies"], obs[at["free_body_velocities"]].reshape(-1, 6)):
            adr = model.body(body).dofadr[0]
            data.qvel[adr:adr + 6] = v


@pytest.mark.parametrize("name", WITH_SENSORS)
def test_state_sensors_read_mujocos_sensordata_on_the_same_state(name):
    """After 20 random-control steps, joint velocities drawn (normal, 0.5 rad/s or m/s) and
    set with ``set_joint_state`` (a floating base at rest): every sensor read from the state
    alone is MuJoCo's, within 2e-5 absolute plus 1e-4 relative (the physics is f32); a
    quaternion up to its sign."""
    path, _ = FILES[name]
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    bodies = named_bodies(model)
    env = made(name, end_effector_ids=[f"site:{b}" for b in bodies])
    env.action_space.seed(0)
    obs, _ = env.reset(seed=0)
    action = np.zeros(env.action_space.shape, dtype=np.float32)
    for _ in range(20):
        action = env.action_space.sample()
        obs, *_ = env.step(action)
    at = segments(env)
    positions = obs[at["joint_positions"]]
    velocities = np.random.default_rng(0).normal(0, 0.5, positions.shape)
    base = ()
    if "base_pose" in at:
        base = np.concatenate([obs[at["base_pose"]], np.zeros(6)])
    obs, _ = env.set_joint_state(positions, velocities, base)
    velocities = obs[at["joint_velocities"]]
    put_state(model, data, env, obs, obs[at["joint_positions"]], velocities, bodies)
    data.ctrl[:] = action[: model.nu] if len(action) >= model.nu else 0
    mujoco.mj_forward(model, data)
    reply = env.bodies()
    ours = np.asarray(reply["sensordata"])
    names = list(reply["sensors"])
    offsets = np.concatenate([[0], np.cumsum(reply["sensor_dims"])])
    compared = 0
    for k in range(model.nsensor):
        kind = type_name(model, k)
        if kind not in STATE_ONLY or mujoco_name(model, k) not in names:
            continue
        if name in MASS_DIFFERS and kind.startswith("SUBTREE"):
            continue  # A subtree's centre and momentum read its masses.
        if kind == "ACTUATORFRC" and model.actuator_dyntype[model.sensor_objid[k]] != 0:
            continue  # The activation's state is not put into MuJoCo's data.
        i = names.index(mujoco_name(model, k))
        got = ours[offsets[i]:offsets[i + 1]]
        adr, dim = model.sensor_adr[k], model.sensor_dim[k]
        want = data.sensordata[adr:adr + dim]
        if kind == "FRAMEQUAT" and got @ want < 0:
            got = -got
        np.testing.assert_allclose(got, want, rtol=1e-4, atol=2e-5,
                                   err_msg=f"{name}: {mujoco_name(model, k)} ({kind.lower()})")
        compared += 1
    env.close()
    if not any(type_name(model, k) in STATE_ONLY for k in range(model.nsensor)):
        pytest.skip(f"{name}: every sensor depends on contacts or accelerations")
    assert compared > 0


#: Every sensor type read from the state alone, on a model of the test's own (the corpus
#: has few of some): an arm of a hinge, a slide and a hinge, a fixed tendon, a motor and a
#: position actuator, a free box, reference frames, a magnetic field, and a rangefinder
#: looking at the floor.
ALL_STATE_SENSORS = """
<mujoco>
  <option magnetic="0.1 -0.3 0.2" timestep="0.004"/>
  <worldbody>
    <geom name="floor" type="plane" size="2 2 0.1"/>
    <site name="world_mark" pos="0.3 -0.2 0.1" euler="0 0 30"/>
    <body name="upper" pos="0 0 1">
      <joint name="shoulder" type="hinge" axis="0 1 0" damping="0.01"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
      <site name="elbow_site" pos="0.3 0 0" euler="20 10 0"/>
      <body name="slider" pos="0.3 0 0">
        <joint name="extend" type="slide" axis="1 0 0" range="-0.1 0.1"/>
        <geom type="box" size="0.05 0.03 0.03" pos="0.05 0 0"/>
        <body name="hand" pos="0.1 0 0" euler="0 0 15">
          <joint name="wrist" type="hinge" axis="0 0 1"/>
          <geom name="palm" type="box" size="0.04 0.02 0.01" pos="0.04 0 0"/>
          <site name="tip" pos="0.08 0 0" euler="180 0 0"/>
        </body>
      </body>
    </body>
    <body name="box" pos="0.8 0.4 0.3">
      <freejoint/>
      <geom type="box" size="0.05 0.04 0.03"/>
      <site name="box_site" pos="0.02 0 0.03" euler="0 30 0"/>
    </body>
  </worldbody>
  <tendon>
    <fixed name="coupled"><joint joint="shoulder" coef="0.5"/><joint joint="wrist" coef="-1"/></fixed>
  </tendon>
  <actuator>
    <motor name="lift" joint="shoulder" gear="2" ctrlrange="-1 1"/>
    <position name="reach" joint="extend" kp="50" ctrlrange="-0.1 0.1"/>
  </actuator>
  <sensor>
    <jointpos joint="wrist"/>
    <jointvel name="extend_rate" joint="extend"/>
    <actuatorfrc name="lift_force" actuator="lift"/>
    <actuatorfrc name="reach_force" actuator="reach"/>
    <tendonpos name="coupled_len" tendon="coupled"/>
    <tendonvel name="coupled_rate" tendon="coupled"/>
    <framepos name="tip_pos" objtype="site" objname="tip"/>
    <framepos name="tip_in_elbow" objtype="site" objname="tip" reftype="site" refname="elbow_site"/>
    <framequat name="tip_quat" objtype="site" objname="tip"/>
    <framequat name="hand_in_upper" objtype="xbody" objname="hand" reftype="xbody" refname="upper"/>
    <framexaxis name="tip_x" objtype="site" objname="tip"/>
    <frameyaxis name="palm_y" objtype="geom" objname="palm"/>
    <framezaxis name="box_z" objtype="site" objname="box_site" reftype="site" refname="world_mark"/>
    <framelinvel name="tip_vel" objtype="site" objname="tip"/>
    <framelinvel name="tip_vel_rel" objtype="site" objname="tip" reftype="site" refname="elbow_site"/>
    <frameangvel name="hand_w" objtype="xbody" objname="hand"/>
    <frameangvel name="box_w_rel" objtype="site" objname="box_site" reftype="xbody" refname="hand"/>
    <subtreecom name="arm_com" body="upper"/>
    <subtreelinvel name="arm_vel" body="upper"/>
    <subtreeangmom name="arm_angmom" body="upper"/>
    <subtreeangmom name="box_angmom" body="box"/>
    <gyro name="box_gyro" site="box_site"/>
    <velocimeter name="tip_velocimeter" site="tip"/>
    <magnetometer name="tip_field" site="tip"/>
    <rangefinder name="tip_range" site="tip"/>
    <rangefinder name="mark_range" site="world_mark"/>
    <framepos name="mark_pos" objtype="site" objname="world_mark" cutoff="0.25"/>
  </sensor>
</mujoco>
"""


def test_every_state_sensor_type_reads_mujocos_sensordata(tmp_path):
    """All 19 types read from the state alone, references and a cutoff included, on the
    model above: after 30 steps of swinging controls, gymfleet's readings are MuJoCo's on
    the same qpos, qvel and ctrl (atol 2e-5, rtol 1e-4)."""
    path = tmp_path / "sensors.xml"
    path.write_text(ALL_STATE_SENSORS)
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    env = gymfleet.make(path, units="si", end_effector_ids=[f"site:{b}" for b in named_bodies(model)])
    types = {type_name(model, k) for k in range(model.nsensor)}
    assert types == STATE_ONLY
    obs, _ = env.reset(seed=0)
    for k in range(30):
        action = np.array([np.sin(0.3 * k), 0.08 * np.cos(0.2 * k)], dtype=np.float32)
        obs, *_ = env.step(action)
    at = segments(env)
    put_state(model, data, env, obs, obs[at["joint_positions"]], obs[at["joint_velocities"]],
              named_bodies(model))
    data.ctrl[:] = action
    mujoco.mj_forward(model, data)
    reply = env.bodies()
    assert list(reply["sensors"]) == [mujoco_name(model, k) for k in range(model.nsensor)]
    ours = np.asarray(reply["sensordata"])
    for k in range(model.nsensor):
        adr, dim = model.sensor_adr[k], model.sensor_dim[k]
        got, want = ours[adr:adr + dim], data.sensordata[adr:adr + dim]
        if type_name(model, k) == "FRAMEQUAT" and got @ want < 0:
            got = -got
        np.testing.assert_allclose(got, want, rtol=1e-4, atol=2e-5,
                                   err_msg=f"{mujoco_name(model, k)} ({type_name(model, k).lower()})")
    # The cutoff bounds the world site's position as MuJoCo's does.
    mark = ours[model.sensor("mark_pos").adr[0]:][:3]
    np.testing.assert_allclose(mark, [0.25, -0.2, 0.1], atol=1e-6)
    env.close()


#: A floor, a beam welded to the world (a cantilever), a damped pendulum and a box resting
#: on the floor, with the sensors that read forces and accelerations.
AT_REST = """
<mujoco>
  <option timestep="0.002"/>
  <worldbody>
    <geom name="floor" type="plane" size="2 2 0.1"/>
    <body name="beam" pos="0 0 1">
      <geom type="box" size="0.1 0.01 0.01" pos="0.1 0 0" density="1000"/>
      <site name="root" pos="0 0 0"/>
    </body>
    <body name="bob" pos="1 0 1">
      <joint name="swing" type="hinge" axis="0 1 0" damping="0.05"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.02" density="1000"/>
      <site name="pivot" pos="0 0 0"/>
    </body>
    <body name="box" pos="-1 0 0.0295">
      <freejoint/>
      <geom type="box" size="0.05 0.04 0.03" density="1000"/>
      <site name="pad" pos="0 0 -0.03" type="box" size="0.06 0.05 0.01"/>
      <site name="imu" pos="0 0 0.03" euler="0 0 40"/>
    </body>
  </worldbody>
  <sensor>
    <force name="root_force" site="root"/>
    <torque name="root_torque" site="root"/>
    <force name="pivot_force" site="pivot"/>
    <accelerometer name="beam_acc" site="root"/>
    <accelerometer name="box_acc" site="imu"/>
    <touch name="pad_touch" site="pad"/>
  </sensor>
</mujoco>
"""


def test_force_torque_touch_and_accelerometers_at_rest_read_as_mujocos(tmp_path):
    """The sensors that read the solver's forces and the accelerations, on a scene at rest
    after 2 s in each simulator: the cantilever's root force and torque, a hanging
    pendulum's pivot force, a resting box's touch pad and accelerometer (MuJoCo's soft
    contacts and gymfleet's hard ones both carry the weight at rest), within 1% of each
    body's weight."""
    path = tmp_path / "at_rest.xml"
    path.write_text(AT_REST)
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    for _ in range(int(2.0 / model.opt.timestep)):
        mujoco.mj_step(model, data)
    env = gymfleet.make(path, units="si")
    env.reset(seed=0)
    for _ in range(int(round(2.0 / env.env_info["dt"]))):
        env.step(np.zeros(env.action_space.shape, dtype=np.float32))
    reply = env.bodies()
    assert list(reply["sensors"]) == [model.sensor(k).name for k in range(model.nsensor)]
    ours = np.asarray(reply["sensordata"])
    weights = {"beam": 0.0, "bob": 0.0, "box": 0.0}
    for b in weights:
        weights[b] = model.body(b).mass[0] * 9.81
    scale = {"root_force": weights["beam"], "root_torque": weights["beam"] * 0.1,
             "pivot_force": weights["bob"], "beam_acc": 9.81, "box_acc": 9.81,
             "pad_touch": weights["box"]}
    # MuJoCo before 4.0 reads 0 from an accelerometer on a body welded to the world (the
    # beam); 4.0 reads gravity's proper acceleration, as gymfleet does. CI installs the
    # MuJoCo that dm-control 1.0.50 runs on (3.17: its indexer predates 4.0's fields).
    mujoco_major = int(mujoco.__version__.split(".")[0])
    for k in range(model.nsensor):
        name = model.sensor(k).name
        adr, dim = model.sensor_adr[k], model.sensor_dim[k]
        want = data.sensordata[adr:adr + dim]
        if name == "beam_acc" and mujoco_major < 4:
            assert np.allclose(want, 0.0)
            want = np.array([0.0, 0.0, 9.81])
        np.testing.assert_allclose(ours[adr:adr + dim], want,
                                   atol=0.01 * scale[name], err_msg=name)
    assert data.sensordata[model.sensor("pad_touch").adr[0]] > 0.9 * weights["box"]
    env.close()

"""Heightfields (MJCF's `<hfield>`, the document's heightfield primitive; issue Z3): terrain
as MuJoCo reads it (rays down onto it meet it where MuJoCo's do, from inline elevations and
from a PNG), a ball rolls down a heightfield ramp as the closed form of the same plane ramp
has it, dm_control's quadruped stands on its file's flat heightfield and on rough terrain,
and a heightfield renders."""

from __future__ import annotations

import math
import pathlib
import re
import shutil
import struct
import zlib

import numpy as np
import pytest

import gymfleet

mujoco = pytest.importorskip("mujoco")

from test_mjcf_corpus import FILES, segments  # noqa: E402

ROWS, COLUMNS = 3, 5
HALF_X, HALF_Y, TOP = 1.0, 0.6, 0.4
#: Elevations as the `elevation` attribute (and an image) writes them: first row at +y.
LEVELS = np.array([[3, 1, 4, 1, 5], [9, 2, 6, 5, 3], [5, 8, 9, 7, 9]], float)


def png(levels: np.ndarray) -> bytes:
    """An 8-bit grayscale PNG of `levels` (0..255), first row on top."""
    height, width = levels.shape
    raw = b"".join(b"\x00" + bytes(int(v) for v in row) for row in levels)

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    header = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


def probed(hfield: str) -> str:
    """A heightfield geom (moved and turned) and, on a static probe body, one downward
    rangefinder beside each grid point and above two edge midpoints of its frame."""
    pos, turn = np.array([0.1, -0.2, 0.3]), math.radians(30)
    rotation = np.array([[math.cos(turn), -math.sin(turn), 0], [math.sin(turn), math.cos(turn), 0], [0, 0, 1]])
    # Beside each grid point along its row (a line both MuJoCo's and Parry's triangles
    # share; a ray exactly through a vertex may slip between triangles).
    local = [(-HALF_X + 2 * HALF_X * j / (COLUMNS - 1) + (0.01 if j < COLUMNS - 1 else -0.01),
              0.999 * (HALF_Y - 2 * HALF_Y * i / (ROWS - 1)))
             for i in range(ROWS) for j in range(COLUMNS)]
    local += [(0.25, 0.0), (-0.75, 0.3)]
    points = [pos[:2] + (rotation @ np.array([x, y, 0]))[:2] for x, y in local]
    sites = "\n".join(f'<site name="s{k}" pos="{x} {y} 2" euler="180 0 0"/>' for k, (x, y) in enumerate(points))
    sensors = "\n".join(f'<rangefinder site="s{k}"/>' for k in range(len(points)))
    return f"""<mujoco>
  <asset>{hfield}</asset>
  <worldbody>
    <geom name="terrain" type="hfield" hfield="h" pos="{pos[0]} {pos[1]} {pos[2]}" euler="0 0 30"/>
    <body name="probe">{sites}</body>
    <body name="ball" pos="0 0 3"><freejoint/><geom type="sphere" size="0.01"/></body>
  </worldbody>
  <sensor>{sensors}</sensor>
</mujoco>"""


def readings(env) -> np.ndarray:
    return np.array(env.bodies()["sensordata"])


def ranges(xml: str, assets=None) -> tuple:
    """Gymfleet's and MuJoCo's rangefinder readings after one step."""
    model = mujoco.MjModel.from_xml_string(xml) if assets is None else mujoco.MjModel.from_xml_path(str(xml))
    data = mujoco.MjData(model)
    mujoco.mj_step(model, data)
    env = gymfleet.make(xml, units="si") if assets is None else gymfleet.make(xml, assets=assets, units="si")
    env.reset(seed=0)
    env.step(np.zeros(env.action_space.shape, np.float32))
    ours = np.array(env.bodies()["sensordata"])
    env.close()
    return ours, data.sensordata.copy()


def test_a_heightfield_meets_rays_where_mujocos_does():
    size = f'size="{HALF_X} {HALF_Y} {TOP} 0.05"'
    elevation = " ".join(str(v) for v in LEVELS.ravel())
    ours, theirs = ranges(probed(f'<hfield name="h" nrow="{ROWS}" ncol="{COLUMNS}" {size} elevation="{elevation}"/>'))
    assert (theirs > 0).all(), "every ray meets the terrain"
    np.testing.assert_allclose(ours, theirs, atol=1e-5)
    # The rows the other way round meet it elsewhere: the test can tell.
    flipped = " ".join(str(v) for v in LEVELS[::-1].ravel())
    other, _ = ranges(probed(f'<hfield name="h" nrow="{ROWS}" ncol="{COLUMNS}" {size} elevation="{flipped}"/>'))
    assert np.abs(other - theirs).max() > 0.1


def test_a_png_heightfield_meets_rays_where_mujocos_does(tmp_path):
    (tmp_path / "terrain.png").write_bytes(png(LEVELS * 25))
    xml = tmp_path / "scene.xml"
    xml.write_text(probed(f'<hfield name="h" file="terrain.png" size="{HALF_X} {HALF_Y} {TOP} 0.05"/>'))
    ours, theirs = ranges(xml, assets=tmp_path)
    assert (theirs > 0).all()
    np.testing.assert_allclose(ours, theirs, atol=1e-5)


def test_a_ball_rolls_down_a_heightfield_ramp_as_down_the_plane_ramp():
    """A ramp rising 0.2 m over 2 m along x (21 columns): a solid ball rolls down it with
    a = 5/7·g·sin θ, within 2 % of the distance after 0.6 s."""
    radius, x0, dt, seconds = 0.05, 0.5, 0.002, 0.6
    slope = 0.2 / 2.0
    theta = math.atan(slope)
    elevation = " ".join(str(j) for _ in range(2) for j in range(21))
    z0 = slope * (x0 + 1.0) + radius / math.cos(theta)
    xml = f"""<mujoco>
  <option timestep="{dt}"/>
  <asset><hfield name="ramp" nrow="2" ncol="21" size="1 0.5 0.2 0.05" elevation="{elevation}"/></asset>
  <worldbody>
    <geom type="hfield" hfield="ramp"/>
    <body name="ball" pos="{x0} 0 {z0}"><freejoint/><geom type="sphere" size="{radius}"/></body>
  </worldbody>
</mujoco>"""
    env = gymfleet.make(xml, units="si", dt=dt)
    obs, _ = env.reset(seed=0)
    at = segments(env)["free_body_poses"]
    start = obs[at][:3].copy()
    for _ in range(int(seconds / dt)):
        obs, *_ = env.step(np.zeros(env.action_space.shape, np.float32))
    end = obs[at][:3]
    travelled = float(np.linalg.norm(end - start))
    expected = 0.5 * 5 / 7 * 9.81 * math.sin(theta) * seconds**2
    assert travelled == pytest.approx(expected, rel=0.02)
    # Down the slope, along −x, on the surface.
    direction = (end - start) / travelled
    np.testing.assert_allclose(direction, [-math.cos(theta), 0, -math.sin(theta)], atol=0.01)
    env.close()


def quadruped(tmp_path: pathlib.Path, terrain: str = None) -> pathlib.Path:
    """dm_control's quadruped without its floor plane: on its terrain heightfield alone
    (flat as the file has it, or with `terrain`'s `<hfield>` instead)."""
    path, assets = FILES["dmc/quadruped"]
    folder = tmp_path / "suite"
    shutil.copytree(assets, folder, ignore=shutil.ignore_patterns("*.py", "__pycache__"))
    text = re.sub(r'<geom name="floor"[^>]*/>', "", path.read_text())
    if terrain is not None:
        text = re.sub(r'<hfield name="terrain"[^>]*/>', terrain, text)
    copy = folder / path.name
    copy.write_text(text)
    return copy


def rough_terrain(rows: int = 201, bumps: int = 16, seed: int = 0) -> np.ndarray:
    """Smooth random bumps (dm_control's escape task's kind, without its bowl), in [0.2, 1]."""
    coarse = np.random.default_rng(seed).uniform(0.2, 1.0, (bumps, bumps))
    at = np.linspace(0, bumps - 1, rows)
    i = np.minimum(at.astype(int), bumps - 2)
    f = at - i
    rows_mixed = coarse[i] * (1 - f)[:, None] + coarse[i + 1] * f[:, None]
    return rows_mixed[:, i] * (1 - f)[None, :] + rows_mixed[:, i + 1] * f[None, :]


def stands(path: pathlib.Path) -> tuple:
    """The torso's height and tilt (rad) after 2 s of zero controls (the actuators hold
    the standing pose), and MuJoCo's torso height there."""
    env = gymfleet.make(path, assets=path.parent, units="si", end_effector_ids=["site:torso"])
    env.reset(seed=0)
    for _ in range(int(2.0 / env.env_info["dt"])):
        obs, _, terminated, _, _ = env.step(np.zeros(env.action_space.shape, np.float32))
        assert not terminated
    pose = obs[segments(env)["end_effector_poses"]]
    tilt = 2 * math.acos(min(1.0, abs(float(pose[3]))))
    env.close()
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    for _ in range(int(2.0 / model.opt.timestep)):
        mujoco.mj_step(model, data)
    return float(pose[2]), tilt, float(data.qpos[2])


def test_the_quadruped_stands_on_its_flat_heightfield(tmp_path):
    height, tilt, theirs = stands(quadruped(tmp_path))
    assert tilt < 0.05, f"the torso tilts {tilt} rad"
    assert height == pytest.approx(theirs, abs=0.02)


def test_the_quadruped_stands_on_rough_terrain(tmp_path):
    terrain = rough_terrain()
    elevation = " ".join(f"{v:.4f}" for v in terrain.ravel())
    hfield = f'<hfield name="terrain" nrow="201" ncol="201" size="30 30 0.3 .1" elevation="{elevation}"/>'
    height, tilt, _ = stands(quadruped(tmp_path, hfield))
    assert tilt < 0.1, f"the torso tilts {tilt} rad"
    # On its feet: the torso well above the terrain's highest point near it.
    assert height > 0.3 + 0.2


def test_a_heightfield_renders():
    bumps = " ".join(str(v) for v in LEVELS.ravel())
    scene = """<mujoco>
  <asset><hfield name="h" nrow="3" ncol="5" size="1 0.6 0.4 0.05" {elevation}/></asset>
  <worldbody>
    <geom type="hfield" hfield="h"/>
    <body name="ball" pos="0 0 1"><freejoint/><geom type="sphere" size="0.05"/></body>
  </worldbody>
</mujoco>"""
    pictures = []
    for elevation in (f'elevation="{bumps}"', ""):
        env = gymfleet.make(scene.format(elevation=elevation), units="si")
        env.reset(seed=0)
        pictures.append(env.picture(camera="front", width=96, height=64))
        env.close()
    bumpy, flat = pictures
    assert bumpy.shape == (64, 96, 3)
    changed = np.any(bumpy != flat, axis=2).sum()
    assert changed > 200, f"only {changed} pixels tell the bumpy terrain from the flat one"


def test_a_heightfield_is_replaced_at_run_time_and_keeps_through_resets_and_saved_states():
    """As dm_control's tasks write `hfield_data`: new heights (row 0 at −y) meet rays
    where MuJoCo's do with the same `hfield_data`, after a reset too, and in an env loaded
    from a saved state; a bad name, count or height changes nothing."""
    size = f'size="{HALF_X} {HALF_Y} {TOP} 0.05"'
    xml = probed(f'<hfield name="h" nrow="{ROWS}" ncol="{COLUMNS}" {size}/>')
    env = gymfleet.make(xml, units="si")
    assert env.env_info["heightfields"] == [("terrain", ROWS, COLUMNS)]
    env.reset(seed=0)
    zero = np.zeros(env.action_space.shape, np.float32)
    new = np.random.default_rng(1).uniform(0, 1, (ROWS, COLUMNS)).astype(np.float32)
    env.set_heightfield("terrain", new)
    env.step(zero)
    model = mujoco.MjModel.from_xml_string(xml)
    model.hfield_data[:] = new.ravel()
    data = mujoco.MjData(model)
    mujoco.mj_step(model, data)
    np.testing.assert_allclose(readings(env), data.sensordata, atol=1e-5)
    env.reset(seed=0)
    env.step(zero)
    np.testing.assert_allclose(readings(env), data.sensordata, atol=1e-5)
    # A fresh env of the same document has the file's flat terrain until it loads the state.
    state = env.save_state()
    other = gymfleet.make(xml, units="si")
    other.reset(seed=0)
    other.step(zero)
    assert np.abs(readings(other) - data.sensordata).max() > 0.05
    other.load_state(state)
    other.step(zero)
    np.testing.assert_allclose(readings(other), data.sensordata, atol=1e-5)
    for name, heights, message in [
        ("hill", new, 'unknown heightfield "hill" \\(known: "terrain"\\)'),
        ("terrain", new[:2], "heightfield \"terrain\": expected rows × columns = 3 × 5 = 15 heights, got 10"),
        ("terrain", new * 2, r"heightfield \"terrain\": heights\[\d+\] is [\d.]+; heights are in \[0, 1\]"),
    ]:
        with pytest.raises(gymfleet.InvalidArgument, match=message):
            env.set_heightfield(name, heights)
    env.step(zero)
    np.testing.assert_allclose(readings(env), data.sensordata, atol=1e-5)
    env.close()
    other.close()


def test_a_batch_replaces_a_heightfield_in_chosen_envs():
    size = f'size="{HALF_X} {HALF_Y} {TOP} 0.05"'
    xml = probed(f'<hfield name="h" nrow="{ROWS}" ncol="{COLUMNS}" {size}/>')
    envs = gymfleet.make_vec(xml, num_envs=3, units="si")
    envs.reset(seed=0)
    new = np.full((ROWS, COLUMNS), 0.5, np.float32)
    envs.set_heightfield("terrain", new, env_indices=[1])
    envs.step(np.zeros(envs.action_space.shape, np.float32))
    states = envs.save_states()
    tops = []
    for state in states:
        env = gymfleet.make(xml, units="si")
        env.reset(seed=0)
        env.load_state(state)
        env.step(np.zeros(env.action_space.shape, np.float32))
        tops.append(readings(env))
        env.close()
    # 2 m above the geom's plane at 0.3 m: flat terrain 1.7 m down, raised 0.2 m.
    np.testing.assert_allclose(tops[0], 1.7, atol=1e-4)
    np.testing.assert_allclose(tops[1], 1.5, atol=1e-4)
    np.testing.assert_allclose(tops[2], 1.7, atol=1e-4)
    envs.close()

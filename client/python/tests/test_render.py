"""`render_mode="rgb_array"`: gymnasium's checker renders, pictures are uint8 H x W x 3,
they change when the robot moves, and gymnasium's RecordVideo wrapper records them."""

from __future__ import annotations

import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import gymfleet
from conftest import MODELS


def test_rgb_array_passes_gymnasiums_checker_with_its_render_check():
    env = gymfleet.make(MODELS / "arm2.json", render_mode="rgb_array")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env, skip_render_check=False)
    assert not [w for w in caught if "render" in str(w.message).lower()], [str(w.message) for w in caught]
    env.close()


def test_frames_are_uint8_rgb_and_follow_the_robot():
    env = gymfleet.make(
        MODELS / "pendulum.json",
        render_mode="rgb_array",
        render_options={"camera": "front", "width": 160, "height": 120,
                        "eye": (10.0, -150.0, 25.0), "target": (10.0, 10.0, 25.0)},
    )
    env.reset(seed=0)
    first = env.render()
    assert first.dtype == np.uint8 and first.shape == (120, 160, 3)
    assert len(np.unique(first.reshape(-1, 3), axis=0)) > 10, "a blank picture"
    for _ in range(120):
        env.step(np.array([2e-3], dtype=np.float32))
    moved = env.render()
    changed = np.any(first != moved, axis=2).sum()
    assert changed > 50, f"only {changed} pixels changed"
    # picture() renders whatever the mode, with its own camera and size.
    top = env.picture(camera="top", width=64, height=48, orthographic=True)
    assert top.shape == (48, 64, 3)
    env.close()


def test_render_without_a_mode_returns_none_and_bad_requests_raise():
    env = gymfleet.make(MODELS / "pendulum.json")
    with pytest.warns(UserWarning, match="render_mode"):
        assert env.render() is None
    with pytest.raises(gymfleet.errors.InvalidArgument, match="image size 4096x10 is out of range"):
        env.picture(width=4096, height=10)
    with pytest.raises(gymfleet.errors.InvalidArgument, match='camera: expected "iso", "front", "side" or "top", got "fisheye"'):
        env.picture(camera="fisheye")
    with pytest.raises(ValueError, match="render_mode: 'human' is not supported"):
        gymfleet.make(MODELS / "pendulum.json", render_mode="human")
    env.close()


def test_record_video_writes_an_episode(tmp_path):
    pytest.importorskip("moviepy")
    env = gymfleet.make(MODELS / "arm2.json", render_mode="rgb_array", max_steps=20)
    env = gym.wrappers.RecordVideo(env, str(tmp_path), episode_trigger=lambda e: True, disable_logger=True)
    env.reset(seed=0)
    done = False
    while not done:
        _, _, terminated, truncated, _ = env.step(env.action_space.sample() * 0)
        done = terminated or truncated
    env.close()
    assert list(tmp_path.glob("*.mp4")), list(tmp_path.iterdir())


@pytest.mark.parametrize("fleet", [False, True])
def test_a_vector_env_renders_one_frame_per_env(fleet):
    servers = [gymfleet.Server(threads=1) for _ in range(2)] if fleet else []
    server = ",".join(s.address for s in servers) or None
    envs = gymfleet.make_vec(
        MODELS / "arm2.json", 3, server=server, render_mode="rgb_array",
        render_options={"width": 64, "height": 48},
    )
    envs.reset(seed=0)
    frames = envs.render()
    assert isinstance(frames, tuple) and len(frames) == 3
    assert all(f.shape == (48, 64, 3) and f.dtype == np.uint8 for f in frames)
    with pytest.raises(gymfleet.errors.InvalidArgument, match="env_index: 3 is out of range: the batch has 3 envs"):
        envs.picture(3)
    envs.close()
    for s in servers:
        s.stop()

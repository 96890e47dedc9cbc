"""The examples run (briefly): they use only the public package."""

from __future__ import annotations

import runpy
import sys

from conftest import REPO


def test_the_ars_reaching_example_runs(capsys, monkeypatch):
    script = REPO / "client" / "python" / "examples" / "ars_reach.py"
    monkeypatch.setattr(sys, "argv", [str(script), "--iterations", "2", "--directions", "4", "--targets", "2"])
    runpy.run_path(str(script), run_name="__main__")
    out = capsys.readouterr().out
    assert "before:" in out and "after:" in out and "2 iterations" in out


def test_the_ars_cartpole_example_runs(capsys, monkeypatch):
    script = REPO / "client" / "python" / "examples" / "ars_cartpole.py"
    monkeypatch.setattr(sys, "argv", [str(script), "--iterations", "1", "--directions", "2", "--episodes", "1", "--top", "1"])
    runpy.run_path(str(script), run_name="__main__")
    out = capsys.readouterr().out
    assert "before:" in out and "after:" in out and "1 iterations" in out


def test_the_ur5_import_example_reaches_its_target(capsys, monkeypatch):
    script = REPO / "client" / "python" / "examples" / "import_ur5.py"
    monkeypatch.setattr(sys, "argv", [str(script)])
    runpy.run_path(str(script), run_name="__main__")
    out = capsys.readouterr().out
    assert "converted: 11 instances, 6 moving joints" in out, out
    error = float(out.split("largest error ")[1].split(" deg")[0])
    assert error < 1.0, out


def _run_learning_example(name, argv, capsys, monkeypatch, tmp_path):
    """A learning example for a few thousand steps: it prints its curve's end and writes the
    PNG. Needs torch and matplotlib, which CI never installs (so it runs where they are)."""
    import pytest

    pytest.importorskip("torch")
    pytest.importorskip("matplotlib")
    script = REPO / "client" / "python" / "examples" / name
    png = tmp_path / "curve.png"
    monkeypatch.setattr(sys, "argv", [str(script), *argv, "--plot", str(png)])
    runpy.run_path(str(script), run_name="__main__")
    out = capsys.readouterr().out
    assert "final return" in out and "steps/s" in out, out
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    return out


def test_the_sb3_ppo_hopper_example_runs(capsys, monkeypatch, tmp_path):
    pytest = __import__("pytest")
    pytest.importorskip("stable_baselines3")
    out = _run_learning_example("sb3_ppo_hopper.py", ["--steps", "1024", "--envs", "4"], capsys, monkeypatch, tmp_path)
    assert "gymfleet/Hopper-v5: 1024 steps" in out


def test_the_cleanrl_ppo_halfcheetah_example_runs(capsys, monkeypatch, tmp_path):
    out = _run_learning_example("cleanrl_ppo_halfcheetah.py", ["--steps", "2048", "--envs", "4"], capsys, monkeypatch, tmp_path)
    assert "gymfleet/HalfCheetah-v5: 2048 steps" in out


def test_the_cleanrl_example_runs_asynchronously_on_a_remote_server(capsys, monkeypatch, tmp_path, remote_server):
    argv = ["--steps", "2048", "--envs", "4", "--batch-size", "2", "--server", remote_server]
    out = _run_learning_example("cleanrl_ppo_halfcheetah.py", argv, capsys, monkeypatch, tmp_path)
    assert "gymfleet/HalfCheetah-v5: 2048 steps" in out

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

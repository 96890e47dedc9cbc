"""Shared fixtures: the seed models, servers run in this process, and the
gymfleet-server binary (built by `cargo test`) run as a separate process."""

from __future__ import annotations

import json
import os
import pathlib
import socket
import subprocess
import time
from typing import Iterator

import pytest

import gymfleet

REPO = pathlib.Path(__file__).resolve().parents[3]
MODELS = REPO / "models"


def model(name: str) -> dict:
    with open(MODELS / f"{name}.json", encoding="utf-8") as f:
        return json.load(f)


@pytest.fixture
def arm2() -> dict:
    return model("arm2")


@pytest.fixture
def pendulum() -> dict:
    return model("pendulum")


@pytest.fixture
def server() -> Iterator[gymfleet.Server]:
    """A fresh server in this process, stopped afterwards."""
    with gymfleet.Server(threads=2) as s:
        yield s


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def remote_server() -> Iterator[str]:
    """The gymfleet-server binary as its own process; yields its address."""
    binary = pathlib.Path(
        os.environ.get("GYMFLEET_SERVER_BIN", REPO / "target" / "debug" / "gymfleet-server")
    )
    if not binary.exists():
        pytest.fail(f"{binary} not found: build it with `cargo build -p gymfleet-server`")
    port = _free_port()
    addr = f"127.0.0.1:{port}"
    proc = subprocess.Popen(
        [str(binary), "--listen", addr, "--threads", "2"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    try:
        deadline = time.monotonic() + 30
        while True:
            try:
                gymfleet.server_info(addr)
                break
            except gymfleet.Unavailable:
                if proc.poll() is not None or time.monotonic() > deadline:
                    raise RuntimeError(
                        f"gymfleet-server did not start: {proc.stderr.read().decode()[-2000:]}"
                    )
                time.sleep(0.05)
        yield addr
    finally:
        proc.terminate()
        proc.wait(timeout=30)

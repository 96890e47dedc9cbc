#!/usr/bin/env python3
"""One build serves every command the README runs (README, "Build once"), checked in the
dev profile: after the one documented build, each documented `cargo run` / `cargo build`
needs only artifacts that build made, and `cargo install --locked` compiles nothing.

Cargo keeps every variant it ever built, so "compiled nothing" is not checked by watching
for `Compiling` lines (an earlier `cargo test` may have left a matching variant). It
compares artifacts: each command's build (`--message-format=json`) must name only files
the one build named, hashes included. A dependency whose features differ between the
two builds has another hash, and the check names it.
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from typing import List, Set

#: The README's one build, in the dev profile (it documents `--release`).
ONE_BUILD = [
    "build", "--bins", "-p", "gymfleet-server", "-p", "gymfleet-load", "-p", "gymfleet-mcp",
    "-p", "gymfleet-client", "--example", "first_session",
]
#: What each documented command builds (`cargo run -p X` builds X's binary).
COMMANDS = {
    "cargo run -p gymfleet-server": ["build", "-p", "gymfleet-server", "--bin", "gymfleet-server"],
    "cargo run -p gymfleet-load": ["build", "-p", "gymfleet-load", "--bin", "gymfleet-load"],
    "cargo run -p gymfleet-mcp": ["build", "-p", "gymfleet-mcp", "--bin", "gymfleet-mcp"],
    "cargo run -p gymfleet-client --example first_session": [
        "build", "-p", "gymfleet-client", "--example", "first_session",
    ],
}


def artifacts(args: List[str]) -> Set[str]:
    out = subprocess.run(
        ["cargo", *args, "-j2", "--message-format=json"],
        check=True, stdout=subprocess.PIPE, text=True,
    ).stdout
    files: Set[str] = set()
    for line in out.splitlines():
        message = json.loads(line)
        if message.get("reason") == "compiler-artifact":
            files.update(message["filenames"])
    return files


def main() -> int:
    one = artifacts(ONE_BUILD)
    failures = []
    for command, args in COMMANDS.items():
        extra = sorted(artifacts(args) - one)
        print(f"{command}: {'reuses the one build' if not extra else f'{len(extra)} artifacts of its own'}")
        if extra:
            failures.append((command, extra))
    with tempfile.TemporaryDirectory() as root:
        install = subprocess.run(
            ["cargo", "install", "--locked", "--debug", "--path", "apps/mcp",
             "--target-dir", "target", "--root", root],
            check=True, stderr=subprocess.PIPE, text=True,
        ).stderr
    compiled = [line.strip() for line in install.splitlines() if line.strip().startswith("Compiling")]
    print(f"cargo install --locked --path apps/mcp --target-dir target: "
          f"{'compiled nothing' if not compiled else f'compiled {len(compiled)} crates'}")
    if compiled:
        failures.append(("cargo install --locked --path apps/mcp", compiled))
    for command, extra in failures:
        print(f"\n{command} does not reuse the one build:", *extra[:20], sep="\n  ")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

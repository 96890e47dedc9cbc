"""Every code block of the READMEs (the repository's, the clients', the MCP adapter's and
the deploy's) and of the guide (docs/) runs in CI, or says where it runs or why not.

A block preceded by ``<!-- runs in CI: WHERE -->`` is run elsewhere (WHERE must exist, and a
block kept as a test's code must be that code); one preceded by ``<!-- not run: REASON -->``
is not run, for the reason given. Every other block is run here: Python blocks are executed
from the repository root (on the embedded server), JSON blocks are parsed, and a JSON robot
document is built into an env and stepped. A block of any other language without a marker
fails.
"""

import json
import pathlib
import re
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]
READMES = ["README.md", "client/python/README.md", "client/js/README.md", "apps/mcp/README.md", "deploy/README.md"]
FILES = READMES + sorted(str(p.relative_to(ROOT)) for p in (ROOT / "docs").glob("*.md"))
MARK = re.compile(r"^<!-- (runs in CI|not run): (.+) -->$")


def blocks(path):
    """(line, language, code, marker) of each fenced block of ``path``."""
    lines = (ROOT / path).read_text(encoding="utf-8").split("\n")
    out, i = [], 0
    while i < len(lines):
        if lines[i].startswith("```"):
            start, lang = i, lines[i][3:].strip()
            j = i + 1
            while j < len(lines) and not lines[j].startswith("```"):
                j += 1
            before = next((lines[k] for k in range(start - 1, -1, -1) if lines[k].strip()), "")
            mark = MARK.match(before.strip())
            out.append((start + 1, lang, "\n".join(lines[start + 1 : j]), mark))
            i = j + 1
        else:
            i += 1
    return out


ALL = [(f, *b) for f in FILES for b in blocks(f)]


def test_the_files_have_blocks_and_every_marker_says_something():
    assert len(ALL) > 10
    for path, line, _lang, _code, mark in ALL:
        if mark:
            assert len(mark.group(2)) > 10, f"{path}:{line}: a marker needs its where or why"


@pytest.mark.parametrize("path,line,lang,code,mark", ALL, ids=[f"{a[0]}:{a[1]}" for a in ALL])
def test_each_block_runs_or_says_where_or_why_not(path, line, lang, code, mark, tmp_path):
    where = f"{path}:{line}"
    if mark and mark.group(1) == "not run":
        return
    if mark:
        # WHERE names a file that holds or runs the block.
        named = re.findall(r"[\w./-]+\.(?:rs|py|ts|sh)|\.ci/\w+", mark.group(2))
        assert named, f"{where}: 'runs in CI' names no file"
        for name in named:
            assert (ROOT / name).exists(), f"{where}: {name} does not exist"
        if "holds this code" in mark.group(2):
            held = " ".join((ROOT / named[0]).read_text(encoding="utf-8").split())
            for code_line in code.split("\n"):
                if code_line.strip() and not code_line.startswith("use "):
                    assert " ".join(code_line.split()) in held, f"{where}: {named[0]} lacks {code_line!r}"
        return
    if lang == "python":
        script = tmp_path / "block.py"
        script.write_text(code, encoding="utf-8")
        run = subprocess.run(
            [sys.executable, str(script)], cwd=ROOT, capture_output=True, text=True, timeout=600
        )
        assert run.returncode == 0, f"{where} failed:\n{run.stdout[-2000:]}\n{run.stderr[-4000:]}"
    elif lang == "json":
        value = json.loads(code)
        if isinstance(value, dict) and "parts" in value:
            import gymfleet

            env = gymfleet.make(value)
            env.reset(seed=0)
            env.step(env.action_space.sample() * 0)
            env.close()
    else:
        pytest.fail(f"{where}: a {lang or 'plain'} block without a marker (<!-- runs in CI: ... --> or <!-- not run: ... -->)")

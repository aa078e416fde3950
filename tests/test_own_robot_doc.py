"""docs/own_robot.md runs as written: every ``rcm-pin`` line of its bash blocks (from the
repository root, in this process, its output files in a temporary folder) exits with the
status its comment gives (0 without one), and every Python block runs."""

from __future__ import annotations

import contextlib
import io
import os
import re
import shlex
from pathlib import Path

import pytest

from rcm_pin.cli import main

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "own_robot.md"
TEXT = PAGE.read_text()
LINES = [
    line
    for block in re.findall(r"^```bash\n(.*?)^```$", TEXT, flags=re.S | re.M)
    for line in block.splitlines()
    if line.startswith("rcm-pin ")
]
PYTHON = re.findall(r"^```python\n(.*?)^```$", TEXT, flags=re.S | re.M)
#: Options whose value is a file the command writes: sent to the temporary folder.
OUTPUTS = {"--html", "--png", "--plot"}


def test_the_page_has_commands():
    assert len(LINES) >= 10 and PYTHON


def _argv(line: str, tmp: Path) -> tuple[list[str], int]:
    command, _, comment = line.partition("#")
    found = re.search(r"exits with status (\d+)", comment)
    words = shlex.split(command)[1:]
    for i, word in enumerate(words[:-1]):
        if word in OUTPUTS:
            words[i + 1] = str(tmp / Path(words[i + 1]).name)
    return words, int(found.group(1)) if found else 0


@pytest.mark.parametrize("line", LINES, ids=lambda line: " ".join(line.split()[:2]))
def test_every_command_runs(line, tmp_path, monkeypatch):
    monkeypatch.chdir(ROOT)
    argv, expected = _argv(line, tmp_path)
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        status = main(argv)
    assert status == expected, line
    for option in OUTPUTS & set(argv):
        assert (tmp_path / Path(argv[argv.index(option) + 1]).name).stat().st_size > 0


@pytest.mark.parametrize("block", PYTHON)
def test_every_python_block_runs(block):
    cwd = os.getcwd()
    try:
        os.chdir(ROOT)
        exec(compile(block, str(PAGE), "exec"), {})
    finally:
        os.chdir(cwd)

"""The examples of the README and of every page of docs/ run as written.

The pages are README.md and docs/*.md, except docs/own_robot.md (its own runner,
tests/test_own_robot_doc.py) and docs/api.md (generated, no code). Every Python block runs
(in a temporary working directory). Every line of the shell blocks (```bash, ```sh,
```console: the ``$ `` lines) runs in ``bash`` with the checkout's ``rcm-pin`` (the console
script beside ``sys.executable``) first on PATH; a block's lines share one temporary
directory and run in order, as when the block is pasted into a shell. The temporary
directory links ``tests`` to the checkout's, so the example files of ``tests/data`` are
found as from the repository root. A line exits 0 unless its comment says
``exits with status N``. The other blocks are checked too: a ```json block parses, an
```xml block is an element of a committed URDF (:func:`test_data_blocks_are_real`).

The lines that cannot run inside the suite are listed in :data:`SPECIAL`, each with the
reason and what is done instead; an entry that matches no line of any page fails, so that
the list cannot outlive the lines it excuses, and a line of the README's Quick start that no
entry matches fails too (those lines create virtual environments).
"""

from __future__ import annotations

import os
import re
import select
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
#: The pages whose examples this module runs (docs/own_robot.md: tests/test_own_robot_doc.py).
PAGES = [README] + [
    p for p in sorted((ROOT / "docs").glob("*.md")) if p.name not in {"own_robot.md", "api.md"}
]
TEXTS = {page: page.read_text() for page in PAGES}
TEXT = TEXTS[README]
#: (page, Python source) of every ```python block.
BLOCKS = [
    (page, code)
    for page, text in TEXTS.items()
    for code in re.findall(r"^```python\n(.*?)^```$", text, flags=re.S | re.M)
]
#: The checkout's console scripts (the virtual environment running the tests).
BIN = Path(sys.executable).parent
#: Wall-clock limit of one line [s].
LINE_TIMEOUT = 300.0
#: The report section the reproduce lines run (the whole report takes about 2 min on 2 cores).
SMALL_REPORT = "--only rcm_pin.report.position --jobs 1"


@dataclass(frozen=True)
class Line:
    """One shell command of a page: its section (``## `` heading), line number, text."""

    section: str
    number: int
    text: str
    page: str = "README.md"

    @property
    def expected_status(self) -> int:
        found = re.search(r"#.*\bexits with status (\d+)", self.text)
        return int(found.group(1)) if found else 0


@dataclass(frozen=True)
class Special:
    """Lines of the pages that do not run as they are: ``pattern`` (a regex that must match the
    whole line), why, and ``how`` they are checked instead."""

    pattern: str
    reason: str
    how: str  # "ci" | "reproduce" | "interrupt"


SPECIAL: tuple[Special, ...] = (
    Special(
        r"python3 -m venv \.venv && \.venv/bin/pip install .+ && "
        r"\.venv/bin/python -m pytest -q -p no:cacheprovider",
        "creates a virtual environment, installs from the package index and runs this very "
        "suite; .ci/run runs the line verbatim (in a fresh .venv), so the test checks that "
        "the README's line is exactly a line of .ci/run",
        "ci",
    ),
    Special(
        r"python3 -m venv \.venv && \.venv/bin/pip install .+ && "
        r"\.venv/bin/rcm-pin reproduce --out report",
        "the virtual environment and the install are those of the test command (.ci/run "
        "makes them in a fresh .venv); the whole report takes about 2 min on 2 cores, so "
        f"`rcm-pin reproduce --out report` runs with {SMALL_REPORT}",
        "reproduce",
    ),
    Special(
        r"rcm-pin reproduce --out report",
        f"the whole report takes about 2 min on 2 cores: it runs with {SMALL_REPORT}",
        "reproduce",
    ),
    Special(
        r"rcm-pin view rcm_bevel +# live viewer on 127\.0\.0\.1 until Ctrl-C",
        "serves until Ctrl-C: it runs until it prints the viewer's address, then gets the "
        "Ctrl-C (SIGINT to its process group) and must exit 0",
        "interrupt",
    ),
)


def _strip_comment(text: str) -> str:
    return re.sub(r"\s+#.*$", "", text).strip()


def shell_blocks(text: str, page: str = "README.md") -> list[list[Line]]:
    """The commands of every ```bash / ```sh / ```console block, block by block (``\\``
    continuations joined; blank and comment lines dropped; console blocks: ``$ `` lines)."""
    blocks: list[list[Line]] = []
    section, lines, i = "", text.splitlines(), 0
    while i < len(lines):
        if lines[i].startswith("## "):
            section = lines[i][3:].strip()
        fence = re.fullmatch(r"```(bash|sh|console)\s*", lines[i])
        if fence is None:
            i += 1
            continue
        body: list[tuple[int, str]] = []
        i += 1
        while not lines[i].startswith("```"):
            body.append((i + 1, lines[i]))
            i += 1
        i += 1
        commands: list[Line] = []
        pending: tuple[int, str] | None = None
        for number, raw in body:
            if fence.group(1) == "console":
                if pending is None and not raw.startswith("$ "):
                    continue  # output
                raw = raw[2:] if pending is None else raw
            if pending is not None:
                number, raw = pending[0], pending[1] + " " + raw.strip()
            if raw.rstrip().endswith("\\"):
                pending = (number, raw.rstrip()[:-1].rstrip())
                continue
            pending = None
            if raw.strip() and not raw.strip().startswith("#"):
                commands.append(Line(section, number, raw.strip(), page))
        blocks.append(commands)
    return blocks


def _name(page: Path) -> str:
    return str(page.relative_to(ROOT))


SHELL = [block for page, text in TEXTS.items() for block in shell_blocks(text, _name(page))]
LINES = [line for block in SHELL for line in block]


def special(line: Line) -> Special | None:
    for entry in SPECIAL:
        if re.fullmatch(entry.pattern, _strip_comment(line.text)) or re.fullmatch(
            entry.pattern, line.text
        ):
            return entry
    return None


def _env() -> dict[str, str]:
    env = dict(os.environ, MPLBACKEND="Agg")
    env["PATH"] = f"{BIN}{os.pathsep}{env.get('PATH', '')}"
    return env


def _run(command: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        ["bash", "-c", command],
        cwd=cwd,
        env=_env(),
        capture_output=True,
        text=True,
        timeout=LINE_TIMEOUT,
        check=False,
    )


def _interrupt(command: str, cwd: Path) -> tuple[int, str]:
    """Run ``command`` until it prints a viewer address, then Ctrl-C its process group."""
    proc = subprocess.Popen(
        ["bash", "-c", f"exec {command}"],
        cwd=cwd,
        env=dict(_env(), PYTHONUNBUFFERED="1"),
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        start_new_session=True,
    )
    assert proc.stdout is not None
    output, deadline = "", time.monotonic() + LINE_TIMEOUT
    try:
        while "http://127.0.0.1:" not in output and time.monotonic() < deadline:
            ready, _, _ = select.select([proc.stdout], [], [], 1.0)
            if ready:
                chunk = proc.stdout.readline()
                if not chunk:  # it ended without serving
                    return proc.wait(timeout=60), output
                output += chunk
        if "http://127.0.0.1:" not in output:
            return -1, output + f"(no viewer address after {LINE_TIMEOUT:g} s)"
        time.sleep(0.5)
        os.killpg(proc.pid, signal.SIGINT)  # Ctrl-C
        status = proc.wait(timeout=60)
        return status, output + proc.stdout.read()
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def _check(line: Line, cwd: Path) -> str | None:
    """None if the line behaves as its page says, else what went wrong."""
    entry = special(line)
    if entry is not None and entry.how == "ci":
        ci = (ROOT / ".ci" / "run").read_text().splitlines()
        return None if line.text in ci else f"not a line of .ci/run: {line.text}"
    command = line.text
    if entry is not None and entry.how == "reproduce":
        command = "rcm-pin reproduce --out report " + SMALL_REPORT
    if entry is not None and entry.how == "interrupt":
        status, output = _interrupt(_strip_comment(command), cwd)
        if status != 0 or "http://127.0.0.1:" not in output:
            return f"exit {status}: {output.strip()[-600:]}"
        return None
    try:
        done = _run(command, cwd)
    except subprocess.TimeoutExpired:
        return f"still running after {LINE_TIMEOUT:g} s"
    if done.returncode != line.expected_status:
        tail = (done.stderr.strip() or done.stdout.strip())[-600:]
        return f"exit {done.returncode} (expected {line.expected_status}): {tail}"
    return None


def _workdir(tmp_path: Path) -> Path:
    """A temporary working directory where ``tests/data/...`` resolves (the checkout's)."""
    (tmp_path / "tests").symlink_to(ROOT / "tests", target_is_directory=True)
    return tmp_path


def test_the_pages_have_python_blocks():
    assert any(page == README for page, _ in BLOCKS), "no Python block in the README"
    assert len(BLOCKS) >= 10


def _block_id(index: int) -> str:
    page, _ = BLOCKS[index]
    return f"{page.stem}-{sum(p == page for p, _ in BLOCKS[:index])}"


@pytest.mark.parametrize("index", range(len(BLOCKS)), ids=_block_id)
def test_python_block_runs(index, tmp_path, monkeypatch):
    monkeypatch.chdir(_workdir(tmp_path))
    page, source = BLOCKS[index]
    code = compile(source, f"{_name(page)} block {_block_id(index)}", "exec")
    exec(code, {"__name__": f"doc_block_{index}"})


def test_data_blocks_are_real():
    """A ```json block is JSON; an ```xml block is the ``<rcm_pin>`` element of a committed
    URDF (the same attributes and values)."""
    import json
    import xml.etree.ElementTree as ET

    checked = 0
    for page, text in TEXTS.items():
        for block in re.findall(r"^```json\n(.*?)^```$", text, flags=re.S | re.M):
            json.loads(block)
            checked += 1
        for block in re.findall(r"^```xml\n(.*?)^```$", text, flags=re.S | re.M):
            shown = ET.fromstring(block)
            urdfs = [ET.parse(u).getroot() for u in sorted((ROOT / "urdf").glob("*.urdf"))]
            found = [e.attrib for root in urdfs for e in root.iter(shown.tag)]
            assert shown.attrib in found, f"{_name(page)}: {block} is in no urdf/*.urdf"
            checked += 1
    assert checked >= 2


def test_the_pages_have_shell_lines_and_every_special_entry_is_used():
    assert len(LINES) >= 30
    unused = [e.pattern for e in SPECIAL if not any(special(line) is e for line in LINES)]
    assert not unused, f"SPECIAL entries that match no line of the pages: {unused}"
    quick = [line for line in LINES if line.section == "Quick start" and line.page == "README.md"]
    assert quick, "no shell line in the README's Quick start"
    untreated = [line.text for line in quick if special(line) is None]
    assert not untreated, f"Quick-start lines without a SPECIAL entry: {untreated}"


def test_the_ik_output_sample_is_what_ik_prints():
    """The sample of ``rcm-pin ik ... --pose`` output (a ```text block of docs/cli.md): its
    header and legend lines as printed, and each solution's in/out prefix and label."""
    pattern = r"^```text\n(rcm_bevel: inverse position problem.*?)^```$"
    samples = [s for text in TEXTS.values() for s in re.finditer(pattern, text, re.S | re.M)]
    assert samples, "no sample of the ik output in the pages"
    sample = samples[0]
    shown = [s for s in sample.group(1).splitlines() if s != "..."]
    (line,) = [x for x in LINES if x.text.startswith("rcm-pin ik rcm_bevel --pose")][:1]
    done = _run(line.text, ROOT)
    assert done.returncode == 0, done.stderr
    printed = done.stdout.splitlines()
    assert shown[:2] == printed[:2]
    for readme, actual in zip(shown[2:], printed[2:], strict=False):
        assert readme.split(": q =")[0] == actual.split(": q =")[0]
    assert sum(p.startswith("in  ") for p in printed) == 2  # "in  branch_k: ..."


def test_the_checkout_rcm_pin_is_beside_the_interpreter():
    assert (BIN / "rcm-pin").exists(), f"no rcm-pin in {BIN}: install the checkout (pip -e .)"


@pytest.mark.parametrize(
    "block",
    range(len(SHELL)),
    ids=[f"{Path(b[0].page).stem}-line{b[0].number}" if b else "empty" for b in SHELL],
)
def test_shell_block_runs(block, tmp_path):
    """Each line of the block, in order, in one temporary directory."""
    failures = []
    cwd = _workdir(tmp_path)
    for line in SHELL[block]:
        problem = _check(line, cwd)
        if problem is not None:
            failures.append(f"{line.page}:{line.number}: {line.text}\n    {problem}")
    assert not failures, "\n".join(failures)

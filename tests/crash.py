"""Helpers of the crash-consistency tests: a process's descendants from /proc, whether a
PID still runs, a folder's files as bytes, SIGKILL once a condition holds."""

from __future__ import annotations

import os
import signal
import subprocess
import time
from collections.abc import Callable
from pathlib import Path


def _ppid_map() -> dict[int, int]:
    out = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                stat = (entry / "stat").read_text()
            except OSError:
                continue
            out[int(entry.name)] = int(stat.rpartition(")")[2].split()[1])
    return out


def descendants(pid: int) -> set[int]:
    """Every live descendant of ``pid`` (children, their children, ...)."""
    parents = _ppid_map()
    found, todo = set(), [pid]
    while todo:
        p = todo.pop()
        kids = {c for c, pp in parents.items() if pp == p} - found
        found |= kids
        todo.extend(kids)
    return found


def alive(pid: int) -> bool:
    """Whether ``pid`` runs (a zombie, dead but not reaped, does not)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat.rpartition(")")[2].split()[0] not in ("Z", "X")


def survivors(pids: set[int], within: float = 5.0) -> set[int]:
    """The PIDs still running after ``within`` seconds (returns as soon as none is)."""
    deadline = time.monotonic() + within
    while time.monotonic() < deadline:
        left = {p for p in pids if alive(p)}
        if not left:
            return left
        time.sleep(0.05)
    return {p for p in pids if alive(p)}


def files(folder: Path, skip: Callable[[str], bool] = lambda name: False) -> dict[str, bytes]:
    """Relative path -> bytes of every file under ``folder`` (but ``skip``ped names)."""
    return {
        str(p.relative_to(folder)): p.read_bytes()
        for p in sorted(Path(folder).rglob("*"))
        if p.is_file() and not skip(str(p.relative_to(folder)))
    }


def wait_for(proc: subprocess.Popen, ready: Callable[[], bool], timeout: float = 60.0) -> bool:
    """Whether ``ready()`` came to hold while ``proc`` runs (polled every 20 ms)."""
    deadline = time.monotonic() + timeout
    while not ready():
        if proc.poll() is not None or time.monotonic() > deadline:
            return False
        time.sleep(0.02)
    return True


def kill_when(
    proc: subprocess.Popen, ready: Callable[[], bool], delay: float, timeout: float = 60.0
) -> bool:
    """SIGKILL ``proc`` ``delay`` s after ``ready()`` first holds; False when it ended
    first (or ``timeout`` passed)."""
    if not wait_for(proc, ready, timeout):
        return False
    time.sleep(delay)
    if proc.poll() is not None:
        return False
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    return True

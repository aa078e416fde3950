"""Processes and folders of parallel runs: pools that die with the run, locks, atomic files.

Used by the report's sections and a design study's chunks: process pools whose workers die
with their parent, an exclusive lock on an output folder, files committed by atomic rename.

* :func:`process_pool`: workers fork from a fork server that has imported the given modules
  once (no import of Pinocchio per process, no threads of the caller inherited); on a
  platform without a fork server (Windows) they are spawned. On Linux the fork server (a
  child of the run: :mod:`rcm_pin._deathsig` in its preload) and every worker (a child of
  the fork server: the pool's initializer) ask the kernel for SIGKILL when their parent
  dies (``prctl(PR_SET_PDEATHSIG)`` through ctypes), and a worker exits at once when the
  run that started it is already gone; so a run killed by SIGKILL leaves no process behind.
  The kernel ties the signal to the parent *thread*: start pools from a thread that lives
  as long as the pool (the CLI's main thread does).
* :func:`folder_lock`: ``fcntl.flock`` on ``FOLDER/.lock`` holding the owner's PID; a
  second run on the folder is refused with :class:`~rcm_pin.errors.FolderBusyError` naming
  that PID (it does not wait). The kernel drops the lock when its holder dies, however it
  dies, so a killed run never leaves a stale lock.
* :func:`atomic_write`: a temporary file in the same folder, flushed, then ``os.replace``:
  a reader sees the old file or the whole new one, never a part.
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import os
import signal
import sys
import tempfile
from collections.abc import Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_all_start_methods, get_context
from pathlib import Path

from rcm_pin.errors import FolderBusyError, InvalidInputError

#: ``PR_SET_PDEATHSIG`` of <linux/prctl.h>.
PR_SET_PDEATHSIG = 1
#: Name of the lock file inside a locked folder.
LOCK = ".lock"
_held: dict[str, int] = {}  # resolved folder -> lock file descriptor held by this process


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


_MODE = 0o666 & ~_umask()  # what open() would give a new file


def parent_death_signal() -> None:
    """Ask the kernel for SIGKILL when this process's parent dies (Linux; elsewhere a
    no-op)."""
    if sys.platform.startswith("linux"):
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
        libc.prctl(PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)


def die_with_parent(run_pid: int) -> None:
    """Pool initializer: SIGKILL this process when its parent dies (Linux), and exit now if
    the run ``run_pid`` is already gone (it died before the request took effect)."""
    parent_death_signal()
    try:
        os.kill(run_pid, 0)
    except ProcessLookupError:
        os._exit(1)
    except PermissionError:  # alive, owned by another user
        pass


def process_pool(workers: int, preload: Sequence[str]) -> ProcessPoolExecutor:
    """A pool of ``workers`` processes forked from a server that imported ``preload``
    (module names), spawned where the platform has no fork server; every worker dies with
    its parent (module docstring)."""
    run = (os.getpid(),)
    if "forkserver" not in get_all_start_methods():
        spawn = get_context("spawn")
        return ProcessPoolExecutor(workers, spawn, initializer=die_with_parent, initargs=run)
    context = get_context("forkserver")
    context.set_forkserver_preload(["rcm_pin._deathsig", *preload])
    return ProcessPoolExecutor(workers, context, initializer=die_with_parent, initargs=run)


def lock_holder(folder: Path) -> int | None:
    """The PID written in the folder's lock file (None: none or unreadable)."""
    try:
        return int((Path(folder) / LOCK).read_text().strip() or "x")
    except (OSError, ValueError):
        return None


@contextlib.contextmanager
def folder_lock(folder: Path, option: str = "--out") -> Iterator[None]:
    """Hold the exclusive lock of ``folder`` (re-entrant within a process).

    Raises:
        FolderBusyError: another process holds it; the message names its PID.
        InvalidInputError: the lock file cannot be created (no such folder, read-only).
    """
    name = str(Path(folder).resolve())
    if name in _held:
        yield
        return
    import fcntl  # POSIX only; imported here so that the module imports on Windows

    try:
        fd = os.open(Path(folder) / LOCK, os.O_RDWR | os.O_CREAT, 0o644)
    except OSError as exc:
        raise InvalidInputError(
            f"{option} {folder}: cannot open its lock file {LOCK} ({exc.strerror}); valid: an "
            "existing folder this user can write"
        ) from None
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(fd)
        pid = lock_holder(Path(folder))
        raise FolderBusyError(
            f"{option} {folder} is in use by another run (PID {pid}); valid: wait until it "
            "ends, or another folder"
        ) from None
    os.ftruncate(fd, 0)
    os.write(fd, f"{os.getpid()}\n".encode())
    _held[name] = fd
    try:
        yield
    finally:
        del _held[name]
        os.ftruncate(fd, 0)
        os.close(fd)  # closing the descriptor releases the lock


def remove_temporaries(folder: Path) -> int:
    """Delete the temporary files :func:`atomic_write` left in ``folder`` (a run killed
    between writing and renaming); call it holding the folder's lock. Returns the count."""
    count = 0
    for path in Path(folder).glob(".*.tmp"):
        with contextlib.suppress(OSError):
            path.unlink()
            count += 1
    return count


def atomic_write(path: Path, data: bytes) -> Path:
    """Write ``data`` to ``path`` by atomic rename (module docstring) and return ``path``."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, _MODE)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
    return path


__all__ = [
    "LOCK",
    "atomic_write",
    "die_with_parent",
    "folder_lock",
    "lock_holder",
    "parent_death_signal",
    "process_pool",
    "remove_temporaries",
]

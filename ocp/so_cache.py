"""Verified entries of the on-disk cache of CasADi artefacts (compiled ``.so``, ``.casadi``).

A shared library is mapped into the process by ``dlopen``: a truncated one kills the
process with SIGBUS when a missing page is touched, an emptied one fails to load, a
modified one may compute anything. No Python ``except`` can catch the first, so no entry is
loaded before it is verified:

* :func:`publish` moves a finished file (written under a temporary name in the cache
  folder) into place with ``os.replace`` and records its size and SHA-256 in a sidecar
  ``<entry>.sha256`` (JSON ``{"size": ..., "sha256": ...}``, itself written to a temporary
  name and renamed);
* :func:`verify` says why an entry must not be used (missing, no sidecar, unreadable, a
  size or checksum that differs from the record), or None when it may be loaded;
* :func:`usable` is the lookup of the callers: True for a verified entry; for a damaged
  one (not merely unrecorded: :data:`NO_RECORD`) a :class:`CacheWarning` (the caller
  rebuilds it, or falls back to the uncompiled function when the folder is read-only).

Two processes that publish the same entry at once leave either one's file and sidecar; a
pair from different processes only differs if the compiler is not deterministic, and
then the next lookup rebuilds it (with a warning). Replacing a library *in place* while
a process has it loaded is outside what a cache can guard against (rename, never
overwrite).
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import warnings
from pathlib import Path

#: Suffix of the checksum record beside an entry.
SIDECAR = ".sha256"
#: :func:`verify`'s reason for an entry without a record (an older version's, or one whose
#: writer stopped between the two renames): rebuilt without a warning, like a miss.
NO_RECORD = "it has no checksum record"


class CacheWarning(UserWarning):
    """A cache entry failed verification (or could not be written): it is rebuilt, or the
    uncompiled function is used."""


def sidecar(path: Path) -> Path:
    """The checksum record of the entry ``path``: ``<path>.sha256``."""
    return path.with_name(path.name + SIDECAR)


def checksum(path: Path) -> tuple[int, str]:
    """(size in bytes, SHA-256 hex digest) of the file ``path``.

    Raises:
        OSError: it cannot be read.
    """
    h, size = hashlib.sha256(), 0
    with open(path, "rb") as f:
        while block := f.read(1 << 20):
            h.update(block)
            size += len(block)
    return size, h.hexdigest()


def verify(path: Path) -> str | None:
    """Why ``path`` must not be loaded, or None when its size and checksum match its record."""
    if not path.exists():
        return "missing"
    try:
        record = json.loads(sidecar(path).read_text())
        want = (int(record["size"]), str(record["sha256"]))
    except FileNotFoundError:
        return NO_RECORD
    except (OSError, ValueError, KeyError, TypeError) as exc:
        return f"its checksum record is unreadable ({exc})"
    try:
        got = checksum(path)
    except OSError as exc:
        return f"it is unreadable ({exc.strerror or exc})"
    if got[0] != want[0]:
        return f"it has {got[0]} bytes; its record says {want[0]}"
    if got[1] != want[1]:
        return "its SHA-256 differs from its record"
    return None


def usable(path: Path) -> bool:
    """Whether ``path`` is a verified entry; a :class:`CacheWarning` when it is present but
    damaged (the caller rebuilds it or uses the uncompiled function)."""
    why = verify(path)
    if why is None:
        return True
    if why not in ("missing", NO_RECORD):  # no record: written by an older version
        warnings.warn(
            f"cache entry {path} is not used: {why}; rebuilding it", CacheWarning, stacklevel=3
        )
    return False


def publish(tmp: Path, path: Path) -> None:
    """Move the finished file ``tmp`` (in the folder of ``path``) to ``path`` and record its
    size and checksum beside it; both by rename, so that no reader sees half a file.

    Raises:
        OSError: the folder is not writable (``tmp`` is then removed).
    """
    try:
        size, digest = checksum(tmp)
        record = path.with_name(f".{path.name}.{os.getpid()}{SIDECAR}.tmp")
        record.write_text(json.dumps({"size": size, "sha256": digest}))
        os.replace(tmp, path)
        os.replace(record, sidecar(path))
    except OSError:
        for leftover in (tmp, path.with_name(f".{path.name}.{os.getpid()}{SIDECAR}.tmp")):
            with contextlib.suppress(OSError):
                leftover.unlink(missing_ok=True)
        raise


__all__ = [
    "NO_RECORD",
    "SIDECAR",
    "CacheWarning",
    "checksum",
    "publish",
    "sidecar",
    "usable",
    "verify",
]

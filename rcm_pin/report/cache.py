"""The report's section cache: one verified JSON entry per section in ``out/.cache``.

An entry (``out/.cache/<slug>.json``) holds the section's key (:func:`rcm_pin.report.runner.
cache_key`), its title, markdown and figures, the SHA-256 of every file the section wrote
or names (its figures), and ``checksum``: the SHA-256 of all of that (canonical JSON). It is
written by atomic rename, after the files it names are in place.

:func:`read_entry` serves an entry only when its checksum matches its content, its key is
the current one, and every file it names is in ``out`` with the recorded hash. A damaged
entry (truncated, emptied, a flipped byte, e.g. in a published value of the markdown) or
one whose files are missing or changed is not served: a :class:`CacheWarning` says why and
the section is computed again. A changed key (a source or a version changed) recomputes
without a warning: that is the cache working.
"""

from __future__ import annotations

import hashlib
import json
import warnings
from dataclasses import asdict
from pathlib import Path
from typing import Any

from rcm_pin.processes import atomic_write
from rcm_pin.report.framework import Section

#: Folder of the entries inside the report's folder.
CACHE = ".cache"


class CacheWarning(UserWarning):
    """A cache entry not served (damaged, or a file it names missing or changed)."""


def file_sha(path: Path) -> str:
    """SHA-256 of a file's bytes."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def _checksum(entry: dict[str, Any]) -> str:
    body = {k: v for k, v in entry.items() if k != "checksum"}
    return hashlib.sha256(json.dumps(body, sort_keys=True).encode()).hexdigest()


def entry_path(out_dir: Path, slug: str) -> Path:
    """The entry file of a section (by its slug)."""
    return Path(out_dir) / CACHE / f"{slug}.json"


def write_entry(
    out_dir: Path, slug: str, name: str, key: str, section: Section, files: dict[str, str]
) -> Path:
    """Record a section: ``files`` (relative name -> SHA-256) plus its figures found in
    ``out_dir``; returns the entry's path."""
    files = dict(files)
    for figure in section.figures:
        if figure not in files and (Path(out_dir) / figure).is_file():
            files[figure] = file_sha(Path(out_dir) / figure)
    entry: dict[str, Any] = {"key": key, "name": name, "files": files, "section": asdict(section)}
    entry["checksum"] = _checksum(entry)
    path = entry_path(out_dir, slug)
    path.parent.mkdir(exist_ok=True)
    return atomic_write(path, json.dumps(entry, indent=1, sort_keys=True).encode())


def _why_not(out_dir: Path, entry: dict[str, Any], sha: Any) -> str | None:
    """Why an entry with the current key cannot be served (None: it can)."""
    files = entry["files"]
    for figure in entry["section"]["figures"]:
        if figure not in files:
            return f"figure {figure!r} is not among the files it recorded"
    for file, recorded in files.items():
        path = Path(out_dir) / file
        if not path.is_file():
            return f"{file} is missing"
        if sha(path) != recorded:
            return f"{file} has changed"
    return None


def read_entry(out_dir: Path, slug: str, key: str, sha: Any = file_sha) -> Section | None:
    """The cached section, or None (module docstring); ``sha(path)`` hashes a file."""
    path = entry_path(out_dir, slug)
    if not path.is_file():
        return None
    try:
        entry = json.loads(path.read_bytes())
        if not isinstance(entry, dict) or entry.get("checksum") != _checksum(entry):
            raise ValueError("its checksum does not match its content")
        if entry["key"] != key:
            return None
        why = _why_not(out_dir, entry, sha)
        if why is None:
            s = entry["section"]
            return Section(s["title"], s["body"], tuple(s["figures"]))
    except (OSError, ValueError, KeyError, TypeError) as exc:
        why = f"damaged ({exc})"
    warnings.warn(f"cache entry {path}: {why}; the section is computed again", CacheWarning, 2)
    return None


__all__ = ["CACHE", "CacheWarning", "entry_path", "file_sha", "read_entry", "write_entry"]

"""The xacro render cache: keyed on every file xacro read, verified on every read.

An entry is found by a key of the main file (its absolute path and content), the sorted
arguments and the package search (:meth:`rcm_pin.model.packages.PackageSearch.key`). It
records what the render depended on: the SHA-256 of every file xacro read (its includes and
YAML files, wherever they are), the folder of every ``$(find)`` package and the value of
every ``$(env)`` / ``$(optenv)`` variable. An entry is served only when all of them still
hold: an edited include in another folder, a package that now resolves elsewhere or a
changed variable renders again, in this process or a new one.

On disk (``$RCM_PIN_CACHE/xacro-renders/<key>.json``, default ``~/.cache/rcm-pin``) an
entry carries the SHA-256 of its own contents: an entry that is truncated, edited or
unreadable is rendered again with a :class:`CacheWarning` naming it (never blamed on the
xacro), then replaced. Writes go to a temporary file renamed over the entry (atomic).
Renders never land in the shipped model folders or the checkout holding them: a cache
folder there is replaced by the default, with a warning.
"""

from __future__ import annotations

import hashlib
import json
import os
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from rcm_pin.model.packages import PackageSearch
from rcm_pin.model.resources import data_dir

#: Version of the entry layout (part of every key).
FORMAT = 1


class CacheWarning(UserWarning):
    """A cache entry or folder that was not used (the message says which and why)."""


@dataclass(frozen=True)
class Rendering:
    """One render and what it depended on.

    Attributes:
        urdf: the URDF text.
        deps: (absolute path, SHA-256) of every file xacro read, the main file included.
        finds: (package, folder) of every ``$(find)`` answered.
        env: (variable, value or None when unset) of every ``$(env)`` / ``$(optenv)``.
    """

    urdf: str
    deps: tuple[tuple[str, str], ...]
    finds: tuple[tuple[str, str], ...] = ()
    env: tuple[tuple[str, str | None], ...] = ()

    def payload(self) -> dict[str, object]:
        """The JSON fields of the entry (without its checksum)."""
        return {"format": FORMAT, "urdf": self.urdf, "deps": self.deps, "finds": self.finds,
                "env": self.env}  # fmt: skip


_memory: dict[str, Rendering] = {}
_redirected: set[str] = set()


def file_digest(path: str | Path) -> str | None:
    """SHA-256 of a file's bytes (None: unreadable)."""
    try:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest()
    except OSError:
        return None


def cache_key(
    path: str | Path, args: Mapping[str, str], search: PackageSearch | None = None
) -> str:
    """Key of a render: the main file (absolute path, content), arguments, package search."""
    p = Path(path).resolve()
    digest = hashlib.sha256(f"format={FORMAT}\0main={p}\0".encode())
    digest.update(p.read_bytes())
    for name in sorted(args):
        digest.update(f"\0{name}={args[name]}".encode())
    digest.update(f"\0{(search or PackageSearch()).key()}".encode())
    return digest.hexdigest()


def _protected() -> list[Path]:
    folders = [data_dir("xacro").resolve(), data_dir("urdf").resolve()]
    package = Path(__file__).resolve().parents[1]
    return [package, *folders, *(f.parent for f in folders)]


def render_dir() -> Path:
    """The folder of rendered entries (``$RCM_PIN_CACHE/xacro-renders``), never inside the
    shipped model folders, the package or the checkout holding them (then the default)."""
    default = Path.home() / ".cache" / "rcm-pin"
    root = Path(os.environ.get("RCM_PIN_CACHE", default))
    resolved = root.resolve()
    inside = [p for p in _protected() if resolved == p or p in resolved.parents]
    if inside and str(root) not in _redirected:
        _redirected.add(str(root))  # said once a process
        warnings.warn(
            f"RCM_PIN_CACHE={root} is inside {inside[0]} (the shipped models or their "
            f"checkout); renders cached in {default} instead",
            CacheWarning,
            stacklevel=3,
        )
    if inside:
        root = default
    return root / "xacro-renders"


def _checksum(payload: Mapping[str, object]) -> str:
    text = json.dumps(payload, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def current(entry: Rendering, search: PackageSearch) -> bool:
    """Whether every file and package the render read is still as it was."""
    if any(file_digest(path) != sha for path, sha in entry.deps):
        return False
    if any(os.environ.get(name) != value for name, value in entry.env):
        return False
    try:
        return all(str(search.find(name)) == folder for name, folder in entry.finds)
    except LookupError:
        return False


def _read_disk(disk: Path) -> Rendering | None:
    try:
        document = json.loads(disk.read_text())
        fields = {k: document[k] for k in ("format", "urdf", "deps", "finds", "env")}
        if document.get("sha256") != _checksum(fields) or fields["format"] != FORMAT:
            raise ValueError("its checksum does not match its contents")
        return Rendering(
            str(fields["urdf"]),
            tuple((str(p), str(s)) for p, s in fields["deps"]),
            tuple((str(n), str(f)) for n, f in fields["finds"]),
            tuple((str(n), None if v is None else str(v)) for n, v in fields["env"]),
        )
    except (OSError, UnicodeDecodeError, ValueError, KeyError, TypeError) as exc:
        reason = "not valid JSON" if isinstance(exc, json.JSONDecodeError) else str(exc)
        warnings.warn(
            f"render cache entry {disk} is damaged ({reason}); rendered again and replaced",
            CacheWarning,
            stacklevel=4,
        )
        return None


def lookup(key: str, search: PackageSearch) -> str | None:
    """The cached URDF of ``key`` if still current (memory, then disk), else None."""
    entry = _memory.get(key)
    if entry is None:
        disk = render_dir() / f"{key}.json"
        if not disk.exists():
            return None
        entry = _read_disk(disk)
    if entry is None or not current(entry, search):
        _memory.pop(key, None)
        return None
    _memory[key] = entry
    return entry.urdf


def store(key: str, entry: Rendering) -> None:
    """Keep ``entry`` in memory and on disk (temporary file, then atomic rename); a
    read-only cache folder only skips the disk."""
    _memory[key] = entry
    payload = entry.payload()
    document = json.dumps({**payload, "sha256": _checksum(json.loads(json.dumps(payload)))})
    from rcm_pin.processes import atomic_write  # only on a render: not at import

    folder = render_dir()
    try:
        folder.mkdir(parents=True, exist_ok=True)
        atomic_write(folder / f"{key}.json", document.encode())
    except OSError:  # a read-only cache still renders, only not kept on disk
        pass


__all__ = ["CacheWarning", "Rendering", "cache_key", "current", "file_digest", "lookup"]
__all__ += ["render_dir", "store"]

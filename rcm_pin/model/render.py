"""Xacro rendering with argument validation and a content-hash cache.

A rendered URDF is cached under a key made of the SHA-256 of every ``*.xacro`` file in
the model's directory (so an edited include invalidates the cache too) and of the
sorted argument mapping. The cache lives in memory and on disk in
``$RCM_PIN_CACHE`` (default ``~/.cache/rcm-pin``).
"""

from __future__ import annotations

import hashlib
import math
import os
import re
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from functools import lru_cache
from pathlib import Path

from rcm_pin.errors import XacroArgumentError

_XACRO_NS = "{http://www.ros.org/wiki/xacro}"
_TRUE = {"true", "1", "yes", "on"}
_FALSE = {"false", "0", "no", "off"}
_memory: dict[str, str] = {}


def cache_dir() -> Path:
    """Directory of the on-disk render cache (``$RCM_PIN_CACHE`` or ``~/.cache/rcm-pin``)."""
    return Path(os.environ.get("RCM_PIN_CACHE", Path.home() / ".cache" / "rcm-pin"))


@lru_cache(maxsize=64)
def _declared_args_cached(path: str, mtime_ns: int) -> dict[str, str]:
    declared: dict[str, str] = {}
    root = ET.parse(path).getroot()
    for element in root.iter(f"{_XACRO_NS}arg"):
        declared[element.attrib["name"]] = element.attrib.get("default", "")
    for element in root.iter(f"{_XACRO_NS}include"):
        filename = element.attrib.get("filename", "")
        if "$(" in filename:
            continue
        included = Path(path).parent / filename
        if included.exists():
            declared.update(declared_args(included))
    return declared


def declared_args(path: str | Path) -> dict[str, str]:
    """The ``xacro:arg`` names of a xacro file (and its includes) with their defaults."""
    p = Path(path)
    return dict(_declared_args_cached(str(p), p.stat().st_mtime_ns))


def _normalise(name: str, value: object, default: str) -> str:
    """Check one argument against the kind of its default and return its text."""
    text = str(value).strip() if not isinstance(value, bool) else str(value).lower()
    if default.lower() in _TRUE | _FALSE:
        if text.lower() not in _TRUE | _FALSE:
            raise XacroArgumentError(
                f"xacro argument {name}={value!r} is not a boolean; valid: true or false"
            )
        return "true" if text.lower() in _TRUE else "false"
    if _is_number(default):
        if not _is_number(text):
            raise XacroArgumentError(
                f"xacro argument {name}={value!r} is not a finite number; "
                f"valid: a finite number (default {default})"
            )
        return text
    if not re.fullmatch(r"[A-Za-z0-9_.\-]+", text):
        raise XacroArgumentError(
            f"xacro argument {name}={value!r} has characters outside [A-Za-z0-9_.-]"
        )
    return text


def _is_number(text: str) -> bool:
    try:
        return math.isfinite(float(text))
    except ValueError:
        return False


def validate_args(path: str | Path, args: Mapping[str, object]) -> dict[str, str]:
    """Validate xacro arguments against the file's declarations.

    Args:
        path: xacro file.
        args: argument name -> value (numbers, booleans or strings).

    Returns:
        The arguments as xacro text values.

    Raises:
        XacroArgumentError: unknown name (the message lists the valid names) or a value
            of the wrong kind (a number where the default is a number, true/false where
            it is a boolean).
    """
    declared = declared_args(path)
    out: dict[str, str] = {}
    for name, value in args.items():
        if name not in declared:
            raise XacroArgumentError(
                f"unknown xacro argument {name!r} for {Path(path).name}; "
                f"valid: {', '.join(sorted(declared))}"
            )
        out[name] = _normalise(name, value, declared[name])
    return out


def cache_key(path: str | Path, args: Mapping[str, str]) -> str:
    """SHA-256 of the xacro sources beside ``path`` and of the sorted arguments."""
    digest = hashlib.sha256()
    p = Path(path).resolve()
    digest.update(f"main={p.name}\0".encode())  # which file is rendered, not only the set
    for source in sorted({p, *p.parent.glob("*.xacro")}):
        digest.update(source.name.encode())
        digest.update(source.read_bytes())
    for name in sorted(args):
        digest.update(f"\0{name}={args[name]}".encode())
    return digest.hexdigest()


def _strip_banner(urdf: str) -> str:
    """Drop xacro's banner comment, which names the (machine-specific) source path."""
    lines = [line for line in urdf.splitlines() if not re.match(r"\s*<!-- [=|]", line)]
    return "\n".join(lines) + "\n"


def render_xacro(path: str | Path, args: Mapping[str, object] | None = None) -> str:
    """Render a xacro file to URDF text, validating arguments, with caching.

    Args:
        path: the ``.xacro`` file.
        args: xacro arguments (``name -> value``); unknown names are an error.

    Returns:
        The URDF XML text.

    Raises:
        XacroArgumentError: bad argument, or xacro failed on the given values.
    """
    import xacro  # local import: xacro is slow to import and not needed for cached reads

    p = Path(path)
    if not p.exists():
        raise XacroArgumentError(f"xacro file {p} does not exist")
    text_args = validate_args(p, args or {})
    key = cache_key(p, text_args)
    if key in _memory:
        return _memory[key]
    disk = cache_dir() / "urdf" / f"{key}.urdf"
    if disk.exists():
        _memory[key] = disk.read_text()
        return _memory[key]
    try:
        document = xacro.process_file(str(p), mappings=text_args)  # type: ignore[attr-defined]
    except Exception as exc:  # xacro raises its own XacroException and NameError
        raise XacroArgumentError(f"xacro failed on {p.name} with {text_args}: {exc}") from exc
    urdf = _strip_banner(document.toprettyxml(indent="  "))
    _memory[key] = urdf
    try:
        disk.parent.mkdir(parents=True, exist_ok=True)
        tmp = disk.with_suffix(f".{os.getpid()}.tmp")
        tmp.write_text(urdf)
        tmp.replace(disk)
    except OSError:
        pass  # a read-only home still renders, only uncached on disk
    return urdf

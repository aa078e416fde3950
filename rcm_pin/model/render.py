"""Xacro rendering with argument validation and a content-hash cache.

Arguments are validated before rendering against the kinds and ranges documented in the
xacro itself (:mod:`rcm_pin.model.xacro_ranges`).

A rendered URDF is cached under a key made of the SHA-256 of every ``*.xacro`` file in
the model's directory (so an edited include invalidates the cache too) and of the
sorted argument mapping. The cache lives in memory and on disk in
``$RCM_PIN_CACHE`` (default ``~/.cache/rcm-pin``).
"""

from __future__ import annotations

import hashlib
import os
import re
from collections.abc import Mapping
from pathlib import Path

from rcm_pin.errors import UntrustedXacroError, XacroArgumentError
from rcm_pin.model.xacro_guard import process_file
from rcm_pin.model.xacro_ranges import check_pairs, check_value, declared_specs
from rcm_pin.model.xacro_safety import check_file

_memory: dict[str, str] = {}


def cache_dir() -> Path:
    """Directory of the on-disk render cache (``$RCM_PIN_CACHE`` or ``~/.cache/rcm-pin``)."""
    return Path(os.environ.get("RCM_PIN_CACHE", Path.home() / ".cache" / "rcm-pin"))


def declared_args(path: str | Path) -> dict[str, str]:
    """The ``xacro:arg`` names of a xacro file (and its includes) with their defaults."""
    return {name: spec.default for name, spec in declared_specs(path).items()}


def validate_args(path: str | Path, args: Mapping[str, object]) -> dict[str, str]:
    """Validate xacro arguments against the file's documented declarations.

    The kinds and ranges come from the xacro's own comments (the convention of
    :mod:`rcm_pin.model.xacro_ranges`); every limit pair is checked after merging the
    given arguments with the defaults.

    Args:
        path: xacro file.
        args: argument name -> value (numbers, booleans or strings).

    Returns:
        The given arguments as xacro text values.

    Raises:
        XacroArgumentError: unknown name (the message lists the valid names); a value of
            the wrong kind, not finite, out of its documented range or not one of its
            enumerated values; a limit pair with lower >= upper. The message names the
            argument, the value and the valid range with its unit.
    """
    p = Path(path)
    specs = declared_specs(p)
    out: dict[str, str] = {}
    for name, value in args.items():
        if name not in specs:
            raise XacroArgumentError(
                f"unknown xacro argument {name!r} for {p.name}; valid: {', '.join(sorted(specs))}"
            )
        out[name] = check_value(specs[name], value, p.name)
    check_pairs(specs, out, p.name)
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


def render_xacro(
    path: str | Path, args: Mapping[str, object] | None = None, *, trusted: bool = False
) -> str:
    """Render a xacro file to URDF text, validating arguments, with caching.

    Args:
        path: the ``.xacro`` file.
        args: xacro arguments (``name -> value``); unknown names are an error.
        trusted: the caller vouches for the file; False (default): its expressions must
            pass the allow-list of :mod:`rcm_pin.model.xacro_safety` (data, not code).

    Returns:
        The URDF XML text.

    Raises:
        XacroArgumentError: bad argument, or xacro failed on the given values.
        UntrustedXacroError: an untrusted file with an expression off the allow-list.
    """
    p = Path(path)
    if not p.exists():
        raise XacroArgumentError(f"xacro file {p} does not exist")
    if not trusted:
        check_file(p)  # before the cache too: a file is refused the same way every time
    text_args = validate_args(p, args or {})
    key = cache_key(p, text_args)
    if key in _memory:
        return _memory[key]
    disk = cache_dir() / "urdf" / f"{key}.urdf"
    if disk.exists():
        _memory[key] = disk.read_text()
        return _memory[key]
    try:  # xacro is imported there: slow to import and not needed for cached reads
        document = process_file(p, text_args, trusted=trusted)
    except UntrustedXacroError:
        raise
    except Exception as exc:  # xacro raises its own XacroException and NameError
        given = ", ".join(sorted(text_args)) or "none"
        first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise XacroArgumentError(
            f"xacro failed on {p.name} (arguments given: {given}): {first}"
        ) from exc
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

"""Xacro rendering with argument validation and a verified render cache.

Arguments are validated before rendering against the kinds and ranges documented in the
xacro itself (:mod:`rcm_pin.model.xacro_ranges`). ``$(find pkg)`` is answered by
:mod:`rcm_pin.model.packages` (no ROS needed). A rendered URDF is cached by
:mod:`rcm_pin.model.render_cache`, keyed on every file xacro read, the arguments and the
package search, and verified on every read.
"""

from __future__ import annotations

import re
import threading
from collections.abc import Mapping
from pathlib import Path

from rcm_pin.errors import PackageNotFoundError, UntrustedXacroError, XacroArgumentError
from rcm_pin.model import render_cache
from rcm_pin.model.packages import PackageSearch, find_hook
from rcm_pin.model.render_cache import cache_key, file_digest
from rcm_pin.model.xacro_guard import process_file
from rcm_pin.model.xacro_ranges import check_pairs, check_value, declared_specs
from rcm_pin.model.xacro_safety import check_file

#: xacro keeps its state in module globals: one render at a time.
_XACRO_LOCK = threading.Lock()


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


def _strip_banner(urdf: str) -> str:
    """Drop xacro's banner comment, which names the (machine-specific) source path."""
    lines = [line for line in urdf.splitlines() if not re.match(r"\s*<!-- [=|]", line)]
    return "\n".join(lines) + "\n"


def render_xacro(
    path: str | Path,
    args: Mapping[str, object] | None = None,
    *,
    search: PackageSearch | None = None,
    trusted: bool = False,
) -> str:
    """Render a xacro file to URDF text, validating arguments, with caching.

    Args:
        path: the ``.xacro`` file.
        args: xacro arguments (``name -> value``); unknown names are an error.
        search: where ``$(find pkg)`` looks (default: the environment and the folders
            above ``path``, :mod:`rcm_pin.model.packages`).
        trusted: the caller vouches for the file; False (default): its expressions must
            pass the allow-list of :mod:`rcm_pin.model.xacro_safety` (data, not code).

    Returns:
        The URDF XML text.

    Raises:
        XacroArgumentError: bad argument, or xacro failed on the given values.
        PackageNotFoundError: a ``$(find pkg)`` package found nowhere.
        UntrustedXacroError: an untrusted file with an expression off the allow-list.
    """
    p = Path(path)
    if not p.exists():
        raise XacroArgumentError(f"xacro file {p} does not exist")
    if not trusted:
        check_file(p)  # before the cache too: a file is refused the same way every time
    text_args = validate_args(p, args or {})
    search = search or PackageSearch(near=p)
    key = cache_key(p, text_args, search)
    cached = render_cache.lookup(key, search)
    if cached is not None:
        return cached
    urdf, entry = _run_xacro(p, text_args, search, trusted)
    render_cache.store(key, entry)
    return urdf


def _package_error(exc: BaseException) -> PackageNotFoundError | None:
    """The PackageNotFoundError xacro wrapped in its own exceptions, if any."""
    seen: BaseException | None = exc
    while seen is not None and not isinstance(seen, PackageNotFoundError):
        seen = getattr(seen, "exc", None) or seen.__cause__ or seen.__context__
    return seen


def _run_xacro(
    p: Path, text_args: dict[str, str], search: PackageSearch, trusted: bool
) -> tuple[str, render_cache.Rendering]:
    """xacro on ``p``: the URDF text and what it read."""
    import xacro  # local import: xacro is slow to import and not needed for cached reads

    with _XACRO_LOCK, find_hook(search) as reads:
        xacro.all_includes.clear()  # type: ignore[attr-defined]
        try:
            document = process_file(p, text_args, trusted=trusted)
        except UntrustedXacroError:
            raise
        except Exception as exc:  # xacro raises its own XacroException and NameError
            missing = _package_error(exc)
            if missing is not None:
                raise PackageNotFoundError(f"{p.name}: {missing}") from None
            given = ", ".join(sorted(text_args)) or "none"
            first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            raise XacroArgumentError(
                f"xacro failed on {p.name} (arguments given: {given}): {first}"
            ) from exc
        read = {str(p.resolve()), *(str(Path(f).resolve()) for f in xacro.all_includes)}  # type: ignore[attr-defined]
        finds = tuple(sorted((name, str(folder)) for name, folder in reads.found.items()))
        env = tuple(sorted(reads.env.items()))
    urdf = _strip_banner(document.toprettyxml(indent="  "))
    deps = tuple((f, file_digest(f) or "") for f in sorted(read))
    return urdf, render_cache.Rendering(urdf, deps, finds, env)

"""Rendering an untrusted xacro file: the allow-list enforced while xacro runs.

:func:`rcm_pin.model.xacro_safety.check_file` checks the file and the includes it can
resolve before anything is evaluated. What only xacro can resolve is checked when xacro
reaches it: while an untrusted file renders, xacro's ``parse`` checks each file it
includes (an include named by ``${…}``, ``$(arg …)`` or ``$(find …)``) before reading it,
and its ``safe_eval`` and ``$(eval …)`` check each expression as it is about to be
evaluated, after substitution (an argument's value or default spliced into an
expression is checked too). Nothing that fails the allow-list is evaluated.
"""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

from rcm_pin.errors import UntrustedXacroError
from rcm_pin.model.xacro_safety import check_expression, check_file

#: xacro keeps its state in module globals: one render at a time changes its hooks.
_LOCK = threading.RLock()


def _current_file(xacro: Any, default: Path) -> str:
    stack = getattr(xacro, "filestack", None) or [None]
    return str(stack[-1] or default)


@contextlib.contextmanager
def _guarded(main: Path, checked: set[Path]) -> Iterator[Any]:
    """xacro with its ``parse``, ``safe_eval`` and ``$(eval …)`` checking first
    (``checked``: the files already checked)."""
    import importlib

    xacro: Any = importlib.import_module("xacro")
    subst: Any = importlib.import_module("xacro.substitution_args")
    parse, safe_eval, eval_subst = xacro.parse, xacro.safe_eval, subst._eval

    def checked_parse(inp: Any, filename: Any = None) -> Any:
        if inp is None and filename:
            path = Path(filename).resolve()
            if path not in checked:
                checked.update(check_file(path))
        return parse(inp, filename)

    def checked_eval(expr: str, globals: Any, locals: Any = None) -> Any:
        check_expression(expr, _current_file(xacro, main), None)
        return safe_eval(expr, globals, locals)

    def checked_subst(s: str, context: Any) -> Any:
        check_expression(s, _current_file(xacro, main), None, kind="$(eval")
        return eval_subst(s, context)

    with _LOCK:
        xacro.parse, xacro.safe_eval, subst._eval = checked_parse, checked_eval, checked_subst
        try:
            yield xacro
        finally:
            xacro.parse, xacro.safe_eval, subst._eval = parse, safe_eval, eval_subst


def _untrusted_cause(exc: BaseException) -> UntrustedXacroError | None:
    """The :class:`UntrustedXacroError` that xacro wrapped in its own exception, if any."""
    seen: set[int] = set()
    todo: list[BaseException | None] = [exc]
    while todo:
        e = todo.pop()
        if e is None or id(e) in seen:
            continue
        seen.add(id(e))
        if isinstance(e, UntrustedXacroError):
            return e
        inner = getattr(e, "exc", None)
        todo += [inner if isinstance(inner, BaseException) else None, e.__cause__, e.__context__]
    return None


def process_file(path: Path, mappings: Mapping[str, str], *, trusted: bool) -> Any:
    """xacro's DOM document of ``path``; an untrusted file under the allow-list.

    Args:
        path: the xacro file.
        mappings: xacro arguments (text values).
        trusted: the user vouches for the file: xacro runs it as it is.

    Raises:
        UntrustedXacroError: an untrusted file (or one it includes) with an expression that
            is not allowed; nothing of it was evaluated.
        Exception: whatever xacro raises on a bad file (callers wrap it).
    """
    if trusted:
        import xacro

        return xacro.process_file(str(path), mappings=dict(mappings))  # type: ignore[attr-defined]
    checked = set(check_file(path))
    try:
        with _guarded(path, checked) as guarded:
            return guarded.process_file(str(path), mappings=dict(mappings))
    except UntrustedXacroError:
        raise
    except Exception as exc:
        found = _untrusted_cause(exc)
        if found is not None:
            raise found from None
        raise


__all__ = ["process_file"]

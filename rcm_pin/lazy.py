"""Lazy imports that keep ``import rcm_pin`` cheap (no scipy, casadi, matplotlib or pandas).

A package's re-exports (PEP 562) are imported from their submodules on first access, and
the LAPACK routines of ``scipy.linalg`` (slow to import) on first call
(``tests/test_startup.py`` checks what ``import rcm_pin`` loads)."""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping
from functools import cache
from typing import Any


def lazy_exports(
    package: str, table: Mapping[str, str]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The module-level ``__getattr__`` and ``__dir__`` of ``package`` for ``table``
    (name → submodule of ``package``); a resolved name is cached in the package."""
    namespace = sys.modules[package].__dict__

    def get(name: str) -> Any:
        module = table.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(f"{package}.{module}"), name)
        namespace[name] = value
        return value

    def names() -> list[str]:
        return sorted({*namespace, *table})

    return get, names


@cache
def lapack(routine: str) -> Callable[..., Any]:
    """The LAPACK routine ``routine`` (e.g. ``"dposv"``) of ``scipy.linalg.lapack``, imported
    on first use and kept: the hot paths call it for ~50 ns more than a module attribute."""
    from scipy.linalg import lapack as routines

    return getattr(routines, routine)  # type: ignore[no-any-return]


__all__ = ["lapack", "lazy_exports"]

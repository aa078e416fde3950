"""Lazy imports that keep ``import rcm_pin`` cheap (no scipy, casadi, matplotlib or pandas).

A package's re-exports (PEP 562) are imported from their submodules on first access, and
the LAPACK routines of ``scipy.linalg`` (slow to import) on first call
(``tests/test_startup.py`` checks what ``import rcm_pin`` loads)."""

from __future__ import annotations

import importlib
import sys
import types
from collections.abc import Callable, Collection, Mapping
from functools import cache
from typing import Any


def lazy_exports(
    package: str, table: Mapping[str, str]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The module-level ``__getattr__`` and ``__dir__`` of ``package`` for ``table``
    (name → submodule of ``package``, or ``"submodule:attribute"`` to export an attribute
    under another name); a resolved name is cached in the package."""
    namespace = sys.modules[package].__dict__

    def get(name: str) -> Any:
        target = table.get(name)
        if target is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        module, _, attribute = target.partition(":")
        value = getattr(importlib.import_module(f"{package}.{module}"), attribute or name)
        namespace[name] = value
        return value

    def names() -> list[str]:
        return sorted({*namespace, *table})

    return get, names


def lazy_modules(
    package: str, names: Collection[str]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The module-level ``__getattr__`` and ``__dir__`` of ``package`` that make each of
    ``names`` (submodules of ``package``) an attribute, imported on first access: after
    ``from rcm_pin.mechanisms import rcm``, ``rcm.workspace`` is the module
    ``rcm_pin.mechanisms.rcm.workspace`` whether or not something imported it before.

    Raises:
        AttributeError: on access to a name that is not one of ``names``.
    """
    namespace = sys.modules[package].__dict__
    public = frozenset(names)

    def get(name: str) -> Any:
        if name not in public:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        return importlib.import_module(f"{package}.{name}")  # sets it on the package

    def listing() -> list[str]:
        return sorted({*namespace, *public})

    return get, listing


def keep_functions(package: str, names: Collection[str]) -> None:
    """Make each of ``names`` in ``package`` stay the function of that name when the
    submodule of the same name is imported (the import system sets a loaded submodule as
    an attribute of its package, which would otherwise shadow the re-exported function)."""

    class _Package(types.ModuleType):
        def __setattr__(self, name: str, value: object) -> None:
            if name in names and isinstance(value, types.ModuleType):
                value = getattr(value, name)
            super().__setattr__(name, value)

    module = sys.modules[package]
    module.__class__ = _Package
    for name in names:  # a submodule imported before the package finished
        if isinstance(module.__dict__.get(name), types.ModuleType):
            setattr(module, name, module.__dict__[name])


@cache
def lapack(routine: str) -> Callable[..., Any]:
    """The LAPACK routine ``routine`` (e.g. ``"dposv"``) of ``scipy.linalg.lapack``, imported
    on first use and kept: the hot paths call it for ~50 ns more than a module attribute."""
    from scipy.linalg import lapack as routines

    return getattr(routines, routine)  # type: ignore[no-any-return]


__all__ = ["keep_functions", "lapack", "lazy_exports", "lazy_modules"]

"""Lazy re-exports of a package (PEP 562): a name is imported from its submodule on first
access, so that importing the package stays cheap (``import rcm_pin`` loads no scipy,
casadi, matplotlib or pandas; ``tests/test_startup.py``)."""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping
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


__all__ = ["lazy_exports"]

"""The code hash of a design's rows: every source its metrics run, and the package versions.

:func:`code_hash` (16 hex digits) is the SHA-256 of

* the sources of every module of ``rcm_pin`` and ``ocp`` that :mod:`rcm_pin.design.evaluate`
  or the mechanism's family imports, directly or not: the import graph, built from the
  sources with the standard library's :mod:`ast` (every ``import`` statement, those inside
  functions included, so lazy imports count; no module is imported to build it);
* the modules of the kernel providers (entry points of ``rcm_pin.kernels``, e.g.
  ``ocp.kernels``), which the closed mechanisms' solves load at run time, and everything
  they import;
* every xacro file (the designs' models);
* the versions of Python and of the numerical packages (:data:`PACKAGES`).

A row carries the hash it was computed under (``model_hash``); a rerun recomputes a design
whose hash changed, and a worker whose own hash differs from the client's refuses its chunk
(:func:`rcm_pin.design.evaluate.evaluate_chunk`).
"""

from __future__ import annotations

import ast
import hashlib
import inspect
import platform
from functools import cache
from importlib import metadata
from pathlib import Path

from rcm_pin.catalog.table import get_entry
from rcm_pin.model.resources import xacro_dir

#: Packages whose versions enter the hash.
PACKAGES = ("pin", "casadi", "numpy", "scipy", "xacro", "example-robot-data")
#: Entry-point group of the kernel providers (rcm_pin.model.kernels.GROUP).
KERNELS = "rcm_pin.kernels"
_ROOT = Path(__file__).resolve().parents[2]
_PACKAGES_SCANNED = ("rcm_pin", "ocp")


@cache
def _modules() -> dict[str, Path]:
    """Module name -> source file, for every module of ``rcm_pin`` and ``ocp``."""
    out = {}
    for package in _PACKAGES_SCANNED:
        for path in sorted((_ROOT / package).rglob("*.py")):
            parts = path.relative_to(_ROOT).with_suffix("").parts
            out[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return out


@cache
def _imports(module: str) -> frozenset[str]:
    """Modules of ``rcm_pin`` / ``ocp`` that ``module``'s source imports (anywhere in it),
    and the packages above each of them (importing ``a.b.c`` runs ``a`` and ``a.b``)."""
    known = _modules()
    path = known[module]
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_bytes(), str(path))):
        if isinstance(node, ast.Import):
            names.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join([*up, base] if base else up)
            names.add(base)
            names.update(f"{base}.{a.name}" for a in node.names)  # from pkg import module
    found = set()
    for name in names:
        parts = name.split(".")
        for i in range(1, len(parts) + 1):
            if ".".join(parts[:i]) in known:
                found.add(".".join(parts[:i]))
    return frozenset(found - {module})


def upstream(roots: set[str]) -> set[str]:
    """``roots`` and every module of ``rcm_pin`` / ``ocp`` they import, directly or not."""
    seen: set[str] = set()
    todo = [r for r in roots if r in _modules()]
    while todo:
        name = todo.pop()
        if name not in seen:
            seen.add(name)
            todo.extend(_imports(name) - seen)
    return seen


def kernel_modules() -> set[str]:
    """The modules of the kernel providers (entry points of :data:`KERNELS`) and every
    module of their packages."""
    names = {ep.module for ep in metadata.entry_points(group=KERNELS)}
    return {m for m in _modules() for n in names if m == n or m.startswith(n + ".")}


def _version(package: str) -> str:
    try:
        return metadata.version(package)
    except metadata.PackageNotFoundError:
        return "-"


def family_module(mechanism: str) -> str:
    """The module defining the mechanism's family class."""
    return type(get_entry(mechanism).family).__module__


@cache
def code_hash(mechanism: str) -> str:
    """The hash of what a design's rows depend on (module docstring), 16 hex digits."""
    roots = {"rcm_pin.design.evaluate", family_module(mechanism), *kernel_modules()}
    family = type(get_entry(mechanism).family)
    family_file = Path(inspect.getfile(family))
    if family_file.name == "__init__.py":  # a family package: all of it
        prefix = family.__module__ + "."
        roots.update(m for m in _modules() if m.startswith(prefix))
    digest = hashlib.sha256()
    for name in sorted(upstream(roots)):
        digest.update(
            f"{name}:{hashlib.sha256(_modules()[name].read_bytes()).hexdigest()}\n".encode()
        )
    for path in sorted(xacro_dir().glob("*.xacro")):
        digest.update(f"{path.name}:{hashlib.sha256(path.read_bytes()).hexdigest()}\n".encode())
    versions = [f"{p}={_version(p)}" for p in PACKAGES] + [platform.python_version()]
    digest.update(" ".join(versions).encode())
    return digest.hexdigest()[:16]


__all__ = ["KERNELS", "PACKAGES", "code_hash", "family_module", "kernel_modules", "upstream"]

"""Running the report's sections: in parallel processes, each cached by what it depends on.

A run holds the lock of ``out`` (:func:`rcm_pin.processes.folder_lock`: a second run on
the same folder exits with :class:`~rcm_pin.errors.FolderBusyError` naming the holder's
PID). Each section runs in a folder of its own inside the run's private work folder
(``out/.work/<pid>-<random>/<slug>``) so that sections running at the same time never mix
their files; its files are then moved into ``out`` by rename (the markdown refers to them
by bare names, so the links stay valid) and only then is its cache entry written. Work
folders left by a killed run are removed by the next run (it holds the lock, so no other
run is using them). Pool processes die with the run (:func:`rcm_pin.processes.process_pool`).

**Cache.** A section's result (title, markdown, figures, the files it wrote and their
hashes, a checksum of it all: :mod:`rcm_pin.report.cache`) is kept in
``out/.cache/<slug>.json`` under a key, the SHA-256 of

* the sources of every module the section's module imports, directly or not (the import
  graph of ``rcm_pin`` and ``ocp`` built by grimp, the library behind import-linter, from
  the ``[report]`` extra), and its own source; without grimp, the sources of every module
  of ``rcm_pin`` and ``ocp`` (a superset: never stale, but any edit recomputes every
  section);
* the same for the kernel providers (the entry points of ``rcm_pin.kernels``, e.g.
  ``ocp.kernels``, every module of their packages and what they import), which every
  closed-mechanism solve loads at run time without a static import;
* every file of ``xacro/`` and ``urdf/`` (the models the sections load);
* the versions of the numerical packages (Pinocchio, CasADi, NumPy, SciPy, matplotlib,
  example-robot-data) and of Python.

A rerun reuses a section when its entry is intact (checksum), its key is unchanged and
every file it names is still in ``out`` with the same hash; a damaged entry is recomputed
with a :class:`~rcm_pin.report.cache.CacheWarning`; ``cache=False`` (``--no-cache``)
recomputes everything.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import platform
import secrets
import shutil
import sys
import time
from collections.abc import Callable, Iterator
from concurrent.futures import as_completed
from dataclasses import dataclass
from functools import cache, lru_cache
from importlib import metadata
from pathlib import Path

from rcm_pin.errors import MissingExtraError, require
from rcm_pin.model.resources import urdf_dir, xacro_dir
from rcm_pin.processes import folder_lock, process_pool, remove_temporaries
from rcm_pin.report.cache import file_sha, read_entry, write_entry
from rcm_pin.report.framework import Section

SectionFn = Callable[[Path], Section]
#: Entry-point group of the kernel providers (rcm_pin.model.kernels.GROUP).
KERNELS = "rcm_pin.kernels"
#: Packages whose versions enter every cache key.
PACKAGES = ("pin", "casadi", "numpy", "scipy", "matplotlib", "example-robot-data")


@dataclass(frozen=True)
class Outcome:
    """One section's result: the section, its run time [s] and whether it came from cache."""

    name: str
    section: Section
    seconds: float
    cached: bool


def slug(name: str) -> str:
    """A file-name form of a section's name."""
    return "".join(c if c.isalnum() else "_" for c in name).strip("_")


def _sha(path: Path) -> str:
    st = path.stat()
    return _sha_of(str(path), st.st_mtime_ns, st.st_size)


@lru_cache(maxsize=4096)
def _sha_of(path: str, mtime_ns: int, size: int) -> str:
    """SHA-256 of a file, computed once per (path, modification time, size) in a process."""
    return file_sha(Path(path))


@lru_cache(maxsize=1)
def _models_digest() -> str:
    """One digest of every file of ``xacro/`` and ``urdf/`` (shared by all section keys)."""
    digest = hashlib.sha256()
    for folder in (xacro_dir(), urdf_dir()):
        for path in sorted(folder.rglob("*")):
            if path.is_file():
                digest.update(f"{path.name}:{_sha(path)}\n".encode())
    return digest.hexdigest()


@lru_cache(maxsize=1)
def _graph() -> object | None:
    """The import graph of ``rcm_pin`` and ``ocp``, or None without grimp (the ``[report]``
    extra)."""
    try:
        grimp = require("report", "grimp")
    except MissingExtraError:
        return None
    return grimp.build_graph("rcm_pin", "ocp", cache_dir=None)


@lru_cache(maxsize=1)
def _every_module() -> frozenset[str]:
    """Every module of ``rcm_pin`` and ``ocp``, from their source files (no import)."""
    root = Path(__file__).resolve().parents[2]
    names = set()
    for package in ("rcm_pin", "ocp"):
        for path in (root / package).rglob("*.py"):
            parts = path.relative_to(root).with_suffix("").parts
            names.add(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
    return frozenset(names)


@cache
def _module_file(module: str) -> Path | None:
    """The source file of a module of ``rcm_pin`` or ``ocp`` (or one already imported),
    found without importing it (importing would run a package's whole ``__init__``)."""
    root = Path(__file__).resolve().parents[2]
    base = root.joinpath(*module.split("."))
    for path in (base.with_suffix(".py"), base / "__init__.py"):
        if path.is_file():
            return path
    loaded = sys.modules.get(module)
    found = getattr(loaded, "__file__", None)
    return Path(found) if found else None


def cache_key(module: str) -> str:
    """The cache key of a section module (module docstring)."""
    graph = _graph()
    if graph is None:  # no import graph: every module (module docstring)
        upstream: set[str] | frozenset[str] = _every_module()
    else:
        upstream = set()
        for root in {module, *_kernel_roots(graph)}:
            if root in graph.modules:  # type: ignore[attr-defined]
                upstream |= {root, *graph.find_upstream_modules(root)}  # type: ignore[attr-defined]
    modules = sorted({module, *upstream})
    digest = hashlib.sha256()
    for name in modules:
        path = _module_file(name)
        if path is not None and path.is_file():
            digest.update(f"{name}:{_sha(path)}\n".encode())
    digest.update(_models_digest().encode())
    versions = [f"{p}={_version(p)}" for p in PACKAGES] + [platform.python_version()]
    digest.update(" ".join(versions).encode())
    return digest.hexdigest()


def _kernel_roots(graph: object) -> set[str]:
    """The kernel providers' modules (entry points of :data:`KERNELS`) and every module of
    their packages."""
    roots = set()
    for ep in metadata.entry_points(group=KERNELS):
        roots.add(ep.module)
        if ep.module in graph.modules:  # type: ignore[attr-defined]
            roots |= graph.find_descendants(ep.module)  # type: ignore[attr-defined]
    return roots


@cache
def _version(package: str) -> str:
    try:
        return metadata.version(package)
    except metadata.PackageNotFoundError:
        return "-"


def _cached(out_dir: Path, name: str, key: str) -> Section | None:
    return read_entry(out_dir, slug(name), key, _sha)


def run_one(
    name: str, module: str, out_dir: Path, key: str, work_root: Path | None = None
) -> Outcome:
    """Run one section in its own work folder (inside ``work_root``, the run's private one),
    move its files out, then record it in the cache."""
    fn = _resolve(module)
    work = (work_root or out_dir / ".work" / f"{os.getpid()}-{secrets.token_hex(4)}") / slug(name)
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    start = time.perf_counter()
    section = fn(work)
    seconds = time.perf_counter() - start
    files = {}
    for path in sorted(p for p in work.rglob("*") if p.is_file()):
        rel = path.relative_to(work)
        (out_dir / rel).parent.mkdir(parents=True, exist_ok=True)
        os.replace(path, out_dir / rel)
        files[str(rel)] = _sha(out_dir / rel)
    shutil.rmtree(work, ignore_errors=True)
    write_entry(out_dir, slug(name), name, key, section, files)
    return Outcome(name, section, seconds, cached=False)


def _resolve(module: str) -> SectionFn:
    """A section module's ``section`` function (imported now)."""
    from rcm_pin.report.sections import section_function

    return section_function(module)


def run_sections(
    chosen: list[tuple[str, str]], out_dir: Path, jobs: int | None = None, cache: bool = True
) -> Iterator[Outcome]:
    """Outcomes of the chosen (name, module) sections, cached ones first, the others as
    they finish, under the lock of ``out_dir``.

    Raises:
        FolderBusyError: another run holds the lock of ``out_dir``.
    """
    jobs = jobs or os.cpu_count() or 1
    with folder_lock(out_dir):
        keys = {name: cache_key(module) for name, module in chosen}
        todo = []
        for name, module in chosen:
            hit = _cached(out_dir, name, keys[name]) if cache else None
            if hit is not None:
                yield Outcome(name, hit, 0.0, cached=True)
            else:
                todo.append((name, module))
        shutil.rmtree(out_dir / ".work", ignore_errors=True)  # left by killed runs: we lock
        for folder in (out_dir, out_dir / ".cache"):
            remove_temporaries(folder)
        work = out_dir / ".work" / f"{os.getpid()}-{secrets.token_hex(4)}"
        try:
            if jobs == 1 or len(todo) <= 1:
                for name, module in todo:
                    yield run_one(name, module, out_dir, keys[name], work)
                return
            with process_pool(min(jobs, len(todo)), [m for _, m in todo]) as pool:
                futures = [pool.submit(run_one, n, m, out_dir, keys[n], work) for n, m in todo]
                for future in as_completed(futures):
                    yield future.result()
        finally:
            shutil.rmtree(work, ignore_errors=True)
            with contextlib.suppress(OSError):
                (out_dir / ".work").rmdir()  # when empty


__all__ = ["Outcome", "cache_key", "run_one", "run_sections", "slug"]

"""CasADi functions compiled to C once and cached on disk.

:func:`compiled` turns a ``casadi.Function`` into a loaded shared library with the same
inputs, outputs and sparsities:

1. C source from CasADi's ``CodeGenerator`` (the function and everything it calls);
2. a key ``sha256(source, compiler, flags, casadi version, key)``; the library is
   ``<cache>/<name>_<key[:20]>.so`` with ``<cache>`` = ``$RCM_PIN_CACHE`` or the user cache
   directory (``$XDG_CACHE_HOME/rcm-pin/casadi``, default ``~/.cache/rcm-pin/casadi``);
3. a hit loads it with ``casadi.external`` once its size and SHA-256 match the record
   beside it (:mod:`ocp.so_cache`: a truncated library would kill the process with
   SIGBUS); a miss, or a damaged entry (rebuilt with a :class:`~ocp.so_cache.CacheWarning`),
   compiles it with the system C compiler (``$CC``, else ``gcc``/``cc``:
   ``<cc> <opt> -shared -fPIC``) to a temporary name in the cache, moves it into place with
   ``os.replace`` and records its checksum (:func:`ocp.so_cache.publish`).

Without a C compiler (or when it fails), or with a cache folder that cannot be written
(read-only, full) and no verified entry in it, the original function is returned, a
:class:`CompileWarning` is issued and :attr:`Compiled.path` is ``None``: results are the
same, only slower. :func:`compile_function` returns that diagnostic record;
:data:`STATS` counts compilations and cache hits in this process (for tests).

Hashing the source needs the function (and its code generation) even on a hit. Callers
that must not build an expensive function on a hit (e.g. symbolic Hessians) use
:func:`compile_lazy`: the hash is of ``name`` and a ``key`` that determines the function
(e.g. the serialised expression it is derived from), and ``build()`` runs only on a miss.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import tempfile
import time
import warnings
from collections import Counter
from collections.abc import Callable
from pathlib import Path
from typing import NamedTuple

import casadi as ca

from ocp import so_cache

#: Compilations (``"compiled"``), cache hits (``"hits"``) and fallbacks (``"fallbacks"``).
STATS: Counter[str] = Counter()


class CompileWarning(UserWarning):
    """No C compiler (or it failed): the uncompiled CasADi function is used."""


class Compiled(NamedTuple):
    """A function from :func:`compile_function` and how it was obtained."""

    function: ca.Function  # the loaded library, or the original function on fallback
    path: Path | None  # the shared library; None: not compiled (fallback)
    cached: bool  # loaded from the cache without compiling
    seconds: float  # [s] wall time of code generation + compilation + loading


def cache_dir() -> Path:
    """``$RCM_PIN_CACHE``, else ``$XDG_CACHE_HOME/rcm-pin/casadi`` (``~/.cache``)."""
    env = os.environ.get("RCM_PIN_CACHE")
    if env:
        return Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "rcm-pin" / "casadi"


def c_compiler() -> str | None:
    """``$CC`` or the first of ``gcc``, ``cc``, ``clang`` on the PATH; None if none."""
    for name in (os.environ.get("CC"), "gcc", "cc", "clang"):
        if name and (path := shutil.which(name)):
            return path
    return None


def _source(fun: ca.Function) -> str:
    cg = ca.CodeGenerator(f"{fun.name()}.c", {"with_header": False})
    cg.add(fun)
    return str(cg.dump())


def compile_function(fun: ca.Function, *, key: str = "", opt: str = "-O1") -> Compiled:
    """Compile ``fun`` (or load it from the cache), keyed by its generated C source.

    Args:
        fun: any CasADi function that code generation supports (SX, or MX of such).
        key: extra text in the hash (e.g. a model or problem fingerprint).
        opt: optimisation flag(s) of the C compiler, space-separated (``-O0`` compiles
            fastest, ``-O1`` is the usual compromise).
    """
    start = time.perf_counter()
    code = _source(fun)
    return _get(fun.name(), code + "\0" + key, lambda: (fun, code), opt, start)


def compile_lazy(
    name: str, key: str, build: Callable[[], ca.Function], *, opt: str = "-O1"
) -> Compiled:
    """Load ``name`` compiled for ``key`` from the cache, or ``build()`` and compile it.

    ``key`` must determine the function (``build`` is not called on a hit); ``build()``
    must return a function called ``name``.
    """

    def make() -> tuple[ca.Function, str]:
        fun = build()
        if fun.name() != name:
            raise ValueError(f"build() made {fun.name()!r}; expected {name!r}")
        return fun, _source(fun)

    return _get(name, "lazy\0" + key, make, opt, time.perf_counter())


def _get(
    name: str,
    text: str,
    make: Callable[[], tuple[ca.Function, str]],
    opt: str,
    start: float,
) -> Compiled:
    """Cache lookup of ``hash(text, compiler, flags, casadi)``; on a miss compile ``make()``."""
    cc, flags = c_compiler(), [*opt.split(), "-shared", "-fPIC"]
    if cc is None:
        return _fallback(make()[0], start, "no C compiler found ($CC, gcc, cc, clang)")
    version = str(ca.__version__)  # type: ignore[attr-defined]
    digest = hashlib.sha256(
        "\0".join([text, os.path.basename(cc), *flags, version]).encode()
    ).hexdigest()[:20]
    folder = cache_dir()
    lib = folder / f"{name}_{digest}.so"
    if so_cache.usable(lib):
        loaded = _load(name, lib)
        if loaded is not None:
            STATS["hits"] += 1
            return Compiled(loaded, lib, True, time.perf_counter() - start)
    fun, code = make()
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryDirectory(dir=folder, prefix=".build_") as tmp:
            src, out = Path(tmp) / f"{name}.c", Path(tmp) / "lib.so"
            src.write_text(code)
            failed = _compile(cc, [*flags, str(src), "-o", str(out), "-lm"])
            if failed:
                return _fallback(fun, start, failed)
            so_cache.publish(out, lib)
    except OSError as exc:  # a read-only (or full) cache folder: the VM serves
        why = f"cache folder {folder} is not writable: {exc.strerror or exc}"
        return _fallback(fun, start, why)
    loaded = _load(name, lib) if so_cache.verify(lib) is None else None
    if loaded is None:
        return _fallback(fun, start, f"{lib} does not load")
    STATS["compiled"] += 1
    return Compiled(loaded, lib, False, time.perf_counter() - start)


def _compile(cc: str, args: list[str]) -> str | None:
    """Run the C compiler; None on success, else why it failed."""
    try:
        run = subprocess.run([cc, *args], capture_output=True)
    except OSError as exc:
        return f"{cc} does not run: {exc}"
    return None if run.returncode == 0 else f"{cc} failed: {run.stderr.decode()[-500:]}"


def _load(name: str, lib: Path) -> ca.Function | None:
    """``casadi.external`` of a verified library; None (with a warning) if it fails."""
    try:
        return ca.external(name, str(lib))
    except RuntimeError as exc:
        msg = f"cache entry {lib} does not load ({str(exc).strip()[-200:]}); rebuilding it"
        warnings.warn(msg, so_cache.CacheWarning, stacklevel=4)
        return None


def _fallback(fun: ca.Function, start: float, why: str) -> Compiled:
    STATS["fallbacks"] += 1
    warnings.warn(
        f"{fun.name()} is not compiled ({why}); using CasADi's VM", CompileWarning, stacklevel=3
    )
    return Compiled(fun, None, False, time.perf_counter() - start)


def compiled(fun: ca.Function, *, key: str = "", opt: str = "-O1") -> ca.Function:
    """``fun`` compiled to C and loaded from the disk cache (see :func:`compile_function`);
    the original ``fun`` (with a :class:`CompileWarning`) when no compiler works."""
    return compile_function(fun, key=key, opt=opt).function


__all__ = [
    "STATS",
    "CompileWarning",
    "Compiled",
    "c_compiler",
    "cache_dir",
    "compile_function",
    "compile_lazy",
    "compiled",
]

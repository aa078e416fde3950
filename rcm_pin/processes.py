"""Process pools of rcm-pin's parallel runs (the report's sections, a design study's chunks).

Workers fork from a fork server that has imported the given modules once (no import of
Pinocchio per process, no threads of the caller inherited); on a platform without a fork
server (Windows) they are spawned.
"""

from __future__ import annotations

from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_all_start_methods, get_context


def process_pool(workers: int, preload: Sequence[str]) -> ProcessPoolExecutor:
    """A pool of ``workers`` processes forked from a server that imported ``preload``
    (module names), spawned where the platform has no fork server."""
    if "forkserver" not in get_all_start_methods():
        return ProcessPoolExecutor(max_workers=workers, mp_context=get_context("spawn"))
    context = get_context("forkserver")
    context.set_forkserver_preload(list(preload))
    return ProcessPoolExecutor(max_workers=workers, mp_context=context)


__all__ = ["process_pool"]

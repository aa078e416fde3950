"""A slow report section for the crash tests (tests/test_crash_reproduce.py): one module
serving several sections, each named by its work folder (the section's slug), writing three
files a moment apart; with ``FAKE_SLOW_PIDS`` set it records its PID there and waits."""

from __future__ import annotations

import os
import time
from pathlib import Path

from rcm_pin.report.framework import Section

#: Seconds between the files a section writes.
DELAY = 0.15


def section(out_dir: Path) -> Section:
    """Three files ``<slug>_<i>.txt`` (deterministic content), one figure per file."""
    name = out_dir.name
    pids = os.environ.get("FAKE_SLOW_PIDS")
    if pids:
        (Path(pids) / f"{os.getpid()}.pid").write_text(str(os.getpid()))
        time.sleep(120)  # killed with its parent long before
    files = []
    for i in range(3):
        time.sleep(DELAY)
        (out_dir / f"{name}_{i}.txt").write_text(f"{name} figure {i}: value {i * 0.125}\n")
        files.append(f"{name}_{i}.txt")
    body = "\n".join(f"[{f}]({f}) measured {len(f) * 0.5} mm" for f in files)
    return Section(f"Slow {name}", body, tuple(files))

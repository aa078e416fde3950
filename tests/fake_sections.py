"""Two tiny report sections for tests/test_report_runner.py (a module the runner imports by
name, in this process or in its worker processes: ``tests/`` is on ``sys.path``)."""

from __future__ import annotations

from pathlib import Path

from rcm_pin.report.framework import Section

CALLS: list[str] = []


def section(out_dir: Path) -> Section:
    """Writes one file and names it."""
    CALLS.append("small")
    (out_dir / "small.txt").write_text("figure")
    return Section("Small", "see [small.txt](small.txt)", ("small.txt",))

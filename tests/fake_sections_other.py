"""A second tiny report section for tests/test_report_runner.py."""

from __future__ import annotations

from pathlib import Path

from rcm_pin.report.framework import Section


def section(out_dir: Path) -> Section:
    """Writes another file."""
    (out_dir / "other.txt").write_text("other")
    return Section("Other", "see [other.txt](other.txt)", ("other.txt",))

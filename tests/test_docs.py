"""Generated documentation never goes stale: the module table of docs/architecture.md."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_the_module_table_lists_every_module_with_its_docstring():
    done = subprocess.run(
        [sys.executable, str(ROOT / "tools" / "modules_table.py"), "--check"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0, done.stdout + done.stderr

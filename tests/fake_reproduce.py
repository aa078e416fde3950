"""``python tests/fake_reproduce.py OUT JOBS``: ``rcm-pin reproduce`` (write_report) on the
slow fake sections of tests/fake_slow.py, for the crash tests; exit 2 on a typed error."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

import fake_slow  # noqa: F401  (imported: its source enters the key, as in the tests)

from rcm_pin.errors import RcmPinError
from rcm_pin.report import writer

#: The fake report: six sections of one slow module.
FAKE = tuple((f"slow {c}", "fake_slow") for c in "abcdef")

if __name__ == "__main__":
    writer.SECTIONS = FAKE  # type: ignore[attr-defined]
    try:
        writer.write_report(Path(sys.argv[1]), jobs=int(sys.argv[2]), quiet=True)
    except RcmPinError as exc:
        print(f"{type(exc).__name__}: {exc}")
        sys.exit(2)

"""The module table of docs/architecture.md, generated from each module's docstring.

Usage::

    python tools/modules_table.py           # rewrite the table in docs/architecture.md
    python tools/modules_table.py --check   # exit 1 if the table is stale (a test runs it)

The table sits between the line ``| module | what |`` (with its separator line) and the
next blank line (or the end of the file); each row is ``| `path` | first sentence |``.
"""

from __future__ import annotations

import argparse
import ast
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "architecture.md"
HEADER = "| module | what |\n| --- | --- |\n"


def summary(path: Path) -> str:
    """The first line of a module's docstring, with ``|`` escaped."""
    doc = ast.get_docstring(ast.parse(path.read_text())) or ""
    first = doc.strip().splitlines()[0] if doc.strip() else "(no docstring)"
    return first.replace("|", "\\|")


def table() -> str:
    """Rows for every module of rcm_pin and ocp, sorted by path."""
    paths = sorted([*(ROOT / "rcm_pin").rglob("*.py"), *(ROOT / "ocp").rglob("*.py")])
    rows = [f"| `{p.relative_to(ROOT)}` | {summary(p)} |" for p in paths]
    return HEADER + "\n".join(rows) + "\n"


def rewritten(text: str) -> str:
    """The document with its module table replaced."""
    start = text.index(HEADER)
    end = text.find("\n\n", start + len(HEADER))
    rest = "" if end < 0 else text[end + 1 :]
    return text[:start] + table() + rest


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="exit 1 if the table is stale")
    args = parser.parse_args()
    text = DOC.read_text()
    new = rewritten(text)
    if args.check:
        if new != text:
            print("docs/architecture.md: the module table is stale; run tools/modules_table.py")
            return 1
        return 0
    DOC.write_text(new)
    return 0


if __name__ == "__main__":
    sys.exit(main())

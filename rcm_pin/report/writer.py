"""``rcm-pin reproduce``: run every report section and write ``report.md``."""

from __future__ import annotations

import time
from pathlib import Path

from rcm_pin.report.sections import SECTIONS


def write_report(out_dir: Path, only: list[str] | None = None, quiet: bool = False) -> Path:
    """Run every section and write ``out_dir/report.md``.

    Args:
        out_dir: output directory (created).
        only: run only sections whose module path contains one of these words.
        quiet: no progress lines on stdout.

    Returns:
        The report path.
    """
    out_dir.mkdir(parents=True, exist_ok=True)
    parts = [
        "# rcm-pin: reproduction report\n",
        "Every number below is computed by rcm-pin from the models in `xacro/`; published"
        " values are typed in from the papers (`../shared/seeds/`) with their source."
        " Where they differ the table says why. Regenerate with `rcm-pin reproduce`.\n",
    ]
    timings = []
    for entry, fn in SECTIONS:
        if only and not any(word in entry for word in only):
            continue
        start = time.perf_counter()
        if not quiet:
            print(f"[reproduce] {entry} ...", flush=True)
        section = fn(out_dir)
        elapsed = time.perf_counter() - start
        timings.append((section.title, elapsed))
        parts.append(f"## {section.title}\n\n{section.body.strip()}\n")
        unshown = [f for f in section.figures if f"]({f})" not in section.body]
        if unshown:  # embed figures the body only names
            parts.append("\n".join(f"![{f}]({f})" for f in unshown) + "\n")
    parts.append("## Run time per section\n")
    parts.append("\n".join(f"- {title}: {sec:.1f} s" for title, sec in timings) + "\n")
    path = out_dir / "report.md"
    path.write_text("\n".join(parts))
    return path


__all__ = ["write_report"]

"""``rcm-pin reproduce``: run every report section and write ``report.md``."""

from __future__ import annotations

import time
from pathlib import Path

from rcm_pin.errors import InvalidInputError
from rcm_pin.report.sections import SECTIONS

#: The papers the report reproduces, cited by reference (all in Russian).
SOURCES = (
    "[000] E. I. Veliev, R. F. Ganiev, V. A. Glazunov, S. A. Skvortsov, R. A. Chernetsov, "
    '"Development and study of mechanisms with a constant point of tool insertion into the '
    'working area, intended for surgical operations and plasma research", journal paper '
    "(section Mechanics of machines), 2020.",
    '[002] G. N. Chusovitin, N. A. Chusovitin, "Synthesis of a spatial four-DOF linkage with '
    'an Assur group of the second class, fourth kind", conference paper, Novosibirsk State '
    "Technical University.",
    "[003] Thesis abstract (candidate of technical sciences) on mechanisms with a constant tool "
    "insertion point, A. A. Blagonravov Institute of Machines Science of the Russian Academy "
    "of Sciences, 2021.",
    '[004] S. V. Kheylo, "Scientific foundations of parallel-structure manipulation mechanisms '
    'for robotic systems of textile and light industry", doctoral thesis abstract, Moscow '
    "State University of Design and Technology, 2014.",
)


def write_report(out_dir: Path, only: list[str] | None = None, quiet: bool = False) -> Path:
    """Run every section and write ``out_dir/report.md``.

    Args:
        out_dir: output directory (created).
        only: run only sections whose module path contains one of these words.
        quiet: no progress lines on stdout.

    Returns:
        The report path.
    """
    chosen = [(entry, fn) for entry, fn in SECTIONS if not only or any(w in entry for w in only)]
    if not chosen:
        raise InvalidInputError(
            f"--only {' '.join(only or [])!r} matches no report section; valid: a word of "
            + ", ".join(entry for entry, _ in SECTIONS)
        )
    out_dir.mkdir(parents=True, exist_ok=True)
    parts = [
        "# rcm-pin: reproduction report\n",
        "Every number below is computed by rcm-pin from the models in `xacro/`; published"
        " values are typed in from the papers (listed under *Sources* at the end) with their"
        " source. Where they differ the table says why. Regenerate with `rcm-pin reproduce`.\n",
    ]
    timings = []
    for entry, fn in chosen:
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
    parts.append("## Sources\n")
    parts.append("\n".join(f"- {ref}" for ref in SOURCES) + "\n")
    parts.append("## Run time per section\n")
    parts.append("\n".join(f"- {title}: {sec:.1f} s" for title, sec in timings) + "\n")
    path = out_dir / "report.md"
    path.write_text("\n".join(parts))
    return path


__all__ = ["write_report"]

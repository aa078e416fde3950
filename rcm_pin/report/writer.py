"""``rcm-pin reproduce``: run every report section and write ``report.md``."""

from __future__ import annotations

from pathlib import Path

from tqdm import tqdm

from rcm_pin.errors import InvalidInputError
from rcm_pin.processes import atomic_write, folder_lock
from rcm_pin.report.runner import Outcome, run_sections
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


def write_report(
    out_dir: Path,
    only: list[str] | None = None,
    quiet: bool = False,
    jobs: int | None = None,
    cache: bool = True,
) -> Path:
    """Run every section and write ``out_dir/report.md``.

    Args:
        out_dir: output directory (created).
        only: run only sections whose module path contains one of these words.
        quiet: no progress bar.
        jobs: parallel processes (default: the number of cores; 1: in this process).
        cache: reuse a section whose inputs are unchanged (:mod:`rcm_pin.report.runner`).

    Returns:
        The report path.

    Raises:
        InvalidInputError: ``only`` matches no section, or ``jobs`` < 1.
        FolderBusyError: another run holds the lock of ``out_dir`` (the run does not wait).
    """
    chosen = [(entry, m) for entry, m in SECTIONS if not only or any(w in entry for w in only)]
    if not chosen:
        raise InvalidInputError(
            f"--only {' '.join(only or [])!r} matches no report section; valid: a word of "
            + ", ".join(entry for entry, _ in SECTIONS)
        )
    if jobs is not None and jobs < 1:
        raise InvalidInputError(f"--jobs {jobs}; valid: >= 1")
    out_dir.mkdir(parents=True, exist_ok=True)
    with folder_lock(out_dir):
        return _write(out_dir, chosen, quiet, jobs, cache)


def _write(
    out_dir: Path, chosen: list[tuple[str, str]], quiet: bool, jobs: int | None, cache: bool
) -> Path:
    outcomes: dict[str, Outcome] = {}
    with tqdm(total=len(chosen), disable=quiet, unit="section", desc="reproduce") as bar:
        for outcome in run_sections(chosen, out_dir, jobs, cache):
            outcomes[outcome.name] = outcome
            bar.set_postfix_str(outcome.name.rsplit(".", 1)[-1], refresh=False)
            bar.update(1)
    parts = [
        "# rcm-pin: reproduction report\n",
        "Every number below is computed by rcm-pin from the models in `xacro/`; published"
        " values are typed in from the papers (listed under *Sources* at the end) with their"
        " source. Where they differ the table says why. Regenerate with `rcm-pin reproduce`.\n",
    ]
    for entry, _ in chosen:
        section = outcomes[entry].section
        parts.append(f"## {section.title}\n\n{section.body.strip()}\n")
        unshown = [f for f in section.figures if f"]({f})" not in section.body]
        if unshown:  # embed figures the body only names
            parts.append("\n".join(f"![{f}]({f})" for f in unshown) + "\n")
    parts.append("## Sources\n")
    parts.append("\n".join(f"- {ref}" for ref in SOURCES) + "\n")
    parts.append("## Run time per section\n")
    parts.append(
        "\n".join(
            f"- {o.section.title}: "
            + ("reused from the cache (inputs unchanged)" if o.cached else f"{o.seconds:.1f} s")
            for o in (outcomes[e] for e, _ in chosen)
        )
        + "\n"
    )
    return atomic_write(out_dir / "report.md", "\n".join(parts).encode())


__all__ = ["write_report"]

"""The report's building blocks: a published number beside its computation, a section.

A section is a function ``(out_dir: Path) -> Section`` (listed in
:mod:`rcm_pin.report.sections`). Each computes its numbers (never copies them), writes its
figures into ``out_dir`` and returns markdown. Published numbers are typed in with their
source; the table shows published, computed, difference and the reason where they differ
(:class:`Comparison` and :func:`comparison_table` live in :mod:`rcm_pin.studies.comparison`,
where the studies that reproduce a paper build their rows; they are re-exported here).
"""

from __future__ import annotations

from dataclasses import dataclass, field

# The rows of a paper's numbers are a study's result (rcm_pin.studies.comparison); the
# report's sections print them.
from rcm_pin.studies.comparison import Comparison, comparison_table


@dataclass(frozen=True)
class Section:
    """A report section: title, markdown body, figures written (relative paths)."""

    title: str
    body: str
    figures: tuple[str, ...] = field(default_factory=tuple)

    @classmethod
    def from_markdown(cls, markdown: str, default_title: str) -> Section:
        """A section from markdown whose first line may be its own ``## `` heading."""
        first, _, rest = markdown.lstrip().partition("\n")
        if first.startswith("## "):
            return cls(first[3:].strip(), rest)
        return cls(default_title, markdown)


__all__ = ["Comparison", "Section", "comparison_table"]

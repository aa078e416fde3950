"""The report's building blocks: a published number beside its computation, a section.

A section is a function ``(out_dir: Path) -> Section`` (listed in
:mod:`rcm_pin.report.sections`). Each computes its numbers (never copies them), writes its
figures into ``out_dir`` and returns markdown. Published numbers are typed in with their
source; the table shows published, computed, difference and the reason where they differ.
"""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class Comparison:
    """One published number next to the project's computation.

    Attributes:
        quantity: what it is (e.g. ``"q5"``).
        published: the value printed in the paper (None when it prints none).
        computed: the value rcm-pin computes.
        unit: unit string (``"rad"``, ``"m/s"``).
        reason: why they differ, when they do (empty when they agree).
        tolerance: |published − computed| up to which they count as agreeing (the
            paper's printed precision).
    """

    quantity: str
    published: float | None
    computed: float
    unit: str = ""
    reason: str = ""
    tolerance: float = 0.0

    @property
    def difference(self) -> float | None:
        """computed − published."""
        return None if self.published is None else self.computed - self.published

    @property
    def agrees(self) -> bool:
        """Whether the difference is within the printed precision."""
        d = self.difference
        return d is not None and abs(d) <= self.tolerance


def comparison_table(rows: list[Comparison]) -> str:
    """Markdown table: quantity, published, computed, difference, verdict and reason."""
    lines = [
        "| quantity | published | computed | difference | verdict | reason |",
        "| --- | ---: | ---: | ---: | --- | --- |",
    ]
    for r in rows:
        pub = "—" if r.published is None else f"{r.published:.6g}"
        diff = "—" if r.difference is None else f"{r.difference:.3g}"
        verdict = "agrees" if r.agrees else ("new" if r.published is None else "**differs**")
        lines.append(
            f"| {r.quantity} [{r.unit}] | {pub} | {r.computed:.6g} | {diff} | {verdict} "
            f"| {r.reason} |"
        )
    return "\n".join(lines)


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

"""A published number beside the project's computation, and the markdown table of them.

The studies that reproduce a paper (:mod:`.eye_paper`) return :class:`Comparison` rows; the
report (:mod:`rcm_pin.report`) and the notebooks print them with :func:`comparison_table`.
Published values are typed in with their source, never copied from a computation.
"""

from __future__ import annotations

from dataclasses import dataclass


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


__all__ = ["Comparison", "comparison_table"]

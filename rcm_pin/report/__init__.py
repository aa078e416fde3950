"""``rcm-pin reproduce``: every paper result the project reproduces, in one report.

A section is a function ``(out_dir: Path) -> Section`` listed in :data:`SECTIONS` by
module path. Each computes its numbers (never copies them), writes its figures into
``out_dir`` and returns markdown. Published numbers are typed in with their source;
the table shows published, computed, difference and the reason where they differ.
"""

from __future__ import annotations

import importlib
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

#: ``"module:function"`` of every report section, in report order.
SECTIONS: tuple[str, ...] = (
    "rcm_pin.report.position:section",
    "rcm_pin.report.velocity:section",
    "rcm_pin.report.analysis:section",
    "rcm_pin.report.dynamics:section",
    "ocp.report:section",
    "rcm_pin.closed_loop.report:section",
    "rcm_pin.report.scenes:section",
)


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


def _resolve(entry: str) -> Callable[[Path], Section] | None:
    module_name, _, func = entry.partition(":")
    try:
        module = importlib.import_module(module_name)
    except ModuleNotFoundError as exc:
        if exc.name is not None and module_name.startswith(exc.name):
            return None  # that part is not in this tree yet
        raise
    fn: Callable[[Path], Section] = getattr(module, func)
    return fn


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
    for entry in SECTIONS:
        if only and not any(word in entry for word in only):
            continue
        fn = _resolve(entry)
        if fn is None:
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

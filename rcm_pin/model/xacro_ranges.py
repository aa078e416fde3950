"""Kinds and ranges of xacro arguments, read from the xacro documentation itself.

Convention (every shipped xacro follows it, ``tests/test_xacro_ranges.py`` enforces it):
each ``<xacro:arg name=".." default=".."/>`` keeps a trailing comment on its own line,

* a number: ``<!-- what it is [unit] in INTERVAL, more notes -->``: the unit in brackets
  (``[-]`` for a pure number such as a tooth count), then ``in`` and an interval
  ``(a, b]``, ``[a, b]``, ``(a, b)`` or ``[a, b)`` of plain numbers, e.g.
  ``<!-- initial link 9 length P7-P10 [m] in (0, 10] -->``, ``[rad] in [-3.1416, 3.1416]``;
* an enumeration: ``one of a, b`` (e.g. ``<!-- wrist pair convention, one of zyz, rpy -->``);
* a boolean: a default of ``true`` or ``false`` (values true/false, 1/0, yes/no, on/off);
* any other text: a name of ``[A-Za-z0-9_.-]`` characters.

A number whose default is a number is checked to be finite and, where the comment states
an interval, inside it. Limit pairs are recognised by name (``X_lower``/``X_upper``,
``lower_X``/``upper_X``, ``X_min``/``X_max``, ``min_X``/``max_X``) and must satisfy
lower < upper once the given arguments are merged with the defaults.
"""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from rcm_pin.errors import XacroArgumentError

_XACRO_NS = "{http://www.ros.org/wiki/xacro}"
_BOOL_TRUE = {"true", "1", "yes", "on"}
_BOOL_FALSE = {"false", "0", "no", "off"}
_NUM = r"[-+]?(?:inf|\d+(?:\.\d*)?(?:[eE][-+]?\d+)?|\.\d+(?:[eE][-+]?\d+)?)"
_RANGE = re.compile(
    rf"^(?P<desc>.*?)\s*\[(?P<unit>[^\]]+)\]\s+in\s+(?P<open>[\[(])\s*(?P<lo>{_NUM})\s*,"
    rf"\s*(?P<hi>{_NUM})\s*(?P<close>[\])])"
)
_UNIT = re.compile(r"^(?P<desc>.*?)\s*\[(?P<unit>[^\]]+)\]")
_CHOICE = re.compile(r"^(?P<desc>.*?)[\s,]*\bone of\s+(?P<items>[\w.-]+(?:\s*,\s*[\w.-]+)*)")
_ARG = re.compile(r"<xacro:arg\b(?P<attrs>[^>]*?)/>[ \t]*(?:<!--(?P<comment>.*?)-->)?")
_ATTR = re.compile(r'(\w+)\s*=\s*"([^"]*)"')
_PAIRS = (("_lower", "_upper"), ("_min", "_max"))


@dataclass(frozen=True)
class ArgSpec:
    """One declared xacro argument with its documented kind and range.

    Attributes:
        name: argument name.
        default: default text.
        kind: ``number``, ``boolean``, ``choice`` or ``text``.
        description: the comment text before the unit (or before ``one of``).
        unit: the unit in brackets (``-`` for a pure number), or None if undocumented.
        interval: the documented interval text such as ``(0, 10]``, or None.
        choices: the values of an enumeration.
    """

    name: str
    default: str
    kind: str
    description: str = ""
    unit: str | None = None
    interval: str | None = None
    choices: tuple[str, ...] = ()

    def contains(self, x: float) -> bool:
        """True if ``x`` lies in the documented interval (always, if there is none)."""
        if self.interval is None:
            return True
        lo, hi = (float(t) for t in self.interval[1:-1].split(","))
        above = x > lo if self.interval[0] == "(" else x >= lo
        below = x < hi if self.interval[-1] == ")" else x <= hi
        return above and below

    def valid(self) -> str:
        """What is valid, for messages: ``(0, 10] [m] (initial link 9 length P7-P10)``."""
        if self.kind == "boolean":
            return "true or false"
        if self.kind == "choice":
            return f"one of {', '.join(self.choices)}"
        if self.kind == "text":
            return "a name of characters A-Z a-z 0-9 _ . -"
        text = self.interval or "a finite number"
        if self.unit is not None:
            text += f" [{self.unit}]"
        return f"{text} ({self.description})" if self.description else text


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def parse_spec(name: str, default: str, comment: str | None) -> ArgSpec:
    """The :class:`ArgSpec` of one declaration from its default and trailing comment."""
    comment = " ".join((comment or "").split())
    if default.lower() in ("true", "false"):
        return ArgSpec(name, default, "boolean", comment)
    if _is_number(default):
        if m := _RANGE.match(comment):
            interval = f"{m['open']}{m['lo']}, {m['hi']}{m['close']}"
            return ArgSpec(name, default, "number", m["desc"].strip(" ,;:"), m["unit"], interval)
        if m := _UNIT.match(comment):
            return ArgSpec(name, default, "number", m["desc"].strip(" ,;:"), m["unit"])
        return ArgSpec(name, default, "number", comment)
    if m := _CHOICE.match(comment):
        items = tuple(item.strip() for item in m["items"].split(","))
        return ArgSpec(name, default, "choice", m["desc"].strip(" ,;:"), choices=items)
    return ArgSpec(name, default, "text", comment)


@lru_cache(maxsize=64)
def _specs_cached(path: str, mtime_ns: int) -> dict[str, ArgSpec]:
    try:
        text = Path(path).read_text()
    except (OSError, UnicodeDecodeError) as exc:
        raise XacroArgumentError(f"cannot read {Path(path).name}: {exc}") from None
    comments: dict[str, str | None] = {}
    for m in _ARG.finditer(text):
        attrs = dict(_ATTR.findall(m["attrs"]))
        if "name" in attrs:
            comments[attrs["name"]] = m["comment"]
    specs: dict[str, ArgSpec] = {}
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        raise XacroArgumentError(f"{Path(path).name} is not valid XML: {exc}") from None
    for element in root.iter(f"{_XACRO_NS}arg"):
        if name := element.attrib.get("name", ""):
            default = element.attrib.get("default", "")
            specs[name] = parse_spec(name, default, comments.get(name))
    for element in root.iter(f"{_XACRO_NS}include"):
        filename = element.attrib.get("filename", "")
        if "$(" in filename:
            continue
        included = Path(path).parent / filename
        if included.exists():
            specs.update(declared_specs(included))
    return specs


def declared_specs(path: str | Path) -> dict[str, ArgSpec]:
    """Every ``xacro:arg`` of a xacro file (and its includes) with its documented range."""
    p = Path(path)
    return dict(_specs_cached(str(p), p.stat().st_mtime_ns))


def check_value(spec: ArgSpec, value: object, source: str) -> str:
    """Check one argument against its declaration and return its xacro text.

    Args:
        spec: the declaration.
        value: the given value (number, boolean or text).
        source: the xacro file name, for messages.

    Returns:
        The value as xacro text.

    Raises:
        XacroArgumentError: the value is of the wrong kind, not finite, out of its range or
            not one of the enumerated values.
    """
    text = str(value).lower() if isinstance(value, bool) else str(value).strip()
    where = f"for {source}; valid: {spec.valid()}"
    if spec.kind == "boolean":
        if text.lower() not in _BOOL_TRUE | _BOOL_FALSE:
            raise XacroArgumentError(f"{spec.name}={text!r} is not a boolean {where}")
        return "true" if text.lower() in _BOOL_TRUE else "false"
    if spec.kind == "number":
        try:
            number = float(text)
        except ValueError:
            raise XacroArgumentError(f"{spec.name}={text!r} is not a number {where}") from None
        if not math.isfinite(number):
            raise XacroArgumentError(f"{spec.name}={number:g} is not finite {where}")
        if not spec.contains(number):
            raise XacroArgumentError(f"{spec.name}={number:g} is out of range {where}")
        return text
    if spec.kind == "choice":
        if text not in spec.choices:
            raise XacroArgumentError(f"{spec.name}={text!r} is not valid {where}")
        return text
    if not re.fullmatch(r"[A-Za-z0-9_.\-]+", text):
        raise XacroArgumentError(f"{spec.name}={text!r} is not a plain name {where}")
    return text


def limit_pairs(names: list[str]) -> list[tuple[str, str]]:
    """(lower, upper) argument names recognised by their suffix or prefix."""
    pairs = []
    for name in names:
        for low, high in _PAIRS:
            if name.endswith(low) and name[: -len(low)] + high in names:
                pairs.append((name, name[: -len(low)] + high))
            prefix_low, prefix_high = low[1:] + "_", high[1:] + "_"
            if name.startswith(prefix_low) and prefix_high + name[len(prefix_low) :] in names:
                pairs.append((name, prefix_high + name[len(prefix_low) :]))
    return pairs


def check_pairs(specs: dict[str, ArgSpec], given: dict[str, str], source: str) -> None:
    """Every limit pair has lower < upper after merging ``given`` with the defaults.

    Raises:
        XacroArgumentError: names both values and the valid relation.
    """
    for low, high in limit_pairs(list(specs)):
        if specs[low].kind != "number" or specs[high].kind != "number":
            continue
        values = [given.get(n, specs[n].default) for n in (low, high)]
        if not all(_is_number(v) for v in values):
            continue
        lo, hi = (float(v) for v in values)
        if not lo < hi:
            raise XacroArgumentError(
                f"{low}={lo:g} is not below {high}={hi:g} in {source}; valid: {low} < {high}"
            )


__all__ = ["ArgSpec", "check_pairs", "check_value", "declared_specs", "limit_pairs", "parse_spec"]

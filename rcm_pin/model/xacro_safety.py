"""Untrusted xacro files are data, not code: an allow-list for their ``${…}`` expressions.

xacro evaluates every ``${…}`` expression (and every ``$(eval …)`` substitution) with
Python's ``eval``; its own guard only looks at the top-level names, so code nested in a
comprehension runs. Before an untrusted file is rendered, :func:`check_file` parses each
expression of the file and of every ``xacro:include`` it can resolve statically with
:mod:`ast` and accepts only :data:`ALLOWED` constructs:

* numbers, strings, ``True`` / ``False`` / ``None``, tuple and list literals;
* arithmetic (``+ - * / // % **``, unary ``+ - not ~``), comparisons (``in`` included),
  ``and`` / ``or``, conditional expressions (``a if c else b``), subscripts (``n[0]``);
* property names (no dunder name, none of xacro's other global callables such as
  ``python``, ``load_yaml``, ``range``);
* calls of :data:`FUNCTIONS` (bare or as ``math.NAME``) and of :data:`XACRO_FUNCTIONS`
  (``xacro.fatal``, ``xacro.arg``, ...), positional arguments only.

Anything else (attribute access, comprehensions, lambdas, f-strings, keyword or starred
arguments, dunders, other calls) raises :class:`~rcm_pin.errors.UntrustedXacroError` naming
the file, the line and the expression. ``$(arg x)`` / ``$(find pkg)`` substitutions are
not Python: inside an expression they are checked as a placeholder here, and the text
they expand to is checked again when xacro evaluates it (:mod:`rcm_pin.model.xacro_guard`).
"""

from __future__ import annotations

import ast
import glob
import math
import os
import re
import xml.parsers.expat
from pathlib import Path

from rcm_pin.errors import UntrustedXacroError

#: Functions an untrusted expression may call (bare, or ``math.NAME`` for math's).
FUNCTIONS = frozenset({
    "sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh", "sqrt", "exp",
    "log", "log10", "hypot", "pow", "fabs", "floor", "ceil", "trunc", "fmod", "copysign",
    "radians", "degrees", "min", "max", "round", "int", "float", "str", "bool", "len",
})  # fmt: skip
#: Constants an untrusted expression may name (besides properties).
CONSTANTS = frozenset({"pi", "e", "tau", "inf", "nan", "True", "False", "None"})
#: ``xacro.NAME`` functions an untrusted expression may call (no side effect but a message).
XACRO_FUNCTIONS = frozenset({"arg", "fatal", "message", "warning", "error"})
_XACRO_GLOBALS = frozenset({
    "python", "xacro", "math", "list", "dict", "map", "sorted", "range", "load_yaml",
    "abs_filename", "dotify", "print_location", "tokenize",
})  # fmt: skip
#: Every name of xacro's global table that an untrusted expression may not name.
REFUSED_NAMES = frozenset(n for n in dir(math) if not n.startswith("_")) | _XACRO_GLOBALS
REFUSED_NAMES -= FUNCTIONS | CONSTANTS
#: AST node types accepted anywhere in an untrusted expression (calls checked apart).
ALLOWED = (
    ast.Expression, ast.Constant, ast.Name, ast.Load, ast.Tuple, ast.List,
    ast.BinOp, ast.UnaryOp, ast.BoolOp, ast.Compare, ast.IfExp, ast.Subscript, ast.Slice,
    ast.operator, ast.unaryop, ast.boolop, ast.cmpop, ast.Call, ast.Attribute,
)  # fmt: skip
#: The valid forms, for messages.
VALID = (
    "numbers, strings, property names, arithmetic, comparisons, and/or/not, "
    "'a if c else b', subscripts and calls of " + ", ".join(sorted(FUNCTIONS)) + " and xacro."
    + "/".join(sorted(XACRO_FUNCTIONS)) + "; a file you trust loads with trusted=True (CLI: "
    "--trusted)"
)  # fmt: skip
#: What stands for a ``$(…)`` substitution inside an expression in the static check.
PLACEHOLDER = "_rcm_pin_substitution_"

# xacro's own lexer (xacro.LEXER): escapes, ${expressions}, $(extensions), text.
_TOKEN = re.compile(r"\$\$+(?:\{|\()|\$\{[^}]*\}|\$\([^)]*\)|[^$]+|\$[^{($]+|\$$")
_EXTENSION = re.compile(r"\$\([^)]*\)")


_WHAT = {
    "ListComp": "a comprehension", "SetComp": "a comprehension", "DictComp": "a comprehension",
    "GeneratorExp": "a generator expression", "Lambda": "a lambda", "JoinedStr": "an f-string",
    "NamedExpr": "an assignment expression", "Dict": "a dict literal", "Set": "a set literal",
    "Starred": "a starred expression", "Yield": "yield", "YieldFrom": "yield", "Await": "await",
}  # fmt: skip


def _refusal(node: ast.AST) -> str | None:
    """Why ``node`` (one node, children apart) is not allowed, or None."""
    if not isinstance(node, ALLOWED):
        kind = type(node).__name__
        return f"{_WHAT.get(kind, kind)} is not allowed"
    if isinstance(node, ast.Name):
        if node.id.startswith("__"):
            return f"the name {node.id} is not allowed"
        if node.id in REFUSED_NAMES:
            return f"the name {node.id} is not allowed"
    if isinstance(node, ast.Constant) and isinstance(node.value, bytes):
        return "bytes are not allowed"
    if isinstance(node, ast.Subscript):
        s = node.slice
        if isinstance(s, ast.Constant) and isinstance(s.value, str) and "__" in s.value:
            return f"the subscript {s.value!r} is not allowed"
    if isinstance(node, ast.Attribute):
        return f"attribute access .{node.attr} is not allowed"
    return None


def _qualified(func: ast.expr) -> str | None:
    """``NAME`` or ``math.NAME`` / ``xacro.NAME`` of a call's function, if allowed."""
    if isinstance(func, ast.Name) and func.id in FUNCTIONS:
        return func.id
    if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name):
        ns, attr = func.value.id, func.attr
        if (ns == "math" and attr in FUNCTIONS | CONSTANTS) or (
            ns == "xacro" and attr in XACRO_FUNCTIONS
        ):
            return f"{ns}.{attr}"
    return None


def expression_problem(expr: str, extra_names: frozenset[str] = frozenset()) -> str | None:
    """Why the Python expression ``expr`` is not allowed in an untrusted xacro, or None.

    Args:
        expr: the text between ``${`` and ``}`` (or after ``$(eval``), substitutions
            already replaced.
        extra_names: more callable names allowed (``arg`` in ``$(eval …)``).
    """
    try:
        tree = ast.parse(expr.strip(), mode="eval")
    except (SyntaxError, ValueError) as exc:
        return f"not a Python expression ({exc.msg if isinstance(exc, SyntaxError) else exc})"
    skip: set[int] = set()
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.Call):
            name = _qualified(node.func)
            if name is None and not (
                isinstance(node.func, ast.Name) and node.func.id in extra_names
            ):
                return f"a call of {ast.unparse(node.func)} is not allowed"
            if node.keywords or any(isinstance(a, ast.Starred) for a in node.args):
                return "keyword and starred arguments are not allowed"
            skip.add(id(node.func))
            if isinstance(node.func, ast.Attribute):
                skip.add(id(node.func.value))
            continue
        if isinstance(node, ast.Attribute) and _qualified(node) in {f"math.{c}" for c in CONSTANTS}:
            skip.add(id(node.value))
            continue
        reason = _refusal(node)
        if reason is not None:
            return reason
    return None


def _refuse(expr: str, file: str, line: int | None, kind: str, reason: str) -> None:
    shown = f"${{{expr}}}" if kind == "${" else f"$(eval {expr})"
    where = f"{file}:{line}" if line is not None else f"{file} (built at render time)"
    raise UntrustedXacroError(
        f"{where}: expression {shown} in an untrusted xacro: {reason}; valid: {VALID}",
        file=file,
        line=line,
        expression=expr,
    )


def check_expression(expr: str, file: str, line: int | None, kind: str = "${") -> None:
    """Raise unless ``expr`` is allowed (:func:`expression_problem`).

    Args:
        expr: the expression, as xacro is about to evaluate it.
        file: the file it comes from.
        line: its line (None: the expression was built at render time).
        kind: ``"${"`` for an expression, ``"$(eval"`` for an eval substitution (which
            may also call ``arg``).

    Raises:
        UntrustedXacroError: naming the file, the line and the expression, e.g.
            "m.xacro:3: expression ${[os for os in ()]} in an untrusted xacro: ListComp is
            not allowed; valid: ...".
    """
    extra = frozenset({"arg"}) if kind == "$(eval" else frozenset()
    reason = expression_problem(expr, extra)
    if reason is not None:
        _refuse(expr, file, line, kind, reason)


def check_text(text: str, file: str, line: int) -> None:
    """Check every ``${…}`` and ``$(eval …)`` of one attribute value or text node that
    starts on ``line`` (``$(…)`` inside an expression checked as a placeholder name).

    Raises:
        UntrustedXacroError: the first refused expression.
    """
    pos = 0
    for token in _TOKEN.finditer(text):
        value, at = token.group(0), line + text[:pos].count("\n")
        pos = token.end()
        if value.startswith("${"):
            expr = value[2:-1]
            reason = expression_problem(_EXTENSION.sub(PLACEHOLDER, expr))
            if reason is not None:
                _refuse(expr, file, at, "${", reason)
        elif re.match(r"\$\(eval\s", value):
            check_expression(value[7:-1], file, at, kind="$(eval")


def _include_files(spec: str, base: Path) -> list[Path] | None:
    """The files ``<xacro:include filename=spec>`` names, None when only xacro can tell."""
    spec = spec.replace("$(dirname)", str(base)).replace("$(cwd)", os.getcwd())
    if "$" in spec:
        return None  # ${…}, $(arg …), $(find …): resolved (and checked) at render time
    full = spec if os.path.isabs(spec) else str(base / spec)
    if re.search(r"[*[?]+", full):
        return [Path(f) for f in sorted(glob.glob(full))]
    return [Path(full)]


def scan_file(path: Path) -> list[Path]:
    """Check one file's expressions; return the files it includes (statically resolved).

    A file that is not well-formed XML is left to xacro (which fails on it before
    evaluating anything).

    Raises:
        UntrustedXacroError: the first refused expression.
    """
    parser = xml.parsers.expat.ParserCreate()
    name, includes = str(path), []
    text: list[str] = []
    state = {"line": 1, "comments": False}

    def flush() -> None:
        if text:
            check_text("".join(text), name, state["line"])
            text.clear()

    def start(tag: str, attrs: dict[str, str]) -> None:
        flush()
        for value in attrs.values():
            check_text(value, name, parser.CurrentLineNumber)
        if tag == "xacro:include" and "filename" in attrs:
            found = _include_files(attrs["filename"], path.parent)
            includes.extend(found or [])

    def data(chunk: str) -> None:
        if not text:
            state["line"] = parser.CurrentLineNumber
        text.append(chunk)

    def comment(body: str) -> None:
        flush()
        if "xacro:eval-comments" in body:
            state["comments"] = "xacro:eval-comments:off" not in body
        elif state["comments"]:
            check_text(body, name, parser.CurrentLineNumber)

    parser.StartElementHandler = start
    parser.EndElementHandler = lambda tag: flush()
    parser.CharacterDataHandler = data
    parser.CommentHandler = comment
    try:
        parser.Parse(path.read_bytes(), True)
    except (xml.parsers.expat.ExpatError, OSError):
        return []
    return includes


def check_file(path: str | Path) -> list[Path]:
    """Check an untrusted xacro file and every include it can resolve statically.

    Returns:
        The files checked (resolved paths), the main file first.

    Raises:
        UntrustedXacroError: the first refused expression (file, line, expression).
    """
    todo, seen = [Path(path).resolve()], []
    while todo:
        current = todo.pop(0)
        if current in seen or not current.is_file():
            continue
        seen.append(current)
        todo.extend(p.resolve() for p in scan_file(current))
    return seen


__all__ = [
    "ALLOWED",
    "CONSTANTS",
    "FUNCTIONS",
    "REFUSED_NAMES",
    "XACRO_FUNCTIONS",
    "check_expression",
    "check_file",
    "check_text",
    "expression_problem",
    "scan_file",
]

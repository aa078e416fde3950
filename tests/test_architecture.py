"""The architecture's rules, checked on the source: no mechanism names in generic code,
modules under 300 lines, the families listed once, the layers of import-linter."""

from __future__ import annotations

import ast
import re
import subprocess
import sys
from pathlib import Path

import pytest

import rcm_pin
from rcm_pin.catalog.table import FAMILIES

ROOT = Path(__file__).resolve().parents[1]
#: Modules that may name mechanisms: the families, the catalogue table, the studies and
#: the report sections of the papers (each reproduces a paper on its named mechanisms),
#: and paper 000's OCP setup.
SPECIFIC = (
    "rcm_pin/mechanisms/",
    "rcm_pin/catalog/table.py",
    "rcm_pin/studies/",
    "rcm_pin/report/position.py",
    "rcm_pin/report/velocity.py",
    "rcm_pin/report/analysis.py",
    "rcm_pin/report/dynamics.py",
    "rcm_pin/report/casadi.py",
    "rcm_pin/report/closed_loops.py",
    "rcm_pin/report/eye_linkage.py",
    "rcm_pin/report/eye_mechanism.py",
    "rcm_pin/report/scenes.py",
    "rcm_pin/report/mujoco.py",
    "ocp/paper000.py",
)
#: Modules over 300 lines, with the reason (none today).
LONG_MODULES: dict[str, str] = {}


def _sources() -> list[Path]:
    return sorted([*(ROOT / "rcm_pin").rglob("*.py"), *(ROOT / "ocp").rglob("*.py")])


def _generic() -> list[Path]:
    return [p for p in _sources() if not str(p.relative_to(ROOT)).startswith(SPECIFIC)]


def _strings(tree: ast.AST) -> list[tuple[int, str]]:
    """String constants that are not docstrings (f-string parts included)."""
    docstrings = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
                docstrings.add(id(body[0].value))
    return [(n.lineno, n.value) for n in ast.walk(tree) if isinstance(n, ast.Constant)
            and isinstance(n.value, str) and id(n) not in docstrings]  # fmt: skip


def test_no_mechanism_name_in_generic_modules():
    names = set(rcm_pin.names()) | {f for f in FAMILIES if len(f) > 4}
    pattern = re.compile(r"(?<![A-Za-z0-9_])(" + "|".join(sorted(names)) + r")(?![A-Za-z0-9])")
    found = []
    for path in _generic():
        for line, text in _strings(ast.parse(path.read_text())):
            if pattern.search(text):
                found.append(f"{path.relative_to(ROOT)}:{line}: {text[:60]!r}")
    assert found == [], "mechanism names in generic modules:\n" + "\n".join(found)


def test_the_name_test_can_fail(tmp_path):
    """The check above finds a name test when there is one."""
    tree = ast.parse(
        'def f(m):\n    """five_bar is fine here."""\n    return m.name == "five_bar"\n'
    )
    assert [t for _, t in _strings(tree)] == ["five_bar"]


def test_modules_are_short():
    long = {}
    for path in _sources():
        n = len(path.read_text().splitlines())
        rel = str(path.relative_to(ROOT))
        if n > 300 and rel not in LONG_MODULES:
            long[rel] = n
    assert long == {}, f"modules over 300 lines: {long}"


def test_families_are_listed_once_and_match_the_urdf_elements():
    """Each catalogue entry's family is the family its URDF's <rcm_pin> element names."""
    from rcm_pin.catalog import mechanisms
    from rcm_pin.catalog.files import render_default
    from rcm_pin.model.sidecar import read_description

    assert len(FAMILIES) == len({id(f) for f in FAMILIES.values()})
    for entry in mechanisms():
        assert entry.family is FAMILIES[entry.family.name]
        if entry.xacro:
            assert read_description(render_default(entry.name)).family == entry.family.name


def test_import_linter_contracts_hold():
    exe = Path(sys.executable).with_name("lint-imports")
    if not exe.exists():
        pytest.fail(f"lint-imports not installed next to {sys.executable} (test extra)")
    proc = subprocess.run([str(exe)], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-2000:]
    assert "0 broken" in proc.stdout

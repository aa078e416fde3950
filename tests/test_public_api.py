"""The public API is the façades' ``__all__`` (docs/api.md lists it; tests/test_docs.py
keeps it current): every public name has a docstring, no re-export hides a submodule, and
the README, docs and notebooks import only from the façades (never from ``rcm_pin.report``
or a deep module)."""

from __future__ import annotations

import ast
import importlib
import json
import re
import sys
import types
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
import api_doc  # noqa: E402

#: What user-facing text may import from: the façades (``ocp``, the CasADi package, is one).
ALLOWED = set(api_doc.FACADES)
TEXTS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))


@pytest.mark.parametrize("facade", api_doc.FACADES)
def test_every_public_name_has_a_docstring(facade):
    package = importlib.import_module(facade)
    assert package.__all__ == sorted(set(package.__all__), key=package.__all__.index)
    missing = [n for n in package.__all__ if not api_doc.summary(package, n)]
    assert not missing, f"{facade}: no docstring for {missing}"


#: Re-exports named like a submodule of their façade, each kept the function by
#: ``rcm_pin.lazy.keep_functions`` (``rcm_pin.control.simulate``: the README's API).
SHADOWING = {("rcm_pin.control", "simulate")}


@pytest.mark.parametrize("facade", api_doc.FACADES)
def test_no_public_name_hides_a_submodule(facade):
    """A re-export named like a submodule makes ``facade.name`` the object, not the module,
    so ``monkeypatch.setattr("facade.name.attr")`` and ``import facade.name as m`` break."""
    import pkgutil

    package = importlib.import_module(facade)
    # a module façade (rcm_pin.rotations) has no submodules
    submodules = {m.name for m in pkgutil.iter_modules(getattr(package, "__path__", []))}
    clashes = {
        (facade, n)
        for n in package.__all__
        if n in submodules and not isinstance(getattr(package, n), types.ModuleType)
    }
    assert clashes <= SHADOWING, sorted(clashes - SHADOWING)


def _python_sources(path: Path) -> list[str]:
    if path.suffix == ".ipynb":
        cells = json.loads(path.read_text())["cells"]
        return ["".join(c["source"]) for c in cells if c["cell_type"] == "code"]
    return re.findall(r"```python\n(.*?)```", path.read_text(), flags=re.S)


def _imported_modules(source: str) -> set[str]:
    """Modules named by the import statements (a notebook's ``!`` / ``%`` lines dropped)."""
    lines = [ln for ln in source.splitlines() if not ln.lstrip().startswith(("!", "%"))]
    out: set[str] = set()
    for node in ast.walk(ast.parse("\n".join(lines))):
        if isinstance(node, ast.ImportFrom) and node.module:
            out.add(node.module)
        elif isinstance(node, ast.Import):
            out.update(alias.name for alias in node.names)
    return out


def _check(path: Path) -> None:
    modules = set().union(*map(_imported_modules, _python_sources(path)), set())
    ours = {m for m in modules if m.split(".")[0] in {"rcm_pin", "ocp"}}
    report = {m for m in ours if m.startswith("rcm_pin.report")}
    assert not report, f"{path.name} imports {sorted(report)}"
    deep = ours - ALLOWED
    assert not deep, f"{path.name} imports from {sorted(deep)}: use a façade (docs/api.md)"


@pytest.mark.parametrize("path", TEXTS + NOTEBOOKS, ids=lambda p: p.name)
def test_user_facing_text_imports_only_from_the_facades(path):
    _check(path)


def test_from_facade_imports_name_public_names():
    """``from rcm_pin.analysis import x`` names a public function, not a submodule."""
    for path in TEXTS + NOTEBOOKS:
        for source in _python_sources(path):
            lines = [ln for ln in source.splitlines() if not ln.lstrip().startswith(("!", "%"))]
            for node in ast.walk(ast.parse("\n".join(lines))):
                if isinstance(node, ast.ImportFrom) and node.module in api_doc.FACADES:
                    public = importlib.import_module(node.module).__all__
                    wrong = [a.name for a in node.names if a.name not in public]
                    assert not wrong, f"{path.name}: {node.module} has no public {wrong}"


@pytest.mark.parametrize("facade", ["rcm_pin.mechanisms", "rcm_pin.studies"])
def test_module_facades_list_every_module_as_an_attribute(facade):
    """``rcm_pin.mechanisms`` lists the families and ``rcm_pin.studies`` the studies (every
    module of the package, none left out), and each family package's modules are its
    attributes (``rcm.closed_form``) whether or not anything imported them before."""
    import pkgutil

    package = importlib.import_module(facade)
    assert sorted(package.__all__) == sorted(m.name for m in pkgutil.iter_modules(package.__path__))
    for name in package.__all__:
        module = getattr(package, name)
        assert isinstance(module, types.ModuleType) and module.__name__ == f"{facade}.{name}"
        for sub in pkgutil.iter_modules(getattr(module, "__path__", [])):
            assert getattr(module, sub.name).__name__ == f"{module.__name__}.{sub.name}"
        with pytest.raises(AttributeError):
            module.no_such_module  # noqa: B018


def test_a_family_module_is_imported_on_first_access():
    import subprocess

    code = (
        "import sys\n"
        "from rcm_pin.mechanisms import spherical_3rrr\n"
        "name = 'rcm_pin.mechanisms.spherical_3rrr.plots'\n"
        "assert name not in sys.modules\n"
        "assert spherical_3rrr.plots.__name__ == name and 'plots' in dir(spherical_3rrr)\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True, cwd=ROOT, timeout=120)

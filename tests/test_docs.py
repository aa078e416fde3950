"""Documentation never goes stale: the generated pages (docs/architecture.md's module table,
docs/api.md, docs/reference/), the closed mechanisms of docs/conventions.md and the notebook
list of docs/notebooks.md."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize(
    "tool",
    [
        "modules_table.py",  # docs/architecture.md: every module with its docstring
        "api_doc.py",  # docs/api.md and docs/reference/: every public name of the façades
    ],
)
def test_generated_docs_are_current(tool):
    done = subprocess.run(
        [sys.executable, str(ROOT / "tools" / tool), "--check"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0, done.stdout + done.stderr


def test_the_conventions_name_every_closed_catalogue_mechanism():
    """docs/conventions.md lists the closed mechanisms (the catalogue's ``closed`` kind:
    families with loop closures) where it explains the cut-open tree."""
    import rcm_pin

    text = (ROOT / "docs" / "conventions.md").read_text()
    closed = [e.name for e in rcm_pin.catalogue() if e.kind == "closed"]
    assert len(closed) >= 7
    missing = [name for name in closed if f"`{name}`" not in text]
    assert not missing, f"docs/conventions.md does not name {missing}"


def test_the_notebooks_page_names_every_notebook():
    """docs/notebooks.md names each notebook of notebooks/ (by file stem)."""
    text = (ROOT / "docs" / "notebooks.md").read_text()
    notebooks = sorted(p.stem for p in (ROOT / "notebooks").glob("*.ipynb"))
    assert len(notebooks) >= 10
    missing = [stem for stem in notebooks if f"`{stem}`" not in text]
    assert not missing, f"docs/notebooks.md does not name the notebooks {missing}"


def test_the_readme_mechanism_table_is_the_catalogue():
    """The README's mechanism table (which docs/getting_started.md includes) lists every
    catalogue entry, in the catalogue's order, with its kind."""
    import re

    import rcm_pin

    text = (ROOT / "README.md").read_text()
    table = text.split("<!-- mechanisms:")[1].split("<!-- /mechanisms -->")[0]
    rows = re.findall(r"^\| `(\w+)` \| (\w+) \|", table, flags=re.M)
    assert rows == [(e.name, e.kind) for e in rcm_pin.catalogue()]


def test_the_extras_table_names_every_extra():
    """docs/getting_started.md's table of extras has one row per extra of pyproject.toml
    (``notebooks`` is described with the notebooks, docs/notebooks.md)."""
    import re

    project = (ROOT / "pyproject.toml").read_text()  # tomllib is Python >= 3.11
    section = project.split("[project.optional-dependencies]")[1].split("\n[")[0]
    extras = set(re.findall(r"^([\w-]+) = \[", section, flags=re.M))
    assert {"design", "arms", "report", "all", "docs", "test", "notebooks"} <= extras
    text = (ROOT / "docs" / "getting_started.md").read_text()
    rows = set(re.findall(r"^\| `rcm-pin\[(\w+)\]` \|", text, flags=re.M))
    assert rows == set(extras) - {"notebooks"}
    assert "[notebooks]" in (ROOT / "docs" / "notebooks.md").read_text()

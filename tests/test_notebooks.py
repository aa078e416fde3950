"""The notebooks as stored: every one is there and stripped (no outputs, no execution counts).

They are executed once per suite, by the documentation build (myst-nb, docs/conf.py: a cell
that raises or outlasts its timeout fails the build), and tests/test_docs_site.py checks that
each one ran to the end and that its page shows its outputs; running them here as well would
double the suite's longest step for nothing more.
"""

from __future__ import annotations

from pathlib import Path

import nbformat
import pytest

NOTEBOOKS = sorted((Path(__file__).parents[1] / "notebooks").glob("*.ipynb"))


def test_notebooks_exist():
    names = [p.stem for p in NOTEBOOKS]
    assert "01_rcm_kinematics" in names, names
    assert "05_parallel_mechanisms" in names, names


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_is_stored_without_outputs(path):
    """Outputs are made by the site's build, never stored: nothing in git can be stale."""
    nb = nbformat.read(path, as_version=4)
    nbformat.validate(nb)
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert code, path.name
    kept = [i for i, c in enumerate(code) if c.outputs or c.execution_count is not None]
    assert not kept, f"{path.name}: code cells {kept} store outputs"

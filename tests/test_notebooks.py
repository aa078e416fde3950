"""Execute every notebook top to bottom (no display, no network) and check it is stripped.

The kernel is this interpreter's ipykernel, described by a temporary kernel spec, so no
``ipykernel install`` and no user-level kernel spec are involved.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import ipykernel  # noqa: F401  (the kernel the notebooks run in; part of the test extra)
import nbclient
import nbformat
import pytest

NOTEBOOKS = sorted((Path(__file__).parents[1] / "notebooks").glob("*.ipynb"))
CELL_TIMEOUT = 120  # [s] per cell

pytestmark = pytest.mark.notebooks


@pytest.fixture(scope="module")
def kernel_dirs(tmp_path_factory):
    """A kernel spec that starts ipykernel with the current interpreter."""
    root = tmp_path_factory.mktemp("kernels")
    spec = root / "rcm-pin-python"
    spec.mkdir()
    argv = [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"]
    spec.joinpath("kernel.json").write_text(
        json.dumps({"argv": argv, "display_name": "rcm-pin", "language": "python"})
    )
    return [str(root)]


def test_notebooks_exist():
    names = [p.stem for p in NOTEBOOKS]
    assert "01_rcm_kinematics" in names, names
    assert "05_parallel_mechanisms" in names, names


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_runs(path, kernel_dirs, monkeypatch):
    from jupyter_client.kernelspec import KernelSpecManager
    from jupyter_client.manager import KernelManager

    nb = nbformat.read(path, as_version=4)
    for cell in nb.cells:  # outputs are stripped in git
        if cell.cell_type == "code":
            assert cell.outputs == [] and cell.execution_count is None, path.name
    monkeypatch.setenv("MPLBACKEND", "Agg")
    ksm = KernelSpecManager(kernel_dirs=kernel_dirs, ensure_native_kernel=False)
    km = KernelManager(kernel_name="rcm-pin-python", kernel_spec_manager=ksm)
    client = nbclient.NotebookClient(
        nb, km=km, timeout=CELL_TIMEOUT, resources={"metadata": {"path": str(path.parent)}}
    )
    client.execute()
    errors = [o for c in nb.cells for o in c.get("outputs", []) if o.output_type == "error"]
    assert not errors

"""The documentation site builds with warnings as errors, its API reference documents every
public name of every façade (tools/api_doc.py FACADES) with its docstring, and every notebook
of notebooks/ is a page that shows its outputs.

The build is the one of docs/development.md, ``python -m sphinx -W -b html docs OUT``, into
a temporary folder; it executes the notebooks (myst-nb, docs/conf.py), the only time the suite
runs them (about 70 s on the project's idle 2-core machine, 55 s of them the notebooks)."""

from __future__ import annotations

import html as html_lib
import importlib
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
import api_doc  # noqa: E402

pytest.importorskip("sphinx", reason="the docs extra (pip install -e '.[docs]') is missing")
pytest.importorskip("myst_parser", reason="the docs extra (pip install -e '.[docs]') is missing")
pytest.importorskip("myst_nb", reason="the docs extra (pip install -e '.[docs]') is missing")
nbformat = pytest.importorskip("nbformat", reason="the docs extra (pip install -e '.[docs]')")

NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("site")  # myst-nb keeps the executed notebooks beside OUT
    out = root / "html"
    done = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-T", "-q", "-b", "html"]
        + ["-d", str(root / ".doctrees"), str(ROOT / "docs"), str(out)],
        capture_output=True,
        text=True,
        timeout=1200,  # ten notebooks of at most 120 s a cell (docs/conf.py) on a busy machine
        check=False,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    return out


def test_every_page_of_docs_is_in_the_site(site):
    pages = sorted(p.stem for p in (ROOT / "docs").glob("*.md"))
    assert len(pages) >= 20
    missing = [name for name in pages if not (site / f"{name}.html").is_file()]
    assert not missing, f"pages not built: {missing}"


@pytest.mark.parametrize("facade", api_doc.FACADES)
def test_the_reference_documents_every_public_name(site, facade):
    """Each name of the façade's ``__all__`` is an entry of its reference page (an anchor
    ``facade.name``, or the module's for a module), followed by its docstring's summary."""
    html = (site / "reference" / f"{facade}.html").read_text()
    package = importlib.import_module(facade)
    missing = []
    for name in package.__all__:
        obj = getattr(package, name)
        if isinstance(obj, type(sys)):  # a module: a section titled with its name
            if f'<span class="pre">{obj.__name__}</span></code>' not in html:
                missing.append(name)
            continue
        # a re-export documented once already (:no-index:) has no anchor: its signature
        signature = rf'<span class="sig-name descname"><span class="pre">{name}<'
        if f'id="{facade}.{name}"' not in html and not re.search(signature, html):
            missing.append(name)
    assert not missing, f"{facade}: not in the reference: {missing}"
    text = " ".join(html_lib.unescape(re.sub(r"<[^>]+>", " ", html)).split())
    undocumented = [
        n for n in package.__all__ if _plain_words(api_doc.summary(package, n)) not in text
    ]
    assert len(undocumented) <= len(package.__all__) // 10, (
        f"{facade}: docstrings not shown: {undocumented}"
    )


def _plain_words(summary: str) -> str:
    """The longest run (up to four) of consecutive words of a summary that carry no reST
    markup or quotes, as the page shows them."""
    runs, run = [], []
    for word in summary.split():
        if re.fullmatch(r"[A-Za-z0-9,;.()/=+-]+", word) and "--" not in word:
            run.append(word)
        else:
            runs.append(run)
            run = []
    best = max([*runs, run], key=len)
    return " ".join(best[:4])


#: What a top-level line of a code cell promises the page shows: (pattern, output type).
PROMISES = {
    "a figure": (r"^(plt\.show\(\)|display\(Image\()", "image/png"),
    "a Meshcat scene": (r"^(show\(|display\(HTML\()", "text/html"),
    "printed figures": (r"\bprint\(", "stream"),
    "a table": (r"^display\(Markdown\(", "text/markdown"),
}


def _kinds(cell) -> set[str]:
    kinds = set()
    for output in cell.outputs:
        if output.output_type == "stream" and output.name == "stdout":
            kinds.add("stream")
        kinds.update(output.get("data", {}))
    return kinds


def _text(html: str) -> str:
    return " ".join(html_lib.unescape(re.sub(r"<[^>]+>", " ", html)).split())


@pytest.mark.notebooks
@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_every_notebook_is_a_page_with_its_outputs(site, path):
    """The notebook ran to its end without an error; each cell shows what its code promises
    (a figure for plt.show() or display(Image(...)), a scene for an embedded Meshcat page,
    text for print, a table for a Markdown table); and its page, linked from the notebooks
    page, shows every figure, scene, printed line and table of the executed notebook."""
    page = site / "notebooks" / f"{path.stem}.html"
    assert page.is_file(), f"{path.stem}: no page"
    assert f'href="notebooks/{path.stem}.html"' in (site / "notebooks.html").read_text()
    executed = nbformat.read(site.parent / "jupyter_execute" / "notebooks" / path.name, 4)
    code = [c for c in executed.cells if c.cell_type == "code"]
    assert all(c.execution_count is not None for c in code), f"{path.stem}: not run to its end"
    errors = [o for c in code for o in c.outputs if o.output_type == "error"]
    assert not errors, f"{path.stem}: {errors}"
    broken = [
        (i, what)
        for i, cell in enumerate(code)
        for what, (pattern, kind) in PROMISES.items()
        if re.search(pattern, cell.source, flags=re.M) and kind not in _kinds(cell)
    ]
    assert not broken, f"{path.stem}: code cells without their output: {broken}"

    html = page.read_text()
    outputs = [o for c in code for o in c.outputs]
    images = re.findall(r'<img [^>]*src="([^"]+)"', html)
    pngs = [o for o in outputs if "image/png" in o.get("data", {})]
    assert len(images) >= len(pngs), f"{path.stem}: {len(pngs)} figures, {len(images)} shown"
    missing = [src for src in images if not (page.parent / src).resolve().is_file()]
    assert not missing, f"{path.stem}: images not in the site: {missing}"
    scenes = [o for o in outputs if "<iframe" in o.get("data", {}).get("text/html", "")]
    assert html.count("<iframe srcdoc=") == len(scenes), f"{path.stem}: Meshcat scenes"
    tables = [
        o
        for o in outputs
        if re.search(r"^\|\s*:?-{3}", o.get("data", {}).get("text/markdown", ""), flags=re.M)
    ]
    assert html.count("<table") >= len(tables), f"{path.stem}: Markdown tables"
    text = _text(html)
    printed = [o.text for o in outputs if o.output_type == "stream" and o.name == "stdout"]
    lost = [line for t in printed for line in t.splitlines() if " ".join(line.split()) not in text]
    assert not lost, f"{path.stem}: printed lines not on the page: {lost[:3]}"

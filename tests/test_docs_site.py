"""The documentation site builds with warnings as errors, and its API reference documents
every public name of every façade (tools/api_doc.py FACADES) with its docstring.

The build is the one of docs/development.md, ``python -m sphinx -W -b html docs OUT``, into
a temporary folder (about 15 s on the project's 2-core machine)."""

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


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("site")
    done = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html"]
        + ["-d", str(out / ".doctrees"), str(ROOT / "docs"), str(out)],
        capture_output=True,
        text=True,
        timeout=600,
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

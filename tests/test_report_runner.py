"""The report runner: sections in parallel processes, each cached by what it depends on."""

from __future__ import annotations

import importlib
import json

import fake_sections
import pytest

from rcm_pin.report import cache, runner
from rcm_pin.report.sections import SECTIONS, section_function

SMALL = [("small", "fake_sections")]


def test_a_rerun_reuses_the_cache_until_a_file_it_wrote_changes(tmp_path):
    fake_sections.CALLS.clear()
    first = list(runner.run_sections(SMALL, tmp_path, jobs=1))
    assert [o.cached for o in first] == [False] and fake_sections.CALLS == ["small"]
    assert (tmp_path / "small.txt").read_text() == "figure"
    assert not (tmp_path / ".work" / "small").exists()
    second = list(runner.run_sections(SMALL, tmp_path, jobs=1))
    assert [o.cached for o in second] == [True] and fake_sections.CALLS == ["small"]
    assert second[0].section == first[0].section
    (tmp_path / "small.txt").write_text("edited by hand")
    with pytest.warns(cache.CacheWarning, match="small.txt has changed"):
        third = list(runner.run_sections(SMALL, tmp_path, jobs=1))
    assert [o.cached for o in third] == [False] and fake_sections.CALLS == ["small", "small"]
    forced = list(runner.run_sections(SMALL, tmp_path, jobs=1, cache=False))
    assert [o.cached for o in forced] == [False]


def test_a_changed_key_recomputes(tmp_path):
    list(runner.run_sections(SMALL, tmp_path, jobs=1))
    entry = tmp_path / ".cache" / "small.json"
    data = json.loads(entry.read_text())
    data["key"] = "0" * 64  # as if a source the section depends on had changed
    data["checksum"] = cache._checksum(data)  # an intact entry of another key
    entry.write_text(json.dumps(data))
    assert [o.cached for o in runner.run_sections(SMALL, tmp_path, jobs=1)] == [False]


def test_parallel_sections_keep_their_files_apart(tmp_path):
    chosen = [*SMALL, ("other", "fake_sections_other")]
    outcomes = {o.name: o for o in runner.run_sections(chosen, tmp_path, jobs=2)}
    assert set(outcomes) == {"small", "other"}
    assert (tmp_path / "small.txt").read_text() == "figure"
    assert (tmp_path / "other.txt").read_text() == "other"
    assert outcomes["other"].section.title == "Other"


def test_every_section_module_has_its_function():
    for _, module in SECTIONS:
        assert callable(section_function(module)), module
        assert importlib.import_module(module).__name__ == module


def test_a_section_key_covers_the_modules_it_imports():
    """The key of a report section follows the sources it imports (grimp's import graph)."""
    graph = runner._graph()
    _, module = SECTIONS[0]
    upstream = graph.find_upstream_modules(module)
    assert "rcm_pin.catalog.loading" in upstream and "rcm_pin.cli" not in upstream
    assert runner.cache_key(module) == runner.cache_key(module)
    assert runner.cache_key(module) != runner.cache_key(SECTIONS[1][1])


def test_every_section_key_covers_the_kernel_providers(monkeypatch):
    """ocp.kernels is loaded at run time (an entry point), imported by no section: a change
    to it changes every section's key."""
    before = {m: runner.cache_key(m) for _, m in SECTIONS}
    original = runner._sha

    def edited(path):
        sha = original(path)
        return "edited" + sha if "ocp/kernels/closure_kernel.py" in str(path) else sha

    monkeypatch.setattr(runner, "_sha", edited)
    after = {m: runner.cache_key(m) for _, m in SECTIONS}
    assert all(after[m] != before[m] for m in before), "a key ignores ocp/kernels"

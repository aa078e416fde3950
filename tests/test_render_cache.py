"""The xacro render cache: keyed on every file xacro read, verified on read, never in the
checkout; and ``urdf --check`` on files in urdf/ that are no catalogue rendering."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

import rcm_pin
from rcm_pin.catalog import files
from rcm_pin.errors import XacroArgumentError
from rcm_pin.model import render_cache
from rcm_pin.model.render import render_xacro
from rcm_pin.model.render_cache import CacheWarning, cache_key, render_dir
from rcm_pin.model.resources import urdf_dir

ROOT = Path(__file__).resolve().parents[1]

MAIN = """<?xml version="1.0"?>
<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:include filename="../lib/part.xacro"/>
  <xacro:part/>
</robot>
"""
PART = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="part"><link name="{name}"/></xacro:macro>
</robot>
"""


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """A fresh cache folder and an empty memory cache."""
    monkeypatch.setenv("RCM_PIN_CACHE", str(tmp_path / "cache"))
    monkeypatch.setattr(render_cache, "_memory", {})
    return tmp_path / "cache" / "xacro-renders"


@pytest.fixture
def model(tmp_path):
    """A xacro in model/ including ../lib/part.xacro (another folder)."""
    (tmp_path / "model").mkdir()
    (tmp_path / "lib").mkdir()
    (tmp_path / "lib" / "part.xacro").write_text(PART.format(name="first"))
    main = tmp_path / "model" / "r.urdf.xacro"
    main.write_text(MAIN)
    return main


def test_key_depends_on_arguments_content_and_place(tmp_path):
    spec = rcm_pin.catalog.get_entry("rcm_bevel")
    k1 = cache_key(spec.xacro_path, {"l9": "0.2"})
    assert k1 != cache_key(spec.xacro_path, {"l9": "0.3"})
    copy = tmp_path / spec.xacro
    shutil.copy(spec.xacro_path, copy)
    assert cache_key(copy, {"l9": "0.2"}) != k1  # another place: its includes may differ
    key = cache_key(copy, {"l9": "0.2"})
    copy.write_text(copy.read_text() + "\n<!-- edit -->\n")
    assert cache_key(copy, {"l9": "0.2"}) != key


def test_edited_include_in_another_folder_renders_again_in_a_fresh_process(model, tmp_path):
    env = {**os.environ, "RCM_PIN_CACHE": str(tmp_path / "cache"), "PYTHONPATH": str(ROOT)}
    code = "import sys; from rcm_pin.model.render import render_xacro; "
    code += "print(render_xacro(sys.argv[1]))"

    def render() -> str:
        run = subprocess.run([sys.executable, "-c", code, str(model)], env=env,
                             capture_output=True, text=True, check=True)  # fmt: skip
        return run.stdout

    assert '<link name="first"/>' in render()
    assert list((tmp_path / "cache" / "xacro-renders").glob("*.json"))
    (tmp_path / "lib" / "part.xacro").write_text(PART.format(name="second"))
    assert '<link name="second"/>' in render()


def test_edited_include_renders_again_in_this_process(cache, model, tmp_path):
    assert '<link name="first"/>' in render_xacro(model)
    (tmp_path / "lib" / "part.xacro").write_text(PART.format(name="second"))
    assert '<link name="second"/>' in render_xacro(model)


def _entry(cache: Path) -> Path:
    (entry,) = cache.glob("*.json")
    return entry


@pytest.mark.parametrize(
    "damage",
    [
        lambda text: text[: len(text) // 2],  # truncated
        lambda text: text.replace('name=\\"first\\"', 'name=\\"forged\\"'),  # edited
        lambda text: "",  # empty
    ],
    ids=["truncated", "edited", "empty"],
)
def test_damaged_entry_is_rendered_again_with_a_warning(cache, model, monkeypatch, damage):
    fresh = render_xacro(model)
    entry = _entry(cache)
    entry.write_text(damage(entry.read_text()))
    monkeypatch.setattr(render_cache, "_memory", {})  # as a new process
    with pytest.warns(CacheWarning, match=f"render cache entry {entry} is damaged"):
        assert render_xacro(model) == fresh
    document = json.loads(entry.read_text())  # replaced by a good entry
    assert document["urdf"] == fresh and len(document["sha256"]) == 64
    monkeypatch.setattr(render_cache, "_memory", {})
    with warnings.catch_warnings():
        warnings.simplefilter("error", CacheWarning)
        assert render_xacro(model) == fresh


def test_entry_written_by_rename_with_no_temporary_left(cache, model):
    render_xacro(model)
    assert [p.suffix for p in cache.iterdir()] == [".json"]


def test_bad_xacro_is_still_blamed_on_the_xacro(cache, tmp_path):
    bad = tmp_path / "bad.urdf.xacro"
    bad.write_text("<robot name='r'><link")
    with pytest.raises(XacroArgumentError, match=r"bad\.urdf\.xacro is not valid XML"):
        render_xacro(bad)


def test_cache_folder_in_the_checkout_is_redirected(model, tmp_path, monkeypatch):
    monkeypatch.setattr(render_cache, "_memory", {})
    monkeypatch.setattr(render_cache, "_redirected", set())
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    monkeypatch.setenv("RCM_PIN_CACHE", str(urdf_dir().resolve().parent))
    before = sorted(p.name for p in urdf_dir().iterdir())
    with pytest.warns(CacheWarning, match="renders cached in"):
        folder = render_dir()
    assert folder == tmp_path / "home" / ".cache" / "rcm-pin" / "xacro-renders"
    with warnings.catch_warnings():
        warnings.simplefilter("error", CacheWarning)  # said once
        render_xacro(model)
    assert sorted(p.name for p in urdf_dir().iterdir()) == before
    assert list(folder.glob("*.json"))


@pytest.fixture
def shipped_copy(tmp_path, monkeypatch):
    """A copy of urdf/ that check_rendered reads instead of the checkout's."""
    copy = shutil.copytree(urdf_dir(), tmp_path / "urdf")
    monkeypatch.setattr(files, "urdf_dir", lambda: copy)
    return copy


def test_urdf_check_fails_on_a_stray_file(shipped_copy, capsys):
    from rcm_pin.cli import main

    assert files.check_rendered() == []
    (shipped_copy / "0123abcd.urdf").write_text("<robot name='stray'/>")
    assert files.check_rendered() == ["0123abcd.urdf"]
    assert main(["urdf", "--check", "--json"]) == 1
    assert json.loads(capsys.readouterr().out) == {
        "stale": ["0123abcd.urdf"],
        "strays": ["0123abcd.urdf"],
    }


def test_package_and_environment_lookups_are_part_of_the_entry(cache, tmp_path, monkeypatch):
    (tmp_path / "pkg_a").mkdir()
    (tmp_path / "pkg_a" / "package.xml").write_text("<package><name>pkg_a</name></package>")
    (tmp_path / "pkg_a" / "part.xacro").write_text(PART.format(name="from_a"))
    main = tmp_path / "m.urdf.xacro"
    main.write_text(
        '<robot name="$(optenv RCM_PIN_TEST_NAME plain)" '
        'xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:include filename="$(find pkg_a)/part.xacro"/><xacro:part/></robot>'
    )
    monkeypatch.delenv("RCM_PIN_TEST_NAME", raising=False)
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(tmp_path / "pkg_a"))
    assert '<robot name="plain">' in render_xacro(main)
    monkeypatch.setenv("RCM_PIN_TEST_NAME", "named")
    assert '<robot name="named">' in render_xacro(main)
    document = json.loads(_entry_named(cache, main))
    assert document["finds"] == [["pkg_a", str((tmp_path / "pkg_a").resolve())]]
    assert document["env"] == [["RCM_PIN_TEST_NAME", "named"]]


def _entry_named(cache: Path, main: Path) -> str:
    (entry,) = cache.glob("*.json")
    assert str(main.resolve()) in entry.read_text()
    return entry.read_text()


def test_cli_truncated_entry_is_a_warning_not_a_bad_xacro(tmp_path):
    env = {**os.environ, "RCM_PIN_CACHE": str(tmp_path), "PYTHONPATH": str(ROOT)}
    argv = [sys.executable, "-m", "rcm_pin", "fk", "rcm_bevel", "--q=0.1,0.2,0.08,0,0.3,0"]
    first = subprocess.run([*argv, "--json"], env=env, capture_output=True, text=True)
    assert first.returncode == 0, first.stderr
    (entry,) = (tmp_path / "xacro-renders").glob("*.json")
    entry.write_text(entry.read_text()[:3000])
    again = subprocess.run([*argv, "--json"], env=env, capture_output=True, text=True)
    assert again.returncode == 0 and json.loads(again.stdout) == json.loads(first.stdout)
    assert again.stderr == (
        f"rcm-pin: warning: render cache entry {entry} is damaged (not valid JSON); "
        "rendered again and replaced\n"
    )

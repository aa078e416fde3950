"""The committed renderings in ``urdf/``: render, write, check for staleness.

``urdf/<name>.urdf`` is the default rendering of every xacro entry of the catalogue, and
``urdf/<name>.yaml`` the LAAS-format loop sidecar of every closed one. ``rcm-pin urdf
--check`` (run in CI and by a test) fails when they differ from a fresh render, or when
``urdf/`` holds any other file (a stray render, say: nothing else belongs there).
"""

from __future__ import annotations

from pathlib import Path

from rcm_pin.catalog.table import CatalogEntry, get_entry, mechanisms
from rcm_pin.model.render import render_xacro
from rcm_pin.model.resources import urdf_dir
from rcm_pin.model.sidecar import read_description, to_yaml


def render_default(name: str, args: dict[str, str] | None = None) -> str:
    """URDF text of a shipped xacro mechanism with its fixed and the given xacro arguments.

    Raises:
        UnknownMechanismError: not a catalogue name.
        XacroArgumentError: a bad argument, or an entry that is a plain URDF.
    """
    entry = get_entry(name)
    if not entry.xacro:
        from rcm_pin.errors import XacroArgumentError

        if args:
            raise XacroArgumentError(f"{name} is a plain URDF; it takes no xacro arguments")
        return entry.urdf_path.read_text()
    return render_xacro(entry.xacro_path, {**entry.fixed_args, **(args or {})}, trusted=True)


def _rendered(entry: CatalogEntry) -> list[tuple[Path, str]]:
    urdf = render_default(entry.name)
    files = [(urdf_dir() / f"{entry.name}.urdf", urdf)]
    desc = read_description(urdf)
    if desc.loops is not None:
        files.append((urdf_dir() / f"{entry.name}.yaml", to_yaml(desc)))
    return files


def write_rendered() -> list[Path]:
    """Re-render every shipped xacro mechanism's default URDF (and sidecar) into ``urdf/``."""
    written = []
    for entry in mechanisms():
        if entry.xacro:
            for path, text in _rendered(entry):
                path.write_text(text)
                written.append(path)
    return written


def check_rendered() -> list[str]:
    """Files in ``urdf/`` that differ from a fresh render (URDFs and loop sidecars), are
    missing, or are no catalogue rendering at all (listed by name, sorted)."""
    stale = []
    for entry in mechanisms():
        if entry.xacro:
            for path, text in _rendered(entry):
                if not path.exists() or path.read_text() != text:
                    stale.append(path.name)
    return sorted(stale) + stray_files()


def stray_files() -> list[str]:
    """Names of the files in ``urdf/`` that are no catalogue rendering (sorted)."""
    expected = {f"{e.name}.{kind}" for e in mechanisms() if e.xacro for kind in ("urdf", "yaml")}
    return sorted(p.name for p in urdf_dir().iterdir() if p.name not in expected)


__all__ = ["check_rendered", "render_default", "stray_files", "write_rendered"]

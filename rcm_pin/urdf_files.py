"""The committed renderings in ``urdf/``: render, write, check for staleness."""

from __future__ import annotations

from pathlib import Path

from rcm_pin.catalog import get_spec, mechanisms
from rcm_pin.render import render_xacro


def render_default(name: str, args: dict[str, str] | None = None) -> str:
    """URDF text of a shipped mechanism with its fixed and the given xacro arguments."""
    spec = get_spec(name)
    return render_xacro(spec.xacro_path, {**spec.fixed_args, **(args or {})})


def write_rendered() -> list[Path]:
    """Re-render every shipped mechanism's default URDF into ``urdf/``."""
    written = []
    for spec in mechanisms():
        spec.urdf_path.write_text(render_default(spec.name))
        written.append(spec.urdf_path)
    return written


def check_rendered() -> list[str]:
    """Names whose committed ``urdf/<name>.urdf`` differs from a fresh render."""
    stale = []
    for spec in mechanisms():
        path = spec.urdf_path
        if not path.exists() or path.read_text() != render_default(spec.name):
            stale.append(spec.name)
    return stale

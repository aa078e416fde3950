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
    """Re-render every shipped mechanism's default URDF (and loop sidecar) into ``urdf/``."""
    from rcm_pin.closed_loop import write_rendered as write_closed

    written = []
    for spec in mechanisms():
        if spec.kind == "serial":
            spec.urdf_path.write_text(render_default(spec.name))
            written.append(spec.urdf_path)
    return written + write_closed()


def check_rendered() -> list[str]:
    """Files in ``urdf/`` that differ from a fresh render (URDFs and loop sidecars)."""
    from rcm_pin.closed_loop import check_rendered as check_closed

    stale = []
    for spec in mechanisms():
        path = spec.urdf_path
        if spec.kind == "serial" and (
            not path.exists() or path.read_text() != render_default(spec.name)
        ):
            stale.append(path.name)
    return stale + check_closed()

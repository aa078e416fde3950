"""Report section: pictures of the RCM mechanisms (Meshcat scenes, PNG snapshots).

Each scene is built with :class:`rcm_pin.viz.Viewer` (mimic model, RCM marker, tool axis),
exported as static HTML and photographed by headless Chromium; without Chromium the same
bodies and markers are rendered by matplotlib from the same camera (the URDF's visual geometry
as shaded triangles, :func:`rcm_pin.viz.drawing.fallback_png`), and the table says which route
made each picture (:func:`rcm_pin.viz.snapshot.snapshot`, the browser-else-fallback picture of
every mechanism).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rcm_pin.analysis.kinematics import rcm_error, tool_pose
from rcm_pin.catalog import load
from rcm_pin.report.framework import Section
from rcm_pin.viz.snapshot import snapshot

#: (mechanism, configuration q1..qn, caption) of every picture.
SCENES: tuple[tuple[str, tuple[float, ...], str], ...] = (
    ("rcm_bevel", (0.0, 0.0, 0.08, 0.0, 0.0, 0.0), "bevel-gear variant, home (q1 = q2 = 0)"),
    ("rcm_bevel", (0.3, -0.4, 0.09, 0.5, 0.6, 0.2), "bevel-gear variant, tilted"),
    ("rcm_belt", (-0.5, 0.5, 0.06, 0.0, 0.0, 0.0), "belt variant, tilted"),
    ("rcm_bevel_4dof", (0.4, 0.3, 0.1, 0.8), "four-DOF bevel variant (no wrist)"),
)

_METHOD = {
    "chromium": "Meshcat scene rendered by headless Chromium",
    "matplotlib": "URDF visual geometry shaded by matplotlib, same camera and markers "
    "(Chromium not available)",
}


def section(out_dir: Path) -> Section:
    """Write one PNG (and its static Meshcat page) per scene; return the markdown."""
    out_dir = Path(out_dir)
    lines = [
        "Bodies from the URDF visual geometry on the mimic model (transmission links "
        "follow q2); the red sphere is the remote centre A, the green rod the output axis "
        "e4 (drawn over the bodies in the matplotlib pictures). Each picture links its "
        "interactive static Meshcat page.",
        "",
        "| picture | mechanism, q | tool centre [m] | RCM error [m] | picture made by |",
        "| --- | --- | --- | ---: | --- |",
    ]
    figures = []
    for k, (name, q_values, caption) in enumerate(SCENES):
        mech = load(name)
        q = np.array(q_values)
        png, html = f"scene_{k}_{name}.png", f"scene_{k}_{name}.html"
        method = snapshot(mech, q, out_dir / png, html=out_dir / html)
        figures.append(png)
        p = tool_pose(mech, q)[:3, 3]
        qtxt = ", ".join(f"{v:g}" for v in q)
        lines.append(
            f"| ![{caption}]({png}) | {caption}; q = ({qtxt}) ([3-D page]({html})) "
            f"| ({p[0]:.4f}, {p[1]:.4f}, {p[2]:.4f}) | {rcm_error(mech, q):.1e} "
            f"| {_METHOD[method]} |"
        )
    return Section(title="Scenes", body="\n".join(lines), figures=tuple(figures))

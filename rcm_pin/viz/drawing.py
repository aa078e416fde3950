"""The no-browser picture: the URDF's visual geometry of any mechanism, shaded by matplotlib.

:func:`fallback_png` triangulates the visual geometry at a configuration
(:func:`rcm_pin.viz.triangles.body_meshes`: boxes, cylinders, spheres, capsules and the
meshes of example-robot-data, in their URDF material colours; grey-orange rods between the
joint origins for a URDF without visual geometry), adds the markers the Meshcat viewer
shows (:func:`rcm_pin.viz.triangles.marker_meshes`: red sphere at the RCM point A and
green rod along the insertion axis; red spheres at the cut frames of each closure; green
sphere at the output where there is no insertion axis) and draws them shaded
(:func:`rcm_pin.viz.shading.render`) from the camera of the Meshcat picture: the viewer's
own camera when given, else the one :meth:`rcm_pin.viz.viewer.Viewer.fit_camera` would
choose (:func:`rcm_pin.viz.viewer.view_direction`, :func:`rcm_pin.viz.camera.frame_points`).
Closed mechanisms are drawn at the configuration given (a closed one, as the viewer shows).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pinocchio as pin

from rcm_pin.model.mechanism import Mechanism
from rcm_pin.viz.camera import frame_points
from rcm_pin.viz.shading import render
from rcm_pin.viz.triangles import Mesh, body_meshes, marker_meshes, visual_model

#: What the picture shows, by whether the URDF has visual geometry.
WHAT = {
    True: "visual geometry shaded by matplotlib",
    False: "links as rods (no visual geometry in the URDF), shaded by matplotlib",
}


def fallback_png(
    mech: Mechanism,
    q: np.ndarray,
    png: str | Path,
    title: str = "",
    *,
    size: tuple[int, int] = (800, 600),
    camera: tuple[np.ndarray, np.ndarray] | None = None,
    geom: pin.GeometryModel | None = None,
    decorations: tuple[Sequence[Mesh], Sequence[Mesh]] = ((), ()),
) -> Path:
    """Write the shaded picture of ``mech`` at coordinates ``q`` (module docstring).

    Args:
        mech: any mechanism.
        q: coordinates (n,) [rad, m] (closed mechanisms: a closed configuration).
        png: output path.
        title: text in the top-left corner (default: the mechanism name and
            :data:`WHAT` it shows; ``"-"``: none).
        size: picture width and height [px].
        camera: (eye, target) world positions [m] (default: fitted to the bodies and
            markers, from the viewer's view direction).
        geom: the mechanism's visual GeometryModel (default: parsed from ``mech.urdf``).
        decorations: world meshes of a viewer's decorations
            (:meth:`rcm_pin.viz.viewer.Viewer.decoration_meshes`): the base plate, drawn
            first, and the others, drawn with the bodies.

    Returns:
        The PNG path.

    Raises:
        InvalidInputError: ``q`` of the wrong shape or not finite.
    """
    q = mech.check_q(q)
    geom = visual_model(mech) if geom is None else geom
    under, over = decorations
    bodies = [*body_meshes(mech, q, geom), *over]
    markers = marker_meshes(mech, q)
    if camera is None:
        from rcm_pin.viz.viewer import view_direction

        points = np.vstack([m.vertices for m in (*bodies, *markers)])
        camera = frame_points(points, view_direction(mech))
    if not title:
        title = f"{mech.name}: {WHAT[geom.ngeoms > 0]}"
    path, _ = render(bodies, markers, *camera, png, size, "" if title == "-" else title, under)
    return path


def describe(mech: Mechanism) -> str:
    """What :func:`fallback_png` shows for this mechanism (:data:`WHAT`)."""
    return WHAT[visual_model(mech).ngeoms > 0]

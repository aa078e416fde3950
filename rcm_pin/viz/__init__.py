"""Pictures of any mechanism: one Meshcat :class:`Viewer`, static HTML, PNG snapshots.

* :mod:`.viewer`: :class:`Viewer` (serial and closed mechanisms; bodies, markers, point
  sets, animations, camera);
* :mod:`.overlays`: the markers drawn from the data (RCM point and insertion axis, cut
  points, output point, point clouds);
* :mod:`.explain`: :class:`SceneStyle` (body colours of :mod:`.palette`; base plate,
  frame triads, drive rings and joint axes of :mod:`.decorations`);
  :mod:`.caption`: labels, colour key and caption on a picture (the gallery's);
* :mod:`.base`: Meshcat plumbing (visual geometry, camera, static HTML, live server on
  127.0.0.1);
* :mod:`.scene`: the in-memory Meshcat scene (no server) and colour helpers;
* :mod:`.camera`: framing and projection arithmetic;
* :mod:`.snapshot`: the browser-else-fallback picture (:func:`picture` of a viewer,
  :func:`~rcm_pin.viz.snapshot.snapshot` of a mechanism at q), headless Chromium;
* :mod:`.drawing`: the no-browser picture (visual geometry shaded by matplotlib), built on
  :mod:`.triangles` (the scene's triangle meshes) and :mod:`.shading` (projection, Lambert
  shading, painter's order).
"""

from rcm_pin.viz.explain import SceneStyle
from rcm_pin.viz.snapshot import picture
from rcm_pin.viz.viewer import Viewer

# No re-export named like a submodule (it would hide the module: rcm_pin.viz.snapshot stays
# the module, its function is imported from it).
__all__ = ["SceneStyle", "Viewer", "picture"]

"""An in-memory Meshcat scene: the viewer protocol without a server process.

:class:`SceneRecorder` implements the part of ``meshcat.visualizer.ViewerWindow`` that
``meshcat.Visualizer`` and Pinocchio's ``MeshcatVisualizer`` use (``send``,
``get_scene``). It keeps the scene tree exactly as ``meshcat-server`` does (same tree
module, same update rules) and writes the same self-contained static HTML, so scenes
and animations can be built and exported with no zmq socket, port or browser.
:func:`panes_html` puts several recorded scenes side by side on one page (Meshcat's
JavaScript once, each scene's commands gzip-compressed).
"""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any

import numpy as np
import umsgpack

with warnings.catch_warnings():  # meshcat imports pyzmq's deprecated zmq.eventloop.ioloop
    warnings.simplefilter("ignore", DeprecationWarning)
    from meshcat.servers.tree import SceneTree, find_node, walk
    from meshcat.servers.zmqserver import VIEWER_ROOT, create_command

_VIEWER_JS = 'var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));'
#: The page meshcat-server writes for ``get_scene`` (same bytes, same indentation).
_HTML = """
                <!DOCTYPE html>
                <html>
                    <head> <meta charset=utf-8> <title>MeshCat</title> </head>
                    <body>
                        <div id="meshcat-pane">
                        </div>
                        <script>
                            {mainminjs}
                        </script>
                        <script>
                            {viewer_js}
                            {commands}
                        </script>
                         <style>
                            body {{margin: 0; }}
                            #meshcat-pane {{
                                width: 100vw;
                                height: 100vh;
                                overflow: hidden;
                            }}
                        </style>
                        <script id="embedded-json"></script>
                    </body>
                </html>
            """


def hex_color(color: Any) -> int:
    """A colour as Meshcat's 0xRRGGBB integer (from an int or RGB in [0, 1])."""
    if isinstance(color, (int, np.integer)):
        return int(color)
    rgb = np.clip(np.asarray(color, dtype=float)[:3], 0.0, 1.0)
    r, g, b = (round(float(c) * 255) for c in rgb)
    return r << 16 | g << 8 | b


def colormap(values: np.ndarray, cmap: str = "viridis", vmin: float | None = None,
             vmax: float | None = None) -> np.ndarray:  # fmt: skip
    """RGB colours (N, 3) in [0, 1] for scalar values (NaN -> grey).

    Args:
        values: (N,) scalars, e.g. a singularity measure.
        cmap: a matplotlib colormap name.
        vmin: value mapped to the low end (default: the finite minimum).
        vmax: value mapped to the high end (default: the finite maximum).
    """
    import matplotlib

    v = np.asarray(values, dtype=float).ravel()
    finite = v[np.isfinite(v)]
    lo = float(finite.min()) if vmin is None and finite.size else (vmin or 0.0)
    hi = float(finite.max()) if vmax is None and finite.size else (vmax or 1.0)
    t = (v - lo) / (hi - lo) if hi > lo else np.zeros_like(v)
    rgb = np.asarray(matplotlib.colormaps[cmap](np.clip(t, 0.0, 1.0)))[:, :3]
    rgb[~np.isfinite(v)] = 0.5
    return rgb


class SceneRecorder:
    """A Meshcat "window" that records commands into a scene tree.

    Attributes:
        server_proc: always None (no server process).
        zmq_url: empty (no socket).
        web_url: empty (no web server; export with :meth:`get_scene`).
        n_commands: number of commands received.
    """

    server_proc = None
    zmq_url = ""
    web_url = ""

    def __init__(self) -> None:
        self.tree: Any = SceneTree()
        self.n_commands = 0

    def send(self, command: Any) -> None:
        """Apply one meshcat command (``SetObject``, ``SetTransform``, ...) to the tree."""
        data = command.lower()
        packed = umsgpack.packb(data)
        path = [p for p in str(data.get("path", "")).split("/") if p]
        kind = data["type"]
        self.n_commands += 1
        if kind == "set_transform":
            find_node(self.tree, path).transform = packed
        elif kind == "set_object":
            node = find_node(self.tree, path)
            node.object = packed
            node.properties = []
        elif kind == "set_property":
            find_node(self.tree, path).properties.append(packed)
        elif kind == "set_animation":
            find_node(self.tree, path).animation = packed
        elif kind == "delete":
            if path:
                parent = find_node(self.tree, path[:-1])
                parent.pop(path[-1], None)
            else:
                self.tree = SceneTree()

    def commands(self) -> list[bytes]:
        """The packed (msgpack) commands that rebuild the scene, in the order
        :meth:`get_scene` sends them (each node: object, properties, transform, animation)."""
        packed: list[bytes] = []
        for node in walk(self.tree):
            if node.object is not None:
                packed.append(node.object)
            packed.extend(node.properties)
            if node.transform is not None:
                packed.append(node.transform)
            if node.animation is not None:
                packed.append(node.animation)
        return packed

    def get_scene(self) -> str:
        """The scene as a self-contained HTML page (Meshcat's JavaScript inlined)."""
        commands = "".join(create_command(c) for c in self.commands())
        script = (Path(VIEWER_ROOT) / "main.min.js").read_text()
        return _HTML.format(mainminjs=script, viewer_js=_VIEWER_JS, commands=commands)

    def open(self) -> SceneRecorder:
        """No browser to open: export the scene with :meth:`get_scene` instead."""
        return self

    def wait(self) -> str:
        """Nothing to wait for."""
        return ""

    def connect_zmq(self) -> None:
        """No socket to connect."""

    def close(self) -> None:
        """Nothing to release."""


#: One page, several Meshcat viewers (:func:`panes_html`).
_PANES_HTML = """<!DOCTYPE html>
<html>
<head>
<meta charset=utf-8>
<title>{title}</title>
<style>
body {{display: flex; margin: 0; font-family: sans-serif;}}
figure {{flex: 1; margin: 4px; min-width: 0;}}
figcaption {{text-align: center;}}
.pane {{width: 100%; height: 90vh; position: relative; overflow: hidden;}}
.dg {{display: none !important;}}
</style>
</head>
<body>
{figures}
<script>
{mainminjs}
</script>
<script>
// Each pane's commands: gzip of (uint32 big-endian length, msgpack command) records,
// base64 in a script element; applied in order to the pane's own viewer.
async function rcmPinPane(index) {{
  const pane = document.getElementById("pane-" + index);
  const data = document.getElementById("commands-" + index).textContent.trim();
  const viewer = new MeshCat.Viewer(pane);
  const packed = await fetch("data:application/octet-stream;base64," + data);
  const stream = packed.body.pipeThrough(new DecompressionStream("gzip"));
  const bytes = new Uint8Array(await new Response(stream).arrayBuffer());
  const view = new DataView(bytes.buffer);
  for (let at = 0; at < bytes.length; ) {{
    const size = view.getUint32(at);
    viewer.handle_command_bytearray(bytes.slice(at + 4, at + 4 + size));
    at += 4 + size;
  }}
}}
for (let i = 0; i < {count}; i++) {{
  rcmPinPane(i).catch((err) => {{
    document.getElementById("pane-" + i).textContent = "could not load the scene: " + err;
  }});
}}
</script>
</body>
</html>
"""


def panes_html(panes: list[tuple[str, list[bytes]]], title: str = "MeshCat") -> str:
    """One self-contained page with one Meshcat viewer per pane, side by side.

    Meshcat's JavaScript is inlined once for all panes (a page of ``iframe`` s carried one
    copy per scene), and each pane's commands (:meth:`SceneRecorder.commands`: every mesh
    set once, the animation as transforms only) travel gzip-compressed, inflated by the
    browser's ``DecompressionStream`` (Chromium 80, Firefox 113, Safari 16.4). The
    ``Open Controls`` panel is hidden.

    Args:
        panes: (caption, packed commands) per viewer, left to right.
        title: the page title.
    """
    import base64
    import gzip
    import html
    import struct

    figures, blobs = [], []
    for i, (caption, commands) in enumerate(panes):
        records = b"".join(struct.pack(">I", len(c)) + c for c in commands)
        data = base64.b64encode(gzip.compress(records, compresslevel=6, mtime=0)).decode()
        figures.append(
            f"<figure><figcaption>{html.escape(caption)}</figcaption>"
            f'<div class="pane" id="pane-{i}"></div></figure>'
        )
        blobs.append(f'<script type="application/octet-stream" id="commands-{i}">{data}</script>')
    script = (Path(VIEWER_ROOT) / "main.min.js").read_text()
    return _PANES_HTML.format(
        title=html.escape(title),
        figures="\n".join(figures + blobs),
        mainminjs=script,
        count=len(panes),
    )

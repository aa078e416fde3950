"""A picture that explains itself: labels on the scene, a colour key, a caption beneath.

:func:`explained_png` takes a rendered scene (a PNG of either route of
:func:`rcm_pin.viz.snapshot.picture`) and draws, with matplotlib, text labels at pixel
positions (:meth:`rcm_pin.viz.viewer.Viewer.project` of
:meth:`~rcm_pin.viz.viewer.Viewer.labels`: the drives' names, ``tool`` / ``output``, ``A``),
a key of the colours in a panel on the right (:func:`key`: the bodies by colour, the
drive rings, the joint axes, the triads' arrows, the markers) and the caption in a strip
beneath, wrapped to the width. Labels that would overlap are moved down
(:func:`place_labels`), with a leader line to their point. The result is written by atomic rename.
"""

from __future__ import annotations

import io
import textwrap
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from rcm_pin.processes import atomic_write
from rcm_pin.viz.decorations import AXIS_COLORS, AXIS_ROD, DRIVE_COLOR
from rcm_pin.viz.overlays import GREEN, RED

#: Caption font size [pt] and line height [px] at 100 dpi.
CAPTION_PT, LINE_PX = 10.5, 17
#: Characters per caption line for each 100 px of picture width.
CHARS_PER_100PX = 11.5
#: Width of the key panel right of the scene [px].
KEY_PX = 270
#: Longest text of a key row (characters).
KEY_CHARS = 36
#: Label text: width of a character and height of a line [px] (9 pt, an estimate).
LABEL_CHAR_PX, LABEL_LINE_PX = 6.5, 14


def key(
    bodies: Sequence[tuple[tuple[float, ...], Sequence[str]]],
    *,
    drives: bool,
    triads: bool,
    axes: bool,
    rcm: bool,
    closed: bool,
    most: int = 3,
    chars: int = KEY_CHARS,
) -> list[tuple[tuple[float, ...], str]]:
    """The colour key of an explained scene: (RGB(A), text) rows.

    Args:
        bodies: (colour, link names) of the bodies (:func:`rcm_pin.viz.palette.legend`);
            more than ``most`` names are shortened with an ellipsis.
        drives: the drive rings are shown.
        triads: the frame triads are shown.
        axes: the joint-axis rods are shown.
        rcm: the mechanism has a remote centre (red sphere at A, green insertion axis).
        closed: the mechanism has loop closures (red spheres at the cut points).
        most: link names listed per colour.
        chars: longest text of a row (longer ones end with an ellipsis).
    """
    rows = []
    for rgba, names in bodies:
        text = ", ".join(names[:most]) + (", …" if len(names) > most else "")
        rows.append((tuple(rgba), text if len(text) <= chars else text[: chars - 1] + "…"))
    if drives:
        rows.append((DRIVE_COLOR, "ring: a driven joint"))
    if axes:
        rows.append((AXIS_ROD, "thin rod: a joint axis"))
    if triads:
        rows.append((AXIS_COLORS[0], "arrows: x, y, z (red, green, blue)"))
    if rcm:
        rows.append((RED, "sphere: remote centre A"))
        rows.append((GREEN, "green rod: insertion axis"))
    if closed:
        rows.append((RED, "small spheres: loop cut points"))
    return rows


def wrap(caption: str, width: int) -> list[str]:
    """The caption's lines for a picture ``width`` pixels wide."""
    chars = max(20, int(width / 100 * CHARS_PER_100PX))
    return textwrap.wrap(caption, chars) or [""]


def place_labels(labels: Sequence[tuple[str, np.ndarray]], size: tuple[int, int]
                 ) -> list[tuple[str, np.ndarray, np.ndarray]]:  # fmt: skip
    """(text, anchor pixel, text pixel) of each label inside the picture: up and right of
    its anchor, moved down in steps of a line until it overlaps no label placed before."""
    placed: list[tuple[float, float, float, float]] = []
    out = []
    for text, anchor in labels:
        col, row = float(anchor[0]), float(anchor[1])
        if not (0 <= col < size[0] and 0 <= row < size[1]):
            continue
        w, h = LABEL_CHAR_PX * len(text) + 6, LABEL_LINE_PX
        x, y = min(col + 8, size[0] - w), row - 8 - h
        for _ in range(40):
            box = (x, y, x + w, y + h)
            if all(
                box[2] < b[0] or box[0] > b[2] or box[3] < b[1] or box[1] > b[3] for b in placed
            ):
                break
            y += h + 1
        placed.append((x, y, x + w, y + h))
        out.append((text, np.array([col, row]), np.array([x, y + h])))
    return out


def explained_png(scene: str | Path, png: str | Path, caption: str,
                  labels: Sequence[tuple[str, np.ndarray]] = (),
                  rows: Sequence[tuple[tuple[float, ...], str]] = ()) -> Path:  # fmt: skip
    """Write ``scene`` with labels, colour key and caption (module docstring).

    Args:
        scene: the rendered scene (PNG).
        png: output path (written by atomic rename).
        caption: text under the picture and key (wrapped).
        labels: (text, (column, row) pixel of the scene) pairs.
        rows: the colour key (:func:`key`), in a panel right of the scene.

    Returns:
        The PNG path.
    """
    from matplotlib.figure import Figure
    from matplotlib.image import imread

    img = imread(str(scene))
    h, w = img.shape[:2]
    panel = KEY_PX if rows else 0
    width = w + panel
    lines = wrap(caption, width)
    strip = LINE_PX * len(lines) + 14
    total = h + strip
    fig = Figure(figsize=(width / 100, total / 100), dpi=100, facecolor="white")
    ax = fig.add_axes((0.0, strip / total, w / width, h / total))
    ax.imshow(img, interpolation="none")
    ax.set_xlim(0, w)
    ax.set_ylim(h, 0)
    ax.set_axis_off()
    box = {"boxstyle": "round,pad=0.15", "facecolor": "white", "alpha": 0.8, "linewidth": 0}
    for text, anchor, at in place_labels(labels, (w, h)):
        if np.linalg.norm(at - anchor) > 3 * LABEL_LINE_PX:  # moved away: a leader line
            ax.plot([anchor[0], at[0]], [anchor[1], at[1]], color="0.4", linewidth=0.6)
        ax.text(at[0] + 3, at[1] - 3, text, fontsize=9, color="0.1", bbox=box)
    if rows:
        kx = fig.add_axes((w / width, strip / total, panel / width, h / total))
        kx.set_xlim(0, panel)
        kx.set_ylim(h, 0)
        kx.set_axis_off()
        for k, (rgba, text) in enumerate(rows):
            y = 24 + 18 * k
            kx.plot([6, 22], [y, y], color=rgba[:3], linewidth=7, solid_capstyle="butt")
            kx.text(28, y, text, fontsize=8.5, va="center", color="0.15")
    fig.text(0.01, (strip - 8) / total, "\n".join(lines), ha="left", va="top",
             fontsize=CAPTION_PT, color="0.1", linespacing=1.25)  # fmt: skip
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=100, facecolor="white")
    path = Path(png)
    path.parent.mkdir(parents=True, exist_ok=True)
    return atomic_write(path, buffer.getvalue())

"""The gallery: one picture per catalogue mechanism that explains it, and docs/gallery.md.

Usage::

    python tools/gallery.py              # render every picture, rewrite the page and manifest
    python tools/gallery.py NAME [NAME]  # only these pictures (the others' entries kept)
    python tools/gallery.py --check      # exit 1 if a picture, caption or entry is missing
                                         # or stale (tests/test_gallery.py runs it)

Each picture is a :class:`rcm_pin.viz.Viewer` in the explained style
(:data:`rcm_pin.viz.explain.EXPLAINED`: a colour per body where the URDF sets none, a base
plate, frame triads at the output / tool frame and at A, a ring on every driven joint's
axis, a rod along every joint axis) at the pose, camera and colours of ``SHOTS``
(tools/gallery_shots.py), rendered by headless Chromium (else matplotlib, the manifest
says which), then labelled, keyed and captioned
(:func:`rcm_pin.viz.caption.explained_png`) into ``docs/images/gallery/<name>.png``.

Staleness: PNG bytes from Chromium (SwiftShader) are not promised to be reproducible, so
the check does not compare pictures. ``docs/images/gallery/manifest.json`` records, per
mechanism, the caption, the route and a SHA-256 of the *scene*: every Meshcat command
of the viewer (bodies, their colours and placements, markers, decorations, camera; the
random object UUIDs replaced by their order, floats rounded to 1e-9) plus the labels and
the picture size. ``--check`` rebuilds each scene (no rendering, a few seconds) and
compares; a change of a URDF, a pose, a colour or the viewer's drawing shows as stale.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import re
import sys
from pathlib import Path
from typing import Any

import numpy as np
import umsgpack

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import rcm_pin  # noqa: E402
from rcm_pin.catalog.table import get_entry  # noqa: E402
from rcm_pin.processes import atomic_write, folder_lock  # noqa: E402
from rcm_pin.viz.caption import explained_png, key  # noqa: E402
from rcm_pin.viz.decorations import drives  # noqa: E402
from rcm_pin.viz.explain import EXPLAINED, SceneStyle  # noqa: E402
from rcm_pin.viz.palette import legend  # noqa: E402
from rcm_pin.viz.snapshot import picture  # noqa: E402
from rcm_pin.viz.viewer import Viewer  # noqa: E402

sys.path.insert(0, str(ROOT / "tools"))
from gallery_shots import SHOTS, Shot  # noqa: E402

__all__ = ["SHOTS", "Shot", "check", "main", "render"]

IMAGES = ROOT / "docs" / "images" / "gallery"
MANIFEST = IMAGES / "manifest.json"
PAGE = ROOT / "docs" / "gallery.md"
#: Size of the rendered scene [px] (the caption strip is added beneath).
SIZE = (800, 560)
_UUID = re.compile(r"^[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}$")


def viewer(name: str) -> Viewer:
    """The explained scene of one mechanism at its shot's pose, camera fitted."""
    mech, shot = rcm_pin.load(name), SHOTS[name]
    view = Viewer(mech, snapshot_style=True, style=SceneStyle(shot.colors))
    if shot.inputs is not None:
        view.display_inputs(np.array(shot.inputs))
    view.show_style(EXPLAINED)  # the base plate sized at the pose shown
    view.fit_camera(None if shot.view is None else np.array(shot.view))
    return view


def caption(name: str, view: Viewer) -> str:
    """The caption: the catalogue's description, the shot's text, the drives, A."""
    mech = view.mech
    driven = drives(mech)
    if mech.loops is None:
        listed = ", ".join(f"{c} ({j})" for c, j in driven.items())
        moves = f"Driven (magenta rings): the joint of each coordinate, {listed}."
    else:
        n_passive = len(mech.loops.passive)
        moves = (
            f"Driven (magenta rings): {', '.join(driven)}; the other {n_passive} joints are "
            "passive, solved to close the loops."
        )
    parts = [f"{name}: {get_entry(name).description}.", SHOTS[name].text, moves]
    if mech.rcm is not None:
        data = mech.model.createData()
        import pinocchio as pin

        pin.forwardKinematics(mech.model, data, mech.to_pin(view.q))
        a = pin.updateFramePlacement(mech.model, data, mech.rcm.point_frame_id).translation
        at = ", ".join(f"{1000 * c:.0f}" for c in a)
        parts.append(
            f"Remote centre A (red sphere) at ({at}) mm: the insertion axis (green) passes "
            "through it at every configuration."
        )
    out = "output" if mech.loops is not None else "tool"
    parts.append(f"Arrows: the {out} frame ({mech.output.frame})" +
                 (" and the frame at A." if mech.rcm is not None else "."))  # fmt: skip
    return " ".join(p for p in parts if p)


def _canonical(value: Any, uuids: dict[str, int]) -> Any:
    """A JSON-able copy of an unpacked Meshcat command: UUIDs by order, floats to 1e-9."""
    if isinstance(value, dict):
        return {str(k): _canonical(v, uuids) for k, v in sorted(value.items())}
    if isinstance(value, (list, tuple)):
        return [_canonical(v, uuids) for v in value]
    if isinstance(value, float):
        return round(value, 9)
    if isinstance(value, str) and _UUID.match(value):
        return f"uuid{uuids.setdefault(value, len(uuids))}"
    if isinstance(value, umsgpack.Ext):
        return f"ext{value.type}:{hashlib.sha256(value.data).hexdigest()}"
    if isinstance(value, bytes):
        return hashlib.sha256(value).hexdigest()
    return value


def scene_digest(view: Viewer, labels: list[tuple[str, list[float]]]) -> str:
    """SHA-256 of the scene (module docstring), its labels and the picture size."""
    uuids: dict[str, int] = {}
    commands = [_canonical(umsgpack.unpackb(c), uuids) for c in view.scene_commands()]
    shot = SHOTS[view.mech.name]
    data = {"commands": commands, "labels": labels, "size": SIZE, "browser": shot.browser}
    blob = json.dumps(data, sort_keys=True)
    return hashlib.sha256(blob.encode()).hexdigest()


def describe(name: str) -> tuple[Viewer, str, list[tuple[str, list[float]]], str]:
    """(viewer, caption, pixel labels, scene digest) of one mechanism."""
    view = viewer(name)
    labels = [(text, [round(float(c), 1) for c in view.project(p, SIZE)[0]])
              for text, p in view.labels()]  # fmt: skip
    return view, caption(name, view), labels, scene_digest(view, labels)


def render(name: str) -> dict[str, Any]:
    """Write one picture; returns its manifest entry."""
    view, text, labels, digest = describe(name)
    mech = view.mech
    rows = key(legend(mech.model, view.viz.visual_model), drives=True, triads=True, axes=True,
               rcm=mech.rcm is not None, closed=mech.loops is not None)  # fmt: skip
    scene = IMAGES / f".{name}.scene.png"
    try:
        route = picture(view, scene, size=SIZE, browser=SHOTS[name].browser)
        explained_png(scene, IMAGES / f"{name}.png", text,
                      [(t, np.array(p)) for t, p in labels], rows)  # fmt: skip
    finally:
        scene.unlink(missing_ok=True)
        view.close()
    return {"caption": text, "route": route, "scene": digest}


def page(manifest: dict[str, dict[str, Any]]) -> str:
    """docs/gallery.md from the manifest (catalogue order)."""
    out = [
        "# Gallery",
        "",
        "One picture per catalogue mechanism, made by `python tools/gallery.py` "
        "(`--check`, run by the tests, fails when one is missing or stale: it compares a "
        "digest of each Meshcat scene with `docs/images/gallery/manifest.json`, not the PNG "
        "bytes, which headless Chromium does not promise to reproduce). Each shows the "
        "mechanism in the viewer's explained style (`SceneStyle.explained()`, "
        "[Visualisation](visualisation.md)): a colour per body where the URDF sets none "
        "(the ground grey), a base plate, a magenta ring on the axis of every driven joint, "
        "a thin dark rod along every joint axis, red-green-blue arrows for the x, y, z axes "
        "of the output (tool) frame and of the remote centre A. The key on the right names "
        "the bodies by colour; the caption says what they are, which joints are driven and "
        "where A is.",
        "",
    ]
    for name in rcm_pin.names():
        if name in manifest:
            entry = manifest[name]
            out += [f"## {name}", "", f"![{name}](images/gallery/{name}.png)", "",
                    entry["caption"], ""]  # fmt: skip
    return "\n".join(out)


def _read_manifest() -> dict[str, dict[str, Any]]:
    return json.loads(MANIFEST.read_text()) if MANIFEST.exists() else {}


def _write(manifest: dict[str, dict[str, Any]]) -> None:
    ordered = {n: manifest[n] for n in rcm_pin.names() if n in manifest}
    atomic_write(MANIFEST, (json.dumps(ordered, indent=1) + "\n").encode())
    atomic_write(PAGE, page(ordered).encode())


def check(only: list[str] | None = None) -> list[str]:
    """What is missing or stale (empty: the gallery is up to date); ``only``: rebuild and
    compare the scenes of these mechanisms only (default: all)."""
    problems, manifest = [], _read_manifest()
    names = rcm_pin.names()
    problems += [f"{n}: no shot in tools/gallery.py SHOTS" for n in names if n not in SHOTS]
    problems += [f"{n}: in SHOTS but not in the catalogue" for n in SHOTS if n not in names]
    problems += [
        f"{n}: in the manifest but not in the catalogue" for n in manifest if n not in names
    ]
    for name in (n for n in names if n in SHOTS and (only is None or n in only)):
        entry, png = manifest.get(name), IMAGES / f"{name}.png"
        if entry is None or not png.exists():
            problems.append(f"{name}: no picture (run python tools/gallery.py {name})")
            continue
        if png.read_bytes()[:8] != b"\x89PNG\r\n\x1a\n":
            problems.append(f"{name}: {png.relative_to(ROOT)} is not a PNG")
        view, text, _, digest = describe(name)
        view.close()
        if text != entry.get("caption") or digest != entry.get("scene"):
            what = "caption" if text != entry.get("caption") else "scene"
            problems.append(f"{name}: stale {what} (run python tools/gallery.py {name})")
    if not PAGE.exists() or PAGE.read_text() != page(manifest):
        problems.append("docs/gallery.md is stale (run python tools/gallery.py)")
    return problems


def main(argv: list[str] | None = None) -> int:
    """Command line (module docstring)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("names", nargs="*", help="mechanisms to render (default: all)")
    parser.add_argument("--check", action="store_true", help="check, write nothing")
    args = parser.parse_args(argv)
    if args.check:
        problems = check()
        for p in problems:
            print(p, file=sys.stderr)
        return 1 if problems else 0
    unknown = [n for n in args.names if n not in SHOTS]
    if unknown:
        print(f"unknown: {', '.join(unknown)}; valid: {', '.join(SHOTS)}", file=sys.stderr)
        return 2
    IMAGES.mkdir(parents=True, exist_ok=True)
    with folder_lock(IMAGES, "docs/images/gallery"):  # one gallery run at a time
        manifest = _read_manifest()
        for name in args.names or list(SHOTS):
            manifest[name] = render(name)
            _write(manifest)  # each picture recorded as it is made
            print(f"{name}: {manifest[name]['route']}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

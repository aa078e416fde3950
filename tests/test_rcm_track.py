"""``rcm-pin rcm-track``: the surgical task on arms and on the mechanical RCM, checked from
the returned joint trajectory by yourdfpy forward kinematics of the URDF (independent of
Pinocchio); the study's typed errors."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import yourdfpy

import rcm_pin
from rcm_pin.cli import main
from rcm_pin.errors import InvalidInputError, UnreachablePoseError
from rcm_pin.studies.rcm_comparison import choose_trocar, make_setup, run
from rcm_pin.studies.surgical_paths import Cone, surgical_path
from rcm_pin.viz.assets import assets

#: The URDF's transforms composed in another order than Pinocchio's: round-off only.
FK = 1e-12


def _rotation(axis, angle):
    k = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


class _UrdfFk:
    """Forward kinematics of the URDF as parsed by yourdfpy, composed here joint by joint
    (origin, then the motion along the axis; mimic joints from their multiplier and
    offset). yourdfpy's own scene graph is not used: it keeps a cached transform when a
    joint moves by less than about 1e-8 (seen on these 1 kHz samples)."""

    def __init__(self, mech):
        urdf = yourdfpy.URDF._parse_robot(yourdfpy.urdf.etree.fromstring(mech.urdf.encode()))
        self.by_child = {j.child: j for j in urdf.joints}
        self.by_name = {j.name: j for j in urdf.joints}

    def value(self, joint, cfg):
        if joint.mimic is not None:
            m = joint.mimic
            return (m.multiplier or 1.0) * self.value(self.by_name[m.joint], cfg) + (
                m.offset or 0.0
            )
        return cfg.get(joint.name, 0.0)

    def transform(self, link, cfg):
        T = np.eye(4)
        while link in self.by_child:
            j = self.by_child[link]
            M = np.eye(4)
            if j.type in ("revolute", "continuous"):
                M[:3, :3] = _rotation(j.axis, self.value(j, cfg))
            elif j.type == "prismatic":
                M[:3, 3] = np.asarray(j.axis) / np.linalg.norm(j.axis) * self.value(j, cfg)
            origin = np.eye(4) if j.origin is None else j.origin
            T = origin @ M @ T
            link = j.parent
        return T


def _cli(capsys, *argv):
    rc = main(["rcm-track", *argv, "--json"])
    return rc, json.loads(capsys.readouterr().out)


def _recompute(doc):
    """(RCM error, tip error) of every row of q by yourdfpy FK: distance of the trocar
    from the line through the shaft frame's origin along its axis, and the tip error."""
    fk = _UrdfFk(rcm_pin.load(doc["name"]))
    axis = "xyz".index(doc["tool_axis"])
    trocar = np.asarray(doc["trocar"])
    rcm, tip = [], []
    for q, p_ref in zip(np.asarray(doc["q"]), np.asarray(doc["p_ref"])):
        cfg = dict(zip(doc["joint_names"], q))
        T = fk.transform(doc["tool_frame"], cfg)
        a = T[:3, axis]
        r = trocar - T[:3, 3]
        rcm.append(np.linalg.norm(np.cross(r, a)))
        Tt = fk.transform(doc["tip_frame"], cfg)
        tip.append(np.linalg.norm(Tt[:3, 3] + doc["tip_offset"] * a - p_ref))
    return np.array(rcm), np.array(tip)


@pytest.mark.parametrize(
    ("name", "path", "extra"),
    [
        ("panda", "circle", []),  # the chosen trocar
        ("ur5", "spiral", ["--trocar", "0.4869,0.10915,0.28186"]),
        ("rcm_bevel", "arc", []),
        ("ur5", "circle", ["--trocar", "0.4869,0.10915,0.28186", "--method", "pink"]),
    ],
)
def test_rcm_track_json_matches_an_independent_fk(capsys, name, path, extra):
    rc, doc = _cli(capsys, name, "--path", path, "--duration", "0.05", *extra)
    assert doc["path"] == path
    assert rc == 0
    assert set(doc) >= {
        "joint_names", "q", "t", "tool_frame", "tool_axis", "trocar", "rcm_error_max",
        "tip_error_max",
    }  # fmt: skip
    mech = rcm_pin.load(name)
    q = np.asarray(doc["q"])
    assert doc["joint_names"] == list(mech.joint_names) and q.shape == (51, mech.nq)
    np.testing.assert_allclose(np.diff(doc["t"]), 1e-3, rtol=0, atol=1e-15)
    rcm, tip = _recompute(doc)
    np.testing.assert_allclose(rcm.max(), doc["rcm_error_max"], rtol=0, atol=FK)
    np.testing.assert_allclose(tip.max(), doc["tip_error_max"], rtol=0, atol=FK)
    assert doc["rcm_error_max"] <= 1e-6 and doc["tip_error_max"] <= 1e-4  # the goals
    assert np.abs(q[1] - q[0]).max() / 1e-3 < 1e-4  # starts at rest: no velocity jump
    assert (doc["rcm"] == "mechanical") == (mech.rcm is not None)


def test_chosen_trocar_is_the_best_reachable_candidate():
    setup, scored = choose_trocar("panda")
    values = [v for _, v in scored]
    assert len(scored) == 9 and max(values) > 0
    assert setup.tool.trocar == scored[int(np.argmax(values))][0]
    assert make_setup("panda").tool.trocar == setup.tool.trocar


def test_the_paths_stay_in_the_cone_at_surgical_speeds():
    cone = Cone((0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    for name in ("circle", "spiral", "arc"):
        path = surgical_path(name, cone, rate=1000.0)
        local = cone.to_local(path.p)
        assert 0.005 < path.peak_speed < 0.06  # 5-60 mm/s
        assert np.ptp(local[:, 2]) > 0.005  # the insertion depth changes
        np.testing.assert_allclose(np.diff(path.p[[0, 1]], axis=0), 0.0, atol=1e-9)  # at rest


def test_bad_input_is_typed_with_exact_messages(capsys):
    cone = Cone((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), half_angle=np.deg2rad(5.0))
    with pytest.raises(InvalidInputError) as err:
        surgical_path("circle", cone)
    assert str(err.value) == (
        "path point 0 lies outside the cone below the trocar (angle 10.0 deg, depth 0.0863 m); "
        "valid: within 5.0 deg of the insertion axis at depths in [0.05, 0.12] m"
    )
    with pytest.raises(UnreachablePoseError) as err:
        make_setup("ur5", (2.0, 0.0, 0.0))
    assert str(err.value) == (
        "ur5: trocar [2.0, 0.0, 0.0] is 2.000 m from the base, beyond the arm's reach with "
        "its tool (1.629 m); valid: a trocar within 1.629 m of the base"
    )
    rc, doc = _cli(
        capsys, "panda", "--path", "arc", "--tool-frame", "shaft", "--trocar", "0.3,0,0.3"
    )
    assert rc == 2 and doc["error"]["type"] == "UnknownFrameError"
    frames = ", ".join(sorted({f.name for f in rcm_pin.load("panda").model.frames}))
    assert doc["error"]["message"] == f"unknown tool frame 'shaft' in panda; valid: {frames}"
    rc, doc = _cli(capsys, "rcm_bevel", "--path", "arc", "--trocar", "0.1,0,0")
    assert rc == 2 and doc["error"]["message"] == (
        "rcm_bevel has a mechanical RCM at [0.0, 0.0, 0.0]; its trocar cannot move; valid: "
        "omit the trocar or give that point"
    )
    with pytest.raises(InvalidInputError, match=r"^method must be qp or pink; got 'ik'$"):
        run(make_setup("rcm_bevel"), "arc", method="ik")


def test_rcm_track_text(capsys):
    assert main(["rcm-track", "rcm_bevel", "--path", "spiral", "--duration", "0.01"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("rcm_bevel (mechanical RCM) spiral: 11 samples over 0.010 s of 6 s")
    assert "RCM error max" in out and "tip error max" in out


def _pane_commands(page: str) -> list[list[dict]]:
    """The commands of each viewer of a :func:`rcm_pin.viz.scene.panes_html` page: gzip of
    (uint32 big-endian length, msgpack command) records, base64 in a script element."""
    import base64
    import gzip
    import re

    import umsgpack

    panes = []
    for blob in re.findall(
        r'<script type="application/octet-stream" id="commands-\d+">([^<]*)<', page
    ):
        raw, at, commands = gzip.decompress(base64.b64decode(blob)), 0, []
        while at < len(raw):
            size = int.from_bytes(raw[at : at + 4], "big")
            commands.append(umsgpack.unpackb(raw[at + 4 : at + 4 + size]))
            at += 4 + size
        panes.append(commands)
    return panes


def _check_panes(page: str, tracks) -> None:
    """One viewer per run, Meshcat's JavaScript once, every visual node set once (no hidden
    collision copies), one animation of every run's frames (20 frames per second)."""
    from meshcat.servers.zmqserver import VIEWER_ROOT

    script = (Path(VIEWER_ROOT) / "main.min.js").read_text()
    assert page.count(script) == 1 and page.count("new MeshCat.Viewer(") == 1
    panes = _pane_commands(page)
    assert len(panes) == len(tracks) == page.count('class="pane"')
    for tr, commands in zip(tracks, panes, strict=True):
        assert page.count(f"<figcaption>{tr.setup.mech.name}</figcaption>") >= 1
        objects = [c["path"] for c in commands if c["type"] == "set_object"]
        assert len(objects) == len(set(objects)), "a node set twice"
        assert not [c for c in commands if "/collisions/" in c["path"]]
        visual = pin.buildGeomFromUrdfString(
            tr.setup.mech.model, tr.setup.mech.urdf, pin.GeometryType.VISUAL,
            package_dirs=list(assets(tr.setup.mech).mesh_dirs(tr.setup.mech)),
        )  # fmt: skip
        assert sum("/pinocchio/visuals/" in o for o in objects) == visual.ngeoms
        (animation,) = [c for c in commands if c["type"] == "set_animation"]
        frames = len(tr.q[:: max(1, round(1.0 / (20.0 * float(tr.t[1] - tr.t[0]))))])
        clips = [a["clip"] for a in animation["animations"]]
        assert {c["fps"] for c in clips} == {20}
        assert {len(c["tracks"][0]["keys"]) for c in clips} == {frames}


def test_side_by_side_animation_has_one_scene_per_run(tmp_path):
    from rcm_pin.report.programmable_rcm import side_by_side

    tr = run(make_setup("rcm_bevel"), "circle", duration=0.2)
    page = side_by_side([tr, tr], tmp_path / "anim.html").read_text()
    _check_panes(page, [tr, tr])


def test_the_reports_side_by_side_page_is_under_10_mb(tmp_path):
    """The report's page (rcm_bevel, panda and ur5 on the whole circle) was 49 MB: three
    iframes, each with Meshcat's JavaScript and every mesh twice (as hidden collision
    geometry too), uncompressed."""
    from rcm_pin.report.programmable_rcm import side_by_side
    from rcm_pin.studies.rcm_comparison import COMPARED

    tracks = [run(make_setup(name), "circle") for name in COMPARED]
    path = side_by_side(tracks, tmp_path / "programmable_rcm.html")
    assert path.stat().st_size < 10e6, f"{path.stat().st_size / 1e6:.1f} MB"
    _check_panes(path.read_text(), tracks)

"""Fuzz of the entry points that read a user's files or run long: ``view`` of a URDF whose
mesh names any path (inside, outside, missing, another scheme), and ``rcm-track`` with
options of every magnitude. Each case ends in exit 0 with one JSON document or exit 2 / 3
with a typed error (:func:`test_fuzz.check_cli`), never a traceback; a refused mesh is never
embedded in the page. ``benchmarks/fuzz_long.py`` runs the same with many more cases."""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

from hypothesis import given, settings
from hypothesis import strategies as st

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_fuzz import BOUNDED, check_cli, numbers

#: A mesh file of our own and a secret beside the description (outside its folder).
OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
SECRET = "v 0 0 0\nv 7 7 7\nv 0 7 0\nf 1 2 3\n# secret-marker-5f3a\n"

URDF = """<robot name="probe"><link name="base"><visual><geometry>
<mesh filename="{mesh}"/></geometry></visual></link><link name="tip"/>
<joint name="j" type="revolute"><parent link="base"/><child link="tip"/>
<origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>
</joint></robot>"""


def mesh_names() -> st.SearchStrategy[str]:
    """Mesh filenames a URDF may hold: inside its folder, outside it, missing, other schemes."""
    return st.one_of(
        st.sampled_from(
            [
                "meshes/own.obj",
                "../private/secret.obj",
                "file://{root}/private/secret.obj",
                "{root}/private/secret.obj",
                "/etc/passwd",
                "file:///etc/hostname",
                "package://no_such_pkg/meshes/a.stl",
                "http://example.invalid/a.stl",
                "meshes/missing.stl",
                "meshes/../../private/secret.obj",
                "",
            ]
        ),
        st.text(alphabet="abc./:_-~%", max_size=30),
    )


def check_view(name: str) -> str:
    """``view`` of the probe URDF with mesh ``name``: exit 0 / 2, and the secret never in
    the page."""
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        (root / "private").mkdir()
        (root / "private" / "secret.obj").write_text(SECRET)
        robot = root / "robot"
        (robot / "meshes").mkdir(parents=True)
        (robot / "meshes" / "own.obj").write_text(OBJ)
        mesh = name.replace("{root}", str(root)).replace('"', "&quot;").replace("<", "&lt;")
        path = robot / "probe.urdf"
        path.write_text(
            URDF.format(
                mesh=mesh.replace("&", "&amp;")
                .replace("&amp;quot;", "&quot;")
                .replace("&amp;lt;", "&lt;")
            )
        )
        page = root / "page.html"
        argv = ["view", str(path), "--tool-frame", "tip", "--html", str(page), "--json"]
        outcome = check_cli(argv)
        if page.exists():
            assert "secret-marker-5f3a" not in page.read_text(errors="replace")
        return outcome


def rcm_track_argv() -> st.SearchStrategy[list[str]]:
    """rcm-track of a mechanical RCM arm with rates and durations of every magnitude."""
    value = st.one_of(numbers(), st.floats(1.0, 2000.0))
    return st.tuples(
        st.sampled_from(["circle", "spiral", "arc"]),
        value.map(lambda v: f"--rate={v!r}"),
        st.one_of(st.floats(0.001, 0.02), numbers()).map(lambda v: f"--duration={v!r}"),
    ).map(lambda t: ["rcm-track", "rcm_bevel", "--path", t[0], t[1], t[2], "--json"])


@settings(BOUNDED, max_examples=12, deadline=20_000)
@given(name=mesh_names())
def test_view_fuzz(name):
    assert check_view(name) in ("valid", "typed")


@settings(BOUNDED, max_examples=12, deadline=30_000)
@given(argv=rcm_track_argv())
def test_rcm_track_fuzz(argv):
    assert check_cli(argv) in ("valid", "typed")

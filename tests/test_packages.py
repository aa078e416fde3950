"""ROS packages without ROS, and meshes only from where the description lives.

The fixture ``tests/data/ros_ws/src`` is a ROS workspace of two packages:
``arm_description`` (folder of the same name) whose xacro includes
``$(find arm_parts)/urdf/link.xacro``, and ``arm_parts`` (folder ``parts``: ROS finds a
package by its package.xml name), whose link macro draws ``package://arm_parts/meshes/link.stl``.
"""

from __future__ import annotations

import base64
import json
import re
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

import rcm_pin
from rcm_pin.errors import MeshLocationError, PackageNotFoundError
from rcm_pin.model.meshes import MissingMeshWarning
from rcm_pin.model.packages import installed_prefix

ROOT = Path(__file__).resolve().parents[1]
WS = ROOT / "tests" / "data" / "ros_ws" / "src"
ARM = WS / "arm_description" / "urdf" / "arm.urdf.xacro"
LINK_STL = WS / "parts" / "meshes" / "link.stl"
BASE_OBJ = WS / "arm_description" / "meshes" / "base.obj"


def _meshes(urdf: str) -> list[str]:
    return re.findall(r'<mesh\b[^>]*filename="([^"]*)"', urdf)


@pytest.fixture
def lonely(tmp_path, monkeypatch):
    """arm_description copied alone (no arm_parts beside it), no ROS environment."""
    for variable in ("ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH"):
        monkeypatch.delenv(variable, raising=False)
    shutil.copytree(WS / "arm_description", tmp_path / "arm_description")
    return tmp_path / "arm_description" / "urdf" / "arm.urdf.xacro"


def test_find_and_package_resolved_from_the_folders_above(monkeypatch):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    mech = rcm_pin.load(ARM)
    assert mech.nq == 2
    assert _meshes(mech.urdf) == [str(BASE_OBJ), str(LINK_STL), str(LINK_STL)]


def test_missing_package_is_a_typed_error_naming_it_and_the_option(lonely):
    with pytest.raises(PackageNotFoundError) as caught:
        rcm_pin.load(lonely)
    assert str(caught.value) == (
        "arm.urdf.xacro: ROS package 'arm_parts' not found (searched: package_dirs, "
        "ROS_PACKAGE_PATH, AMENT_PREFIX_PATH, the folders above "
        f"{lonely}); valid: --package-dir arm_parts=PATH or "
        "package_dirs={'arm_parts': PATH}, PATH the folder holding its package.xml"
    )


def test_package_dirs_resolve_find_and_meshes(lonely):
    mech = rcm_pin.load(lonely, package_dirs={"arm_parts": WS / "parts"})
    base = lonely.parents[1] / "meshes" / "base.obj"
    assert _meshes(mech.urdf) == [str(base), str(LINK_STL), str(LINK_STL)]


def test_ros_package_path_is_crawled_by_package_name(lonely, monkeypatch):
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(WS.parent))
    assert _meshes(rcm_pin.load(lonely).urdf)[1] == str(LINK_STL)


def test_ament_prefix_path_share_folders(lonely, tmp_path, monkeypatch):
    prefix = tmp_path / "install"
    shutil.copytree(WS / "parts", prefix / "share" / "arm_parts")
    monkeypatch.setenv("AMENT_PREFIX_PATH", str(prefix))
    expected = prefix / "share" / "arm_parts" / "meshes" / "link.stl"
    assert _meshes(rcm_pin.load(lonely).urdf)[1] == str(expected)


def test_declared_folder_comes_first(lonely, tmp_path, monkeypatch):
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(WS.parent))
    other = shutil.copytree(WS / "parts", tmp_path / "mine")
    mech = rcm_pin.load(lonely, package_dirs={"arm_parts": other})
    assert _meshes(mech.urdf)[1] == str(other / "meshes" / "link.stl")


def test_installed_example_robot_data_resolves_by_itself():
    prefix = installed_prefix()
    assert prefix is not None, "example-robot-data is a dependency of the test environment"
    path = prefix / "share" / "example-robot-data" / "robots" / "xarm_description" / "urdf"
    mech = rcm_pin.load(path / "xarm7.urdf", tool_frame="link7")
    files = _meshes(mech.urdf)
    assert files and all(Path(f).is_file() for f in files)


def _urdf_with_mesh(folder: Path, filename: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "robot.urdf"
    path.write_text(
        f"""<robot name="robot"><link name="base"><visual><geometry>
        <mesh filename="{filename}"/></geometry></visual></link><link name="mid"/>
        <link name="tool"/>
        <joint name="j1" type="revolute"><parent link="base"/><child link="mid"/>
        <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
        <joint name="j2" type="revolute"><parent link="mid"/><child link="tool"/>
        <origin xyz="0.1 0 0"/><axis xyz="0 1 0"/>
        <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
        <rcm_pin tool_frame="tool"/></robot>"""
    )
    return path


@pytest.mark.parametrize(
    "filename",
    [
        "file:///etc/passwd",
        "../../private/secret.obj",
        "/etc/hostname",
        "package://arm_parts/../../../private/secret.obj",
    ],
)
def test_mesh_outside_the_description_is_refused(tmp_path, filename):
    secret = tmp_path / "private" / "secret.obj"
    secret.parent.mkdir()
    secret.write_text(BASE_OBJ.read_text())
    path = _urdf_with_mesh(tmp_path / "robots" / "mine", filename)
    mech = rcm_pin.load(path, package_dirs={"arm_parts": WS / "parts"})  # kinematics load
    from rcm_pin.viz import Viewer

    with pytest.raises(MeshLocationError, match=r"--mesh-dir PATH \(mesh_dirs=\[PATH\]"):
        Viewer(mech)  # the mesh is never read


def test_mesh_dirs_allow_a_folder(tmp_path):
    secret = tmp_path / "private" / "secret.obj"
    secret.parent.mkdir()
    secret.write_text(BASE_OBJ.read_text())
    path = _urdf_with_mesh(tmp_path / "robots" / "mine", f"file://{secret}")
    mech = rcm_pin.load(path, mesh_dirs=[secret.parent])
    assert _meshes(mech.urdf) == [str(secret)]


def test_urdf_text_may_not_name_local_files():
    """URDF text has no folder of its own: no local mesh is allowed."""
    urdf = '<robot name="r"><link name="a"><visual><geometry><mesh filename="/etc/hostname"/>'
    urdf += '</geometry></visual></link><link name="b"/><joint name="j" type="revolute">'
    urdf += '<parent link="a"/><child link="b"/><limit lower="-1" upper="1" effort="1" '
    urdf += 'velocity="1"/></joint><rcm_pin tool_frame="b"/></robot>'
    from rcm_pin.viz import Viewer

    with pytest.raises(MeshLocationError):
        Viewer(rcm_pin.from_urdf(urdf))


def test_viewer_draws_without_a_missing_mesh_and_names_it(tmp_path):
    from rcm_pin.viz import Viewer

    mech = rcm_pin.load(_urdf_with_mesh(tmp_path, "package://nowhere_pkg/meshes/a.stl"))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        Viewer(mech).close()
    messages = [str(w.message) for w in caught if issubclass(w.category, MissingMeshWarning)]
    assert messages == [
        "mesh package://nowhere_pkg/meshes/a.stl not drawn (package 'nowhere_pkg' not "
        "found; valid: --package-dir nowhere_pkg=PATH)"
    ]


def _cli(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "rcm_pin", *args], capture_output=True, text=True, cwd=cwd,
        env={**__import__("os").environ, "PYTHONPATH": str(ROOT)},
    )  # fmt: skip


def _embedded(html: str) -> bytes:
    """Every binary command of a static Meshcat page, concatenated."""
    chunks = re.findall(r"data:application/octet-binary;base64,([A-Za-z0-9+/=]+)", html)
    return b"".join(base64.b64decode(c) for c in chunks)


def test_cli_view_html_with_package_dir_writes_the_meshes(lonely, tmp_path):
    out = tmp_path / "arm.html"
    run = _cli("view", str(lonely), "--package-dir", f"arm_parts={WS / 'parts'}",
               "--html", str(out), "--json")  # fmt: skip
    assert run.returncode == 0, run.stdout + run.stderr
    assert json.loads(run.stdout)["warnings"] == []
    scene = _embedded(out.read_text())
    assert LINK_STL.read_bytes() in scene and BASE_OBJ.read_bytes() in scene


def test_cli_missing_package_exits_2_with_one_document(lonely):
    run = _cli("view", str(lonely), "--html", str(lonely.parent / "x.html"), "--json")
    assert run.returncode == 2 and "Traceback" not in run.stderr
    error = json.loads(run.stdout)["error"]
    assert error["type"] == "PackageNotFoundError"
    assert "--package-dir arm_parts=PATH" in error["message"]


def test_cli_missing_mesh_falls_back_with_a_warning(tmp_path):
    path = _urdf_with_mesh(tmp_path, "meshes/gone.stl")
    run = _cli("view", str(path), "--html", str(tmp_path / "r.html"), "--json")
    assert run.returncode == 0 and "Traceback" not in run.stderr
    gone = tmp_path / "meshes" / "gone.stl"
    assert json.loads(run.stdout)["warnings"] == [f"mesh {gone} not drawn (no such file)"]
    assert f"rcm-pin: warning: mesh {gone} not drawn" in run.stderr


def test_cli_mesh_outside_and_bad_package_dir_exit_2(tmp_path):
    path = _urdf_with_mesh(tmp_path / "robot", "file:///etc/passwd")
    run = _cli("view", str(path), "--html", str(tmp_path / "r.html"), "--json")
    assert run.returncode == 2
    assert json.loads(run.stdout)["error"]["type"] == "MeshLocationError"
    run = _cli("view", str(path), "--package-dir", "nonsense", "--json")
    assert run.returncode == 2
    assert "NAME=PATH" in json.loads(run.stdout)["error"]["message"]


def test_crawl_skips_ignored_folders_and_survives_link_cycles(tmp_path):
    from rcm_pin.model.packages import crawl

    shutil.copytree(WS / "parts", tmp_path / "root" / "a" / "parts")
    shutil.copytree(WS / "parts", tmp_path / "root" / "b" / "parts")
    (tmp_path / "root" / "b" / "CATKIN_IGNORE").touch()
    (tmp_path / "root" / "a" / "loop").symlink_to(tmp_path / "root")
    assert list(crawl(tmp_path / "root")) == [("arm_parts", tmp_path / "root" / "a" / "parts")]

"""Loading by name or by path, the tool frame never guessed, and one Mechanism from threads."""

from __future__ import annotations

import threading

import numpy as np
import pytest

import rcm_pin
from rcm_pin.analysis.jacobians import jacobian_derivative, tool_jacobian
from rcm_pin.errors import InvalidInputError, UnknownFrameError, UnknownMechanismError
from rcm_pin.model.resources import urdf_dir, xacro_dir

EXACT = 1e-12


@pytest.mark.parametrize("name", ["rcm_bevel", "rcm_belt", "rcm_bevel_4dof", "rcm_two_mass"])
def test_committed_urdf_by_path_equals_the_catalogue(name):
    by_name = rcm_pin.load(name)
    by_path = rcm_pin.load(urdf_dir() / f"{name}.urdf")
    assert by_path.family is by_name.family and by_path.joint_names == by_name.joint_names
    assert by_path.rcm is not None and by_path.output.frame == "tool"
    rng = np.random.default_rng(0)
    for q in rng.uniform(by_name.lower, by_name.upper, (200, by_name.nq)):
        np.testing.assert_allclose(
            rcm_pin.tool_pose(by_path, q), rcm_pin.tool_pose(by_name, q), atol=EXACT
        )
        assert rcm_pin.rcm_error(by_path, q) < EXACT


@pytest.mark.parametrize("name", ["planar_3rrr", "five_bar", "four_bar"])
def test_committed_closed_urdf_by_path_equals_the_catalogue(name):
    """The committed rendering of a closed mechanism carries its loops: the same closures,
    drives and output, and the same closed configurations and outputs."""
    by_name = rcm_pin.load(name)
    by_path = rcm_pin.load(urdf_dir() / f"{name}.urdf")
    assert by_path.family is by_name.family and by_path.loops.spec == by_name.loops.spec
    assert by_path.output.coords == by_name.output.coords
    home = by_name.home
    drives = home[by_name.loops.drive_q]
    rng = np.random.default_rng(1)
    for delta in rng.uniform(-0.05, 0.05, (20, drives.size)):
        a = rcm_pin.forward(by_name, drives + delta, q_guess=home).solutions[0]
        b = rcm_pin.forward(by_path, drives + delta, q_guess=home).solutions[0]
        np.testing.assert_allclose(b.q, a.q, atol=EXACT)
        np.testing.assert_allclose(b.output, a.output, atol=EXACT)


def test_path_as_text_and_xacro_path():
    text = str(urdf_dir() / "rcm_bevel.urdf")
    assert rcm_pin.load(text).nq == 6
    m = rcm_pin.load(xacro_dir() / "rcm_bevel.urdf.xacro", wrist="false")
    assert m.nq == 4 and m.family.name == "rcm" and m.rebuild is not None


def _strip_element(tmp_path, name):
    import xml.etree.ElementTree as ET

    root = ET.fromstring((urdf_dir() / f"{name}.urdf").read_text())
    root.remove(root.find("rcm_pin"))
    path = tmp_path / f"{name}_plain.urdf"
    path.write_text(ET.tostring(root, encoding="unicode"))
    return path


def test_a_urdf_without_the_element_needs_the_tool_frame(tmp_path):
    path = _strip_element(tmp_path, "rcm_bevel")
    with pytest.raises(UnknownFrameError) as exc:
        rcm_pin.load(path)
    message = str(exc.value)
    assert message.startswith("rcm_bevel_plain: the tool frame is not known (no tool_frame")
    assert "valid: tool_frame=one of " in message and "tool" in message.split("one of ")[1]
    m = rcm_pin.load(path, tool_frame="tool", rcm_frame="rcm")
    assert m.family.name == "generic" and m.nq == 6 and m.rcm is not None
    catalogue = rcm_pin.load("rcm_bevel")
    q = np.array([0.2, -0.3, 0.08, 0.4, 0.5, -0.6])
    # no <rcm_pin> element: no paper numbering, Pinocchio's order (the same here)
    np.testing.assert_allclose(rcm_pin.tool_pose(m, q), rcm_pin.tool_pose(catalogue, q), atol=EXACT)


def test_the_cli_takes_the_tool_frame_of_a_path(tmp_path, capsys):
    import json

    from rcm_pin.cli import main

    path = _strip_element(tmp_path, "rcm_bevel")
    q = "0.2,-0.3,0.08,0.4,0.5,-0.6"
    assert main(["fk", str(path), "--q", q, "--json"]) == 2
    assert json.loads(capsys.readouterr().out)["error"]["type"] == "UnknownFrameError"
    argv = ["fk", str(path), "--tool-frame", "tool", "--rcm-frame", "rcm", "--q", q, "--json"]
    assert main(argv) == 0
    (sol,) = json.loads(capsys.readouterr().out)["solutions"]
    expected = rcm_pin.tool_pose(
        rcm_pin.load("rcm_bevel"), np.array([float(v) for v in q.split(",")])
    )
    np.testing.assert_allclose(sol["pose"], expected, atol=EXACT)
    # no rcm_axis_frame given: the insertion axis is the tool frame's z axis
    p, z = expected[:3, 3], expected[:3, 2]
    np.testing.assert_allclose(sol["rcm_error"], np.linalg.norm(np.cross(p, z)), rtol=EXACT)


def test_a_bad_tool_frame_lists_the_frames():
    with pytest.raises(UnknownFrameError, match=r"unknown tool frame 'nope' in rcm_bevel; valid: "):
        rcm_pin.load(urdf_dir() / "rcm_bevel.urdf", tool_frame="nope")


@pytest.mark.parametrize("kind", ["file", "folder"])
def test_a_catalogue_name_is_never_a_path(tmp_path, monkeypatch, kind):
    """A file or folder named like a catalogue entry in the working directory is ignored."""
    monkeypatch.chdir(tmp_path)
    if kind == "file":
        (tmp_path / "rcm_bevel").write_text('<robot name="x"><link name="a"/></robot>')
    else:
        (tmp_path / "rcm_bevel").mkdir()
    m = rcm_pin.load("rcm_bevel")
    assert m.name == "rcm_bevel" and m.nq == 6 and m.family.name == "rcm"


def test_a_bare_unknown_name_is_unknown_even_if_a_file_has_it(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "my_arm").write_text("<robot/>")
    with pytest.raises(UnknownMechanismError) as exc:
        rcm_pin.load("my_arm")
    assert str(exc.value).startswith("unknown mechanism 'my_arm'; valid: rcm_bevel, ")
    assert "(or a path to a .urdf / .xacro file)" in str(exc.value)


@pytest.mark.parametrize(
    ("target", "error", "message"),
    [
        ("missing/arm.urdf", InvalidInputError, "missing/arm.urdf is no file; valid: an existing"),
        ("arm.txt", UnknownMechanismError, "unknown mechanism 'arm.txt'; valid:"),
        ("dir/arm.txt", UnknownMechanismError, "'dir/arm.txt' is neither a catalogue name nor"),
        ("", UnknownMechanismError, "unknown mechanism ''; valid:"),
    ],
)
def test_bad_paths_are_typed(target, error, message):
    with pytest.raises(error) as exc:
        rcm_pin.load(target)
    assert message in str(exc.value)


def test_a_malformed_urdf_is_typed(tmp_path):
    path = tmp_path / "broken.urdf"
    path.write_text("<robot name='x'><link name='a'></robot>")
    with pytest.raises(InvalidInputError, match=r"the URDF is not well-formed XML"):
        rcm_pin.load(path, tool_frame="a")


def _in_threads(fn, n_threads=4):
    results: list = [None] * n_threads
    barrier = threading.Barrier(n_threads)

    def run(i):
        barrier.wait()
        results[i] = fn()

    threads = [threading.Thread(target=run, args=(i,)) for i in range(n_threads)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    return results


def test_one_mechanism_from_four_threads_gives_the_one_thread_results():
    """forward, the tool Jacobian and J̇ from 4 threads equal the 1-thread results exactly."""
    mech = rcm_pin.load("rcm_bevel")
    rng = np.random.default_rng(3)
    qs = rng.uniform(mech.lower, mech.upper, (300, 6))
    qds = rng.normal(size=(300, 6))

    def work():
        out = []
        for q, qd in zip(qs, qds, strict=True):
            pose = np.asarray(rcm_pin.forward(mech, q).to_json()["solutions"][0]["pose"])
            out.append((pose, tool_jacobian(mech, q), jacobian_derivative(mech, q, qd)))
        return out

    reference = work()
    for result in _in_threads(work):
        for (p, j, dj), (p0, j0, dj0) in zip(result, reference, strict=True):
            np.testing.assert_array_equal(p, p0)
            np.testing.assert_array_equal(j, j0)
            np.testing.assert_array_equal(dj, dj0)


def test_closed_mechanism_from_four_threads():
    mech = rcm_pin.load("planar_3rrr")
    home = mech.home
    drives = home[mech.loops.drive_q] + np.linspace(-0.05, 0.05, 40)[:, None]

    def work():
        return [rcm_pin.forward(mech, d, all_modes=True).solutions[0].q for d in drives]

    reference = work()
    for result in _in_threads(work):
        np.testing.assert_array_equal(np.array(result), np.array(reference))

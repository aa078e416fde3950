"""Every bad input the issue "Bad input never crashes" lists under *Why*, in one place.

Each row is one reported case with the status and the exact message the command line gives
now (``--json``: the ``{"error": {...}}`` document; without it, one line on stderr). The
API cases raise an :class:`RcmPinError` subclass. Warnings are errors in this module, so an
overflow warning leaking out of numpy fails it. More cases of each kind are in
test_cli_errors.py, test_xacro_ranges.py, test_solver_outcomes.py and test_fuzz.py.
"""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import rcm_pin
from rcm_pin import errors
from rcm_pin.analysis.kinematics import tool_pose
from rcm_pin.catalog.table import ENTRIES, names
from rcm_pin.cli import main
from rcm_pin.report.sections import SECTIONS

pytestmark = pytest.mark.filterwarnings("error")

Q = "0,0,0.08,0,0,0"
BEVEL = "rcm_bevel.urdf.xacro"
NAMES = ", ".join(names())
SERIAL = ", ".join(e.name for e in ENTRIES if rcm_pin.load(e.name).loops is None)
OUTSIDE = (
    "rcm_bevel: none of the 4 solutions of target x=1, y=1, z=1 lies within the joint limits "
    "(branch_0: q3 = 1.73205 > 0.12; branch_1: q1 = 2.35619 > 1.0472, q2 = 2.52611 > 1.0472, "
    "q3 = 1.73205 > 0.12; branch_2: q1 = 2.35619 > 1.0472, q3 = -1.73205 < 0.05; branch_3: "
    "q2 = -2.52611 < -1.0472, q3 = -1.73205 < 0.05); valid: a target with a solution inside "
    "the limits"
)

#: (case, argv, exit status, error type, exact message)
CASES = [
    (
        "l9=1e308 overflows the inertias",
        ["fk", "rcm_bevel", "--q", Q, "--arg", "l9=1e308"],
        2,
        "XacroArgumentError",
        f"l9=1e+308 is out of range for {BEVEL}; valid: (0, 10] [m] (initial link 9 length P7-P10)",
    ),
    (
        "negative mass",
        ["fk", "rcm_bevel", "--q", Q, "--arg", "m_platform=-0.3"],
        2,
        "XacroArgumentError",
        f"m_platform=-0.3 is out of range for {BEVEL}; valid: (0, 1000] [kg] (platform 6)",
    ),
    (
        "q3_lower above q3_upper",
        ["fk", "rcm_bevel", "--q", Q, "--arg", "q3_lower=0.2"],
        2,
        "XacroArgumentError",
        f"q3_lower=0.2 is not below q3_upper=0.12 in {BEVEL}; valid: q3_lower < q3_upper",
    ),
    (
        "negative effort",
        ["fk", "rcm_bevel", "--q", Q, "--arg", "effort_revolute=-1"],
        2,
        "XacroArgumentError",
        f"effort_revolute=-1 is out of range for {BEVEL}; valid: (0, 10000] [N*m] (torque "
        "limit of the revolute drives)",
    ),
    (
        "negative velocity",
        ["fk", "rcm_bevel", "--q", Q, "--arg", "velocity_prismatic=-1"],
        2,
        "XacroArgumentError",
        f"velocity_prismatic=-1 is out of range for {BEVEL}; valid: (0, 100] [m/s] (speed "
        "limit of the linear drive 24)",
    ),
    (
        "ocp ik on a closed mechanism given xyz",
        ["ocp", "ik", "planar_3rrr", "--xyz", "0.1,0.1,0"],
        2,
        "InvalidInputError",
        "planar_3rrr is a closed mechanism: give pose = its output coordinates (x, y, rz of "
        "frame platform_centre); xyz / rpy are for serial ones",
    ),
    (
        "ocp track on a closed mechanism",
        ["ocp", "track", "five_bar"],
        2,
        "InvalidInputError",
        "paper 000's tracking OCP takes a serial mechanism; five_bar has loop closures (its "
        "efforts need the constraint forces of the loops); valid: a serial rcm_pin.Mechanism "
        f"({SERIAL}) or a pin.Model of a tree",
    ),
    (
        "a 74.5 GiB singularity grid",
        ["singularities", "rcm_bevel", "--grid", "1,2,100000"],
        2,
        "InvalidInputError",
        "grid of 100000x100000 cells; valid: at most 250000 cells",
    ),
    (
        "reproduce into /proc",
        ["reproduce", "--out", "/proc/x"],
        2,
        "InvalidInputError",
        "--out '/proc/x': cannot create the folder (No such file or directory); valid: a "
        "folder in a writable location",
    ),
    (
        "--q 1e300 (overflow warning)",
        ["fk", "rcm_bevel", "--q", "1e300,0,0.08,0,0,0"],
        2,
        "InvalidInputError",
        "q has an entry of magnitude 1e+300; valid: |value| <= 1e+06 (larger values are "
        "meaningless for a mechanism)",
    ),
    (
        "--xyz 1e300 (overflow warning)",
        ["ik", "rcm_bevel", "--xyz", "1e300,0,0"],
        2,
        "InvalidInputError",
        "target has an entry of magnitude 1e+300; valid: |value| <= 1e+06 (larger values are "
        "meaningless for a mechanism)",
    ),
    (
        "--rpy 1e20",
        ["ik", "rcm_bevel", "--xyz", "0,0,-0.1", "--rpy", "1e20,0,0"],
        2,
        "InvalidInputError",
        "--rpy has an angle of magnitude 1e+20 rad; valid: |angle| <= 1e+06 rad (larger "
        "angles are meaningless)",
    ),
    (
        "--xyz with --pose",
        ["ik", "rcm_bevel", "--xyz", "0,0,-0.1", "--pose", "1,0,0,0;0,1,0,0;0,0,1,-0.1"],
        2,
        "InvalidInputError",
        "--pose conflicts with --xyz / --rpy; valid: one of them",
    ),
    (
        "--within-limits with no branch inside",
        ["ik", "rcm_bevel", "--xyz", "1,1,1", "--within-limits"],
        2,
        "UnreachablePoseError",
        OUTSIDE,
    ),
    (
        "reproduce --only zzzz",
        ["reproduce", "--only", "zzzz"],
        2,
        "InvalidInputError",
        "--only 'zzzz' matches no report section; valid: a word of "
        + ", ".join(name for name, _ in SECTIONS),
    ),
    (
        "an argparse error under --json",
        ["fk", "rcm_bevel"],
        2,
        "UsageError",
        "rcm-pin fk: the following arguments are required: --q",
    ),
    (
        "view creates a missing parent tree",
        ["view", "rcm_bevel", "--png", "/nonexistent-dir/x/y.png"],
        2,
        "InvalidInputError",
        "--png '/nonexistent-dir/x/y.png': folder '/nonexistent-dir/x' does not exist; valid: "
        "a path in an existing folder",
    ),
    (
        "urdf -o creates a missing parent tree",
        ["urdf", "rcm_bevel", "-o", "/nonexistent-dir/x/y.urdf"],
        2,
        "InvalidInputError",
        "-o '/nonexistent-dir/x/y.urdf': folder '/nonexistent-dir/x' does not exist; valid: "
        "a path in an existing folder",
    ),
]


@pytest.mark.parametrize(
    ("argv", "status", "kind", "message"),
    [pytest.param(*row[1:], id=row[0]) for row in CASES],
)
def test_reported_case_json(capsys, argv, status, kind, message):
    code = main([*argv, "--json"])
    out = capsys.readouterr()
    assert code == status
    assert json.loads(out.out) == {"error": {"type": kind, "message": message}}
    assert "Traceback" not in out.err and "Warning" not in out.err


@pytest.mark.parametrize(
    ("argv", "status", "kind", "message"),
    [pytest.param(*row[1:], id=row[0]) for row in CASES],
)
def test_reported_case_text_is_one_line(capsys, argv, status, kind, message):
    code = main(argv)
    out = capsys.readouterr()
    assert code == status
    assert out.out == ""
    assert out.err.strip().splitlines() == [f"rcm-pin: error: {kind}: {message}"]


@pytest.mark.parametrize(
    ("argv", "q", "drives"),
    [
        (["fk", "rcm_bevel", "--q", "-0.2,0.1,0.08,0,0,0"], [-0.2, 0.1, 0.08, 0, 0, 0], None),
        (["fk", "five_bar", "--q", "-0.2,2.9"], None, {"A1": -0.2, "A2": 2.9}),
    ],
    ids=["serial", "closed"],
)
def test_a_negative_value_needs_no_equals_sign(capsys, argv, q, drives):
    code = main([*argv, "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert code == 0
    first = doc["solutions"][0]
    if q is not None:
        np.testing.assert_allclose(first["q"], q, rtol=0, atol=0)
    else:  # a closed mechanism reports its drives by name
        assert first["drives"].keys() == drives.keys()
        np.testing.assert_allclose(list(first["drives"].values()), list(drives.values()), atol=0)


def test_the_four_dof_urdf_has_its_own_robot_name():
    root = Path(__file__).parents[1] / "urdf"
    robots = {
        n: ET.parse(root / f"{n}.urdf").getroot().get("name")
        for n in ("rcm_bevel", "rcm_bevel_4dof")
    }
    assert robots == {"rcm_bevel": "rcm_bevel", "rcm_bevel_4dof": "rcm_bevel_4dof"}


# -- API -------------------------------------------------------------------------------------
def test_load_of_a_missing_file():
    with pytest.raises(errors.InvalidInputError) as exc:
        rcm_pin.load("/nonexistent-dir/m.urdf")
    assert (
        str(exc.value)
        == "/nonexistent-dir/m.urdf is no file; valid: an existing .urdf or .xacro file"
    )


def test_load_of_a_malformed_urdf(tmp_path):
    bad = tmp_path / "bad.urdf"
    bad.write_text("<robot name='x'><link")
    with pytest.raises(errors.InvalidInputError) as exc:
        rcm_pin.load(bad)
    assert str(exc.value) == (
        f"{bad}: the URDF is not well-formed XML: unclosed token: line 1, column 16"
    )


@pytest.mark.parametrize("name", ["", None])
def test_load_of_an_empty_name(name):
    with pytest.raises(errors.UnknownMechanismError) as exc:
        rcm_pin.load(name)
    assert str(exc.value) == (
        f"unknown mechanism {str(name)!r}; valid: {NAMES} (or a path to a .urdf / .xacro file)"
    )


def test_tool_pose_of_a_string():
    with pytest.raises(errors.InvalidInputError) as exc:
        tool_pose(rcm_pin.load("rcm_bevel"), "abc")
    assert str(exc.value) == "q 'abc' is not numeric; valid: real numbers"


def test_accuracy_on_the_planar_mechanisms_is_a_result(capsys):
    for name in ("planar_3rrr", "five_bar"):
        assert main(["accuracy", name, "--json"]) == 0
        doc = json.loads(capsys.readouterr().out)
        assert doc["mechanism"] == name and doc["rows"]
        for row in doc["rows"]:  # the linear theory against the nonlinear recomputation:
            # they differ by the second-order term, (0.1°)² × a link length ≈ 1e-5 at most
            gap = abs(row["linear_output"] - row["nonlinear_output"])
            assert gap <= 0.05 * abs(row["nonlinear_output"]) + 1e-5, row

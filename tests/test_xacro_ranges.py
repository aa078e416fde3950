"""Every xacro argument is validated before rendering against its documented range.

The ranges are written in the xacro documentation itself (the convention of
:mod:`rcm_pin.model.xacro_ranges`); a shipped xacro whose numeric argument lacks a unit or a
range, or whose default lies outside it, fails here.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import rcm_pin
import rcm_pin.cli
from rcm_pin.catalog.files import render_default
from rcm_pin.catalog.table import mechanisms
from rcm_pin.errors import XacroArgumentError
from rcm_pin.model.render import validate_args
from rcm_pin.model.resources import urdf_dir, xacro_dir
from rcm_pin.model.xacro_ranges import declared_specs, limit_pairs, parse_spec

XACROS = sorted(xacro_dir().glob("*.xacro"))
BEVEL = "rcm_bevel.urdf.xacro"
L9 = "(0, 10] [m] (initial link 9 length P7-P10)"


def undocumented(path: Path) -> list[str]:
    """Arguments of ``path`` that break the convention (empty for a conforming file)."""
    bad = []
    for name, spec in declared_specs(path).items():
        if spec.kind == "number":
            if spec.unit is None or spec.interval is None:
                bad.append(f"{name}: no unit and range")
            elif not spec.contains(float(spec.default)):
                bad.append(f"{name}: default {spec.default} outside {spec.interval}")
        elif spec.kind == "choice" and spec.default not in spec.choices:
            bad.append(f"{name}: default {spec.default} not one of {spec.choices}")
    return bad


def test_shipped_xacros_are_found():
    assert {p.name for p in XACROS} >= {BEVEL, "rcm_common.xacro", "four_bar.urdf.xacro"}


@pytest.mark.parametrize("path", XACROS, ids=lambda p: p.name)
def test_every_numeric_argument_declares_unit_and_range(path):
    assert declared_specs(path)
    assert undocumented(path) == []


@pytest.mark.parametrize("path", XACROS, ids=lambda p: p.name)
def test_defaults_pass_validation(path):
    specs = declared_specs(path)
    assert validate_args(path, {n: s.default for n, s in specs.items()}) == {
        n: s.default for n, s in specs.items()
    }


def test_a_xacro_without_ranges_fails_the_convention(tmp_path):
    path = tmp_path / "bare.urdf.xacro"
    path.write_text(
        '<robot name="bare" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:arg name="length" default="0.2"/>  <!-- a length [m] -->\n'
        '  <xacro:arg name="mass" default="0.2"/>\n'
        '  <xacro:arg name="width" default="2"/>  <!-- width [m] in (0, 1] -->\n'
        '  <xacro:arg name="mode" default="c"/>  <!-- one of a, b -->\n'
        "</robot>\n"
    )
    assert undocumented(path) == [
        "length: no unit and range",
        "mass: no unit and range",
        "width: default 2 outside (0, 1]",
        "mode: default c not one of ('a', 'b')",
    ]
    # an undocumented number is still checked to be finite
    with pytest.raises(XacroArgumentError) as exc:
        validate_args(path, {"mass": "inf"})
    assert str(exc.value) == "mass=inf is not finite for bare.urdf.xacro; valid: a finite number"


def test_parse_spec_reads_the_convention():
    spec = parse_spec("q", "0", "joint offset [rad] in [-3.1416, 3.1416], a note")
    assert (spec.kind, spec.unit, spec.interval, spec.description) == (
        "number",
        "rad",
        "[-3.1416, 3.1416]",
        "joint offset",
    )
    assert spec.contains(-3.1416) and spec.contains(3.1416) and not spec.contains(3.2)
    open_spec = parse_spec("m", "1", "mass [kg] in (0, 1000)")
    assert not open_spec.contains(0.0) and not open_spec.contains(1000.0)
    assert parse_spec("w", "zyz", "wrist pairs, one of zyz, rpy (notes)").choices == ("zyz", "rpy")
    assert parse_spec("b", "true", "a switch").kind == "boolean"
    assert parse_spec("n", "rcm", "a name").kind == "text"


def test_limit_pairs_by_name():
    names = ["q3_lower", "q3_upper", "lower_x", "upper_x", "v_min", "v_max", "min_w", "max_w"]
    assert limit_pairs([*names, "q4_lower", "q1_limit"]) == [
        ("q3_lower", "q3_upper"),
        ("lower_x", "upper_x"),
        ("v_min", "v_max"),
        ("min_w", "max_w"),
    ]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ({"l9": 1e308}, f"l9=1e+308 is out of range for {BEVEL}; valid: {L9}"),
        ({"l9": "1e308"}, f"l9=1e+308 is out of range for {BEVEL}; valid: {L9}"),
        ({"l9": 0}, f"l9=0 is out of range for {BEVEL}; valid: {L9}"),
        ({"l9": float("nan")}, f"l9=nan is not finite for {BEVEL}; valid: {L9}"),
        ({"l9": "inf"}, f"l9=inf is not finite for {BEVEL}; valid: {L9}"),
        ({"l9": "-inf"}, f"l9=-inf is not finite for {BEVEL}; valid: {L9}"),
        ({"l9": "abc"}, f"l9='abc' is not a number for {BEVEL}; valid: {L9}"),
        (
            {"m_platform": -0.3},
            f"m_platform=-0.3 is out of range for {BEVEL}; valid: (0, 1000] [kg] (platform 6)",
        ),
        (
            {"effort_revolute": -5},
            f"effort_revolute=-5 is out of range for {BEVEL}; valid: (0, 10000] [N*m] "
            "(torque limit of the revolute drives)",
        ),
        (
            {"effort_prismatic": 0},
            f"effort_prismatic=0 is out of range for {BEVEL}; valid: (0, 100000] [N] "
            "(force limit of the linear drive 24)",
        ),
        (
            {"velocity_revolute": 0.0},
            f"velocity_revolute=0 is out of range for {BEVEL}; valid: (0, 1000] [rad/s] "
            "(speed limit of the revolute pairs)",
        ),
        (
            {"velocity_prismatic": -0.5},
            f"velocity_prismatic=-0.5 is out of range for {BEVEL}; valid: (0, 100] [m/s] "
            "(speed limit of the linear drive 24)",
        ),
        (
            {"z13": 3},
            f"z13=3 is out of range for {BEVEL}; valid: [6, 1000] [-] "
            "(teeth of wheel 13 (fixed to platform 6))",
        ),
        (
            {"wrist_type": "xyz"},
            f"wrist_type='xyz' is not valid for {BEVEL}; valid: one of zyz, rpy",
        ),
        ({"wrist": "maybe"}, f"wrist='maybe' is not a boolean for {BEVEL}; valid: true or false"),
        (
            {"q3_lower": 0.2},
            f"q3_lower=0.2 is not below q3_upper=0.12 in {BEVEL}; valid: q3_lower < q3_upper",
        ),
        (
            {"q3_upper": 0.05},
            f"q3_lower=0.05 is not below q3_upper=0.05 in {BEVEL}; valid: q3_lower < q3_upper",
        ),
        (
            {"q3_lower": 0.3, "q3_upper": 0.1},
            f"q3_lower=0.3 is not below q3_upper=0.1 in {BEVEL}; valid: q3_lower < q3_upper",
        ),
    ],
)
def test_load_rejects_bad_argument(args, message):
    with pytest.raises(XacroArgumentError) as exc:
        rcm_pin.load("rcm_bevel", **args)
    assert str(exc.value) == message


@pytest.mark.parametrize(
    ("name", "args", "message"),
    [
        (
            "rcm_bevel_4dof",
            {"q3_lower": 0.2},
            f"q3_lower=0.2 is not below q3_upper=0.12 in {BEVEL}; valid: q3_lower < q3_upper",
        ),
        (
            "rcm_two_mass",
            {"m": -1},
            "m=-1 is out of range for rcm_two_mass.urdf.xacro; valid: (0, 1000] [kg] "
            "(mass at the tool centre)",
        ),
        (
            "rcm_belt",
            {"d1": 1e308},
            "d1=1e+308 is out of range for rcm_belt.urdf.xacro; valid: (0, 1] [m] "
            "(pulley diameter at pair 7 (belt 1, driving))",
        ),
        (
            "planar_3rrr",
            {"m_platform": -0.3},
            "m_platform=-0.3 is out of range for planar_3rrr.urdf.xacro; valid: (0, 1000] [kg] "
            "(platform mass (uniform triangle plate))",
        ),
        (
            "five_bar",
            {"base_distance": "nan"},
            "base_distance=nan is not finite for five_bar.urdf.xacro; valid: (0, 10] [m] "
            "(d = |A_1 A_2|)",
        ),
    ],
)
def test_every_catalogue_xacro_is_validated(name, args, message):
    with pytest.raises(XacroArgumentError) as exc:
        rcm_pin.load(name, **args)
    assert str(exc.value) == message


def test_load_by_path_is_validated_too():
    with pytest.raises(XacroArgumentError) as exc:
        rcm_pin.load(xacro_dir() / BEVEL, l9=1e308)
    assert str(exc.value) == f"l9=1e+308 is out of range for {BEVEL}; valid: {L9}"


def test_bounds_of_the_intervals_are_honoured():
    path = xacro_dir() / BEVEL
    assert validate_args(path, {"l9": 10, "z13": 6, "q3_lower": -0.2, "q3_upper": 0.3}) == {
        "l9": "10",
        "z13": "6",
        "q3_lower": "-0.2",
        "q3_upper": "0.3",
    }
    with pytest.raises(XacroArgumentError, match=r"^l9=10\.0001 is out of range"):
        validate_args(path, {"l9": 10.0001})


def test_cli_json_error_and_status(capsys):
    status = rcm_pin.cli.main(["urdf", "rcm_bevel", "--arg", "l9=1e308", "--json"])
    assert status == 2
    document = json.loads(capsys.readouterr().out)
    assert document == {
        "error": {
            "type": "XacroArgumentError",
            "message": f"l9=1e+308 is out of range for {BEVEL}; valid: {L9}",
        }
    }


def test_cli_plain_error_and_status(capsys):
    status = rcm_pin.cli.main(["urdf", "rcm_bevel", "--arg", "q3_lower=0.2"])
    assert status == 2
    err = capsys.readouterr().err
    assert err.strip().splitlines() == [
        "rcm-pin: error: XacroArgumentError: q3_lower=0.2 is not below q3_upper=0.12 in "
        f"{BEVEL}; valid: q3_lower < q3_upper"
    ]


def test_four_dof_rendering_has_its_own_robot_name():
    assert '<robot name="rcm_bevel_4dof">' in (urdf_dir() / "rcm_bevel_4dof.urdf").read_text()
    assert '<robot name="rcm_bevel">' in (urdf_dir() / "rcm_bevel.urdf").read_text()
    assert '<robot name="rcm_bevel_4dof">' in render_default("rcm_bevel_4dof")
    assert rcm_pin.load("rcm_bevel_4dof").model.name == "rcm_bevel_4dof"
    assert rcm_pin.load("rcm_bevel").model.name == "rcm_bevel"
    with pytest.raises(XacroArgumentError) as exc:
        rcm_pin.load("rcm_bevel_4dof", robot_name="x")
    assert str(exc.value) == (
        "xacro argument 'robot_name' is fixed by mechanism rcm_bevel_4dof "
        "(robot_name=rcm_bevel_4dof); load rcm_bevel.urdf.xacro variants by path instead"
    )


def test_every_rendering_is_named_after_its_entry():
    for entry in mechanisms():
        if entry.xacro:
            assert f'<robot name="{entry.name}">' in render_default(entry.name)

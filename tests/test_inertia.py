"""A robot without inertias: kinematics work, dynamics refuse with the links named."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import rcm_pin
from rcm_pin.cli import main
from rcm_pin.control import simulate
from rcm_pin.dynamics.inertia import massless_links, require_inertia
from rcm_pin.errors import InvalidInputError

ARM = Path(__file__).parent / "data" / "no_inertia_arm.urdf"
MESSAGE = (
    "no_inertia_arm: the mass matrix is singular (joints shoulder, elbow, slide move no "
    "inertia); links without <inertial>: base, upper, fore, tool; dynamics needs a mass and "
    "inertia on the links each joint moves; valid: a URDF with <inertial> elements "
    "(kinematic commands work without them)"
)


@pytest.fixture(scope="module")
def arm():
    return rcm_pin.load(ARM, tool_frame="tool")


def test_the_links_without_inertia_are_named(arm):
    assert massless_links(arm) == ["base", "upper", "fore", "tool"]


def test_simulate_refuses_with_the_links_named(arm):
    with pytest.raises(InvalidInputError) as info:
        simulate(arm, None, 0.1, q0=arm.home)
    assert str(info.value) == MESSAGE


def test_the_cli_refuses_with_one_json_document(arm, capsys):
    status = main(["simulate", str(ARM), "--tool-frame", "tool", "--duration", "0.1", "--json"])
    assert status == 2
    assert json.loads(capsys.readouterr().out)["error"] == {
        "type": "InvalidInputError",
        "message": MESSAGE,
    }


def test_kinematics_work_without_inertia(arm):
    q = np.array([0.3, -0.4, 0.05])
    status = main(["fk", str(ARM), "--tool-frame", "tool", "--q", "0.3,-0.4,0.05", "--json"])
    assert status == 0
    assert rcm_pin.tool_pose(arm, q).shape == (4, 4)


@pytest.mark.parametrize("name", ["rcm_bevel", "rcm_two_mass", "planar_3rrr", "spherical_3rrr"])
def test_every_catalogue_mechanism_carries_its_inertia(name):
    """rcm_two_mass has a massless platform and point masses; closed mechanisms are checked
    on the motions the closures allow (Nᵀ M N), so neither is refused."""
    mech = rcm_pin.load(name)
    require_inertia(mech, mech.home)

"""The singularity capability: every family's model or the numeric default, one path."""

from __future__ import annotations

import numpy as np
import pytest

import rcm_pin
from rcm_pin.analysis import maps
from rcm_pin.analysis.closed_singularity import configuration_report
from rcm_pin.analysis.loop_velocity import velocity_matrices
from rcm_pin.analysis.singularity_model import (
    NumericSingularity,
    SingularityModel,
    singularity_model,
)
from rcm_pin.model.family import Family

#: Closed catalogue mechanisms whose family gives the paper's A and B.
PAPER_AB = ("planar_3rrr", "five_bar", "four_bar", "spherical_3rrr", "translational_3ppapa")


def test_the_hooks_are_gone_from_family():
    for hook in ("ab_matrices", "singularity_causes", "singularity_map"):
        assert not hasattr(Family, hook)


@pytest.mark.parametrize("name", PAPER_AB)
def test_families_give_the_paper_matrices_and_the_report_their_determinants(name):
    m = rcm_pin.load(name)
    ab = singularity_model(m).ab_matrices(m, m.home)
    assert isinstance(singularity_model(m), SingularityModel) and ab.paper
    rep = configuration_report(m, m.home)
    assert rep["det_A"] == pytest.approx(np.linalg.det(ab.A), abs=0)
    assert rep["det_B"] == pytest.approx(np.linalg.det(ab.B), abs=0)


def test_the_default_is_pinocchio_without_determinants_or_causes():
    m = rcm_pin.load("four_bar")
    ab = NumericSingularity().ab_matrices(m, m.home)
    vm = velocity_matrices(m, m.home)
    assert not ab.paper and ab.det_A is None and ab.det_B is None
    assert np.array_equal(ab.A, vm.A) and np.array_equal(ab.B, vm.B)
    assert NumericSingularity().causes(m, m.home) == ()
    assert singularity_model(rcm_pin.load("eye_4dof")).causes(m, m.home) == ()


def test_rcm_names_its_causes_and_the_map_keys_stay():
    m = rcm_pin.load("rcm_bevel")
    q = np.array([0.1, 0.2, 0.0, 0.1, 0.5, 0.1])
    assert "tool_centre_at_A" in {c.name for c in singularity_model(m).causes(m, q)}
    res = maps.singularity_map(rcm_pin.load("five_bar"), mode=1, n=7)
    assert list(res)[:7] == ["mechanism", "x", "y", "det_A", "det_B", "mode", "phi"]
    assert res["mode"] == "+-" and res["phi"] is None

"""The control layer's capabilities (rcm_pin.control.capabilities): resolvers, defaults,
and a family's stop events on serial and closed plants alike."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import rcm_pin
from rcm_pin.control.capabilities import (
    DefaultScenarios,
    FrameJacobianTask,
    ScenarioSource,
    StopEvent,
    TaskModel,
    scenario_source,
    task_model,
)
from rcm_pin.control.scenario import run, scenarios
from rcm_pin.control.task import task_kinematics, task_output
from rcm_pin.model import family as model_family
from rcm_pin.model.family import Family


def test_the_model_layer_defines_no_control_type_or_hook():
    for name in ("TaskKinematics", "StopEvent"):
        assert not hasattr(model_family, name)
    for hook in ("task_kinematics", "scenarios", "stop_events"):
        assert not hasattr(Family, hook)


def test_resolvers_give_the_family_implementation_or_the_default():
    rcm, panda, rrr = (rcm_pin.load(n) for n in ("rcm_bevel", "panda", "planar_3rrr"))
    assert type(task_model(panda)) is FrameJacobianTask
    assert type(scenario_source(panda)) is DefaultScenarios
    assert isinstance(task_model(rcm), FrameJacobianTask)
    assert type(task_model(rcm)) is not FrameJacobianTask
    assert isinstance(scenario_source(rrr), ScenarioSource)
    assert isinstance(task_model(rrr), TaskModel)
    # the closed form where the family has one, the frame Jacobian route elsewhere
    assert task_kinematics(rcm, task_output(rcm, None)).closed_form
    assert not task_kinematics(rcm, task_output(rcm, ("x", "y"))).closed_form
    assert not task_kinematics(panda, task_output(panda, None)).closed_form
    assert list(scenarios(panda)) == ["home_circle"]
    assert list(scenarios(rcm)) == ["paper000", "rig_circle", "home_circle"]
    assert scenario_source(panda).stop_events(panda) == ()
    events = scenario_source(rcm).stop_events(rcm)
    assert [e.description for e in events] == ["q3 < 1 mm", "cos q2 < 0.01"]


class _Seen(DefaultScenarios):
    """A stop event on the plant's first coordinate after a time: records the q it sees."""

    def __init__(self) -> None:
        self.sizes: set[int] = set()

    def stop_events(self, mech: rcm_pin.Mechanism) -> tuple[StopEvent, ...]:
        def g(t: float, q: np.ndarray, v: np.ndarray) -> float:
            self.sizes.add(len(q))
            return 0.02 - t

        return (StopEvent("t > 0.02 s", g),)


@pytest.mark.parametrize("name, scenario", [("planar_3rrr", "circle"), ("five_bar", "crossing")])
def test_family_stop_events_end_closed_simulations(monkeypatch, name, scenario):
    """A closed plant's run stops at its family's events, evaluated on the full q."""
    mech = rcm_pin.load(name)
    sc = dataclasses.replace(scenarios(mech)[scenario], duration=0.05)
    seen = _Seen()
    monkeypatch.setattr(mech.family, "capabilities", (seen, *mech.family.capabilities))
    res = run(mech, sc)
    assert res.status == "stopped: t > 0.02 s"
    assert res.t[-1] == pytest.approx(0.02, abs=1e-9)
    assert seen.sizes == {mech.nq}
    monkeypatch.undo()
    assert run(mech, sc).status == "completed"


def test_paper000_ocp_refuses_a_task_without_the_closed_form():
    """ocp.paper000 asks the TaskModel's closed_form flag (the frame route has none)."""
    pytest.importorskip("casadi")
    from ocp import paper000
    from rcm_pin.errors import InvalidInputError

    with pytest.raises(InvalidInputError, match="panda has none"):
        paper000.build("panda")

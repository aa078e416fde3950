"""Workspace: volume by three routes, convergence, rig-spec verdict."""

from __future__ import annotations

import numpy as np
import pytest

import rcm_pin
from rcm_pin.errors import InvalidInputError
from rcm_pin.mechanisms.rcm import workspace as ws
from rcm_pin.mechanisms.rcm.closed_form import tool_position


@pytest.fixture(scope="module")
def mech():
    return rcm_pin.load("rcm_bevel")


def test_volume_routes_converge(mech):
    exact = ws.volume_analytic(mech)
    assert np.isclose(exact, (2 * np.pi / 3) * np.sqrt(3) * (0.12**3 - 0.05**3) / 3)
    v1, _ = ws.volume_monte_carlo(mech, 4000, seed=1)
    v2, _ = ws.volume_monte_carlo(mech, 16000, seed=2)
    assert abs(v1 - v2) / v2 < 0.02
    assert abs(v2 - exact) / exact < 0.02
    pts = ws.tool_centres(mech, ws.sample_joints(mech, 1_000_000))
    vox = ws.volume_voxels(pts, 0.002)
    assert abs(vox - exact) / exact < 0.05


def test_sampled_points_match_pinocchio(mech):
    qs = ws.sample_joints(mech, 200, seed=3)
    np.testing.assert_allclose(
        ws.tool_centres(mech, qs), rcm_pin.tool_poses(mech, qs)[:, :3, 3], atol=1e-12
    )
    np.testing.assert_allclose(ws.tool_centres(mech, qs), tool_position(qs), atol=0)


def test_spec_verdict_and_margins(mech):
    s = ws.spec_check(mech)
    assert s.contains and s.fraction_reached == 1.0
    assert (s.angular_margin, s.inner_margin, s.outer_margin) == (0.0, 0.0, 0.0)
    assert np.isclose(s.max_half_angle, np.pi / 3, atol=1e-9)
    small = rcm_pin.load("rcm_bevel", q1_limit=0.9, q3_upper=0.11)
    s2 = ws.spec_check(small)
    assert not s2.contains and s2.fraction_reached < 1.0
    assert np.isclose(s2.angular_margin, 0.9 - np.pi / 3, atol=1e-9)
    assert np.isclose(s2.outer_margin, -0.01)


def test_errors(mech):
    with pytest.raises(InvalidInputError) as exc:
        ws.sample_joints(mech, 0)
    assert str(exc.value) == "sample count 0; valid: >= 1"
    with pytest.raises(InvalidInputError) as exc:
        ws.volume_voxels(np.zeros((3, 3)), 0.0)
    assert str(exc.value) == "voxel edge 0.0; valid: > 0"


def test_numeric_closed_loop_workspace_refuses_a_run_it_cannot_afford(monkeypatch):
    """The cost guard times PROBE Newton samples and refuses before the rest are solved; when
    the affordable count is below MIN_SAMPLES it says so instead of suggesting it."""
    from rcm_pin.analysis import workspace as ws

    mech = rcm_pin.load("four_bar")  # without its family's closed form: the Newton route
    monkeypatch.setattr(ws, "workspace_model", lambda mech: ws.NumericWorkspace())
    monkeypatch.setattr(ws, "MAX_SECONDS", 1e-9)
    with pytest.raises(InvalidInputError) as exc:
        ws.summary(mech, samples=2000)
    text = str(exc.value)
    assert text.startswith("four_bar: 2000 samples would take about ")
    assert text.endswith(
        "samples, fewer than the 1000 a volume estimate needs: this mechanism's workspace "
        "needs a closed-form route"
    )


def test_numeric_closed_loop_workspace_reuses_its_probe_samples(monkeypatch):
    """The PROBE samples timed by the guard are part of the result: the same cloud as one
    uninterrupted run over the same inputs."""
    from rcm_pin.analysis import workspace as ws

    mech = rcm_pin.load("four_bar")  # without its family's closed form: the Newton route
    monkeypatch.setattr(ws, "workspace_model", lambda mech: ws.NumericWorkspace())
    s = ws.summary(mech, samples=1000, seed=3)
    pts = ws.output_points(mech, ws.sample_joints(mech, 1000, 3))
    ok = np.all(np.isfinite(pts), axis=1)
    np.testing.assert_allclose(s["extent_min"], pts[ok].min(axis=0), rtol=0, atol=1e-12)
    assert s["assembled_fraction"] == ok.mean()


def test_a_closed_loop_run_the_estimate_allows_is_not_refused():
    """eye_4dof (no closed-form workspace): the first Newton solve builds or loads its kernel;
    the guard warms it before timing, so a run of a few seconds is not refused as minutes
    (the five timed samples with the warm-up in them projected 15x)."""
    from rcm_pin.analysis import workspace as ws

    mech = rcm_pin.load("eye_4dof")
    assert isinstance(ws.workspace_model(mech), ws.NumericWorkspace)
    s = ws.summary(mech, samples=1500, seed=1)
    assert s["samples"] == 1500 and s["assembled_fraction"] > 0

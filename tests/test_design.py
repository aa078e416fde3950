"""Design studies (rcm_pin.design): validation, samplers, metrics by a second route, reruns."""

from __future__ import annotations

import numpy as np
import pytest

import rcm_pin
from rcm_pin.analysis.jacobians import tool_jacobian
from rcm_pin.design import Study, Vary, designs, run, validate
from rcm_pin.design.metrics import metric_source
from rcm_pin.design.study import parse_constraint, parse_vary, unit_points
from rcm_pin.errors import (
    InvalidInputError,
    UnknownMechanismError,
    UnreachablePoseError,
    XacroArgumentError,
)
from rcm_pin.mechanisms.rcm import design as rd
from rcm_pin.mechanisms.rcm.workspace import (
    SPEC_HALF_ANGLE,
    SPEC_R_MAX,
    SPEC_R_MIN,
    volume_analytic,
)

SMALL = Study(
    "rcm_bevel",
    (Vary("q2_limit", 0.8, 1.3, 3), Vary("q3_lower", 0.02, 0.06, 2)),
    ("cone_coverage", "worst_conditioning"),
    constraints=(parse_constraint("cone_coverage>=1"),),
)


# -- bad studies: typed errors before any work ----------------------------------------------
@pytest.mark.parametrize(
    ("study", "kind", "message"),
    [
        (
            Study("rcm_bevel", (Vary("q2_limit", 1.0, 1.0),), ("cone_coverage",)),
            InvalidInputError,
            "--vary q2_limit=1:1 is empty; valid: LO < HI",
        ),
        (
            Study("rcm_bevel", (Vary("l99", 0.1, 0.2),), ("cone_coverage",)),
            XacroArgumentError,
            "unknown xacro argument 'l99' for rcm_bevel; valid: ",
        ),
        (
            Study("rcm_bevel", (Vary("q2_limit", 0.5, 1.0),), ("speed",)),
            InvalidInputError,
            "unknown metric 'speed' for rcm_bevel; valid: cone_coverage, cone_margin, "
            "worst_conditioning, global_conditioning, rcm_drift",
        ),
        (
            Study("rcm_bevel", (Vary("l9", -0.1, 0.3),), ("rcm_drift",)),
            XacroArgumentError,
            "--vary l9=-0.1:0.3 leaves the argument's range in rcm_bevel.urdf.xacro; valid: "
            "(0, 10] [m] (initial link 9 length P7-P10)",
        ),
        (
            Study("rcm_bevel", (), ("cone_coverage",)),
            InvalidInputError,
            "the study varies nothing; valid: at least one --vary ARG=LO:HI",
        ),
        (
            Study("panda", (Vary("x", 0, 1),), ("cone_coverage",)),
            UnknownMechanismError,
            "panda has no xacro arguments to vary; valid: a xacro mechanism of the catalogue "
            "(`rcm-pin list`)",
        ),
    ],
    ids=["empty range", "unknown argument", "unknown metric", "outside bounds", "nothing", "urdf"],
)
def test_bad_studies_are_refused(study, kind, message):
    with pytest.raises(kind) as exc:
        validate(study)
    assert str(exc.value).startswith(message)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("q2_limit", "--vary 'q2_limit'; valid: ARG=LO:HI:N (N values on a grid) or ARG=LO:HI"),
        ("q2=a:b", "--vary 'q2=a:b'; valid: ARG=LO:HI:N (N values on a grid) or ARG=LO:HI"),
    ],
)
def test_bad_vary_text(text, message):
    with pytest.raises(InvalidInputError) as exc:
        parse_vary(text)
    assert str(exc.value) == message


def test_bad_constraint_text():
    with pytest.raises(InvalidInputError) as exc:
        parse_constraint("coverage > 1")
    assert str(exc.value) == "--constraint 'coverage > 1'; valid: METRIC>=VALUE or METRIC<=VALUE"


# -- samplers ------------------------------------------------------------------------------
def test_grid_is_the_product_with_ends_included():
    ds = designs(SMALL)
    values = sorted({dict(d.args)["q2_limit"] for d in ds})
    assert len(ds) == 6 and values == ["0.8", "1.05", "1.3"]
    assert len({d.key for d in ds}) == 6


@pytest.mark.parametrize("sampler", ["lhs", "random"])
def test_lhs_and_random_are_seeded_and_inside_the_box(sampler):
    study = Study("rcm_bevel", SMALL.vary, SMALL.metrics, sampler=sampler, samples=50, seed=4)
    u = unit_points(study)
    assert u.shape == (50, 2) and np.all((u >= 0) & (u <= 1))
    np.testing.assert_array_equal(u, unit_points(study))
    if sampler == "lhs":  # one point per stratum in each dimension
        for k in range(2):
            np.testing.assert_array_equal(np.sort(np.floor(u[:, k] * 50)), np.arange(50))


# -- metrics against independent routes -----------------------------------------------------
@pytest.mark.parametrize("args", [{}, {"q2_limit": "0.7", "q3_lower": "0.03"}])
def test_worst_conditioning_equals_the_corner_closed_form_and_pinocchio(args):
    mech = rcm_pin.load("rcm_bevel", **args)
    q2max = max(abs(mech.lower[1]), abs(mech.upper[1]))
    closed = mech.lower[2] / mech.upper[2] * np.cos(q2max)
    np.testing.assert_allclose(rd.worst_conditioning(mech), closed, rtol=1e-12)
    rng = np.random.default_rng(0)
    q = rng.uniform(mech.lower, mech.upper, size=(20, mech.nq))
    jac = rd.point_jacobians(q)
    for qi, ji in zip(q, jac, strict=True):  # Pinocchio's tool Jacobian, position rows
        np.testing.assert_allclose(ji, tool_jacobian(mech, qi)[:3, :3], atol=1e-12)


def test_cone_coverage_is_the_volume_ratio_when_the_workspace_lies_inside_the_spec():
    # limits strictly inside the spec region: coverage = V_workspace / V_spec (analytic)
    mech = rcm_pin.load("rcm_bevel", q1_limit="0.3", q2_limit="0.3", q3_lower="0.06")
    v_spec = 2 * np.pi * (1 - np.cos(SPEC_HALF_ANGLE)) * (SPEC_R_MAX**3 - SPEC_R_MIN**3) / 3
    ratio = volume_analytic(mech) / v_spec
    n = rd.COVERAGE_SAMPLES
    stderr = np.sqrt(ratio * (1 - ratio) / n)
    assert abs(rd.METRICS["cone_coverage"].evaluate(mech) - ratio) < 4 * stderr


def test_rcm_drift_linear_rms_matches_a_nonlinear_monte_carlo():
    """E|c|² = Σ σ_k²|S_k|² (first order) against 400 models with every placement perturbed
    at once: the Monte Carlo RMS has a relative standard error of about 1/sqrt(2·400) = 3.5 %
    plus the second-order remainder (σ ~ 1e-3 rad: 0.1 %), hence the 12 % bound (3.4 σ)."""
    from rcm_pin.studies.rig_design import monte_carlo_drift

    linear, mc = monte_carlo_drift("rcm_bevel", samples=400, seed=7)
    assert abs(mc - linear) < 0.12 * linear, (mc, linear)
    mech = rcm_pin.load("rcm_bevel")
    shares = rd.drift_contributions(mech, mech.configurations["mid"])
    np.testing.assert_allclose(sum(s for _, s in shares), 1.0, rtol=1e-12)


# -- execution and the table ---------------------------------------------------------------
def test_parallel_run_equals_the_serial_run_and_a_rerun_reuses_it(tmp_path):
    serial = run(SMALL, workers=1, progress=False)
    folder = tmp_path / "study"
    folder.mkdir()
    parallel = run(SMALL, out=folder, workers=2, chunk=2, progress=False)
    assert parallel.frame.equals(serial.frame)
    assert (parallel.computed, parallel.reused) == (6, 0)
    again = run(SMALL, out=folder, workers=2, progress=False)
    assert (again.computed, again.reused) == (0, 6) and again.frame.equals(serial.frame)
    frame = serial.frame
    assert list(frame["feasible"]) == list(frame["cone_coverage"] >= 1.0)


def test_a_design_that_cannot_be_built_is_a_row_with_its_error():
    study = Study("rcm_bevel", (Vary("q3_lower", 0.05, 0.2, 2),), ("worst_conditioning",))
    frame = run(study, workers=1, progress=False).frame.set_index("arg.q3_lower")
    assert frame.loc[0.05, "status"] == "ok"
    assert frame.loc[0.2, "status"] == (
        "XacroArgumentError: q3_lower=0.2 is not below q3_upper=0.12 in rcm_bevel.urdf.xacro; "
        "valid: q3_lower < q3_upper"
    )
    assert np.isnan(frame.loc[0.2, "worst_conditioning"]) and not frame.loc[0.2, "feasible"]


def test_planar_3rrr_conditioning_uses_the_jacobian_pinocchio_gives():
    """−A⁻¹B of the closed form at region points equals Pinocchio's output Jacobian (route 2),
    and the region lies inside the constant-orientation workspace, free of singularities."""
    from rcm_pin.analysis.loop_velocity import velocity_matrices
    from rcm_pin.mechanisms.planar_3rrr import design as pd3

    mech = rcm_pin.load("planar_3rrr")
    grid, region, q = pd3.regular_region(mech)
    poses, drives = grid.poses(0.0)[region], q[region]
    from rcm_pin.mechanisms.planar_3rrr import geometry
    from rcm_pin.mechanisms.planar_3rrr.workspace import constant_orientation

    reach = constant_orientation(geometry(mech), grid, 0.0)
    assert region.any() and not np.any(region & ~reach)  # inside W(0)
    rng = np.random.default_rng(2)
    for k in rng.choice(len(poses), size=5, replace=False):
        sol = next(s for s in rcm_pin.inverse(mech, poses[k]).solutions if s.mode == "+++")
        np.testing.assert_allclose(sol.q[mech.loops.drive_q], drives[k], atol=1e-9)
        pin_j = velocity_matrices(mech, sol.q).output_jacobian()
        closed = pd3.output_jacobians(mech, poses[k][None], drives[k][None])[0]
        np.testing.assert_allclose(closed, pin_j, rtol=1e-9, atol=1e-9)
    value = pd3.mean_conditioning(mech)
    assert 0 < value <= 1


def test_the_cli_samplers_are_the_design_samplers():
    from rcm_pin.cli import design as cli_design
    from rcm_pin.design.study import SAMPLERS

    assert cli_design.SAMPLERS == SAMPLERS


def test_four_bar_swing_metric_equals_the_family_closed_form_and_a_sweep():
    """Swing by the linkage module's dead centres against the family's own rocker_range
    (circle intersections) and a dense sweep of the crank turn on Pinocchio's closed loop."""
    from rcm_pin.mechanisms import four_bar as fb

    args = {"frame": "0.06", "crank": "0.018", "coupler": "0.075", "rocker": "0.05"}
    mech = rcm_pin.load("four_bar", **args)
    metrics = metric_source(mech.family).metrics()
    lo, hi = fb.rocker_range(fb.geometry(mech))
    np.testing.assert_allclose(metrics["swing"].evaluate(mech), np.rad2deg(hi - lo), rtol=1e-12)
    psi = []
    for q1 in np.linspace(-np.pi, np.pi, 181):
        sol = rcm_pin.forward(mech, [q1]).solutions[0]
        psi.append(sol.output[0] if sol.output.size == 1 else sol.output[-1])
    sweep = np.rad2deg(np.ptp(np.unwrap(psi)))
    assert 0 <= np.rad2deg(hi - lo) - sweep < 0.05  # 2° crank steps sample the extremes
    assert 0 < metrics["worst_transmission"].evaluate(mech) <= 90
    assert metrics["time_ratio"].evaluate(mech) >= 1


@pytest.mark.parametrize(
    "args", [{}, {"theta_11": "80", "theta_12": "70"}], ids=["agile", "general"]
)
def test_spherical_regular_share_verdicts_agree_with_pinocchio(args):
    """At sampled orientations the closed-form measures' regular / near-singular verdict
    (margin 0.05) agrees with Pinocchio's A/B classifier on the polished configuration."""
    from rcm_pin.analysis.loop_velocity import velocity_matrices
    from rcm_pin.mechanisms.spherical_3rrr import design as sd

    mech = rcm_pin.load("spherical_3rrr", **args)
    rots = sd.sample_rotations(12, seed=3)
    ok, _ = sd.regular_mask(mech, rots)
    checked = 0
    for R, regular in zip(rots, ok, strict=True):
        try:
            sols = [s for s in rcm_pin.inverse(mech, R).solutions if s.mode == "+++"]
        except UnreachablePoseError:  # a leg cannot reach R: never counted as regular
            sols = []
        if not sols:
            assert not regular
            continue
        vm = velocity_matrices(mech, sols[0].q)
        if regular:  # regular in the closed form: Pinocchio's measures are far from 0 too
            assert min(vm.measure_type1, vm.measure_type2) > 1e-3
            checked += 1
    assert checked >= 3
    share = sd.regular_share(mech)
    assert 0 < share < 1


@pytest.mark.parametrize("args", [{}, {"q2_limit": "0.7", "q3_lower": "0.03"}])
def test_global_conditioning_equals_its_closed_form(args):
    """κ⁻¹ = q3·cos q2 / L on the box (σ = q3 cos q2 / L, q3 / L, 1 with q3 ≤ L), so the
    volume-weighted mean is (1/L)·(∫q3³/∫q3²)·(∫cos²q2/∫cos q2) over the limits."""
    mech = rcm_pin.load("rcm_bevel", **args)
    a, b, c = mech.lower[2], mech.upper[2], mech.upper[1]
    assert mech.lower[1] == -c
    radial = ((b**4 - a**4) / 4) / ((b**3 - a**3) / 3)
    angular = (c + np.sin(2 * c) / 2) / (2 * np.sin(c))
    np.testing.assert_allclose(rd.global_conditioning(mech), radial * angular / b, rtol=1e-12)

"""The 3-PPaPa's workspace volumes, sections and the accuracy hook.

Routes: Monte Carlo vs the grid vs the closed-form reach (2 min(l1, l2))³; the restored
Cramer denominator vs det A; the linear theory vs central differences of the nonlinear
re-solve; the ``accuracy`` hook through the CLI.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import EXACT

import rcm_pin
from rcm_pin.analysis.accuracy import accuracy_model
from rcm_pin.analysis.workspace import workspace_model
from rcm_pin.cli import main
from rcm_pin.errors import SingularConfigurationError
from rcm_pin.mechanisms import translational_3ppapa as tp
from rcm_pin.mechanisms.translational_3ppapa import accuracy as acc
from rcm_pin.mechanisms.translational_3ppapa import workspace as ws


@pytest.fixture(scope="module")
def mm():
    return rcm_pin.load("translational_3ppapa")


@pytest.fixture(scope="module")
def g(mm):
    return tp.geometry(mm)


@pytest.fixture(scope="module")
def vol(mm, g):
    return ws.volumes(g, tp.drive_limits(mm), samples=4000, grid=22, seed=3)


def test_reach_volume_three_routes(vol):
    assert vol["exact_reach"] == pytest.approx(0.512, abs=EXACT)  # (2 · 0.4)³
    # 22 cells a side put the cube's faces on cell faces: the grid's reach is exact
    np.testing.assert_allclose(vol["grid"]["reach"], vol["exact_reach"], atol=EXACT)
    dev = np.abs(vol["monte_carlo"]["reach"] - vol["exact_reach"])
    assert np.all(dev <= 4 * vol["standard_error"]["reach"])


def test_det_sign_volumes_split_the_reach_and_routes_agree(vol):
    for route in ("grid", "monte_carlo"):
        split = vol[route]["det_positive"] + vol[route]["det_negative"]
        np.testing.assert_allclose(split, vol[route]["reach"], atol=EXACT)
    for key in ("det_positive", "conditioned"):
        dev = np.abs(vol["monte_carlo"][key] - vol["grid"][key])
        # 4 standard errors of the Monte Carlo plus the grid's cell-size error (~5 % of V)
        assert np.all(dev <= 4 * vol["standard_error"][key] + 0.05 * vol["exact_reach"])


def test_drive_limits_cut_the_reach(g):
    rng = np.random.default_rng(7)
    p = rng.uniform(-0.45, 0.45, (500, 3))
    m = ws.measures(g, p, (0.9, 1.1))
    for k in (0, 21, 63):
        q = ws.drives(g, p, np.broadcast_to(ws.SIGNS[k], (500, 3, 2)))
        with np.errstate(invalid="ignore"):
            expect = np.isfinite(q).all(1) & (q >= 0.9).all(1) & (q <= 1.1).all(1)
        np.testing.assert_array_equal(m["reach"][k], expect)
    assert 0 < m["reach"][0].sum() < np.isfinite(ws.drives(g, p, ws.SIGNS[0])).all(1).sum()


def test_diagonal_point_is_type_2_and_sections_show_it(g):
    t = tp.diagonal_singularity(g)
    assert t == pytest.approx(0.19785, abs=1e-5)
    s = np.broadcast_to(ws.SIGNS[0], (3, 3, 2))
    dets = np.linalg.det(tp.a_matrix(g, np.array([t - 1e-3, t, t + 1e-3])[:, None] * [1, 1, 1], s))
    assert abs(dets[1]) < EXACT and dets[0] < 0 < dets[2]
    sec = ws.section(g, 0, t, tp.MODES[0], n=41)
    assert np.nanmin(sec["det"]) < 0 < np.nanmax(sec["det"])


def test_workspace_model_writes_png(mm, tmp_path):
    path = workspace_model(mm).plot(mm, tmp_path / "w.png", 200_000, 0)
    assert path.stat().st_size > 10_000


def test_cramer_denominator_is_det_a(g):
    rng = np.random.default_rng(8)
    for p in rng.uniform(-0.35, 0.35, (20, 3)):
        for lab, _, ang in tp.inverse_position(g, p)[::9]:
            assert acc.cramer_denominator(ang) == pytest.approx(
                np.linalg.det(tp.a_from_angles(ang)), abs=EXACT
            ), lab


def test_linear_theory_is_the_derivative_of_the_nonlinear_error(mm, g):
    q = mm.configurations["regular"]
    rep = accuracy_model(mm).report(mm, q).to_dict()
    np.testing.assert_allclose(rep["point"], tp.REGULAR, atol=EXACT)
    drives, p = rep["drives"], rep["point"]
    signs, ang = np.ones((3, 2)), tp.crank_angles(mm, q)
    h = 1e-6
    for j in range(3):
        dl = np.zeros(3)
        dl[j] = h
        fd = (acc.nonlinear_error(g, drives, p, signs, dl)
              - acc.nonlinear_error(g, drives, p, signs, -dl)) / (2 * h)  # fmt: skip
        lin = acc.linear_error(tp.a_matrix(g, p, signs), -acc.length_jacobian(ang) @ dl) / h
        np.testing.assert_allclose(lin, fd, rtol=1e-6)  # central difference O(h²) + rounding
    norms = [r for r in rep["rows"] if r["component"] == "|p|"]
    assert [r["joint"] for r in norms] == ["l1", "l2", "l3"]
    rel = [r["relative_difference"] for r in norms]
    assert all(1e-4 < x < 0.05 for x in rel)  # 1 mm errors: second-order terms ~1 %


def test_linear_theory_refuses_the_type_2_point(g):
    t = tp.diagonal_singularity(g)
    a = tp.a_matrix(g, np.full(3, t), np.ones((3, 2)))
    with pytest.raises(SingularConfigurationError) as e:
        acc.linear_error(a, np.ones(3))
    det = float(np.linalg.det(a))
    assert str(e.value) == (
        f"3-PPaPa accuracy: Cramer's rule: det A = {det:.3e} (type-2 singularity: no "
        "denominator); valid: a configuration with |det A| >= 1e-12"
    )


def test_accuracy_cli_uses_the_hook(capsys):
    code = main(["accuracy", "translational_3ppapa", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and len(out["rows"]) == 12
    assert out["denominator"] == acc.DENOMINATOR
    assert {r["joint"] for r in out["rows"]} == {"l1", "l2", "l3"}


def test_report_tables_are_well_formed(mm):
    """The report section's mobility and accuracy tables (the full section runs in
    ``rcm-pin reproduce``: ~30 s): every table row has its header's column count."""
    from rcm_pin.report import translational as rep

    ml = rcm_pin.load(tp.MODELS[1])
    text = "\n".join([*rep._mobility(mm, ml), "", *rep._accuracy(mm)])
    tables = [b for b in text.split("\n\n") if b.startswith("|")]
    assert len(tables) == 3  # mobility, accuracy, comparison
    for table in tables:
        rows = table.splitlines()
        assert len(rows) >= 3 and len({x.count("|") for x in rows}) == 1
    assert "W = 6·21 − 6·2 − 5·21 − 3·6 = -9" in "\n".join(rep._mobility(mm, ml))

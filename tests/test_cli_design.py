"""``rcm-pin sweep`` and ``rcm-pin optimize``: JSON documents, files, typed errors."""

from __future__ import annotations

import json

import pandas as pd
import pytest

from rcm_pin.cli import main

SWEEP = [
    "sweep", "rcm_bevel", "--vary", "q2_limit=0.8:1.2:3", "--vary", "q3_lower=0.03:0.06:2",
    "--metric", "worst_conditioning", "--metric", "cone_coverage",
    "--constraint", "cone_coverage>=1", "--workers", "1",
]  # fmt: skip


def run_json(capsys, argv):
    code = main([*argv, "--json"])
    return code, json.loads(capsys.readouterr().out)


def test_sweep_writes_the_table_and_the_maps(capsys, tmp_path):
    code, doc = run_json(capsys, [*SWEEP, "--out", str(tmp_path)])
    assert code == 0
    assert (doc["designs"], doc["computed"], doc["reused"]) == (6, 6, 0)
    assert sorted(p.rsplit("/", 1)[1] for p in doc["figures"]) == [
        "map_cone_coverage.png",
        "map_worst_conditioning.png",
    ]
    table = pd.read_parquet(tmp_path / "designs.parquet")
    assert sorted(table["key"]) == sorted(r["key"] for r in doc["rows"])
    for row in doc["rows"]:
        assert row["feasible"] == (row["cone_coverage"] >= 1.0)
    code, again = run_json(capsys, [*SWEEP, "--out", str(tmp_path)])
    assert (again["computed"], again["reused"]) == (0, 6) and again["rows"] == doc["rows"]


def test_optimize_returns_a_pareto_front(capsys):
    argv = [
        "optimize", "rcm_bevel", "--vary", "q2_limit=0.6:1.4", "--vary", "q3_lower=0.02:0.07",
        "--metric", "cone_coverage", "--metric", "worst_conditioning",
        "--trials", "8", "--population", "4", "--workers", "1", "--seed", "3",
    ]  # fmt: skip
    code, doc = run_json(capsys, argv)
    assert code == 0 and (doc["trials"], doc["generations"]) == (8, 2)
    front = doc["pareto"]
    assert front
    for a in front:  # no member of the front dominates another
        for b in front:
            assert not (
                b["cone_coverage"] >= a["cone_coverage"]
                and b["worst_conditioning"] >= a["worst_conditioning"]
                and (b["cone_coverage"], b["worst_conditioning"])
                != (a["cone_coverage"], a["worst_conditioning"])
            )


@pytest.mark.parametrize(
    ("extra", "kind", "message"),
    [
        (
            ["--vary", "q2_limit=1.2:0.8"],
            "InvalidInputError",
            "--vary q2_limit=1.2:0.8 is empty; valid: LO < HI",
        ),
        (
            ["--vary", "q2_limit=0.5:1", "--scheduler", "tcp://127.0.0.1:1", "--workers", "2"],
            "InvalidInputError",
            "--scheduler and --workers conflict; valid: one of them",
        ),
        (
            ["--vary", "q2_limit=0.5:1", "--out", "/nonexistent-dir/x"],
            "InvalidInputError",
            "--out '/nonexistent-dir/x': folder '/nonexistent-dir' does not exist; valid: a "
            "path in an existing folder",
        ),
    ],
    ids=["empty range", "conflict", "missing folder"],
)
def test_sweep_errors(capsys, extra, kind, message):
    argv = ["sweep", "rcm_bevel", "--metric", "cone_coverage", *extra]
    code, doc = run_json(capsys, argv)
    assert code == 2 and doc == {"error": {"type": kind, "message": message}}

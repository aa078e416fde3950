"""Crash consistency of ``rcm-pin sweep`` (tiny studies): SIGKILL at seeded random points
then a rerun gives the uninterrupted table bit for bit and computes only what is missing;
one run per folder; damaged parts of the store are recomputed with a warning; no pool
process outlives a killed run; the code hash follows every module the metrics run.

Compared: the whole table (``designs.parquet``, every column). It has no timing column
(a run's duration is in the command's output, ``seconds``, not in the rows), so nothing is
excluded.
"""

from __future__ import annotations

import json
import os
import random
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest
from crash import descendants, kill_when, survivors, wait_for

from rcm_pin.cli import main
from rcm_pin.design import Study, Vary, provenance, run, store
from rcm_pin.design.evaluate import evaluate_chunk
from rcm_pin.design.study import designs
from rcm_pin.errors import CodeMismatchError
from rcm_pin.processes import lock_holder

ROOT = Path(__file__).resolve().parents[1]
ARGS = ["rcm_bevel", "--vary", "q2_limit=0.8:1.3:4", "--metric", "worst_conditioning"]
S1 = [*ARGS, "--vary", "q3_upper=0.1:0.2:2"]  # 8 designs
S2 = [*ARGS, "--vary", "q3_upper=0.1:0.2:3"]  # 12 designs, 8 of them those of S1
STUDY = Study(
    "rcm_bevel",
    (Vary("q2_limit", 0.8, 1.3, 4), Vary("q3_upper", 0.1, 0.2, 2)),
    ("worst_conditioning",),
)


def sweep(out: Path, argv: list[str], *options: str) -> subprocess.Popen:
    cmd = [sys.executable, "-m", "rcm_pin", "sweep", *argv, "--out", str(out), "--json", *options]
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def part_rows(out: Path) -> int:
    return sum(len(pd.read_parquet(p)) for p in store.parts(out))


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The uninterrupted run's table (bytes) and frame."""
    out = tmp_path_factory.mktemp("reference")
    res = run(STUDY, out, workers=1, chunk=1, progress=False)
    assert res.computed == 8
    return (out / store.TABLE).read_bytes(), res.frame


@pytest.mark.parametrize("seed", [1, 2])
def test_killed_sweeps_then_a_rerun_give_the_uninterrupted_table(seed, tmp_path, reference):
    rng = random.Random(seed)
    killed = 0
    for _ in range(2):  # two kills at random points (after 1..3 more committed chunks)
        start = len(store.parts(tmp_path))
        proc = sweep(tmp_path, S1, "--workers", "2", "--chunk", "1")
        chunks, family = start + rng.randint(1, 3), set()

        def ready(proc=proc, chunks=chunks, family=family) -> bool:
            family |= descendants(proc.pid)
            return len(store.parts(tmp_path)) >= chunks

        killed += kill_when(proc, ready, rng.uniform(0.0, 0.3))
        assert not survivors(family), "pool processes outlived the killed sweep"
    assert killed  # at least one kill landed mid-run
    kept = part_rows(tmp_path)
    again = run(STUDY, tmp_path, workers=1, progress=False)
    assert (again.computed, again.reused) == (8 - kept, kept)  # only what was missing
    assert (tmp_path / store.TABLE).read_bytes() == reference[0]
    assert again.frame.equals(reference[1])
    left = {p.name for p in tmp_path.iterdir()} - {"map_worst_conditioning.png"}  # a CLI run's
    assert left == {".lock", store.TABLE, store.PARTS}  # no temporary file left behind
    assert [p.suffix for p in (tmp_path / store.PARTS).iterdir()] == [".parquet"]  # compacted


def test_a_second_sweep_on_the_folder_is_refused_naming_the_holder(tmp_path, capsys):
    first = sweep(tmp_path, S1, "--workers", "1", "--chunk", "1")
    assert wait_for(first, lambda: lock_holder(tmp_path) == first.pid)
    code = main(["sweep", *S2, "--workers", "1", "--out", str(tmp_path), "--json"])
    error = json.loads(capsys.readouterr().out)["error"]
    assert code == 2 and error["type"] == "FolderBusyError"
    assert error["message"] == (
        f"--out {tmp_path} is in use by another run (PID {first.pid}); valid: wait until it "
        "ends, or another folder"
    )
    out, _ = first.communicate()
    assert first.returncode == 0 and json.loads(out)["computed"] == 8
    code = main(["sweep", *S2, "--workers", "1", "--out", str(tmp_path), "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert code == 0 and (doc["computed"], doc["reused"]) == (4, 8)
    assert len(pd.read_parquet(tmp_path / store.TABLE)) == 12  # the union, each design once


def _interrupted(out: Path, after: int) -> None:
    """A run stopped (an exception) after ``after`` committed chunks of 2 designs."""

    def stop(done: int, total: int) -> None:
        if done >= 2 * after:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run(STUDY, out, workers=1, chunk=2, progress=False, on_chunk=stop)


@pytest.mark.parametrize("damage", ["truncated", "emptied", "byte-flipped"])
def test_a_damaged_part_is_set_aside_and_recomputed(damage, tmp_path, reference):
    _interrupted(tmp_path, after=3)
    parts = store.parts(tmp_path)
    assert len(parts) == 3 and part_rows(tmp_path) == 6
    data = parts[1].read_bytes()
    if damage == "truncated":
        data = data[: len(data) // 2]
    elif damage == "emptied":
        data = b""
    else:
        data = data[:100] + bytes([data[100] ^ 0x01]) + data[101:]
    parts[1].write_bytes(data)
    stale = [tmp_path / ".designs.parquet.x1.tmp", tmp_path / store.PARTS / ".abc.parquet.x2.tmp"]
    for path in stale:  # as a run killed between writing and renaming leaves them
        path.write_bytes(data[:10])
    with pytest.warns(store.StoreWarning, match="do not match its SHA-256 name"):
        again = run(STUDY, tmp_path, workers=1, progress=False)
    assert (again.computed, again.reused) == (4, 4)  # the damaged part's 2 and the 2 missing
    assert (tmp_path / store.TABLE).read_bytes() == reference[0]
    assert parts[1].with_suffix(".damaged").is_file()  # kept aside, not served
    assert not any(path.exists() for path in stale)


def _edited(monkeypatch, tmp_path, module: str) -> None:
    """As if ``module``'s source had changed (its file swapped for an edited copy)."""
    files = dict(provenance._modules())
    copy = tmp_path / "edited.py"
    copy.write_bytes(files[module].read_bytes() + b"\n# edited\n")
    monkeypatch.setattr(provenance, "_modules", lambda: {**files, module: copy})
    provenance.code_hash.cache_clear()
    monkeypatch.setattr(provenance.code_hash, "cache_clear", provenance.code_hash.cache_clear)


@pytest.mark.parametrize(
    "module",
    ["rcm_pin.linkage.fourbar", "ocp.kernels.closure_kernel", "rcm_pin.mechanisms.rcm.design"],
)
def test_a_changed_module_the_metrics_run_recomputes_every_design(module, monkeypatch, tmp_path):
    out = tmp_path / "study"
    out.mkdir()
    assert run(STUDY, out, workers=1, progress=False).computed == 8
    before = provenance.code_hash("rcm_bevel")
    _edited(monkeypatch, tmp_path, module)
    try:
        assert provenance.code_hash("rcm_bevel") != before
        again = run(STUDY, out, workers=1, progress=False)
        assert (again.computed, again.reused) == (8, 0)
        assert set(again.frame["model_hash"]) == {provenance.code_hash("rcm_bevel")}
    finally:
        provenance.code_hash.cache_clear()


def test_a_module_the_metrics_never_run_keeps_the_hash(monkeypatch, tmp_path):
    before = provenance.code_hash("rcm_bevel")
    _edited(monkeypatch, tmp_path, "rcm_pin.cli.design")
    try:
        assert provenance.code_hash("rcm_bevel") == before
    finally:
        provenance.code_hash.cache_clear()


def test_a_worker_with_another_code_hash_refuses_its_chunk():
    chunk = designs(STUDY)[:2]
    with pytest.raises(
        CodeMismatchError, match=r"runs code hash \w{16} for rcm_bevel, the client 0{16}"
    ):
        evaluate_chunk(chunk, ("worst_conditioning",), expected="0" * 16)
    assert (
        len(evaluate_chunk(chunk, ("worst_conditioning",), provenance.code_hash("rcm_bevel"))) == 2
    )

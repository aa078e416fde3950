"""Optional features without their extra: a typed error that names the install command.

A missing package is simulated by ``sys.modules[name] = None`` (``import name`` then
raises ModuleNotFoundError), in a fresh interpreter where the feature's modules may
already be imported in this one.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import fake_sections
import pytest

from rcm_pin.errors import EXTRAS, MissingExtraError, RcmPinError, require
from rcm_pin.report import runner

DESIGN = "pip install 'rcm-pin[design]'"
ARMS = "pip install 'rcm-pin[arms]'"
SWEEP = ["sweep", "rcm_bevel", "--vary", "q2_limit=0.8:1.4:2", "--metric", "cone_coverage"]


def message(package: str, extra: str) -> str:
    return (
        f"{package}, needed for {EXTRAS[extra]}, is not installed; "
        f"valid: pip install 'rcm-pin[{extra}]'"
    )


def cli_without(blocked: list[str], argv: list[str]) -> tuple[int, str, str]:
    """``rcm-pin argv`` in a fresh interpreter where the ``blocked`` modules are missing."""
    code = textwrap.dedent(
        f"""
        import sys
        for name in {blocked!r}:
            sys.modules[name] = None
        from rcm_pin.cli import main
        raise SystemExit(main({argv!r}))
        """
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    return proc.returncode, proc.stdout, proc.stderr


def test_require_names_package_feature_and_install_command(monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(MissingExtraError) as exc:
        require("design", "pandas")
    assert str(exc.value) == (
        "pandas, needed for design studies (rcm-pin sweep / optimize), is not installed; "
        "valid: pip install 'rcm-pin[design]'"
    )
    assert isinstance(exc.value, RcmPinError) and isinstance(exc.value, ImportError)
    assert exc.value.name == "pandas"
    assert isinstance(exc.value.__cause__, ModuleNotFoundError)


@pytest.mark.parametrize(
    ("extra", "module", "blocked", "package"),
    [
        ("arms", "pink.tasks", "pink", "pin-pink"),  # the distribution, not the module
        ("design", "distributed", "distributed", "dask[distributed]"),
        ("arms", "qpsolvers", "qpsolvers", "qpsolvers"),
        ("report", "grimp", "grimp", "grimp"),
    ],
)
def test_require_names_the_distribution(monkeypatch, extra, module, blocked, package):
    monkeypatch.setitem(sys.modules, blocked, None)
    with pytest.raises(MissingExtraError) as exc:
        require(extra, module)
    assert str(exc.value) == message(package, extra)


def test_require_a_broken_package_says_so(tmp_path, monkeypatch):
    (tmp_path / "half_installed.py").write_text("import not_a_module_of_any_extra\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    with pytest.raises(MissingExtraError) as exc:
        require("design", "half_installed")
    assert str(exc.value) == (
        f"half_installed, needed for {EXTRAS['design']}, cannot be imported (No module named "
        f"'not_a_module_of_any_extra'); valid: {DESIGN}"
    )


def test_require_returns_an_installed_module():
    import json as json_module

    assert require("design", "json") is json_module


def test_sweep_without_pandas_is_bad_input_with_the_install_command():
    code, out, err = cli_without(["pandas"], [*SWEEP, "--json"])
    assert code == 2, err
    doc = json.loads(out)
    assert doc == {"error": {"type": "MissingExtraError", "message": message("pandas", "design")}}
    assert DESIGN in doc["error"]["message"]


def test_sweep_without_pandas_prints_one_line():
    code, out, err = cli_without(["pandas"], SWEEP)
    assert code == 2 and out == ""
    assert err == f"rcm-pin: error: MissingExtraError: {message('pandas', 'design')}\n"


def test_sweep_into_a_folder_without_pyarrow_fails_before_computing(tmp_path):
    code, out, _ = cli_without(["pyarrow"], [*SWEEP, "--out", str(tmp_path / "s"), "--json"])
    assert code == 2
    assert json.loads(out)["error"]["message"] == message("pyarrow", "design")
    assert not (tmp_path / "s" / "designs.parquet").exists()


def test_optimize_without_optuna():
    argv = ["optimize", *SWEEP[1:], "--trials", "2", "--json"]
    code, out, _ = cli_without(["optuna"], argv)
    assert code == 2
    assert json.loads(out)["error"]["message"] == message("optuna", "design")


def test_a_study_is_described_without_the_design_extra():
    """Only running a study needs pandas: Study / Vary (rcm_pin.design.study) do not."""
    code = textwrap.dedent(
        """
        import sys
        sys.modules["pandas"] = None
        from rcm_pin.design import Study, Vary, designs
        study = Study("rcm_bevel", (Vary("q2_limit", 0.8, 1.4, 3),), ("cone_coverage",))
        print(len(designs(study)))
        """
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "3"


def test_rcm_track_on_an_arm_without_qpsolvers():
    argv = ["rcm-track", "panda", "--path", "circle", "--duration", "0.01", "--json"]
    code, out, err = cli_without(["qpsolvers"], argv)
    assert code == 2, err
    assert json.loads(out)["error"] == {
        "type": "MissingExtraError",
        "message": message("qpsolvers", "arms"),
    }


def test_rcm_track_on_a_mechanical_rcm_needs_no_extra():
    argv = ["rcm-track", "rcm_bevel", "--path", "circle", "--duration", "0.01", "--json"]
    code, out, err = cli_without(["qpsolvers", "daqp", "pink"], argv)
    assert code == 0, err
    assert json.loads(out)["rcm"] == "mechanical"


def test_pink_route_without_pink():
    code = textwrap.dedent(
        """
        import sys
        sys.modules["pink"] = None
        from rcm_pin.errors import MissingExtraError
        try:
            import rcm_pin.control.rcm_pink
        except MissingExtraError as exc:
            print(exc)
        """
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.stdout.strip() == message("pin-pink", "arms"), proc.stderr


@pytest.fixture
def no_grimp(monkeypatch):
    """The report runner as without the [report] extra (its import graph is cached)."""
    monkeypatch.setitem(sys.modules, "grimp", None)
    runner._graph.cache_clear()
    yield
    runner._graph.cache_clear()


def test_report_cache_without_grimp_keys_on_every_module(no_grimp, tmp_path):
    """Without grimp the report still runs; a section's key covers every module of rcm_pin
    and ocp (never stale, only coarser) and a rerun still comes from the cache."""
    assert runner._graph() is None
    every = runner._every_module()
    assert {"rcm_pin", "rcm_pin.errors", "rcm_pin.report.position", "ocp", "ocp.kernels"} <= every
    assert len(runner.cache_key("fake_sections")) == 64
    small = [("small", "fake_sections")]
    fake_sections.CALLS.clear()
    assert [o.cached for o in runner.run_sections(small, tmp_path, jobs=1)] == [False]
    assert [o.cached for o in runner.run_sections(small, tmp_path, jobs=1)] == [True]
    assert fake_sections.CALLS == ["small"]

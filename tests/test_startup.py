"""Start-up: ``import rcm_pin`` and the light CLI commands load none of the heavy packages.

Each check runs in a fresh interpreter (this process has imported everything already) and
reads ``sys.modules``; no timing is asserted (``benchmarks/bench_startup.py`` measures it).
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

#: Packages that must stay unloaded until a feature needs them (top-level names).
HEAVY = (
    "scipy",
    "casadi",
    "ocp",
    "matplotlib",
    "meshcat",
    "pandas",
    "pyarrow",
    "optuna",
    "dask",
    "distributed",
    "pink",
    "qpsolvers",
    "daqp",
    "grimp",
    "tqdm",
)
FK = ["fk", "rcm_bevel", "--q=0.1,0.2,0.08,0,0.3,0", "--json"]


def loaded_after(code: str) -> tuple[dict[str, object], set[str]]:
    """Run ``code`` (which sets ``result``) in a fresh interpreter: (result, the top-level
    names of the loaded modules)."""
    script = (
        "import contextlib, io, json, sys\n"
        f"{code}\n"
        "print(json.dumps({'result': result, 'modules': sorted(sys.modules)}))\n"
    )
    proc = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=120, check=True
    )
    doc = json.loads(proc.stdout.splitlines()[-1])
    return doc["result"], {m.split(".")[0] for m in doc["modules"]}


def test_import_rcm_pin_loads_no_heavy_package():
    result, top = loaded_after("import rcm_pin\nresult = rcm_pin.__version__")
    assert result
    assert not top & set(HEAVY), sorted(top & set(HEAVY))
    assert not top & {"xacro", "yaml"}  # the xacro render cache serves loads; sidecars lazy


@pytest.mark.parametrize(
    "argv",
    [FK, ["--help"], ["simulate", "--help"], ["sweep", "--help"], ["list", "--json"]],
    ids=["fk", "help", "simulate-help", "sweep-help", "list"],
)
def test_light_cli_commands_load_no_heavy_package(argv):
    code = (
        "from rcm_pin.cli import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        "    try:\n"
        f"        result = main({argv!r})\n"
        "    except SystemExit as exc:  # --help\n"
        "        result = exc.code\n"
    )
    result, top = loaded_after(code)
    assert result == 0
    assert not top & set(HEAVY), sorted(top & set(HEAVY))


def test_lazy_re_exports_still_resolve():
    """The packages whose ``__init__`` re-exports lazily (PEP 562) give the same objects."""
    import ocp
    import rcm_pin.control as control
    import rcm_pin.design as design
    from ocp.ik import IKProblem
    from rcm_pin.control.computed_torque import ComputedTorque
    from rcm_pin.control.simulate import simulate
    from rcm_pin.design.study import Study

    assert control.ComputedTorque is ComputedTorque and design.Study is Study
    assert ocp.IKProblem is IKProblem
    # the function, not the submodule of the same name (as with the eager re-export)
    assert control.simulate is simulate and callable(control.simulate)
    assert {"simulate", "Gains", "TRAJECTORIES"} <= set(dir(control))
    assert set(control.__all__) <= set(dir(control)) and set(design.__all__) <= set(dir(design))
    assert set(ocp.__all__) <= set(dir(ocp))
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        _ = control.nope
